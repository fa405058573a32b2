//! The trace's `tip` is where the machine puts the tool tip (forward kinematics of the sampled
//! axes with the tool length in effect, in the active workpiece system), never the programmed
//! point; `programmed` and `programmed_in` carry the commanded point and the name of its system
//! (`docs/conventions.md`, Positions; docs/contracts.md: trace).

use crate::common;

use common::interpreter;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::tip::System;
use fivex_engine::Dialect;

fn trace(src: &str, preset: &str, dialect: Dialect) -> (Vec<Sample>, RunResult) {
    let mut interp = interpreter(src, preset, dialect);
    let mut samples = Vec::new();
    let r = run(&mut interp, &RunOptions::default(), |s| samples.push(*s));
    assert!(r.completed(), "{:?}", r.alarms);
    (samples, r)
}

fn kin(preset: &str) -> Kinematics {
    Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap()
}

fn dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    Vec3::from(a).metric_distance(&Vec3::from(b))
}

/// `tip` of every sample is FK(axes, `length(line)`) − `origin`, computed here independently
/// of the run; returns how far `tip` and `programmed` are apart at most.
fn tip_is_fk(samples: &[Sample], kin: &Kinematics, origin: [f64; 3], length: impl Fn(u32) -> f64) -> f64 {
    let mut apart: f64 = 0.0;
    for s in samples {
        let pose = kin.forward(&s.machine, length(s.line));
        let expected = [pose.tip.x - origin[0], pose.tip.y - origin[1], pose.tip.z - origin[2]];
        assert!(dist(s.tip, expected) < 1e-9, "line {} t {}: tip {:?}, FK {:?}", s.line, s.t, s.tip, expected);
        assert!(dist(s.tool, pose.tool.into()) < 1e-12, "line {}: tool {:?}", s.line, s.tool);
        apart = apart.max(dist(s.tip, s.programmed));
    }
    apart
}

/// 3 axes, G54 = (10, 20, −300), G43 H1 (100 mm): tip = machine − tool length − work offset.
/// During the G43 block the machine moves by the offset while the program point moves
/// elsewhere: the tip tells where the tool is (a tool length change mid-program, machine ≠
/// program), the programmed point does not.
#[test]
fn three_axis_g43_tip_is_machine_minus_length_minus_work_offset() {
    let src = "N1 G10 L2 P1 X10. Y20. Z-300.\nN2 G90 G54 G00 X0 Y0 Z200.\nN3 G43 H1 Z50.\n\
               N4 G01 X30. F3000\nN5 G49 Z200.\nN6 M30\n";
    let (samples, r) = trace(src, "mill3", Dialect::Fanuc);
    for s in &samples {
        let length = if (3..=4).contains(&s.line) { 100.0 } else { 0.0 };
        let m = s.machine;
        let expected = [m[0] - 10.0, m[1] - 20.0, m[2] - length + 300.0];
        assert!(dist(s.tip, expected) < 1e-9, "line {}: {:?} ≠ {expected:?}", s.line, s.tip);
        assert_eq!(s.tool, [0.0, 0.0, 1.0]);
        assert_eq!(s.programmed_in, System::Workpiece);
    }
    // The G43 block's first sample: the 100 mm tool hangs 100 mm below where the program
    // point (Z200, from N2) is; the old trace showed 200.
    let first = samples.iter().find(|s| s.line == 3).unwrap();
    assert!((first.tip[2] - 100.0).abs() < 1e-3 && (first.programmed[2] - 200.0).abs() < 1e-3, "{first:?}");
    // Once the offset is in, the machine is where the program says.
    for s in samples.iter().filter(|s| s.line == 4) {
        assert!(dist(s.tip, s.programmed) < 1e-9, "{s:?}");
    }
    // The summary reads the end the same way (after G49: the nose).
    assert!(dist(r.tip.tip, [30.0, 0.0, 200.0]) < 1e-9, "{:?}", r.tip);
    assert_eq!((r.programmed, r.programmed_in), ([30.0, 0.0, 200.0], System::Workpiece));
}

