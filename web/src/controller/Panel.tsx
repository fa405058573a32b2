// The operator panel: mode keys, cycle start / feed hold / reset / emergency stop, the single
// block, optional stop, block delete, dry run, machine lock, Z-axis neglect (FANUC) and
// auxiliary function lock switches, feed, rapid and spindle override, the part count and the
// operating / cutting time, and the manual feeds (JOG with hold-to-move keys, HANDLE with
// increments, the 5-axis manual feeds).
import { useEffect, useState } from "preact/hooks";
import { api, type Status, errorText } from "../api/client";
import type { components } from "../api/schema";
import type { Act } from "./useController";
import { clock } from "./clock";

// The words the document lists (its enums), so the typed client takes them.
type Mode = components["schemas"]["ModeName"];
type Coordinates = components["schemas"]["CoordinatesName"];
type Feed = components["schemas"]["ManualFeed"];

const MODES: [Mode, string][] = [
  ["auto", "MEM"],
  ["mdi", "MDI"],
  ["jog", "JOG"],
  ["handle", "HANDLE"],
  ["inc", "INC"],
  ["ref", "REF"],
];
const FEED_STEPS = [0, 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, 150, 160, 170, 180, 190, 200];
const RAPID_STEPS = [0, 25, 50, 100];
/// The spindle override switch: 50–120 % in 10 % steps.
const SPINDLE_STEPS = [50, 60, 70, 80, 90, 100, 110, 120];
type Switch = "single_block" | "optional_stop" | "block_delete" | "dry_run" | "machine_lock" | "z_neglect" | "aux_lock";
const SWITCHES: [Switch, string][] = [
  ["single_block", "SINGLE BLOCK"],
  ["optional_stop", "OPT STOP"],
  ["block_delete", "BLOCK DELETE"],
  ["dry_run", "DRY RUN"],
  ["machine_lock", "MC LOCK"],
  ["z_neglect", "Z NEGLECT"],
  ["aux_lock", "AUX LOCK"],
];

/// The 5-axis manual feeds (`POST /jog` `feed`).
const FIVE_AXIS_FEEDS: [Feed, string][] = [
  ["tool-axis", "tool axis"],
  ["right-angle1", "right angle 1"],
  ["right-angle2", "right angle 2"],
  ["table-vertical", "table vertical"],
  ["table-horizontal1", "table horizontal 1"],
  ["table-horizontal2", "table horizontal 2"],
];

type Target = { axis: string } | { feed: Feed } | { tip_rotation: string };

