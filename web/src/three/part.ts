// What the view shows of the part: the active work offset's zero as a frame (a triad that keeps
// its size on screen at any zoom), and the box a "fit to part" frames — the programmed path, the
// executed tip trace and the work zero, not the machine around them.

import * as THREE from "three";

/** The work-zero triad's colours: lighter than the machine's axis lines, so the two differ. */
export const WORK_ZERO_COLORS = [0xff7a7a, 0x7aff9a, 0x7ab0ff] as const;

/** The triad's arm length as a fraction of the camera's distance: about 6 % of the view's height. */
export const WORK_ZERO_SCREEN = 0.045;

/**
 * The active work offset's zero and axes, a child of the table frame (it rides with the table),
 * drawn over everything; hidden until a position gives its place.
 */
export class WorkZeroFrame {
  readonly object = new THREE.Group();

  constructor() {
    this.object.name = "work-zero";
    this.object.visible = false;
    const axes: [number, number, number][] = [
      [1, 0, 0],
      [0, 1, 0],
      [0, 0, 1],
    ];
    axes.forEach((d, i) => {
      const g = new THREE.BufferGeometry().setFromPoints([new THREE.Vector3(), new THREE.Vector3(...d)]);
      const line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: WORK_ZERO_COLORS[i], depthTest: false, transparent: true }));
      line.renderOrder = 12;
      this.object.add(line);
    });
  }

  /** The work zero in the table frame; returns whether it moved. */
  set(x: number, y: number, z: number): boolean {
    if (![x, y, z].every(Number.isFinite)) return false;
    const p = this.object.position;
    if (this.object.visible && p.x === x && p.y === y && p.z === z) return false;
    p.set(x, y, z);
    this.object.visible = true;
    this.object.updateMatrixWorld(true);
    return true;
  }

  /** Size it for a camera at `camera` (world): the same size on screen at any distance. */
  fitScreen(camera: THREE.Vector3): void {
    if (!this.object.visible) return;
    const here = this.object.getWorldPosition(new THREE.Vector3());
    const s = Math.max(here.distanceTo(camera) * WORK_ZERO_SCREEN, 1e-6);
    this.object.scale.setScalar(s);
    this.object.updateMatrixWorld(true);
  }

  dispose(): void {
    for (const c of this.object.children) {
      const line = c as THREE.Line;
      line.geometry.dispose();
      (line.material as THREE.Material).dispose();
    }
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
