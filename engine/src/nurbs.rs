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
    /// A run of equal knots inside the curve as long as the rank or longer (the curve could
    /// jump there), or longer than the rank at its ends.
    Multiplicity,
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
    /// equal and the last `rank` equal, no interior run of `rank` equal knots, positive weights.
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
        // Runs of equal knots: `rank` at each end (checked above), fewer than `rank` inside.
        let mut start = 0;
        while start < n {
            let mut end = start;
            while end + 1 < n && knots[end + 1] == knots[start] {
                end += 1;
            }
            let run = end - start + 1;
            let at_end = start == 0 || end == n - 1;
            if run > rank || (!at_end && run >= rank) {
                return Err(Error::Multiplicity);
            }
            start = end + 1;
        }
        if weights.iter().any(|w| !(w.is_finite() && *w > 0.0)) {
            return Err(Error::Weight);
        }
        Ok(Curve { rank, knots, points, weights })
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
        let pts6 = vec![[0.0], [1.0], [2.0], [3.0], [4.0], [5.0]];
        let knots = vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0];
        assert_eq!(Curve::<1>::new(3, knots, pts6, vec![1.0; 6]), Err(Error::Multiplicity));
    }
}
