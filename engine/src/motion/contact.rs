//! Where the tool touches the programmed contour under cutter compensation (G41/G42, the tool
//! side offset G41.2…G42.6, the leading edge offset G41.3), on the real tool — placed by forward
//! kinematics of the sampled axes, a cylinder of the compensation's radius standing on the tip:
//! - at its side (`Touch::Side`): its point nearest to the piece of the programmed contour the
//!   motion cuts. Where the machine does what was programmed it is on the contour (the tool at
//!   its radius); where it does not (an inside corner the tool cannot reach, a corner it moves
//!   round at a distance, a line that runs below the tool's end) it is off the contour by the
//!   gap; where the tool overlaps the contour (a gouge), past it by as much as the tool cuts in;
//! - at the leading edge of its end (`Touch::LeadingEdge`): the end's edge toward the block's
//!   programmed move, across the tool.
//!
//! `docs/conventions.md`, "Positions: tip and programmed point".

use crate::canon::Touch;
use crate::kin::Vec3;
use std::f64::consts::{PI, TAU};

/// The piece of the programmed contour (the tip path the program gives, before the
/// compensation; table frame) that a compensated motion cuts.
#[derive(Debug, Clone, PartialEq)]
pub enum Contour {
    /// The contour does not move: a corner the tool turns about (its straight moves, a G39
    /// arc), a start-up's inserted move.
    Point(Vec3),
    Line(Vec3, Vec3),
    /// A circle (helix) from `from` to `to` about `center`, turning by `sweep` radians
    /// right-handed about `axis` (unit).
    Arc {
        from: Vec3,
        to: Vec3,
        center: Vec3,
        axis: Vec3,
        sweep: f64,
    },
}

impl Contour {
    /// The contour from `from` to `to` of a motion that moves the tool on a circle about
    /// `center` turning right-handed about `axis` (unit) by `sweep` radians (`None`: straight).
    /// The contour is concentric with the tool's circle; its own sweep goes from `from` to `to`
    /// the same way round (the tool's ends may be further round or short of them, where an
    /// inside corner's offset curves meet), the whole way round where they coincide on a circle
    /// of more than half a turn.
    pub fn of(from: Vec3, to: Vec3, circle: Option<(Vec3, Vec3, f64)>) -> Contour {
        match circle {
            Some((center, axis, sweep)) => {
                let flat = |p: Vec3| {
                    let r = p - center;
                    r - axis * axis.dot(&r)
                };
                let (a, b) = (flat(from), flat(to));
                let angle = (sweep.signum() * axis.dot(&a.cross(&b))).atan2(a.dot(&b)).rem_euclid(TAU);
                let angle = if angle < 1e-9 && sweep.abs() > PI { TAU } else { angle };
                Contour::Arc { from, to, center, axis, sweep: angle * sweep.signum() }
            }
            None if (to - from).norm() <= 1e-9 => Contour::Point(to),
            None => Contour::Line(from, to),
        }
    }
}

/// A compensated motion's contour and the tool that cuts it.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    contour: Contour,
    radius: f64,
    touch: Touch,
}

impl Contact {
    pub fn new(contour: Contour, radius: f64, touch: Touch) -> Contact {
        Contact { contour, radius, touch }
    }

    /// Where the contour ends: where the next compensated motion's begins.
    pub fn contour_end(&self) -> Vec3 {
        match self.contour {
            Contour::Point(p) | Contour::Line(_, p) | Contour::Arc { to: p, .. } => p,
        }
    }

