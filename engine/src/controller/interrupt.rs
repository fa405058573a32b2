//! Manual handle interruption (FANUC; `docs/five-axis.md`, 5-axis manual operation): handle
//! pulses in AUTO/MDI while a program is under way move the machine by a shift laid over the
//! program's motion, which goes on unchanged. The shift is added where positions leave the
//! controller ([`Controller::point`]); the program's coordinates, its planned path and the
//! interpreter never see it. A pulse's move is a segment of its own with its own jerk-limited
//! profile, sampled at the controller's time like the program's runs (never integrated).
//!
//! Coordinates: while a program is under way (`Interrupt::applied`), `Controller::here` and
//! `queued_machine` are the program's planned machine coordinates and the machine stands at
//! them plus the shift; otherwise (manual modes, idle, a manual intervention) they are where
//! the machine stands, and the program's machine position is that minus the shift.

use super::manual::AT_CLAMP;
use super::signals::ManualTarget;
use super::{Controller, Mode, Refusal, RunState};
use crate::canon::{Motion, MotionContext, MotionKind, Pos};
use crate::kin::Vec3;
use crate::machine::MAX_AXES;
use crate::motion::{Cursor, Planned, Segment};

/// The handle interruption's shift.
#[derive(Default)]
pub(super) struct Interrupt {
    /// The shift of every finished interrupt, machine coordinates per axis.
    pub(super) done: Pos,
    /// A pulse's move under way, and when it started.
    pub(super) moving: Option<(Planned, f64)>,
    /// `here` / `queued_machine` are the program's planned coordinates (the shift is added at
    /// the output), not the machine's.
    pub(super) applied: bool,
}

impl Interrupt {
    /// The shift at time `t`.
    pub(super) fn at(&self, t: f64) -> Pos {
        let Some((p, t0)) = &self.moving else { return self.done };
        let elapsed = (t - t0).clamp(0.0, p.profile.duration());
        let point = p.point(elapsed, &mut Cursor::default()).machine;
        let from = p.segments[0].from();
        std::array::from_fn(|i| self.done[i] + point[i] - from[i])
    }

    /// The shift once the move under way has ended.
    pub(super) fn last(&self) -> Pos {
        let Some((p, _)) = &self.moving else { return self.done };
        let (from, to) = (p.segments[0].from(), p.segments.last().map_or(p.segments[0].to(), |s| s.to()));
        std::array::from_fn(|i| self.done[i] + to[i] - from[i])
    }

    pub(super) fn is_zero(&self) -> bool {
        self.moving.is_none() && self.done.iter().all(|d| *d == 0.0)
    }
}

impl Controller {
    /// The handle interruption's shift now, machine coordinates per axis (FANUC's handle
    /// interrupt amount; zero when there is none).
    pub fn interrupt_shift(&self) -> Pos {
        self.interrupt.at(self.exec.time())
    }

    /// Where the program and the manual moves put the machine now (the program's point —
    /// through the filter after interpolation where it acts — plus the interruption's shift
    /// while a program is under way); without machine lock, where it stands (`lock.rs`).
    pub(super) fn moved_machine(&self) -> Pos {
        let axes = self.exec.axes_now();
        if !self.interrupt.applied || self.interrupt.is_zero() {
            return axes;
        }
        let shift = self.interrupt.at(self.exec.time());
        std::array::from_fn(|i| axes[i] + shift[i])
    }

    /// The program's machine position (where the machine stands without the shift): the point
    /// a program started now goes from, not the interpreter's, which has read ahead of the
    /// machine while blocks are queued.
    pub fn program_machine(&self) -> Pos {
        if self.interrupt.applied {
            return self.exec.here.machine;
        }
        let shift = self.interrupt.done;
        std::array::from_fn(|i| self.exec.here.machine[i] - shift[i])
    }

    /// A program starts (or comes back from a manual intervention): `here` becomes the
    /// program's coordinates.
    pub(super) fn apply_interrupt(&mut self) {
        if self.interrupt.applied {
            return;
        }
        self.interrupt.applied = true;
        let shift = self.interrupt.done;
        for (x, d) in self.exec.here.machine.iter_mut().zip(&shift) {
            *x -= d;
        }
        for (x, d) in self.exec.queued.machine.iter_mut().zip(&shift) {
            *x -= d;
        }
    }

