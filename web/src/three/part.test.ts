// The part in the 3D view: the work zero's triad (placed in the table frame, the same size on
// screen at any distance), the part's bounds a "fit part" frames, and the key that does it.
import * as THREE from "three";
import { describe, expect, it } from "vitest";
import { fixture } from "./fixtures/fixture";
import { MachineScene } from "./scene";
import { MIN_PART_RADIUS, WORK_ZERO_SCREEN, WorkZeroFrame, WorkpieceBoxes } from "./part";
import { planeInTable, workZeroInTable } from "./frameTrace";
import { isFitKey } from "./View3D";

const tableAc = () => fixture.machines.find((m) => m.source === "table-ac") ?? fixture.machines[0];

describe("the work zero", () => {
  it("is tip_table − tip of a frame", () => {
    expect(workZeroInTable({ tip: [10, -20, 30], tip_table: [110, 80, 25] })).toEqual([100, 100, -5]);
    expect(workZeroInTable({ tip: [NaN, 0, 0], tip_table: [0, 0, 0] })).toBeNull();
  });

  it("rides with the table: its world place is the table frame's point, at any pose", () => {
    const m = tableAc();
    const s = new MachineScene(m.model);
    expect(s.workZero.object.visible).toBe(false);
    s.setWorkZero(100, 50, -20);
    expect(s.workZero.object.visible).toBe(true);
    for (const p of m.poses.slice(0, 4)) {
      s.setAxes(p.axes);
      s.rig.root.updateMatrixWorld(true);
      const world = s.workZero.object.getWorldPosition(new THREE.Vector3());
      const want = new THREE.Vector3(...s.rig.kinematics.tableToMachine([100, 50, -20], s.getAxes()));
      expect(world.distanceTo(want)).toBeLessThanOrEqual(1e-9);
    }
    s.dispose();
  });

  it("keeps its size on screen: its scale grows with the camera's distance", () => {
    const z = new WorkZeroFrame();
    z.set([0, 0, 0]);
    z.fitScreen(new THREE.Vector3(0, 0, 100));
    expect(z.object.scale.x).toBeCloseTo(100 * WORK_ZERO_SCREEN, 12);
    z.fitScreen(new THREE.Vector3(0, 3000, 4000));
    expect(z.object.scale.x).toBeCloseTo(5000 * WORK_ZERO_SCREEN, 9);
    z.dispose();
  });
});

describe("the tilted working plane", () => {
  const s30 = Math.sin(Math.PI / 6);
  const c30 = Math.cos(Math.PI / 6);
  // G68.2 X10. I0 J30. K0: the FCS X is the workpiece X, its Z tilted 30° about it.
  const plane = { code: "G68.2", origin: [10, 0, 0], axes: [[1, 0, 0], [0, c30, s30], [0, -s30, c30]] };

  it("is the frame's plane moved into the table frame by tip_table − tip", () => {
    const got = planeInTable({ tip: [10, -20, 30], tip_table: [110, 80, 25], plane });
    expect(got).toEqual({ origin: [110, 100, -5], axes: plane.axes });
    expect(planeInTable({ tip: [0, 0, 0], tip_table: [0, 0, 0] })).toBeNull();
    expect(planeInTable({ tip: [0, 0, 0], tip_table: [0, 0, 0], plane: null })).toBeNull();
  });

  it("rides with the table, turned as the plane at any pose, and hides when the plane ends", () => {
    const m = tableAc();
    const s = new MachineScene(m.model);
    const frame = s.workingPlane.object;
    expect(frame.visible).toBe(false);
    const inTable = planeInTable({ tip: [0, 0, 0], tip_table: [100, 50, -20], plane });
    if (!inTable) throw new Error("no plane");
    s.setWorkingPlane(inTable);
    expect(frame.visible).toBe(true);
    for (const p of m.poses.slice(0, 4)) {
      s.setAxes(p.axes);
      s.rig.root.updateMatrixWorld(true);
      const world = frame.getWorldPosition(new THREE.Vector3());
      const at = (q: number[]) => new THREE.Vector3(...s.rig.kinematics.tableToMachine(q as [number, number, number], s.getAxes()));
      expect(world.distanceTo(at([110, 50, -20]))).toBeLessThanOrEqual(1e-9);
      // Its Z arm's end is the plane's Z axis from its origin (the scale is 1 before a render).
      const zEnd = new THREE.Vector3(0, 0, 1).applyMatrix4(frame.matrixWorld);
      expect(zEnd.distanceTo(at([110, 50 - s30, -20 + c30]))).toBeLessThanOrEqual(1e-9);
    }
    expect(s.partBounds().containsPoint(frame.getWorldPosition(new THREE.Vector3()))).toBe(true);
    s.setWorkingPlane(null);
    expect(frame.visible).toBe(false);
    s.dispose();
  });
});

