//! Workpiece setting error compensation in programs (FANUC G54.4, spec
//! `fanuc-twp-wsec-manual-params.md` WSE-01…WSE-26): the error data sets beside the work
//! offsets (`State::setting_errors`, macro variables #26000…#26077), the effective error of a
//! set, and how positions follow it. Geometry: `crate::wse`; decisions: `docs/five-axis.md`,
//! "Workpiece setting error compensation (G54.4)".
//!
//! While a set is in effect, programmed points are in the workpiece setting coordinate system
//! (WSCS): `State::pos` holds WSCS coordinates and X/Y/Z go to the WCS as `R_e·p + Δ` before the
//! work offsets are added (`State::program_to_machine`), so lines stay lines. The rotary axes
//! are left as programmed (tool direction compensation, RCM = 1, is not modelled yet). A circle
//! whose plane the error tilts is a circle in space: every G02/G03 under G54.4 therefore runs as
//! a tool tip path (`canon::TipMove`) with the tool length as a plain G43 applies it (along Z).
//! G54.4 Pn and P0 do not move the machine: the current point is recomputed in the new system.

use super::nc::Words;
use super::tcp::FollowPath;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, MotionKind, Pos};
use crate::kin::{Kinematics, Vec3};
use crate::machine::{AxisKind, Side, MAX_AXES};
use crate::twp::Frame;
use crate::wse::{self, ErrorSet};

/// The set in effect.
#[derive(Debug, Clone, Copy)]
pub(super) struct Active {
    /// 1…7.
    pub(super) set: u8,
    /// The effective error (COMMON + set, at table position 0): the WSCS in the WCS.
    pub(super) frame: Frame,
    /// The indices of the basic axes X, Y, Z.
    xyz: [usize; 3],
}

impl State {
    /// The number of the set in effect and its effective error (the WSCS as a frame in the
    /// WCS), as the "active workpiece setting error" screen shows them (WSE-07).
    pub fn active_setting_error(&self) -> Option<(u8, Frame)> {
        self.wse.map(|a| (a.set, a.frame))
    }

    /// The effective error of set `n` (1…7): COMMON's and the set's translations added, the
    /// set's rotation, each first converted to table machine position 0 when the machine turns
    /// its table (WSE-03, WSE-04, §2.13.3).
    pub fn effective_setting_error(&self, n: usize) -> Frame {
        let sets = &self.setting_errors.sets;
        let common = self.at_table_zero(&sets[0], [0.0; 3]);
        let set = sets.get(n).copied().unwrap_or_default();
        wse::effective(&common, &self.at_table_zero(&set, set.rotation))
    }

    /// One set's error as a frame, converted to table machine position 0.
    fn at_table_zero(&self, s: &ErrorSet, rotation: [f64; 3]) -> Frame {
        let e = wse::frame(s.shift, rotation);
        match &self.kinematics {
            Some(kin) if kin.joints().iter().any(|j| j.side == Side::Table && j.index.is_some()) => {
                wse::at_table_zero(&e, &self.table_motion(kin, s.table))
            }
            _ => e,
        }
    }

    /// The table's motion from machine position 0 to `table` (table position 1 = the master
    /// or only table axis, 2 = the slave) as seen in the WCS: an ideal workpiece point's WCS
    /// coordinates at position 0 → its WCS coordinates with the table at `table`. Hypothetical
    /// table axes count as 0 (WSE-25).
    fn table_motion(&self, kin: &Kinematics, table: [f64; 2]) -> Frame {
        let zero: Pos = [0.0; MAX_AXES];
        let mut turned = zero;
        let table_joints = kin.joints().into_iter().filter(|j| j.side == Side::Table);
        for (k, j) in table_joints.enumerate() {
            if let (Some(i), Some(v)) = (j.index, table.get(k)) {
                turned[i] = *v;
            }
        }
        let f0 = self.wcs_on_table(kin, &zero);
        let ft = self.wcs_on_table(kin, &turned);
        wse::inverse(&ft).then(&f0)
    }

