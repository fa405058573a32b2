//! 5-axis manual operation of a [`Controller`] (`docs/five-axis.md`, 5-axis manual operation):
//! FANUC's 5-axis JOG/HANDLE feeds with their settings (`MachineConfig.manual`), manual
//! intervention in a held program with manual absolute on or off, Syntec's manual RTCP
//! registers R518/R519.

use super::signals::{signal_axis, ManualTarget};
use super::{Controller, Mode, Refusal, RunState};
use crate::alarm::AlarmId;
use crate::canon::{Motion, MotionKind, Pos};
use crate::kin::{latitude_longitude, ManualFeed, Vec3};
use crate::machine::{ManualOptions, ManualVertical};
use crate::motion::{AxisLimits, Segment};

/// The feed of handle pulses: higher than any axis goes, so the manual rapid rates (No.1424)
/// set the speed; the feed override does not act on it (`Controller::push_manual`).
pub(super) const AT_CLAMP: f64 = 1.0e9;

/// Syntec R518: the coordinate system of manual X/Y/Z moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema), schema(as = CoordinatesName))]
#[serde(rename_all = "lowercase")]
pub enum ManualCoordinates {
    /// R518 = 0: each axis on its own.
    #[default]
    Machine,
    /// R518 = 1: the programming coordinate system (turning with the table under tool centre
    /// point control, the tilted working plane's axes in one).
    Program,
    /// R518 = 2: the tool's (X, Y: right-angle directions 1 and 2, Z: the tool axis).
    Tool,
}

/// A held program while the operator moves the machine by hand.
pub(super) struct Intervention {
    /// The mode to come back to, and whether the program was held (or at a block stop).
    pub(super) mode: Mode,
    pub(super) held: bool,
    /// Where the machine stood.
    pub(super) start: Pos,
    /// The rest of the path, and where it ends.
    pub(super) path: Vec<Segment>,
    pub(super) queued: (Pos, Pos),
}

/// The shift of manual absolute off (FANUC MAN-02/03): every axis by `machine`; a tool tip path
/// (TCP, tilted working plane) by `tip` in the table frame.
#[derive(Debug, Clone, Copy)]
pub(super) struct Shift {
    pub(super) machine: Pos,
    pub(super) tip: Vec3,
}

impl Controller {
    /// Back from a manual intervention: the held path goes on from where the machine stands,
    /// to the programmed end point (manual absolute on) or shifted by the intervention (off).
    pub(super) fn end_intervention(&mut self) {
        let Some(i) = self.cycle.end_intervention() else { return };
        // Back to the program's coordinates (a handle interruption's shift stays over them).
        self.apply_interrupt();
        self.mode = i.mode;
        let here = self.exec.here.machine;
        let moved: Pos = std::array::from_fn(|k| here[k] - i.start[k]);
        let mut path = i.path;
        (self.exec.queued.machine, self.exec.queued.work) = i.queued;
        if moved.iter().any(|d| d.abs() > 1e-9) {
            if !self.panel.manual_absolute {
                let shift = self.intervention_shift(&i.start, &moved);
                if let Some(seg) = path.iter().find(|seg| seg.is_tip_path() && self.turns_rotary(&shift)) {
                    // The rest of the block under way is a tool tip path (`refuses_on_tip_path`).
                    let (line, n) = (seg.line, seg.n);
                    (self.exec.queued.machine, self.exec.queued.work) = (here, self.exec.here.work);
                    self.raise(AlarmId::RotaryShiftOnTipPath, line, n);
                    return;
                }
                path = path.iter().map(|seg| seg.shifted(&shift.machine, shift.tip)).collect();
                if let Some(last) = path.last() {
                    (self.exec.queued.machine, self.exec.queued.work) = (last.to(), last.work_to());
                } else {
                    (self.exec.queued.machine, self.exec.queued.work) = (here, self.exec.here.work);
                }
                self.shift = Some(match self.shift {
                    Some(s) => Shift {
                        machine: std::array::from_fn(|k| s.machine[k] + shift.machine[k]),
                        tip: s.tip + shift.tip,
                    },
                    None => shift,
                });
            } else if path.is_empty() {
                // At a block stop: the next block starts where the machine is.
                (self.exec.queued.machine, self.exec.queued.work) = (here, self.exec.here.work);
                self.reposition = true;
            }
            let continues =
                path.first().is_some_and(|seg| seg.from().iter().zip(&here).all(|(a, b)| (a - b).abs() < 1e-9));
            if !path.is_empty() && !continues {
                // The rest of the block under way becomes one straight move to its end.
                let line = path[0].line;
                let block = path.iter().take_while(|seg| seg.line == line).count();
                let seg = self.straight(here, self.exec.here.work, &path[block - 1]);
                path.splice(0..block, [seg]);
            }
            // Where a shifted path meets one that was not (a move in machine coordinates), the
            // later block goes straight from where the earlier one ends.
            for k in 1..path.len() {
                let (to, work_to) = (path[k - 1].to(), path[k - 1].work_to());
                if path[k].from().iter().zip(&to).any(|(a, b)| (a - b).abs() > 1e-9) {
                    path[k] = self.straight(to, work_to, &path[k]);
                }
            }
        }
        self.exec.requeue(path);
        if i.held {
            self.set_state(RunState::Hold);
        }
    }

