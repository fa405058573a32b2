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

/// The largest whole number ≤ `x`, for |x| < 2⁶³ (by truncation; see [`round`]).
pub fn floor(x: f64) -> f64 {
    let t = x as i64 as f64;
    if t > x {
        t - 1.0
    } else {
        t
    }
}

/// The smallest whole number ≥ `x`, for |x| < 2⁶³.
pub fn ceil(x: f64) -> f64 {
    -floor(-x)
}

/// `deg` reduced to [0, 360) (what `rem_euclid(360.0)` gives, without its `fmod` call).
pub fn basic(deg: f64) -> f64 {
    let a = deg - 360.0 * floor(deg * (1.0 / 360.0));
    // The product can round up to a whole turn, or just below zero.
    if a >= 360.0 {
        a - 360.0
    } else if a < 0.0 {
        a + 360.0
    } else {
        a
    }
}

/// The travel of a rollover rotary axis at `from` (any number of turns) commanded to the
/// absolute angle `command`: the end angle is `command` modulo 360; with `shortest` the axis
/// takes the shorter way round (half a turn goes positive), otherwise the command's sign gives
/// the direction (FANUC No.1008 ROA with RAB = 0 / 1; Syntec Pr201~ types 1 / 2, spec SYN-30).
pub fn rollover_travel(from: f64, command: f64, shortest: bool) -> f64 {
    let ahead = basic(basic(command) - basic(from));
    if shortest {
        if ahead > 180.0 {
            ahead - 360.0
        } else {
            ahead
        }
    } else if command.is_sign_negative() {
        if ahead > 0.0 {
            ahead - 360.0
        } else {
            0.0
        }
    } else {
        ahead
    }
}

/// The travel of a rollover rotary axis at `from` (any number of turns) back to the machine
/// angle `reference` by a reference return (G28, G30, manual REF): less than one turn. A
/// rollover axis of FANUC's is a rotary axis of A type, whose machine coordinate is kept within
/// one turn, and its automatic reference return goes the way of the manual one without
/// exceeding a turn (FANUC 15i-B connection manual B-63783EN-1 §1.6.3, No.1006#1 ROS; Power Mate
/// i B-63172EN §7.4); that way is No.1006#5 ZMI, which fivex writes and reads as 0: positive.
/// With `shortest` the shorter way instead (half a turn positive: the Haas dialect,
/// `docs/conventions.md`, "Rollover axes and machine positions").
pub fn reference_travel(from: f64, reference: f64, shortest: bool) -> f64 {
    if shortest {
        return rollover_travel(from, reference, true);
    }
    let ahead = basic(reference - from);
    // Already there, but for the rounding of unwound positions: not a whole turn.
    if 360.0 - ahead < WHOLE_TURN_SLACK {
        0.0
    } else {
        ahead
    }
}

/// How close to a whole turn a reference return's travel is taken as none (degrees): far below
/// the least input increment (0.001°), far above the rounding of positions thousands of
/// degrees unwound.
const WHOLE_TURN_SLACK: f64 = 1e-6;

/// sin and cos of an angle in degrees, exact at multiples of 90° (so that a quarter turn maps
/// axes onto axes without rounding noise), and the same on every platform.
///
/// The angle is reduced in degrees to the nearest quarter turn plus a rest within ±45° (the
/// subtraction is exact); the rest goes to [`sin_cos_small`]. This is most of the cost of
/// forward kinematics.
pub fn sin_cos_deg(deg: f64) -> (f64, f64) {
    let q = round(deg * (1.0 / 90.0));
    let (s, c) = sin_cos_small((deg - 90.0 * q as f64).to_radians());
    // `+ 0.0` turns −0.0 into 0.0, so that quarter turns print as plain zeros.
    match q & 3 {
        0 => (s + 0.0, c),
        1 => (c, -s + 0.0),
        2 => (-s + 0.0, -c),
        _ => (-c, s + 0.0),
    }
}

