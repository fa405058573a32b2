//! Workpiece setting error compensation (FANUC G54.4) geometry: the error data sets, the rigid
//! transform from the workpiece setting coordinate system (WSCS) to the workpiece coordinate
//! system (WCS), and the conversion of a set measured with the table turned to table position 0
//! (spec `fanuc-twp-wsec-manual-params.md` §2.13, WSE-02…WSE-04, WSE-08). Pure geometry: the
//! interpreter (`interp/wse.rs`) decides when a set acts and how positions follow it.
//!
//! Conventions (the extract's engine defaults, `docs/five-axis.md`): Δa, Δb, Δc turn about the
//! fixed WCS axes X, then Y, then Z, right-handed (OQ-10, OQ-11): `R_e = Rz(Δc)·Ry(Δb)·Rx(Δa)`,
//! and a WSCS point `p_s` is at `p_w = R_e·p_s + Δ` in the WCS.

use crate::geom::Rigid;
use crate::kin::{axis_rotation, Vec3};
use nalgebra::Matrix3;

/// No.00 (COMMON) and No.01…No.07.
pub const SETS: usize = 8;
/// The first macro variable of the sets: `#26000 + 10·n + k`.
pub const FIRST_VARIABLE: u32 = 26000;

/// One set of error data as entered (WSE-02): the WSCS origin in the WCS (mm), the rotation
/// errors about X, Y, Z (degrees; always 0 in COMMON) and the table rotary axes' machine
/// positions at the time of measurement (master / only table axis, slave table axis).
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ErrorSet {
    pub shift: [f64; 3],
    pub rotation: [f64; 3],
    pub table: [f64; 2],
}

/// The eight sets, index 0 = COMMON.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SettingErrors {
    pub sets: [ErrorSet; SETS],
}

impl SettingErrors {
    /// The value behind macro variable `number` (#26000…#26077, WSE-08); `None` when the
    /// variable does not exist (outside the range, k = 8/9, or COMMON's Δa/Δb/Δc #26003–#26005).
    pub fn variable(&self, number: u32) -> Option<f64> {
        let (n, k) = split(number)?;
        let s = &self.sets[n];
        Some(match k {
            0..=2 => s.shift[k],
            3..=5 => s.rotation[k - 3],
            _ => s.table[k - 6],
        })
    }

    /// The storage of macro variable `number`, as [`SettingErrors::variable`].
    pub fn variable_mut(&mut self, number: u32) -> Option<&mut f64> {
        let (n, k) = split(number)?;
        let s = &mut self.sets[n];
        Some(match k {
            0..=2 => &mut s.shift[k],
            3..=5 => &mut s.rotation[k - 3],
            _ => &mut s.table[k - 6],
        })
    }
}

/// Whether macro variable `number` is a shift Δx, Δy, Δz of a set (a length; the others are
/// angles).
pub fn is_shift_variable(number: u32) -> bool {
    matches!(split(number), Some((_, 0..=2)))
}

/// Set number and item of a variable that exists.
fn split(number: u32) -> Option<(usize, usize)> {
    let i = number.checked_sub(FIRST_VARIABLE)?;
    let (n, k) = ((i / 10) as usize, (i % 10) as usize);
    let exists = n < SETS && k <= 7 && !(n == 0 && (3..=5).contains(&k));
    exists.then_some((n, k))
}

/// `R_e = Rz(c)·Ry(b)·Rx(a)` (degrees, fixed axes, right-handed).
pub fn rotation([a, b, c]: [f64; 3]) -> Matrix3<f64> {
    axis_rotation(2, c) * axis_rotation(1, b) * axis_rotation(0, a)
}

/// The angles `[a, b, c]` of [`rotation`] back from a matrix (b in [−90°, 90°]).
pub fn angles(r: &Matrix3<f64>) -> [f64; 3] {
    let b = (-r[(2, 0)]).clamp(-1.0, 1.0).asin();
    let (a, c) = if b.cos() > 1e-12 {
        (r[(2, 1)].atan2(r[(2, 2)]), r[(1, 0)].atan2(r[(0, 0)]))
    } else {
        // Gimbal lock: only a ∓ c is defined; put it all in a.
        ((-r[(1, 2)]).atan2(r[(1, 1)]), 0.0)
    };
    [a.to_degrees(), b.to_degrees(), c.to_degrees()]
}

/// The WSCS as a frame in the WCS: `p_w = R_e·p_s + Δ`.
pub fn frame(shift: [f64; 3], rot: [f64; 3]) -> Rigid {
    Rigid { r: rotation(rot), o: Vec3::from(shift) }
}

/// The inverse rigid motion of `f`.
pub fn inverse(f: &Rigid) -> Rigid {
    let rt = f.r.transpose();
    Rigid { r: rt, o: -(rt * f.o) }
}

/// An error `e` measured with the table turned, expressed at table position 0 (§2.13.3):
/// `E_0 = M⁻¹ ∘ E_m ∘ M`, where `table` (M) carries an ideal workpiece point's WCS
/// coordinates at table position 0 to its WCS coordinates at the measuring position. The actual
/// workpiece was the ideal one turned by the table and then displaced by `e`; turning the table
/// back gives the displacement at position 0.
pub fn at_table_zero(e: &Rigid, table: &Rigid) -> Rigid {
    inverse(table).then(e).then(table)
}

/// The error in effect for set n (WSE-03/04, §2.13.2): translations of COMMON and set n added,
/// the rotation of set n; both already at table position 0.
pub fn effective(common: &Rigid, set: &Rigid) -> Rigid {
    Rigid { r: set.r, o: common.o + set.o }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variables_map_sets_and_items() {
        let mut e = SettingErrors::default();
        *e.variable_mut(26013).unwrap() = 1.5;
        *e.variable_mut(26077).unwrap() = -30.0;
        *e.variable_mut(26002).unwrap() = 4.0;
        assert_eq!(e.sets[1].rotation[0], 1.5);
        assert_eq!(e.sets[7].table[1], -30.0);
        assert_eq!(e.sets[0].shift[2], 4.0);
        for missing in [26003, 26004, 26005, 26008, 26009, 26078, 26080, 25999] {
            assert!(e.variable(missing).is_none(), "#{missing}");
        }
    }

    #[test]
    fn angles_invert_rotation() {
        for rot in [[1.5, -2.0, 20.0], [0.0, 0.0, -20.0], [10.0, 30.0, -170.0]] {
            let back = angles(&rotation(rot));
            for k in 0..3 {
                assert!((back[k] - rot[k]).abs() < 1e-9, "{rot:?} → {back:?}");
            }
        }
    }

    #[test]
    fn conjugation_by_a_turn_about_z_rotates_the_shift() {
        // M = Rz(−90°) (a left-hand C table at C = 90): Δ_0 = Rz(90°)·Δ_m, Δc unchanged.
        let m = Rigid { r: axis_rotation(2, -90.0), o: Vec3::zeros() };
        let e0 = at_table_zero(&frame([5.0, 0.0, 0.0], [0.0, 0.0, 2.0]), &m);
        assert!((e0.o - Vec3::new(0.0, 5.0, 0.0)).norm() < 1e-12);
        assert!((angles(&e0.r)[2] - 2.0).abs() < 1e-12);
    }
}
