//! 5-axis cutter compensation in the table coordinate system without tool centre point control
//! (FANUC No.19746#4 TBP = 1 with No.19696#5 WKP = 0 on a machine with a rotary table; CRC-38,
//! M-14, the 5-axis manual's §3.2.2/§3.3.2). Under TCP the table coordinate system is TCP's Π
//! (`super::tcp`); without it this module makes it:
//!
//! - At the end of the start block (G41.2/G42.2, or G41.4/G41.5 with SPG) the workpiece system
//!   is frozen to the table as the table then stands (INZ = 0: "a table rotary move in the start
//!   block is completed first"), or as it stands with the table axes at 0 (INZ = 1, No.19754#5).
//!   The start block itself is an ordinary move in the workpiece system.
//! - The blocks of the mode, up to and including the G40 block, read X/Y/Z in that system: their
//!   point is carried by the table (`canon::TipMove::head_fixed`: the point a plain G43 puts at
//!   X/Y/Z, which a head axis does not move — no TCP — but the table's turn does), on a straight
//!   line in the table system: while the table stands a straight line on the part, and where the
//!   block turns the table too, still a straight line on the part (the linear axes follow it
//!   through the table's turn; *decision*, as "linear interpolation is compensated on the table
//!   coordinate system" reads).
//! - After the G40 block the current point is the same machine position read in the workpiece
//!   system again.
//!
//! The stage compensates in the table system as it does under TCP (`stage::tool_shift`).
//! Rules and decisions: `docs/cutter-compensation.md`, "Tool side offset", rule 8.

use super::gcode::{code, group};
use super::tcp::{xyz, FollowPath};
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind, MotionKind, Pos};
use crate::geom::Rigid;
use crate::kin::Kinematics;
use crate::machine::{Side, TcpCoordinates};
use std::sync::Arc as Shared;

/// The table coordinate system of the compensation in force.
#[derive(Debug, Clone)]
pub(super) struct TableCrc {
    kin: Shared<Kinematics>,
    /// The table coordinate system in the table frame (programming coordinates → table frame).
    frame: Rigid,
}

impl State {
    /// 5-axis cutter compensation after this block works in the table coordinate system
    /// without TCP (the tool side offset on a machine with a rotary table, TBP = 1, WKP = 0).
    fn table_crc_applies(&self) -> bool {
        let five = &self.cfg.machine.five_axis;
        code::TOOL_SIDE.contains(&self.modes[group::CUTTER_COMP])
            && !self.tcp_active()
            && five.crc_in_table()
            && self.cfg.machine.rotary.iter().any(|l| l.side == Side::Table)
    }

    /// Whether the moves read X/Y/Z in the table coordinate system (this module).
    pub(super) fn table_crc_active(&self) -> bool {
        self.table_crc.is_some()
    }

    /// The unturned tip (table frame) with the axes at `machine` and the tool length of a plain
    /// G43 block.
    fn table_point(&self, kin: &Kinematics, machine: &Pos) -> crate::kin::Vec3 {
        kin.unturned_tip(machine, self.active_tool_length())
    }

    /// After the block's motion (`comp_before`: group 07 before the block): the start block
    /// freezes the table coordinate system, the G40 block (or the end of the mode any other
    /// way) leaves it. `first` is the index in `out` of the block's first command.
    pub(super) fn table_crc_after_block(&mut self, comp_before: u16, first: usize, out: &mut [Canon]) {
        let on = self.table_crc_applies();
        if self.table_crc.is_some() && !on {
            self.table_crc_end();
        } else if self.table_crc.is_none() && on && !code::TOOL_SIDE.contains(&comp_before) {
            self.table_crc_begin(first, out);
        }
    }

