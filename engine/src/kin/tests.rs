use super::*;
use crate::dialect::Dialect;
use crate::machine::{Axis, Hand, RotaryLink};
use proptest::prelude::*;

fn kin(preset: &str) -> Kinematics {
    Kinematics::new(&MachineConfig::preset(preset).unwrap()).unwrap()
}

/// The spec examples' machine: the preset's mechanism without movement ranges (the examples
/// turn B to 270°, beyond the preset's ±110°).
fn spec_machine(preset: &str) -> MachineConfig {
    let mut m = MachineConfig::preset(preset).unwrap();
    for l in &mut m.rotary {
        l.range = None;
    }
    m
}

fn close(a: Vec3, b: [f64; 3], tol: f64) -> bool {
    (a - vec3(b)).norm() < tol
}

const FANUC: Selection = Selection { dialect: Dialect::Fanuc, pri: false, p: 0 };

/// The rotary angles (B, C on head-bc) FANUC chooses for a tool direction from a position.
fn chosen(k: &Kinematics, tool: [f64; 3], from: &[f64], how: Selection) -> Result<Vec<f64>, AlarmId> {
    let candidates = k.inverse(Vec3::zeros(), vec3(tool), 0.0, from);
    k.select(&candidates, from, how).map(|c| c.pos[3..].to_vec())
}

use crate::alarm::AlarmId;

/// The hand calculations of `docs/machine-config.md` ("By hand").
#[test]
fn forward_by_hand_on_the_presets() {
    // head-bc (pivot 150 above the nose), tool 100 long, X10 Y20 Z30 B90: the pivot is at
    // (10, 20, 180); B90 lays the tool along +X, so the nose is 150 and the tip 250 toward −X.
    let p = kin("head-bc").forward(&[10.0, 20.0, 30.0, 90.0, 0.0], 100.0);
    assert!(close(p.tool, [1.0, 0.0, 0.0], 1e-12));
    assert!(close(p.tip, [-240.0, 20.0, 180.0], 1e-12));
    // Then C90 turns it about Z to +Y.
    let p = kin("head-bc").forward(&[0.0, 0.0, 0.0, 90.0, 90.0], 100.0);
    assert!(close(p.tool, [0.0, 1.0, 0.0], 1e-12));
    assert!(close(p.tip, [0.0, -250.0, 150.0], 1e-12));
    // table-ac (A line 120 below the table top): A90 (left hand about X) turns the table by −90°
    // about that line: the tip at machine (0, 0, 50), 170 above the line, is at table
    // (0, −170, −120), and seen from the table the tool points −Y.
    let p = kin("table-ac").forward(&[0.0, 0.0, 50.0, 90.0, 0.0], 0.0);
    assert!(close(p.tip_machine, [0.0, 0.0, 50.0], 1e-12));
    assert!(close(p.tool, [0.0, -1.0, 0.0], 1e-12));
    assert!(close(p.tip, [0.0, -170.0, -120.0], 1e-12));
    // Every preset points the tool along the table's +Z at zero angles, the tip at the nose.
    for name in MachineConfig::PRESETS {
        let k = kin(name);
        let p = k.forward(&vec![0.0; k.axes], 50.0);
        assert!(close(p.tool, [0.0, 0.0, 1.0], 1e-12) && close(p.tip, [0.0, 0.0, -50.0], 1e-12), "{name}");
    }
    // Tool directions (table frame) of the presets' rotary axes.
    let tool = |name: &str, pos: &[f64]| kin(name).forward(pos, 0.0).tool;
    assert!(close(tool("head-bc", &[0.0, 0.0, 0.0, 0.0, 37.0]), [0.0, 0.0, 1.0], 1e-12), "C alone never tilts");
    // Table B at +90 (left hand about +Y): the tool lies along the part's +X.
    assert!(close(tool("table-bc", &[0.0, 0.0, 0.0, 90.0, 0.0]), [1.0, 0.0, 0.0], 1e-12));
    // Mixed: head B +90 gives machine +X; table C +90 (left hand) shows it as part +Y.
    assert!(close(tool("mixed-bc", &[0.0, 0.0, 0.0, 90.0, 90.0]), [0.0, 1.0, 0.0], 1e-12));
}

