// The 3D machine view as a Preact component.
//
//   <View3D machine={model} axes={position.machine} toolLength={L} path={points}
//           onReady={(h) => (trace = h)} />
//   trace?.addTrace(tip[0], tip[1], tip[2]);       // table frame, e.g. from the position stream
//   trace?.addCuttingTrace(c[0], c[1], c[2]);      // under G43.8/G43.9: the cutting point, table frame
//   trace?.endCuttingTrace();                      // a frame without one
//
// `machine` (re)builds the view when its content changes; `chain`, `axes`, `toolLength` and
// `path` are applied as they change (a new chain rebuilds the rig alone: the traces, the path and
// the camera stay). Trace points are pushed through the handle given to `onReady`
// (pushing them through props would re-render per point).

import { useEffect, useRef, useState } from "preact/hooks";
import type { CSSProperties } from "preact";
import { MachineView } from "./scene";
import type { MachineViewOptions, ViewPreset } from "./scene";
import type { MachineModel, MachineModelInput } from "./model";
import type { Chain } from "./chain";
import type { PlaneInTable } from "./frameTrace";
import type { WorkpieceBox } from "./part";

export interface View3DHandle {
  /** One executed tool-tip position, table frame. */
  addTrace(x: number, y: number, z: number): void;
  /** Many positions at once (xyz triples, table frame). */
  addTracePoints(xyz: ArrayLike<number>): void;
  /** Add the current tool tip (forward kinematics of the axes and tool length last given) to the trace. */
  addTraceAtTip(): void;
  /**
   * One cutting point (cutting point control G43.8/G43.9: where the tool touches the part), table
   * frame: extends the cutting trace, drawn beside the tip trace, and moves its marker there.
   */
  addCuttingTrace(x: number, y: number, z: number): void;
  /** A position without a cutting point: the cutting trace's stretch ends (the next point starts a new one), the marker hides. */
  endCuttingTrace(): void;
  /** Clear the tip trace and the cutting point's trace. */
  clearTrace(): void;
  fit(): void;
  /** Frame the part: the programmed path, the tip trace, the work zero and the workpiece (key F). */
  fitPart(): void;
  /** The active work offset's zero in the table frame (a frame's `tip_table − tip`). */
  setWorkZero(x: number, y: number, z: number): void;
  /** The tilted working plane in the table frame (`planeInTable`), or null to hide it. */
  setWorkingPlane(plane: PlaneInTable | null): void;
  /** The workpiece's boxes in the table frame (`GET …/workpiece` `boxes`); empty: nothing on the table. */
  setWorkpiece(boxes: readonly WorkpieceBox[]): void;
  setView(view: ViewPreset): void;
  /** The underlying view (camera, controls, scene) for anything else. */
  view: MachineView;
}

export interface View3DProps {
  machine: MachineModel | MachineModelInput;
  /**
   * The mechanism chain the machine executes in (the position stream's `chain`, Syntec
   * `G10 L5000 P_ Q_`); absent: set 1 as described.
   */
  chain?: Chain;
  /** Machine axis values by address (as the position stream's `machine`). */
  axes?: Record<string, number>;
  /** Active tool length, mm (0: the nose). */
  toolLength?: number;
  /** The programmed path, xyz triples in the table frame (`GET …/programs/{n}/path` `xyz`). */
  path?: Float32Array;
  /** Per path point: the move to it is a rapid (the same response's `rapid`); drawn dim. */
  pathRapid?: ArrayLike<boolean>;
  /**
   * Under cutter compensation: the programmed path (the same response's `programmed.xyz`),
   * drawn dashed beside `path`, which is then the tool centre's; a legend tells them apart.
   */
  programmedPath?: Float32Array | null;
  /** What is clamped on the table (`GET …/workpiece` `boxes`, table frame): drawn translucent, riding with the table. */
  workpiece?: readonly WorkpieceBox[] | null;
  /** Receives the handle once the view exists, and null when it goes away. */
  onReady?: (handle: View3DHandle | null) => void;
  /** Hide the toolbar. */
  noToolbar?: boolean;
  class?: string;
  style?: CSSProperties;
  /** Passed to MachineView (renderer injection, trace cap). */
  options?: MachineViewOptions;
}

const toolbar: CSSProperties = {
  position: "absolute",
  top: "6px",
  left: "6px",
  display: "flex",
  gap: "4px",
  zIndex: 1,
};

const button: CSSProperties = {
  font: "12px sans-serif",
  padding: "2px 8px",
  background: "rgba(40, 44, 50, 0.85)",
  color: "#e8e8e8",
  border: "1px solid #60666e",
  borderRadius: "3px",
  cursor: "pointer",
};

const legend: CSSProperties = {
  position: "absolute",
  bottom: "6px",
  left: "6px",
  padding: "4px 8px",
  font: "12px sans-serif",
  color: "#e8e8e8",
  background: "rgba(40, 44, 50, 0.85)",
  border: "1px solid #60666e",
  borderRadius: "3px",
  zIndex: 1,
  pointerEvents: "none",
};

const swatch: CSSProperties = { display: "inline-block", width: "22px", verticalAlign: "middle", marginRight: "4px" };

