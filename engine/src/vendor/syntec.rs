//! Syntec parameters (syntec.md §1). Angles and lengths are whole BLU (0.001° / 0.001 mm).
//!
//! Per axis i = 0, 1, … (consecutive numbers): Pr21+i servo channel (0: the axis is not set
//! up), Pr201+i axis type, Pr321+i axis name, Pr401+i acceleration time, Pr421+i jerk time,
//! Pr461+i rapid rate, Pr2401+i / Pr2421+i stroke. The 5-axis set: Pr3001 type, Pr3002–3004 tool
//! direction, Pr3005–3008 rotary axes, Pr3009–3012 ranges, Pr3013 holder offset, Pr3051–3053 and Pr407 STCP, Pr3015–3020
//! orientation and zero errors, Pr3021–3046 mechanism-chain vectors; Pr3201 machine type.
//!
//! The seed names Pr21~, Pr201~ and Pr321~ without their value tables, and no rates or strokes:
//! the value codes and Pr401/421/461/2401/2421 are fivex's reading (`docs/machine-config.md`).

use super::Params;
use super::{chain, direction, reference_angles, reference_direction, unit, unrepresentable};
use crate::alarm::AlarmId;
use crate::kin::{vec3, Vec3};
use crate::machine::{
    Axis, AxisKind, ConfigError, FiveAxisOptions, Hand, MachineConfig, PlaneAfterReset, RotaryLink, Side,
    TcpCoordinates,
};

/// Pr321~ name codes 1…9.
const NAMES: [char; 9] = ['X', 'Y', 'Z', 'A', 'B', 'C', 'U', 'V', 'W'];
/// At most this many axes are read.
const SLOTS: u32 = 16;

/// BLU (0.001 mm or °) → mm or °.
fn from_blu(x: f64) -> f64 {
    x / 1000.0
}

