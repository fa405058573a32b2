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

mod feed_directions;
mod ik;
mod select;

pub use feed_directions::{latitude_longitude, ManualDirections, ManualFeed};
pub use ik::{Candidate, Candidates, PerJoint, Reach};
pub use select::{Choice, Selection};

use crate::alarm::AlarmId;
pub use crate::geom::{axis_rotation, Vec3};
use crate::machine::{AxisKind, ConfigError, MachineConfig, Side};
use nalgebra::Rotation3;

/// What kind of mechanism carries the rotary axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
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
    /// The axis rolls over (its angle counts modulo 360°): a range limits the angle, not the
    /// count of turns.
    pub rollover: bool,
}

impl Joint {
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

/// A reference tool direction as FANUC No.19697–19699 give it: the coordinate axis `k` (0 X,
/// 1 Y, 2 Z) with the largest component, tilted by RA in [0°, 180°] toward the next axis and
/// RB in (−180°, 180°] about axis `k` (RB 0 when RA is 0° or 180°).
pub(crate) fn reference_angles(t: Vec3) -> (usize, f64, f64) {
    let k = if t[0] > t[1] && t[0] > t[2] {
        0
    } else if t[1] > t[2] {
        1
    } else {
        2
    };
    // The two other components in the order of the closed form: (cos RB, sin RB)·sin RA.
    let (c, s) = (t[(k + 1) % 3], t[(k + 2) % 3]);
    let ra = c.hypot(s).atan2(t[k]).to_degrees();
    let rb = if c == 0.0 && s == 0.0 { 0.0 } else { s.atan2(c).to_degrees() };
    (k, ra, rb)
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
    /// Indices of the X, Y and Z axes (the carriage); a missing one stays at 0.
    pub linear: [Option<usize>; 3],
}

/// One joint turned: a rotation by an angle with sine `s` and cosine `c` about the joint's line
/// (Rodrigues' formula on vectors, no matrix).
#[derive(Clone, Copy)]
struct Turn<'a> {
    joint: &'a Joint,
    s: f64,
    c: f64,
}

impl Turn<'_> {
    #[inline(always)]
    fn vector(&self, v: Vec3, s: f64) -> Vec3 {
        // Written out in scalars: nalgebra's vector code shuffles lanes for the cross product.
        let (u, c) = (&self.joint.direction, self.c);
        let d = (u.x * v.x + u.y * v.y + u.z * v.z) * (1.0 - c);
        Vec3::new(
            v.x * c + (u.y * v.z - u.z * v.y) * s + u.x * d,
            v.y * c + (u.z * v.x - u.x * v.z) * s + u.y * d,
            v.z * c + (u.x * v.y - u.y * v.x) * s + u.z * d,
        )
    }

    #[inline(always)]
    fn point(&self, x: Vec3, s: f64) -> Vec3 {
        let p = self.joint.point;
        p + self.vector(x - p, s)
    }
}

/// The rigid motion of one side's chain, master first (a small plain array: collecting into an
/// `ArrayVec` of copied joint data cost as much as the trigonometry).
struct ChainMotion<'a> {
    turns: [Option<Turn<'a>>; 2],
}

impl ChainMotion<'_> {
    #[inline(always)]
    fn links(&self) -> impl DoubleEndedIterator<Item = &Turn<'_>> {
        self.turns.iter().flatten()
    }

    /// Where a point carried by the chain (at zero angles) goes: the joint nearest the end of
    /// the chain (the slave) acts first.
    #[inline(always)]
    fn apply(&self, mut x: Vec3) -> Vec3 {
        for t in self.links().rev() {
            x = t.point(x, t.s);
        }
        x
    }

    /// The inverse of [`ChainMotion::apply`].
    #[inline(always)]
    fn undo(&self, mut x: Vec3) -> Vec3 {
        for t in self.links() {
            x = t.point(x, -t.s);
        }
        x
    }

    /// A direction carried by the chain.
    #[inline(always)]
    fn turn(&self, mut v: Vec3) -> Vec3 {
        for t in self.links().rev() {
            v = t.vector(v, t.s);
        }
        v
    }

    /// The inverse of [`ChainMotion::turn`].
    #[inline(always)]
    fn unturn(&self, mut v: Vec3) -> Vec3 {
        for t in self.links() {
            v = t.vector(v, -t.s);
        }
        v
    }
}

/// How near a posture is to the singular one (FANUC No.11204 / No.19738 compare this angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Singularity {
    /// The axis at the workpiece end of the chain (head-head: the master; table-table: the
    /// slave; mixed: the table axis): with the tool along it, turning it does not change the
    /// tool direction, so the inverse leaves it free.
    pub axis: char,
    /// Angle between the tool direction and that axis's line, degrees in [0, 90]; 0 is singular.
    pub angle: f64,
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

