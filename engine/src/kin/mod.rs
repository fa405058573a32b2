//! The 5-axis mechanism: forward kinematics, inverse kinematics and the choice among the inverse
//! solutions (`docs/machine-config.md` writes the formulas out).
//!
//! Built from a [`MachineConfig`]: every rotary axis is a rotation about a line (a point and a
//! unit direction, at all angles zero), turning by `sign · (θ + zero_offset)` (sign −1 for a
//! left-hand axis). Head axes are chained from the carriage to the spindle, table axes from the
//! bed to the table top: the first of each side (the master) carries the second.
//!
//! Frames: *machine* coordinates are those of the linear axes; the *table* frame is fixed on the
//! table and equals the machine frame when every table axis is at zero (for head-only machines
//! the two are the same). The tool tip and direction a program commands are in the table frame.

mod ik;
mod select;

pub use ik::Candidate;
pub use select::{Choice, Selection};

use crate::machine::{AxisKind, MachineConfig, Side};
use nalgebra::{Rotation3, Vector3};

pub type Vec3 = Vector3<f64>;

/// What kind of mechanism carries the rotary axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MachineKind {
    ThreeAxis,
    /// Both rotary axes on the spindle head (tool rotation, Syntec spindle type).
    HeadHead,
    /// Both on the table (table rotation, trunnion).
    TableTable,
    /// One on the head, one on the table.
    HeadTable,
    /// A single rotary axis on the head (4-axis).
    Head,
    /// A single rotary axis on the table (4-axis).
    Table,
}

/// One rotary axis of the chain.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: char,
    /// Index of the axis in the machine's axis list; `None` for a hypothetical (fixed) axis.
    pub index: Option<usize>,
    pub side: Side,
    /// Unit direction at all angles zero (inclined axes and setting errors included).
    pub direction: Vec3,
    /// +1 right hand, −1 left hand: the rotation is `sign · (θ + zero_offset)` about `direction`.
    pub sign: f64,
    pub zero_offset: f64,
    /// A point on the axis line at all angles zero: relative to the carriage reference point
    /// (the machine X/Y/Z position) for head axes, in machine coordinates for table axes.
    pub point: Vec3,
    /// Angle of a hypothetical axis.
    pub fixed: f64,
    /// Allowed commanded angles `[low, high]`; `None`: unrestricted.
    pub range: Option<[f64; 2]>,
}

impl Joint {
    /// The rotation at commanded angle `theta` (degrees).
    fn rotation(&self, theta: f64) -> Rotation3<f64> {
        rotation_deg(&self.direction, self.sign * (theta + self.zero_offset))
    }

    /// The commanded angle that turns the axis by `phi` degrees about `direction`.
    fn command(&self, phi: f64) -> f64 {
        self.sign * phi - self.zero_offset
    }
}

/// Rotation by `deg` degrees about the unit vector `u` (right hand; Rodrigues), exact at quarter
/// turns about a coordinate axis.
pub fn rotation_deg(u: &Vec3, deg: f64) -> Rotation3<f64> {
    let (s, c) = crate::angle::sin_cos_deg(deg);
    let k = u.cross_matrix();
    Rotation3::from_matrix_unchecked(nalgebra::Matrix3::identity() + k * s + k * k * (1.0 - c))
}

/// The kinematic model of one machine.
#[derive(Debug, Clone, PartialEq)]
pub struct Kinematics {
    pub kind: MachineKind,
    /// Head joints, master first (carriage → spindle).
    pub head: Vec<Joint>,
    /// Table joints, master first (bed → table top).
    pub table: Vec<Joint>,
    /// Unit tool direction (tip → holder) with every head axis at zero.
    pub tool_axis: Vec3,
    /// The spindle nose (gauge point) relative to the carriage reference point, at zero angles.
    pub nose: Vec3,
    /// Number of machine axes (positions are given in axis order).
    pub axes: usize,
}

/// Tool tip and direction for given axis positions.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    /// Tool tip in the table frame.
    pub tip: Vec3,
    /// Unit tool direction (tip → holder) in the table frame.
    pub tool: Vec3,
    /// Tool tip in machine coordinates.
    pub tip_machine: Vec3,
    /// Unit tool direction in machine coordinates.
    pub tool_machine: Vec3,
}

fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

impl Kinematics {
    /// The model of a machine (which `MachineConfig::validate` has accepted).
    pub fn new(m: &MachineConfig) -> Result<Kinematics, String> {
        m.validate()?;
        let joint = |link: &crate::machine::RotaryLink| {
            let index = m.axes.iter().position(|a| a.name == link.axis && a.kind == AxisKind::Rotary);
            Joint {
                name: link.axis,
                index,
                side: link.side,
                direction: vec3(link.direction).normalize(),
                sign: if link.hand == crate::machine::Hand::Right { 1.0 } else { -1.0 },
                zero_offset: link.zero_offset,
                point: vec3(link.point),
                fixed: link.fixed.unwrap_or(0.0),
                range: link.range,
            }
        };
        let head: Vec<Joint> = m.rotary.iter().filter(|l| l.side == Side::Head).map(joint).collect();
        let table: Vec<Joint> = m.rotary.iter().filter(|l| l.side == Side::Table).map(joint).collect();
        let kind = match (head.len(), table.len()) {
            (0, 0) => MachineKind::ThreeAxis,
            (2, 0) => MachineKind::HeadHead,
            (0, 2) => MachineKind::TableTable,
            (1, 1) => MachineKind::HeadTable,
            (1, 0) => MachineKind::Head,
            (0, 1) => MachineKind::Table,
            _ => return Err("a machine has at most two rotary axes in its mechanism chain".into()),
        };
        let tool_axis = vec3(m.tool_axis).normalize();
        let kin = Kinematics { kind, head, table, tool_axis, nose: vec3(m.nose), axes: m.axes.len() };
        kin.check()?;
        Ok(kin)
    }

