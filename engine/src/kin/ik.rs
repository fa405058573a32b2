//! Inverse kinematics: the axis positions that put the tool tip at a point with a direction.
//!
//! The orientation is solved first. Every machine kind reduces to at most two rotations about
//! fixed unit vectors, `Rot(a, x)·Rot(b, y)·p = q` (a head chain turns the reference tool
//! direction into the wanted one; a table chain turns the wanted one, seen from the table, back
//! into the reference), which has zero, one or two solutions in closed form. The linear axes
//! follow from the tip.

use super::{Joint, Kinematics, MachineKind, Side, Vec3};
use crate::machine::MAX_AXES;
use arrayvec::ArrayVec;

/// Per-joint values in [`Kinematics::joints`] order (at most two joints).
pub type PerJoint<T> = ArrayVec<T, 2>;

/// The inverse solutions: at most two.
pub type Candidates = ArrayVec<Candidate, 2>;

/// Below this, a vector counts as parallel to an axis (the angle about it is free).
const PARALLEL: f64 = 1e-9;

/// One inverse solution.
#[derive(Debug, Clone, PartialEq)]
pub struct Candidate {
    /// Every axis position in axis order: X, Y, Z of the carriage reference, the rotary axes at
    /// their basic angle in [0, 360) (a free one at its current angle), other axes unchanged.
    pub pos: ArrayVec<f64, MAX_AXES>,
    /// For each joint (in [`Kinematics::joints`] order): its angle is free in this posture
    /// (a singular posture), so it was left where it was.
    pub free: PerJoint<bool>,
}

/// The angle (degrees) that turns `u` into `w` about the unit vector `k`; `None` when `u` is
/// parallel to `k` (any angle does).
fn angle_about(k: &Vec3, u: &Vec3, w: &Vec3) -> Option<f64> {
    let u = u - k * k.dot(u);
    let w = w - k * k.dot(w);
    if u.norm() < PARALLEL || w.norm() < PARALLEL {
        return None;
    }
    Some(k.dot(&u.cross(&w)).atan2(u.dot(&w)).to_degrees())
}

/// `Rot(k, x)·p = q`: the angle x, `Some(None)` when any angle does, `None` when there is no
/// solution (p and q differ along k).
fn one_axis(k: &Vec3, p: &Vec3, q: &Vec3, tol: f64) -> Option<Option<f64>> {
    if (k.dot(p) - k.dot(q)).abs() > tol {
        return None;
    }
    Some(angle_about(k, p, q))
}

/// `Rot(a, x)·Rot(b, y)·p = q` for unit vectors, `a` not parallel to `b`: every (x, y), an angle
/// being `None` where it is free.
fn two_axes(a: &Vec3, b: &Vec3, p: &Vec3, q: &Vec3, tol: f64) -> PerJoint<(Option<f64>, Option<f64>)> {
    // c = Rot(b, y)·p = Rot(a, −x)·q keeps p's component along b and q's along a.
    let s = a.dot(b);
    let n = a.cross(b);
    let denom = 1.0 - s * s;
    let (pa, pb) = (a.dot(q), b.dot(p));
    let alpha = (pa - s * pb) / denom;
    let beta = (pb - s * pa) / denom;
    // γ²·|n|² = |c|² − |αa + βb|², a difference of numbers near 1 where c is near the a–b
    // plane: near a pole of either axis that left γ with an error of √ε (1.5·10⁻⁸, B frozen
    // at 0 for the first micrometres of a way from the singular posture, a jerk of thousands of
    // mm/s³ in the samples). The part of c across a (or b) is q's across a (p's across b),
    // whose cross product keeps its digits: γ²·|n|² = |q×a|² − β²(1 − s²) = |p×b|² − α²(1 − s²),
    // taken from the axis c is nearer to.
    let (across_a, across_b) = (q.cross(a).norm_squared(), p.cross(b).norm_squared());
    let g2 = if across_a <= across_b { across_a - beta * beta * denom } else { across_b - alpha * alpha * denom }
        / n.norm_squared();
    if g2 < -tol {
        return PerJoint::new();
    }
    let g = g2.max(0.0).sqrt();
    let gammas: &[f64] = if g < 1e-12 { &[0.0] } else { &[g, -g] };
    gammas
        .iter()
        .map(|&gamma| {
            let c = a * alpha + b * beta + n * gamma;
            (angle_about(a, &c, q), angle_about(b, p, &c))
        })
        .collect()
}