    /// A manual intervention starts, or the program is over: `here` becomes where the machine
    /// stands (nothing moves; the pulse's move has ended).
    pub(super) fn release_interrupt(&mut self) {
        if !self.interrupt.applied {
            return;
        }
        self.end_interrupt_move();
        self.interrupt.applied = false;
        let shift = self.interrupt.done;
        for (x, d) in self.exec.here.machine.iter_mut().zip(&shift) {
            *x += d;
        }
        for (x, d) in self.exec.queued.machine.iter_mut().zip(&shift) {
            *x += d;
        }
    }

    /// The pulse's move stops where it is (emergency stop), or has ended.
    pub(super) fn end_interrupt_move(&mut self) {
        if self.interrupt.moving.is_some() {
            self.interrupt.done = self.interrupt.at(self.exec.time());
            self.interrupt.moving = None;
        }
    }

    /// After a tick: a pulse's move that has ended becomes part of the shift; a program that is
    /// over hands `here` back to the machine's coordinates.
    pub(super) fn settle_interrupt(&mut self) {
        if let Some((p, t0)) = &self.interrupt.moving {
            if self.exec.time() >= t0 + p.profile.duration() {
                self.interrupt.done = self.interrupt.last();
                self.interrupt.moving = None;
            }
        }
        let over = self.exec.is_idle()
            && self.stopping.is_none()
            && self.cycle.program_over()
            && self.interrupt.moving.is_none();
        if self.interrupt.applied && over {
            self.release_interrupt();
        }
    }

    /// Reference return clears the shift (FANUC clears the handle interrupt amount at the
    /// reference return): the program's point is derived again from where the machine stands.
    pub(super) fn clear_interrupt(&mut self) {
        if !self.interrupt.applied && !self.interrupt.is_zero() {
            self.interrupt.done = [0.0; MAX_AXES];
            self.stand_here();
            self.tell_machine_view();
        }
    }

