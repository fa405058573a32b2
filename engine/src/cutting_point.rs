//! Cutting point control (FANUC G43.8/G43.9, 30i-A5 manual §2.1.2, §2.2.4/2.2.5,
//! §2.3.20/2.3.21): the program gives the point where the tool touches the surface (the
//! cutting point) and the surface's normal there (`,L2 I J K`); the tool tip, which tool centre
//! point control then moves, is the cutting point plus a vector that depends on the tool shape,
//! the tool direction and the normal. The geometry here is shared by the interpreter (a block's
//! end) and `motion::path` (every point along the block), so both put the tool alike.
//!
//! The vector (`docs/five-axis.md`, "Cutting point control"): the corner's centre lies `r`
//! along the normal from the cutting point, the tool axis `R − r` from it across the tool
//! towards the normal's side, and the tip `r` below the corner centre along the tool —
//! `r·n + (R − r)·ŵ − r·v`, ŵ the unit part of n across the tool. The manual's three vectors
//! (corner R, tool radius, tool length) with the length to the tip, as the tool length offset
//! of G43.4 has it. With n along the tool (ŵ undefined) the flat end touches the surface at the
//! cutting point (ŵ = 0).
//!
//! Near that singular posture (No.11262 > 0, a square or bull-nose end mill) the vector is held
//! at its value where the posture came within the angle (§2.3.21); when the posture leaves it
//! again within a block, the difference fades out linearly by the block's end, so the tool comes
//! back onto the cutting point without a jump (the manual does not say how it comes back: a
//! decision).

use crate::kin::Vec3;

/// The tool as cutting point control reads it from the offsets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tool {
    /// R: the tool radius (D, geometry + wear), mm.
    pub radius: f64,
    /// r: the corner radius, mm (0 ≤ r ≤ R: r = R a ball end mill, 0 a square end mill).
    pub corner: f64,
}

impl Tool {
    /// Tool tip minus cutting point, for the tool direction `tool` (tip → holder) and the
    /// surface normal `normal` (out of the material), both unit.
    pub fn vector(&self, tool: Vec3, normal: Vec3) -> Vec3 {
        let flat = self.radius - self.corner;
        let across = normal - tool * normal.dot(&tool);
        let w = if flat > 0.0 { across.try_normalize(1e-12).unwrap_or_else(Vec3::zeros) } else { Vec3::zeros() };
        normal * self.corner + w * flat - tool * self.corner
    }

    /// Whether the tool has a singular posture (a flat part at its end).
    fn flat(&self) -> bool {
        self.radius > self.corner
    }
}

/// The surface normal `u` of the way from `a` to `b` (unit): on the great circle between them.
pub fn normal_at(a: Vec3, b: Vec3, u: f64) -> Vec3 {
    let angle = a.angle(&b);
    if angle < 1e-12 {
        return a;
    }
    let s = angle.sin();
    if s < 1e-12 {
        // Opposite normals: no great circle (the interpreter refuses such a block).
        return if u < 0.5 { a } else { b };
    }
    (a * ((1.0 - u) * angle).sin() + b * (u * angle).sin()) / s
}

/// What one block's tool vector does between two points of it.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Stretch {
    /// Near the singular posture: the vector held.
    Held(Vec3),
    /// The tool's own vector plus `fade · (1 − u) / (1 − from)` (zero when it never was held).
    Free { fade: Vec3, from: f64 },
}

/// The vector tip − cutting point all along one block (table frame).
#[derive(Debug, Clone, PartialEq)]
pub struct Along {
    tool: Tool,
    normals: (Vec3, Vec3),
    /// From which `u` each stretch holds, in order; the first from 0.
    stretches: Vec<(f64, Stretch)>,
}

/// Points per block where the singular posture is looked for (then refined by bisection).
const PROBES: usize = 64;

/// Closer than this (radians) to the surface normal's line the tool is in the singular posture.
const SINGULAR: f64 = 1e-7;

/// Points per block where a tool with nothing to hold its vector is looked at for the singular
/// posture: fewer than `PROBES`, as the bound between them (`touches_singular`) tells where to
/// look closer.
const SINGULAR_PROBES: usize = 16;

impl Along {
    /// The block's vector: `tool_at(u)` the tool direction `u` of the way (table frame, unit),
    /// `normals` the surface normal at its start and end, `limit_deg` No.11262, `start` the
    /// vector in use where the block starts.
    pub fn new(tool: Tool, normals: (Vec3, Vec3), limit_deg: f64, start: Vec3, tool_at: impl Fn(f64) -> Vec3) -> Along {
        let mut along = Along { tool, normals, stretches: Vec::new() };
        if limit_deg <= 0.0 || !tool.flat() {
            along.stretches.push((0.0, Stretch::Free { fade: Vec3::zeros(), from: 0.0 }));
            return along;
        }
        let limit = limit_deg.to_radians();
        let near = |u: f64| tool_at(u).angle(&normal_at(normals.0, normals.1, u)) < limit;
        let first = if near(0.0) { Stretch::Held(start) } else { Stretch::Free { fade: Vec3::zeros(), from: 0.0 } };
        along.stretches.push((0.0, first));
        let mut inside = near(0.0);
        let mut lo = 0.0;
        for k in 1..=PROBES {
            let hi = k as f64 / PROBES as f64;
            if near(hi) == inside {
                lo = hi;
                continue;
            }
            // The crossing between lo and hi.
            let (mut a, mut b) = (lo, hi);
            for _ in 0..50 {
                let m = 0.5 * (a + b);
                if near(m) == inside {
                    a = m;
                } else {
                    b = m;
                }
            }
            let at = b;
            let own = tool.vector(tool_at(at), normal_at(normals.0, normals.1, at));
            let stretch = if inside {
                // Leaving: fade from the held vector to the tool's own by the block's end.
                Stretch::Free { fade: along.vector(at, own) - own, from: at }
            } else {
                Stretch::Held(along.vector(at, own))
            };
            along.stretches.push((at, stretch));
            inside = !inside;
            lo = hi;
        }
        along
    }

