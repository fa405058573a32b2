//! The Haas list: the machine rotary zero point (MRZP, NGC Settings 255/256/257) and the
//! machine's configuration (`docs/machine-config.md`, "Haas settings").
//!
//! The NGC keeps the rotary centres in user settings: Setting 255/256/257 are the MRZP X/Y/Z
//! offsets, the machine coordinates where the tilt axis line meets the platter's axis (a VF's
//! 4th axis: the Y/Z of its line). What the machine is — travels, rapids, which rotary unit —
//! Haas keeps in factory parameters whose numbers are not public: fivex gives those a
//! **constructed** range, 9000–9011, documented as such. Haas machine zero is the positive end
//! of every linear travel, so a travel `t` is the stroke `[-t, 0]`.
//!
//! The rotary units fivex knows (9000): 1 a 4th axis A about X on the table (an HRT rotary);
//! 2 a trunnion on a VF, A tilting about X carrying a platter B about Z (TR160, TRT160: Haas
//! names the platter of a VF's 5th axis B); 3 a UMC, B tilting about Y carrying a platter C
//! about Z (the line of Autodesk's certified "HAAS - Next Generation Control" Fusion post,
//! whose UMC-500/750/1000 models have B `axis:[0, 1, 0]`, C `axis:[0, 0, 1]`; `docs/dialects.md`,
//! "Haas 5-axis"). Table axes turn left-hand, as in fivex's presets (ISO 841: the table turns the
//! other way than the tool would). The platter and a 4th axis without a range roll over and take
//! the shortest way (decision, `docs/dialects.md`, "Haas 5-axis").

use super::{unrepresentable, Params};
use crate::machine::{Axis, AxisKind, ConfigError, Hand, MachineConfig, MotionOptions, RotaryLink, Side};

/// Setting 9, Dimensioning: programs start in inch (1) or mm (0, the default) at power on. The
/// NGC shows the choice by name (INCH / MM); the numbers are fivex's.
pub const DIMENSIONING: u32 = 9;
/// Setting 255: MRZP X offset (the first of three, X/Y/Z).
pub const MRZP: u32 = 255;
/// Constructed: the rotary unit (0 none, 1 4th axis A, 2 VF trunnion A/B, 3 UMC B/C).
pub const UNIT: u32 = 9000;
/// Constructed: X/Y/Z travel, mm (stroke `[-t, 0]`).
pub const TRAVEL: u32 = 9001;
/// Constructed: X/Y/Z rapid, mm/min.
pub const RAPID: u32 = 9004;
/// Constructed: rapid of the tilt axis (or the 4th axis), then of the platter, °/min.
pub const ROTARY_RAPID: u32 = 9007;
/// Constructed: the tilt axis range, low then high, degrees (both 0: no range, rollover).
pub const TILT_RANGE: u32 = 9009;
/// Constructed: linear acceleration, mm/s² (0: the engine's default).
pub const ACCEL: u32 = 9011;

/// The line of the unit's tilt (or 4th) axis: a UMC's B about Y, an A about X.
fn tilt_direction(unit: i64) -> [f64; 3] {
    if unit == 3 {
        [0.0, 1.0, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    }
}

/// The rotary units: (tilt or 4th axis, platter) letters.
fn unit_axes(unit: i64) -> &'static [char] {
    match unit {
        1 => &['A'],
        2 => &['A', 'B'],
        3 => &['B', 'C'],
        _ => &[],
    }
}

pub fn machine(name: &str, p: &Params) -> Result<MachineConfig, ConfigError> {
    let unit = p.code(UNIT, 0, 3)?;
    let travel = p.get3(TRAVEL)?;
    let rapid = p.get3(RAPID)?;
    let accel = p.get(ACCEL)?;
    if accel < 0.0 {
        return Err(ConfigError::invalid(format!("parameter {ACCEL} (acceleration) must not be negative")));
    }
    let mut axes = Vec::new();
    for (k, letter) in ['X', 'Y', 'Z'].into_iter().enumerate() {
        if travel[k] <= 0.0 || rapid[k] <= 0.0 {
            return Err(ConfigError::invalid(format!(
                "parameters {} and {} ({letter} travel and rapid) must be positive",
                TRAVEL + k as u32,
                RAPID + k as u32
            )));
        }
        axes.push(Axis {
            stroke: Some([-travel[k], 0.0]),
            accel: (accel > 0.0).then_some(accel),
            ..Axis::new(letter, AxisKind::Linear, rapid[k])
        });
    }
    let mrzp = p.get3(MRZP)?;
    let [low, high] = [p.get(TILT_RANGE)?, p.get(TILT_RANGE + 1)?];
    if low > high {
        return Err(ConfigError::invalid(format!(
            "Setting {TILT_RANGE}/{} (tilt range): low above high",
            TILT_RANGE + 1
        )));
    }
    let range = (low != 0.0 || high != 0.0).then_some([low, high]);
    let mut rotary = Vec::new();
    for (j, &letter) in unit_axes(unit).iter().enumerate() {
        let tilt = j == 0;
        let r = p.get(ROTARY_RAPID + j as u32)?;
        if r <= 0.0 {
            return Err(ConfigError::invalid(format!(
                "parameter {} ({letter} rapid) must be positive",
                ROTARY_RAPID + j as u32
            )));
        }
        // The tilt (or 4th) axis has the range; the platter always rolls over.
        let range = if tilt { range } else { None };
        rotary.push(RotaryLink {
            axis: letter,
            side: Side::Table,
            direction: if tilt { tilt_direction(unit) } else { [0.0, 0.0, 1.0] },
            hand: Hand::Left,
            point: mrzp,
            zero_offset: 0.0,
            fixed: None,
            range,
        });
        axes.push(Axis {
            stroke: range,
            rollover: range.is_none(),
            shortest: range.is_none(),
            ..Axis::new(letter, AxisKind::Rotary, r)
        });
    }
    // The control lists the axes by address (A, B, C after X, Y, Z).
    axes.sort_by_key(|a| (a.kind == AxisKind::Rotary, a.name));
    Ok(MachineConfig {
        name: name.to_string(),
        axes,
        rotary,
        tool_axis: [0.0, 0.0, 1.0],
        nose: [0.0; 3],
        holder: 0.0,
        sub_chains: Vec::new(),
        chains: Vec::new(),
        motion: MotionOptions { power_on_inch: p.code(DIMENSIONING, 0, 1)? == 1, ..MotionOptions::default() },
        five_axis: Default::default(),
        manual: Default::default(),
        cycles: Default::default(),
    })
}

