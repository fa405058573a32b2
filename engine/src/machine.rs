//! The machine as the interpreter needs it: its axes, their kinds, limits of speed.
//!
//! This is the minimal model of issue 2 (axis names and rapid rates for ideal motion). The
//! kinematic model of the 5-axis mechanism extends it (issue 3).

use serde::{Deserialize, Serialize};

/// At most this many controlled axes per machine.
pub const MAX_AXES: usize = 8;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AxisKind {
    Linear,
    Rotary,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Address letter: X Y Z U V W (linear) or A B C (rotary).
    pub name: char,
    pub kind: AxisKind,
    /// Rapid traverse rate, mm/min or deg/min.
    pub rapid: f64,
}

/// Which part of the machine a rotary axis turns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Tool side (head): turns the spindle.
    Head,
    /// Workpiece side (table): turns the part.
    Table,
}

/// Rotation sense about the axis direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hand {
    Right,
    Left,
}

/// One rotary axis in the mechanism chain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RotaryLink {
    /// The axis letter (must be a rotary axis of `axes`).
    pub axis: char,
    pub side: Side,
    /// Direction the axis turns about, machine coordinates at zero angles (normalised on use).
    pub direction: [f64; 3],
    pub hand: Hand,
    /// A point on the axis line at zero angles, mm: relative to the carriage reference point
    /// (the X/Y/Z position) for a head axis, in machine coordinates for a table axis.
    #[serde(default)]
    pub point: [f64; 3],
    /// Added to the commanded angle (the axis's zero-point error), degrees.
    #[serde(default)]
    pub zero_offset: f64,
    /// The angle of a hypothetical axis (one the machine does not have as a controlled axis).
    #[serde(default)]
    pub fixed: Option<f64>,
    /// Movement range `[low, high]` of commanded angles, degrees.
    #[serde(default)]
    pub range: Option<[f64; 2]>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineConfig {
    pub name: String,
    pub axes: Vec<Axis>,
    /// Rotary axes from the machine base outward: head links from the column to the spindle,
    /// table links from the bed to the table top (so the master axis comes first on each side).
    #[serde(default)]
    pub rotary: Vec<RotaryLink>,
    /// Tool direction (tip → holder) with every head axis at zero, machine coordinates.
    #[serde(default = "plus_z")]
    pub tool_axis: [f64; 3],
    /// The spindle nose (gauge point) relative to the carriage reference point at zero angles,
    /// mm (e.g. `-pivot · tool_axis` when X/Y/Z locate the head's pivot).
    #[serde(default)]
    pub nose: [f64; 3],
}

fn plus_z() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

impl MachineConfig {
    /// The axis index of an address letter, if the machine has that axis.
    pub fn axis_index(&self, letter: u8) -> Option<usize> {
        self.axes.iter().position(|a| a.name as u32 == letter as u32)
    }

    /// A built-in preset (see `docs/machine-config.md`).
    pub fn preset(name: &str) -> Option<MachineConfig> {
        let rotary: &[char] = match name {
            "mill3" => &[],
            "head-bc" | "table-bc" | "mixed-bc" => &['B', 'C'],
            "table-ac" => &['A', 'C'],
            _ => return None,
        };
        let mut axes: Vec<Axis> =
            ['X', 'Y', 'Z'].iter().map(|&name| Axis { name, kind: AxisKind::Linear, rapid: 30_000.0 }).collect();
        axes.extend(rotary.iter().map(|&name| Axis { name, kind: AxisKind::Rotary, rapid: 10_800.0 }));
        // CONTRACTS.md: head-bc has C master about Z and B slave about Y; table-ac A master about
        // X and C slave; table-bc B master about Y and C slave; mixed-bc B on the head, C on the
        // table. Head axes turn right-hand, table axes left-hand (ISO 841, both manuals).
        let link = |axis: char, side: Side| {
            let direction = match axis {
                'A' => [1.0, 0.0, 0.0],
                'B' => [0.0, 1.0, 0.0],
                _ => [0.0, 0.0, 1.0],
            };
            let hand = if side == Side::Head { Hand::Right } else { Hand::Left };
            RotaryLink { axis, side, direction, hand, point: [0.0; 3], zero_offset: 0.0, fixed: None, range: None }
        };
        let rotary = match name {
            "head-bc" => vec![link('C', Side::Head), link('B', Side::Head)],
            "table-ac" => vec![link('A', Side::Table), link('C', Side::Table)],
            "table-bc" => vec![link('B', Side::Table), link('C', Side::Table)],
            "mixed-bc" => vec![link('B', Side::Head), link('C', Side::Table)],
            _ => vec![],
        };
        Some(MachineConfig { name: name.to_string(), axes, rotary, tool_axis: plus_z(), nose: [0.0; 3] })
    }

