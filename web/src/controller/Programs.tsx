// Stored programs: the list, the text with the executing block highlighted, an editor that
// stores through the service's check (diagnostics shown on their lines), upload, and start.
import { useEffect, useRef, useState } from "preact/hooks";
import { api, authFetch, must, type Schemas, type Status, errorText } from "../api/client";
import type { Act } from "./useController";
import { programNumber } from "../api/program";
import { CodeView, type Mark } from "./CodeView";
import { refusal } from "../api/refusal";
import { Restart } from "./Restart";

export function Programs({
  status,
  line,
  selected,
  onSelect,
  run,
  onError,
  onStored,
}: {
  status: Status;
  /// The line moving now (from the position stream).
  line: number;
  selected: number | null;
  onSelect: (n: number | null) => void;
  run: Act;
  onError: (e: string | null) => void;
  /// A program was stored (its estimate is asked for again).
  onStored?: (n: number) => void;
}) {
  const id = status.id;
  const [list, setList] = useState<Schemas["ProgramSummary"][]>([]);
  const [text, setText] = useState("");
  const [draft, setDraft] = useState<string | null>(null);
  /// What the draft started from (the stored text, a new program's template): it holds an
  /// unsaved edit when it differs.
  const [base, setBase] = useState<string | null>(null);
  const edit = (from: string | null) => {
    setDraft(from);
    setBase(from);
  };
  const unsaved = draft != null && draft !== base;
  /// Whether what is being typed may go: nothing unsaved, or the operator says so.
  const mayDiscard = () => !unsaved || confirm(`Discard the unsaved changes to O${String(selected).padStart(4, "0")}?`);
  // A reload or closing the tab asks too while an edit is unsaved.
  useEffect(() => {
    if (!unsaved) return;
    const ask = (e: BeforeUnloadEvent) => {
      e.preventDefault();
      e.returnValue = "";
    };
    addEventListener("beforeunload", ask);
    return () => removeEventListener("beforeunload", ask);
  }, [unsaved]);
  const [marks, setMarks] = useState<Mark[]>([]);
  const [newNumber, setNewNumber] = useState("");
  /// The template of a program being created, shown in the editor once it is selected.
  const fresh = useRef<string | null>(null);
  const refresh = () => must(api.GET("/api/v1/controllers/{id}/programs", { params: { path: { id } } })).then(setList, () => {});

  useEffect(() => {
    refresh();
  }, [id]);
  useEffect(() => {
    if (selected == null && list.length) onSelect(status.program ?? list[0].number);
  }, [list]);
  useEffect(() => {
    // The running program shows as it runs, unless another one is being edited (background
    // edit: its draft must not be lost to a run state change).
    if (status.program != null && status.run_state !== "idle" && draft == null) onSelect(status.program);
  }, [status.program, status.run_state]);
  useEffect(() => {
    setMarks([]);
    edit(fresh.current);
    if (fresh.current != null) {
      fresh.current = null;
      return setText("");
    }
    if (selected == null) return setText("");
    authFetch(`/api/v1/controllers/${id}/programs/${selected}`)
      .then((r) => (r.ok ? r.text() : ""))
      .then(setText);
  }, [selected, id]);

  const store = async (number: number, body: string, force = false) => {
    onError(null);
    setMarks([]);
    try {
      const res = await authFetch(`/api/v1/controllers/${id}/programs/${number}${force ? "?force=true" : ""}`, {
        method: "PUT",
        headers: { "content-type": "text/plain" },
        body,
      });
      const raw = await res.text();
      let answer: unknown = raw;
      try {
        answer = JSON.parse(raw);
      } catch {
        /* not JSON: the text itself */
      }
      if (!res.ok) {
        // The draft stays in the editor: the reason is shown, and the marks on their lines.
        const refused = refusal(res.status, res.statusText, answer);
        setMarks(refused.marks);
        onError(refused.message);
        return false;
      }
      const stored = answer as Schemas["StoredProgram"];
      setMarks((stored.diagnostics ?? []).map((d) => ({ line: d.line, text: `${d.code} ${d.message}` })));
      await refresh();
      onStored?.(number);
      if (selected === number) setText(body);
      else onSelect(number);
      edit(null);
      return true;
    } catch (e) {
      onError(errorText(e));
      return false;
    }
  };

  const upload = async (input: HTMLInputElement) => {
    const file = input.files?.[0];
    if (!file) return;
    if (!mayDiscard()) {
      input.value = "";
      return;
    }
    const body = await file.text();
    // A text with its own O number can only go in that slot; otherwise the file name's number.
    const own = programNumber(body);
    const m = /(\d{1,4})/.exec(file.name);
    const number = Number(prompt("Store as program number", String(own ?? (m ? Number(m[1]) : 1))));
    input.value = "";
    if (number >= 1 && number <= 9999) await store(number, body);
  };

  const running = status.program === selected && status.run_state !== "idle";
  return (
    <div class="programs">
      <aside class="prog-list">
        <ul>
          {list.map((p) => (
            <li key={p.number} class={p.number === selected ? "sel" : ""}>
              <a onClick={() => p.number !== selected && mayDiscard() && onSelect(p.number)} data-program={p.number}>
                O{String(p.number).padStart(4, "0")}
              </a>
              <span class="size">{p.size} B</span>
            </li>
          ))}
        </ul>
        <div class="new">
          <input class="short" placeholder="O no." value={newNumber} onInput={(e) => setNewNumber(e.currentTarget.value)} />
          <button
            onClick={() => {
              const n = Number(newNumber);
              if (n >= 1 && n <= 9999 && mayDiscard()) {
                const template = `O${String(n).padStart(4, "0")}\n\nM30\n`;
                if (n === selected) edit(template);
                else {
                  fresh.current = template;
                  onSelect(n);
                }
              }
            }}
          >
            new
          </button>
        </div>
        <label class="upload">
          upload <input type="file" accept=".nc,.txt,.tap,text/plain" onChange={(e) => upload(e.currentTarget)} />
        </label>
      </aside>
      <div class="prog-main">
        <div class="prog-bar">
          <strong>{selected != null ? `O${String(selected).padStart(4, "0")}` : "no program"}</strong>
          {selected != null && draft == null && (
            <>
              <button
                class="primary"
                data-action="run"
                onClick={async () => {
                  onError(null);
                  try {
                    await run(() => api.POST("/api/v1/controllers/{id}/cycle-start", { params: { path: { id } }, body: { program: selected } }));
                  } catch (e) {
                    onError(errorText(e));
                  }
                }}
              >
                cycle start O{selected}
              </button>
              <button onClick={() => edit(text)} disabled={running}>
                edit
              </button>
              <button
                class="danger"
                onClick={async () => {
                  if (!confirm(`Delete O${selected}?`)) return;
                  await authFetch(`/api/v1/controllers/${id}/programs/${selected}`, { method: "DELETE" });
                  onSelect(null);
                  refresh();
                }}
              >
                delete
              </button>
              <Restart status={status} program={selected} run={run} onError={onError} />
            </>
          )}
          {draft != null && selected != null && (
            <>
              <button class="primary" data-action="save" onClick={() => store(selected, draft)}>
                check &amp; save
              </button>
              <button title="store even with diagnostics" onClick={() => store(selected, draft, true)}>
                save anyway
              </button>
              <button onClick={() => mayDiscard() && edit(null)}>cancel</button>
            </>
          )}
        </div>
        {draft != null ? (
          <div class="editor">
            <textarea class="nc" spellcheck={false} value={draft} onInput={(e) => setDraft(e.currentTarget.value)} />
            {marks.length > 0 && (
              <ul class="diags">
                {marks.map((m) => (
                  <li>
                    line {m.line}: {m.text}
                  </li>
                ))}
              </ul>
            )}
          </div>
        ) : (
          <CodeView text={text} active={status.program === selected ? line : undefined} marks={marks} />
        )}
      </div>
    </div>
  );
}
