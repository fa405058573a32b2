// What the view shows of the part: the active work offset's zero as a frame (a triad that keeps
// its size on screen at any zoom), the tilted working plane's frame while one is in force, and
// the box a "fit to part" frames — the programmed path, the executed tip trace and the work
// zero, not the machine around them.

import * as THREE from "three";

/** The work-zero triad's colours: lighter than the machine's axis lines, so the two differ. */
export const WORK_ZERO_COLORS = [0xff7a7a, 0x7aff9a, 0x7ab0ff] as const;

/** The triad's arm length as a fraction of the camera's distance: about 6 % of the view's height. */
export const WORK_ZERO_SCREEN = 0.045;

/** The tilted working plane's triad: deeper colours than the work zero's, arms half as long again. */
export const WORKING_PLANE_COLORS = [0xff3d00, 0x00e05a, 0x2f7bff] as const;
export const WORKING_PLANE_SCREEN = 0.07;
/** The square drawn in the plane (its X–Y plane), translucent, so the plane reads as a plane. */
export const WORKING_PLANE_FILL = 0xffb000;

type Vec3 = readonly [number, number, number];

/**
 * A coordinate system drawn as a triad (and, for a plane, a translucent square in its X–Y
 * plane), a child of the table frame (it rides with the table), drawn over everything and the
 * same size on screen at any distance; hidden until `set` places it.
 */
export class ScreenFrame {
  readonly object = new THREE.Group();
  private readonly screen: number;

  constructor(name: string, colors: readonly number[], screen: number, fill?: number) {
    this.screen = screen;
    this.object.name = name;
    this.object.visible = false;
    const axes: Vec3[] = [
      [1, 0, 0],
      [0, 1, 0],
      [0, 0, 1],
    ];
    axes.forEach((d, i) => {
      const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(...d)]);
      const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: colors[i], depthTest: false, transparent: true }));
      line.renderOrder = 12;
      this.object.add(line);
    });
    if (fill !== undefined) {
      const square = new THREE.Mesh(
        new THREE.PlaneGeometry(1.2, 1.2).translate(0.6, 0.6, 0),
        new THREE.MeshBasicMaterial({ color: fill, transparent: true, opacity: 0.22, side: THREE.DoubleSide, depthTest: false, depthWrite: false }),
      );
      square.renderOrder = 11;
      this.object.add(square);
    }
  }

  /** Its origin in the table frame and, if given, its X, Y, Z axes there (unit vectors); returns whether it changed. */
  set(origin: Vec3, axes?: readonly [Vec3, Vec3, Vec3]): boolean {
    if (!origin.every(Number.isFinite) || (axes && !axes.every((a) => a.every(Number.isFinite)))) return false;
    const o = this.object;
    const turn = axes ? new THREE.Quaternion().setFromRotationMatrix(new THREE.Matrix4().makeBasis(...(axes.map((a) => new THREE.Vector3(...a)) as [THREE.Vector3, THREE.Vector3, THREE.Vector3]))) : new THREE.Quaternion();
    if (o.visible && o.position.x === origin[0] && o.position.y === origin[1] && o.position.z === origin[2] && o.quaternion.equals(turn)) return false;
    o.position.set(...origin);
    o.quaternion.copy(turn);
    o.visible = true;
    o.updateMatrixWorld(true);
    return true;
  }

  /** No longer drawn; returns whether it was. */
  hide(): boolean {
    const was = this.object.visible;
    this.object.visible = false;
    return was;
  }

  /** Size it for a camera at `camera` (world): the same size on screen at any distance. */
  fitScreen(camera: THREE.Vector3): void {
    if (!this.object.visible) return;
    const here = this.object.getWorldPosition(new THREE.Vector3());
    const s = Math.max(here.distanceTo(camera) * this.screen, 1e-6);
    this.object.scale.setScalar(s);
    this.object.updateMatrixWorld(true);
  }

  dispose(): void {
    for (const c of this.object.children) {
      const shape = c as THREE.Line | THREE.Mesh;
      shape.geometry.dispose();
      (shape.material as THREE.Material).dispose();
    }
  }
}

/** The active work offset's zero and axes. */
export class WorkZeroFrame extends ScreenFrame {
  constructor() {
    super("work-zero", WORK_ZERO_COLORS, WORK_ZERO_SCREEN);
  }
}

