//! Where the tool tip is, as the machine puts it: the forward kinematics of the machine axes
//! with the tool length the control has in effect, expressed in the active workpiece system
//! (G54…, after G52/G92, before any tilted working plane; on a table machine the workpiece
//! system is fixed on the table, as `fivex kin fk` gives the table frame). The trace, the
//! controller's samples, the stream and the run summary all read the tip here, so a program
//! point that the machine does not reach can never be shown as the tip.
//!
//! Beside it, the commanded point keeps the name of the coordinate system it is in
//! ([`System`]); `docs/conventions.md` (Positions) lists them.

use crate::canon::Pos;
use crate::kin::{Kinematics, Vec3};

/// The named coordinate system a programmed point is expressed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum System {
    /// The active workpiece system (G54…, external offset, G52, G92; after G68/G51/G51.1).
    #[default]
    Workpiece,
    /// The workpiece system's origin with the machine's axis directions, not turned with the
    /// table: FANUC DET's position display under tool centre point control, or in 5-axis cutter
    /// compensation's table coordinate system (the same as
    /// `Workpiece` on a head machine or with the table axes at zero).
    WorkpieceMachineAxes,
    /// The programming coordinate system of tool centre point control (FANUC G43.4/G43.5 Π,
    /// Syntec RTCP), or the table coordinate system of 5-axis cutter compensation without TCP
    /// (FANUC TBP = 1, `interp::table_crc`).
    Programming,
    /// The feature coordinate system of a tilted working plane (G68.2/G68.3/G68.4).
    Feature,
    /// The workpiece setting coordinate system of G54.4 (the workpiece system carried by the
    /// setting error).
    Wscs,
}

impl System {
    /// The name the trace, the stream and the summary print.
    pub fn name(self) -> &'static str {
        match self {
            System::Workpiece => "workpiece",
            System::WorkpieceMachineAxes => "workpiece_machine_axes",
            System::Programming => "programming",
            System::Feature => "feature",
            System::Wscs => "wscs",
        }
    }
}

/// What is needed besides the machine axes to place the tip: the tool length in effect
/// (G43 +H, G44 −H, G43.4/G43.5 the TCP length, G49 0; Syntec the same codes) and the origin of
/// the active workpiece system in the table frame (work offsets + G52 + G92 shift + the spindle
/// nose: where a plain G43 puts programming zero at zero angles). `programmed_in` names the
/// system of the commanded point of the same motion.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Basis {
    pub tool_length: f64,
    pub origin: [f64; 3],
    pub programmed_in: System,
    /// The mechanism chain of the block (Syntec `G10 L5000`): whose kinematics reads the tip.
    pub chain: crate::machine::Chain,
}

/// A motion queued after the workpiece origin changed without motion (G10, G92, a work offset)
/// starts its programmed point where the machine stands, in the new system: `work` (the
/// programmed X/Y/Z the next motion starts from, in `before`) is restated in `after`.
pub fn restate_start(work: &mut crate::canon::Pos, before: &Basis, after: &Basis) {
    if before.origin != after.origin
        && before.programmed_in == System::Workpiece
        && after.programmed_in == System::Workpiece
    {
        for (k, w) in work.iter_mut().take(3).enumerate() {
            *w += before.origin[k] - after.origin[k];
        }
    }
}

/// The tip as the machine puts it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tip {
    /// Tool tip in the active workpiece system, mm.
    pub tip: [f64; 3],
    /// Unit tool vector, tip toward holder, in the workpiece system (the table frame's axes).
    pub tool: [f64; 3],
    /// Tool tip in the table frame (machine coordinates on a machine without table axes).
    pub table: [f64; 3],
}

/// The tip at the machine axes `machine` (the planned position, before rollover display).
/// A mechanism the kinematics refuses (`kin` = `None`) is read as a 3-axis machine: X/Y/Z are
/// the nose, the tool along +Z. One forward kinematics call, no allocation.
pub fn locate(kin: Option<&Kinematics>, machine: &Pos, basis: &Basis) -> Tip {
    let (table, tool) = match kin {
        Some(k) => {
            let pose = k.forward(machine, basis.tool_length);
            (pose.tip, pose.tool)
        }
        None => (Vec3::new(machine[0], machine[1], machine[2] - basis.tool_length), Vec3::z()),
    };
    let o = basis.origin;
    Tip { tip: [table.x - o[0], table.y - o[1], table.z - o[2]], tool: tool.into(), table: table.into() }
}
