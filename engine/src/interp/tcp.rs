//! Tool centre point control: FANUC G43.4 (type 1, the tool direction by rotary angles) and
//! G43.5 (type 2, by a vector I, J, K), Haas G234 TCPC (type 1 with Π the work coordinate
//! system fixed to the table at the rotary zero, FANUC's `TableAtZero`; `docs/dialects.md`,
//! "Haas 5-axis"), Syntec RTCP (spec `fanuc-tcp.md` TCP-03…TCP-35,
//! `syntec.md` SYN-07…SYN-11), and the same under cutting point control (G43.8/G43.9, whose
//! X/Y/Z are the cutting point: `super::cutting_point`). The choices the manuals leave open are
//! in `docs/five-axis.md`.
//!
//! A block's X/Y/Z are the tool tip in the programming coordinate system Π (FANUC M-2), which
//! is fixed on the table: its frame in the table frame is taken when TCP starts (or with the
//! table axes at their program zero, or, for the workpiece system, at each block's end angles).
//! The block's motion carries the tip path relative to the table (`canon::TipMove`); the axes
//! follow it through the kinematics, so the tip moves on the programmed line or arc while the
//! rotary axes turn. The start block and the G49 block are ordinary moves that apply or remove
//! the tool length at their end only (TCP-03, TCP-17); a Haas or Syntec G49 block without axis
//! words moves nothing (`nc::length_in_place`).

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, CanonKind, CuttingMove, MotionKind, Pos, TipArc, TipMove};
use crate::geom::Rigid;
use crate::kin::{Kinematics, Selection, Vec3};
use crate::machine::TcpCoordinates;
use std::sync::Arc as Shared;

/// Tool centre point control in force.
#[derive(Debug, Clone)]
pub(super) struct Tcp {
    /// Group 08's code: 434 (type 1) or 435 (type 2), 438/439 the same types under cutting
    /// point control.
    code: u16,
    kin: Shared<Kinematics>,
    /// Π in the table frame; `None`: Π is the workpiece system (FANUC WKP = 1), placed on the
    /// table at each block's end angles.
    frame: Option<Rigid>,
    /// Tool posture control (FANUC P1 / TPC, Syntec Pr3054 = 1).
    posture: bool,
    pub(super) tool_length: f64,
    /// Type 2: the tool direction last commanded, in Π (unit), and the inclination Q (degrees).
    direction: Vec3,
    inclination: f64,
    /// Type 2: this block's I/J/K (omitted ones 0), if it has any.
    commanded: Option<Vec3>,
    /// The start block is being executed: its move is an ordinary one.
    starting: bool,
    /// The machine position at the end of the start block (the table angles WKP = 1 arcs are
    /// checked against, M-13).
    start_machine: Pos,
    /// Cutting point control (G43.8/G43.9): the program's X/Y/Z are the cutting point.
    pub(super) cutting: Option<super::cutting_point::CuttingPoint>,
}

impl Tcp {
    /// The tool direction is a vector I, J, K (G43.5, G43.9), not the rotary angles.
    fn type2(&self) -> bool {
        code::TCP_TYPE2.contains(&self.code)
    }
}

impl State {
    pub(super) fn tcp_active(&self) -> bool {
        self.tcp.is_some()
    }

    /// Under TCP, a table rotary axis stands elsewhere than at the end of the TCP start block
    /// (angles compared modulo 360°: the table's turn, not the axis's count, fixes a table
    /// coordinate system). False without TCP.
    pub(super) fn table_turned_since_tcp_start(&self) -> bool {
        let (Some(t), Some(now)) = (&self.tcp, self.follow_machine) else { return false };
        t.kin.joints().iter().any(|j| {
            j.side == crate::machine::Side::Table
                && j.index.is_some_and(|i| {
                    let d = (now[i] - t.start_machine[i]).rem_euclid(360.0);
                    d.min(360.0 - d) > 1e-6
                })
        })
    }

    /// Whether moves follow the tool tip through the kinematics (TCP or a tilted plane).
    pub(super) fn follows_tip(&self) -> bool {
        self.tcp.is_some() || self.plane_active() || self.table_crc_active() || self.wse_follows()
    }

    /// A move under TCP or in the tilted plane (`follows_tip`).
    pub(super) fn tip_motion(
        &mut self,
        kind: MotionKind,
        target: Pos,
        arc: Option<Box<Arc>>,
        out: &mut Vec<crate::canon::Canon>,
    ) -> Result<(), AlarmId> {
        if self.tcp_active() {
            self.tcp_motion(kind, target, arc, out)
        } else if self.plane_active() {
            self.plane_motion(kind, target, arc, out)
        } else if self.table_crc_active() {
            self.table_crc_motion(kind, target, arc, out)
        } else {
            self.wse_motion(kind, target, arc, out)
        }
    }

