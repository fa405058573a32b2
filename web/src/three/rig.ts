// The machine drawn from its configuration as a three.js scene graph that *is* the kinematic
// chain (no WebGL needed to build it: tests construct and check it in node).
//
// World coordinates are machine coordinates (mm, Z up). The graph:
//
//   root                                   machine frame
//   ├─ bed, gantry columns/rails, static table (no table axes)
//   ├─ bridge  (0, Y, 0)                   Y-moving beam
//   ├─ saddle  (X, Y, 0)                   X-moving saddle on the beam
//   ├─ table joint 1 group  matrix = T₁    (master; its axis line + bearings drawn in the parent)
//   │   └─ table joint 2 group  matrix = T₂
//   │       └─ tableFrame (identity)        table top, workpiece triad, path, trace
//   └─ carriage  (X, Y, Z)                  ram
//       └─ head joint 1 group  matrix = H₁ (point relative to the carriage)
//           └─ head joint 2 group  matrix = H₂
//               └─ spindle, tool (n → n − L·t₀), tip marker at n − L·t₀
//
// Each joint group's matrix is Tⱼ(x) = pⱼ + Rot(uⱼ, φⱼ)(x − pⱼ) computed by kinematics.ts (the
// engine's arithmetic), bodies are modelled at zero angles in their group's coordinates, so a
// point's world position is exactly the forward kinematics: tip = M + H₁(H₂(n − L·t₀)), and a
// table-frame point w is drawn at T₁(T₂(w)).

import * as THREE from "three";
import { Kinematics, turnRigid } from "./kinematics";
import type { AxisValues, Joint } from "./kinematics";
import type { MachineModel, MachineModelInput, Vec3 } from "./model";

// ---- small vector helpers on tuples ----
const add = (a: Vec3, b: Vec3): Vec3 => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const sub = (a: Vec3, b: Vec3): Vec3 => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const mul = (a: Vec3, k: number): Vec3 => [a[0] * k, a[1] * k, a[2] * k];
const dot = (a: Vec3, b: Vec3): number => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a: Vec3, b: Vec3): Vec3 => [
  a[1] * b[2] - a[2] * b[1],
  a[2] * b[0] - a[0] * b[2],
  a[0] * b[1] - a[1] * b[0],
];
const len = (a: Vec3): number => Math.sqrt(dot(a, a));
const unit = (a: Vec3): Vec3 => mul(a, 1 / (len(a) || 1));
const clamp = (x: number, lo: number, hi: number) => Math.min(hi, Math.max(lo, x));
/** The projection of x onto the line through p along unit u. */
const onLine = (x: Vec3, p: Vec3, u: Vec3): Vec3 => add(p, mul(u, dot(sub(x, p), u)));
/** A unit vector perpendicular to u, preferring `hint`'s component. */
function perpendicular(u: Vec3, hint: Vec3): Vec3 {
  let h = sub(hint, mul(u, dot(hint, u)));
  if (len(h) < 1e-6) h = sub([1, 0, 0], mul(u, u[0]));
  if (len(h) < 1e-6) h = sub([0, 1, 0], mul(u, u[1]));
  return unit(h);
}
/** u turned to point along `toward` (a line's two senses are the same line). */
const aligned = (u: Vec3, toward: Vec3): Vec3 => (dot(u, toward) < 0 ? mul(u, -1) : u);

// ---- materials ----
export interface RigMaterials {
  bed: THREE.Material;
  frame: THREE.Material;
  /** The gantry's static frame (rails, legs, beam): see-through so it never hides the work zone. */
  gantry: THREE.Material;
  /** Ram and saddle: half see-through, so a top view shows the tool and the part. */
  ram: THREE.Material;
  table: THREE.Material;
  tableTop: THREE.Material;
  head: THREE.Material;
  spindle: THREE.Material;
  tool: THREE.Material;
  tip: THREE.Material;
}

function makeMaterials(): RigMaterials {
  const m = (color: number, metalness = 0.2, roughness = 0.6) =>
    new THREE.MeshStandardMaterial({ color, metalness, roughness });
  return {
    bed: m(0x4a5058),
    frame: m(0xb8bec6),
    gantry: new THREE.MeshStandardMaterial({ color: 0xb8bec6, transparent: true, opacity: 0.22, depthWrite: false }),
    ram: new THREE.MeshStandardMaterial({ color: 0xb8bec6, transparent: true, opacity: 0.5, depthWrite: false }),
    table: m(0x6f8fb0),
    tableTop: m(0x9fb4c8),
    head: m(0xe0a040),
    spindle: m(0xc8ccd0, 0.6, 0.35),
    tool: m(0xf2f2f2, 0.8, 0.25),
    tip: new THREE.MeshBasicMaterial({ color: 0xff2020 }),
  };
}

