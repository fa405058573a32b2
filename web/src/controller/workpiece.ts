// What is clamped on the table as the controller's stream tells it: the snapshot carries the
// workpiece, a `workpiece` message every change (a PUT from this page or from any other client),
// so every dashboard on the controller redraws the boxes and relists them without a reload.
import type { ControllerMessage, Schemas } from "../api/client";

export type Workpiece = Schemas["Workpiece"];

/** What a stream message says is on the table now; `undefined`: the message does not say. */
export function workpieceOf(msg: ControllerMessage): Workpiece | undefined {
  switch (msg.type) {
    case "snapshot":
      return msg.workpiece;
    case "workpiece":
      return { boxes: msg.boxes };
    default:
      return undefined;
  }
}

/** The Workpiece tab's editor: its text, and whether the user changed it since it was filled. */
export type Editor = { text: string; edited: boolean };

/**
 * The editor once `workpiece` is on the table: filled from it, unless the user is in the middle
 * of an edit (a change another client made must not throw away what is being typed; the list
 * above the editor shows the new boxes at once either way).
 */
export function editorFor(editor: Editor, workpiece: Workpiece | null): Editor {
  return editor.edited ? editor : { text: JSON.stringify(workpiece ?? { boxes: [] }, null, 1), edited: false };
}
