//! The plane geometry of cutter compensation C: a programmed block as a line or a circle in the
//! compensation plane, its offset curve at a signed distance, and where two offset curves meet.
//!
//! Coordinates are the plane's first and second axis (G17: X, Y; G18: Z, X; G19: Y, Z), so
//! that "left" is always the left of the travel direction seen from the plane's normal. A
//! signed offset `r` puts the tool on the left for `r > 0` (G41 with a positive radius).

/// Offset curves that miss each other by less than this touch (mm): programs round their
/// points (to 1 µm), so a tangent transition is rarely exactly tangent.
const TOUCH: f64 = 1e-3;

/// A point or a direction in the plane.
pub type P2 = [f64; 2];

pub fn add(a: P2, b: P2) -> P2 {
    [a[0] + b[0], a[1] + b[1]]
}
pub fn sub(a: P2, b: P2) -> P2 {
    [a[0] - b[0], a[1] - b[1]]
}
pub fn scale(a: P2, k: f64) -> P2 {
    [a[0] * k, a[1] * k]
}
pub fn dot(a: P2, b: P2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
/// z of the cross product: positive when `b` turns left of `a`.
pub fn cross(a: P2, b: P2) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
pub fn norm(a: P2) -> f64 {
    a[0].hypot(a[1])
}
pub fn unit(a: P2) -> P2 {
    let n = norm(a);
    if n > 0.0 {
        scale(a, 1.0 / n)
    } else {
        [0.0, 0.0]
    }
}
/// The left normal of a direction.
pub fn left(t: P2) -> P2 {
    [-t[1], t[0]]
}

/// A programmed block in the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Curve {
    Line {
        from: P2,
        to: P2,
    },
    /// A circle (or a spiral, when the end is not at the start's distance from the centre):
    /// `sweep` in radians, positive counter-clockwise.
    Arc {
        from: P2,
        to: P2,
        center: P2,
        sweep: f64,
    },
}

impl Curve {
    pub fn from(&self) -> P2 {
        match *self {
            Curve::Line { from, .. } | Curve::Arc { from, .. } => from,
        }
    }
    pub fn to(&self) -> P2 {
        match *self {
            Curve::Line { to, .. } | Curve::Arc { to, .. } => to,
        }
    }

    /// Unit travel direction at the start (`end` false) or the end.
    pub fn tangent(&self, end: bool) -> P2 {
        match *self {
            Curve::Line { from, to } => unit(sub(to, from)),
            Curve::Arc { from, to, center, sweep } => {
                let radial = unit(sub(if end { to } else { from }, center));
                // Counter-clockwise travel is the radial direction turned left.
                if sweep >= 0.0 {
                    left(radial)
                } else {
                    scale(left(radial), -1.0)
                }
            }
        }
    }

    /// The offset point at the start or the end: the programmed point moved by `r` to the left
    /// of the travel direction.
    pub fn offset_point(&self, end: bool, r: f64) -> P2 {
        let p = if end { self.to() } else { self.from() };
        add(p, scale(left(self.tangent(end)), r))
    }

    /// The offset curve, as the set of points a corner point is looked for on.
    fn offset(&self, r: f64) -> Offset {
        match *self {
            Curve::Line { from, to } => {
                let t = unit(sub(to, from));
                Offset::Line { point: add(from, scale(left(t), r)), dir: t }
            }
            Curve::Arc { to, center, sweep, .. } => {
                // Left of counter-clockwise travel is toward the centre.
                let rho = norm(sub(to, center));
                let radius = if sweep >= 0.0 { rho - r } else { rho + r };
                Offset::Circle { center, radius }
            }
        }
    }

    /// The radius of the offset circle of an arc (at its end); `None` for a line. Zero or
    /// negative: the tool does not fit inside the arc.
    pub fn offset_radius(&self, r: f64) -> Option<f64> {
        match self.offset(r) {
            Offset::Circle { radius, .. } => Some(radius),
            Offset::Line { .. } => None,
        }
    }
}

enum Offset {
    Line { point: P2, dir: P2 },
    Circle { center: P2, radius: f64 },
}

/// Where the offset curve of `a` (at `ra`) meets that of `b` (at `rb`): of the points where
/// they cross, the one nearest the programmed corner `corner`. `None`: they do not meet
/// (parallel lines, circles apart).
pub fn intersection(a: &Curve, ra: f64, b: &Curve, rb: f64, corner: P2) -> Option<P2> {
    let candidates = crossings(&a.offset(ra), &b.offset(rb));
    candidates.into_iter().flatten().min_by(|p, q| norm(sub(*p, corner)).total_cmp(&norm(sub(*q, corner))))
}

