//! Canned cycles G73–G89, expanded into canonical motions.
//!
//! FANUC conventions: the drilling axis is the plane normal; in G91 the R word is the distance
//! from the initial level and the drilling-axis word the distance from the R point (kept as that
//! distance when a later G91 block changes R alone); G98 returns to the initial level, G99 to
//! the R point; K repeats the cycle (K0 only stores its data), L is refused (`repeats`).
//!
//! Every point of a cycle is computed in programmed coordinates and goes through the programming
//! transforms (`frames`) like any other: hole positions and R/Z levels are rotated, scaled and
//! mirrored. Peck depths Q, the G73/G83 retract and the G76/G87 shift are lengths scaling does
//! not change (FANUC), so they are divided by the axis's magnification here. Haas scales the
//! hole positions only: the drilling-axis levels and pecks are kept unscaled
//! ([`State::cycle_level`]). In the tilted
//! working plane (twp §1.3.2 allows the cycles there) the programmed coordinates are the feature
//! coordinate system's, and every move of the cycle follows the tool tip through the kinematics
//! like any move in the plane: the hole is drilled at the FCS point along the FCS Z.

use super::gcode::{self, code, group};
use super::mcode;
use super::nc::Words;
use super::unbuilt;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind, FeedMode, Motion, MotionKind, Pos, SpindleState, Tapping};
use crate::dialect::Dialect;
use crate::notice::BlockNotice;

/// Canonical commands one cycle block may expand into (pecks × holes), so that a tiny Q or a
/// huge L ends in alarm FX0003 instead of exhausting memory.
pub const MAX_COMMANDS_PER_BLOCK: usize = 200_000;

pub(super) fn check_output(out: &[Canon]) -> Result<(), AlarmId> {
    if out.len() > MAX_COMMANDS_PER_BLOCK {
        return Err(AlarmId::BlockOutputExceeded { limit: MAX_COMMANDS_PER_BLOCK });
    }
    Ok(())
}

impl State {
    /// Whether scaling leaves the drilling-axis levels (initial, R, Z) and the peck depths
    /// alone: Haas, "scaling does not affect canned cycle Z-axis movements such as clearance
    /// planes and incremental values" (96-8000 rev R, G51, programming notes). FANUC scales the
    /// levels (`docs/conventions.md`).
    fn levels_unscaled(&self) -> bool {
        self.cfg.dialect == Dialect::Haas
    }

    /// The cycle level that programmed coordinate `p` on the drilling axis `d` stands at: `p`,
    /// or where the tool is along `d` once scaling is taken out (Haas).
    pub(super) fn cycle_level(&self, d: usize, p: f64) -> f64 {
        if self.levels_unscaled() {
            self.xf.unscaled_level(d, p)
        } else {
            p
        }
    }

    /// The programmed coordinate on the drilling axis `d` of the cycle level `level`.
    fn level_target(&self, d: usize, level: f64) -> f64 {
        if self.levels_unscaled() {
            self.xf.programmed_level(d, level)
        } else {
            level
        }
    }

    /// Run the active cycle at the block's hole position(s). Returns whether anything moved.
    /// `length_before` is the tool length offset vector before the block: a G43/G44/G49 or H
    /// of the block takes effect at the move to point R (FANUC 15i-MA operator's manual, G76
    /// "Tool length compensation": "the offset is applied at the time of positioning to point
    /// R"), so the positioning over the hole runs with the old length.
    pub(super) fn canned_cycle(
        &mut self,
        w: &Words,
        length_before: Pos,
        out: &mut Vec<Canon>,
    ) -> Result<bool, AlarmId> {
        let repeats = repeats(w, self.cfg.dialect)?;
        let (d, plane) = self.cycle_data(w)?;
        self.with_length_at_r(length_before, |s| s.holes(w, repeats, d, plane, out))?;
        Ok(repeats > 0)
    }

    /// Make the holes of a cycle block (`drill`) with the block's tool length change
    /// (`tool_vec` against `length_before`) held back until the first move to R. No hole
    /// (K0) or an alarm: the block's length stands all the same.
    pub(super) fn with_length_at_r<T>(
        &mut self,
        length_before: Pos,
        drill: impl FnOnce(&mut Self) -> Result<T, AlarmId>,
    ) -> Result<T, AlarmId> {
        if self.tool_vec != length_before {
            self.cycle.length_due = Some(self.tool_vec);
            self.tool_vec = length_before;
        }
        let drilled = drill(self);
        self.apply_due_length();
        drilled
    }

