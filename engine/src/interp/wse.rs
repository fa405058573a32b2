//! Workpiece setting error compensation in programs (FANUC G54.4, spec
//! `fanuc-twp-wsec-manual-params.md` WSE-01…WSE-26): the error data sets beside the work
//! offsets (`State::setting_errors`, macro variables #26000…#26077), the effective error of a
//! set, and how positions follow it. Geometry: `crate::wse`; decisions: `docs/five-axis.md`,
//! "Workpiece setting error compensation (G54.4)".
//!
//! While a set is in effect, programmed points are in the workpiece setting coordinate system
//! (WSCS): `State::pos` holds WSCS coordinates and X/Y/Z go to the WCS as `R_e·p + Δ` before the
//! work offsets are added (`State::program_to_machine`), so lines stay lines. Without tool
//! direction compensation (RCM = 0) the rotary axes are left as programmed; with it (second
//! half of this file) moves follow the tool tip and the rotary axes are corrected. A circle
//! whose plane the error tilts is a circle in space: every G02/G03 under G54.4 therefore runs as
//! a tool tip path (`canon::TipMove`) with the tool length as a plain G43 applies it (along Z).
//! G54.4 Pn and P0 do not move the machine: the current point is recomputed in the new system.
//! Also here: the settings RCM needs (PS0438), the canned-cycle feed (No.5412), the rotary
//! clamp (No.11202/11203), the display choice (DAK) and the manual-move ban (WSE-25).

use super::gcode::code;
use super::nc::Words;
use super::tcp::FollowPath;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, MotionKind, Pos};
use crate::geom::Rigid;
use crate::kin::{Kinematics, MachineKind, Selection, Vec3};
use crate::machine::{AxisKind, Side, MAX_AXES};
use crate::wse::{self, ErrorSet};
use nalgebra::Matrix3;
use std::sync::Arc as Shared;

/// The set in effect.
#[derive(Debug, Clone, Copy)]
pub(super) struct Active {
    /// 1…7.
    pub(super) set: u8,
    /// The effective error (COMMON + set, at table position 0): the WSCS in the WCS.
    pub(super) frame: Rigid,
    /// The indices of the basic axes X, Y, Z.
    xyz: [usize; 3],
}

impl State {
    /// The number of the set in effect and its effective error (the WSCS as a frame in the
    /// WCS), as the "active workpiece setting error" screen shows them (WSE-07).
    pub fn active_setting_error(&self) -> Option<(u8, Rigid)> {
        self.wse.map(|a| (a.set, a.frame))
    }

    /// The effective error of set `n` (1…7): COMMON's and the set's translations added, the
    /// set's rotation, each first converted to table machine position 0 when the machine turns
    /// its table (WSE-03, WSE-04, §2.13.3).
    pub fn effective_setting_error(&self, n: usize) -> Rigid {
        let sets = &self.setting_errors.sets;
        let common = self.at_table_zero(&sets[0], [0.0; 3]);
        let set = sets.get(n).copied().unwrap_or_default();
        wse::effective(&common, &self.at_table_zero(&set, set.rotation))
    }

    /// One set's error as a frame, converted to table machine position 0.
    fn at_table_zero(&self, s: &ErrorSet, rotation: [f64; 3]) -> Rigid {
        let e = wse::frame(s.shift, rotation);
        match &self.wse_kinematics {
            Some(kin) if kin.joints().iter().any(|j| j.side == Side::Table && j.index.is_some()) => {
                wse::at_table_zero(&e, &self.table_motion(kin, s.table))
            }
            _ => e,
        }
    }

    /// The table's motion from machine position 0 to `table` (table position 1 = the master
    /// or only table axis, 2 = the slave) as seen in the WCS: an ideal workpiece point's WCS
    /// coordinates at position 0 → its WCS coordinates with the table at `table`. Hypothetical
    /// table axes count as 0 (WSE-25: `kin` is the compensation's mechanism).
    fn table_motion(&self, kin: &Kinematics, table: [f64; 2]) -> Rigid {
        let zero: Pos = [0.0; MAX_AXES];
        let mut turned = zero;
        let table_joints = kin.joints().into_iter().filter(|j| j.side == Side::Table);
        for (k, j) in table_joints.enumerate() {
            if let (Some(i), Some(v)) = (j.index, table.get(k)) {
                turned[i] = *v;
            }
        }
        let f0 = self.wcs_on_table(kin, &zero);
        let ft = self.wcs_on_table(kin, &turned);
        wse::inverse(&ft).then(&f0)
    }

