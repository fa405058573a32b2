//! 5-axis manual operation in the controller (`docs/five-axis.md`, 5-axis manual operation):
//! FANUC's 5-axis manual feeds with their settings (spec `fanuc-twp-wsec-manual-params.md`
//! §1.3 MAN-04…MAN-17, §2.15, §3.8 TV-MAN-01…12), manual intervention in a held program
//! (MAN-01…03) and Syntec's manual RTCP registers R518/R519 (`syntec.md` SYN-12, TV-27).
#![allow(clippy::approx_constant)]

use fivex_engine::canon::Pos;
use fivex_engine::controller::{Controller, ManualCoordinates, ManualSignals, ManualTarget, Mode, Refusal, RunState};
use fivex_engine::interp::Config;
use fivex_engine::kin::{Kinematics, ManualFeed, Vec3};
use fivex_engine::machine::{MachineConfig, ManualOptions, ManualVertical};
use fivex_engine::vendor::{machine_from, params_of};
use fivex_engine::{AlarmId, Dialect};

const TICK: f64 = 0.002;

/// A controller for `m` with H1…H5 = 50, 100, …, 250 mm.
fn controller(m: MachineConfig, dialect: Dialect) -> Controller {
    let mut c = Controller::new(Config::new(m, dialect));
    for n in 1..=5 {
        c.interpreter_mut().state.offsets.tool_mut(n).unwrap().h_geometry = 50.0 * n as f64;
    }
    c
}

fn preset(name: &str) -> MachineConfig {
    MachineConfig::preset(name).unwrap()
}

/// Tick until the controller stops running (at most `limit` s); the machine positions.
fn settle(c: &mut Controller, limit: f64) -> Vec<Pos> {
    let start = c.time();
    let mut xs = Vec::new();
    while c.run_state() == RunState::Running && c.time() - start < limit {
        c.tick(TICK);
        xs.push(c.point().machine);
    }
    xs
}

