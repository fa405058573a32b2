//! What the 5-axis manual feeds need to know of the program's state (the controller asks):
//! the tool length offset in force (FANUC MAN-13) and the tilted working plane's axes (TWD,
//! MAN-10), and whether tool centre point control is on (Syntec manual RTCP, R519).

use super::gcode::{code, group};
use super::{Interpreter, Pos};
use crate::kin::Vec3;

impl Interpreter {
    /// The tool length offset data when an offset is "active" in FANUC's sense (MAN-13): group
    /// 08 is G43, G44, G43.4, G43.5, G43.8 or G43.9 (not G49) and H is not 0.
    pub fn active_length_offset(&self) -> Option<f64> {
        let st = &self.state;
        let mode = st.modes[group::LENGTH_COMP];
        ((matches!(mode, code::G43 | code::G44) || code::TCP.contains(&mode)) && st.h != 0)
            .then(|| st.offsets.length(st.h))
    }

    /// The tilted working plane's X, Y, Z axes in machine coordinates with the machine at
    /// `machine` (the plane is fixed to the workpiece, so it turns with the table); `None`
    /// outside a tilted working plane.
    pub fn plane_axes(&self, machine: &Pos) -> Option<[Vec3; 3]> {
        let st = &self.state;
        let (fcs, kin) = (st.plane?, st.kinematics.clone()?);
        // FCS → table frame as the plane functions place it, then the table as it stands.
        let zero = st.at_rotary_zero(&kin, &st.machine_position());
        let frame = st.frame_on_table(&kin, &zero).then(&fcs);
        let table = kin.table_frame(machine);
        Some([frame.x(), frame.y(), frame.z()].map(|d| table.direction_to_parent(&d)))
    }

    /// Tool centre point control (G43.4/G43.5) is in force.
    pub fn tcp_on(&self) -> bool {
        self.state.tcp_active()
    }
}
