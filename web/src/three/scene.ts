// The live 3D machine view.
//
// `MachineScene` is everything but the renderer: the machine rig (rig.ts), lights, the
// programmed path, the executed tip trace and, under cutting point control or a cutter
// compensation, the cutting point's
// trace and marker (children of the innermost table group, so they ride with the part). It
// needs no DOM or WebGL, so tests build and check it in node. The rig is the mechanism chain the
// machine executes in (`setChain`, Syntec G10 L5000): a switch rebuilds the rig from that
// chain's view of the machine (chain.ts) and moves the path and traces onto its table frame.
// `MachineView` puts a `MachineScene` in a container: a WebGL renderer (injectable), a
// perspective camera with Z up, OrbitControls, a ResizeObserver, and on-demand rendering (a
// frame is drawn only after something changed: axes, tool, path, trace, camera, size).

import * as THREE from "three";
import { OrbitControls } from "three/examples/jsm/controls/OrbitControls.js";
import { axisColor, buildMachine } from "./rig";
import type { MachineRig } from "./rig";
import type { AxisValues } from "./kinematics";
import { MAIN_CHAIN, chainView, sameChain } from "./chain";
import type { Chain } from "./chain";
import { normalizeModel } from "./model";
import type { MachineModel, MachineModelInput } from "./model";
import { PathLine, ProgrammedLine, TraceLine, TraceStretches } from "./trace";
import { MIN_PART_RADIUS, WorkZeroFrame, WorkingPlaneFrame, WorkpieceBoxes, pointsBounds } from "./part";
import type { WorkpieceBox } from "./part";
import type { PlaneInTable } from "./frameTrace";

export type ViewPreset = "iso" | "front" | "top" | "side";

/** The tool-tip trace's colour (yellow). */
export const TIP_TRACE_COLOR = 0xffd000;
/**
 * The cutting point's trace and marker (magenta): under cutting point control the programmed
 * path (cyan) is the cutting point's path, so the trace is drawn in cyan's complement, apart from
 * the tip trace (yellow), the tip marker (red) and the axis lines and triad (red, green, blue).
 * The dashed pink programmed path appears only under cutter compensation; there the cutting
 * point runs on it wherever the tool touches the contour (solid over dashed).
 */
export const CUTTING_TRACE_COLOR = 0xff30ff;
/** The tool tip's dot: red like the tip marker, a fixed size in pixels (over the marker, which shrinks with distance). */
export const TIP_POINT_COLOR = 0xff3030;
export const TIP_POINT_PX = 7;

export class MachineScene {
  readonly scene = new THREE.Scene();
  /** The whole machine, every chain. */
  readonly machine: MachineModel;
  readonly trace: TraceLine;
  /**
   * Where the tool touches the part under cutting point control (G43.8/G43.9) or a cutter
   * compensation, table frame: a stretch per run of position frames that carry `cutting`.
   */
  readonly cutting: TraceStretches;
  /** A dot at the latest cutting point; hidden while the latest frame has none. */
  readonly cuttingMarker: THREE.Mesh;
  readonly path: PathLine;
  /** The programmed path beside a compensated `path` (empty without cutter compensation). */
  readonly programmed: ProgrammedLine;
  /** The tool tip as a dot of a fixed size in pixels: where the tool is, seen at any zoom. */
  readonly tipPoint: THREE.Points;
  /** The active work offset's zero and axes (`setWorkZero`). */
  readonly workZero = new WorkZeroFrame();
  /** The tilted working plane's frame while one is in force (`setWorkingPlane`). */
  readonly workingPlane = new WorkingPlaneFrame();
  /** What is clamped on the table, the boxes a G31 probe touches (`setWorkpiece`). */
  readonly workpiece = new WorkpieceBoxes();
  private axes: AxisValues = {};
  private toolLength = 0;
  private current: MachineRig;
  private currentChain: Chain = MAIN_CHAIN;
  /** Called whenever something visible changed (MachineView schedules a frame). */
  onChange: () => void = () => {};