    /// The surface normal `u` of the way.
    pub fn normal(&self, u: f64) -> Vec3 {
        normal_at(self.normals.0, self.normals.1, u)
    }

    /// Whether the vector is the tool's own at `u` (then [`Along::vector`] needs the tool
    /// direction there).
    pub fn held(&self, u: f64) -> Option<Vec3> {
        match self.stretch(u) {
            Stretch::Held(v) => Some(v),
            Stretch::Free { .. } => None,
        }
    }

    /// The vector `u` of the way, `own` the tool's own vector there
    /// (`Tool::vector(tool, self.normal(u))`).
    pub fn vector(&self, u: f64, own: Vec3) -> Vec3 {
        match self.stretch(u) {
            Stretch::Held(v) => v,
            Stretch::Free { fade, from } if from < 1.0 => own + fade * ((1.0 - u) / (1.0 - from)).clamp(0.0, 1.0),
            Stretch::Free { .. } => own,
        }
    }

    /// Where a tool with its tip at `tip` and direction `tool` touches the surface `u` of the
    /// way: its lowest point along the normal there (the programmed cutting point unless a held
    /// vector lets it drift).
    pub fn contact(&self, u: f64, tip: Vec3, tool: Vec3) -> Vec3 {
        tip - self.tool.vector(tool, self.normal(u))
    }

    /// The vector `u` of the way for the tool direction `tool` there.
    pub fn vector_for(&self, u: f64, tool: Vec3) -> Vec3 {
        match self.held(u) {
            Some(v) => v,
            None => self.vector(u, self.tool.vector(tool, self.normal(u))),
        }
    }

    fn stretch(&self, u: f64) -> Stretch {
        self.stretches.iter().rev().find(|(from, _)| *from <= u).map_or(self.stretches[0].1, |s| s.1)
    }
}

/// Whether a block takes a tool with a flat end into or out of its singular posture with nothing
/// to hold the vector (No.11262 = 0): its vector would turn at once there (the tip would jump by
/// up to 2(R − r)), so the tool cannot follow and the interpreter refuses the block. A tool that
/// stays in the posture all along is not such a block. Arguments as [`Along::new`]'s.
pub fn through_singular(tool: Tool, normals: (Vec3, Vec3), limit_deg: f64, tool_at: impl Fn(f64) -> Vec3) -> bool {
    limit_deg <= 0.0 && tool.flat() && touches_singular(normals, &tool_at)
}

