// The parameter editor in the dialect's numbering (FANUC No.…, Syntec Pr…, Haas Setting …): the whole list,
// filterable, each value editable (per-axis values as comma-separated lists).
import { memo } from "preact/compat";
import { useEffect, useState } from "preact/hooks";
import { api, must, type Schemas, type Status, errorText } from "../api/client";
import { EditCell } from "./EditCell";

function ParametersView({ status, onError }: { status: Status; onError: (e: string | null) => void }) {
  const id = status.id;
  const [params, setParams] = useState<Schemas["Params"]>({});
  const [filter, setFilter] = useState("");
  const load = () =>
    must(api.GET("/api/v1/controllers/{id}/parameters", { params: { path: { id } } })).then((l) => setParams(l.parameters), (e) => onError(errorText(e)));
  useEffect(() => {
    load();
  }, [id]);
  const set = async (number: string, text: string) => {
    onError(null);
    const parts = text.split(",").map((s) => s.trim());
    if (parts.includes("")) return onError("a value is missing (per-axis values: one per axis, comma-separated)");
    // Not a number: NaN, sent as null, which the service refuses with its reason.
    const value: Schemas["ParameterValue"] = parts.length > 1 ? parts.map(Number) : Number(parts[0]);
    try {
      await must(api.PUT("/api/v1/controllers/{id}/parameters/{number}", { params: { path: { id, number: Number(number) } }, body: { value } }));
    } catch (e) {
      onError(errorText(e));
    }
    load();
  };
  const prefix = status.dialect === "syntec" ? "Pr" : status.dialect === "haas" ? "Setting " : "No.";
  const rows = Object.entries(params).filter(([n]) => !filter || n.includes(filter.replace(/\D/g, "")));
  return (
    <div class="parameters">
      <div class="row">
        <input placeholder={`${prefix} filter`} value={filter} onInput={(e) => setFilter(e.currentTarget.value)} />
        <span class="quiet">{status.run_state === "idle" ? "a change restarts the controller on the new machine" : "parameters change only while idle"}</span>
      </div>
      <table class="grid">
        <thead>
          <tr>
            <th>number</th>
            <th>value</th>
          </tr>
        </thead>
        <tbody>
          {rows.map(([n, v]) => (
            <tr key={n}>
              <th>
                {prefix}
                {n}
              </th>
              <td>
                <EditCell wide value={Array.isArray(v) ? v.join(", ") : String(v)} onCommit={(text) => set(n, text)} />
              </td>
            </tr>
          ))}
        </tbody>
      </table>
    </div>
  );
}

/// Re-rendered only when its own props change, not with every position frame.
export const Parameters = memo(ParametersView);
