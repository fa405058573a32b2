//! Acceleration/deceleration *after* interpolation (FANUC No.1610 type, No.1622 time constant
//! per axis): where look-ahead is off, the control interpolates at the commanded feed at once
//! and each axis's interpolated positions pass through a filter before the servo, which
//! changes the path (corners rounded, circles shrunk: `docs/motion.md`, "Without look-ahead").
//! The filter runs on the interpolation period of the control, [`TICK_S`], whatever period the
//! trace samples at, so a run's motion does not depend on how it is watched.

use crate::canon::Pos;
use crate::machine::{AfterInterpolation, MachineConfig, MAX_AXES};

/// The interpolation period the filter runs on (FANUC's 1 ms ITP), seconds.
pub const TICK_S: f64 = 0.001;

/// An axis has stopped when its filtered position is this near its interpolated one (mm or
/// deg): the samples' own bound (`docs/motion.md`). An exponential filter never gets there
/// exactly; the linear and bell-shaped ones do after their time constant.
pub const SETTLED: f64 = 1e-6;

/// A moving average of the last `ring.len()` inputs.
#[derive(Debug, Clone)]
struct Average {
    ring: Vec<f64>,
    next: usize,
    sum: f64,
}

impl Average {
    fn new(ticks: usize, at: f64) -> Average {
        let ring = vec![at; ticks.max(1)];
        Average { sum: at * ring.len() as f64, ring, next: 0 }
    }

    fn step(&mut self, x: f64) -> f64 {
        self.sum += x - self.ring[self.next];
        self.ring[self.next] = x;
        self.next += 1;
        if self.next == self.ring.len() {
            // Once per window the sum is taken afresh, so rounding cannot drift with time.
            self.next = 0;
            self.sum = self.ring.iter().sum();
        }
        self.sum / self.ring.len() as f64
    }
}

/// One axis's filter.
#[derive(Debug, Clone)]
enum Axis {
    /// No time constant: the interpolated position goes straight on.
    Through,
    /// Linear: the average over T (a step of speed becomes a ramp over T).
    Linear(Average),
    /// Bell-shaped: two averages over T/2 in a row (a step of speed becomes two parabolas, half
    /// the step at T/2, all of it at T: the curve of the FANUC descriptions); for rapids, over
    /// T1 and then T2.
    Bell(Average, Average),
    /// First order with time constant T: y += (x − y)·(1 − e^(−tick/T)).
    Exponential { gain: f64, y: f64 },
}

/// The ticks of a time constant of `ms` milliseconds.
fn ticks(ms: f64) -> usize {
    crate::angle::round(ms * 0.001 / TICK_S).max(0) as usize
}

/// What one axis's filter is made of.
#[derive(Debug, Clone, Copy)]
enum Shape {
    /// Cutting feed: the machine's type, the axis's time constant (No.1622).
    Cutting(AfterInterpolation, f64),
    /// Rapid traverse: linear over T1 (No.1620), bell-shaped by T2 more (No.1621).
    Rapid(f64, f64),
}

impl Axis {
    fn of(shape: Shape, at: f64) -> Axis {
        match shape {
            Shape::Cutting(kind, ms) => Axis::new(kind, ms, at),
            Shape::Rapid(t1, t2) => match (ticks(t1), ticks(t2)) {
                (0, _) => Axis::Through,
                (n, 0) => Axis::Linear(Average::new(n, at)),
                (n, m) => Axis::Bell(Average::new(n, at), Average::new(m, at)),
            },
        }
    }

    fn new(kind: AfterInterpolation, ms: f64, at: f64) -> Axis {
        let ticks = ticks(ms);
        if ticks == 0 {
            return Axis::Through;
        }
        match kind {
            AfterInterpolation::Linear => Axis::Linear(Average::new(ticks, at)),
            AfterInterpolation::Bell => {
                let half = crate::angle::round(ticks as f64 / 2.0).max(1) as usize;
                Axis::Bell(Average::new(half, at), Average::new(half, at))
            }
            AfterInterpolation::Exponential => Axis::Exponential { gain: 1.0 - exp_neg(TICK_S / (ms * 0.001)), y: at },
        }
    }

    fn step(&mut self, x: f64) -> f64 {
        match self {
            Axis::Through => x,
            Axis::Linear(a) => a.step(x),
            Axis::Bell(a, b) => b.step(a.step(x)),
            Axis::Exponential { gain, y } => {
                *y += (x - *y) * *gain;
                *y
            }
        }
    }
}

