import * as THREE from "three";
import { describe, expect, it } from "vitest";
import { fixture } from "./fixtures/fixture";
import { MachineScene } from "./scene";
import { PathLine, ProgrammedLine, TraceLine } from "./trace";
import type { Vec3 } from "./model";

const diff = (a: THREE.Vector3, b: readonly number[]) =>
  Math.max(Math.abs(a.x - b[0]), Math.abs(a.y - b[1]), Math.abs(a.z - b[2]));

describe("the scene graph is the kinematic chain", () => {
  for (const m of fixture.machines) {
    it(`${m.source}: the drawn tool tip is the FK tip`, () => {
      const s = new MachineScene(m.model);
      for (const p of m.poses) {
        s.setAxes(p.axes);
        s.setToolLength(p.tool_length);
        const tip = s.rig.tip.getWorldPosition(new THREE.Vector3());
        const where = `${m.source} ${JSON.stringify(p.axes)} L${p.tool_length}`;
        expect(diff(tip, p.tip_machine), where).toBeLessThanOrEqual(1e-9);
        // The tool ends at the tip: the far end of the drawn tool cylinder.
        const tool = s.rig.root.getObjectByName("tool")!;
        if (p.tool_length > 0) {
          const end = tool.localToWorld(new THREE.Vector3(0, 1, 0));
          expect(diff(end, p.tip_machine), `${where} tool end`).toBeLessThanOrEqual(1e-6);
        }
        // The table frame's origin and axes are where the table motion puts them: the FK tip
        // in the table frame maps to the machine tip.
        const w = s.rig.tableFrame.localToWorld(new THREE.Vector3(...p.tip));
        expect(diff(w, p.tip_machine), `${where} table frame`).toBeLessThanOrEqual(1e-9);
      }
      s.dispose();
    });

    it(`${m.source}: a trace point sits where its table-frame point maps to`, () => {
      const s = new MachineScene(m.model);
      const kin = s.rig.kinematics;
      // Points exactly representable in Float32, so the check can be exact to rounding.
      const pts: Vec3[] = [
        [12.5, -40.25, 3.75],
        [-100, 50.5, -20.125],
      ];
      for (const p of m.poses.slice(0, 6)) {
        s.setAxes(p.axes);
        for (const w of pts) {
          s.addTrace(...w);
          const i = s.trace.length - 1;
          const stored = new THREE.Vector3(...s.trace.point(i));
          const world = stored.applyMatrix4(s.trace.object.matrixWorld);
          expect(diff(world, kin.tableToMachine(w, p.axes))).toBeLessThanOrEqual(1e-9);
        }
        // The FK tip in the table frame, added to the trace, lands on the drawn tool tip
        // (to Float32 storage precision).
        s.setToolLength(p.tool_length);
        s.addTrace(...p.tip);
        const world = new THREE.Vector3(...s.trace.point(s.trace.length - 1)).applyMatrix4(s.trace.object.matrixWorld);
        expect(diff(world, p.tip_machine)).toBeLessThanOrEqual(1e-3);
      }
      // addTraceAtTip: the FK tip of the current pose, drawn on the tip marker.
      s.addTraceAtTip();
      const at = new THREE.Vector3(...s.trace.point(s.trace.length - 1)).applyMatrix4(s.trace.object.matrixWorld);
      expect(at.distanceTo(s.rig.tip.getWorldPosition(new THREE.Vector3()))).toBeLessThanOrEqual(1e-3);
      expect(s.trace.object.parent).toBe(s.rig.tableFrame);
      expect(s.path.object.parent).toBe(s.rig.tableFrame);
      s.dispose();
    });
  }

  it("every rotary axis has a joint group and an axis line", () => {
    for (const m of fixture.machines) {
      const s = new MachineScene(m.model);
      for (const r of s.rig.model.rotary) {
        expect(s.rig.joints.get(r.axis), `${m.source} ${r.axis}`).toBeDefined();
        expect(s.rig.root.getObjectByName(`axis-line-${r.axis}`), `${m.source} ${r.axis}`).toBeDefined();
      }
      const b = s.bounds();
      expect(b.isEmpty()).toBe(false);
      s.dispose();
    }
  });
});