    /// A G54.4 block (alone in its block, its P checked by the mode rules): start set n or
    /// cancel (P0). The machine does not move; the current point is recomputed (WSE-09).
    pub(super) fn apply_wse(&mut self, w: &Words) -> Result<(), AlarmId> {
        if !w.gcodes().contains(&code::G54_4) {
            return Ok(());
        }
        let n = w.integer(b'P').unwrap_or(0.0) as usize;
        let machine = self.machine_position();
        if n == 0 {
            if self.wse.take().is_none() {
                return Ok(());
            }
        } else {
            let axes = &self.cfg.machine.axes;
            let basic = [b'X', b'Y', b'Z'].map(|l| self.axis_of(l).filter(|&i| axes[i].kind == AxisKind::Linear));
            let [Some(x), Some(y), Some(z)] = basic else { return Err(AlarmId::WseBasicAxes) };
            let frame = self.effective_setting_error(n);
            self.wse = Some(Active { set: n as u8, frame, xyz: [x, y, z] });
            if self.wse_follows() {
                return self.wse_start(machine);
            }
        }
        if !self.tcp_active() && !self.plane_active() {
            self.follow_machine = None;
        }
        self.pos = self.machine_to_program(&machine);
        self.sync_programmed();
        Ok(())
    }

    /// The start block with tool direction compensation (§2.13.4): the tip in the WSCS, the
    /// rotary coordinates the angles whose error-free tool direction is the actual one seen
    /// from the WSCS (PS0438 when there are none). When the tool is singular both as it stands
    /// and as the error turns it, the absolute coordinates stay (WSE-09, TV-WSE-27).
    fn wse_start(&mut self, machine: Pos) -> Result<(), AlarmId> {
        let kin = self.wse_kinematics.clone().ok_or(AlarmId::WseToolDirection)?;
        let turn = self.wse_turn(&kin, &machine);
        let tool = kin.forward(&machine, 0.0).tool;
        let seen = turn.transpose() * tool;
        if self.wse_singular(&kin, &tool) && self.wse_singular(&kin, &seen) {
            self.follow_machine = Some(machine);
            return Ok(());
        }
        self.wse_programmed_angles(&machine).ok_or(AlarmId::WseToolDirection)?;
        self.wse_moved_to(machine);
        Ok(())
    }

    /// The angles (less the work offsets) whose error-free tool direction is the actual one at
    /// `machine` seen from the WSCS (§2.13.4), chosen as FANUC chooses rotary solutions.
    pub(super) fn wse_programmed_angles(&self, machine: &Pos) -> Option<Pos> {
        let kin = self.wse_kinematics.as_deref()?;
        let seen = self.wse_turn(kin, machine).transpose() * kin.forward(machine, 0.0).tool;
        let candidates = kin.inverse(Vec3::zeros(), seen, 0.0, &machine[..kin.axes]);
        let how = Selection { dialect: self.cfg.dialect, pri: self.cfg.machine.five_axis.second_axis_first, p: 0 };
        let angles = kin.select(&candidates, &machine[..kin.axes], how).ok()?;
        let off = self.offset_vector();
        let mut p = self.pos;
        for j in kin.joints() {
            if let Some(i) = j.index {
                p[i] = angles.pos[i] - off[i];
            }
        }
        Some(p)
    }

    /// What tool direction compensation needs when G54.4 Pn starts it (WSE-11, TV-WSE-19d;
    /// PS0438 otherwise): look-ahead on (G05.1 Q1, or on from power-on), linear-type rapids
    /// (LRP), look-ahead set up for rapids (FRP, No.1671) and cutting feed (No.1660).
    pub(super) fn wse_settings_ready(&self) -> bool {
        let m = &self.cfg.machine.motion;
        self.look_ahead && !m.nonlinear_rapid && m.look_ahead_set_up()
    }