/// G44 subtracts the length: the control's tool is −100 long, and the tip says so.
#[test]
fn g44_reads_the_tip_with_the_negative_length() {
    let src = "N1 G90 G54 G00 X0 Y0 Z0\nN2 G44 H1 Z50.\nN3 G49\nN4 M30\n";
    let (samples, _) = trace(src, "mill3", Dialect::Fanuc);
    let end = samples.iter().rev().find(|s| s.line == 2).unwrap();
    assert!((end.machine[2] - (50.0 - 100.0)).abs() < 1e-6, "{:?}", end.machine);
    assert!((end.tip[2] - 50.0).abs() < 1e-6, "{:?}", end.tip);
}

/// FANUC G43.4 on head-bc with a work offset: the tip is FK of the axes with the 100 mm tool,
/// minus the offset; on a head machine Π is the workpiece system, so the programmed tip is
/// followed to 1 µm, and B/C turning changes nothing of that.
#[test]
fn tcp_on_head_bc_tip_is_fk_in_the_workpiece_system() {
    let src = "N1 G10 L2 P2 X50. Y-40. Z-250.\nN2 G00 G90 B0 C0\nN3 G55\nN4 G43.4 H01\n\
               N5 G00 X20. Y10. Z30.\nN6 G01 X5. Y5. Z5. B30. C45. F2000\nN7 G49\nN8 M30\n";
    let (samples, _) = trace(src, "head-bc", Dialect::Fanuc);
    let length = |line: u32| if (4..=6).contains(&line) { 100.0 } else { 0.0 };
    let k = kin("head-bc");
    tip_is_fk(&samples, &k, [50.0, -40.0, -250.0], length);
    let moving: Vec<_> = samples.iter().filter(|s| s.line == 6).collect();
    assert!(moving.len() > 10);
    for s in moving {
        assert_eq!(s.programmed_in, System::Programming);
        assert!(dist(s.tip, s.programmed) < 1e-3, "{s:?}");
    }
    let end = samples.iter().rev().find(|s| s.line == 6).unwrap();
    // (The last sample falls within the block's last interpolation period.)
    assert!(dist(end.tip, [5.0, 5.0, 5.0]) < 1e-3, "{:?}", end.tip);
    // B30 C45: the tool leans 30° from Z toward +X turned by 45° about Z (right-hand head).
    let (s, c) = (30f64.to_radians().sin(), 30f64.to_radians().cos());
    let expected = [s * 45f64.to_radians().cos(), s * 45f64.to_radians().sin(), c];
    assert!(dist(end.tool, expected) < 1e-4, "{:?} vs {expected:?}", end.tool);
}

/// G43.4 on table-ac started with the table at A30: Π is fixed on the table as it stood (the
/// programmed point), while `tip` is in the workpiece system fixed on the table at A0 C0
/// (`fivex kin fk`'s table frame minus the work offset): the two differ, and `tip` is FK.
#[test]
fn tcp_on_table_ac_tip_is_fk_in_the_table_fixed_workpiece_system() {
    let src = "N1 G00 G90 X0 Y0 Z100. A30. C0\nN2 G43.4 H01\nN3 G01 X10. Y10. Z10. A45. C30. F2000\n\
               N4 G49\nN5 M30\n";
    let (samples, _) = trace(src, "table-ac", Dialect::Fanuc);
    let k = kin("table-ac");
    let apart = tip_is_fk(&samples, &k, [0.0; 3], |line| if (2..=3).contains(&line) { 100.0 } else { 0.0 });
    assert!(apart > 1.0, "tip and programmed should differ: {apart}");
    let end = samples.iter().rev().find(|s| s.line == 3).unwrap();
    assert_eq!(end.programmed_in, System::Programming);
    assert!(dist(end.programmed, [10.0, 10.0, 10.0]) < 1e-2, "{:?}", end.programmed);
}