    /// A straight move (all axes linear) from `from` to the end of `end`, at its programmed feed
    /// (its rapid if it is one), standing in for it.
    fn straight(&mut self, from: Pos, from_work: Pos, end: &Segment) -> Segment {
        let m = Motion::straight(end.rapid, end.work_to(), end.to(), end.programmed_feed());
        let queued = (self.exec.queued.machine, self.exec.queued.work);
        (self.exec.queued.machine, self.exec.queued.work) = (from, from_work);
        let mut seg = self.segment(&m);
        (seg.line, seg.n, seg.stop_after, seg.tip_basis) = (end.line, end.n, end.stop_after, end.tip_basis);
        (self.exec.queued.machine, self.exec.queued.work) = queued;
        seg
    }

    /// What a manual intervention from `start` that moved the axes by `moved` shifts: every
    /// axis of plain motions by `moved`; a tool tip path by the tip's displacement seen from
    /// the table (a rotary axis moved by hand shifts the tool centre point, MAN-02; on table
    /// machines the shift turns with the table, MAN-03).
    pub(super) fn intervention_shift(&self, start: &Pos, moved: &Pos) -> Shift {
        let tip = match self.machine.kinematics() {
            Some(kin) => {
                let length = self.interp.active_length_offset().unwrap_or(0.0);
                kin.forward(&self.exec.here.machine, length).tip - kin.forward(start, length).tip
            }
            None => Vec3::zeros(),
        };
        Shift { machine: *moved, tip }
    }

    /// Whether a shift of manual absolute off turned a rotary axis of the mechanism.
    fn turns_rotary(&self, shift: &Shift) -> bool {
        let Some(kin) = self.machine.kinematics() else { return false };
        let mut rotary = kin.head.iter().chain(&kin.table).filter_map(|j| j.index);
        rotary.any(|i| shift.machine[i].abs() > 1e-9)
    }

    /// A program motion refused after a manual intervention with manual absolute off turned a
    /// rotary axis (FX0007, decision, `docs/five-axis.md`): on a tool tip path (tool centre
    /// point control, the tilted working plane). The manual says the later end points get the
    /// intervention added and the turn shifts the tool centre point (S000 IV §1.1, MAN-02), and
    /// the TCP manual that the compensation vector comes from the rotary position before the
    /// intervention; how that vector follows a block that turns the axis, and what a table
    /// machine keeps "on the table coordinate system" (MAN-03) for a turned table, it does not
    /// say. Carrying the tip shift with the axis at its programmed angle turned the axis by the
    /// amount in the next block without tool tip path (G49), so the case is refused instead.
    pub(super) fn refuses_on_tip_path(&self, shift: &Shift, m: &Motion) -> bool {
        m.tip.is_some() && m.kind != MotionKind::MachineRapid && self.turns_rotary(shift)
    }

