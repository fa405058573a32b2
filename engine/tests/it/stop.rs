//! A host stops a run (`run::Observer::stop`, how a cancelled fleet run ends): the run ends
//! where it is asked to, before the next block or sample, however long the program would go on.

use crate::common;

use common::*;
use fivex_engine::run::{run, run_observed, Observer, RunOptions, Sample};
use fivex_engine::Dialect;

/// Says stop once it has been asked `after` times; counts the samples it saw.
struct StopAfter {
    asked: u64,
    after: u64,
    samples: u64,
}

impl Observer for StopAfter {
    fn sample(
        &mut self,
        _: &Sample,
        _: &fivex_engine::canon::Pos,
        _: Option<(&fivex_engine::motion::Segment, f64, u64)>,
    ) {
        self.samples += 1;
    }
    fn stop(&mut self) -> bool {
        self.asked += 1;
        self.asked > self.after
    }
}

#[test]
fn an_endless_macro_loop_stops_when_asked() {
    let src = "O1\n#1=0\nWHILE[#1 GE 0]DO1\n#1=#1+1\nEND1\nM30\n";
    let mut observer = StopAfter { asked: 0, after: 1_000, samples: 0 };
    let opts = RunOptions { period_s: 0.0, ..RunOptions::default() };
    let result = run_observed(&mut interpreter(src, "mill3", Dialect::Fanuc), &opts, |_| {}, &mut observer);
    // Asked before every block: exactly the blocks before the stop ran.
    assert_eq!(result.blocks, 1_000);
    assert!(result.alarms.is_empty(), "{:?}", result.alarms);
}

#[test]
fn a_long_dwell_stops_between_samples() {
    // 100,000 s at 1 ms: 10^8 samples if nothing stopped it.
    let src = "O1\nG04 X100000.\nM30\n";
    let mut observer = StopAfter { asked: 0, after: 5_000, samples: 0 };
    let opts = RunOptions { period_s: 0.001, max_time_s: 1.0e6, ..RunOptions::default() };
    run_observed(&mut interpreter(src, "mill3", Dialect::Fanuc), &opts, |_| {}, &mut observer);
    assert!(observer.samples < 5_000, "{} samples", observer.samples);
    assert!(observer.samples > 0);
}

#[test]
fn an_observer_that_never_stops_changes_nothing() {
    let src = "O1\nG91 G01 X10. F1000\nY5.\nG04 X0.5\nX-10. Y-5.\nM30\n";
    let opts = RunOptions { period_s: 0.001, ..RunOptions::default() };
    let plain = run(&mut interpreter(src, "mill3", Dialect::Fanuc), &opts, |_| {});
    let mut observer = StopAfter { asked: 0, after: u64::MAX, samples: 0 };
    let observed = run_observed(&mut interpreter(src, "mill3", Dialect::Fanuc), &opts, |_| {}, &mut observer);
    assert_eq!(plain, observed);
    assert!(observer.asked > observer.samples, "asked before every block and sample");
}
