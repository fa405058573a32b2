//! The tool offsets a controller starts with when nobody gave any (docs/contracts.md: without
//! `--tools`, every offset number 1–99 has length 100 mm and radius 5 mm), and the range a
//! tool offset value given from outside a program must lie in, for the CLI and the service
//! alike.

use fivex_engine::interp::{tool_value_fits, tool_value_limit, Offsets};

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