/// fanuc-tcp.md §3.1 (TV-01 … TV-05): BC machine, tool axis Z, C master about Z, B slave about
/// Y. The extract's pairs (B90, C180) and (B270, C0) point the tool along −X with right-hand
/// axes (`v = Rz(C)·Ry(B)·ẑ`, the convention of the O100 example; spec Q-3): the tests command −X.
#[test]
fn fanuc_type2_selection_tv01_to_tv05() {
    let k = Kinematics::new(&spec_machine("head-bc")).unwrap();
    // Axis order X Y Z B C.
    let cands = k.inverse(Vec3::zeros(), Vec3::new(-1.0, 0.0, 0.0), 0.0, &[0.0; 5]);
    let mut pairs: Vec<(f64, f64)> = cands.iter().map(|c| (c.pos[3].round(), c.pos[4].round())).collect();
    pairs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(pairs, vec![(90.0, 180.0), (270.0, 0.0)]);
    let bc = |b: f64, c: f64| [0.0, 0.0, 0.0, b, c];
    let run = |from: [f64; 5]| chosen(&k, [-1.0, 0.0, 0.0], &from, FANUC).unwrap();
    let round = |v: Vec<f64>| v.iter().map(|x| (x * 1e9).round() / 1e9).collect::<Vec<_>>();
    assert_eq!(round(run(bc(-70.0, 30.0))), vec![-90.0, 0.0], "TV-01");
    assert_eq!(round(run(bc(80.0, 500.0))), vec![90.0, 540.0], "TV-02");
    assert_eq!(round(run(bc(60.0, 90.0))), vec![90.0, 180.0], "TV-03");
    assert_eq!(round(run(bc(180.0, 90.0))), vec![270.0, 0.0], "TV-04");
    // TV-05: +Z is the singular posture (B0): C stays.
    assert_eq!(round(chosen(&k, [0.0, 0.0, 1.0], &bc(45.0, 90.0), FANUC).unwrap()), vec![0.0, 90.0], "TV-05");
    // TV-18/TV-19: PRI judges the slave first.
    let pri = Selection { pri: true, ..FANUC };
    assert_eq!(round(chosen(&k, [-1.0, 0.0, 0.0], &bc(60.0, 90.0), pri).unwrap()), vec![90.0, 180.0], "TV-18");
    assert_eq!(round(chosen(&k, [-1.0, 0.0, 0.0], &bc(-70.0, 30.0), pri).unwrap()), vec![-90.0, 0.0], "TV-19");
}

/// TV-13 … TV-17 (constructed in the extract from §2.3.19): a master with the two basic angles
/// 10° and 190° for one direction — here the C master of head-bc, whose solutions are (C, B) and
/// (C + 180, −B); the extract's "A" is this master.
#[test]
fn fanuc_movement_ranges_tv13_to_tv17() {
    let mut m = spec_machine("head-bc");
    let k = Kinematics::new(&m).unwrap();
    let v = k.forward(&[0.0, 0.0, 0.0, 30.0, 10.0], 0.0).tool;
    // (B, C) chosen from C = 350, B = 0.
    let pick = |k: &Kinematics| {
        let from = [0.0, 0.0, 0.0, 0.0, 350.0];
        let cands = k.inverse(Vec3::zeros(), v, 0.0, &from);
        k.select(&cands, &from, FANUC).map(|c| ((c.pos[3] * 1e6).round() / 1e6, (c.pos[4] * 1e6).round() / 1e6))
    };
    assert_eq!(pick(&k), Ok((30.0, 370.0)), "TV-13: 10 + 360 is 20 away");
    m.rotary[0].range = Some([0.0, 360.0]);
    assert_eq!(pick(&Kinematics::new(&m).unwrap()), Ok((-30.0, 190.0)), "TV-14: 370 is out of range");
    m.rotary[0].range = Some([360.0, 0.0]);
    assert_eq!(pick(&Kinematics::new(&m).unwrap()), Err(AlarmId::NoRotarySolution), "TV-15: lower > upper");
    m.rotary[0].range = Some([20.0, 30.0]);
    assert_eq!(pick(&Kinematics::new(&m).unwrap()), Err(AlarmId::NoRotarySolution), "TV-16: nothing fits");
    m.rotary[0].range = Some([0.0, 0.0]);
    assert_eq!(pick(&Kinematics::new(&m).unwrap()), Ok((30.0, 370.0)), "TV-17: 0/0 is no range");
}

