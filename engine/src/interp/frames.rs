//! Programming transforms of the FANUC M series: polar coordinate command (G15/G16, group 17),
//! programmable mirror image (G50.1/G51.1, group 22), scaling (G50/G51, group 11) and coordinate
//! system rotation (G68/G69, group 16). The decisions are in `docs/conventions.md`, "Programming
//! transforms"; `engine/tests/it/frames.rs` pins them.
//!
//! A block's axis words give a point in *programmed* coordinates (G16 words already turned into
//! Cartesian ones). The point goes through the mirror image, then scaling, then rotation (FANUC's
//! processing order) and comes out as the end point in the workpiece coordinate system: what
//! `State::pos`, a motion's `target` and `#5001` hold. The programmed coordinates of the current
//! point are kept in [`Transforms::programmed`], exactly as programmed, so that incremental words
//! and omitted axes work in the programmed space. Whatever changes the relation between the two
//! without a programmed move (a transform starts, changes or ends; an offset changes; a move in
//! machine coordinates) keeps the tool where it is and derives its programmed coordinates again
//! from `pos`, as a work offset change does.

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::angle::sin_cos_deg;
use crate::canon::Pos;
use crate::machine::{AxisKind, MAX_AXES};

/// Largest magnification of G51 (FANUC: 999999 in units of 0.001).
const MAX_MAGNIFICATION: f64 = 999.999;
/// Smallest magnification of G51: one unit of 0.001 (FANUC's range 0.001…999.999; a smaller
/// factor written with a point, `P.0004`, would shrink the part to nothing).
const MIN_MAGNIFICATION: f64 = 0.001;

/// The largest magnitude of G68's angle R, degrees: FANUC's range of the rotation angle (the
/// angle taken when R is omitted, No.5410, is −360000…360000 in 0.001°); the manuals at hand
/// name no alarm for an R beyond it, so fivex's own FX0010 refuses it (R400. is a typing error
/// or a bad variable, not 40°). A sum of G91 R's may go beyond (the repetition example of
/// `docs/conventions.md` turns 45° more at each call): only the R written is held to it.
const MAX_ROTATION_ANGLE: f64 = 360.0;

/// The codes that start a programming transform: G51.1 (Haas G101), G51, G68. Each takes the
/// block's axis words as its data (mirror axis positions, scaling centre, rotation centre), and
/// FANUC commands them in that order, one block each (30i user's manual B-63944EN-2, §6,
/// "Scaling and coordinate system rotation": `G51 ;` `G68 ;` … `G69 ;` `G50 ;`).
const STARTS: [u16; 4] = [code::G51_1, code::G101, code::G51, code::G68];

/// The reference position returns and coordinate system changes FANUC forbids while mirror
/// image, scaling or rotation is on ("G27, G28, G29, G30, etc." and "G52 to G59, G92, etc.";
/// the work systems G54–G59 are asked apart: naming the one in force changes nothing).
const RETURNS_AND_SYSTEMS: [u16; 10] = [
    code::G27,
    code::G28,
    code::G28_2,
    code::G29,
    code::G30,
    code::G30_1,
    code::G52,
    code::G53,
    code::G92,
    code::G92_1,
];

/// The second code of `codes` (a block's G codes, in order) that starts a programming transform,
/// if there is one: two in one block are refused (PS0010, `docs/conventions.md`,
/// "Programming transforms"), since fivex gave both the same axis words and applied them in
/// its own order, whatever the block meant. `fivex check` asks the same (`crate::check`).
pub(crate) fn second_start(codes: &[u16]) -> Option<u16> {
    codes.iter().copied().filter(|c| STARTS.contains(c)).nth(1)
}

/// Whether G68's angle `r` (degrees) is within ±360° (1e-9° for a product of 0.001° steps).
pub(crate) fn rotation_angle_fits(r: f64) -> bool {
    r.abs() <= MAX_ROTATION_ANGLE + 1e-9
}

