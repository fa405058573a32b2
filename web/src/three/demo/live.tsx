// The 3D view on a real controller: creates one from a preset (?preset=table-ac), stores and
// starts a small 5-axis program (or ?id=… an existing controller, no program), draws its path
// and follows the position stream (axes, tool length, `tip_table` trace, the cutting point's
// trace under G43.8/G43.9). Serve the page with a dev server that proxies /api to `fivex serve`
// (README, "Looking at it").
import { render } from "preact";
import { useEffect, useState } from "preact/hooks";
import { View3D } from "../View3D";
import type { View3DHandle } from "../View3D";
import { traceFrame } from "../frameTrace";
import type { MachineModelInput } from "../model";
import type { ControllerMessage } from "../../api/client";

const q = new URLSearchParams(location.search);
const PROGRAM = `O0001
G90 G54 G00 X0 Y0 Z100
G43.4 H1
G00 X-60 Y-40 Z30
G01 Z5 F3000
#1 = 0
WHILE [#1 LE 360] DO1
X[60*COS[#1]] Y[40*SIN[#1]] Z[5+#1/60] ${q.get("rot") ?? "A"}[30*SIN[#1]] C[#1] F6000
#1 = #1 + 5
END1
G49
G00 Z100
M30
`;


function Live() {
  const [machine, setMachine] = useState<MachineModelInput | null>(null);
  const [axes, setAxes] = useState<Record<string, number>>({});
  const [L, setL] = useState(0);
  const [path, setPath] = useState<{ xyz: Float32Array; rapid: boolean[] } | null>(null);
  const [handle, setHandle] = useState<View3DHandle | null>(null);
  const [id, setId] = useState<string | null>(q.get("id"));
  const [frames, setFrames] = useState(0);
  const [status, setStatus] = useState("starting");

  useEffect(() => {
    (async () => {
      let cid = id;
      if (!cid) {
        const r = await fetch("/api/v1/controllers", {
          method: "POST",
          headers: { "content-type": "application/json" },
          body: JSON.stringify({ name: `live-3d-${Date.now()}`, preset: q.get("preset") ?? "table-ac" }),
        });
        cid = (await r.json()).id as string;
        await fetch(`/api/v1/controllers/${cid}/programs/1`, { method: "PUT", headers: { "content-type": "text/plain" }, body: PROGRAM });
        const p = await (await fetch(`/api/v1/controllers/${cid}/programs/1/path`)).json();
        if (p.alarm) setStatus(`path alarm ${JSON.stringify(p.alarm)}`);
        setPath({ xyz: new Float32Array(p.xyz), rapid: p.rapid });
        setId(cid);
      }
      setMachine(await (await fetch(`/api/v1/controllers/${cid}/machine`)).json());
    })().catch((e) => setStatus(String(e)));
  }, []);

  useEffect(() => {
    if (!id || !handle) return;
    const ws = new WebSocket(`${location.origin.replace(/^http/, "ws")}/api/v1/controllers/${id}/stream?rate=60`);
    let n = 0;
    ws.onmessage = (ev) => {
      const m = JSON.parse(ev.data) as ControllerMessage;
      if (m.type !== "position") return;
      setAxes(m.machine);
      setL(m.tool_length);
      traceFrame(handle, m);
      setFrames(++n);
    };
    ws.onopen = async () => {
      if (!q.get("id")) {
        const r = await fetch(`/api/v1/controllers/${id}/cycle-start`, {
          method: "POST",
          headers: { "content-type": "application/json" },
          body: JSON.stringify({ program: 1 }),
        });
        setStatus(`cycle-start ${r.status}`);
      }
    };
    return () => ws.close();
  }, [id, handle]);

  (window as unknown as { live: unknown }).live = { frames, status, handle };
  return (
    <div style={{ height: "100%", display: "flex", flexDirection: "column" }}>
      <div style={{ padding: "4px" }}>
        {status} · frames {frames} · {Object.entries(axes).map(([k, v]) => `${k}${v.toFixed(3)}`).join(" ")} · L{L}
      </div>
      <div style={{ flex: "1" }}>
        {machine && <View3D machine={machine} axes={axes} toolLength={L} path={path?.xyz} pathRapid={path?.rapid} onReady={setHandle} />}
      </div>
    </div>
  );
}

render(<Live />, document.getElementById("app")!);