describe("path", () => {
  it("is one geometry of segments, rapids coloured apart, riding with the table", () => {
    const m = fixture.machines.find((x) => x.source === "table-ac")!;
    const s = new MachineScene(m.model);
    s.setPath(new Float32Array([0, 0, 0, 10, 0, 0, 10, 10, 0]), [false, true, false]);
    const g = s.path.object.geometry;
    expect(g.getAttribute("position").count).toBe(4);
    const col = g.getAttribute("color") as THREE.BufferAttribute;
    expect(col.getX(0)).toBeCloseTo(PathLine.RAPID.r, 6); // the move to point 1 is a rapid
    expect(col.getX(2)).toBeCloseTo(PathLine.FEED.r, 6);
    s.setAxes({ A: 90, C: 30 });
    const world = new THREE.Vector3().fromBufferAttribute(g.getAttribute("position") as THREE.BufferAttribute, 1).applyMatrix4(s.path.object.matrixWorld);
    const want = s.rig.kinematics.tableToMachine([10, 0, 0], { A: 90, C: 30 });
    expect(diff(world, want)).toBeLessThanOrEqual(1e-9);
    expect(s.bounds().isEmpty()).toBe(false);
    s.dispose();
  });
});

describe("programmed path", () => {
  it("is drawn dashed in its own colour beside the compensated path, and cleared with null", () => {
    const m = fixture.machines.find((x) => x.source === "table-ac")!;
    const s = new MachineScene(m.model);
    expect(s.programmed.segments).toBe(0);
    s.setPath(new Float32Array([0, -5, 0, 45, -5, 0, 45, 45, 0]), [false, false, false]);
    s.setProgrammedPath(new Float32Array([0, 0, 0, 40, 0, 0, 40, 40, 0]));
    expect(s.programmed.segments).toBe(2);
    const material = s.programmed.object.material as THREE.LineDashedMaterial;
    expect(material.type).toBe("LineDashedMaterial");
    expect(material.color.getHex()).toBe(ProgrammedLine.COLOR.getHex());
    expect(material.color.getHex()).not.toBe(PathLine.FEED.getHex());
    expect(s.programmed.object.geometry.getAttribute("lineDistance")).toBeTruthy(); // dashes need them
    expect(s.programmed.object.parent).toBe(s.path.object.parent); // rides with the table too
    s.setProgrammedPath(null);
    expect(s.programmed.segments).toBe(0);
    s.dispose();
  });
});

describe("trace buffer", () => {
  it("holds 100,000+ points, uploading only new ranges", () => {
    const t = new TraceLine();
    const first = t.object.geometry;
    for (let i = 0; i < 150_000; i++) t.add(i, Math.sin(i), 0);
    t.flush();
    expect(t.length).toBe(150_000);
    expect(t.object.geometry.drawRange.count).toBe(150_000);
    expect(t.object.geometry).not.toBe(first); // grew by doubling
    expect(t.capacity).toBe(262_144);
    const attr = t.object.geometry.getAttribute("position") as THREE.BufferAttribute;
    attr.clearUpdateRanges(); // what the renderer does after uploading
    for (let i = 0; i < 10; i++) t.add(1, 2, i);
    t.flush();
    expect(attr.updateRanges).toEqual([{ start: 3 * 150_000, count: 30 }]);
    expect(t.point(150_005)).toEqual([1, 2, 5]);
    t.clear();
    expect(t.length).toBe(0);
    t.dispose();
  });

  it("skips a repeat of the last point (a machine standing still draws nothing new)", () => {
    const t = new TraceLine();
    expect(t.add(1, 2, 3)).toBe(true);
    expect(t.add(1, 2, 3)).toBe(false);
    expect(t.add(1, 2, 3.5)).toBe(true);
    expect(t.length).toBe(2);
  });

  it("keeps the newest half when the cap is reached", () => {
    const t = new TraceLine(0xffffff, 1024, 256);
    for (let i = 0; i < 1025; i++) t.add(i, 0, 0);
    expect(t.capacity).toBe(1024);
    expect(t.length).toBe(513);
    expect(t.point(0)[0]).toBe(512);
    expect(t.point(512)[0]).toBe(1024);
    t.flush();
    expect(t.object.geometry.drawRange.count).toBe(513);
  });

  it("adds 100,000 points quickly", () => {
    const t = new TraceLine();
    const start = performance.now();
    for (let i = 0; i < 100_000; i++) {
      t.add(i * 0.01, 0, 0);
      if (i % 100 === 0) t.flush();
    }
    expect(performance.now() - start).toBeLessThan(500);
  });
});
