// The macro variable table: the common variables that are set (live), editable in place, and
// any variable (system variables too) read by number.
import { memo } from "preact/compat";
import { useState } from "preact/hooks";
import { api, must, errorText } from "../api/client";
import { EditCell } from "./EditCell";

function VariablesView({ id, values, onError }: { id: string; values: Record<string, number | null>; onError: (e: string | null) => void }) {
  const [number, setNumber] = useState("");
  const [read, setRead] = useState<string | null>(null);
  const set = async (n: number, text: string) => {
    onError(null);
    const value = text.trim() === "" ? null : Number(text);
    if (value !== null && !Number.isFinite(value)) {
      onError(`${text} is not a number`);
      return false;
    }
    try {
      await must(api.PUT("/api/v1/controllers/{id}/variables/{number}", { params: { path: { id, number: n } }, body: { value } }));
      return true;
    } catch (e) {
      onError(errorText(e));
      return false;
    }
  };
  const rows = Object.entries(values)
    .filter(([, v]) => v != null)
    .map(([k, v]) => [Number(k.slice(1)), v] as [number, number])
    .sort((a, b) => a[0] - b[0]);
  return (
    <div class="variables">
      <form
        class="row"
        onSubmit={async (e) => {
          e.preventDefault();
          const n = Number(number.replace("#", ""));
          try {
            const v = await must(api.GET("/api/v1/controllers/{id}/variables/{number}", { params: { path: { id, number: n } } }));
            setRead(`#${n} = ${v.value ?? "<vacant>"}`);
          } catch (err) {
            setRead(errorText(err));
          }
        }}
      >
        <input class="short" name="var-number" placeholder="#500" value={number} onInput={(e) => setNumber(e.currentTarget.value)} />
        <button type="submit">read</button>
        <button
          type="button"
          onClick={() => {
            const n = Number(number.replace("#", ""));
            const v = prompt(`New value of #${n} (empty: vacant)`);
            if (v !== null) set(n, v);
          }}
        >
          set
        </button>
        {read && <span class="read">{read}</span>}
      </form>
      <table class="grid vars">
        <thead>
          <tr>
            <th>variable</th>
            <th>value</th>
          </tr>
        </thead>
        <tbody>
          {rows.length === 0 && (
            <tr>
              <td colSpan={2} class="quiet">
                Every common variable (#100–#199, #500–#999) is vacant.
              </td>
            </tr>
          )}
          {rows.map(([n, v]) => (
            <tr key={n} data-var={n}>
              <th>#{n}</th>
              <td>
                <EditCell value={String(v)} onCommit={(text) => set(n, text)} />
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

/// Re-rendered only when its own props change, not with every position frame.
export const Variables = memo(VariablesView);
