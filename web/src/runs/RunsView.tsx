// Fleet runs: one program on many machines (presets, library machines, existing controllers),
// progress while it runs (or waits, queued behind others), a Cancel button until it is over,
// and the comparison across the fleet as a table and plots; any machine's run opens in the 3D
// view.
import { useEffect, useMemo, useState } from "preact/hooks";
import { api, authFetch, errorText, fmt, liveSocket, must, wsUrl, type MachineDocument, type Progress, type Schemas } from "../api/client";
import { programNumber } from "../api/program";
import { go } from "../route";
import { Bars, Lines } from "./Plots";

type FleetResult = Schemas["FleetResult"];
type FleetRequest = Schemas["FleetRequest"];
/// A machine of the comparison: its result, or only its name when a stopped run did not finish it.
type Row = { machine: string; result: FleetResult | null };

export function RunsView({ id }: { id?: string }) {
  return id ? <RunDetail id={id} /> : <RunsHome />;
}

/// Runs that are not over yet: a cancel stops them.
const underWay = (status: string) => status === "queued" || status === "running";

/// `POST /fleet/runs/{id}/cancel`: answers once the run has stopped.
function cancelRun(id: string) {
  return must(api.POST("/api/v1/fleet/runs/{id}/cancel", { params: { path: { id } } }));
}

function CancelButton({ id, onDone }: { id: string; onDone: (run: Schemas["FleetRunInfo"] | null, error?: string) => void }) {
  const [busy, setBusy] = useState(false);
  return (
    <button
      type="button"
      class="cancel-run"
      disabled={busy}
      title="stop this run (a queued run never starts)"
      onClick={async () => {
        setBusy(true);
        try {
          onDone(await cancelRun(id));
        } catch (e) {
          onDone(null, errorText(e));
        }
        setBusy(false);
      }}
    >
      cancel
    </button>
  );
}

