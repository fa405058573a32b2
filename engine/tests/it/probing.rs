//! The skip function with a workpiece on the table (`interp::skip`, `crate::workpiece`): on every
//! machine kind the machine stops where the probe's ball first touches a box — the ball read
//! from the sampled axes by forward kinematics, as the trace reads the tip — and no sample
//! before puts it into a box.

use crate::common;

use common::{cases, interpreter_with};
use fivex_engine::kin::Vec3;
use fivex_engine::machine::{AxisKind, MachineConfig};
use fivex_engine::run::{run, RunOptions, RunResult, Sample};
use fivex_engine::vendor::{self, ParamFile};
use fivex_engine::workpiece::{Cuboid, Workpiece};
use fivex_engine::Dialect;
use proptest::prelude::*;

/// The radius of D1 in `common::interpreter_with`: the stylus ball.
const BALL: f64 = 5.0;

fn machine(name: &str) -> (MachineConfig, Dialect) {
    if let Some(m) = MachineConfig::preset(name) {
        return (m, Dialect::Fanuc);
    }
    let path = format!("{}/../machines/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let f: ParamFile = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let m = vendor::machine_from(f.dialect, &f.name, &f.parameters).unwrap_or_else(|e| panic!("{name}: {e:?}"));
    (m, f.dialect)
}

const MACHINES: [&str; 8] =
    ["mill3", "head-bc", "table-ac", "table-bc", "mixed-bc", "haas-umc-750", "haas-vf2-tr160", "haas-vf2-hrt160"];

fn run_on(m: &MachineConfig, dialect: Dialect, src: &str, workpiece: &Workpiece) -> (RunResult, Vec<Sample>) {
    let mut interp = interpreter_with(src, "mill3", dialect, |c| {
        c.machine = m.clone().into();
        c.workpiece = workpiece.clone().into();
    });
    let mut samples = Vec::new();
    let options = RunOptions { max_time_s: 120.0, period_s: 0.001, ..RunOptions::default() };
    let r = run(&mut interp, &options, |s| samples.push(*s));
    assert!(r.completed(), "{:?} in\n{src}", r.alarms);
    (r, samples)
}

/// The stylus ball's centre at a sample: the tip in the table frame, up the tool by the radius.
fn centre(s: &Sample) -> Vec3 {
    Vec3::from(s.tip_table) + Vec3::from(s.tool) * BALL
}

fn distance(b: &Cuboid, p: Vec3) -> f64 {
    let d: [f64; 3] = std::array::from_fn(|k| (b.min[k] - p[k]).max(p[k] - b.max[k]).max(0.0));
    Vec3::from(d).norm()
}

/// The machine's axes at fractions of their strokes (rotary axes without one: −170…170°).
fn axis_words(m: &MachineConfig, fractions: &[f64]) -> String {
    let mut s = String::new();
    for (a, f) in m.axes.iter().zip(fractions) {
        let [lo, hi] = match (a.stroke, a.kind) {
            (Some(r), _) => r,
            (None, AxisKind::Rotary) => [-170.0, 170.0],
            (None, _) => [-200.0, 200.0],
        };
        s += &format!(" {}{:.3}", a.name, lo + (hi - lo) * f);
    }
    s
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(24), ..ProptestConfig::default() })]

    /// From a random pose (rotary axes anywhere, X/Y/Z in the middle of their strokes) the probe
    /// feeds 30–60 mm toward a point around which a box of half-size 1–10 mm sits on the table:
    /// it starts clear of the box and must touch it. The machine stops with the ball on the box
    /// (its centre at the radius, 1e-6 mm), no sample of the move puts the ball into the box,
    /// and #5061… hold the programmed point where it stopped.
    #[test]
    fn the_probe_stops_on_the_box_on_every_machine(
        which in 0..MACHINES.len(),
        fractions in proptest::collection::vec(0.35f64..0.65, 6),
        rotary in proptest::collection::vec(0.05f64..0.95, 6),
        direction in proptest::array::uniform3(-1.0f64..1.0),
        length in 30.0f64..60.0,
        half in 1.0f64..10.0,
    ) {
        let (m, dialect) = machine(MACHINES[which]);
        let d = Vec3::from(direction);
        prop_assume!(d.norm() > 0.2);
        let step = d.normalize() * length;
        let fractions: Vec<f64> = m.axes.iter().enumerate()
            .map(|(i, a)| if a.kind == AxisKind::Rotary { rotary[i] } else { fractions[i] })
            .collect();
        let src = format!(
            "G90 G21 G40 G49 G80\nG53 G00{}\nG43 H1 D1\nG91 G31 X{:.4} Y{:.4} Z{:.4} F500.\nG04 P100\n#100=#5061\n#101=#5062\n#102=#5063\nG90\nM30\n",
            axis_words(&m, &fractions), step.x, step.y, step.z
        );
        // Where the ball's centre ends without a workpiece: the box goes around it.
        let (_, free) = run_on(&m, dialect, &src, &Workpiece::default());
        let probe_line = 4;
        let moves: Vec<&Sample> = free.iter().filter(|s| s.line == probe_line).collect();
        prop_assume!(!moves.is_empty());
        let target = centre(moves[moves.len() - 1]);
        let b = Cuboid { min: (target - Vec3::repeat(half)).into(), max: (target + Vec3::repeat(half)).into() };
        let workpiece = Workpiece { boxes: vec![b] };

        let (r, samples) = run_on(&m, dialect, &src, &workpiece);
        let on_line: Vec<&Sample> = samples.iter().filter(|s| s.line == probe_line).collect();
        prop_assert!(!on_line.is_empty());
        let first = centre(on_line[0]);
        prop_assert!(distance(&b, first) > BALL, "starts touching: {}", distance(&b, first));
        for s in &on_line {
            prop_assert!(distance(&b, centre(s)) >= BALL - 1e-9, "{}: inside the box at t={}", MACHINES[which], s.t);
        }
        // At rest in the dwell after the move.
        let last = samples.last().unwrap();
        let gap = distance(&b, centre(last)) - BALL;
        prop_assert!(gap.abs() < 1e-6, "{}: stopped {gap} mm off the box", MACHINES[which]);
        let skip: Vec<f64> = (100..103).map(|n| r.variables.iter().find(|(k, _)| *k == n).unwrap().1).collect();
        for (k, (v, at)) in skip.iter().zip(last.programmed).enumerate() {
            prop_assert!((v - at).abs() < 1e-6, "#{} = {v} but the machine stopped at {:?}", 5061 + k, last.programmed);
        }
    }
}

