//! Nano smoothing (FANUC G05.1 Q3, `docs/motion.md`, "Nano smoothing"): the end points of
//! consecutive short straight blocks become a smooth curve the tool follows instead of the
//! polygon, as FANUC's manual describes it — insertion points (here: the programmed points)
//! are corrected within a tolerance, and the curve is built through the corrected points. The
//! linear group (X, Y, Z or their parallels) is corrected within one tolerance on its 3-D
//! distance, each rotary axis within its own (FANUC No.19587); the two groups are one curve
//! parameter, interpolated independently.
//!
//! What FANUC does not publish, fivex decides (the choices and why: `docs/motion.md`):
//! - a **run** is a sequence of blocks the curve goes through without a corner; a block that
//!   is too long or too short (linear group only), or meets the one before at a corner or at a
//!   very different length, ends the run there and the point is kept exactly;
//! - the **correction** moves a point to a quadratic fitted (least squares, along the path's
//!   length) to the points two each side, clamped to the tolerance;
//! - the **curve** is the cubic spline through the corrected points whose curvature is
//!   continuous (C²) — each point's slope is solved over the points `WINDOW` each side, so a
//!   span can be moved while the program is still being read — leaving the run's ends with
//!   the slope of the parabola through the three points there;
//! - a span of the curve that would leave the tolerance of its programmed segment goes
//!   straight between its corrected points instead (per group): the tool is never farther
//!   from the programmed segments than the tolerance.
//!
//! Pure: no state beyond the run being built, no IO. A point has `D` components.

use crate::chords;

/// Each point's slope is solved over this many points each way: the spline's dependence on a
/// point falls by about 0.27 per point (2 − √3), so what the window leaves out is 0.27¹⁰ ≈
/// 2e-6 of a slope change — the curvature jump it leaves at a point is below what a tool can
/// follow.
pub const WINDOW: usize = 10;

/// The correction's quadratic is fitted to the points this many each side.
const FIT: usize = 2;

/// Points of a span compared with its programmed segment (the curve's deviation is a smooth
/// function of the span's parameter: the largest one between samples is the sample's to a
/// small fraction of the tolerance).
const CHECK_SAMPLES: usize = 32;

/// A linear move shorter than this does not move (mm): the block is not smoothed.
const NO_MOVE: f64 = 1e-9;

/// Chords one span may need at most (a span is at most the longest block smoothed long).
const MAX_CHORDS_PER_SPAN: usize = 100_000;

/// Emitted spans kept before the run's front is dropped (what later points still need is
/// kept: a run of any length holds a bounded number of points).
const TRIM_AFTER: usize = 64;

/// How a machine smooths and which components take part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings<const D: usize> {
    /// The components smoothed as the linear group (the axes G05.1 Q3 names).
    pub linear: [bool; D],
    /// The rotary components smoothed, each with its tolerance (degrees, > 0).
    pub rotary: [Option<f64>; D],
    /// The linear group's tolerance: the 3-D distance a point may be corrected by (mm, > 0).
    pub tolerance: f64,
    /// Blocks shorter or longer than these (linear group, mm) are not smoothed.
    pub min_block: f64,
    pub max_block: f64,
    /// A point where the linear direction turns by more than this angle is kept (cosine).
    pub corner_cos: f64,
    /// A point between two blocks whose lengths differ by more than this factor is kept.
    pub spacing_ratio: f64,
    /// Components measured in mm by the chords (the machine's linear axes); the others in
    /// degrees.
    pub mm: [bool; D],
    /// Each component's highest acceleration (per s²; infinite: none): the curve's bending
    /// bounds the speed along it by it ([`Span::speed_cap`]).
    pub accel: [f64; D],
}

/// A piece of the path to move, in order: straight chords to these points, at the feed of and
/// counted to the block `tag`, no faster along the linear group than `speed_cap` (mm/s: what
/// the curve's bending leaves each component's acceleration; infinite for a straight span —
/// its corners are the planner's).
#[derive(Debug, Clone, PartialEq)]
pub struct Span<T, const D: usize> {
    pub chords: Vec<[f64; D]>,
    pub tag: T,
    pub speed_cap: f64,
}

