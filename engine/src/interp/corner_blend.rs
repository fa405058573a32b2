//! Haas G187, the smoothness level and maximum corner rounding (`docs/dialects.md`, "Haas
//! cycles"): `G187 [P1|P2|P3] [E…]` turns corner rounding on until a reset or M02/M30 (another
//! G187 replaces it). In the mode a G01 block of linear axis words and F alone is a move whose
//! corners with the moves before and after it are rounded (`crate::blend`); any other block
//! first moves what is held to its programmed end, then runs as it always does, so every corner
//! with a rapid, an arc, a rotary axis, a dwell or any non-motion block stays exact. The pieces
//! of the path are emitted as motions of their blocks (line, sequence number, F).
//!
//! E is the maximum corner rounding (the program's unit: inch under G20). Without E it is
//! Setting 85 scaled by the level (P1 rough ×2, P2 medium ×1, P3 finish ×½; without P the level
//! is Setting 191's, Medium): fivex's machines keep every corner exact outside G187, so their
//! Setting 85 is 0 and only E rounds a corner. The level's other effect on the NGC, the axes'
//! acceleration, is not published and not modelled (**Partly**).

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::blend::{Blender, Piece, MAX_CHORDS};
use crate::canon::{Canon, MotionKind};
use crate::machine::{AxisKind, MAX_AXES};

use super::BlockTag as Tag;

/// Setting 191, Default Smoothness: Medium (P2), the NGC's default (Haas UK, "Smooth Operator").
const SETTING_191: u8 = 2;

/// Setting 85, Maximum Corner Rounding, mm: 0, the corners exact (see the module docs).
const SETTING_85_MM: f64 = 0.0;

/// G187 in force with a corner rounding above 0.
#[derive(Debug, Clone)]
pub(super) struct CornerBlend {
    /// The maximum corner rounding, mm.
    tolerance: f64,
    /// The moves being rounded (`None` until the first: it starts where the tool is then).
    run: Option<Blender<Tag, MAX_AXES>>,
    /// The block being executed is a move to round.
    point: bool,
}

/// How the level scales Setting 85 (Haas, "Advances in Motion Control": P1 doubles the corner
/// rounding, P3 halves it).
fn level_factor(level: u8) -> f64 {
    match level {
        1 => 2.0,
        3 => 0.5,
        _ => 1.0,
    }
}

impl State {
    /// G187 [P] [E]: the mode on with this level and rounding (what was held has been moved:
    /// the block is not a move to round). P other than 1, 2, 3 and a negative E are
    /// `CycleArgument`; a rounding of 0 (E0, or no E) keeps every corner exact.
    pub(super) fn g187(&mut self, w: &Words) -> Result<(), AlarmId> {
        let level = match w.integer(b'P') {
            None => SETTING_191,
            Some(p @ (1.0 | 2.0 | 3.0)) => p as u8,
            Some(_) => return Err(AlarmId::CycleArgument),
        };
        let tolerance = match w.number(b'E') {
            Some(e) if !(e.is_finite() && e >= 0.0) => return Err(AlarmId::CycleArgument),
            Some(e) if self.modes[group::UNITS] == code::G20 => e * 25.4,
            Some(e) => e,
            None => SETTING_85_MM * level_factor(level),
        };
        self.blend = (tolerance > 0.0).then(|| Box::new(CornerBlend { tolerance, run: None, point: false }));
        Ok(())
    }

    /// G187 ends (a reset drops what is held; M02/M30 and the end of the text have moved it).
    pub(super) fn blend_end(&mut self) {
        self.blend = None;
    }

    /// The maximum corner rounding (mm) in force, if G187 rounds corners.
    pub fn corner_rounding(&self) -> Option<f64> {
        self.blend.as_deref().map(|b| b.tolerance)
    }