export function View3D(props: View3DProps) {
  const host = useRef<HTMLDivElement>(null);
  const view = useRef<MachineView | null>(null);
  const latest = useRef(props);
  latest.current = props;
  const machineKey = JSON.stringify(props.machine);
  const [error, setError] = useState<string | null>(null);

  useEffect(() => {
    const el = host.current;
    if (!el) return;
    const p = latest.current;
    let v: MachineView;
    try {
      v = new MachineView(el, p.machine, p.options);
      setError(null);
    } catch (e) {
      // A model the view cannot draw (more than two rotary axes on a side, no WebGL…).
      setError(e instanceof Error ? e.message : String(e));
      p.onReady?.(null);
      return;
    }
    view.current = v;
    if (p.chain) v.setChain(p.chain);
    if (p.axes) v.setAxes(p.axes);
    if (p.toolLength !== undefined) v.setToolLength(p.toolLength);
    if (p.path) v.setPath(p.path, p.pathRapid);
    if (p.programmedPath) v.setProgrammedPath(p.programmedPath);
    if (p.workpiece) v.machineScene.setWorkpiece(p.workpiece);
    v.setView("iso");
    const handle: View3DHandle = {
      addTrace: (x, y, z) => v.addTrace(x, y, z),
      addTracePoints: (xyz) => v.addTracePoints(xyz),
      addTraceAtTip: () => v.addTraceAtTip(),
      addCuttingTrace: (x, y, z) => v.addCutting(x, y, z),
      endCuttingTrace: () => v.endCutting(),
      clearTrace: () => v.clearTrace(),
      fit: () => v.fit(),
      fitPart: () => v.fitPart(),
      setWorkZero: (x, y, z) => v.machineScene.setWorkZero(x, y, z),
      setWorkingPlane: (plane) => v.machineScene.setWorkingPlane(plane),
      setWorkpiece: (boxes) => v.machineScene.setWorkpiece(boxes),
      setView: (name) => v.setView(name),
      view: v,
    };
    p.onReady?.(handle);
    return () => {
      latest.current.onReady?.(null);
      view.current = null;
      v.dispose();
    };
  }, [machineKey]);

  // Before the axes: a frame's axes belong to its chain.
  useEffect(() => {
    if (props.chain) view.current?.setChain(props.chain);
  }, [props.chain?.set, props.chain?.sub]);

  useEffect(() => {
    if (props.axes) view.current?.setAxes(props.axes);
  }, [props.axes]);

  useEffect(() => {
    if (props.toolLength !== undefined) view.current?.setToolLength(props.toolLength);
  }, [props.toolLength]);

  useEffect(() => {
    view.current?.setPath(props.path ?? new Float32Array(0), props.pathRapid);
  }, [props.path, props.pathRapid]);

  useEffect(() => {
    view.current?.setProgrammedPath(props.programmedPath ?? null);
  }, [props.programmedPath]);

  useEffect(() => {
    view.current?.machineScene.setWorkpiece(props.workpiece ?? null);
  }, [props.workpiece]);

  // F frames the part, as on a control's graphic screen, unless a field has the keyboard.
  useEffect(() => {
    if (props.noToolbar) return;
    const onKey = (e: KeyboardEvent) => {
      if (!isFitKey(e)) return;
      e.preventDefault();
      view.current?.fitPart();
    };
    addEventListener("keydown", onKey);
    return () => removeEventListener("keydown", onKey);
  }, [props.noToolbar]);

  const act = (f: (v: MachineView) => void) => () => {
    if (view.current) f(view.current);
  };

  return (
    <div
      class={props.class}
      style={{ position: "relative", width: "100%", height: "100%", minHeight: "200px", overflow: "hidden", ...props.style }}
      data-testid="view3d"
    >
      <div ref={host} style={{ position: "absolute", inset: "0" }} />
      {error && (
        <div style={{ position: "absolute", inset: "0", display: "flex", alignItems: "center", justifyContent: "center", color: "#e88", font: "13px sans-serif", padding: "1em", textAlign: "center" }}>
          3D view unavailable: {error}
        </div>
      )}
      {!props.noToolbar && !error && (
        <div style={toolbar}>
          <button type="button" style={button} title="Frame the machine" onClick={act((v) => v.fit())}>
            fit
          </button>
          <button type="button" style={button} title="Frame the part: the path, the tool tip trace, the work zero and the workpiece (key F)" data-action="fit-part" onClick={act((v) => v.fitPart())}>
            fit part (F)
          </button>
          <button type="button" style={button} title="Isometric view" onClick={act((v) => v.setView("iso"))}>
            iso
          </button>
          <button type="button" style={button} title="Front view (from −Y)" onClick={act((v) => v.setView("front"))}>
            front
          </button>
          <button type="button" style={button} title="Top view (from +Z)" onClick={act((v) => v.setView("top"))}>
            top
          </button>
          <button type="button" style={button} title="Clear the tool-tip trace and the cutting point's trace" onClick={act((v) => v.clearTrace())}>
            clear trace
          </button>
        </div>
      )}
      {props.programmedPath && props.programmedPath.length >= 6 && !error && (
        <div style={legend} data-testid="path-legend">
          <div>
            <span style={{ ...swatch, borderTop: "2px solid #30d0ff" }} /> tool centre path (compensated)
          </div>
          <div>
            <span style={{ ...swatch, borderTop: "2px dashed #ff5ad2" }} /> programmed path
          </div>
        </div>
      )}
    </div>
  );
}

/** The fit-to-part key: F alone, not typed into a field. */
export function isFitKey(e: Pick<KeyboardEvent, "key" | "ctrlKey" | "metaKey" | "altKey" | "target">): boolean {
  if (e.key !== "f" && e.key !== "F") return false;
  if (e.ctrlKey || e.metaKey || e.altKey) return false;
  const t = e.target as { tagName?: string; isContentEditable?: boolean } | null;
  return !(t && (["INPUT", "TEXTAREA", "SELECT"].includes(t.tagName ?? "") || t.isContentEditable));
}