/// The run being built: points come in with [`Smoother::push`], spans go out as soon as the
/// points after them fix their shape.
#[derive(Debug, Clone)]
pub struct Smoother<T, const D: usize> {
    s: Settings<D>,
    /// The run's programmed points (the first is where it starts, already reached) …
    p: Vec<[f64; D]>,
    /// … their distance along the linear group from the run's start (mm) …
    t: Vec<f64>,
    /// … and the block each ends (none for the first).
    tags: Vec<Option<T>>,
    /// Corrected points and slopes (d/dt) known so far, from the first.
    q: Vec<[f64; D]>,
    m: Vec<[f64; D]>,
    /// Spans moved: span k (from point k − 1 to k) for k ≤ `moved`.
    moved: usize,
    /// No point comes after the last one of the run.
    closed: bool,
}

impl<T: Clone, const D: usize> Smoother<T, D> {
    /// A run starting at `start` (where the tool is).
    pub fn new(settings: Settings<D>, start: [f64; D]) -> Self {
        Smoother {
            s: settings,
            p: vec![start],
            t: vec![0.0],
            tags: vec![None],
            q: vec![start],
            m: Vec::new(),
            moved: 0,
            closed: false,
        }
    }

    /// Blocks held: read, not yet moved.
    pub fn held(&self) -> usize {
        self.p.len() - 1 - self.moved
    }

    /// The next block's end point; the spans it lets go are appended to `out`.
    pub fn push(&mut self, point: [f64; D], tag: T, out: &mut Vec<Span<T, D>>) {
        let last = *self.p.last().expect("a run has its start");
        let length = self.linear_distance(&last, &point);
        let others_move = (0..D).any(|c| !self.smoothed(c) && point[c] != last[c]);
        if length <= NO_MOVE || length < self.s.min_block || length > self.s.max_block || others_move {
            // Not smoothed: the run ends before it, the block moves straight.
            self.close(out);
            out.push(Span { chords: vec![point], tag, speed_cap: f64::INFINITY });
            self.restart(point);
            return;
        }
        if self.p.len() >= 2 && self.keeps(&point, length) {
            self.close(out);
        }
        self.p.push(point);
        self.t.push(self.t.last().expect("a run has its start") + length);
        self.tags.push(Some(tag));
        self.advance(out);
    }

    /// No more points for this run (a block that is not smoothed comes, the mode ends, the
    /// program ends): every span held is appended to `out`.
    pub fn finish(&mut self, out: &mut Vec<Span<T, D>>) {
        self.close(out);
    }

    fn close(&mut self, out: &mut Vec<Span<T, D>>) {
        self.closed = true;
        self.advance(out);
        let last = *self.p.last().expect("a run has its start");
        self.restart(last);
    }

    fn restart(&mut self, start: [f64; D]) {
        *self = Smoother::new(self.s, start);
    }

    fn smoothed(&self, c: usize) -> bool {
        self.s.linear[c] || self.s.rotary[c].is_some()
    }

    fn linear_distance(&self, a: &[f64; D], b: &[f64; D]) -> f64 {
        (0..D).filter(|&c| self.s.linear[c]).map(|c| (b[c] - a[c]).powi(2)).sum::<f64>().sqrt()
    }

    /// The run's last point is kept (a corner, or a jump in block length) before `point`.
    fn keeps(&self, point: &[f64; D], length: f64) -> bool {
        let n = self.p.len();
        let (a, b) = (&self.p[n - 2], &self.p[n - 1]);
        let before = self.t[n - 1] - self.t[n - 2];
        let turn: f64 = (0..D).filter(|&c| self.s.linear[c]).map(|c| (b[c] - a[c]) * (point[c] - b[c])).sum::<f64>()
            / (before * length);
        turn < self.s.corner_cos || length > before * self.s.spacing_ratio || before > length * self.s.spacing_ratio
    }

