// The executed tool-tip trace, the cutting point's trace (in stretches) and the programmed path,
// as lines in the table frame.
//
// Trace: one preallocated Float32 BufferGeometry drawn as a line strip. Capacity starts at
// TRACE_INITIAL points and doubles (a new geometry, the old one disposed: log₂ times in all)
// up to TRACE_CAP points; when full, the oldest half is dropped (one copy and one full upload
// every TRACE_CAP / 2 points, amortised O(1) per point). Between frames only the new range is
// uploaded: `flush()` (called before each render) adds one update range covering the points
// added since the last flush and moves the draw range. Nothing is rebuilt per point.

import * as THREE from "three";

export const TRACE_INITIAL = 16_384;
/** The most points the trace keeps (the newest ones); 1,048,576 points = 12 MiB of positions. */
export const TRACE_CAP = 1 << 20;

export class TraceLine {
  readonly object: THREE.Line;
  private positions: Float32Array;
  private attribute: THREE.BufferAttribute;
  private n = 0;
  /** First point not yet uploaded; −1: the whole buffer must be uploaded. */
  private dirtyFrom = 0;
  readonly cap: number;

  constructor(color = 0xffd000, cap = TRACE_CAP, initial = TRACE_INITIAL) {
    this.cap = cap;
    this.positions = new Float32Array(Math.min(initial, cap) * 3);
    this.attribute = new THREE.BufferAttribute(this.positions, 3);
    this.attribute.setUsage(THREE.DynamicDrawUsage);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", this.attribute);
    geometry.setDrawRange(0, 0);
    this.object = new THREE.Line(geometry, new THREE.LineBasicMaterial({ color }));
    this.object.name = "trace";
    // The bounding sphere would have to be recomputed over the whole buffer; the trace is small
    // next to the machine, so it is never culled.
    this.object.frustumCulled = false;
  }

  /** Number of points held. */
  get length(): number {
    return this.n;
  }

  /** Capacity of the current buffer, points. */
  get capacity(): number {
    return this.positions.length / 3;
  }

  /** Point i (table frame) as stored (Float32). */
  point(i: number): [number, number, number] {
    const p = this.positions;
    return [p[3 * i], p[3 * i + 1], p[3 * i + 2]];
  }

  /** Append a point; a repeat of the last point (a machine standing still) is skipped: returns false. */
  add(x: number, y: number, z: number): boolean {
    const p = this.positions;
    if (this.n > 0) {
      const j = 3 * (this.n - 1);
      if (p[j] === Math.fround(x) && p[j + 1] === Math.fround(y) && p[j + 2] === Math.fround(z)) return false;
    }
    if (this.n === this.capacity) this.makeRoom();
    const i = 3 * this.n;
    this.positions[i] = x;
    this.positions[i + 1] = y;
    this.positions[i + 2] = z;
    this.n++;
    return true;
  }

  /** Add many points at once (xyz triples); returns how many were added. */
  addMany(xyz: ArrayLike<number>): number {
    let added = 0;
    for (let k = 0; k + 2 < xyz.length; k += 3) if (this.add(xyz[k], xyz[k + 1], xyz[k + 2])) added++;
    return added;
  }

  clear(): void {
    this.n = 0;
    this.dirtyFrom = 0;
    this.object.geometry.setDrawRange(0, 0);
  }

  /** Whether points were added since the last flush. */
  get dirty(): boolean {
    return this.dirtyFrom < 0 || this.dirtyFrom < this.n;
  }

  /** Upload what changed and draw every point (call before rendering). */
  flush(): void {
    const geometry = this.object.geometry;
    if (this.dirtyFrom < 0) {
      this.attribute.clearUpdateRanges();
      this.attribute.needsUpdate = true;
    } else if (this.dirtyFrom < this.n) {
      this.attribute.addUpdateRange(3 * this.dirtyFrom, 3 * (this.n - this.dirtyFrom));
      this.attribute.needsUpdate = true;
    }
    this.dirtyFrom = this.n;
    geometry.setDrawRange(0, this.n);
  }

