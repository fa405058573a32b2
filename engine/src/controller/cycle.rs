//! The program cycle of a [`super::Controller`] as one explicit state: where the program is in
//! its text ([`Blocks`]), what it waits for besides motion ([`Course`]), and whether the
//! operator has taken it over for a manual intervention ([`Cycle`]). The motion itself (the
//! run under way, what is queued, a deceleration) is the executor's and the controller's
//! `stopping`; the public `RunState` is set by the controller beside these transitions.
//!
//! Three layers, so that no flag can contradict another: a dwell or a stop always knows which
//! program it belongs to, and an intervention holds the whole course it interrupted (a dwell
//! or a block stop included) and cannot hold another intervention.

use super::manual::Intervention;
use super::Item;
use std::collections::VecDeque;

/// Where the program is in its text, and the commands it has read ahead of the machine.
pub(super) enum Blocks {
    /// No program under way, or it is over: read to its end and carried out.
    Off,
    /// The interpreter has blocks still to read; the commands read and not yet carried out.
    Reading(VecDeque<Item>),
    /// The interpreter has ended (M02/M30, the end of its text, an alarm): only the commands it
    /// read remain (perhaps none: the motion they queued still runs). Equivalent to `Off` once
    /// empty; the tick makes it `Off` when it finds nothing left ([`Cycle::over`]).
    Draining(VecDeque<Item>),
}

impl Blocks {
    /// The interpreter has more blocks to read.
    pub(super) fn reading(&self) -> bool {
        matches!(self, Blocks::Reading(_))
    }

    /// Commands read and not yet carried out.
    pub(super) fn ahead(&self) -> Option<&VecDeque<Item>> {
        match self {
            Blocks::Off => None,
            Blocks::Reading(q) | Blocks::Draining(q) => Some(q),
        }
    }

    pub(super) fn nothing_ahead(&self) -> bool {
        match self.ahead() {
            Some(q) => q.is_empty(),
            None => true,
        }
    }

    /// The program has more to do: blocks to read, or commands read and not yet carried out.
    pub(super) fn has_more(&self) -> bool {
        self.reading() || !self.nothing_ahead()
    }

    /// The next command to carry out.
    pub(super) fn pop(&mut self) -> Option<Item> {
        match self {
            Blocks::Off => None,
            Blocks::Reading(q) | Blocks::Draining(q) => q.pop_front(),
        }
    }

    /// A command read (at the back) or one that must wait (back at the front). Without a
    /// program the command is all that is left of one: draining.
    fn queue(&mut self) -> &mut VecDeque<Item> {
        if let Blocks::Off = self {
            *self = Blocks::Draining(VecDeque::new());
        }
        match self {
            Blocks::Reading(q) | Blocks::Draining(q) => q,
            Blocks::Off => unreachable!("made draining above"),
        }
    }

    pub(super) fn push(&mut self, item: Item) {
        self.queue().push_back(item);
    }

    pub(super) fn push_front(&mut self, item: Item) {
        self.queue().push_front(item);
    }

    /// The interpreter has ended: what it read is still carried out.
    pub(super) fn end_reading(&mut self) {
        if let Blocks::Reading(q) = self {
            *self = Blocks::Draining(std::mem::take(q));
        }
    }

    /// What was read ahead is dropped; the interpreter reads on if it was reading.
    pub(super) fn drop_ahead(&mut self) {
        if let Blocks::Reading(q) | Blocks::Draining(q) = self {
            q.clear();
        }
    }
}

/// The program's course besides motion: going on, or waiting for time or for the operator.
pub(super) enum Course {
    /// Nothing to wait for: the program (if any, `Blocks::Off` otherwise) goes on.
    Going(Blocks),
    /// A dwell or a tool change: the program goes on at `until` (controller time).
    Dwelling { until: f64, blocks: Blocks },
    /// M00/M01 or a single-block stop: cycle start goes on. An M00 carried out as the program
    /// ends (in its last block) leaves `Stopped(Off)`: the stop outlives the program until a
    /// cycle start or a reset.
    Stopped(Blocks),
}

impl Course {
    pub(super) fn blocks(&self) -> &Blocks {
        match self {
            Course::Going(b) | Course::Dwelling { blocks: b, .. } | Course::Stopped(b) => b,
        }
    }

    pub(super) fn blocks_mut(&mut self) -> &mut Blocks {
        match self {
            Course::Going(b) | Course::Dwelling { blocks: b, .. } | Course::Stopped(b) => b,
        }
    }

    fn take_blocks(&mut self) -> Blocks {
        std::mem::replace(self.blocks_mut(), Blocks::Off)
    }

    /// When the dwell under way ends.
    pub(super) fn dwell_end(&self) -> Option<f64> {
        match self {
            Course::Dwelling { until, .. } => Some(*until),
            _ => None,
        }
    }

    pub(super) fn stopped(&self) -> bool {
        matches!(self, Course::Stopped(_))
    }

