//! Chamfering `,C` and corner rounding `,R` between two G01 blocks (FANUC M series "optional
//! angle chamfering and corner R", Haas NGC G01 "corner rounding and chamfering";
//! `docs/dialects.md`, "Chamfering and corner R"): `G01 X… Y… ,C c` moves to the virtual
//! corner of this block and the next, cut short by `c` along each line from that corner and
//! joined by a straight line; `,R r` joins them by an arc of radius `r` tangent to both.
//!
//! The block cannot move until the next block is read: its line is held (the current point is
//! its corner, so that an incremental next block starts there), and the next block must be a
//! G01 move in the selected plane (`CornerNextBlock`, FANUC PS0051; a G00 is `CornerNotG01`,
//! PS0052; a G02/G03 — FANUC's line–arc — is not built). A line shorter than the chamfer or
//! the arc's tangent length is `CornerTooShort` (PS0055). Built: line–line corners in the
//! plane, in G90/G91, under coordinate rotation and mirror image (the corner is built on the
//! transformed lines: a rigid motion keeps the lengths, and a mirrored corner turns the other
//! way) and in cutter compensation's offset mode (the stage offsets the pieces), with the modes
//! of a plain 3-axis path; every other mode is refused as not built (`refuse_corner_modes`).
//!
//! The held line, the chamfer and the arc are motions of the first block (its line, sequence
//! number and F); the second block's line (from the chamfer's end) is the second block's.

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, CanonKind, MotionContext, MotionKind, Pos};

/// What joins the two lines.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Join {
    /// `,C`: a straight line between the points at the distance from the corner.
    Chamfer,
    /// `,R`: an arc of the radius tangent to both lines.
    Round,
}

/// Closer than this (mm) counts as the same point, and a piece this short is not emitted.
const EPS: f64 = 1e-9;

/// A G01 block with `,C`/`,R` whose move waits for the next block.
#[derive(Debug, Clone)]
pub(super) struct HeldCorner {
    join: Join,
    /// The chamfer distance or the radius, mm.
    size: f64,
    /// Where the held line starts now (its programmed start, or the end of the chamfer before
    /// it), workpiece coordinates.
    from: Pos,
    /// The line's direction in the plane (unit), from its programmed start.
    dir: [f64; 2],
    /// The virtual corner: the block's end point.
    corner: Pos,
    /// The block's line, sequence number and F.
    tag: (u32, Option<u32>, f64),
    /// The block's modal context (its G09, cutter compensation …): the pieces are emitted while
    /// the next block runs, and carry their own block's.
    context: MotionContext,
}

/// The corner between a line arriving along `d1` (unit, `avail` mm of it left before the
/// corner) and the line from `corner` to `end`, all in the plane's two coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Corner {
    /// Where the first line stops.
    pub p1: [f64; 2],
    /// Where the second line starts.
    pub p2: [f64; 2],
    /// For `,R`: the arc's center and its signed sweep (radians, positive counter-clockwise);
    /// `None` for a chamfer or where the lines go straight on (nothing to round).
    pub arc: Option<([f64; 2], f64)>,
}

