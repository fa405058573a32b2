//! Tilted working plane: G68.2 / G68.3 / G68.4 define the feature coordinate system (FCS) in
//! the workpiece system, G69 ends it, and the tool axis direction controls G53.1, G53.3
//! (Syntec) and G53.6 turn the rotary axes so that the tool is along the FCS +Z (spec
//! `fanuc-twp-wsec-manual-params.md` TWP-01…TWP-13, `syntec.md` SYN-18…SYN-22).
//!
//! In the plane a block's X/Y/Z are FCS coordinates of the tool tip (of the spindle nose under
//! G49). The FCS is fixed to the workpiece, so to the table: its frame in the table frame is the
//! workpiece system placed on the table at the rotary axes' program zero (Syntec §7.2: the G54
//! rotary offsets), composed with the FCS. Every move goes through `follow_motion`: X/Y/Z come
//! from the kinematics with the tool length along the actual tool direction, which after a
//! G53.1 is the FCS Z.

use super::gcode::{code, group};
use super::nc::Words;
use super::tcp::{xyz, FollowPath};
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind, MotionKind, Pos};
use crate::geom::Rigid;
use crate::kin::{Kinematics, Selection, Vec3};
use crate::machine::{ManualVertical, PlaneAfterReset};
use crate::twp;
use std::sync::Arc as Shared;

/// A G68.2 P2 (three points) or P3 (two vectors) definition in progress.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Definition {
    points: [Option<Vec3>; 3],
    shift: Vec3,
    r: f64,
    /// P3 Q1: origin and the FCS +X vector.
    origin: Vec3,
    x: Option<Vec3>,
}

/// A tilted working plane: the G code of group 16 and the feature coordinate system in the
/// workpiece system. The one in force is shown (the 3D view draws its frame) and, where the
/// machine keeps planes over a restart (Syntec Pr3014 = 2, SYN-25), kept.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TiltedPlane {
    /// 682, 683 or 684 (G68.2, G68.3, G68.4); 2540 for Haas DWO (G254, `super::dwo`).
    pub code: u16,
    /// The FCS origin in the workpiece system.
    pub origin: [f64; 3],
    /// The FCS X, Y, Z axes in the workpiece system.
    pub axes: [[f64; 3]; 3],
}

impl State {
    /// The plane to keep over a restart: the active one when the machine keeps it there
    /// (`PlaneAfterReset::KeptOverRestart`), else none.
    pub fn kept_plane(&self) -> Option<TiltedPlane> {
        self.active_plane().filter(|_| self.cfg.machine.five_axis.plane_after_reset == PlaneAfterReset::KeptOverRestart)
    }

    /// The tilted working plane in force at the block read last.
    pub fn active_plane(&self) -> Option<TiltedPlane> {
        let fcs = self.plane?;
        let column = |k: usize| [fcs.r[(0, k)], fcs.r[(1, k)], fcs.r[(2, k)]];
        Some(TiltedPlane {
            // Haas DWO runs as a plane (`super::dwo`): shown as G254.
            code: if self.dwo_active() { code::G254 } else { self.modes[group::ROTATION] },
            origin: fcs.o.into(),
            axes: [column(0), column(1), column(2)],
        })
    }

    /// After a restart: the plane kept over it becomes active again, the machine where it
    /// stands (nothing when the machine does not keep planes over a restart, or `kept` is no
    /// plane).
    pub fn restore_plane(&mut self, kept: &TiltedPlane) {
        let keeps = self.cfg.machine.five_axis.plane_after_reset == PlaneAfterReset::KeptOverRestart;
        if !keeps || !code::TILTED_PLANES.contains(&kept.code) || self.kinematics.is_none() {
            return;
        }
        let machine = self.machine_position();
        let r = nalgebra::Matrix3::from_columns(&kept.axes.map(Vec3::from));
        self.plane = Some(Rigid { r, o: Vec3::from(kept.origin) });
        self.modes[group::ROTATION] = kept.code;
        self.plane_moved_to(machine);
    }

