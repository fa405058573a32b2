//! The controller's calendar clock, `#3011` (date, YYYYMMDD) and `#3012` (time, HHMMSS).
//!
//! The engine has no wall clock: the host tells the interpreter the local time once (at a cycle
//! start, `Interpreter::set_wall_clock`), and the clock then runs with simulated time, so a
//! program that reads `#3012` twice sees the time its own motion took, and a run is repeatable
//! from the same start. Without a host clock (`fivex run`) both read 0.

/// The local wall clock at an instant of simulated time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct WallClock {
    /// Local time, seconds since 1970-01-01 00:00 (Unix time plus the UTC offset).
    pub local_s: f64,
    /// The interpreter's simulated clock at that instant.
    pub at_clock_s: f64,
}

impl WallClock {
    /// `#3011` and `#3012` at simulated time `clock_s`.
    pub fn read(&self, clock_s: f64) -> (f64, f64) {
        let t = (self.local_s + (clock_s - self.at_clock_s)).floor() as i64;
        let (days, secs) = (t.div_euclid(86_400), t.rem_euclid(86_400));
        let (y, m, d) = civil_from_days(days);
        let (h, min, s) = (secs / 3600, secs / 60 % 60, secs % 60);
        ((y * 10_000 + m * 100 + d) as f64, (h * 10_000 + min * 100 + s) as f64)
    }
}

/// The proleptic Gregorian date of a day counted from 1970-01-01 (H. Hinnant's
/// `civil_from_days`, public domain): March-based years make February the last month, so leap
/// days need no special case.
fn civil_from_days(z: i64) -> (i64, i64, i64) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_across_month_year_and_leap_day() {
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
        // 2000-02-29 (a leap day of a century divisible by 400) is day 11016.
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(11_017), (2000, 3, 1));
        // 2100 is not a leap year: 2100-02-28 is followed by 2100-03-01 (days 47540, 47541).
        assert_eq!(civil_from_days(47_540), (2100, 2, 28));
        assert_eq!(civil_from_days(47_541), (2100, 3, 1));
    }

    #[test]
    fn the_clock_runs_with_simulated_time_over_midnight() {
        // 2026-12-31 23:59:58 local, given when the interpreter's clock stood at 100 s.
        let clock = WallClock { local_s: 1_798_761_598.0, at_clock_s: 100.0 };
        assert_eq!(clock.read(100.0), (20_261_231.0, 235_958.0));
        assert_eq!(clock.read(101.9), (20_261_231.0, 235_959.0));
        assert_eq!(clock.read(102.0), (20_270_101.0, 0.0));
        assert_eq!(clock.read(102.0 + 3_723.0), (20_270_101.0, 10_203.0));
    }
}