/// The tool directions (table frame) two rotary axes reach: the other joint sweeps the tool
/// over a cone, so a direction's component along `axis` lies between `lo` and `hi`
/// (`two_axes` has a solution iff (a·q − s·b·p)² ≤ (1 − s²)(1 − (b·p)²), s = a·b, with b·p
/// fixed). At such an edge the two solutions meet and the axes turn without bound — unless
/// the edge is ±1, the pole of `axis`: that is the singular posture, where the axis is free.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Reach {
    axis: Vec3,
    lo: f64,
    hi: f64,
}

impl Reach {
    /// How far (a dot product) the unit direction `tool` is inside the band from its nearest
    /// edge that is not a pole (negative: the axes cannot give it; infinite: no such edge).
    pub fn slack(&self, tool: &Vec3) -> f64 {
        /// An edge this near ±1 is the pole.
        const POLE: f64 = 1e-9;
        let d = self.axis.dot(tool);
        let above = if self.lo > -1.0 + POLE { d - self.lo } else { f64::INFINITY };
        let below = if self.hi < 1.0 - POLE { self.hi - d } else { f64::INFINITY };
        above.min(below)
    }
}

/// The angle in [0, 360), a hair below a whole turn counting as 0.
fn basic(angle: f64) -> f64 {
    let a = crate::angle::basic(angle);
    if a >= 360.0 - 1e-12 {
        0.0
    } else {
        a
    }
}

impl Kinematics {
    /// Every candidate for tool tip `tip` and direction `tool` (table frame; `tool` need not be
    /// unit) with tool length `tool_length`; free angles and other axes are taken from `from`.
    pub fn inverse(&self, tip: Vec3, tool: Vec3, tool_length: f64, from: &[f64]) -> Candidates {
        let mut out = Candidates::new();
        let Some(v) = tool.try_normalize(1e-12) else { return out };
        let joints = self.joints();
        let t0 = self.tool_axis;
        // Each entry: the rotation amounts φ about the joints' directions, in joints() order
        // (`None`: free; plain arrays, because collecting into `ArrayVec`s cost more than the
        // arithmetic).
        let mut orientations: ArrayVec<[Option<f64>; 2], 2> = ArrayVec::new();
        let tol = 1e-7;
        match self.kind {
            MachineKind::ThreeAxis => {
                if (v - t0).norm() < tol {
                    orientations.push([None; 2]);
                }
            }
            MachineKind::Head => orientations.extend(one_axis(&joints[0].direction, &t0, &v, tol).map(|x| [x, None])),
            MachineKind::Table => orientations.extend(one_axis(&joints[0].direction, &v, &t0, tol).map(|x| [x, None])),
            MachineKind::HeadHead => {
                let (a, b) = (joints[0].direction, joints[1].direction);
                orientations.extend(two_axes(&a, &b, &t0, &v, tol).into_iter().map(|(x, y)| [x, y]));
            }
            MachineKind::TableTable => {
                let (a, b) = (joints[0].direction, joints[1].direction);
                orientations.extend(two_axes(&a, &b, &v, &t0, tol).into_iter().map(|(x, y)| [x, y]));
            }
            MachineKind::HeadTable => {
                // Table⁻¹·Head·t0 = v, i.e. Rot(−table axis, φt)·Rot(head axis, φh)·t0 = v.
                let (h, t) = (joints[0].direction, joints[1].direction);
                orientations.extend(two_axes(&-t, &h, &t0, &v, tol).into_iter().map(|(x, y)| [y, x]));
            }
        }
        let n = joints.len();
        let axes = from.len().min(MAX_AXES);
        for phis in orientations {
            let mut free = PerJoint::new();
            for phi in &phis[..n] {
                free.push(phi.is_none());
            }
            // A free angle stays where it is; the other one is then solved again with it.
            let Some(phis) = self.fix_free(&joints, &phis[..n], from, &v) else { continue };
            let mut pos = ArrayVec::<f64, MAX_AXES>::new();
            pos.try_extend_from_slice(&from[..axes]).expect("at most MAX_AXES");
            for ((j, phi), free) in joints.iter().zip(phis).zip(&free) {
                if let Some(i) = j.index {
                    pos[i] = if *free { from[i] } else { basic(j.command(phi)) };
                }
            }
            // The carriage from the tip, with the rotary axes' motions computed once.
            let (head, table) = (self.motion(Side::Head, &pos), self.motion(Side::Table, &pos));
            let carriage = self.carriage_with(&head, &table, tip, tool_length);
            for (axis, value) in self.linear.iter().zip(carriage.iter()) {
                if let Some(i) = axis {
                    pos[*i] = *value;
                }
            }
            // Keep only true solutions, once each.
            if (table.unturn(head.turn(self.tool_axis)) - v).norm() > 1e-6 {
                continue;
            }
            if !out.iter().any(|c| c.pos.iter().zip(&pos).all(|(a, b)| (a - b).abs() < 1e-9)) {
                out.push(Candidate { pos, free });
            }
        }
        out
    }