    /// Correct, solve and move what the points so far fix.
    fn advance(&mut self, out: &mut Vec<Span<T, D>>) {
        let n = self.p.len();
        while self.q.len() < n && (self.closed || self.q.len() + FIT < n) {
            let q = self.corrected(self.q.len());
            self.q.push(q);
        }
        while n >= 2 && self.m.len() < n && (self.closed || self.m.len() + WINDOW + 1 < self.q.len()) {
            let m = self.slope(self.m.len());
            self.m.push(m);
        }
        while self.moved + 1 < self.m.len() {
            self.moved += 1;
            out.push(self.span(self.moved));
        }
        self.trim();
    }

    /// Drop the run's front that nothing to come needs: the corrections still to be made
    /// look `FIT` back, the slopes `WINDOW` back and one more for their boundary's estimate,
    /// the next span its start.
    fn trim(&mut self) {
        if self.moved < TRIM_AFTER + WINDOW + FIT + 1 {
            return;
        }
        let cut = (self.q.len() - FIT).min(self.m.len() - WINDOW - 1).min(self.moved - 1);
        self.p.drain(..cut);
        self.t.drain(..cut);
        self.tags.drain(..cut);
        self.q.drain(..cut);
        self.m.drain(..cut);
        self.moved -= cut;
    }

    /// Point j corrected: the run's ends are kept; inside, the least-squares quadratic (along
    /// t) through the points `FIT` each side, at j, clamped to the tolerances.
    fn corrected(&self, j: usize) -> [f64; D] {
        let n = self.p.len();
        let p = self.p[j];
        if j == 0 || (self.closed && j == n - 1) {
            return p;
        }
        let (lo, hi) = (j.saturating_sub(FIT), (j + FIT).min(n - 1));
        let fit = quadratic_at(&self.t[lo..=hi], &self.p[lo..=hi], self.t[j]);
        let mut q = p;
        let shift = self.linear_distance(&p, &fit);
        let scale = if shift > self.s.tolerance { self.s.tolerance / shift } else { 1.0 };
        for c in 0..D {
            if self.s.linear[c] {
                q[c] = p[c] + (fit[c] - p[c]) * scale;
            } else if let Some(tol) = self.s.rotary[c] {
                q[c] = p[c] + (fit[c] - p[c]).clamp(-tol, tol);
            }
        }
        q
    }

    /// The spline's slope (d/dt) at point j, solved over the points `WINDOW` each side; at
    /// the window's ends the slope of the parabola through three corrected points there.
    fn slope(&self, j: usize) -> [f64; D] {
        let last = self.q.len() - 1;
        let (lo, hi) = (j.saturating_sub(WINDOW), (j + WINDOW).min(last));
        let t = &self.t;
        let k = hi - lo + 1;
        // Rows a·m[i−1] + b·m[i] + c·m[i+1] = r, solved by the Thomas algorithm (on the stack:
        // this runs once per block).
        const ROWS: usize = 2 * WINDOW + 1;
        let mut a = [0.0; ROWS];
        let mut b = [0.0; ROWS];
        let mut cc = [0.0; ROWS];
        let mut r = [[0.0; D]; ROWS];
        for i in lo..=hi {
            let row = i - lo;
            if i == lo || i == hi {
                (b[row], r[row]) = (1.0, self.end_slope(i, lo == 0 && i == 0, self.closed && i == last));
            } else {
                let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
                let (d0, d1) = (self.chord(i - 1), self.chord(i));
                (a[row], b[row], cc[row]) = (h1, 2.0 * (h0 + h1), h0);
                r[row] = std::array::from_fn(|c| 3.0 * (h1 * d0[c] + h0 * d1[c]));
            }
        }
        for row in 1..k {
            let w = a[row] / b[row - 1];
            b[row] -= w * cc[row - 1];
            let prev = r[row - 1];
            for (x, p) in r[row].iter_mut().zip(prev) {
                *x -= w * p;
            }
        }
        let mut m = [[0.0; D]; ROWS];
        for row in (0..k).rev() {
            let next = if row + 1 < k { m[row + 1] } else { [0.0; D] };
            m[row] = std::array::from_fn(|c| (r[row][c] - cc[row] * next[c]) / b[row]);
        }
        let mut slope = m[j - lo];
        for (c, s) in slope.iter_mut().enumerate() {
            if !self.smoothed(c) {
                *s = 0.0;
            }
        }
        slope
    }