    /// The work offsets (G54…, external, G52, G92) of every axis: programming + this = machine,
    /// without tool length.
    pub(super) fn offset_vector(&self) -> Pos {
        let w = self.offsets.work(self.work_index());
        let ext = self.external_offset();
        std::array::from_fn(|i| w[i] + ext[i] + self.local[i] + self.shift[i])
    }

    /// A frame that puts programming coordinates on the table as it stands at `machine`:
    /// the point `p` is at `p + offsets + nose` in machine coordinates there (the same tip a
    /// plain G43 gives at zero angles).
    pub(super) fn frame_on_table(&self, kin: &Kinematics, machine: &Pos) -> Rigid {
        let wcs = self.wcs_on_table(kin, machine);
        // Under G54.4 programming coordinates are in the workpiece setting system.
        self.active_setting_error().map_or(wcs, |(_, e)| wcs.then(&e))
    }

    /// As `frame_on_table` for workpiece coordinates (without a G54.4 error).
    pub(super) fn wcs_on_table(&self, kin: &Kinematics, machine: &Pos) -> Rigid {
        let table = kin.table_frame(machine);
        let off = self.offset_vector();
        let shift = Vec3::new(off[0], off[1], off[2]) + kin.nose;
        let r = table.r.transpose();
        Rigid { r, o: r * (shift - table.o) }
    }

    /// The block starts (or restarts with new data) tool centre point control (group 08 is
    /// G43.4/G43.5 and the block commands it).
    /// `machine_before`: where the machine stands at the block's start (the position before
    /// group 08 changed the tool length the program position is read with).
    pub(super) fn tcp_begin(&mut self, w: &Words, machine_before: Pos) -> Result<(), AlarmId> {
        let Some(kin) = self.kinematics.clone() else {
            return Err(AlarmId::IllegalCommandInTcp);
        };
        if self.cfg.dialect == crate::Dialect::Fanuc {
            let five = &self.cfg.machine.five_axis;
            // TCP-14, TV-65: TCP needs linear-type rapids (LRP = 1) and look-ahead set up for
            // rapids and cutting feed (FRP, No.1671, No.1660; No.1672 always exists in the model).
            let motion = &self.cfg.machine.motion;
            if motion.nonlinear_rapid || !motion.look_ahead_set_up() {
                return Err(AlarmId::TcpParameter);
            }
            // TCP-08/23, TV-60: type 2 cannot work in the workpiece system (WKP = 1); on every
            // kind of machine (Q-23, decision: the parameter check does not look at the type).
            if code::TCP_TYPE2.contains(&self.modes[group::LENGTH_COMP])
                && five.tcp_coordinates == TcpCoordinates::Workpiece
            {
                return Err(AlarmId::MachineParameter);
            }
            // §2.3.19 CAUTION 1 (TCP-35): a movement range whose lower limit is above its upper
            // limit raises PS5459 "when G43.5 is specified", not at the first block that needs
            // the type 2 angles.
            if code::TCP_TYPE2.contains(&self.modes[group::LENGTH_COMP])
                && kin.joints().iter().any(|j| j.range.is_some_and(|[lo, hi]| lo > hi))
            {
                return Err(AlarmId::MachineParameter);
            }
        }
        let haas = self.cfg.dialect == crate::Dialect::Haas;
        let machine = if haas { machine_before } else { self.machine_position() };
        if haas && self.h == 0 {
            // Haas G234 takes the tool length from H (given in the block or in force): without
            // one the tip would be the spindle nose (decision, `docs/dialects.md`, "Haas 5-axis").
            return Err(AlarmId::TcpcNoToolLength);
        }
        // The start block is read in the workpiece system on the table as it stands (TCP-22:
        // also with INZ = 1); the frame for later blocks is set at its end (`tcp_started`).
        // Haas TCPC: the work coordinate system is fixed to the table as it is at the rotary
        // axes' zero (the active work offset and the MRZP), from the G234 block on.
        let frame = Some(if haas {
            self.frame_on_table(&kin, &self.at_rotary_zero(&kin, &machine))
        } else {
            self.frame_on_table(&kin, &machine)
        });
        // The NGC has no tool posture control: the rotary axes interpolate their angles.
        let posture = match w.integer(b'P') {
            _ if haas => false,
            Some(p) => p == 1.0,
            None => self.cfg.machine.five_axis.posture_control,
        };
        let tool_length = self.offsets.length(self.h);
        let tool = kin.forward(&machine, tool_length).tool;
        let inclination =
            if self.modes[group::LENGTH_COMP] == code::G43_5 { self.angle_word(w, b'Q').unwrap_or(0.0) } else { 0.0 };
        let cutting = self.cutting_begin(w)?;
        self.tcp = Some(Tcp {
            code: self.modes[group::LENGTH_COMP],
            kin: kin.clone(),
            frame,
            posture,
            tool_length,
            direction: tool,
            inclination,
            commanded: None,
            starting: true,
            start_machine: machine,
            cutting,
        });
        self.follow_machine = Some(machine);
        if haas {
            // The G234 block does not move by itself (decision): the current point becomes
            // the tool tip, length H, in the table-fixed work coordinates, where it stands.
            if let Some(f) = frame {
                self.pos = self.tip_position(&kin, &f, &machine, tool_length);
                self.sync_programmed();
            }
        }
        Ok(())
    }

