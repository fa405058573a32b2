//! Random machines of every kind for property tests (`docs/five-axis.md`, "Property tests over
//! random machines"): head-head, table-table, mixed, and the 4-axis head and table kinds; any two
//! of A/B/C in either chain place and either axis order; both rotation senses; axes along a
//! coordinate axis (either sign) or inclined up to 30° off it; random axis-line offsets, zero
//! errors, spindle nose and reference tool direction (RA/RB tilt off X, Y or Z); movement ranges
//! or rollover; random rates, accelerations and jerks.
//!
//! Every machine it makes passes `Kinematics::new` (the mechanism checks) with a margin: the two
//! rotary axes are at least 20° from parallel, and so is an axis from the tool direction where
//! the model refuses them parallel (the head axis next to the tool; the master of a table-table
//! machine). Nearly parallel axes are accepted by the model but make every inverse solution
//! ill-conditioned, which the 1 µm properties cannot tell from a bug.

use fivex_engine::kin::{Kinematics, MachineKind, Vec3};
use fivex_engine::machine::{Axis, AxisKind, FiveAxisOptions, Hand, MachineConfig, RotaryLink, Side};
use proptest::prelude::*;

/// The kinds the generator makes (every kind with a rotary axis).
pub const KINDS: [MachineKind; 5] =
    [MachineKind::HeadHead, MachineKind::TableTable, MachineKind::HeadTable, MachineKind::Head, MachineKind::Table];

/// The sides of each kind's chain links, head links first (as `Kinematics::joints`).
fn sides(kind: MachineKind) -> &'static [Side] {
    match kind {
        MachineKind::HeadHead => &[Side::Head, Side::Head],
        MachineKind::TableTable => &[Side::Table, Side::Table],
        MachineKind::HeadTable => &[Side::Head, Side::Table],
        MachineKind::Head => &[Side::Head],
        MachineKind::Table => &[Side::Table],
        MachineKind::ThreeAxis => &[],
    }
}

/// One rotary link's random data.
#[derive(Debug, Clone)]
struct LinkSpec {
    /// Chosen coordinate axis (0 X, 1 Y, 2 Z) offset: the actual base axis is picked so that the
    /// chain is not degenerate (see `base_axes`).
    base_pick: usize,
    negative: bool,
    /// Inclination off the coordinate axis (degrees) and the direction it leans to (degrees about it).
    tilt: f64,
    lean: f64,
    right: bool,
    point: [f64; 3],
    zero_offset: f64,
    /// 0: a movement range (and stroke) `[lo, hi]`; 1: rollover (shortest way or by sign);
    /// 2: neither (an unbounded rotary axis).
    travel: u8,
    range: [f64; 2],
    shortest: bool,
    rapid: f64,
    accel: f64,
    jerk: f64,
}

fn link_spec() -> impl Strategy<Value = LinkSpec> {
    (
        (0usize..3, any::<bool>(), prop_oneof![1 => Just(0.0), 1 => 0.0f64..30.0], 0.0f64..360.0, any::<bool>()),
        (prop::array::uniform3(-200.0f64..200.0), prop_oneof![1 => Just(0.0), 1 => -5.0f64..5.0]),
        (prop_oneof![2 => Just(0u8), 2 => Just(1u8), 1 => Just(2u8)], -150.0f64..-60.0, 60.0f64..150.0, any::<bool>()),
        (3_600.0f64..14_400.0, 500.0f64..2_500.0, 10_000.0f64..60_000.0),
    )
        .prop_map(
            |(
                (base_pick, negative, tilt, lean, right),
                (point, zero_offset),
                (travel, lo, hi, shortest),
                (rapid, accel, jerk),
            )| {
                LinkSpec {
                    base_pick,
                    negative,
                    tilt,
                    lean,
                    right,
                    point,
                    zero_offset,
                    travel,
                    range: [lo, hi],
                    shortest,
                    rapid,
                    accel,
                    jerk,
                }
            },
        )
}

fn unit(k: usize) -> Vec3 {
    let mut v = Vec3::zeros();
    v[k % 3] = 1.0;
    v
}

/// A direction `tilt`° off coordinate axis `k`, leaning toward `lean`° about it (FANUC's RA/RB
/// form of No.19697–19699 for the tool direction).
fn tilted(k: usize, tilt: f64, lean: f64) -> Vec3 {
    let (st, ct) = tilt.to_radians().sin_cos();
    let (sl, cl) = lean.to_radians().sin_cos();
    unit(k) * ct + (unit(k + 1) * cl + unit(k + 2) * sl) * st
}

/// The coordinate axes the links are built about, from the tool's axis `tool` and each link's
/// pick: the axis next to the tool on the head (and a table-table master) is not the tool's, and
/// the two links differ.
fn base_axes(kind: MachineKind, tool: usize, picks: [usize; 2]) -> [usize; 2] {
    let other = |not: usize, pick: usize| (not + 1 + pick % 2) % 3;
    match kind {
        // Master anywhere (a C master along the tool is the usual fork head), the slave off both.
        MachineKind::HeadHead => {
            let master = picks[0] % 3;
            let free: Vec<usize> = (0..3).filter(|&k| k != master && k != tool).collect();
            [master, free[picks[1] % free.len()]]
        }
        MachineKind::TableTable => {
            let master = other(tool, picks[0]);
            [master, other(master, picks[1])]
        }
        MachineKind::HeadTable => {
            let head = other(tool, picks[0]);
            [head, other(head, picks[1])]
        }
        MachineKind::Head => [other(tool, picks[0]), 0],
        _ => [picks[0] % 3, 0],
    }
}

