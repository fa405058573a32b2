// What is clamped on the table: the boxes a G31 probe touches (`GET/PUT …/workpiece`, table
// frame, mm), listed, and edited as the JSON the service takes. The 3D view draws them. The
// list follows the controller's stream, so a change another client makes shows at once.
import { useEffect, useState } from "preact/hooks";
import { api, must, errorText, fmt } from "../api/client";
import { editorFor, type Editor, type Workpiece } from "./workpiece";

export function WorkpieceView({ id, workpiece, onChanged, onError }: { id: string; workpiece: Workpiece | null; onChanged: (w: Workpiece) => void; onError: (e: string | null) => void }) {
  const [editor, setEditor] = useState<Editor>({ text: "", edited: false });
  // The editor starts from what is on the table, and again after each change unless an edit is
  // under way.
  useEffect(() => setEditor((e) => editorFor(e, workpiece)), [JSON.stringify(workpiece)]);
  const put = async (body: Workpiece) => {
    onError(null);
    try {
      const now = await must(api.PUT("/api/v1/controllers/{id}/workpiece", { params: { path: { id } }, body }));
      setEditor(editorFor({ text: "", edited: false }, now));
      onChanged(now);
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
      <textarea class="nc" rows={6} spellcheck={false} value={editor.text} onInput={(e) => setEditor({ text: e.currentTarget.value, edited: true })} aria-label="workpiece JSON" />
      <div class="row">
        <button
          onClick={() => {
            let body: Workpiece;
            try {
              body = JSON.parse(editor.text);
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
