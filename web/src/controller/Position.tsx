// The position display of a control's "all" screen: absolute (workpiece), relative, machine and
// distance to go for every axis, the tool tip and tool vector, actual feed and spindle speed.
// Every length and feed says its unit: under G20 the absolute, relative and distance-to-go
// positions are in inch, as a FANUC shows them, the rest in the machine's mm (`units.ts`).
import { useState } from "preact/hooks";
import { fmt, type Frame, type Schemas, type Status } from "../api/client";
import { inchInput, inInput } from "./units";

/// The relative counter's origin per controller, kept in the browser (like the panel's ORIGIN
/// soft key: an operator's own reference, not a part of the program state).
function useOrigin(id: string) {
  const key = `fivex.origin.${id}`;
  const [origin, setOrigin] = useState<Record<string, number>>(() => JSON.parse(localStorage.getItem(key) ?? "{}"));
  const set = (o: Record<string, number>) => {
    localStorage.setItem(key, JSON.stringify(o));
    setOrigin(o);
  };
  return [origin, set] as const;
}

export function Position({ status, frame, modal }: { status: Status; frame: Frame | null; modal: Schemas["ModalState"] | null }) {
  const [origin, setOrigin] = useOrigin(status.id);
  const machine = frame?.machine ?? status.position.machine;
  const work = frame?.workpiece ?? status.position.workpiece;
  const toGo = frame?.to_go ?? {};
  const axes = Object.keys(machine);
  const rotary = (a: string) => "ABC".includes(a);
  const inch = inchInput(modal);
  const input = inch ? "in" : "mm";
  /// A position in the input unit (a rotary axis in degrees, whatever the unit).
  const shown = (a: string, mm: number | null | undefined) => {
    if (rotary(a)) return fmt(mm);
    const v = inInput(mm, inch);
    return fmt(v.value, v.digits);
  };
  const unit = (u: string) => <span class="unit">{u}</span>;
  return (
    <div class="position panel-box">
      <table class="pos">
        <thead>
          <tr>
            <th />
            <th>absolute {unit(input)}</th>
            <th>
              relative {unit(input)}{" "}
              <button class="tiny" title="ORIGIN: set every relative axis to 0 here" onClick={() => setOrigin({ ...work })}>
                origin
              </button>
            </th>
            <th>machine {unit("mm")}</th>
            <th>distance to go {unit(input)}</th>
          </tr>
        </thead>
        <tbody>
          {axes.map((a) => (
            <tr key={a} data-axis={a}>
              <th class="axis">
                {a}
                {rotary(a) && unit("°")}
              </th>
              <td class="num abs">{shown(a, work[a])}</td>
              <td class="num rel">{shown(a, (work[a] ?? 0) - (origin[a] ?? 0))}</td>
              <td class="num mach">{fmt(machine[a])}</td>
              <td class="num dtg">{shown(a, toGo[a] ?? 0)}</td>
            </tr>
          ))}
        </tbody>
      </table>
      {Object.values(status.interrupt_shift ?? {}).some((v) => Math.abs(v as number) > 1e-9) && (
        <p class="shift">
          handle interrupt shift (mm, °):{" "}
          {Object.entries(status.interrupt_shift)
            .filter(([, v]) => Math.abs(v as number) > 1e-9)
            .map(([a, v]) => `${a} ${fmt(v as number)}`)
            .join("  ")}
        </p>
      )}
      <dl class="readouts">
        <dt>tool tip {unit("mm")}</dt>
        <dd class="num tip">{frame ? frame.tip.map((v) => fmt(v)).join("  ") : "—"}</dd>
        <dt>
          programmed{frame ? ` (${frame.programmed_in})` : ""} {unit("mm")}
        </dt>
        <dd class="num">{frame ? frame.programmed.map((v) => fmt(v)).join("  ") : "—"}</dd>
        <dt>tool vector</dt>
        <dd class="num">{frame ? frame.tool.map((v) => fmt(v, 4)).join("  ") : "—"}</dd>
        <dt>act. F</dt>
        <dd class="num feed">
          {fmt(frame?.feed ?? status.feed, 0)} {unit("mm/min")}
        </dd>
        <dt>act. S</dt>
        <dd class="num">{fmt(frame?.spindle ?? 0, 0)} /min</dd>
        <dt>tool length</dt>
        {/* Unknown until the stream's first position frame: "—", not a length of 0. */}
        <dd class="num tool-length">
          {fmt(frame?.tool_length)}
          {frame?.tool_length != null && <> {unit("mm")}</>}
        </dd>
        <dt>run time</dt>
        <dd class="num">{fmt(frame?.t ?? status.time_s, 1)} s</dd>
      </dl>
    </div>
  );
}
