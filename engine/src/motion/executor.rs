//! The one place where canonical motions become motion: a motion is turned into a [`Segment`]
//! from where the last one ends (in the workpiece system of its block), checked against the
//! stored strokes and queued in the look-ahead [`Planner`]; the runs the planner releases are
//! executed one after the other on the executor's clock, and [`Executor::sample`] reads the
//! machine where it is (axes, tip by forward kinematics, feed, block).
//!
//! Two drivers use it: `crate::run` executes a program to its end and samples it every
//! interpolation period; `crate::controller` is the operator panel over it (ticks, feed hold,
//! overrides, manual moves). `crate::preview` uses its segment geometry without planning.
//! Time advances only by [`Executor::advance_to`] and [`Executor::idle_until`]: the engine reads
//! no clock.

use super::after::Filter;
use super::contact::{Contact, Contour};
use super::path::TurnCenter;
use super::{AxisLimits, Cursor, FeedContext, Limits, PathState, Planned, Planner, Point, Profile, Segment};
use crate::alarm::AlarmId;
use crate::canon::{Canon, Motion, Pos, TipMove};
use crate::kin::{Kinematics, Vec3};
use crate::machine::Machine;
use crate::tip::{Basis, System};
use std::sync::Arc;

/// One instant of the machine, as the trace, the controller's stream and the run report read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t: f64,
    pub line: u32,
    pub n: Option<u32>,
    /// Machine axes, rollover axes shown modulo 360.
    pub machine: Pos,
    /// Tool tip in the active workpiece system, from the machine axes and the tool length in
    /// effect by forward kinematics (`crate::tip`): where the machine puts it.
    pub tip: [f64; 3],
    /// Unit tool vector, tip toward holder, in the workpiece system (from the rotary axes).
    pub tool: [f64; 3],
    /// The same tip in the table frame (machine coordinates on a machine without table axes).
    pub tip_table: [f64; 3],
    /// The commanded point (X, Y, Z) in the system `programmed_in` names.
    pub programmed: [f64; 3],
    pub programmed_in: System,
    /// Tool tip speed relative to the workpiece, mm/min.
    pub feed: f64,
    /// Where the tool touches, in the workpiece system as `tip`, on the tool placed by the
    /// sampled axes (`motion::Segment::cutting_point`): under cutting point control (G43.8/G43.9)
    /// its lowest point along the surface normal; under a cutter compensation its side nearest to
    /// the programmed contour or G41.3's leading edge (`motion::contact`). `None` elsewhere.
    pub cutting: Option<[f64; 3]>,
    /// The number (in queue order) of the motion segment the machine is on; `None` standing.
    /// Several segments can share a line — a compensated corner's connecting moves, a block
    /// cut into pieces — and the axes' acceleration is bounded within a segment, not across
    /// a corner between two (`docs/motion.md`, "Corners").
    pub segment: Option<u64>,
}

/// Where the last queued motion ends: where the next one starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Endpoint {
    pub machine: Pos,
    /// The programmed position, in the workpiece system of `basis`.
    pub work: Pos,
    pub basis: Basis,
}

/// The run being executed: its plan, the time it started and where its samples are.
#[derive(Debug, Clone)]
struct Current {
    planned: Planned,
    start: f64,
    cursor: Cursor,
    /// Where the filter after interpolation reads the run (its ticks: `after::TICK_S`).
    tick_cursor: Cursor,
}

/// Acceleration/deceleration after interpolation (`motion::after`) on a machine that has it:
/// the filters of cutting feed and of rapids, the next tick of the interpolation period, and
/// which filter the motion under way (or last ended) passes through.
#[derive(Debug, Clone)]
struct After {
    feed: Option<Filter>,
    rapid: Option<Filter>,
    /// Index of the next tick: tick k is at k × `after::TICK_S`.
    tick: u64,
    /// The filter in use: true the rapids', false cutting feed's; `None`: neither.
    engaged: Option<bool>,
    /// The last run ended at rest (a stop): the machine waits there for the filter.
    at_rest: bool,
}

impl After {
    fn of(m: &Machine, at: &Pos) -> Option<After> {
        let (feed, rapid) = (Filter::of(m, at), Filter::of_rapid(m, at));
        (feed.is_some() || rapid.is_some()).then_some(After { feed, rapid, tick: 0, engaged: None, at_rest: true })
    }

    fn filter(&mut self, rapid: bool) -> Option<&mut Filter> {
        if rapid {
            self.rapid.as_mut()
        } else {
            self.feed.as_mut()
        }
    }

    fn active(&self) -> Option<&Filter> {
        match self.engaged? {
            true => self.rapid.as_ref(),
            false => self.feed.as_ref(),
        }
    }
}

/// How a deceleration to rest along the path began ([`Executor::brake`]).
#[derive(Debug, Clone, PartialEq)]
pub enum Braking {
    /// Nothing was moving.
    Idle,
    /// The run under way ends at rest as planned: a non-linear rapid (it cannot be slowed
    /// along a path: its axes finish their own profiles), or a run planned against the axes
    /// at every point too near the stop it makes to stop sooner.
    Finishing,
    /// The machine was at the very end of its path: it stands; `rest` is what was queued.
    AtEnd { rest: Vec<Segment> },
    /// A stop profile runs now, over the path ahead (queued segments included).
    Started,
}

/// A run executed to its end ([`Executor::finish`]).
#[derive(Debug, Clone)]
pub struct Finished {
    pub planned: Planned,
}