/// e^(−x) for 0 < x ≤ 1 by its series: additions and products only, so bit-identical on every
/// platform (the engine uses no libm: `crate::angle`).
fn exp_neg(x: f64) -> f64 {
    let (mut term, mut sum) = (1.0, 1.0);
    for k in 1..30 {
        term *= -x / k as f64;
        sum += term;
    }
    sum
}

/// The filters of every axis of a machine, and where they put the axes.
#[derive(Debug, Clone)]
pub struct Filter {
    shapes: Vec<Shape>,
    axes: Vec<Axis>,
    out: Pos,
    input: Pos,
}

impl Filter {
    /// The machine's filter standing at `at`, or `None` when no axis has a time constant.
    pub fn of(m: &MachineConfig, at: &Pos) -> Option<Filter> {
        let kind = m.motion.after_interpolation;
        Filter::with(m.axes.iter().map(|a| Shape::Cutting(kind, a.after_interpolation_ms)).collect(), at)
    }

    /// The machine's filter of rapid traverse (No.1620 linear, with No.1621 bell-shaped)
    /// standing at `at`, or `None` when no axis has a time constant for it.
    pub fn of_rapid(m: &MachineConfig, at: &Pos) -> Option<Filter> {
        Filter::with(
            m.axes
                .iter()
                .map(|a| Shape::Rapid(a.rapid_after_interpolation_ms[0], a.rapid_after_interpolation_ms[1]))
                .collect(),
            at,
        )
    }

    fn with(shapes: Vec<Shape>, at: &Pos) -> Option<Filter> {
        let none = |s: &Shape| match *s {
            Shape::Cutting(_, ms) => ticks(ms) == 0,
            Shape::Rapid(t1, _) => ticks(t1) == 0,
        };
        if shapes.iter().all(none) {
            return None;
        }
        let axes = shapes.iter().zip(at).map(|(s, x)| Axis::of(*s, *x)).collect();
        Some(Filter { shapes, axes, out: *at, input: *at })
    }

    /// One interpolation period: the interpolated positions `x` in, the filtered ones out.
    pub fn step(&mut self, x: &Pos) -> Pos {
        self.input = *x;
        for (i, axis) in self.axes.iter_mut().enumerate() {
            self.out[i] = axis.step(x[i]);
        }
        self.out
    }

    /// Where the filter puts the axes now.
    pub fn output(&self) -> Pos {
        self.out
    }

    /// Every axis is within [`SETTLED`] of the last input: the motion has ended.
    pub fn settled(&self) -> bool {
        self.out.iter().zip(&self.input).all(|(y, x)| (y - x).abs() <= SETTLED)
    }

    /// Stand at `at` with nothing in the filter (the motion ended there, or an emergency stop:
    /// the axes stand where they are).
    pub fn stand(&mut self, at: &Pos) {
        let fresh: Vec<Axis> = self.shapes.iter().zip(at).map(|(s, x)| Axis::of(*s, *x)).collect();
        self.axes = fresh;
        (self.out, self.input) = (*at, *at);
    }
}