/// TV-32 (Syntec SYN-18…, FANUC G68.2): G68.2 X100 Y100 Z50 I30 J15 K20, G53.1, G43 H1,
/// G01 X0 Y0 Z0 puts the tip at workpiece (100, 100, 50): `tip` says so, `programmed` is the
/// feature point (0, 0, 0) in `feature`; the old trace printed (0, 0, 0) as the tip.
#[test]
fn tilted_plane_tip_is_in_the_workpiece_system_programmed_in_the_feature_system() {
    let src = "N1 G90 G54 G01 X0 Y0 Z50. F1000\nN2 G68.2 X100. Y100. Z50. I30. J15. K20.\n\
               N3 G01 X0 Y0 Z50.\nN4 G53.1\nN5 G43 H1\nN6 G01 X0 Y0 Z0\nN98 G49\nN99 G69\nM30\n";
    for dialect in [Dialect::Fanuc, Dialect::Syntec] {
        for preset in ["head-bc", "table-ac"] {
            let (samples, r) = trace(src, preset, dialect);
            let length = |line: u32| if (5..=6).contains(&line) { 100.0 } else { 0.0 };
            tip_is_fk(&samples, &kin(preset), [0.0; 3], length);
            let end = samples.iter().rev().find(|s| s.line == 6).unwrap();
            // (The last sample falls within the block's last interpolation period.)
            assert!(dist(end.tip, [100.0, 100.0, 50.0]) < 1e-2, "{preset}: {:?}", end.tip);
            assert!(dist(end.programmed, [0.0, 0.0, 0.0]) < 1e-2, "{preset}: {:?}", end.programmed);
            assert_eq!(end.programmed_in, System::Feature);
            // The summary after G69 (which does not move): the workpiece system again.
            assert_eq!(r.programmed_in, System::Workpiece, "{preset}: after G69");
        }
    }
}

/// A move in machine coordinates in a tilted plane (G28's return, TWP-13) shows its programmed
/// point in the FCS, as its `feature` label says: it ends at the tip seen from the plane, which
/// is what #5001… read after it. The trace showed the machine position under that name (110 mm
/// off).
#[test]
fn a_reference_return_in_a_tilted_plane_shows_the_tip_in_the_feature_system() {
    let src = "N1 G90 G00 X50. Y20. Z-100.\nN2 G68.2 X0 Y0 Z0 I0 J30. K0\nN3 G53.1\nN4 G43 H1 Z50.\n\
               N5 G00 X10. Y5.\nN6 G91 G28 Z0\nN7 G90\nN8 G49\nN9 G69\nN10 M30\n";
    let (samples, _) = trace(src, "head-bc", Dialect::Fanuc);
    // The FCS: turned 30° about X (Euler I0 J30 K0), origin at the workpiece zero.
    let (s, c) = (0.5, 3f64.sqrt() / 2.0);
    let in_plane = |t: [f64; 3]| [t[0], c * t[1] + s * t[2], -s * t[1] + c * t[2]];
    let on_return: Vec<_> = samples.iter().filter(|x| x.line == 6).collect();
    assert!(on_return.len() > 20, "{} samples of the return", on_return.len());
    let (first, last) = (on_return[0].machine[2], on_return.last().unwrap().machine[2]);
    assert!(first > 100.0 && last.abs() < 1e-3, "Z from {first} to {last}, not to machine zero");
    assert!(on_return.iter().all(|x| x.programmed_in == System::Feature));
    // The return cancels the length vector (the tip read without it from the block's start, as
    // in a G43 block the programmed point and the tip part there); it ends on the tip.
    let end = on_return.last().unwrap();
    assert!(dist(end.programmed, in_plane(end.tip)) < 1e-3, "{:?} vs {:?}", end.programmed, in_plane(end.tip));
}

/// The length the block takes from the offset memory (set by G10 L10 in the program) is the one
/// the tip is read with.
#[test]
fn tool_length_from_the_offset_memory_in_effect() {
    let src = "N1 G90 G54 G00 X0 Y0 Z0\nN2 G10 L10 P7 R80.\nN3 G43 H7 Z20.\nN4 G49 Z100.\nN5 M30\n";
    let (samples, _) = trace(src, "mill3", Dialect::Fanuc);
    let end = samples.iter().rev().find(|s| s.line == 3).unwrap();
    assert!((end.machine[2] - 100.0).abs() < 1e-6 && (end.tip[2] - 20.0).abs() < 1e-6, "{end:?}");
}

