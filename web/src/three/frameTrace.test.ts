// Position frames to the 3D view's traces: the tip always, the cutting point (in the table frame)
// only from frames that carry one.
import * as THREE from "three";
import { describe, expect, it } from "vitest";
import { fixture } from "./fixtures/fixture";
import { cuttingInTable, traceFrame, type FrameTraceTarget } from "./frameTrace";
import { MachineScene } from "./scene";

/** The handle View3D gives, on a scene without a renderer. */
const target = (s: MachineScene): FrameTraceTarget => ({
  addTrace: (x, y, z) => s.addTrace(x, y, z),
  addCuttingTrace: (x, y, z) => s.addCutting(x, y, z),
  endCuttingTrace: () => s.endCutting(),
});

// Workpiece system = table frame + (−10, 20, −30) (a G54 offset): tip and cutting are in it.
const frame = (tipTable: number[], cutting?: number[] | null) => ({
  tip: [tipTable[0] + 10, tipTable[1] - 20, tipTable[2] + 30],
  tip_table: tipTable,
  ...(cutting === undefined ? {} : { cutting }),
});

describe("traceFrame", () => {
  it("puts the cutting point in the table frame: cutting + (tip_table − tip)", () => {
    expect(cuttingInTable(frame([1, 2, 3], [15.5, -16, 30]))).toEqual([5.5, 4, 0]);
    expect(cuttingInTable(frame([1, 2, 3]))).toBeNull();
    expect(cuttingInTable(frame([1, 2, 3], null))).toBeNull();
    expect(cuttingInTable(frame([1, 2, 3], []))).toBeNull();
  });

  it("adds the cutting point to the cutting trace in the table frame group; a frame without one adds nothing", () => {
    const m = fixture.machines.find((x) => x.source === "head-bc")!;
    const s = new MachineScene(m.model);
    const t = target(s);
    traceFrame(t, frame([0, 0, 100]));
    expect(s.trace.length).toBe(1);
    expect(s.cutting.length).toBe(0);
    expect(s.cuttingMarker.visible).toBe(false);

    traceFrame(t, frame([5, 0, 99], [10, -20, 130])); // cutting point (0, 0, 100) in the table frame
    traceFrame(t, frame([5, 1, 98], [10, -19, 129]));
    expect(s.trace.length).toBe(3);
    expect(s.cutting.length).toBe(2);
    const line = s.cutting.lines[0];
    expect(line.point(0)).toEqual([0, 0, 100]);
    expect(line.point(1)).toEqual([0, 1, 99]);
    expect(line.object.parent).toBe(s.cutting.object);
    expect(s.cutting.object.parent).toBe(s.rig.tableFrame);
    const world = new THREE.Vector3(...line.point(1)).applyMatrix4(line.object.matrixWorld);
    expect(world.distanceTo(new THREE.Vector3(...s.rig.kinematics.tableToMachine([0, 1, 99], s.getAxes())))).toBeLessThanOrEqual(1e-9);
    expect(s.cuttingMarker.visible).toBe(true);
    expect(s.cuttingMarker.position.toArray()).toEqual([0, 1, 99]);

    // Frames without `cutting` (absent or null): the tip trace grows, the cutting trace does not.
    traceFrame(t, frame([5, 2, 97]));
    traceFrame(t, frame([5, 3, 96], null));
    expect(s.trace.length).toBe(5);
    expect(s.cutting.length).toBe(2);
    expect(s.cuttingMarker.visible).toBe(false);

    // Cutting again: a new stretch, not joined to the last one.
    traceFrame(t, frame([5, 9, 90], [10, -11, 120]));
    expect(s.cutting.lines.length).toBe(2);
    expect(s.cutting.lines[1].point(0)).toEqual([0, 9, 90]);
    s.dispose();
  });
});
