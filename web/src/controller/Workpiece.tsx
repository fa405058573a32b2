// What is clamped on the table: the boxes a G31 probe touches (`GET/PUT …/workpiece`, table
// frame, mm), listed, and edited as the JSON the service takes. The 3D view draws them.
import { useEffect, useState } from "preact/hooks";
import { api, must, type Schemas, errorText, fmt } from "../api/client";

type Workpiece = Schemas["Workpiece"];

export function WorkpieceView({ id, workpiece, onChanged, onError }: { id: string; workpiece: Workpiece | null; onChanged: (w: Workpiece) => void; onError: (e: string | null) => void }) {
  const [text, setText] = useState("");
  // The editor starts from what is on the table, and again after each change.
  useEffect(() => setText(JSON.stringify(workpiece ?? { boxes: [] }, null, 1)), [JSON.stringify(workpiece)]);
  const put = async (body: Workpiece) => {
    onError(null);
    try {
      onChanged(await must(api.PUT("/api/v1/controllers/{id}/workpiece", { params: { path: { id } }, body })));
    } catch (e) {
      onError(errorText(e));
    }
  };
  const boxes = workpiece?.boxes ?? [];
  return (
    <div class="workpiece">
      <h3>Workpiece (what a G31 probe touches)</h3>
      <p class="hint">Axis-aligned boxes in the table frame (machine coordinates with the table axes at zero), mm.</p>
      {boxes.length === 0 ? (
        <p data-testid="workpiece-empty">Nothing on the table: a G31 runs its whole move.</p>
      ) : (
        <table class="grid" data-testid="workpiece-boxes">
          <thead>
            <tr>
              <th>box</th>
              <th>min X</th>
              <th>min Y</th>
              <th>min Z</th>
              <th>max X</th>
              <th>max Y</th>
              <th>max Z</th>
            </tr>
          </thead>
          <tbody>
            {boxes.map((b, i) => (
              <tr key={i}>
                <th>{i + 1}</th>
                {[...b.min, ...b.max].map((v) => (
                  <td class="num">{fmt(v)}</td>
                ))}
              </tr>
            ))}
          </tbody>
        </table>
      )}
      <textarea class="nc" rows={6} spellcheck={false} value={text} onInput={(e) => setText(e.currentTarget.value)} aria-label="workpiece JSON" />
      <div class="row">
        <button
          onClick={() => {
            let body: Workpiece;
            try {
              body = JSON.parse(text);
            } catch (e) {
              return onError(`not JSON: ${errorText(e)}`);
            }
            put(body);
          }}
        >
          Put on the table
        </button>
        <button onClick={() => put({ boxes: [] })}>Clear the table</button>
      </div>
    </div>
  );
}
