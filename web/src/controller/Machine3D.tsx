// The live 3D machine of a controller: the kinematic chain moved by the streamed axis values
// (the mechanism chain each frame names: after Syntec's G10 L5000 P2 the view turns set 2's head),
// the programmed path of the selected program, the executed tool tip trace and, under cutting
// point control (G43.8/G43.9), the trace of the cutting point (where the tool touches the part),
// the active work offset's zero as a triad and, while a tilted working plane is in force, its
// frame (triad and square), and what is clamped on the table (the workpiece's boxes, translucent,
// riding with the table); F (or "fit part") frames the part.
import { useEffect, useRef } from "preact/hooks";
import type { Frame, Machine, Schemas } from "../api/client";
import { View3D, type View3DHandle } from "../three/View3D";
import { planeInTable, traceFrame, workZeroInTable } from "../three/frameTrace";

export function Machine3D({
  machine,
  frame,
  path,
  workpiece,
  onFrame,
}: {
  machine: Machine;
  frame: Frame | null;
  path: { xyz: Float32Array; rapid: boolean[]; programmed: Float32Array | null } | null;
  /** The boxes on the table (`GET …/workpiece`), table frame. */
  workpiece: Schemas["Workpiece"] | null;
  onFrame: (f: (frame: Frame) => void) => () => void;
}) {
  const view = useRef<View3DHandle | null>(null);
  // Every frame's tip (and cutting point) goes to the traces as it arrives (the panel repaints
  // at most once per animation frame; the traces must not lose points in between).
  useEffect(
    () =>
      onFrame((f) => {
        if (!view.current) return;
        traceFrame(view.current, f);
        const zero = workZeroInTable(f);
        if (zero) view.current.setWorkZero(...zero);
        view.current.setWorkingPlane(planeInTable(f));
      }),
    [onFrame],
  );
  return (
    <div class="view3d">
      <View3D
        machine={machine}
        chain={frame?.chain}
        axes={frame?.machine}
        toolLength={frame?.tool_length ?? 0}
        path={path?.xyz}
        pathRapid={path?.rapid}
        programmedPath={path?.programmed ?? null}
        workpiece={workpiece?.boxes ?? null}
        onReady={(h) => {
          view.current = h;
          // The browser tests reach the view through this.
          (window as Window & { __fivexView?: View3DHandle | null }).__fivexView = h;
        }}
        style={{ position: "absolute", inset: "0" }}
      />
    </div>
  );
}