/** Axis-line colours by address: A/X red, B/Y green, C/Z blue (the usual triad colours). */
export function axisColor(name: string): number {
  return { A: 0xff4040, B: 0x40d040, C: 0x4080ff }[name] ?? 0xd0d040;
}

// ---- mesh helpers (geometry modelled along local Y, then placed) ----
const Y: THREE.Vector3 = new THREE.Vector3(0, 1, 0);

/** A cylinder from a to b. */
function cylinder(a: Vec3, b: Vec3, r: number, mat: THREE.Material, segments = 32, rTop = r): THREE.Mesh {
  const d = sub(b, a);
  const l = Math.max(len(d), 1e-6);
  const mesh = new THREE.Mesh(new THREE.CylinderGeometry(rTop, r, l, segments), mat);
  mesh.position.set(...mul(add(a, b), 0.5));
  mesh.quaternion.setFromUnitVectors(Y, new THREE.Vector3(...unit(d)));
  return mesh;
}

/** A box from a to b (its length), `w` wide along `across` (perpendicular part), `t` thick. */
function box(a: Vec3, b: Vec3, w: number, t: number, across: Vec3, mat: THREE.Material): THREE.Mesh {
  const d = sub(b, a);
  const l = Math.max(len(d), 1e-6);
  const yv = unit(d);
  const xv = perpendicular(yv, across);
  const zv = cross(xv, yv);
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(w, l, t), mat);
  const basis = new THREE.Matrix4().makeBasis(
    new THREE.Vector3(...xv),
    new THREE.Vector3(...yv),
    new THREE.Vector3(...zv),
  );
  mesh.quaternion.setFromRotationMatrix(basis);
  mesh.position.set(...mul(add(a, b), 0.5));
  return mesh;
}

/** An axis-aligned box between two corners. */
function block(min: Vec3, max: Vec3, mat: THREE.Material): THREE.Mesh {
  const mesh = new THREE.Mesh(new THREE.BoxGeometry(max[0] - min[0], max[1] - min[1], max[2] - min[2]), mat);
  mesh.position.set(...mul(add(min, max), 0.5));
  return mesh;
}

/** The line of a rotary axis, drawn through p along u for ±half. */
function axisLine(p: Vec3, u: Vec3, half: number, name: string): THREE.Line {
  const g = new THREE.BufferGeometry().setFromPoints([
    new THREE.Vector3(...sub(p, mul(u, half))),
    new THREE.Vector3(...add(p, mul(u, half))),
  ]);
  const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: axisColor(name), depthTest: false }));
  line.renderOrder = 10;
  line.name = `axis-line-${name}`;
  return line;
}

/** A joint group whose matrix is set from Tⱼ (no position/quaternion bookkeeping). */
function jointGroup(name: string): THREE.Group {
  const g = new THREE.Group();
  g.name = name;
  g.matrixAutoUpdate = false;
  return g;
}

export interface MachineRig {
  kinematics: Kinematics;
  model: MachineModel;
  /** The whole machine; world = machine coordinates. */
  root: THREE.Group;
  /** The machine's bodies (for bounds; excludes path and trace). */
  bodies: THREE.Object3D[];
  /** The innermost table group: table-frame coordinates (the machine frame without table axes). */
  tableFrame: THREE.Group;
  /** A marker whose world position is the drawn tool tip. */
  tip: THREE.Object3D;
  /** Joint groups by axis letter. */
  joints: Map<string, THREE.Group>;
  /** The working zone's bodies (table chain, head chain, tool): what `fit` frames. */
  focus: THREE.Object3D[];
  /** A characteristic size, mm (for the camera). */
  size: number;
  /** Pose the machine: axis values by address (missing: 0), tool length. Updates world matrices. */
  update(axes: AxisValues, toolLength: number): void;
  dispose(): void;
}