pub struct Executor {
    /// The machine: configuration, mechanism and the axis limits of program motion.
    machine: Arc<Machine>,
    planner: Planner,
    /// Simulated seconds.
    t: f64,
    current: Option<Current>,
    /// Where the machine is (machine axes before rollover display, programmed position).
    pub here: Point,
    pub queued: Endpoint,
    /// The tip basis of the last run's last segment (or of a command the machine stands in).
    last_basis: Basis,
    /// The tool length offset of the last run's last segment.
    last_tool_length: f64,
    /// Segments executed to their end so far.
    executed: u64,
    /// The filter after interpolation (`None`: no axis has a time constant).
    after: Option<After>,
    /// The axes' limits for cutting feed without look-ahead: the commanded feed at once
    /// (within two ticks), the machine's speeds.
    at_once: AxisLimits,
    /// Where the programmed contour of the last queued program motion ends under cutter
    /// compensation (table frame; `None`: at the tip where the motion ends).
    queued_contour: Option<Vec3>,
    /// The block ends (serial, line) single block switched on under way made stops in the path
    /// read ahead, where the program asked for none: switched off again, they go
    /// ([`Executor::clear_block_stops`]).
    block_stops: Vec<(u64, u32)>,
}

impl Executor {
    /// An executor standing at `machine` (programmed position `work` in `basis`) at time 0.
    pub fn new(machine: Arc<Machine>, start: Endpoint) -> Executor {
        let after = After::of(&machine, &start.machine);
        let at_once = at_once(machine.limits());
        Executor {
            planner: super::planner_for(&machine),
            machine,
            t: 0.0,
            current: None,
            here: Point { machine: start.machine, work: start.work, feed: 0.0, line: 0, n: None, s: 0.0 },
            queued: start,
            last_basis: start.basis,
            last_tool_length: 0.0,
            executed: 0,
            after,
            at_once,
            queued_contour: None,
            block_stops: Vec::new(),
        }
    }

    pub fn machine(&self) -> &Arc<Machine> {
        &self.machine
    }

    pub fn kinematics(&self) -> Option<&Arc<Kinematics>> {
        self.machine.kinematics()
    }

    /// From a program command of mechanism chain `chain` on (Syntec `G10 L5000`), its segments
    /// and the manual moves are made with that chain's mechanism. The interpreter refused a
    /// chain the machine cannot take, so one that has none leaves the machine as it is.
    pub fn follow_chain(&mut self, chain: crate::machine::Chain) {
        if chain != self.machine.chain() {
            if let Some(m) = self.machine.with_chain(chain) {
                self.machine = Arc::new(m);
            }
        }
    }

    /// The axis limits of program motion.
    pub fn axes(&self) -> &AxisLimits {
        self.machine.limits()
    }

    pub fn time(&self) -> f64 {
        self.t
    }

    /// Nothing is moving and nothing is queued.
    pub fn is_idle(&self) -> bool {
        self.current.is_none() && self.planner.is_empty()
    }

    /// A run is being executed, or at its stop the filter after interpolation still moves the
    /// axes.
    pub fn is_moving(&self) -> bool {
        self.current.is_some() || self.lagging()
    }

    /// Segments are queued, not yet released.
    pub fn has_queued(&self) -> bool {
        !self.planner.is_empty()
    }

    /// The segment the machine is on, with the distance along it and its number in queue order.
    pub fn on(&self) -> Option<(&Segment, f64, u64)> {
        let c = self.current.as_ref()?;
        let k = c.cursor.index();
        Some((&c.planned.segments[k], self.here.s - c.cursor.start(), self.executed + k as u64))
    }

    /// The segments ahead of the machine in the run being executed (the one it is on first).
    pub fn run_ahead(&self) -> &[Segment] {
        self.current.as_ref().map_or(&[], |c| &c.planned.segments[c.cursor.index()..])
    }

    /// Every segment queued and not yet released, in order.
    pub fn queued_segments(&self) -> impl Iterator<Item = &Segment> {
        self.planner.segments()
    }

    /// The tool length and tip basis of the last finished run's last segment.
    pub fn last_basis(&self) -> Basis {
        self.last_basis
    }

    /// How the tip is read where the machine stands: the segment's under way, else the last run's.
    pub fn basis(&self) -> Basis {
        self.on().map_or(self.last_basis, |(seg, _, _)| seg.tip_basis)
    }

    /// The tool length offset of the segment under way (of the last one when nothing moves).
    pub fn tool_length(&self) -> f64 {
        self.on().map_or(self.last_tool_length, |(seg, _, _)| seg.tool_length)
    }

    /// The machine stands in another block's workpiece system and tool length (a command that
    /// waits for the motion before it).
    pub fn stand_in(&mut self, basis: Basis) {
        self.last_basis = basis;
    }

    /// The feed context of a program motion under these overrides.
    pub fn feed_context(&self, feed_override: f64, rapid_override: f64, exact_stop: bool) -> FeedContext {
        FeedContext { feed_override, rapid_override, exact_stop, options: self.machine.motion }
    }

    /// The segment of motion `m` from the queued endpoint, within `axes`.
    pub fn segment_within(&self, m: &Motion, ctx: FeedContext, axes: &AxisLimits) -> Segment {
        self.segment_from(m, (&self.queued.machine, &self.queued.work), ctx, axes)
    }

