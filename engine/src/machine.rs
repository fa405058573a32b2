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

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MachineConfig {
    pub name: String,
    pub axes: Vec<Axis>,
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
        Some(MachineConfig { name: name.to_string(), axes })
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
}
