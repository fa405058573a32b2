//! The tool offsets a controller starts with when nobody gave any (docs/contracts.md: without
//! `--tools`, every offset number 1–99 has length 100 mm and radius 5 mm), for the CLI and the
//! service alike.

use fivex_engine::interp::Offsets;

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