/** Build the machine's scene graph from its model (defaults applied by `Kinematics`). */
export function buildMachine(input: MachineModelInput | MachineModel, materials: RigMaterials = makeMaterials()): MachineRig {
  const kin = new Kinematics(input);
  const model = kin.model;
  const mat = materials;
  const root = new THREE.Group();
  root.name = `machine-${model.name}`;
  const bodies: THREE.Object3D[] = [];
  const joints = new Map<string, THREE.Group>();

  // ---- sizes from the strokes and the mechanism's points ----
  const stroke = (c: string, d: [number, number]): [number, number] => {
    const a = model.axes.find((x) => x.name === c && x.kind === "linear");
    return a?.stroke ?? d;
  };
  const [xMin, xMax] = stroke("X", [-500, 500]);
  const [yMin, yMax] = stroke("Y", [-400, 400]);
  const [zMin, zMax] = stroke("Z", [-400, 300]);
  const spanX = Math.max(xMax - xMin, 100);
  const spanY = Math.max(yMax - yMin, 100);
  const size = Math.max(spanX, spanY, zMax - zMin, 300);
  const tableR = clamp(0.28 * Math.min(spanX, spanY), 60, 450);
  const t0 = kin.toolAxis;
  const nose = kin.nose;
  // Head size: from the distance of the head axes from the nose (the pivot length).
  const pivot = kin.head.length ? Math.max(...kin.head.map((j) => len(sub(onLine(nose, j.point, j.direction), nose)) || len(sub(j.point, nose)))) : 150;
  const headR = clamp(0.4 * pivot, 30, 120);
  const toolR = clamp(0.12 * headR, 2, 10);

  // ---- table chain ----
  const tableTopT = clamp(0.2 * tableR, 20, 60);
  let parent: THREE.Group = root;
  let swing = 0; // how far table bodies reach below the master line (for the bed height)
  let lowest = -tableTopT; // lowest static table point
  const housings: Vec3[] = []; // bearing housings of a horizontal master, standing on pillars
  const tableJoints = kin.table;
  tableJoints.forEach((j: Joint, k: number) => {
    const g = jointGroup(`table-${j.name}`);
    joints.set(j.name, g);
    const u = j.direction;
    const p = j.point;
    const isLast = k === tableJoints.length - 1;
    const w = tableR + 50; // cradle half width along a tilting axis
    const hubR = clamp(0.3 * tableR, 30, 120);
    const hubL = 60;
    const body: THREE.Object3D[] = [];
    if (isLast) {
      // The rotary table: a disc about the axis, its top face through the table-frame origin.
      const up = Math.abs(u[2]) >= 0.5 ? aligned(u, [0, 0, 1]) : aligned(u, [1, 0, 0]);
      const top = onLine([0, 0, 0], p, up);
      const discR = Math.abs(u[2]) >= 0.5 ? tableR : clamp(len(sub([0, 0, 0], onLine([0, 0, 0], p, up))) + 60, 60, tableR);
      const bottom = sub(top, mul(up, tableTopT));
      body.push(cylinder(bottom, top, discR, mat.tableTop, 48));
      // A mark on the rim so the rotation shows.
      const side = perpendicular(up, [1, 0, 0]);
      body.push(box(add(bottom, mul(side, discR - 15)), add(top, mul(add(side, mul(up, 0.02)), discR - 15)), 24, 24, perpendicular(up, cross(up, side)), mat.table));
      // T-slots as thin bars, for a machined look.
      const s2 = cross(up, side);
      for (const f of [-0.5, 0, 0.5]) {
        const c = add(top, mul(s2, f * discR));
        const half = Math.sqrt(Math.max(discR * discR - (f * discR) ** 2, 0)) * 0.9;
        body.push(box(sub(c, mul(side, half)), add(c, mul(side, half)), 6, 2, s2, mat.table));
      }
      if (k === 0) {
        // Its bearing on the bed: a pedestal (vertical axis) or a headstock (horizontal axis).
        if (Math.abs(u[2]) >= 0.5) {
          const ped = cylinder(sub(bottom, mul(up, 1)), sub(bottom, mul(up, 80)), discR * 0.85, mat.table, 40);
          parent.add(ped);
          bodies.push(ped);
          lowest = Math.min(lowest, bottom[2] - 80);
        } else {
          const back = sub(bottom, mul(up, 120));
          const hs = cylinder(sub(bottom, mul(up, 2)), back, Math.max(discR * 0.7, 50), mat.table, 40);
          parent.add(hs);
          bodies.push(hs);
          swing = Math.max(swing, discR);
        }
      }
      swing = Math.max(swing, Math.hypot(len(sub(top, onLine(top, p, u))), discR));
    } else {
      // A cradle (trunnion) carrying the next axis: two hubs on this axis's line, side plates
      // down (or up) to a floor under the next axis's disc.
      const next = tableJoints[k + 1];
      const nu = Math.abs(next.direction[2]) >= 0.5 ? aligned(next.direction, [0, 0, 1]) : aligned(next.direction, [1, 0, 0]);
      const nextTop = onLine([0, 0, 0], next.point, nu);
      const floorT = clamp(0.15 * tableR, 20, 50);
      const floorTop = sub(nextTop, mul(nu, tableTopT + 2));
      const floorC = sub(floorTop, mul(nu, floorT / 2));
      const q = onLine(floorC, p, u);
      body.push(box(sub(floorC, mul(u, w)), add(floorC, mul(u, w)), floorT, 1.6 * tableR, nu, mat.table));
      for (const s of [-1, 1]) {
        const hub = add(q, mul(u, s * w));
        body.push(cylinder(add(hub, mul(u, -s * 30)), add(hub, mul(u, s * (hubL / 2))), hubR, mat.table, 40));
        if (len(sub(floorC, q)) > 1) {
          body.push(box(hub, add(floorC, mul(u, s * w)), 40, 1.4 * hubR, u, mat.table));
        }
      }
      swing = Math.max(swing, Math.hypot(len(sub(floorC, q)) + floorT, tableR), hubR, len(sub(nextTop, q)) + 20);
      if (k === 0) {
        // Bearings on the bed: two pillars with bearing housings at the line's ends.
        for (const s of [-1, 1]) {
          const c = add(q, mul(u, s * (w + hubL / 2 + 40)));
          const housing = cylinder(sub(c, mul(u, 40)), add(c, mul(u, 40)), hubR * 1.15, mat.frame, 40);
          parent.add(housing);
          bodies.push(housing);
          if (Math.abs(u[2]) < 0.5) housings.push(c);
        }
      }
    }
    for (const b of body) {
      g.add(b);
      bodies.push(b);
    }
    parent.add(axisLine(p, u, (isLast ? tableR : w) + 120, j.name));
    parent.add(g);
    parent = g;
  });
  const tableFrame = new THREE.Group();
  tableFrame.name = "table-frame";
  parent.add(tableFrame);
  if (tableJoints.length === 0) {
    // A fixed table, top face at machine zero.
    const tw = clamp(0.8 * spanX, 300, 3000);
    const td = clamp(0.8 * spanY, 250, 2500);
    const t = block([-tw / 2, -td / 2, -tableTopT - 40], [tw / 2, td / 2, 0], mat.tableTop);
    root.add(t);
    bodies.push(t);
    lowest = -tableTopT - 40;
  }
  const triad = new THREE.AxesHelper(clamp(0.5 * tableR, 40, 200));
  triad.name = "workpiece-triad";
  (triad.material as THREE.Material).depthTest = false;
  triad.renderOrder = 11;
  tableFrame.add(triad);

  // Bed under everything the table can swing through.
  const master = tableJoints[0];
  let bedTop = lowest - 30;
  if (master) {
    const lineZ = Math.min(master.point[2], onLine([0, 0, 0], master.point, master.direction)[2]);
    bedTop = Math.min(bedTop, (Math.abs(master.direction[2]) >= 0.5 ? lowest : lineZ - swing) - 40);
  }
  const margin = 200;
  const bed = block([xMin - margin, yMin - margin, bedTop - 150], [xMax + margin, yMax + margin, bedTop], mat.bed);
  bed.name = "bed";
  root.add(bed);
  bodies.push(bed);
  // Pillars under the master's bearing housings.
  for (const c of housings) {
    const pill = block([c[0] - 45, c[1] - 45, bedTop], [c[0] + 45, c[1] + 45, c[2]], mat.frame);
    root.add(pill);
    bodies.push(pill);
  }

  // ---- head chain ----
  const carriage = new THREE.Group();
  carriage.name = "carriage";
  root.add(carriage);
  let hp: THREE.Group = carriage;
  // The top of the head (carriage coordinates, zero angles), where the ram begins.
  let headTop: Vec3 = add(nose, mul(t0, pivot + headR));
  const headJoints = kin.head;
  const w = headR + 22; // yoke half width
  const gap = 6;
  headJoints.forEach((j: Joint, k: number) => {
    const g = jointGroup(`head-${j.name}`);
    joints.set(j.name, g);
    const u = j.direction;
    const p = j.point;
    const isLast = k === headJoints.length - 1;
    const swivel = Math.abs(dot(u, t0)) > 0.7;
    const body: THREE.Object3D[] = [];
    // The bearing of a tilt axis: a yoke in the parent, arms from the line's ends up to a bridge.
    const yoke = (into: THREE.Object3D[], center: Vec3, axis: Vec3): Vec3 => {
      const upv = perpendicular(axis, t0);
      const rise = headR + 40;
      for (const s of [-1, 1]) {
        const e = add(center, mul(axis, s * (w + 14)));
        into.push(cylinder(sub(e, mul(axis, 14)), add(e, mul(axis, 14)), headR * 0.85, mat.head));
        into.push(box(e, add(e, mul(upv, rise)), 2 * headR * 0.85, 28, axis, mat.head));
      }
      const bridgeC = add(center, mul(upv, rise + 15));
      into.push(box(sub(bridgeC, mul(axis, w + 28)), add(bridgeC, mul(axis, w + 28)), 2 * headR * 0.85, 30, upv, mat.head));
      return add(bridgeC, mul(upv, 15));
    };
    if (isLast) {
      // The spindle housing on the tool line, and this axis's hub.
      const c = onLine(p, nose, t0);
      const housingTop = add(c, mul(t0, headR * 0.9));
      body.push(cylinder(add(nose, mul(t0, 35)), housingTop, headR * 0.6, mat.spindle, 32));
      body.push(cylinder(nose, add(nose, mul(t0, 35)), toolR * 2.2, mat.spindle, 24, headR * 0.45));
      body.push(cylinder(sub(p, mul(u, w - gap)), add(p, mul(u, w - gap)), headR * 0.8, mat.head, 40));
      const marker = box(p, add(p, mul(perpendicular(u, mul(t0, -1)), headR * 0.95)), 14, 2 * (w - gap) - 4, u, mat.head);
      body.push(marker);
    } else {
      // A master carrying the next axis: the next axis's yoke, and this axis's body above it.
      const next = headJoints[k + 1];
      const top = yoke(body, next.point, next.direction);
      if (swivel) {
        const ua = aligned(u, t0);
        const base = onLine(top, p, ua);
        const drumTop = add(base, mul(ua, headR * 1.2));
        body.push(cylinder(base, drumTop, headR * 1.1, mat.head, 40));
        body.push(box(base, add(base, mul(perpendicular(ua, [1, 0, 0]), headR * 1.15)), 16, headR * 1.2, ua, mat.spindle));
        headTop = drumTop;
      } else {
        const c = p;
        body.push(cylinder(sub(c, mul(u, w - gap)), add(c, mul(u, w - gap)), headR * 0.9, mat.head, 40));
        body.push(box(c, top, 2 * headR * 0.8, 2 * headR * 0.8, u, mat.head));
        headTop = add(c, mul(t0, headR));
      }
    }
    if (k === 0) {
      // The master's bearing in the carriage.
      if (swivel) {
        // the ram holds the drum (headTop set above)
      } else {
        const parts: THREE.Object3D[] = [];
        headTop = yoke(parts, p, u);
        for (const b of parts) {
          hp.add(b);
          bodies.push(b);
        }
      }
    }
    for (const b of body) {
      g.add(b);
      bodies.push(b);
    }
    hp.add(axisLine(p, u, w + 120, j.name));
    hp.add(g);
    hp = g;
  });
  if (headJoints.length === 0) {
    const top = add(nose, mul(t0, 220));
    const parts = [
      cylinder(nose, add(nose, mul(t0, 35)), toolR * 2.2, mat.spindle, 24, headR * 0.45),
      cylinder(add(nose, mul(t0, 35)), top, headR * 0.6, mat.spindle, 32),
    ];
    for (const b of parts) {
      carriage.add(b);
      bodies.push(b);
    }
    headTop = top;
  }
  // Tool and tip in the innermost head group.
  const toolMesh = new THREE.Mesh(new THREE.CylinderGeometry(toolR, toolR, 1, 20).translate(0, 0.5, 0), mat.tool);
  toolMesh.name = "tool";
  toolMesh.position.set(...nose);
  toolMesh.quaternion.setFromUnitVectors(Y, new THREE.Vector3(...mul(t0, -1)));
  hp.add(toolMesh);
  const tip = new THREE.Mesh(new THREE.SphereGeometry(toolR * 1.6, 16, 12), mat.tip);
  tip.name = "tool-tip";
  hp.add(tip);
  bodies.push(toolMesh);

  const focus = bodies.filter((b) => b !== bed);
  // Ram: from the head top straight up (+Z) through the saddle.
  const ramW = 2 * headR + 60;
  const ramLen = zMax - zMin + 300;
  const ramBase: Vec3 = [headTop[0], headTop[1], headTop[2]];
  const ram = block(
    [ramBase[0] - ramW / 2, ramBase[1] - ramW / 2, ramBase[2]],
    [ramBase[0] + ramW / 2, ramBase[1] + ramW / 2, ramBase[2] + ramLen],
    mat.ram,
  );
  ram.name = "ram";
  carriage.add(ram);
  bodies.push(ram);

  // Gantry: the saddle (X) on a beam (Y) on two rails over the bed.
  const zSaddle = ramBase[2] + zMax + 120;
  const saddle = new THREE.Group();
  saddle.name = "saddle";
  const saddleBox = block([ramBase[0] - ramW / 2 - 40, ramBase[1] - ramW / 2 - 40, zSaddle - 120], [ramBase[0] + ramW / 2 + 40, ramBase[1] + ramW / 2 + 40, zSaddle + 120], mat.ram);
  saddle.add(saddleBox);
  root.add(saddle);
  bodies.push(saddleBox);
  const bridge = new THREE.Group();
  bridge.name = "bridge";
  const beamX0 = xMin - margin + 60;
  const beamX1 = xMax + margin - 60;
  // Behind the ram (+Y), so the operator's view (from −Y) sees the head.
  const beamY = ramBase[1] + ramW / 2 + 40 + 90;
  const beam = block([beamX0, beamY - 90, zSaddle - 110], [beamX1, beamY + 90, zSaddle + 110], mat.gantry);
  bridge.add(beam);
  root.add(bridge);
  bodies.push(beam);
  for (const x of [beamX0 + 60, beamX1 - 60]) {
    const rail = block([x - 60, yMin - margin + 30, zSaddle - 230], [x + 60, yMax + margin - 30, zSaddle - 110], mat.gantry);
    root.add(rail);
    bodies.push(rail);
    for (const y of [yMin - margin + 90, yMax + margin - 90]) {
      const leg = block([x - 60, y - 60, bedTop], [x + 60, y + 60, zSaddle - 230], mat.gantry);
      root.add(leg);
      bodies.push(leg);
    }
  }

  const update = (axes: AxisValues, toolLength: number) => {
    const m = kin.carriage(axes);
    carriage.position.set(m[0], m[1], m[2]);
    saddle.position.set(m[0], m[1], 0);
    bridge.position.set(0, m[1], 0);
    for (const side of ["head", "table"] as const) {
      for (const t of kin.turns(side, axes)) {
        const r = turnRigid(t);
        const g = joints.get(t.joint.name)!;
        g.matrix.set(r.r[0], r.r[1], r.r[2], r.o[0], r.r[3], r.r[4], r.r[5], r.o[1], r.r[6], r.r[7], r.r[8], r.o[2], 0, 0, 0, 1);
        g.matrixWorldNeedsUpdate = true;
      }
    }
    const L = Math.max(0, toolLength);
    toolMesh.visible = L > 0;
    toolMesh.scale.set(1, L > 0 ? L : 1, 1);
    tip.position.set(...kin.tipLocal(toolLength));
    root.updateMatrixWorld(true);
  };
  update({}, 0);

  const dispose = () => {
    root.traverse((o) => {
      const mesh = o as THREE.Mesh;
      if (mesh.geometry) mesh.geometry.dispose();
      const material = mesh.material as THREE.MeshBasicMaterial | undefined;
      if (material && !Object.values(mat).includes(material)) {
        material.map?.dispose();
        material.dispose();
      }
    });
    for (const m of Object.values(mat)) m.dispose();
  };

  return { kinematics: kin, model, root, bodies, focus, tableFrame, tip, joints, size, update, dispose };
}
