//! FANUC's end-point change near a singular posture (spec `fanuc-tcp.md` TCP-30/31, M-9):
//! under TCP type 2 with tool posture control, a line whose tool posture passes closer to the
//! singular posture than No.19738 (`five_axis.singular_angle`) ends instead with the tool-side
//! axis mirrored about its singular angle and the workpiece-side axis at its start angle, so
//! the posture goes through the singular one instead of swinging the workpiece-side axis
//! round it. The decisions on the open points are in `docs/five-axis.md`.

use crate::alarm::AlarmId;
use crate::kin::{Kinematics, MachineKind, Vec3};
use crate::machine::FiveAxisOptions;

/// The angle between the tool direction and the singular line (both senses, Q-9), degrees in
/// [0, 90], at the start, at the end and at its nearest along the great circle from `v0` to
/// `v1` (the tool posture control path, M-7).
pub(super) fn approach(v0: Vec3, v1: Vec3, line: Vec3) -> [f64; 3] {
    let off = |c: f64| c.abs().min(1.0).acos().to_degrees();
    let (a, b) = (v0.dot(&line), v1.dot(&line));
    let mut best = a.abs().max(b.abs());
    // On the great circle v(θ) = cos θ·v0 + sin θ·w (θ in [0, Ω]), v·line = R cos(θ − φ): its
    // largest size inside the arc is at θ = φ or φ ± π.
    let omega = v0.dot(&v1).clamp(-1.0, 1.0).acos();
    if let Some(w) = (v1 - v0 * v0.dot(&v1)).try_normalize(1e-12) {
        let (p, q) = (a, w.dot(&line));
        let phi = q.atan2(p);
        for theta in [phi, phi + std::f64::consts::PI, phi - std::f64::consts::PI] {
            if (0.0..=omega).contains(&theta) {
                best = best.max(p.hypot(q));
            }
        }
    }
    [off(a), off(b), off(best)]
}

/// M-9 on the numbers (TV-06…TV-09): the tool-side end `tool_end` mirrored about the singular
/// angle `singular`, the workpiece-side axis back at `work_start`; refused (`Err` with the
/// deviation) when the commanded workpiece-side end `work_end` is more than `tolerance` from
/// `work_start` + 180° (taken round the circle: Q-8).
pub(super) fn mirrored(
    tool_end: f64,
    singular: f64,
    work_start: f64,
    work_end: f64,
    tolerance: f64,
) -> Result<(f64, f64), f64> {
    let deviation = crate::angle::distance_to_zero(work_end - work_start - 180.0);
    if deviation > tolerance + 1e-9 {
        return Err(deviation);
    }
    Ok((2.0 * singular - tool_end, work_start))
}

/// The end-point change for a type 2 line from `from` to `end` (machine positions; `end`'s
/// rotary axes are changed in place). `Ok(true)`: changed, the block then moves its rotary
/// axes in proportion (the workpiece-side axis stays, the tool-side one passes through its
/// singular angle); `Ok(false)`: unchanged; PS5421 when refused with NPC = 1.
pub(super) fn change_end(
    kin: &Kinematics,
    options: &FiveAxisOptions,
    from: &[f64],
    end: &mut [f64],
) -> Result<bool, AlarmId> {
    if options.singular_angle <= 0.0 {
        return Ok(false);
    }
    // The workpiece-side axis (its line is the singular posture) and the tool-side one.
    let (work, tool) = match kin.kind {
        MachineKind::HeadHead => (&kin.head[0], &kin.head[1]),
        MachineKind::TableTable => (&kin.table[1], &kin.table[0]),
        MachineKind::HeadTable => (&kin.table[0], &kin.head[0]),
        _ => return Ok(false),
    };
    let (Some(w), Some(t)) = (work.index, tool.index) else { return Ok(false) };
    let (v0, v1) = (kin.forward(from, 0.0).tool, kin.forward(end, 0.0).tool);
    // Equal or opposite directions: no posture control in the block (TCP-27), nothing to pass.
    if v0.cross(&v1).norm() < 1e-9 {
        return Ok(false);
    }
    let [at_start, at_end, nearest] = approach(v0, v1, work.direction);
    // Exactly singular at either end or on the way: no change (TCP-31). "Exactly" is within
    // 1e-4° (acos near 1 keeps about 1e-6° of rounding).
    const EXACT: f64 = 1e-4;
    if at_start < EXACT || at_end < EXACT || nearest < EXACT || nearest >= options.singular_angle {
        return Ok(false);
    }
    // The singular angles of the tool-side axis: where the tool lies along the line (either
    // sense); the one passed is taken as the member nearest the middle of its travel.
    let middle = 0.5 * (from[t] + end[t]);
    let mut singular: Option<f64> = None;
    for line in [work.direction, -work.direction] {
        for c in &kin.inverse(Vec3::zeros(), line, 0.0, from) {
            let s = c.pos[t] + 360.0 * ((middle - c.pos[t]) / 360.0).round();
            if singular.is_none_or(|best| (s - middle).abs() < (best - middle).abs()) {
                singular = Some(s);
            }
        }
    }
    let Some(singular) = singular else { return Ok(false) };
    match mirrored(end[t], singular, from[w], end[w], options.singular_tolerance) {
        Ok((tool_end, work_end)) => {
            (end[t], end[w]) = (tool_end, work_end);
            Ok(true)
        }
        Err(_) if options.singular_alarm => Err(AlarmId::IllegalCommandInTcp),
        Err(_) => Ok(false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tv06_to_tv09_mirror_and_workpiece_side_check() {
        // TV-06/07/08: tool side 60 about the singular 20 → −20; workpiece side 30 → its
        // start −150; |30 − (−150 + 180)| = 0 is within any tolerance.
        assert_eq!(mirrored(60.0, 20.0, -150.0, 30.0, 0.0), Ok((-20.0, -150.0)));
        // TV-09: start −100, end 30: |30 − 80| = 50 > 10 → refused.
        assert_eq!(mirrored(60.0, 20.0, -100.0, 30.0, 10.0), Err(50.0));
        assert_eq!(mirrored(60.0, 20.0, -100.0, 30.0, 50.0), Ok((-20.0, -100.0)));
        // Round the circle (decision Q-8): 30 vs −150 + 180 + 360.
        assert_eq!(mirrored(60.0, 20.0, -150.0, 390.0, 0.0), Ok((-20.0, -150.0)));
    }

    #[test]
    fn approach_finds_the_nearest_point_of_the_great_circle() {
        let z = Vec3::z();
        let s = 10f64.to_radians();
        let v0 = Vec3::new(s.sin(), 0.0, s.cos());
        let v1 = Vec3::new(0.0, s.sin(), s.cos());
        let [a, b, m] = approach(v0, v1, z);
        assert!((a - 10.0).abs() < 1e-9 && (b - 10.0).abs() < 1e-9);
        // Half-way: (sin10, sin10, ·)/|·| at 45° azimuth.
        let mid = (v0 + v1).normalize();
        assert!((m - mid.z.acos().to_degrees()).abs() < 1e-9, "{m}");
        // Through the line: 0. Away from it: the nearer end.
        assert!(approach(v0, Vec3::new(-s.sin(), 0.0, s.cos()), z)[2] < 1e-9);
        let far = approach(Vec3::x(), Vec3::y(), z);
        assert!((far[2] - 90.0).abs() < 1e-9);
        // The opposite sense counts too.
        assert!(approach(-v0, Vec3::new(s.sin(), 0.0, -s.cos()), z)[2] < 1e-9);
    }
}
