import { describe, expect, it } from "vitest";
import { restartRequest, restartSummary, type RestartInfo } from "./restart";

describe("the restart dialog's request", () => {
  it("names the block by N or by line, with the pass count (1 when empty) and the program", () => {
    expect(restartRequest({ type: "p", by: "n", value: "50", occurrence: "" }, 12)).toEqual({ type: "p", n: 50, occurrence: 1, program: 12 });
    expect(restartRequest({ type: "q", by: "line", value: " 7 ", occurrence: "3" }, null)).toEqual({ type: "q", line: 7, occurrence: 3 });
  });
  it("refuses what the service would refuse", () => {
    expect(restartRequest({ type: "q", by: "n", value: "0", occurrence: "" }, 1)).toMatch(/sequence number/);
    expect(restartRequest({ type: "q", by: "line", value: "x", occurrence: "" }, 1)).toMatch(/line/);
    expect(restartRequest({ type: "q", by: "n", value: "10", occurrence: "-1" }, 1)).toMatch(/pass count/);
    expect(restartRequest({ type: "q", by: "n", value: "100000000", occurrence: "" }, 1)).toMatch(/sequence number/);
  });
});

describe("the restart line", () => {
  const info: RestartInfo = {
    type: "p",
    phase: "searched",
    line: 6,
    n: 50,
    blocks: 5,
    position: { X: 40, Y: 20, Z: 30 },
    tool: 3,
    spindle: -1500,
    m_codes: [8],
  };
  it("shows the block, the restart position and the M/S/T to output", () => {
    expect(restartSummary(info)).toBe(
      "P type restart at N50 (line 6), searched: cycle start returns the axes; to X40.000 Y20.000 Z30.000; output T3 S1500 M04 M08",
    );
  });
  it("shows how far a search under way has got, not a restart position", () => {
    expect(restartSummary({ ...info, phase: "searching", blocks: 15000, n: null, line: 4 })).toBe(
      "P type restart searching: 15000 blocks, at (line 4); reset stops it",
    );
  });
  it("leaves out what the search did not pass", () => {
    const s = restartSummary({ ...info, type: "q", phase: "returning", n: null, tool: null, spindle: 0, m_codes: [] });
    expect(s).toBe("Q type restart at (line 6), returning to the restart position; to X40.000 Y20.000 Z30.000; output M05");
  });
});