    pub(super) fn plane_active(&self) -> bool {
        self.plane.is_some()
    }

    fn kin(&self) -> Result<Shared<Kinematics>, AlarmId> {
        self.kinematics.clone().ok_or(AlarmId::TwpFormat)
    }

    /// Tool length of group 08 as it acts now (G43 +H, G44 −H, otherwise 0; 0 while a
    /// reference return has cancelled the vector, `cancel_length_vector`).
    pub(super) fn active_tool_length(&self) -> f64 {
        if self.length_cancelled {
            return 0.0;
        }
        match self.modes[group::LENGTH_COMP] {
            code::G43 => self.offsets.length(self.h),
            code::G44 => -self.offsets.length(self.h),
            _ => 0.0,
        }
    }

    /// FCS → table frame: the workpiece system on the table at the rotary axes' program zero,
    /// then the FCS in it.
    fn plane_frame(&self, kin: &Kinematics, fcs: &Rigid) -> Rigid {
        let zero = self.at_rotary_zero(kin, &self.machine_position());
        self.frame_on_table(kin, &zero).then(fcs)
    }

    /// G69, or a reset that cancels the plane: programming coordinates are the workpiece
    /// system again, the machine stays where it is.
    pub(super) fn end_plane(&mut self) {
        let machine = self.machine_position();
        let programmed = self.pos;
        self.plane = None;
        self.definition = Definition::default();
        self.modes[group::ROTATION] = code::G69;
        self.follow_machine = None;
        self.pos = self.machine_to_program(&machine);
        self.sync_programmed();
        // Under G54.4 with tool direction compensation the current point is the tip in the
        // WSCS again, and the rotary coordinates stay the programmed angles (nothing moves).
        self.wse_moved_to(machine);
        self.wse_keep_programmed_angles(&programmed);
    }

    /// The FCS point of the tool tip at machine position `machine`.
    fn tip_in_plane(&self, kin: &Kinematics, frame: &Rigid, machine: &Pos) -> Pos {
        self.tip_position(kin, frame, machine, self.active_tool_length())
    }

    /// The machine is at `machine` while the plane is active (after a move in machine
    /// coordinates, a manual move): the current point follows.
    pub(super) fn plane_moved_to(&mut self, machine: Pos) {
        let (Some(fcs), Ok(kin)) = (self.plane, self.kin()) else { return };
        self.follow_machine = Some(machine);
        let frame = self.plane_frame(&kin, &fcs);
        self.pos = self.tip_in_plane(&kin, &frame, &machine);
        // Under G54.4 with tool direction compensation the rotary coordinates are the angles
        // whose error-free tool direction is the actual one seen from the WSCS (§2.13.4).
        if let Some(angles) = self.wse_follows().then(|| self.wse_programmed_angles(&machine)).flatten() {
            self.pos = angles;
        }
        self.sync_programmed();
    }

    /// The block's G68.2/G68.3/G68.4/G69, after the modal groups were updated. Returns whether
    /// the block's axis words were the definition's (no motion then).
    pub(super) fn apply_plane(&mut self, w: &Words) -> Result<bool, AlarmId> {
        let mut owns_axes = false;
        for &code in w.gcodes() {
            let defined = match code {
                code::G68_2 | code::G68_4 => {
                    owns_axes = true;
                    self.define(w, code == code::G68_4)?
                }
                code::G68_3 => {
                    owns_axes = true;
                    Some(self.tool_axis_plane(w)?)
                }
                code::G69 if self.plane.is_some() => {
                    self.end_plane();
                    None
                }
                _ => None,
            };
            if let Some(fcs) = defined {
                let machine = self.machine_position();
                let programmed = self.pos;
                self.plane = Some(fcs);
                self.plane_moved_to(machine);
                // Nothing moves: under G54.4 with RCM = 1 the programmed angles stay as they are.
                self.wse_keep_programmed_angles(&programmed);
            }
        }
        Ok(owns_axes)
    }