    /// The segment of motion `m` from `from` (machine and programmed points), within `axes`: a
    /// manual move laid over the program (a handle interruption's pulse) starts where the
    /// machine is, not where the queue ends.
    pub fn segment_from(&self, m: &Motion, from: (&Pos, &Pos), ctx: FeedContext, axes: &AxisLimits) -> Segment {
        Segment::new(m, from.0, from.1, axes, ctx, self.machine.kinematics())
    }

    /// A rotation of the rotary axes from `from` to `to` about the tool tip (tool length
    /// `tool_length`) at `feed_deg_min`, within `axes` (`None` without a 5-axis mechanism).
    pub fn tip_rotation(
        &self,
        (from, work_from): (&Pos, &Pos),
        to: &Pos,
        tool_length: f64,
        feed_deg_min: f64,
        axes: &AxisLimits,
    ) -> Option<Segment> {
        let kin = self.machine.kinematics()?.clone();
        Some(Segment::tip_rotation(kin, from, work_from, to, tool_length, feed_deg_min, axes))
    }

    /// The plan of one segment on its own, from rest to rest (a handle interruption's pulse
    /// move, executed beside the program's runs).
    pub fn plan_alone(&self, seg: Segment) -> Option<Planned> {
        let mut planner = super::planner_for(&self.machine);
        planner.push(seg);
        planner.pop(true)
    }

    /// The segment of command `c`'s motion `m` (the command's, or a shifted copy of it) read in
    /// block `block`: from where the last queued one ends, restated in its block's workpiece
    /// system (the queued start stays restated; its end is not queued).
    fn segment_of(&mut self, c: &Canon, m: &Motion, ctx: FeedContext, block: u64) -> Segment {
        let before = std::mem::replace(&mut self.queued.basis, c.tip_basis);
        crate::tip::restate_start(&mut self.queued.work, &before, &c.tip_basis);
        let into_workpiece = c.tip_basis.programmed_in == crate::tip::System::Workpiece;
        if before.programmed_in != c.tip_basis.programmed_in && into_workpiece && m.tip.is_none() {
            // The programmed point came back to the workpiece system without a motion (G69
            // after a tilted plane, G49 after TCP): there a plain motion's programmed and
            // machine points differ by a translation (the offsets), so its start is where the
            // machine stands, moved by that.
            for (k, w) in self.queued.work.iter_mut().enumerate() {
                *w = self.queued.machine[k] + m.target[k] - m.machine[k];
            }
        }
        self.follow_chain(c.tip_basis.chain);
        // Cutting feed or rapids without look-ahead, on a machine with a filter after
        // interpolation for them: lines and arcs (a kinematic path keeps its planning, and a
        // non-linear rapid its axes' own profiles: docs/motion.md).
        let mut seg = self.segment_within(m, ctx, self.machine.limits());
        let filtered = self.after.as_mut().is_some_and(|a| a.filter(seg.rapid).is_some());
        if m.no_look_ahead && filtered && !seg.is_kinematic() && !seg.is_independent() {
            seg = self.segment_within(m, ctx, &self.at_once);
            seg.set_after_interpolation(true);
        }
        (seg.line, seg.n, seg.tip_basis, seg.block) = (c.line, c.n, c.tip_basis, block);
        seg.block_limit = m.block_limit;
        seg.contact = self.contact(m, &seg).map(Box::new);
        seg
    }

    /// Where a motion that a cutter compensation stage moved cuts (`motion::contact`): its
    /// piece of the programmed contour goes from where the last queued motion's programmed
    /// point ended to the tip where the block put the axes (`canon::Offset`), about the centre
    /// of its circle if it moves on one.
    fn contact(&self, m: &Motion, seg: &Segment) -> Option<Contact> {
        let o = m.offset.as_deref()?;
        let kin = self.machine.kinematics_of(seg.tip_basis.chain).map(|k| &**k);
        let tip = |p: &Pos| Vec3::from(crate::tip::locate(kin, p, &seg.tip_basis).table);
        let from = self.queued_contour.unwrap_or_else(|| tip(&self.queued.machine));
        let circle = seg.turn().map(|t| match t.center {
            TurnCenter::Tip(center) => (center, t.axis, t.sweep),
            // A circle of the axes turns in machine directions: the table's as it stands.
            TurnCenter::Axes(p) => (tip(&p), kin.map_or(t.axis, |k| k.table_frame(&p).r.transpose() * t.axis), t.sweep),
        });
        let contour = Contour::of(from, tip(&o.programmed_machine), circle);
        Some(Contact::new(contour, o.radius, o.touch))
    }

    /// The queued end moved to motion `m`'s, whose segment is `seg`.
    fn queued_to(&mut self, m: &Motion, seg: &Segment) {
        (self.queued.machine, self.queued.work) = (m.machine, m.target);
        self.queued_contour = seg.contact.as_ref().map(|c| c.contour_end());
    }

    /// The geometry of command `c`'s motion `m` as [`Executor::queue`] would queue it, without
    /// planning (a preview): the next one starts at its end.
    pub fn geometry(&mut self, c: &Canon, m: &Motion, ctx: FeedContext) -> Segment {
        let seg = self.segment_of(c, m, ctx, 0);
        self.queued_to(m, &seg);
        seg
    }

