//! Golden-section search: the least value of a function with a single dip on an interval.

/// The least value of `f` on `[lo, hi]` that `iterations` golden-section steps find (one new
/// evaluation a step), for a function with one dip there. The least of every value evaluated
/// is the answer, not the last bracket's: it is never above a value `f` takes.
pub(crate) fn least(f: impl Fn(f64) -> f64, lo: f64, hi: f64, iterations: usize) -> f64 {
    bottom(f, lo, hi, iterations).1
}

/// Where [`least`] finds its value, and the value.
pub(crate) fn bottom(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64, iterations: usize) -> (f64, f64) {
    const R: f64 = 0.618_033_988_749_894_9;
    let (mut a, mut b) = (hi - R * (hi - lo), lo + R * (hi - lo));
    let (mut fa, mut fb) = (f(a), f(b));
    let mut best = if fa <= fb { (a, fa) } else { (b, fb) };
    for _ in 0..iterations {
        if fa < fb {
            (hi, b, fb) = (b, a, fa);
            a = hi - R * (hi - lo);
            fa = f(a);
            if fa < best.1 {
                best = (a, fa);
            }
        } else {
            (lo, a, fa) = (a, b, fb);
            b = lo + R * (hi - lo);
            fb = f(b);
            if fb < best.1 {
                best = (b, fb);
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    #[test]
    fn finds_the_bottom_of_a_dip() {
        let f = |x: f64| (x - 0.3).powi(2) - 2.0;
        assert!((super::least(f, 0.0, 1.0, 60) + 2.0).abs() < 1e-12);
        // A dip at the interval's end.
        assert!((super::least(|x| x, 0.25, 1.0, 60) - 0.25).abs() < 1e-9);
        let (x, y) = super::bottom(f, 0.0, 1.0, 60);
        assert!((x - 0.3).abs() < 1e-6 && (y + 2.0).abs() < 1e-12);
    }
}
