//! The cycle-time estimate (`host::estimate`) against the run it estimates: the fixture programs
//! run on a hosted controller tick by tick, as the workers run them, and the estimate made
//! before the cycle start from the same controller must be that run's time within 1 %.

use std::time::Duration;

use fivex_engine::controller::RunState;
use fivex_engine::machine::MachineConfig;
use fivex_server::host::estimate::{self, Conditions, Estimate};
use fivex_server::host::{Hosted, Spec};

/// The preset a fixture names in its `(fivex: --preset NAME)` line, mill3 without one.
fn preset(text: &str) -> &str {
    text.split("--preset ").nth(1).and_then(|rest| rest.split(')').next()).unwrap_or("mill3").trim()
}

fn hosted(text: &str) -> Hosted {
    Hosted::new(Spec {
        id: "c1".into(),
        name: "estimate".into(),
        dialect: fivex_engine::Dialect::Fanuc,
        machine: MachineConfig::preset(preset(text)).expect("the fixture's preset"),
        created_at: "2025-01-01T00:00:00Z".into(),
        speed: 1.0,
    })
}

/// The estimate of `text` on a fresh controller of its preset, with a wall-clock `budget`.
fn estimate_of(text: &str, budget: Duration) -> Estimate {
    let interp = hosted(text).station().controller.interpreter().clone();
    estimate::compute(interp, &text.into(), budget)
}

/// The estimate of `text` on the controller as it stands, then the controller's own run of it
/// in 1 ms ticks: (estimate, the run's simulated time from cycle start to idle).
fn estimate_and_run(text: &str) -> (Estimate, f64) {
    let hosted = hosted(text);
    let mut station = hosted.station();
    let interp = station.controller.interpreter().clone();
    let estimate = estimate::compute(interp, &text.into(), Duration::from_secs(60));
    let c = &mut station.controller;
    c.select_program(text).expect("selected");
    let start = c.time();
    c.cycle_start().expect("started");
    // A deadline in simulated time: ten times the estimate, and at least ten minutes.
    let limit = start + (estimate.cycle_time_s.unwrap_or(0.0) * 10.0).max(600.0);
    while c.run_state() == RunState::Running && c.time() < limit {
        c.tick(0.001);
    }
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    (estimate, c.time() - start)
}