    /// Queue the motion `m` of command `c` (see [`Executor::segment_of`]). A motion that would
    /// cross a stroke limit (moved by `shift`, a handle interruption's) is not queued: its
    /// alarm is returned and the queued end stays. Without the check before movement (G54.4,
    /// `MotionContext::no_stroke_precheck`) the motion is queued up to where the axis reaches
    /// the limit, ending at rest there, and `Ok(Some(alarm))` tells the caller to raise the
    /// alarm when the machine has stopped. `queued` sees the segment before it is queued.
    pub fn queue(
        &mut self,
        c: &Canon,
        m: &Motion,
        ctx: FeedContext,
        block: u64,
        shift: Option<&Pos>,
        mut queued: impl FnMut(&Segment),
    ) -> Result<Option<AlarmId>, AlarmId> {
        self.checked_segments(c, m, ctx, block, shift, |exec, seg| {
            queued(&seg);
            exec.planner.push(seg);
        })
    }

    /// [`Executor::queue`]'s stroke check without the planner (`fivex check`): the alarm the
    /// run raises for motion `m` (before it moves, or where it stops at a limit without the
    /// check before movement), if any; the next motion starts at this one's end.
    pub fn check_strokes(&mut self, c: &Canon, m: &Motion, ctx: FeedContext) -> Result<(), AlarmId> {
        match self.checked_segments(c, m, ctx, 0, None, |_, _| {})? {
            Some(alarm) => Err(alarm),
            None => Ok(()),
        }
    }

    /// The segments of motion `m` as the machine runs them (a tool posture control motion
    /// through the singular posture in its parts), each checked against the stored strokes
    /// (moved by `shift`) and handed to `each` once all passed, the queued end then at the
    /// last; at the first limit crossed, its alarm, nothing handed on and the queued end left —
    /// or, without the check before movement, the part up to the limit handed on and the alarm
    /// to raise when the machine stands (`Ok(Some)`).
    fn checked_segments(
        &mut self,
        c: &Canon,
        m: &Motion,
        ctx: FeedContext,
        block: u64,
        shift: Option<&Pos>,
        mut each: impl FnMut(&mut Self, Segment),
    ) -> Result<Option<AlarmId>, AlarmId> {
        let check = |exec: &Self, seg: &Segment| match shift {
            Some(shift) => super::stroke_check_shifted(seg, &exec.machine, shift),
            None => super::stroke_check(seg, &exec.machine),
        };
        let Some(parts) = self.singular_parts(c, m) else {
            let seg = self.segment_of(c, m, ctx, block);
            if let Err(id) = check(self, &seg) {
                let stop = m.context.no_stroke_precheck.then(|| {
                    super::stroke_stop(&seg, &self.machine, shift.unwrap_or(&[0.0; crate::machine::MAX_AXES]))
                });
                let Some((head, alarm)) = stop.flatten() else { return Err(id) };
                (self.queued.machine, self.queued.work) = (head.to(), head.work_to());
                self.queued_contour = None;
                if head.len > 0.0 {
                    each(self, head);
                }
                return Ok(Some(alarm));
            }
            self.queued_to(m, &seg);
            each(self, seg);
            return Ok(None);
        };
        // All the block's parts or none.
        let (was, was_contour) = (self.queued, self.queued_contour);
        let mut segs = Vec::with_capacity(parts.len());
        for (k, part) in parts.iter().enumerate() {
            let mut seg = self.segment_of(c, part, ctx, block);
            // The free axis turns from rest to rest: the tip stands while it turns, and a
            // corner between the turn and the way would step the linear axes' speed.
            seg.stop_after |= k + 1 < parts.len();
            if let Err(id) = check(self, &seg) {
                (self.queued, self.queued_contour) = (was, was_contour);
                return Err(id);
            }
            self.queued_to(part, &seg);
            segs.push(seg);
        }
        for seg in segs {
            each(self, seg);
        }
        Ok(None)
    }

    /// A tool posture control motion from or to the singular posture as the machine runs it
    /// (`path::singular_turns`): the free axis turning with the tip standing, the way, and the
    /// free axis turning at its end, as they are needed; `None`: the motion as it is.
    fn singular_parts(&mut self, c: &Canon, m: &Motion) -> Option<Vec<Motion>> {
        let tip = m.tip.as_deref().filter(|t| t.posture.is_some() && m.offset.is_none())?;
        self.follow_chain(c.tip_basis.chain);
        let kin = self.machine.kinematics()?;
        let from = self.queued.machine;
        let turns = super::path::singular_turns(kin, tip, &from, &m.machine)?;
        // The carriage where the turned angles put the tip where it stands.
        let placed = |mut q: Pos, tip_at: Vec3| {
            let carriage = tip.carriage_for(kin, &q, tip_at);
            for (axis, index) in kin.linear.iter().enumerate() {
                if let Some(i) = index {
                    q[*i] = carriage[axis];
                }
            }
            q
        };
        let (lead, trail) = (turns.lead.map(|q| placed(q, tip.from)), turns.trail.map(|q| placed(q, tip.to)));
        let way = Some(Box::new(TipMove { posture: Some(turns.way), ..tip.clone() }));
        // A turn about the standing tip, as fast as the axes go (not a programmed rotary move).
        let standing = |at: Vec3| TipMove {
            from: at,
            to: at,
            arc: None,
            posture: None,
            posture_on_arc: false,
            rotary_feed: false,
            ..tip.clone()
        };
        // The programmed position with the rotary axes where `machine` has them (their
        // programmed values differ from the machine's by a constant offset); the tip, and so
        // the programmed X, Y, Z, stands.
        let shifted = |target: &Pos, machine_was: &Pos, machine: &Pos| -> Pos {
            let mut at = *target;
            for i in kin.joints().iter().filter_map(|j| j.index) {
                at[i] += machine[i] - machine_was[i];
            }
            at
        };
        let mut parts = Vec::with_capacity(3);
        if let Some(lead) = lead {
            let target = shifted(&self.queued.work, &from, &lead);
            let at = Box::new(standing(tip.from));
            parts.push(Motion { machine: lead, target, arc: None, tip: Some(at), ..m.clone() });
        }
        match trail {
            Some(trail) => {
                let target = shifted(&m.target, &m.machine, &trail);
                parts.push(Motion { machine: trail, target, tip: way, ..m.clone() });
                parts.push(Motion { arc: None, tip: Some(Box::new(standing(tip.to))), ..m.clone() });
            }
            None => parts.push(Motion { tip: way, ..m.clone() }),
        }
        Some(parts)
    }

