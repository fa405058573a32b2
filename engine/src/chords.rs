//! Curves the interpreter emits as straight chords (NURBS, `crate::nurbs`; nano smoothing,
//! `crate::smoothing`): a parameter interval of a curve is halved until three points inside
//! each piece (at ¼, ½, ¾) are within the tolerance of its chord, on the linear components in
//! mm and on the others (rotary axes) in degrees, both at one point of the chord
//! ([`along`]): the machine runs a chord as a G01, every axis at the same share of its travel.
//!
//! Pure: no state, no IO. A curve has `D` components and is given as its evaluation function.

/// The largest distance, mm, from a curve to one of its chords (0.1 µm, measured on the linear
/// components). It is a tenth of the 1 µm least input increment of FANUC's IS-B (and of the
/// 1 µm the tests hold sampled paths to), so the path a program cuts is the curve to the
/// resolution a program can state; a radius-10 circle needs about 180 chords per quadrant at
/// this tolerance (`docs/motion.md`, "NURBS").
pub const TOLERANCE_MM: f64 = 1e-4;

/// The same bound, degrees, on the rotary components (their chord turns the tool linearly).
pub const TOLERANCE_DEG: f64 = 1e-4;

/// A curve halved this many times over is taken as it is (2⁻⁴⁰ of its interval: far below any
/// increment; only a curve that is not continuous gets there).
const MAX_DEPTH: u32 = 40;

/// The share of an axis's acceleration a curve's bending may take at the speed it caps (the
/// rest is left to speed changes along it), as the planner's cruise share for kinematic paths
/// (`motion::path`).
pub const BENDING_SHARE: f64 = 0.9;

/// A curve's second derivative by its path length s at one point, from its first and second
/// derivatives by any parameter t there (`linear` marks the components whose length s is):
/// x_ss = (x'' − x'·s''/s')/s'², s' = |x'| and s'' = x'·x''/s' over the linear components.
/// `None` where the curve does not move.
pub fn by_length<const D: usize>(x1: &[f64; D], x2: &[f64; D], linear: &[bool; D]) -> Option<[f64; D]> {
    let s1 = (0..D).filter(|&c| linear[c]).map(|c| x1[c] * x1[c]).sum::<f64>().sqrt();
    if s1 <= 1e-12 {
        return None;
    }
    let s2 = (0..D).filter(|&c| linear[c]).map(|c| x1[c] * x2[c]).sum::<f64>() / s1;
    Some(std::array::from_fn(|c| (x2[c] - x1[c] * s2 / s1) / (s1 * s1)))
}

/// The highest speed along a curve at which no component's acceleration from the curve's
/// bending, v²·x_ss (`xss`, [`by_length`]), passes `BENDING_SHARE` of `accel` (per s²).
/// Infinite where the curve does not bend.
pub fn bending_speed<const D: usize>(xss: &[f64; D], accel: &[f64; D]) -> f64 {
    // One root, of the lowest quotient: the root is monotone, also as rounded.
    xss.iter()
        .zip(accel)
        .filter(|(x, _)| x.abs() > 1e-12)
        .map(|(x, a)| BENDING_SHARE * a / x.abs())
        .fold(f64::INFINITY, f64::min)
        .sqrt()
}

/// The same for the jerk of the bending, v³·x_sss, with x_sss the change of x_ss from `xss0` to
/// `xss1` over a path length `ds`, against `BENDING_SHARE` of `jerk` (per s³).
pub fn bending_jerk_speed<const D: usize>(xss0: &[f64; D], xss1: &[f64; D], ds: f64, jerk: &[f64; D]) -> f64 {
    if ds <= 1e-12 {
        return f64::INFINITY;
    }
    (0..D)
        .map(|c| ((xss1[c] - xss0[c]) / ds, jerk[c]))
        .filter(|(x, _)| x.abs() > 1e-12)
        .map(|(x, j)| (BENDING_SHARE * j / x.abs()).cbrt())
        .fold(f64::INFINITY, f64::min)
}

/// More chords than a caller allows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooMany;

/// The chords of `curve` over `[a, b]`, whose end points `pa`, `pb` the caller has evaluated:
/// their end points and parameters are appended to `out` (not `pa`), ending with `(b, pb)`.
/// `linear` marks the components measured in mm. More than `max` entries in `out`: `TooMany`.
#[allow(clippy::too_many_arguments)]
pub fn split<const D: usize>(
    curve: &impl Fn(f64) -> [f64; D],
    a: f64,
    pa: &[f64; D],
    b: f64,
    pb: &[f64; D],
    linear: &[bool; D],
    max: usize,
    out: &mut Vec<(f64, [f64; D])>,
) -> Result<(), TooMany> {
    Halving { curve, linear, max, out }.piece((a, pa), (b, pb), 0)
}