/// A block after an offset change without motion (G10 L2) starts where the machine stands,
/// expressed in the new system: `programmed` runs from −100 (not from the old 0) to 10, with
/// the tip, along the whole move.
#[test]
fn programmed_starts_where_the_machine_stands_after_an_offset_change() {
    let src = "N1 G10 L2 P1 X100.\nN2 G90 G54 G01 X10. F600\nN3 M30\n";
    let (samples, _) = trace(src, "mill3", Dialect::Fanuc);
    assert!(samples[0].programmed[0] == -100.0 && samples[0].tip[0] == -100.0, "{:?}", samples[0]);
    for s in &samples {
        assert!(dist(s.tip, s.programmed) < 1e-9, "{s:?}");
    }
}

/// The controller's live position reads the tip the same way, tick by tick: FK of the axes it
/// is at with the length in effect, less the work offset; with the machine standing after the
/// program, the interpreter's state (here G55 with a 100 mm tool under G43).
#[test]
fn controller_tip_is_fk_of_the_live_axes() {
    use fivex_engine::controller::RunState;
    let src = "N1 G10 L2 P2 X50. Y-40. Z-250.\nN2 G00 G90 B0 C0\nN3 G55\nN4 G43.4 H01\n\
               N5 G00 X20. Y10. Z30.\nN6 G01 X5. Y5. Z5. B30. C45. F2000\nN7 G49\nN8 G43 H1 Z50.\nN9 M30\n";
    let mut c = started(src, "head-bc");
    let k = kin("head-bc");
    let mut seen_tcp = 0;
    while c.run_state() == RunState::Running && c.time() < 300.0 {
        c.tick(0.01);
        let p = c.point();
        // Line 9 (M30) is shown once reached: the machine stands where N8 left it, H1 on.
        let length = if (4..=6).contains(&p.line) || p.line >= 8 { 100.0 } else { 0.0 };
        let pose = k.forward(&p.machine, length);
        let origin = if p.line >= 3 { [50.0, -40.0, -250.0] } else { [0.0; 3] };
        let expected = [pose.tip.x - origin[0], pose.tip.y - origin[1], pose.tip.z - origin[2]];
        let tip = c.tip();
        assert!(dist(tip.tip, expected) < 1e-9, "line {}: {:?} vs {expected:?}", p.line, tip.tip);
        assert!(dist(tip.tool, pose.tool.into()) < 1e-12);
        if p.line == 6 {
            seen_tcp += 1;
            assert_eq!(c.tip_basis().programmed_in, System::Programming);
            assert!(dist(tip.tip, [p.work[0], p.work[1], p.work[2]]) < 1e-3, "{tip:?} {:?}", p.work);
        }
    }
    assert!(seen_tcp > 5, "{seen_tcp} ticks on the TCP move");
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    // At rest after G43 H1 Z50 in G55 with the head still at B30 C45: plain G43 adds the
    // length along machine Z, so the tilted tool's tip is not at the programmed (5, 5, 50);
    // the tip says where it is (from the interpreter's state now that nothing runs).
    let (tip, p) = (c.tip(), c.point());
    let pose = k.forward(&p.machine, 100.0);
    let expected = [pose.tip.x - 50.0, pose.tip.y + 40.0, pose.tip.z + 250.0];
    assert!(dist(tip.tip, expected) < 1e-9, "{tip:?} vs {expected:?}");
    assert!(dist([p.work[0], p.work[1], p.work[2]], [5.0, 5.0, 50.0]) < 1e-9, "{:?}", p.work);
    assert!(dist(tip.tip, [5.0, 5.0, 50.0]) > 10.0, "{tip:?}");
    assert_eq!(c.tip_basis().programmed_in, System::Workpiece);
}

