// The fleet: every controller with its machine, state, program and alarm, live over the fleet
// websocket; create (from a preset or a machine file), clone and delete.
import { useEffect, useMemo, useState } from "preact/hooks";
import { api, liveSocket, must, wsUrl, type FleetEntry, type FleetMessage, type MachineDocument, type Schemas, errorText } from "../api/client";
import { go } from "../route";
import { applyDelta } from "./delta";

export function FleetView() {
  const [fleet, setFleet] = useState<FleetEntry[] | null>(null);
  const [live, setLive] = useState(false);
  const [filter, setFilter] = useState("");
  const [error, setError] = useState<string | null>(null);

  useEffect(() => {
    // The socket's first message is the whole fleet (again after a reconnect); then only the
    // controllers that changed and the ids removed.
    const socket = liveSocket<FleetMessage>(
      () => wsUrl("/api/v1/stream", { rate: 4 }),
      (msg) => {
        if (msg.type === "fleet") setFleet(msg.controllers);
        else if (msg.type === "fleet_delta") setFleet((fleet) => applyDelta(fleet ?? [], msg));
      },
      setLive,
    );
    return () => socket.close();
  }, []);

  const shown = useMemo(() => {
    const f = filter.trim().toLowerCase();
    if (!fleet || !f) return fleet ?? [];
    return fleet.filter((c) => [c.name, c.machine, c.kind, c.dialect, c.run_state, c.mode].some((s) => s.toLowerCase().includes(f)));
  }, [fleet, filter]);

  const counts = useMemo(() => {
    const n = { running: 0, hold: 0, alarm: 0, idle: 0 } as Record<string, number>;
    for (const c of fleet ?? []) n[c.run_state] = (n[c.run_state] ?? 0) + 1;
    return n;
  }, [fleet]);

  const act = async (what: () => Promise<unknown>) => {
    setError(null);
    try {
      await what();
    } catch (e) {
      setError(errorText(e));
    }
  };

  return (
    <section class="fleet">
      <div class="fleet-head">
        <h1>Fleet</h1>
        <div class="counts">
          <span class="pill running">{counts.running} running</span>
          <span class="pill hold">{counts.hold} hold</span>
          <span class="pill alarm">{counts.alarm} alarm</span>
          <span class="pill idle">{counts.idle} idle</span>
          <span class={`pill ${live ? "live" : "stale"}`} title="fleet websocket">
            {live ? "live" : "reconnecting"}
          </span>
        </div>
        <input class="filter" placeholder="filter…" value={filter} onInput={(e) => setFilter(e.currentTarget.value)} />
      </div>
      <CreateForm onError={setError} />
      {error && <p class="error" role="alert">{error}</p>}
      {fleet === null ? (
        <p>Loading…</p>
      ) : fleet.length === 0 ? (
        <p class="empty">No controllers yet: create one above.</p>
      ) : (
        <table class="grid fleet-table">
          <thead>
            <tr>
              <th>name</th>
              <th>machine</th>
              <th>kind</th>
              <th>dialect</th>
              <th>mode</th>
              <th>state</th>
              <th>program</th>
              <th>line</th>
              <th>alarm</th>
              <th />
            </tr>
          </thead>
          <tbody>
            {shown.map((c) => (
              <tr key={c.id} class={`row-${c.run_state}`} data-id={c.id}>
                <td>
                  <a href={`#/c/${c.id}`} class="name">
                    {c.name}
                  </a>
                </td>
                <td>{c.machine}</td>
                <td>{c.kind}</td>
                <td>{c.dialect}</td>
                <td class="mode">{c.mode.toUpperCase()}</td>
                <td>
                  <span class={`state ${c.run_state}`}>{c.run_state}</span>
                </td>
                <td>{c.program != null ? `O${String(c.program).padStart(4, "0")}` : ""}</td>
                <td class="num">{lineText(c)}</td>
                <td class="alarm-cell">{c.alarm ? `${c.alarm.code} ${c.alarm.message}` : ""}</td>
                <td class="actions">
                  <button
                    title="clone"
                    onClick={() =>
                      act(async () => {
                        const name = prompt("Name of the copy", `${c.name} (copy)`);
                        if (name) await must(api.POST("/api/v1/controllers/{id}/clone", { params: { path: { id: c.id } }, body: { name } }));
                      })
                    }
                  >
                    clone
                  </button>
                  <button
                    class="danger"
                    title="delete"
                    onClick={() =>
                      act(async () => {
                        if (confirm(`Delete ${c.name} with its programs and history?`))
                          await must(api.DELETE("/api/v1/controllers/{id}", { params: { path: { id: c.id } } }));
                      })
                    }
                  >
                    delete
                  </button>
                </td>
              </tr>
            ))}
          </tbody>
        </table>
      )}
    </section>
  );
}

function CreateForm({ onError }: { onError: (e: string | null) => void }) {
  const [presets, setPresets] = useState<Schemas["Preset"][]>([]);
  const [name, setName] = useState("");
  const [preset, setPreset] = useState("table-ac");
  const [dialect, setDialect] = useState("fanuc");
  const [machine, setMachine] = useState<{ file: string; doc: MachineDocument } | null>(null);
  const [busy, setBusy] = useState(false);

  useEffect(() => {
    must(api.GET("/api/v1/presets")).then(setPresets, () => {});
  }, []);

  const submit = async (e: Event) => {
    e.preventDefault();
    onError(null);
    setBusy(true);
    try {
      const body: Schemas["CreateController"] = machine
        ? { name: name || machine.file, machine: machine.doc, dialect }
        : { name: name || preset, preset, dialect };
      const created = await must(api.POST("/api/v1/controllers", { body }));
      setName("");
      go(`#/c/${created.id}`);
    } catch (err) {
      onError(errorText(err));
    } finally {
      setBusy(false);
    }
  };

  const load = async (input: HTMLInputElement) => {
    const file = input.files?.[0];
    if (!file) return setMachine(null);
    try {
      // Taken as the document it should be: the service checks it and answers why not (422).
      setMachine({ file: file.name.replace(/\.json$/, ""), doc: JSON.parse(await file.text()) as MachineDocument });
    } catch {
      onError(`${file.name} is not JSON`);
      input.value = "";
    }
  };

  return (
    <form class="create" onSubmit={submit}>
      <label>
        name <input name="name" value={name} placeholder="cell 1" onInput={(e) => setName(e.currentTarget.value)} />
      </label>
      <label>
        preset
        <select name="preset" value={preset} disabled={!!machine} onChange={(e) => setPreset(e.currentTarget.value)}>
          {(presets.length ? presets : [{ name: "table-ac", kind: "", axes: [] }]).map((p) => (
            <option value={p.name}>
              {p.name} {p.kind && `(${p.kind}, ${p.axes.join("")})`}
            </option>
          ))}
        </select>
      </label>
      <label>
        or machine file <input type="file" accept=".json,application/json" onChange={(e) => load(e.currentTarget)} />
      </label>
      <label>
        dialect
        <select name="dialect" value={dialect} onChange={(e) => setDialect(e.currentTarget.value)}>
          <option value="fanuc">FANUC</option>
          <option value="syntec">Syntec</option>
          <option value="haas">Haas NGC</option>
        </select>
      </label>
      <button type="submit" class="primary" disabled={busy}>
        create controller
      </button>
    </form>
  );
}

/** The executing line; inside a called program, with that program's O number. */
function lineText(c: FleetEntry): string {
  if (!c.line) return "";
  const called = c.line_program != null && c.line_program !== c.program;
  return called ? `${c.line} (O${String(c.line_program).padStart(4, "0")})` : String(c.line);
}