/// Whether the tool comes within `SINGULAR` of the normal's line somewhere in the block but not
/// all along it.
fn touches_singular(normals: (Vec3, Vec3), tool_at: &impl Fn(f64) -> Vec3) -> bool {
    let off = |v: Vec3, n: Vec3| {
        let a = v.angle(&n);
        a.min(std::f64::consts::PI - a)
    };
    let at = |u: f64| (tool_at(u), normal_at(normals.0, normals.1, u));
    let points: Vec<(Vec3, Vec3)> = (0..=SINGULAR_PROBES).map(|k| at(k as f64 / SINGULAR_PROBES as f64)).collect();
    let probes: Vec<f64> = points.iter().map(|&(v, n)| off(v, n)).collect();
    if probes.iter().all(|&a| a < SINGULAR) {
        return false;
    }
    // Between two probes the angle falls by no more than the tool and the normal turn there
    // (taken twice: the tool's way between probes need not be a great circle): only a stretch
    // that may come near is looked at closer (usually none: one pass over the block).
    let reach = |i: usize| 2.0 * (points[i].0.angle(&points[i + 1].0) + points[i].1.angle(&points[i + 1].1));
    // Each stretch that may come near: a golden-section search for its closest point.
    let step = 1.0 / SINGULAR_PROBES as f64;
    let angle = |u: f64| {
        let (v, n) = at(u);
        off(v, n)
    };
    (0..SINGULAR_PROBES).filter(|&i| probes[i].min(probes[i + 1]) - reach(i) <= SINGULAR).any(|i| {
        let closest = crate::golden::least(angle, i as f64 * step, (i + 1) as f64 * step, 60);
        probes[i].min(probes[i + 1]).min(closest) < SINGULAR
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(x: f64, y: f64, z: f64) -> Vec3 {
        Vec3::new(x, y, z).normalize()
    }

    /// The tool touches the cutting point from the normal's side: no point of the tool (its
    /// corner torus, whose rim is also the flat end's) lies below the plane through the cutting
    /// point across the normal, and the corner point that touches it is the cutting point.
    #[test]
    fn the_tool_touches_the_cutting_point_and_stays_above_the_surface() {
        let (v, n) = (unit(0.3, -0.2, 1.0), unit(-0.6, 0.1, 0.5));
        let e1 = v.cross(&Vec3::x()).normalize();
        let e2 = v.cross(&e1);
        for (radius, corner) in [(5.0, 5.0), (5.0, 0.0), (6.0, 2.0)] {
            let tip = Tool { radius, corner }.vector(v, n);
            let mut lowest = f64::INFINITY;
            for i in 0..720 {
                let phi = (i as f64 / 2.0).to_radians();
                let out = e1 * phi.cos() + e2 * phi.sin();
                let centre = tip + v * corner + out * (radius - corner);
                for k in 0..=90 {
                    let psi = (k as f64).to_radians();
                    let p = centre + (out * psi.cos() - v * psi.sin()) * corner;
                    lowest = lowest.min(p.dot(&n));
                }
            }
            assert!((-1e-9..1e-3).contains(&lowest), "{radius} {corner}: {lowest}");
            // The corner centre below which the tool touches: r along n from the cutting point.
            let w = (n - v * n.dot(&v)).normalize();
            let touching = tip + v * corner - w * (radius - corner) - n * corner;
            assert!(touching.norm() < 1e-12, "{radius} {corner}");
        }
    }

    /// A ball end mill: its centre is r along the normal from the cutting point, the tip r below
    /// it — the familiar ball-nose offset. A square end mill on a wall (normal across the tool):
    /// the axis R away, the tip level with the cutting point.
    #[test]
    fn ball_and_square_end_mills() {
        let v = Vec3::z();
        let ball = Tool { radius: 5.0, corner: 5.0 };
        assert!((ball.vector(v, Vec3::x()) - Vec3::new(5.0, 0.0, -5.0)).norm() < 1e-12);
        assert!(ball.vector(v, Vec3::z()).norm() < 1e-12);
        let square = Tool { radius: 5.0, corner: 0.0 };
        assert!((square.vector(v, Vec3::x()) - Vec3::new(5.0, 0.0, 0.0)).norm() < 1e-12);
        // Along the tool: the flat end on the cutting point.
        assert!(square.vector(v, Vec3::z()).norm() < 1e-12);
    }

    #[test]
    fn normals_turn_on_the_great_circle() {
        let (a, b) = (Vec3::x(), Vec3::y());
        let m = normal_at(a, b, 0.5);
        assert!((m - unit(1.0, 1.0, 0.0)).norm() < 1e-12);
        assert_eq!(normal_at(a, a, 0.3), a);
    }

    /// No.11262: the tool turns through the surface normal; inside the angle the vector stays
    /// where it entered, and after leaving it fades back so that the block ends on the tool's own
    /// vector; without the parameter, always the tool's own.
    #[test]
    fn near_the_singular_posture_the_vector_is_held_then_fades_back() {
        let tool = Tool { radius: 5.0, corner: 1.0 };
        let n = Vec3::z();
        // The tool swings in the XZ plane from −20° to +20° about the normal.
        let tool_at = |u: f64| {
            let a = (-20.0 + 40.0 * u).to_radians();
            Vec3::new(a.sin(), 0.0, a.cos())
        };
        let own = |u: f64| tool.vector(tool_at(u), n);
        let start = own(0.0);
        let free = Along::new(tool, (n, n), 0.0, start, tool_at);
        for u in [0.0, 0.3, 0.5, 0.9] {
            assert_eq!(free.vector_for(u, tool_at(u)), own(u));
        }
        let along = Along::new(tool, (n, n), 5.0, start, tool_at);
        // It enters at u = 15/40 and leaves at 25/40.
        let (enter, leave) = (15.0 / 40.0, 25.0 / 40.0);
        let held = along.vector_for(0.5, tool_at(0.5));
        assert!((held - own(enter)).norm() < 1e-9, "{held} {}", own(enter));
        assert_eq!(along.vector_for(0.45, tool_at(0.45)), held);
        assert_eq!(along.vector_for(0.2, tool_at(0.2)), own(0.2));
        // Continuous where it leaves, and on the tool's own vector at the end.
        let just = along.vector_for(leave + 1e-9, tool_at(leave + 1e-9));
        assert!((just - held).norm() < 1e-6, "{just} {held}");
        assert!((along.vector_for(1.0, tool_at(1.0)) - own(1.0)).norm() < 1e-12);
        // A block that starts inside keeps the vector it starts with.
        let inside = |u: f64| {
            let a = (2.0 * u).to_radians();
            Vec3::new(a.sin(), 0.0, a.cos())
        };
        let kept = Vec3::new(1.0, 2.0, 3.0);
        let along = Along::new(tool, (n, n), 5.0, kept, inside);
        assert_eq!(along.vector_for(0.7, inside(0.7)), kept);
    }
}