/// The circle words of a G02/G03 block in its plane: R, the centre offset (I/J/K of the plane's
/// two axes) and the direction.
#[derive(Debug, Clone, Copy)]
pub(super) struct ArcWords {
    pub(super) r: Option<f64>,
    pub(super) offset: (f64, f64),
    pub(super) cw: bool,
}

/// The active programming transforms and the programmed current point.
#[derive(Debug, Clone, Default)]
pub(super) struct Transforms {
    /// The current point in programmed coordinates (before the transforms).
    pub(super) programmed: Pos,
    /// Per axis, the position of the mirror axis (G51.1); `None` = not mirrored.
    mirror: [Option<f64>; MAX_AXES],
    scale: Option<Scale>,
    rotation: Option<Rotation>,
    /// Whether any of the three is on (the usual case, off, costs one test per motion).
    active: bool,
}

/// G51: `x' = center + factor · (x − center)` per axis; a negative factor mirrors.
#[derive(Debug, Clone, Copy)]
struct Scale {
    center: Pos,
    /// 1 on the axes scaling does not act on.
    factor: Pos,
}

/// G68 in the plane of `axes`, about `center` (workpiece coordinates of that plane).
#[derive(Debug, Clone, Copy)]
struct Rotation {
    axes: (usize, usize),
    center: (f64, f64),
    /// R as programmed (summed under G91), degrees: what a following G91 R adds to.
    angle: f64,
    /// Of the angle applied: R, or −R when the mirror image and scaling active when G68 was
    /// commanded mirror the plane (the whole rotation is mirrored with the program).
    cos: f64,
    sin: f64,
}

impl Transforms {
    fn refresh(&mut self) {
        self.active = self.scale.is_some() || self.rotation.is_some() || self.mirror.iter().any(Option::is_some);
    }

    /// Whether mirror image, scaling or rotation is on.
    pub(super) fn active(&self) -> bool {
        self.active
    }

    /// Whether scaling (G51) is on.
    pub(super) fn scaling(&self) -> bool {
        self.scale.is_some()
    }

    /// Whether an axis is mirrored by G51.1.
    pub(super) fn mirrored(&self) -> bool {
        self.mirror.iter().any(Option::is_some)
    }

    /// Whether G51.1 mirrors axis `i`.
    pub(super) fn mirrors(&self, i: usize) -> bool {
        self.mirror[i].is_some()
    }

    /// Mirror image then scaling: the input of the rotation.
    fn before_rotation(&self, p: &Pos) -> Pos {
        let mut q = *p;
        for (x, m) in q.iter_mut().zip(&self.mirror) {
            if let Some(c) = m {
                *x = 2.0 * c - *x;
            }
        }
        if let Some(s) = &self.scale {
            for ((x, c), f) in q.iter_mut().zip(&s.center).zip(&s.factor) {
                if *f != 1.0 {
                    *x = c + f * (*x - c);
                }
            }
        }
        q
    }

    /// Undo the rotation stage only.
    fn unrotate(&self, w: &Pos) -> Pos {
        let mut q = *w;
        if let Some(r) = &self.rotation {
            let (a, b) = r.axes;
            let (dx, dy) = (q[a] - r.center.0, q[b] - r.center.1);
            q[a] = r.center.0 + dx * r.cos + dy * r.sin;
            q[b] = r.center.1 - dx * r.sin + dy * r.cos;
        }
        q
    }

    /// Programmed → workpiece coordinates.
    pub(super) fn forward(&self, p: &Pos) -> Pos {
        if !self.active {
            return *p;
        }
        let mut q = self.before_rotation(p);
        if let Some(r) = &self.rotation {
            let (a, b) = r.axes;
            let (dx, dy) = (q[a] - r.center.0, q[b] - r.center.1);
            q[a] = r.center.0 + dx * r.cos - dy * r.sin;
            q[b] = r.center.1 + dx * r.sin + dy * r.cos;
        }
        q
    }