/// Run `text` in MDI to its end.
fn mdi(c: &mut Controller, text: &str) {
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi(text).unwrap();
    c.cycle_start().unwrap();
    settle(c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{text}: {:?}", c.alarms());
}

fn close(a: Vec3, b: [f64; 3], tol: f64) -> bool {
    (a - Vec3::new(b[0], b[1], b[2])).norm() < tol
}

fn xyz(p: &Pos) -> Vec3 {
    Vec3::new(p[0], p[1], p[2])
}

// --- the feeds -----------------------------------------------------------------------------

/// TV-MAN-07: tool tip centre rotation on a BC head whose control point is L = 100 above the
/// tip (the B pivot at the spindle nose): B 0 → 30 moves the control point (0, 0, 100) →
/// (50, 0, 86.602540), the linear axes by (+50, 0, −13.397460).
#[test]
fn tip_rotation_on_a_bc_head_tv_man_07() {
    let mut m = preset("head-bc");
    for link in &mut m.rotary {
        link.point = [0.0; 3];
    }
    m.holder = 0.0;
    let mut c = controller(m, Dialect::Fanuc);
    c.manual_options_mut().tool_length = 100.0;
    mdi(&mut c, "G90 G00 X0 Y0 Z100. B0 C0");
    c.set_mode(Mode::Handle).unwrap();
    c.handle_tip_rotation('B', 30.0).unwrap();
    settle(&mut c, 10.0);
    let p = c.point().machine;
    assert!(close(xyz(&p), [50.0, 0.0, 86.602540], 1e-6) && (p[3] - 30.0).abs() < 1e-9, "{p:?}");
}

/// MAN-12: 5-axis JOG tip rotation: without JFR the linear axes' resultant runs at the dry run
/// rate (B head with the control point L = 100 above the tip: 600 mm/min is 6 / (100 π / 180)
/// deg/s of B); with JFR the rotary axis at the jog feed.
#[test]
fn jog_tip_rotation_feeds_man_12() {
    for (jfr, b_rate) in [(false, 10.0 / (100.0 * std::f64::consts::PI / 180.0)), (true, 6.0)] {
        let mut m = preset("head-bc");
        for link in &mut m.rotary {
            link.point = [0.0; 3];
        }
        m.holder = 0.0;
        let mut c = controller(m, Dialect::Fanuc);
        let o = c.manual_options_mut();
        (o.tool_length, o.dry_run_feed, o.jog_feedrate) = (100.0, 600.0, jfr);
        c.panel.jog_feed = 360.0;
        mdi(&mut c, "G90 G00 X0 Y0 Z100. B0 C0");
        c.set_mode(Mode::Jog).unwrap();
        c.jog_tip_rotation('B', true).unwrap();
        let mut xs = Vec::new();
        for _ in 0..1000 {
            c.tick(TICK);
            xs.push(c.point().machine);
        }
        let (a, b) = (xs[xs.len() - 2], xs[xs.len() - 1]);
        let rate = (b[3] - a[3]) / TICK;
        assert!((rate - b_rate).abs() < 1e-6, "JFR {jfr}: B at {rate} deg/s");
        if !jfr {
            assert!((speed(&xs) - 10.0).abs() < 1e-3, "resultant {} mm/s", speed(&xs));
        }
        c.jog_stop();
        settle(&mut c, 5.0);
    }
}

/// TV-MAN-04/04b through the controller (BC head, FLL = 0), and TV-MAN-05: the FLL/TWD truth
/// table with and without a tilted working plane (G68.2 I0 J45 K0: FCS X = +X, Y = (0, cos 45,
/// sin 45), Z = (0, −sin 45, cos 45)).
#[test]
fn directions_follow_fll_and_twd_tv_man_04_05() {
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    mdi(&mut c, "G90 G00 X0 Y0 Z0 B30. C90.");
    let d = |c: &Controller, f: ManualFeed| c.manual_direction(f).unwrap();
    assert!(close(d(&c, ManualFeed::ToolAxis), [0.0, 0.5, 0.866025], 1e-6));
    assert!(close(d(&c, ManualFeed::RightAngle1), [0.0, 0.866025, -0.5], 1e-6));
    assert!(close(d(&c, ManualFeed::RightAngle2), [-1.0, 0.0, 0.0], 1e-6));
    mdi(&mut c, "G90 G00 B30. C0");
    let h = 0.5f64.sqrt();
    let conventional = [[0.5, 0.0, 0.866025], [0.866025, 0.0, -0.5], [0.0, 1.0, 0.0]];
    // TV-MAN-04c: longitude/latitude about +Z of T = (0.5, 0, 0.866).
    let latitude = [[0.5, 0.0, 0.866025], [0.0, 1.0, 0.0], [-0.866025, 0.0, 0.5]];
    let plane = [[0.0, -h, h], [1.0, 0.0, 0.0], [0.0, h, h]];
    let feeds = [ManualFeed::ToolAxis, ManualFeed::RightAngle1, ManualFeed::RightAngle2];
    for plane_on in [false, true] {
        if plane_on {
            mdi(&mut c, "G68.2 X0 Y0 Z0 I0 J45. K0");
        }
        for (fll, twd) in [(false, false), (false, true), (true, false), (true, true)] {
            let o = c.manual_options_mut();
            (o.latitude_longitude, o.plane_directions, o.vertical) = (fll, twd, ManualVertical::Z);
            let expect = match (fll, twd && plane_on) {
                (_, true) => plane,
                (false, false) => conventional,
                (true, false) => latitude,
            };
            for (f, e) in feeds.iter().zip(expect) {
                assert!(close(d(&c, *f), e, 1e-6), "FLL {fll} TWD {twd} plane {plane_on} {f:?}: {:?}", d(&c, *f));
            }
            // The table feeds follow the same rules on the same signals.
            let table = [ManualFeed::TableVertical, ManualFeed::TableHorizontal1, ManualFeed::TableHorizontal2];
            if twd && plane_on {
                for (f, e) in table.iter().zip(plane) {
                    assert!(close(d(&c, *f), e, 1e-6), "{f:?}");
                }
            }
        }
    }
    mdi(&mut c, "G69");
    c.manual_options_mut().plane_directions = true;
    c.manual_options_mut().latitude_longitude = false;
    assert!(close(d(&c, ManualFeed::ToolAxis), conventional[0], 1e-6), "no plane: conventional");
}

/// §2.15 [A]: the table horizontal feeds' longitude/latitude are those of the table vertical
/// V, the right-angle feeds' those of the tool direction T.
#[test]
fn table_horizontal_latitude_uses_the_table_vertical() {
    let mut c = controller(preset("table-ac"), Dialect::Fanuc);
    mdi(&mut c, "G90 G00 A30. C0");
    let o = c.manual_options_mut();
    (o.latitude_longitude, o.vertical) = (true, ManualVertical::Z);
    let kin = Kinematics::new(&preset("table-ac")).unwrap();
    let v = kin.manual_directions(&c.point().machine).table_vertical;
    assert!((v.z - 0.866025).abs() < 1e-6, "{v:?}");
    let r1 = Vec3::z().cross(&v).normalize();
    let r2 = v.cross(&r1).normalize();
    let h1 = c.manual_direction(ManualFeed::TableHorizontal1).unwrap();
    let h2 = c.manual_direction(ManualFeed::TableHorizontal2).unwrap();
    assert!((h1 - r1).norm() < 1e-12 && (h2 - r2).norm() < 1e-12, "{h1:?} {h2:?}");
    // The tool (+Z) is parallel to P: the right-angle feeds take the fixed pair +X, +Y.
    assert!(close(c.manual_direction(ManualFeed::RightAngle1).unwrap(), [1.0, 0.0, 0.0], 1e-12));
    assert!(close(c.manual_direction(ManualFeed::RightAngle2).unwrap(), [0.0, 1.0, 0.0], 1e-12));
}

/// TV-MAN-06…06d: the tool length of the manual feeds (LOD, LOZ, No.12318; "active" = G43,
/// G44, G43.4 or G43.5 with H ≠ 0).
#[test]
fn tool_length_of_the_manual_feeds_tv_man_06() {
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    c.manual_options_mut().tool_length = 80.0;
    mdi(&mut c, "G90 G00 X0 Y0 Z100. B0 C0");
    mdi(&mut c, "G43 H5 Z0");
    assert_eq!(c.manual_tool_length(), 80.0, "LOD = 0: No.12318 whatever is active");
    c.manual_options_mut().length_from_offset = true;
    assert_eq!(c.manual_tool_length(), 250.0, "LOD = 1, G43 H5: the offset data");
    for (cancel, name) in [("G49 Z0", "G49"), ("G43 H0 Z0", "G43 H0"), ("G49\nG43.4 H0", "G43.4 H0")] {
        mdi(&mut c, cancel);
        c.manual_options_mut().zero_length_without_offset = false;
        assert_eq!(c.manual_tool_length(), 80.0, "{name}, LOZ = 0");
        c.manual_options_mut().zero_length_without_offset = true;
        assert_eq!(c.manual_tool_length(), 0.0, "{name}, LOZ = 1");
    }
    mdi(&mut c, "G49\nG43.4 H2");
    assert_eq!(c.manual_tool_length(), 100.0, "G43.4 H2 is active");
}

/// Speed along the path between the last two samples, mm/s.
fn speed(xs: &[Pos]) -> f64 {
    let (a, b) = (xs[xs.len() - 2], xs[xs.len() - 1]);
    (xyz(&b) - xyz(&a)).norm() / TICK
}

/// TV-MAN-08: the 5-axis JOG feed is the dry run rate (No.1410) or, with JFR, the jog feedrate;
/// the override acts on both.
#[test]
fn jog_feed_is_the_dry_run_rate_or_the_jog_feedrate_tv_man_08() {
    for (jfr, expect) in [(false, 1200.0 * 0.5 / 60.0), (true, 3000.0 * 0.5 / 60.0)] {
        let mut c = controller(preset("head-bc"), Dialect::Fanuc);
        let o = c.manual_options_mut();
        (o.dry_run_feed, o.jog_feedrate) = (1200.0, jfr);
        c.panel.jog_feed = 3000.0;
        c.set_overrides(0.5, 1.0);
        c.set_mode(Mode::Jog).unwrap();
        c.jog_direction(ManualFeed::ToolAxis, false).unwrap();
        let mut xs = Vec::new();
        for _ in 0..500 {
            c.tick(TICK);
            xs.push(c.point().machine);
        }
        assert!((speed(&xs) - expect).abs() < 1e-6, "JFR {jfr}: {} mm/s", speed(&xs));
        c.jog_stop();
        settle(&mut c, 5.0);
    }
}

/// TV-MAN-09: no axis of a manual feed faster than its manual rapid rate (No.1424): the tool
/// axis at B30 with Z clamped to 600 mm/min runs at 600 / cos 30 along the tool.
#[test]
fn manual_rapid_clamps_every_axis_tv_man_09() {
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    mdi(&mut c, "G90 G00 X0 Y0 Z0 B30. C0");
    c.manual_options_mut().rapid = vec![0.0, 0.0, 600.0];
    c.panel.jog_feed = 6000.0;
    c.set_mode(Mode::Handle).unwrap();
    c.handle_direction(ManualFeed::ToolAxis, 20.0).unwrap();
    let xs = settle(&mut c, 10.0);
    let top = xs.windows(2).map(|w| (w[1][2] - w[0][2]).abs() / TICK).fold(0.0, f64::max);
    assert!(top <= 10.0 + 1e-6 && top > 9.99, "Z at most 10 mm/s: {top}");
    let path = xs.windows(2).map(|w| (xyz(&w[1]) - xyz(&w[0])).norm() / TICK).fold(0.0, f64::max);
    assert!((path - 10.0 / 0.866_025_403_784_438_6).abs() < 1e-3, "{path}");
    assert!(close(xyz(&c.point().machine), [10.0, 0.0, 17.320508], 1e-6));
}

/// A 5-axis manual feed cut short by a stroke ends in the overtravel alarm of that axis, as a
/// single axis's jog does (`controller.rs`, `manual_moves_to_a_stroke_limit_end_in_the_overtravel_alarm`):
/// head-bc at zero angles, the tool axis is +Z; Z's stroke ends at 300.
#[test]
fn a_manual_feed_to_a_stroke_ends_in_the_overtravel_alarm() {
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    c.panel.jog_feed = 30000.0;
    c.set_mode(Mode::Handle).unwrap();
    c.handle_direction(ManualFeed::ToolAxis, 1000.0).unwrap();
    settle(&mut c, 10.0);
    assert_eq!(c.point().machine[2], 300.0);
    assert_eq!((c.run_state(), c.alarms()[0].code.as_str()), (RunState::Alarm, "OT0500"));
    c.reset();
    // At the limit already: the alarm at once; back along −Z it moves.
    c.handle_direction(ManualFeed::ToolAxis, 1.0).unwrap();
    assert_eq!(c.alarms()[0].code, "OT0500");
    c.reset();
    c.handle_direction(ManualFeed::ToolAxis, -20.0).unwrap();
    settle(&mut c, 10.0);
    assert_eq!((c.point().machine[2], c.run_state()), (280.0, RunState::Idle));
}

/// TV-MAN-10 and the refusals: the 5-axis feeds need JOG or HANDLE (not REF), a machine with
/// the kinematics, a rotary axis to turn and a finite amount; nothing panics.
#[test]
fn manual_feeds_refuse_cleanly_tv_man_10() {
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    c.set_mode(Mode::Ref).unwrap();
    assert_eq!(c.handle_direction(ManualFeed::ToolAxis, 1.0), Err(Refusal::WrongMode));
    assert_eq!(c.jog_direction(ManualFeed::TableVertical, true), Err(Refusal::WrongMode));
    assert_eq!(c.handle_tip_rotation('B', 1.0), Err(Refusal::WrongMode));
    assert_eq!(c.jog_tip_rotation('B', true), Err(Refusal::WrongMode));
    c.set_mode(Mode::Handle).unwrap();
    assert_eq!(c.handle_direction(ManualFeed::ToolAxis, f64::NAN), Err(Refusal::BadValue));
    assert_eq!(c.handle_tip_rotation('B', f64::INFINITY), Err(Refusal::BadValue));
    assert_eq!(c.handle('X', f64::NAN), Err(Refusal::BadValue));
    assert_eq!(c.handle_tip_rotation('Z', 1.0), Err(Refusal::NoAxis));
    c.handle_direction(ManualFeed::ToolAxis, 5.0).unwrap();
    assert_eq!(c.handle_direction(ManualFeed::ToolAxis, 5.0), Err(Refusal::Busy), "one move at a time");
    assert_eq!(c.set_manual_rtcp(true), Err(Refusal::Busy));
    settle(&mut c, 5.0);
    // A machine whose mechanism the kinematics refuse has no 5-axis feeds.
    let mut m = preset("head-bc");
    m.rotary[1].direction = [0.0, 0.0, 1.0]; // B parallel to C
    let mut c = controller(m, Dialect::Fanuc);
    c.set_mode(Mode::Handle).unwrap();
    assert_eq!(c.handle_direction(ManualFeed::ToolAxis, 1.0), Err(Refusal::NoAxis));
}

/// The settings in FANUC's parameters both ways (No.12318, 12320#0–#2, 12321, 12322,
/// 19746#2/#3, 1410, 1424), and TV-MAN-04h: No.12321 outside 0…3 is PS5459.
#[test]
fn manual_settings_in_fanuc_parameters_tv_man_04h() {
    let mut m = preset("head-bc");
    m.manual = ManualOptions {
        tool_length: 125.5,
        length_from_offset: true,
        zero_length_without_offset: true,
        plane_directions: true,
        latitude_longitude: true,
        vertical: ManualVertical::Y,
        parallel_deg: 1.5,
        jog_feedrate: true,
        dry_run_feed: 2500.0,
        rapid: vec![6000.0, 6000.0, 3000.0, 0.0, 1800.0],
        jog_feed: vec![1000.0, 0.0, 2000.0, 720.0, 0.0],
        handle_codes: [10, 11, 12, 0, 31],
    };
    let p = params_of(Dialect::Fanuc, &m).unwrap();
    assert_eq!(p.get(12320).unwrap(), 7.0);
    assert_eq!(p.get(19746).unwrap(), 12.0);
    assert_eq!(p.get(12321).unwrap(), 2.0);
    let back = machine_from(Dialect::Fanuc, "m", &p).unwrap();
    assert_eq!(back.manual, m.manual);
    assert_eq!(params_of(Dialect::Fanuc, &back).unwrap(), p);
    // The defaults write nothing and read back as defaults.
    let plain = params_of(Dialect::Fanuc, &preset("head-bc")).unwrap();
    assert_eq!((p.get(12310).unwrap(), p.get(12314).unwrap()), (10.0, 31.0));
    assert!(!p.0.contains_key(&12313));
    for n in [12318, 12320, 12321, 12322, 19746, 1410, 1423, 1424, 12310, 12311, 12312, 12313, 12314] {
        assert!(!plain.0.contains_key(&n), "No.{n}");
    }
    // JSON: absent means the defaults.
    let json = serde_json::to_string(&m).unwrap();
    let again: MachineConfig = serde_json::from_str(&json).unwrap();
    assert_eq!(again.manual, m.manual);
    for bad in [4.0, -1.0, 2.5] {
        let mut q = p.clone();
        q.set(12321, bad);
        let e = machine_from(Dialect::Fanuc, "m", &q).unwrap_err();
        assert_eq!(e.alarm, Some(AlarmId::MachineParameter), "12321 = {bad}");
        assert!(e.describe(Dialect::Fanuc).contains("PS5459"), "{}", e.describe(Dialect::Fanuc));
    }
    // HS1A–HS1E are five bits: a code outside 0…31 is refused.
    for bad in [32.0, -1.0, 1.5] {
        let mut q = p.clone();
        q.set(12312, bad);
        assert!(machine_from(Dialect::Fanuc, "m", &q).is_err(), "12312 = {bad}");
    }
    // Syntec has no such parameters: its list does not carry them.
    let s = params_of(Dialect::Syntec, &m).unwrap();
    assert_eq!(machine_from(Dialect::Syntec, "m", &s).unwrap().manual, ManualOptions::default());
}

/// Cycle start during a manual move (a JOG, a handle move running) is refused as at rest in
/// that mode: nothing starts (it answered as if it had, the run state `running`).
#[test]
fn cycle_start_during_a_manual_move_is_refused_as_in_its_mode() {
    let mut c = Controller::new(Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc));
    c.set_mode(Mode::Jog).unwrap();
    assert_eq!(c.cycle_start(), Err(Refusal::WrongMode), "at rest");
    c.jog_start('X', true).unwrap();
    c.tick(0.1);
    assert_eq!(c.run_state(), RunState::Running);
    assert_eq!(c.cycle_start(), Err(Refusal::WrongMode), "while jogging");
    c.jog_stop();
    c.tick(1.0);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('X', 30.0).unwrap();
    c.tick(0.1);
    assert_eq!(c.cycle_start(), Err(Refusal::WrongMode), "during a handle move");
}

