//! Corner rounding between straight feed moves (Haas G187, `docs/dialects.md`, "Haas cycles"):
//! the corner where one straight move meets the next is replaced by a circular arc tangent to
//! both, in their common plane, that passes within the tolerance of the programmed corner.
//!
//! The rules (fivex's decisions where the Haas pages are silent):
//! - the arc's nearest point to the corner is `tolerance` from it where the moves are long
//!   enough: the tangent points lie d = tolerance / tan(θ/4) from the corner (θ the turn
//!   between the two directions; the arc's distance to the corner is d·tan(θ/4));
//! - a tangent point may use at most half of either move (so two blends never overlap, and a
//!   move keeps a straight middle), and then the arc passes closer than the tolerance;
//! - a corner that turns by less than [`COLLINEAR_RAD`] needs no arc, one that turns back by
//!   more than π − [`REVERSAL_RAD`] is kept exact (the arc would shrink to nothing at the
//!   corner's point anyway);
//! - on the arc the speed is capped so that no axis's acceleration v²/r passes its share of the
//!   axis's acceleration (`chords::bending_speed`), nor what its jerk gives in one 1 ms
//!   interpolation period ([`STEP_S`]): the acceleration steps from 0 to v²/r where the arc
//!   meets the line, as the speed steps at a corner by what the acceleration gives in 1 ms;
//! - the arc is emitted as chords within `chords::TOLERANCE_MM`, its first half counted to the
//!   move before the corner, its second half to the move after it, the midpoint (the arc's
//!   point nearest the corner) always a chord's end.
//!
//! Only the `linear` components take part; the others must not change along a move (the
//! caller sends a move that turns a rotary axis as a corner kept exact: [`Blender::finish`]
//! first). Pure: no state beyond the move held, no IO.

use crate::chords;

/// A turn smaller than this (radians) is a straight continuation: no arc.
pub const COLLINEAR_RAD: f64 = 1e-9;

/// A turn within this of π (radians) is a reversal: kept exact.
pub const REVERSAL_RAD: f64 = 1e-6;

/// The interpolation period over which an arc's end may step an axis's acceleration by what
/// its jerk gives (s).
pub const STEP_S: f64 = 0.001;

/// A move shorter than this (mm) does not move: it ends the corner rounding there.
const NO_MOVE: f64 = 1e-9;

/// Chords one half arc may have at most (more: `TooMany`).
pub const MAX_CHORDS: usize = 200_000;

/// Straight pieces of the path to move, in order, counted to the block `tag`, no faster than
/// `speed_cap` (mm/s; infinite on a straight piece).
#[derive(Debug, Clone, PartialEq)]
pub struct Piece<T, const D: usize> {
    pub chords: Vec<[f64; D]>,
    pub tag: T,
    pub speed_cap: f64,
}

/// More chords than an arc may have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooMany;

/// The move held until the next one says how its end corner is rounded.
#[derive(Debug, Clone)]
struct Held<T, const D: usize> {
    /// Its programmed start (the corner before it) and end.
    start: [f64; D],
    end: [f64; D],
    tag: T,
}

/// Corner rounding in progress: moves come in with [`Blender::push`], pieces go out as soon as
/// the next move fixes the corner.
#[derive(Debug, Clone)]
pub struct Blender<T, const D: usize> {
    tolerance: f64,
    linear: [bool; D],
    /// Each component's highest acceleration (per s²; infinite: none): an arc's bending caps
    /// the speed on it.
    accel: [f64; D],
    /// … and jerk (per s³): the acceleration's step where an arc meets a line caps it too.
    jerk: [f64; D],
    /// Where the path moved so far ends (a corner, or the last arc's exit point).
    from: [f64; D],
    held: Option<Held<T, D>>,
}

/// The rounding of one corner: tangent distance, radius, and the arc's distance to the corner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rounding {
    pub tangent: f64,
    pub radius: f64,
    pub deviation: f64,
}

/// How the corner between a move of length `l1` and one of length `l2` turning by `turn`
/// radians is rounded within `tolerance` (`None`: kept exact).
pub fn rounding(turn: f64, l1: f64, l2: f64, tolerance: f64) -> Option<Rounding> {
    if !(COLLINEAR_RAD..=std::f64::consts::PI - REVERSAL_RAD).contains(&turn) || tolerance <= 0.0 {
        return None;
    }
    let q = (turn / 4.0).tan();
    let tangent = (tolerance / q).min(0.5 * l1.min(l2));
    if tangent <= NO_MOVE {
        return None;
    }
    Some(Rounding { tangent, radius: tangent / (turn / 2.0).tan(), deviation: tangent * q })
}