    /// After the start block: Π as the machine's setting says, and the tool direction in it.
    fn tcp_started(&mut self) {
        let (Some(t), Some(machine)) = (&self.tcp, self.follow_machine) else { return };
        let kin = t.kin.clone();
        let frame = match self.tcp_coordinates() {
            TcpCoordinates::TableAtStart => Some(self.frame_on_table(&kin, &machine)),
            TcpCoordinates::TableAtZero => Some(self.frame_on_table(&kin, &self.at_rotary_zero(&kin, &machine))),
            TcpCoordinates::Workpiece => None,
        };
        let t = self.tcp.as_mut().expect("checked above");
        let pose = kin.forward(&machine, t.tool_length);
        // In Π, or for the workpiece system in machine directions.
        t.direction = frame.map_or(pose.tool_machine, |f| f.r.transpose() * pose.tool);
        t.frame = frame;
        t.starting = false;
        t.start_machine = machine;
        self.tcp_moved_to(machine);
    }

    /// Where Π is fixed after the start block. Haas TCPC has one convention, whatever the FANUC
    /// parameters say: the work coordinate system fixed to the table at the rotary zero
    /// (`tcp_begin`).
    fn tcp_coordinates(&self) -> TcpCoordinates {
        match self.cfg.dialect {
            crate::Dialect::Haas => TcpCoordinates::TableAtZero,
            _ => self.cfg.machine.five_axis.tcp_coordinates,
        }
    }

    /// This block starts TCP and its X/Y/Z are read in another system than Π (FANUC INZ = 1,
    /// Syntec Pr3055 = 1: the start block moves in the workpiece system, the next blocks in the
    /// table system at zero, §2.3.5). Its end then sets the current point itself, the tip in Π
    /// (`tcp_started`); the block's programmed X/Y/Z must not stand for it, or the next block's
    /// incremental and omitted coordinates would be the start block's workpiece values.
    pub(super) fn tcp_start_changes_system(&self) -> bool {
        self.tcp.as_ref().is_some_and(|t| t.starting)
            && self.cfg.dialect != crate::Dialect::Haas
            && self.tcp_coordinates() == TcpCoordinates::TableAtZero
    }

    /// `machine` with every rotary axis at its program zero (machine angle = work offset).
    pub(super) fn at_rotary_zero(&self, kin: &Kinematics, machine: &Pos) -> Pos {
        let off = self.offset_vector();
        let mut zero = *machine;
        for j in kin.joints() {
            if let Some(i) = j.index {
                zero[i] = off[i];
            }
        }
        zero
    }

    /// Programming coordinates at `machine`: X/Y/Z the tool tip (`tool_length` long) in `frame`
    /// (programming coordinates → table frame), the other axes the machine's minus the offsets.
    pub(super) fn tip_position(&self, kin: &Kinematics, frame: &Rigid, machine: &Pos, tool_length: f64) -> Pos {
        let p = frame.from_parent(&kin.forward(machine, tool_length).tip);
        let off = self.offset_vector();
        let mut pos: Pos = std::array::from_fn(|i| machine[i] - off[i]);
        for (axis, index) in kin.linear.iter().enumerate() {
            if let Some(i) = index {
                pos[*i] = p[axis];
            }
        }
        pos
    }

    /// The block cancels tool centre point control (G49): the current point becomes the tool
    /// tip in the workpiece system; the block's move then removes the tool length at its end.
    pub(super) fn tcp_end(&mut self) {
        let (Some(t), Some(machine)) = (self.tcp.take(), self.follow_machine.take()) else { return };
        let programmed = self.pos;
        let frame = self.frame_on_table(&t.kin, &machine);
        self.pos = self.tip_position(&t.kin, &frame, &machine, t.tool_length);
        if self.wse_follows() {
            // G54.4 with RCM = 1 goes on: the machine position stays beside the tip and the
            // rotary coordinates are programmed angles, so the G49 block compensates them once:
            // type 1's as programmed, type 2's (machine angles for a direction in Π, which
            // holds the error) the angles whose error-free direction is the actual one.
            self.follow_machine = Some(machine);
            let angles = if t.type2() { self.wse_programmed_angles(&machine) } else { Some(programmed) };
            if let Some(angles) = angles {
                self.wse_keep_programmed_angles(&angles);
            }
        }
        self.sync_programmed();
    }

