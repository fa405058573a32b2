// MachineView with an injected renderer and stand-in DOM objects: render on demand, coalesced.
import * as THREE from "three";
import { afterEach, beforeEach, describe, expect, it } from "vitest";
import { fixture } from "./fixtures/fixture";
import { MachineView } from "./scene";
import type { RendererLike } from "./scene";

const noop = () => {};
let queue: FrameRequestCallback[] = [];
const g = globalThis as unknown as Record<string, unknown>;

beforeEach(() => {
  queue = [];
  g.requestAnimationFrame = (f: FrameRequestCallback) => queue.push(f);
  g.cancelAnimationFrame = noop;
});
afterEach(() => {
  delete g.requestAnimationFrame;
  delete g.cancelAnimationFrame;
});

function runFrames() {
  const q = queue;
  queue = [];
  for (const f of q) f(0);
}

function fakes() {
  const doc = { addEventListener: noop, removeEventListener: noop };
  let removed = false;
  const canvas = {
    style: {} as Record<string, string>,
    addEventListener: noop,
    removeEventListener: noop,
    ownerDocument: doc,
    remove: () => (removed = true),
  } as unknown as HTMLCanvasElement;
  const calls: { renders: number; size: [number, number] } = { renders: 0, size: [0, 0] };
  const renderer: RendererLike = {
    domElement: canvas,
    setPixelRatio: noop,
    setSize: (w, h) => (calls.size = [w, h]),
    render: (scene, camera) => {
      expect(scene).toBeInstanceOf(THREE.Scene);
      expect(camera.up.z).toBe(1); // Z up
      calls.renders++;
    },
    dispose: noop,
  };
  const container = { clientWidth: 800, clientHeight: 500, appendChild: noop } as unknown as HTMLElement;
  return { renderer, container, calls, removed: () => removed };
}

describe("MachineView", () => {
  it("renders only when something changed, one frame per animation frame", () => {
    const f = fakes();
    const model = fixture.machines.find((m) => m.source === "table-ac")!.model;
    const v = new MachineView(f.container, model, { createRenderer: () => f.renderer });
    expect(f.calls.size).toEqual([800, 500]);
    runFrames();
    expect(f.calls.renders).toBe(1);
    runFrames();
    expect(f.calls.renders).toBe(1); // nothing changed: no frame

    v.setAxes({ X: 0, A: 0 }); // the same values
    runFrames();
    expect(f.calls.renders).toBe(1);

    for (let i = 1; i <= 50; i++) {
      v.setAxes({ A: i, C: 2 * i });
      v.addTrace(i, 0, 0);
    }
    expect(queue.length).toBe(1); // coalesced
    runFrames();
    expect(f.calls.renders).toBe(2);
    expect(v.machineScene.trace.object.geometry.drawRange.count).toBe(50);

    v.addTrace(50, 0, 0); // a repeat: nothing to draw
    runFrames();
    expect(f.calls.renders).toBe(2);

    v.setToolLength(120);
    v.setView("top");
    runFrames();
    expect(f.calls.renders).toBe(3);
    v.dispose();
    expect(f.removed()).toBe(true);
  });

  it("draws the cutting point's trace on demand; clear trace clears both traces", () => {
    const f = fakes();
    const model = fixture.machines.find((m) => m.source === "head-bc")!.model;
    const v = new MachineView(f.container, model, { createRenderer: () => f.renderer });
    runFrames();
    const base = f.calls.renders;
    v.endCutting(); // nothing to hide: no frame
    runFrames();
    expect(f.calls.renders).toBe(base);
    for (let i = 0; i < 20; i++) {
      v.addTrace(i, 5, 100);
      v.addCutting(i, 0, 100);
    }
    runFrames();
    expect(f.calls.renders).toBe(base + 1);
    const cutting = v.machineScene.cutting;
    expect(cutting.lines[0].object.geometry.drawRange.count).toBe(20);
    v.clearTrace();
    runFrames();
    expect(f.calls.renders).toBe(base + 2);
    expect(v.machineScene.trace.length).toBe(0);
    expect(cutting.length).toBe(0);
    expect(cutting.object.children.length).toBe(0);
    v.dispose();
  });

  it("draws a chain switch once, keeping the camera where it is", () => {
    const f = fakes();
    const model = fixture.machines.find((m) => m.source === "library/head-exchange-bc-ac.json")!.model;
    const v = new MachineView(f.container, model, { createRenderer: () => f.renderer });
    runFrames();
    const base = f.calls.renders;
    const camera = v.camera.position.clone();
    v.setChain({ set: 2, sub: 1 });
    v.setChain({ set: 2, sub: 1 }); // the same chain: nothing more to draw
    runFrames();
    expect(f.calls.renders).toBe(base + 1);
    expect(v.machineScene.chain).toEqual({ set: 2, sub: 1 });
    expect(v.machineScene.rig.joints.has("A")).toBe(true);
    expect(v.camera.position.equals(camera)).toBe(true);
    v.dispose();
  });

  it("fit frames the working zone from the current direction", () => {
    const f = fakes();
    const model = fixture.machines.find((m) => m.source === "head-bc")!.model;
    const v = new MachineView(f.container, model, { createRenderer: () => f.renderer });
    v.setView("front");
    const dir = v.camera.position.clone().sub(v.controls.target).normalize();
    expect(dir.y).toBeCloseTo(-1, 6);
    v.fit();
    const box = v.machineScene.bounds();
    expect(box.containsPoint(v.controls.target)).toBe(true);
    expect(v.camera.position.clone().sub(v.controls.target).normalize().y).toBeCloseTo(-1, 6);
    v.dispose();
  });
});