    /// The slope of the straight line from corrected point i to the next (d/dt).
    fn chord(&self, i: usize) -> [f64; D] {
        let (q, t) = (&self.q, &self.t);
        std::array::from_fn(|c| (q[i + 1][c] - q[i][c]) / (t[i + 1] - t[i]))
    }

    /// The slope given at a window's end i: the parabola's through i and the points each side
    /// of it, or at the run's first or last point through it and the two next to it (the
    /// chord in a run of two points).
    fn end_slope(&self, i: usize, first: bool, last: bool) -> [f64; D] {
        let (q, t) = (&self.q, &self.t);
        let n = q.len();
        if (first || last) && n == 2 {
            return self.chord(0);
        }
        if first {
            let (d0, d1, h0, h1) = (self.chord(0), self.chord(1), t[1] - t[0], t[2] - t[1]);
            return std::array::from_fn(|c| d0[c] - (d1[c] - d0[c]) * h0 / (h0 + h1));
        }
        if last {
            let (d0, d1, h0, h1) = (self.chord(i - 2), self.chord(i - 1), t[i - 1] - t[i - 2], t[i] - t[i - 1]);
            return std::array::from_fn(|c| d1[c] + (d1[c] - d0[c]) * h1 / (h0 + h1));
        }
        let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        std::array::from_fn(|c| {
            (h1 * h1 * (q[i][c] - q[i - 1][c]) + h0 * h0 * (q[i + 1][c] - q[i][c])) / (h0 * h1 * (h0 + h1))
        })
    }

    /// Span k (point k − 1 to k) as chords: the spline between the corrected points, or per
    /// group the straight line between them where the spline leaves the tolerance of the
    /// programmed segment.
    fn span(&self, k: usize) -> Span<T, D> {
        let h = self.t[k] - self.t[k - 1];
        let (q0, q1) = (self.q[k - 1], self.q[k]);
        let (mut m0, mut m1) = (self.m[k - 1], self.m[k]);
        let (p0, p1) = (self.p[k - 1], self.p[k]);
        let curve = |m0: &[f64; D], m1: &[f64; D], u: f64| hermite(&q0, &q1, m0, m1, h, u);
        // Which components leave their tolerance somewhere on the span (one pass of samples):
        // the linear group as one, each rotary axis on its own; the others are not smoothed.
        let mut out: [bool; D] = std::array::from_fn(|c| !self.s.linear[c] && self.s.rotary[c].is_none());
        let mut linear_out = false;
        for i in 1..CHECK_SAMPLES {
            let u = i as f64 / CHECK_SAMPLES as f64;
            let at = curve(&m0, &m1, u);
            linear_out = linear_out || chords::deviation(&p0, &p1, &at, &self.s.linear, true) > self.s.tolerance;
            for (c, tol) in self.s.rotary.iter().enumerate() {
                if let Some(tol) = tol {
                    out[c] = out[c] || (at[c] - (p0[c] + u * (p1[c] - p0[c]))).abs() > *tol;
                }
            }
        }
        for c in 0..D {
            if out[c] || (self.s.linear[c] && linear_out) {
                let straight = (q1[c] - q0[c]) / h;
                (m0[c], m1[c]) = (straight, straight);
            }
        }
        let mut chords = Vec::new();
        let f = |u: f64| curve(&m0, &m1, u);
        // A span is at most `max_block` long: far fewer chords than the bound.
        let _ = chords::split(&f, 0.0, &q0, 1.0, &q1, &self.s.mm, MAX_CHORDS_PER_SPAN, &mut chords);
        let mut points: Vec<[f64; D]> = chords.into_iter().map(|(_, p)| p).collect();
        if let Some(end) = points.last_mut() {
            *end = q1;
        }
        let speed_cap = self.speed_cap(&q0, &q1, &m0, &m1, h);
        Span { chords: points, tag: self.tags[k].clone().expect("a span ends a block"), speed_cap }
    }

