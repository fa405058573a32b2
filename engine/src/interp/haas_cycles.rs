//! The Haas NGC's own cycles and motion settings (Haas dialect only; `gcode::GDef::haas_only`):
//! G12/G13 circular pocket milling, the bolt patterns G70 (circle), G71 (arc) and G72 (line at
//! an angle) around the canned cycle in force, G150 general purpose pocket milling (its outline
//! read from the subprogram P, its geometry `crate::pocket`), and G103's block look-ahead limit.
//! G47 (text engraving) stays refused (`unbuilt`); G187's corner rounding is `corner_blend`.
//! Sources, decisions and what is not built: `docs/dialects.md`, "Haas cycles".

use super::gcode::{code, group};
use super::nc::Words;
use super::program::Slot;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, MotionKind, Pos};
use crate::lang::BlockKind;
use crate::pocket::{self, Move, Refusal, Seg, P};
use std::collections::HashMap;

/// The most holes one bolt pattern block may give (the canned cycles' own output limit,
/// `cycles::MAX_COMMANDS_PER_BLOCK`, bounds what they expand into).
const MAX_HOLES: f64 = 9999.0;

/// The most pocket passes (I to K by Q) and depth loops (L) of one G12/G13 block.
const MAX_PASSES: f64 = 10_000.0;

/// The most depth passes of one G150 block (R to Z by Q).
const MAX_LEVELS: f64 = 10_000.0;

/// The most blocks a G150 outline subprogram may have before its M99 (the 1999 manual allows
/// fewer than 20 moves; the bound keeps the geometry's pairwise checks small).
const MAX_OUTLINE_BLOCKS: usize = 1_000;

/// Highest G103 P (the NGC's range, 0–15).
pub const MAX_BLOCK_LIMIT: f64 = 15.0;

/// A count address (L of G12/G13/G70–G72): a whole number from 1 to `max`; `None` if absent.
fn count(w: &Words, letter: u8, max: f64) -> Result<Option<u32>, AlarmId> {
    match w.integer(letter) {
        None => Ok(None),
        Some(v) if v.fract() == 0.0 && (1.0..=max).contains(&v) => Ok(Some(v as u32)),
        Some(_) => Err(AlarmId::CycleArgument),
    }
}

/// The tool centre's radii of a circular pocket's passes: I, I + Q, I + 2Q … up to K (the last
/// pass on K itself), each less the tool radius `tool`; I alone without K and Q. The checks are
/// the manual's: I greater than the tool radius and less than K, Q (positive) with K only.
pub fn pocket_radii(i: Option<f64>, k: Option<f64>, q: Option<f64>, tool: f64) -> Result<Vec<f64>, AlarmId> {
    let i = i.ok_or(AlarmId::CycleArgument)?;
    if tool < 0.0 || i <= tool {
        return Err(AlarmId::CycleArgument);
    }
    let Some(k) = k else {
        return if q.is_some() { Err(AlarmId::CycleArgument) } else { Ok(vec![i - tool]) };
    };
    let q = q.ok_or(AlarmId::CycleArgument)?;
    if k <= i || q <= 0.0 || (k - i) / q > MAX_PASSES {
        return Err(AlarmId::CycleArgument);
    }
    let mut radii = Vec::new();
    let mut r = i;
    // A pass within a micrometre of K is K's (no sliver pass of 0.0001 mm before it).
    while r < k - 1e-6 {
        radii.push(r - tool);
        r += q;
    }
    radii.push(k - tool);
    Ok(radii)
}