    /// Freeze the table coordinate system where the start block ends (CRC-38, M-14) and read
    /// the current point in it. The stage is told the system and the start block's ends in it
    /// (its end given as its motion's target, so that the compensation sees one system).
    fn table_crc_begin(&mut self, first: usize, out: &mut [Canon]) {
        let Some(kin) = self.kinematics.clone() else { return };
        let machine = self.machine_position();
        let at = match self.cfg.machine.five_axis.tcp_coordinates {
            TcpCoordinates::TableAtZero => self.at_rotary_zero(&kin, &machine),
            _ => machine,
        };
        let frame = self.wcs_on_table(&kin, &at);
        let in_table = |state: &State, machine: &Pos, pos: &Pos| -> Pos {
            let p = frame.from_parent(&state.table_point(&kin, machine));
            let mut pos = *pos;
            for (axis, index) in kin.linear.iter().enumerate() {
                if let Some(i) = index {
                    pos[*i] = p[axis];
                }
            }
            pos
        };
        // The start block's move (if any) ends here: its target in the table system.
        let mut moved = false;
        for c in out[first..].iter_mut() {
            if let CanonKind::Motion(m) = &mut c.kind {
                moved = true;
                m.target = in_table(self, &m.machine, &m.target);
            }
        }
        self.pos = in_table(self, &machine, &self.pos);
        self.sync_programmed();
        self.follow_machine = Some(machine);
        self.table_crc = Some(TableCrc { kin: kin.clone(), frame });
        // Where the start-up block starts: where the start block started, in the table system
        // (a start block without a move: here).
        if let Some(mut s) = self.cfg.stages.take_comp_start() {
            if moved {
                // The start block moves in the workpiece system: its start is read in the table
                // system as the table stands at its end, as its end is (a turn of the table alone
                // is no move in the plane; with INZ = 0 the numbers stay the workpiece system's).
                let mut from = s.machine;
                for i in kin.joints().iter().filter_map(|j| j.index) {
                    from[i] = machine[i];
                }
                s.pos = in_table(self, &from, &s.pos);
            } else {
                s.pos = self.pos;
            }
            s.table = Some(frame);
            self.cfg.stages.comp_started(s);
        }
    }

    /// The G40 block in the table coordinate system "suppresses buffering" (CRC-38): it is not
    /// read ahead, so the machine stops at the end of the block before it. fivex reads on (the
    /// path is the same) and gives the stop as a dwell of no time before the block's move, which
    /// every driver carries out by letting the motion before it end at rest.
    pub(super) fn table_crc_cancel_stop(&mut self, comp_before: u16, out: &mut Vec<Canon>) {
        let cancels = code::TOOL_SIDE.contains(&comp_before) && self.modes[group::CUTTER_COMP] == code::G40;
        if self.table_crc_active() && cancels {
            self.emit(out, CanonKind::Dwell { seconds: 0.0 });
        }
    }

    /// The mode ends: the current point is the machine position read in the workpiece system.
    pub(super) fn table_crc_end(&mut self) {
        if self.table_crc.take().is_none() {
            return;
        }
        if let Some(machine) = self.follow_machine.take() {
            self.pos = self.machine_to_program(&machine);
            self.sync_programmed();
        }
    }

    /// The machine was moved outside the program in the mode: the current point is read there.
    pub(super) fn table_crc_moved_to(&mut self, machine: Pos) {
        let Some(t) = &self.table_crc else { return };
        let (kin, frame) = (t.kin.clone(), t.frame);
        let p = frame.from_parent(&self.table_point(&kin, &machine));
        let off = self.offset_vector();
        self.pos = std::array::from_fn(|i| machine[i] - off[i]);
        for (axis, index) in kin.linear.iter().enumerate() {
            if let Some(i) = index {
                self.pos[*i] = p[axis];
            }
        }
        self.follow_machine = Some(machine);
        self.sync_programmed();
    }

    /// A move of the mode to `target` (table coordinate system; the rotary axes as programmed).
    pub(super) fn table_crc_motion(
        &mut self,
        kind: MotionKind,
        target: Pos,
        arc: Option<Box<crate::canon::Arc>>,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let t = self.table_crc.as_ref().expect("table_crc_motion in the mode");
        let (kin, frame) = (t.kin.clone(), t.frame);
        let path = FollowPath {
            frame,
            tool_length: self.active_tool_length(),
            posture: false,
            along: true,
            cutting: None,
            head_fixed: true,
        };
        self.follow_motion(&kin, kind, target, arc, path, out)
    }

    /// The current point in the workpiece system (FANUC DET = 1 under the table coordinate
    /// system: `None` when the display shows the table system, DET = 0).
    pub(super) fn table_crc_shown(&self) -> Option<Pos> {
        let t = self.table_crc.as_ref()?;
        if !self.cfg.machine.five_axis.display_workpiece {
            return None;
        }
        let machine = self.machine_position();
        let point = t.kin.table_frame(&machine).to_parent(&t.frame.to_parent(&xyz(&t.kin, &self.pos)));
        let off = self.offset_vector();
        let shift = crate::kin::Vec3::new(off[0], off[1], off[2]) + t.kin.nose;
        let mut shown = self.pos;
        for (axis, index) in t.kin.linear.iter().enumerate() {
            if let Some(i) = index {
                shown[*i] = point[axis] - shift[axis];
            }
        }
        Some(shown)
    }
}