  constructor(machine: MachineModelInput | MachineModel, options: { traceCap?: number } = {}) {
    this.machine = normalizeModel(machine);
    this.current = buildMachine(this.machine);
    for (const a of this.rig.model.axes) this.axes[a.name] = 0; // the rig is built at zero
    this.scene.add(this.rig.root);
    this.scene.background = new THREE.Color(0x1d2126);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x404850, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.8);
    sun.position.set(0.6, -1, 1.4).multiplyScalar(this.rig.size * 2);
    this.scene.add(sun);
    const fill = new THREE.DirectionalLight(0xffffff, 0.5);
    fill.position.set(-1, 0.8, 0.4).multiplyScalar(this.rig.size * 2);
    this.scene.add(fill);
    this.trace = new TraceLine(TIP_TRACE_COLOR, options.traceCap);
    this.cutting = new TraceStretches(CUTTING_TRACE_COLOR, options.traceCap, "cutting-trace");
    // The dot is drawn over everything: the cutting point is on the tool's surface, which the
    // drawn tool (a nominal cylinder, not the offset's radius) may hide.
    const tipMarker = this.rig.tip instanceof THREE.Mesh ? this.rig.tip.geometry : null;
    tipMarker?.computeBoundingSphere();
    const r = 0.6 * (tipMarker?.boundingSphere?.radius ?? this.rig.size / 250);
    this.cuttingMarker = new THREE.Mesh(
      new THREE.SphereGeometry(r, 12, 8),
      new THREE.MeshBasicMaterial({ color: CUTTING_TRACE_COLOR, depthTest: false, transparent: true, opacity: 0.9 }),
    );
    this.cuttingMarker.name = "cutting-point";
    this.cuttingMarker.renderOrder = 11;
    this.cuttingMarker.visible = false;
    this.tipPoint = new THREE.Points(
      new THREE.BufferGeometry().setAttribute("position", new THREE.Float32BufferAttribute([0, 0, 0], 3)),
      new THREE.PointsMaterial({ color: TIP_POINT_COLOR, size: TIP_POINT_PX, sizeAttenuation: false, depthTest: false }),
    );
    this.tipPoint.name = "tip-point";
    this.tipPoint.renderOrder = 13;
    this.scene.add(this.tipPoint);
    this.placeTipPoint();
    this.path = new PathLine();
    this.programmed = new ProgrammedLine();
    this.rig.tableFrame.add(this.path.object, this.programmed.object, this.trace.object, this.cutting.object, this.cuttingMarker, this.workZero.object, this.workingPlane.object, this.workpiece.object);
    this.rig.root.updateMatrixWorld(true);
  }

  /** The rig of the chain in use: its model is that chain's view of the machine. */
  get rig(): MachineRig {
    return this.current;
  }

  /** The mechanism chain drawn (set 1 as described until `setChain`). */
  get chain(): Chain {
    return { ...this.currentChain };
  }

  /**
   * Draw the machine in mechanism chain `chain` (the position frames' `chain`): the rig is
   * rebuilt from that chain's rotary links, tool axis and nose, posed at the current axes and tool
   * length; the path, the traces and the cutting point marker move onto its table frame as they
   * are (their points are table-frame points, whichever head turns). Returns whether the drawing
   * changed: false for the chain already drawn and for one the machine does not describe (the
   * control refuses to switch to it, COR-161, so no frame names it).
   */
  setChain(chain: Chain): boolean {
    if (sameChain(chain, this.currentChain)) return false;
    const view = chainView(this.machine, chain);
    if (!view) return false;
    const old = this.current;
    const rig = buildMachine(view);
    // Moved out before the old rig is disposed (which disposes everything under its root).
    rig.tableFrame.add(this.path.object, this.programmed.object, this.trace.object, this.cutting.object, this.cuttingMarker, this.workZero.object, this.workingPlane.object, this.workpiece.object);
    this.scene.remove(old.root);
    old.dispose();
    this.scene.add(rig.root);
    this.current = rig;
    this.currentChain = { set: chain.set, sub: chain.sub };
    rig.update(this.axes, this.toolLength);
    this.placeTipPoint();
    this.onChange();
    return true;
  }

  /** Axis values by address; missing ones keep their last value (initially 0). */
  setAxes(values: AxisValues): void {
    let changed = false;
    for (const [k, v] of Object.entries(values)) {
      if (typeof v === "number" && Number.isFinite(v) && this.axes[k] !== v) {
        this.axes[k] = v;
        changed = true;
      }
    }
    if (changed) this.pose();
  }

  getAxes(): AxisValues {
    return { ...this.axes };
  }

  setToolLength(L: number): void {
    if (Number.isFinite(L) && L !== this.toolLength) {
      this.toolLength = L;
      this.pose();
    }
  }

  getToolLength(): number {
    return this.toolLength;
  }

  /** The programmed path: xyz triples in the table frame (replaces the previous path); `rapid[i]`: the move to point i is a rapid. */
  setPath(points: ArrayLike<number> | null | undefined, rapid?: ArrayLike<boolean> | null): void {
    this.path.set(points, rapid);
    this.onChange();
  }

  /** The programmed path beside a compensated path (`GET …/path` `programmed.xyz`), table frame; null: none. */
  setProgrammedPath(points: ArrayLike<number> | null | undefined): void {
    this.programmed.set(points);
    this.onChange();
  }

  /** One executed tip position, table frame. */
  addTrace(x: number, y: number, z: number): void {
    if (this.trace.add(x, y, z)) this.onChange();
  }

  /** Add the current tool tip (the forward kinematics of the current axes and tool length, in the table frame) to the trace; returns it. */
  addTraceAtTip(): [number, number, number] {
    const tip = this.rig.kinematics.forward(this.axes, this.toolLength).tip;
    this.addTrace(tip[0], tip[1], tip[2]);
    return tip;
  }

  /** Many tip positions at once, xyz triples in the table frame. */
  addTracePoints(xyz: ArrayLike<number>): void {
    if (this.trace.addMany(xyz) > 0) this.onChange();
  }

  /**
   * One cutting point (cutting point control G43.8/G43.9, a cutter compensation), table frame: extends the cutting trace's
   * open stretch and puts the marker there.
   */
  addCutting(x: number, y: number, z: number): void {
    const added = this.cutting.add(x, y, z);
    const m = this.cuttingMarker;
    if (added || !m.visible) {
      m.position.set(x, y, z);
      m.visible = true;
      m.updateMatrixWorld();
      this.onChange();
    }
  }

  /** A position without a cutting point: the cutting trace's stretch ends, the marker hides. */
  endCutting(): void {
    this.cutting.end();
    if (this.cuttingMarker.visible) {
      this.cuttingMarker.visible = false;
      this.onChange();
    }
  }

  /** Clear the tip trace and the cutting point's trace (the marker stays where the tool touches now). */
  clearTrace(): void {
    this.trace.clear();
    this.cutting.clear();
    this.onChange();
  }

  /** World (machine) bounds of the working zone (table and head chains, tool) and the path, at the current pose; `all`: the whole machine. */
  bounds(all = false): THREE.Box3 {
    const box = new THREE.Box3();
    for (const b of all ? this.rig.bodies : this.rig.focus) box.expandByObject(b);
    const pb = this.path.bounds;
    if (pb && !pb.isEmpty()) box.union(pb.clone().applyMatrix4(this.rig.tableFrame.matrixWorld));
    const qb = this.programmed.bounds;
    if (qb && !qb.isEmpty()) box.union(qb.clone().applyMatrix4(this.rig.tableFrame.matrixWorld));
    return box;
  }

  /** The active work offset's zero in the table frame (a position frame's `tip_table − tip`). */
  setWorkZero(x: number, y: number, z: number): void {
    if (this.workZero.set([x, y, z])) this.onChange();
  }

  /** The tilted working plane in the table frame (`planeInTable`), or null: none in force. */
  setWorkingPlane(plane: PlaneInTable | null): void {
    if (plane ? this.workingPlane.set(plane.origin, plane.axes) : this.workingPlane.hide()) this.onChange();
  }

  /** The workpiece's boxes in the table frame (`GET …/workpiece` `boxes`); null or empty: nothing on the table. */
  setWorkpiece(boxes: readonly WorkpieceBox[] | null | undefined): void {
    if (this.workpiece.set(boxes)) this.onChange();
  }

  /**
   * World bounds of the part at the current pose: the programmed path, the executed tip trace,
   * the work zero, the working plane's origin and the workpiece's boxes (empty when there is
   * none of them), at least MIN_PART_RADIUS around.
   */
  partBounds(): THREE.Box3 {
    this.rig.root.updateMatrixWorld(true);
    const table = this.rig.tableFrame.matrixWorld;
    const box = new THREE.Box3();
    for (const b of [this.path.bounds, this.programmed.bounds]) if (b && !b.isEmpty()) box.union(b.clone().applyMatrix4(table));
    pointsBounds(this.trace.length, (i) => this.trace.point(i), table, box);
    this.workpiece.bounds(table, box);
    for (const frame of [this.workZero, this.workingPlane]) if (frame.object.visible) box.expandByPoint(frame.object.getWorldPosition(new THREE.Vector3()));
    if (!box.isEmpty()) box.union(new THREE.Box3().setFromCenterAndSize(box.getCenter(new THREE.Vector3()), new THREE.Vector3().setScalar(2 * MIN_PART_RADIUS)));
    return box;
  }

  /** Upload pending trace points (before each render). */
  flush(): void {
    this.trace.flush();
    this.cutting.flush();
  }

  private pose(): void {
    this.rig.update(this.axes, this.toolLength);
    this.placeTipPoint();
    this.onChange();
  }

  /** The tip dot onto the drawn tool tip. */
  private placeTipPoint(): void {
    this.rig.root.updateMatrixWorld(true);
    this.rig.tip.getWorldPosition(this.tipPoint.position);
    this.tipPoint.updateMatrixWorld();
  }

  dispose(): void {
    this.tipPoint.geometry.dispose();
    (this.tipPoint.material as THREE.Material).dispose();
    this.trace.dispose();
    this.cutting.dispose();
    this.cuttingMarker.geometry.dispose();
    (this.cuttingMarker.material as THREE.Material).dispose();
    this.path.dispose();
    this.programmed.dispose();
    this.workZero.dispose();
    this.workingPlane.dispose();
    this.workpiece.dispose();
    this.rig.dispose();
  }
}