/// mm or ° → whole BLU.
fn blu(x: f64) -> f64 {
    let r = (x * 1000.0).round();
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

fn axis_error(detail: String) -> ConfigError {
    ConfigError::alarm(AlarmId::AxisSetting, detail)
}

pub fn machine(name: &str, p: &Params) -> Result<MachineConfig, ConfigError> {
    let mut axes = Vec::new();
    for i in 0..SLOTS {
        let code = p.code(321 + i, 0, NAMES.len() as i64)?;
        if code == 0 {
            break;
        }
        let letter = NAMES[code as usize - 1];
        if p.code(21 + i, 0, 64)? == 0 {
            return Err(axis_error(format!("axis {letter}: Pr{} (servo channel) is not set", 21 + i)));
        }
        let kind = p.code(201 + i, 0, 3)?;
        let rapid = p.get(461 + i)?;
        let (accel_ms, jerk_ms) = (p.code(401 + i, 0, 60_000)?, p.code(421 + i, 0, 60_000)?);
        let accel = (accel_ms > 0).then(|| rapid / 60.0 / (accel_ms as f64 / 1000.0));
        let jerk = accel.filter(|_| jerk_ms > 0).map(|a| a / (jerk_ms as f64 / 1000.0));
        let (plus, minus) = (p.get(2401 + i)?, p.get(2421 + i)?);
        axes.push(Axis {
            accel,
            jerk,
            stroke: (plus != 0.0 || minus != 0.0).then_some([from_blu(minus), from_blu(plus)]),
            rollover: kind == 1 || kind == 2,
            shortest: kind == 1,
            ..Axis::new(letter, if kind == 0 { AxisKind::Linear } else { AxisKind::Rotary }, rapid)
        });
    }
    if axes.is_empty() {
        return Err(ConfigError::invalid("Pr321~ (axis names) names no axis"));
    }
    let kind = p.code(3001, 0, 5)?;
    let machine_type = p.get(3201)?;
    if kind != 0 && !(machine_type.fract() == 0.0 && (0.0..=3.0).contains(&machine_type)) {
        let detail = "Pr3201 (machine type) must be 0 to 3 with a 5-axis set";
        return Err(ConfigError::alarm(AlarmId::MechanismConflict, detail));
    }
    let tool_code = p.code(3002, 0, 3)?;
    if kind != 0 && tool_code == 0 {
        return Err(ConfigError::alarm(AlarmId::ToolDirectionSetting, "Pr3002 (tool direction) is not set"));
    }
    let (ra, rb) = (p.code(3003, 0, 360_000)?, p.code(3004, 0, 360_000)?);
    let tool_axis = match tool_code {
        0 => unit(3),
        c => reference_direction(c, from_blu(ra as f64), from_blu(rb as f64)),
    };
    let sides: &[Side] = match kind {
        0 => &[],
        1 => &[Side::Head, Side::Head],
        2 => &[Side::Table, Side::Table],
        3 => &[Side::Head, Side::Table],
        4 => &[Side::Head],
        _ => &[Side::Table],
    };
    let mut rotary = Vec::new();
    for (j, side) in sides.iter().enumerate() {
        let j = j as u32;
        let code = p.code(3005 + j, 0, 3)?;
        let hand = p.code(3007 + j, 0, 2)?;
        if code == 0 || hand == 0 {
            return Err(axis_error(format!("Pr{} / Pr{} (rotation axis, direction) are not set", 3005 + j, 3007 + j)));
        }
        let letter = ['A', 'B', 'C'][code as usize - 1];
        if rotary.iter().any(|l: &RotaryLink| l.axis == letter) {
            return Err(axis_error(format!("Pr3005 and Pr3006 both name axis {letter}")));
        }
        if !axes.iter().any(|a| a.name == letter && a.kind == AxisKind::Rotary) {
            return Err(axis_error(format!(
                "Pr{} = {code} names axis {letter}, which Pr321~/Pr201~ do not set up as rotary",
                3005 + j
            )));
        }
        // Orientation errors (§1.5): the component named after the axis is its zero offset, the
        // other two tilt it about the other coordinate axes.
        let errors = p.get3(3015 + 3 * j)?;
        for (k, e) in errors.iter().enumerate() {
            super::params::whole(3015 + 3 * j + k as u32, *e, -360_000, 360_000)?;
        }
        let [a, b, c] = errors.map(from_blu);
        let tan = |deg: f64| {
            if deg.abs() >= 90.0 {
                Err(axis_error(format!("Pr{}~{}: an orientation error of 90° or more", 3015 + 3 * j, 3017 + 3 * j)))
            } else {
                Ok(deg.to_radians().tan())
            }
        };
        let (tilted, zero_offset) = match code {
            1 => ([1.0, tan(c)?, -tan(b)?], a),
            2 => ([-tan(c)?, 1.0, tan(a)?], b),
            _ => ([tan(b)?, -tan(a)?, 1.0], c),
        };
        let (start, end) = (p.code(3009 + 2 * j, 0, 360_000)?, p.code(3010 + 2 * j, 0, 360_000)?);
        rotary.push(RotaryLink {
            axis: letter,
            side: *side,
            direction: direction(tilted).into(),
            hand: if hand == 1 { Hand::Right } else { Hand::Left },
            point: [0.0; 3],
            zero_offset,
            fixed: None,
            // [start, end] read in the positive sense, as low ≤ high: Area 1 (290° → 70°) is
            // [290, 430].
            range: (start != end).then(|| {
                let (start, end) = (from_blu(start as f64), from_blu(end as f64));
                [start, start + (end - start).rem_euclid(360.0)]
            }),
        });
    }
    // Mechanism-chain vectors (§1.6, §1.7): X/Y/Z are the spindle nose at zero angles; the tool
    // holder point is Pr3013 above it, a (Pr3021) leads from there to the slave, d (Pr3024) on to
    // the master; e (Pr3041) from the holder to a single head axis. m (Pr3034) is a point on the
    // table master, b (Pr3031) leads to the slave; f (Pr3044) is a point on a mixed table axis.
    let vector = |first: u32| -> Result<Vec3, ConfigError> {
        let v = p.get3(first)?;
        for (k, x) in v.iter().enumerate() {
            super::params::whole(first + k as u32, *x, -999_999_999, 999_999_999)?;
        }
        Ok(vec3(v.map(from_blu)))
    };
    let holder = if matches!(kind, 1 | 3 | 4) { from_blu(p.code(3013, 0, 999_999_999)? as f64) } else { 0.0 };
    let grip = tool_axis * holder;
    // Master point first.
    let points = match kind {
        1 => {
            let a = vector(3021)? + grip;
            vec![a + vector(3024)?, a]
        }
        2 => {
            let m = vector(3034)?;
            vec![m, m + vector(3031)?]
        }
        3 => vec![vector(3041)? + grip, vector(3044)?],
        4 => vec![vector(3041)? + grip],
        5 => vec![vector(3034)?],
        _ => vec![],
    };
    for (link, point) in rotary.iter_mut().zip(points) {
        link.point = point.into();
    }
    Ok(MachineConfig {
        name: name.to_string(),
        axes,
        rotary,
        tool_axis: tool_axis.into(),
        nose: [0.0; 3],
        holder,
        sub_chains: Vec::new(),
        chains: Vec::new(),
        motion: Default::default(),
        five_axis: FiveAxisOptions {
            // Pr3054 = 1 tool-vector interpolation, Pr3055 = 1 table coordinates at the rotary
            // axes' work zero.
            posture_control: p.get(3054)? == 1.0,
            tcp_coordinates: if p.get(3055)? == 1.0 {
                TcpCoordinates::TableAtZero
            } else {
                TcpCoordinates::TableAtStart
            },
            // Pr3014: 0 the plane ends at reset, 1 kept through reset, 2 also through a restart.
            plane_after_reset: match p.code(3014, 0, 2)? {
                0 => PlaneAfterReset::Cancelled,
                1 => PlaneAfterReset::Kept,
                _ => PlaneAfterReset::KeptOverRestart,
            },
            // Pr3051 STCP without L; Pr3052/3053 its rotary tolerances, 0.001° (absent: 500).
            smooth_tcp: p.code(3051, 0, 1)? == 1,
            smooth_tolerance: if p.0.contains_key(&3052) || p.0.contains_key(&3053) {
                let tolerance = |n: u32| -> Result<f64, ConfigError> {
                    Ok(from_blu(if p.0.contains_key(&n) { p.code(n, 0, 360_000)? as f64 } else { 500.0 }))
                };
                Some([tolerance(3052)?, tolerance(3053)?])
            } else {
                None
            },
            // Pr407, µm (STCP's tip path tolerance; absent: 3).
            smooth_path_tolerance: if p.0.contains_key(&407) {
                Some(p.code(407, 2, 20)? as f64 / 1000.0)
            } else {
                None
            },
            ..FiveAxisOptions::default()
        },
        // Syntec has no parameters for the 5-axis manual feeds (its manual RTCP is the PLC
        // registers R518/R519, the controller's panel): they are not carried.
        manual: Default::default(),
        cycles: Default::default(),
    })
}

pub fn params(m: &MachineConfig) -> Result<Params, ConfigError> {
    if m.cycles != Default::default() {
        // The Syntec sources at hand give no parameter numbers for the canned cycles.
        return Err(unrepresentable("Syntec", "canned cycle settings other than the defaults"));
    }
    // Spec Q-22: the manual gives only the type parameters of sets 2–4 (Pr3101, Pr5501,
    // Pr5601), not the numbers of their vectors; sub-chains have none at all.
    if !m.chains.is_empty() || !m.sub_chains.is_empty() {
        return Err(unrepresentable(
            "Syntec",
            "mechanism-chain sets 2–4 and sub-chains (their parameter numbers are not in the manual)",
        ));
    }
    let mut p = Params::default();
    if m.axes.len() > SLOTS as usize {
        return Err(unrepresentable("Syntec", format!("more than {SLOTS} axes")));
    }
    for (i, a) in m.axes.iter().enumerate() {
        let i = i as u32;
        let code = NAMES.iter().position(|&c| c == a.name).map_or(0, |c| c + 1);
        let kind = match (a.kind, a.rollover, a.shortest) {
            (AxisKind::Linear, ..) => 0,
            (_, true, true) => 1,
            (_, true, false) => 2,
            _ => 3,
        };
        p.set(21 + i, (i + 1) as f64);
        p.set(201 + i, kind as f64);
        p.set(321 + i, code as f64);
        p.set(461 + i, a.rapid);
        p.set(401 + i, (1000.0 * a.rapid / 60.0 / a.max_accel()).round());
        p.set(421 + i, (1000.0 * a.max_accel() / a.max_jerk()).round());
        let [minus, plus] = a.stroke.unwrap_or([0.0, 0.0]);
        p.set(2401 + i, blu(plus));
        p.set(2421 + i, blu(minus));
    }
    let (code, ra, rb) = reference_angles(direction(m.tool_axis));
    p.set(3002, code as f64);
    p.set(3003, blu(ra));
    p.set(3004, blu(rb.rem_euclid(360.0)) % 360_000.0);
    let t0 = reference_direction(code, from_blu(p.get(3003)?), from_blu(p.get(3004)?));
    if m.nose.iter().any(|x| x.abs() > 1e-9) {
        return Err(unrepresentable("Syntec", "machine X/Y/Z must be the spindle nose at zero angles (nose 0)"));
    }
    // A hypothetical axis that stays at 0° is no axis at all; other fixed angles Syntec cannot set.
    let mut links: Vec<&RotaryLink> = chain(m);
    if let Some(l) = links.iter().find(|l| l.fixed.is_some_and(|f| (f + l.zero_offset).rem_euclid(360.0) != 0.0)) {
        return Err(unrepresentable("Syntec", format!("hypothetical axis {} at a fixed angle", l.axis)));
    }
    links.retain(|l| l.fixed.is_none());
    let sides: Vec<Side> = links.iter().map(|l| l.side).collect();
    let kind = match sides[..] {
        [] => 0,
        [Side::Head, Side::Head] => 1,
        [Side::Table, Side::Table] => 2,
        [Side::Head, Side::Table] => 3,
        [Side::Head] => 4,
        _ => 5,
    };
    p.set(3001, kind as f64);
    p.set(3201, 0.0);
    for (j, l) in links.iter().enumerate() {
        let j = j as u32;
        let code = match l.axis {
            'A' => 1,
            'B' => 2,
            _ => 3,
        };
        // Point the axis along its coordinate axis (flipping the hand if it points the other way),
        // then read the tilts back as the §1.5 error angles.
        let mut u = direction(l.direction);
        let mut hand = l.hand;
        let along = u[code - 1];
        if along.abs() < 1e-9 {
            return Err(unrepresentable(
                "Syntec",
                format!("axis {} does not turn about {}", l.axis, ["X", "Y", "Z"][code - 1]),
            ));
        }
        if along < 0.0 {
            u = -u;
            hand = if hand == Hand::Right { Hand::Left } else { Hand::Right };
        }
        let deg = |x: f64| x.atan().to_degrees();
        let [a, b, c] = match code {
            1 => [l.zero_offset, deg(-u[2] / u[0]), deg(u[1] / u[0])],
            2 => [deg(u[2] / u[1]), l.zero_offset, deg(-u[0] / u[1])],
            _ => [deg(-u[1] / u[2]), deg(u[0] / u[2]), l.zero_offset],
        };
        p.set(3005 + j, code as f64);
        p.set(3007 + j, if hand == Hand::Right { 1.0 } else { 2.0 });
        for (k, e) in [a, b, c].into_iter().enumerate() {
            p.set(3015 + 3 * j + k as u32, blu(e));
        }
        let (start, end) = match l.range {
            Some([lo, hi]) => (blu(lo.rem_euclid(360.0)) % 360_000.0, blu(hi.rem_euclid(360.0)) % 360_000.0),
            None => (0.0, 0.0),
        };
        p.set(3009 + 2 * j, start);
        p.set(3010 + 2 * j, end);
    }
    let holder = if matches!(kind, 1 | 3 | 4) { m.holder } else { 0.0 };
    if holder < 0.0 {
        return Err(unrepresentable("Syntec", "a negative tool holder offset (Pr3013)"));
    }
    let o = &m.motion;
    if o.power_on_inch
        || o.helical_feed_on_path
        || o.nonlinear_rapid
        || o.look_ahead_by_command
        || o.no_feed_look_ahead
        || o.no_rapid_look_ahead
        || o.cutter_startup_type_b
        || o.cutter_startup_perpendicular
        || o.cutter_interference_avoidance
        || o.commons_kept_at_reset
        || o.after_interpolation != Default::default()
        || m.axes.iter().any(|a| a.after_interpolation_ms != 0.0 || a.rapid_after_interpolation_ms != [0.0; 2])
    {
        // (The Syntec seed names no parameter for these: a list without them would drop them.)
        return Err(unrepresentable(
            "Syntec",
            "inch at power on (INI), HTG, LRP, the look-ahead settings and cutter compensation start-up types B \
             and C (SUP, SUV), interference avoidance (CAV), #100–#199 kept at reset (CCV) and acceleration/deceleration \
             after interpolation (No.1610, No.1620–1622) are FANUC settings",
        ));
    }
    p.set(3013, blu(holder));
    let f = &m.five_axis;
    if f.tcp_coordinates == TcpCoordinates::Workpiece
        || f.rotary_feed
        || f.second_axis_first
        || f.multiple_planes
        || f.plane_min_distance != 0.0
    {
        return Err(unrepresentable(
            "Syntec",
            "workpiece TCP coordinates, RFC, PRI, MTW and No.11220 are FANUC settings",
        ));
    }
    let persistence = match f.plane_after_reset {
        PlaneAfterReset::Cancelled => 0.0,
        PlaneAfterReset::Kept => 1.0,
        PlaneAfterReset::KeptOverRestart => 2.0,
    };
    if persistence != 0.0 {
        p.set(3014, persistence);
    }
    let wse = f.length_offset_by_motion
        || f.wse_cycle_feed != 0.0
        || f.wse_feed_clamp_pct != 0.0
        || f.wse_rapid_clamp_pct != 0.0
        || f.wse_display_wcs;
    if f.tool_direction_compensation || f.singular_tolerance_deg != 0.0 || wse {
        return Err(unrepresentable(
            "Syntec",
            "G54.4 settings (RCM, No.11202–11204, TOS, No.5412, DAK) are FANUC settings",
        ));
    }
    let singular = f.singular_angle != 0.0 || f.singular_tolerance != 0.0 || f.singular_alarm;
    let clamp = f.deviation_clamp || f.rapid_deviation != 0.0 || f.cutting_deviation != 0.0;
    let compensation = f.cutting_point_distance != 0.0
        || f.plane_change_angle != 0.0
        || f.leading_edge_tolerance != 0.0
        || f.cutting_point_singular_angle != 0.0
        || f.avoidance_max_tool_angle != 0.0
        || f.crc_check_in_plane
        || !f.crc_variant.is_30i()
        || f.plane_change_check_off
        || f.non_movement_limit != 0.0;
    if singular
        || clamp
        || f.mirror_direction
        || f.display_workpiece
        || compensation
        || f.crc_table_coordinates
        || f.crc_codes_by_mechanism
    {
        return Err(unrepresentable(
            "Syntec",
            "No.19738/19739/NPC, MIR, DET, CRS, TBP, SPG, NI5, No.19631/19632/19635/19636/11262 and the 16i variant \
             (No.19605#5 NIC, No.19630) are FANUC settings",
        ));
    }
    if m.axes.iter().any(|a| a.smoothing_tolerance != 0.0) {
        return Err(unrepresentable("Syntec", "No.19587 (nano smoothing's rotary tolerance) is a FANUC setting"));
    }
    if f.posture_control {
        p.set(3054, 1.0);
    }
    if f.tcp_coordinates == TcpCoordinates::TableAtZero {
        p.set(3055, 1.0);
    }
    if f.smooth_tcp {
        p.set(3051, 1.0);
    }
    if let Some([master, slave]) = f.smooth_tolerance {
        p.set(3052, blu(master));
        p.set(3053, blu(slave));
    }
    if let Some(t) = f.smooth_path_tolerance {
        let um = t * 1000.0;
        if (um - um.round()).abs() > 1e-9 {
            return Err(unrepresentable("Syntec", "Pr407 holds whole micrometres"));
        }
        p.set(407, um.round());
    }
    let grip = t0 * from_blu(p.get(3013)?);
    let point = |k: usize| vec3(links[k].point);
    let vectors = match kind {
        1 => vec![(3021, point(1) - grip), (3024, point(0) - point(1))],
        2 => vec![(3034, point(0)), (3031, point(1) - point(0))],
        3 => vec![(3041, point(0) - grip), (3044, point(1))],
        4 => vec![(3041, point(0) - grip)],
        5 => vec![(3034, point(0))],
        _ => vec![],
    };
    for first in [3021, 3024, 3031, 3034, 3041, 3044] {
        let v = vectors.iter().find(|(f, _)| *f == first).map_or(Vec3::zeros(), |(_, v)| *v);
        for (k, x) in v.iter().enumerate() {
            p.set(first + k as u32, blu(*x));
        }
    }
    Ok(p)
}