/// A move that turns a rotary axis toward a workpiece is not built, nor a probe without length
/// compensation: both refused at their block.
#[test]
fn what_the_skip_does_not_model_is_refused() {
    let (m, _) = machine("table-ac");
    let workpiece = Workpiece { boxes: vec![Cuboid { min: [0.0, 0.0, -20.0], max: [50.0, 40.0, 0.0] }] };
    for (src, line) in [("G43 H1\nG31 X10. C10. F100.\nM30\n", 2), ("G49\nG31 Z-10. F100.\nM30\n", 2)] {
        let mut interp = interpreter_with(src, "mill3", Dialect::Fanuc, |c| {
            c.machine = m.clone().into();
            c.workpiece = workpiece.clone().into();
        });
        let r = run(&mut interp, &RunOptions::default(), |_| {});
        assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("PS0010", line), "{src}");
    }
}

/// A controller under machine lock or Z-axis neglect probes with the axes that really move:
/// the locked probe touches nothing (the skip ends at the end point), and after the lock the
/// probe starts from where the machine really stands.
#[test]
fn a_locked_axis_does_not_carry_the_probe() {
    use fivex_engine::controller::{Controller, RunState};
    use fivex_engine::interp::Config;
    let controller = || {
        let mut cfg = Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc);
        cfg.workpiece =
            Workpiece { boxes: vec![Cuboid { min: [-10.0, -10.0, -50.0], max: [10.0, 10.0, -20.0] }] }.into();
        Controller::new(cfg)
    };
    let run = |c: &mut Controller, src: &str| {
        c.select_program(src).unwrap();
        c.cycle_start().unwrap();
        let start = c.time();
        while c.run_state() == RunState::Running && c.time() - start < 60.0 {
            c.tick(0.001);
        }
        c.interpreter().state.common_variables().iter().find(|(n, _)| *n == 100).map(|(_, v)| *v)
    };
    // The tool table is empty: H1 has length 0 and D0 radius 0, the probe is a point at the nose.
    let probe = "G90 G43 H1 G31 Z-40. F3000.\n#100=#5063\nM30\n";
    assert_eq!(run(&mut controller(), probe), Some(-20.0), "free: it touches the top");

    let mut locked = controller();
    locked.set_machine_lock(true).unwrap();
    assert_eq!(run(&mut locked, probe), Some(-40.0), "locked: nothing moves, nothing is touched");
    let mut neglected = controller();
    neglected.set_z_neglect(true).unwrap();
    assert_eq!(run(&mut neglected, probe), Some(-40.0), "Z neglected: the probe stays up");

    // Unlocked again: the machine stands at Z0, the program's coordinates at Z-40. An
    // incremental skip of 40 mm down touches the top after 20 mm of real travel: Z-60 in the
    // program's coordinates.
    locked.set_machine_lock(false).unwrap();
    assert_eq!(run(&mut locked, "G91 G31 Z-40. F3000.\n#100=#5063\nM30\n"), Some(-60.0));
}