#[test]
fn the_estimate_is_the_run_s_cycle_time_within_one_percent() {
    let fixtures = [
        "helix.nc",
        "g81_drill_g98_g99_repeat.nc",
        "dwell.nc",
        "crc_pocket_inside.nc",
        "tcp_table_ac_type1.nc",
        "tcp_head_bc_swing.nc",
        "twp_g68_2_g53_1.nc",
        "twp_three_points_head_bc.nc",
    ];
    for name in fixtures {
        let path = format!("{}/../tests/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
        let text = std::fs::read_to_string(&path).expect("the fixture");
        let (estimate, run) = estimate_and_run(&text);
        assert_eq!(estimate.state, "ready", "{name}: {estimate:?}");
        let estimated = estimate.cycle_time_s.expect("a cycle time");
        assert!(run > 0.0, "{name}: the run took no time");
        let error = (estimated - run).abs() / run;
        assert!(error <= 0.01, "{name}: estimate {estimated} s, run {run} s ({:.3} %)", error * 100.0);
    }
}

#[test]
fn a_program_that_stops_at_an_alarm_is_estimated_up_to_it() {
    let text = "G01 X10. F600\n#3000=1(STOP)\nG01 X20.\nM30\n";
    let e = estimate_of(text, Duration::from_secs(60));
    assert_eq!(e.state, "alarm", "{e:?}");
    assert_eq!(e.alarm.as_ref().map(|a| a.line), Some(2), "{e:?}");
    // 10 mm at 600 mm/min is a second, plus the speed changes.
    let t = e.cycle_time_s.unwrap();
    assert!((1.0..1.5).contains(&t), "{t}");
}

#[test]
fn an_estimate_out_of_wall_time_is_unknown() {
    // An endless loop: only the wall-clock budget ends it.
    let text = "#1=0\nWHILE[#1GE0]DO1\n#1=#1+1\nEND1\nM30\n";
    let e = estimate_of(text, Duration::from_millis(50));
    assert_eq!((e.state.as_str(), e.cycle_time_s), ("unknown", None), "{e:?}");
    assert!(e.reason.unwrap().contains("longer than"));
}

#[test]
fn progress_is_elapsed_against_the_estimate_and_names_what_differs() {
    let ready =
        Estimate { state: "ready".into(), cycle_time_s: Some(40.0), alarm: None, reason: None, depends_on: vec![] };
    let as_estimated = Conditions {
        feed_override: 1.0,
        rapid_override: 1.0,
        single_block: false,
        optional_stop: false,
        held: false,
        dry_run: false,
        aux_lock: false,
    };
    let p = estimate::progress(7, 10.0, ready.clone(), as_estimated);
    assert_eq!((p.remaining_s, p.percent, p.caveats.len()), (Some(30.0), Some(25.0), 0));
    // Past the estimate: nothing remains, 100 % at most.
    let p = estimate::progress(7, 50.0, ready.clone(), Conditions { feed_override: 0.5, held: true, ..as_estimated });
    assert_eq!((p.remaining_s, p.percent), (Some(0.0), Some(100.0)));
    assert_eq!(p.caveats, ["feed_override", "held"]);
    let p = estimate::progress(7, 5.0, ready.clone(), Conditions { dry_run: true, aux_lock: true, ..as_estimated });
    assert_eq!(p.caveats, ["dry_run", "aux_lock"]);
    // Without a finished estimate there is no remaining time to tell.
    let alarm = Estimate { state: "alarm".into(), ..ready };
    let p = estimate::progress(7, 5.0, alarm, as_estimated);
    assert_eq!((p.remaining_s, p.percent), (None, None));
}

#[test]
fn what_the_time_depends_on_outside_the_program_is_named() {
    let depends = |text: &str| estimate::depends_on(text);
    assert_eq!(depends("G01 X1. F100\nM00\n#1=#1000\nM30\n"), ["input_signals", "program_stop"]);
    assert_eq!(depends("IF[#1035 EQ 1] GOTO 5\nM0\n"), ["input_signals", "program_stop"]);
    // In comments, outputs, other numbers and other M codes: nothing.
    assert!(depends("(M00 WAITS, #1000 IS READ)\nG01 X1. F100 (M0)\nM30\n").is_empty());
    assert!(depends("#1100=1\n#10000=2\n#999=#100\nM01\nM03 S1000\nM30\n").is_empty());
    assert!(depends("POPEN\nDPRNT[DIM00]\nPCLOS\nM30\n").is_empty(), "the M of a word, not an M code");
    // The estimate carries them.
    let e = estimate_of("G01 X10. F600\nM00\nG01 X0\nM30\n", Duration::from_secs(60));
    assert_eq!((e.state.as_str(), e.depends_on.as_slice()), ("ready", &["program_stop".to_string()][..]), "{e:?}");
}

#[test]
fn estimates_under_way_are_limited_and_their_slots_given_back() {
    let slots = estimate::Slots::new();
    let a = slots.take(2).expect("a first slot");
    let b = slots.take(2).expect("a second slot");
    assert!(slots.take(2).is_none(), "no third one");
    drop(a);
    let c = slots.take(2).expect("the slot given back");
    assert!(slots.take(2).is_none());
    drop((b, c));
    assert!(slots.take(1).is_some());
}

#[test]
fn the_key_changes_with_what_the_run_reads() {
    let text = "G01 X[#100] F600\nM30\n";
    let hosted = hosted(text);
    let mut station = hosted.station();
    let before = estimate::key(&text.into(), station.controller.interpreter());
    assert_eq!(before, estimate::key(&text.into(), station.controller.interpreter()), "the same inputs, the same key");
    assert_ne!(
        before,
        estimate::key(&"G01 X[#100] F601\nM30\n".into(), station.controller.interpreter()),
        "another text"
    );
    station.controller.interpreter_mut().state.set_common_variable(100, Some(10.0)).expect("#100 is common");
    let common = estimate::key(&text.into(), station.controller.interpreter());
    assert_ne!(before, common, "a common variable");
    station.controller.interpreter_mut().state.offsets.work_mut(1)[0] = 5.0;
    let offset = estimate::key(&text.into(), station.controller.interpreter());
    assert_ne!(common, offset, "a work offset");
    // A program may branch on an input signal, and a G31 stops on the workpiece: the estimate
    // kept its first answer after either changed (audit svc 1, 2).
    station.controller.interpreter_mut().state.signals.inputs[0] = 1;
    let signal = estimate::key(&text.into(), station.controller.interpreter());
    assert_ne!(offset, signal, "an input signal");
    let boxes = vec![fivex_engine::workpiece::Cuboid { min: [0.0, 0.0, -10.0], max: [10.0, 10.0, 20.0] }];
    station.controller.set_workpiece(std::sync::Arc::new(fivex_engine::workpiece::Workpiece { boxes })).unwrap();
    assert_ne!(signal, estimate::key(&text.into(), station.controller.interpreter()), "the workpiece");
}
