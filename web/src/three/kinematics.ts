// Forward kinematics, the same arithmetic as the engine's `engine/src/kin/mod.rs`
// (`docs/machine-config.md`, "Forward kinematics"):
//
//   joint j turns by φⱼ = sⱼ·(θⱼ + δⱼ) about the line through pⱼ with unit direction uⱼ,
//   Tⱼ(x) = pⱼ + Rot(uⱼ, φⱼ)·(x − pⱼ); the master carries the slave (the slave acts first).
//   tip_machine  = M + H(n − L·t₀),  tool_machine = R_H·t₀        (H: the head chain, M = X/Y/Z)
//   tip (table)  = W⁻¹(tip_machine), tool (table) = R_Wᵀ·tool_machine   (W: the table chain)
//
// sin/cos of degrees are computed as the engine does (quarter-turn reduction + Taylor series), so
// the results agree with `fivex kin fk` to rounding (the fixture test asks ≤ 1e-9).

import { machineKind, normalizeModel } from "./model";
import type { MachineKind, MachineModel, MachineModelInput, Side, Vec3 } from "./model";

export type AxisValues = Record<string, number>;

/** `x` rounded half away from zero (the engine's `angle::round`). */
function roundHalfAway(x: number): number {
  return Math.trunc(x + (x < 0 || Object.is(x, -0) ? -0.5 : 0.5));
}

// 1/n! for n = 2 … 16, built the way the engine builds them.
const F: number[] = (() => {
  const f: number[] = [];
  let fact = 1;
  for (let n = 2; n <= 16; n++) {
    fact *= n;
    f.push(1 / fact);
  }
  return f;
})();

function sinCosSmall(x: number): [number, number] {
  const z = x * x;
  const sinTail = F[1] - z * (F[3] - z * (F[5] - z * (F[7] - z * (F[9] - z * (F[11] - z * F[13])))));
  const cosTail =
    F[0] - z * (F[2] - z * (F[4] - z * (F[6] - z * (F[8] - z * (F[10] - z * (F[12] - z * F[14]))))));
  return [x - x * z * sinTail, 1 - z * cosTail];
}

/** sin and cos of an angle in degrees, exact at multiples of 90° (the engine's `sin_cos_deg`). */
export function sinCosDeg(deg: number): [number, number] {
  const q = roundHalfAway(deg * (1 / 90));
  const [s, c] = sinCosSmall((deg - 90 * q) * (Math.PI / 180));
  switch (((q % 4) + 4) % 4) {
    case 0:
      return [s + 0, c];
    case 1:
      return [c, -s + 0];
    case 2:
      return [-s + 0, -c];
    default:
      return [-c, s + 0];
  }
}

export interface Joint {
  /** The axis letter. */
  name: string;
  /** Whether the machine has this axis (false: hypothetical, always at `fixed`). */
  real: boolean;
  side: Side;
  /** Unit direction at zero angles. */
  direction: Vec3;
  /** +1 right hand, −1 left hand. */
  sign: number;
  zeroOffset: number;
  /** Head: relative to the carriage reference point; table: machine coordinates. */
  point: Vec3;
  fixed: number;
}

/** One joint turned: sine and cosine of φ. */
export interface Turn {
  joint: Joint;
  s: number;
  c: number;
}

export interface Pose {
  /** Tool tip in the table frame. */
  tip: Vec3;
  /** Unit tool direction (tip → holder) in the table frame. */
  tool: Vec3;
  tipMachine: Vec3;
  toolMachine: Vec3;
}

/** A rigid motion x ↦ R·x + o; `r` row-major 3×3. */
export interface Rigid {
  r: [number, number, number, number, number, number, number, number, number];
  o: Vec3;
}

function normalize(v: Vec3): Vec3 {
  const n = Math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return [v[0] / n, v[1] / n, v[2] / n];
}

/** Rot(u, φ)·v by Rodrigues' formula in scalars, as the engine writes it. */
export function turnVector(t: Turn, v: Vec3, s: number = t.s): Vec3 {
  const u = t.joint.direction;
  const c = t.c;
  const d = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) * (1 - c);
  return [
    v[0] * c + (u[1] * v[2] - u[2] * v[1]) * s + u[0] * d,
    v[1] * c + (u[2] * v[0] - u[0] * v[2]) * s + u[1] * d,
    v[2] * c + (u[0] * v[1] - u[1] * v[0]) * s + u[2] * d,
  ];
}

/** Tⱼ(x) = p + Rot·(x − p) (or its inverse with `s` = −t.s). */
export function turnPoint(t: Turn, x: Vec3, s: number = t.s): Vec3 {
  const p = t.joint.point;
  const r = turnVector(t, [x[0] - p[0], x[1] - p[1], x[2] - p[2]], s);
  return [p[0] + r[0], p[1] + r[1], p[2] + r[2]];
}

