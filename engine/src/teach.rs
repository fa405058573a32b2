//! Syntec's tilted working plane teach function (the Offset/Setting screen of §3.3–§3.4, spec
//! `syntec.md` SYN-13…SYN-17): points latched from where the machine stands (F1, "Latch G54
//! Coordinate"), a teach mode — three points, tool direction, Euler angles, two vectors — that
//! makes the feature coordinate system of them, and the G68.2 block that sets it (Syntec's
//! G68.2 has the Euler form only, so every mode ends as `G68.2 X_ Y_ Z_ I_ J_ K_`, the format of
//! §4.1.3). The frame geometry is `twp`'s; what this module adds is the screen's rules and the
//! way back from a frame to Z–X–Z Euler angles. The decisions where the manual is silent are in
//! `docs/five-axis.md` ("Teach function (Syntec)").

use crate::controller::Controller;
use crate::geom::{Rigid, Vec3};
use crate::interp::gcode::{code, group};
use crate::twp;
use nalgebra::Matrix3;

/// The input boxes a latch fills: P1 (the origin in every mode), P2, P3 (three points).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Slot {
    P1,
    P2,
    P3,
}

impl Slot {
    pub const ALL: [Slot; 3] = [Slot::P1, Slot::P2, Slot::P3];

    pub fn name(self) -> &'static str {
        match self {
            Slot::P1 => "p1",
            Slot::P2 => "p2",
            Slot::P3 => "p3",
        }
    }

    pub fn parse(name: &str) -> Option<Slot> {
        Slot::ALL.into_iter().find(|s| s.name().eq_ignore_ascii_case(name))
    }

    fn index(self) -> usize {
        self as usize
    }
}

/// What one latch keeps: the tool tip's absolute coordinate (the active workpiece system, mm)
/// and the tool direction there (unit, tip toward holder, in the same system's axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Latched {
    pub point: Vec3,
    pub tool: Vec3,
}

/// The setting area: what was latched into each box.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Points {
    slots: [Option<Latched>; 3],
}

impl Points {
    pub fn get(&self, slot: Slot) -> Option<Latched> {
        self.slots[slot.index()]
    }

    pub fn set(&mut self, slot: Slot, latched: Latched) {
        self.slots[slot.index()] = Some(latched);
    }

    pub fn clear(&mut self) {
        self.slots = [None; 3];
    }

    fn need(&self, slot: Slot) -> Result<Latched, Failure> {
        self.get(slot).ok_or(Failure::Missing(slot))
    }
}

/// Why F1 does nothing (§3.3, notes 1 and 2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LatchRefused {
    /// The teach screen is Syntec's; a FANUC control has no such function.
    NotSyntec,
    /// Tool length compensation is cancelled (G49): the position would be the spindle nose's.
    LengthCompensationOff,
    /// A tilted working plane is in force: F1 works in the G69 state only.
    PlaneActive,
}

impl LatchRefused {
    pub fn reason(self) -> &'static str {
        match self {
            LatchRefused::NotSyntec => {
                "the tilted working plane teach function is Syntec's (§3.3); a FANUC control has none"
            }
            LatchRefused::LengthCompensationOff => {
                "F1 Latch G54 Coordinate needs tool length compensation (G43.4, G43 or G44), not G49 (§3.3 note 1)"
            }
            LatchRefused::PlaneActive => "F1 Latch G54 Coordinate is available in the G69 state only (§3.3 note 2)",
        }
    }
}

/// F1: the current absolute coordinate of the tool tip (forward kinematics of the machine axes
/// with the tool length in effect, in the active workpiece system) and the tool direction,
/// under the executing block's modal state.
pub fn latch(c: &Controller) -> Result<Latched, LatchRefused> {
    if c.interpreter().config().dialect != crate::Dialect::Syntec {
        return Err(LatchRefused::NotSyntec);
    }
    let modal = c.modal();
    if code::LENGTH_CANCEL.contains(&modal.modal(group::LENGTH_COMP)) {
        return Err(LatchRefused::LengthCompensationOff);
    }
    if code::TILTED_PLANES.contains(&modal.modal(group::ROTATION)) {
        return Err(LatchRefused::PlaneActive);
    }
    let tip = c.tip();
    Ok(Latched { point: Vec3::from(tip.tip), tool: Vec3::from(tip.tool) })
}

/// The guidance mode and the values typed into the setting area (the ones not taught).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Method {
    /// §3.4.1: P1 the origin, P1→P2 the +X direction, P3 on the +Y side.
    ThreePoints,
    /// §3.4.2: P1 the origin, Z the tool direction latched with P1, turned by `i` degrees.
    ToolDirection { i: f64 },
    /// §3.4.3: P1 the origin, Euler angles Z–X–Z as G68.2's I, J, K.
    Euler { i: f64, j: f64, k: f64 },
    /// §3.4.4: P1 the origin, the plane's X and Z axes in G54 components.
    TwoVectors { x: Vec3, z: Vec3 },
}

/// Why the teach fails (the state stays G69; the manual names no alarm).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// A box the mode needs was never latched.
    Missing(Slot),
    /// §3.4.1 note: the three points are collinear (or two coincide).
    Collinear,
    /// §3.4.4 note 2: X or Z is a zero vector.
    ZeroVector,
    /// §3.4.4 note 1: X and Z are not orthogonal.
    NotOrthogonal,
    /// A value typed is not a finite number.
    NotFinite,
}