/** What MachineView needs of a renderer (a WebGLRenderer, or a stand-in in tests). */
export interface RendererLike {
  domElement: HTMLCanvasElement;
  setPixelRatio(r: number): void;
  setSize(w: number, h: number, updateStyle?: boolean): void;
  render(scene: THREE.Object3D, camera: THREE.Camera): void;
  dispose(): void;
}

export interface MachineViewOptions {
  /** Make the renderer (default: a WebGLRenderer, antialiased, drawing buffer preserved so tests can read the canvas). */
  createRenderer?: () => RendererLike;
  /** Trace capacity, points (default TRACE_CAP). */
  traceCap?: number;
  /** Letters at the rotary axis lines (default true; needs a DOM canvas). */
  labels?: boolean;
}

/** A text sprite (canvas texture) for the end of each rotary axis line. */
function addAxisLabels(rig: MachineRig): void {
  for (const link of rig.model.rotary) {
    const line = rig.root.getObjectByName(`axis-line-${link.axis}`) as THREE.Line | undefined;
    if (!line?.parent) continue;
    const text = link.fixed !== null ? `${link.axis} ${link.fixed}°` : link.axis;
    const canvas = document.createElement("canvas");
    canvas.width = 128;
    canvas.height = 64;
    const ctx = canvas.getContext("2d");
    if (!ctx) continue;
    ctx.font = "bold 40px sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    ctx.lineWidth = 6;
    ctx.strokeStyle = "rgba(0, 0, 0, 0.8)";
    ctx.strokeText(text, 64, 32);
    ctx.fillStyle = `#${axisColor(link.axis).toString(16).padStart(6, "0")}`;
    ctx.fillText(text, 64, 32);
    const material = new THREE.SpriteMaterial({ map: new THREE.CanvasTexture(canvas), depthTest: false });
    const sprite = new THREE.Sprite(material);
    const end = new THREE.Vector3().fromBufferAttribute(line.geometry.getAttribute("position") as THREE.BufferAttribute, 1);
    sprite.position.copy(end);
    const h = rig.size / 22;
    sprite.scale.set(2 * h, h, 1);
    sprite.renderOrder = 12;
    sprite.name = `axis-label-${link.axis}`;
    line.parent.add(sprite);
  }
}

