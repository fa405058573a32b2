// The modal state: the G code of each group, F S T H D, and the 5-axis functions in force.
import { useEffect, useState } from "preact/hooks";
import { api, must, type Schemas } from "../api/client";
import { modalFeed } from "./units";

const FIVE_AXIS: Record<string, string> = {
  "G43.4": "TCP type 1",
  "G43.5": "TCP type 2",
  "G68.2": "tilted plane",
  "G68.3": "tilted plane (tool axis)",
  "G68.4": "tilted plane (incremental)",
  "G54.4": "setting error comp.",
};

/// The modal state of the block executing, read again at every `tick` (a run state or line
/// change): the modal panel shows it, and the readout takes its unit from it (G20/G21).
export function useModal(id: string, tick: unknown): Schemas["ModalState"] | null {
  const [modal, setModal] = useState<Schemas["ModalState"] | null>(null);
  useEffect(() => {
    let gone = false;
    must(api.GET("/api/v1/controllers/{id}/modal", { params: { path: { id } } })).then((m) => !gone && setModal(m), () => {});
    return () => {
      gone = true;
    };
  }, [id, tick]);
  return modal;
}

export function Modal({ modal }: { modal: Schemas["ModalState"] | null }) {
  if (!modal) return <div class="panel-box modal">…</div>;
  const codes = Object.values(modal.groups);
  const active = codes.filter((c) => FIVE_AXIS[c]);
  const feed = modalFeed(modal);
  return (
    <div class="panel-box modal">
      <div class="gcodes">
        {Object.entries(modal.groups).map(([g, code]) => (
          <span key={g} class={`g ${FIVE_AXIS[code] ? "hot" : ""}`} title={`group ${g}`}>
            {code}
          </span>
        ))}
      </div>
      <div class="words">
        <span class="modal-f">
          F {feed.text} <span class="unit">{feed.unit}</span>
        </span> <span>S {modal.s}</span> <span>T {modal.t}</span> <span>spindle T {modal.spindle_tool}</span>{" "}
        <span>H {modal.h}</span> <span>D {modal.d}</span>
      </div>
      <div class="five">
        {active.length ? active.map((c) => <span class="badge on">{`${c} ${FIVE_AXIS[c]}`}</span>) : <span class="badge">no 5-axis function active</span>}
      </div>
    </div>
  );
}