/// One tessellation in progress: the curve, how it is measured, and the chords so far.
struct Halving<'a, F, const D: usize> {
    curve: &'a F,
    linear: &'a [bool; D],
    max: usize,
    out: &'a mut Vec<(f64, [f64; D])>,
}

impl<F: Fn(f64) -> [f64; D], const D: usize> Halving<'_, F, D> {
    /// The piece from `a` to `b` (parameters and points), halved `depth` times so far.
    fn piece(&mut self, (a, pa): (f64, &[f64; D]), (b, pb): (f64, &[f64; D]), depth: u32) -> Result<(), TooMany> {
        let (curve, linear) = (self.curve, self.linear);
        let fine = depth >= MAX_DEPTH || {
            // The three points in order along the chord: the machine runs it one way.
            let mut s = 0.0;
            [0.25, 0.5, 0.75].iter().all(|t| match along(pa, pb, &curve(a + (b - a) * t), linear) {
                Some((lo, hi)) if hi >= s => {
                    s = s.max(lo);
                    true
                }
                _ => false,
            })
        };
        if fine {
            if self.out.len() >= self.max {
                return Err(TooMany);
            }
            self.out.push((b, *pb));
            return Ok(());
        }
        let m = 0.5 * (a + b);
        let pm = curve(m);
        self.piece((a, pa), (m, &pm), depth + 1)?;
        self.piece((m, &pm), (b, pb), depth + 1)
    }
}

/// Where on the chord `a`–`b`, run as a G01 (the point a + s·(b − a), s from 0 to 1, every
/// component at the same s), the point `q` is within the tolerances: `TOLERANCE_MM` on the
/// components `linear` marks, `TOLERANCE_DEG` on the others, both at one s. `None` where no s
/// holds both. Each group's distance to its part of the chord is within its bound on an
/// interval of s (a ball cut by a line); a group that does not move (a linear length of zero
/// where only rotary axes turn, or rotary axes standing still) bounds s nowhere, but is
/// within its bound everywhere or nowhere. Measured apart, a rotary axis turning unevenly
/// while X/Y/Z move evenly was within its bound of its own part of the chord at another s
/// than the linear axes' (C a cubic of X: 3° off between the vertices).
pub fn along<const D: usize>(a: &[f64; D], b: &[f64; D], q: &[f64; D], linear: &[bool; D]) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
    for (on, tol) in [(true, TOLERANCE_MM), (false, TOLERANCE_DEG)] {
        let group = || (0..D).filter(move |&c| linear[c] == on);
        // |a + s·d − q|² = d²·s² − 2·s·(d·e) + e², e = q − a.
        let d2: f64 = group().map(|c| (b[c] - a[c]).powi(2)).sum();
        let de: f64 = group().map(|c| (b[c] - a[c]) * (q[c] - a[c])).sum();
        let e2: f64 = group().map(|c| (q[c] - a[c]).powi(2)).sum();
        if d2 == 0.0 {
            if e2 > tol * tol {
                return None;
            }
            continue;
        }
        let s0 = de / d2;
        // The squared distance at the nearest point, from the point itself (no cancellation).
        let off2: f64 = group().map(|c| (a[c] + s0 * (b[c] - a[c]) - q[c]).powi(2)).sum();
        if off2 > tol * tol {
            return None;
        }
        let half = ((tol * tol - off2) / d2).sqrt();
        (lo, hi) = (lo.max(s0 - half), hi.min(s0 + half));
    }
    (lo <= hi).then_some((lo, hi))
}