/// The same block under plain G43 and under G43.4 with the head at B30: the programmed point
/// is the same, but only TCP puts the tip there. By hand (head-bc, `docs/machine-config.md`):
/// plain G43 puts the carriage at (10, 0, 10 + 100), the B pivot 150 above it at (10, 0, 260),
/// the tool along (sin 30°, 0, cos 30°), so the tip is 250 mm down it: (−115, 0, 43.4936).
#[test]
fn plain_g43_with_the_head_tilted_shows_the_real_tip_tcp_the_programmed_one() {
    let tilted = "N1 G90 G54 G00 X0 Y0 Z200. B30. C0\n";
    let plain = format!("{tilted}N2 G43 H1\nN3 G01 X10. Y0 Z10. F3000\nN4 G04 X0.05\nN5 M30\n");
    let tcp = format!("{tilted}N2 G43.4 H1\nN3 G01 X10. Y0 Z10. F3000\nN4 G04 X0.05\nN5 M30\n");
    let at_rest = |src: &str| {
        let (samples, _) = trace(src, "head-bc", Dialect::Fanuc);
        *samples.iter().rev().find(|s| s.line == 4).expect("dwell samples")
    };
    let (p, t) = (at_rest(&plain), at_rest(&tcp));
    let (s30, c30) = (0.5, 3f64.sqrt() / 2.0);
    assert!(dist(p.tip, [10.0 - 250.0 * s30, 0.0, 260.0 - 250.0 * c30]) < 1e-9, "plain G43: {:?}", p.tip);
    assert!(dist(p.programmed, [10.0, 0.0, 10.0]) < 1e-9, "{:?}", p.programmed);
    assert!(dist(t.tip, [10.0, 0.0, 10.0]) < 1e-9, "G43.4: {:?}", t.tip);
    assert!(dist(t.programmed, [10.0, 0.0, 10.0]) < 1e-9, "{:?}", t.programmed);
    assert!(dist(p.tool, [s30, 0.0, c30]) < 1e-12 && dist(t.tool, [s30, 0.0, c30]) < 1e-12);
}

/// The controller (the service) applies the same rule as `fivex run`: after G10 L2 without
/// motion the next move's programmed point starts where the machine stands, in the new system,
/// and stays on the tip.
#[test]
fn controller_programmed_starts_where_the_machine_stands_after_an_offset_change() {
    use fivex_engine::controller::RunState;
    let src = "N1 G10 L2 P1 X100.\nN2 G90 G54 G01 X10. F600\nN3 M30\n";
    let mut c = started(src, "mill3");
    let mut ticks = 0;
    while c.run_state() == RunState::Running && c.time() < 60.0 {
        c.tick(0.01);
        let (p, tip) = (c.point(), c.tip());
        if p.line == 2 {
            ticks += 1;
            assert!(dist(tip.tip, [p.work[0], p.work[1], p.work[2]]) < 1e-9, "{:?} vs {:?}", tip.tip, p.work);
        }
    }
    assert!(ticks > 10, "{ticks} ticks on the move");
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
}

/// A controller (with the tests' tool offsets) running `src` in AUTO.
fn started(src: &str, preset: &str) -> fivex_engine::controller::Controller {
    use fivex_engine::controller::{Controller, Mode};
    let i = interpreter(src, preset, Dialect::Fanuc);
    let mut c = Controller::new(i.config().clone());
    c.interpreter_mut().state.offsets = i.state.offsets.clone();
    c.set_mode(Mode::Auto).unwrap();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    c
}

/// Audit of offsets F7: a tool change block that also selects H (`T3 M06 H3` under G43) stands
/// with the block's own state: its samples show the new tool's length. By hand: G43 H2 (150)
/// at Z100 puts machine Z at 250; H3 (50) shifts the coordinates without a move (FANUC TOS = 1),
/// so the tip during the change is 250 − 50 = 200 (it showed 100, the H2 length's).
#[test]
fn a_tool_change_block_with_h_shows_the_new_length_while_it_stands() {
    let src = "N1 G10 L10 P2 R150.\nN2 G10 L10 P3 R50.\nN3 G90 G54 G00 X0 Y0 Z100.\nN4 G43 H2 Z100.\n\
               N5 T3 M06 H3\nN6 M30\n";
    let (samples, _) = trace(src, "mill3", Dialect::Fanuc);
    let change: Vec<_> = samples.iter().filter(|s| s.line == 5).collect();
    assert!(!change.is_empty(), "the tool change takes time");
    for s in change {
        assert!(
            (s.machine[2] - 250.0).abs() < 1e-9 && (s.tip[2] - 200.0).abs() < 1e-9,
            "t {}: {:?} {:?}",
            s.t,
            s.machine,
            s.tip
        );
    }
}