    /// Syntec R518: the direction (machine coordinates) manual moves of axis `i` follow when it
    /// is X, Y or Z and the choice is not the machine's. Program coordinates: the tilted working
    /// plane's axes, or under tool centre point control the table's (they turn with it),
    /// otherwise the machine's; tool coordinates: right-angle directions 1, 2 and the tool axis.
    pub(super) fn coordinate_direction(&self, i: usize) -> Option<Vec3> {
        let kin = self.machine.kinematics()?;
        let k = kin.linear.iter().position(|&index| index == Some(i))?;
        match self.panel.manual_coordinates {
            ManualCoordinates::Machine => None,
            ManualCoordinates::Program => {
                if let Some(axes) = self.interp.plane_axes(&self.exec.here.machine) {
                    return Some(axes[k]);
                }
                let r = if self.interp.tcp_on() {
                    kin.table_frame(&self.exec.here.machine).r
                } else {
                    nalgebra::Matrix3::identity()
                };
                Some(r.column(k).into())
            }
            ManualCoordinates::Tool => {
                let d = kin.manual_directions(&self.exec.here.machine);
                Some([d.right_angle[0], d.right_angle[1], d.tool][k])
            }
        }
    }

    /// Syntec R519: the tool length rotary axis `i` turns about when manual RTCP is on under
    /// tool centre point control (the active offset; none: the spindle nose stays).
    pub(super) fn rtcp_length(&self, i: usize) -> Option<f64> {
        let kin = self.machine.kinematics()?;
        let rotary = kin.head.iter().chain(&kin.table).any(|j| j.index == Some(i));
        (self.panel.manual_rtcp && rotary && self.interp.tcp_on())
            .then(|| self.interp.active_length_offset().unwrap_or(0.0))
    }

    /// JOG along a 5-axis manual feed direction (tool axis, its right angles, table vertical
    /// or horizontal; `kin::ManualDirections`, `ManualOptions`), at the 5-axis jog feed
    /// ([`Controller::manual_jog_feed`]), until jog stop or the strokes.
    /// In INC mode by the panel's increment (FANUC's incremental feed of the same families).
    pub fn jog_direction(&mut self, feed: ManualFeed, positive: bool) -> Result<(), Refusal> {
        let reach = self.jog_reach()?;
        let d = self.manual_direction(feed)?;
        let axis = self.machine.kinematics().and_then(|k| signal_axis(k, feed));
        self.move_along(if positive { d } else { -d }, reach, self.manual_jog_feed_of(axis))
    }

    /// HANDLE along a 5-axis manual feed direction by `amount` mm (stopping at the strokes).
    pub fn handle_direction(&mut self, feed: ManualFeed, amount: f64) -> Result<(), Refusal> {
        if self.mode != Mode::Handle {
            return Err(Refusal::WrongMode);
        }
        if !amount.is_finite() {
            return Err(Refusal::BadValue);
        }
        let d = self.manual_direction(feed)?;
        self.move_along(if amount < 0.0 { -d } else { d }, amount.abs(), self.panel.jog_feed)
    }

    /// JOG tool tip centre rotation (FANUC MAN-12): turn rotary `axis` while X/Y/Z keep the
    /// tool tip (MAN-13's length) where it is on the table, until jog stop or a stroke. JFR:
    /// the rotary axis at the jog feed, deg/min; otherwise the linear axes' resultant at the
    /// dry run rate (with the override).
    /// In INC mode the rotary axis turns by the panel's increment, degrees.
    pub fn jog_tip_rotation(&mut self, axis: char, positive: bool) -> Result<(), Refusal> {
        let turn = self.jog_reach()?.min(360.0);
        let o = &self.machine.manual;
        let linear = (!o.jog_feedrate && o.dry_run_feed > 0.0).then_some(o.dry_run_feed * self.panel.feed_override);
        let feed = self.jog_feed_of(self.axis(axis)?) * self.panel.feed_override;
        self.turn_about_tip(axis, if positive { turn } else { -turn }, self.manual_tool_length(), feed, linear)
    }

