import { describe, expect, it } from "vitest";
import type { ControllerMessage } from "../api/client";
import { editorFor, workpieceOf, type Workpiece } from "./workpiece";

const bottom = { min: [-60, -40, 0], max: [60, 40, 30] };
const block: Workpiece = { boxes: [bottom] };
const two: Workpiece = { boxes: [bottom, { min: [-20, -20, 30], max: [20, 20, 50] }] };

/** What the page holds after these stream messages, in order (null: not told yet). */
function fold(messages: ControllerMessage[]): Workpiece | null {
  let now: Workpiece | null = null;
  for (const m of messages) now = workpieceOf(m) ?? now;
  return now;
}

describe("the workpiece from the controller's stream", () => {
  const snapshot = (workpiece: Workpiece) => ({ type: "snapshot", controller: {}, variables: {}, workpiece }) as unknown as ControllerMessage;
  const told = (w: Workpiece): ControllerMessage => ({ type: "workpiece", boxes: w.boxes ?? [] });
  const state = { type: "state", run_state: "idle", mode: "auto", program: null } as unknown as ControllerMessage;
  const variables: ControllerMessage = { type: "variables", changes: { "#500": 1 } };

  it("starts from the snapshot's workpiece", () => {
    expect(fold([snapshot(block)])).toEqual(block);
    expect(fold([snapshot({ boxes: [] })])).toEqual({ boxes: [] });
  });
  it("takes every change another client made, the newest winning", () => {
    expect(fold([snapshot({ boxes: [] }), told(block)])).toEqual(block);
    expect(fold([snapshot(block), told(two), state, told({ boxes: [] })])).toEqual({ boxes: [] });
  });
  it("keeps what it has through messages that do not say", () => {
    expect(fold([snapshot(two), state, variables])).toEqual(two);
    expect(fold([state, variables])).toBeNull();
  });
  it("starts again from a later snapshot (a client that fell behind, a controller that moved)", () => {
    expect(fold([snapshot(block), told({ boxes: [] }), snapshot(two)])).toEqual(two);
  });
});

describe("the Workpiece tab's editor", () => {
  it("is filled from what is on the table", () => {
    expect(editorFor({ text: "", edited: false }, block)).toEqual({ text: JSON.stringify(block, null, 1), edited: false });
    expect(JSON.parse(editorFor({ text: "x", edited: false }, null).text)).toEqual({ boxes: [] });
  });
  it("keeps an edit under way when the table changes", () => {
    const typing = { text: '{"boxes": [', edited: true };
    expect(editorFor(typing, two)).toBe(typing);
  });
});
