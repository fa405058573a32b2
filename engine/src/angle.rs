//! Angles in degrees, as NC programs and machines give them.

/// `x` rounded half away from zero, for |x| < 2⁶³: by truncation, because `f64::round` (and
/// `floor`, `rem_euclid`) are library calls on baseline x86-64 and dominated the choice of a
/// rotary solution.
pub fn round(x: f64) -> i64 {
    (x + 0.5f64.copysign(x)) as i64
}

/// Distance (degrees) from `deg` to the nearest multiple of 360°.
pub fn distance_to_zero(deg: f64) -> f64 {
    (deg - 360.0 * round(deg * (1.0 / 360.0)) as f64).abs()
}

/// sin and cos of an angle in degrees, exact at multiples of 90° (so that a quarter turn maps
/// axes onto axes without rounding noise).
///
/// The angle is reduced in degrees to the nearest quarter turn plus a rest within ±45° (the
/// subtraction is exact), and only the rest goes to `sin`/`cos`: exact quarter turns, no
/// `fmod`, and the library's fast small-argument path — this is most of the cost of forward
/// kinematics.
pub fn sin_cos_deg(deg: f64) -> (f64, f64) {
    let q = round(deg * (1.0 / 90.0));
    let (s, c) = (deg - 90.0 * q as f64).to_radians().sin_cos();
    // `+ 0.0` turns −0.0 into 0.0, so that quarter turns print as plain zeros.
    match q.rem_euclid(4) {
        0 => (s + 0.0, c),
        1 => (c, -s + 0.0),
        2 => (-s + 0.0, -c),
        _ => (-c, s + 0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_turns_are_exact() {
        assert_eq!(sin_cos_deg(180.0), (0.0, -1.0));
        assert_eq!(sin_cos_deg(-90.0), (-1.0, 0.0));
        assert_eq!(sin_cos_deg(450.0), (1.0, 0.0));
        assert_eq!(sin_cos_deg(-360.0), (0.0, 1.0));
        assert!(sin_cos_deg(-180.0).0.is_sign_positive(), "no negative zero");
        let (s, c) = sin_cos_deg(30.0);
        assert!((s - 0.5).abs() < 1e-15 && (c - 3f64.sqrt() / 2.0).abs() < 1e-15);
    }

    #[test]
    fn rounding_and_distance_to_zero() {
        assert_eq!((round(2.5), round(-2.5), round(2.4999), round(-0.2)), (3, -3, 2, 0));
        for i in -5000..5000 {
            let x = i as f64 * 0.377;
            let r = x.rem_euclid(360.0);
            assert!((distance_to_zero(x) - r.min(360.0 - r)).abs() < 1e-9, "{x}");
        }
    }

    #[test]
    fn agrees_with_sin_and_cos_of_radians() {
        for i in -20_000..20_000 {
            let deg = i as f64 * 0.0731 + 0.003;
            let (s, c) = sin_cos_deg(deg);
            let r = deg.to_radians();
            assert!((s - r.sin()).abs() < 1e-14 && (c - r.cos()).abs() < 1e-14, "{deg}");
        }
    }
}
