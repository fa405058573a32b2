//! FANUC 30i-A5 parameters (fanuc-twp-wsec-manual-params.md §2.9, §5; fanuc-tcp.md §5).
//!
//! Axis parameters hold one value per axis: No.1020 name (ASCII), 1022 basic axis, 1006#0 ROT (#5 ZMI
//! refused on a rollover axis),
//! 1008#0 ROA / #1 RAB, 1260 per revolution, 1320/1321 stroke, 1401#1 LRP, 1403#5 HTG, 1420 rapid, 1660 acceleration,
//! 1672 bell-shaped time. The mechanism: 19680 type, 19681–19690 the two rotary axes, 19696#0/#1
//! hypothetical axes, 19697–19699 reference tool direction, 19700–19705 table positions, 19666
//! tool holder offset, 19709–19714 head offset vectors, 19741–19744 movement ranges.
//! Look-ahead: 1604#0 SHP, 19501#5 FRP, 1660 / 1671 all 0. G54.4: 11200#0 RCM, 11202/11203
//! rotary clamp, 11204, 3106#6 DAK, 5006#6 TOS, 5412 cycle feed, 5400#2 D3R. Cutter
//! compensation: 5003#0 SUP (start-up/cancel type B), #1 SUV (perpendicular to the next movement), 19607#5 CAV (interference avoidance),
//! 19607#1 SPG (the tool side offset's G codes by mechanism: G41.4 table, G41.5 mixed).
//! The 16i variant of 3-D cutter compensation: 19605#5 NIC, 19630 (a list holding either is a 16i's).
//! Cutting point control: 11262 (the singular posture's angle). Canned cycles: 5114 G73's retract,
//! 5115 G83's clearance, 5101#4 RD1 / #5 RD2 the G76/G87 shift direction.

use super::{chain, direction, half_turn, reference_angles, reference_direction, unit, unrepresentable};
use super::{Params, Value};
use crate::alarm::AlarmId;
use crate::kin::{vec3, Vec3};
use crate::machine::{
    AfterInterpolation, Axis, AxisKind, BoreShift, ConfigError, CrcVariant, CycleOptions, FiveAxisOptions, Hand,
    MachineConfig, ManualOptions, ManualVertical, MotionOptions, PlaneAfterReset, RotaryLink, Side, TcpCoordinates,
    DEFAULT_PECK_DISTANCE, MAX_PECK_DISTANCE,
};

const NAMES: &str = "XYZUVWABC";

/// No.1022 basic axis attribute of an axis name (X, Y, Z are 1–3, U, V, W parallel to them 5–7).
fn basic(name: char) -> f64 {
    match name {
        'X' => 1.0,
        'Y' => 2.0,
        'Z' => 3.0,
        'U' => 5.0,
        'V' => 6.0,
        'W' => 7.0,
        _ => 0.0,
    }
}

