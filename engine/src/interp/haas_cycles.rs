//! The Haas NGC's own cycles and motion settings (Haas dialect only; `gcode::GDef::haas_only`):
//! G12/G13 circular pocket milling, the bolt patterns G70 (circle), G71 (arc) and G72 (line at
//! an angle) around the canned cycle in force, and G103's block look-ahead limit. G47 (text
//! engraving) and G150 (general purpose pocket milling) stay refused
//! (`unbuilt`); G187's corner rounding is `corner_blend`. Sources, decisions and what is not built: `docs/dialects.md`, "Haas cycles".

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Arc, Canon, MotionKind, Pos};

/// The most holes one bolt pattern block may give (the canned cycles' own output limit,
/// `cycles::MAX_COMMANDS_PER_BLOCK`, bounds what they expand into).
const MAX_HOLES: f64 = 9999.0;

/// The most pocket passes (I to K by Q) and depth loops (L) of one G12/G13 block.
const MAX_PASSES: f64 = 10_000.0;

/// Highest G103 P (the NGC's range, 0–15).
pub const MAX_BLOCK_LIMIT: f64 = 15.0;

/// A count address (L of G12/G13/G70–G72): a whole number from 1 to `max`; `None` if absent.
fn count(w: &Words, letter: u8, max: f64) -> Result<Option<u32>, AlarmId> {
    match w.integer(letter) {
        None => Ok(None),
        Some(v) if v.fract() == 0.0 && (1.0..=max).contains(&v) => Ok(Some(v as u32)),
        Some(_) => Err(AlarmId::CycleArgument),
    }
}

/// The tool centre's radii of a circular pocket's passes: I, I + Q, I + 2Q … up to K (the last
/// pass on K itself), each less the tool radius `tool`; I alone without K and Q. The checks are
/// the manual's: I greater than the tool radius and less than K, Q (positive) with K only.
pub fn pocket_radii(i: Option<f64>, k: Option<f64>, q: Option<f64>, tool: f64) -> Result<Vec<f64>, AlarmId> {
    let i = i.ok_or(AlarmId::CycleArgument)?;
    if tool < 0.0 || i <= tool {
        return Err(AlarmId::CycleArgument);
    }
    let Some(k) = k else {
        return if q.is_some() { Err(AlarmId::CycleArgument) } else { Ok(vec![i - tool]) };
    };
    let q = q.ok_or(AlarmId::CycleArgument)?;
    if k <= i || q <= 0.0 || (k - i) / q > MAX_PASSES {
        return Err(AlarmId::CycleArgument);
    }
    let mut radii = Vec::new();
    let mut r = i;
    // A pass within a micrometre of K is K's (no sliver pass of 0.0001 mm before it).
    while r < k - 1e-6 {
        radii.push(r - tool);
        r += q;
    }
    radii.push(k - tool);
    Ok(radii)
}

/// The angles (degrees, CCW from the plane's first axis) of a bolt pattern's holes: G70 `l`
/// holes evenly around the circle from `j` (clockwise when I is negative), G71 `l` holes from
/// `j` every `k` degrees.
pub fn bolt_angles(j: f64, step: f64, l: u32) -> impl Iterator<Item = f64> {
    (0..l).map(move |n| j + step * n as f64)
}