    fn holes(
        &mut self,
        w: &Words,
        repeats: u32,
        d: usize,
        plane: (usize, usize),
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        for _ in 0..repeats {
            // Position over the hole: every axis but the drilling axis.
            let hole = self.programmed_target(w, Some(d));
            self.cycle_at(hole, d, plane, out)?;
        }
        Ok(())
    }

    /// The tool length the cycle block selected takes effect (at the move to R); whether one
    /// was due.
    fn apply_due_length(&mut self) -> bool {
        match self.cycle.length_due.take() {
            Some(v) => {
                self.tool_vec = v;
                true
            }
            None => false,
        }
    }

    /// A tool length change (G43/G44/G49, H, or tool centre point control starting) in a cycle
    /// block while the cycle's moves follow the tool tip (the tilted working plane, Syntec
    /// RTCP): the tip is followed with the new length from the positioning on, where the
    /// control applies it at the move to R; not built (*decision*, `docs/conventions.md`,
    /// "Canned cycles").
    pub(super) fn refuse_length_change_in_tip_cycle(&self, w: &Words) -> Result<(), AlarmId> {
        let length_code = self.block_code(w, group::LENGTH_COMP);
        let changes = length_code.is_some() || w.has(b'H');
        let follows = self.plane_active() || self.tcp_active() || length_code.is_some_and(|c| code::TCP.contains(&c));
        if changes && follows && self.cycle_after_block(w) {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// G76/G87 with a shift (Q) while a coordinate rotation or a mirror image (G51.1, a negative
    /// magnification) is in force: refused as not built. The shift moves the tool's oriented
    /// edge off the bore wall; the spindle orients it in a fixed direction of the machine, and
    /// no manual at hand says whether the control turns or mirrors the shift with the program
    /// (fivex did: mirrored, the retract would push the edge into the wall). (Audit of the
    /// transforms; `docs/conventions.md`, "Canned cycles".)
    pub(super) fn refuse_shift_under_transforms(&self, w: &Words) -> Result<(), AlarmId> {
        let cycle = self.after_block(w, group::CYCLE);
        if !self.cycle_after_block(w) || ![code::G76, code::G87].contains(&cycle) {
            return Ok(());
        }
        let shifted = self.value(w, b'Q').unwrap_or(self.cycle.q) != 0.0;
        if shifted && self.xf.turns_or_mirrors() {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// Haas: a block that runs the canned cycle in force (or names it) with a word the cycle does
    /// not perform. The I, J, K peck forms of G73/G83 and G76's shift by I/J are functions not
    /// built (`unbuilt`, asked here of the cycle in force, which the block need not name); I and
    /// J mean nothing to the other cycles (K is the repeat count's, [`repeats`]): refused rather
    /// than ignored (*decision*, `docs/dialects.md`, "Haas cycles"). A bolt pattern, a macro
    /// call or G10 in the block takes them as its own words.
    pub(super) fn refuse_unperformed_cycle_words(&self, w: &Words) -> Result<(), AlarmId> {
        let codes = w.gcodes();
        let own = |c: &u16| unbuilt::OWN_IJK.contains(c) || code::MACRO_CALLS.contains(c) || *c == code::G10;
        if self.cfg.dialect != Dialect::Haas || codes.iter().any(own) || !self.cycle_after_block(w) {
            return Ok(());
        }
        let cycle = self.after_block(w, group::CYCLE);
        let word = |l: u8| if w.has(l) { unbuilt::Word::Value(0.0) } else { unbuilt::Word::Absent };
        if self.cfg.refuse_unbuilt && unbuilt::g_code(cycle, self.cfg.dialect, codes, word).is_some() {
            return Err(AlarmId::GCodeNotBuilt);
        }
        if w.has(b'I') || w.has(b'J') {
            return Err(AlarmId::ImproperAddress);
        }
        Ok(())
    }

    /// A canned cycle is in force after the block: it is not cancelled there (G80, a group-01
    /// code) and one was in force or the block names one.
    fn cycle_after_block(&self, w: &Words) -> bool {
        let group_of = |c: u16| gcode::lookup(c, self.cfg.dialect).map(|d| d.group);
        let cancels = w.gcodes().iter().any(|&c| c == code::G80 || group_of(c) == Some(group::MOTION));
        !cancels && self.after_block(w, group::CYCLE) != code::G80
    }

    /// A plane change (G17/G18/G19) while a canned cycle stays in force changes the drilling
    /// axis under levels taken on the old one (the initial level, R, the bottom); FANUC's
    /// canned-cycle restrictions ask for the cycle to be cancelled before the drilling axis is
    /// changed, naming no alarm: refused as a G code the mode does not allow (PS0010,
    /// *decision*, `docs/conventions.md`, "Canned cycles"). A block that cancels the cycle
    /// (G80, a group-01 code) may change the plane.
    pub(super) fn refuse_plane_change_in_cycle(&self, w: &Words) -> Result<(), AlarmId> {
        let plane_change = self.block_code(w, group::PLANE).is_some_and(|c| c != self.modes[group::PLANE]);
        if plane_change && self.modes[group::CYCLE] != code::G80 && self.cycle_after_block(w) {
            return Err(AlarmId::ImproperGCode);
        }
        Ok(())
    }

    /// The block's cycle data (R, the drilling-axis level, Q, P) taken into the modal cycle data
    /// and checked; the drilling axis and the plane's two axes.
    pub(super) fn cycle_data(&mut self, w: &Words) -> Result<(usize, (usize, usize)), AlarmId> {
        // Under TCP type 2 (Syntec G43.5; FANUC refuses cycles in TCP) I/J/K are the tool
        // direction: a K there cannot also be the repeat count (*decision*, docs/five-axis.md).
        if self.ijk_is_direction() && [b'I', b'J', b'K'].iter().any(|&l| w.has(l)) {
            return Err(AlarmId::IllegalCommandInTcp);
        }
        let (pa, pb, d) = self.plane_axes()?;
        let incremental = self.modes[group::DISTANCE] == code::G91;
        let drill_letter = self.cfg.machine.axes[d].name as u8;
        let new_r = self.value(w, b'R');
        if let Some(r) = new_r {
            self.cycle.r = if incremental { self.cycle.initial + r } else { r };
            self.cycle.r_set = true;
        }
        if !self.cycle.r_set {
            self.cycle.r = self.cycle_level(d, self.xf.programmed[d]);
        }
        match self.value(w, drill_letter) {
            Some(z) => {
                self.cycle.z = if incremental { self.cycle.r + z } else { z };
                self.cycle.z_set = true;
            }
            // G91: the retained bottom is a distance from R, so it moves with a new R (FANUC).
            None if incremental && new_r.is_some() => self.cycle.z = self.cycle.r + self.cycle.depth,
            None => {}
        }
        self.cycle.depth = self.cycle.z - self.cycle.r;
        if let Some(q) = self.value(w, b'Q') {
            self.cycle.q = q.abs();
        }
        self.refuse_point_at_dwell_p(w)?;
        if let Some(p) = w.integer(b'P') {
            self.cycle.p = self.dwell_p_seconds(w, p);
        }
        let code = self.modes[group::CYCLE];
        if matches!(code, code::G73 | code::G83) && self.cycle.q <= 0.0 {
            return Err(AlarmId::MissingQ);
        }
        self.check_feed()?;
        Ok((d, (pa, pb)))
    }

    /// The active cycle at one hole: positioned over `hole` (programmed coordinates, every axis
    /// but the drilling axis `d`), then the hole.
    pub(super) fn cycle_at(
        &mut self,
        hole: Pos,
        d: usize,
        plane: (usize, usize),
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        // No manual at hand says what depth the control drills to when no bottom was given
        // since the cycle started (the first cycle, or after G80 or a group-01 code cleared
        // the data): refused rather than drilled to a depth fivex makes up (*decision*,
        // `docs/conventions.md`, "Canned cycles").
        if !self.cycle.z_set {
            return Err(AlarmId::CycleBottomMissing);
        }
        let code = self.modes[group::CYCLE];
        let first = out.len();
        self.cycle_move(MotionKind::Rapid, hole, out)?;
        // Operation 1, the positioning at the initial level.
        self.stop_point(&mut out[first..]);
        let first = out.len();
        self.hole(code, d, plane, out)?;
        // Operation 6, the return: the hole's end (the block's too, for its last hole).
        self.stop_point(&mut out[first..]);
        check_output(out)
    }

    /// Single block stops at the end of the cycle's last motion in `moves` (and the commands
    /// without motion after it): FANUC stops three times per hole, "at the end of operations
    /// 1, 2 and 6" (the positioning, the rapid to R, the return), not in the hole
    /// (`docs/conventions.md`, "Canned cycles"). Syntec and Haas: once at the block's end, as
    /// any block (no text at hand says otherwise).
    fn stop_point(&self, moves: &mut [Canon]) {
        if self.cfg.dialect == Dialect::Fanuc {
            if let Some(m) = motions(moves).last() {
                m.context.cycle_stop = true;
            }
        }
    }

    fn move_drill_axis(&mut self, d: usize, level: f64, kind: MotionKind, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let mut t = self.xf.programmed;
        t[d] = self.level_target(d, level);
        self.cycle_move(kind, t, out)
    }

    /// A shift along `axis` by `by` mm in programmed coordinates: scaling does not change its
    /// length (undone here), rotation and mirror image turn it with the program, which is why
    /// a shift under them is refused (`refuse_shift_under_transforms`).
    fn shift(&mut self, axis: usize, by: f64, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let mut t = self.xf.programmed;
        t[axis] += by / self.xf.length_factor(axis);
        self.cycle_move(MotionKind::Rapid, t, out)
    }

    /// A move of the cycle to the programmed point `t`. In the tilted working plane and under
    /// tool centre point control (Syntec; FANUC refuses cycles there) it follows the tool tip
    /// as `group01_motion` does; under G54.4 every rapid of the cycle
    /// (positioning, to R, the retracts) is a cutting move at No.5412's feed (WSE-19,
    /// [`State::wse_cycle_feed`]).
    fn cycle_move(&mut self, kind: MotionKind, t: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let feed = self.wse_cycle_feed().filter(|_| kind == MotionKind::Rapid);
        let kind = if feed.is_some() { MotionKind::Linear } else { kind };
        let first = out.len();
        if self.plane_active() || self.tcp_active() {
            let target = self.xf.forward(&t);
            self.tip_motion(kind, target, None, out)?;
            self.xf.programmed = t;
        } else {
            self.move_to(kind, t, out);
        }
        if let Some(feed) = feed {
            for c in &mut out[first..] {
                if let CanonKind::Motion(m) = &mut c.kind {
                    (m.feed, m.feed_mode) = (feed, FeedMode::PerMinute);
                }
            }
        }
        Ok(())
    }

    fn spindle(&mut self, state: SpindleState, out: &mut Vec<Canon>) {
        self.emit(out, CanonKind::Spindle { state, speed: self.s });
    }

    fn hole(&mut self, code: u16, d: usize, plane: (usize, usize), out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let first = out.len();
        self.hole_moves(code, d, plane, out)?;
        if self.r_beyond_z(code, d) {
            mark_first_feed(&mut out[first..], BlockNotice::CycleRBeyondZ);
        }
        Ok(())
    }

    /// Point R lies beyond point Z on the side the cycle cuts toward, seen in the workpiece (or
    /// feature) system, where the tool comes from the drilling axis's + side: R below Z, or for
    /// G87 (back boring from below, R under Z by design) R above Z. The control runs it as
    /// programmed, as far as the manuals at hand say (RS274NGC calls R below Z an error): the
    /// run tells (`docs/five-axis.md`, "Notices").
    fn r_beyond_z(&self, code: u16, d: usize) -> bool {
        let level = |v: f64| {
            let mut p = self.xf.programmed;
            p[d] = v;
            self.xf.forward(&p)[d]
        };
        let (r, z) = (level(self.cycle.r), level(self.cycle.z));
        if code == code::G87 {
            r > z
        } else {
            r < z
        }
    }

    fn hole_moves(&mut self, code: u16, d: usize, plane: (usize, usize), out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        use MotionKind::{Linear, Rapid};
        let c = self.cycle;
        let ret = if self.modes[group::RETURN_LEVEL] == code::G99 { c.r } else { c.initial };
        // Peck depth and retract in programmed units along the drilling axis (Haas: the levels
        // are unscaled, and so are they).
        let unit = if self.levels_unscaled() { 1.0 } else { self.xf.length_factor(d) };
        // G73's retract and G83's clearance are the machine's (FANUC No.5114/No.5115). The Haas
        // dialect uses them too: its G73 retract is Setting 22 and G83's return to R is raised
        // by Setting 52, whose units and defaults no source at hand gives (unverified,
        // `docs/dialects.md`, "Haas cycles").
        let settings = self.cfg.machine.cycles;
        let (q, retract, clearance) = (c.q / unit, settings.peck_retract / unit, settings.peck_clearance / unit);
        // G76's and G87's shift: along the plane axis and toward the side the machine sets.
        let (second, sign) = settings.bore_shift.in_plane();
        let (shift_axis, shift) = (if second { plane.1 } else { plane.0 }, sign * c.q);
        let dir = if c.z < c.r { -1.0 } else { 1.0 };
        let dwell = |st: &mut State, out: &mut Vec<Canon>| {
            if c.p > 0.0 {
                st.emit(out, CanonKind::Dwell { seconds: c.p });
            }
        };
        if code == code::G87 {
            // Back boring: orient, shift, go below to R (the hole bottom), bore upward to Z.
            self.emit(out, CanonKind::Aux { m: mcode::M19 });
            self.shift(shift_axis, shift, out)?;
            self.apply_due_length();
            let first = out.len();
            self.move_drill_axis(d, c.r, Rapid, out)?;
            // Operation 2: oriented and shifted, at point R below the hole.
            self.stop_point(&mut out[first..]);
            self.shift(shift_axis, -shift, out)?;
            self.spindle(SpindleState::Cw, out);
            self.move_drill_axis(d, c.z, Linear, out)?;
            dwell(self, out);
            self.emit(out, CanonKind::Aux { m: mcode::M19 });
            self.shift(shift_axis, shift, out)?;
            self.move_drill_axis(d, c.initial, Rapid, out)?;
            self.shift(shift_axis, -shift, out)?;
            self.spindle(SpindleState::Cw, out);
            return Ok(());
        }
        // Already at R, the tool still moves there if the block's tool length takes effect.
        if self.apply_due_length() || self.xf.programmed[d] != self.level_target(d, c.r) {
            let first = out.len();
            self.move_drill_axis(d, c.r, Rapid, out)?;
            // Operation 2, the rapid to point R.
            self.stop_point(&mut out[first..]);
        }
        match code {
            code::G73 | code::G83 => {
                let pecks = peck_count(c.z - c.r, q);
                for k in 1..=pecks {
                    let depth = if k == pecks { c.z } else { c.r + dir * q * k as f64 };
                    self.move_drill_axis(d, depth, Linear, out)?;
                    check_output(out)?;
                    if k == pecks {
                        break;
                    }
                    if code == code::G73 {
                        self.move_drill_axis(d, depth - dir * retract, Rapid, out)?;
                    } else {
                        self.move_drill_axis(d, c.r, Rapid, out)?;
                        self.move_drill_axis(d, depth - dir * clearance, Rapid, out)?;
                    }
                }
                // FANUC: G73/G83 have no dwell (their format has no P), a P left from G82/G89 is
                // kept for those cycles, not used here. Haas: P is the "pause at the bottom of
                // the hole after the last peck", kept for the later blocks until the cycle is
                // cancelled (96-8000, the G73 and G83 pages; `docs/dialects.md`, "Haas cycles").
                if self.cfg.dialect == Dialect::Haas {
                    dwell(self, out);
                }
                self.move_drill_axis(d, ret, Rapid, out)?;
            }
            code::G74 | code::G84 | code::G84_2 | code::G84_3 => {
                let (forward, reverse) = if matches!(code, code::G74 | code::G84_3) {
                    (SpindleState::Ccw, SpindleState::Cw)
                } else {
                    (SpindleState::Cw, SpindleState::Ccw)
                };
                // The tap in the hole: from the feed in to the end of the feed out, a feed hold
                // waits and the spindle override does not act (the controller).
                let first = out.len();
                self.move_drill_axis(d, c.z, Linear, out)?;
                motions(&mut out[first..]).for_each(|m| m.context.tapping = Tapping::In);
                dwell(self, out);
                self.spindle(reverse, out);
                let first = out.len();
                self.move_drill_axis(d, c.r, Linear, out)?;
                motions(&mut out[first..]).for_each(|m| m.context.tapping = Tapping::Out);
                self.spindle(forward, out);
                if ret != c.r {
                    self.move_drill_axis(d, ret, Rapid, out)?;
                }
            }
            // The shift goes the machine's way (FANUC RD1/RD2; the Haas dialect takes the same
            // setting for Setting 27, whose default is unverified, `docs/dialects.md`).
            code::G76 => {
                self.move_drill_axis(d, c.z, Linear, out)?;
                dwell(self, out);
                self.emit(out, CanonKind::Aux { m: mcode::M19 });
                self.shift(shift_axis, shift, out)?;
                self.move_drill_axis(d, ret, Rapid, out)?;
                self.shift(shift_axis, -shift, out)?;
                self.spindle(SpindleState::Cw, out);
            }
            code::G85 | code::G89 => {
                self.move_drill_axis(d, c.z, Linear, out)?;
                if code == code::G89 {
                    dwell(self, out);
                }
                self.move_drill_axis(d, c.r, Linear, out)?;
                if ret != c.r {
                    self.move_drill_axis(d, ret, Rapid, out)?;
                }
            }
            code::G86 | code::G88 => {
                self.move_drill_axis(d, c.z, Linear, out)?;
                if code == code::G88 {
                    dwell(self, out);
                }
                self.spindle(SpindleState::Stop, out);
                if code == code::G88 {
                    // The hold for the manual retraction: the machine stops at the bottom, the
                    // operator may jog the tool out, and cycle start goes on with the return
                    // (FANUC G88; the Haas list's "bore in, dwell, manual retract"). It rapided
                    // out on its own, as G86 does.
                    self.emit(out, CanonKind::Stop { optional: false, message: None });
                }
                self.move_drill_axis(d, ret, Rapid, out)?;
                self.spindle(SpindleState::Cw, out);
            }
            // G81, G82
            _ => {
                self.move_drill_axis(d, c.z, Linear, out)?;
                if code == code::G82 {
                    dwell(self, out);
                }
                self.move_drill_axis(d, ret, Rapid, out)?;
            }
        }
        Ok(())
    }
}

/// The motions among `commands`.
fn motions(commands: &mut [Canon]) -> impl DoubleEndedIterator<Item = &mut Motion> {
    commands.iter_mut().filter_map(|c| match &mut c.kind {
        CanonKind::Motion(m) => Some(m),
        _ => None,
    })
}

/// Marks the first cutting feed among a hole's commands with `notice`.
fn mark_first_feed(hole: &mut [Canon], notice: BlockNotice) {
    let feed = hole.iter_mut().find_map(|c| match &mut c.kind {
        CanonKind::Motion(m) if m.kind == MotionKind::Linear => Some(m),
        _ => None,
    });
    if let Some(m) = feed {
        m.notice = Some(notice);
    }
}

/// How many cutting feeds of at most `q` a G73/G83 hole `depth` deep takes (at least one). The
/// control counts in least input increments (0.001 mm), so a depth that is a whole number of
/// pecks ends on its last full peck: a remainder below `PECK_TOLERANCE` (binary fractions:
/// 4.2 / 0.7 is 6.000000000000001) is no further peck.
fn peck_count(depth: f64, q: f64) -> u64 {
    ((depth.abs() - PECK_TOLERANCE) / q).ceil().max(1.0) as u64
}

/// Far below the least input increment (0.001 mm), far above the rounding of a depth.
const PECK_TOLERANCE: f64 = 1e-6;

/// The repeat count of a cycle block: K, 0–9999 (FANUC 30i and Syntec; K0 stores the cycle's
/// data without machining), 1 without K. L (the repeat count of older FANUC controls and of
/// the 30i's FS15 program format, a parameter) is refused rather than read one way or ignored
/// (*decision*, `docs/dialects.md`). The Haas NGC counts with L (L0: the data only, as the bolt
/// patterns' examples put it on the cycle's line), and its K is a peck argument of G73/G83
/// that fivex does not perform: refused there.
fn repeats(w: &Words, dialect: Dialect) -> Result<u32, AlarmId> {
    let (count, other) = if dialect == Dialect::Haas { (b'L', b'K') } else { (b'K', b'L') };
    if w.has(other) {
        return Err(AlarmId::ImproperAddress);
    }
    match w.integer(count) {
        None => Ok(1),
        Some(k) if (0.0..=9999.0).contains(&k) && k.fract() == 0.0 => Ok(k as u32),
        Some(_) => Err(AlarmId::ImproperAddress),
    }
}