    /// Reset: workpiece setting error compensation ends unless FANUC D3R (No.5400#2) keeps it
    /// (WSE-21; `five_axis.plane_after_reset`, the same bit that keeps the tilted plane). The machine stays; the current point is recomputed in the WCS.
    pub(super) fn wse_reset(&mut self) {
        if self.wse.is_none()
            || self.cfg.machine.five_axis.plane_after_reset != crate::machine::PlaneAfterReset::Cancelled
        {
            return;
        }
        let machine = self.machine_position();
        self.wse = None;
        self.five.clear_wse();
        if !self.tcp_active() && !self.plane_active() {
            self.follow_machine = None;
        }
        self.pos = self.machine_to_program(&machine);
        self.sync_programmed();
    }

    /// WSCS → WCS on X/Y/Z (identity without G54.4).
    #[inline]
    pub(super) fn wse_to_wcs(&self, p: &mut Pos) {
        if let Some(a) = &self.wse {
            let [x, y, z] = a.xyz;
            let q = a.frame.to_parent(&Vec3::new(p[x], p[y], p[z]));
            (p[x], p[y], p[z]) = (q[0], q[1], q[2]);
        }
    }

    /// WCS → WSCS on X/Y/Z (identity without G54.4).
    #[inline]
    pub(super) fn wse_from_wcs(&self, p: &mut Pos) {
        if let Some(a) = &self.wse {
            let [x, y, z] = a.xyz;
            let q = a.frame.from_parent(&Vec3::new(p[x], p[y], p[z]));
            (p[x], p[y], p[z]) = (q[0], q[1], q[2]);
        }
    }

    /// WSE-18, FANUC DAK (No.3106#6) = 1: under G54.4 the absolute position shows X/Y/Z in the
    /// WCS instead of the WSCS (the rotary axes as programmed, as #5041… do). Only where G54.4's
    /// circles follow the tip (a kinematic model), so that no plain circle is given in the WCS.
    pub(super) fn wse_shows_wcs(&self) -> bool {
        self.wse.is_some() && self.kinematics.is_some() && self.cfg.machine.five_axis.wse_display_wcs
    }

    /// A motion's display coordinates (its `target`, a tip path's frame) as WSE-18 chooses.
    pub(super) fn wse_display(&self, m: &mut crate::canon::Motion) {
        let Some(a) = self.wse.filter(|_| self.wse_shows_wcs()) else { return };
        self.wse_to_wcs(&mut m.target);
        if let Some(tip) = &mut m.tip {
            tip.frame = tip.frame.then(&wse::inverse(&a.frame));
        }
    }

    /// The current point as the absolute position display shows it (WSE-18: in the WCS with
    /// DAK = 1 under G54.4; TCP-26: the tip in the workpiece system with DET = 1 under TCP;
    /// otherwise the programming coordinates, [`State::position`]).
    pub fn shown_position(&self) -> Pos {
        if self.wse_shows_wcs() {
            self.wcs_position()
        } else {
            self.tcp_shown().or_else(|| self.table_crc_shown()).unwrap_or(self.pos)
        }
    }

    /// The current point in the WCS (#5041…, WSE-20): the WSCS point carried by the error.
    pub(super) fn wcs_position(&self) -> Pos {
        let mut p = self.pos;
        self.wse_to_wcs(&mut p);
        p
    }

    /// Whether a circle must run as a tip path: under G54.4 (the error may tilt its plane).
    pub(super) fn wse_arc(&self) -> bool {
        self.wse.is_some() && self.kinematics.is_some()
    }

    /// G02/G03 under G54.4 without tool centre point control or a tilted plane: the circle
    /// (WSCS) carried into the WCS as a circle in space, the tool length along Z as plain G43
    /// applies it, so the end point is exactly `program_to_machine(target)`.
    pub(super) fn wse_arc_motion(
        &mut self,
        kind: MotionKind,
        target: Pos,
        arc: Box<Arc>,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let Some((kin, active)) = self.kinematics.clone().zip(self.wse) else { return Ok(()) };
        let end = self.program_to_machine(&target);
        let [x, y, z] = active.xyz;
        let length = Rigid {
            r: nalgebra::Matrix3::identity(),
            o: Vec3::new(self.tool_vec[x], self.tool_vec[y], self.tool_vec[z]),
        };
        let frame = self.wcs_on_table(&kin, &end).then(&length).then(&active.frame);
        let path =
            FollowPath { frame, tool_length: 0.0, posture: false, along: true, cutting: None, head_fixed: false };
        self.follow_motion(&kin, kind, target, Some(arc), path, out)?;
        // Not a mode that follows the tip: the machine position is the programmed point's.
        self.follow_machine = None;
        Ok(())
    }
}