    /// The highest speed along the span's linear path at which no component's acceleration
    /// from the curve's bending passes its share (`chords::bending_speed`), at the span's
    /// samples and ends. (The bending's jerk, v³·x_sss, is not capped here: through points
    /// rounded to 0.1 µm a spline's third derivative is the rounding's more than the surface's —
    /// ±0.1/mm² against 0.016 on a test wave. The planner bounds it at the chords' junctions,
    /// from how far they turn the machine's axes: `motion::planner`, `docs/motion.md`.)
    fn speed_cap(&self, q0: &[f64; D], q1: &[f64; D], m0: &[f64; D], m1: &[f64; D], h: f64) -> f64 {
        let (d1, d2) = hermite_derivatives(q0, q1, m0, m1, h);
        (0..=CHECK_SAMPLES)
            .map(|i| i as f64 / CHECK_SAMPLES as f64)
            .filter_map(|u| chords::by_length(&d1(u), &d2(u), &self.s.linear))
            .map(|xss| chords::bending_speed(&xss, &self.s.accel))
            .fold(f64::INFINITY, f64::min)
    }
}

/// The cubic Hermite curve from `q0` (slope `m0`) to `q1` (slope `m1`) over a parameter length
/// `h`, at `u` in [0, 1].
fn hermite<const D: usize>(q0: &[f64; D], q1: &[f64; D], m0: &[f64; D], m1: &[f64; D], h: f64, u: f64) -> [f64; D] {
    let (u2, u3) = (u * u, u * u * u);
    let (h00, h10, h01, h11) = (2.0 * u3 - 3.0 * u2 + 1.0, u3 - 2.0 * u2 + u, 3.0 * u2 - 2.0 * u3, u3 - u2);
    std::array::from_fn(|c| h00 * q0[c] + h10 * h * m0[c] + h01 * q1[c] + h11 * h * m1[c])
}

/// The first and second derivatives by t of the Hermite curve of [`hermite`], as functions of u.
fn hermite_derivatives<'a, const D: usize>(
    q0: &'a [f64; D],
    q1: &'a [f64; D],
    m0: &'a [f64; D],
    m1: &'a [f64; D],
    h: f64,
) -> (impl Fn(f64) -> [f64; D] + 'a, impl Fn(f64) -> [f64; D] + 'a) {
    let d1 = move |u: f64| -> [f64; D] {
        let (a, b, c, d) =
            (6.0 * u * u - 6.0 * u, 3.0 * u * u - 4.0 * u + 1.0, 6.0 * u - 6.0 * u * u, 3.0 * u * u - 2.0 * u);
        std::array::from_fn(|k| (a * q0[k] + b * h * m0[k] + c * q1[k] + d * h * m1[k]) / h)
    };
    let d2 = move |u: f64| -> [f64; D] {
        let (a, b, c, d) = (12.0 * u - 6.0, 6.0 * u - 4.0, 6.0 - 12.0 * u, 6.0 * u - 2.0);
        std::array::from_fn(|k| (a * q0[k] + b * h * m0[k] + c * q1[k] + d * h * m1[k]) / (h * h))
    };
    (d1, d2)
}