/// syntec.md TV-33: spindle C–B (right hand), the Zc of TV-32 (C −60, B 15 or C 120, B −15):
/// P0 takes the master's shortest path from 0.
#[test]
fn syntec_p0_p1_p2_tv33() {
    let k = Kinematics::new(&spec_machine("head-bc")).unwrap();
    let v = k.forward(&[0.0, 0.0, 0.0, 15.0, -60.0], 0.0).tool;
    let run = |p: u8| {
        let how = Selection { dialect: Dialect::Syntec, pri: false, p };
        chosen(&k, [v.x, v.y, v.z], &[0.0; 5], how)
            .map(|x| x.iter().map(|a| (a * 1e9).round() / 1e9).collect::<Vec<_>>())
    };
    assert_eq!(run(0), Ok(vec![15.0, -60.0]));
    assert_eq!(run(1), Ok(vec![-15.0, 120.0]));
    assert_eq!(run(2), Ok(vec![15.0, -60.0]));
    assert_eq!(run(3), Err(AlarmId::AlignmentP));
}

#[test]
fn syntec_ranges_fall_back_and_then_fail() {
    let mut m = spec_machine("head-bc");
    // Master C allowed only from 90° to 180°: the shortest-path C −60 is out, C 120 fits.
    m.rotary[0].range = Some([90.0, 180.0]);
    let k = Kinematics::new(&m).unwrap();
    let v = k.forward(&[0.0, 0.0, 0.0, 15.0, -60.0], 0.0).tool;
    let from = [0.0, 0.0, 0.0, 0.0, 100.0];
    let how = Selection { dialect: Dialect::Syntec, pri: false, p: 0 };
    let c = k.select(&k.inverse(Vec3::zeros(), v, 0.0, &from), &from, how).unwrap();
    assert!((c.pos[4] - 120.0).abs() < 1e-9 && (c.pos[3] + 15.0).abs() < 1e-9, "{:?}", c.pos);
    // P1 from C100 turns +20° to 120 — inside; P2 would turn −40° to 60 — outside: COR-153.
    let p2 = Selection { p: 2, ..how };
    assert_eq!(k.select(&k.inverse(Vec3::zeros(), v, 0.0, &from), &from, p2), Err(AlarmId::NoRotarySolution));
}