    /// The machine was moved outside the program (manual intervention during TCP), or the
    /// start block ended: the current point becomes the tool tip there, in Π (under cutting
    /// point control the cutting point, the tool's vector back from the tip).
    pub(super) fn tcp_moved_to(&mut self, machine: Pos) {
        let Some(t) = &self.tcp else { return };
        let kin = t.kin.clone();
        let frame = t.frame.unwrap_or_else(|| self.frame_on_table(&kin, &machine));
        self.cutting_moved_to(&kin, &machine);
        let t = self.tcp.as_ref().expect("checked above");
        self.pos = self.tip_position(&kin, &frame, &machine, t.tool_length);
        // Under cutting point control the current point is the cutting point, the tool's
        // vector back from the tip.
        if let Some(c) = &t.cutting {
            let back = frame.r.transpose() * c.vector;
            for (axis, index) in kin.linear.iter().enumerate() {
                if let Some(i) = index {
                    self.pos[*i] -= back[axis];
                }
            }
        }
        self.follow_machine = Some(machine);
        self.sync_programmed();
    }

    /// Type 2: the block's I/J/K (a tool direction, not an arc centre) and Q.
    pub(super) fn tcp_words(&mut self, w: &Words) -> Result<(), AlarmId> {
        // `,L2 I J K`: the surface normal of cutting point control, kept until a move takes it.
        let cutting = self.tcp.as_ref().is_some_and(|t| t.cutting.is_some());
        if let Some(normal) = self.surface_normal(w, cutting)? {
            // (The start block's normal is taken where it starts, `cutting_begin`.)
            let t = self.tcp.as_mut().expect("only cutting point control takes ,L2");
            if let (Some(c), false) = (&mut t.cutting, t.starting) {
                c.commanded = Some(normal);
            }
        }
        let Some(t) = &self.tcp else { return Ok(()) };
        if !t.type2() {
            return Ok(());
        }
        let [i, j, k] = [b'I', b'J', b'K'].map(|l| self.value(w, l));
        if t.starting && [i, j, k].iter().any(Option::is_some) {
            // §2.2.3: a tool rotation machine may give the direction in the G43.5 block itself,
            // which turns the tool there (`tcp_motion`); a table or mixed machine may not
            // (PS5421, the mode rule TCP-08 for FANUC; the same for the other dialects).
            // *Decision*: with an inclination Q the start block's lean is not defined (its
            // move is not a tip travel under TCP): refused.
            if !t.kin.table.is_empty() || t.inclination != 0.0 {
                return Err(AlarmId::IllegalCommandInTcp);
            }
        } else if t.starting {
            return Ok(());
        }
        let commanded = if i.is_none() && j.is_none() && k.is_none() {
            None
        } else {
            // A zero vector: Syntec COR-159; FANUC names no alarm, the direction stays.
            let mut v = Vec3::new(i.unwrap_or(0.0), j.unwrap_or(0.0), k.unwrap_or(0.0));
            // FANUC MIR (TCP-46): the mirror image of X/Y/Z mirrors I/J/K too; without it the
            // direction stays as programmed.
            if self.cfg.machine.five_axis.mirror_direction {
                for (axis, index) in t.kin.linear.iter().enumerate() {
                    if index.is_some_and(|i| self.xf.mirrors(i)) {
                        v[axis] = -v[axis];
                    }
                }
            }
            let v = v.try_normalize(1e-12);
            if v.is_none() && self.cfg.dialect == crate::Dialect::Syntec {
                return Err(AlarmId::ZeroToolVector);
            }
            v
        };
        self.tcp.as_mut().expect("checked above").commanded = commanded;
        Ok(())
    }

    /// Whether group 01's I/J/K are a tool direction here (type 2), not an arc centre.
    pub(super) fn ijk_is_direction(&self) -> bool {
        self.tcp.as_ref().is_some_and(|t| t.type2() && !t.starting)
    }