/// The geometry of the corner, or the alarm: the second line has no length in the plane
/// (`CornerNextBlock`), the lines turn back on themselves, or either is shorter than the
/// chamfer or the arc's tangent length (`CornerTooShort`).
pub(crate) fn corner(
    d1: [f64; 2],
    avail: f64,
    corner: [f64; 2],
    end: [f64; 2],
    join: Join,
    size: f64,
) -> Result<Corner, AlarmId> {
    let v2 = [end[0] - corner[0], end[1] - corner[1]];
    let len2 = v2[0].hypot(v2[1]);
    if len2 < EPS {
        return Err(AlarmId::CornerNextBlock);
    }
    let d2 = [v2[0] / len2, v2[1] / len2];
    let cross = d1[0] * d2[1] - d1[1] * d2[0];
    let dot = d1[0] * d2[0] + d1[1] * d2[1];
    // The turn from the first direction to the second, 0 (straight on) to π (back).
    let turn = cross.abs().atan2(dot);
    // Lines that turn straight back have no corner to cut (**decision**: the manuals are
    // silent; the chamfer would have no length and the arc no tangent points).
    if size > 0.0 && std::f64::consts::PI - turn < 1e-9 {
        return Err(AlarmId::CornerTooShort);
    }
    let t = match join {
        Join::Chamfer => size,
        Join::Round => size * (turn / 2.0).tan(),
    };
    if t > avail + EPS || t > len2 + EPS {
        return Err(AlarmId::CornerTooShort);
    }
    let p1 = [corner[0] - t * d1[0], corner[1] - t * d1[1]];
    let p2 = [corner[0] + t * d2[0], corner[1] + t * d2[1]];
    let arc = (join == Join::Round && t > EPS).then(|| {
        // The center is on the inside of the turn, `size` from the first line at p1.
        let left = cross > 0.0;
        let n = if left { [-d1[1], d1[0]] } else { [d1[1], -d1[0]] };
        let center = [p1[0] + size * n[0], p1[1] + size * n[1]];
        (center, if left { turn } else { -turn })
    });
    Ok(Corner { p1, p2, arc })
}

impl State {
    /// The block's `,C`/`,R` (FANUC and Haas; Syntec refuses them as addresses not built), as
    /// (join, size in mm). A block with both is `ImproperAddress` (**decision**: FANUC's
    /// PS0009 family; one of them at a time, the sources say), a negative size too.
    fn corner_words(&self, w: &Words) -> Result<Option<(Join, f64)>, AlarmId> {
        let (c, r) = (self.value(w, b'c'), self.value(w, b'r'));
        let (join, size) = match (c, r) {
            (None, None) => return Ok(None),
            (Some(_), Some(_)) => return Err(AlarmId::ImproperAddress),
            (Some(c), None) => (Join::Chamfer, c),
            (None, Some(r)) => (Join::Round, r),
        };
        if !(size.is_finite() && size >= 0.0) {
            return Err(AlarmId::ImproperAddress);
        }
        Ok(Some((join, size)))
    }

    /// Before anything of the block is done: while a corner is held the block must be a G01
    /// move in the plane; a block with `,C`/`,R` must be a G01 block in a mode the corner is
    /// built for (`refuse`).
    pub(super) fn corner_block(&mut self, w: &Words) -> Result<(), AlarmId> {
        if self.cfg.dialect == crate::Dialect::Syntec {
            return Ok(());
        }
        let words = self.corner_words(w)?;
        let motion = self.after_block(w, group::MOTION);
        if self.corner.is_some() {
            let g_ok = w
                .gcodes()
                .iter()
                .all(|&g| matches!(g, code::G00 | code::G01 | code::G02 | code::G03 | code::G90 | code::G91));
            // Axis words of any axis: one that moves off the plane is refused where the move is
            // known (`corner_motion`), one that stays where it is (Z0 at Z0) does not count.
            let letters_ok = w.mcodes().is_empty()
                && w.letters().all(|l| matches!(l, b'G' | b'F' | b'N' | b'c' | b'r') || self.axis_of(l).is_some());
            let moves = w.letters().any(|l| self.axis_of(l).is_some());
            if motion == code::G00 && moves {
                return Err(AlarmId::CornerNotG01);
            }
            if matches!(motion, code::G02 | code::G03) && moves && g_ok {
                // FANUC's line–arc corner: not built.
                return Err(AlarmId::GCodeNotBuilt);
            }
            if !(g_ok && letters_ok && moves && motion == code::G01) {
                return Err(AlarmId::CornerNextBlock);
            }
        }
        if words.is_some() {
            if motion != code::G01 {
                // On G00 nothing to chamfer; FANUC's arc–line corner (G02/G03 ,C) not built.
                return Err(AlarmId::AddressNotBuilt);
            }
            self.refuse_corner_modes(w)?;
            if !w.letters().any(|l| self.axis_of(l).is_some()) {
                // A `,C`/`,R` without a move: nothing to chamfer (**decision**: PS0055).
                return Err(AlarmId::CornerTooShort);
            }
        }
        Ok(())
    }

