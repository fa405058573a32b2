//! Manual handle interruption and INC mode (`docs/five-axis.md`, 5-axis manual operation; spec
//! `fanuc-twp-wsec-manual-params.md` MAN-04, MAN-06/08/12/15/17 "JOG / INC", the global
//! restrictions, WSE-24): handle pulses in AUTO/MDI shift the machine under the running
//! program; each JOG key press of INC mode moves by the panel's increment.
#![allow(clippy::approx_constant)]

use fivex_engine::canon::Pos;
use fivex_engine::controller::{Controller, ManualSignals, Mode, Refusal, RunState};
use fivex_engine::interp::Config;
use fivex_engine::kin::{Kinematics, Vec3};
use fivex_engine::machine::MachineConfig;
use fivex_engine::Dialect;

const TICK: f64 = 0.002;

fn controller(name: &str) -> Controller {
    let mut m = MachineConfig::preset(name).unwrap();
    // The handle select codes of the 5-axis feeds (No.12310–12314).
    m.manual.handle_codes = [10, 11, 12, 13, 14];
    let mut c = Controller::new(Config::new(m, Dialect::Fanuc));
    for n in 1..=5 {
        c.interpreter_mut().state.offsets.tool_mut(n).unwrap().h_geometry = 50.0 * n as f64;
    }
    c
}

fn signals(alngh: bool, rghth: bool, rndh: bool, handle_select: u8) -> ManualSignals {
    ManualSignals { alngh, rghth, rndh, tb_base: false, handle_select }
}

/// Tick until the controller stops running (at most `limit` s); the machine positions.
fn settle(c: &mut Controller, limit: f64) -> Vec<Pos> {
    let start = c.time();
    let mut xs = Vec::new();
    while c.run_state() == RunState::Running && c.time() - start < limit {
        c.tick(TICK);
        xs.push(c.point().machine);
    }
    // Whatever the handle still moves.
    for _ in 0..500 {
        c.tick(TICK);
    }
    xs
}

/// Start `src` in AUTO and run it for `secs` s.
fn start(c: &mut Controller, src: &str, secs: f64) {
    c.set_mode(Mode::Auto).unwrap();
    c.select_program(src).unwrap();
    c.cycle_start().unwrap();
    let t = c.time();
    while c.time() - t < secs {
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Running, "{:?}", c.alarms());
}

fn near(a: &[f64], b: &[f64], tol: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < tol)
}