/// The centre of an arc of the XY plane from `start` to `end`: by radius `r` (negative: more
/// than a half circle) or by the centre's offset `ij` from the start; its sweep in radians
/// (positive counter-clockwise; a full turn when the ends meet). `ArcRadiusTolerance` where the
/// ends are not on one circle within `tol` (as `nc.rs` reads G02/G03).
pub fn arc_centre(start: P, end: P, r: Option<f64>, ij: P, cw: bool, tol: f64) -> Result<(P, f64), AlarmId> {
    let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
    let d = dx.hypot(dy);
    let c = match r {
        Some(r) => {
            // R cannot give a full circle.
            if d < 1e-9 || d / 2.0 - r.abs() > tol {
                return Err(AlarmId::ArcRadiusTolerance);
            }
            let h = (r * r - d * d / 4.0).max(0.0).sqrt();
            let side = if cw { -1.0 } else { 1.0 } * if r < 0.0 { -1.0 } else { 1.0 };
            [start[0] + dx / 2.0 - side * h * dy / d, start[1] + dy / 2.0 + side * h * dx / d]
        }
        None => [start[0] + ij[0], start[1] + ij[1]],
    };
    let r0 = pocket::dist(start, c);
    if (r0 - pocket::dist(end, c)).abs() > tol || r0 < 1e-9 {
        return Err(AlarmId::ArcRadiusTolerance);
    }
    let a0 = (start[1] - c[1]).atan2(start[0] - c[0]);
    let a1 = (end[1] - c[1]).atan2(end[0] - c[0]);
    let tau = std::f64::consts::TAU;
    let s = if cw { (a0 - a1).rem_euclid(tau) } else { (a1 - a0).rem_euclid(tau) };
    let s = if d < 1e-9 || s == 0.0 { tau } else { s };
    Ok((c, if cw { -s } else { s }))
}

/// The depths of a G150's passes: from R down by Q, the last at Z.
pub fn pocket_levels(r: f64, z: f64, q: f64) -> Result<Vec<f64>, AlarmId> {
    if q.is_nan() || q <= 0.0 || z >= r || (r - z) / q > MAX_LEVELS {
        return Err(AlarmId::CycleArgument);
    }
    let mut levels = Vec::new();
    let mut at = r - q;
    // A pass within a micrometre of Z is Z's.
    while at > z + 1e-6 {
        levels.push(at);
        at -= q;
    }
    levels.push(z);
    Ok(levels)
}

/// The angles (degrees, CCW from the plane's first axis) of a bolt pattern's holes: G70 `l`
/// holes evenly around the circle from `j` (clockwise when I is negative), G71 `l` holes from
/// `j` every `k` degrees.
pub fn bolt_angles(j: f64, step: f64, l: u32) -> impl Iterator<Item = f64> {
    (0..l).map(move |n| j + step * n as f64)
}

