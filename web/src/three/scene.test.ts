import * as THREE from "three";
import { describe, expect, it } from "vitest";
import { fixture } from "./fixtures/fixture";
import { CUTTING_TRACE_COLOR, MachineScene, TIP_TRACE_COLOR } from "./scene";
import { MAIN_CHAIN, chainView } from "./chain";
import { Kinematics } from "./kinematics";
import { PathLine, ProgrammedLine, STRETCH_MAX, TraceLine, TraceStretches } from "./trace";
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

describe("the scene draws the mechanism chain the machine executes in", () => {
  const chained = fixture.machines.filter((m) => m.chains?.length);

  for (const m of chained) {
    for (const c of m.chains!) {
      it(`${m.source} chain ${c.chain.set},${c.chain.sub}: the drawn tool tip is that chain's FK tip`, () => {
        const s = new MachineScene(m.model);
        expect(s.setChain(c.chain)).toBe(true);
        expect(s.chain).toEqual(c.chain);
        for (const p of c.poses) {
          s.setAxes(p.axes);
          s.setToolLength(p.tool_length);
          const where = `${m.source} ${c.chain.set},${c.chain.sub} ${JSON.stringify(p.axes)} L${p.tool_length}`;
          expect(diff(s.rig.tip.getWorldPosition(new THREE.Vector3()), p.tip_machine), where).toBeLessThanOrEqual(1e-9);
          // The drawn tool points along the chain's tool direction (tip → holder).
          if (p.tool_length > 0) {
            const tool = s.rig.root.getObjectByName("tool")!;
            const holder = tool.localToWorld(new THREE.Vector3(0, 0, 0));
            const tip = tool.localToWorld(new THREE.Vector3(0, 1, 0));
            const dir = holder.sub(tip).normalize();
            expect(diff(dir, p.tool_machine), `${where} tool direction`).toBeLessThanOrEqual(1e-6);
          }
          expect(diff(s.rig.tableFrame.localToWorld(new THREE.Vector3(...p.tip)), p.tip_machine), `${where} table frame`).toBeLessThanOrEqual(1e-9);
        }
        s.dispose();
      });
    }
  }

  it("a switch rebuilds the rig at the current pose with the chain's joints; path and traces carry over", () => {
    const m = fixture.machines.find((x) => x.source === "library/head-exchange-bc-ac.json")!;
    const s = new MachineScene(m.model);
    let changes = 0;
    s.onChange = () => changes++;
    s.setPath(new Float32Array([0, 0, 0, 10, 0, 0]), [false, false]);
    s.addTrace(1, 2, 3);
    s.addCutting(4, 5, 6);
    const axes = { X: 10, Y: -20, Z: 30, A: 30, B: -45, C: 60 };
    s.setAxes(axes);
    s.setToolLength(80);
    const set1 = s.rig;
    expect([...set1.joints.keys()].sort()).toEqual(["B", "C"]);
    changes = 0;

    expect(s.setChain({ set: 2, sub: 1 })).toBe(true);
    expect(changes).toBe(1);
    const set2 = s.rig;
    expect(set2).not.toBe(set1);
    expect([...set2.joints.keys()].sort()).toEqual(["A", "C"]);
    expect(s.scene.children).toContain(set2.root);
    expect(s.scene.children).not.toContain(set1.root);
    // Posed at once: the axes and tool length given before the switch, through set 2's chain.
    const want = new Kinematics(chainView(m.model, { set: 2, sub: 1 })!).forward(axes, 80).tipMachine;
    expect(diff(set2.tip.getWorldPosition(new THREE.Vector3()), want)).toBeLessThanOrEqual(1e-9);
    for (const o of [s.path.object, s.programmed.object, s.trace.object, s.cutting.object, s.cuttingMarker]) {
      expect(o.parent).toBe(set2.tableFrame);
    }
    expect(s.trace.length).toBe(1);
    expect(s.cutting.length).toBe(1);
    expect(s.path.object.geometry.getAttribute("position").count).toBe(2);

    // The same chain again, or one the machine does not describe: nothing changes.
    expect(s.setChain({ set: 2, sub: 1 })).toBe(false);
    expect(s.setChain({ set: 3, sub: 1 })).toBe(false);
    expect(s.rig).toBe(set2);
    expect(changes).toBe(1);

    expect(s.setChain(MAIN_CHAIN)).toBe(true);
    expect([...s.rig.joints.keys()].sort()).toEqual(["B", "C"]);
    const back = new Kinematics(m.model).forward(axes, 80).tipMachine;
    expect(diff(s.rig.tip.getWorldPosition(new THREE.Vector3()), back)).toBeLessThanOrEqual(1e-9);
    s.dispose();
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

describe("cutting point trace", () => {
  const lineColor = (o: THREE.Object3D) => ((o as THREE.Line).material as THREE.LineBasicMaterial).color.getHex();

  it("is drawn in the table frame group, in its own colour, with a marker at the latest point", () => {
    for (const m of fixture.machines) {
      const s = new MachineScene(m.model);
      const kin = s.rig.kinematics;
      expect(s.cutting.object.parent).toBe(s.rig.tableFrame);
      expect(s.cuttingMarker.parent).toBe(s.rig.tableFrame);
      expect(s.cuttingMarker.visible).toBe(false);
      const pts: Vec3[] = [
        [12.5, -40.25, 3.75],
        [-100, 50.5, -20.125],
      ];
      for (const p of m.poses.slice(0, 4)) {
        s.setAxes(p.axes);
        for (const w of pts) {
          s.addCutting(...w);
          const line = s.cutting.lines[s.cutting.lines.length - 1];
          expect(line.object.parent).toBe(s.cutting.object);
          expect(lineColor(line.object)).toBe(CUTTING_TRACE_COLOR);
          const world = new THREE.Vector3(...line.point(line.length - 1)).applyMatrix4(line.object.matrixWorld);
          const where = `${m.source} ${JSON.stringify(p.axes)}`;
          expect(diff(world, kin.tableToMachine(w, p.axes)), where).toBeLessThanOrEqual(1e-9);
          expect(s.cuttingMarker.visible).toBe(true);
          const dot = s.cuttingMarker.getWorldPosition(new THREE.Vector3());
          expect(diff(dot, kin.tableToMachine(w, p.axes)), `${where} marker`).toBeLessThanOrEqual(1e-6);
        }
      }
      // The cutting points went to the cutting trace only.
      expect(s.trace.length).toBe(0);
      expect(s.cutting.length).toBe(2 * Math.min(4, m.poses.length));
      expect(s.cutting.lines.length).toBe(1); // one stretch: nothing ended it
      s.dispose();
    }
  });

  it("differs in colour from the tip trace, the path and the programmed path", () => {
    const s = new MachineScene(fixture.machines[0].model);
    expect(lineColor(s.trace.object)).toBe(TIP_TRACE_COLOR);
    for (const other of [TIP_TRACE_COLOR, PathLine.FEED.getHex(), PathLine.RAPID.getHex(), ProgrammedLine.COLOR.getHex()]) expect(CUTTING_TRACE_COLOR).not.toBe(other);
    s.dispose();
  });

  it("a position without a cutting point adds nothing, ends the stretch and hides the marker", () => {
    const s = new MachineScene(fixture.machines[0].model);
    let changes = 0;
    s.onChange = () => changes++;
    s.endCutting(); // nothing was open, nothing shown: no change
    expect(changes).toBe(0);
    expect(s.cutting.length).toBe(0);
    expect(s.cutting.lines.length).toBe(0);
    s.addCutting(0, 0, 0);
    s.addCutting(1, 0, 0);
    s.addCutting(1, 0, 0); // a repeat: nothing new, the marker already there
    expect(changes).toBe(2);
    s.endCutting();
    expect(changes).toBe(3); // the marker hid
    expect(s.cuttingMarker.visible).toBe(false);
    s.endCutting();
    expect(changes).toBe(3);
    expect(s.cutting.length).toBe(2);
    // The next stretch is a line of its own: nothing joins (1, 0, 0) to (5, 5, 5).
    s.addCutting(5, 5, 5);
    s.addCutting(6, 5, 5);
    expect(s.cutting.lines.length).toBe(2);
    expect(s.cutting.lines.map((l) => l.length)).toEqual([2, 2]);
    expect(s.cutting.lines[1].point(0)).toEqual([5, 5, 5]);
    s.flush();
    expect(s.cutting.lines.map((l) => l.object.geometry.drawRange.count)).toEqual([2, 2]);
    s.dispose();
  });

  it("clearTrace clears the tip trace and the cutting trace", () => {
    const s = new MachineScene(fixture.machines[0].model);
    s.addTrace(1, 2, 3);
    s.addTrace(2, 2, 3);
    s.addCutting(1, 2, 0);
    s.endCutting();
    s.addCutting(2, 2, 0);
    s.addCutting(3, 2, 0);
    expect(s.cutting.lines.length).toBe(2);
    s.clearTrace();
    s.flush();
    expect(s.trace.length).toBe(0);
    expect(s.trace.object.geometry.drawRange.count).toBe(0);
    expect(s.cutting.length).toBe(0);
    expect(s.cutting.lines.length).toBe(0);
    expect(s.cutting.object.children.length).toBe(0);
    // A point after the clear starts a new stretch.
    s.addCutting(4, 2, 0);
    expect(s.cutting.lines.length).toBe(1);
    expect(s.cutting.length).toBe(1);
    s.dispose();
  });

  it("keeps the newest points and stretches within its bounds", () => {
    const t = new TraceStretches(0x00ff00, 1000);
    for (let k = 0; k < 5; k++) {
      for (let i = 0; i < 300; i++) t.add(k, i, 0);
      t.end();
    }
    // 1,500 points in 5 stretches of 300: the two oldest dropped.
    expect(t.length).toBe(900);
    expect(t.lines.map((l) => l.point(0)[0])).toEqual([2, 3, 4]);
    expect(t.object.children.length).toBe(3);
    // One stretch longer than the cap halves itself as the tip trace does.
    for (let i = 0; i < 3000; i++) t.add(9, i, 1);
    expect(t.lines.length).toBe(1);
    expect(t.length).toBeLessThanOrEqual(1000);
    t.end();
    const u = new TraceStretches(0x00ff00);
    for (let k = 0; k < STRETCH_MAX + 10; k++) {
      u.add(k, 0, 0);
      u.add(k, 1, 0);
      u.end();
    }
    expect(u.lines.length).toBe(STRETCH_MAX);
    expect(u.lines[0].point(0)[0]).toBe(10);
    expect(u.length).toBe(2 * STRETCH_MAX);
    u.end(); // an empty stretch is never kept
    expect(u.lines.length).toBe(STRETCH_MAX);
    t.dispose();
    u.dispose();
  });
});
