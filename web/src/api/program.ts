/**
 * The number a program text gives its first program (`O1000`, or the ISO form `:1000`), read as
 * the service reads it: after blank lines, `%` lines and comment-only lines; `null` when the text
 * starts without one. The service stores a text with a number only in that slot (a text in
 * another slot is refused with 422), so this is where an upload or a fleet program goes.
 */
export function programNumber(text: string): number | null {
  for (const raw of text.split("\n")) {
    const line = raw.trim();
    if (line === "" || line.startsWith("%") || /^(\([^)]*\)\s*)+$/.test(line)) continue;
    const own = /^[Oo:](\d{1,8})/.exec(line);
    return own ? Number(own[1]) : null;
  }
  return null;
}
