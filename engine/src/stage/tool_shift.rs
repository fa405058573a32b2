//! What the 5-axis compensation stages (`tool_side`, `leading_edge`) share: reading the tool
//! direction of a motion's axes in its programming coordinates, and moving a motion by a 3-D
//! vector given in them. Without TCP the programming coordinates are the machine's directions
//! moved by the work offsets (on a table machine they do not turn with the table: FANUC's
//! workpiece coordinate system, TBP = 0), so the tool is its machine direction and a vector
//! moves the machine's X/Y/Z as it is. Under TCP they are the motion's `TipMove::frame` in the
//! table frame: the tool is read there, the tip moved there, and the machine's X/Y/Z put where
//! the kinematics carry the moved tip (with TBP = 1, WKP = 0 that frame is the table coordinate
//! system the compensation works in). With TBP = 1 without TCP the interpreter gives the moves of
//! the mode the table coordinate system as their frame (their point the unturned tip,
//! `canon::TipMove::head_fixed`) and the stage that system for the start block, an ordinary
//! move whose end it reads there (`table`).

use super::PerpendicularStart;
use crate::canon::{Canon, CanonKind, Motion, MotionKind, Pos};
use crate::geom::Rigid;
use crate::kin::{Kinematics, Vec3};
use crate::machine::MachineConfig;
use nalgebra::Matrix3;
use std::sync::Arc;

/// The tool and the vector where it stands, for one stage.
#[derive(Clone)]
pub(super) struct ToolShift {
    /// Axis indices of X, Y, Z.
    xyz: [Option<usize>; 3],
    kin: Option<Arc<Kinematics>>,
    /// The tool direction with the rotary axes at 0 (a machine without rotary axes).
    tool_axis: Vec3,
    /// The compensated point minus the programmed one where the tool is (programming
    /// coordinates), and the same in the table frame (the tip's shift under TCP).
    pub(super) vector: Vec3,
    vector_table: Vec3,
    /// 5-axis cutter compensation in the table coordinate system without TCP: that system in
    /// the table frame, for a motion that does not carry it (the start block, an ordinary move
    /// whose end the interpreter gives in it).
    pub(super) table: Option<Rigid>,
    /// Which point of the tool the stage puts on the contour (for the trace, `canon::Offset`).
    touch: crate::canon::Touch,
}

impl ToolShift {
    /// `touch`: which point of the tool the stage puts on the contour.
    pub(super) fn new(m: &crate::machine::Machine, touch: crate::canon::Touch) -> ToolShift {
        let c: &MachineConfig = m;
        ToolShift {
            xyz: [c.axis_index(b'X'), c.axis_index(b'Y'), c.axis_index(b'Z')],
            kin: m.kinematics().cloned(),
            tool_axis: crate::kin::vec3(c.tool_axis).normalize(),
            vector: Vec3::zeros(),
            vector_table: Vec3::zeros(),
            table: None,
            touch,
        }
    }

    /// X, Y, Z of a position.
    pub(super) fn xyz(&self, p: &Pos) -> Vec3 {
        let at = |i: Option<usize>| i.map_or(0.0, |i| p[i]);
        Vec3::new(at(self.xyz[0]), at(self.xyz[1]), at(self.xyz[2]))
    }

    /// Which of X, Y, Z (0, 1, 2) the machine axis `index` is.
    pub(super) fn linear_of(&self, index: usize) -> Option<usize> {
        self.xyz.iter().position(|&x| x == Some(index))
    }

    /// The tool direction (tip → holder, programming coordinates of `m`) with the machine axes
    /// at `machine`.
    pub(super) fn tool(&self, m: &Motion, machine: &Pos) -> Vec3 {
        let Some(kin) = &self.kin else { return self.tool_axis };
        let pose = kin.forward(machine, 0.0);
        match (&m.tip, &self.table) {
            (Some(t), _) => t.frame.r.transpose() * pose.tool,
            (None, Some(f)) => f.r.transpose() * pose.tool,
            (None, None) => pose.tool_machine,
        }
    }

    /// The rotation from programming to table coordinates of a motion (under TCP its frame; in
    /// the table coordinate system that one; else none: the work offsets only translate).
    fn frame(&self, m: &Motion) -> Matrix3<f64> {
        match (&m.tip, &self.table) {
            (Some(t), _) => t.frame.r,
            (None, Some(f)) => f.r,
            (None, None) => Matrix3::identity(),
        }
    }

    /// `c` moved by `vector` (programming coordinates) at its end, starting where the tool
    /// is; the tool is then there.
    pub(super) fn placed(&mut self, mut c: Canon, vector: Vec3) -> Canon {
        if let CanonKind::Motion(m) = &mut c.kind {
            m.record_offset(self.touch);
            for (k, i) in self.xyz.iter().enumerate() {
                if let Some(i) = *i {
                    m.target[i] += vector[k];
                }
            }
            let table = self.frame(m) * vector;
            // Under TCP the machine's X/Y/Z carry the moved tip (on a table machine the table's
            // turn at the end stands between); without it they move as the program does — in
            // the table coordinate system turned as the table stands at the end.
            let carriage = match (m.tip.as_deref_mut(), &self.kin) {
                (Some(t), Some(kin)) => {
                    t.from += self.vector_table;
                    t.to += table;
                    Some(t.carriage_for(kin, &m.machine, t.to))
                }
                _ => None,
            };
            let machine_vector = match (&self.table, &self.kin) {
                (Some(_), Some(kin)) => kin.table_frame(&m.machine).r * table,
                _ => vector,
            };
            for (k, i) in self.xyz.iter().enumerate() {
                if let Some(i) = *i {
                    m.machine[i] = carriage.map_or(m.machine[i] + machine_vector[k], |p| p[k]);
                }
            }
            self.vector_table = table;
        }
        self.vector = vector;
        c
    }

    /// The move a compensation's start block makes when the first block after it comes (the
    /// leading edge offset's G41.3 block, a start-up perpendicular to the next movement): from
    /// where the program stood (`pos`, the machine at `machine`) straight by `vector`, the rotary
    /// axes standing, made from the first block `c` — at its feed, in G00 or G01 as the start
    /// block `block` was, with that block's line and sequence number.
    pub(super) fn startup_move(
        &mut self,
        c: &Canon,
        pos: Pos,
        machine: Pos,
        block: Option<PerpendicularStart>,
        vector: Vec3,
    ) -> Canon {
        let mut template = c.clone();
        if let Some(b) = block {
            (template.line, template.n) = (b.line, b.n);
        }
        if let CanonKind::Motion(m) = &mut template.kind {
            m.target = pos;
            m.machine = machine;
            m.arc = None;
            let rapid = block.map_or(m.kind == MotionKind::Rapid, |b| b.rapid);
            m.kind = if rapid { MotionKind::Rapid } else { MotionKind::Linear };
            if let Some(t) = m.tip.as_deref_mut() {
                t.to = t.from;
                t.arc = None;
                t.posture = None;
            }
        }
        self.placed(template, vector)
    }

    /// A reset: the tool stands where the program says.
    pub(super) fn reset(&mut self) {
        self.vector = Vec3::zeros();
        self.vector_table = Vec3::zeros();
        self.table = None;
    }
}