  private makeRoom(): void {
    const cap = this.capacity;
    if (cap < this.cap) {
      // Double: a new geometry (a buffer's size is fixed once uploaded), the old one disposed.
      const positions = new Float32Array(Math.min(cap * 2, this.cap) * 3);
      positions.set(this.positions);
      this.replace(positions);
      this.dirtyFrom = 0;
    } else {
      // Full: keep the newest half.
      const half = Math.floor(cap / 2);
      this.positions.copyWithin(0, 3 * (cap - half), 3 * cap);
      this.n = half;
      this.dirtyFrom = -1;
    }
  }

  private replace(positions: Float32Array): void {
    const old = this.object.geometry;
    this.positions = positions;
    this.attribute = new THREE.BufferAttribute(positions, 3);
    this.attribute.setUsage(THREE.DynamicDrawUsage);
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", this.attribute);
    geometry.setDrawRange(0, this.n);
    this.object.geometry = geometry;
    old.dispose();
  }

  dispose(): void {
    this.object.geometry.dispose();
    (this.object.material as THREE.Material).dispose();
  }
}

/** Points a new stretch of a `TraceStretches` starts with room for (it doubles as `TraceLine` does). */
export const STRETCH_INITIAL = 256;
/** The most stretches a `TraceStretches` keeps (the newest ones): each is one draw call. */
export const STRETCH_MAX = 1024;

/**
 * A trace that exists only at times, drawn in stretches: the cutting point under cutting point
 * control (G43.8/G43.9), which the position stream carries only while such a block moves. Each
 * stretch is a `TraceLine` of its own in `object` (a group), so two stretches are never joined
 * by a line across the part. `end()` closes the open stretch; the next point opens a new one
 * (starting at STRETCH_INITIAL points and doubling). Bounded like the tip trace: when the points
 * held pass `cap`, or the stretches STRETCH_MAX, the oldest stretches are dropped (the open one
 * halves itself as a `TraceLine` does).
 */
export class TraceStretches {
  readonly object = new THREE.Group();
  readonly color: number;
  readonly cap: number;
  private readonly stretches: TraceLine[] = [];
  /** The stretch points are added to; null after `end()` or `clear()`. */
  private open: TraceLine | null = null;
  /** Points held by the closed stretches. */
  private closed = 0;

  constructor(color: number, cap = TRACE_CAP, name = "stretches") {
    this.color = color;
    this.cap = cap;
    this.object.name = name;
  }

  /** Points held, all stretches. */
  get length(): number {
    return this.closed + (this.open?.length ?? 0);
  }

  /** The stretches, oldest first (the last one may be open). */
  get lines(): readonly TraceLine[] {
    return this.stretches;
  }

  /** Whether a stretch is open (the next point continues it). */
  get isOpen(): boolean {
    return this.open !== null;
  }

  /** Append a point to the open stretch, opening one if none is; a repeat of its last point is skipped: returns false. */
  add(x: number, y: number, z: number): boolean {
    if (!this.open) {
      if (this.stretches.length >= STRETCH_MAX) this.dropOldest();
      const line = new TraceLine(this.color, this.cap, STRETCH_INITIAL);
      line.object.name = `${this.object.name}-stretch`;
      this.stretches.push(line);
      this.object.add(line.object);
      line.object.updateMatrixWorld(); // placed with the group now, not only at the next render
      this.open = line;
    }
    if (!this.open.add(x, y, z)) return false;
    while (this.closed > 0 && this.length > this.cap) this.dropOldest();
    return true;
  }

  /** Close the open stretch (nothing if none is open): the next point starts a new one. */
  end(): void {
    if (!this.open) return;
    const line = this.open;
    this.open = null;
    if (line.length === 0) {
      this.remove(line);
      return;
    }
    this.closed += line.length;
    line.flush();
  }

  clear(): void {
    for (const line of this.stretches) {
      this.object.remove(line.object);
      line.dispose();
    }
    this.stretches.length = 0;
    this.open = null;
    this.closed = 0;
  }

  /** Upload what changed (closed stretches were flushed when they closed). */
  flush(): void {
    this.open?.flush();
  }

  dispose(): void {
    this.clear();
  }

  private dropOldest(): void {
    const line = this.stretches[0];
    if (!line) return;
    if (line === this.open) this.open = null;
    else this.closed -= line.length;
    this.remove(line);
  }

  private remove(line: TraceLine): void {
    const i = this.stretches.indexOf(line);
    if (i >= 0) this.stretches.splice(i, 1);
    this.object.remove(line.object);
    line.dispose();
  }
}