    /// A motion under tool centre point control to `target` (Π; rotary axes as programmed),
    /// with the circle `arc` (in Π) for G02/G03.
    pub(super) fn tcp_motion(
        &mut self,
        kind: MotionKind,
        mut target: Pos,
        arc: Option<Box<Arc>>,
        out: &mut Vec<crate::canon::Canon>,
    ) -> Result<(), AlarmId> {
        let t = self.tcp.as_ref().expect("tcp_motion under TCP");
        if t.cutting.is_some_and(|c| c.disturbed) {
            return Err(AlarmId::CuttingPoint);
        }
        let kin = t.kin.clone();
        let from_machine = self.machine_position();
        let off = self.offset_vector();
        let mut through_singular = false;
        // (The start block turns the tool only to a direction it gives: `tcp_words`.)
        if t.type2() && (!t.starting || t.commanded.is_some()) {
            // Type 2: the rotary angles that give the commanded direction (TCP-09, M-10).
            let mut v = t.commanded.unwrap_or(t.direction);
            if t.inclination != 0.0 {
                v = incline(v, xyz(&kin, &target) - xyz(&kin, &self.pos), t.inclination);
            }
            let frame = t.frame.unwrap_or_else(|| self.frame_on_table(&kin, &from_machine));
            let tip = frame.to_parent(&xyz(&kin, &target));
            let candidates = kin.inverse(tip, frame.r * v, t.tool_length, &from_machine[..kin.axes]);
            let how = Selection { dialect: self.cfg.dialect, pri: self.cfg.machine.five_axis.second_axis_first, p: 0 };
            let mut choice = kin.select(&candidates, &from_machine[..kin.axes], how)?;
            // Near a singular posture a FANUC TPC line may end through it instead (M-9), but
            // not while workpiece setting error compensation is on (WSE-24).
            if t.posture
                && !t.starting
                && self.wse.is_none()
                && self.cfg.dialect == crate::Dialect::Fanuc
                && matches!(kind, MotionKind::Rapid | MotionKind::Linear)
            {
                let five = self.cfg.machine.five_axis;
                through_singular =
                    super::singular::change_end(&kin, &five, &from_machine[..kin.axes], &mut choice.pos)?;
            }
            for j in kin.joints() {
                if let Some(i) = j.index {
                    target[i] = choice.pos[i] - off[i];
                }
            }
            if let Some(c) = t.commanded {
                self.tcp.as_mut().expect("under TCP").direction = c;
            }
        }
        if self.cfg.dialect == crate::Dialect::Fanuc
            && turns_with_the_tip_standing(&kin, kind, &arc, &self.pos, &target)
        {
            // TCP-06/07/10: a move that turns the rotary axes only must be G00/G01. The mode rule
            // (`modes.rs`) sees a G02/G03 without X/Y/Z words; this one an R circle to its own
            // start point (no circle, `State::arc`) while the tool turns.
            return Err(AlarmId::IllegalCommandInTcp);
        }
        let programmed = target;
        if self.tcp.as_ref().is_some_and(|t| !t.type2()) {
            // Type 1 under G54.4 with RCM = 1: the programmed angles seen from the WSCS.
            self.wse_compensate(&kin, &mut target)?;
        }
        let t = self.tcp.as_ref().expect("under TCP");
        let mut machine_end: Pos = std::array::from_fn(|i| target[i] + off[i]);
        // Syntec Pr3054 = 1 reads a cutting block as a tool vector (SYN-10, TV-10): end angles
        // on the other branch of the inverse than the start's would make the axes jump off the
        // V1–V2 plane, so the block ends at the equivalent pair the plane leads to.
        let tool_vector = t.posture && self.cfg.dialect == crate::Dialect::Syntec && kind != MotionKind::Rapid;
        if tool_vector
            && !t.starting
            && !crate::motion::path::great_circle_continuous(&kin, &from_machine, &machine_end)
        {
            let v2 = kin.forward(&machine_end, 0.0).tool;
            if let Some(end) = kin.angles_near(v2, &from_machine) {
                let mut equivalent = machine_end;
                for i in kin.joints().iter().filter_map(|j| j.index) {
                    equivalent[i] = end[i];
                }
                if crate::motion::path::great_circle_continuous(&kin, &from_machine, &equivalent) {
                    for i in kin.joints().iter().filter_map(|j| j.index) {
                        (machine_end[i], target[i]) = (equivalent[i], equivalent[i] - off[i]);
                    }
                }
            }
        }
        if self.cfg.dialect == crate::Dialect::Syntec {
            kin.syntec_move_in_range(&from_machine, &machine_end)?;
        }
        if let (Some(a), None, false) = (&arc, t.frame, t.starting) {
            workpiece_arc_allowed(&kin, a.plane_axes.2, &t.start_machine, &from_machine, &machine_end)?;
        }
        // The start block is placed in the workpiece system on the table as it will stand;
        // later blocks in Π (or the workpiece system at the block's end angles, WKP = 1).
        let frame = match (t.starting, t.frame) {
            (false, Some(f)) => f,
            // Haas: Π from the G234 block on (`tcp_begin`).
            (true, Some(f)) if self.cfg.dialect == crate::Dialect::Haas => f,
            _ => self.frame_on_table(&kin, &machine_end),
        };
        // FANUC tool posture control acts on lines (G00 of the linear type, G01) and circles
        // (its own arc rule, M-8); Syntec's tool-vector interpolation on cutting moves (G01,
        // G02, G03).
        let posture = t.posture
            && !through_singular
            && match self.cfg.dialect {
                crate::Dialect::Fanuc => true,
                crate::Dialect::Syntec => kind != MotionKind::Rapid,
                // The NGC has no tool posture control (`tcp_begin` never turns it on).
                crate::Dialect::Haas => false,
            };
        if let (true, Some(a), crate::Dialect::Fanuc, false) = (posture, &arc, self.cfg.dialect, t.starting) {
            posture_stays_on_one_side(&kin, a, &frame, &from_machine, &machine_end, t.tool_length)?;
        }
        let (tool_length, starting) = (t.tool_length, t.starting);
        let cutting = match self.tcp.as_mut().and_then(|t| t.cutting.as_mut()) {
            Some(c) => {
                let normals = c.take_normals(&frame)?;
                let singular_deg = self.cfg.machine.five_axis.cutting_point_singular_angle;
                Some(CuttingMove { tool: c.tool, normals, singular_deg, start: c.vector })
            }
            None => None,
        };
        let path = FollowPath { frame, tool_length, posture, along: !starting, cutting, head_fixed: false };
        self.follow_motion(&kin, kind, target, arc, path, out)?;
        if let Some(c) = self.tcp.as_mut().and_then(|t| t.cutting.as_mut()) {
            let tip = kin.forward(&self.follow_machine.expect("a tip move leaves it"), tool_length).tip;
            c.vector = tip - frame.to_parent(&xyz(&kin, &target));
        }
        if starting {
            self.tcp_started();
        }
        self.wse_keep_programmed_angles(&programmed);
        Ok(())
    }

