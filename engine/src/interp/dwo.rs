//! Haas G254 dynamic work offset (DWO) and G255, its cancel (group 23; `docs/dialects.md`,
//! "Haas 5-axis"). DWO is 3+2 positioning: with the rotary axes standing where the program put
//! them, G254 carries the active work offset's origin with the table's rotation about the rotary
//! centres (MRZP) and leaves the axes parallel to the machine's: the block's X/Y/Z are the tip
//! from that origin along machine X, Y, Z, so Z is the spindle direction and a canned cycle feeds
//! along the tool. That is how the Haas manual describes it ("applies the appropriate offsets to
//! account for the differences between the programmed workpiece location and the actual
//! workpiece location") and how Autodesk's Haas NGC post writes 3+2 programs (coordinates turned
//! by the remaining orientation, machine-aligned).
//!
//! fivex runs it as a tilted working plane (`super::plane`, `plane_motion`) whose feature
//! coordinate system, in the workpiece system, has the work origin and the machine's axes as the
//! table stands: the tool length along the tool as it stands, the current point the tip where it
//! stands (an X/Y block then moves machine X/Y only, as the manual's "X and Y in one block, Z in
//! a separate block" expects). The rules of the manual are checked before the block changes
//! anything (`super::modes`, the `Haas` rows): no rotary motion under G254 or in its block, not
//! with G234 or a tilted plane, the work offset's tilt axis at zero, and X, Y and Z all commanded
//! before the first cutting move (tracked here), no G28/G29 (the manual advises against them;
//! which point they start from is not said: a decision); only on machines whose rotary axes are
//! all on the table (decision: the pages describe table units; on a head the tool turns, and
//! whether the NGC's X/Y/Z would then turn with it is not said). G53 and M06 ignore it (they move
//! in machine terms; the current point follows), reset, M02, M30 and G255 cancel it, M00/M01 do
//! not.

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::geom::Rigid;

/// The bits of X, Y and Z in [`State::dwo_due`].
const XYZ: u8 = 0b111;

impl State {
    /// G254 is in force.
    pub(super) fn dwo_active(&self) -> bool {
        self.modes[group::DYNAMIC_FIXTURE] == code::G254
    }

    /// The linear axes not yet commanded since G254 (bits X 0, Y 1, Z 2).
    pub(super) fn dwo_due(&self) -> u8 {
        self.dwo_due
    }

    /// The machine has rotary axes for G254 to act on, all of them on the table: a 3-axis
    /// machine's kinematics has no joint (a 3-axis preset has kinematics too, so its presence
    /// alone says nothing); a head axis is refused (decision, see the module's note).
    pub(super) fn dwo_mechanism_fits(&self) -> bool {
        self.kinematics.as_ref().is_some_and(|k| k.head.is_empty() && !k.table.is_empty())
    }

    /// The DWO frame in the workpiece system at machine position `machine`: the work origin,
    /// carried by the table (`plane_frame` places the workpiece system on the table at the
    /// rotary zero), and the machine's axes as the table stands now, seen from the table at the
    /// rotary zero.
    fn dwo_frame(&self, machine: &crate::canon::Pos) -> Rigid {
        let Some(kin) = &self.kinematics else { return Rigid::identity() };
        let zero = self.at_rotary_zero(kin, machine);
        let r = kin.table_frame(&zero).r * kin.table_frame(machine).r.transpose();
        Rigid { r, o: nalgebra::Vector3::zeros() }
    }

    /// The active work offset's value on the tilt axis (the master of a trunnion, which carries
    /// the platter), 0 on other machines: the manual asks for 0 with G254 (a tilted work
    /// offset would turn the workpiece system out of the table's plane).
    pub(super) fn dwo_tilt_offset(&self) -> f64 {
        let Some(kin) = &self.kinematics else { return 0.0 };
        if kin.kind != crate::kin::MachineKind::TableTable {
            return 0.0;
        }
        let off = self.offset_vector();
        kin.joints().first().and_then(|j| j.index).map_or(0.0, |i| off[i])
    }

    /// The block's linear axis words X, Y, Z as bits 0, 1, 2.
    pub(super) fn xyz_given(&self, w: &Words) -> u8 {
        let Some(kin) = &self.kinematics else { return 0 };
        let mut bits = 0;
        for (k, index) in kin.linear.iter().enumerate() {
            if index.is_some_and(|i| w.has(self.cfg.machine.axes[i].name as u8)) {
                bits |= 1 << k;
            }
        }
        bits
    }

    /// The block's G254/G255 after the modal groups were updated (`before`: group 23 before
    /// the block). G254 carries the work origin with the table as it stands, the axes the
    /// machine's; G255 ends it, the machine staying where it is.
    pub(super) fn apply_dwo(&mut self, w: &Words, before: u16) {
        let given = self.xyz_given(w);
        let on = self.dwo_active();
        if on && before != code::G254 {
            let machine = self.machine_position();
            self.plane = Some(self.dwo_frame(&machine));
            self.plane_moved_to(machine);
            self.dwo_due = XYZ & !given;
        } else if on {
            self.dwo_due &= !given;
        } else if before == code::G254 {
            self.dwo_end();
        }
    }

    /// DWO ends (G255, reset, M02/M30): the current point is the workpiece system again.
    fn dwo_end(&mut self) {
        self.end_plane();
        self.modes[group::DYNAMIC_FIXTURE] = code::G255;
        self.dwo_due = 0;
    }

    /// Haas: reset, M02 and M30 cancel DWO (the manual's list) and TCPC (decision: the same
    /// list, G234 having no other), the machine staying where it is.
    pub(super) fn haas_end_five_axis(&mut self) {
        if self.cfg.dialect != crate::Dialect::Haas {
            return;
        }
        if self.dwo_active() {
            self.dwo_end();
        }
        if self.modes[group::LENGTH_COMP] == code::G234 {
            let machine = self.machine_position();
            self.tcp_end();
            self.modes[group::LENGTH_COMP] = code::G49;
            self.refresh_tool_length();
            self.follow_machine = None;
            self.pos = self.machine_to_program(&machine);
            self.sync_programmed();
        }
    }
}
