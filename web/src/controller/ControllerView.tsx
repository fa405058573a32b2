// One controller: what a control's screen shows (position, modal state, program, alarms,
// variables, parameters, offsets), its operator panel, and the live 3D machine.
//
// Layout (style.css, "controller"): the readout (position, cycle time, modal state), the program
// and the 3D view side by side on a wide screen, the 3D view under the first two on a narrow
// one; the operator panel below them, and the other pages behind the tabs under the panel.
// The program column is always there: its text, with the executing block, stays in view beside
// the readout whatever tab is open, and another program can be edited in it while one runs.
import { useEffect, useState } from "preact/hooks";
import { api, must, type Schemas } from "../api/client";
import { useController } from "./useController";
import { Position } from "./Position";
import { Modal, useModal } from "./Modal";
import { Panel } from "./Panel";
import { Programs } from "./Programs";
import { Mdi } from "./Mdi";
import { Alarms } from "./Alarms";
import { Variables } from "./Variables";
import { Parameters } from "./Parameters";
import { Offsets } from "./Offsets";
import { WorkpieceView } from "./Workpiece";
import { Machine3D } from "./Machine3D";
import { Teach } from "./Teach";
import { Progress } from "./Progress";

/// The pages behind the tabs; the default route's tab (`program`) opens none of them, the
/// program being in its own column.
const TABS: [string, string][] = [
  ["mdi", "MDI"],
  ["alarms", "Alarms"],
  ["variables", "Macro variables"],
  ["offsets", "Offsets"],
  ["workpiece", "Workpiece"],
  ["parameters", "Parameters"],
];

export function ControllerView({ id, tab }: { id: string; tab: string }) {
  const live = useController(id);
  const [error, setError] = useState<string | null>(null);
  const [program, setProgram] = useState<number | null>(null);
  /// Bumped when a program is stored: its estimate is asked for again.
  const [stored, setStored] = useState(0);
  const [path, setPath] = useState<{ xyz: Float32Array; rapid: boolean[]; programmed: Float32Array | null } | null>(null);
  const status = live.status;
  const modal = useModal(id, `${status?.run_state}:${live.frame?.line ?? 0}`);
  // The path shows the program running, else the one selected (which may be another one being
  // edited while it runs).
  const running = status != null && status.run_state !== "idle" && status.program != null;
  const shown = running ? status.program : program;

  // The programmed path of the selected program, for the 3D view (again when it starts, since
  // it is computed from where the machine is); under cutter compensation the tool centre's
  // path with the programmed one beside it.
  useEffect(() => {
    if (shown == null) return setPath(null);
    must(api.GET("/api/v1/controllers/{id}/programs/{number}/path", { params: { path: { id, number: shown } } })).then(
      (p) => setPath({ xyz: new Float32Array(p.xyz), rapid: p.rapid, programmed: p.programmed ? new Float32Array(p.programmed.xyz) : null }),
      () => setPath(null),
    );
  }, [id, shown, status?.run_state === "running"]);

  // What is on the table, for the 3D view and the workpiece tab: as the stream tells it (its
  // snapshot, then every change, this page's or another client's), and the answer to an edit
  // here at once.
  const [workpiece, setWorkpiece] = useState<Schemas["Workpiece"] | null>(null);
  useEffect(() => setWorkpiece(live.workpiece), [live.workpiece]);

  if (live.error && !status) return <p class="error">{live.error}</p>;
  if (!status) return <p>Loading…</p>;
  const axes = Object.keys(status.position.machine);
  const alarmed = live.alarms.length > 0;
  return (
    <section class="controller">
      <div class="ctl-head">
        <h1>{status.name}</h1>
        <span class="meta">
          {status.machine} · {status.kind} · {status.dialect.toUpperCase()}
        </span>
        <span class="mode-pill">{status.mode.toUpperCase()}</span>
        <span class={`state ${status.run_state}`} data-run-state={status.run_state}>
          {status.run_state}
        </span>
        <span class="prog">
          {status.program != null ? `O${String(status.program).padStart(4, "0")}` : ""} {live.frame?.line ? `line ${live.frame.line}` : ""}
          {live.frame?.n != null ? ` N${live.frame.n}` : ""}
        </span>
        <span class={`pill ${live.connected ? "live" : "stale"}`}>{live.connected ? "live" : "reconnecting"}</span>
      </div>
      {alarmed && (
        <div class="alarm-banner" role="alert">
          {live.alarms.map((a) => (
            <div>
              <strong>{a.code}</strong> {a.message} (line {a.line})
            </div>
          ))}
        </div>
      )}
      {error && (
        <p class="error" role="alert" onClick={() => setError(null)}>
          {error}
        </p>
      )}
      <div class="ctl-grid">
        <div class="readout">
          <Position status={status} frame={live.frame} modal={modal} />
          <Progress status={status} selected={program} revision={stored} />
          <Modal modal={modal} />
        </div>
        <div class="program-col panel-box">
          <Programs status={status} line={live.frame?.line ?? status.line} selected={program} onSelect={setProgram} run={live.act} onError={setError} onStored={() => setStored((n) => n + 1)} />
        </div>
        <div class="view-col">{live.machine && <Machine3D machine={live.machine} frame={live.frame} path={path} workpiece={workpiece} onFrame={live.onFrame} />}</div>
      </div>
      <Panel status={status} axes={axes} run={live.act} onError={setError} />
      {status.dialect === "syntec" && <Teach status={status} run={live.act} onError={setError} />}
      <nav class="tabs">
        {TABS.map(([t, label]) => (
          <a key={t} href={`#/c/${id}/${t}`} class={tab === t ? "active" : ""}>
            {label}
            {t === "alarms" && alarmed ? " ●" : ""}
          </a>
        ))}
      </nav>
      <div class={`tab-body ${TABS.some(([t]) => t === tab) ? "" : "closed"}`}>
        {tab === "mdi" && <Mdi status={status} run={live.act} onError={setError} />}
        {tab === "alarms" && <Alarms id={id} active={live.alarms} messages={live.messages} notices={live.notices} />}
        {tab === "variables" && <Variables id={id} values={live.variables} onError={setError} />}
        {tab === "offsets" && <Offsets id={id} axes={axes} onError={setError} />}
        {tab === "parameters" && <Parameters status={status} onError={setError} />}
        {tab === "workpiece" && <WorkpieceView id={id} workpiece={workpiece} onChanged={setWorkpiece} onError={setError} />}
      </div>
    </section>
  );
}
