// NC text with line numbers, the executing line highlighted and kept in view, and diagnostics
// marked on their lines. Only the visible lines are in the page, so a program of 100,000
// lines scrolls as smoothly as one of ten.
import { useEffect, useMemo, useRef, useState } from "preact/hooks";

const LINE_PX = 18;

export type Mark = { line: number; text: string };

export function CodeView({ text, active, marks = [], height = 420 }: { text: string; active?: number; marks?: Mark[]; height?: number }) {
  const lines = useMemo(() => text.split("\n"), [text]);
  const byLine = useMemo(() => {
    const m = new Map<number, string[]>();
    for (const d of marks) m.set(d.line, [...(m.get(d.line) ?? []), d.text]);
    return m;
  }, [marks]);
  const box = useRef<HTMLDivElement>(null);
  const [top, setTop] = useState(0);
  const [follow, setFollow] = useState(true);

  useEffect(() => {
    const el = box.current;
    if (!el || !follow || !active) return;
    const y = (active - 1) * LINE_PX;
    if (y < el.scrollTop || y > el.scrollTop + height - 3 * LINE_PX) el.scrollTop = Math.max(0, y - height / 3);
  }, [active, follow, height]);

  const first = Math.max(0, Math.floor(top / LINE_PX) - 20);
  const last = Math.min(lines.length, first + Math.ceil(height / LINE_PX) + 40);
  const digits = String(lines.length).length;
  return (
    <div class="code-wrap">
      <label class="follow">
        <input type="checkbox" checked={follow} onChange={(e) => setFollow(e.currentTarget.checked)} /> follow the executing block
      </label>
      <div class="code" ref={box} style={{ height: `${height}px` }} onScroll={(e) => setTop(e.currentTarget.scrollTop)}>
        <div style={{ height: `${lines.length * LINE_PX}px`, position: "relative" }}>
          {lines.slice(first, last).map((l, i) => {
            const n = first + i + 1;
            const notes = byLine.get(n);
            return (
              <div
                key={n}
                class={`line ${n === active ? "active" : ""} ${notes ? "marked" : ""}`}
                data-line={n}
                style={{ top: `${(n - 1) * LINE_PX}px` }}
                title={notes?.join("\n")}
              >
                <span class="ln">{String(n).padStart(digits, " ")}</span>
                <span class="src">{l || " "}</span>
                {notes && <span class="note">{notes.join("; ")}</span>}
              </div>
            );
          })}
        </div>
      </div>
    </div>
  );
}
