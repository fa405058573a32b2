// Alarms in force (live) and the alarm and run history.
import { memo } from "preact/compat";
import { useEffect, useState } from "preact/hooks";
import { api, must, fmt, type AlarmInfo, type Schemas } from "../api/client";
import type { LocatedNotice } from "./useController";

type Props = { id: string; active: AlarmInfo[]; messages: string[]; notices: LocatedNotice[] };

/// Where a block is: its line, in the stored program it is in when known, and its N.
function where(line: number, n: number | null | undefined, program: number | null | undefined): string {
  return `${program != null ? `O${program} ` : ""}line ${line}${n != null ? ` N${n}` : ""}`;
}

function AlarmsView({ id, active, messages, notices }: Props) {
  const [history, setHistory] = useState<Schemas["Alarms"]["history"]>([]);
  const [runs, setRuns] = useState<Schemas["Run"][]>([]);
  useEffect(() => {
    // History grows with every alarm: fetch again when the active set changes.
    must(api.GET("/api/v1/controllers/{id}/alarms", { params: { path: { id }, query: { limit: 100 } } })).then((a) => setHistory(a.history), () => {});
    must(api.GET("/api/v1/controllers/{id}/runs", { params: { path: { id } } })).then(setRuns, () => {});
  }, [id, active]);
  return (
    <div class="alarms">
      <h3>Active</h3>
      {active.length === 0 ? (
        <p class="quiet">No alarm.</p>
      ) : (
        <ul class="active-alarms">
          {active.map((a) => (
            <li class="alarm-line">
              <strong>{a.code}</strong> {a.message} <span class="where">{where(a.line, a.n, a.program)}</span>
            </li>
          ))}
        </ul>
      )}
      {messages.length > 0 && (
        <>
          <h3>Operator messages</h3>
          <ul>
            {messages.map((m) => (
              <li>{m}</li>
            ))}
          </ul>
        </>
      )}
      {notices.length > 0 && (
        <>
          <h3>Notices</h3>
          <p class="quiet">Blocks fivex ran by a rule of its own where the manuals do not say what the control does.</p>
          <ul class="notices">
            {notices.map((n) => (
              <li>
                <strong>{n.code}</strong> {n.message} <span class="where">{where(n.line, n.n, n.program)}</span>
              </li>
            ))}
          </ul>
        </>
      )}
      <h3>History</h3>
      <table class="grid">
        <thead>
          <tr>
            <th>raised</th>
            <th>code</th>
            <th>message</th>
            <th>line</th>
          </tr>
        </thead>
        <tbody>
          {history.map((h) => (
            <tr>
              <td>{h.raised_at}</td>
              <td>{h.code}</td>
              <td>{h.message}</td>
              <td class="num">{where(h.line, h.n, h.program)}</td>
            </tr>
          ))}
        </tbody>
      </table>
      <h3>Runs</h3>
      <table class="grid">
        <thead>
          <tr>
            <th>program</th>
            <th>started</th>
            <th>cycle time</th>
            <th>result</th>
          </tr>
        </thead>
        <tbody>
          {runs.map((r) => (
            <tr>
              <td>{r.program != null ? `O${r.program}` : "MDI"}</td>
              <td>{r.started_at}</td>
              <td class="num">{fmt(r.cycle_time_s, 2)} s</td>
              <td>{r.result}</td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

/// Re-rendered only when its own props change, not with every position frame.
export const Alarms = memo(AlarmsView);