/// mill3: Y +2 by the handle (select code 2 = the second axis) in the middle of an X block.
/// The block goes on to its X end, the machine is 2 mm off in Y from then on (the next block
/// too, and a later program), the absolute position never shows it; reset keeps it, the
/// reference return clears it.
#[test]
fn interruption_mid_block_on_mill3() {
    let mut c = controller("mill3");
    c.set_manual_signals(signals(false, false, false, 2)).unwrap();
    start(&mut c, "G90 G01 X100. Y0 Z0 F600\nY10.\nM30\n", 1.0);
    let x_before = c.point().machine[0];
    assert!(x_before > 1.0 && x_before < 20.0, "mid block: X {x_before}");
    assert_eq!(c.handle_pulses(2.0), Ok(2.0));
    let mut xs = Vec::new();
    let mut shifts = Vec::new();
    for _ in 0..200 {
        c.tick(TICK);
        xs.push(c.point());
        shifts.push(c.interrupt_shift()[1]);
    }
    // The program goes on: X keeps moving, the absolute Y stays 0 while the machine's leaves.
    assert!(xs.last().unwrap().machine[0] > x_before + 1.0);
    assert!(xs.iter().all(|p| p.work[1].abs() < 1e-12), "absolute Y stays");
    assert!(shifts.windows(2).all(|w| w[1] >= w[0] - 1e-12), "the shift grows to its amount");
    assert!((shifts.last().unwrap() - 2.0).abs() < 1e-9, "{:?}", shifts.last());
    // Each sample: machine = program (absolute, no offsets on mill3) + shift.
    for (p, s) in xs.iter().zip(&shifts) {
        assert!((p.machine[1] - (p.work[1] + s)).abs() < 1e-9 && (p.machine[0] - p.work[0]).abs() < 1e-9);
    }
    let ys: Vec<f64> = xs.iter().map(|p| p.machine[1]).collect();
    let top = ys.windows(2).map(|w| (w[1] - w[0]).abs() / TICK).fold(0.0, f64::max);
    assert!(top > 1.0 && top <= 30_000.0 / 60.0 + 1e-6, "Y at most at its rapid rate: {top} mm/s");
    settle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    let p = c.point();
    assert!(near(&p.machine[..3], &[100.0, 12.0, 0.0], 1e-9), "N2 shifted too: {:?}", p.machine);
    assert!(near(&p.work[..3], &[100.0, 10.0, 0.0], 1e-9), "absolute without the shift: {:?}", p.work);
    // A later program is shifted too.
    start(&mut c, "G90 G00 X0 Y0\nM30\n", 0.01);
    settle(&mut c, 60.0);
    assert!(near(&c.point().machine[..3], &[0.0, 2.0, 0.0], 1e-9), "{:?}", c.point().machine);
    assert!(near(&c.point().work[..3], &[0.0, 0.0, 0.0], 1e-9));
    // Reset keeps it (and INC right after it moves from where the machine stands).
    c.reset();
    assert!((c.interrupt_shift()[1] - 2.0).abs() < 1e-12 && (c.point().work[1]).abs() < 1e-9);
    // JOG in between moves machine and absolute alike.
    c.set_mode(Mode::Inc).unwrap();
    c.set_increment(1.0).unwrap();
    c.jog_start('Y', true).unwrap();
    settle(&mut c, 5.0);
    assert!(near(&c.point().machine[..2], &[0.0, 3.0], 1e-9) && near(&c.point().work[..2], &[0.0, 1.0], 1e-9));
    // The reference return clears it: at machine zero the absolute is the machine's again.
    c.set_mode(Mode::Ref).unwrap();
    c.reference_return().unwrap();
    settle(&mut c, 10.0);
    assert_eq!(c.interrupt_shift(), [0.0; fivex_engine::machine::MAX_AXES]);
    assert!(near(&c.point().machine[..3], &[0.0; 3], 1e-9) && near(&c.point().work[..3], &[0.0; 3], 1e-9));
    start(&mut c, "G90 G00 X0 Y5.\nM30\n", 0.01);
    settle(&mut c, 60.0);
    assert!(near(&c.point().machine[..2], &[0.0, 5.0], 1e-9), "{:?}", c.point().machine);
}

/// head-bc at B30: the tool axis direction handle interrupt (ALNGH, code No.12310) during an X
/// block shifts the machine along the tool, (0.5, 0, 0.866) × 4 mm, and the block ends there.
#[test]
fn tool_axis_interruption_on_a_head_machine() {
    let mut c = controller("head-bc");
    c.set_manual_signals(signals(true, false, false, 10)).unwrap();
    start(&mut c, "G90 G00 X0 Y0 Z0 B30. C0\nG01 X100. F600\nM30\n", 1.5);
    assert!(c.point().machine[0] > 1.0, "in N2");
    assert_eq!(c.handle_pulses(4.0), Ok(4.0));
    settle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    let s = c.interrupt_shift();
    let along = Vec3::new(0.5, 0.0, 0.866_025_403_784_438_6) * 4.0;
    assert!(near(&s[..3], &[along.x, along.y, along.z], 1e-9) && s[3] == 0.0 && s[4] == 0.0, "{s:?}");
    let p = c.point().machine;
    assert!(near(&p, &[100.0 + along.x, 0.0, along.z, 30.0, 0.0], 1e-9), "{p:?}");
    // The tool tip moved along the tool axis only: the shift is (tool direction) × amount.
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let d = kin.manual_directions(&p).tool;
    assert!((Vec3::new(s[0], s[1], s[2]).normalize() - d).norm() < 1e-9);
}

