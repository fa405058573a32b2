// What one position frame of the stream adds to the 3D view's traces: the tip (`tip_table`) to
// the tip trace, and under cutting point control (G43.8/G43.9) or a cutter compensation the
// cutting point to the cutting trace. The frame's `cutting` is in the active workpiece system, as `tip`; that system differs
// from the table frame by a translation only, so in the table frame the cutting point is
// `cutting + (tip_table − tip)`.
import type { Frame } from "../api/client";
import type { View3DHandle } from "./View3D";

/** What `traceFrame` needs of the view. */
export type FrameTraceTarget = Pick<View3DHandle, "addTrace" | "addCuttingTrace" | "endCuttingTrace">;

type Vec3 = [number, number, number];

/** The frame's cutting point in the table frame; null when it has none (under neither cutting point control nor a cutter compensation, or not moving). */
export function cuttingInTable(f: Pick<Frame, "tip" | "tip_table" | "cutting">): Vec3 | null {
  const c = f.cutting;
  if (!c || c.length < 3) return null;
  const p: Vec3 = [0, 0, 0];
  for (let k = 0; k < 3; k++) {
    p[k] = c[k] + (f.tip_table[k] - f.tip[k]);
    if (!Number.isFinite(p[k])) return null;
  }
  return p;
}

/** Feed one position frame to the view: the tip trace always, the cutting trace when the frame has a cutting point (else its stretch ends). */
export function traceFrame(target: FrameTraceTarget, f: Pick<Frame, "tip" | "tip_table" | "cutting">): void {
  target.addTrace(f.tip_table[0], f.tip_table[1], f.tip_table[2]);
  const c = cuttingInTable(f);
  if (c) target.addCuttingTrace(c[0], c[1], c[2]);
  else target.endCuttingTrace();
}

/** The active work offset's zero in the table frame: `tip_table − tip` (the systems differ by a translation); null for a frame without finite values. */
export function workZeroInTable(f: Pick<Frame, "tip" | "tip_table">): Vec3 | null {
  const p: Vec3 = [0, 0, 0];
  for (let k = 0; k < 3; k++) {
    p[k] = f.tip_table[k] - f.tip[k];
    if (!Number.isFinite(p[k])) return null;
  }
  return p;
}

/** A tilted working plane in the table frame: its origin and X, Y, Z axes. */
export type PlaneInTable = { origin: Vec3; axes: [Vec3, Vec3, Vec3] };

/** The frame's tilted working plane in the table frame (its origin moved by `tip_table − tip`, its axes as they are); null when none is in force. */
export function planeInTable(f: Pick<Frame, "tip" | "tip_table" | "plane">): PlaneInTable | null {
  const zero = workZeroInTable(f);
  const p = f.plane;
  if (!zero || !p || p.origin.length < 3 || p.axes.length < 3) return null;
  const axes = p.axes.slice(0, 3).map((a) => [a[0], a[1], a[2]] as Vec3) as [Vec3, Vec3, Vec3];
  return { origin: [zero[0] + p.origin[0], zero[1] + p.origin[1], zero[2] + p.origin[2]], axes };
}