    /// Emit a motion to `target` (programming coordinates) whose X/Y/Z are the tool tip placed
    /// on the table by `path.frame`; the other axes go to `target` plus the work offsets.
    pub(super) fn follow_motion(
        &mut self,
        kin: &Shared<Kinematics>,
        kind: MotionKind,
        target: Pos,
        arc: Option<Box<Arc>>,
        path: FollowPath,
        out: &mut Vec<crate::canon::Canon>,
    ) -> Result<(), AlarmId> {
        let from_machine = self.machine_position();
        let off = self.offset_vector();
        let FollowPath { frame, tool_length, posture, along, cutting, head_fixed } = path;
        // G54.4's compensation along the way, as the block's `wse_compensate` left it.
        let compensation = self.wse_between.take();
        // The rotary axes' end is known here; X/Y/Z are placed below, for the tip.
        let mut machine: Pos = std::array::from_fn(|i| target[i] + off[i]);
        let tip_to = frame.to_parent(&xyz(kin, &target));
        let tip = along.then(|| {
            let mut from = kin.forward(&from_machine, tool_length);
            if head_fixed {
                from.tip = kin.unturned_tip(&from_machine, tool_length);
            }
            if let Some(c) = &cutting {
                // The path is the cutting point's.
                from.tip -= c.start;
            }
            let end_tool = kin.forward(&machine, tool_length).tool;
            let tip_arc = arc.as_deref().map(|a| {
                let mut normal = Vec3::zeros();
                if let Some(axis) = kin.linear.iter().position(|&i| i == Some(a.plane_axes.2)) {
                    normal[axis] = 1.0;
                }
                TipArc {
                    center: frame.to_parent(&xyz(kin, &a.center)),
                    normal: frame.r * normal,
                    sweep_deg: a.sweep_deg,
                }
            });
            Box::new(TipMove {
                from: from.tip,
                to: tip_to,
                arc: tip_arc,
                tool_length,
                posture: posture.then_some((from.tool, end_tool)),
                posture_on_arc: self.cfg.dialect == crate::Dialect::Fanuc,
                display_shift: display_shift(self, kin),
                deviation: deviation_limit(self, kind),
                frame,
                rotary_feed: self.cfg.machine.five_axis.rotary_feed,
                rotary_clamp: self.wse_rotary_clamp(kind),
                compensation,
                cutting,
                head_fixed,
            })
        });
        // Cutting point control puts the tip away from the cutting point as the path turns
        // the tool (an ordinary start block: by the tool's own vector at its end).
        let aimed = match (&cutting, &tip) {
            (Some(_), Some(t)) => {
                tip_to
                    + crate::motion::path::cutting_end(kin, t, &from_machine, &machine).ok_or(AlarmId::CuttingPoint)?
            }
            (Some(c), None) => tip_to + c.tool.vector(kin.forward(&machine, 0.0).tool, c.normals.1),
            (None, _) => tip_to,
        };
        let carriage = if head_fixed {
            kin.carriage_for_unturned(&machine, aimed, tool_length)
        } else {
            kin.carriage_for(&machine, aimed, tool_length)
        };
        for (axis, index) in kin.linear.iter().enumerate() {
            if let Some(i) = index {
                machine[*i] = carriage[axis];
            }
        }
        let mut motion = self.motion(kind, target, machine, None, tip);
        self.wse_display(&mut motion);
        self.emit(out, CanonKind::Motion(motion));
        self.pos = target;
        self.follow_machine = Some(machine);
        Ok(())
    }
}

impl State {
    /// FANUC DET = 1 (TCP-26): the current point as the absolute display shows it under TCP
    /// with Π fixed on the table — the tip in the workpiece system (as [`display_shift`] gives
    /// it for every sample); `None` when the display shows the programming coordinates.
    pub(super) fn tcp_shown(&self) -> Option<Pos> {
        let t = self.tcp.as_ref()?;
        let (kin, frame) = (&t.kin, t.frame.as_ref()?);
        let shift = display_shift(self, kin)?;
        let tip = kin.table_frame(&self.machine_position()).to_parent(&frame.to_parent(&xyz(kin, &self.pos))) - shift;
        let mut shown = self.pos;
        for (axis, index) in kin.linear.iter().enumerate() {
            if let Some(i) = index {
                shown[*i] = tip[axis];
            }
        }
        Some(shown)
    }
}