/** Tⱼ as a rigid motion (R, p − R·p). */
export function turnRigid(t: Turn): Rigid {
  const ex = turnVector(t, [1, 0, 0]);
  const ey = turnVector(t, [0, 1, 0]);
  const ez = turnVector(t, [0, 0, 1]);
  const p = t.joint.point;
  const rp = turnVector(t, p);
  return {
    r: [ex[0], ey[0], ez[0], ex[1], ey[1], ez[1], ex[2], ey[2], ez[2]],
    o: [p[0] - rp[0], p[1] - rp[1], p[2] - rp[2]],
  };
}

export class Kinematics {
  readonly model: MachineModel;
  readonly kind: MachineKind;
  /** Head joints, master first (carriage → spindle). */
  readonly head: Joint[];
  /** Table joints, master first (bed → table top). */
  readonly table: Joint[];
  readonly toolAxis: Vec3;
  readonly nose: Vec3;
  /** Which of X, Y, Z are linear axes of the machine (a missing one stays at 0). */
  readonly linear: [boolean, boolean, boolean];

  constructor(input: MachineModelInput | MachineModel) {
    const m = normalizeModel(input);
    this.model = m;
    this.kind = machineKind(m);
    const joint = (l: MachineModel["rotary"][number]): Joint => ({
      name: l.axis,
      real: m.axes.some((a) => a.name === l.axis && a.kind === "rotary"),
      side: l.side,
      direction: normalize(l.direction),
      sign: l.hand === "right" ? 1 : -1,
      zeroOffset: l.zero_offset,
      point: [...l.point] as Vec3,
      fixed: l.fixed ?? 0,
    });
    this.head = m.rotary.filter((l) => l.side === "head").map(joint);
    this.table = m.rotary.filter((l) => l.side === "table").map(joint);
    this.toolAxis = normalize(m.tool_axis);
    this.nose = [...m.nose] as Vec3;
    const lin = (c: string) => m.axes.some((a) => a.name === c && a.kind === "linear");
    this.linear = [lin("X"), lin("Y"), lin("Z")];
  }

  /** The carriage reference point M = (X, Y, Z). */
  carriage(axes: AxisValues): Vec3 {
    const at = (i: number, c: string) => (this.linear[i] ? (axes[c] ?? 0) : 0);
    return [at(0, "X"), at(1, "Y"), at(2, "Z")];
  }

  /** The commanded angle θ of a joint (its `fixed` angle when hypothetical). */
  angle(j: Joint, axes: AxisValues): number {
    return j.real ? (axes[j.name] ?? 0) : j.fixed;
  }

  /** The turned joints of one side, master first. */
  turns(side: Side, axes: AxisValues): Turn[] {
    const joints = side === "head" ? this.head : this.table;
    return joints.map((j) => {
      const [s, c] = sinCosDeg(j.sign * (this.angle(j, axes) + j.zeroOffset));
      return { joint: j, s, c };
    });
  }

  /** The point of the tool at distance `L` from the nose, in the innermost head frame (zero angles, relative to the carriage). */
  tipLocal(toolLength: number): Vec3 {
    const n = this.nose;
    const t = this.toolAxis;
    return [n[0] - toolLength * t[0], n[1] - toolLength * t[1], n[2] - toolLength * t[2]];
  }

  forward(axes: AxisValues, toolLength: number): Pose {
    const m = this.carriage(axes);
    const head = this.turns("head", axes);
    let x = this.tipLocal(toolLength);
    let v = this.toolAxis;
    for (let k = head.length - 1; k >= 0; k--) {
      x = turnPoint(head[k], x);
      v = turnVector(head[k], v);
    }
    const tipMachine: Vec3 = [m[0] + x[0], m[1] + x[1], m[2] + x[2]];
    const toolMachine = v;
    const table = this.turns("table", axes);
    let tip = tipMachine;
    let tool = toolMachine;
    for (const t of table) {
      tip = turnPoint(t, tip, -t.s);
      tool = turnVector(t, tool, -t.s);
    }
    return { tip, tool, tipMachine, toolMachine };
  }

  /** W(w): a point of the table frame → machine coordinates at these axis values. */
  tableToMachine(w: Vec3, axes: AxisValues): Vec3 {
    const table = this.turns("table", axes);
    let x = w;
    for (let k = table.length - 1; k >= 0; k--) x = turnPoint(table[k], x);
    return x;
  }

  /** W⁻¹(x): machine coordinates → the table frame. */
  machineToTable(x: Vec3, axes: AxisValues): Vec3 {
    let w = x;
    for (const t of this.turns("table", axes)) w = turnPoint(t, w, -t.s);
    return w;
  }
}