    /// The point where the tool touches, the tool tip at `tip` pointing along `tool` (unit, tip
    /// toward holder; both in the table frame).
    pub fn point(&self, tip: Vec3, tool: Vec3) -> Vec3 {
        let (rel, along) = match (self.touch, &self.contour) {
            (Touch::LeadingEdge, Contour::Line(a, b)) => (b - a, 0.0),
            (Touch::LeadingEdge, _) => (self.nearest(tip, tool, 0.0) - tip, 0.0),
            (Touch::Side { along }, _) => {
                let rel = self.nearest(tip, tool, along) - tip;
                // The cylinder stands on the tip: below it, the end's edge touches.
                (rel, tool.dot(&rel).max(0.0))
            }
        };
        let side = rel - tool * tool.dot(&rel);
        let at = tip + tool * along;
        match side.try_normalize(1e-9) {
            Some(d) => at + d * self.radius,
            // Along the tool's axis (the contour on it: a radius of 0; a move along the tool).
            None => at,
        }
    }

    /// The contour's point nearest to the tool's axis (a line: exactly; an arc: nearest to the
    /// axis's point `along` up from the tip, seen along the circle's axis).
    fn nearest(&self, tip: Vec3, tool: Vec3, along: f64) -> Vec3 {
        match &self.contour {
            Contour::Point(p) => *p,
            Contour::Line(a, b) => nearest_on_segment(*a, *b, tip, tool),
            Contour::Arc { from, to, center, axis, sweep } => {
                let height = |p: &Vec3| axis.dot(&(p - center));
                let flat = |p: Vec3| p - center - axis * height(&p);
                let start = flat(*from);
                let radius = start.norm();
                let Some(e1) = start.try_normalize(1e-12) else {
                    // A circle of radius 0: a corner's arc about its point.
                    return *center + axis * height(from);
                };
                let e2 = axis.cross(&e1);
                let d = flat(tip + tool * along);
                let angle = (sweep.signum() * d.dot(&e2)).atan2(d.dot(&e1)).rem_euclid(TAU);
                let share = angle / sweep.abs();
                if share > 1.0 {
                    // Beyond the arc: the nearer of its ends.
                    let out = angle - sweep.abs();
                    return if out < TAU - angle { *to } else { *from };
                }
                let turned = angle * sweep.signum();
                let rise = height(from) + (height(to) - height(from)) * share;
                center + (e1 * turned.cos() + e2 * turned.sin()) * radius + axis * rise
            }
        }
    }
}