/// FANUC real parameters carry at most nine decimals; rounding there makes the written set the
/// canonical one whatever floating-point noise the conversion left.
fn real(x: f64) -> f64 {
    let r = (x * 1e9).round() / 1e9;
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn bad(detail: String) -> ConfigError {
    ConfigError::alarm(AlarmId::AxisSetting, detail)
}

/// Parameters that change the unit of every length the list and the programs give: refused,
/// not reported as unmodelled, since the same list read in fivex's units describes another
/// machine (an inch machine read as mm is 25.4 times too small; an IS-C axis read as IS-B moves
/// `X10` ten times as far). fivex's FANUC machines are metric (No.1001#0 INM = 0), with the
/// increment system IS-B (No.1013#0–#3 = 0) and numbers without a point in least increments
/// (No.3401#0 DPI = 0; the programs' own G20/G21 and No.0000#2 INI are built).
fn refuse_other_units(p: &Params, names: &[f64]) -> Result<(), ConfigError> {
    if p.0.contains_key(&1001) && p.bit(1001, 0)? {
        return Err(ConfigError::invalid(
            "No.1001#0 INM = 1 (an inch machine: the parameters' lengths in inch) is not built; fivex's FANUC machines are metric",
        ));
    }
    if p.0.contains_key(&3401) && p.bit(3401, 0)? {
        return Err(ConfigError::invalid(
            "No.3401#0 DPI = 1 (a number without a point in mm or degrees) is not built; fivex reads it in least increments",
        ));
    }
    for (i, bits) in p.axes(1013, names.len())?.into_iter().enumerate() {
        if super::params::whole(1013, bits, 0, 255)? & 0x0f != 0 {
            let letter = super::params::whole(1020, names[i], 0, 127)? as u8 as char;
            return Err(ConfigError::invalid(format!(
                "No.1013 of axis {letter}: an increment system other than IS-B (ISA/ISC/ISD/ISE) is not built; \
                 fivex's least increment is 0.001 mm / 0.001 deg"
            )));
        }
    }
    Ok(())
}

pub fn machine(name: &str, p: &Params) -> Result<MachineConfig, ConfigError> {
    let names = match p.0.get(&1020) {
        Some(Value::PerAxis(v)) if !v.is_empty() => v.clone(),
        _ => return Err(ConfigError::invalid("No.1020 (axis names, ASCII codes, one per axis) is needed")),
    };
    let n = names.len();
    refuse_other_units(p, &names)?;
    let (rot, roll, per_rev, basics) = (p.axes(1006, n)?, p.axes(1008, n)?, p.axes(1260, n)?, p.axes(1022, n)?);
    let references = [p.axes(1241, n)?, p.axes(1242, n)?, p.axes(1243, n)?];
    let smoothing = p.axes(19587, n)?;
    let after_ms = p.axes(1622, n)?;
    let (rapid_t1, rapid_t2) = (p.axes(1620, n)?, p.axes(1621, n)?);
    let (plus, minus, rapid, accel, bell) =
        (p.axes(1320, n)?, p.axes(1321, n)?, p.axes(1420, n)?, p.axes(1660, n)?, p.axes(1672, n)?);
    let mut axes = Vec::with_capacity(n);
    for i in 0..n {
        let code = super::params::whole(1020, names[i], 0, 127)? as u8;
        let letter = code as char;
        if !NAMES.contains(letter) || code == 0 {
            return Err(ConfigError::invalid(format!("No.1020 axis {}: {} is not one of {NAMES}", i + 1, names[i])));
        }
        let rot_bits = super::params::whole(1006, rot[i], 0, 255)?;
        let rotary = rot_bits & 1 == 1;
        let bits = super::params::whole(1008, roll[i], 0, 255)?;
        if basics[i] != 0.0 && basics[i] != basic(letter) {
            return Err(ConfigError::invalid(format!(
                "No.1022 of axis {letter} is {}, not {}",
                basics[i],
                basic(letter)
            )));
        }
        let rollover = rotary && bits & 1 == 1;
        // No.1006#5 ZMI: the manual reference return's direction, which a rollover axis's G28/G30
        // follow (`angle::reference_travel`); fivex turns them positive (ZMI = 0) only, so a
        // negative one is refused rather than turned the other way round.
        if rollover && rot_bits & 0x20 != 0 {
            return Err(ConfigError::invalid(format!(
                "No.1006#5 ZMI of axis {letter}: fivex returns a rollover axis to its reference in the positive direction only"
            )));
        }
        // No.1260, the move per revolution: fivex turns a rotary axis 360° per revolution (and
        // rolls over there), so any other value is refused rather than ignored.
        if rotary && per_rev[i] != 360.0 && per_rev[i] != 0.0 {
            return Err(ConfigError::invalid(format!("No.1260 of axis {letter}: fivex turns 360 per revolution only")));
        }
        if smoothing[i] < 0.0 || (!rotary && smoothing[i] != 0.0) {
            return Err(ConfigError::invalid(format!("No.19587 of axis {letter}: 0 or more, on rotary axes only")));
        }
        for (number, ms) in [(1622, after_ms[i]), (1620, rapid_t1[i]), (1621, rapid_t2[i])] {
            if !(0.0..=crate::machine::MAX_AFTER_INTERPOLATION_MS).contains(&ms) {
                return Err(ConfigError::invalid(format!("No.{number} of axis {letter}: 0 to 4000 ms")));
            }
        }
        let stroke = (plus[i] != 0.0 || minus[i] != 0.0).then_some([minus[i], plus[i]]);
        let a = (accel[i] > 0.0).then_some(accel[i]);
        let jerk = a.filter(|_| bell[i] > 0.0).map(|a| a / (bell[i] / 1000.0));
        axes.push(Axis {
            accel: a,
            jerk,
            stroke,
            rollover,
            shortest: rollover && bits & 2 == 0,
            references: [references[0][i], references[1][i], references[2][i]],
            smoothing_tolerance: smoothing[i],
            after_interpolation_ms: after_ms[i],
            rapid_after_interpolation_ms: [rapid_t1[i], rapid_t2[i]],
            ..Axis::new(letter, if rotary { AxisKind::Rotary } else { AxisKind::Linear }, rapid[i])
        });
    }
    let kind = p.code(19680, 0, 21)?;
    let tool_code = p.code(19697, 0, 3)?;
    if kind != 0 && tool_code == 0 {
        let detail = "No.19697 (reference tool direction) must be 1, 2 or 3";
        return Err(ConfigError::alarm(AlarmId::ToolDirectionSetting, detail));
    }
    let tool_axis = if tool_code == 0 { unit(3) } else { reference_direction(tool_code, p.get(19698)?, p.get(19699)?) };
    let sides = match kind {
        0 => vec![],
        2 => vec![Side::Head, Side::Head],
        12 => vec![Side::Table, Side::Table],
        21 => vec![Side::Head, Side::Table],
        _ => return Err(ConfigError::invalid(format!("No.19680 = {kind}: the type is 0, 2, 12 or 21"))),
    };
    let mut rotary = Vec::new();
    for (j, side) in sides.iter().enumerate() {
        let base = 19681 + 5 * j as u32;
        let hypothetical = p.bit(19696, j as u32)?;
        let number = p.code(base, 0, n as i64)?;
        let code = p.code(base + 1, 1, 6)?;
        let tilt = p.get(base + 2)?;
        if code <= 3 && tilt != 0.0 {
            return Err(bad(format!("No.{} must be 0 when No.{} is {code} (TV-KIN-08)", base + 2, base + 1)));
        }
        let (s, c) = crate::angle::sin_cos_deg(tilt);
        let direction = match code {
            1..=3 => unit(code),
            4 => Vec3::new(c, s, 0.0),
            5 => Vec3::new(0.0, c, s),
            _ => Vec3::new(s, 0.0, c),
        };
        let hand = if p.code(base + 3, 0, 1)? == 0 { Hand::Right } else { Hand::Left };
        let axis = if hypothetical {
            if number != 0 {
                return Err(bad(format!("No.{base} must be 0 for a hypothetical axis (No.19696#{j})")));
            }
            // A name for the model only: a letter no axis or other link uses ('H' when A, B and C
            // are all taken).
            let taken = |c: char| axes.iter().any(|a| a.name == c) || rotary.iter().any(|l: &RotaryLink| l.axis == c);
            "ABCH".chars().find(|&c| !taken(c)).unwrap_or('G')
        } else {
            let i = number as usize;
            if i == 0 || axes[i - 1].kind != AxisKind::Rotary {
                return Err(bad(format!("No.{base} = {number} is not a rotary axis (No.1006#0, TV-KIN-16)")));
            }
            axes[i - 1].name
        };
        let (upper, lower) = (p.get(19741 + 2 * j as u32)?, p.get(19742 + 2 * j as u32)?);
        rotary.push(RotaryLink {
            axis,
            side: *side,
            direction: direction.into(),
            hand,
            point: [0.0; 3],
            zero_offset: 0.0,
            fixed: hypothetical.then(|| p.get(base + 4)).transpose()?,
            range: (upper != 0.0 || lower != 0.0).then_some([lower, upper]),
        });
    }
    // Positions. The controlled point — where machine X/Y/Z are at zero angles — lies on the
    // tool axis, No.19666 above the spindle nose: the tool length offset plus No.19666 is the
    // distance from the tool centre point to the controlled point on every mechanism type, a
    // table-rotation one too (A-79348E, "Tool length offset value and setting in parameter
    // No. 19666"; the note that type 12 does not shift the controlled point is about No.19665#5).
    // No.19709 leads from it to the tool-side axis next to the tool, No.19712 from there to the
    // other head axis. The table's first axis passes through No.19700, the second through
    // No.19700 + No.19703.
    let holder = p.get(19666)?;
    let (v1, v2) = (vec3(p.get3(19709)?), vec3(p.get3(19712)?));
    let (a, d) = (vec3(p.get3(19700)?), vec3(p.get3(19703)?));
    let points = match kind {
        2 => [v1 + v2, v1],
        12 => [a, a + d],
        21 => [v1, a],
        _ => [Vec3::zeros(); 2],
    };
    for (link, point) in rotary.iter_mut().zip(points) {
        link.point = point.into();
    }
    let nose = (tool_axis * -holder).into();
    // No.1403#5 HTG: helical feed along the whole path (absent: 0, along the arc).
    let helical_feed_on_path = p.0.contains_key(&1403) && p.bit(1403, 5)?;
    // No.1401#1 LRP: written only when 0 (non-linear rapids); absent means fivex's default,
    // linear-type rapids.
    let nonlinear_rapid = p.0.contains_key(&1401) && !p.bit(1401, 1)?;
    // No.0000#2 INI: the input unit at power on (absent: 0, mm).
    let power_on_inch = p.0.contains_key(&0) && p.bit(0, 2)?;
    // No.6001#6 CCV: a reset keeps #100–#199 (absent: 0, clears them). The other bits are not
    // read (reported when set).
    let commons_kept_at_reset = p.0.contains_key(&6001) && p.bit(6001, 6)?;
    // No.5003#0 SUP: cutter compensation start-up/cancel type B (absent: 0, type A); #1 SUV:
    // "perpendicular to the next movement" where the G41/G42/G40 block does not move in the
    // plane. The other bits are not read.
    let cutter_startup_type_b = p.0.contains_key(&5003) && p.bit(5003, 0)?;
    let cutter_startup_perpendicular = p.0.contains_key(&5003) && p.bit(5003, 1)?;
    // No.19607#5 CAV: the interference check avoids instead of stopping (absent: 0). (#1 SPG
    // is read with the 5-axis settings; the parameter's other bits are not read.)
    let cutter_interference_avoidance = p.0.contains_key(&19607) && p.bit(19607, 5)?;
    let motion = MotionOptions {
        helical_feed_on_path,
        nonlinear_rapid,
        power_on_inch,
        commons_kept_at_reset,
        cutter_startup_type_b,
        cutter_startup_perpendicular,
        cutter_interference_avoidance,
        after_interpolation: after_interpolation(p, &after_ms)?,
        ..look_ahead_options(p, n, &accel)?
    };
    let five_axis = five_axis_options(p)?;
    let manual = manual_options(p, n)?;
    let cycles = cycle_options(p)?;
    Ok(MachineConfig {
        name: name.to_string(),
        axes,
        rotary,
        tool_axis: tool_axis.into(),
        nose,
        holder,
        sub_chains: Vec::new(),
        chains: Vec::new(),
        motion,
        five_axis,
        manual,
        cycles,
    })
}

/// The canned cycles: No.5114 G73's retract and No.5115 G83's clearance (absent: fivex's
/// 0.5 mm), No.5101#4 RD1 / #5 RD2 the shift direction of G76/G87 (absent: +X in G17). The
/// other bits of No.5101 are not read.
fn cycle_options(p: &Params) -> Result<CycleOptions, ConfigError> {
    let distance = |number: u32| -> Result<f64, ConfigError> {
        if !p.0.contains_key(&number) {
            return Ok(DEFAULT_PECK_DISTANCE);
        }
        match non_negative(p, number)? {
            x if x <= MAX_PECK_DISTANCE => Ok(x),
            x => Err(ConfigError::invalid(format!("No.{number} = {x} is more than {MAX_PECK_DISTANCE} mm"))),
        }
    };
    let bit = |b: u32| -> Result<bool, ConfigError> { Ok(p.0.contains_key(&5101) && p.bit(5101, b)?) };
    let bore_shift = match (bit(5)?, bit(4)?) {
        (false, false) => BoreShift::PlusX,
        (false, true) => BoreShift::MinusX,
        (true, false) => BoreShift::PlusY,
        (true, true) => BoreShift::MinusY,
    };
    Ok(CycleOptions { peck_retract: distance(5114)?, peck_clearance: distance(5115)?, bore_shift })
}

/// [`cycle_options`] the other way: what differs from fivex's defaults is written.
fn cycle_params(p: &mut Params, m: &MachineConfig) {
    let c = &m.cycles;
    for (number, value) in [(5114, c.peck_retract), (5115, c.peck_clearance)] {
        if value != DEFAULT_PECK_DISTANCE {
            p.set(number, real(value));
        }
    }
    let (second, sign) = c.bore_shift.in_plane();
    let bits = (u32::from(sign < 0.0) << 4) | (u32::from(second) << 5);
    if bits != 0 {
        p.set_bits(5101, bits);
    }
}

/// Look-ahead (acceleration/deceleration before interpolation): No.1604#0 SHP, No.19501#5 FRP
/// (written only when 0, absent: fivex's default, on), No.1660 / No.1671 all 0 (read only when
/// present). `accel` is No.1660.
fn look_ahead_options(p: &Params, axes: usize, accel: &[f64]) -> Result<MotionOptions, ConfigError> {
    let cleared =
        |number: u32, bit: u32| -> Result<bool, ConfigError> { Ok(p.0.contains_key(&number) && !p.bit(number, bit)?) };
    let all_zero = |number: u32, values: &[f64]| p.0.contains_key(&number) && values.iter().all(|x| *x == 0.0);
    Ok(MotionOptions {
        look_ahead_by_command: cleared(1604, 0)?,
        no_feed_look_ahead: all_zero(1660, accel),
        no_rapid_look_ahead: cleared(19501, 5)? || all_zero(1671, &p.axes(1671, axes)?),
        ..MotionOptions::default()
    })
}

/// The type of cutting feed's acceleration/deceleration after interpolation: No.1610 (per
/// axis) #0 CTL linear, #1 CTB bell-shaped, neither exponential (0i-A connection manual
/// p.314 names the same parameter's #4 JGL). fivex models one type for the machine: the axes
/// with a time constant (No.1622) must agree.
fn after_interpolation(p: &Params, after_ms: &[f64]) -> Result<AfterInterpolation, ConfigError> {
    let bits = p.axes(1610, after_ms.len())?;
    let mut kind = None;
    let mut first = None;
    for (b, ms) in bits.iter().zip(after_ms) {
        let b = super::params::whole(1610, *b, 0, 255)?;
        let this = match (b & 1 == 1, b & 2 == 2) {
            (_, true) => AfterInterpolation::Bell,
            (true, false) => AfterInterpolation::Linear,
            (false, false) => AfterInterpolation::Exponential,
        };
        first.get_or_insert(this);
        if *ms == 0.0 {
            continue;
        }
        if kind.is_some_and(|k| k != this) {
            return Err(ConfigError::invalid("No.1610 #0/#1: fivex takes one type of acceleration/deceleration after interpolation for every axis with a No.1622 time constant"));
        }
        kind = Some(this);
    }
    // Without a time constant the type is the first axis's (as written for a model).
    Ok(kind.or(first).unwrap_or_default())
}

/// [`look_ahead_options`] the other way: SHP = 0 and FRP = 0 as `1604: 0`, `19501: 0`; no
/// cutting-feed look-ahead as No.1660 (and its bell-shaped time No.1672) 0 on every axis, which
/// leaves no room for the axes' own accelerations.
fn look_ahead_params(p: &mut Params, m: &MachineConfig) -> Result<(), ConfigError> {
    let o = &m.motion;
    if o.look_ahead_by_command {
        p.set(1604, 0.0);
    }
    if o.no_rapid_look_ahead {
        p.set(19501, 0.0);
    }
    if o.no_feed_look_ahead {
        if m.axes.iter().any(|a| a.accel.is_some() || a.jerk.is_some()) {
            return Err(unrepresentable(
                "FANUC",
                "axis accelerations without look-ahead for cutting feed (No.1660 = 0)",
            ));
        }
        p.set_axes(1660, vec![0.0; m.axes.len()]);
        p.set_axes(1672, vec![0.0; m.axes.len()]);
    }
    Ok(())
}

/// The 5-axis manual feed settings: No.12318 tool length, 12320#0 TWD / #1 FLL / #2 JFR, 12321
/// vertical axis (outside 0…3: PS5459, as S002 lists 12321 among the machine configuration
/// parameters), 12322 parallel angle, 19746#2 LOD / #3 LOZ, 1410 dry run rate, 1423 jog feed
/// and 1424 manual rapid per axis (absent: 0), 12310–12314 handle select codes (0…31).
fn manual_options(p: &Params, axes: usize) -> Result<ManualOptions, ConfigError> {
    let bit =
        |number: u32, bit: u32| -> Result<bool, ConfigError> { Ok(p.0.contains_key(&number) && p.bit(number, bit)?) };
    let code = p.get(12321)?;
    let vertical = match [0.0, 1.0, 2.0, 3.0].iter().position(|&c| c == code) {
        Some(0) => ManualVertical::Tool,
        Some(1) => ManualVertical::X,
        Some(2) => ManualVertical::Y,
        Some(3) => ManualVertical::Z,
        _ => return Err(ConfigError::alarm(AlarmId::MachineParameter, format!("No.12321 = {code} is not 0…3"))),
    };
    let rapid = p.axes(1424, axes)?;
    let jog = p.axes(1423, axes)?;
    let mut handle_codes = [0u8; 5];
    for (k, code) in handle_codes.iter_mut().enumerate() {
        // HS1A–HS1E: five signal bits.
        *code = p.code(12310 + k as u32, 0, 31)? as u8;
    }
    Ok(ManualOptions {
        tool_length: p.get(12318)?,
        length_from_offset: bit(19746, 2)?,
        zero_length_without_offset: bit(19746, 3)?,
        plane_directions: bit(12320, 0)?,
        latitude_longitude: bit(12320, 1)?,
        jog_feedrate: bit(12320, 2)?,
        vertical,
        parallel_deg: p.get(12322)?,
        dry_run_feed: p.get(1410)?,
        rapid: if rapid.iter().all(|x| *x == 0.0) { Vec::new() } else { rapid },
        jog_feed: if jog.iter().all(|x| *x == 0.0) { Vec::new() } else { jog },
        handle_codes,
    })
}

/// [`manual_options`] the other way; only what differs from 0 is written.
fn manual_params(p: &mut Params, m: &MachineConfig) {
    let o = &m.manual;
    let bits = |b: &[bool]| b.iter().enumerate().fold(0u32, |acc, (i, &on)| acc | (on as u32) << i) as f64;
    let vertical = match o.vertical {
        ManualVertical::Tool => 0.0,
        ManualVertical::X => 1.0,
        ManualVertical::Y => 2.0,
        ManualVertical::Z => 3.0,
    };
    for (number, value) in [
        (12318, real(o.tool_length)),
        (12320, bits(&[o.plane_directions, o.latitude_longitude, o.jog_feedrate])),
        (12321, vertical),
        (12322, real(o.parallel_deg)),
        (1410, real(o.dry_run_feed)),
    ] {
        if value != 0.0 {
            p.set(number, value);
        }
    }
    let lod_loz = bits(&[false, false, o.length_from_offset, o.zero_length_without_offset]) as u32;
    if lod_loz != 0 {
        p.set_bits(19746, lod_loz);
    }
    for (number, values) in [(1424, &o.rapid), (1423, &o.jog_feed)] {
        if values.iter().any(|x| *x != 0.0) {
            p.set_axes(number, (0..m.axes.len()).map(|i| real(values.get(i).copied().unwrap_or(0.0))).collect());
        }
    }
    for (k, &code) in o.handle_codes.iter().enumerate() {
        if code != 0 {
            p.set(12310 + k as u32, code as f64);
        }
    }
}

/// The 5-axis function bits: No.19696#3 NPC, #5 WKP, #6 RFC, No.19754#5 INZ, No.19604#0 TPC,
/// No.19608#1 NI5, #2 DET, #5 PRI, #6 MIR, No.19746#4 TBP, #6 CRS, No.11221#0 MTW, No.5400#2 D3R, and
/// No.19738/19739/19751/19752/11220; G54.4: No.11200#0 RCM, No.11204 singular tolerance (degrees),
/// No.5006#6 TOS (absent: 1), No.5412, No.11202/11203 (percent), No.3106#6 DAK (absent: 0).
fn five_axis_options(p: &Params) -> Result<FiveAxisOptions, ConfigError> {
    let bit =
        |number: u32, bit: u32| -> Result<bool, ConfigError> { Ok(p.0.contains_key(&number) && p.bit(number, bit)?) };
    let tcp_coordinates = match (bit(19696, 5)?, bit(19754, 5)?) {
        (true, _) => TcpCoordinates::Workpiece,
        (false, true) => TcpCoordinates::TableAtZero,
        (false, false) => TcpCoordinates::TableAtStart,
    };
    Ok(FiveAxisOptions {
        tcp_coordinates,
        posture_control: bit(19604, 0)?,
        second_axis_first: bit(19608, 5)?,
        rotary_feed: bit(19696, 6)?,
        multiple_planes: bit(11221, 0)?,
        plane_min_distance: p.get(11220)?,
        plane_after_reset: if bit(5400, 2)? { PlaneAfterReset::Kept } else { PlaneAfterReset::Cancelled },
        tool_direction_compensation: bit(11200, 0)?,
        singular_tolerance_deg: if p.0.contains_key(&11204) { p.get(11204)? } else { 0.0 },
        singular_angle: if p.0.contains_key(&19738) { p.get(19738)? } else { 0.0 },
        singular_tolerance: if p.0.contains_key(&19739) { p.get(19739)? } else { 0.0 },
        singular_alarm: bit(19696, 3)?,
        mirror_direction: bit(19608, 6)?,
        display_workpiece: bit(19608, 2)?,
        deviation_clamp: bit(19746, 6)?,
        crc_table_coordinates: bit(19746, 4)?,
        crc_codes_by_mechanism: bit(19607, 1)?,
        crc_check_in_plane: bit(19608, 1)?,
        // The 16i variant: a list holding No.19605 (#5 NIC) or No.19630 is a 16i's (A-78438E;
        // the 30i's No.19605 bits are not read).
        crc_variant: if p.0.contains_key(&19605) || p.0.contains_key(&19630) {
            CrcVariant::Fanuc16i
        } else {
            CrcVariant::Fanuc30i
        },
        plane_change_check_off: bit(19605, 5)?,
        non_movement_limit: non_negative(p, 19630)?,
        avoidance_max_tool_angle: if p.0.contains_key(&19636) { p.get(19636)? } else { 0.0 },
        rapid_deviation: if p.0.contains_key(&19751) { p.get(19751)? } else { 0.0 },
        cutting_point_distance: if p.0.contains_key(&19632) { p.get(19632)? } else { 0.0 },
        plane_change_angle: if p.0.contains_key(&19635) { p.get(19635)? } else { 0.0 },
        leading_edge_tolerance: if p.0.contains_key(&19631) { p.get(19631)? } else { 0.0 },
        cutting_point_singular_angle: if p.0.contains_key(&11262) { p.get(11262)? } else { 0.0 },
        cutting_deviation: if p.0.contains_key(&19752) { p.get(19752)? } else { 0.0 },
        length_offset_by_motion: p.0.contains_key(&5006) && !p.bit(5006, 6)?,
        wse_cycle_feed: non_negative(p, 5412)?,
        wse_feed_clamp_pct: percent(p, 11202)?,
        wse_rapid_clamp_pct: percent(p, 11203)?,
        wse_display_wcs: bit(3106, 6)?,
        // Syntec's STCP: FANUC has none.
        ..FiveAxisOptions::default()
    })
}

/// A parameter that cannot be negative (absent: 0).
fn non_negative(p: &Params, number: u32) -> Result<f64, ConfigError> {
    match p.get(number)? {
        x if x >= 0.0 => Ok(x),
        x => Err(ConfigError::invalid(format!("No.{number} = {x} cannot be negative"))),
    }
}

/// An override percentage 0…100 (absent: 0).
fn percent(p: &Params, number: u32) -> Result<f64, ConfigError> {
    match p.get(number)? {
        x if (0.0..=100.0).contains(&x) => Ok(x),
        x => Err(ConfigError::invalid(format!("No.{number} = {x} is not a percentage 0…100"))),
    }
}

pub fn params(m: &MachineConfig) -> Result<Params, ConfigError> {
    if !m.chains.is_empty() || !m.sub_chains.is_empty() {
        return Err(unrepresentable("FANUC", "more than one mechanism chain (Syntec G10 L5000)"));
    }
    let mut p = Params::default();
    let each = |f: &dyn Fn(&Axis) -> f64| m.axes.iter().map(|a| real(f(a))).collect::<Vec<f64>>();
    p.set_axes(1020, each(&|a| a.name as u32 as f64));
    p.set_axes(1022, each(&|a| basic(a.name)));
    p.set_axes(1006, each(&|a| (a.kind == AxisKind::Rotary) as u8 as f64));
    p.set_axes(1008, each(&|a| if a.rollover { 1.0 + if a.shortest { 0.0 } else { 2.0 } } else { 0.0 }));
    p.set_axes(1260, each(&|a| if a.kind == AxisKind::Rotary { 360.0 } else { 0.0 }));
    p.set_axes(1320, each(&|a| a.stroke.map_or(0.0, |s| s[1])));
    p.set_axes(1321, each(&|a| a.stroke.map_or(0.0, |s| s[0])));
    p.set_axes(1420, each(&|a| a.rapid));
    for (k, number) in [1241, 1242, 1243].into_iter().enumerate() {
        if m.axes.iter().any(|a| a.references[k] != 0.0) {
            p.set_axes(number, each(&|a| a.references[k]));
        }
    }
    if m.axes.iter().any(|a| a.smoothing_tolerance != 0.0) {
        p.set_axes(19587, each(&|a| a.smoothing_tolerance));
    }
    if m.axes.iter().any(|a| a.after_interpolation_ms != 0.0) {
        p.set_axes(1622, each(&|a| a.after_interpolation_ms));
    }
    for (k, number) in [1620, 1621].into_iter().enumerate() {
        if m.axes.iter().any(|a| a.rapid_after_interpolation_ms[k] != 0.0) {
            p.set_axes(number, each(&|a| a.rapid_after_interpolation_ms[k]));
        }
    }
    let type_bits = match m.motion.after_interpolation {
        AfterInterpolation::Exponential => 0.0,
        AfterInterpolation::Linear => 1.0,
        AfterInterpolation::Bell => 2.0,
    };
    if type_bits != 0.0 {
        p.set_axes(1610, vec![type_bits; m.axes.len()]);
    }
    p.set_axes(1660, each(&|a| a.max_accel()));
    p.set_axes(1672, each(&|a| 1000.0 * a.max_accel() / a.max_jerk()));
    if m.motion.helical_feed_on_path {
        p.set(1403, 32.0);
    }
    if m.motion.nonlinear_rapid {
        p.set(1401, 0.0);
    }
    if m.motion.power_on_inch {
        p.set(0, 4.0);
    }
    if m.motion.commons_kept_at_reset {
        p.set(6001, 64.0);
    }
    if m.motion.cutter_startup_type_b || m.motion.cutter_startup_perpendicular {
        let bits = m.motion.cutter_startup_type_b as u8 | (m.motion.cutter_startup_perpendicular as u8) << 1;
        p.set(5003, bits as f64);
    }
    if m.motion.cutter_interference_avoidance {
        p.set_bits(19607, 32);
    }
    if m.five_axis.crc_codes_by_mechanism {
        p.set_bits(19607, 2);
    }
    look_ahead_params(&mut p, m)?;

    let (code, ra, rb) = reference_angles(direction(m.tool_axis));
    p.set(19697, code as f64);
    p.set(19698, real(ra));
    p.set(19699, real(rb));
    let t0 = reference_direction(code, ra, rb);
    let mut links: Vec<RotaryLink> = chain(m).into_iter().cloned().collect();
    if links.len() == 1 {
        links.insert(0, hypothetical_master(&links[0], t0));
    }
    let kind = match links.iter().map(|l| l.side).collect::<Vec<_>>()[..] {
        [] => 0,
        [Side::Head, Side::Head] => 2,
        [Side::Table, Side::Table] => 12,
        _ => 21,
    };
    p.set(19680, kind as f64);
    // The controlled point must be on the tool axis through the nose (No.19666).
    let nose = vec3(m.nose);
    let holder = -nose.dot(&t0);
    let on_axis = (nose + t0 * holder).iter().all(|x| x.abs() < 1e-9);
    if !on_axis {
        return Err(unrepresentable("FANUC", "the spindle nose must lie on the tool axis through X/Y/Z (No.19666)"));
    }
    let mut ia = 0;
    for (j, l) in links.iter().enumerate() {
        let base = 19681 + 5 * j as u32;
        if l.zero_offset != 0.0 {
            return Err(unrepresentable("FANUC", format!("axis {} has a zero offset", l.axis)));
        }
        let (code, tilt, flip) = direction_code(direction(l.direction)).ok_or_else(|| {
            unrepresentable("FANUC", format!("axis {} is not in a coordinate plane (No.19682)", l.axis))
        })?;
        let number = match l.fixed {
            Some(_) => {
                ia |= 1 << j;
                0
            }
            None => m.axis_index(l.axis as u8).map_or(0, |i| i + 1),
        };
        let left = (l.hand == Hand::Left) != flip;
        p.set(base, number as f64);
        p.set(base + 1, code as f64);
        p.set(base + 2, real(tilt));
        p.set(base + 3, left as u8 as f64);
        p.set(base + 4, real(l.fixed.unwrap_or(0.0)));
        let [lower, upper] = l.range.unwrap_or([0.0, 0.0]);
        p.set(19741 + 2 * j as u32, real(upper));
        p.set(19742 + 2 * j as u32, real(lower));
    }
    let f = &m.five_axis;
    let wkp = f.tcp_coordinates == TcpCoordinates::Workpiece;
    let npc = (f.singular_alarm as u32) << 3;
    p.set(19696, (ia | npc | (wkp as u32) << 5 | (f.rotary_feed as u32) << 6) as f64);
    for (number, value) in [
        (19738, f.singular_angle),
        (19739, f.singular_tolerance),
        (19751, f.rapid_deviation),
        (19752, f.cutting_deviation),
        (19632, f.cutting_point_distance),
        (19635, f.plane_change_angle),
        (19631, f.leading_edge_tolerance),
        (11262, f.cutting_point_singular_angle),
        (19636, f.avoidance_max_tool_angle),
    ] {
        if value != 0.0 {
            p.set(number, real(value));
        }
    }
    for (number, value) in [
        (19754, ((f.tcp_coordinates == TcpCoordinates::TableAtZero) as u32) << 5),
        (19604, f.posture_control as u32),
        (11221, f.multiple_planes as u32),
        (5400, ((f.plane_after_reset == PlaneAfterReset::Kept) as u32) << 2),
        (11200, f.tool_direction_compensation as u32),
        (
            19608,
            (f.crc_check_in_plane as u32) << 1
                | (f.display_workpiece as u32) << 2
                | (f.second_axis_first as u32) << 5
                | (f.mirror_direction as u32) << 6,
        ),
    ] {
        if value != 0 {
            p.set(number, value as f64);
        }
    }
    if !f.crc_variant.is_30i() {
        // Written whole, 0 too: its presence marks the list as a 16i's.
        p.set(19605, ((f.plane_change_check_off as u32) << 5) as f64);
        if f.non_movement_limit != 0.0 {
            p.set(19630, real(f.non_movement_limit));
        }
    }
    if f.deviation_clamp || f.crc_table_coordinates {
        p.set_bits(19746, (f.deviation_clamp as u32) << 6 | (f.crc_table_coordinates as u32) << 4);
    }
    if f.smooth_tcp || f.smooth_tolerance.is_some() || f.smooth_path_tolerance.is_some() {
        return Err(unrepresentable("FANUC", "STCP (Syntec Pr3051–3053, Pr407)"));
    }
    if f.plane_after_reset == PlaneAfterReset::KeptOverRestart {
        return Err(unrepresentable("FANUC", "a tilted working plane kept over a restart (Syntec Pr3014 = 2)"));
    }
    if f.plane_min_distance != 0.0 {
        p.set(11220, real(f.plane_min_distance));
    }
    if f.singular_tolerance_deg != 0.0 {
        p.set(11204, real(f.singular_tolerance_deg));
    }
    // G54.4: TOS = 0 written as `5006: 0` (absent: fivex's default, TOS = 1); the rest only
    // when not 0.
    if f.length_offset_by_motion {
        p.set(5006, 0.0);
    }
    for (number, value) in [(5412, f.wse_cycle_feed), (11202, f.wse_feed_clamp_pct), (11203, f.wse_rapid_clamp_pct)] {
        if value != 0.0 {
            p.set(number, real(value));
        }
    }
    if f.wse_display_wcs {
        p.set(3106, 64.0);
    }
    let zero = Vec3::zeros();
    let point = |k: usize| vec3(links[k].point);
    let (v1, v2, a, d) = match kind {
        2 => (point(1), point(0) - point(1), zero, zero),
        12 => (zero, zero, point(0), point(1) - point(0)),
        21 => (point(0), zero, point(1), zero),
        _ => (zero, zero, zero, zero),
    };
    manual_params(&mut p, m);
    cycle_params(&mut p, m);
    p.set(19666, real(holder));
    for (first, v) in [(19700, a), (19703, d), (19709, v1), (19712, v2)] {
        for (i, x) in v.iter().enumerate() {
            p.set(first + i as u32, real(*x));
        }
    }
    Ok(p)
}

/// No.19682 code and inclination of a unit direction, and whether it points the other way
/// (then the hand flips): coordinate axes 1–3; 4 in the XY plane at φ from +X toward +Y, 5 in
/// YZ from +Y toward +Z, 6 in ZX from +Z toward +X.
fn direction_code(u: Vec3) -> Option<(i64, f64, bool)> {
    const EPS: f64 = 1e-12;
    if let Some(k) = u.iter().position(|x| (x.abs() - 1.0).abs() < EPS) {
        return Some((k as i64 + 1, 0.0, u[k] < 0.0));
    }
    let plane = |zero: usize, cos: usize, sin: usize, code: i64| {
        (u[zero].abs() < EPS).then(|| (code, half_turn(u[sin].atan2(u[cos]).to_degrees()), false))
    };
    plane(2, 0, 1, 4).or_else(|| plane(0, 1, 2, 5)).or_else(|| plane(1, 2, 0, 6))
}

/// The hypothetical first axis that lets FANUC describe a single rotary axis (fixed at 0°): a
/// coordinate axis neither parallel to the real one nor, on a table, to the tool.
fn hypothetical_master(real: &RotaryLink, t0: Vec3) -> RotaryLink {
    let parallel = |a: Vec3, b: Vec3| a.cross(&b).norm() < 1e-9;
    let d = direction(real.direction);
    let code = (1..=3).find(|&c| !parallel(unit(c), d) && (real.side == Side::Head || !parallel(unit(c), t0)));
    let code = code.unwrap_or(1);
    let axis = ['A', 'B', 'C'].into_iter().find(|&c| c != real.axis).unwrap_or('A');
    RotaryLink {
        axis,
        direction: unit(code).into(),
        hand: if real.side == Side::Head { Hand::Right } else { Hand::Left },
        zero_offset: 0.0,
        fixed: Some(0.0),
        range: None,
        ..*real
    }
}
