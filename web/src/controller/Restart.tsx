// FANUC program restart in the program area: a small dialog that searches the selected program to
// a restart block (P or Q type, by N or line, the pass count), and the line that shows the restart
// under way until the return has ended (`restart.ts`; `docs/dialects.md`, "Program restart").
import { useState } from "preact/hooks";
import { api, errorText, type Status } from "../api/client";
import type { Act } from "./useController";
import { restartRequest, restartSummary, type RestartForm } from "./restart";

export function Restart({
  status,
  program,
  run,
  onError,
}: {
  status: Status;
  /// The program shown in the program area (searched in AUTO).
  program: number | null;
  run: Act;
  onError: (e: string | null) => void;
}) {
  const [open, setOpen] = useState(false);
  const [form, setForm] = useState<RestartForm>({ type: "p", by: "n", value: "", occurrence: "" });
  const set = (change: Partial<RestartForm>) => setForm((f) => ({ ...f, ...change }));
  const id = status.id;

  const search = async () => {
    const body = restartRequest(form, program);
    if (typeof body === "string") return onError(body);
    onError(null);
    try {
      await run(() => api.POST("/api/v1/controllers/{id}/restart", { params: { path: { id } }, body }));
      setOpen(false);
    } catch (e) {
      onError(errorText(e));
    }
  };

  return (
    <span class="restart">
      <button data-action="restart" onClick={() => setOpen(!open)} disabled={status.run_state !== "idle"} title="program restart (block search)">
        restart…
      </button>
      {open && (
        <div class="restart-dialog" role="dialog" aria-label="program restart">
          <select value={form.type} onChange={(e) => set({ type: e.currentTarget.value as "p" | "q" })} title="P: after a broken tool; Q: after a power-off or emergency stop">
            <option value="p">P type</option>
            <option value="q">Q type</option>
          </select>
          <select value={form.by} onChange={(e) => set({ by: e.currentTarget.value as "n" | "line" })}>
            <option value="n">N</option>
            <option value="line">line</option>
          </select>
          <input class="short" name="restart-block" placeholder={form.by === "n" ? "N" : "line"} value={form.value} onInput={(e) => set({ value: e.currentTarget.value })} />
          <input class="short" name="restart-occurrence" placeholder="pass 1" title="the how-many-th time the block is reached" value={form.occurrence} onInput={(e) => set({ occurrence: e.currentTarget.value })} />
          <button class="primary" data-action="restart-search" onClick={search}>
            search
          </button>
          <button onClick={() => setOpen(false)}>cancel</button>
        </div>
      )}
      {status.restart && (
        <div class="restart-info" data-restart={status.restart.phase} title={restartSummary(status.restart)}>
          {restartSummary(status.restart)}
        </div>
      )}
    </span>
  );
}
