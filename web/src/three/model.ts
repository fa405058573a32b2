// The machine model file (`docs/machine-config.md`), as `fivex machine --preset NAME` prints it
// and `--machine FILE.json` / `POST /controllers {"machine": …}` take it.
//
// `MachineModelInput` is the file as written (optional fields may be missing);
// `MachineModel` is the same with every default applied (`normalizeModel`). The 3D view and the
// kinematics only read the mechanism (axes, rotary, tool_axis, nose, holder, and the further
// chains that `chain.ts` turns into a machine of their own); the option blocks
// (`motion`, `five_axis`, `manual`) are carried through untouched for callers that want them.

import type { components } from "../api/schema";

export type Vec3 = [number, number, number];

/** The file as the service's document describes it (`MachineConfig`, generated from the engine's
 * types: `npm run gen`): what `GET /controllers/{id}/machine` answers and `--machine` takes. */
export type MachineModelInput = components["schemas"]["MachineConfig"];
export type AxisInput = components["schemas"]["Axis"];
export type RotaryLinkInput = components["schemas"]["RotaryLink"];
export type AxisKind = components["schemas"]["AxisKind"];
export type Side = components["schemas"]["Side"];
export type Hand = components["schemas"]["Hand"];
type ChainSetInput = components["schemas"]["ChainSet"];
type SubChainInput = components["schemas"]["SubChain"];

export interface Axis {
  name: string;
  kind: AxisKind;
  rapid: number;
  accel: number;
  jerk: number;
  stroke: [number, number] | null;
  references: Vec3;
  rollover: boolean;
  shortest: boolean;
}

export interface RotaryLink {
  axis: string;
  side: Side;
  direction: Vec3;
  hand: Hand;
  point: Vec3;
  zero_offset: number;
  fixed: number | null;
  range: [number, number] | null;
}

/** A head attachment of a spindle-type set (Syntec `G10 L5000 P_ Q2..Q4`): it replaces the set's tool direction, nose and holder. */
export interface SubChain {
  q: number;
  tool_axis: Vec3;
  nose: Vec3;
  holder: number;
}

/** A further mechanism chain, Syntec's set 2–4: a whole mechanism as the main fields describe set 1. */
export interface ChainSet {
  set: number;
  rotary: RotaryLink[];
  tool_axis: Vec3;
  nose: Vec3;
  holder: number;
  sub_chains: SubChain[];
}

export interface MachineModel {
  name: string;
  axes: Axis[];
  rotary: RotaryLink[];
  tool_axis: Vec3;
  nose: Vec3;
  holder: number;
  /** Set 1's sub-chains (empty: none). */
  sub_chains: SubChain[];
  /** Sets 2–4 (empty: the machine has the one chain above). */
  chains: ChainSet[];
  motion: components["schemas"]["MotionOptions"];
  five_axis: components["schemas"]["FiveAxisOptions"];
  manual: components["schemas"]["ManualOptions"];
}

const vec = (v: readonly number[] | undefined | null, d: Vec3): Vec3 =>
  v && v.length === 3 ? [Number(v[0]), Number(v[1]), Number(v[2])] : [d[0], d[1], d[2]];

/** The model with every default of `docs/machine-config.md` applied (also accepts an already normalised model). */
export function normalizeModel(m: MachineModelInput | MachineModel): MachineModel {
  const axes: Axis[] = m.axes.map((a) => {
    const accel = a.accel ?? a.rapid / 60 / 0.2;
    return {
      name: a.name,
      kind: a.kind,
      rapid: a.rapid,
      accel,
      jerk: a.jerk ?? accel / 0.05,
      stroke: a.stroke ? [a.stroke[0], a.stroke[1]] : null,
      references: vec(a.references, [0, 0, 0]),
      rollover: a.rollover ?? false,
      shortest: a.shortest ?? false,
    };
  });
  const rotary = (links: RotaryLinkInput[] | RotaryLink[] | undefined): RotaryLink[] =>
    (links ?? []).map((r) => ({
      axis: r.axis,
      side: r.side,
      direction: vec(r.direction, [0, 0, 1]),
      hand: r.hand,
      point: vec(r.point, [0, 0, 0]),
      zero_offset: r.zero_offset ?? 0,
      fixed: r.fixed ?? null,
      range: r.range && !(r.range[0] === 0 && r.range[1] === 0) ? [r.range[0], r.range[1]] : null,
    }));
  // The tail of a mechanism past its last head axis (the fields a sub-chain replaces).
  const tail = (c: { tool_axis?: readonly number[] | null; nose?: readonly number[] | null; holder?: number | null }) => ({
    tool_axis: vec(c.tool_axis, [0, 0, 1]),
    nose: vec(c.nose, [0, 0, 0]),
    holder: c.holder ?? 0,
  });
  const subChains = (subs: SubChainInput[] | SubChain[] | undefined): SubChain[] => (subs ?? []).map((s) => ({ q: s.q, ...tail(s) }));
  return {
    name: m.name,
    axes,
    rotary: rotary(m.rotary),
    ...tail(m),
    sub_chains: subChains(m.sub_chains),
    chains: (m.chains ?? []).map((c: ChainSetInput | ChainSet) => ({
      set: c.set,
      rotary: rotary(c.rotary),
      ...tail(c),
      sub_chains: subChains(c.sub_chains),
    })),
    motion: { ...(m.motion ?? {}) },
    five_axis: { ...(m.five_axis ?? {}) },
    manual: { ...(m.manual ?? {}) },
  };
}

/** The machine's kind, as the engine's `MachineKind` names it (kebab-case; the service says
 * `unknown` for a machine its kinematics refuses, which never reaches the view). */
export type MachineKind = Exclude<components["schemas"]["MechanismName"], "unknown">;

export function machineKind(m: MachineModel): MachineKind {
  const h = m.rotary.filter((r) => r.side === "head").length;
  const t = m.rotary.filter((r) => r.side === "table").length;
  if (h === 0 && t === 0) return "three-axis";
  if (h === 2 && t === 0) return "head-head";
  if (h === 0 && t === 2) return "table-table";
  if (h === 1 && t === 1) return "head-table";
  if (h === 1 && t === 0) return "head";
  if (h === 0 && t === 1) return "table";
  throw new Error(`${m.name}: a machine has at most two rotary axes in its mechanism chain`);
}