    /// Queue a segment made elsewhere (a manual move) and take its end as the queued endpoint
    /// (the workpiece system stays).
    pub fn push(&mut self, seg: Segment) {
        (self.queued.machine, self.queued.work) = (seg.to(), seg.work_to());
        self.planner.push(seg);
    }

    /// Queue segments again as they are (the rest of a path after a stop); the queued endpoint
    /// does not move.
    pub fn requeue(&mut self, rest: Vec<Segment>) {
        for seg in rest {
            self.planner.push(seg);
        }
    }

    /// Everything queued and not released, the queue emptied (the next release starts at rest).
    pub fn take_queued(&mut self) -> Vec<Segment> {
        self.planner.take_all()
    }

    /// The next motion starts where the machine stands (programmed position `work` in `basis`).
    pub fn queue_from_here(&mut self, work: Pos, basis: Basis) {
        self.queued = Endpoint { machine: self.here.machine, work, basis };
        self.queued_contour = None;
    }

    /// Start the next run whose speeds are final, if nothing runs (`stop`: release everything
    /// queued, ending at rest). True when a run is under way after it.
    pub fn release(&mut self, stop: bool) -> bool {
        if self.current.is_none() {
            if let Some(p) = self.planner.pop(stop) {
                self.start(p);
            }
        }
        self.current.is_some()
    }

    fn start(&mut self, planned: Planned) {
        let which = planned.segments.first().filter(|s| s.after_interpolation()).map(|s| s.rapid);
        if let Some(a) = &mut self.after {
            if let Some(rapid) = which.filter(|w| a.engaged != Some(*w)) {
                // The machine is at rest here (look-ahead switched off, or from a rapid to
                // cutting feed: at a stop).
                if let Some(f) = a.filter(rapid) {
                    f.stand(&self.here.machine);
                }
            }
            (a.engaged, a.at_rest) = (which, false);
        }
        self.current =
            Some(Current { planned, start: self.t, cursor: Cursor::default(), tick_cursor: Cursor::default() });
    }

    /// Run the filter after interpolation over its ticks up to the clock: the run's
    /// interpolated positions at each tick in, or where the machine stands.
    fn tick(&mut self) {
        let Some(a) = &mut self.after else { return };
        loop {
            let tk = a.tick as f64 * super::after::TICK_S;
            if tk > self.t {
                return;
            }
            a.tick += 1;
            let Some(rapid) = a.engaged else { continue };
            let x = match &mut self.current {
                Some(c) if tk >= c.start => c.planned.point(tk - c.start, &mut c.tick_cursor).machine,
                _ => self.here.machine,
            };
            if let Some(f) = a.filter(rapid) {
                f.step(&x);
            }
        }
    }

    /// Where the axes are: the interpolated positions, through the filter after interpolation
    /// where it acts (the trace's and the report's machine: what the machine does).
    pub fn axes_now(&self) -> Pos {
        match self.after.as_ref().and_then(After::active) {
            Some(f) => f.output(),
            None => self.here.machine,
        }
    }

    /// At rest after a run, the filter after interpolation still moves the axes (its lag):
    /// the motion has not ended until they are within `after::SETTLED` of the end.
    pub fn lagging(&self) -> bool {
        self.current.is_none()
            && self.after.as_ref().is_some_and(|a| a.at_rest && a.active().is_some_and(|f| !f.settled()))
    }

    /// Tick the filter toward `until` while it lags at a stop; the clock stops at the tick it
    /// settles on (the motion ends there, and the next one starts then).
    fn settle_to(&mut self, until: f64) {
        while self.lagging() {
            let next = self.next_tick();
            if next > until {
                break;
            }
            self.t = next;
            self.tick();
        }
        if self.lagging() {
            self.t = self.t.max(until);
            self.tick();
        }
    }

    /// The time of the next tick of the interpolation period (the filter's), or the clock's
    /// where there is no filter.
    pub fn next_tick(&self) -> f64 {
        match &self.after {
            Some(a) => (a.tick as f64 * super::after::TICK_S).max(self.t),
            None => self.t,
        }
    }

    /// When the run under way ends.
    pub fn run_end(&self) -> Option<f64> {
        self.current.as_ref().map(|c| c.start + c.planned.profile.duration())
    }

    /// Move the clock to `until`, at most to the end of the run under way (standing still,
    /// to `until`); the machine is then where the run puts it.
    pub fn advance_to(&mut self, until: f64) {
        let Some(c) = &mut self.current else {
            if self.lagging() {
                self.settle_to(until);
                return;
            }
            self.t = self.t.max(until);
            self.tick();
            return;
        };
        let end = c.start + c.planned.profile.duration();
        self.t = until.min(end).max(self.t);
        self.here = c.planned.point(self.t - c.start, &mut c.cursor);
        self.tick();
    }