const VIEW_DIRECTIONS: Record<ViewPreset, [number, number, number]> = {
  // From the operator's side (−Y), right and above.
  iso: [1, -1.2, 0.9],
  front: [0, -1, 0],
  side: [1, 0, 0],
  // Straight down; a hair toward −Y keeps OrbitControls' Z-up orbit defined.
  top: [0, -1e-4, 1],
};

export class MachineView {
  readonly machineScene: MachineScene;
  readonly camera: THREE.PerspectiveCamera;
  readonly controls: OrbitControls;
  readonly renderer: RendererLike;
  private readonly container: HTMLElement;
  private readonly resizeObserver: ResizeObserver | null;
  private frame = 0;
  private disposed = false;
  private readonly labels: boolean;
  /** Frames drawn so far (for tests and diagnostics). */
  frames = 0;

  constructor(container: HTMLElement, machine: MachineModelInput | MachineModel, options: MachineViewOptions = {}) {
    this.container = container;
    this.machineScene = new MachineScene(machine, { traceCap: options.traceCap });
    this.renderer =
      options.createRenderer?.() ??
      new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(globalThis.devicePixelRatio ?? 1, 2));
    const canvas = this.renderer.domElement;
    canvas.style.display = "block";
    canvas.style.width = "100%";
    canvas.style.height = "100%";
    canvas.style.touchAction = "none";
    container.appendChild(canvas);

