import { describe, expect, it } from "vitest";
import type { FleetEntry } from "../api/client";
import { applyDelta } from "./delta";

const entry = (id: string, run_state: FleetEntry["run_state"] = "idle"): FleetEntry => ({
  id,
  name: `cell ${id}`,
  machine: "table-ac",
  kind: "table-table",
  dialect: "fanuc",
  mode: "auto",
  run_state,
  program: null,
  line: 0,
  line_program: null,
  alarm: null,
});

describe("applyDelta", () => {
  it("replaces a changed controller in place and keeps the others", () => {
    const fleet = [entry("a"), entry("b"), entry("c")];
    const next = applyDelta(fleet, { type: "fleet_delta", controllers: [entry("b", "running")], removed: [] });
    expect(next.map((c) => [c.id, c.run_state])).toEqual([
      ["a", "idle"],
      ["b", "running"],
      ["c", "idle"],
    ]);
    expect(next[0]).toBe(fleet[0]);
  });

  it("removes first, then appends a new controller", () => {
    const next = applyDelta([entry("a"), entry("b")], { type: "fleet_delta", controllers: [entry("d")], removed: ["a"] });
    expect(next.map((c) => c.id)).toEqual(["b", "d"]);
  });
});