/// The least-squares quadratic in t through the points, at `at` (three points or fewer: the
/// curve through them, two: the line, one: the point).
fn quadratic_at<const D: usize>(t: &[f64], p: &[[f64; D]], at: f64) -> [f64; D] {
    let n = t.len();
    if n < 3 {
        return p[n / 2];
    }
    // Normal equations of c0 + c1·τ + c2·τ², τ = t − at (so that the value at `at` is c0).
    let mut s = [0.0; 5];
    let mut y = [[0.0; D]; 3];
    for (ti, pi) in t.iter().zip(p) {
        let tau = ti - at;
        let pow = [1.0, tau, tau * tau, tau * tau * tau, tau * tau * tau * tau];
        for (k, v) in s.iter_mut().enumerate() {
            *v += pow[k];
        }
        for (k, row) in y.iter_mut().enumerate() {
            for c in 0..D {
                row[c] += pow[k] * pi[c];
            }
        }
    }
    let a = nalgebra::Matrix3::new(s[0], s[1], s[2], s[1], s[2], s[3], s[2], s[3], s[4]);
    let Some(inv) = a.try_inverse() else {
        return p[n / 2];
    };
    std::array::from_fn(|c| inv[(0, 0)] * y[0][c] + inv[(0, 1)] * y[1][c] + inv[(0, 2)] * y[2][c])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> Settings<3> {
        Settings {
            linear: [true, true, true],
            rotary: [None; 3],
            tolerance: 0.01,
            min_block: 0.0,
            max_block: 5.0,
            corner_cos: 30f64.to_radians().cos(),
            spacing_ratio: 5.0,
            mm: [true; 3],
            accel: [f64::INFINITY; 3],
        }
    }

    fn run(points: &[[f64; 3]], s: Settings<3>) -> Vec<Span<usize, 3>> {
        let mut sm = Smoother::new(s, points[0]);
        let mut out = Vec::new();
        for (i, p) in points.iter().enumerate().skip(1) {
            sm.push(*p, i, &mut out);
        }
        sm.finish(&mut out);
        out
    }

    #[test]
    fn a_straight_line_stays_straight_and_every_block_is_moved_once_in_order() {
        let points: Vec<[f64; 3]> = (0..40).map(|i| [i as f64 * 0.5, 0.0, 0.0]).collect();
        let spans = run(&points, settings());
        assert_eq!(spans.iter().map(|s| s.tag).collect::<Vec<_>>(), (1..40).collect::<Vec<_>>());
        for s in &spans {
            assert_eq!(s.chords.len(), 1, "a straight span is one chord");
            assert!(s.chords[0].iter().zip(&points[s.tag]).all(|(a, b)| (a - b).abs() < 1e-12));
        }
    }

    #[test]
    fn points_on_a_circle_give_a_curve_on_the_circle() {
        // A radius-20 circle cut into δ = 2° chords (0.698 mm, sagitta 3 µm). Inside the run
        // each point is corrected to the quadratic fitted to five: its weights at the middle
        // are (−3, 12, 17, 12, −3)/35, which the circle's θ⁴ term (−R·θ⁴/24, at θ = 0, ±δ,
        // ±2δ) turns into 3·R·δ⁴/35 = 2.545 µm towards the centre. The curve between follows
        // the circle to a fraction of that; the two end spans, whose end slope is a
        // parabola's, within 3.6 µm.
        let (r, delta) = (20.0, 2f64.to_radians());
        let points: Vec<[f64; 3]> =
            (0..=90).map(|i| i as f64 * delta).map(|a| [r * a.cos(), r * a.sin(), 0.0]).collect();
        let spans = run(&points, settings());
        assert_eq!(spans.len(), 90);
        let inward = 3.0 * r * delta.powi(4) / 35.0;
        for s in &spans[2..88] {
            let end = s.chords.last().unwrap();
            assert!((r - end[0].hypot(end[1]) - inward).abs() < 1e-7, "{}: {end:?}", s.tag);
        }
        let worst = spans.iter().flat_map(|s| &s.chords).map(|p| (p[0].hypot(p[1]) - r).abs()).fold(0.0, f64::max);
        assert!(worst < 3.6e-6, "{worst}");
    }

    #[test]
    fn a_point_out_of_line_is_corrected_within_the_tolerance() {
        // A 0.05 mm bump in a straight line: the curve's point there moves back by at most the
        // tolerance (0.01 mm), so it passes 0.04 mm or more from the line.
        let mut points: Vec<[f64; 3]> = (0..30).map(|i| [i as f64 * 0.5, 0.0, 0.0]).collect();
        points[15][1] = 0.05;
        let spans = run(&points, settings());
        let at = spans.iter().find(|s| s.tag == 15).unwrap().chords.last().unwrap();
        assert!((at[1] - 0.04).abs() < 1e-12, "{at:?}");
    }

    #[test]
    fn a_corner_is_kept() {
        // Two lines meeting at 90°: the corner point is reached exactly, both sides straight.
        let mut points: Vec<[f64; 3]> = (0..10).map(|i| [i as f64 * 0.5, 0.0, 0.0]).collect();
        points.extend((1..10).map(|i| [4.5, i as f64 * 0.5, 0.0]));
        let spans = run(&points, settings());
        assert!(spans.iter().all(|s| s.chords.len() == 1));
        assert_eq!(spans[8].chords[0], [4.5, 0.0, 0.0]);
    }

    #[test]
    fn a_long_run_holds_a_bounded_number_of_points() {
        let mut sm = Smoother::new(settings(), [20.0, 0.0, 0.0]);
        let mut out = Vec::new();
        for i in 1..=5000 {
            let a = (i as f64 * 0.5).to_radians();
            sm.push([20.0 * a.cos(), 20.0 * a.sin(), 0.0], i, &mut out);
            assert!(sm.p.len() <= TRIM_AFTER + 2 * (WINDOW + FIT) + 4, "{}", sm.p.len());
        }
        assert_eq!(sm.held(), WINDOW + FIT + 1);
    }

    #[test]
    fn the_curvature_is_continuous_at_every_point() {
        // Noisy points (±3 µm, a pseudo-random sequence) along a wave with uneven spacing: the
        // second derivative of the spans each side of a point agree to 1e-5 of its size.
        let mut sm = Smoother::new(settings(), [0.0; 3]);
        let mut out = Vec::new();
        let (mut x, mut seed) = (0.0f64, 7u64);
        for i in 1..200 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let noise = ((seed >> 33) as f64 / (1u64 << 31) as f64 - 0.5) * 0.006;
            x += 0.3 + 0.2 * ((i % 5) as f64 / 4.0);
            sm.push([x, 3.0 * (x / 7.0).sin() + noise, 0.0], i, &mut out);
        }
        let second = |k: usize, end: bool| -> [f64; 3] {
            let (q0, q1, m0, m1) = (sm.q[k - 1], sm.q[k], sm.m[k - 1], sm.m[k]);
            let h = sm.t[k] - sm.t[k - 1];
            std::array::from_fn(|c| {
                let d = if end {
                    6.0 * q0[c] + 2.0 * h * m0[c] - 6.0 * q1[c] + 4.0 * h * m1[c]
                } else {
                    -6.0 * q0[c] - 4.0 * h * m0[c] + 6.0 * q1[c] - 2.0 * h * m1[c]
                };
                d / (h * h)
            })
        };
        let mut joints = 0;
        for k in 1..sm.m.len() - 1 {
            let (left, right) = (second(k, true), second(k + 1, false));
            let size = left[1].abs().max(1e-3);
            assert!((left[1] - right[1]).abs() < 1e-5 * size.max(0.05), "point {k}: {left:?} / {right:?}");
            joints += 1;
        }
        assert!(joints > 10, "{joints}");
    }

    #[test]
    fn a_circles_speed_cap_is_what_its_curvature_leaves_the_axes() {
        // Radius 20 in 1° blocks, 4000 mm/s² per axis: a component of the circle accelerates
        // v²/R·|cos| at a steady v, so with 90 % of 4000 the speed is at most √(3600·20) =
        // 268.33 mm/s where a component's share is whole (at 0°, 90°, …), more in between.
        let mut s = settings();
        s.accel = [4000.0; 3];
        let points: Vec<[f64; 3]> =
            (0..=180).map(|i| (i as f64).to_radians()).map(|a| [20.0 * a.cos(), 20.0 * a.sin(), 0.0]).collect();
        let spans = run(&points, s);
        let least = spans.iter().map(|s| s.speed_cap).fold(f64::INFINITY, f64::min);
        assert!((least - (3600.0f64 * 20.0).sqrt()).abs() < 0.5, "{least}");
        // At 45° both components take 1/√2 of the bending: √2^(1/2) times more.
        let at_45 = spans.iter().find(|s| s.tag == 45).unwrap().speed_cap;
        assert!((at_45 / least - 2f64.sqrt().sqrt()).abs() < 0.02, "{at_45}");
        // A straight run is not capped.
        let line: Vec<[f64; 3]> = (0..20).map(|i| [i as f64 * 0.5, 0.0, 0.0]).collect();
        assert!(run(&line, s).iter().all(|s| s.speed_cap.is_infinite()));
    }
}