    /// Handle pulses in AUTO/MDI while a program is under way (running, held or at a block
    /// stop): the manual handle interruption. What the select code and the 5-axis signals choose
    /// moves by `amount` as a shift over the program, at the handle clamp (No.1424), within the
    /// strokes (for the machine where it is and every point queued ahead, with the new shift);
    /// answers the amount taken. Discarded (0): the select code chooses nothing, an earlier
    /// pulse's move is still under way, a 5-axis feed while a block moving a rotary axis
    /// executes (S000-IV §2 note 2: "must not be generated"; no alarm is named), or any pulse
    /// in a cutter compensation for 5-axis machining (S000 §3.5.1: the manual handle
    /// interruption "cannot be used" there; no alarm is named).
    pub(super) fn handle_interrupt(&mut self, amount: f64) -> Result<f64, Refusal> {
        if self.estop || self.run_state == RunState::Alarm {
            return Err(Refusal::Busy);
        }
        if !self.interrupt.applied || self.cycle.intervening() {
            // No automatic operation under way: nothing to interrupt.
            return Err(Refusal::WrongMode);
        }
        if self.interrupt.moving.is_some() || self.in_five_axis_compensation() {
            return Ok(0.0);
        }
        let target = self.panel.manual_signals.handle_target(self.machine.kinematics().map(|k| &**k), &self.machine);
        if matches!(target, ManualTarget::Feed(_) | ManualTarget::TipRotation(_)) && self.rotary_block_under_way() {
            return Ok(0.0);
        }
        let from = self.moved_machine();
        let direction = match target {
            // The direction where the machine really stands (the shift may have turned it).
            ManualTarget::Feed(feed) => {
                let planned = std::mem::replace(&mut self.exec.here.machine, from);
                let d = self.manual_direction(feed);
                self.exec.here.machine = planned;
                Some(d?)
            }
            _ => None,
        };
        let Some(seg) = self.interrupt_segment(target, direction, &from, amount) else { return Ok(0.0) };
        // The largest part of the pulses that keeps the machine and the path ahead inside the
        // strokes with the new shift.
        let ahead: Vec<Pos> = self.path_ahead();
        let base = self.interrupt.at(self.exec.time());
        let fits = |seg: &Segment| {
            let (start, end) = (seg.from(), seg.to());
            let shift: Pos = std::array::from_fn(|i| base[i] + end[i] - start[i]);
            let sampled = (0..=16).map(|k| seg.at(seg.len * k as f64 / 16.0).0);
            let queued = ahead.iter().map(|p| std::array::from_fn(|i| p[i] + shift[i]));
            self.inside(sampled) && self.inside(queued)
        };
        let (seg, fraction) = if fits(&seg) {
            (seg, 1.0)
        } else {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                match self.interrupt_segment(target, direction, &from, amount * mid) {
                    Some(s) if fits(&s) => lo = mid,
                    _ => hi = mid,
                }
            }
            match self.interrupt_segment(target, direction, &from, amount * lo) {
                Some(s) => (s, lo),
                None => return Ok(0.0),
            }
        };
        let Some(planned) = self.exec.plan_alone(seg) else { return Ok(0.0) };
        self.interrupt.moving = Some((planned, self.exec.time()));
        self.tell_machine_view();
        Ok(amount * fraction)
    }

    /// The move of `amount` from `from` (machine coordinates) that the handle's target makes:
    /// the axis alone, X/Y/Z along the 5-axis feed direction where the machine stands, or the
    /// rotary axis about the tool tip. `None`: nothing moves.
    fn interrupt_segment(
        &self,
        target: ManualTarget,
        direction: Option<Vec3>,
        from: &Pos,
        amount: f64,
    ) -> Option<Segment> {
        let mut to = *from;
        match target {
            ManualTarget::Nothing => return None,
            ManualTarget::Axis(i) => to[i] += amount,
            ManualTarget::Feed(_) => {
                let (d, kin) = (direction?, self.machine.kinematics()?);
                for (axis, index) in kin.linear.iter().enumerate() {
                    if let Some(i) = index {
                        to[*i] += d[axis] * amount;
                    }
                }
            }
            ManualTarget::TipRotation(i) => {
                to[i] += amount;
                let length = self.manual_tool_length();
                let seg = self.exec.tip_rotation((from, from), &to, length, AT_CLAMP, &self.manual_limits())?;
                return (seg.len > 0.0).then_some(seg);
            }
        }
        let m = Motion {
            kind: MotionKind::Linear,
            target: to,
            machine: to,
            arc: None,
            tip: None,
            feed: AT_CLAMP,
            feed_mode: crate::canon::FeedMode::PerMinute,
            spindle: 0.0,
            context: MotionContext { fixed_feed: true, ..MotionContext::default() },
            speed_cap: f32::INFINITY,
            offset: None,
            no_look_ahead: false,
            block_limit: 0,
            notice: None,
        };
        // At the handle clamp whatever the overrides.
        let ctx = self.exec.feed_context(1.0, 1.0, true);
        let seg = self.exec.segment_from(&m, (from, from), ctx, &self.manual_limits());
        (seg.len > 0.0).then_some(seg)
    }

    /// The end points of the path still to run (the run under way from where the machine is,
    /// then what is queued), program coordinates.
    fn path_ahead(&self) -> Vec<Pos> {
        let mut out = vec![self.exec.here.machine];
        out.extend(self.exec.run_ahead().iter().map(|seg| seg.to()));
        out.extend(self.exec.queued_segments().map(|seg| seg.to()));
        out
    }

    fn inside(&self, mut points: impl Iterator<Item = Pos>) -> bool {
        points.all(|p| {
            self.machine.axes.iter().enumerate().all(|(i, axis)| {
                axis.stroke.is_none_or(|[lo, hi]| {
                    let tol = 1e-9 * (1.0 + hi.abs().max(lo.abs()));
                    p[i] >= lo - tol && p[i] <= hi + tol
                })
            })
        })
    }

    /// A block that moves a rotary axis of the mechanism is executing: the one the machine is
    /// in (moving, or held in it).
    fn rotary_block_under_way(&self) -> bool {
        let Some(kin) = self.machine.kinematics() else { return false };
        let seg = match self.exec.on() {
            Some((seg, _, _)) => Some(seg),
            None => self.exec.queued_segments().next().filter(|seg| seg.line == self.exec.here.line),
        };
        let Some(seg) = seg else { return false };
        let (from, to) = (seg.from(), seg.to());
        kin.head.iter().chain(&kin.table).filter_map(|j| j.index).any(|i| (to[i] - from[i]).abs() > 1e-9)
    }

    /// Whether the handle's pulses are a handle interruption (AUTO or MDI mode).
    pub(super) fn interrupting(&self) -> bool {
        matches!(self.mode, Mode::Auto | Mode::Mdi)
    }
}