/// Manual §2.1 note 7: with P1 or P2 a target (or path) out of range is COR-153, not the other
/// solution (P0's fallback, note 6). From C0 P2 turns −60° to (B15, C−60); with the slave B
/// allowed only from 270° to 0° that is out, and the other solution (B−15, reached by C −240°)
/// is not taken. The same for P1 with B allowed from 0° to 90°.
#[test]
fn syntec_p1_and_p2_do_not_fall_back() {
    let solve = |range: [f64; 2], p: u8| {
        let mut m = spec_machine("head-bc");
        m.rotary[1].range = Some(range);
        let k = Kinematics::new(&m).unwrap();
        let v = k.forward(&[0.0, 0.0, 0.0, 15.0, -60.0], 0.0).tool;
        let from = [0.0; 5];
        let how = Selection { dialect: Dialect::Syntec, pri: false, p };
        k.select(&k.inverse(Vec3::zeros(), v, 0.0, &from), &from, how)
            .map(|c| [c.pos[3], c.pos[4]].map(|a| (a * 1e9).round() / 1e9))
    };
    assert_eq!(solve([270.0, 0.0], 2), Err(AlarmId::NoRotarySolution));
    assert_eq!(solve([270.0, 0.0], 1), Ok([-15.0, 120.0]));
    assert_eq!(solve([270.0, 0.0], 0), Ok([-15.0, 120.0]), "P0 falls back");
    assert_eq!(solve([0.0, 90.0], 1), Err(AlarmId::NoRotarySolution));
    assert_eq!(solve([0.0, 90.0], 2), Ok([15.0, -60.0]));
}

/// P0 with the master's two paths equally long (Q-25, decision): the smaller slave travel. From
/// (B30, C0) to the tool of (B30, C−90) the master turns 90° either way; (B−30, C90) would swing
/// the tool 60° through the vertical. A direction given to six digits chooses alike.
#[test]
fn syntec_p0_breaks_a_master_tie_on_the_slave() {
    let k = Kinematics::new(&spec_machine("head-bc")).unwrap();
    let from = [0.0, 0.0, 0.0, 30.0, 0.0];
    let how = Selection { dialect: Dialect::Syntec, pri: false, p: 0 };
    let exact = k.forward(&[0.0, 0.0, 0.0, 30.0, -90.0], 0.0).tool;
    let six_digits = exact.map(|x| (x * 1e6).round() / 1e6);
    for v in [exact, six_digits, Vec3::new(6e-7, exact.y, exact.z)] {
        let c = k.select(&k.inverse(Vec3::zeros(), v, 0.0, &from), &from, how).unwrap();
        assert!((c.pos[3] - 30.0).abs() < 1e-3 && (c.pos[4] + 90.0).abs() < 1e-3, "{v:?}: {:?}", c.pos);
    }
}

/// The singular posture of each kind: the tool along the axis at the workpiece end of the chain,
/// where the inverse leaves that axis free (and keeps it where it is).
#[test]
fn singular_postures_are_detected() {
    let angle =
        |preset: &str, pos: &[f64]| kin(preset).singularity(pos).map(|s| (s.axis, (s.angle * 1e9).round() / 1e9));
    assert_eq!(angle("head-bc", &[0.0, 0.0, 0.0, 0.0, 77.0]), Some(('C', 0.0)));
    assert_eq!(angle("head-bc", &[0.0, 0.0, 0.0, 30.0, 77.0]), Some(('C', 30.0)));
    assert_eq!(angle("head-bc", &[0.0, 0.0, 0.0, -180.0, 77.0]), Some(('C', 0.0)), "pointing down the axis");
    assert_eq!(angle("table-ac", &[0.0, 0.0, 0.0, 0.0, 10.0]), Some(('C', 0.0)));
    assert_eq!(angle("table-ac", &[0.0, 0.0, 0.0, 90.0, 10.0]), Some(('C', 90.0)));
    assert_eq!(angle("mixed-bc", &[0.0, 0.0, 0.0, -45.0, 10.0]), Some(('C', 45.0)));
    assert_eq!(angle("mill3", &[0.0; 3]), None);
    // At the singular posture the inverse marks the axis free and keeps its current angle.
    let k = kin("table-ac");
    let from = [0.0, 0.0, 0.0, 0.0, 123.0];
    let c = k.inverse(Vec3::zeros(), Vec3::new(0.0, 0.0, 1.0), 0.0, &from);
    assert!(c.iter().all(|c| c.free[..] == [false, true] && c.pos[4] == 123.0), "{c:?}");
}