/// sin and cos of |x| ≤ π/4 radians by their Taylor series: through x¹⁵ and x¹⁶ the first
/// omitted term is below 10⁻¹⁶ · 0.7 (half an ulp), so the results are within about an ulp of
/// the true values. Plain multiplications and additions: no library call, no branch, and
/// bit-identical on every platform (the library's `sin_cos` is not).
fn sin_cos_small(x: f64) -> (f64, f64) {
    // 1/n! for n = 2 … 16.
    const F: [f64; 15] = {
        let mut f = [0.0; 15];
        let mut fact = 1.0;
        let mut n = 2;
        while n <= 16 {
            fact *= n as f64;
            f[n - 2] = 1.0 / fact;
            n += 1;
        }
        f
    };
    let z = x * x;
    let sin_tail = F[1] - z * (F[3] - z * (F[5] - z * (F[7] - z * (F[9] - z * (F[11] - z * F[13])))));
    let cos_tail = F[0] - z * (F[2] - z * (F[4] - z * (F[6] - z * (F[8] - z * (F[10] - z * (F[12] - z * F[14]))))));
    (x - x * z * sin_tail, 1.0 - z * cos_tail)
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

    #[test]
    fn rollover_travel_follows_syntec_tv_40_and_fanuc_tv_13() {
        // Syntec TV-40, type 1 (shortest): C350 → C10 moves +20; C0 → C−90 moves −90.
        assert_eq!(rollover_travel(350.0, 10.0, true), 20.0);
        assert_eq!(rollover_travel(0.0, -90.0, true), -90.0);
        // Type 2 (sign is the direction): C0 → C90 +90; C0 → C−90 turns negative to 270.
        assert_eq!(rollover_travel(0.0, 90.0, false), 90.0);
        assert_eq!(rollover_travel(0.0, -90.0, false), -90.0);
        assert_eq!(rollover_travel(10.0, -90.0, false), -100.0);
        assert_eq!(rollover_travel(10.0, 20.0, false), 10.0);
        assert_eq!(rollover_travel(20.0, 10.0, false), 350.0);
        // FANUC TV-13: from A350 the member 10 is 20 ahead; many turns wound up count as none.
        assert_eq!(rollover_travel(350.0 + 720.0, 10.0, true), 20.0);
        // Half a turn goes positive; already there is no travel either way.
        assert_eq!(rollover_travel(0.0, 180.0, true), 180.0);
        assert_eq!((rollover_travel(90.0, 450.0, true), rollover_travel(90.0, -270.0, false)), (0.0, 0.0));
    }

    #[test]
    fn reference_travel_is_less_than_a_turn() {
        // From 3630 (ten turns and 30°) to 0: +330, not −3630.
        assert_eq!(reference_travel(3630.0, 0.0, false), 330.0);
        assert_eq!(reference_travel(-30.0, 0.0, false), 30.0);
        assert_eq!(reference_travel(-720.0, 0.0, false), 0.0);
        assert_eq!(reference_travel(100.0, 270.0, false), 170.0);
        // A position a rounding short of a whole number of turns is there already.
        assert_eq!(reference_travel(-720.0 + 1e-10, 0.0, false), 0.0);
        assert!(reference_travel(720.0 - 1e-10, 0.0, false) < 1e-9);
        // The shorter way: from 3630 back 30; from 950 (230) on 130.
        assert_eq!(reference_travel(3630.0, 0.0, true), -30.0);
        assert_eq!(reference_travel(950.0, 0.0, true), 130.0);
    }

    #[test]
    fn series_is_within_two_ulps_of_the_library() {
        let mut worst: f64 = 0.0;
        for i in -100_000..=100_000 {
            let x = i as f64 * (std::f64::consts::FRAC_PI_4 / 100_000.0);
            let (s, c) = sin_cos_small(x);
            worst = worst.max((s - x.sin()).abs()).max((c - x.cos()).abs());
        }
        assert!(worst <= 2.0 * f64::EPSILON, "worst {worst:e}");
    }

    #[test]
    fn floor_ceil_and_basic_angle() {
        for x in [-2.5, -2.0, -0.3, -0.0, 0.0, 0.7, 3.0, 1e15 + 0.5] {
            assert_eq!((floor(x), ceil(x)), (x.floor(), x.ceil()), "{x}");
        }
        for i in -5000..5000 {
            let x = i as f64 * 0.377;
            assert_eq!(basic(x), x.rem_euclid(360.0), "{x}");
        }
        assert_eq!((basic(-1e-20), basic(720.0), basic(-360.0)), (0.0, 0.0, 0.0));
    }
}