    /// A G68.2/G68.4 block: the new FCS (in the workpiece system), or `None` while a P2/P3
    /// definition is still incomplete.
    fn define(&mut self, w: &Words, relative: bool) -> Result<Option<Rigid>, AlarmId> {
        let word = |s: &State, l: u8| s.value(w, l);
        let point = |s: &State| {
            Vec3::new(word(s, b'X').unwrap_or(0.0), word(s, b'Y').unwrap_or(0.0), word(s, b'Z').unwrap_or(0.0))
        };
        let angles = |s: &State| [b'I', b'J', b'K'].map(|l| s.angle_word(w, l).unwrap_or(0.0));
        let vector = |s: &State| {
            Vec3::new(word(s, b'I').unwrap_or(0.0), word(s, b'J').unwrap_or(0.0), word(s, b'K').unwrap_or(0.0))
        };
        let q = w.integer(b'Q').map(|q| q as u32);
        // Syntec's G68.2 has the Euler form only (SYN-18): the mode table refuses its P, Q, R.
        let form = match self.cfg.dialect {
            crate::Dialect::Fanuc => w.integer(b'P').unwrap_or(0.0) as u32,
            crate::Dialect::Syntec => 0,
            // The NGC has no G68.2 (its tilted plane is G268, not built): the Haas dialect refuses
            // G68.2 as no code of it (310 INVALID G CODE, `gcode::HAAS_HAS`), so no Haas block
            // comes here.
            crate::Dialect::Haas => return Err(AlarmId::ImproperGCode),
        };
        let local = match form {
            0 => {
                let [i, j, k] = angles(self);
                twp::euler(point(self), i, j, k)
            }
            1 => {
                let [i, j, k] = angles(self);
                twp::roll_pitch_yaw(point(self), q, i, j, k)?
            }
            2 => {
                if let Some(r) = self.angle_word(w, b'R') {
                    self.definition.r = r;
                }
                let p = point(self);
                match q {
                    Some(0) => self.definition.shift = p,
                    Some(n @ 1..=3) => self.definition.points[n as usize - 1] = Some(p),
                    _ => return Err(AlarmId::TwpFormat),
                }
                let Definition { points: [Some(a), Some(b), Some(c)], shift, r, .. } = self.definition else {
                    return Ok(None);
                };
                self.definition = Definition::default();
                twp::three_points([a, b, c], shift, r, self.cfg.machine.five_axis.plane_min_distance)?
            }
            3 => match q {
                Some(1) => {
                    self.definition =
                        Definition { origin: point(self), x: Some(vector(self)), ..Definition::default() };
                    return Ok(None);
                }
                Some(2) => {
                    let d = std::mem::take(&mut self.definition);
                    let x = d.x.ok_or(AlarmId::TwpFormat)?;
                    twp::two_vectors(d.origin, x, vector(self))?
                }
                _ => return Err(AlarmId::TwpFormat),
            },
            4 => {
                let [i, j, k] = angles(self);
                twp::projection(point(self), i, j, k)?
            }
            _ => return Err(AlarmId::TwpFormat),
        };
        Ok(Some(match (relative, &self.plane) {
            (true, Some(old)) => old.then(&local),
            _ => local,
        }))
    }