fn sub<const D: usize>(a: &[f64; D], b: &[f64; D]) -> [f64; D] {
    std::array::from_fn(|c| a[c] - b[c])
}

impl<T: Clone, const D: usize> Blender<T, D> {
    /// Rounding within `tolerance` (mm) from `start` (where the tool is).
    pub fn new(tolerance: f64, linear: [bool; D], accel: [f64; D], jerk: [f64; D], start: [f64; D]) -> Self {
        Blender { tolerance, linear, accel, jerk, from: start, held: None }
    }

    /// A move is held (read, not yet moved).
    pub fn holds(&self) -> bool {
        self.held.is_some()
    }

    fn length(&self, v: &[f64; D]) -> f64 {
        (0..D).filter(|&c| self.linear[c]).map(|c| v[c] * v[c]).sum::<f64>().sqrt()
    }

    /// The next move's end point: the pieces it lets go are appended to `out`.
    pub fn push(&mut self, point: [f64; D], tag: T, out: &mut Vec<Piece<T, D>>) -> Result<(), TooMany> {
        let last = self.held.as_ref().map_or(self.from, |h| h.end);
        let others_move = (0..D).any(|c| !self.linear[c] && point[c] != last[c]);
        if self.length(&sub(&point, &last)) <= NO_MOVE || others_move {
            // Not rounded: what is held moves to its end, then this move, straight.
            self.finish(out);
            out.push(Piece { chords: vec![point], tag, speed_cap: f64::INFINITY });
            self.from = point;
            return Ok(());
        }
        let Some(held) = self.held.take() else {
            self.held = Some(Held { start: last, end: point, tag });
            return Ok(());
        };
        let corner = held.end;
        let (a, b) = (sub(&corner, &held.start), sub(&point, &corner));
        let (l1, l2) = (self.length(&a), self.length(&b));
        let u: [f64; D] = std::array::from_fn(|c| if self.linear[c] { a[c] / l1 } else { 0.0 });
        let v: [f64; D] = std::array::from_fn(|c| if self.linear[c] { b[c] / l2 } else { 0.0 });
        // The turn from the length of u − v (accurate at small and large turns alike).
        let turn = 2.0 * (0.5 * self.length(&sub(&v, &u))).min(1.0).asin();
        match rounding(turn, l1, l2, self.tolerance) {
            None => {
                out.push(Piece { chords: vec![corner], tag: held.tag, speed_cap: f64::INFINITY });
                self.from = corner;
            }
            Some(r) => {
                let enter: [f64; D] = std::array::from_fn(|c| corner[c] - u[c] * r.tangent);
                // The centre lies along the bisector v − u, r / cos(θ/2) from the corner.
                let w = sub(&v, &u);
                let wl = self.length(&w);
                let to_centre = r.radius / (turn / 2.0).cos();
                let centre: [f64; D] = std::array::from_fn(|c| corner[c] + w[c] / wl * to_centre);
                let e1 = sub(&enter, &centre);
                let (radius, linear) = (r.radius, self.linear);
                let arc = move |t: f64| -> [f64; D] {
                    let phi = t * turn;
                    let (s, k) = phi.sin_cos();
                    std::array::from_fn(
                        |c| if linear[c] { centre[c] + e1[c] * k + u[c] * radius * s } else { corner[c] },
                    )
                };
                // The bending v²/r along each axis: the arc's plane is spanned by e1/r and u.
                let xss: [f64; D] =
                    std::array::from_fn(|c| if self.linear[c] { (e1[c] / radius).hypot(u[c]) / radius } else { 0.0 });
                let step: [f64; D] = std::array::from_fn(|c| self.jerk[c] * STEP_S / chords::BENDING_SHARE);
                let cap = chords::bending_speed(&xss, &self.accel).min(chords::bending_speed(&xss, &step));
                let mid = arc(0.5);
                let mut first = Vec::new();
                let mut second = Vec::new();
                chords::split(&arc, 0.0, &enter, 0.5, &mid, &self.mm(), MAX_CHORDS, &mut first).map_err(|_| TooMany)?;
                let exit = arc(1.0);
                chords::split(&arc, 0.5, &mid, 1.0, &exit, &self.mm(), MAX_CHORDS, &mut second).map_err(|_| TooMany)?;
                out.push(Piece { chords: vec![enter], tag: held.tag.clone(), speed_cap: f64::INFINITY });
                out.push(Piece { chords: first.into_iter().map(|(_, p)| p).collect(), tag: held.tag, speed_cap: cap });
                out.push(Piece {
                    chords: second.into_iter().map(|(_, p)| p).collect(),
                    tag: tag.clone(),
                    speed_cap: cap,
                });
                self.from = exit;
            }
        }
        self.held = Some(Held { start: corner, end: point, tag });
        Ok(())
    }

