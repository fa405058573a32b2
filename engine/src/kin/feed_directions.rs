//! The directions of the 5-axis manual feeds (spec `fanuc-twp-wsec-manual-params.md` §2.15,
//! MAN-05…MAN-17), in machine coordinates, for the axis positions of the moment.

use super::{axis_rotation, Kinematics, Side, Vec3};

/// Where the 5-axis manual feeds move the tool.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ManualDirections {
    /// Tool axis direction T (tip → holder): the reference tool direction turned by the
    /// tool-side axes (MAN-05/06).
    pub tool: Vec3,
    /// Tool axis right-angle directions 1 and 2 (MAN-07/08): with every axis at zero and no
    /// tilt, +Y and +Z for a reference tool direction along X, +Z and +X for Y, +X and +Y for
    /// Z; tilted like the reference direction (RA/RB) and turned by the tool-side axes.
    pub right_angle: [Vec3; 2],
    /// Table vertical V (MAN-14/15): the coordinate axis of the reference tool direction,
    /// turned with the table.
    pub table_vertical: Vec3,
    /// Table horizontal directions 1 and 2 (MAN-16/17): the right-angle pair at zero, turned
    /// with the table.
    pub table_horizontal: [Vec3; 2],
}

/// Which feed a manual move follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "kebab-case")]
pub enum ManualFeed {
    ToolAxis,
    RightAngle1,
    RightAngle2,
    TableVertical,
    TableHorizontal1,
    TableHorizontal2,
}

/// FANUC's latitude/longitude right-angle directions (FLL = 1, MAN-09): longitude R1 = P × T,
/// latitude R2 = T × R1 (normalised), with P the vertical axis (No.12321). When T is within
/// `parallel_deg` (No.12322) of P, the fixed pair of the table instead: P = +X: +Y, +Z;
/// P = +Y: +Z, +X; P = +Z: +X, +Y.
pub fn latitude_longitude(tool: Vec3, vertical: Vec3, parallel_deg: f64) -> [Vec3; 2] {
    let (t, p) = (tool.normalize(), vertical.normalize());
    let across = p.cross(&t);
    // The angle by atan2 (acos is ill-conditioned near parallel); a cross product too short
    // to give a direction counts as parallel whatever No.12322 says.
    let angle = across.norm().atan2(t.dot(&p).abs()).to_degrees();
    if angle <= parallel_deg || across.norm() < 1e-9 {
        let k = p.iamax();
        return [Vec3::ith((k + 1) % 3, 1.0), Vec3::ith((k + 2) % 3, 1.0)];
    }
    let r1 = across.normalize();
    [r1, t.cross(&r1).normalize()]
}

impl ManualFeed {
    /// Every feed, for lists and pickers.
    pub const ALL: [ManualFeed; 6] = [
        ManualFeed::ToolAxis,
        ManualFeed::RightAngle1,
        ManualFeed::RightAngle2,
        ManualFeed::TableVertical,
        ManualFeed::TableHorizontal1,
        ManualFeed::TableHorizontal2,
    ];
}

impl ManualDirections {
    pub fn of(&self, feed: ManualFeed) -> Vec3 {
        match feed {
            ManualFeed::ToolAxis => self.tool,
            ManualFeed::RightAngle1 => self.right_angle[0],
            ManualFeed::RightAngle2 => self.right_angle[1],
            ManualFeed::TableVertical => self.table_vertical,
            ManualFeed::TableHorizontal1 => self.table_horizontal[0],
            ManualFeed::TableHorizontal2 => self.table_horizontal[1],
        }
    }
}

impl Kinematics {
    /// The feed the ±J signal of linear axis `axis` (0 X, 1 Y, 2 Z) selects in 5-axis JOG
    /// (FANUC MAN-06/08/15/17, §6.7): the axis of the reference tool direction's code
    /// (No.19697, whatever RA/RB tilt it, TV-MAN-03e) the tool axis or table vertical feed,
    /// the next axis direction 1, the one after direction 2 (OQ-26: 19697 = 1: Y, Z; 2: Z, X).
    pub fn manual_feed_of_axis(&self, axis: usize, table_based: bool) -> Option<ManualFeed> {
        let (k, _, _) = super::reference_angles(self.tool_axis);
        let feeds = if table_based {
            [ManualFeed::TableVertical, ManualFeed::TableHorizontal1, ManualFeed::TableHorizontal2]
        } else {
            [ManualFeed::ToolAxis, ManualFeed::RightAngle1, ManualFeed::RightAngle2]
        };
        (axis < 3).then(|| feeds[(axis + 3 - k) % 3])
    }

