// MDI: type blocks and run them (the service switches to MDI mode).
import { memo } from "preact/compat";
import { useState } from "preact/hooks";
import { api, type Status, errorText } from "../api/client";
import type { Act } from "./useController";

function MdiView({ status, run: act, onError }: { status: Status; run: Act; onError: (e: string | null) => void }) {
  const [text, setText] = useState("");
  const [history, setHistory] = useState<string[]>([]);
  const run = async (e: Event) => {
    e.preventDefault();
    if (!text.trim()) return;
    onError(null);
    try {
      await act(() => api.POST("/api/v1/controllers/{id}/mdi", { params: { path: { id: status.id } }, body: { text } }));
      setHistory((h) => [text, ...h.filter((x) => x !== text)].slice(0, 20));
    } catch (err) {
      onError(errorText(err));
    }
  };
  return (
    <form class="mdi" onSubmit={run}>
      <textarea
        class="nc"
        name="mdi"
        rows={4}
        placeholder="G91 G01 X10. F500"
        value={text}
        onInput={(e) => setText(e.currentTarget.value)}
        onKeyDown={(e) => {
          if (e.key === "Enter" && (e.ctrlKey || e.metaKey)) run(e);
        }}
      />
      <div>
        <button type="submit" class="primary">
          run MDI (Ctrl+Enter)
        </button>
      </div>
      {history.length > 0 && (
        <ul class="mdi-history">
          {history.map((h) => (
            <li>
              <a onClick={() => setText(h)}>{h.replace(/\n/g, " ⏎ ")}</a>
            </li>
          ))}
        </ul>
      )}
    </form>
  );
}

/// Re-rendered only when its own props change, not with every position frame.
export const Mdi = memo(MdiView);