/// Under Haas DWO (G254) on a UMC, the table turned B20 C30, a skip move straight down the
/// machine's Z (DWO's axes are the machine's, `docs/dialects.md`) from above the work origin
/// touches the part's tilted top: the ball's centre stops r from the top plane, whose normal
/// makes the tilt θ with the spindle, so at (top + r)/cos θ above the carried origin, and the
/// tip, r below it along the spindle, at (top + r)/cos θ − r. (Under TCPC, G234, G31 is refused by
/// the interlock of the modes, as FANUC's G43.4 list leaves it out.)
#[test]
fn under_dwo_the_tilted_ball_touches_the_top() {
    let (m, dialect) = machine("haas-umc-750");
    let g54 = m.rotary[0].point;
    let top = 10.0;
    let part = Cuboid {
        min: [g54[0] - 30.0, g54[1] - 30.0, g54[2] - 20.0],
        max: [g54[0] + 30.0, g54[1] + 30.0, g54[2] + top],
    };
    let src = format!(
        "G10 L2 P1 X{:.4} Y{:.4} Z{:.4}\nG90 G54 G17 G00 B0 C0\nG43 H1 D1 Z150.\nB20. C30.\nG254\nX0 Y0 Z80.\nG31 Z-20. F300.\nG04 P100\n#100=#5063\nG255\nM30\n",
        g54[0], g54[1], g54[2]
    );
    let (r, samples) = run_on(&m, dialect, &src, &Workpiece { boxes: vec![part] });
    let last = samples.last().unwrap();
    let tilt_cos = last.tool[2];
    assert!(tilt_cos < 0.99, "the tool is tilted: {:?}", last.tool);
    let z = r.variables.iter().find(|(n, _)| *n == 100).unwrap().1;
    let want = (top + BALL) / tilt_cos - BALL;
    assert!((z - want).abs() < 1e-6, "#5063 = {z}, the tilted ball touches with the tip at {want}");
    assert!((distance(&part, centre(last)) - BALL).abs() < 1e-6);
    let refused = format!(
        "G10 L2 P1 X{:.4} Y{:.4} Z{:.4}\nG90 G54 G00 B0 C0\nG234 H1 D1\nX0 Y0 Z80.\nG31 Z-20. F300.\nM30\n",
        g54[0], g54[1], g54[2]
    );
    let mut interp = interpreter_with(&refused, "mill3", dialect, |c| c.machine = m.clone().into());
    let r = run(&mut interp, &RunOptions::default(), |_| {});
    assert_eq!((r.alarms[0].code.as_str(), r.alarms[0].line), ("731", 5));
}