impl State {
    /// Whether the block's Haas code can be carried out in the current modes: its path is built
    /// in plain programming coordinates of the XY plane only (`docs/dialects.md`, "Haas
    /// cycles"); elsewhere it is refused rather than run on a path fivex has not computed.
    fn pocket_modes_supported(&self) -> Result<(), AlarmId> {
        if self.modes[group::PLANE] != code::G17 {
            // The manual: the circular pockets work in the XY plane (G17) only.
            return Err(AlarmId::ImproperGCode);
        }
        if self.modes[group::CYCLE] != code::G80 {
            return Err(AlarmId::IllegalGCodeCombination);
        }
        let compensated = self.modes[group::CUTTER_COMP] != code::G40;
        let transformed = self.xf.active() || self.modes[group::POLAR] == code::G16;
        if compensated || transformed || self.follows_tip() || self.wse.is_some() || self.smoothing.is_some() {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// G12 (clockwise) / G13 (counter-clockwise) circular pocket milling. The block's X/Y put
    /// the centre (the tool goes there at rapid, at its height); Z is the depth (G91: the
    /// increment, cut L times). At each depth: a feed down at the centre, a half circle out to
    /// the first pass radius, a full circle there, a half circle out to each next pass radius
    /// and a full circle there, a half circle back to the centre. The tool ends at the centre
    /// at the last depth. The radii are less the tool radius of D (D0: the tool centre), as the
    /// manual's implied G42 (G12) / G41 (G13) put the tool inside the circle.
    pub(super) fn circular_pocket(&mut self, cw: bool, w: &Words, out: &mut Vec<Canon>) -> Result<bool, AlarmId> {
        self.pocket_modes_supported()?;
        let (a, b, c) = self.plane_axes()?;
        // Another axis's word has no place in the cycle: refused rather than ignored.
        let axes = &self.cfg.machine.axes;
        if (0..axes.len()).any(|k| ![a, b, c].contains(&k) && w.has(axes[k].name as u8)) {
            return Err(AlarmId::CycleArgument);
        }
        let tool = self.offsets.radius(self.d);
        let radii = pocket_radii(self.value(w, b'I'), self.value(w, b'K'), self.value(w, b'Q'), tool)?;
        let incremental = self.modes[group::DISTANCE] == code::G91;
        let loops = count(w, b'L', MAX_PASSES)?.unwrap_or(1);
        // L repeats the Z increment (G91, the manual); in G90 it would cut the same depth again.
        if loops > 1 && !incremental {
            return Err(AlarmId::CycleArgument);
        }
        if self.f <= 0.0 {
            return Err(AlarmId::FeedZero);
        }
        let target = self.programmed_target(w, None);
        let step = target[c] - self.xf.programmed[c];
        // The centre at the tool's height.
        let mut centre = self.xf.programmed;
        (centre[a], centre[b]) = (target[a], target[b]);
        if centre != self.xf.programmed {
            self.move_to(MotionKind::Rapid, centre, out);
        }
        let sign = if cw { -1.0 } else { 1.0 };
        for n in 1..=loops {
            let mut bottom = centre;
            bottom[c] = if incremental { centre[c] + step * n as f64 } else { target[c] };
            self.move_to(MotionKind::Linear, bottom, out);
            // Along the plane's first axis: the half circles' ends, from the centre out.
            let mut at = 0.0;
            for &r in &radii {
                self.pocket_arc(bottom, (a, b, c), (at + r) / 2.0, (r - at) / 2.0, r, sign * 180.0, out);
                self.pocket_arc(bottom, (a, b, c), 0.0, r, r, sign * 360.0, out);
                at = r;
                // Passes × loops may be 10⁸ arcs: FX0003 before memory runs out.
                super::cycles::check_output(out)?;
            }
            self.pocket_arc(bottom, (a, b, c), at / 2.0, at / 2.0, 0.0, sign * 180.0, out);
        }
        Ok(true)
    }

    /// An arc of a pocket at `bottom` (the centre at the cutting depth): about the point
    /// `centre` along the plane's first axis from the pocket's centre, of `radius`, ending at
    /// `end` along that axis, sweeping `sweep` degrees (positive: counter-clockwise).
    #[allow(clippy::too_many_arguments)]
    fn pocket_arc(
        &mut self,
        bottom: Pos,
        (a, b, c): (usize, usize, usize),
        centre: f64,
        radius: f64,
        end: f64,
        sweep: f64,
        out: &mut Vec<Canon>,
    ) {
        let mut target = bottom;
        target[a] += end;
        let mut at = bottom;
        at[a] += centre;
        let kind = if sweep < 0.0 { MotionKind::ArcCw } else { MotionKind::ArcCcw };
        let arc = Arc { center: at, plane_axes: (a, b, c), radius, sweep_deg: sweep };
        // Plain programming coordinates (`pocket_modes_supported`): the programmed point is
        // the workpiece one.
        self.push_motion(kind, target, Some(Box::new(arc)), out);
        self.xf.programmed = target;
    }

    /// G70 bolt hole circle, G71 bolt hole arc, G72 bolt holes along an angle: the canned cycle
    /// in force at each hole. The block's X/Y give the pattern's centre (G70/G71) or its first
    /// hole (G72), where the cycle does not drill; its R/Z/Q/P/F are the cycle's data, as in a
    /// cycle block. The tool ends over the last hole at the cycle's return level.
    pub(super) fn bolt_pattern(&mut self, code: u16, w: &Words, out: &mut Vec<Canon>) -> Result<bool, AlarmId> {
        if self.modes[group::CYCLE] == code::G80 {
            // The manual: a canned cycle must be in force for a hole to be made at each
            // position; without one fivex refuses the block rather than guess a move.
            return Err(AlarmId::ImproperGCode);
        }
        if self.modes[group::PLANE] != code::G17 {
            return Err(AlarmId::ImproperGCode);
        }
        let i = self.value(w, b'I').ok_or(AlarmId::CycleArgument)?;
        let j = self.angle_word(w, b'J').unwrap_or(0.0);
        let l = count(w, b'L', MAX_HOLES)?.ok_or(AlarmId::CycleArgument)?;
        let (d, (pa, pb)) = self.cycle_data(w)?;
        let origin = self.programmed_target(w, Some(d));
        let hole = |radius: f64, angle: f64| {
            let (s, c) = crate::angle::sin_cos_deg(angle);
            let mut p = origin;
            p[pa] += radius * c;
            p[pb] += radius * s;
            p
        };
        let holes: Vec<Pos> = match code {
            code::G70 if i != 0.0 => {
                // I negative: the holes clockwise (the manual's sign of I).
                let step = 360.0 / l as f64 * i.signum();
                bolt_angles(j, step, l).map(|t| hole(i.abs(), t)).collect()
            }
            code::G71 if i != 0.0 => {
                let k = self.angle_word(w, b'K').ok_or(AlarmId::CycleArgument)?;
                if k == 0.0 {
                    return Err(AlarmId::CycleArgument);
                }
                bolt_angles(j, k, l).map(|t| hole(i, t)).collect()
            }
            // I is the distance between holes; the first is the block's point.
            code::G72 => (0..l).map(|n| hole(i * n as f64, j)).collect(),
            _ => return Err(AlarmId::CycleArgument),
        };
        for mut h in holes {
            // Over the next hole at the level the last one left the tool (G98/G99), as a
            // cycle block's next hole.
            h[d] = self.xf.programmed[d];
            self.cycle_at(h, d, (pa, pb), out)?;
        }
        Ok(true)
    }

    /// G103 P0–P15: the look-ahead of the motions that follow limited to P blocks (P0, or no P:
    /// not limited). Every motion carries it to the planner (`canon::Motion::block_limit`).
    pub(super) fn block_look_ahead(&mut self, w: &Words) -> Result<(), AlarmId> {
        let p = w.integer(b'P').unwrap_or(0.0);
        if p.fract() != 0.0 || !(0.0..=MAX_BLOCK_LIMIT).contains(&p) {
            return Err(AlarmId::CycleArgument);
        }
        self.block_limit = p as u8;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pocket_radii_follow_the_manual_s_rules() {
        // I only: one pass on I less the tool radius.
        assert_eq!(pocket_radii(Some(10.0), None, None, 3.0), Ok(vec![7.0]));
        // I, K, Q: I, I+Q … and K itself last.
        assert_eq!(pocket_radii(Some(2.0), Some(10.0), Some(3.0), 1.0), Ok(vec![1.0, 4.0, 7.0, 9.0]));
        assert_eq!(pocket_radii(Some(2.0), Some(8.0), Some(3.0), 0.0), Ok(vec![2.0, 5.0, 8.0]));
        // I not greater than the tool radius, K not greater than I, Q without K, K without Q,
        // Q not positive, I missing.
        for (i, k, q) in [
            (Some(3.0), None, None),
            (Some(5.0), Some(5.0), Some(1.0)),
            (Some(5.0), None, Some(1.0)),
            (Some(5.0), Some(9.0), None),
            (Some(5.0), Some(9.0), Some(0.0)),
            (None, Some(9.0), Some(1.0)),
        ] {
            assert_eq!(pocket_radii(i, k, q, 3.0), Err(AlarmId::CycleArgument), "{i:?} {k:?} {q:?}");
        }
        assert_eq!(pocket_radii(Some(1.0), None, None, -0.5), Err(AlarmId::CycleArgument));
    }
}