    /// A G54.4 block (alone in its block, its P checked by the mode rules): start set n or
    /// cancel (P0). The machine does not move; the current point is recomputed (WSE-09).
    pub(super) fn apply_wse(&mut self, w: &Words) -> Result<(), AlarmId> {
        if !w.gcodes().contains(&544) {
            return Ok(());
        }
        let n = w.integer(b'P').unwrap_or(0.0) as usize;
        let machine = self.machine_position();
        if n == 0 {
            if self.wse.take().is_none() {
                return Ok(());
            }
        } else {
            let axes = &self.cfg.machine.axes;
            let basic = [b'X', b'Y', b'Z'].map(|l| self.axis_of(l).filter(|&i| axes[i].kind == AxisKind::Linear));
            let [Some(x), Some(y), Some(z)] = basic else { return Err(AlarmId::WseBasicAxes) };
            let frame = self.effective_setting_error(n);
            self.wse = Some(Active { set: n as u8, frame, xyz: [x, y, z] });
        }
        self.pos = self.machine_to_program(&machine);
        self.sync_programmed();
        Ok(())
    }

    /// Reset: workpiece setting error compensation ends unless FANUC D3R (No.5400#2) keeps it
    /// (WSE-21). The machine stays; the current point is recomputed in the WCS.
    pub(super) fn wse_reset(&mut self) {
        if self.wse.is_none() || self.cfg.machine.five_axis.wse_kept_on_reset {
            return;
        }
        let machine = self.machine_position();
        self.wse = None;
        self.five.clear_wse();
        self.pos = self.machine_to_program(&machine);
        self.sync_programmed();
    }

    /// WSCS → WCS on X/Y/Z (identity without G54.4).
    #[inline]
    pub(super) fn wse_to_wcs(&self, p: &mut Pos) {
        if let Some(a) = &self.wse {
            let [x, y, z] = a.xyz;
            let q = a.frame.to_parent(&Vec3::new(p[x], p[y], p[z]));
            (p[x], p[y], p[z]) = (q[0], q[1], q[2]);
        }
    }

    /// WCS → WSCS on X/Y/Z (identity without G54.4).
    #[inline]
    pub(super) fn wse_from_wcs(&self, p: &mut Pos) {
        if let Some(a) = &self.wse {
            let [x, y, z] = a.xyz;
            let q = a.frame.from_parent(&Vec3::new(p[x], p[y], p[z]));
            (p[x], p[y], p[z]) = (q[0], q[1], q[2]);
        }
    }

    /// The current point in the WCS (#5041…, WSE-20): the WSCS point carried by the error.
    pub(super) fn wcs_position(&self) -> Pos {
        let mut p = self.pos;
        self.wse_to_wcs(&mut p);
        p
    }

    /// Whether a circle must run as a tip path: under G54.4 (the error may tilt its plane).
    pub(super) fn wse_arc(&self) -> bool {
        self.wse.is_some() && self.kinematics.is_some()
    }

    /// G02/G03 under G54.4 without tool centre point control or a tilted plane: the circle
    /// (WSCS) carried into the WCS as a circle in space, the tool length along Z as plain G43
    /// applies it, so the end point is exactly `program_to_machine(target)`.
    pub(super) fn wse_arc_motion(&mut self, kind: MotionKind, target: Pos, arc: Box<Arc>, out: &mut Vec<Canon>) {
        let Some((kin, active)) = self.kinematics.clone().zip(self.wse) else { return };
        let end = self.program_to_machine(&target);
        let [x, y, z] = active.xyz;
        let length = Frame {
            r: nalgebra::Matrix3::identity(),
            o: Vec3::new(self.tool_vec[x], self.tool_vec[y], self.tool_vec[z]),
        };
        let frame = self.wcs_on_table(&kin, &end).then(&length).then(&active.frame);
        let path = FollowPath { frame, tool_length: 0.0, posture: false, along: true };
        self.follow_motion(&kin, kind, target, Some(arc), path, out);
        // Not a mode that follows the tip: the machine position is the programmed point's.
        self.follow_machine = None;
    }
}