    /// Workpiece → programmed coordinates (every factor is non-zero, so this always exists).
    pub(super) fn inverse(&self, w: &Pos) -> Pos {
        if !self.active {
            return *w;
        }
        let mut q = self.unrotate(w);
        if let Some(s) = &self.scale {
            for ((x, c), f) in q.iter_mut().zip(&s.center).zip(&s.factor) {
                if *f != 1.0 {
                    *x = c + (*x - c) / f;
                }
            }
        }
        for (x, m) in q.iter_mut().zip(&self.mirror) {
            if let Some(c) = m {
                *x = 2.0 * c - *x;
            }
        }
        q
    }

    /// Signed factor of mirror and scaling on one axis.
    fn axis_factor(&self, i: usize) -> f64 {
        let m = if self.mirror[i].is_some() { -1.0 } else { 1.0 };
        m * self.scale.map_or(1.0, |s| s.factor[i])
    }

    /// How much a programmed length along axis `i` grows (rotation and mirror keep lengths): the
    /// peck depths and shifts of canned cycles, which scaling does not change, are divided by it.
    pub(super) fn length_factor(&self, i: usize) -> f64 {
        self.scale.map_or(1.0, |s| s.factor[i].abs())
    }

    /// The level on axis `i` that programmed coordinate `p` stands at when scaling leaves
    /// levels alone: `p` through the mirror image and the scaling, back through the mirror
    /// image (a Haas canned cycle's drilling-axis levels, `cycles`).
    pub(super) fn unscaled_level(&self, i: usize, p: f64) -> f64 {
        match self.scale.map(|s| (s.center[i], s.factor[i])) {
            Some((c, f)) if f != 1.0 => self.mirror_on(i, c + f * (self.mirror_on(i, p) - c)),
            _ => p,
        }
    }

    /// The programmed coordinate on axis `i` that puts the tool at `level` when scaling leaves
    /// levels alone: the inverse of [`Transforms::unscaled_level`].
    pub(super) fn programmed_level(&self, i: usize, level: f64) -> f64 {
        match self.scale.map(|s| (s.center[i], s.factor[i])) {
            Some((c, f)) if f != 1.0 => self.mirror_on(i, c + (self.mirror_on(i, level) - c) / f),
            _ => level,
        }
    }

    /// A coordinate on axis `i` through the mirror image (its own inverse).
    fn mirror_on(&self, i: usize, x: f64) -> f64 {
        self.mirror[i].map_or(x, |c| 2.0 * c - x)
    }

    /// Whether a coordinate rotation or a mirror image (G51.1, a negative magnification) is in
    /// force: a direction of the program is then not the machine's.
    pub(super) fn turns_or_mirrors(&self) -> bool {
        self.rotation.is_some() || (0..self.mirror.len()).any(|i| self.axis_factor(i) < 0.0)
    }

    /// Whether the transforms mirror the plane of axes `a`, `b` (an odd number of its axes
    /// mirrored by G51.1 or a negative magnification): G02 and G03 swap, as do G41 and G42.
    pub(super) fn flips(&self, a: usize, b: usize) -> bool {
        self.axis_factor(a) * self.axis_factor(b) < 0.0
    }
}

