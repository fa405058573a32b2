// Syntec's tilted working plane teach screen (Offset/Setting, manual §3.3–§3.4): F1 latches the
// tool tip into P1/P2/P3, a guidance mode with its typed values teaches the plane, F2 runs the
// G68.2 block it gives in MDI (after G49, which G68.2 needs), F8 runs G69. Shown for Syntec
// controllers only; everything goes through `/controllers/{id}/teach…` (docs/api.md, "Teach").
import { useEffect, useState } from "preact/hooks";
import { api, must, errorText, type Schemas, type Status } from "../api/client";
import type { Act } from "./useController";

import { SLOTS, teachRequest, type Mode, type Typed } from "./teachRequest";

const MODES: [Mode, string][] = [
  ["three_points", "three points"],
  ["tool_direction", "tool direction"],
  ["euler", "Euler angle"],
  ["two_vectors", "2 vectors"],
];

const fmt = (v: number[]) => v.map((x) => x.toFixed(3)).join(", ");

export function Teach({ status, run, onError }: { status: Status; run: Act; onError: (e: string | null) => void }) {
  const id = status.id;
  const [screen, setScreen] = useState<Schemas["TeachState"] | null>(null);
  const [mode, setMode] = useState<Mode>("three_points");
  const [typed, setTyped] = useState<Typed>({});
  const [plane, setPlane] = useState<Schemas["TaughtPlane"] | null>(null);
  const [failed, setFailed] = useState<string | null>(null);
  const path = { params: { path: { id } } };
  const reload = () => must(api.GET("/api/v1/controllers/{id}/teach", path)).then(setScreen, (e) => onError(errorText(e)));
  // Again whenever the controller's state may have changed what F1 allows, and once a second
  // (the screen's state display: an MDI block may change the modal state without a status change
  // the page sees).
  useEffect(() => {
    reload();
  }, [id, status.run_state, status.mode, status.line]);
  useEffect(() => {
    const every = setInterval(() => must(api.GET("/api/v1/controllers/{id}/teach", path)).then(setScreen, () => {}), 1000);
    return () => clearInterval(every);
  }, [id]);

  const act = async (call: () => Promise<unknown>) => {
    onError(null);
    try {
      await call();
    } catch (e) {
      onError(errorText(e));
    }
    await reload();
  };
  const latch = (slot: string) => act(() => must(api.POST("/api/v1/controllers/{id}/teach/points/{slot}", { params: { path: { id, slot } } })));
  const clear = () => act(() => must(api.DELETE("/api/v1/controllers/{id}/teach/points", path)).then(() => setPlane(null)));
  const teach = async () => {
    setFailed(null);
    setPlane(null);
    try {
      setPlane(await must(api.POST("/api/v1/controllers/{id}/teach/plane", { ...path, body: teachRequest(mode, typed) })));
    } catch (e) {
      setFailed(errorText(e));
    }
  };
  const mdi = (text: string) => act(() => run(() => api.POST("/api/v1/controllers/{id}/mdi", { ...path, body: { text } })));

  const points = new Map((screen?.points ?? []).map((p) => [p.slot, p]));
  const field = (name: keyof Typed, label: string, placeholder: string) => (
    <label>
      {label}{" "}
      <input name={`teach-${name}`} size={name === "x" || name === "z" ? 14 : 7} placeholder={placeholder} value={typed[name] ?? ""} onInput={(e) => setTyped({ ...typed, [name]: e.currentTarget.value })} />
    </label>
  );
  return (
    <div class="panel-box teach">
      <h3>Tilted plane teach</h3>
      <div class="teach-modes">
        {MODES.map(([m, label]) => (
          <label key={m}>
            <input type="radio" name="teach-mode" value={m} checked={mode === m} onChange={() => (setMode(m), setPlane(null), setFailed(null))} /> {label}
          </label>
        ))}
      </div>
      <table class="teach-points">
        <tbody>
          {SLOTS[mode].map((slot) => {
            const p = points.get(slot);
            return (
              <tr key={slot} data-slot={slot}>
                <th>{slot.toUpperCase()}</th>
                <td class="num">{p ? fmt(p.point) : "—"}</td>
                <td class="num tool">{p && mode === "tool_direction" ? `tool ${fmt(p.tool)}` : ""}</td>
                <td>
                  <button disabled={!!screen?.latch_refused} title={screen?.latch_refused ?? "F1 Latch G54 Coordinate"} onClick={() => latch(slot)}>
                    F1 latch
                  </button>
                </td>
              </tr>
            );
          })}
        </tbody>
      </table>
      {screen?.latch_refused && <p class="hint teach-refused">{screen.latch_refused}</p>}
      <div class="teach-values">
        {mode === "tool_direction" && field("i", "I", "0")}
        {mode === "euler" && (
          <>
            {field("i", "I", "0")} {field("j", "J", "0")} {field("k", "K", "0")}
          </>
        )}
        {mode === "two_vectors" && (
          <>
            {field("x", "Xc", "1, 0, 0")} {field("z", "Zc", "0, 0, 1")}
          </>
        )}
      </div>
      <div class="teach-actions">
        <button class="primary" onClick={teach}>
          teach
        </button>
        <button disabled={!plane} title="F2 Teach Finish: G49, then the G68.2 block, in MDI" onClick={() => plane && mdi(`G49\n${plane.block}`)}>
          F2 finish
        </button>
        <button title="F8 Cancel Tilt Work Plane: G69 in MDI" onClick={() => mdi("G69")}>
          F8 G69
        </button>
        <button onClick={clear}>clear</button>
      </div>
      {failed && (
        <p class="error teach-failed" role="alert">
          {failed}
        </p>
      )}
      {plane && (
        <div class="teach-result">
          <code class="teach-block">{plane.block}</code>
          <div class="teach-axes">
            Xc {fmt(plane.x)} · Yc {fmt(plane.y)} · Zc {fmt(plane.z)}
          </div>
        </div>
      )}
    </div>
  );
}