    /// HANDLE tool tip centre rotation (FANUC MAN-11): turn rotary `axis` by `amount` degrees
    /// about the tool tip, stopping before a stroke.
    pub fn handle_tip_rotation(&mut self, axis: char, amount: f64) -> Result<(), Refusal> {
        if self.mode != Mode::Handle {
            return Err(Refusal::WrongMode);
        }
        if !amount.is_finite() {
            return Err(Refusal::BadValue);
        }
        self.turn_about_tip(axis, amount, self.manual_tool_length(), self.panel.jog_feed, None)
    }

    /// Syntec R518: the coordinate system manual X/Y/Z moves use.
    pub fn set_manual_coordinates(&mut self, choice: ManualCoordinates) -> Result<(), Refusal> {
        if self.moving() {
            return Err(Refusal::Busy);
        }
        self.panel.manual_coordinates = choice;
        Ok(())
    }

    /// Syntec R519: manual RTCP on or off (rotary JOG/HANDLE keep the tool tip under tool
    /// centre point control).
    pub fn set_manual_rtcp(&mut self, on: bool) -> Result<(), Refusal> {
        if self.moving() {
            return Err(Refusal::Busy);
        }
        self.panel.manual_rtcp = on;
        Ok(())
    }

    /// The 5-axis manual feed settings (FANUC No.12318, 12320–12322, 19746#2/#3, 1410, 1424), to
    /// change as a parameter screen would.
    pub fn manual_options(&self) -> &ManualOptions {
        &self.machine.manual
    }

    pub fn manual_options_mut(&mut self) -> &mut ManualOptions {
        // The first edit gives the controller a machine of its own; the executor's keeps the
        // old manual settings, which it never reads (manual moves take their limits from here).
        std::sync::Arc::make_mut(&mut self.machine).manual_mut()
    }

    /// The tool length of the 5-axis manual feeds (FANUC MAN-13): No.12318, or with LOD the
    /// offset data while an offset is active, else No.12318 (LOZ = 0) or 0 (LOZ = 1).
    pub fn manual_tool_length(&self) -> f64 {
        let o = &self.machine.manual;
        if !o.length_from_offset {
            return o.tool_length;
        }
        match self.interp.active_length_offset() {
            Some(length) => length,
            None if o.zero_length_without_offset => 0.0,
            None => o.tool_length,
        }
    }

    /// The feed of the 5-axis JOG feeds (FANUC MAN-06, TV-MAN-08) without a driving axis: the
    /// dry run rate (No.1410), or the panel's jog feed with JFR (or when no dry run rate is set);
    /// the feed override acts on it as on every JOG feed.
    pub fn manual_jog_feed(&self) -> f64 {
        self.manual_jog_feed_of(None)
    }

    /// As [`Controller::manual_jog_feed`] for the feed the ±J signal of `axis` (index) drives:
    /// with JFR that axis's jog feedrate (No.1423, MAN-08/17 "of the driven signal's axis").
    pub fn manual_jog_feed_of(&self, axis: Option<usize>) -> f64 {
        let o = &self.machine.manual;
        if o.jog_feedrate || o.dry_run_feed <= 0.0 {
            axis.map_or(self.panel.jog_feed, |i| self.jog_feed_of(i))
        } else {
            o.dry_run_feed
        }
    }

    /// The jog feedrate of axis `i` (FANUC No.1423), or the panel's where it is not set.
    pub fn jog_feed_of(&self, i: usize) -> f64 {
        match self.machine.manual.jog_feed.get(i) {
            Some(&f) if f > 0.0 => f,
            _ => self.panel.jog_feed,
        }
    }

    // --- FANUC's panel signals (`signals.rs`) ---------------------------------------------

    /// The 5-axis feed signals ALNGH, RGHTH, RNDH, TB_BASE and the handle select code; refused
    /// (`Busy`) while a manual move is under way, as a real panel's change would not act
    /// mid-move. While a program runs they may change (the handle interrupt's select code)
    /// unless the handle's pulses are still moving.
    pub fn set_manual_signals(&mut self, signals: super::ManualSignals) -> Result<(), Refusal> {
        let manual_moving = if self.interrupt.applied { self.interrupt.moving.is_some() } else { self.moving() };
        if manual_moving {
            return Err(Refusal::Busy);
        }
        self.panel.manual_signals = signals;
        Ok(())
    }