    /// The run under way, if the clock has reached its end: it is over.
    pub fn finish(&mut self) -> Option<Finished> {
        if self.run_end()? > self.t {
            return None;
        }
        let Current { planned, .. } = self.current.take()?;
        self.executed += planned.segments.len() as u64;
        if let Some(last) = planned.segments.last() {
            (self.last_basis, self.last_tool_length) = (last.tip_basis, last.tool_length);
        }
        if planned.profile.end_speed().abs() < 1e-9 {
            self.here.feed = 0.0;
            if let Some(a) = &mut self.after {
                a.at_rest = true;
            }
        }
        Some(Finished { planned })
    }

    /// The run ended on its last point exactly (not a stop part-way along it).
    pub fn arrive(&mut self, finished: &Finished) {
        if let Some(last) = finished.planned.segments.last() {
            (self.here.machine, self.here.work) = (last.to(), last.work_to());
        }
    }

    /// Stand still until `until` (a dwell, a tool change).
    pub fn idle_until(&mut self, until: f64) {
        debug_assert!(self.current.is_none());
        self.t = self.t.max(until);
        self.tick();
    }

    /// Stop at once where the machine is (emergency stop): nothing runs or is queued.
    pub fn halt(&mut self) {
        self.current = None;
        self.planner.take_all();
        self.here.feed = 0.0;
        if let Some(a) = &mut self.after {
            // The axes stop where they are.
            if let Some(f) = a.active() {
                self.here.machine = f.output();
            }
            for f in [&mut a.feed, &mut a.rapid].into_iter().flatten() {
                f.stand(&self.here.machine);
            }
        }
    }

    /// Decelerate to rest along the path, within the limits of every segment the stop covers;
    /// the rest of the path after the stop point comes with the run when it ends.
    pub fn brake(&mut self) -> Braking {
        let Some(c) = self.current.take() else { return Braking::Idle };
        if c.planned.segments.first().is_some_and(Segment::is_independent) {
            self.current = Some(c);
            return Braking::Finishing;
        }
        let state = c.planned.profile.at(self.t - c.start);
        let mut rest = c.planned.rest(state.s);
        let in_run = rest.len();
        rest.extend(self.planner.take_all());
        if rest.is_empty() {
            self.here.feed = 0.0;
            return Braking::AtEnd { rest };
        }
        // A run planned against the axes at every point may be faster than its path limits:
        // its stop is planned the same way, within what is left of it.
        let tabled = c.planned.profile.is_tabled();
        let planned_stop = tabled.then(|| {
            // Up to the next exact stop: the machine must be at rest there.
            let end = rest.iter().position(|s| s.stop_after).map_or(rest.len(), |k| k + 1);
            let path: Vec<&Segment> = rest[..end].iter().collect();
            super::optimal::stop(&path, &self.planner.corners(&path), state.v, state.a, self.machine.limits())
        });
        let profile = match planned_stop.flatten() {
            Some(profile) => profile,
            None => {
                let lim = stop_limits(&rest, state.v, state.a);
                // Still accelerating: the acceleration's return to zero raises the speed by
                // a²/2J first; with the lower jerk of later segments that could pass the speed
                // where the machine is. That first turn may use the jerk of the segment it is on.
                let here = &rest[0];
                let turning = state.a > 0.0 && state.v + state.a * state.a / (2.0 * lim.j) > here.limits.v;
                let first = if turning { here.limits.j } else { lim.j };
                let stop = Profile::stop_turning(state.v, state.a, &lim, first);
                // A run planned at every point may be faster than the path limits that stop
                // uses; and that stop may not end before the exact stop ahead. Where the run
                // itself ends at rest, it is the stop (too near the one it is planned to make);
                // where the stop would run past the exact stop, the plan to it is.
                let overruns = stop.len() > to_next_stop(&rest).1 + 1e-9;
                if (tabled || overruns) && c.planned.profile.end_speed() <= 0.0 {
                    self.planner.continue_at(0.0);
                    self.requeue(rest.split_off(in_run));
                    self.current = Some(c);
                    return Braking::Finishing;
                }
                // The plan itself, to the exact stop ahead, where it ends at rest.
                let planned = if overruns { self.plan_to_stop(&c, state.s, &rest, in_run) } else { None };
                planned.unwrap_or(stop)
            }
        };
        self.start(Planned { segments: rest, profile });
        Braking::Started
    }

    /// The motion as planned from where run `c` is (distance `s` into it) to the next exact
    /// stop in `rest` (the run's rest, its first `in_run`, and what was queued), where it ends
    /// at rest: the run's own profile, then the runs a fresh plan of the queued segments up to
    /// that stop gives. `None` when the stop is not beyond the run or the pieces do not join.
    fn plan_to_stop(&self, c: &Current, s: f64, rest: &[Segment], in_run: usize) -> Option<Profile> {
        let end = rest.iter().position(|seg| seg.stop_after)? + 1;
        if end <= in_run {
            return None;
        }
        let mut phases = c.planned.profile.phases_after(self.t - c.start);
        let mut offset = c.planned.profile.len() - s;
        let mut plan = self.planner.fresh();
        plan.continue_at(c.planned.profile.end_speed());
        for seg in &rest[in_run..end] {
            plan.push(seg.clone());
        }
        while let Some(run) = plan.pop(true) {
            let shift = offset;
            phases.extend(
                run.profile.phases_after(0.0).into_iter().map(|(d, j, x)| (d, j, PathState { s: x.s + shift, ..x })),
            );
            offset += run.profile.len();
        }
        let profile = Profile::tabled(phases, offset, 0.0);
        profile.is_continuous(1e-9).then_some(profile)
    }