function RunsHome() {
  const [runs, setRuns] = useState<Schemas["FleetRunInfo"][]>([]);
  const [error, setError] = useState<string | null>(null);
  const load = () => must(api.GET("/api/v1/fleet/runs", { params: { query: { limit: 50 } } })).then(setRuns, () => {});
  useEffect(() => {
    load();
  }, []);
  return (
    <section class="runs">
      <h1>Fleet runs</h1>
      <p class="quiet">One program on many machines, faster than real time: which machines can run it, how long each takes, and why the others cannot.</p>
      <NewRun />
      <h3>Runs</h3>
      {error && <p class="error">{error}</p>}
      <table class="grid runs-list">
        <thead>
          <tr>
            <th>started</th>
            <th>status</th>
            <th>machines</th>
            <th>completed</th>
            <th>alarm</th>
            <th />
          </tr>
        </thead>
        <tbody>
          {runs.map((r) => (
            <tr key={r.id} data-run={r.id}>
              <td>
                <a href={`#/runs/${r.id}`}>{r.created_at}</a>
              </td>
              <td class={`run-status ${r.status}`}>{r.status}</td>
              <td class="num">{r.machines}</td>
              <td class="num">{r.completed}</td>
              <td class="num">{r.alarms}</td>
              <td>
                {underWay(r.status) && (
                  <CancelButton
                    id={r.id}
                    onDone={(_, e) => {
                      setError(e ?? null);
                      load();
                    }}
                  />
                )}
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </section>
  );
}

function NewRun() {
  const [program, setProgram] = useState("");
  const [presets, setPresets] = useState<Schemas["Preset"][]>([]);
  const [library, setLibrary] = useState<Schemas["LibraryMachine"][]>([]);
  const [controllers, setControllers] = useState<Schemas["ControllerStatus"][]>([]);
  const [picked, setPicked] = useState<Set<string>>(new Set());
  const [dialect, setDialect] = useState("fanuc");
  const [error, setError] = useState<string | null>(null);
  useEffect(() => {
    must(api.GET("/api/v1/presets")).then(setPresets, () => {});
    must(api.GET("/api/v1/fleet/library")).then(setLibrary, () => {});
    must(api.GET("/api/v1/controllers")).then(setControllers, () => {});
  }, []);
  const toggle = (key: string) => {
    const next = new Set(picked);
    next.has(key) ? next.delete(key) : next.add(key);
    setPicked(next);
  };
  const pick = (keys: string[], on: boolean) => {
    const next = new Set(picked);
    for (const k of keys) on ? next.add(k) : next.delete(k);
    setPicked(next);
  };
  const chosen = (prefix: string) => [...picked].filter((k) => k.startsWith(prefix)).map((k) => k.slice(prefix.length));
  const submit = async (e: Event) => {
    e.preventDefault();
    setError(null);
    try {
      const body: FleetRequest = { program, presets: chosen("preset:"), library: chosen("library:"), controllers: chosen("controller:"), dialect, report: true };
      const started = await must(api.POST("/api/v1/fleet/runs", { params: { query: { wait: false } }, body }));
      // `wait=false` answers 202 with the run, never the results.
      if (!("id" in started)) throw new Error("the service answered the results instead of the run");
      go(`#/runs/${started.id}`);
    } catch (err) {
      setError(errorText(err));
    }
  };
  const box = (key: string, label: string, title?: string) => (
    <label key={key} class="pick" title={title}>
      <input type="checkbox" checked={picked.has(key)} onChange={() => toggle(key)} data-pick={key} /> {label}
    </label>
  );
  return (
    <form class="new-run panel-box" onSubmit={submit}>
      <div class="run-program">
        <textarea class="nc" name="program" placeholder="NC program (O…)" value={program} onInput={(e) => setProgram(e.currentTarget.value)} />
        <label class="upload">
          upload{" "}
          <input
            type="file"
            accept=".nc,.txt,.tap,text/plain"
            onChange={async (e) => {
              const f = e.currentTarget.files?.[0];
              if (f) setProgram(await f.text());
            }}
          />
        </label>
      </div>
      <div class="run-machines">
        <h3>
          Presets{" "}
          <button type="button" class="tiny" onClick={() => pick(presets.map((p) => `preset:${p.name}`), true)}>
            all
          </button>
        </h3>
        <div class="picks">{presets.map((p) => box(`preset:${p.name}`, p.name, `${p.kind}, ${p.axes.join("")}`))}</div>
        <h3>
          Machine library{" "}
          <button type="button" class="tiny" onClick={() => pick(library.map((m) => `library:${m.name}`), true)}>
            all
          </button>{" "}
          <button type="button" class="tiny" onClick={() => pick(library.map((m) => `library:${m.name}`), false)}>
            none
          </button>
        </h3>
        <div class="picks">{library.map((m) => box(`library:${m.name}`, m.name, `${m.kind} · ${m.dialect ?? "model file"} · ${m.axes.join("")}`))}</div>
        {controllers.length > 0 && (
          <>
            <h3>Controllers</h3>
            <div class="picks">{controllers.slice(0, 200).map((c) => box(`controller:${c.id}`, c.name, `${c.machine} (${c.kind})`))}</div>
          </>
        )}
        <div class="row">
          <label>
            dialect{" "}
            <select value={dialect} onChange={(e) => setDialect(e.currentTarget.value)}>
              <option value="fanuc">FANUC</option>
              <option value="syntec">Syntec</option>
              <option value="haas">Haas NGC</option>
            </select>
          </label>
          <button type="submit" class="primary" disabled={!program.trim() || picked.size === 0}>
            run on {picked.size} machine{picked.size === 1 ? "" : "s"}
          </button>
        </div>
        {error && <p class="error">{error}</p>}
      </div>
    </form>
  );
}

function RunDetail({ id }: { id: string }) {
  const [progress, setProgress] = useState<Schemas["Progress"] | null>(null);
  const [run, setRun] = useState<Schemas["FleetRun"] | null>(null);
  const [error, setError] = useState<string | null>(null);
  useEffect(() => {
    let done = false;
    const fetchRun = () => must(api.GET("/api/v1/fleet/runs/{id}", { params: { path: { id } } })).then(setRun, (e) => setError(errorText(e)));
    fetchRun();
    const socket = liveSocket<Progress>(
      () => wsUrl(`/api/v1/fleet/runs/${encodeURIComponent(id)}/stream`),
      (msg) => {
        if (msg.type !== "progress") return;
        setProgress(msg);
        if (msg.finished && !done) {
          done = true;
          socket.close();
          fetchRun();
        }
      },
    );
    return () => socket.close();
  }, [id]);
  // A cancelled or interrupted run has no result for the machines it did not finish.
  const results: Row[] | null =
    run?.results?.map((r, i) => (r ? { machine: r.machine, result: r } : { machine: progress?.machines[i]?.machine || `machine ${i + 1}`, result: null })) ?? null;
  const status = progress?.status ?? run?.status;
  return (
    <section class="run">
      <h1>
        <a href="#/runs">Fleet runs</a> / {id.slice(0, 8)}
      </h1>
      {status && (
        <p>
          <span class={`run-status ${status}`} data-run-status={status}>
            {status}
          </span>{" "}
          {underWay(status) && (
            <CancelButton
              id={id}
              onDone={(stopped, e) => {
                if (e) setError(e);
                if (stopped) must(api.GET("/api/v1/fleet/runs/{id}", { params: { path: { id } } })).then(setRun, () => {});
              }}
            />
          )}
        </p>
      )}
      {error && <p class="error">{error}</p>}
      {progress && !results && (
        <div class="progress panel-box">
          {progress.status === "queued" && <p class="quiet">Waiting for the runs before it (`fivex serve --fleet-jobs`).</p>}
          <progress max={progress.total} value={progress.done} /> {progress.done} of {progress.total} machines
          <ul class="machine-progress">
            {progress.machines.map((m) => (
              <li class={m.state}>
                {m.machine}: {m.state}
                {m.cycle_time_s != null ? ` (${fmt(m.cycle_time_s, 2)} s)` : ""}
              </li>
            ))}
          </ul>
        </div>
      )}
      {results && run && <Comparison results={results} request={run.request} />}
    </section>
  );
}

/// Where a result came from: results are in the order presets, machines, library, controllers.
type Source = { kind: "preset" | "library" | "controller"; value: string } | { kind: "machine"; value: MachineDocument };

function sources(request: FleetRequest): Source[] {
  return [
    ...(request.presets ?? []).map((value): Source => ({ kind: "preset", value })),
    ...(request.machines ?? []).map((value): Source => ({ kind: "machine", value })),
    ...(request.library ?? []).map((value): Source => ({ kind: "library", value })),
    ...(request.controllers ?? []).map((value): Source => ({ kind: "controller", value })),
  ];
}

function Comparison({ results, request }: { results: Row[]; request: FleetRequest }) {
  const [axisPlot, setAxisPlot] = useState<number>(0);
  const [error, setError] = useState<string | null>(null);
  const from = useMemo(() => sources(request), [request]);
  const ok = results.filter((r) => r.result?.status === "completed").length;
  const open = async (i: number) => {
    setError(null);
    try {
      const src = from[i];
      if (src.kind === "controller") return go(`#/c/${src.value}`);
      const body: Schemas["CreateController"] = { name: `${results[i].machine} (fleet run)`, dialect: results[i].result?.dialect };
      if (src.kind === "preset") body.preset = src.value;
      else if (src.kind === "machine") body.machine = src.value;
      else body.machine = (await must(api.GET("/api/v1/fleet/library/{name}", { params: { path: { name: src.value } } }))).machine;
      const c = await must(api.POST("/api/v1/controllers", { body }));
      // The program's own O number is its slot (the service refuses another); 1 without one.
      const number = programNumber(request.program) ?? 1;
      const stored = await authFetch(`/api/v1/controllers/${c.id}/programs/${number}?force=true`, { method: "PUT", headers: { "content-type": "text/plain" }, body: request.program });
      if (!stored.ok) throw new Error((await stored.json().catch(() => ({}))).error ?? `${stored.status}`);
      await must(api.POST("/api/v1/controllers/{id}/cycle-start", { params: { path: { id: c.id } }, body: { program: number } }));
      go(`#/c/${c.id}`);
    } catch (e) {
      setError(errorText(e));
    }
  };
  const withSpeeds = results.flatMap((row) => (row.result?.report ? [{ machine: row.machine, report: row.result.report }] : []));
  const plotted = withSpeeds[axisPlot] ?? withSpeeds[0];
  return (
    <div class="comparison">
      <p>
        <strong>{ok}</strong> of {results.length} machines can run the program.
      </p>
      {error && <p class="error">{error}</p>}
      <div class="table-scroll">
        <table class="grid compare">
          <thead>
            <tr>
              <th>machine</th>
              <th>result</th>
              <th>cycle time</th>
              <th>travel</th>
              <th>rotary max / mean speed</th>
              <th>near singular</th>
              <th>closest to a limit</th>
              <th>unwinds</th>
              <th>tip deviation</th>
              <th />
            </tr>
          </thead>
          <tbody>
            {results.map((row, i) => {
              const r = row.result;
              const status = r?.status ?? "cancelled";
              const rep = r?.report;
              const axes = rep?.axes ?? [];
              const rot = axes.filter((a) => "ABC".includes(a.name));
              const tight = axes.filter((a) => a.margin != null).sort((a, b) => (a.margin ?? 0) - (b.margin ?? 0))[0];
              const alarm = r?.alarms[0];
              return (
                <tr key={i} class={status === "completed" ? "" : "row-alarm"} data-machine={row.machine}>
                  <th>
                    {row.machine}
                    <div class="quiet small">{r?.dialect}</div>
                  </th>
                  <td class={status === "completed" ? "ok" : "bad"}>{status === "completed" ? "completed" : alarm ? `${alarm.code} ${alarm.message} (line ${alarm.line})` : status}</td>
                  <td class="num">{fmt(r?.cycle_time_s, 2)} s</td>
                  <td class="num small">{axes.map((a) => `${a.name} ${fmt(a.travel, 0)}`).join("  ")}</td>
                  <td class="num small">{rot.map((a) => `${a.name} ${fmt(a.max_speed, 0)} / ${fmt(a.mean_speed, 0)}`).join("  ") || "—"}</td>
                  <td class="num">{rep?.near_singular_deg == null ? "—" : `${fmt(rep.near_singular_s, 2)} s (min ${fmt(rep.min_singular_angle_deg, 2)}°)`}</td>
                  <td class="num small">{tight ? `${tight.name} ${fmt(tight.margin, 2)} (${tight.margin_side})` : "—"}</td>
                  <td class="num">{rot.reduce((n, a) => n + (a.unwinds ?? 0), 0)}</td>
                  <td class="num">{rep?.tip_deviation ? `${fmt(rep.tip_deviation.max, 4)} mm${rep.tip_deviation.line ? ` (line ${rep.tip_deviation.line})` : ""}` : "—"}</td>
                  <td>
                    <button onClick={() => open(i)} title="open this machine with the program in the 3D view and start it">
                      open in 3D
                    </button>
                  </td>
                </tr>
              );
            })}
          </tbody>
        </table>
      </div>
      <h3>Cycle time per machine</h3>
      <Bars rows={results.map(({ machine, result }) => ({ label: machine, value: result?.status === "completed" ? result.cycle_time_s : null, bad: result?.status !== "completed" }))} unit="s" />
      {plotted && (
        <>
          <h3>
            Axis speed over time —{" "}
            <select value={withSpeeds.indexOf(plotted)} onChange={(e) => setAxisPlot(Number(e.currentTarget.value))}>
              {withSpeeds.map((r, i) => (
                <option value={i}>{r.machine}</option>
              ))}
            </select>
          </h3>
          <Lines
            series={plotted.report.speeds.axes.map((a) => ({ label: `${a.axis} ${"ABC".includes(a.axis) ? "°/min" : "mm/min"}`, ys: a.speeds }))}
            dt={plotted.report.speeds.period_s}
            unit="per min"
          />
        </>
      )}
    </div>
  );
}