describe("the workpiece", () => {
  /** The drawn box `i`'s corner at fractions `f` of its size (0 or 1 per axis), in the world. */
  const corner = (s: MachineScene, i: number, f: [number, number, number]) => {
    s.rig.root.updateMatrixWorld(true);
    const box = s.workpiece.object.getObjectByName(`workpiece-box-${i}`);
    if (!box) throw new Error(`no box ${i}`);
    return new THREE.Vector3(...f).applyMatrix4(box.matrixWorld);
  };

  it("rides with the table: a box's corner at the engine's table-frame tip is drawn at its machine tip, on every machine at every pose", () => {
    let checked = 0;
    for (const m of fixture.machines) {
      const s = new MachineScene(m.model);
      for (const p of m.poses) {
        // A box whose least corner is where the engine puts the tip in the table frame, and its
        // greatest 40 × 30 × 20 beyond.
        const min = p.tip;
        const max = [min[0] + 40, min[1] + 30, min[2] + 20];
        s.setWorkpiece([{ min, max }]);
        s.setAxes(p.axes);
        s.setToolLength(p.tool_length);
        expect(corner(s, 0, [0, 0, 0]).distanceTo(new THREE.Vector3(...p.tip_machine)), `${m.source} ${JSON.stringify(p.axes)}`).toBeLessThanOrEqual(1e-6);
        const far = new THREE.Vector3(...s.rig.kinematics.tableToMachine(max as [number, number, number], s.getAxes()));
        expect(corner(s, 0, [1, 1, 1]).distanceTo(far)).toBeLessThanOrEqual(1e-6);
        checked++;
      }
      s.dispose();
    }
    expect(checked).toBeGreaterThanOrEqual(fixture.machines.length * 4);
  });

  it("stays on the table frame when the mechanism chain changes", () => {
    const m = fixture.machines.find((x) => x.chains && x.chains.length > 0);
    if (!m?.chains) throw new Error("no machine with further chains in the fixture");
    const s = new MachineScene(m.model);
    s.setWorkpiece([{ min: [0, 0, -20], max: [50, 40, 0] }]);
    s.setChain(m.chains[0].chain);
    expect(s.workpiece.object.parent).toBe(s.rig.tableFrame);
    const p = m.chains[0].poses[0];
    s.setAxes(p.axes);
    const want = new THREE.Vector3(...s.rig.kinematics.tableToMachine([50, 40, 0], s.getAxes()));
    expect(corner(s, 0, [1, 1, 1]).distanceTo(want)).toBeLessThanOrEqual(1e-6);
    s.dispose();
  });

  it("is translucent boxes, one per box, replaced as a whole; what no box can be is left out", () => {
    const w = new WorkpieceBoxes();
    expect(w.set([{ min: [0, 0, -20], max: [50, 40, 0] }, { min: [60, 0, -20], max: [70, 40, 0] }])).toBe(true);
    expect(w.object.children.length).toBe(2);
    const fill = w.object.children[0].children[0] as THREE.Mesh;
    const material = fill.material as THREE.MeshBasicMaterial;
    expect(material.transparent && material.opacity < 1 && !material.depthWrite).toBe(true);
    expect(w.set([{ min: [0, 0, -20], max: [50, 40, 0] }, { min: [60, 0, -20], max: [70, 40, 0] }])).toBe(false);
    expect(w.set([{ min: [0, 0, 0], max: [1, 1, 0] }, { min: [0, 0, NaN], max: [1, 1, 1] }, { min: [0, 0, 0], max: [1, 2, 3] }])).toBe(true);
    expect(w.boxes.map((b) => b.max.toArray())).toEqual([[1, 2, 3]]);
    expect(w.set([])).toBe(true);
    expect(w.object.children.length).toBe(0);
    w.dispose();
  });

  it("is in the part's bounds, at the pose the table is in", () => {
    const m = tableAc();
    const s = new MachineScene(m.model);
    s.setWorkpiece([{ min: [0, 0, -20], max: [50, 40, 0] }]);
    for (const p of m.poses.slice(0, 4)) {
      s.setAxes(p.axes);
      const b = s.partBounds();
      for (const f of [[0, 0, 0], [1, 1, 1], [1, 0, 1], [0, 1, 0]] as [number, number, number][]) {
        expect(b.distanceToPoint(corner(s, 0, f))).toBeLessThanOrEqual(1e-9);
      }
      const size = b.getSize(new THREE.Vector3());
      expect(size.length()).toBeLessThanOrEqual(Math.hypot(50, 40, 20) * Math.sqrt(3) + 1e-6);
    }
    s.setWorkpiece([]);
    expect(s.partBounds().isEmpty()).toBe(true);
    s.dispose();
  });
});

