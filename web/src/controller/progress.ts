// The words and numbers of the cycle-time box: a program's estimate before it runs, the time
// left and the percentage while it runs, and what makes them inexact (`docs/api.md`,
// "Cycle-time estimate and progress").
import type { Schemas } from "../api/client";

export type Estimate = Schemas["Estimate"];
export type RunProgress = Schemas["RunProgress"];

/** Seconds as m:ss.s, or h:mm:ss from an hour on. */
export function clock(s: number): string {
  if (!Number.isFinite(s) || s < 0) return "—";
  if (s >= 3600) {
    const t = Math.round(s);
    const [h, m, sec] = [Math.floor(t / 3600), Math.floor((t % 3600) / 60), t % 60];
    return `${h}:${String(m).padStart(2, "0")}:${String(sec).padStart(2, "0")}`;
  }
  const tenths = Math.round(s * 10);
  const m = Math.floor(tenths / 600);
  const rest = (tenths % 600) / 10;
  return `${m}:${rest < 10 ? "0" : ""}${rest.toFixed(1)}`;
}

const CAVEATS: Record<string, string> = {
  feed_override: "feed override ≠ 100 %",
  rapid_override: "rapid override ≠ 100 %",
  single_block: "single block",
  optional_stop: "optional stop on",
  held: "was held",
  input_signals: "reads input signals #1000–#1035",
  program_stop: "waits at M00",
};

/** What the program's time depends on outside it (the estimate's `depends_on`), in words. */
const dependsText = (e: Estimate | null | undefined) => (e?.depends_on ?? []).map((d) => CAVEATS[d] ?? d).join(", ");

/** What the estimate itself says: its time, or why there is none. */
export function estimateText(e: Estimate | null): string {
  if (!e) return "";
  switch (e.state) {
    case "pending":
      return "estimating…";
    case "ready":
      return `cycle time ${clock(e.cycle_time_s ?? NaN)}`;
    case "alarm":
      return `stops at ${e.alarm?.code ?? "an alarm"} (line ${e.alarm?.line ?? "?"}) after ${clock(e.cycle_time_s ?? NaN)}`;
    default:
      return `no estimate: ${e.reason ?? e.state}`;
  }
}

export type ProgressView = {
  /** The main line. */
  text: string;
  /** 0–100 for the bar; null: no bar. */
  percent: number | null;
  /** Why the remaining time is not exact; empty when it runs as estimated. */
  caveats: string;
};

/** The box's content: the run under way when there is one, else the selected program's estimate. */
export function progressView(run: RunProgress | null | undefined, estimate: Estimate | null): ProgressView {
  if (run) {
    const caveats = [...run.caveats, ...(run.estimate.depends_on ?? [])].map((c) => CAVEATS[c] ?? c).join(", ");
    if (run.remaining_s == null || run.percent == null) {
      return { text: `O${pad(run.program)} ${clock(run.elapsed_s)} elapsed · ${estimateText(run.estimate)}`, percent: null, caveats };
    }
    return {
      text: `O${pad(run.program)} ${clock(run.elapsed_s)} elapsed · ${clock(run.remaining_s)} left · ${run.percent.toFixed(0)} %`,
      percent: run.percent,
      caveats: caveats && `estimate at 100 %, no stops: ${caveats}`,
    };
  }
  const depends = dependsText(estimate);
  return { text: estimateText(estimate), percent: null, caveats: depends && `depends on the run: ${depends}` };
}

const pad = (n: number) => String(n).padStart(4, "0");