/// The 5-axis handle interrupt is refused while a block that moves a rotary axis executes
/// (S000-IV §2 note 2): the pulses are discarded without an alarm; an ordinary axis's interrupt
/// is not restricted; once the rotary block is over, the 5-axis feed is taken again.
#[test]
fn five_axis_interruption_refused_during_a_rotary_block() {
    let mut c = controller("head-bc");
    c.set_manual_signals(signals(true, false, false, 10)).unwrap();
    start(&mut c, "G90 G00 X0 Y0 Z0 B0 C0\nG01 X20. B30. F300\nG01 X40.\nM30\n", 1.0);
    assert!(c.point().machine[3] > 0.1 && c.point().machine[3] < 29.0, "in the B block");
    assert_eq!(c.handle_pulses(3.0), Ok(0.0), "5-axis feed during a rotary block");
    assert_eq!(c.interrupt_shift(), [0.0; fivex_engine::machine::MAX_AXES]);
    assert!(c.alarms().is_empty());
    // Tip rotation (RNDH, code 13) is a 5-axis feed too.
    c.set_manual_signals(signals(false, false, true, 13)).unwrap();
    assert_eq!(c.handle_pulses(5.0), Ok(0.0), "tip rotation during a rotary block");
    assert_eq!(c.interrupt_shift(), [0.0; fivex_engine::machine::MAX_AXES]);
    // An ordinary axis: Y by 1.
    let mut c2 = controller("head-bc");
    c2.set_manual_signals(signals(false, false, false, 2)).unwrap();
    start(&mut c2, "G90 G00 X0 Y0 Z0 B0 C0\nG01 X20. B30. F300\nG01 X40.\nM30\n", 1.0);
    assert_eq!(c2.handle_pulses(1.0), Ok(1.0), "an ordinary axis is not restricted");
    settle(&mut c2, 60.0);
    assert!(near(&c2.point().machine, &[40.0, 1.0, 0.0, 30.0, 0.0], 1e-9), "{:?}", c2.point().machine);
    // Held in the rotary block: still refused; in N3 (no rotary motion) taken.
    let mut c3 = controller("head-bc");
    c3.set_manual_signals(signals(true, false, false, 10)).unwrap();
    start(&mut c3, "G90 G00 X0 Y0 Z0 B0 C0\nG01 X20. B30. F300\nG01 X40.\nM30\n", 1.0);
    c3.feed_hold();
    for _ in 0..500 {
        c3.tick(TICK);
    }
    assert_eq!(c3.run_state(), RunState::Hold);
    assert_eq!(c3.handle_pulses(3.0), Ok(0.0), "held in the rotary block");
    c3.cycle_start().unwrap();
    let t = c3.time();
    while c3.point().machine[0] < 25.0 && c3.time() - t < 30.0 {
        c3.tick(TICK);
    }
    assert_eq!(c3.handle_pulses(3.0), Ok(3.0), "N3 moves no rotary axis");
    settle(&mut c3, 60.0);
    let along = Vec3::new(0.5, 0.0, 0.866_025_403_784_438_6) * 3.0;
    assert!(near(&c3.point().machine, &[40.0 + along.x, 0.0, along.z, 30.0, 0.0], 1e-9));
}

