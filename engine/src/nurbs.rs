//! NURBS curves (FANUC G06.2, `docs/dialects.md`, "NURBS interpolation"): validation of the
//! rank, knots and weights the program gives, evaluation by de Boor's algorithm in homogeneous
//! coordinates, and the tessellation into the straight chords the interpreter emits.
//!
//! Pure: no state, no IO. A curve has `D` components (the interpreter uses every axis of the
//! machine: X/Y/Z and, under tool centre point control, the rotary axes follow the same curve
//! parameter).

/// The largest distance, mm, from the curve to a chord of its tessellation (`crate::chords`).
pub const CHORD_TOLERANCE_MM: f64 = crate::chords::TOLERANCE_MM;

/// A curve that needs more chords than this is refused (PS5115) rather than emitted: 200,000
/// chords are a 20 m long curve of radius 10 at `CHORD_TOLERANCE_MM`.
pub const MAX_CHORDS: usize = 200_000;

/// How close the control points on either side of an interior run of `rank` equal knots must
/// be for the curve to be continuous there: the same point up to the rounding of the
/// programming transforms and of G91 sums (a program states 1 µm, or 0.0001°).
pub const SAME_POINT: f64 = 1e-9;

/// Rank (degree + 1) limits of FANUC's conventional NURBS: P2 (linear) to P4 (cubic).
pub const RANKS: std::ops::RangeInclusive<usize> = 2..=4;

/// Why a curve is refused (all FANUC PS5115, `docs/dialects.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Error {
    /// The rank is not 2, 3 or 4.
    Rank,
    /// Fewer control points than the rank.
    TooFewPoints,
    /// The number of knots is not the number of control points plus the rank.
    KnotCount,
    /// A knot smaller than the one before it.
    Decreasing,
    /// The first rank knots (or the last) are not equal, or the curve's knot range is empty.
    Ends,
    /// A run of equal knots longer than the rank.
    Multiplicity,
    /// A run of equal knots as long as the rank inside the curve where the control points on
    /// either side differ: the curve jumps there.
    Break,
    /// A weight that is not positive (or not finite).
    Weight,
    /// More than `MAX_CHORDS` chords.
    TooManyChords,
}

/// A rational B-spline curve of `D` components.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve<const D: usize> {
    rank: usize,
    knots: Vec<f64>,
    points: Vec<[f64; D]>,
    weights: Vec<f64>,
}