impl State {
    /// Whether the block's Haas code can be carried out in the current modes: its path is built
    /// in plain programming coordinates of the XY plane only (`docs/dialects.md`, "Haas
    /// cycles"); elsewhere it is refused rather than run on a path fivex has not computed.
    fn pocket_modes_supported(&self) -> Result<(), AlarmId> {
        if self.modes[group::PLANE] != code::G17 {
            // The manual: the circular pockets work in the XY plane (G17) only.
            return Err(AlarmId::ImproperGCode);
        }
        if self.modes[group::CYCLE] != code::G80 {
            return Err(AlarmId::IllegalGCodeCombination);
        }
        let compensated = self.modes[group::CUTTER_COMP] != code::G40;
        let transformed = self.xf.active() || self.modes[group::POLAR] == code::G16;
        if compensated || transformed || self.follows_tip() || self.wse.is_some() || self.smoothing.is_some() {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// G12 (clockwise) / G13 (counter-clockwise) circular pocket milling. The block's X/Y put
    /// the centre (the tool goes there at rapid, at its height); Z is the depth (G91: the
    /// increment, cut L times). At each depth: a feed down at the centre, a half circle out to
    /// the first pass radius, a full circle there, a half circle out to each next pass radius
    /// and a full circle there, a half circle back to the centre. The tool ends at the centre
    /// at the last depth. The radii are less the tool radius of D (D0: the tool centre), as the
    /// manual's implied G42 (G12) / G41 (G13) put the tool inside the circle.
    pub(super) fn circular_pocket(&mut self, cw: bool, w: &Words, out: &mut Vec<Canon>) -> Result<bool, AlarmId> {
        self.pocket_modes_supported()?;
        let (a, b, c) = self.plane_axes()?;
        // Another axis's word has no place in the cycle: refused rather than ignored.
        let axes = &self.cfg.machine.axes;
        if (0..axes.len()).any(|k| ![a, b, c].contains(&k) && w.has(axes[k].name as u8)) {
            return Err(AlarmId::CycleArgument);
        }
        let tool = self.offsets.radius(self.d);
        let radii = pocket_radii(self.value(w, b'I'), self.value(w, b'K'), self.value(w, b'Q'), tool)?;
        let incremental = self.modes[group::DISTANCE] == code::G91;
        let loops = count(w, b'L', MAX_PASSES)?.unwrap_or(1);
        // L repeats the Z increment (G91, the manual); in G90 it would cut the same depth again.
        if loops > 1 && !incremental {
            return Err(AlarmId::CycleArgument);
        }
        self.check_feed()?;
        let target = self.programmed_target(w, None);
        let step = target[c] - self.xf.programmed[c];
        // The centre at the tool's height.
        let mut centre = self.xf.programmed;
        (centre[a], centre[b]) = (target[a], target[b]);
        if centre != self.xf.programmed {
            self.move_to(MotionKind::Rapid, centre, out);
        }
        let sign = if cw { -1.0 } else { 1.0 };
        for n in 1..=loops {
            let mut bottom = centre;
            bottom[c] = if incremental { centre[c] + step * n as f64 } else { target[c] };
            self.move_to(MotionKind::Linear, bottom, out);
            // Along the plane's first axis: the half circles' ends, from the centre out.
            let mut at = 0.0;
            for &r in &radii {
                self.pocket_arc(bottom, (a, b, c), (at + r) / 2.0, (r - at) / 2.0, r, sign * 180.0, out);
                self.pocket_arc(bottom, (a, b, c), 0.0, r, r, sign * 360.0, out);
                at = r;
                // Passes × loops may be 10⁸ arcs: FX0003 before memory runs out.
                super::cycles::check_output(out)?;
            }
            self.pocket_arc(bottom, (a, b, c), at / 2.0, at / 2.0, 0.0, sign * 180.0, out);
        }
        Ok(true)
    }

    /// An arc of a pocket at `bottom` (the centre at the cutting depth): about the point
    /// `centre` along the plane's first axis from the pocket's centre, of `radius`, ending at
    /// `end` along that axis, sweeping `sweep` degrees (positive: counter-clockwise).
    #[allow(clippy::too_many_arguments)]
    fn pocket_arc(
        &mut self,
        bottom: Pos,
        (a, b, c): (usize, usize, usize),
        centre: f64,
        radius: f64,
        end: f64,
        sweep: f64,
        out: &mut Vec<Canon>,
    ) {
        let mut target = bottom;
        target[a] += end;
        let mut at = bottom;
        at[a] += centre;
        let kind = if sweep < 0.0 { MotionKind::ArcCw } else { MotionKind::ArcCcw };
        let arc = Arc { center: at, plane_axes: (a, b, c), radius, sweep_deg: sweep };
        // Plain programming coordinates (`pocket_modes_supported`): the programmed point is
        // the workpiece one.
        self.push_motion(kind, target, Some(Box::new(arc)), out);
        self.xf.programmed = target;
    }

    /// G70 bolt hole circle, G71 bolt hole arc, G72 bolt holes along an angle: the canned cycle
    /// in force at each hole. The block's X/Y give the pattern's centre (G70/G71) or its first
    /// hole (G72), where the cycle does not drill; its R/Z/Q/P/F are the cycle's data, as in a
    /// cycle block, and a tool length change of the block takes effect at the first move to R
    /// (`with_length_at_r`; `length_before`: the length before the block). The tool ends over
    /// the last hole at the cycle's return level.
    pub(super) fn bolt_pattern(
        &mut self,
        code: u16,
        w: &Words,
        length_before: Pos,
        out: &mut Vec<Canon>,
    ) -> Result<bool, AlarmId> {
        if self.modes[group::CYCLE] == code::G80 {
            // The manual: a canned cycle must be in force for a hole to be made at each
            // position; without one fivex refuses the block rather than guess a move.
            return Err(AlarmId::ImproperGCode);
        }
        if self.modes[group::PLANE] != code::G17 {
            return Err(AlarmId::ImproperGCode);
        }
        let i = self.value(w, b'I').ok_or(AlarmId::CycleArgument)?;
        let j = self.angle_word(w, b'J').unwrap_or(0.0);
        let l = count(w, b'L', MAX_HOLES)?.ok_or(AlarmId::CycleArgument)?;
        let (d, (pa, pb)) = self.cycle_data(w)?;
        let origin = self.programmed_target(w, Some(d));
        let hole = |radius: f64, angle: f64| {
            let (s, c) = crate::angle::sin_cos_deg(angle);
            let mut p = origin;
            p[pa] += radius * c;
            p[pb] += radius * s;
            p
        };
        let holes: Vec<Pos> = match code {
            code::G70 if i != 0.0 => {
                // I negative: the holes clockwise (the manual's sign of I).
                let step = 360.0 / l as f64 * i.signum();
                bolt_angles(j, step, l).map(|t| hole(i.abs(), t)).collect()
            }
            code::G71 if i != 0.0 => {
                let k = self.angle_word(w, b'K').ok_or(AlarmId::CycleArgument)?;
                if k == 0.0 {
                    return Err(AlarmId::CycleArgument);
                }
                bolt_angles(j, k, l).map(|t| hole(i, t)).collect()
            }
            // I is the distance between holes; the first is the block's point.
            code::G72 => (0..l).map(|n| hole(i * n as f64, j)).collect(),
            _ => return Err(AlarmId::CycleArgument),
        };
        self.with_length_at_r(length_before, |s| {
            for mut h in holes {
                // Over the next hole at the level the last one left the tool (G98/G99), as a
                // cycle block's next hole.
                h[d] = s.xf.programmed[d];
                s.cycle_at(h, d, (pa, pb), out)?;
            }
            Ok(true)
        })
    }

    /// G150 general purpose pocket milling. The block's X/Y are the start hole (reached at rapid
    /// at the tool's height, then R at rapid); the outline is the subprogram P (the block N<P>
    /// of this program, else the program O<P>): its first move from the hole to the outline,
    /// the outline's moves back to where that first move ended. At each depth (R less Q, less
    /// 2Q … down to Z) a feed down at the hole and the moves of `pocket::plan`; with K the pass
    /// at the tool radius alone at Z; the tool ends at the hole, back at R (`docs/dialects.md`,
    /// "Haas cycles", G150).
    pub(super) fn general_pocket(
        &mut self,
        progs: &[Slot],
        by_number: &HashMap<u32, usize>,
        w: &Words,
        out: &mut Vec<Canon>,
    ) -> Result<bool, AlarmId> {
        self.pocket_modes_supported()?;
        let (a, b, c) = self.plane_axes()?;
        let axes = &self.cfg.machine.axes;
        if (0..axes.len()).any(|k| ![a, b, c].contains(&k) && w.has(axes[k].name as u8)) {
            return Err(AlarmId::CycleArgument);
        }
        // Not built: the repetition count L (with G91 X/Y moving the pocket) and the block in
        // G91 (whose R and Z the manual does not define).
        if w.integer(b'L').is_some_and(|l| l != 1.0) || self.modes[group::DISTANCE] == code::G91 {
            return Err(AlarmId::GCodeNotBuilt);
        }
        let (i, j) = (self.value(w, b'I'), self.value(w, b'J'));
        let (step, along_x) = match (i, j) {
            (Some(i), None) => (i, false),
            (None, Some(j)) => (j, true),
            _ => return Err(AlarmId::CycleArgument),
        };
        let k = self.value(w, b'K').unwrap_or(0.0);
        let tool = self.offsets.radius(self.d);
        // A step wider than the tool would leave ribs standing between the strokes.
        if step.is_nan() || step <= 0.0 || k < 0.0 || tool < 0.0 || step > 2.0 * tool {
            return Err(AlarmId::CycleArgument);
        }
        let q = self.value(w, b'Q').ok_or(AlarmId::CycleArgument)?;
        // R: the block's, or the last G150's (the manual: else the last R given is used).
        let r = self.value(w, b'R').or(self.pocket_r).ok_or(AlarmId::CycleArgument)?;
        if !w.has(b'Z') {
            return Err(AlarmId::CycleArgument);
        }
        self.check_feed()?;
        let target = self.programmed_target(w, None);
        let levels = pocket_levels(r, target[c], q)?;
        let hole = [target[a], target[b]];
        let p = w.integer(b'P').ok_or(AlarmId::MissingP)?;
        let outline = self.pocket_outline(progs, by_number, p, hole)?;
        // G41 / G42 in the block name the side the tool cuts on: inside the pocket, so the
        // outline runs counter-clockwise (G41) or clockwise (G42).
        let ccw = pocket::area(&outline) > 0.0;
        match self.block_code(w, group::CUTTER_COMP) {
            Some(code::G41) if !ccw => return Err(AlarmId::CycleArgument),
            Some(code::G42) if ccw => return Err(AlarmId::CycleArgument),
            Some(code::G40 | code::G41 | code::G42) | None => {}
            Some(_) => return Err(AlarmId::CycleArgument),
        }
        let plan = pocket::plan(&outline, hole, tool, k, step, along_x).map_err(|e| match e {
            Refusal::Argument(_) => AlarmId::CycleArgument,
            Refusal::NotBuilt(_) => AlarmId::GCodeNotBuilt,
        })?;
        self.pocket_r = Some(r);
        let mut at = self.xf.programmed;
        (at[a], at[b]) = (hole[0], hole[1]);
        if at != self.xf.programmed {
            self.move_to(MotionKind::Rapid, at, out);
        }
        at[c] = r;
        if at != self.xf.programmed {
            self.move_to(MotionKind::Rapid, at, out);
        }
        let last = levels.len() - 1;
        for (n, &z) in levels.iter().enumerate() {
            at[c] = z;
            self.move_to(MotionKind::Linear, at, out);
            self.pocket_moves(&plan.level, z, (a, b, c), out);
            if n == last {
                self.pocket_moves(&plan.finish, z, (a, b, c), out);
            }
            super::cycles::check_output(out)?;
        }
        at[c] = r;
        self.move_to(MotionKind::Rapid, at, out);
        Ok(true)
    }

    /// The moves of a pocket pass at depth `z`, at F, in plain programming coordinates.
    fn pocket_moves(&mut self, moves: &[Move], z: f64, (a, b, c): (usize, usize, usize), out: &mut Vec<Canon>) {
        for m in moves {
            let mut target = self.xf.programmed;
            (target[a], target[b], target[c]) = (m.to()[0], m.to()[1], z);
            match *m {
                Move::Line { .. } => self.move_to(MotionKind::Linear, target, out),
                Move::Arc { centre, sweep, .. } => {
                    let mut at = target;
                    (at[a], at[b]) = (centre[0], centre[1]);
                    let from = [self.xf.programmed[a], self.xf.programmed[b]];
                    let kind = if sweep < 0.0 { MotionKind::ArcCw } else { MotionKind::ArcCcw };
                    let radius = pocket::dist(from, centre);
                    let arc = Arc { center: at, plane_axes: (a, b, c), radius, sweep_deg: sweep.to_degrees() };
                    self.push_motion(kind, target, Some(Box::new(arc)), out);
                    self.xf.programmed = target;
                }
            }
        }
    }

    /// A G150's outline from its subprogram P: the block N<P> of the running program, else the
    /// program O<P> (neither: `ProgramNotFound`, the manual's 314), read to its M99. Only
    /// G01/G02/G03 with X, Y and I, J or R, and G90/G91, may be in it (anything else is
    /// `CycleArgument`); the first move, a G01 from the start hole, leads to the outline,
    /// which must end where that move did. Returns the outline without the entry move.
    fn pocket_outline(
        &self,
        progs: &[Slot],
        by_number: &HashMap<u32, usize>,
        p: f64,
        hole: P,
    ) -> Result<Vec<Seg>, AlarmId> {
        let (prog, pc) = self.frames.last().map_or((0, 0), |f| (f.prog, f.pc));
        let n = super::nc::sequence_number(p).ok_or(AlarmId::ProgramNotFound)?;
        let (prog, first) = match progs.get(prog).and_then(|l| l.find_label(n, pc.saturating_sub(1))) {
            Some(at) => (prog, at),
            None => (*by_number.get(&n).ok_or(AlarmId::ProgramNotFound)?, 0),
        };
        let program = &progs[prog];
        let bad = AlarmId::CycleArgument;
        let mut incremental = self.modes[group::DISTANCE] == code::G91;
        let mut motion: Option<u16> = None;
        let mut at = hole;
        let mut segs: Vec<Seg> = Vec::new();
        let mut ended = false;
        for idx in first..program.len().min(first + MAX_OUTLINE_BLOCKS) {
            let block = program.block(idx);
            if block.deleted(self.cfg.block_delete) {
                continue;
            }
            let words = match &block.kind {
                BlockKind::Empty => continue,
                // Syntec's text (`%@MACRO`, a `(*` comment) is nothing in the Haas dialect.
                BlockKind::SyntecOnly(s) if s.others.is_none() => continue,
                BlockKind::Words(words) => words,
                _ => return Err(bad),
            };
            let mut w = Words::new();
            self.collect_into(words, &mut w)?;
            if w.mcodes() == [super::mcode::M99] {
                if w.letters().any(|l| l != b'M') {
                    return Err(bad);
                }
                ended = true;
                break;
            }
            if !w.mcodes().is_empty() || w.letters().any(|l| !matches!(l, b'G' | b'X' | b'Y' | b'I' | b'J' | b'R')) {
                return Err(bad);
            }
            for &g in w.gcodes() {
                match g {
                    code::G90 => incremental = false,
                    code::G91 => incremental = true,
                    code::G01 | code::G02 | code::G03 => motion = Some(g),
                    _ => return Err(bad),
                }
            }
            let coord = |letter: u8, k: usize| match self.value(&w, letter) {
                Some(v) if incremental => at[k] + v,
                Some(v) => v,
                None => at[k],
            };
            let end = [coord(b'X', 0), coord(b'Y', 1)];
            let arcs = w.has(b'I') || w.has(b'J') || w.has(b'R');
            let moves = w.has(b'X') || w.has(b'Y') || arcs;
            if !moves {
                continue;
            }
            let seg = match motion {
                Some(code::G01) if !arcs => Seg::line(at, end),
                Some(g @ (code::G02 | code::G03)) => {
                    let ij = [self.value(&w, b'I').unwrap_or(0.0), self.value(&w, b'J').unwrap_or(0.0)];
                    let r = self.value(&w, b'R');
                    let (centre, sweep) = arc_centre(at, end, r, ij, g == code::G02, self.cfg.arc_tolerance)?;
                    Seg { start: at, end, arc: Some((centre, sweep)) }
                }
                _ => return Err(bad),
            };
            // The first move is the way from the hole to the outline: a straight one.
            if segs.is_empty() && seg.arc.is_some() {
                return Err(bad);
            }
            if seg.arc.is_some() || pocket::dist(at, end) > pocket::EPS {
                segs.push(seg);
            }
            at = end;
        }
        if !ended || segs.len() < 2 {
            return Err(bad);
        }
        let outline = segs.split_off(1);
        // "Do not move back to the starting hole": the outline closes where the entry ended.
        if pocket::dist(at, segs[0].end) > pocket::EPS {
            return Err(bad);
        }
        Ok(outline)
    }

    /// G103 P0–P15: the look-ahead of the motions that follow limited to P blocks (P0, or no P:
    /// not limited). Every motion carries it to the planner (`canon::Motion::block_limit`).
    pub(super) fn block_look_ahead(&mut self, w: &Words) -> Result<(), AlarmId> {
        let p = w.integer(b'P').unwrap_or(0.0);
        if p.fract() != 0.0 || !(0.0..=MAX_BLOCK_LIMIT).contains(&p) {
            return Err(AlarmId::CycleArgument);
        }
        self.block_limit = p as u8;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pocket_radii_follow_the_manual_s_rules() {
        // I only: one pass on I less the tool radius.
        assert_eq!(pocket_radii(Some(10.0), None, None, 3.0), Ok(vec![7.0]));
        // I, K, Q: I, I+Q … and K itself last.
        assert_eq!(pocket_radii(Some(2.0), Some(10.0), Some(3.0), 1.0), Ok(vec![1.0, 4.0, 7.0, 9.0]));
        assert_eq!(pocket_radii(Some(2.0), Some(8.0), Some(3.0), 0.0), Ok(vec![2.0, 5.0, 8.0]));
        // I not greater than the tool radius, K not greater than I, Q without K, K without Q,
        // Q not positive, I missing.
        for (i, k, q) in [
            (Some(3.0), None, None),
            (Some(5.0), Some(5.0), Some(1.0)),
            (Some(5.0), None, Some(1.0)),
            (Some(5.0), Some(9.0), None),
            (Some(5.0), Some(9.0), Some(0.0)),
            (None, Some(9.0), Some(1.0)),
        ] {
            assert_eq!(pocket_radii(i, k, q, 3.0), Err(AlarmId::CycleArgument), "{i:?} {k:?} {q:?}");
        }
        assert_eq!(pocket_radii(Some(1.0), None, None, -0.5), Err(AlarmId::CycleArgument));
    }
}