    /// The modes the corner is not built for, refused like a function not built: cutter
    /// compensation other than in G41/G42's offset mode, TCP or a tilted plane (the tip path), G54.4, nano smoothing, G187,
    /// scaling, inverse time feed, a modal macro call.
    fn refuse_corner_modes(&self, w: &Words) -> Result<(), AlarmId> {
        let after = |group: usize| self.after_block(w, group);
        // Under cutter compensation C the corner is built on the programmed path and its pieces
        // go to the compensation stage as any other motions (FANUC offsets the chamfered path):
        // only in offset mode, G41/G42 in force before the block and no group-07 code in it
        // (the start-up and cancel blocks, G41.x/G42.x, are not built).
        let before = self.modes[group::CUTTER_COMP];
        let comp_not_built = (before != code::G40 || after(group::CUTTER_COMP) != code::G40)
            && (self.block_code(w, group::CUTTER_COMP).is_some() || !matches!(before, code::G41 | code::G42));
        let refused = self.follows_tip()
            || code::TILTED_PLANES.contains(&after(group::ROTATION))
            || code::TCP.contains(&after(group::LENGTH_COMP))
            || after(group::DYNAMIC_FIXTURE) == code::G254
            || self.wse.is_some()
            || comp_not_built
            || self.smoothing.is_some()
            || self.blend.is_some()
            // Rotation and mirror image move the lines rigidly: the corner is built on the
            // transformed lines, lengths kept. Whether scaling scales `c`/`r` no source says.
            || self.xf.scaling()
            || after(group::FEED_MODE) == code::G93
            || !self.modal_calls.is_empty()
            || self.rotary_word(w);
        if refused {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// Whether the G01 block being executed takes part in a corner (holds one or ends one).
    pub(super) fn corner_motion_block(&self, w: &Words) -> bool {
        self.cfg.dialect != crate::Dialect::Syntec && (self.corner.is_some() || w.has(b'c') || w.has(b'r'))
    }

    /// The G01 move of a block that ends a held corner, holds one, or both.
    pub(super) fn corner_motion(&mut self, w: &Words, programmed: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        self.check_feed()?;
        let target = self.xf.forward(&programmed);
        let (a, b, c) = self.plane_axes()?;
        let off_plane = |p: &Pos, q: &Pos| (0..p.len()).any(|i| i != a && i != b && (p[i] - q[i]).abs() > EPS);
        // The block's programmed line starts at the current point: the corner held before it,
        // if any (the chamfer below moves the tool on to `start`).
        let line_start = self.pos;
        let mut start = self.pos;
        if let Some(held) = self.corner.take() {
            if off_plane(&held.corner, &target) {
                return Err(AlarmId::CornerNextBlock);
            }
            let avail = (held.corner[a] - held.from[a]).hypot(held.corner[b] - held.from[b]);
            let k = corner(
                held.dir,
                avail,
                [held.corner[a], held.corner[b]],
                [target[a], target[b]],
                held.join,
                held.size,
            )?;
            let at = |q: [f64; 2]| {
                let mut p = held.corner;
                (p[a], p[b]) = (q[0], q[1]);
                p
            };
            let (p1, p2) = (at(k.p1), at(k.p2));
            let first = out.len();
            let here = (self.line, self.n, self.f);
            (self.line, self.n, self.f) = held.tag;
            self.pos = held.from;
            if (p1[a] - held.from[a]).hypot(p1[b] - held.from[b]) > EPS {
                self.push_motion(MotionKind::Linear, p1, None, out);
            }
            match k.arc {
                Some((center, sweep)) => {
                    let kind = if sweep > 0.0 { MotionKind::ArcCcw } else { MotionKind::ArcCw };
                    let arc = Arc {
                        center: at(center),
                        plane_axes: (a, b, c),
                        radius: held.size,
                        sweep_deg: sweep.to_degrees(),
                    };
                    self.push_motion(kind, p2, Some(Box::new(arc)), out);
                }
                None if (p2[a] - p1[a]).hypot(p2[b] - p1[b]) > EPS => {
                    self.push_motion(MotionKind::Linear, p2, None, out)
                }
                None => {}
            }
            (self.line, self.n, self.f) = here;
            for c in &mut out[first..] {
                if let CanonKind::Motion(m) = &mut c.kind {
                    m.context = held.context;
                }
            }
            self.pos = p2;
            start = p2;
        }
        match self.corner_words(w)? {
            Some((join, size)) => {
                let from = line_start;
                if off_plane(&from, &target) {
                    return Err(AlarmId::GCodeNotBuilt);
                }
                let len = (target[a] - from[a]).hypot(target[b] - from[b]);
                if len < EPS {
                    return Err(AlarmId::CornerTooShort);
                }
                let dir = [(target[a] - from[a]) / len, (target[b] - from[b]) / len];
                self.corner = Some(Box::new(HeldCorner {
                    join,
                    size,
                    from: start,
                    dir,
                    corner: target,
                    tag: (self.line, self.n, self.f),
                    context: self.context(),
                }));
                // The next block starts at the corner (incremental words count from it).
                self.pos = target;
            }
            None => {
                if (target[a] - start[a]).hypot(target[b] - start[b]) > EPS || off_plane(&start, &target) {
                    self.push_motion(MotionKind::Linear, target, None, out);
                }
                self.pos = target;
            }
        }
        self.xf.programmed = programmed;
        Ok(())
    }

    /// The end of the text, M02/M30 or a reset with a corner held: the next move never comes.
    pub(super) fn corner_end(&mut self) -> Result<(), AlarmId> {
        if self.corner.take().is_some() {
            return Err(AlarmId::CornerNextBlock);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
        (p[0] - q[0]).hypot(p[1] - q[1])
    }

    #[test]
    fn mitsubishi_example() {
        // G91 G01 X100. ,C10. ; X100. Y100. (from X0 Y0): the chamfer from (90, 0) to
        // (100 + 10/√2, 10/√2).
        let k = corner([1.0, 0.0], 100.0, [100.0, 0.0], [200.0, 100.0], Join::Chamfer, 10.0).unwrap();
        let h = 10.0 / 2f64.sqrt();
        assert!(dist(k.p1, [90.0, 0.0]) < 1e-12);
        assert!(dist(k.p2, [100.0 + h, h]) < 1e-12);
        assert_eq!(k.arc, None);
    }

    #[test]
    fn right_angle_round() {
        // X0 Y0 → X20 Y0 ,R5 → X20 Y20: tangent points (15, 0) and (20, 5), center (15, 5), +90°.
        let k = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, 20.0], Join::Round, 5.0).unwrap();
        assert!(dist(k.p1, [15.0, 0.0]) < 1e-12 && dist(k.p2, [20.0, 5.0]) < 1e-12);
        let (c, sweep) = k.arc.unwrap();
        assert!(dist(c, [15.0, 5.0]) < 1e-12);
        assert!((sweep - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Turning right: clockwise, the center below.
        let k = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, -20.0], Join::Round, 5.0).unwrap();
        let (c, sweep) = k.arc.unwrap();
        assert!(dist(c, [15.0, -5.0]) < 1e-12 && sweep < 0.0);
    }

    #[test]
    fn alarms() {
        let too_short = corner([1.0, 0.0], 2.0, [2.0, 0.0], [2.0, 20.0], Join::Chamfer, 3.0);
        assert_eq!(too_short, Err(AlarmId::CornerTooShort));
        let second_short = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, 2.0], Join::Round, 3.0);
        assert_eq!(second_short, Err(AlarmId::CornerTooShort));
        let back = corner([1.0, 0.0], 20.0, [20.0, 0.0], [10.0, 0.0], Join::Chamfer, 1.0);
        assert_eq!(back, Err(AlarmId::CornerTooShort));
        let no_move = corner([1.0, 0.0], 20.0, [20.0, 0.0], [20.0, 0.0], Join::Chamfer, 1.0);
        assert_eq!(no_move, Err(AlarmId::CornerNextBlock));
        // Exactly the length of the line: allowed (the line is used up).
        assert!(corner([1.0, 0.0], 3.0, [3.0, 0.0], [3.0, 3.0], Join::Chamfer, 3.0).is_ok());
    }

    proptest! {
        /// Random line–line corners: the chamfer's ends lie on the lines at `c` from the
        /// corner; the arc has radius `r`, is tangent to both lines at its ends, and turns by
        /// the angle between them; the pieces join (p1 on the first line, p2 on the second).
        #[test]
        fn corners_are_exact(
            sx in -100.0..100.0f64, sy in -100.0..100.0f64,
            cx in -100.0..100.0f64, cy in -100.0..100.0f64,
            ex in -100.0..100.0f64, ey in -100.0..100.0f64,
            size in 0.0..30.0f64, round in any::<bool>(),
        ) {
            let len1 = (cx - sx).hypot(cy - sy);
            let len2 = (ex - cx).hypot(ey - cy);
            prop_assume!(len1 > 1e-3 && len2 > 1e-3);
            let d1 = [(cx - sx) / len1, (cy - sy) / len1];
            let d2 = [(ex - cx) / len2, (ey - cy) / len2];
            let join = if round { Join::Round } else { Join::Chamfer };
            let turn = (d1[0] * d2[1] - d1[1] * d2[0]).abs().atan2(d1[0] * d2[0] + d1[1] * d2[1]);
            prop_assume!(std::f64::consts::PI - turn > 1e-6);
            let t = if round { size * (turn / 2.0).tan() } else { size };
            let got = corner(d1, len1, [cx, cy], [ex, ey], join, size);
            if t > len1 + 1e-6 || t > len2 + 1e-6 {
                prop_assert_eq!(got, Err(AlarmId::CornerTooShort));
                return Ok(());
            }
            prop_assume!(t < len1 - 1e-6 && t < len2 - 1e-6);
            let k = got.unwrap();
            let tol = 1e-9 * (1.0 + t);
            // p1 on the first line, t before the corner; p2 on the second, t after it.
            prop_assert!(dist(k.p1, [cx, cy]) - t < tol && t - dist(k.p1, [cx, cy]) < tol);
            prop_assert!((dist([sx, sy], k.p1) + dist(k.p1, [cx, cy]) - len1).abs() < tol);
            prop_assert!((dist([cx, cy], k.p2) + dist(k.p2, [ex, ey]) - len2).abs() < tol);
            prop_assert!((dist(k.p2, [cx, cy]) - t).abs() < tol);
            if round && t > 1e-9 {
                let (c, sweep) = k.arc.expect("a turn is rounded");
                prop_assert!((dist(c, k.p1) - size).abs() < tol * 10.0);
                prop_assert!((dist(c, k.p2) - size).abs() < tol * 10.0);
                // Tangent: the radius at each end is perpendicular to its line.
                let r1 = [k.p1[0] - c[0], k.p1[1] - c[1]];
                let r2 = [k.p2[0] - c[0], k.p2[1] - c[1]];
                prop_assert!((r1[0] * d1[0] + r1[1] * d1[1]).abs() < 1e-7 * (1.0 + size));
                prop_assert!((r2[0] * d2[0] + r2[1] * d2[1]).abs() < 1e-7 * (1.0 + size));
                // Sweeping p1 about c by `sweep` lands on p2, and the arc leaves along d1.
                let (s, co) = sweep.sin_cos();
                let rot = [c[0] + r1[0] * co - r1[1] * s, c[1] + r1[0] * s + r1[1] * co];
                prop_assert!(dist(rot, k.p2) < 1e-7 * (1.0 + size));
                prop_assert!((sweep.abs() - turn).abs() < 1e-9);
                let tangent = if sweep > 0.0 { [-r1[1], r1[0]] } else { [r1[1], -r1[0]] };
                prop_assert!(tangent[0] * d1[0] + tangent[1] * d1[1] > 0.0);
            } else {
                prop_assert!(k.arc.is_none());
            }
        }
    }
}
