// Tool offset memory (H length and D radius, geometry and wear; the corner radius G43.8/G43.9
// read) and the work offsets.
import { memo } from "preact/compat";
import { useEffect, useState } from "preact/hooks";
import { api, must, type Schemas, errorText } from "../api/client";
import { EditCell } from "./EditCell";

/// A number as typed in a cell (blank, `abc`, `1..2`, `Infinity`: none).
export function parseNumber(text: string): number | null {
  const t = text.trim();
  if (t === "") return null;
  const v = Number(t);
  return Number.isFinite(v) ? v : null;
}

const TOOL_FIELDS = ["length", "length_wear", "radius", "radius_wear", "corner_radius"] as const;

function OffsetsView({ id, axes, onError }: { id: string; axes: string[]; onError: (e: string | null) => void }) {
  const [tools, setTools] = useState<Schemas["ToolOffsetDto"][]>([]);
  const [works, setWorks] = useState<Schemas["WorkOffsetDto"][]>([]);
  const [more, setMore] = useState("");
  const p = { params: { path: { id } } };
  const load = () => {
    must(api.GET("/api/v1/controllers/{id}/tool-offsets", p)).then(setTools, (e) => onError(errorText(e)));
    must(api.GET("/api/v1/controllers/{id}/work-offsets", p)).then(setWorks, (e) => onError(errorText(e)));
  };
  useEffect(load, [id]);
  /// A change: whether the service took it (refused, the reason is shown and the cell goes back
  /// to the value the service holds).
  const setTool = async (number: number, field: string, value: number) => {
    onError(null);
    try {
      await must(api.PUT("/api/v1/controllers/{id}/tool-offsets/{number}", { params: { path: { id, number } }, body: { [field]: value } }));
      return true;
    } catch (e) {
      onError(errorText(e));
      return false;
    } finally {
      load();
    }
  };
  const setWork = async (name: string, axis: string, value: number) => {
    onError(null);
    try {
      await must(api.PUT("/api/v1/controllers/{id}/work-offsets/{name}", { params: { path: { id, name } }, body: { axes: { [axis]: value } } }));
      return true;
    } catch (e) {
      onError(errorText(e));
      return false;
    } finally {
      load();
    }
  };
  const numberInput = (value: number, what: string, on: (v: number) => Promise<boolean>) => (
    <EditCell
      value={String(value)}
      onCommit={(text) => {
        const v = parseNumber(text);
        if (v == null) {
          onError(`${what}: "${text}" is not a number (${value} kept)`);
          return false;
        }
        return on(v);
      }}
    />
  );
  return (
    <div class="offsets">
      <h3>Tool offsets</h3>
      <table class="grid">
        <thead>
          <tr>
            <th>no.</th>
            <th>length (H)</th>
            <th>wear</th>
            <th>radius (D)</th>
            <th>wear</th>
            <th title="corner radius (cutting point control G43.8/G43.9): 0 for a square or a ball end mill">Corner R</th>
          </tr>
        </thead>
        <tbody>
          {tools.map((t) => (
            <tr key={t.number} data-tool={t.number}>
              <th>{t.number}</th>
              {TOOL_FIELDS.map((f) => (
                <td data-field={f}>{numberInput(t[f], `tool offset ${t.number} ${f}`, (v) => setTool(t.number, f, v))}</td>
              ))}
            </tr>
          ))}
        </tbody>
      </table>
      <div class="row">
        <input class="short" placeholder="offset no." value={more} onInput={(e) => setMore(e.currentTarget.value)} />
        <button
          onClick={() => {
            const n = Number(more);
            // A new row to fill in; the service lists only the offsets that are not all zero.
            if (n >= 1 && n <= 999 && !tools.some((t) => t.number === n))
              setTools([...tools, { number: n, length: 0, length_wear: 0, radius: 0, radius_wear: 0, corner_radius: 0 }].sort((a, b) => a.number - b.number));
          }}
        >
          add
        </button>
      </div>
      <h3>Work offsets</h3>
      <table class="grid">
        <thead>
          <tr>
            <th />
            {axes.map((a) => (
              <th>{a}</th>
            ))}
          </tr>
        </thead>
        <tbody>
          {works.map((w) => (
            <tr key={w.name}>
              <th>{w.name}</th>
              {axes.map((a) => (
                <td>{numberInput(w.axes[a] ?? 0, `${w.name} ${a}`, (v) => setWork(w.name, a, v))}</td>
              ))}
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

/// Re-rendered only when its own props change, not with every position frame.
export const Offsets = memo(OffsetsView);