/**
 * The programmed path: one BufferGeometry of line segments (point i → i + 1), replaced as a
 * whole by `set`. With per-point `rapid` flags (`GET …/programs/{n}/path` gives them), a rapid move
 * to a point is drawn dim orange and a cutting move cyan.
 */
export class PathLine {
  readonly object: THREE.LineSegments;
  static readonly FEED = new THREE.Color(0x30d0ff);
  static readonly RAPID = new THREE.Color(0xd08030);

  constructor() {
    this.object = new THREE.LineSegments(
      new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ vertexColors: true, transparent: true, opacity: 0.85 }),
    );
    this.object.name = "path";
    this.object.frustumCulled = false;
  }

  /** xyz triples in the table frame; `rapid[i]`: the move to point i is a rapid. */
  set(points: ArrayLike<number> | null | undefined, rapid?: ArrayLike<boolean> | null): void {
    const old = this.object.geometry;
    const geometry = new THREE.BufferGeometry();
    const n = points ? Math.floor(points.length / 3) : 0;
    if (points && n >= 2) {
      const pos = new Float32Array((n - 1) * 6);
      const col = new Float32Array((n - 1) * 6);
      for (let i = 0; i + 1 < n; i++) {
        for (let k = 0; k < 3; k++) {
          pos[6 * i + k] = points[3 * i + k];
          pos[6 * i + 3 + k] = points[3 * (i + 1) + k];
        }
        const c = rapid && rapid[i + 1] ? PathLine.RAPID : PathLine.FEED;
        col.set([c.r, c.g, c.b, c.r, c.g, c.b], 6 * i);
      }
      geometry.setAttribute("position", new THREE.BufferAttribute(pos, 3));
      geometry.setAttribute("color", new THREE.BufferAttribute(col, 3));
      geometry.computeBoundingBox();
    }
    this.object.geometry = geometry;
    old.dispose();
  }

  /** Bounds in the path's own (table-frame) coordinates, or null when empty. */
  get bounds(): THREE.Box3 | null {
    return this.object.geometry.boundingBox;
  }

  dispose(): void {
    this.object.geometry.dispose();
    (this.object.material as THREE.Material).dispose();
  }
}

/**
 * The programmed path drawn beside a compensated tool path (cutter compensation G41/G42: the
 * path above is where the tool centre goes, this one the contour as written): dashed, in one
 * colour of its own, rapids and feeds alike.
 */
export class ProgrammedLine {
  readonly object: THREE.LineSegments;
  static readonly COLOR = new THREE.Color(0xff5ad2);

  constructor() {
    this.object = new THREE.LineSegments(
      new THREE.BufferGeometry(),
      new THREE.LineDashedMaterial({ color: ProgrammedLine.COLOR, dashSize: 2, gapSize: 1.2, transparent: true, opacity: 0.95 }),
    );
    this.object.name = "programmed-path";
    this.object.frustumCulled = false;
  }

  /** xyz triples in the table frame; null or fewer than two points: nothing drawn. */
  set(points: ArrayLike<number> | null | undefined): void {
    const old = this.object.geometry;
    const geometry = new THREE.BufferGeometry();
    const n = points ? Math.floor(points.length / 3) : 0;
    if (points && n >= 2) {
      const pos = new Float32Array((n - 1) * 6);
      for (let i = 0; i + 1 < n; i++) {
        for (let k = 0; k < 3; k++) {
          pos[6 * i + k] = points[3 * i + k];
          pos[6 * i + 3 + k] = points[3 * (i + 1) + k];
        }
      }
      geometry.setAttribute("position", new THREE.BufferAttribute(pos, 3));
      geometry.computeBoundingBox();
    }
    this.object.geometry = geometry;
    if (n >= 2) this.object.computeLineDistances();
    old.dispose();
  }

  /** Segments drawn (0 when there is no programmed path). */
  get segments(): number {
    const pos = this.object.geometry.getAttribute("position");
    return pos ? pos.count / 2 : 0;
  }

  get bounds(): THREE.Box3 | null {
    return this.object.geometry.boundingBox;
  }

  dispose(): void {
    this.object.geometry.dispose();
    (this.object.material as THREE.Material).dispose();
  }
}
