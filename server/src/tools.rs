//! The tool offsets a controller starts with when nobody gave any (docs/contracts.md: without
//! `--tools`, every offset number 1–99 has length 100 mm and radius 5 mm), and the range a
//! tool offset value given from outside a program must lie in, for the CLI and the service
//! alike.

use fivex_engine::interp::{tool_value_fits, tool_value_limit, Offsets, ToolOffset};

pub const DEFAULT_NUMBERS: std::ops::RangeInclusive<u32> = 1..=99;
pub const DEFAULT_LENGTH: f64 = 100.0;
pub const DEFAULT_RADIUS: f64 = 5.0;

/// Give offsets 1–99 the default length and radius (geometry; wear and corner radius stay 0).
pub fn equip_defaults(offsets: &mut Offsets) {
    for n in DEFAULT_NUMBERS {
        if let Some(t) = offsets.tool_mut(n) {
            t.h_geometry = DEFAULT_LENGTH;
            t.d_geometry = DEFAULT_RADIUS;
        }
    }
}

/// A tool offset value from outside a program (the API, a fleet run's `tools`, `--tools`), in
/// mm: within the range G10 takes (`tool_value_limit`, geometry or `wear`). Beyond it the
/// request or file is refused, naming the value (`what`) and the range: a program could not
/// set such an offset, and a run would take it (a length of a metre as an overtravel far from
/// its cause, or none at all).
pub fn check_value(what: &str, value: f64, wear: bool) -> Result<f64, String> {
    let limit = tool_value_limit(wear, false);
    if tool_value_fits(value, wear, false) {
        Ok(value)
    } else {
        Err(format!("{what} {value} is outside ±{limit} mm (the range of a tool offset value, as G10 takes it)"))
    }
}

/// A tool's corner radius: 0 or more, and within the geometry range of [`check_value`].
pub fn check_corner_radius(value: f64) -> Result<f64, String> {
    let limit = tool_value_limit(false, false);
    if value >= 0.0 && tool_value_fits(value, false, false) {
        Ok(value)
    } else {
        Err(format!("corner_radius {value} must be a number from 0 to {limit} mm"))
    }
}

/// The values of one tool offset given from outside a program, each optional (absent: as it
/// is): what `PUT /controllers/{id}/tool-offsets/{n}` changes and what an entry of a tool table
/// (`--tools`, a fleet run's `tools`: `fleet::Tool`) sets. One type, so both take the same
/// values with the same ranges.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ToolValues {
    /// H geometry and wear, mm.
    pub length: Option<f64>,
    pub length_wear: Option<f64>,
    /// D geometry and wear, mm.
    pub radius: Option<f64>,
    pub radius_wear: Option<f64>,
    pub corner_radius: Option<f64>,
}

impl ToolValues {
    /// The values, each within the range G10 takes ([`check_value`], [`check_corner_radius`]);
    /// the first one beyond it, named, otherwise.
    pub fn checked(self) -> Result<ToolValues, String> {
        let value = |v: Option<f64>, what: &str, wear: bool| v.map(|v| check_value(what, v, wear)).transpose();
        Ok(ToolValues {
            length: value(self.length, "length", false)?,
            length_wear: value(self.length_wear, "length_wear", true)?,
            radius: value(self.radius, "radius", false)?,
            radius_wear: value(self.radius_wear, "radius_wear", true)?,
            corner_radius: self.corner_radius.map(check_corner_radius).transpose()?,
        })
    }

    /// Sets the values given in `t` (the others stay as they are).
    pub fn apply(&self, t: &mut ToolOffset) {
        let set = |slot: &mut f64, v: Option<f64>| *slot = v.unwrap_or(*slot);
        set(&mut t.h_geometry, self.length);
        set(&mut t.h_wear, self.length_wear);
        set(&mut t.d_geometry, self.radius);
        set(&mut t.d_wear, self.radius_wear);
        set(&mut t.corner_radius, self.corner_radius);
    }
}