/// The point of the segment `a`–`b` nearest to the line through `p` along `dir` (unit).
fn nearest_on_segment(a: Vec3, b: Vec3, p: Vec3, dir: Vec3) -> Vec3 {
    let ab = b - a;
    // Seen along the line, the segment's point nearest to it.
    let flat = ab - dir * dir.dot(&ab);
    let len2 = flat.norm_squared();
    if len2 <= 1e-24 {
        // The segment runs along the line: every point is as near; its nearest to `p`.
        let len2 = ab.norm_squared();
        let t = if len2 > 0.0 { (ab.dot(&(p - a)) / len2).clamp(0.0, 1.0) } else { 0.0 };
        return a + ab * t;
    }
    let ap = p - a;
    let t = (flat.dot(&(ap - dir * dir.dot(&ap))) / len2).clamp(0.0, 1.0);
    a + ab * t
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    const SIDE: Touch = Touch::Side { along: 0.0 };

    /// The leading edge offset: the end's edge toward the move, across a tilted tool, wherever
    /// the tool stands.
    #[test]
    fn the_leading_edge_is_toward_the_move() {
        let tool = Vec3::new(0.5, 0.0, 0.75_f64.sqrt());
        let c = Contact::new(Contour::Line(Vec3::zeros(), Vec3::new(100.0, 0.0, 0.0)), 6.0, Touch::LeadingEdge);
        let tip = Vec3::new(-5.0, 1.0, 3.0);
        let across = Vec3::new(0.75, 0.0, -0.75_f64.sqrt() * 0.5).normalize();
        assert!((c.point(tip, tool) - (tip + across * 6.0)).norm() < 1e-12);
    }

    /// A corner's arc about its point: the tool (radius 5 about a tip on the arc) touches the
    /// corner all the way.
    #[test]
    fn a_corner_keeps_the_tool_on_its_point() {
        let corner = Vec3::new(10.0, 0.0, 0.0);
        let c = Contact::new(Contour::Point(corner), 5.0, SIDE);
        for k in 0..=8 {
            let angle = -FRAC_PI_2 + FRAC_PI_2 * k as f64 / 8.0;
            let tip = corner + Vec3::new(angle.cos(), angle.sin(), 0.0) * 5.0;
            assert!((c.point(tip, Vec3::z()) - corner).norm() < 1e-12, "angle {angle}");
        }
    }

    /// A line and a tool tilted out of its plane, its tip at the radius from the line at
    /// the height `h` below: the contact is on the line, up the tool.
    #[test]
    fn a_tilted_tool_touches_a_line_up_its_side() {
        let tool = Vec3::new(0.0, -1.0, 1.0).normalize();
        let (a, b) = (Vec3::new(0.0, 0.0, 0.0), Vec3::new(100.0, 0.0, 0.0));
        // The side of the tool: perpendicular to both the line and the tool.
        let side = Vec3::x().cross(&tool).normalize();
        let h = 2.0;
        let tip = Vec3::new(30.0, 0.0, 0.0) + side * 6.0 - tool * h;
        let c = Contact::new(Contour::Line(a, b), 6.0, SIDE);
        assert!((c.point(tip, tool) - Vec3::new(30.0, 0.0, 0.0)).norm() < 1e-12);
        // Past the line's end: the tool's side faces the end, at the end's height.
        let beyond = tip + Vec3::x() * 80.0;
        let perp = |v: Vec3| v - tool * tool.dot(&v);
        let (p, e) = (c.point(beyond, tool) - beyond, b - beyond);
        assert!((perp(p) - perp(e).normalize() * 6.0).norm() < 1e-12);
        assert!((p.dot(&tool) - e.dot(&tool)).abs() < 1e-12);
    }

    /// A tool inside an arc of radius 20 at radius 15 (a radius-5 tool on the inside of a
    /// counter-clockwise half circle): the contact is on the arc, radially out; beyond the arc's
    /// end, the end.
    #[test]
    fn an_arc_is_touched_radially_and_ends_at_its_ends() {
        let center = Vec3::new(1.0, 2.0, 0.0);
        let (from, to) = (center + Vec3::new(20.0, 0.0, 0.0), center + Vec3::new(-20.0, 0.0, 3.0));
        let c = Contact::new(Contour::Arc { from, to, center, axis: Vec3::z(), sweep: PI }, 5.0, SIDE);
        let angle = 1.0_f64;
        let tip = center + Vec3::new(angle.cos(), angle.sin(), 0.0) * 15.0 + Vec3::z() * (3.0 * angle / PI);
        let expect = center + Vec3::new(angle.cos(), angle.sin(), 0.0) * 20.0 + Vec3::z() * (3.0 * angle / PI);
        assert!((c.point(tip, Vec3::z()) - expect).norm() < 1e-12);
        // Below the start (angle −0.3): the start is nearer than the end.
        let below = center + Vec3::new((-0.3f64).cos(), (-0.3f64).sin(), 0.0) * 15.0;
        let p = c.point(below, Vec3::z());
        assert!(((p - below).normalize() - (from - below).normalize()).norm() < 1e-12);
        // Clockwise, the same half circle the other way round reads the lower half.
        let cw = Contact::new(Contour::Arc { from, to, center, axis: Vec3::z(), sweep: -PI }, 5.0, SIDE);
        let lower = center + Vec3::new((-1.0f64).cos(), (-1.0f64).sin(), 0.0) * 15.0;
        let expect = center + Vec3::new((-1.0f64).cos(), (-1.0f64).sin(), 0.0) * 20.0 + Vec3::z() * (3.0 / PI);
        assert!((cw.point(lower, Vec3::z()) - expect).norm() < 1e-12);
    }
}