/// Where the interrupt is taken: AUTO/MDI with a program under way. AUTO at rest has nothing to
/// interrupt; an emergency stop or alarm refuses; pulses while the earlier ones still move are
/// discarded; a bad amount is refused.
#[test]
fn interruption_refusals() {
    let mut c = controller("mill3");
    c.set_manual_signals(signals(false, false, false, 1)).unwrap();
    assert_eq!(c.handle_pulses(1.0), Err(Refusal::WrongMode), "AUTO at rest");
    start(&mut c, "G90 G01 X100. F600\nM30\n", 0.5);
    assert_eq!(c.handle_pulses(f64::INFINITY), Err(Refusal::BadValue));
    assert_eq!(c.handle_pulses(5.0), Ok(5.0));
    c.tick(TICK);
    assert_eq!(c.handle_pulses(5.0), Ok(0.0), "still following the earlier pulses");
    assert_eq!(c.set_manual_signals(signals(false, false, false, 2)), Err(Refusal::Busy), "pulses moving");
    settle(&mut c, 60.0);
    assert!(near(&c.point().machine[..1], &[105.0], 1e-9));
    // During a program the select code may change (the pulses at rest).
    start(&mut c, "G90 G01 X0 F600\nM30\n", 0.5);
    c.set_manual_signals(signals(false, false, false, 2)).unwrap();
    assert_eq!(c.handle_pulses(-1.0), Ok(-1.0));
    settle(&mut c, 60.0);
    assert!(near(&c.point().machine[..2], &[5.0, -1.0], 1e-9), "{:?}", c.point().machine);
    c.set_mode(Mode::Jog).unwrap();
    assert_eq!(c.handle_pulses(1.0), Err(Refusal::WrongMode), "JOG: no handle");
    c.set_mode(Mode::Inc).unwrap();
    assert_eq!(c.handle_pulses(1.0), Err(Refusal::WrongMode), "INC: no handle");
}

/// The strokes hold on the shifted position: the pulses are cut so that the machine and every
/// end point queued ahead stay inside (mill3 X ±600); a later block that the shift carries over
/// the stroke raises the over-travel alarm before it moves.
#[test]
fn interruption_keeps_the_strokes() {
    let mut c = controller("mill3");
    c.set_manual_signals(signals(false, false, false, 1)).unwrap();
    start(&mut c, "G90 G01 X590. F6000\nG04 X0.5\nG00 X595.\nM30\n", 0.2);
    let taken = c.handle_pulses(50.0).unwrap();
    assert!((taken - 10.0).abs() < 1e-6, "what X590 leaves of the stroke: {taken}");
    c.tick(TICK);
    let mut xs = settle(&mut c, 60.0);
    xs.push(c.point().machine);
    assert!(xs.iter().all(|p| p[0] <= 600.0 + 1e-6), "inside the stroke");
    assert_eq!(c.run_state(), RunState::Alarm, "N3 would reach X605");
    let a = &c.alarms()[0];
    assert!(a.code.starts_with("OT") && a.line == 3, "{a:?}");
    assert!(near(&c.point().machine[..1], &[600.0], 1e-6), "stopped before N3: {:?}", c.point().machine);
}

/// WSE-24: the handle interrupt is not compensated by G54.4: with a 10° rotation error about Z
/// the program's X move is rotated, the interrupt's X amount is a plain machine X shift.
#[test]
fn interruption_bypasses_g54_4() {
    let mut c = controller("mill3");
    c.set_manual_signals(signals(false, false, false, 1)).unwrap();
    // Error set 1: rotation 10° about Z (#26015: set 1, about Z).
    let src = "#26015=10.\nG90\nG54.4 P1\nG01 X100. Y0 Z0 F600\nG01 X100. Y10.\nM30\n";
    start(&mut c, src, 1.0);
    assert_eq!(c.handle_pulses(5.0), Ok(5.0));
    settle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    assert!(near(&c.interrupt_shift()[..3], &[5.0, 0.0, 0.0], 1e-12), "{:?}", c.interrupt_shift());
    // The program's end point, compensated, plus the plain X shift.
    let (s, co) = (10f64.to_radians().sin(), 10f64.to_radians().cos());
    let (x, y) = (100.0 * co - 10.0 * s, 100.0 * s + 10.0 * co);
    let p = c.point().machine;
    assert!(near(&p[..2], &[x + 5.0, y], 1e-6), "{p:?} vs {x} {y}");
}

// --- INC mode --------------------------------------------------------------------------------