export function Panel({ status, axes, run, onError }: { status: Status; axes: string[]; run: Act; onError: (e: string | null) => void }) {
  const id = status.id;
  const p = { params: { path: { id } } };
  const [target, setTarget] = useState<Target>({ axis: axes[0] ?? "X" });
  const [increment, setIncrement] = useState(0.1);
  const rotaries = axes.filter((a) => "ABC".includes(a));
  const panel = status.panel;
  const signals = panel.signals;
  /// With a feed mode signal on, an axis key is a ±J key: the signals choose what it moves.
  const bySignals = !!(signals.alngh || signals.rghth || signals.rndh) && "axis" in target;

  const act = async (call: Parameters<Act>[0]) => {
    onError(null);
    try {
      await run(call);
    } catch (e) {
      onError(errorText(e));
    }
  };
  /// The hand wheel: in HANDLE mode a move of the selected target; during a program (a manual
  /// handle interruption) pulses through the handle's axis select code.
  const turnHandle = (amount: number) => {
    if (status.mode === "handle") return act(() => api.POST("/api/v1/controllers/{id}/handle", { ...p, body: { ...target, amount } }));
    if (!("axis" in target)) return;
    const code = axes.indexOf(target.axis) + 1;
    act(async () => {
      if (signals.handle_select !== code) await api.PUT("/api/v1/controllers/{id}/manual-signals", { ...p, body: { handle_select: code } });
      const r = await api.POST("/api/v1/controllers/{id}/handle-pulses", { ...p, body: { amount } });
      return { data: r.data?.status, error: r.error, response: r.response };
    });
  };
  // The counters go on while a program runs and the stream carries positions, not them: the
  // status is read again at each change of the run state, and each second while running.
  useEffect(() => {
    const read = () => run(() => api.GET("/api/v1/controllers/{id}", p)).catch(() => {});
    read();
    if (status.run_state !== "running") return;
    const timer = setInterval(read, 1000);
    return () => clearInterval(timer);
  }, [status.run_state, id]);
  const key = (t: Target) => JSON.stringify(t);
  const selected = (t: Target) => key(t) === key(target);

  return (
    <div class="op-panel panel-box">
      <div class="row modes" role="group" aria-label="mode">
        {MODES.map(([m, label]) => (
          <button key={m} class={`key ${status.mode === m ? "lit" : ""}`} data-mode={m} onClick={() => act(() => api.PUT("/api/v1/controllers/{id}/mode", { ...p, body: { mode: m } }))}>
            {label}
          </button>
        ))}
      </div>
      <div class="row cycle">
        <button class="key start" title="cycle start" onClick={() => act(() => api.POST("/api/v1/controllers/{id}/cycle-start", { ...p, body: {} }))}>
          CYCLE START
        </button>
        <button class="key hold" title="feed hold" onClick={() => act(() => api.POST("/api/v1/controllers/{id}/feed-hold", p))}>
          FEED HOLD
        </button>
        <button class="key" title="reset" onClick={() => act(() => api.POST("/api/v1/controllers/{id}/reset", p))}>
          RESET
        </button>
        <EStop status={status} act={act} />
      </div>
      <div class="row switches">
        {SWITCHES.filter(([k]) => k !== "z_neglect" || status.dialect === "fanuc").map(([k, label]) => (
          <button
            key={k}
            class={`key toggle ${panel[k] ? "lit" : ""}`}
            data-switch={k}
            aria-pressed={panel[k]}
            onClick={() => act(() => api.PUT("/api/v1/controllers/{id}/switches", { ...p, body: { [k]: !panel[k] } }))}
          >
            {label}
          </button>
        ))}
      </div>
      <div class="row overrides">
        <label>
          feed {panel.feed_override}%
          <input
            type="range"
            min={0}
            max={200}
            step={10}
            list="feed-steps"
            value={panel.feed_override}
            onChange={(e) => act(() => api.PUT("/api/v1/controllers/{id}/overrides", { ...p, body: { feed: Number(e.currentTarget.value) } }))}
          />
          <datalist id="feed-steps">
            {FEED_STEPS.map((v) => (
              <option value={v} />
            ))}
          </datalist>
        </label>
        <span class="rapid" role="group" aria-label="rapid override">
          rapid
          {RAPID_STEPS.map((r) => (
            <button
              key={r}
              class={`key small ${panel.rapid_override === r ? "lit" : ""}`}
              title={r === 0 ? "rapids hold: FANUC's F0 rate (No.1421) is not modelled" : undefined}
              onClick={() => act(() => api.PUT("/api/v1/controllers/{id}/overrides", { ...p, body: { rapid: r } }))}
            >
              {`${r}%`}
            </button>
          ))}
        </span>
        <span class="spindle" role="group" aria-label="spindle override">
          spindle {Math.abs(status.spindle)} min⁻¹
          <select
            title="spindle override"
            value={String(panel.spindle_override)}
            onChange={(e) => act(() => api.PUT("/api/v1/controllers/{id}/overrides", { ...p, body: { spindle: Number(e.currentTarget.value) } }))}
          >
            {SPINDLE_STEPS.map((v) => (
              <option value={String(v)}>{v}%</option>
            ))}
          </select>
        </span>
      </div>
      <div class="row counters quiet" aria-label="counters">
        <span title="#3901 / #3902">
          parts {status.counters.parts}
          {status.counters.parts_required > 0 ? ` / ${status.counters.parts_required}` : ""}
        </span>
        <span title="operating time">run {clock(status.counters.operating_time_s)}</span>
        <span title="cutting time">cut {clock(status.counters.cutting_time_s)}</span>
      </div>
      <div class="row manual">
        <span class="targets" role="group" aria-label="axis or 5-axis feed">
          {axes.map((a) => (
            <button key={a} class={`key small ${selected({ axis: a }) ? "lit" : ""}`} onClick={() => setTarget({ axis: a })}>
              {a}
            </button>
          ))}
          {rotaries.length > 0 && (
            <select
              title="5-axis manual feed"
              value={"feed" in target ? target.feed : "tip_rotation" in target ? `tip:${target.tip_rotation}` : ""}
              onChange={(e) => {
                const v = e.currentTarget.value;
                if (v.startsWith("tip:")) setTarget({ tip_rotation: v.slice(4) });
                else if (v) setTarget({ feed: FIVE_AXIS_FEEDS.find(([f]) => f === v)?.[0] ?? "tool-axis" });
                else setTarget({ axis: axes[0] });
              }}
            >
              <option value="">5-axis feed…</option>
              {FIVE_AXIS_FEEDS.map(([f, label]) => (
                <option value={f}>{label}</option>
              ))}
              {rotaries.map((r) => (
                <option value={`tip:${r}`}>tool tip rotation {r}</option>
              ))}
            </select>
          )}
        </span>
        {(status.mode === "handle" || status.mode === "inc") && (
          <span class="increments" role="group" aria-label="increment">
            {[0.001, 0.01, 0.1, 1].map((inc) => (
              <button
                key={inc}
                class={`key small ${(status.mode === "inc" ? panel.increment : increment) === inc ? "lit" : ""}`}
                title={`${inc} mm (° on a rotary axis)`}
                onClick={() => (status.mode === "inc" ? act(() => api.PUT("/api/v1/controllers/{id}/manual", { ...p, body: { increment: inc } })) : setIncrement(inc))}
              >
                ×{Math.round(inc * 1000)}
              </button>
            ))}
          </span>
        )}
        {status.mode === "handle" || ((status.mode === "auto" || status.mode === "mdi") && status.run_state !== "idle" && "axis" in target) ? (
          <span class="handle">
            {status.mode !== "handle" && <span class="quiet">handle interrupt</span>}
            {[-1, 1].map((sign) => (
              <button key={sign} class="key small" title={`handle ${sign < 0 ? "−" : "+"}`} onClick={() => turnHandle(sign * increment)}>
                {sign < 0 ? "−" : "+"}
              </button>
            ))}
          </span>
        ) : (
          <span class="jog">
            {[false, true].map((positive) => (
              <button
                key={String(positive)}
                class="key small"
                title={status.mode === "inc" ? `one increment ${positive ? "+" : "−"}` : `jog ${positive ? "+" : "−"} (hold)`}
                disabled={status.mode !== "jog" && status.mode !== "inc"}
                onPointerDown={() =>
                  act(() =>
                    bySignals && "axis" in target
                      ? api.POST("/api/v1/controllers/{id}/jog-signal", { ...p, body: { axis: target.axis, positive } })
                      : api.POST("/api/v1/controllers/{id}/jog", { ...p, body: { ...target, positive } }),
                  )
                }
                onPointerUp={() => status.mode === "jog" && act(() => api.POST("/api/v1/controllers/{id}/jog-stop", p))}
                onPointerLeave={(e) => status.mode === "jog" && e.buttons && act(() => api.POST("/api/v1/controllers/{id}/jog-stop", p))}
              >
                {positive ? "+" : "−"}
              </button>
            ))}
            <label>
              jog feed
              <input
                type="number"
                class="short"
                key={panel.jog_feed}
                defaultValue={String(panel.jog_feed)}
                min={1}
                onChange={(e) => act(() => api.PUT("/api/v1/controllers/{id}/manual", { ...p, body: { jog_feed: Number(e.currentTarget.value) } }))}
              />{" "}
              <span class="unit">mm/min</span>
            </label>
          </span>
        )}
        {status.mode === "ref" && (
          <button class="key small" onClick={() => act(() => api.POST("/api/v1/controllers/{id}/reference-return", p))}>
            home all
          </button>
        )}
        <button
          class={`key small toggle ${panel.manual_absolute ? "lit" : ""}`}
          title="manual absolute"
          onClick={() => act(() => api.PUT("/api/v1/controllers/{id}/manual", { ...p, body: { manual_absolute: !panel.manual_absolute } }))}
        >
          MANUAL ABS
        </button>
        {status.dialect === "syntec" && (
          <>
            <select
              title="R518: coordinates of manual X/Y/Z"
              value={panel.coordinates}
              onChange={(e) => act(() => api.PUT("/api/v1/controllers/{id}/manual", { ...p, body: { coordinates: e.currentTarget.value as Coordinates } }))}
            >
              <option value="machine">R518 machine</option>
              <option value="program">R518 program</option>
              <option value="tool">R518 tool</option>
            </select>
            <button class={`key small toggle ${panel.rtcp ? "lit" : ""}`} title="R519 manual RTCP" onClick={() => act(() => api.PUT("/api/v1/controllers/{id}/manual", { ...p, body: { rtcp: !panel.rtcp } }))}>
              R519 RTCP
            </button>
          </>
        )}
      </div>
      {status.dialect === "fanuc" && rotaries.length > 0 && (
        <div class="row signals" role="group" aria-label="5-axis feed signals">
          <span class="quiet">feed mode signals</span>
          {(
            [
              ["alngh", "ALNGH"],
              ["rghth", "RGHTH"],
              ["rndh", "RNDH"],
              ["tb_base", "TB_BASE"],
            ] as const
          ).map(([k, label]) => (
            <button
              key={k}
              class={`key small toggle ${signals[k] ? "lit" : ""}`}
              aria-pressed={!!signals[k]}
              title="with a signal on, the ±J keys of the axis letters move the 5-axis feed it selects"
              onClick={() => act(() => api.PUT("/api/v1/controllers/{id}/manual-signals", { ...p, body: { [k]: !signals[k] } }))}
            >
              {label}
            </button>
          ))}
        </div>
      )}
    </div>
  );
}

function EStop({ status, act }: { status: Status; act: (c: Parameters<Act>[0]) => void }) {
  const [pressed, setPressed] = useState(false);
  return (
    <button
      class={`key estop ${pressed ? "lit" : ""}`}
      title="emergency stop"
      aria-pressed={pressed}
      onClick={() => {
        const now = !pressed;
        setPressed(now);
        act(() => api.PUT("/api/v1/controllers/{id}/emergency-stop", { params: { path: { id: status.id } }, body: { pressed: now } }));
      }}
    >
      E-STOP
    </button>
  );
}