/// The distance from `q` to the segment `a`–`b`, on the components `linear` marks (`on` true)
/// or on the others.
pub fn deviation<const D: usize>(a: &[f64; D], b: &[f64; D], q: &[f64; D], linear: &[bool; D], on: bool) -> f64 {
    let pick = |c: usize| linear[c] == on;
    let (mut ab2, mut t) = (0.0, 0.0);
    for c in (0..D).filter(|&c| pick(c)) {
        let ab = b[c] - a[c];
        ab2 += ab * ab;
        t += (q[c] - a[c]) * ab;
    }
    let t = if ab2 > 0.0 { (t / ab2).clamp(0.0, 1.0) } else { 0.0 };
    (0..D).filter(|&c| pick(c)).map(|c| (a[c] + t * (b[c] - a[c]) - q[c]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_parabola_is_cut_until_every_chord_is_within_the_tolerance() {
        // y = x² over [0, 1]: a chord of width w sags w²/4 at its middle, so chords of width
        // 2⁻⁵ (sag 2.4e-4) are too coarse and 2⁻⁶ (6.1e-5) fine: 64 chords.
        let curve = |u: f64| [u, u * u];
        let mut out = Vec::new();
        split(&curve, 0.0, &curve(0.0), 1.0, &curve(1.0), &[true, true], 1000, &mut out).unwrap();
        assert_eq!(out.len(), 64);
        assert_eq!(out.last().unwrap().1, [1.0, 1.0]);
        assert_eq!(split(&curve, 0.0, &curve(0.0), 1.0, &curve(1.0), &[true, true], 10, &mut Vec::new()), Err(TooMany));
    }

    #[test]
    fn rotary_components_are_held_to_degrees() {
        // The same parabola on two rotary components beside a linear one that stands still:
        // the same bound, in degrees.
        let curve = |u: f64| [0.0, u, u * u];
        let mut out = Vec::new();
        split(&curve, 0.0, &curve(0.0), 1.0, &curve(1.0), &[true, false, false], 1000, &mut out).unwrap();
        assert_eq!(out.len(), 64);
    }

    #[test]
    fn a_rotary_axis_turning_unevenly_is_on_the_curve_where_the_machine_runs_the_chord() {
        // C a cubic of X (the Bézier of C 0, 190, 270, 360 over X 0–30, X = 30·u, C rising):
        // each chord runs X and C at one share s of their travel. A machine point (x, C) is on
        // the curve where some u has 30·u within 0.1 µm of x and c(u) within 0.0001° of C: u
        // within tol/30 of x/30, where c, rising, spans c((x − tol)/30) to c((x + tol)/30).
        // Measured apart, X's part and C's part of the chords each held the curve, and the
        // machine was 3° off C between the vertices.
        let c = |u: f64| 3.0 * u * (1.0 - u).powi(2) * 190.0 + 3.0 * u * u * (1.0 - u) * 270.0 + 360.0 * u.powi(3);
        let curve = |u: f64| [30.0 * u, c(u)];
        let mut out = Vec::new();
        split(&curve, 0.0, &curve(0.0), 1.0, &curve(1.0), &[true, false], 100_000, &mut out).unwrap();
        // 214 chords (4 when the groups were measured apart).
        assert!((150..400).contains(&out.len()), "{} chords", out.len());
        let (mut from, slack) = (curve(0.0), 1e-9);
        for (_, to) in &out {
            for k in 0..=64 {
                let s = k as f64 / 64.0;
                let (x, at) = (from[0] + s * (to[0] - from[0]), from[1] + s * (to[1] - from[1]));
                let (lo, hi) = (c((x - TOLERANCE_MM) / 30.0), c((x + TOLERANCE_MM) / 30.0));
                assert!(
                    at >= lo - TOLERANCE_DEG - slack && at <= hi + TOLERANCE_DEG + slack,
                    "X{x}: C{at}, curve {lo}–{hi}"
                );
            }
            from = *to;
        }
        // X standing still and two rotary axes, B even and C uneven: only the rotary group
        // moves, and the machine's (B, C) is within 0.0001° of the curve's at some u (the
        // nearest, by a ternary search where B is within the bound).
        let curve = |u: f64| [0.0, 30.0 * u, c(u)];
        let mut out = Vec::new();
        split(&curve, 0.0, &curve(0.0), 1.0, &curve(1.0), &[true, false, false], 100_000, &mut out).unwrap();
        let mut from = curve(0.0);
        for (_, to) in &out {
            for k in 0..=64 {
                let s = k as f64 / 64.0;
                let m = [from[1] + s * (to[1] - from[1]), from[2] + s * (to[2] - from[2])];
                let off = |u: f64| (m[0] - 30.0 * u).hypot(m[1] - c(u));
                let (mut lo, mut hi) = ((m[0] - TOLERANCE_DEG) / 30.0, (m[0] + TOLERANCE_DEG) / 30.0);
                for _ in 0..100 {
                    let (u1, u2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
                    (lo, hi) = if off(u1) < off(u2) { (lo, u2) } else { (u1, hi) };
                }
                assert!(off(lo) <= TOLERANCE_DEG + slack, "B{} C{}: {}° off", m[0], m[1], off(lo));
            }
            from = *to;
        }
    }

    #[test]
    fn a_point_is_on_a_chord_at_one_share_of_its_travel() {
        let lin = [true, false];
        // X 0→10 with C 0→10: X5 C5 is at s = ½; X5 C7 is on neither group's own line at that s.
        let (lo, hi) = along(&[0.0, 0.0], &[10.0, 10.0], &[5.0, 5.0], &lin).unwrap();
        assert!(lo < 0.5 && hi > 0.5 && hi - lo < 1e-4);
        assert_eq!(along(&[0.0, 0.0], &[10.0, 10.0], &[5.0, 7.0], &lin), None);
        // No linear travel: C alone sets s; X must stay within the bound.
        assert!(along(&[1.0, 0.0], &[1.0, 10.0], &[1.0, 2.5], &lin).is_some_and(|(lo, hi)| lo < 0.25 && hi > 0.25));
        assert_eq!(along(&[1.0, 0.0], &[1.0, 10.0], &[1.001, 2.5], &lin), None);
        // Nothing moves: the whole chord, or nowhere.
        assert_eq!(along(&[1.0, 2.0], &[1.0, 2.0], &[1.0, 2.0], &lin), Some((0.0, 1.0)));
    }
}
