// The cycle-time box beside the readout: before a cycle start the selected program's simulated
// cycle time (asked of the service, again while it is being computed), while a stored program
// runs its time left and percentage (the status's `progress`, read twice a second: the stream
// carries positions and run states, not progress).
import { useEffect, useState } from "preact/hooks";
import { api, must, type Status } from "../api/client";
import { progressView, type Estimate, type RunProgress } from "./progress";

/** How often a pending estimate and a run's progress are read again, ms. */
const POLL_MS = 500;

/// `revision` changes when a program was stored: the selected one's estimate is asked again.
export function Progress({ status, selected, revision }: { status: Status; selected: number | null; revision: number }) {
  const id = status.id;
  const running = status.run_state !== "idle" && status.program != null;
  const [estimate, setEstimate] = useState<Estimate | null>(null);
  const [run, setRun] = useState<RunProgress | null>(status.progress ?? null);

  // The selected program's estimate, from the state the machine stands in (asked again after a
  // run, which moved it).
  useEffect(() => {
    setEstimate(null);
    if (selected == null || running) return;
    let stop = false;
    let timer = 0;
    const ask = () =>
      must(api.GET("/api/v1/controllers/{id}/programs/{number}/estimate", { params: { path: { id, number: selected } } })).then(
        (e) => {
          if (stop) return;
          setEstimate(e);
          if (e.state === "pending") timer = window.setTimeout(ask, POLL_MS);
        },
        () => !stop && setEstimate(null),
      );
    ask();
    return () => {
      stop = true;
      clearTimeout(timer);
    };
  }, [id, selected, running, revision]);

  useEffect(() => {
    if (!running) return setRun(null);
    let stop = false;
    const read = () =>
      must(api.GET("/api/v1/controllers/{id}", { params: { path: { id } } })).then(
        (s) => !stop && setRun(s.progress ?? null),
        () => {},
      );
    read();
    const timer = window.setInterval(read, POLL_MS);
    return () => {
      stop = true;
      clearInterval(timer);
    };
  }, [id, running]);

  const view = progressView(running ? run : null, estimate);
  if (!view.text) return null;
  return (
    <div class="cycle panel-box" data-testid="cycle-time">
      <div class="cycle-text">{view.text}</div>
      {view.percent != null && (
        <div class="bar" role="progressbar" aria-valuenow={Math.round(view.percent)} aria-valuemin={0} aria-valuemax={100}>
          <div style={{ width: `${view.percent}%` }} />
        </div>
      )}
      {view.caveats && <div class="caveats">{view.caveats}</div>}
    </div>
  );
}