    /// G68.3 X_ Y_ Z_ R_: the FCS +Z along the tool as it stands, X and Y from the vertical
    /// axis (SYN-23, TWP-06); Syntec's G68.3 P1: the FCS turned as the rotary axes turn the tool
    /// (SYN-24, R ignored). The origin is absolute (all omitted: the current point).
    fn tool_axis_plane(&mut self, w: &Words) -> Result<Rigid, AlarmId> {
        let kin = self.kin()?;
        let machine = self.machine_position();
        // The workpiece system is the table frame at the rotary zero.
        let base = self.plane_frame(&kin, &Rigid::identity());
        let tool = base.r.transpose() * kin.forward(&machine, 0.0).tool;
        let here = match self.plane {
            Some(fcs) => fcs.to_parent(&xyz(&kin, &self.pos)),
            None => xyz(&kin, &self.pos),
        };
        let mut origin = here;
        for (axis, letter) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
            if let Some(v) = self.value(w, letter) {
                origin[axis] = v;
            }
        }
        if self.cfg.dialect == crate::Dialect::Syntec && w.integer(b'P') == Some(1.0) {
            return Ok(Rigid { r: base.r.transpose() * kin.tool_rotation(&machine), o: origin });
        }
        // FANUC No.12321 (the machine's `manual.vertical`, shared with the manual feeds): X, Y or
        // Z; 0 (*decision*, OQ-07 leaves it open) the coordinate axis of the reference tool
        // direction (No.19697). No.12322 is the parallel tolerance.
        let vertical = match self.cfg.machine.manual.vertical {
            ManualVertical::X => Vec3::x(),
            ManualVertical::Y => Vec3::y(),
            ManualVertical::Z => Vec3::z(),
            ManualVertical::Tool => Vec3::ith(kin.tool_axis.iamax(), 1.0),
        };
        let r = self.angle_word(w, b'R').unwrap_or(0.0);
        twp::tool_axis(origin, tool, vertical, r, self.cfg.machine.manual.parallel_deg)
    }

    /// A move in the plane to `target` (FCS), with the circle `arc` (FCS) for G02/G03.
    pub(super) fn plane_motion(
        &mut self,
        kind: MotionKind,
        target: Pos,
        arc: Option<Box<crate::canon::Arc>>,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let kin = self.kin()?;
        let fcs = self.plane.expect("plane_motion in the plane");
        // G54.4 with RCM = 1: the rotary axes at the compensated angles, along the way too; the
        // current point keeps the programmed ones (as TCP type 1 and plain G54.4 moves).
        let programmed = target;
        let mut target = target;
        self.wse_compensate(&kin, &mut target)?;
        let path = FollowPath {
            frame: self.plane_frame(&kin, &fcs),
            tool_length: self.active_tool_length(),
            posture: false,
            along: true,
            cutting: None,
            head_fixed: false,
        };
        self.follow_motion(&kin, kind, target, arc, path, out)?;
        self.wse_keep_programmed_angles(&programmed);
        Ok(())
    }

    /// G53.1 / G53.3 / G53.6: turn the rotary axes so that the tool is along the FCS +Z (P: the
    /// Syntec solution choice). G53.1 moves the rotary axes only (the tip moves with them);
    /// G53.6 keeps the tip where it is (tool length on with H), or with R the point R up the
    /// tool from the tip; G53.3 switches the tool length on with H and puts the tip on X/Y/Z in
    /// the same rapid.
    pub(super) fn align(&mut self, code: u16, w: &Words, out: &mut Vec<Canon>) -> Result<bool, AlarmId> {
        // Outside the plane the mode table refuses the block first (nothing to align to).
        let Some(fcs) = self.plane else { return Err(AlarmId::TwpIllegalCommand) };
        let kin = self.kin()?;
        if code != code::G53_1 {
            if let Some(h) = w.integer(b'H') {
                self.h = h as u32;
            }
            self.modes[group::LENGTH_COMP] = code::G43;
            self.refresh_tool_length();
        }
        let frame = self.plane_frame(&kin, &fcs);
        let machine = self.machine_position();
        let length = self.active_tool_length();
        if code == code::G53_1 && self.wse_follows() {
            return self.align_compensated(&kin, &fcs, &frame, out);
        }
        let tool = frame.r * Vec3::z();
        let tip = kin.forward(&machine, length).tip;
        let candidates = kin.inverse(tip, tool, length, &machine[..kin.axes]);
        let how = Selection {
            dialect: self.cfg.dialect,
            pri: self.cfg.machine.five_axis.second_axis_first,
            p: w.integer(b'P').unwrap_or(0.0) as u8,
        };
        let choice = kin.select(&candidates, &machine[..kin.axes], how)?;
        let off = self.offset_vector();
        // The point that stays: the tip of the tool whose length now acts, or with G53.6 R the
        // point R from the tip toward the holder (SYN-21, TV-45).
        let pivot = if code == code::G53_6 { self.value(w, b'R').unwrap_or(0.0) } else { 0.0 };
        let mut target = self.tip_position(&kin, &frame, &machine, length - pivot);
        for j in kin.joints() {
            if let Some(i) = j.index {
                target[i] = choice.pos[i] - off[i];
            }
        }
        match code {
            code::G53_1 => {
                let mut end = machine;
                for j in kin.joints() {
                    if let Some(i) = j.index {
                        end[i] = choice.pos[i];
                    }
                }
                let target = self.tip_in_plane(&kin, &frame, &end);
                let motion = self.motion(MotionKind::Rapid, target, end, None, None);
                self.emit(out, CanonKind::Motion(motion));
                self.plane_moved_to(end);
            }
            _ => {
                if code == code::G53_3 {
                    for (axis, letter) in [b'X', b'Y', b'Z'].into_iter().enumerate() {
                        if let (Some(v), Some(i)) = (self.value(w, letter), kin.linear[axis]) {
                            target[i] = v;
                        }
                    }
                }
                let path = FollowPath {
                    frame,
                    tool_length: length - pivot,
                    posture: false,
                    along: code == code::G53_6,
                    cutting: None,
                    head_fixed: false,
                };
                self.follow_motion(&kin, MotionKind::Rapid, target, None, path, out)?;
                match self.follow_machine {
                    // The current point is the tip again, wherever the pivot put it.
                    Some(end) if pivot != 0.0 => self.plane_moved_to(end),
                    _ => self.sync_programmed(),
                }
            }
        }
        Ok(true)
    }
}