impl super::Interpreter {
    /// WSE-25: G54.4 compensates the tool direction on a machine with a table rotary axis (table
    /// or mixed type, hypothetical axes included): manual moves raise an alarm there.
    pub fn wse_forbids_manual(&self) -> bool {
        let st = &self.state;
        st.wse_follows() && st.cfg.machine.rotary.iter().any(|l| l.side == Side::Table)
    }
}

/// Steps along the programmed interpolation at which a start in the singular posture looks for
/// the first posture that is not (rule 3 of §2.14 decides there, as it would in the first
/// interpolation period that leaves the singular cone).
const LEAVING: [f64; 8] = [1e-3, 1e-2, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0];

impl State {
    /// Tool direction compensation is in effect (G54.4 with RCM = 1): X/Y/Z follow the tool
    /// tip through the kinematics, the rotary axes are corrected (WSE-11, WSE-12).
    pub(super) fn wse_follows(&self) -> bool {
        self.wse.is_some() && self.cfg.machine.five_axis.tool_direction_compensation
    }

    /// The error's rotation in the table frame (the WCS placed on the table at the rotary
    /// program zero): a tool direction relative to the ideal workpiece → relative to the
    /// displaced one.
    fn wse_turn(&self, kin: &Kinematics, machine: &Pos) -> Matrix3<f64> {
        let Some(a) = &self.wse else { return Matrix3::identity() };
        let w = self.wcs_on_table(kin, &self.at_rotary_zero(kin, machine));
        w.r * a.frame.r * w.r.transpose()
    }

    /// The machine stands at `machine` under tool direction compensation (start block, a move
    /// in machine coordinates, manual intervention): the current point is the tip in the WSCS.
    pub(super) fn wse_moved_to(&mut self, machine: Pos) {
        if !self.wse_follows() || self.tcp_active() || self.plane_active() {
            return;
        }
        let Some(kin) = self.kinematics.clone() else { return };
        let frame = self.frame_on_table(&kin, &self.at_rotary_zero(&kin, &machine));
        self.pos = self.tip_position(&kin, &frame, &machine, self.active_tool_length());
        self.follow_machine = Some(machine);
        if let Some(angles) = self.wse_programmed_angles(&machine) {
            self.wse_keep_programmed_angles(&angles);
        }
        self.sync_programmed();
    }

    /// A move under tool direction compensation without TCP or a tilted plane: the tip on the
    /// WSCS line or circle relative to the table (TCP-like, WSE-12), the rotary axes at the
    /// compensated angles.
    pub(super) fn wse_motion(
        &mut self,
        kind: MotionKind,
        mut target: Pos,
        arc: Option<Box<Arc>>,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let kin = self.kinematics.clone().ok_or(AlarmId::WseToolDirection)?;
        let programmed = target;
        self.wse_compensate(&kin, &mut target)?;
        let from = self.machine_position();
        let frame = self.frame_on_table(&kin, &self.at_rotary_zero(&kin, &from));
        let path = FollowPath {
            frame,
            tool_length: self.active_tool_length(),
            posture: false,
            along: true,
            cutting: None,
            head_fixed: false,
        };
        self.follow_motion(&kin, kind, target, arc, path, out)?;
        self.wse_keep_programmed_angles(&programmed);
        Ok(())
    }

    /// WSE-19: under G54.4 the rapids of hole-machining canned cycles run at this feed, mm/min:
    /// FANUC No.5412, or when that is 0 the dry run rate (No.1410); `None` outside G54.4 or
    /// when both are 0 (then they stay rapids).
    pub(super) fn wse_cycle_feed(&self) -> Option<f64> {
        self.wse?;
        let feed = match self.cfg.machine.five_axis.wse_cycle_feed {
            0.0 => self.cfg.machine.manual.dry_run_feed,
            f => f,
        };
        (feed > 0.0).then_some(feed)
    }