/// INC: each JOG key press moves the axis by the increment at the jog feed, stopping at the
/// stroke; jog stop does not cut it short; the increment is positive and finite.
#[test]
fn inc_mode_moves_by_the_increment() {
    let mut c = controller("mill3");
    c.set_mode(Mode::Inc).unwrap();
    assert_eq!(c.mode(), Mode::Inc);
    assert_eq!(serde_json::to_string(&Mode::Inc).unwrap(), "\"inc\"");
    assert_eq!(c.panel.increment, 0.001, "FANUC ×1");
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(c.set_increment(bad), Err(Refusal::BadValue));
    }
    c.set_increment(0.1).unwrap();
    for _ in 0..3 {
        c.jog_start('X', true).unwrap();
        c.jog_stop();
        settle(&mut c, 5.0);
    }
    assert!(near(&c.point().machine[..3], &[0.3, 0.0, 0.0], 1e-9), "{:?}", c.point().machine);
    c.set_increment(1.0).unwrap();
    c.jog_start('Z', false).unwrap();
    let xs = settle(&mut c, 5.0);
    assert!(near(&c.point().machine[..3], &[0.3, 0.0, -1.0], 1e-9));
    // At the jog feed (1000 mm/min by default): 1 mm takes at least 60 ms.
    let top = xs.windows(2).map(|w| (w[1][2] - w[0][2]).abs() / TICK).fold(0.0, f64::max);
    assert!(top <= 1000.0 / 60.0 + 1e-6 && top > 10.0, "{top}");
    // The stroke: Z +300.
    c.set_increment(1000.0).unwrap();
    c.jog_start('Z', true).unwrap();
    settle(&mut c, 120.0);
    assert!((c.point().machine[2] - 300.0).abs() < 1e-9);
    // INC is a mode of its own: HANDLE's commands are refused, and JOG's in other modes.
    assert_eq!(c.handle('X', 1.0), Err(Refusal::WrongMode));
    c.set_mode(Mode::Handle).unwrap();
    assert_eq!(c.jog_start('X', true), Err(Refusal::WrongMode));
}

/// INC through the 5-axis families (MAN-06/08/12 "JOG / INC"): ALNGH + ±J of the 19697 axis
/// moves the increment along the tool; RGHTH along direction 1; RNDH turns the rotary axis by
/// the increment in degrees about the tool tip.
#[test]
fn inc_mode_drives_the_five_axis_feeds() {
    let mut c = controller("head-bc");
    c.set_mode(Mode::Mdi).unwrap();
    c.set_mdi("G90 G00 X0 Y0 Z0 B30. C0").unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 30.0);
    c.set_mode(Mode::Inc).unwrap();
    c.set_increment(2.0).unwrap();
    c.set_manual_signals(signals(true, false, false, 0)).unwrap();
    c.jog_signal('Z', true).unwrap();
    settle(&mut c, 5.0);
    let p = c.point().machine;
    assert!(near(&p[..3], &[1.0, 0.0, 1.732_050_807_568_877_2], 1e-9), "{p:?}");
    c.set_manual_signals(signals(false, true, false, 0)).unwrap();
    c.jog_signal('X', false).unwrap();
    settle(&mut c, 5.0);
    let q = c.point().machine;
    // Direction 1 at B30 C0 is (0.866, 0, −0.5): −2 mm of it.
    assert!(near(&q[..3], &[1.0 - 1.732_050_807_568_877_2, 0.0, 1.732_050_807_568_877_2 + 1.0], 1e-9), "{q:?}");
    c.set_manual_signals(signals(false, false, true, 0)).unwrap();
    let kin = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
    let length = c.manual_tool_length();
    let tip = kin.forward(&q, length).tip;
    c.jog_signal('B', true).unwrap();
    settle(&mut c, 10.0);
    let r = c.point().machine;
    assert!((r[3] - 32.0).abs() < 1e-9, "B by the increment: {r:?}");
    assert!((kin.forward(&r, length).tip - tip).norm() < 1e-6, "about the tool tip");
    // The direct entry points too.
    c.jog_direction(fivex_engine::kin::ManualFeed::ToolAxis, false).unwrap();
    settle(&mut c, 5.0);
    let d = kin.manual_directions(&r).tool;
    let s = c.point().machine;
    assert!((Vec3::new(s[0] - r[0], s[1] - r[1], s[2] - r[2]) + d * 2.0).norm() < 1e-9);
    c.jog_tip_rotation('B', false).unwrap();
    settle(&mut c, 10.0);
    assert!((c.point().machine[3] - 30.0).abs() < 1e-9);
}