    /// JOG signal ±J of `axis` (FANUC MAN-06/08/12/15/17): the 5-axis feed the panel signals
    /// select for it ([`super::ManualSignals::jog_target`]) at the 5-axis JOG feed, or the
    /// ordinary JOG of the axis.
    /// In INC mode each press moves by the panel's increment (MAN-06/08/12/15/17 "JOG / INC").
    pub fn jog_signal(&mut self, axis: char, positive: bool) -> Result<(), Refusal> {
        let reach = self.jog_reach()?;
        let i = self.axis(axis)?;
        match self.panel.manual_signals.jog_target(self.machine.kinematics().map(|k| &**k), i) {
            ManualTarget::Feed(feed) => {
                let d = self.manual_direction(feed)?;
                self.move_along(if positive { d } else { -d }, reach, self.manual_jog_feed_of(Some(i)))
            }
            ManualTarget::TipRotation(_) => self.jog_tip_rotation(axis, positive),
            ManualTarget::Axis(_) | ManualTarget::Nothing => self.jog_start(axis, positive),
        }
    }

    /// Pulses of the first handle, `amount` mm (deg) in all: they drive what the select code and
    /// the signals choose ([`super::ManualSignals::handle_target`]) as fast as the manual rapid
    /// rates allow (No.1424, the clamp of MAN-05/07/11/14/16), stopping at the strokes as the
    /// other manual moves do. Answers the amount taken (for one axis what the strokes leave of
    /// it): 0 when the pulses are discarded — the select code chooses nothing, or the machine is
    /// still moving the earlier pulses (the handle turned faster than the clamp lets it
    /// follow: "handle pulses generated while the clamp feedrate is exceeded are ignored").
    ///
    /// In AUTO or MDI while a program is under way the pulses are a manual handle interruption
    /// (`interrupt.rs`): a shift over the program instead of a move of their own.
    pub fn handle_pulses(&mut self, amount: f64) -> Result<f64, Refusal> {
        if !amount.is_finite() {
            return Err(Refusal::BadValue);
        }
        if self.interrupting() {
            return self.handle_interrupt(amount);
        }
        if self.mode != Mode::Handle {
            return Err(Refusal::WrongMode);
        }
        if self.estop || self.run_state == RunState::Alarm || self.cycle.program_reading() {
            return Err(Refusal::Busy);
        }
        if self.moving() || self.exec.has_queued() {
            return Ok(0.0);
        }
        let target = self.panel.manual_signals.handle_target(self.machine.kinematics().map(|k| &**k), &self.machine);
        let taken = match target {
            ManualTarget::Nothing => return Ok(0.0),
            ManualTarget::Feed(feed) => {
                let d = self.manual_direction(feed)?;
                self.move_along(if amount < 0.0 { -d } else { d }, amount.abs(), AT_CLAMP)?;
                amount
            }
            ManualTarget::TipRotation(i) => {
                let name = self.machine.axes[i].name;
                self.turn_about_tip(name, amount, self.manual_tool_length(), AT_CLAMP, None)?;
                amount
            }
            ManualTarget::Axis(i) => {
                let from = self.exec.here.machine[i];
                let mut to = from + amount;
                if let Some([lo, hi]) = self.machine.axes[i].stroke {
                    to = to.clamp(lo, hi);
                }
                self.manual_move(i, to, AT_CLAMP)?;
                to - from
            }
        };
        Ok(taken)
    }