    /// The manual feed directions at the axis positions `pos`.
    pub fn manual_directions(&self, pos: &[f64]) -> ManualDirections {
        // The reference direction's tilt (§2.9): RB about axis k after RA about the axis
        // after next, cyclic in X → Y → Z.
        let t0 = self.tool_axis;
        let (k, ra, rb) = super::reference_angles(t0);
        let tilt = axis_rotation(k, rb) * axis_rotation((k + 2) % 3, ra);
        let unit = |i: usize| Vec3::ith(i, 1.0);
        let (d1, d2) = (unit((k + 1) % 3), unit((k + 2) % 3));
        let head = self.motion(Side::Head, pos);
        let table = self.motion(Side::Table, pos);
        ManualDirections {
            tool: head.turn(t0),
            right_angle: [head.turn(tilt * d1), head.turn(tilt * d2)],
            table_vertical: table.turn(unit(k)),
            table_horizontal: [table.turn(d1), table.turn(d2)],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::machine::MachineConfig;

    fn close(a: Vec3, b: [f64; 3]) -> bool {
        (a - Vec3::new(b[0], b[1], b[2])).norm() < 1e-6
    }

    #[test]
    fn right_angle_directions_at_zero_tv_man_01() {
        for (tool, d1, d2) in [
            ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
            ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ] {
            let mut m = MachineConfig::preset("mill3").unwrap();
            m.tool_axis = tool;
            let d = Kinematics::new(&m).unwrap().manual_directions(&[0.0; 3]);
            assert!(close(d.right_angle[0], d1) && close(d.right_angle[1], d2), "{tool:?}: {d:?}");
            assert!(close(d.table_horizontal[0], d1) && close(d.table_horizontal[1], d2), "{tool:?}");
            assert!(close(d.tool, tool) && close(d.table_vertical, tool));
        }
    }

    #[test]
    fn latitude_and_longitude_tv_man_04c_to_04e() {
        let (s, c) = (0.5, 3f64.sqrt() / 2.0);
        let [r1, r2] = latitude_longitude(Vec3::new(s, 0.0, c), Vec3::z(), 1.0);
        assert!(close(r1, [0.0, 1.0, 0.0]) && close(r2, [-0.866025, 0.0, 0.5]), "{r1:?} {r2:?}");
        let h = 0.5f64.sqrt();
        let [r1, r2] = latitude_longitude(Vec3::new(0.0, h, h), Vec3::z(), 1.0);
        assert!(close(r1, [-1.0, 0.0, 0.0]) && close(r2, [0.0, -h, h]), "{r1:?} {r2:?}");
        let [r1, r2] = latitude_longitude(Vec3::new(s, 0.0, c), Vec3::x(), 1.0);
        assert!(close(r1, [0.0, -1.0, 0.0]) && close(r2, [0.866025, 0.0, -0.5]), "{r1:?} {r2:?}");
        // The tool along the vertical axis: the fixed pair of the table (P = +Z: +X, +Y).
        let [r1, r2] = latitude_longitude(Vec3::z(), Vec3::z(), 1.0);
        assert!(close(r1, [1.0, 0.0, 0.0]) && close(r2, [0.0, 1.0, 0.0]), "{r1:?} {r2:?}");
    }

    #[test]
    fn bc_head_tv_man_04() {
        let k = Kinematics::new(&MachineConfig::preset("head-bc").unwrap()).unwrap();
        let d = k.manual_directions(&[0.0, 0.0, 0.0, 30.0, 0.0]);
        assert!(close(d.tool, [0.5, 0.0, 0.866025]), "{d:?}");
        assert!(close(d.right_angle[0], [0.866025, 0.0, -0.5]) && close(d.right_angle[1], [0.0, 1.0, 0.0]), "{d:?}");
        let d = k.manual_directions(&[0.0, 0.0, 0.0, 30.0, 90.0]);
        assert!(close(d.tool, [0.0, 0.5, 0.866025]), "{d:?}");
        assert!(close(d.right_angle[0], [0.0, 0.866025, -0.5]) && close(d.right_angle[1], [-1.0, 0.0, 0.0]), "{d:?}");
    }

    #[test]
    fn parallel_fallback_tv_man_04f_04g() {
        // The tool along the vertical axis (angle 0 <= No.12322 even at 0): the fixed pair.
        for (p, d1, d2) in [
            (Vec3::x(), [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]),
            (Vec3::y(), [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]),
            (Vec3::z(), [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ] {
            let [r1, r2] = latitude_longitude(p, p, 0.0);
            assert!(close(r1, d1) && close(r2, d2), "{p:?}: {r1:?} {r2:?}");
        }
        // Numerically almost parallel with No.12322 = 0: still the fixed pair, never NaN.
        let [r1, r2] = latitude_longitude(Vec3::new(1e-17, 0.0, 1.0), Vec3::z(), 0.0);
        assert!(close(r1, [1.0, 0.0, 0.0]) && close(r2, [0.0, 1.0, 0.0]), "{r1:?} {r2:?}");
        // Within No.12322 of P counts as parallel; just outside it does not.
        let t = Vec3::new(2f64.to_radians().sin(), 0.0, 2f64.to_radians().cos());
        let [r1, _] = latitude_longitude(t, Vec3::z(), 3.0);
        assert!(close(r1, [1.0, 0.0, 0.0]), "{r1:?}");
        let [r1, _] = latitude_longitude(t, Vec3::z(), 1.0);
        assert!(close(r1, [0.0, 1.0, 0.0]), "longitude Z × T: {r1:?}");
    }

    #[test]
    fn jog_signals_select_the_feeds_tv_man_02_03_03e() {
        use ManualFeed::*;
        for (tool, expect) in [
            // 19697 = 3, RA = RB = 0: +J3 tool axis, J1 direction 1, J2 direction 2.
            ([0.0, 0.0, 1.0], [RightAngle1, RightAngle2, ToolAxis]),
            // 19697 = 3 tilted by RA = 30: still J3 (TV-MAN-03e).
            ([0.5, 0.0, 0.866_025_403_784_438_6], [RightAngle1, RightAngle2, ToolAxis]),
            // OQ-26: 19697 = 1: J2 direction 1, J3 direction 2; 19697 = 2: J3 direction 1, J1 direction 2.
            ([1.0, 0.0, 0.0], [ToolAxis, RightAngle1, RightAngle2]),
            ([0.0, 1.0, 0.0], [RightAngle2, ToolAxis, RightAngle1]),
        ] {
            let mut m = MachineConfig::preset("mill3").unwrap();
            m.tool_axis = tool;
            let k = Kinematics::new(&m).unwrap();
            let got: Vec<_> = (0..3).map(|a| k.manual_feed_of_axis(a, false).unwrap()).collect();
            assert_eq!(got, expect, "{tool:?}");
        }
        // TB_BASE = 1 (TV-MAN-03b/03c): the table feeds on the same signals.
        let k = Kinematics::new(&MachineConfig::preset("table-ac").unwrap()).unwrap();
        let got: Vec<_> = (0..3).map(|a| k.manual_feed_of_axis(a, true).unwrap()).collect();
        assert_eq!(got, [TableHorizontal1, TableHorizontal2, TableVertical]);
        assert_eq!(k.manual_feed_of_axis(3, true), None);
    }

    #[test]
    fn tilted_reference_directions_stay_perpendicular() {
        // A reference tool direction tilted by RA/RB: the pair is tilted with it.
        for tool in [[0.3, 0.2, 0.93], [0.9, 0.3, -0.2], [0.1, 0.95, 0.25], [-0.2, 0.3, 0.9]] {
            let mut m = MachineConfig::preset("mill3").unwrap();
            m.tool_axis = tool;
            let k = Kinematics::new(&m).unwrap();
            let d = k.manual_directions(&[0.0; 3]);
            let t = Vec3::new(tool[0], tool[1], tool[2]).normalize();
            assert!((d.tool - t).norm() < 1e-12);
            let [a, b] = d.right_angle;
            assert!(a.dot(&t).abs() < 1e-12 && b.dot(&t).abs() < 1e-12 && a.dot(&b).abs() < 1e-12, "{tool:?}");
            assert!((a.cross(&b) - t).norm() < 1e-12, "right-handed: dir1 × dir2 = T ({tool:?})");
        }
    }

    #[test]
    fn table_vertical_turns_with_the_table() {
        // table-ac: A (left-hand about X) at 30°: the table's vertical leans with it.
        let k = Kinematics::new(&MachineConfig::preset("table-ac").unwrap()).unwrap();
        let d = k.manual_directions(&[0.0, 0.0, 0.0, 30.0, 0.0]);
        assert!((d.table_vertical.norm() - 1.0).abs() < 1e-12 && (d.table_vertical.z - 0.866025).abs() < 1e-6);
        assert!(close(d.tool, [0.0, 0.0, 1.0]), "a table machine's tool does not tilt");
        // The tool seen from the table is the vertical seen from the machine, turned back.
        let pose = k.forward(&[0.0, 0.0, 0.0, 30.0, 0.0], 0.0);
        assert!((pose.tool.dot(&Vec3::z()) - d.table_vertical.dot(&Vec3::z())).abs() < 1e-12);
    }
}