    const size = this.machineScene.rig.size;
    this.camera = new THREE.PerspectiveCamera(35, 1, size / 200, size * 40);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, canvas);
    this.controls.screenSpacePanning = true;
    this.controls.addEventListener("change", () => this.requestRender());
    this.machineScene.onChange = () => this.requestRender();

    this.labels = options.labels !== false && typeof document !== "undefined";
    if (this.labels) addAxisLabels(this.machineScene.rig);

    this.resize();
    this.resizeObserver = typeof ResizeObserver === "undefined" ? null : new ResizeObserver(() => this.resize());
    this.resizeObserver?.observe(container);
    this.setView("iso");
  }

  setAxes(values: Record<string, number>): void {
    this.machineScene.setAxes(values);
  }

  setToolLength(L: number): void {
    this.machineScene.setToolLength(L);
  }

  /** Draw the mechanism chain the machine executes in (a frame's `chain`); the camera stays where it is. */
  setChain(chain: Chain): void {
    if (this.machineScene.setChain(chain) && this.labels) addAxisLabels(this.machineScene.rig);
  }

  /** The programmed path, xyz triples in the TABLE frame; `rapid[i]`: the move to point i is a rapid (drawn dim). */
  setPath(points: Float32Array, rapid?: ArrayLike<boolean>): void {
    this.machineScene.setPath(points, rapid);
  }

  /** The programmed path beside a compensated one (TABLE frame, drawn dashed); null: none. */
  setProgrammedPath(points: Float32Array | null): void {
    this.machineScene.setProgrammedPath(points);
  }

  /** One executed tool-tip position in the TABLE frame. */
  addTrace(x: number, y: number, z: number): void {
    this.machineScene.addTrace(x, y, z);
  }

  /** Add where the tool tip is now (from the axes and tool length: needs no work offsets). */
  addTraceAtTip(): void {
    this.machineScene.addTraceAtTip();
  }

  /** Many executed positions at once (xyz triples, table frame). */
  addTracePoints(xyz: ArrayLike<number>): void {
    this.machineScene.addTracePoints(xyz);
  }

  /** One cutting point (under cutting point control or a cutter compensation) in the TABLE frame: the cutting trace and its marker. */
  addCutting(x: number, y: number, z: number): void {
    this.machineScene.addCutting(x, y, z);
  }

  /** A position without a cutting point: the cutting trace's stretch ends and its marker hides. */
  endCutting(): void {
    this.machineScene.endCutting();
  }

  /** Clear the tip trace and the cutting point's trace. */
  clearTrace(): void {
    this.machineScene.clearTrace();
  }

  /** Frame the machine (and path) from the current viewing direction. */
  fit(): void {
    const dir = this.camera.position.clone().sub(this.controls.target);
    if (dir.lengthSq() === 0) dir.set(...VIEW_DIRECTIONS.iso);
    this.frameFrom(dir);
  }

  /** Frame the part (the path, the tip trace, the work zero and the workpiece) from the current viewing direction; the machine when there is none. */
  fitPart(): void {
    const box = this.machineScene.partBounds();
    if (box.isEmpty()) return this.fit();
    const dir = this.camera.position.clone().sub(this.controls.target);
    if (dir.lengthSq() === 0) dir.set(...VIEW_DIRECTIONS.iso);
    this.frameFrom(dir, box);
  }

  /** Look from a preset direction and frame the machine. */
  setView(view: ViewPreset): void {
    this.frameFrom(new THREE.Vector3(...VIEW_DIRECTIONS[view]));
  }

  private frameFrom(direction: THREE.Vector3, box = this.machineScene.bounds()): void {
    const sphere = box.isEmpty() ? new THREE.Sphere(new THREE.Vector3(), 500) : box.getBoundingSphere(new THREE.Sphere());
    const vfov = THREE.MathUtils.degToRad(this.camera.fov) / 2;
    const hfov = Math.atan(Math.tan(vfov) * Math.max(this.camera.aspect, 1e-3));
    const dist = (sphere.radius / Math.sin(Math.min(vfov, hfov))) * 1.15;
    this.controls.target.copy(sphere.center);
    this.camera.position.copy(sphere.center).add(direction.normalize().multiplyScalar(dist));
    this.camera.near = Math.max(dist / 500, 0.1);
    this.camera.far = dist * 20;
    this.camera.updateProjectionMatrix();
    this.controls.update();
    this.requestRender();
  }

  /** Draw a frame at the next animation frame (coalesced). */
  requestRender(): void {
    if (this.frame || this.disposed) return;
    const raf = globalThis.requestAnimationFrame ?? ((f: FrameRequestCallback) => setTimeout(() => f(performance.now()), 16) as unknown as number);
    this.frame = raf(() => {
      this.frame = 0;
      this.render();
    });
  }

  /** Draw now. */
  render(): void {
    if (this.disposed) return;
    this.machineScene.flush();
    this.machineScene.workZero.fitScreen(this.camera.position);
    this.machineScene.workingPlane.fitScreen(this.camera.position);
    this.renderer.render(this.machineScene.scene, this.camera);
    this.frames++;
  }

  private resize(): void {
    const w = Math.max(1, this.container.clientWidth);
    const h = Math.max(1, this.container.clientHeight);
    this.renderer.setSize(w, h, false);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.requestRender();
  }

  dispose(): void {
    if (this.disposed) return;
    this.disposed = true;
    if (this.frame) (globalThis.cancelAnimationFrame ?? clearTimeout)(this.frame);
    this.resizeObserver?.disconnect();
    this.controls.dispose();
    this.machineScene.dispose();
    this.renderer.dispose();
    this.renderer.domElement.remove();
  }
}