describe("the part's bounds", () => {
  it("hold the path, the trace and the work zero, not the machine", () => {
    const s = new MachineScene(tableAc().model);
    expect(s.partBounds().isEmpty()).toBe(true);
    s.setPath(new Float32Array([0, 0, 0, 40, 0, 0, 40, 40, 0]));
    s.addTrace(0, 0, 50);
    s.setWorkZero(-10, -10, 0);
    const b = s.partBounds();
    const table = s.rig.tableFrame.matrixWorld;
    for (const p of [
      [40, 40, 0],
      [0, 0, 50],
      [-10, -10, 0],
    ]) {
      expect(b.containsPoint(new THREE.Vector3(...p).applyMatrix4(table))).toBe(true);
    }
    const size = b.getSize(new THREE.Vector3());
    expect(Math.max(size.x, size.y, size.z)).toBeLessThanOrEqual(60 + 1e-6);
    const machine = s.bounds(true).getSize(new THREE.Vector3());
    expect(size.length()).toBeLessThan(machine.length());
    s.dispose();
  });

  it("give a single point a view of its own", () => {
    const s = new MachineScene(tableAc().model);
    s.setWorkZero(1, 2, 3);
    const size = s.partBounds().getSize(new THREE.Vector3());
    expect(size.toArray()).toEqual([2 * MIN_PART_RADIUS, 2 * MIN_PART_RADIUS, 2 * MIN_PART_RADIUS]);
    s.dispose();
  });
});

describe("the fit-to-part key", () => {
  const key = (key: string, target: unknown = null, mods = {}) => ({ key, ctrlKey: false, metaKey: false, altKey: false, target, ...mods }) as unknown as KeyboardEvent;
  it("is F alone, outside fields", () => {
    expect(isFitKey(key("f"))).toBe(true);
    expect(isFitKey(key("F", { tagName: "DIV" }))).toBe(true);
    expect(isFitKey(key("g"))).toBe(false);
    expect(isFitKey(key("f", null, { ctrlKey: true }))).toBe(false);
    expect(isFitKey(key("f", { tagName: "TEXTAREA" }))).toBe(false);
    expect(isFitKey(key("f", { tagName: "INPUT" }))).toBe(false);
    expect(isFitKey(key("f", { tagName: "DIV", isContentEditable: true }))).toBe(false);
  });
});

describe("the tool tip's dot", () => {
  it("sits on the drawn tip at every pose and keeps its size in pixels", () => {
    const m = tableAc();
    const s = new MachineScene(m.model);
    const material = s.tipPoint.material as THREE.PointsMaterial;
    expect(material.sizeAttenuation).toBe(false);
    for (const p of m.poses.slice(0, 4)) {
      s.setAxes(p.axes);
      s.setToolLength(p.tool_length);
      const tip = s.rig.tip.getWorldPosition(new THREE.Vector3());
      expect(s.tipPoint.position.distanceTo(tip)).toBeLessThanOrEqual(1e-9);
      expect(s.tipPoint.position.distanceTo(new THREE.Vector3(...p.tip_machine))).toBeLessThanOrEqual(1e-9);
    }
    s.dispose();
  });
});