    /// The unit tool vector (tip toward holder) in workpiece coordinates for machine axis
    /// positions `pos` (in axis order): head rotations turn +Z, the inverse of the table
    /// rotations brings it into the part's frame.
    pub fn tool_direction(&self, pos: &[f64]) -> [f64; 3] {
        use nalgebra::{Rotation3, Unit, Vector3};
        let rotation = |link: &RotaryLink| -> Rotation3<f64> {
            let angle = self.axis_index(link.axis as u8).map_or(0.0, |i| pos[i]).to_radians();
            let angle = if link.hand == Hand::Right { angle } else { -angle };
            let d = Vector3::from(link.direction);
            match Unit::try_new(d, 1e-12) {
                Some(axis) => Rotation3::from_axis_angle(&axis, angle),
                None => Rotation3::identity(),
            }
        };
        let mut head = Rotation3::identity();
        let mut table = Rotation3::identity();
        for link in &self.rotary {
            match link.side {
                Side::Head => head *= rotation(link),
                Side::Table => table *= rotation(link),
            }
        }
        let tool = table.inverse() * (head * Vector3::z());
        [tool.x, tool.y, tool.z]
    }

    pub const PRESETS: &'static [&'static str] = &["mill3", "head-bc", "table-ac", "table-bc", "mixed-bc"];

    /// Checks what the engine relies on: 1..=MAX_AXES axes, unique valid letters, positive rates.
    pub fn validate(&self) -> Result<(), String> {
        if self.axes.is_empty() || self.axes.len() > MAX_AXES {
            return Err(format!("a machine needs 1 to {MAX_AXES} axes"));
        }
        for (i, a) in self.axes.iter().enumerate() {
            let ok = match a.kind {
                AxisKind::Linear => "XYZUVW".contains(a.name),
                AxisKind::Rotary => "ABC".contains(a.name),
            };
            if !ok {
                return Err(format!("axis '{}' cannot be {:?}", a.name, a.kind));
            }
            if self.axes[..i].iter().any(|b| b.name == a.name) {
                return Err(format!("axis '{}' appears twice", a.name));
            }
            if !(a.rapid.is_finite() && a.rapid > 0.0) {
                return Err(format!("axis '{}' needs a positive rapid rate", a.name));
            }
        }
        for (i, link) in self.rotary.iter().enumerate() {
            let is_rotary = self.axes.iter().any(|a| a.name == link.axis && a.kind == AxisKind::Rotary);
            if !is_rotary && link.fixed.is_none() {
                return Err(format!("rotary link '{}' is not a rotary axis of the machine", link.axis));
            }
            if self.rotary[..i].iter().any(|l| l.axis == link.axis) {
                return Err(format!("rotary link '{}' appears twice", link.axis));
            }
            let norm = link.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !(norm.is_finite() && norm > 1e-9) {
                return Err(format!("rotary link '{}' needs a non-zero direction", link.axis));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_preset_is_valid() {
        for name in MachineConfig::PRESETS {
            let m = MachineConfig::preset(name).unwrap();
            m.validate().unwrap();
        }
        assert_eq!(MachineConfig::preset("table-ac").unwrap().axis_index(b'A'), Some(3));
        assert!(MachineConfig::preset("nope").is_none());
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn tool_direction_of_the_presets() {
        let at = |preset: &str, pos: &[f64]| MachineConfig::preset(preset).unwrap().tool_direction(pos);
        assert!(close(at("mill3", &[1.0, 2.0, 3.0]), [0.0, 0.0, 1.0]));
        // Head B (right hand about +Y) at +90 lays the tool along +X; C then turns it about Z.
        assert!(close(at("head-bc", &[0.0, 0.0, 0.0, 90.0, 0.0]), [1.0, 0.0, 0.0]));
        assert!(close(at("head-bc", &[0.0, 0.0, 0.0, 90.0, 90.0]), [0.0, 1.0, 0.0]));
        // C alone never tilts the tool.
        assert!(close(at("head-bc", &[0.0, 0.0, 0.0, 0.0, 37.0]), [0.0, 0.0, 1.0]));
        // Table A (left hand about +X) at +90 turns the part's +Z toward the machine's +Y, so the
        // machine's +Z tool points along the part's -Y.
        assert!(close(at("table-ac", &[0.0, 0.0, 0.0, 90.0, 0.0]), [0.0, -1.0, 0.0]));
        // Table B at +90 (left hand about +Y): the tool lies along the part's +X.
        assert!(close(at("table-bc", &[0.0, 0.0, 0.0, 90.0, 0.0]), [1.0, 0.0, 0.0]));
        // Mixed: head B +90 gives machine +X; table C +90 (left hand) shows it as part +Y.
        assert!(close(at("mixed-bc", &[0.0, 0.0, 0.0, 90.0, 90.0]), [0.0, 1.0, 0.0]));
    }

    #[test]
    fn bad_rotary_links_are_refused() {
        let mut m = MachineConfig::preset("head-bc").unwrap();
        m.rotary[0].axis = 'X';
        assert!(m.validate().is_err());
        let mut m = MachineConfig::preset("head-bc").unwrap();
        m.rotary[1].direction = [0.0; 3];
        assert!(m.validate().is_err());
    }
}