/// A manual intervention (INC in a held program) with a handle interrupt shift in force: the
/// hand moves go from where the machine stands, the shift stays on the rest of the program.
#[test]
fn inc_intervention_with_an_interrupt_shift() {
    let mut c = controller("mill3");
    c.set_manual_signals(signals(false, false, false, 2)).unwrap();
    start(&mut c, "G90 G01 X50. F600\nG01 X60.\nM30\n", 1.0);
    assert_eq!(c.handle_pulses(3.0), Ok(3.0));
    for _ in 0..200 {
        c.tick(TICK);
    }
    c.feed_hold();
    for _ in 0..500 {
        c.tick(TICK);
    }
    assert_eq!(c.run_state(), RunState::Hold);
    let held = c.point().machine;
    c.set_mode(Mode::Inc).unwrap();
    c.set_increment(1.0).unwrap();
    c.jog_start('Z', true).unwrap();
    settle(&mut c, 5.0);
    let p = c.point().machine;
    assert!(near(&p[..3], &[held[0], held[1], held[2] + 1.0], 1e-9), "{p:?} from {held:?}");
    c.set_mode(Mode::Auto).unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 60.0);
    assert_eq!(c.run_state(), RunState::Idle, "{:?}", c.alarms());
    // Manual absolute on: the programmed end points, plus the interrupt's Y.
    assert!(near(&c.point().machine[..3], &[60.0, 3.0, 0.0], 1e-9), "{:?}", c.point().machine);
}

// --- properties ------------------------------------------------------------------------------

mod properties {
    use super::*;
    use proptest::prelude::*;

    const PROGRAMS: &[&str] = &[
        "G90 G00 X0 Y0 Z0 B0 C0\nG01 X50. Y20. F1200\nG00 X-40. Z-20.\nG01 B20. C30. F3000\nG01 X10. Y-30. Z10. F900\nM30\n",
        "G90 G00 X10. Y10. Z0 B30. C0\nG02 X30. Y10. R10. F800\nG01 Z-30. F2000\nG00 B-20. C90.\nG01 X-20. F1500\nM30\n",
    ];

    /// Run program `k`, with `pulses` (tick, select code, signals family, amount) as handle
    /// interrupts; the samples (machine, work, shift) at every tick.
    fn run(k: usize, pulses: &[(usize, u8, u8, f64)]) -> (Vec<(Pos, Pos, Pos)>, Controller) {
        let mut c = controller("head-bc");
        c.select_program(PROGRAMS[k]).unwrap();
        c.cycle_start().unwrap();
        let mut out = Vec::new();
        for n in 0..6000 {
            for &(at, code, family, amount) in pulses {
                if at == n {
                    let s = signals(family == 1, family == 2, family == 3, code);
                    if c.set_manual_signals(s).is_ok() {
                        let taken = c.handle_pulses(amount).unwrap();
                        assert!(
                            taken == 0.0 || (taken.signum() == amount.signum() && taken.abs() <= amount.abs() + 1e-12)
                        );
                    }
                }
            }
            c.tick(TICK);
            let p = c.point();
            out.push((p.machine, p.work, c.interrupt_shift()));
        }
        (out, c)
    }