/// Near the singular posture the inverse keeps its digits: a direction 10⁻⁸…10⁻⁴ rad off the
/// singular line (below 10⁻⁹ the axis counts as free) comes back from every candidate's forward
/// kinematics within 10⁻¹⁵ (the tool
/// side's angle was found from a difference of numbers near 1, with an error of 1.5·10⁻⁸ rad:
/// the first micrometres of a way from the posture ran a linear axis's jerk 9 % over).
#[test]
fn the_inverse_keeps_its_digits_near_the_singular_posture() {
    for preset in ["head-bc", "table-ac", "table-bc", "mixed-bc"] {
        let k = kin(preset);
        for e in 4..=8 {
            let tilt = 10f64.powi(-e);
            for azimuth in [0.3f64, 2.0, -1.1] {
                let v = Vec3::new(tilt.sin() * azimuth.cos(), tilt.sin() * azimuth.sin(), tilt.cos());
                let candidates = k.inverse(Vec3::zeros(), v, 0.0, &[0.0; 5]);
                assert!(!candidates.is_empty(), "{preset}: no candidate {tilt} rad off");
                for c in &candidates {
                    let back = k.forward(&c.pos, 0.0).tool;
                    assert!((back - v).norm() < 1e-15, "{preset}, {tilt} rad off: back {back:?}, not {v:?}");
                }
            }
        }
    }
}

#[test]
fn unreachable_directions_have_no_candidate() {
    // A single table C axis cannot tilt the tool.
    let m = MachineConfig {
        name: "c-table".into(),
        axes: "XYZC"
            .chars()
            .map(|n| Axis::new(n, if n == 'C' { AxisKind::Rotary } else { AxisKind::Linear }, 1.0))
            .collect(),
        rotary: vec![RotaryLink {
            axis: 'C',
            side: Side::Table,
            direction: [0.0, 0.0, 1.0],
            hand: Hand::Left,
            point: [0.0; 3],
            zero_offset: 0.0,
            fixed: None,
            range: None,
        }],
        tool_axis: [0.0, 0.0, 1.0],
        nose: [0.0; 3],
        holder: 0.0,
        sub_chains: Vec::new(),
        chains: Vec::new(),
        motion: Default::default(),
        five_axis: Default::default(),
        manual: Default::default(),
        cycles: Default::default(),
    };
    let k = Kinematics::new(&m).unwrap();
    assert_eq!(k.kind, MachineKind::Table);
    assert!(k.inverse(Vec3::zeros(), Vec3::new(1.0, 0.0, 0.0), 0.0, &[0.0; 4]).is_empty());
    assert_eq!(k.inverse(Vec3::zeros(), Vec3::new(0.0, 0.0, 1.0), 0.0, &[0.0; 4]).len(), 1);
    assert!(kin("mill3").inverse(Vec3::zeros(), Vec3::new(0.0, 1.0, 0.0), 0.0, &[0.0; 3]).is_empty());
}

