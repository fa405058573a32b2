//! Cutter compensation C (`stage::cutter`): tool centre end points worked out by hand
//! (`docs/cutter-compensation.md` gives the rules), through the real interpreter and the
//! pipeline every driver uses, and the run's alarms. Tool offsets 1–99 have radius 5.

use crate::common::*;
use fivex_engine::canon::CanonKind;
use fivex_engine::interp::Step;
use fivex_engine::stage::Pipeline;
use fivex_engine::Dialect::{self, Fanuc, Syntec};

/// The end point (X, Y) of every motion that comes out of the stages, with its line; and the
/// alarm the interpreter raised, if any.
fn centre(src: &str, dialect: Dialect) -> (Vec<(u32, [f64; 2])>, Option<(String, u32)>) {
    let mut interp = interpreter(src, "mill3", dialect);
    let mut stages = Pipeline::for_config(interp.config());
    let mut out = Vec::new();
    let mut ends = Vec::new();
    loop {
        let step = interp.step(&mut out);
        let end = !matches!(step, Ok(Step::Continue | Step::NeedInput));
        stages.process(&mut out, end);
        for c in out.drain(..) {
            if let CanonKind::Motion(m) = c.kind {
                ends.push((c.line, [m.target[0], m.target[1]]));
            }
        }
        match step {
            Ok(Step::Continue) => {}
            Ok(Step::NeedInput) => interp.finish(),
            Ok(Step::Ended) => return (ends, None),
            Err(a) => return (ends, Some((a.code, a.line))),
        }
    }
}

/// Every motion end, compared with the expected (line, X, Y) in order, to 1e-6.
#[track_caller]
fn assert_ends(src: &str, want: &[(u32, f64, f64)]) {
    let (got, alarm) = centre(src, Fanuc);
    assert_eq!(alarm, None, "{src}");
    let close = got.len() == want.len()
        && got.iter().zip(want).all(|((l, p), (wl, x, y))| l == wl && approx(p[0], *x) && approx(p[1], *y));
    assert!(close, "got {got:?}\nwant {want:?}\n{src}");
}

#[test]
fn outside_of_a_square_g42_counter_clockwise() {
    // Square 0..20; the tool (R5) right of counter-clockwise travel is outside: start-up from
    // below (inner corner: intersection), 90° outer corners at the offset lines' intersections,
    // a straight run into the cancel (the offset point, then the programmed end).
    let src = "G90 G00 X0. Y-10. Z0\nG42 D1 G01 Y0. F500\nX20.\nY20.\nX0.\nY0.\nG40 Y-10.\nM30\n";
    assert_ends(
        src,
        &[(1, 0.0, -10.0), (2, 5.0, -5.0), (3, 25.0, -5.0), (4, 25.0, 25.0), (5, -5.0, 25.0), (6, -5.0, 0.0), (7, 0.0, -10.0)],
    );
}

#[test]
fn inside_of_a_pocket_g41_counter_clockwise() {
    // Pocket 0..40: every corner is inside (intersections); cancel at an inner corner.
    let src = "G90 G00 X20. Y10. Z0\nG41 D1 G01 Y0. F500\nX40.\nY40.\nX0.\nY0.\nX20.\nG40 Y10.\nM30\n";
    assert_ends(
        src,
        &[
            (1, 20.0, 10.0),
            (2, 25.0, 5.0),
            (3, 35.0, 5.0),
            (4, 35.0, 35.0),
            (5, 5.0, 35.0),
            (6, 5.0, 5.0),
            (7, 15.0, 5.0),
            (8, 20.0, 10.0),
        ],
    );
}

#[test]
fn boss_full_circle_g41_clockwise() {
    // Circle of radius 10 about the origin, clockwise, tool left = outside (offset radius 15).
    // Start-up along y = 0 meets it at y = 5, cancel along y = 0 backwards leaves it at y = −5.
    let src = "G90 G00 X-20. Y0. Z0\nG41 D1 G01 X-10. F500\nG02 I10.\nG40 G01 X-20.\nM30\n";
    let x = -(15.0f64 * 15.0 - 25.0).sqrt();
    assert_ends(src, &[(1, -20.0, 0.0), (2, x, 5.0), (3, x, -5.0), (4, -20.0, 0.0)]);
}