    fn pulse() -> impl Strategy<Value = (usize, u8, u8, f64)> {
        // Codes 1…5 the axes, 10…14 the 5-axis feeds (ALNGH, RGHTH, RNDH as `family`).
        (0usize..3000, prop::sample::select(vec![0u8, 1, 2, 3, 4, 5, 10, 11, 12, 13, 14]), 0u8..4, -5.0..5.0f64)
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

        /// Handle interrupts at random times never change the program: at every sample the
        /// machine position minus the shift and the absolute position are those of the run
        /// without them; the machine stays inside every stroke, and no axis moves faster than
        /// its rapid rate plus the handle's clamp (the two motions superimpose).
        #[test]
        fn interrupts_leave_the_program_alone(k in 0usize..2, pulses in prop::collection::vec(pulse(), 0..6)) {
            let (plain, c0) = run(k, &[]);
            prop_assert!(c0.alarms().is_empty(), "{:?}", c0.alarms());
            prop_assert_eq!(c0.run_state(), RunState::Idle, "the whole program compared");
            let (shifted, c) = run(k, &pulses);
            prop_assert!(c.alarms().is_empty(), "{:?}", c.alarms());
            let m = MachineConfig::preset("head-bc").unwrap();
            let rolled = |d: f64, i: usize| if m.axes[i].rollover { let d = d.rem_euclid(360.0); d.min(360.0 - d) } else { d.abs() };
            for (n, ((pm, pw, _), (sm, sw, s))) in plain.iter().zip(&shifted).enumerate() {
                for i in 0..5 {
                    prop_assert!(rolled(sm[i] - s[i] - pm[i], i) < 1e-9, "tick {} axis {}: {} - {} vs {}", n, i, sm[i], s[i], pm[i]);
                    prop_assert!((sw[i] - pw[i]).abs() < 1e-9, "absolute, tick {} axis {}", n, i);
                    if let Some([lo, hi]) = m.axes[i].stroke {
                        prop_assert!(sm[i] >= lo - 1e-6 && sm[i] <= hi + 1e-6);
                    }
                }
            }
            for w in shifted.windows(2) {
                for i in 0..5 {
                    let top = 2.0 * m.axes[i].rapid / 60.0 * TICK * (1.0 + 1e-6) + 1e-9;
                    prop_assert!(rolled(w[1].0[i] - w[0].0[i], i) <= top, "axis {} jumped", i);
                }
            }
        }
    }
}

/// Tool tip centre rotation as a handle interrupt (RNDH, code No.12313: the first rotary axis
/// of the mechanism, C on head-bc): C turns by the amount and X/Y/Z by what keeps the tool tip;
/// on a head machine that displacement depends on the angles only, so the block ends with the
/// tip where the program puts it. An emergency stop keeps the shift (the machine does not move
/// back); a single-block stop takes interrupts like a running block.
#[test]
fn tip_rotation_interruption_keeps_the_tip() {
    let mut c = controller("head-bc");
    c.set_manual_signals(signals(false, false, true, 13)).unwrap();
    c.panel.single_block = true;
    c.set_mode(Mode::Auto).unwrap();
    c.select_program("G90 G00 X0 Y0 Z0 B30. C0\nG01 X50. F600\nG01 Y20.\nM30\n").unwrap();
    c.cycle_start().unwrap();
    settle(&mut c, 30.0);
    assert_eq!(c.run_state(), RunState::Idle, "at the single-block stop after N1");
    assert_eq!(c.handle_pulses(10.0), Ok(10.0), "a block stop is automatic operation");
    settle(&mut c, 30.0);
    let s = c.interrupt_shift();
    assert!((s[4] - 10.0).abs() < 1e-9 && s[3] == 0.0 && s[0].abs() > 0.1, "{s:?}");
    c.cycle_start().unwrap();
    settle(&mut c, 30.0);
    let m = MachineConfig::preset("head-bc").unwrap();
    let kin = Kinematics::new(&m).unwrap();
    let length = c.manual_tool_length();
    let mut planned = [0.0; fivex_engine::machine::MAX_AXES];
    (planned[0], planned[3]) = (50.0, 30.0);
    let real = c.point().machine;
    assert!((real[4] - 10.0).abs() < 1e-9, "{real:?}");
    let (a, b) = (kin.forward(&real, length).tip, kin.forward(&planned, length).tip);
    assert!((a - b).norm() < 1e-6, "the tip where the program puts it: {a:?} vs {b:?}");
    // N3 under way: an emergency stop keeps the shift.
    c.cycle_start().unwrap();
    for _ in 0..300 {
        c.tick(TICK);
    }
    c.emergency_stop(true);
    c.tick(TICK);
    assert!((c.interrupt_shift()[4] - 10.0).abs() < 1e-9);
    let p = c.point();
    assert!((p.machine[4] - 10.0).abs() < 1e-9 && p.work[4].abs() < 1e-9, "{p:?}");
}