    /// New overrides: every queued segment takes them; the run under way changes speed at
    /// once within the limits when it can be sure of keeping to every junction and stop ahead
    /// after the change (true: a transition runs now, and its end hands the rest of the path
    /// back with [`Executor::resume`]); otherwise it ends as planned and the rest takes them.
    pub fn set_overrides(&mut self, feed: f64, rapid: f64) -> bool {
        let Some(c) = self.current.take() else {
            // Between runs (or at rest): what is queued takes the new speed from here.
            let v = self.planner.speed();
            let queued = self.planner.take_all();
            self.planner.continue_at(v);
            for mut seg in queued {
                seg.set_override(feed, rapid);
                self.planner.push(seg);
            }
            return false;
        };
        let state = c.planned.profile.at(self.t - c.start);
        let mut rest = c.planned.rest(state.s);
        let in_run = rest.len();
        rest.extend(self.planner.take_all());
        for seg in &mut rest {
            seg.set_override(feed, rapid);
        }
        let Some(first) = rest.first() else {
            self.current = Some(c);
            return false;
        };
        let (lim, _) = to_next_stop(&rest);
        let transition = Profile::transition(state.v, state.a, first.limits.v, &lim);
        // Where the transition ends, the machine must still be able to keep to every junction
        // and exact stop ahead.
        let after = Planned { segments: rest.clone(), profile: transition.clone() }.rest(transition.len());
        let fits = transition.end_speed() <= self.planner.entry_speed(&after) + 1e-9;
        // A run planned against the axes at every point (its path limits may be below where
        // it is) changes speed only when it ends.
        let tabled = c.planned.profile.is_tabled();
        if state.a < 0.0 || !fits || tabled || c.planned.segments[0].is_independent() {
            // Braking already, too near a junction or stop to be sure of keeping to it after
            // the change, a run planned at every point, or a non-linear rapid: the run under way ends as planned, the rest
            // takes the override.
            self.planner.continue_at(c.planned.profile.end_speed());
            self.requeue(rest.split_off(in_run));
            self.current = Some(c);
            return false;
        }
        self.start(Planned { segments: rest, profile: transition });
        true
    }

    /// Single block switched on under way: every block end from the first the machine can
    /// reach at rest within its limits becomes an exact stop — in the run under way (replanned
    /// to end at rest there: a run holds every block of a stretch without a binding corner, a
    /// line of collinear blocks as one move), at its end, and in what is queued. `complete`:
    /// the serial of the last block the program has read to its end, so that the end of what
    /// is queued is a block end when its block is that one or earlier. True when the run under
    /// way was replanned (it ends at rest at the stop).
    pub fn stop_at_block_ends(&mut self, complete: u64) -> bool {
        let v = self.current.as_ref().map_or(self.planner.speed(), |c| c.planned.profile.end_speed());
        let mut queued = self.planner.take_all();
        let replanned = self.stop_in_run(&mut queued, complete);
        let v = if replanned { 0.0 } else { v };
        let need = match queued.is_empty() {
            true => 0.0,
            false => Profile::stop(v, 0.0, &stop_limits(&queued, v, 0.0)).len(),
        };
        mark_block_ends(&mut queued, need, complete, &mut self.block_stops);
        self.planner.continue_at(v);
        self.requeue(queued);
        replanned
    }

    /// Single block switched off again under way: the block ends it marked in the path read
    /// ahead stop no more (those the program asked for, G09/G61/rapids, stay), and that path is
    /// planned again from the speed the run under way ends with. The run under way keeps its
    /// end: the machine may already be braking for it.
    pub fn clear_block_stops(&mut self) {
        let marked = std::mem::take(&mut self.block_stops);
        let ours = |seg: &Segment| seg.stop_after && marked.contains(&(seg.block, seg.line));
        if !self.planner.segments().any(ours) {
            return;
        }
        let v = self.current.as_ref().map_or(self.planner.speed(), |c| c.planned.profile.end_speed());
        let mut queued = self.planner.take_all();
        for k in 0..queued.len() {
            // The block's last segment (a kinematic path is queued in pieces).
            let last = queued.get(k + 1).is_none_or(|n| (n.block, n.line) != (queued[k].block, queued[k].line));
            if last && ours(&queued[k]) {
                queued[k].stop_after = false;
            }
        }
        self.planner.continue_at(v);
        self.requeue(queued);
    }

