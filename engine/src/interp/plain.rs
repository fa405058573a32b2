//! The fast path for the block CAM output is made of: `[G00|G01] axis words [F]`.
//!
//! Such a block, while no canned cycle, modal macro call or 5-axis mode is active, only sets
//! the motion mode and the feed and moves; the general path (`nc::exec_words`) would ask and
//! answer "no" to a few dozen questions about it first. The fast path does exactly what the
//! general one does for these blocks, and nothing else: `engine/tests/it/fast_path.rs` runs every
//! fixture and random programs both ways and compares commands and final state.

use super::gcode::{code, group};
use super::nc::Words;
use super::{modes, State};
use crate::alarm::AlarmId;
use crate::canon::Canon;
use crate::machine::AxisKind;

impl State {
    /// Whether the block (already evaluated) is a plain linear or rapid motion block here.
    pub(super) fn is_plain_motion(&self, w: &Words) -> bool {
        let g = w.gcodes();
        let motion = match g {
            [] => self.modes[group::MOTION],
            [code] => *code,
            _ => return false,
        };
        matches!(motion, code::G00 | code::G01)
            && w.mcodes().is_empty()
            && self.modes[group::CYCLE] == code::G80
            // Under cutter compensation a rotary axis word is refused (`unbuilt::cutter`) by the
            // general path; the block's other conditions are modal, checked where they were set.
            && (self.modes[group::CUTTER_COMP] == code::G40 || !self.rotary_word(w))
            && self.modal_calls.is_empty()
            // A move of Z re-establishes a tool length vector a reference return cancelled.
            && !self.length_cancelled
            && modes::no_rule_applies(self, g)
            && w.letters().all(|l| l == b'G' || l == b'F' || self.axis_of(l).is_some())
    }

    pub(super) fn rotary_word(&self, w: &Words) -> bool {
        w.letters().any(|l| self.axis_of(l).is_some_and(|i| self.cfg.machine.axes[i].kind == AxisKind::Rotary))
    }

    /// Execute a block for which [`State::is_plain_motion`] holds.
    pub(super) fn plain_motion(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        self.refuse_syntec_undecided_unit(w)?;
        // (A group-01 code also clears the canned cycle data, which G80 has already cleared.)
        if let [code] = w.gcodes() {
            self.modes[group::MOTION] = *code;
        }
        self.set_feed(w)?;
        if w.letters().any(|l| l != b'G' && l != b'F') {
            self.group01_motion(w, out)?;
        }
        Ok(())
    }
}