    /// The components the chords measure in mm.
    fn mm(&self) -> [bool; D] {
        self.linear
    }

    /// The move held goes to its programmed end (the rounding ends there).
    pub fn finish(&mut self, out: &mut Vec<Piece<T, D>>) {
        if let Some(h) = self.held.take() {
            out.push(Piece { chords: vec![h.end], tag: h.tag, speed_cap: f64::INFINITY });
            self.from = h.end;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn blend(tol: f64, points: &[[f64; 2]]) -> Vec<Piece<usize, 2>> {
        let mut b = Blender::new(tol, [true; 2], [f64::INFINITY; 2], [f64::INFINITY; 2], [0.0; 2]);
        let mut out = Vec::new();
        for (k, p) in points.iter().enumerate() {
            b.push(*p, k, &mut out).unwrap();
        }
        b.finish(&mut out);
        out
    }

    fn dist(a: &[f64; 2], b: &[f64; 2]) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    #[test]
    fn a_right_angle_is_rounded_within_the_tolerance() {
        // 90°: d = E / tan(22.5°) = 0.1 · 2.41421 = 0.241421, r = d / tan(45°) = d; the arc's
        // nearest point to the corner (10, 0) is E from it.
        let out = blend(0.1, &[[10.0, 0.0], [10.0, 10.0]]);
        let r = rounding(std::f64::consts::FRAC_PI_2, 10.0, 10.0, 0.1).unwrap();
        assert!((r.tangent - 0.1 / (std::f64::consts::PI / 8.0).tan()).abs() < 1e-12);
        assert!((r.radius - r.tangent).abs() < 1e-12 && (r.deviation - 0.1).abs() < 1e-12);
        assert_eq!(out[0].chords, vec![[10.0 - r.tangent, 0.0]]);
        let nearest = out.iter().flat_map(|p| &p.chords).map(|p| dist(p, &[10.0, 0.0])).fold(f64::INFINITY, f64::min);
        assert!((nearest - 0.1).abs() < 1e-12, "{nearest}");
        // The arc's halves are counted to the two blocks; the last piece ends at the end.
        assert_eq!((out[1].tag, out[2].tag), (0, 1));
        let exit = out[2].chords.last().unwrap();
        assert!(dist(exit, &[10.0, r.tangent]) < 1e-12, "{exit:?}");
        assert_eq!(out.last().unwrap().chords.last(), Some(&[10.0, 10.0]));
    }

    #[test]
    fn short_moves_give_half_their_length_and_reversals_and_straight_runs_stay_exact() {
        // Moves of 0.2: the tangent points at 0.1, the deviation 0.1 · tan(22.5°) < E = 1.
        let out = blend(1.0, &[[0.2, 0.0], [0.2, 0.2]]);
        assert!((out[0].chords[0][0] - 0.1).abs() < 1e-12);
        let nearest = out.iter().flat_map(|p| &p.chords).map(|p| dist(p, &[0.2, 0.0])).fold(f64::INFINITY, f64::min);
        assert!((nearest - 0.1 * (std::f64::consts::PI / 8.0).tan()).abs() < 1e-12);
        // Collinear: one straight piece per block; reversal: exact.
        let line = blend(0.1, &[[1.0, 0.0], [2.0, 0.0]]);
        assert_eq!(line.iter().map(|p| p.chords.clone()).collect::<Vec<_>>(), vec![vec![[1.0, 0.0]], vec![[2.0, 0.0]]]);
        let back = blend(0.1, &[[1.0, 0.0], [0.0, 0.0]]);
        assert_eq!(back[0].chords, vec![[1.0, 0.0]]);
    }
}
