//! The operator's switches that change how a program runs without changing the program (dry
//! run, spindle speed override) and the counters of automatic operation (operating time,
//! cutting time). Rules and decisions: `docs/dialects.md`, "The operator's switches and
//! counters".

use super::{Controller, Mode, Refusal, RunState};
use crate::canon::{FeedMode, Motion, MotionKind};

/// The spindle speed override's range, fractions (the standard FANUC machine operator's panel:
/// 50–120 % in 10 % steps; the service refuses other steps).
pub const SPINDLE_OVERRIDE: std::ops::RangeInclusive<f64> = 0.5..=1.2;

/// The counters of automatic operation, seconds of simulated time (FANUC's operating time
/// No.6751/6752 and cutting time No.6753/6754, kept as seconds).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Times {
    /// Automatic operation under way (AUTO or MDI, the cycle running: not held, not at a
    /// single-block or M00/M01 stop, not in a manual intervention).
    pub operating_s: f64,
    /// The part of it the machine moved along a cutting feed (not a rapid).
    pub cutting_s: f64,
}

/// A stretch of simulated time and what the controller was doing at its start.
#[derive(Debug, Clone, Copy)]
pub(super) struct Piece {
    from: f64,
    operating: bool,
    cutting: bool,
}

impl Controller {
    /// Dry run (FANUC DRN): the program's cutting feeds run at the dry run rate (No.1410, or the
    /// panel's jog feed where none is set) with the feed override, instead of F; rapids stay
    /// rapids. Changed only at a block boundary: refused while motion is under way or queued
    /// (running or held), since what is planned already keeps its feed.
    pub fn set_dry_run(&mut self, on: bool) -> Result<(), Refusal> {
        if on != self.panel.dry_run && !self.at_block_boundary() {
            return Err(Refusal::Busy);
        }
        self.panel.dry_run = on;
        Ok(())
    }

    /// Spindle speed override, a fraction within [`SPINDLE_OVERRIDE`] (clamped): the speed the
    /// spindle turns at, and reports, is the commanded one times this, at once.
    pub fn set_spindle_override(&mut self, fraction: f64) {
        if fraction.is_finite() {
            self.panel.spindle_override = fraction.clamp(*SPINDLE_OVERRIDE.start(), *SPINDLE_OVERRIDE.end());
        }
    }

    /// The spindle speed the program commanded (S with M03/M04), 1/min, signed as
    /// [`Controller::spindle`], before the override.
    pub fn spindle_commanded(&self) -> f64 {
        self.spindle
    }

    /// The operating and cutting time counted since the controller was made.
    pub fn times(&self) -> Times {
        self.times
    }

    /// The counters as saved before a power cycle (FANUC keeps No.6751–6754 through power
    /// off): counting goes on from them. Negative or non-finite values count as 0.
    pub fn load_times(&mut self, times: Times) {
        let kept = |s: f64| if s.is_finite() { s.max(0.0) } else { 0.0 };
        self.times = Times { operating_s: kept(times.operating_s), cutting_s: kept(times.cutting_s) };
        // Haas #3021/#3022 go on from the kept counters too.
        self.interp.state.load_operation_times(self.times.operating_s, self.times.cutting_s);
    }

    /// Motion `m` as dry run feeds it: a cutting feed at the dry run rate per minute (F, its
    /// feed mode and G95's spindle no longer matter); `None` when it runs as programmed.
    pub(super) fn dry_run_motion(&self, m: &Motion) -> Option<Motion> {
        if !self.panel.dry_run || matches!(m.kind, MotionKind::Rapid | MotionKind::MachineRapid) {
            return None;
        }
        let rate = self.machine.manual.dry_run_feed;
        let feed = if rate > 0.0 { rate } else { self.panel.jog_feed };
        Some(Motion { feed, feed_mode: FeedMode::PerMinute, ..m.clone() })
    }

    /// Where a stretch of time starts and what it counts towards.
    pub(super) fn piece(&self) -> Piece {
        let operating = self.run_state == RunState::Running
            && matches!(self.mode, Mode::Auto | Mode::Mdi)
            && !self.cycle.intervening()
            && !self.cycle.course().stopped();
        let cutting = operating && self.exec.on().is_some_and(|(seg, _, _)| !seg.rapid);
        Piece { from: self.exec.time(), operating, cutting }
    }

    /// Counts the stretch since `piece` began and starts the next one.
    pub(super) fn count(&mut self, piece: &mut Piece) {
        let dt = self.exec.time() - piece.from;
        if piece.operating {
            self.times.operating_s += dt;
        }
        if piece.cutting {
            self.times.cutting_s += dt;
        }
        *piece = self.piece();
    }
}