impl Failure {
    pub fn reason(self) -> String {
        match self {
            Failure::Missing(slot) => format!("{} has not been latched", slot.name().to_uppercase()),
            Failure::Collinear => "the three points are collinear (§3.4.1)".into(),
            Failure::ZeroVector => "the X or Z axis is a zero vector (§3.4.4)".into(),
            Failure::NotOrthogonal => {
                format!("the X and Z axes are not orthogonal (§3.4.4; within {ORTHOGONAL_TOLERANCE_DEG}°)")
            }
            Failure::NotFinite => "a value is not a finite number".into(),
        }
    }
}

/// Decision (the manual is silent): a point nearer than one BLU (0.001 mm) to the line through
/// the other two makes the three points collinear.
pub const COLLINEAR_MM: f64 = 0.001;

/// Decision (Q-13, the manual gives no tolerance): X and Z are orthogonal within 0.5°, enough
/// for unit vectors typed with three decimals (each off by up to about 0.06°), far tighter than
/// FANUC's 85°…95° for G68.2 P3.
pub const ORTHOGONAL_TOLERANCE_DEG: f64 = 0.5;

/// Decision: a tool within this angle of the workpiece Z has no "right-hand direction"
/// of its own; X is then the workpiece +X (the operator facing the machine, looking down).
pub const VERTICAL_TOOL_DEG: f64 = 0.001;

/// The taught feature coordinate system and the G68.2 block that sets it.
#[derive(Debug, Clone, PartialEq)]
pub struct Taught {
    /// The FCS in the workpiece system: origin and X, Y, Z axes.
    pub frame: Rigid,
    /// Z–X–Z Euler angles I, J, K of the frame, degrees (J in [0, 180], I and K in (−180, 180]).
    pub euler: [f64; 3],
    /// `G68.2 X_ Y_ Z_ I_ J_ K_`, the values to 0.001 (mm, degrees).
    pub block: String,
}

/// F2: the feature coordinate system of `method` from the latched `points`.
pub fn teach(method: Method, points: &Points) -> Result<Taught, Failure> {
    let p1 = points.need(Slot::P1)?;
    let frame = match method {
        Method::ThreePoints => {
            let p = [p1.point, points.need(Slot::P2)?.point, points.need(Slot::P3)?.point];
            twp::three_points(p, Vec3::zeros(), 0.0, COLLINEAR_MM).map_err(|_| Failure::Collinear)?
        }
        Method::ToolDirection { i } => {
            finite(&[i])?;
            twp::tool_axis(p1.point, p1.tool, Vec3::z(), i, VERTICAL_TOOL_DEG).map_err(|_| Failure::ZeroVector)?
        }
        Method::Euler { i, j, k } => {
            finite(&[i, j, k])?;
            twp::euler(p1.point, i, j, k)
        }
        Method::TwoVectors { x, z } => {
            finite(&[x.x, x.y, x.z, z.x, z.y, z.z])?;
            if x.norm() == 0.0 || z.norm() == 0.0 {
                return Err(Failure::ZeroVector);
            }
            twp::two_vectors_within(p1.point, x, z, ORTHOGONAL_TOLERANCE_DEG).map_err(|_| Failure::NotOrthogonal)?
        }
    };
    let euler = euler_angles(&frame.r);
    let block = g68_2(&frame.o, euler);
    Ok(Taught { frame, euler, block })
}

fn finite(values: &[f64]) -> Result<(), Failure> {
    values.iter().all(|v| v.is_finite()).then_some(()).ok_or(Failure::NotFinite)
}

/// The Z–X–Z Euler angles (I, J, K) of the rotation `r` = Rz(I)·Rx(J)·Rz(K), degrees. Of the two
/// solutions the one with J in [0, 180]; where J is 0 or 180 only I ± K is fixed, and K is 0.
pub fn euler_angles(r: &Matrix3<f64>) -> [f64; 3] {
    // Third column (sin I sin J, −cos I sin J, cos J), third row (sin J sin K, sin J cos K, cos J).
    let sin_j = r[(2, 0)].hypot(r[(2, 1)]);
    let j = sin_j.atan2(r[(2, 2)]).to_degrees();
    if sin_j > 1e-9 {
        let i = r[(0, 2)].atan2(-r[(1, 2)]).to_degrees();
        let k = r[(2, 0)].atan2(r[(2, 1)]).to_degrees();
        [i, j, k]
    } else {
        // Rz(I)·Rx(0 or 180): the first column is (cos I, sin I, 0).
        [r[(1, 0)].atan2(r[(0, 0)]).to_degrees(), j, 0.0]
    }
}

/// `G68.2 X_ Y_ Z_ I_ J_ K_` (§4.1.3), every value to one BLU (0.001 mm / 0.001°) with a
/// decimal point, as the manual's programs write them (`X100.`, `J-30.5`).
pub fn g68_2(origin: &Vec3, euler: [f64; 3]) -> String {
    let words = [('X', origin.x), ('Y', origin.y), ('Z', origin.z), ('I', euler[0]), ('J', euler[1]), ('K', euler[2])];
    let mut out = String::from("G68.2");
    for (letter, value) in words {
        out.push(' ');
        out.push(letter);
        out.push_str(&decimal(value));
    }
    out
}

/// `v` to 0.001 with a decimal point and no trailing zeros (`10.`, `-0.5`, `0.`).
fn decimal(v: f64) -> String {
    let blu = crate::angle::round(v * 1000.0);
    let sign = if blu < 0 { "-" } else { "" };
    let (whole, fraction) = (blu.unsigned_abs() / 1000, blu.unsigned_abs() % 1000);
    let digits = format!("{fraction:03}");
    format!("{sign}{whole}.{}", digits.trim_end_matches('0'))
}