fn crossings(a: &Offset, b: &Offset) -> [Option<P2>; 2] {
    match (a, b) {
        (Offset::Line { point: p, dir: d }, Offset::Line { point: q, dir: e }) => {
            let den = cross(*d, *e);
            if den.abs() < 1e-12 {
                return [None, None];
            }
            let s = cross(sub(*q, *p), *e) / den;
            [Some(add(*p, scale(*d, s))), None]
        }
        (Offset::Line { point, dir }, Offset::Circle { center, radius })
        | (Offset::Circle { center, radius }, Offset::Line { point, dir }) => {
            // |point + s·dir − center| = radius, dir a unit vector.
            let w = sub(*point, *center);
            let half_b = dot(w, *dir);
            let disc = half_b * half_b - (dot(w, w) - radius * radius);
            if disc < -2.0 * radius * TOUCH || *radius <= 0.0 {
                return [None, None];
            }
            let root = disc.max(0.0).sqrt();
            [Some(add(*point, scale(*dir, -half_b - root))), Some(add(*point, scale(*dir, -half_b + root)))]
        }
        (Offset::Circle { center: c1, radius: r1 }, Offset::Circle { center: c2, radius: r2 }) => {
            let d = sub(*c2, *c1);
            let dist = norm(d);
            if dist < 1e-12 || *r1 <= 0.0 || *r2 <= 0.0 || dist > r1 + r2 + TOUCH || dist < (r1 - r2).abs() - TOUCH {
                return [None, None];
            }
            let along = (dist * dist + r1 * r1 - r2 * r2) / (2.0 * dist);
            let h = (r1 * r1 - along * along).max(0.0).sqrt();
            let u = scale(d, 1.0 / dist);
            let base = add(*c1, scale(u, along));
            [Some(add(base, scale(left(u), h))), Some(sub(base, scale(left(u), h)))]
        }
    }
}

/// The length of a path piece (an arc whose radius changes along it: approximately).
pub fn length(c: &Curve) -> f64 {
    match *c {
        Curve::Line { from, to } => norm(sub(to, from)),
        Curve::Arc { from, to, center, sweep } => {
            0.5 * (norm(sub(from, center)) + norm(sub(to, center))) * sweep.abs() + norm(sub(to, from))
        }
    }
}

/// The point at the fraction `t` (0…1) along a path piece: on an arc, the angle and the
/// radius change in proportion.
pub fn point_at(c: &Curve, t: f64) -> P2 {
    match *c {
        Curve::Line { from, to } => add(from, scale(sub(to, from), t)),
        Curve::Arc { from, to, center, sweep } => {
            let (r0, r1) = (norm(sub(from, center)), norm(sub(to, center)));
            let a0 = (from[1] - center[1]).atan2(from[0] - center[0]);
            let a = a0 + t * sweep;
            let r = r0 + t * (r1 - r0);
            add(center, [r * a.cos(), r * a.sin()])
        }
    }
}

/// How far `p` is from the programmed block `g` on the side of the tool (signed radius `r`:
/// positive on the left): beside the block (its foot within it), the distance from it, negative
/// on the other side; elsewhere, the distance from the nearer end.
pub fn clearance(g: &Curve, r: f64, p: P2) -> f64 {
    let ends = || norm(sub(p, g.from())).min(norm(sub(p, g.to())));
    match *g {
        Curve::Line { from, to } => {
            let d = sub(to, from);
            let l2 = dot(d, d);
            let t = if l2 > 0.0 { dot(sub(p, from), d) / l2 } else { -1.0 };
            if t > 0.0 && t < 1.0 {
                cross(d, sub(p, from)) / l2.sqrt() * r.signum()
            } else {
                ends()
            }
        }
        Curve::Arc { from, center, sweep, .. } => {
            let (a, b) = (sub(from, center), sub(p, center));
            let mut angle = cross(a, b).atan2(dot(a, b));
            if sweep < 0.0 {
                angle = -angle;
            }
            let angle = angle.rem_euclid(std::f64::consts::TAU);
            if norm(b) > 0.0 && angle > 0.0 && angle < sweep.abs() {
                let rho = norm(a);
                // The tool inside the circle: its offset radius is smaller.
                let inside = g.offset_radius(r).is_some_and(|o| o < rho);
                if inside {
                    rho - norm(b)
                } else {
                    norm(b) - rho
                }
            } else {
                ends()
            }
        }
    }
}