/// Whether the mechanism keeps the generator's 20° margins.
pub fn well_formed(m: &MachineConfig) -> bool {
    let Ok(kin) = Kinematics::new(m) else { return false };
    let apart = |a: &Vec3, b: &Vec3| a.cross(b).norm() > 20f64.to_radians().sin();
    let joints = kin.joints();
    if joints.len() == 2 && !apart(&joints[0].direction, &joints[1].direction) {
        return false;
    }
    if let Some(last) = kin.head.last() {
        if !apart(&last.direction, &kin.tool_axis) {
            return false;
        }
    }
    kin.kind != MachineKind::TableTable || apart(&kin.table[0].direction, &kin.tool_axis)
}

/// A valid machine of a random kind.
pub fn random_machine() -> impl Strategy<Value = MachineConfig> {
    (0..KINDS.len()).prop_flat_map(|k| random_machine_of(KINDS[k]))
}

/// A valid machine of `kind` with random geometry.
pub fn random_machine_of(kind: MachineKind) -> impl Strategy<Value = MachineConfig> {
    let letters = Just(vec!['A', 'B', 'C']).prop_shuffle();
    let tool = (
        prop_oneof![1 => Just(0usize), 1 => Just(1usize), 4 => Just(2usize)],
        prop_oneof![1 => Just(0.0), 1 => 0.0f64..30.0],
        -180.0f64..180.0,
    );
    let linear = (10_000.0f64..40_000.0, 1_000.0f64..6_000.0, 20_000.0f64..120_000.0);
    (letters, tool, prop::array::uniform3(-40.0f64..40.0), link_spec(), link_spec(), any::<bool>(), linear)
        .prop_map(move |(letters, (tk, ra, rb), nose, l1, l2, swap_order, (rapid, accel, jerk))| {
            let tool_axis = tilted(tk, ra, rb);
            let bases = base_axes(kind, tk, [l1.base_pick, l2.base_pick]);
            let mut axes: Vec<Axis> = ['X', 'Y', 'Z']
                .map(|name| Axis {
                    accel: Some(accel),
                    jerk: Some(jerk),
                    stroke: Some([-3_000.0, 3_000.0]),
                    ..Axis::new(name, AxisKind::Linear, rapid)
                })
                .into();
            let mut rotary = Vec::new();
            let mut rotary_axes = Vec::new();
            for (i, (side, l)) in sides(kind).iter().zip([l1, l2]).enumerate() {
                let mut direction = tilted(bases[i], l.tilt, l.lean);
                if l.negative {
                    direction = -direction;
                }
                // A head axis passes near the spindle (a pivot above the nose); a table axis
                // anywhere under the table.
                let point = match side {
                    Side::Head => [l.point[0] / 4.0, l.point[1] / 4.0, l.point[2].abs()],
                    Side::Table => l.point,
                };
                let range = (l.travel == 0).then_some(l.range);
                rotary.push(RotaryLink {
                    axis: letters[i],
                    side: *side,
                    direction: direction.into(),
                    hand: if l.right { Hand::Right } else { Hand::Left },
                    point,
                    zero_offset: l.zero_offset,
                    fixed: None,
                    range,
                });
                rotary_axes.push(Axis {
                    accel: Some(l.accel),
                    jerk: Some(l.jerk),
                    stroke: range,
                    rollover: l.travel == 1,
                    shortest: l.travel == 1 && l.shortest,
                    ..Axis::new(letters[i], AxisKind::Rotary, l.rapid)
                });
            }
            if swap_order {
                rotary_axes.reverse();
            }
            axes.extend(rotary_axes);
            MachineConfig {
                name: format!("random-{kind:?}"),
                axes,
                rotary,
                tool_axis: tool_axis.into(),
                nose,
                holder: 0.0,
                sub_chains: Vec::new(),
                chains: Vec::new(),
                motion: Default::default(),
                five_axis: FiveAxisOptions::default(),
                manual: Default::default(),
                cycles: Default::default(),
            }
        })
        .prop_filter("a mechanism the model accepts with margin", well_formed)
}

/// Commanded angles of the machine's rotary axes (axis order, other axes 0) that lie inside
/// every movement range by `margin` degrees: `fractions` (each in [0, 1)) pick them.
pub fn angles_inside(m: &MachineConfig, fractions: &[f64], margin: f64) -> Vec<f64> {
    let mut q = vec![0.0; m.axes.len()];
    for (i, a) in m.axes.iter().enumerate() {
        if a.kind != AxisKind::Rotary {
            continue;
        }
        let link = m.rotary.iter().find(|l| l.axis == a.name).expect("a link per rotary axis");
        let [lo, hi] = link.range.map_or([-170.0, 170.0], |[lo, hi]| [lo + margin, hi - margin]);
        q[i] = lo + (hi - lo) * fractions[i % fractions.len()];
    }
    q
}