/// A reset in a held program with a shift: at once (no tick in between) the manual modes move
/// from where the machine stands, and the absolute position stays without the shift.
#[test]
fn reset_hands_the_machine_position_back_at_once() {
    let mut c = controller("mill3");
    c.set_manual_signals(signals(false, false, false, 2)).unwrap();
    start(&mut c, "G90 G01 X50. F600\nM30\n", 1.0);
    assert_eq!(c.handle_pulses(4.0), Ok(4.0));
    for _ in 0..300 {
        c.tick(TICK);
    }
    c.feed_hold();
    for _ in 0..500 {
        c.tick(TICK);
    }
    let held = c.point();
    assert!((held.machine[1] - 4.0).abs() < 1e-9 && held.work[1].abs() < 1e-9);
    c.reset();
    c.set_mode(Mode::Inc).unwrap();
    c.set_increment(0.5).unwrap();
    c.jog_start('Y', true).unwrap();
    settle(&mut c, 5.0);
    let p = c.point();
    assert!(near(&p.machine[..2], &[held.machine[0], 4.5], 1e-9), "{:?}", p.machine);
    assert!(near(&p.work[..2], &[held.work[0], 0.5], 1e-9), "{:?}", p.work);
}

/// In a cutter compensation for 5-axis machining (here the tool side offset G41.2 under
/// G43.4) S000 §3.5.1 makes the manual handle interruption unusable (its pulses are discarded:
/// no alarm is named) and a manual interruption operation a PS alarm (PS5460, the mode's;
/// nothing moves). Cutter compensation C (G41) keeps both.
#[test]
fn five_axis_cutter_compensation_takes_no_handle_interruption_and_no_intervention() {
    let program = |comp: &str| {
        let head = if comp == "G41.2" { "G43.4 H1\n" } else { "G43 H1\n" };
        format!("G90 G00 X-50. Y0 Z0 B0 C0\n{head}{comp} D1\nG01 X0 F1000.\nX100.\nG40 X150.\nG49\nM30\n")
    };
    for (comp, five_axis) in [("G41.2", true), ("G41", false)] {
        let run = || {
            let mut c = controller("head-bc");
            c.interpreter_mut().state.offsets.tool_mut(1).unwrap().d_geometry = 5.0;
            c.set_manual_signals(signals(false, false, false, 2)).unwrap();
            start(&mut c, &program(comp), 4.0);
            c
        };
        let mut c = run();
        let taken = c.handle_pulses(2.0).unwrap();
        assert_eq!(taken, if five_axis { 0.0 } else { 2.0 }, "{comp}: handle interruption");
        let mut c2 = run();
        c2.feed_hold();
        settle(&mut c2, 2.0);
        assert_eq!(c2.run_state(), RunState::Hold, "{comp}");
        let at = c2.point().machine;
        assert_eq!(c2.set_mode(Mode::Jog), Ok(()));
        let alarm = c2.alarms().first().map(|a| a.code.clone());
        if five_axis {
            assert_eq!((alarm.as_deref(), c2.run_state()), (Some("PS5460"), RunState::Alarm), "{comp}");
            assert_eq!(c2.point().machine, at, "{comp}: nothing moved");
        } else {
            assert_eq!(alarm, None, "{comp}: an intervention");
        }
    }
}