    /// In G187, before anything of the block is done: whether it is a move to round (a G01
    /// block of linear axis words and F, in G94/G95, outside canned cycles and modal calls);
    /// if not, what is held moves first.
    pub(super) fn blend_block(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        if self.blend.is_none() {
            return Ok(());
        }
        let motion = match w.gcodes() {
            [] => self.modes[group::MOTION],
            [c] => *c,
            _ => 0,
        };
        let point = motion == code::G01
            && w.mcodes().is_empty()
            && self.modes[group::FEED_MODE] != code::G93
            && self.modes[group::CYCLE] == code::G80
            && self.modal_calls.is_empty()
            && !self.rotary_word(w)
            && w.letters().all(|l| l == b'G' || l == b'F' || self.axis_of(l).is_some());
        if !point {
            self.blend_flush(out)?;
        }
        if let Some(b) = self.blend.as_deref_mut() {
            b.point = point;
        }
        Ok(())
    }

    /// The G01 block being executed is a move to round (`blend_block`).
    pub(super) fn blend_point_block(&self) -> bool {
        self.blend.as_deref().is_some_and(|b| b.point)
    }

    /// The block's end point `target` (after the programming transforms) into the rounding; the
    /// pieces its corner fixes are moved.
    pub(super) fn blend_point(&mut self, target: crate::canon::Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let tag = self.block_tag();
        let start = self.pos;
        let m = &self.cfg.machine;
        let linear: [bool; MAX_AXES] =
            std::array::from_fn(|i| m.axes.get(i).is_some_and(|a| a.kind == AxisKind::Linear));
        let accel = std::array::from_fn(|i| m.axes.get(i).map_or(f64::INFINITY, crate::machine::Axis::max_accel));
        let jerk = std::array::from_fn(|i| m.axes.get(i).map_or(f64::INFINITY, crate::machine::Axis::max_jerk));
        let b = self.blend.as_deref_mut().expect("G187 in force");
        let tolerance = b.tolerance;
        let run = b.run.get_or_insert_with(|| Blender::new(tolerance, linear, accel, jerk, start));
        let mut pieces = Vec::new();
        // An arc of more chords than memory should hold: the block budget's alarm.
        run.push(target, tag, &mut pieces).map_err(|_| AlarmId::BlockOutputExceeded { limit: MAX_CHORDS })?;
        self.emit_pieces(pieces, out);
        Ok(())
    }

    /// Move what is held to its programmed end (the next move starts a new rounding there).
    pub(super) fn blend_flush(&mut self, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let Some(mut run) = self.blend.as_deref_mut().and_then(|b| b.run.take()) else { return Ok(()) };
        let mut pieces = Vec::new();
        run.finish(&mut pieces);
        self.emit_pieces(pieces, out);
        Ok(())
    }

    /// Each piece's chords as motions of its block (its line, sequence number and F).
    fn emit_pieces(&mut self, pieces: Vec<Piece<Tag, MAX_AXES>>, out: &mut Vec<Canon>) {
        for piece in pieces {
            let first = out.len();
            self.as_block(piece.tag, |s| {
                for q in piece.chords {
                    s.push_motion(MotionKind::Linear, q, None, out);
                }
            });
            crate::canon::cap_speed(&mut out[first..], piece.speed_cap);
        }
    }

    /// Under G187 (in force after the block) the modes whose path the rounding is not built
    /// for are refused like a function not built: TCP, a tilted working plane or DWO, G54.4,
    /// cutter compensation, nano smoothing.
    pub(super) fn refuse_unbuilt_blend(&self, w: &Words) -> Result<(), AlarmId> {
        if self.blend.is_none() && !w.has_g(code::G187) {
            return Ok(());
        }
        let after = |group: usize| self.after_block(w, group);
        let tilted =
            code::TILTED_PLANES.contains(&after(group::ROTATION)) || code::ALIGNMENTS.iter().any(|&c| w.has_g(c));
        let refused = self.follows_tip()
            || tilted
            || code::TCP.contains(&after(group::LENGTH_COMP))
            || after(group::DYNAMIC_FIXTURE) == code::G254
            || self.wse.is_some()
            || self.block_code(w, group::WSE).is_some()
            || after(group::CUTTER_COMP) != code::G40
            || self.smoothing.is_some();
        if refused {
            return Err(AlarmId::CornerRoundingInMode);
        }
        Ok(())
    }
}