    /// FANUC No.11202 (cutting) / No.11203 (rapid), WSE-24: under tool direction compensation
    /// the rotary axes turn at most that percentage of their rate (the seed's "maximum cutting
    /// feedrate / rapid traverse rate"; the model's one rate per axis stands for both); 0: no
    /// clamp.
    pub(super) fn wse_rotary_clamp(&self, kind: MotionKind) -> Option<f64> {
        if !self.wse_follows() {
            return None;
        }
        let f = &self.cfg.machine.five_axis;
        let pct = if kind == MotionKind::Rapid { f.wse_rapid_clamp_pct } else { f.wse_feed_clamp_pct };
        (pct > 0.0 && pct < 100.0).then_some(pct / 100.0)
    }

    /// A plain move (`push_motion`: canned cycles, the G28/G30 intermediate point) ended at
    /// `machine` under tool direction compensation, which keeps the machine position beside
    /// the tip: these moves are not compensated (the tool length along Z, the rotary axes as
    /// programmed), but the machine position must follow them.
    pub(super) fn wse_plain_move_done(&mut self, machine: Pos) {
        if self.wse_follows() && !self.tcp_active() && !self.plane_active() {
            self.follow_machine = Some(machine);
        }
    }

    /// Under tool direction compensation the rotary coordinates of the current point are the
    /// programmed (WSCS) angles, not the machine's compensated ones: the next block
    /// interpolates from them and #5001… show them.
    pub(super) fn wse_keep_programmed_angles(&mut self, programmed: &Pos) {
        let Some(kin) = self.kinematics.clone().filter(|_| self.wse_follows()) else { return };
        for j in kin.joints() {
            if let Some(i) = j.index {
                self.pos[i] = programmed[i];
            }
        }
        self.sync_programmed();
    }

    /// RCM = 1: the rotary coordinates of `target` (programmed angles) become the machine
    /// angles, less the work offsets, that give relative to the displaced workpiece the tool
    /// direction the programmed angles give relative to the ideal one (§2.13.5), chosen by the
    /// singular-posture rules of §2.14, at the block's end points; between them the motion
    /// recomputes the direction (`canon::Compensation`, handed to `follow_motion`).
    pub(super) fn wse_compensate(&mut self, kin: &Shared<Kinematics>, target: &mut Pos) -> Result<(), AlarmId> {
        self.wse_between = None;
        if !self.wse_follows() || kin.joints().is_empty() {
            return Ok(());
        }
        let off = self.offset_vector();
        let from = self.machine_position();
        let programmed = |p: &Pos| -> Pos {
            let mut m = from;
            for j in kin.joints() {
                if let Some(i) = j.index {
                    m[i] = p[i] + off[i];
                }
            }
            m
        };
        let (start, end) = (programmed(&self.xf.programmed), programmed(target));
        // The directions as the compensation sees them (hypothetical table axes at 0°, WSE-25).
        let seen = self.wse_kinematics.clone().unwrap_or_else(|| kin.clone());
        let angles = self.wse_angles(&seen, &from, &start, &end)?;
        let turn = self.wse_turn(&seen, &from);
        // Along the way the motion works in the machine's table frame: the same turn seen from
        // there (the motion checks that its path meets these end points, else it turns the axes
        // in proportion: a hypothetical table master at an angle makes the frames differ by a
        // rotation that changes with the slave).
        let turn = if Shared::ptr_eq(&seen, kin) {
            turn
        } else {
            let c = kin.table_frame(&from).r.transpose() * seen.table_frame(&from).r;
            c * turn * c.transpose()
        };
        self.wse_between = Some(crate::canon::Compensation { turn, from: start, to: end });
        for j in kin.joints() {
            if let Some(i) = j.index {
                target[i] = angles[i] - off[i];
            }
        }
        Ok(())
    }

    /// Within the singular tolerance (No.11204; 0 = exact) of the singular posture: the tool
    /// direction `tool` (table frame) along the workpiece-side axis.
    fn wse_singular(&self, kin: &Kinematics, tool: &Vec3) -> bool {
        let Some((_, wp)) = sides(kin) else { return false };
        let axis = kin.joints()[wp].direction;
        let angle = tool.dot(&axis).abs().min(1.0).acos().to_degrees();
        angle <= self.cfg.machine.five_axis.singular_tolerance_deg.max(1e-6)
    }