/// The angle from `from` to `to` about `center`, turning the way `sweep` does, in
/// [0, 2π) — or [0, 4π) made nearest to `sweep` for arcs of a full turn or more.
pub fn swept(from: P2, to: P2, center: P2, sweep: f64) -> f64 {
    let (a, b) = (sub(from, center), sub(to, center));
    let mut angle = cross(a, b).atan2(dot(a, b));
    if sweep < 0.0 {
        angle = -angle;
    }
    let tau = std::f64::consts::TAU;
    if angle < 0.0 {
        angle += tau;
    }
    // A start and end that coincide on an arc of a whole turn: the whole turn.
    if (angle + tau - sweep.abs()).abs() < (angle - sweep.abs()).abs() {
        angle += tau;
    }
    angle
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: P2, b: P2) -> bool {
        norm(sub(a, b)) < 1e-9
    }

    #[test]
    fn line_offsets_meet_at_the_inner_corner() {
        // +X then +Y, tool on the left (inside the turn) at 2: the corner (10,0) moves to (8,2).
        let a = Curve::Line { from: [0.0, 0.0], to: [10.0, 0.0] };
        let b = Curve::Line { from: [10.0, 0.0], to: [10.0, 10.0] };
        assert!(close(intersection(&a, 2.0, &b, 2.0, [10.0, 0.0]).unwrap(), [8.0, 2.0]));
        // On the right (outside), the offsets meet at (12,−2).
        assert!(close(intersection(&a, -2.0, &b, -2.0, [10.0, 0.0]).unwrap(), [12.0, -2.0]));
    }

    #[test]
    fn arc_offsets_shrink_toward_the_centre_on_the_left_of_counter_clockwise_travel() {
        let arc = Curve::Arc { from: [10.0, 0.0], to: [0.0, 10.0], center: [0.0, 0.0], sweep: 1.0 };
        assert_eq!(arc.offset_radius(2.0), Some(8.0));
        assert!(close(arc.offset_point(false, 2.0), [8.0, 0.0]));
        assert!(close(arc.offset_point(true, 2.0), [0.0, 8.0]));
        let cw = Curve::Arc { from: [0.0, 10.0], to: [10.0, 0.0], center: [0.0, 0.0], sweep: -1.0 };
        assert_eq!(cw.offset_radius(2.0), Some(12.0));
        assert!(close(cw.offset_point(true, 2.0), [12.0, 0.0]));
    }

    #[test]
    fn line_meets_circle_nearest_the_corner() {
        // Line along y = 8 toward a circle of radius 10 about the origin: it crosses at x = ±6.
        let line = Curve::Line { from: [-20.0, 10.0], to: [0.0, 10.0] };
        let arc = Curve::Arc { from: [0.0, 10.0], to: [10.0, 0.0], center: [0.0, 0.0], sweep: -1.0 };
        // Line offset to its right by 2 (y = 8), arc (clockwise) offset to its right: radius 8.
        let p = intersection(&line, -2.0, &arc, -2.0, [0.0, 10.0]).unwrap();
        assert!(close(p, [0.0, 8.0]), "{p:?}");
        let p = intersection(&line, 2.0, &arc, 2.0, [0.0, 10.0]).unwrap();
        // y = 12 and radius 12: tangent at (0, 12).
        assert!((p[0]).abs() < 1e-6 && (p[1] - 12.0).abs() < 1e-9, "{p:?}");
    }

    #[test]
    fn clearance_is_signed_beside_a_block_and_a_distance_past_its_ends() {
        // The line 0,0 → 10,0 with the tool on the left (r 5): 3 above it is 3 on the tool's
        // side, 3 below it −3; past its end, the distance from the end.
        let line = Curve::Line { from: [0.0, 0.0], to: [10.0, 0.0] };
        assert!((clearance(&line, 5.0, [5.0, 3.0]) - 3.0).abs() < 1e-12);
        assert!((clearance(&line, 5.0, [5.0, -3.0]) + 3.0).abs() < 1e-12);
        assert!((clearance(&line, -5.0, [5.0, -3.0]) - 3.0).abs() < 1e-12);
        assert!((clearance(&line, 5.0, [13.0, 4.0]) - 5.0).abs() < 1e-12);
        // The counter-clockwise quarter circle R10 about the origin, tool on the left (inside):
        // at 45°, radius 5 is 5 inside; radius 12 is 2 on the wrong side; past its ends, the
        // distance from the nearer end.
        let arc =
            Curve::Arc { from: [10.0, 0.0], to: [0.0, 10.0], center: [0.0, 0.0], sweep: std::f64::consts::FRAC_PI_2 };
        let at = |rho: f64, deg: f64| [rho * deg.to_radians().cos(), rho * deg.to_radians().sin()];
        assert!((clearance(&arc, 5.0, at(5.0, 45.0)) - 5.0).abs() < 1e-12);
        assert!((clearance(&arc, 5.0, at(12.0, 45.0)) + 2.0).abs() < 1e-12);
        assert!((clearance(&arc, -5.0, at(12.0, 45.0)) - 2.0).abs() < 1e-12);
        assert!((clearance(&arc, 5.0, [10.0, -3.0]) - 3.0).abs() < 1e-12);
        // Along the arc of a path piece, the points keep the radius.
        assert!((norm(point_at(&arc, 0.5)) - 10.0).abs() < 1e-12);
    }

    #[test]
    fn swept_angles_follow_the_direction() {
        let q = std::f64::consts::FRAC_PI_2;
        assert!((swept([1.0, 0.0], [0.0, 1.0], [0.0, 0.0], q) - q).abs() < 1e-12);
        assert!((swept([1.0, 0.0], [0.0, 1.0], [0.0, 0.0], -3.0 * q) - 3.0 * q).abs() < 1e-12);
        let full = std::f64::consts::TAU;
        assert!((swept([1.0, 0.0], [1.0, 0.0], [0.0, 0.0], full) - full).abs() < 1e-12);
        // Slightly past the start of a whole turn: a little more than a turn.
        assert!(swept([1.0, 0.0], [1.0, 0.01], [0.0, 0.0], full) > full);
    }
}
