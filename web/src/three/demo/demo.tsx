// A stand-alone page for looking at the 3D view (`npm run dev`, then
// /src/three/demo/index.html?machine=table-ac&A=30&C=45&L=100&view=iso). The preset models come
// from the kinematics fixture; a spiral path and a trace are drawn on the table.
import { render } from "preact";
import { useEffect, useState } from "preact/hooks";
import { fixture } from "../fixtures/fixture";
import { View3D } from "../View3D";
import type { View3DHandle } from "../View3D";

const q = new URLSearchParams(location.search);
const source = q.get("machine") ?? "head-bc";
const machine = (fixture.machines.find((m) => m.source === source) ?? fixture.machines[0]).model;
const axes: Record<string, number> = {};
for (const a of machine.axes) axes[a.name] = Number(q.get(a.name) ?? 0);
const L = Number(q.get("L") ?? 100);

const path = new Float32Array(3 * 400);
for (let i = 0; i < 400; i++) {
  const t = (i / 400) * Math.PI * 6;
  path.set([Math.cos(t) * (20 + 8 * t), Math.sin(t) * (20 + 8 * t), 10 + i * 0.1], 3 * i);
}

// The first 20 moves are rapids (drawn dim orange).
const rapid = Array.from({ length: 400 }, (_, i) => i < 20);

function Demo() {
  const [handle, setHandle] = useState<View3DHandle | null>(null);
  const [a, setA] = useState(axes);
  useEffect(() => {
    if (!handle) return;
    const pts = new Float32Array(3 * 120_000);
    for (let i = 0; i < 120_000; i++) {
      const t = (i / 120_000) * Math.PI * 2;
      pts.set([Math.cos(t) * 60, Math.sin(t) * 60, 5], 3 * i);
    }
    handle.addTracePoints(pts);
    if (q.get("view")) handle.setView(q.get("view") as "iso");
    const zoom = Number(q.get("zoom") ?? 1);
    if (zoom !== 1) {
      // Dolly toward the tool tip.
      const v = handle.view;
      const tip = v.machineScene.rig.tip.getWorldPosition(v.controls.target.clone());
      v.controls.target.copy(tip);
      v.camera.position.sub(tip).multiplyScalar(1 / zoom).add(tip);
      v.controls.update();
      v.requestRender();
    }
    (window as unknown as { demoHandle: View3DHandle }).demoHandle = handle;
    (window as unknown as { demoReady: boolean }).demoReady = true;
  }, [handle]);
  useEffect(() => {
    if (!q.get("animate")) return;
    let t = 0;
    const id = setInterval(() => {
      t += 1;
      const next = { ...a };
      for (const x of machine.axes) if (x.kind === "rotary") next[x.name] = 40 * Math.sin(t / 30);
      setA(next);
    }, 30);
    return () => clearInterval(id);
  }, []);
  return (
    <div style={{ height: "100%" }}>
      <View3D machine={machine} axes={a} toolLength={L} path={path} pathRapid={rapid} onReady={setHandle} />
    </div>
  );
}

render(<Demo />, document.getElementById("app")!);