    /// The compensated machine angles for a block from machine `from` whose programmed angles
    /// go from `start` to `end` (machine-like positions), by §2.14:
    /// 1. current and target singular: the workpiece-side axis stays (1) or, when the
    ///    programmed posture is singular too, moves as commanded (2): by the block's programmed
    ///    motion of that axis, from where it stands (a block that does not command it leaves
    ///    it where an earlier rule held it);
    /// 2. target singular only: the workpiece-side axis stays;
    /// 3. current singular only: the pair with the smaller workpiece-side motion, judged where
    ///    the programmed interpolation first leaves the singular posture;
    /// 4. neither: the pair that keeps the tool-side axis on its side of the singular angle.
    fn wse_angles(&self, kin: &Shared<Kinematics>, from: &Pos, start: &Pos, end: &Pos) -> Result<Pos, AlarmId> {
        let turn = self.wse_turn(kin, from);
        let wanted = |p: &Pos| turn * kin.forward(p, 0.0).tool;
        let options = |tool: Vec3| -> Vec<Pos> {
            let joints = kin.joints();
            kin.inverse(Vec3::zeros(), tool, 0.0, &from[..kin.axes])
                .iter()
                .map(|c| {
                    let mut p = *from;
                    for (k, j) in joints.iter().enumerate() {
                        if let Some(i) = j.index {
                            p[i] = if c.free[k] { from[i] } else { nearest(c.pos[i], from[i]) };
                        }
                    }
                    p
                })
                .collect()
        };
        let target = wanted(end);
        let found = options(target);
        if found.is_empty() {
            return Err(AlarmId::WseUnreachable);
        }
        let Some((ts, ws)) = sides(kin) else { return Ok(found[0]) };
        let joints = kin.joints();
        let (ti, wi) = (joints[ts].index, joints[ws].index);
        let moved = |p: &Pos, i: Option<usize>| i.map_or(0.0, |i| (p[i] - from[i]).abs());
        let least = |ps: &[Pos], i: Option<usize>| -> Pos {
            *ps.iter().min_by(|a, b| moved(a, i).total_cmp(&moved(b, i))).expect("not empty")
        };
        let current_singular = self.wse_singular(kin, &kin.forward(from, 0.0).tool);
        if self.wse_singular(kin, &target) {
            // Rules 1 and 2: the tool-side axis moves least; the workpiece side as the rules say.
            let mut p = least(&found, ti);
            if let Some(i) = wi {
                let programmed_singular = self.wse_singular(kin, &kin.forward(end, 0.0).tool);
                let commanded = if current_singular && programmed_singular { end[i] - start[i] } else { 0.0 };
                p[i] = from[i] + commanded;
            }
            return Ok(p);
        }
        let Some(singular_angle) = singular_tool_angle(kin, ts, from) else { return Ok(least(&found, ti)) };
        let side = |p: &Pos| ti.map_or(0.0, |i| (crate::angle::basic(p[i] - singular_angle + 180.0) - 180.0).signum());
        let keep = if current_singular {
            // Rule 3 where the programmed interpolation first leaves the singular posture.
            let leaving = LEAVING.iter().find_map(|&u| {
                let p: Pos = std::array::from_fn(|i| start[i] + u * (end[i] - start[i]));
                let tool = wanted(&p);
                (!self.wse_singular(kin, &tool)).then(|| options(tool)).filter(|o| !o.is_empty())
            });
            side(&least(leaving.as_deref().unwrap_or(&found), wi))
        } else if let Some(leaving) = self.wse_passing(kin, start, end, &wanted) {
            // Rule 4 per interpolation period: where the path passes within the tolerance of
            // the singular posture, rule 2 holds the workpiece-side axis at its angle on
            // entering, and rule 3 on leaving takes the pair that moves it least.
            let (entering, leaving) = (options(wanted(&leaving.0)), options(wanted(&leaving.1)));
            let held = entering.iter().find(|p| side(p) == side(from)).or(entering.first()).copied();
            match (held, wi) {
                (Some(h), Some(w)) if !leaving.is_empty() => side(
                    leaving
                        .iter()
                        .min_by(|a, b| (a[w] - h[w]).abs().total_cmp(&(b[w] - h[w]).abs()))
                        .expect("not empty"),
                ),
                _ => side(from),
            }
        } else {
            side(from)
        };
        // Rule 4 (and the side rule 3 chose): no passing through the singular posture.
        let same: Vec<Pos> = found.iter().copied().filter(|p| side(p) == keep).collect();
        Ok(if same.is_empty() { least(&found, wi) } else { least(&same, ti) })
    }
}

