import { describe, expect, it } from "vitest";
import { clock, estimateText, progressView, type Estimate, type RunProgress } from "./progress";

const ready: Estimate = { state: "ready", cycle_time_s: 83.42, alarm: null, reason: null, depends_on: [] };

describe("the cycle-time box", () => {
  it("writes times as m:ss.s and h:mm:ss", () => {
    expect(clock(0)).toBe("0:00.0");
    expect(clock(83.42)).toBe("1:23.4");
    expect(clock(59.96)).toBe("1:00.0");
    expect(clock(3725.4)).toBe("1:02:05");
    expect(clock(-1)).toBe("—");
    expect(clock(NaN)).toBe("—");
  });

  it("says what the estimate is, or why there is none", () => {
    expect(estimateText(ready)).toBe("cycle time 1:23.4");
    expect(estimateText({ state: "pending", cycle_time_s: null, alarm: null, reason: null })).toBe("estimating…");
    expect(estimateText({ state: "alarm", cycle_time_s: 1.25, alarm: { code: "MC3000", message: "STOP", line: 2, n: null }, reason: "x" })).toBe("stops at MC3000 (line 2) after 0:01.3");
    expect(estimateText({ state: "unknown", cycle_time_s: null, alarm: null, reason: "the simulation took longer than 30 s" })).toBe("no estimate: the simulation took longer than 30 s");
  });

  it("shows a run's time left and percentage, and what makes them inexact", () => {
    const run: RunProgress = { program: 7, elapsed_s: 20, estimate: ready, remaining_s: 63.42, percent: 23.97, caveats: [] };
    expect(progressView(run, null)).toEqual({ text: "O0007 0:20.0 elapsed · 1:03.4 left · 24 %", percent: 23.97, caveats: "" });
    const slow = progressView({ ...run, caveats: ["feed_override", "held"] }, null);
    expect(slow.caveats).toBe("estimate at 100 %, no stops: feed override ≠ 100 %, was held");
    const none = progressView({ ...run, remaining_s: null, percent: null, estimate: { state: "unknown", cycle_time_s: null, alarm: null, reason: "why" } }, ready);
    expect(none).toEqual({ text: "O0007 0:20.0 elapsed · no estimate: why", percent: null, caveats: "" });
    // Without a run: the selected program's estimate, and what its time depends on.
    expect(progressView(null, ready)).toEqual({ text: "cycle time 1:23.4", percent: null, caveats: "" });
    const waits = { ...ready, depends_on: ["program_stop", "input_signals"] };
    expect(progressView(null, waits).caveats).toBe("depends on the run: waits at M00, reads input signals #1000–#1035");
    expect(progressView({ ...run, estimate: waits }, null).caveats).toBe("estimate at 100 %, no stops: waits at M00, reads input signals #1000–#1035");
  });
});