/// A random machine of every kind: inclined axes, both hands, offsets, zero errors.
fn machine() -> impl Strategy<Value = MachineConfig> {
    let unit = (-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0)
        .prop_filter("a direction", |(x, y, z)| (x * x + y * y + z * z).sqrt() > 0.3)
        .prop_map(|(x, y, z)| [x, y, z]);
    let point = (-300.0f64..300.0, -300.0f64..300.0, -300.0f64..300.0).prop_map(|(x, y, z)| [x, y, z]);
    let link = (unit.clone(), point.clone(), any::<bool>(), -5.0f64..5.0);
    (0usize..6, link.clone(), link, unit, point).prop_map(|(kind, l1, l2, tool_axis, nose)| {
        let sides: &[Side] = match kind {
            0 => &[],
            1 => &[Side::Head, Side::Head],
            2 => &[Side::Table, Side::Table],
            3 => &[Side::Head, Side::Table],
            4 => &[Side::Head],
            _ => &[Side::Table],
        };
        let names = ['B', 'C'];
        let mut axes: Vec<Axis> = ['X', 'Y', 'Z'].iter().map(|&name| Axis::new(name, AxisKind::Linear, 1.0)).collect();
        let mut rotary = Vec::new();
        for (i, (side, l)) in sides.iter().zip([l1, l2]).enumerate() {
            axes.push(Axis::new(names[i], AxisKind::Rotary, 1.0));
            rotary.push(RotaryLink {
                axis: names[i],
                side: *side,
                direction: l.0,
                hand: if l.2 { Hand::Right } else { Hand::Left },
                point: l.1,
                zero_offset: l.3,
                fixed: None,
                range: None,
            });
        }
        MachineConfig {
            name: "random".into(),
            axes,
            rotary,
            tool_axis,
            nose,
            holder: 0.0,
            sub_chains: Vec::new(),
            chains: Vec::new(),
            motion: Default::default(),
            five_axis: Default::default(),
            manual: Default::default(),
            cycles: Default::default(),
        }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    /// ik(fk(q)) contains q (rotary angles modulo 360), and every candidate's fk reproduces the
    /// tip and the direction.
    #[test]
    fn inverse_of_forward(m in machine(), q in prop::collection::vec(-400.0f64..400.0, 5), length in 0.0f64..200.0) {
        let Ok(k) = Kinematics::new(&m) else { return Ok(()) };
        let q = &q[..k.axes];
        let pose = k.forward(q, length);
        let cands = k.inverse(pose.tip, pose.tool, length, q);
        let same = |a: &[f64]| a.iter().zip(q).enumerate().all(|(i, (x, y))| {
            if i < 3 { (x - y).abs() < 1e-6 } else { ((x - y).rem_euclid(360.0) + 1e-7).rem_euclid(360.0) < 1e-6 }
        });
        prop_assert!(cands.iter().any(|c| same(&c.pos)), "{:?} not among {:?}", q, cands);
        for c in &cands {
            let p = k.forward(&c.pos, length);
            prop_assert!((p.tip - pose.tip).norm() < 1e-9 * (1.0 + pose.tip.norm()), "tip {:?} vs {:?}", p.tip, pose.tip);
            prop_assert!((p.tool - pose.tool).norm() < 1e-9, "tool {:?} vs {:?}", p.tool, pose.tool);
        }
    }

    /// `reach` is exactly the set the inverse solves: every posture of the axes is inside it,
    /// and a direction is solved where it is inside and not where it is outside.
    #[test]
    fn reach_is_where_the_inverse_has_solutions(
        m in machine(),
        q in prop::collection::vec(-400.0f64..400.0, 5),
        direction in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let Ok(k) = Kinematics::new(&m) else { return Ok(()) };
        let Some(reach) = k.reach() else { return Ok(()) };
        let q = &q[..k.axes];
        let tool = k.forward(q, 0.0).tool;
        prop_assert!(reach.slack(&tool) > -1e-12, "{q:?} gives {tool:?}, slack {}", reach.slack(&tool));
        let Some(v) = Vec3::from(direction).try_normalize(1e-3) else { return Ok(()) };
        let (slack, solved) = (reach.slack(&v), !k.inverse(Vec3::zeros(), v, 0.0, q).is_empty());
        prop_assert!(slack.abs() < 1e-6 || solved == (slack > 0.0), "{v:?}: slack {slack}, solved {solved}");
    }

    /// With movement ranges (FANUC No.19741–19744): whenever the posture of `q`, which lies in
    /// the ranges, is asked for, a choice exists, every chosen rotary angle lies in its range,
    /// and it reproduces the tip and direction. Syntec P0 likewise with cyclic ranges around q.
    #[test]
    fn choices_respect_movement_ranges(
        m in machine(),
        q in prop::collection::vec(-170.0f64..170.0, 5),
        from in prop::collection::vec(-400.0f64..400.0, 5),
        widths in (5.0f64..200.0, 5.0f64..200.0),
        length in 0.0f64..200.0,
    ) {
        let mut m = m;
        let spans = [widths.0, widths.1];
        for (k, l) in m.rotary.iter_mut().enumerate() {
            let i = m.axes.iter().position(|a| a.name == l.axis).unwrap();
            l.range = Some([q[i] - spans[k] / 2.0, q[i] + spans[k] / 2.0]);
        }
        let Ok(kin) = Kinematics::new(&m) else { return Ok(()) };
        let n = kin.axes;
        let (q, from) = (&q[..n], &from[..n]);
        let pose = kin.forward(q, length);
        let cands = kin.inverse(pose.tip, pose.tool, length, from);
        // Haas takes FANUC's cascade (`docs/dialects.md`, "Haas 5-axis"): the same choice.
        let fanuc = kin.select(&cands, from, Selection { dialect: Dialect::Fanuc, pri: false, p: 0 });
        let haas = kin.select(&cands, from, Selection { dialect: Dialect::Haas, pri: false, p: 0 });
        prop_assert_eq!(&fanuc, &haas);
        for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
            let how = Selection { dialect, pri: false, p: 0 };
            let choice = kin.select(&cands, from, how);
            if dialect == Dialect::Syntec && choice.is_err() {
                // Syntec also needs the swept path inside the range, which `from` may not allow.
                continue;
            }
            let choice = choice.map_err(|e| TestCaseError::fail(format!("{dialect:?}: {e:?} for {q:?} from {from:?}")))?;
            for j in kin.joints() {
                let (i, [lo, hi]) = (j.index.unwrap(), j.range.unwrap());
                let a = choice.pos[i];
                let inside = match dialect {
                    Dialect::Fanuc | Dialect::Haas => a >= lo - 1e-6 && a <= hi + 1e-6,
                    Dialect::Syntec => (a - lo).rem_euclid(360.0) <= hi - lo + 1e-6,
                };
                prop_assert!(inside, "{dialect:?} axis {} at {a} outside [{lo}, {hi}]", j.name);
            }
            let p = kin.forward(&choice.pos, length);
            prop_assert!((p.tip - pose.tip).norm() < 1e-9 * (1.0 + pose.tip.norm()));
            prop_assert!((p.tool - pose.tool).norm() < 1e-9);
        }
    }
}

/// G53.1 after the tilted planes of TV-TWP-01 and -03 (spec `fanuc-twp-wsec-manual-params.md`):
/// the tool must lie along the frame's Z (`twp::euler`), chosen by FANUC's cascade.
#[test]
fn tool_axis_control_tv_twp_05_and_06() {
    let k = Kinematics::new(&spec_machine("head-bc")).unwrap();
    // TV-TWP-06: T = (1, 0, 0) from (B90, C−90): masters both move 90 → the slave's smaller
    // move decides, (B90, C0).
    let z = crate::twp::euler(Vec3::zeros(), 90.0, 90.0, 0.0).z();
    assert!((z - Vec3::x()).norm() < 1e-12);
    let got = chosen(&k, z.into(), &[0.0, 0.0, 0.0, 90.0, -90.0], FANUC).unwrap();
    assert!((got[0] - 90.0).abs() < 1e-9 && got[1].abs() < 1e-9, "{got:?}");
    // TV-TWP-05: T = (0, −1, 0): the candidates are (B90, C270≡−90) and (B270≡−90, C90).
    let z = crate::twp::euler(Vec3::zeros(), 0.0, 90.0, 0.0).z();
    let mut pairs: Vec<(f64, f64)> =
        k.inverse(Vec3::zeros(), z, 0.0, &[0.0; 5]).iter().map(|c| (c.pos[3].round(), c.pos[4].round())).collect();
    pairs.sort_by(|a, b| a.partial_cmp(b).unwrap());
    assert_eq!(pairs, vec![(90.0, 270.0), (270.0, 90.0)]);
}