impl State {
    /// Whether the programmed interpolation from `start` to `end` (neither end singular)
    /// passes within the singular tolerance: the programmed positions just before entering and
    /// just after leaving the singular cone around the closest approach. A coarse scan finds the
    /// closest sample, a ternary search refines it.
    fn wse_passing(
        &self,
        kin: &Kinematics,
        start: &Pos,
        end: &Pos,
        wanted: &dyn Fn(&Pos) -> Vec3,
    ) -> Option<(Pos, Pos)> {
        if self.cfg.machine.five_axis.singular_tolerance_deg <= 0.0 {
            return None;
        }
        let (_, wp) = sides(kin)?;
        let axis = kin.joints()[wp].direction;
        let at = |u: f64| -> Pos { std::array::from_fn(|i| start[i] + u * (end[i] - start[i])) };
        let off_axis = |u: f64| 1.0 - wanted(&at(u)).dot(&axis).abs();
        const N: usize = 64;
        let best = (0..=N).map(|k| k as f64 / N as f64).min_by(|a, b| off_axis(*a).total_cmp(&off_axis(*b)))?;
        let (mut lo, mut hi) = ((best - 1.0 / N as f64).max(0.0), (best + 1.0 / N as f64).min(1.0));
        for _ in 0..60 {
            let (a, b) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
            if off_axis(a) < off_axis(b) {
                hi = b;
            } else {
                lo = a;
            }
        }
        let closest = 0.5 * (lo + hi);
        if !self.wse_singular(kin, &wanted(&at(closest))) {
            return None;
        }
        // Step out of the cone on both sides.
        let step = 1e-4;
        let mut enter = closest;
        while enter > 0.0 && self.wse_singular(kin, &wanted(&at(enter))) {
            enter -= step;
        }
        let mut leave = closest;
        while leave < 1.0 && self.wse_singular(kin, &wanted(&at(leave))) {
            leave += step;
        }
        Some((at(enter.max(0.0)), at(leave.min(1.0))))
    }
}

/// Indices in `Kinematics::joints` of the tool-side and the workpiece-side axis (WSE-13):
/// head-head slave / master, table-table master / slave, mixed head / table.
fn sides(kin: &Kinematics) -> Option<(usize, usize)> {
    match kin.kind {
        MachineKind::HeadHead => Some((1, 0)),
        MachineKind::TableTable | MachineKind::HeadTable => Some((0, 1)),
        _ => None,
    }
}

/// The tool-side angle at which the tool is along the workpiece-side axis (the singular
/// angle, WSE-14), if the machine has one.
fn singular_tool_angle(kin: &Kinematics, tool_side: usize, from: &Pos) -> Option<f64> {
    let joints = kin.joints();
    let i = joints[tool_side].index?;
    let axis = joints[1 - tool_side].direction;
    [axis, -axis]
        .into_iter()
        .find_map(|d| kin.inverse(Vec3::zeros(), d, 0.0, &from[..kin.axes]).first().map(|c| c.pos[i]))
}

/// The member of `basic + 360k` nearest `current` (no movement range: WSE-23 applies the
/// compensation after the range limitation).
fn nearest(basic: f64, current: f64) -> f64 {
    current + (crate::angle::basic(basic - current + 180.0) - 180.0)
}

/// The mechanism G54.4's tool direction compensation computes with: the machine's, except that
/// a hypothetical table axis is at 0° whatever its fixed angle (WSE-25, "compensated with that
/// axis at 0°"). The same `Arc` when no hypothetical table axis has a fixed angle.
pub(super) fn compensation_kinematics(
    m: &crate::machine::MachineConfig,
    kin: Option<&Shared<Kinematics>>,
) -> Option<Shared<Kinematics>> {
    let kin = kin?;
    if !kin.table.iter().any(|j| j.index.is_none() && j.fixed != 0.0) {
        return Some(kin.clone());
    }
    let mut at_zero = m.clone();
    for link in at_zero.rotary.iter_mut().filter(|l| l.side == Side::Table) {
        if link.fixed.is_some() && !m.axes.iter().any(|a| a.name == link.axis && a.kind == AxisKind::Rotary) {
            link.fixed = Some(0.0);
        }
    }
    Kinematics::new(&at_zero).ok().map(Shared::new)
}
