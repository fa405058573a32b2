// What a refused request's body says, for a person: the service's reason (`error`, always
// there on the service's own errors, `docs/api.md` "Errors") and, where `details` holds
// diagnostics (a program `check` refused) or names a line (a second program in the text), marks
// on those lines. `details` is not always a list: a program whose O number is not its slot
// answers `{"slot", "text_number"}`, a second program `{"slot", "line", "text_number"}`, and a
// shape no document foresaw must not hide the reason either.

export type Mark = { line: number; text: string };

export type Refusal = { message: string; marks: Mark[] };

const isObject = (v: unknown): v is Record<string, unknown> => typeof v === "object" && v !== null && !Array.isArray(v);
const str = (v: unknown): string => (typeof v === "string" ? v : v == null ? "" : JSON.stringify(v));
const lineOf = (v: unknown): number | null => (typeof v === "number" && Number.isInteger(v) && v >= 1 ? v : null);

/// A diagnostic (`Diagnostic`) as a mark, or null for anything else.
function diagnosticMark(d: unknown): Mark | null {
  if (!isObject(d)) return null;
  const line = lineOf(d.line);
  if (line == null) return null;
  const head = [str(d.code), str(d.message)].filter((s) => s !== "").join(" ");
  const detail = str(d.detail);
  return { line, text: `${head}${detail ? `: ${detail}` : ""}` || "refused" };
}

/// The reason and the marks of a refused answer (`status`, its body as parsed, or whatever it
/// was when it was not JSON).
export function refusal(status: number, statusText: string, body: unknown): Refusal {
  const error = isObject(body) && typeof body.error === "string" && body.error.trim() !== "" ? body.error : null;
  const details = isObject(body) ? body.details : undefined;
  const marks: Mark[] = [];
  let unread = false;
  if (Array.isArray(details)) {
    for (const d of details) {
      const m = diagnosticMark(d);
      if (m) marks.push(m);
      else unread = true;
    }
  } else if (isObject(details)) {
    // `{"slot", "line", "text_number"}`: the line where the second program starts.
    const line = lineOf(details.line);
    if (line != null) {
      const n = typeof details.text_number === "number" ? ` O${String(details.text_number).padStart(4, "0")}` : "";
      marks.push({ line, text: `a second program${n} starts here` });
    }
  } else if (details != null) unread = true;
  let message = error ?? `${status}${statusText ? ` ${statusText}` : ""}: the service gave no reason`;
  // Without a reason of its own, whatever else the body holds is the only clue.
  if (!error && (unread || isObject(details))) message += ` (${str(details)})`;
  else if (!error && typeof body === "string" && body.trim() !== "") message += ` (${body.trim().slice(0, 200)})`;
  return { message, marks };
}