    /// [`Executor::stop_at_block_ends`] in the run under way: the first block end in its rest
    /// that the machine can stop at from where it is (`Profile::stop_at`, within the lowest
    /// limits of the way there) becomes the end of the run, at rest; the rest of the run goes
    /// to the front of `queued` (true). The run stays as it is (false) where no block end in
    /// it is far enough, it already ends at rest at one, or its motion is not a path profile
    /// to cut short (a non-linear rapid, a run planned against the axes at every point).
    fn stop_in_run(&mut self, queued: &mut Vec<Segment>, complete: u64) -> bool {
        let Some(c) = self.current.as_mut() else { return false };
        if c.planned.profile.is_tabled() || c.planned.segments.first().is_none_or(Segment::is_independent) {
            return false;
        }
        let state = c.planned.profile.at(self.t - c.start);
        let mut rest = c.planned.rest(state.s);
        let (mut len, mut lim) = (0.0, rest.first().map_or(c.planned.segments[0].limits, |s| s.limits));
        for k in 0..rest.len() {
            (len, lim) = (len + rest[k].len, lim.min(rest[k].limits));
            if !block_end(&rest[k], rest.get(k + 1).or(queued.first()), complete) {
                continue;
            }
            if k + 1 == rest.len() && c.planned.profile.end_speed() <= 0.0 {
                // The run ends at rest there as planned.
                if let Some(last) = c.planned.segments.last_mut() {
                    last.stop_after = true;
                }
                return false;
            }
            if let Some(profile) = Profile::stop_at(state.v, state.a, len, &lim) {
                let after = rest.split_off(k + 1);
                rest[k].stop_after = true;
                queued.splice(0..0, after);
                self.start(Planned { segments: rest, profile });
                return true;
            }
        }
        false
    }

    /// After a stop or a speed change that ended at `speed` with `rest` of the path ahead:
    /// queue the rest again, moving on at that speed.
    pub fn resume(&mut self, rest: Vec<Segment>, speed: f64) {
        self.planner.continue_at(speed);
        self.requeue(rest);
    }

    /// The machine where it is now, read as the trace reads it: the sample at time `t`
    /// (the clock's, or a sample time the run passes through) with the tip by forward
    /// kinematics of `machine` (the axes as they stand; a handle interruption's shift in them).
    pub fn sample(&self, t: f64, machine: &Pos, basis: &Basis) -> Sample {
        let placed = crate::tip::locate(self.machine.kinematics_of(basis.chain).map(|k| &**k), machine, basis);
        let o = basis.origin;
        let (tip, tool) = (Vec3::from(placed.table), Vec3::from(placed.tool));
        let on = self.on();
        let cutting = on
            .and_then(|(seg, s, _)| seg.cutting_point(s, machine, tip, tool))
            .map(|p| [p.x - o[0], p.y - o[1], p.z - o[2]]);
        Sample {
            t,
            line: self.here.line,
            n: self.here.n,
            machine: self.machine.shown(machine),
            tip: placed.tip,
            tool: placed.tool,
            tip_table: placed.table,
            programmed: [self.here.work[0], self.here.work[1], self.here.work[2]],
            programmed_in: basis.programmed_in,
            feed: self.here.feed,
            cutting,
            segment: on.map(|(_, _, k)| k),
        }
    }
}

/// The axes' limits of cutting feed without look-ahead: each axis's speed, its acceleration
/// that speed per tick of the interpolation period and its jerk that per tick again, so a
/// jerk-limited profile reaches any feed within two ticks (2·√(Δv/J) ≤ 2 ticks for Δv ≤ v):
/// the commanded feed at once, as the control interpolates it; the filter after interpolation
/// is what accelerates the axes.
fn at_once(axes: &AxisLimits) -> AxisLimits {
    let tick = super::after::TICK_S;
    let mut l = axes.clone();
    for i in 0..l.count {
        l.a[i] = l.v[i] / tick;
        l.j[i] = l.a[i] / tick;
    }
    l
}

/// The lowest limits of the segments up to the next place the machine must stop at (an exact
/// stop, or the end of the path), and the distance to it.
fn to_next_stop(path: &[Segment]) -> (Limits, f64) {
    let mut lim = path[0].limits;
    let mut room = 0.0;
    for seg in path {
        lim = lim.min(seg.limits);
        room += seg.len;
        if seg.stop_after {
            break;
        }
    }
    (lim, room)
}

/// The limits for the quickest stop from speed `v` and acceleration `a` along `path`: those
/// of every segment the stop covers, as long as it still ends before the next exact stop and
/// the braking under way can end at rest with their jerk (the motion was planned to stop there
/// with the limits of the segments before it, so those always do).
fn stop_limits(path: &[Segment], v: f64, a: f64) -> Limits {
    let (_, boundary) = to_next_stop(path);
    let mut lim = path[0].limits;
    let mut covered = path[0].len;
    for seg in &path[1..] {
        if Profile::stop(v, a, &lim).len() <= covered || covered >= boundary {
            break;
        }
        let next = lim.min(seg.limits);
        if (a < 0.0 && a * a > 2.0 * next.j * v) || Profile::stop(v, a, &next).len() > boundary {
            break;
        }
        lim = next;
        covered += seg.len;
    }
    lim
}

/// Whether `seg` ends its block: the segment after it (`next`) is another block's, or nothing
/// follows and its block was read to its end (serial `complete` or before). Another line is
/// another block too: a path stage releases a block it held with the one read after it, both
/// under the later block's serial (cutter compensation: the block before a G40).
pub(crate) fn block_end(seg: &Segment, next: Option<&Segment>, complete: u64) -> bool {
    next.map_or(seg.block <= complete, |n| n.block != seg.block || n.line != seg.line)
}

/// Every block end of `path` at least `need` from its start becomes an exact stop (`complete`:
/// [`block_end`]'s); those that were not stops already are added to `marked`.
fn mark_block_ends(path: &mut [Segment], need: f64, complete: u64, marked: &mut Vec<(u64, u32)>) {
    let mut s = 0.0;
    for k in 0..path.len() {
        s += path[k].len;
        if s >= need - 1e-9 && block_end(&path[k], path.get(k + 1), complete) && !path[k].stop_after {
            path[k].stop_after = true;
            marked.push((path[k].block, path[k].line));
        }
    }
}