/// The number of axes a filter covers never exceeds the position's.
const _: () = assert!(MAX_AXES >= 3);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::{Axis as MachineAxis, AxisKind, MachineConfig};

    fn machine(kind: AfterInterpolation, ms: f64) -> MachineConfig {
        let mut m = MachineConfig::preset("mill3").unwrap();
        for a in &mut m.axes {
            a.after_interpolation_ms = ms;
        }
        m.motion.after_interpolation = kind;
        m
    }

    /// The filtered radius of a circle of radius `r` run at `v` mm/s (in X/Y about the
    /// origin), read once the filter has run a whole turn: its smallest distance from the
    /// centre over the next turn.
    fn filtered_radius(kind: AfterInterpolation, ms: f64, r: f64, v: f64) -> f64 {
        let m = machine(kind, ms);
        let w = v / r;
        let at = |k: usize| -> Pos {
            let (s, c) = crate::angle::sin_cos_deg((w * k as f64 * TICK_S).to_degrees());
            let mut p = [0.0; MAX_AXES];
            (p[0], p[1]) = (r * c, r * s);
            p
        };
        let mut f = Filter::of(&m, &at(0)).unwrap();
        let turn = crate::angle::ceil(std::f64::consts::TAU / w / TICK_S) as usize;
        let mut least = f64::INFINITY;
        for k in 1..3 * turn {
            let y = f.step(&at(k));
            if k > turn {
                least = least.min(y[0].hypot(y[1]));
            }
        }
        least
    }

    #[test]
    fn a_linear_filter_shrinks_a_circle_by_the_manuals_radius_error() {
        // FANUC 0i-A connection manual p.314: Δr = (T1²/24 + T2²/2)·v²/r for linear
        // acceleration/deceleration after interpolation; fivex has no servo lag (T2 = 0).
        // v = 100 mm/s (F6000), r = 10 mm, T1 = 32 ms: Δr = 0.032²/24 · 100²/10 = 0.042667 mm.
        // The filter's own gain on a circle is sin(Nφ/2)/(N·sin(φ/2)), φ = v/r·1 ms = 0.01 rad,
        // N = 32: sin 0.16 / (32·sin 0.005) = 0.99574294, Δr = 0.042571 mm (0.2 % below the
        // formula, which keeps the first term of the series).
        let dr = 10.0 - filtered_radius(AfterInterpolation::Linear, 32.0, 10.0, 100.0);
        assert!((dr - 0.042667).abs() < 0.042667 * 0.01, "Δr {dr}");
        assert!((dr - 0.042571).abs() < 1e-6, "Δr {dr}");
    }

    #[test]
    fn an_exponential_filter_shrinks_a_circle_twelve_times_as_much() {
        // Exponential: Δr = T1²/2 · v²/r (the same page: the linear type's error is 1/12 of
        // it). v = 100 mm/s, r = 50 mm, T1 = 32 ms: 0.032²/2 · 100²/50 = 0.1024 mm. The
        // first-order gain on the circle, 1/√(1 + (ωT)²) with ωT = 2·0.032 = 0.064, gives
        // 0.10209 mm; by 1 ms steps (gain g = 1 − e^(−1/32), |g / (1 − (1 − g)·e^(−iωh))| at
        // ωh = 0.002) 0.102078 mm.
        let dr = 50.0 - filtered_radius(AfterInterpolation::Exponential, 32.0, 50.0, 100.0);
        assert!((dr - 0.1024).abs() < 0.1024 * 0.01, "Δr {dr}");
        assert!((dr - 0.102078).abs() < 2e-6, "Δr {dr}");
    }

    #[test]
    fn a_bell_filter_is_two_averages_over_half_the_time() {
        // Two averages of 16 ms: each has the gain sin 0.08 / (16·sin 0.005) = 0.99893786
        // (φ = 0.01 rad at v = 100 mm/s, r = 10 mm), together Δr = 10·(1 − 0.99893786²) =
        // 0.021232 mm: half the manual's T1²/24 = 0.042667 mm (the page gives the linear
        // type's error for the bell too, an upper bound).
        let dr = 10.0 - filtered_radius(AfterInterpolation::Bell, 32.0, 10.0, 100.0);
        assert!((dr - 0.021232).abs() < 1e-6, "Δr {dr}");
    }

    #[test]
    fn a_linear_filter_follows_a_step_of_speed_over_its_time_constant_and_stops_after_it() {
        // X from rest at 100 mm/s (0.1 mm a tick), 8 ms filter: the filtered speed climbs by
        // 1/8 of it each tick, so the lag once at speed is 0.1·(8 − 1)/2 = 0.35 mm; once X
        // stands the filter is still for the 8th tick after.
        let m = machine(AfterInterpolation::Linear, 8.0);
        let mut f = Filter::of(&m, &[0.0; MAX_AXES]).unwrap();
        let mut x = [0.0; MAX_AXES];
        let mut speeds = vec![];
        let mut last = 0.0;
        for _ in 0..20 {
            x[0] += 0.1;
            let y = f.step(&x)[0];
            speeds.push(y - last);
            last = y;
        }
        for (k, s) in speeds.iter().take(8).enumerate() {
            assert!((s - 0.1 * (k + 1) as f64 / 8.0).abs() < 1e-12, "tick {k}: {s}");
        }
        assert!((x[0] - last - 0.35).abs() < 1e-12);
        let mut ticks = 0;
        while !f.settled() {
            f.step(&x);
            ticks += 1;
        }
        assert_eq!(ticks, 7, "the last of the 8 inputs in the window arrives 7 ticks later");
    }

    #[test]
    fn no_time_constant_no_filter() {
        let m = machine(AfterInterpolation::Linear, 0.0);
        assert!(Filter::of(&m, &[0.0; MAX_AXES]).is_none());
        let _ = MachineAxis::new('X', AxisKind::Linear, 1.0);
    }

    #[test]
    fn the_series_is_the_exponential() {
        for x in [0.001, 0.03125, 0.5, 1.0] {
            assert!((exp_neg(x) - (-x).exp()).abs() < 1e-15);
        }
    }
}