    /// G04, a tool change: wait until `until` (replacing any other wait).
    pub(super) fn dwell(&mut self, until: f64) {
        let blocks = self.take_blocks();
        *self = Course::Dwelling { until, blocks };
    }

    /// M00/M01, a single-block stop: wait for cycle start (replacing any other wait).
    pub(super) fn stop(&mut self) {
        let blocks = self.take_blocks();
        *self = Course::Stopped(blocks);
    }

    /// Whatever the wait was, it is over.
    fn go_on(&mut self) {
        let blocks = self.take_blocks();
        *self = Course::Going(blocks);
    }

    /// The dwell's time is up: the program goes on.
    pub(super) fn dwell_over(&mut self) {
        if let Course::Dwelling { .. } = self {
            self.go_on();
        }
    }

    /// Cycle start at a stop (a dwell held by feed hold keeps its end time).
    pub(super) fn release_stop(&mut self) {
        if let Course::Stopped(_) = self {
            self.go_on();
        }
    }
}

/// The program cycle: the program's course on its own, or held under a manual intervention.
pub(super) enum Cycle {
    Program(Course),
    /// A manual intervention in a held program (JOG/HANDLE between feed hold or a block stop
    /// and the return to AUTO/MDI): the course it interrupted waits in `course`, unchanged but
    /// for an alarm or a dwell's time running out.
    Intervening {
        intervention: Box<Intervention>,
        course: Course,
    },
}

impl Cycle {
    /// No program, nothing to wait for.
    pub(super) const OFF: Cycle = Cycle::Program(Course::Going(Blocks::Off));

    /// The course of the program, held or not.
    pub(super) fn course(&self) -> &Course {
        match self {
            Cycle::Program(c) | Cycle::Intervening { course: c, .. } => c,
        }
    }

    pub(super) fn course_mut(&mut self) -> &mut Course {
        match self {
            Cycle::Program(c) | Cycle::Intervening { course: c, .. } => c,
        }
    }

    pub(super) fn blocks(&self) -> &Blocks {
        self.course().blocks()
    }

    pub(super) fn blocks_mut(&mut self) -> &mut Blocks {
        self.course_mut().blocks_mut()
    }

    pub(super) fn intervention(&self) -> Option<&Intervention> {
        match self {
            Cycle::Intervening { intervention, .. } => Some(intervention),
            Cycle::Program(_) => None,
        }
    }

    pub(super) fn intervening(&self) -> bool {
        matches!(self, Cycle::Intervening { .. })
    }

    /// A program reads its blocks on its own (not held for a manual intervention).
    pub(super) fn program_reading(&self) -> bool {
        matches!(self, Cycle::Program(c) if c.blocks().reading())
    }

    /// The program waits for cycle start at M00/M01 or a single-block stop.
    pub(super) fn at_operator_stop(&self) -> bool {
        self.course().stopped() && self.blocks().has_more()
    }

    /// Nothing of a program is left (no blocks, no commands, no intervention holding one);
    /// a wait may outlive it (`Course::Stopped`).
    pub(super) fn program_over(&self) -> bool {
        !self.intervening() && !self.blocks().has_more()
    }

    /// Cycle start runs a program from its start: blocks to read, nothing to wait for. What
    /// was read ahead stays (nothing is, when cycle start gets here).
    pub(super) fn start(&mut self) {
        let ahead = match self.course_mut().take_blocks() {
            Blocks::Off => VecDeque::new(),
            Blocks::Reading(q) | Blocks::Draining(q) => q,
        };
        *self.course_mut() = Course::Going(Blocks::Reading(ahead));
    }

    /// The tick found nothing more to read or carry out: the program is over.
    pub(super) fn over(&mut self) {
        if let Blocks::Draining(q) = self.blocks_mut() {
            if q.is_empty() {
                *self.blocks_mut() = Blocks::Off;
            }
        }
    }

    /// An alarm: nothing more is read or carried out (a wait stays until the reset).
    pub(super) fn abort(&mut self) {
        *self.blocks_mut() = Blocks::Off;
    }

    /// Reset, emergency stop: the program is abandoned.
    pub(super) fn abandon(&mut self) {
        *self = Cycle::OFF;
    }

    /// The operator takes over the held program (`Controller::set_mode`).
    pub(super) fn intervene(&mut self, intervention: Intervention) {
        let course = match std::mem::replace(self, Cycle::OFF) {
            Cycle::Program(c) | Cycle::Intervening { course: c, .. } => c,
        };
        *self = Cycle::Intervening { intervention: Box::new(intervention), course };
    }

    /// Back to the program's mode (its course goes on as it was), or a reset or an emergency
    /// stop ends the intervention: the intervention's record, if there was one.
    pub(super) fn end_intervention(&mut self) -> Option<Intervention> {
        match std::mem::replace(self, Cycle::OFF) {
            Cycle::Intervening { intervention, course } => {
                *self = Cycle::Program(course);
                Some(*intervention)
            }
            program => {
                *self = program;
                None
            }
        }
    }
}
