// FANUC program restart in the dashboard: the request the restart dialog sends and the line the
// program area shows while a restart is under way (`docs/dialects.md`, "Program restart").
import type { Schemas } from "../api/client";

export type RestartRequest = Schemas["RestartRequest"];
export type RestartInfo = Schemas["RestartInfo"];

/// What the dialog holds: the type, whether the block is given by N or by line, the number and
/// the pass count as typed.
export type RestartForm = { type: "p" | "q"; by: "n" | "line"; value: string; occurrence: string };

const MAX = 99_999_999;

/// A whole number 1…99999999 typed in a field, or null.
function count(text: string): number | null {
  const t = text.trim();
  if (!/^\d+$/.test(t)) return null;
  const v = Number(t);
  return v >= 1 && v <= MAX ? v : null;
}

/// The request for `program`, or the reason the form cannot be sent.
export function restartRequest(form: RestartForm, program: number | null): RestartRequest | string {
  const value = count(form.value);
  if (value == null) return form.by === "n" ? "the sequence number is 1–99999999" : "the line is 1–99999999";
  const occurrence = form.occurrence.trim() === "" ? 1 : count(form.occurrence);
  if (occurrence == null) return "the pass count is 1–99999999";
  const request: RestartRequest = { type: form.type, occurrence };
  if (program != null) request.program = program;
  if (form.by === "n") request.n = value;
  else request.line = value;
  return request;
}

/// One line on the restart under way: the block, where the axes go, what is output first (while
/// the search runs: how far it has got; a reset stops it).
export function restartSummary(r: RestartInfo): string {
  const block = `${r.n != null ? `N${r.n} ` : ""}(line ${r.line})`;
  if (r.phase === "searching") {
    return `${r.type.toUpperCase()} type restart searching: ${r.blocks} blocks, at ${block}; reset stops it`;
  }
  const where = Object.entries(r.position)
    .map(([axis, v]) => `${axis}${(v as number).toFixed(3)}`)
    .join(" ");
  const output = [
    r.tool != null ? `T${r.tool}` : null,
    r.spindle != null ? (r.spindle === 0 ? "M05" : `S${Math.abs(r.spindle)} ${r.spindle > 0 ? "M03" : "M04"}`) : null,
    ...r.m_codes.map((m) => `M${String(m).padStart(2, "0")}`),
  ].filter((x) => x != null);
  const phase = r.phase === "searched" ? "searched: cycle start returns the axes" : "returning to the restart position";
  return `${r.type.toUpperCase()} type restart at ${block}, ${phase}; to ${where}${output.length ? `; output ${output.join(" ")}` : ""}`;
}