    /// Where a 5-axis manual feed moves the tool now, machine coordinates (FANUC §2.15,
    /// TV-MAN-05): in a tilted working plane with TWD the plane's axes; otherwise the
    /// conventional directions, or with FLL longitude and latitude.
    pub fn manual_direction(&self, feed: ManualFeed) -> Result<Vec3, Refusal> {
        let kin = self.machine.kinematics().ok_or(Refusal::NoAxis)?;
        let o = &self.machine.manual;
        if o.plane_directions {
            if let Some([x, y, z]) = self.interp.plane_axes(&self.exec.here.machine) {
                return Ok(match feed {
                    ManualFeed::ToolAxis | ManualFeed::TableVertical => z,
                    ManualFeed::RightAngle1 | ManualFeed::TableHorizontal1 => x,
                    ManualFeed::RightAngle2 | ManualFeed::TableHorizontal2 => y,
                });
            }
        }
        let d = kin.manual_directions(&self.exec.here.machine);
        let first = matches!(feed, ManualFeed::RightAngle1 | ManualFeed::TableHorizontal1);
        let table = matches!(feed, ManualFeed::TableHorizontal1 | ManualFeed::TableHorizontal2);
        if !o.latitude_longitude || matches!(feed, ManualFeed::ToolAxis | ManualFeed::TableVertical) {
            return Ok(d.of(feed));
        }
        // Longitude and latitude of the tool direction, or for the table feeds of the table
        // vertical (§2.15 [A]); No.12321 = 0: the reference tool direction for the tool feeds,
        // the tool direction for the table feeds (OQ-28, each section literally).
        let vertical = match o.vertical {
            ManualVertical::Tool if table => d.tool,
            ManualVertical::Tool => kin.tool_axis,
            ManualVertical::X => Vec3::x(),
            ManualVertical::Y => Vec3::y(),
            ManualVertical::Z => Vec3::z(),
        };
        let normal = if table { d.table_vertical } else { d.tool };
        let [r1, r2] = latitude_longitude(normal, vertical, o.parallel_deg);
        Ok(if first { r1 } else { r2 })
    }

    pub(super) fn turn_about_tip(
        &mut self,
        axis: char,
        amount: f64,
        length: f64,
        feed_deg_min: f64,
        linear_feed: Option<f64>,
    ) -> Result<(), Refusal> {
        let kin = self.machine.kinematics().cloned().ok_or(Refusal::NoAxis)?;
        let i = self.axis(axis)?;
        if kin.linear.contains(&Some(i)) {
            return Err(Refusal::NoAxis);
        }
        if self.manual_blocked() {
            return Err(Refusal::Busy);
        }
        if self.manual_refused_in_wse() {
            return Ok(());
        }
        let from = self.exec.here.machine;
        // The dry run rate is the linear axes' resultant: the rotary rate that gives it (the
        // carriage turns on a circle about the rotary axis).
        let feed = match linear_feed {
            Some(f) => {
                let mut step = from;
                step[i] += 1e-3;
                let tip = kin.forward(&from, length).tip;
                let per_deg =
                    (kin.carriage_for(&step, tip, length) - kin.carriage_for(&from, tip, length)).norm() / 1e-3;
                if per_deg > 1e-9 {
                    f / per_deg
                } else {
                    feed_deg_min
                }
            }
            None => feed_deg_min,
        };
        let axes = self.manual_limits();
        let basis = crate::tip::Basis { tool_length: length, ..self.tip_basis() };
        let segment = |amount: f64| {
            let mut to = from;
            to[i] += amount;
            // (The mechanism is there: checked above.)
            let seg = self.exec.tip_rotation((&from, &self.exec.here.work), &to, length, feed, &axes);
            let mut seg = seg.ok_or(Refusal::NoAxis)?;
            seg.tip_basis = basis;
            Ok(seg)
        };
        // The largest part of the turn whose path (sampled) stays inside every stroke.
        let inside = |seg: &Segment| {
            (0..=64).all(|k| {
                let p = seg.at(seg.len * k as f64 / 64.0).0;
                self.machine
                    .axes
                    .iter()
                    .enumerate()
                    .all(|(a, ax)| ax.stroke.is_none_or(|[lo, hi]| p[a] >= lo && p[a] <= hi))
            })
        };
        let mut seg = segment(amount)?;
        if !inside(&seg) {
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                if inside(&segment(amount * mid)?) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            seg = segment(amount * lo)?;
        }
        // Under TCP the tip keeps its program coordinates (in Π; FANUC DET = 1 shows the tip in
        // the workpiece system instead, which the table's turn moves: left to the samples).
        if self.interp.tcp_on() && !self.cycle.intervening() && !self.machine.five_axis.display_workpiece {
            seg = seg.keeping_program_xyz();
        }
        (seg.line, seg.n) = self.manual_shown_at();
        self.exec.push(seg);
        self.set_state(RunState::Running);
        Ok(())
    }