impl State {
    /// G53.1 inside G54.4 with tool direction compensation (RCM = 1, WSE-11, §2.3.6 note 5):
    /// the programmed angles put the tool along the FCS +Z as the error-free workpiece carries
    /// it (the FCS is defined in the WSCS), chosen by FANUC's cascade from the programmed angles
    /// as they stand; the compensation then turns them as it turns any programmed angles (the
    /// §2.14 rules at the end point), so the tool ends along the FCS +Z of the displaced
    /// workpiece. X/Y/Z stay, the rotary axes move at rapid (the tip moves with the tool), and
    /// the current point keeps the programmed angles.
    fn align_compensated(
        &mut self,
        kin: &Shared<Kinematics>,
        fcs: &Rigid,
        frame: &Rigid,
        out: &mut Vec<Canon>,
    ) -> Result<bool, AlarmId> {
        let machine = self.machine_position();
        let off = self.offset_vector();
        let ideal = self.wcs_on_table(kin, &self.at_rotary_zero(kin, &machine)).then(fcs);
        let programmed_now: Pos = std::array::from_fn(|i| self.pos[i] + off[i]);
        let candidates = kin.inverse(Vec3::zeros(), ideal.r * Vec3::z(), 0.0, &programmed_now[..kin.axes]);
        let how = Selection { dialect: self.cfg.dialect, pri: self.cfg.machine.five_axis.second_axis_first, p: 0 };
        let choice = kin.select(&candidates, &programmed_now[..kin.axes], how)?;
        let mut programmed = self.pos;
        for j in kin.joints() {
            if let Some(i) = j.index {
                programmed[i] = choice.pos[i] - off[i];
            }
        }
        let mut target = programmed;
        self.wse_compensate(kin, &mut target)?;
        // A rotary-only rapid in axis space: nothing to recompute along it.
        self.wse_between = None;
        let mut end = machine;
        for j in kin.joints() {
            if let Some(i) = j.index {
                end[i] = target[i] + off[i];
            }
        }
        let shown = self.tip_in_plane(kin, frame, &end);
        let motion = self.motion(MotionKind::Rapid, shown, end, None, None);
        self.emit(out, CanonKind::Motion(motion));
        self.plane_moved_to(end);
        self.wse_keep_programmed_angles(&programmed);
        Ok(true)
    }
}