    /// A chain whose two axes are parallel, or whose orientation cannot leave a plane because
    /// an axis is parallel to what it must turn, has no use: refused.
    fn check(&self) -> Result<(), String> {
        let parallel = |a: &Vec3, b: &Vec3| a.cross(b).norm() < 1e-9;
        let joints: Vec<&Joint> = self.head.iter().chain(&self.table).collect();
        if let [a, b] = joints[..] {
            if parallel(&a.direction, &b.direction) {
                return Err(format!("rotary axes {} and {} are parallel", a.name, b.name));
            }
        }
        // The axis next to the tool (head slave, head axis of a mixed machine) must be able to
        // tilt it (Syntec COR-155/157).
        if let Some(last) = self.head.last() {
            if parallel(&last.direction, &self.tool_axis) {
                return Err(format!("rotary axis {} is parallel to the tool direction", last.name));
            }
        }
        if self.kind == MachineKind::TableTable && parallel(&self.table[0].direction, &self.tool_axis) {
            return Err(format!("table master axis {} is parallel to the tool direction", self.table[0].name));
        }
        Ok(())
    }

    /// The commanded angle of a joint in `pos` (axis order).
    fn angle(&self, j: &Joint, pos: &[f64]) -> f64 {
        j.index.map_or(j.fixed, |i| pos[i])
    }

    /// The head's rigid motion: rotation and where a spindle point `x` (relative to the
    /// carriage reference, at zero angles) goes, relative to the carriage reference.
    fn head_motion(&self, angles: &[f64]) -> (Rotation3<f64>, impl Fn(Vec3) -> Vec3 + '_) {
        let rotations: Vec<Rotation3<f64>> = self.head.iter().zip(angles).map(|(j, &a)| j.rotation(a)).collect();
        let total = rotations.iter().fold(Rotation3::identity(), |acc, r| acc * r);
        let apply = move |mut x: Vec3| {
            // The joint nearest the tool acts first.
            for (j, r) in self.head.iter().zip(&rotations).rev() {
                x = j.point + r * (x - j.point);
            }
            x
        };
        (total, apply)
    }

    /// The table's rigid motion: rotation and where a table point `w` (machine coordinates at
    /// zero angles) goes.
    fn table_motion(&self, angles: &[f64]) -> (Rotation3<f64>, impl Fn(Vec3) -> Vec3 + '_) {
        let rotations: Vec<Rotation3<f64>> = self.table.iter().zip(angles).map(|(j, &a)| j.rotation(a)).collect();
        let total = rotations.iter().fold(Rotation3::identity(), |acc, r| acc * r);
        let apply = move |mut w: Vec3| {
            for (j, r) in self.table.iter().zip(&rotations).rev() {
                w = j.point + r * (w - j.point);
            }
            w
        };
        (total, apply)
    }

    /// Forward kinematics: axis positions (axis order; X, Y, Z are the carriage reference in
    /// machine coordinates) and tool length → tool tip and direction.
    pub fn forward(&self, pos: &[f64], tool_length: f64) -> Pose {
        let head_angles: Vec<f64> = self.head.iter().map(|j| self.angle(j, pos)).collect();
        let table_angles: Vec<f64> = self.table.iter().map(|j| self.angle(j, pos)).collect();
        let carriage = Vec3::new(pos[0], pos[1], pos[2]);
        let (head_rot, head_point) = self.head_motion(&head_angles);
        let tip_machine = carriage + head_point(self.nose - tool_length * self.tool_axis);
        let tool_machine = head_rot * self.tool_axis;
        let (table_rot, _) = self.table_motion(&table_angles);
        // Table frame: undo the table's motion.
        let tip = self.table_inverse(&table_angles, tip_machine);
        let tool = table_rot.inverse() * tool_machine;
        Pose { tip, tool, tip_machine, tool_machine }
    }

    /// Table frame → machine coordinates at the given table angles.
    pub fn table_forward(&self, table_angles: &[f64], w: Vec3) -> Vec3 {
        let (_, apply) = self.table_motion(table_angles);
        apply(w)
    }

    /// Machine coordinates → table frame at the given table angles.
    pub fn table_inverse(&self, table_angles: &[f64], mut p: Vec3) -> Vec3 {
        for (j, &a) in self.table.iter().zip(table_angles) {
            p = j.point + j.rotation(a).inverse() * (p - j.point);
        }
        p
    }

    /// The joints in FANUC's order θ1, θ2 (No.19680): master, slave on a head-head or
    /// table-table machine; head, table on a mixed one.
    pub fn joints(&self) -> Vec<&Joint> {
        self.head.iter().chain(&self.table).collect()
    }
}

#[cfg(test)]
mod tests;