/// FANUC DET (TCP-26): under TCP with Π fixed on the table (WKP = 0), the absolute position
/// shows the tip in the workpiece system: machine coordinates minus the work offsets and the
/// nose (where a plain G43 puts the programmed point).
fn display_shift(state: &State, kin: &Kinematics) -> Option<Vec3> {
    shows_workpiece(state).then(|| {
        let off = state.offset_vector();
        Vec3::new(off[0], off[1], off[2]) + kin.nose
    })
}

/// Whether TCP's position display shows the tip in the workpiece system (DET with Π on the
/// table) instead of in Π.
pub(super) fn shows_workpiece(state: &State) -> bool {
    // (The table coordinate system of 5-axis cutter compensation is on the table too, and
    // FANUC's DET, No.19608#2, chooses its display the same way: CRC-38.)
    let on_table = state.tcp.as_ref().is_some_and(|t| t.frame.is_some()) || state.table_crc_active();
    on_table && state.cfg.machine.five_axis.display_workpiece
}

/// FANUC CRS (TCP-25, M-12): the path deviation a TCP move's speed must keep to: No.19751 for
/// rapids, No.19752 for cutting; 0 is the least input increment, a negative value no clamp.
fn deviation_limit(state: &State, kind: MotionKind) -> Option<f64> {
    let f = &state.cfg.machine.five_axis;
    if !f.deviation_clamp || !state.tcp_active() {
        return None;
    }
    let limit = if kind == MotionKind::Rapid { f.rapid_deviation } else { f.cutting_deviation };
    match limit {
        x if x < 0.0 => None,
        0.0 => Some(0.001),
        x => Some(x),
    }
}

/// How a motion follows a tool tip path.
#[derive(Debug, Clone, Copy)]
pub(super) struct FollowPath {
    /// Programming coordinates → table frame.
    pub(super) frame: Rigid,
    pub(super) tool_length: f64,
    /// Tool posture control (great-circle tool direction).
    pub(super) posture: bool,
    /// The tip follows the path; `false`: an ordinary move to the end point (TCP start block).
    pub(super) along: bool,
    /// Cutting point control: X/Y/Z are the cutting point, the tip away from it.
    pub(super) cutting: Option<CuttingMove>,
    /// Without TCP (5-axis cutter compensation in the table coordinate system): X/Y/Z are the
    /// unturned tip, which the table's turn carries and the head's does not (`TipMove::head_fixed`).
    pub(super) head_fixed: bool,
}

/// FANUC M-13 (§2.3.7, TV-30…42): a circle under TCP in the workpiece system (WKP = 1) is
/// refused (PS5421) when a table rotary axis whose line is not normal to the plane turns in the
/// block, or stands at another angle than at the end of the TCP start block. The line is taken
/// in machine directions (those of W) at the block start, tilted by any table axis carrying it;
/// tool rotary axes are free.
fn workpiece_arc_allowed(kin: &Kinematics, normal: usize, at_start: &Pos, from: &Pos, to: &Pos) -> Result<(), AlarmId> {
    let Some(normal_axis) = kin.linear.iter().position(|&i| i == Some(normal)) else {
        return Ok(());
    };
    for (k, j) in kin.table.iter().enumerate() {
        let Some(i) = j.index else { continue };
        let line = kin.table_axis_direction(k, from);
        let normal = line.cross(&Vec3::ith(normal_axis, 1.0)).norm() < 1e-9;
        let turns = (to[i] - from[i]).abs() > 1e-9;
        let moved = (from[i] - at_start[i]).abs() > 1e-9;
        if !normal && (turns || moved) {
            return Err(AlarmId::IllegalCommandInTcp);
        }
    }
    Ok(())
}

/// Programming coordinates carried by the table's turn over a block: a circle under TCP in
/// the workpiece system (WKP = 1) is on the table (§2.2.2: the tip "moves along an arc with
/// respect to the table"; §2.3.7: "the start point, end point, and center of an arc change as
/// the table rotation axis rotates"), so its start point, and the centre I/J/K give from it
/// ("the vector … from the start point in the rotary axis position" of the block's start), are
/// taken where the table carries them by the block's end, where the end point is read.
pub(super) struct Carry {
    kin: Shared<Kinematics>,
    /// Programming coordinates at the block's start → the same table points' at its end.
    map: Rigid,
}

impl Carry {
    /// Where the table carries the point `p` (its X/Y/Z; the other axes stay).
    pub(super) fn point(&self, p: &Pos) -> Pos {
        with_xyz(&self.kin, p, self.map.to_parent(&xyz(&self.kin, p)))
    }