impl State {
    /// The block's end point in programmed coordinates: the programmed current point with the
    /// block's axis words (G90/G91, G16 polar words) applied, except on axis `skip` (the drilling
    /// axis of a canned cycle).
    pub(super) fn programmed_target(&self, w: &Words, skip: Option<usize>) -> Pos {
        let here = self.xf.programmed;
        let mut t = here;
        let incremental = self.modes[group::DISTANCE] == code::G91;
        let polar = if self.modes[group::POLAR] == code::G16 { self.plane_axes().ok() } else { None };
        for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
            if Some(i) == skip || polar.is_some_and(|(a, b, _)| i == a || i == b) {
                continue;
            }
            if let Some(v) = self.value(w, axis.name as u8) {
                t[i] = match (incremental, axis.rollover) {
                    (true, _) => here[i] + v,
                    // Positions of a rollover axis stay unwound here (the travel is what
                    // matters); they are shown modulo 360 (`MachineConfig::shown`).
                    (false, true) => here[i] + crate::angle::rollover_travel(here[i], v, axis.shortest),
                    (false, false) => v,
                };
            }
        }
        if let Some((a, b, _)) = polar {
            self.polar(w, a, b, &mut t);
        }
        t
    }

    /// G16: the plane's first axis word is the radius, the second the angle (degrees, CCW from
    /// the first axis). The origin is the workpiece zero, or the current point when the radius
    /// is incremental (G91). An omitted radius is the current point's distance from the zero; an
    /// incremental or omitted angle counts from the current point's angle about the zero.
    fn polar(&self, w: &Words, a: usize, b: usize, t: &mut Pos) {
        let axes = &self.cfg.machine.axes;
        let radius = self.value(w, axes[a].name as u8);
        let angle = self.angle_word(w, axes[b].name as u8);
        if radius.is_none() && angle.is_none() {
            return;
        }
        let incremental = self.modes[group::DISTANCE] == code::G91;
        let (x, y) = (self.xf.programmed[a], self.xf.programmed[b]);
        let (origin, r) = match radius {
            Some(r) if incremental => ((x, y), r),
            Some(r) => ((0.0, 0.0), r),
            None => ((0.0, 0.0), x.hypot(y)),
        };
        let current = if x == 0.0 && y == 0.0 { 0.0 } else { y.atan2(x).to_degrees() };
        let theta = match angle {
            Some(v) if incremental => current + v,
            Some(v) => v,
            None => current,
        };
        let (s, c) = sin_cos_deg(theta);
        t[a] = origin.0 + r * c;
        t[b] = origin.1 + r * s;
    }

    /// An angle word in degrees: without a decimal point it counts 0.001° (IS-B), in mm and
    /// inch alike.
    pub(super) fn angle_word(&self, w: &Words, letter: u8) -> Option<f64> {
        let (v, no_point) = w.raw(letter)?;
        Some(if no_point && !self.cfg.pocket_calculator { v * 0.001 } else { v })
    }

    /// A magnification of G51 (P, I, J, K): without a decimal point in units of 0.001 (FANUC
    /// No.5400#7 SCR = 0), with one as written.
    fn magnification(&self, w: &Words, letter: u8) -> Result<Option<f64>, AlarmId> {
        let Some((v, no_point)) = w.raw(letter) else { return Ok(None) };
        let m = if no_point && !self.cfg.pocket_calculator { v * 0.001 } else { v };
        // FANUC PS0142 (ILLEGAL SCALE RATE); P must be positive, I/J/K may be negative (mirror).
        // The 1e-9 margin keeps a written 0.001 inside despite its binary value.
        if m.abs() < MIN_MAGNIFICATION - 1e-9 || m.abs() > MAX_MAGNIFICATION || (letter == b'P' && m < 0.0) {
            return Err(AlarmId::IllegalScaleRate);
        }
        Ok(Some(m))
    }

    /// What a block's transform codes may not hold, refused before the block changes anything:
    /// two transforms started (`second_start`), a G68 angle beyond ±360° (FX0010), a plane
    /// change under G68 (PS0144), a transform changed out of its nesting order (FX0011).
    pub(super) fn refuse_transform_block(&self, w: &Words) -> Result<(), AlarmId> {
        if second_start(w.gcodes()).is_some() {
            return Err(AlarmId::IllegalGCodeCombination);
        }
        if w.has_g(code::G68) && self.angle_word(w, b'R').is_some_and(|r| !rotation_angle_fits(r)) {
            return Err(AlarmId::RotationAngleOutOfRange);
        }
        self.refuse_plane_change_in_rotation(w)?;
        self.refuse_out_of_order(w)?;
        self.refuse_returns_and_systems(w)
    }

    /// FX0012: a reference position return (G27–G30) or a change of the coordinate system
    /// (G52–G59, G92, another work system) while mirror image, scaling or rotation stays on.
    /// FANUC names the three codes' ranges in each of the three functions' restrictions ("must
    /// not be specified … specify it only after cancelling", 30i B-63944EN-2 §6, 16/18-C
    /// B-62764EN §15.10) and no alarm; controls differ on what follows (Mitsubishi moves the
    /// rotation centre with a work offset change, fivex kept it). Refused, not guessed. A
    /// cancel in the block counts first; the work system in force named again changes nothing.
    fn refuse_returns_and_systems(&self, w: &Words) -> Result<(), AlarmId> {
        if !self.transforms_stay(w) {
            return Ok(());
        }
        if w.gcodes().iter().any(|c| RETURNS_AND_SYSTEMS.contains(c)) || self.selects_another_work_system(w) {
            return Err(AlarmId::ReturnOrSystemInTransforms);
        }
        Ok(())
    }

    /// Whether mirror image, scaling or rotation is on after the block's transform codes.
    fn transforms_stay(&self, w: &Words) -> bool {
        let started = STARTS.iter().any(|&c| w.has_g(c));
        let rotation = self.xf.rotation.is_some() && !w.has_g(code::G69);
        let scaling = self.xf.scale.is_some() && !w.has_g(code::G50);
        let cancelled = self.mirror_cancels(w);
        let mirror = (0..MAX_AXES).any(|i| self.xf.mirrors(i) && !cancelled[i]);
        started || rotation || scaling || mirror
    }

    /// Whether the block selects a work coordinate system other than the one in force (G54–G59,
    /// G54.1 with another P; Haas G110–G129/G154).
    fn selects_another_work_system(&self, w: &Words) -> bool {
        let selected = self.after_block(w, group::WORK_SYSTEM);
        if selected != self.modes[group::WORK_SYSTEM] {
            return true;
        }
        if selected != code::G54_1 || !w.has_g(code::G54_1) {
            return false;
        }
        // A P the block does not give is P1 (FANUC; Haas refuses it where the P is read).
        let haas = self.cfg.dialect == crate::Dialect::Haas;
        let p = w.haas_wcs_p.map(f64::from).or_else(|| w.integer(b'P')).or((!haas).then_some(1.0));
        p.is_some_and(|p| p != f64::from(self.wcs_p))
    }

    /// PS0144: another plane selected while G68 stays on (a G68 in the block sets the rotation
    /// anew, in the block's plane). FANUC: "G17, G18 or G19 must not be designated in the mode
    /// of coordinate system rotation" (15i B-63324EN §14, 16/18-C B-62764EN §15.10), as Haas
    /// ("Do not change the plane of rotation while G68 is in effect"); fivex went on rotating
    /// the old plane's axes while the moves, cycles and polar words took the new plane's.
    /// PS0144 is FANUC's alarm for a circle or compensation outside the rotation plane.
    fn refuse_plane_change_in_rotation(&self, w: &Words) -> Result<(), AlarmId> {
        let stays = self.xf.rotation.is_some() && !w.has_g(code::G69) && !w.has_g(code::G68);
        if stays && self.after_block(w, group::PLANE) != self.modes[group::PLANE] {
            return Err(AlarmId::IllegalPlaneInRotation);
        }
        Ok(())
    }

    /// FX0011: a change of the mirror image while scaling or rotation stays on, or of scaling
    /// while rotation stays on. FANUC processes mirror image → scaling → rotation and asks for
    /// the commands in that order and the cancels in reverse ("Do not specify G50.1 or G51.1
    /// during scaling or coordinate rotation mode"; `G51 ;` `G68 ;` … `G69 ;` `G50 ;`). fivex
    /// applies them in that order whatever the commands' order, and the rotation keeps the
    /// sense and centre it took when G68 was commanded, so another order ran a path no
    /// reading of the program gives (G51.1, G68 R30., G50.1 went on turning −30°). A cancel
    /// in the block counts first: `G69 G50 G50.1` ends all three. A cancel of what is not on
    /// changes nothing and is let pass (the `G50 G50.1 G69` of a safety block).
    fn refuse_out_of_order(&self, w: &Words) -> Result<(), AlarmId> {
        let rotation_stays = self.xf.rotation.is_some() && !w.has_g(code::G69);
        let scaling_stays = self.xf.scale.is_some() && !w.has_g(code::G50);
        let mirror_changes = w.has_g(code::G51_1) || w.has_g(code::G101) || self.mirror_cancel_changes(w);
        let scaling_changes = w.has_g(code::G51) || (w.has_g(code::G50) && self.xf.scale.is_some());
        if (mirror_changes && (scaling_stays || rotation_stays)) || (scaling_changes && rotation_stays) {
            return Err(AlarmId::TransformOrder);
        }
        Ok(())
    }

    /// Whether the block's G50.1 (Haas G100) cancels the mirror image of an axis now mirrored.
    fn mirror_cancel_changes(&self, w: &Words) -> bool {
        let cancelled = self.mirror_cancels(w);
        (0..MAX_AXES).any(|i| cancelled[i] && self.xf.mirrors(i))
    }

    /// Per axis, whether the block's G50.1 (Haas G100) cancels its mirror image: the named
    /// axes; without axis words, all of them.
    fn mirror_cancels(&self, w: &Words) -> [bool; MAX_AXES] {
        let mut cancelled = [false; MAX_AXES];
        if w.has_g(code::G50_1) || w.has_g(code::G100) {
            let axes = &self.cfg.machine.axes;
            let all = !axes.iter().any(|a| w.has(a.name as u8));
            for (i, a) in axes.iter().enumerate() {
                cancelled[i] = all || w.has(a.name as u8);
            }
        }
        cancelled
    }

    /// Derive the programmed current point from the workpiece one (after a transform or an
    /// offset changed without a programmed move).
    pub(super) fn sync_programmed(&mut self) {
        self.xf.programmed = self.xf.inverse(&self.pos);
    }

    /// The transform codes of a block (G50/G51, G50.1/G51.1, G68/G69), after the modal groups
    /// were updated. Returns whether the block's axis words were theirs (no motion then).
    pub(super) fn apply_transforms(&mut self, w: &Words) -> Result<bool, AlarmId> {
        let mut owns_axes = false;
        for &code in w.gcodes() {
            match code {
                code::G51_1 => {
                    for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                        if let Some(v) = self.value(w, axis.name as u8) {
                            self.xf.mirror[i] = Some(v);
                        }
                    }
                    owns_axes = true;
                }
                // Haas G101: the named axes mirrored about work zero, whatever their values
                // (96-8000, G101: "around your work coordinate zero point").
                code::G101 => {
                    for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
                        if w.has(axis.name as u8) {
                            self.xf.mirror[i] = Some(0.0);
                        }
                    }
                    owns_axes = true;
                }
                code::G50_1 | code::G100 => {
                    let cancels = self.mirror_cancels(w);
                    for (m, cancelled) in self.xf.mirror.iter_mut().zip(cancels) {
                        if cancelled {
                            *m = None;
                        }
                    }
                    owns_axes = true;
                }
                code::G51 => {
                    self.start_scaling(w)?;
                    owns_axes = true;
                }
                code::G50 => {
                    if self.xf.scale.take().is_none() {
                        continue;
                    }
                }
                code::G68 => {
                    self.start_rotation(w)?;
                    owns_axes = true;
                }
                code::G69 => {
                    if self.xf.rotation.take().is_none() {
                        continue;
                    }
                }
                _ => continue,
            }
            self.xf.refresh();
            self.sync_programmed();
        }
        // G68.2… took group 16: the plane rotation of G68 is over.
        if self.modes[group::ROTATION] != code::G68 && self.xf.rotation.is_some() {
            self.xf.rotation = None;
            self.xf.refresh();
            self.sync_programmed();
        }
        self.modes[group::MIRROR] = if self.xf.mirrored() { code::G51_1 } else { code::G50_1 };
        Ok(owns_axes)
    }

    /// `G51 X_ Y_ Z_ P_` or `G51 X_ Y_ Z_ I_ J_ K_`: the center is absolute (also under G91),
    /// omitted coordinates are the current point's; P scales every linear axis, I/J/K the X, Y
    /// and Z axes (they override P); without either the magnification is 1.
    fn start_scaling(&mut self, w: &Words) -> Result<(), AlarmId> {
        let p = self.magnification(w, b'P')?;
        let mut factor = [1.0; MAX_AXES];
        for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
            if axis.kind == AxisKind::Linear {
                factor[i] = p.unwrap_or(1.0);
            }
        }
        for (letter, axis) in [(b'I', b'X'), (b'J', b'Y'), (b'K', b'Z')] {
            if let (Some(m), Some(i)) = (self.magnification(w, letter)?, self.axis_of(axis)) {
                factor[i] = m;
            }
        }
        // The center is a fixed point of the scaling: given coordinates are programmed ones
        // (through the mirror image), omitted ones the tool's position before the rotation.
        let mut center = self.xf.unrotate(&self.pos);
        for (i, axis) in self.cfg.machine.axes.iter().enumerate() {
            if let Some(v) = self.value(w, axis.name as u8) {
                center[i] = match self.xf.mirror[i] {
                    Some(c) => 2.0 * c - v,
                    None => v,
                };
            }
        }
        self.xf.scale = Some(Scale { center, factor });
        Ok(())
    }

    /// `G68 α_ β_ R_` in the selected plane: the center is absolute (also under G91) and goes
    /// through the mirror image and scaling; omitted coordinates are the tool's position. R is
    /// degrees CCW (0 when omitted); under G91 it is added to the active rotation's angle when
    /// `Config::rotation_angle_incremental` (FANUC No.5400#0 RIN) is set.
    fn start_rotation(&mut self, w: &Words) -> Result<(), AlarmId> {
        let (a, b, _) = self.plane_axes()?;
        let mut center = (self.pos[a], self.pos[b]);
        let given = self.xf.before_rotation(&{
            let mut c = self.xf.programmed;
            for i in [a, b] {
                if let Some(v) = self.value(w, self.cfg.machine.axes[i].name as u8) {
                    c[i] = v;
                }
            }
            c
        });
        if w.has(self.cfg.machine.axes[a].name as u8) {
            center.0 = given[a];
        }
        if w.has(self.cfg.machine.axes[b].name as u8) {
            center.1 = given[b];
        }
        let r = self.angle_word(w, b'R').unwrap_or(0.0);
        let angle = match self.xf.rotation {
            Some(prev) if self.modes[group::DISTANCE] == code::G91 && self.cfg.rotation_angle_incremental => {
                prev.angle + r
            }
            _ => r,
        };
        let applied = if self.xf.flips(a, b) { -angle } else { angle };
        let (sin, cos) = sin_cos_deg(applied);
        self.xf.rotation = Some(Rotation { axes: (a, b), center, angle, cos, sin });
        Ok(())
    }

    /// The circle words of a G02/G03 block in the plane (`a`, `b`) carried into workpiece
    /// coordinates: R grows by the larger magnification of the two axes (FANUC), the centre
    /// offset I/J/K goes through mirror, scaling and rotation, and the direction turns over when
    /// the transforms mirror the plane.
    pub(super) fn arc_words(&self, (a, b): (usize, usize), words: ArcWords) -> Result<ArcWords, AlarmId> {
        let ArcWords { r, offset, cw } = words;
        if !self.xf.active {
            return Ok(words);
        }
        let (fa, fb) = (self.xf.axis_factor(a), self.xf.axis_factor(b));
        let mut v = (offset.0 * fa, offset.1 * fb);
        if let Some(rot) = &self.xf.rotation {
            if rot.axes != (a, b) {
                // FANUC PS0144 (ILLEGAL PLANE SELECTED): the arc must be in the rotation plane.
                return Err(AlarmId::IllegalPlaneInRotation);
            }
            v = (v.0 * rot.cos - v.1 * rot.sin, v.0 * rot.sin + v.1 * rot.cos);
        }
        let r = r.map(|r| r * self.xf.length_factor(a).max(self.xf.length_factor(b)));
        Ok(ArcWords { r, offset: v, cw: cw != self.xf.flips(a, b) })
    }
}
