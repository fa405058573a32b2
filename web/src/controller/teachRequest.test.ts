import { describe, expect, it } from "vitest";
import { SLOTS, teachRequest } from "./teachRequest";

describe("the Teach panel's request", () => {
  it("sends only the values of its mode", () => {
    const typed = { i: "30", j: "15", k: "20", x: "1, 0, 0", z: "0 0 1" };
    expect(teachRequest("three_points", typed)).toEqual({ mode: "three_points" });
    expect(teachRequest("tool_direction", typed)).toEqual({ mode: "tool_direction", i: 30 });
    expect(teachRequest("euler", typed)).toEqual({ mode: "euler", i: 30, j: 15, k: 20 });
    expect(teachRequest("two_vectors", typed)).toEqual({ mode: "two_vectors", x: [1, 0, 0], z: [0, 0, 1] });
  });

  it("leaves blank values out and refuses what is not a number", () => {
    expect(teachRequest("euler", { i: " ", j: "-40.5" })).toEqual({ mode: "euler", i: undefined, j: -40.5, k: undefined });
    expect(() => teachRequest("euler", { i: "thirty" })).toThrow(/I is not a number/);
    expect(() => teachRequest("two_vectors", { x: "1, 0", z: "0,0,1" })).toThrow(/Xc needs three components/);
    expect(() => teachRequest("two_vectors", { x: "1, 0, y", z: "0,0,1" })).toThrow(/Xc is not a number/);
  });

  it("latches P2 and P3 only for three points", () => {
    expect(SLOTS.three_points).toEqual(["p1", "p2", "p3"]);
    for (const mode of ["tool_direction", "euler", "two_vectors"] as const) expect(SLOTS[mode]).toEqual(["p1"]);
  });
});