    /// The axis limits of manual moves: no axis faster than its manual rapid rate (FANUC
    /// No.1424, TV-MAN-09; 0: the rapid rate).
    pub(super) fn manual_limits(&self) -> AxisLimits {
        let mut axes = self.exec.axes().clone();
        for (i, &rapid) in self.machine.manual.rapid.iter().enumerate().take(axes.count) {
            if rapid > 0.0 {
                axes.v[i] = axes.v[i].min(rapid / 60.0);
            }
        }
        axes
    }

    /// Move X, Y, Z up to `distance` along the unit direction `d` (machine coordinates),
    /// clamped to the strokes: a move the first stroke met cuts short ends in its overtravel
    /// alarm, as a single axis's does (`Controller::manual_move_within_stroke`).
    pub(super) fn move_along(&mut self, d: Vec3, distance: f64, feed: f64) -> Result<(), Refusal> {
        let kin = self.machine.kinematics().cloned().ok_or(Refusal::NoAxis)?;
        if !d.iter().all(|x| x.is_finite()) || (d.norm() - 1.0).abs() > 1e-6 {
            return Err(Refusal::NoAxis);
        }
        if self.manual_blocked() {
            return Err(Refusal::Busy);
        }
        if self.manual_refused_in_wse() {
            return Ok(());
        }
        // The longest move along d that stays inside every stroke, and the stroke that ends it.
        let (mut reach, mut over) = (distance, None);
        for (axis, &index) in kin.linear.iter().enumerate() {
            let Some(i) = index else { continue };
            let (x, di) = (self.exec.here.machine[i], d[axis]);
            if let (Some([lo, hi]), true) = (self.machine.axes[i].stroke, di.abs() > 1e-12) {
                let bound = if di > 0.0 { hi } else { lo };
                let to_bound = ((bound - x) / di).max(0.0);
                if to_bound < reach {
                    reach = to_bound;
                    over = self.stroke_limited(i, x + di * distance).map(|(_, alarm)| alarm);
                }
            }
        }
        if !reach.is_finite() {
            reach = 1.0e6;
        }
        if reach == 0.0 {
            if let Some(alarm) = over {
                self.raise(alarm, self.exec.here.line, self.exec.here.n);
                return Ok(());
            }
        }
        let mut to = self.exec.here.machine;
        for (axis, &index) in kin.linear.iter().enumerate() {
            if let Some(i) = index {
                to[i] += d[axis] * reach;
            }
        }
        self.push_manual(MotionKind::Linear, to, feed);
        self.stroke_reached = over;
        Ok(())
    }

    /// A motion of the program after a manual intervention: with manual absolute off moved by
    /// the interventions so far (`shift`); the first after one at a block stop with manual
    /// absolute on starts its tool tip path where the tip is (`reposition`).
    pub(super) fn moved_motion(&self, m: &Motion, shift: Option<&Shift>) -> Motion {
        let mut m = m.clone();
        if let (true, Some(tip), Some(kin)) = (self.reposition, &mut m.tip, self.machine.kinematics()) {
            tip.from = tip.point_at(kin, &self.exec.queued.machine);
        }
        // Machine-coordinate moves (G53, reference returns) go where they say.
        let Some(shift) = shift.filter(|_| m.kind != MotionKind::MachineRapid) else { return m };
        match (&mut m.tip, self.machine.kinematics()) {
            (Some(tip), Some(kin)) => {
                tip.from += shift.tip;
                tip.to += shift.tip;
                if let Some(arc) = &mut tip.arc {
                    arc.center += shift.tip;
                }
                let carriage = tip.carriage_for(kin, &m.machine, tip.to);
                for (axis, index) in kin.linear.iter().enumerate() {
                    if let Some(i) = index {
                        m.machine[*i] = carriage[axis];
                    }
                }
            }
            _ => {
                for (x, d) in m.machine.iter_mut().zip(&shift.machine) {
                    *x += d;
                }
            }
        }
        m
    }
}