/// A machine-file vector as a `Vec3`.
pub(crate) fn vec3(a: [f64; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

impl Kinematics {
    /// The model of a machine; refuses what `MachineConfig::validate` refuses and mechanisms that
    /// cannot work (with the alarm the vendors raise for them).
    pub fn new(m: &MachineConfig) -> Result<Kinematics, ConfigError> {
        m.validate().map_err(ConfigError::invalid)?;
        let joint = |link: &crate::machine::RotaryLink| {
            let index = m.axes.iter().position(|a| a.name == link.axis && a.kind == AxisKind::Rotary);
            let rollover = index.is_some_and(|i| m.axes[i].rollover);
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
                rollover,
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
            _ => {
                let detail = "a machine has at most two rotary axes in its mechanism chain";
                return Err(ConfigError::alarm(AlarmId::AxisSetting, detail));
            }
        };
        let tool_axis = vec3(m.tool_axis).normalize();
        let linear = [b'X', b'Y', b'Z'].map(|c| m.axis_index(c).filter(|&i| m.axes[i].kind == AxisKind::Linear));
        let kin = Kinematics { kind, head, table, tool_axis, nose: vec3(m.nose), axes: m.axes.len(), linear };
        kin.check()?;
        Ok(kin)
    }

    /// A chain whose two axes are parallel, or whose orientation cannot leave a plane because
    /// an axis is parallel to what it must turn, has no use: refused (Syntec COR-155/156/157,
    /// FANUC PS5459).
    fn check(&self) -> Result<(), ConfigError> {
        let parallel = |a: &Vec3, b: &Vec3| a.cross(b).norm() < 1e-9;
        let joints: Vec<&Joint> = self.head.iter().chain(&self.table).collect();
        if let [a, b] = joints[..] {
            if parallel(&a.direction, &b.direction) {
                let detail = format!("rotary axes {} and {} are parallel", a.name, b.name);
                return Err(ConfigError::alarm(AlarmId::AxisSetting, detail));
            }
        }
        // The axis next to the tool (head slave, head axis of a mixed machine) must be able to
        // tilt it.
        if let Some(last) = self.head.last() {
            if parallel(&last.direction, &self.tool_axis) {
                let detail = format!("rotary axis {} is parallel to the tool direction", last.name);
                let id = if self.kind == MachineKind::HeadTable {
                    AlarmId::ToolAxisParallel
                } else {
                    AlarmId::ToolDirectionSetting
                };
                return Err(ConfigError::alarm(id, detail));
            }
        }
        if self.kind == MachineKind::TableTable && parallel(&self.table[0].direction, &self.tool_axis) {
            let detail = format!("table master axis {} is parallel to the tool direction", self.table[0].name);
            return Err(ConfigError::alarm(AlarmId::ToolDirectionSetting, detail));
        }
        Ok(())
    }

    /// The carriage reference point (machine X, Y, Z) in `pos`.
    fn carriage(&self, pos: &[f64]) -> Vec3 {
        let at = |i: Option<usize>| i.map_or(0.0, |i| pos[i]);
        Vec3::new(at(self.linear[0]), at(self.linear[1]), at(self.linear[2]))
    }

    /// The commanded angle of a joint in `pos` (axis order).
    fn angle(&self, j: &Joint, pos: &[f64]) -> f64 {
        j.index.map_or(j.fixed, |i| pos[i])
    }

    /// The rigid motion of the head (`Side::Head`) or the table at the axis positions `pos`.
    #[inline(always)]
    fn motion(&self, side: Side, pos: &[f64]) -> ChainMotion<'_> {
        let joints = if side == Side::Head { &self.head } else { &self.table };
        let mut motion = ChainMotion { turns: [None; 2] };
        for (t, j) in motion.turns.iter_mut().zip(joints) {
            let (s, c) = crate::angle::sin_cos_deg(j.sign * (self.angle(j, pos) + j.zero_offset));
            *t = Some(Turn { joint: j, s, c });
        }
        motion
    }

    /// Forward kinematics: axis positions (axis order; X, Y, Z are the carriage reference in
    /// machine coordinates) and tool length → tool tip and direction.
    pub fn forward(&self, pos: &[f64], tool_length: f64) -> Pose {
        let carriage = self.carriage(pos);
        let head = self.motion(Side::Head, pos);
        let tip_machine = carriage + head.apply(self.nose - tool_length * self.tool_axis);
        let tool_machine = head.turn(self.tool_axis);
        // Table frame: undo the table's motion.
        let table = self.motion(Side::Table, pos);
        let tip = table.undo(tip_machine);
        let tool = table.unturn(tool_machine);
        Pose { tip, tool, tip_machine, tool_machine }
    }

    /// The carriage position (X, Y, Z) that puts the tool tip at `tip` (table frame) with the
    /// rotary axes of `pos`.
    pub fn carriage_for(&self, pos: &[f64], tip: Vec3, tool_length: f64) -> Vec3 {
        self.carriage_with(&self.motion(Side::Head, pos), &self.motion(Side::Table, pos), tip, tool_length)
    }

    /// The point X/Y/Z carry without tool centre point control (table frame): the tool tip as
    /// it would be with the head's axes at zero, which only the carriage and the table move —
    /// the head's turn swings the real tip about it (the programmed point of a plain G43 block,
    /// which 5-axis cutter compensation in the table coordinate system carries with the table).
    pub fn unturned_tip(&self, pos: &[f64], tool_length: f64) -> Vec3 {
        let machine = self.carriage(pos) + self.nose - tool_length * self.tool_axis;
        self.motion(Side::Table, pos).undo(machine)
    }

    /// The carriage position that puts [`Kinematics::unturned_tip`] at `point` (table frame)
    /// with the rotary axes of `pos`: [`Kinematics::carriage_for`] with the head left out.
    pub fn carriage_for_unturned(&self, pos: &[f64], point: Vec3, tool_length: f64) -> Vec3 {
        self.motion(Side::Table, pos).apply(point) - (self.nose - tool_length * self.tool_axis)
    }

    /// [`Kinematics::carriage_for`] with the chain motions already computed.
    fn carriage_with(&self, head: &ChainMotion, table: &ChainMotion, tip: Vec3, tool_length: f64) -> Vec3 {
        table.apply(tip) - head.apply(self.nose - tool_length * self.tool_axis)
    }

    /// The table's rigid motion at `pos`: a point of the table frame (its coordinates) → the
    /// same point in machine coordinates (`to_parent`).
    pub fn table_frame(&self, pos: &[f64]) -> crate::geom::Rigid {
        let t = self.motion(Side::Table, pos);
        let r = nalgebra::Matrix3::from_columns(&[t.turn(Vec3::x()), t.turn(Vec3::y()), t.turn(Vec3::z())]);
        crate::geom::Rigid { r, o: t.apply(Vec3::zeros()) }
    }

    /// The rotation the rotary axes at `pos` give the tool relative to the table frame: the
    /// head's turn, seen from the turned table (Syntec G68.3 P1 takes its frame from it).
    pub fn tool_rotation(&self, pos: &[f64]) -> nalgebra::Matrix3<f64> {
        let (head, table) = (self.motion(Side::Head, pos), self.motion(Side::Table, pos));
        let axis = |e: Vec3| table.unturn(head.turn(e));
        nalgebra::Matrix3::from_columns(&[axis(Vec3::x()), axis(Vec3::y()), axis(Vec3::z())])
    }

    /// The line direction of table joint `k` (master first) in machine coordinates at `pos`: a
    /// slave's line is turned by its master.
    pub fn table_axis_direction(&self, k: usize, pos: &[f64]) -> Vec3 {
        let m = self.motion(Side::Table, pos);
        let mut v = self.table[k].direction;
        for t in m.links().take(k).collect::<Vec<_>>().into_iter().rev() {
            v = t.vector(v, t.s);
        }
        v
    }

    /// How near the posture at `pos` is to singular; `None` on machines with fewer than two
    /// rotary axes (one axis never has a free angle).
    pub fn singularity(&self, pos: &[f64]) -> Option<Singularity> {
        let joint = self.singular_joint()?;
        let cos = self.forward(pos, 0.0).tool.dot(&joint.direction).abs().min(1.0);
        Some(Singularity { axis: joint.name, angle: cos.acos().to_degrees() })
    }

    /// The joint whose angle is free at the singular posture ([`Singularity::axis`]): the tool
    /// along its line, which keeps its direction in the table frame whatever the angles.
    pub fn singular_joint(&self) -> Option<&Joint> {
        match self.kind {
            MachineKind::HeadHead => Some(&self.head[0]),
            MachineKind::TableTable => Some(&self.table[1]),
            MachineKind::HeadTable => Some(&self.table[0]),
            _ => None,
        }
    }

    /// The joints in FANUC's order θ1, θ2 (No.19680): master, slave on a head-head or
    /// table-table machine; head, table on a mixed one.
    pub fn joints(&self) -> PerJoint<&Joint> {
        self.head.iter().chain(&self.table).collect()
    }
}

#[cfg(test)]
mod tests;
