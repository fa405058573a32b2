import { describe, expect, it } from "vitest";
import { parse } from "./route";

describe("hash routes", () => {
  it("names the fleet and a controller with its tab", () => {
    expect(parse("")).toEqual({ page: "fleet" });
    expect(parse("#/")).toEqual({ page: "fleet" });
    expect(parse("#/c/abc")).toEqual({ page: "controller", id: "abc", tab: "program" });
    expect(parse("#/c/a%20b/alarms")).toEqual({ page: "controller", id: "a b", tab: "alarms" });
    expect(parse("#/nothing")).toEqual({ page: "fleet" });
    expect(parse("#/runs")).toEqual({ page: "runs" });
    expect(parse("#/runs/r1")).toEqual({ page: "runs", id: "r1" });
  });
});