    /// The directions the rotary axes reach; `None` on machines with fewer than two.
    pub fn reach(&self) -> Option<Reach> {
        // `w` is the joint whose dot product with the direction varies in `two_axes`, `other`
        // the one whose dot product is fixed at `fixed`.
        let band = |w: Vec3, other: Vec3, fixed: f64| {
            let s = w.dot(&other);
            let half = ((1.0 - s * s) * (1.0 - fixed * fixed)).max(0.0).sqrt();
            Reach { axis: w, lo: s * fixed - half, hi: s * fixed + half }
        };
        let joints = self.joints();
        let t0 = self.tool_axis;
        match self.kind {
            MachineKind::HeadHead => {
                let (a, b) = (joints[0].direction, joints[1].direction);
                Some(band(a, b, b.dot(&t0)))
            }
            MachineKind::TableTable => {
                let (a, b) = (joints[0].direction, joints[1].direction);
                Some(band(b, a, a.dot(&t0)))
            }
            MachineKind::HeadTable => {
                let (h, t) = (joints[0].direction, joints[1].direction);
                Some(band(-t, h, h.dot(&t0)))
            }
            _ => None,
        }
    }

    /// Fill in free angles (at the joint's current rotation in `from`) and solve the other
    /// joint again: the rotations φ in joints() order (unused entries 0).
    fn fix_free(&self, joints: &[&Joint], phis: &[Option<f64>], from: &[f64], v: &Vec3) -> Option<[f64; 2]> {
        if let [Some(x), Some(y)] = *phis {
            return Some([x, y]);
        }
        let current = |j: &Joint| j.sign * (j.index.map_or(j.fixed, |i| from[i]) + j.zero_offset);
        let t0 = self.tool_axis;
        let rot = |j: &Joint, phi: f64| super::rotation_deg(&j.direction, phi);
        match (self.kind, phis) {
            (_, []) => Some([0.0; 2]),
            (_, [x]) => Some([x.unwrap_or_else(|| current(joints[0])), 0.0]),
            (MachineKind::HeadHead, [x, y]) => {
                let x = x.unwrap_or_else(|| current(joints[0]));
                let y = y.or_else(|| angle_about(&joints[1].direction, &t0, &(rot(joints[0], x).inverse() * v)));
                Some([x, y.unwrap_or_else(|| current(joints[1]))])
            }
            (MachineKind::TableTable, [x, y]) => {
                let x = x.unwrap_or_else(|| current(joints[0]));
                let y = y.or_else(|| angle_about(&joints[1].direction, v, &(rot(joints[0], x).inverse() * t0)));
                Some([x, y.unwrap_or_else(|| current(joints[1]))])
            }
            (MachineKind::HeadTable, [h, t]) => {
                let t = t.unwrap_or_else(|| current(joints[1]));
                let h = h.or_else(|| angle_about(&joints[0].direction, &t0, &(rot(joints[1], t) * v)));
                Some([h.unwrap_or_else(|| current(joints[0])), t])
            }
            _ => None,
        }
    }
}