    /// The vector `v` along the plane axes `(a, b)` as the table turns it (the circle's plane
    /// is normal to the turning axis, `workpiece_arc_allowed`, so it stays in the plane).
    pub(super) fn vector(&self, (a, b): (usize, usize), v: (f64, f64)) -> (f64, f64) {
        let mut p: Pos = [0.0; crate::machine::MAX_AXES];
        (p[a], p[b]) = v;
        let turned = with_xyz(&self.kin, &p, self.map.r * xyz(&self.kin, &p));
        (turned[a], turned[b])
    }
}

impl State {
    /// A G02/G03 in the plane whose normal is the axis `normal`, to `target`: under TCP in the
    /// workpiece system (WKP = 1) the rule of M-13 (PS5421), then, where a table axis turns in
    /// the block, how the table carries the circle's start and centre (`Carry`). `None`: the
    /// circle is read as it is.
    pub(super) fn workpiece_arc_carry(&self, target: &Pos, normal: usize) -> Result<Option<Carry>, AlarmId> {
        let Some(t) = self.tcp.as_ref().filter(|t| t.frame.is_none() && !t.starting) else { return Ok(None) };
        let kin = t.kin.clone();
        let from = self.machine_position();
        let off = self.offset_vector();
        let mut to = from;
        for i in kin.joints().iter().filter_map(|j| j.index) {
            to[i] = target[i] + off[i];
        }
        workpiece_arc_allowed(&kin, normal, &t.start_machine, &from, &to)?;
        if !kin.table.iter().filter_map(|j| j.index).any(|i| (to[i] - from[i]).abs() > 1e-9) {
            return Ok(None);
        }
        let (start, end) = (self.frame_on_table(&kin, &from), self.frame_on_table(&kin, &to));
        let map = Rigid { r: end.r.transpose() * start.r, o: end.from_parent(&start.o) };
        Ok(Some(Carry { kin, map }))
    }
}

/// FANUC tool posture control on a circle (M-8, TCP-29): the tool keeps to one side of the
/// plane; a start and end direction on opposite sides are refused (P/S0432). A direction in the
/// plane (within 1e-6) is on either side (and the block turns on the great circle, `motion::path`).
fn posture_stays_on_one_side(
    kin: &Kinematics,
    arc: &Arc,
    frame: &Rigid,
    from: &Pos,
    to: &Pos,
    tool_length: f64,
) -> Result<(), AlarmId> {
    let Some(axis) = kin.linear.iter().position(|&i| i == Some(arc.plane_axes.2)) else { return Ok(()) };
    let normal = frame.r * Vec3::ith(axis, 1.0);
    let side = |p: &Pos| kin.forward(p, tool_length).tool.dot(&normal);
    let (s, e) = (side(from), side(to));
    if (s > 1e-6 && e < -1e-6) || (s < -1e-6 && e > 1e-6) {
        return Err(AlarmId::PostureCrossesPlane);
    }
    Ok(())
}

/// X, Y, Z of a position (the machine's linear axes; a missing one 0).
pub(super) fn xyz(kin: &Kinematics, p: &Pos) -> Vec3 {
    let mut v = Vec3::zeros();
    for (axis, index) in kin.linear.iter().enumerate() {
        v[axis] = index.map_or(0.0, |i| p[i]);
    }
    v
}

/// A G02/G03 that has no circle (an R arc whose end point is its start point in the plane)
/// and no move along the normal either, while a rotary axis turns: the tip stands.
fn turns_with_the_tip_standing(
    kin: &Kinematics,
    kind: MotionKind,
    arc: &Option<Box<Arc>>,
    from: &Pos,
    to: &Pos,
) -> bool {
    matches!(kind, MotionKind::ArcCw | MotionKind::ArcCcw)
        && arc.is_none()
        && (xyz(kin, to) - xyz(kin, from)).norm() < 1e-9
        && kin.joints().iter().filter_map(|j| j.index).any(|i| (to[i] - from[i]).abs() > 1e-9)
}

/// `p` with its X/Y/Z (the machine's linear axes) set to `v`.
fn with_xyz(kin: &Kinematics, p: &Pos, v: Vec3) -> Pos {
    let mut out = *p;
    for (axis, index) in kin.linear.iter().enumerate() {
        if let Some(i) = index {
            out[*i] = v[axis];
        }
    }
    out
}

/// Type 2 inclination Q (TCP-13, M-6): `v` leans by `deg` toward the direction of travel, in
/// the plane of the two (unchanged when the tip does not move or moves along `v`).
fn incline(v: Vec3, travel: Vec3, deg: f64) -> Vec3 {
    let Some(d) = travel.try_normalize(1e-12) else { return v };
    let Some(perp) = (d - v * d.dot(&v)).try_normalize(1e-9) else { return v };
    let (s, c) = crate::angle::sin_cos_deg(deg);
    v * c + perp * s
}