/// The MRZP settings (255–257) a list with a rotary unit leaves out: each is then 0, machine
/// zero, which is no rotary centre of a real machine (reported when the list is loaded).
pub fn missing_mrzp(p: &Params) -> Vec<u32> {
    if p.code(UNIT, 0, 3).unwrap_or(0) == 0 {
        return Vec::new();
    }
    (MRZP..MRZP + 3).filter(|n| !p.0.contains_key(n)).collect()
}

/// The Haas list of `m`, if `m` is one of the rotary units a Haas list describes.
pub fn params(m: &MachineConfig) -> Result<Params, ConfigError> {
    let no = |what: String| unrepresentable("Haas", what);
    let linear: Vec<&Axis> = m.axes.iter().filter(|a| a.kind == AxisKind::Linear).collect();
    if linear.iter().map(|a| a.name).collect::<String>() != "XYZ" {
        return Err(no("the linear axes are not X, Y, Z".into()));
    }
    let letters: Vec<char> = m.rotary.iter().map(|l| l.axis).collect();
    let unit = (0..=3)
        .find(|&u| unit_axes(u) == letters.as_slice())
        .ok_or_else(|| no("the rotary axes are not A, A/B or B/C".into()))?;
    if m.axes.len() != 3 + letters.len() {
        return Err(no("an axis outside the rotary unit".into()));
    }
    if m.tool_axis != [0.0, 0.0, 1.0] || m.nose != [0.0; 3] || m.holder != 0.0 {
        return Err(no("the tool is not along +Z from the spindle nose".into()));
    }
    if (MotionOptions { power_on_inch: false, ..m.motion }) != MotionOptions::default() {
        return Err(no("motion options other than the defaults".into()));
    }
    if m.cycles != Default::default() {
        // Settings 22, 27 and 52 are the NGC's, but no source gives their units and codes.
        return Err(no("canned cycle settings other than the defaults".into()));
    }
    if m.five_axis != Default::default()
        || m.manual != Default::default()
        || !m.chains.is_empty()
        || !m.sub_chains.is_empty()
    {
        return Err(no("5-axis, manual or chain options".into()));
    }
    let mut p = Params::default();
    if m.motion.power_on_inch {
        p.set(DIMENSIONING, 1.0);
    }
    p.set(UNIT, unit as f64);
    let accel = linear[0].accel;
    for (k, a) in linear.iter().enumerate() {
        let Some([lo, 0.0]) = a.stroke.filter(|s| s[0] < 0.0 && s[1] == 0.0) else {
            return Err(no(format!("the {} stroke is not [-travel, 0]", a.name)));
        };
        if a.accel != accel || a.jerk.is_some() || a.references != [0.0; 3] || a.rollover {
            return Err(no(format!("{} axis options", a.name)));
        }
        p.set(TRAVEL + k as u32, -lo);
        p.set(RAPID + k as u32, a.rapid);
    }
    if let Some(a) = accel {
        p.set(ACCEL, a);
    }
    let mrzp = m.rotary.first().map_or([0.0; 3], |l| l.point);
    for (j, l) in m.rotary.iter().enumerate() {
        let tilt = j == 0;
        let direction = if tilt { tilt_direction(unit) } else { [0.0, 0.0, 1.0] };
        if l.side != Side::Table || l.direction != direction || l.hand != Hand::Left || l.point != mrzp {
            return Err(no(format!("{}: not the Haas unit's axis through the MRZP", l.axis)));
        }
        if l.zero_offset != 0.0 || l.fixed.is_some() || (!tilt && l.range.is_some()) {
            return Err(no(format!("{}: zero offset, hypothetical axis or platter range", l.axis)));
        }
        let a = m.axes.iter().find(|a| a.name == l.axis).ok_or_else(|| no("a rotary link without its axis".into()))?;
        let rolls = l.range.is_none();
        if a.stroke != l.range || a.rollover != rolls || a.shortest != rolls || a.accel.is_some() || a.jerk.is_some() {
            return Err(no(format!("{} axis options", l.axis)));
        }
        p.set(ROTARY_RAPID + j as u32, a.rapid);
        if let Some([lo, hi]) = l.range {
            p.set(TILT_RANGE, lo);
            p.set(TILT_RANGE + 1, hi);
        }
    }
    if unit != 0 {
        for (k, v) in mrzp.iter().enumerate() {
            p.set(MRZP + k as u32, *v);
        }
    }
    Ok(p)
}