// --- manual intervention (MAN-01…03) ---------------------------------------------------------

/// Start `src` in AUTO, hold after `hold_after` s, come to rest.
fn held(c: &mut Controller, src: &str, hold_after: f64) {
    c.set_mode(Mode::Auto).unwrap();
    // Ended by M30, which `resume` runs to (a FANUC text ending without it is PS5010).
    c.select_program(format!("{src}\nM30\n")).unwrap();
    c.cycle_start().unwrap();
    let t = c.time();
    while c.time() - t < hold_after {
        c.tick(TICK);
    }
    c.feed_hold();
    settle(c, 5.0);
    for _ in 0..100 {
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Hold);
}

/// Back to AUTO, cycle start, run to the end.
fn resume(c: &mut Controller) -> Vec<Pos> {
    c.set_mode(Mode::Auto).unwrap();
    c.cycle_start().unwrap();
    let xs = settle(c, 120.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    xs
}

/// TV-MAN-11/12 on a plain mill: +1.0 mm in X during N1; manual absolute off shifts N1's and
/// every later end point; on, the tool goes to the programmed end points.
#[test]
fn intervention_during_a_block_tv_man_11_12() {
    for absolute in [false, true] {
        let mut c = controller(preset("mill3"), Dialect::Fanuc);
        c.panel.manual_absolute = absolute;
        held(&mut c, "G90 G01 X100. F600.\nY50.\nX0\n", 5.0);
        let stop = c.point().machine;
        assert!(stop[0] > 40.0 && stop[0] < 60.0, "{stop:?}");
        assert_eq!(c.point().line, 1);
        c.set_mode(Mode::Handle).unwrap();
        c.handle('X', 1.0).unwrap();
        settle(&mut c, 5.0);
        assert!((c.point().machine[0] - stop[0] - 1.0).abs() < 1e-9);
        // The interrupted block is still the one shown (it showed line 0 until cycle start).
        assert_eq!(c.point().line, 1, "absolute {absolute}");
        let xs = resume(&mut c);
        let shift = if absolute { 0.0 } else { 1.0 };
        // N1's end: where Y starts to move.
        let corner = xs.iter().find(|p| p[1] > 1e-6).unwrap();
        assert!((corner[0] - (100.0 + shift)).abs() < 1e-6, "absolute {absolute}: N1 ends at {corner:?}");
        let end = c.point().machine;
        assert!(close(xyz(&end), [shift, 50.0, 0.0], 1e-9), "absolute {absolute}: {end:?}");
    }
}

/// Manual absolute off shifts the program's points, not machine coordinates: G53 after the
/// intervention goes to the machine position it names.
#[test]
fn the_shift_leaves_machine_coordinates_alone() {
    let mut c = controller(preset("mill3"), Dialect::Fanuc);
    c.panel.manual_absolute = false;
    held(&mut c, "G90 G01 X100. F600.\nY50.\nG53 X10. Y20.\nG00 X30.\n", 2.0);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('Y', -4.0).unwrap();
    settle(&mut c, 5.0);
    let mut corners = Vec::new();
    let mut xs = resume(&mut c);
    let step = xs.windows(2).flat_map(|w| (0..3).map(move |i| (w[1][i] - w[0][i]).abs())).fold(0.0, f64::max);
    assert!(step <= 500.0 * TICK + 1e-9, "no jump where shifted and unshifted blocks meet: {step}");
    xs.dedup_by(|a, b| (xyz(a) - xyz(b)).norm() < 1e-12);
    for w in xs.windows(3) {
        let (d1, d2) = (xyz(&w[1]) - xyz(&w[0]), xyz(&w[2]) - xyz(&w[1]));
        if d1.norm() > 1e-9 && d2.norm() > 1e-9 && d1.normalize().dot(&d2.normalize()) < 0.99 {
            corners.push(xyz(&w[1]));
        }
    }
    let end = c.point().machine;
    assert!(close(xyz(&end), [30.0, 20.0 - 4.0, 0.0], 1e-9), "G00 X30. shifted in Y only: {end:?}");
    assert!(corners.iter().any(|p| close(*p, [10.0, 20.0, 0.0], 1e-4)), "G53 X10. Y20. not shifted: {corners:?}");
    assert!(corners.iter().any(|p| close(*p, [100.0, 46.0, 0.0], 1e-4)), "N2 shifted: {corners:?}");
}

/// The same at a single-block stop, moved by JOG.
#[test]
fn intervention_at_a_single_block_stop() {
    for absolute in [false, true] {
        let mut c = controller(preset("mill3"), Dialect::Fanuc);
        c.panel.manual_absolute = absolute;
        c.panel.single_block = true;
        c.panel.jog_feed = 600.0;
        c.select_program("G90 G01 X10. F3000.\nX20.\n").unwrap();
        c.cycle_start().unwrap();
        settle(&mut c, 10.0);
        assert!((c.point().machine[0] - 10.0).abs() < 1e-9);
        c.set_mode(Mode::Jog).unwrap();
        c.jog_start('Y', true).unwrap();
        for _ in 0..200 {
            c.tick(TICK);
        }
        c.jog_stop();
        settle(&mut c, 5.0);
        let dy = c.point().machine[1];
        assert!(dy > 1.0, "{dy}");
        resume(&mut c);
        let end = c.point().machine;
        let y = if absolute { 0.0 } else { dy };
        assert!(close(xyz(&end), [20.0, y, 0.0], 1e-9), "absolute {absolute}: {end:?}");
    }
}

/// Manual absolute on at a block stop under tool centre point control: the next block's tip
/// path starts where the tip is (no jump) and ends at the programmed point.
#[test]
fn intervention_at_a_block_stop_under_tcp() {
    let kin = Kinematics::new(&preset("head-bc")).unwrap();
    for absolute in [false, true] {
        let mut c = controller(preset("head-bc"), Dialect::Fanuc);
        c.panel.manual_absolute = absolute;
        c.panel.single_block = true;
        c.select_program("G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG01 X50. F3000.\nX50. Y20. B10.\n").unwrap();
        c.cycle_start().unwrap();
        settle(&mut c, 10.0);
        while (kin.forward(&c.point().machine, 50.0).tip - Vec3::new(50.0, 0.0, 0.0)).norm() > 1e-9 {
            c.cycle_start().unwrap();
            settle(&mut c, 10.0);
            assert!(c.alarms().is_empty(), "{:?}", c.alarms());
        }
        c.set_mode(Mode::Handle).unwrap();
        c.handle('X', 2.0).unwrap();
        settle(&mut c, 5.0);
        c.set_mode(Mode::Auto).unwrap();
        c.cycle_start().unwrap();
        let mut xs = vec![c.point().machine];
        xs.extend(settle(&mut c, 10.0));
        let step = xs.windows(2).map(|w| (xyz(&w[1]) - xyz(&w[0])).norm()).fold(0.0, f64::max);
        assert!(step < 0.5, "absolute {absolute}: a jump of {step} mm (the hand move was 2)");
        let tip = kin.forward(&c.point().machine, 50.0).tip;
        let x = if absolute { 50.0 } else { 52.0 };
        assert!(close(tip, [x, 20.0, 0.0], 1e-6), "absolute {absolute}: {tip:?}");
    }
}

/// MAN-01/02 under tool centre point control on a BC head: B turned by hand during a block;
/// manual absolute on goes to the programmed tip; off is refused with FX0007 at the block
/// under way (decision: how the turn is carried on a tool tip path is not established).
#[test]
fn rotary_intervention_under_tcp_man_01_02() {
    let kin = Kinematics::new(&preset("head-bc")).unwrap();
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG01 X100. F600.\nX100. Y50. B20.\n";
    for absolute in [false, true] {
        let mut c = controller(preset("head-bc"), Dialect::Fanuc);
        c.panel.manual_absolute = absolute;
        held(&mut c, src, 8.0);
        let stop = c.point().machine;
        assert!(stop[0] > 1.0 && stop[0] < 99.0, "held in N3");
        let before = kin.forward(&stop, 50.0).tip;
        c.set_mode(Mode::Handle).unwrap();
        c.handle('B', 10.0).unwrap();
        settle(&mut c, 5.0);
        let after = kin.forward(&c.point().machine, 50.0).tip;
        assert!((after - before).norm() > 5.0, "the plain B move carried the tip");
        if !absolute {
            c.set_mode(Mode::Auto).unwrap();
            assert_eq!(c.run_state(), RunState::Alarm);
            assert_eq!((c.alarms()[0].code.as_str(), c.alarms()[0].line), ("FX0007", 3), "{:?}", c.alarms());
            assert!(c.cycle_start().is_err());
            for _ in 0..100 {
                c.tick(TICK);
            }
            let here = c.point().machine;
            assert!((0..5).all(|k| (here[k] - stop[k] - if k == 3 { 10.0 } else { 0.0 }).abs() < 1e-9), "{here:?}");
            continue;
        }
        resume(&mut c);
        let end = c.point().machine;
        let tip = kin.forward(&end, 50.0).tip;
        assert!(close(tip, [100.0, 50.0, 0.0], 1e-6), "tip {tip:?}");
        assert!((end[3] - 20.0).abs() < 1e-9, "B as programmed: {end:?}");
    }
}

/// Run the AUTO program one single block at a time until line `line` has been carried out.
fn single_blocks_to(c: &mut Controller, line: u32) {
    loop {
        c.cycle_start().unwrap();
        settle(c, 30.0);
        assert!(c.alarms().is_empty(), "{:?}", c.alarms());
        if c.point().line >= line {
            return;
        }
    }
}

/// The audit's case (manual absolute off, single block): B turned +5° by hand at the stop
/// after a TCP block. The next TCP block is refused with FX0007 before anything moves
/// (the tip moved off by the turn, B at 10 as programmed, then the G49 block turning B by 5°
/// without a B word); after reset the next run goes where it says (the shift is gone).
#[test]
fn rotary_intervention_at_a_block_stop_under_tcp_is_refused() {
    let src = "G49 G90 G54 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG01 X10. F1000\nX20. B10.\nX30. C20.\nG49\nM30\n";
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    c.panel.manual_absolute = false;
    c.panel.single_block = true;
    c.set_mode(Mode::Auto).unwrap();
    c.select_program(src).unwrap();
    single_blocks_to(&mut c, 3);
    // H1 = 50: the tip (10, 0, 0) with B0 has the pivot 50 above.
    assert!(close(xyz(&c.point().machine), [10.0, 0.0, 50.0], 1e-9), "{:?}", c.point().machine);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('B', 5.0).unwrap();
    settle(&mut c, 5.0);
    c.set_mode(Mode::Auto).unwrap();
    let stop = c.point().machine;
    c.cycle_start().unwrap();
    settle(&mut c, 30.0);
    assert_eq!(c.run_state(), RunState::Alarm);
    assert_eq!((c.alarms()[0].code.as_str(), c.alarms()[0].line), ("FX0007", 4), "{:?}", c.alarms());
    assert_eq!(c.point().machine, stop, "nothing of N4 moved");
    c.reset();
    c.panel.single_block = false;
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    let end = c.point().machine;
    assert!((0..5).all(|k| (end[k] - [30.0, 0.0, 0.0, 10.0, 20.0][k]).abs() < 1e-9), "as programmed: {end:?}");
}

/// Manual absolute off: the shift lasts until the program's end (S000 IV §1.1: it is added
/// to the later end points of that program). X +1 and B +5 by hand at a single-block stop of
/// a plain program shift its later blocks per axis; a G49 block under no tool tip path keeps
/// B where the hand left it; the next run of the program goes where it says.
#[test]
fn the_shift_of_manual_absolute_off_ends_with_the_program() {
    let src = "G90 G00 X0 Y0 Z0 B0 C0\nG01 X10. F3000.\nX20.\nG49\nM30\n";
    let mut c = controller(preset("head-bc"), Dialect::Fanuc);
    c.panel.manual_absolute = false;
    c.panel.single_block = true;
    c.set_mode(Mode::Auto).unwrap();
    c.select_program(src).unwrap();
    single_blocks_to(&mut c, 2);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('X', 1.0).unwrap();
    settle(&mut c, 5.0);
    c.handle('B', 5.0).unwrap();
    settle(&mut c, 5.0);
    c.set_mode(Mode::Auto).unwrap();
    c.panel.single_block = false;
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    let end = c.point().machine;
    assert!((0..5).all(|k| (end[k] - [21.0, 0.0, 0.0, 5.0, 0.0][k]).abs() < 1e-9), "X20. shifted by X+1 B+5: {end:?}");
    // The program ended (M30): a new run from the top is not shifted.
    c.cycle_start().unwrap();
    let mut after_n1 = None;
    while c.run_state() == RunState::Running {
        c.tick(TICK);
        if c.point().line == 1 {
            after_n1 = Some(c.point().machine);
        }
    }
    // The last sample in N1, within a tick of its end.
    let after_n1 = after_n1.unwrap();
    assert!((0..5).all(|k| after_n1[k].abs() < 1e-3), "G00 X0 Y0 Z0 B0 C0 not shifted: {after_n1:?}");
    let end = c.point().machine;
    assert!((0..5).all(|k| (end[k] - [20.0, 0.0, 0.0, 0.0, 0.0][k]).abs() < 1e-9), "{end:?}");
}

/// MAN-03: on a table machine the intervention amount is kept in the table coordinate system
/// (it turns with the table): +1 X by hand at A0, then a block that tilts the table to A30
/// ends with the tip +1 along the table's X.
#[test]
fn intervention_on_a_table_machine_turns_with_the_table_man_03() {
    let kin = Kinematics::new(&preset("table-ac")).unwrap();
    let src = "G90 G00 X0 Y0 Z50. A0 C0\nG43.4 H1\nG01 X50. F600.\nY20. A30.\n";
    for absolute in [false, true] {
        let mut c = controller(preset("table-ac"), Dialect::Fanuc);
        c.panel.manual_absolute = absolute;
        held(&mut c, src, 3.0);
        assert!(c.point().machine[0] > 1.0 && c.point().machine[0] < 49.0, "held in N3");
        c.set_mode(Mode::Handle).unwrap();
        c.handle('X', 1.0).unwrap();
        settle(&mut c, 5.0);
        resume(&mut c);
        let end = c.point().machine;
        assert!((end[3] - 30.0).abs() < 1e-9);
        let tip = kin.forward(&end, 50.0).tip;
        let shift = if absolute { 0.0 } else { 1.0 };
        assert!(close(tip, [50.0 + shift, 20.0, 50.0], 1e-6), "absolute {absolute}: tip (table) {tip:?}");
    }
}

/// What an intervention allows and refuses.
#[test]
fn intervention_refusals() {
    let mut c = controller(preset("mill3"), Dialect::Fanuc);
    held(&mut c, "G90 G01 X100. F600.\nY50.\n", 2.0);
    assert_eq!(c.set_mode(Mode::Mdi), Err(Refusal::Busy), "held: only JOG/HANDLE");
    assert_eq!(c.set_mode(Mode::Ref), Err(Refusal::Busy));
    c.set_mode(Mode::Jog).unwrap();
    c.set_mode(Mode::Handle).unwrap();
    assert_eq!(c.cycle_start(), Err(Refusal::WrongMode));
    assert_eq!(c.select_program("X0"), Err(Refusal::Busy));
    assert_eq!(c.set_mode(Mode::Mdi), Err(Refusal::Busy), "back only to the held program's mode");
    c.handle('Y', 3.0).unwrap();
    assert_eq!(c.set_mode(Mode::Auto), Err(Refusal::Busy), "not while the hand move runs");
    settle(&mut c, 5.0);
    // Without a return to AUTO nothing of the program runs.
    for _ in 0..500 {
        c.tick(TICK);
    }
    assert!((c.point().machine[1] - 3.0).abs() < 1e-9);
    // Reset abandons the held program; the mode stays.
    c.reset();
    assert_eq!(c.run_state(), RunState::Idle);
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mode(Mode::Auto).unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert!(close(xyz(&c.point().machine), [100.0, 50.0, 0.0], 1e-9), "the program runs again from the top");
}

// --- Syntec manual RTCP (R518 / R519) --------------------------------------------------------

/// TV-27: R518 = 0 / 1 / 2: X/Y/Z by hand in machine / program / tool coordinates. Tool
/// coordinates on a BC head at B30: Z along the tool, X along right-angle direction 1.
#[test]
fn r518_tool_coordinates_on_a_spindle_machine_tv_27() {
    let mut c = controller(preset("head-bc"), Dialect::Syntec);
    mdi(&mut c, "G90 G00 X0 Y0 Z0 B30. C0");
    c.set_mode(Mode::Handle).unwrap();
    c.set_manual_coordinates(ManualCoordinates::Tool).unwrap();
    c.handle('Z', 10.0).unwrap();
    settle(&mut c, 5.0);
    assert!(close(xyz(&c.point().machine), [5.0, 0.0, 8.660254], 1e-6), "{:?}", c.point().machine);
    c.handle('X', -2.0).unwrap();
    settle(&mut c, 5.0);
    assert!(close(xyz(&c.point().machine), [5.0 - 1.732051, 0.0, 8.660254 + 1.0], 1e-6));
    c.set_manual_coordinates(ManualCoordinates::Machine).unwrap();
    let before = c.point().machine;
    c.handle('Z', 1.0).unwrap();
    settle(&mut c, 5.0);
    assert!(close(xyz(&c.point().machine) - xyz(&before), [0.0, 0.0, 1.0], 1e-9));
    // R518 never changes rotary jogging (no RTCP here: B alone).
    c.set_manual_coordinates(ManualCoordinates::Tool).unwrap();
    let before = c.point().machine;
    c.handle('B', 5.0).unwrap();
    settle(&mut c, 5.0);
    let p = c.point().machine;
    assert!(close(xyz(&p) - xyz(&before), [0.0, 0.0, 0.0], 1e-9) && (p[3] - 35.0).abs() < 1e-9);
}

/// R518 = 1 on a table machine under RTCP: the program coordinates turn with the table, so
/// Z by hand moves the tip along the table's Z.
#[test]
fn r518_program_coordinates_on_a_table_machine() {
    let kin = Kinematics::new(&preset("table-ac")).unwrap();
    let mut c = controller(preset("table-ac"), Dialect::Syntec);
    mdi(&mut c, "G90 G00 X0 Y0 Z50. A0 C0\nG43.4 H1\nG00 A30.");
    c.set_mode(Mode::Handle).unwrap();
    for (choice, expect_table_z) in [(ManualCoordinates::Program, true), (ManualCoordinates::Machine, false)] {
        c.set_manual_coordinates(choice).unwrap();
        let before = kin.forward(&c.point().machine, 50.0).tip;
        c.handle('Z', 10.0).unwrap();
        settle(&mut c, 5.0);
        let moved = kin.forward(&c.point().machine, 50.0).tip - before;
        assert_eq!(close(moved, [0.0, 0.0, 10.0], 1e-6), expect_table_z, "{choice:?}: {moved:?}");
        assert!((moved.norm() - 10.0).abs() < 1e-6);
    }
}

/// TV-27b: R519 = 1 with G43.4 on a spindle machine: jogging B keeps the tip (machine X and Z
/// change); without tool centre point control, or with R519 = 0, B turns alone.
#[test]
fn r519_manual_rtcp_keeps_the_tip_tv_27b() {
    let kin = Kinematics::new(&preset("head-bc")).unwrap();
    let mut c = controller(preset("head-bc"), Dialect::Syntec);
    c.panel.jog_feed = 3600.0;
    mdi(&mut c, "G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1");
    c.set_manual_rtcp(true).unwrap();
    c.set_mode(Mode::Jog).unwrap();
    let start = c.point().machine;
    let tip = kin.forward(&start, 50.0).tip;
    c.jog_start('B', true).unwrap();
    for _ in 0..150 {
        c.tick(TICK);
        assert!((kin.forward(&c.point().machine, 50.0).tip - tip).norm() < 1e-6);
    }
    c.jog_stop();
    for p in settle(&mut c, 5.0) {
        assert!((kin.forward(&p, 50.0).tip - tip).norm() < 1e-6);
    }
    let p = c.point().machine;
    assert!(p[3] > 5.0 && (p[0] - start[0]).abs() > 1.0 && (p[2] - start[2]).abs() > 0.1, "{p:?}");
    assert!((p[1] - start[1]).abs() < 1e-9);
    // R519 = 0: B alone.
    c.set_manual_rtcp(false).unwrap();
    c.set_mode(Mode::Handle).unwrap();
    let before = c.point().machine;
    c.handle('B', -5.0).unwrap();
    settle(&mut c, 5.0);
    assert!(close(xyz(&c.point().machine) - xyz(&before), [0.0; 3], 1e-9));
    // R519 = 1 without tool centre point control: B alone too.
    c.set_manual_rtcp(true).unwrap();
    mdi(&mut c, "G49");
    c.set_mode(Mode::Handle).unwrap();
    let before = c.point().machine;
    c.handle('B', -5.0).unwrap();
    settle(&mut c, 5.0);
    assert!(close(xyz(&c.point().machine) - xyz(&before), [0.0; 3], 1e-9));
}

// --- any sequence of 5-axis manual actions -----------------------------------------------------

mod sequences {
    use super::*;
    use proptest::prelude::*;

    #[derive(Debug, Clone)]
    enum Action {
        Ticks(usize),
        CycleStart,
        FeedHold,
        Reset,
        Mode(Mode),
        Handle(char, f64),
        Jog(char, bool),
        JogStop,
        Along(ManualFeed, f64),
        Tip(char, f64),
        JogTip(char, bool),
        Absolute(bool),
        Rtcp(bool),
        Coordinates(ManualCoordinates),
        SingleBlock(bool),
        Signals(ManualSignals),
        JogSignal(char, bool),
        Pulses(f64),
    }

    const PROGRAM: &str =
        "G90 G00 X0 Y0 Z0 B0 C0\nG43.4 H1\nG01 X40. F3000.\nX40. Y30. B20.\nX0 C45.\nG49\nG53 Z50.\nG00 X10. B0\nM30\n";

    fn action() -> impl Strategy<Value = Action> {
        let axis = prop::sample::select(vec!['X', 'Y', 'Z', 'B', 'C']);
        let rotary = prop::sample::select(vec!['B', 'C', 'X']);
        prop_oneof![
            4 => (1usize..400).prop_map(Action::Ticks),
            2 => Just(Action::CycleStart),
            1 => Just(Action::FeedHold),
            1 => Just(Action::Reset),
            2 => prop::sample::select(vec![Mode::Auto, Mode::Jog, Mode::Handle, Mode::Ref]).prop_map(Action::Mode),
            1 => (axis.clone(), -50.0..50.0f64).prop_map(|(a, d)| Action::Handle(a, d)),
            1 => (axis, any::<bool>()).prop_map(|(a, p)| Action::Jog(a, p)),
            1 => Just(Action::JogStop),
            1 => (prop::sample::select(ManualFeed::ALL.to_vec()), -50.0..50.0f64).prop_map(|(f, d)| Action::Along(f, d)),
            1 => (rotary.clone(), -40.0..40.0f64).prop_map(|(a, d)| Action::Tip(a, d)),
            1 => (rotary, any::<bool>()).prop_map(|(a, p)| Action::JogTip(a, p)),
            1 => any::<bool>().prop_map(Action::Absolute),
            1 => any::<bool>().prop_map(Action::Rtcp),
            1 => prop::sample::select(vec![ManualCoordinates::Machine, ManualCoordinates::Program, ManualCoordinates::Tool])
                .prop_map(Action::Coordinates),
            1 => any::<bool>().prop_map(Action::SingleBlock),
            1 => (any::<[bool; 4]>(), 0u8..12).prop_map(|([a, r, n, t], code)| Action::Signals(super::signals(a, r, n, t, code))),
            1 => (prop::sample::select(vec!['X', 'Y', 'Z', 'B', 'C']), any::<bool>()).prop_map(|(a, p)| Action::JogSignal(a, p)),
            1 => (-50.0..50.0f64).prop_map(Action::Pulses),
        ]
    }

    /// `n` ticks; between two samples no axis may move more than its rapid rate allows, in
    /// the program's motion and in a manual handle interruption's shift each (the two add up
    /// on the machine: `docs/five-axis.md`, handle interruption).
    fn ticks(c: &mut Controller, last: &mut Pos, rapid: &[f64], n: usize) -> Result<(), TestCaseError> {
        for _ in 0..n {
            let shift_before = c.interrupt_shift();
            c.tick(TICK);
            let p = c.point().machine;
            let shift = c.interrupt_shift();
            for i in 0..5 {
                let step = |d: f64| if i == 4 { d.abs().min(360.0 - d.abs()) } else { d.abs() }; // C rolls over
                let moved = step((p[i] - shift[i]) - (last[i] - shift_before[i]));
                let shifted = (shift[i] - shift_before[i]).abs();
                prop_assert!(moved <= rapid[i], "axis {} jumped {} at {:?}", i, moved, p);
                prop_assert!(shifted <= rapid[i], "axis {} shifted {} at {:?}", i, shifted, p);
            }
            *last = p;
        }
        Ok(())
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

        /// Whatever the operator does with the 5-axis manual functions on a BC head running a
        /// TCP program (interventions and FANUC's panel signals included), nothing panics, no axis leaves its stroke or
        /// jumps (no axis moves faster than its rapid rate between two samples), and a machine
        /// that is not running stands still.
        #[test]
        fn any_sequence_of_manual_actions_is_safe(actions in prop::collection::vec(action(), 1..40)) {
            let mut m = preset("head-bc");
            m.manual.handle_codes = [6, 7, 8, 9, 10];
            let rapid: Vec<f64> = m.axes.iter().map(|a| a.rapid / 60.0 * TICK * (1.0 + 1e-6) + 1e-9).collect();
            let strokes: Vec<Option<[f64; 2]>> = m.axes.iter().map(|a| a.stroke).collect();
            let mut c = controller(m, Dialect::Syntec);
            c.manual_options_mut().tool_length = 60.0;
            c.select_program(PROGRAM).unwrap();
            // Running from the start: feed holds and interventions come early and often.
            c.cycle_start().unwrap();
            let mut last = c.point().machine;
            for a in actions {
                let _ = match a {
                    Action::Ticks(n) => {
                        ticks(&mut c, &mut last, &rapid, n)?;
                        Ok(())
                    }
                    Action::CycleStart => c.cycle_start(),
                    Action::FeedHold => {
                        c.feed_hold();
                        Ok(())
                    }
                    Action::Reset => {
                        c.reset();
                        Ok(())
                    }
                    Action::Mode(m) => c.set_mode(m),
                    Action::Handle(a, d) => c.handle(a, d),
                    Action::Jog(a, p) => c.jog_start(a, p),
                    Action::JogStop => {
                        c.jog_stop();
                        Ok(())
                    }
                    Action::Along(f, d) => c.handle_direction(f, d),
                    Action::Tip(a, d) => c.handle_tip_rotation(a, d),
                    Action::JogTip(a, p) => c.jog_tip_rotation(a, p),
                    Action::Absolute(on) => {
                        c.panel.manual_absolute = on;
                        Ok(())
                    }
                    Action::Rtcp(on) => c.set_manual_rtcp(on),
                    Action::Coordinates(choice) => c.set_manual_coordinates(choice),
                    Action::SingleBlock(on) => {
                        c.panel.single_block = on;
                        Ok(())
                    }
                    Action::Signals(s) => c.set_manual_signals(s),
                    Action::JogSignal(a, p) => c.jog_signal(a, p),
                    Action::Pulses(d) => c.handle_pulses(d).map(|taken| {
                        assert!(taken == 0.0 || taken.abs() <= d.abs() + 1e-12, "took {taken} of {d}");
                    }),
                };
                let p = c.point().machine;
                for (i, s) in strokes.iter().enumerate() {
                    if let Some([lo, hi]) = s {
                        prop_assert!(p[i] >= lo - 1e-6 && p[i] <= hi + 1e-6, "axis {} at {}", i, p[i]);
                    }
                }
                if c.run_state() != RunState::Running {
                    ticks(&mut c, &mut last, &rapid, 1000)?;
                    let settled = c.point().machine;
                    if c.run_state() != RunState::Running {
                        ticks(&mut c, &mut last, &rapid, 100)?;
                        prop_assert_eq!(c.point().machine, settled);
                    }
                }
            }
        }
    }
}

// --- FANUC's panel signals (MAN-05…17, §6.7) -------------------------------------------------

fn signals(alngh: bool, rghth: bool, rndh: bool, tb_base: bool, handle_select: u8) -> ManualSignals {
    ManualSignals { alngh, rghth, rndh, tb_base, handle_select }
}

/// TV-MAN-02, 03, 03b, 03c, 03d, 03e and OQ-27: which JOG signal drives which feed (head-bc:
/// X, Y, Z, B, C are axes 1…5, No.19697 = 3).
#[test]
fn jog_signals_choose_the_feed_tv_man_02_03() {
    use ManualFeed::*;
    use ManualTarget::{Axis, Feed, TipRotation};
    let kin = Kinematics::new(&preset("head-bc")).unwrap();
    let k = Some(&kin);
    // TV-MAN-02: ALNGH, TB_BASE 0: ±J3 the tool axis; the others their own axis.
    let along = signals(true, false, false, false, 0);
    assert_eq!(along.jog_target(k, 2), Feed(ToolAxis));
    assert_eq!(along.jog_target(k, 0), Axis(0));
    assert_eq!(along.jog_target(k, 3), Axis(3));
    // TV-MAN-03: RGHTH: ±J1 direction 1, ±J2 direction 2; ±J3 plain Z.
    let right = signals(false, true, false, false, 0);
    assert_eq!([right.jog_target(k, 0), right.jog_target(k, 1)], [Feed(RightAngle1), Feed(RightAngle2)]);
    assert_eq!(right.jog_target(k, 2), Axis(2));
    // TV-MAN-03b/03c: TB_BASE 1: the table feeds on the same signals.
    let table = signals(false, true, false, true, 0);
    assert_eq!([table.jog_target(k, 0), table.jog_target(k, 1)], [Feed(TableHorizontal1), Feed(TableHorizontal2)]);
    assert_eq!(signals(true, false, false, true, 0).jog_target(k, 2), Feed(TableVertical));
    // TV-MAN-03d: RNDH: ±J4 (B) turns B about the tip; a linear axis jogs alone.
    let round = signals(false, false, true, false, 0);
    assert_eq!([round.jog_target(k, 3), round.jog_target(k, 4)], [TipRotation(3), TipRotation(4)]);
    assert_eq!(round.jog_target(k, 1), Axis(1));
    // TV-MAN-03e: the reference direction tilted by RA = 30: still ±J3 (No.19697 alone).
    let mut tilted = preset("head-bc");
    tilted.tool_axis = [0.5, 0.0, 0.866_025_403_784_438_6];
    let kin_tilted = Kinematics::new(&tilted).unwrap();
    assert_eq!(along.jog_target(Some(&kin_tilted), 2), Feed(ToolAxis));
    assert_eq!(right.jog_target(Some(&kin_tilted), 0), Feed(RightAngle1));
    // OQ-27 (decision): two mode signals at once, or none, or no kinematics: the axis alone.
    for s in [signals(true, true, false, false, 0), signals(true, false, true, false, 0), ManualSignals::default()] {
        assert_eq!(s.jog_target(k, 2), Axis(2), "{s:?}");
    }
    assert_eq!(along.jog_target(None, 2), Axis(2));
    // 19697 = 1 (OQ-26): ±J1 the tool axis, ±J2 direction 1 (+Y), ±J3 direction 2 (+Z).
    let mut x_tool = preset("head-bc");
    x_tool.tool_axis = [1.0, 0.0, 0.0];
    let kin_x = Kinematics::new(&x_tool).unwrap();
    assert_eq!(along.jog_target(Some(&kin_x), 0), Feed(ToolAxis));
    assert_eq!(
        [right.jog_target(Some(&kin_x), 1), right.jog_target(Some(&kin_x), 2)],
        [Feed(RightAngle1), Feed(RightAngle2)]
    );
}

/// MAN-05/07/11/14/16: the handle select code against No.12310–12314 (OQ-25: 12311 direction
/// 1, 12312 direction 2, 12313 the first rotary axis — C on head-bc —, 12314 the second, B);
/// a code that is no 5-axis feed is an axis number.
#[test]
fn handle_select_codes_choose_the_feed_no_12310_12314() {
    use ManualFeed::*;
    use ManualTarget::{Axis, Feed, Nothing, TipRotation};
    let mut m = preset("head-bc");
    m.manual.handle_codes = [10, 11, 12, 13, 14];
    let kin = Kinematics::new(&m).unwrap();
    let k = Some(&kin);
    let t = |a, r, n, tb, code| signals(a, r, n, tb, code).handle_target(k, &m);
    assert_eq!(t(true, false, false, false, 10), Feed(ToolAxis));
    assert_eq!(t(true, false, false, true, 10), Feed(TableVertical));
    assert_eq!(t(false, true, false, false, 11), Feed(RightAngle1));
    assert_eq!(t(false, true, false, false, 12), Feed(RightAngle2));
    assert_eq!(t(false, true, false, true, 12), Feed(TableHorizontal2));
    assert_eq!(t(false, false, true, false, 13), TipRotation(4));
    assert_eq!(t(false, false, true, true, 14), TipRotation(3));
    // The code of another family, or no mode signal: an axis number, else nothing.
    assert_eq!(t(false, true, false, false, 10), Nothing, "10 is no axis of five");
    assert_eq!(t(true, false, false, false, 3), Axis(2));
    assert_eq!(t(false, false, false, false, 10), Nothing);
    assert_eq!(t(true, true, false, false, 10), Nothing, "OQ-27: conflicting signals");
    assert_eq!(t(true, false, false, false, 0), Nothing);
    assert_eq!(signals(true, false, false, false, 10).handle_target(None, &m), Nothing);
    // Unset codes (0) select no 5-axis feed.
    let plain = preset("head-bc");
    assert_eq!(signals(true, false, false, false, 1).handle_target(k, &plain), Axis(0));
}

/// The signal entry points move the machine: JOG along the tool with ALNGH (B30: the tool is
/// (0.5, 0, 0.866)), a plain axis otherwise; the handle by its select code.
#[test]
fn signal_entry_points_move_the_machine() {
    let mut m = preset("head-bc");
    m.manual.handle_codes = [10, 11, 12, 13, 14];
    let mut c = controller(m, Dialect::Fanuc);
    mdi(&mut c, "G90 G00 X0 Y0 Z0 B30. C0");
    c.set_mode(Mode::Jog).unwrap();
    c.set_manual_signals(signals(true, false, false, false, 0)).unwrap();
    c.jog_signal('Z', true).unwrap();
    for _ in 0..200 {
        c.tick(TICK);
    }
    c.jog_stop();
    settle(&mut c, 5.0);
    let p = xyz(&c.point().machine);
    assert!(p.norm() > 1.0 && close(p.normalize(), [0.5, 0.0, 0.866_025_403_784_438_6], 1e-9), "{p:?}");
    c.jog_signal('X', false).unwrap();
    for _ in 0..100 {
        c.tick(TICK);
    }
    c.jog_stop();
    settle(&mut c, 5.0);
    let q = xyz(&c.point().machine);
    assert!(q.x < p.x - 0.1 && (q.y - p.y).abs() < 1e-12 && (q.z - p.z).abs() < 1e-12, "X alone: {q:?}");
    // HANDLE: code 11 with RGHTH is direction 1 = (0.866, 0, −0.5) at B30 C0; code 13 with RNDH
    // turns C (the first rotary axis) about the tip; code 0 discards.
    c.set_mode(Mode::Handle).unwrap();
    c.set_manual_signals(signals(false, true, false, false, 11)).unwrap();
    assert_eq!(c.handle_pulses(2.0), Ok(2.0));
    settle(&mut c, 5.0);
    let r = xyz(&c.point().machine);
    assert!(close(r - q, [1.732_050_807_568_877_2, 0.0, -1.0], 1e-9), "{:?}", r - q);
    c.set_manual_signals(signals(false, false, true, false, 13)).unwrap();
    let tip = |c: &Controller| {
        let kin = Kinematics::new(&preset("head-bc")).unwrap();
        kin.forward(&c.point().machine, c.manual_tool_length()).tip
    };
    let before = tip(&c);
    assert_eq!(c.handle_pulses(-45.0), Ok(-45.0));
    settle(&mut c, 5.0);
    // C rolls over: −45 is shown as 315.
    let cc = c.point().machine[4];
    assert!((cc.rem_euclid(360.0) - 315.0).abs() < 1e-9 && (tip(&c) - before).norm() < 1e-6, "C {cc}");
    c.set_manual_signals(signals(false, false, true, false, 0)).unwrap();
    let here = c.point().machine;
    assert_eq!(c.handle_pulses(5.0), Ok(0.0), "nothing selected: discarded");
    assert_eq!(c.run_state(), RunState::Idle);
    assert_eq!(c.point().machine, here);
    // Refusals: the mode, the amount, and the signals while moving.
    assert_eq!(c.handle_pulses(f64::NAN), Err(Refusal::BadValue));
    c.set_mode(Mode::Jog).unwrap();
    assert_eq!(c.handle_pulses(1.0), Err(Refusal::WrongMode));
    c.set_mode(Mode::Handle).unwrap();
    assert_eq!(c.jog_signal('X', true), Err(Refusal::WrongMode));
    c.set_manual_signals(signals(false, false, false, false, 1)).unwrap();
    assert_eq!(c.handle_pulses(5.0), Ok(5.0));
    assert_eq!(c.set_manual_signals(ManualSignals::default()), Err(Refusal::Busy));
    settle(&mut c, 5.0);
}

/// TV-MAN-09 with the signals: the handle moves as fast as No.1424 lets every axis go (the
/// override does not act on it), and pulses that arrive while it is still following the
/// earlier ones are discarded ("handle pulses generated while the clamp feedrate is exceeded
/// are ignored").
#[test]
fn handle_pulses_beyond_the_clamp_are_discarded_tv_man_09() {
    let mut m = preset("head-bc");
    m.manual.handle_codes = [10, 0, 0, 0, 0];
    m.manual.rapid = vec![0.0, 0.0, 600.0];
    let mut c = controller(m, Dialect::Fanuc);
    mdi(&mut c, "G90 G00 X0 Y0 Z0 B30. C0");
    c.set_overrides(0.5, 1.0);
    c.set_mode(Mode::Handle).unwrap();
    c.set_manual_signals(signals(true, false, false, false, 10)).unwrap();
    assert_eq!(c.handle_pulses(20.0), Ok(20.0));
    let mut xs = Vec::new();
    for _ in 0..100 {
        c.tick(TICK);
        xs.push(c.point().machine);
    }
    assert_eq!(c.handle_pulses(5.0), Ok(0.0), "still following: discarded");
    xs.extend(settle(&mut c, 10.0));
    let top = xs.windows(2).map(|w| (w[1][2] - w[0][2]).abs() / TICK).fold(0.0, f64::max);
    assert!(top <= 10.0 + 1e-6 && top > 9.99, "Z at its No.1424, 10 mm/s, whatever the override: {top}");
    assert!(close(xyz(&c.point().machine), [10.0, 0.0, 17.320508], 1e-6), "20 mm along the tool only");
    assert_eq!(c.handle_pulses(5.0), Ok(5.0), "at rest the pulses move again");
    settle(&mut c, 10.0);
    assert!(close(xyz(&c.point().machine), [12.5, 0.0, 21.650635], 1e-6));
}

/// TV-MAN-08 with No.1423 per axis: JFR = 1 runs the 5-axis JOG at the jog feedrate of the axis
/// whose signal drives it (Z for the tool axis, X for direction 1), JFR = 0 at the dry run
/// rate; the override acts in both; an ordinary JOG runs at its axis's No.1423.
#[test]
fn jog_feed_per_axis_no_1423_tv_man_08() {
    let run = |c: &mut Controller, f: &dyn Fn(&mut Controller)| {
        f(c);
        let mut xs = Vec::new();
        for _ in 0..600 {
            c.tick(TICK);
            xs.push(c.point().machine);
        }
        c.jog_stop();
        settle(c, 5.0);
        speed(&xs) * 60.0
    };
    for (jfr, tool, dir1) in [(true, 2400.0 * 0.5, 1800.0 * 0.5), (false, 1200.0 * 0.5, 1200.0 * 0.5)] {
        let mut m = preset("head-bc");
        (m.manual.jog_feedrate, m.manual.dry_run_feed) = (jfr, 1200.0);
        m.manual.jog_feed = vec![1800.0, 0.0, 2400.0];
        let mut c = controller(m, Dialect::Fanuc);
        c.panel.jog_feed = 3000.0;
        c.set_overrides(0.5, 1.0);
        c.set_mode(Mode::Jog).unwrap();
        let v = run(&mut c, &|c| c.jog_direction(ManualFeed::ToolAxis, true).unwrap());
        assert!((v - tool).abs() < 1e-6, "JFR {jfr}: tool axis at {v}");
        c.set_manual_signals(signals(false, true, false, false, 0)).unwrap();
        let v = run(&mut c, &|c| c.jog_signal('X', true).unwrap());
        assert!((v - dir1).abs() < 1e-6, "JFR {jfr}: direction 1 at {v}");
        // Y has no No.1423: the panel's jog feed; X its own.
        c.set_manual_signals(ManualSignals::default()).unwrap();
        let v = run(&mut c, &|c| c.jog_start('Y', true).unwrap());
        assert!((v - 1500.0).abs() < 1e-6, "plain Y at {v}");
        let v = run(&mut c, &|c| c.jog_signal('X', false).unwrap());
        assert!((v - 900.0).abs() < 1e-6, "plain X at {v}");
    }
}

#[test]
fn a_program_started_after_manual_moves_begins_where_the_machine_stands() {
    // A HANDLE move that runs to its end and an INC step leave the machine elsewhere; the next
    // MDI's incremental move starts from there (not from where the last program left off).
    let mut c = controller(preset("mill3"), Dialect::Fanuc);
    c.set_mode(Mode::Handle).unwrap();
    c.handle('X', 10.0).unwrap();
    for _ in 0..5000 {
        c.tick(TICK);
    }
    assert!((c.point().machine[0] - 10.0).abs() < 1e-9);
    mdi(&mut c, "G91 G01 X1. F600.");
    assert!((c.point().machine[0] - 11.0).abs() < 1e-9, "{:?}", c.point().machine);
    assert!((c.point().work[0] - 11.0).abs() < 1e-9);
    c.set_mode(Mode::Inc).unwrap();
    c.set_increment(1.0).unwrap();
    c.jog_start('Y', true).unwrap();
    for _ in 0..5000 {
        c.tick(TICK);
    }
    mdi(&mut c, "G91 G01 Y2. F600.");
    assert!((c.point().machine[1] - 3.0).abs() < 1e-9, "{:?}", c.point().machine);
}

/// TV-27b (SYN-12): during and after R519 manual RTCP the program X/Y/Z (the tip under G43.4)
/// stay as they were while B turns; the interpreter's current point keeps them, and its machine
/// position follows the machine — without another mode or block in between.
#[test]
fn r519_keeps_the_program_xyz_and_the_position_variables_tv_27b() {
    let mut c = controller(preset("head-bc"), Dialect::Syntec);
    c.panel.jog_feed = 3600.0;
    mdi(&mut c, "G90 G00 X10. Y20. Z30. B0 C0\nG43.4 H1");
    assert!(close(xyz(&c.point().work), [10.0, 20.0, 30.0], 1e-9), "{:?}", c.point().work);
    c.set_manual_rtcp(true).unwrap();
    c.set_mode(Mode::Handle).unwrap();
    c.handle('B', 30.0).unwrap();
    let mut turned = false;
    while c.run_state() == RunState::Running {
        c.tick(TICK);
        let p = c.point();
        assert!(close(xyz(&p.work), [10.0, 20.0, 30.0], 1e-9), "program X/Y/Z during the turn: {:?}", p.work);
        turned |= p.machine[3] > 1.0;
    }
    assert!(turned);
    let p = c.point();
    assert!((p.work[3] - 30.0).abs() < 1e-9 && (p.machine[3] - 30.0).abs() < 1e-9, "{p:?}");
    assert!(close(xyz(&p.work), [10.0, 20.0, 30.0], 1e-9), "after: {:?}", p.work);
    // The interpreter's current point right now (what FANUC's #5001…/#5021… read; the Syntec
    // dialect refuses those numbers, its user parameters, `syntec_macro.rs`).
    let state = &c.interpreter().state;
    let (work, machine) = (state.position(), state.machine_position());
    assert!(close(xyz(&work), [10.0, 20.0, 30.0], 1e-9), "{work:?}");
    assert!((work[3] - 30.0).abs() < 1e-9, "B {}", work[3]);
    let m = xyz(&p.machine);
    assert!((m - Vec3::new(10.0, 20.0, 80.0)).norm() > 10.0, "the machine moved: {m:?}");
    assert!(close(xyz(&machine), [m.x, m.y, m.z], 1e-9), "{machine:?}");
}

// --- the clamp of tool tip centre rotation (MAN-11/12, TV-MAN-09) --------------------------

/// How a tool tip centre rotation is started: the ±J signal with RNDH in JOG and in INC, the
/// handle's pulses with RNDH and a select code of No.12313/12314, and the direct commands
/// (the server's `/jog` and `/handle` with `tip_rotation`).
#[derive(Debug, Clone, Copy)]
enum TipTurn {
    JogSignal,
    IncSignal,
    HandlePulses,
    JogTip,
    HandleTip,
}

/// What a tip rotation did, sampled every tick: each axis's top speed (units/min), the linear
/// axes' resultant's, which linear axes moved, how far the tip strayed on the table (mm), and
/// how far the rotary axis turned (degrees).
struct Turned {
    top: Vec<f64>,
    resultant: f64,
    moved: [bool; 3],
    drift: f64,
    turned: f64,
}

/// Turn rotary axis `axis` (index `i`) positive about the tip by `how`.
fn tip_turn(c: &mut Controller, m: &MachineConfig, axis: char, i: usize, how: TipTurn) -> Turned {
    let kin = &Kinematics::new(m).unwrap();
    let rndh = |select: u8| signals(false, false, true, false, select);
    let length = c.manual_tool_length();
    let tip = |p: &Pos| kin.forward(p, length).tip;
    let start = c.point().machine;
    match how {
        TipTurn::JogSignal | TipTurn::JogTip => {
            c.set_mode(Mode::Jog).unwrap();
            c.set_manual_signals(rndh(0)).unwrap();
            match how {
                TipTurn::JogSignal => c.jog_signal(axis, true).unwrap(),
                _ => c.jog_tip_rotation(axis, true).unwrap(),
            }
        }
        TipTurn::IncSignal => {
            c.set_mode(Mode::Inc).unwrap();
            c.set_increment(10.0).unwrap();
            c.set_manual_signals(rndh(0)).unwrap();
            c.jog_signal(axis, true).unwrap();
        }
        TipTurn::HandlePulses => {
            c.set_mode(Mode::Handle).unwrap();
            let select = [13, 14]
                .into_iter()
                .find(|&s| rndh(s).handle_target(Some(kin), m) == ManualTarget::TipRotation(i))
                .unwrap();
            c.set_manual_signals(rndh(select)).unwrap();
            assert_eq!(c.handle_pulses(15.0), Ok(15.0));
        }
        TipTurn::HandleTip => {
            c.set_mode(Mode::Handle).unwrap();
            c.handle_tip_rotation(axis, 15.0).unwrap();
        }
    }
    let mut xs = vec![start];
    if matches!(how, TipTurn::JogSignal | TipTurn::JogTip) {
        for _ in 0..500 {
            c.tick(TICK);
            xs.push(c.point().machine);
        }
        c.jog_stop();
    }
    xs.extend(settle(c, 30.0));
    assert_eq!(c.run_state(), RunState::Idle, "{how:?}: {:?}", c.alarms());
    c.set_manual_signals(ManualSignals::default()).unwrap();
    let step = |a: &Pos, b: &Pos, k: usize| {
        let d = b[k] - a[k];
        if k >= 3 {
            (d + 180.0).rem_euclid(360.0) - 180.0
        } else {
            d
        }
    };
    let top = (0..5).map(|k| xs.windows(2).map(|w| step(&w[0], &w[1], k).abs()).fold(0.0, f64::max) / TICK * 60.0);
    let end = xs[xs.len() - 1];
    Turned {
        top: top.collect(),
        resultant: xs.windows(2).map(|w| (xyz(&w[1]) - xyz(&w[0])).norm()).fold(0.0, f64::max) / TICK * 60.0,
        moved: std::array::from_fn(|k| (end[k] - start[k]).abs() > 1e-6),
        drift: xs.iter().map(|p| (tip(p) - tip(&start)).norm()).fold(0.0, f64::max),
        turned: step(&start, &end, i),
    }
}

/// TV-MAN-09 for tool tip centre rotation (MAN-11/12 "Feedrate clamp"): whichever way it is
/// started, on head, table and mixed machines and about either rotary axis, no axis runs
/// faster than its No.1424, the linear axes' resultant no faster than the lowest No.1424 of
/// the linear axes that move, the tip stays where it is on the table, and the slowest of these
/// constraints sets the speed of the whole move (it is reached). The JOG feeds ask for more
/// (the dry run rate 6000 mm/min, the jog feed 100 000 deg/min), the handle as fast as the
/// clamp allows. Before, the rotation was planned against the machine's own axis rates: the
/// outside tester's head-bc case (first set) ran X at 23 500 mm/min and B at 7 180 deg/min
/// under a clamp of 1000.
#[test]
fn tip_rotation_keeps_to_the_manual_rapid_clamp_tv_man_09() {
    let machines = [
        ("head-bc", "G90 G00 X0 Y0 Z0 B30. C0", ['B', 'C']),
        ("table-ac", "G90 G00 X50. Y20. Z0 A30. C0", ['A', 'C']),
        ("table-bc", "G90 G00 X50. Y20. Z0 B30. C0", ['B', 'C']),
        ("mixed-bc", "G90 G00 X50. Y20. Z0 B30. C0", ['B', 'C']),
    ];
    let clamps = [[1000.0; 5], [1000.0, 800.0, 1200.0, 900.0, 500.0]];
    let turns = [TipTurn::JogSignal, TipTurn::IncSignal, TipTurn::HandlePulses, TipTurn::JogTip, TipTurn::HandleTip];
    for (name, setup, rotary) in machines {
        for rapid in clamps {
            for axis in rotary {
                for how in turns {
                    let mut m = preset(name);
                    m.manual.handle_codes = [0, 0, 0, 13, 14];
                    (m.manual.tool_length, m.manual.dry_run_feed) = (100.0, 6000.0);
                    m.manual.rapid = rapid.to_vec();
                    let i = m.axis_index(axis as u8).unwrap();
                    let mut c = controller(m.clone(), Dialect::Fanuc);
                    c.panel.jog_feed = 100_000.0;
                    mdi(&mut c, setup);
                    let t = tip_turn(&mut c, &m, axis, i, how);
                    let case =
                        format!("{name} {axis} {how:?} No.1424 {rapid:?}: top {:?}, resultant {}", t.top, t.resultant);
                    let over = |v: f64, limit: f64| v > limit * (1.0 + 1e-6) + 1e-6;
                    for (k, (&v, &limit)) in t.top.iter().zip(&rapid).enumerate() {
                        assert!(!over(v, limit), "{case}: axis {k} over its No.1424");
                    }
                    let linear = (0..3).filter(|&k| t.moved[k]).map(|k| rapid[k]).fold(f64::INFINITY, f64::min);
                    assert!(!over(t.resultant, linear), "{case}: the resultant over {linear}");
                    let share = (t.top[i] / rapid[i]).max(t.resultant / linear);
                    assert!(share > 0.98, "{case}: the slowest constraint not reached ({share})");
                    assert!(t.drift < 1e-6, "{case}: the tip strayed {} mm", t.drift);
                    let amount = match how {
                        TipTurn::IncSignal => Some(10.0),
                        TipTurn::HandlePulses | TipTurn::HandleTip => Some(15.0),
                        _ => None,
                    };
                    match amount {
                        Some(a) => assert!((t.turned - a).abs() < 1e-9, "{case}: turned {}", t.turned),
                        None => assert!(t.turned > 1.0, "{case}: turned {}", t.turned),
                    }
                }
            }
        }
    }
}