impl<const D: usize> Curve<D> {
    /// Check and build a curve: `points.len() + rank` knots, non-decreasing, the first `rank`
    /// equal and the last `rank` equal, no run longer than the rank, positive weights. An
    /// interior run as long as the rank ends one piece of the curve at the control point before
    /// it and starts the next at the one after it (all basis functions but theirs are zero
    /// there): the curve is continuous only where those two coincide (to `SAME_POINT`).
    pub fn new(rank: usize, knots: Vec<f64>, points: Vec<[f64; D]>, weights: Vec<f64>) -> Result<Self, Error> {
        if !RANKS.contains(&rank) {
            return Err(Error::Rank);
        }
        if points.len() < rank {
            return Err(Error::TooFewPoints);
        }
        if knots.len() != points.len() + rank || weights.len() != points.len() {
            return Err(Error::KnotCount);
        }
        if knots.iter().any(|k| !k.is_finite()) || knots.windows(2).any(|w| w[1] < w[0]) {
            return Err(Error::Decreasing);
        }
        let n = knots.len();
        if knots[..rank].iter().any(|&k| k != knots[0])
            || knots[n - rank..].iter().any(|&k| k != knots[n - 1])
            || knots[0] >= knots[n - 1]
        {
            return Err(Error::Ends);
        }
        // Runs of equal knots: `rank` at each end (checked above), at most `rank` inside
        // (FANUC: not "in excess of the rank value"), and a run of `rank` only where the curve
        // stays continuous.
        let mut start = 0;
        while start < n {
            let mut end = start;
            while end + 1 < n && knots[end + 1] == knots[start] {
                end += 1;
            }
            let run = end - start + 1;
            if run > rank {
                return Err(Error::Multiplicity);
            }
            let inside = start > 0 && end < n - 1;
            let apart = |a: &[f64; D], b: &[f64; D]| a.iter().zip(b).any(|(x, y)| (x - y).abs() > SAME_POINT);
            if inside && run == rank && apart(&points[start - 1], &points[start]) {
                return Err(Error::Break);
            }
            start = end + 1;
        }
        if weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(Error::Weight);
        }
        Ok(Curve { rank, knots, points, weights })
    }

    /// Whether `u` is an interior knot where the curve may have a corner: a run of equal knots
    /// at least `rank − 1` long (the degree) leaves the curve only continuous there, so the
    /// chords on either side meet at an angle the curve itself has (a rank-2 curve: every
    /// interior knot, its control polygon's corners).
    pub fn corner_at(&self, u: f64) -> bool {
        let (a, b) = self.domain();
        u > a && u < b && self.knots.iter().filter(|&&k| k == u).count() + 1 >= self.rank
    }

    /// The parameter range: from the first knot to the last.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[0], self.knots[self.knots.len() - 1])
    }

    /// The index `i` of the knot span `[knots[i], knots[i + 1])` holding `u` (the last
    /// non-empty span for the curve's end).
    fn span(&self, u: f64) -> usize {
        let p = self.rank - 1;
        let last = self.points.len() - 1;
        if u >= self.knots[last + 1] {
            return last;
        }
        let mut i = p;
        while i < last && u >= self.knots[i + 1] {
            i += 1;
        }
        i
    }

    /// The curve's point at parameter `u` (clamped to the domain): de Boor's algorithm on the
    /// homogeneous control points (w·P, w), then divided by the weight.
    pub fn eval(&self, u: f64) -> [f64; D] {
        let (a, b) = self.domain();
        let u = u.clamp(a, b);
        let p = self.rank - 1;
        let k = self.span(u);
        // (hp[j], hw[j]): the homogeneous control point k - p + j (w·P, w).
        let mut hw = [0.0; 4];
        let mut hp = [[0.0; D]; 4];
        for j in 0..=p {
            let i = k - p + j;
            let w = self.weights[i];
            hw[j] = w;
            hp[j] = std::array::from_fn(|c| self.points[i][c] * w);
        }
        for r in 1..=p {
            for j in (r..=p).rev() {
                let i = k - p + j;
                let lo = self.knots[i];
                let hi = self.knots[i + p + 1 - r];
                let alpha = if hi > lo { (u - lo) / (hi - lo) } else { 0.0 };
                hw[j] = (1.0 - alpha) * hw[j - 1] + alpha * hw[j];
                let (before, here) = (hp[j - 1], hp[j]);
                hp[j] = std::array::from_fn(|c| (1.0 - alpha) * before[c] + alpha * here[c]);
            }
        }
        std::array::from_fn(|c| hp[p][c] / hw[p])
    }

    /// The curve's point and its first and second derivatives by u at `u` (clamped to the
    /// domain): the basis functions' derivatives (Piegl & Tiller, The NURBS Book, A2.3) give
    /// those of the homogeneous curve A = Σ N·w·P and of W = Σ N·w, and the quotient rule those
    /// of C = A/W: C' = (A' − W'·C)/W, C'' = (A'' − 2·W'·C' − W''·C)/W.
    pub fn derivatives(&self, u: f64) -> [[f64; D]; 3] {
        let (a, b) = self.domain();
        let u = u.clamp(a, b);
        let p = self.rank - 1;
        let k = self.span(u);
        let ders = self.basis_derivatives(k, u);
        let mut hp = [[0.0; D]; 3];
        let mut hw = [0.0; 3];
        for (d, row) in ders.iter().enumerate() {
            for (j, n) in row.iter().take(p + 1).enumerate() {
                let i = k - p + j;
                let w = self.weights[i];
                hw[d] += n * w;
                for (h, x) in hp[d].iter_mut().zip(&self.points[i]) {
                    *h += n * w * x;
                }
            }
        }
        let c0: [f64; D] = std::array::from_fn(|c| hp[0][c] / hw[0]);
        let c1: [f64; D] = std::array::from_fn(|c| (hp[1][c] - hw[1] * c0[c]) / hw[0]);
        let c2: [f64; D] = std::array::from_fn(|c| (hp[2][c] - 2.0 * hw[1] * c1[c] - hw[2] * c0[c]) / hw[0]);
        [c0, c1, c2]
    }

    /// The non-zero basis functions of span `k` at `u` and their first and second derivatives
    /// (`ders[d][j]` for N_{k−p+j}), by The NURBS Book's algorithm A2.3; a quotient whose knot
    /// difference is zero (a repeated knot) counts 0.
    fn basis_derivatives(&self, k: usize, u: f64) -> [[f64; 4]; 3] {
        let p = self.rank - 1;
        let t = &self.knots;
        let div = |x: f64, y: f64| if y == 0.0 { 0.0 } else { x / y };
        let mut ndu = [[0.0; 4]; 4];
        let (mut left, mut right) = ([0.0; 4], [0.0; 4]);
        ndu[0][0] = 1.0;
        for j in 1..=p {
            left[j] = u - t[k + 1 - j];
            right[j] = t[k + j] - u;
            let mut saved = 0.0;
            for r in 0..j {
                ndu[j][r] = right[r + 1] + left[j - r];
                let temp = div(ndu[r][j - 1], ndu[j][r]);
                ndu[r][j] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            ndu[j][j] = saved;
        }
        let mut ders = [[0.0; 4]; 3];
        for j in 0..=p {
            ders[0][j] = ndu[j][p];
        }
        let n = 2.min(p);
        for r in 0..=p {
            let mut a = [[0.0; 4]; 2];
            let (mut s1, mut s2) = (0, 1);
            a[0][0] = 1.0;
            for kk in 1..=n {
                let mut d = 0.0;
                let rk = r as isize - kk as isize;
                let pk = p - kk;
                if rk >= 0 {
                    a[s2][0] = div(a[s1][0], ndu[pk + 1][rk as usize]);
                    d = a[s2][0] * ndu[rk as usize][pk];
                }
                let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
                let j2 = if r as isize - 1 <= pk as isize { kk - 1 } else { p - r };
                for j in j1..=j2 {
                    let at = (rk + j as isize) as usize;
                    a[s2][j] = div(a[s1][j] - a[s1][j - 1], ndu[pk + 1][at]);
                    d += a[s2][j] * ndu[at][pk];
                }
                if r <= pk {
                    a[s2][kk] = div(-a[s1][kk - 1], ndu[pk + 1][r]);
                    d += a[s2][kk] * ndu[r][pk];
                }
                ders[kk][r] = d;
                std::mem::swap(&mut s1, &mut s2);
            }
        }
        let mut factor = p as f64;
        for row in ders.iter_mut().take(n + 1).skip(1) {
            for x in row.iter_mut().take(p + 1) {
                *x *= factor;
            }
            factor *= (p - 1) as f64;
        }
        ders
    }

    /// The curve as chords: the end points (and their parameters) of straight pieces from the
    /// curve's start to its end, within `crate::chords`' tolerances of the curve (`linear`
    /// marks the components in mm). Every non-empty knot span starts as four pieces, so a span
    /// whose quarter points happen to lie on one chord is still looked at more closely.
    pub fn chords(&self, linear: &[bool; D]) -> Result<Vec<(f64, [f64; D])>, Error> {
        let mut out = Vec::new();
        let curve = |u: f64| self.eval(u);
        for span in self.knots.windows(2) {
            let (a, b) = (span[0], span[1]);
            if b <= a {
                continue;
            }
            let mut pa = self.eval(a);
            for q in 1..=4 {
                let ua = a + (b - a) * (q - 1) as f64 / 4.0;
                let ub = if q == 4 { b } else { a + (b - a) * q as f64 / 4.0 };
                let pb = self.eval(ub);
                crate::chords::split(&curve, ua, &pa, ub, &pb, linear, MAX_CHORDS, &mut out)
                    .map_err(|_| Error::TooManyChords)?;
                pa = pb;
            }
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_linear_curve_is_its_polygon() {
        let c = Curve::<2>::new(2, vec![0.0, 0.0, 1.0, 1.0], vec![[0.0, 0.0], [10.0, 0.0]], vec![1.0, 1.0]).unwrap();
        assert_eq!(c.eval(0.5), [5.0, 0.0]);
        assert_eq!(c.chords(&[true, true]).unwrap().last().unwrap().1, [10.0, 0.0]);
    }

    /// A full circle of radius `r` about (r, 0) through the origin: nine control points.
    fn circle(r: f64) -> Curve<2> {
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let p =
            [[0.0, 0.0], [0.0, r], [r, r], [2.0 * r, r], [2.0 * r, 0.0], [2.0 * r, -r], [r, -r], [0.0, -r], [0.0, 0.0]];
        let knots = vec![0.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 3.0, 3.0, 4.0, 4.0, 4.0];
        Curve::new(3, knots, p.to_vec(), vec![1.0, h, 1.0, h, 1.0, h, 1.0, h, 1.0]).unwrap()
    }

    #[test]
    fn chords_stay_within_the_tolerance_and_are_bounded() {
        let c = circle(10.0);
        let chords = c.chords(&[true, true]).unwrap();
        // About 180 per quadrant (a chord of angle θ is r·θ²/8 from the arc).
        assert!((600..1600).contains(&chords.len()), "{}", chords.len());
        let mut from = [0.0, 0.0];
        for (_, q) in &chords {
            assert!(((q[0] - 10.0).hypot(q[1]) - 10.0).abs() < 1e-9);
            // The chord's middle is inside the circle by at most the tolerance.
            let m = [(from[0] + q[0]) / 2.0, (from[1] + q[1]) / 2.0];
            assert!(10.0 - (m[0] - 10.0).hypot(m[1]) <= CHORD_TOLERANCE_MM * 1.0001);
            from = *q;
        }
        assert_eq!(circle(4.0e6).chords(&[true, true]), Err(Error::TooManyChords));
    }

    #[test]
    fn knot_rules() {
        let pts = vec![[0.0], [1.0], [2.0]];
        let w = vec![1.0; 3];
        assert_eq!(Curve::<1>::new(5, vec![0.0; 8], pts.clone(), w.clone()), Err(Error::Rank));
        assert_eq!(Curve::<1>::new(3, vec![0.0, 0.0, 0.0, 1.0, 1.0], pts.clone(), w.clone()), Err(Error::KnotCount));
        assert_eq!(
            Curve::<1>::new(3, vec![0.0, 0.0, 0.0, 1.0, 1.0, 0.5], pts.clone(), w.clone()),
            Err(Error::Decreasing)
        );
        assert_eq!(Curve::<1>::new(3, vec![0.0, 0.0, 0.5, 1.0, 1.0, 1.0], pts.clone(), w.clone()), Err(Error::Ends));
        assert_eq!(
            Curve::<1>::new(3, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0], pts.clone(), vec![1.0, 0.0, 1.0]),
            Err(Error::Weight)
        );
        // An interior run as long as the rank: the curve jumps from points[2] to points[3]
        // unless they coincide; a run longer than the rank is refused either way.
        let pts6 = vec![[0.0], [1.0], [2.0], [3.0], [4.0], [5.0]];
        let knots = vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
        assert_eq!(Curve::<1>::new(3, knots.clone(), pts6, vec![1.0; 6]), Err(Error::Break));
        let joined = vec![[0.0], [1.0], [2.0], [2.0], [4.0], [5.0]];
        let c = Curve::<1>::new(3, knots, joined.clone(), vec![1.0, 1.0, 0.5, 3.0, 1.0, 1.0]).unwrap();
        assert_eq!((c.eval(0.5), c.eval(0.5 - 1e-12)[0].round()), ([2.0], 2.0));
        assert!(c.corner_at(0.5) && !c.corner_at(0.25) && !c.corner_at(0.0));
        let knots = vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
        let mut pts7 = joined;
        pts7.push([6.0]);
        assert_eq!(Curve::<1>::new(3, knots, pts7, vec![1.0; 7]), Err(Error::Multiplicity));
    }

    #[test]
    fn derivatives_are_those_of_the_curve() {
        // Against central differences of `eval` (h 1e-5 and 1e-4: errors of order h² times the
        // third and fourth derivatives) on the full circle (rational, repeated interior knots)
        // and on a rational cubic with uneven knots; the point itself is `eval`'s.
        let cubic = Curve::<3>::new(
            4,
            vec![0.0, 0.0, 0.0, 0.0, 0.7, 1.9, 3.0, 3.0, 3.0, 3.0],
            vec![
                [0.0, 0.0, 0.0],
                [5.0, 12.0, 1.0],
                [15.0, -4.0, 3.0],
                [22.0, 9.0, -2.0],
                [30.0, 1.0, 0.5],
                [41.0, 6.0, 2.0],
            ],
            vec![1.0, 0.5, 2.0, 1.0, 1.5, 1.0],
        )
        .unwrap();
        let c = circle(10.0);
        let check = |d: [[f64; 3]; 3], at: &dyn Fn(f64) -> [f64; 3], u: f64| {
            let (h1, h2) = (1e-5, 1e-4);
            for k in 0..3 {
                let fd1 = (at(u + h1)[k] - at(u - h1)[k]) / (2.0 * h1);
                let fd2 = (at(u + h2)[k] - 2.0 * at(u)[k] + at(u - h2)[k]) / (h2 * h2);
                assert!((d[0][k] - at(u)[k]).abs() < 1e-12, "{u}: {:?}", d[0]);
                assert!((d[1][k] - fd1).abs() < 1e-5 * (1.0 + fd1.abs()), "{u}: {} vs {fd1}", d[1][k]);
                assert!((d[2][k] - fd2).abs() < 1e-3 * (1.0 + fd2.abs()), "{u}: {} vs {fd2}", d[2][k]);
            }
        };
        for i in 1..30 {
            let u = 3.0 * i as f64 / 30.0 + 0.013;
            check(cubic.derivatives(u), &|u| cubic.eval(u), u);
        }
        let c3 = |u: f64| {
            let p = c.eval(u);
            [p[0], p[1], 0.0]
        };
        for i in 1..40 {
            let u = 4.0 * i as f64 / 40.0 + 0.017;
            let d = c.derivatives(u);
            check([[d[0][0], d[0][1], 0.0], [d[1][0], d[1][1], 0.0], [d[2][0], d[2][1], 0.0]], &c3, u);
        }
    }
}