/** The tilted working plane's feature coordinate system (G68.2…): triad and square. */
export class WorkingPlaneFrame extends ScreenFrame {
  constructor() {
    super("working-plane", WORKING_PLANE_COLORS, WORKING_PLANE_SCREEN, WORKING_PLANE_FILL);
  }
}

/** World bounds of `count` xyz points read by `point`, mapped by `matrix` (a table frame's). */
export function pointsBounds(count: number, point: (i: number) => readonly number[], matrix: THREE.Matrix4, into = new THREE.Box3()): THREE.Box3 {
  const v = new THREE.Vector3();
  for (let i = 0; i < count; i++) {
    const p = point(i);
    into.expandByPoint(v.set(p[0], p[1], p[2]).applyMatrix4(matrix));
  }
  return into;
}

/** The smallest half size a part box is framed with, mm (a single point still gives a view). */
export const MIN_PART_RADIUS = 5;

/** One box of the workpiece: its least and greatest corner in the table frame, mm (the service's `Cuboid`). */
export type WorkpieceBox = { min: readonly number[]; max: readonly number[] };

/**
 * The workpiece's boxes: a translucent fill, so the path and the tool inside stay visible, and
 * solid edges; a warm stock colour that the grey-blue table and machine do not have.
 */
export const WORKPIECE_FILL = 0xc8894a;
export const WORKPIECE_OPACITY = 0.35;
export const WORKPIECE_EDGES = 0xf2c48e;

/**
 * What is clamped on the table (`GET /controllers/{id}/workpiece`): its boxes, children of the
 * table frame like the path (the service keeps them in the table frame), so they ride with the
 * table. Each box is a unit cube scaled and moved onto its corners, drawn as a translucent fill
 * with its edges.
 */
export class WorkpieceBoxes {
  readonly object = new THREE.Group();
  private readonly cube = new THREE.BoxGeometry(1, 1, 1).translate(0.5, 0.5, 0.5);
  private readonly edges = new THREE.EdgesGeometry(this.cube);
  private readonly fill = new THREE.MeshBasicMaterial({ color: WORKPIECE_FILL, transparent: true, opacity: WORKPIECE_OPACITY, side: THREE.DoubleSide, depthWrite: false });
  private readonly line = new THREE.LineBasicMaterial({ color: WORKPIECE_EDGES });
  private key = "[]";
  /** The boxes in the table frame (empty: nothing on the table). */
  readonly boxes: THREE.Box3[] = [];

  constructor() {
    this.object.name = "workpiece";
  }

  /** Replace the boxes (a box whose corners are not finite, or not below each other, is left out); returns whether the drawing changed. */
  set(boxes: readonly WorkpieceBox[] | null | undefined): boolean {
    const good = (boxes ?? []).filter((b) => b.min.length >= 3 && b.max.length >= 3 && [0, 1, 2].every((k) => Number.isFinite(b.min[k]) && Number.isFinite(b.max[k]) && b.min[k] < b.max[k]));
    const key = JSON.stringify(good.map((b) => [b.min.slice(0, 3), b.max.slice(0, 3)]));
    if (key === this.key) return false;
    this.key = key;
    this.object.clear();
    this.boxes.length = 0;
    good.forEach((b, i) => {
      const box = new THREE.Box3(new THREE.Vector3(b.min[0], b.min[1], b.min[2]), new THREE.Vector3(b.max[0], b.max[1], b.max[2]));
      this.boxes.push(box);
      const group = new THREE.Group();
      group.name = `workpiece-box-${i}`;
      group.position.copy(box.min);
      group.scale.copy(box.getSize(new THREE.Vector3()));
      const fill = new THREE.Mesh(this.cube, this.fill);
      // After the opaque machine, so the table shows through it.
      fill.renderOrder = 5;
      group.add(fill, new THREE.LineSegments(this.edges, this.line));
      this.object.add(group);
    });
    this.object.updateMatrixWorld(true);
    return true;
  }

  /** World bounds of the boxes mapped by `matrix` (the table frame's), added to `into`. */
  bounds(matrix: THREE.Matrix4, into = new THREE.Box3()): THREE.Box3 {
    for (const b of this.boxes) into.union(b.clone().applyMatrix4(matrix));
    return into;
  }

  dispose(): void {
    this.object.clear();
    this.cube.dispose();
    this.edges.dispose();
    this.fill.dispose();
    this.line.dispose();
  }
}
