//! G06.2 NURBS interpolation (FANUC's format; `docs/dialects.md`, "NURBS interpolation"). The
//! curve spans several blocks: the G06.2 block starts a [`Builder`] with the first control
//! point, each later block adds a control point with its knot or a knot alone, and the block
//! with the `rank`-th knot-only word completes it: the curve is checked (`crate::nurbs`) and
//! emitted there as straight chords within `nurbs::CHORD_TOLERANCE_MM` of it, at the feed in
//! force, through the tip path under tool centre point control, each no faster than the bending
//! of the chords' polygon leaves the axes' acceleration and jerk ([`polygon_caps`]).

use super::gcode::{self, code, group};
use super::modes;
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, MotionKind, Pos};
use crate::machine::{AxisKind, MAX_AXES};
use crate::nurbs::{Curve, CHORD_TOLERANCE_MM};

/// Rank when the G06.2 block gives no P (cubic).
const DEFAULT_RANK: usize = 4;

/// A NURBS curve being given, block by block.
#[derive(Debug, Clone)]
pub(super) struct Builder {
    rank: usize,
    knots: Vec<f64>,
    /// Control points in programmed coordinates (before the programming transforms).
    points: Vec<Pos>,
    weights: Vec<f64>,
    /// Knot-only blocks so far (the curve is complete at `rank` of them).
    closing: usize,
    /// The curve's axes (bit per axis index): those of the G06.2 block, or of the second
    /// block when the G06.2 block names none (`None` until then). An axis outside them in a
    /// later control point is PS5115 (15i-MA: an axis not given a control point in the first
    /// block "cannot be specified until the next NURBS curved line starts").
    axes: Option<u32>,
    /// The angle last written for each rollover axis (absolute control points; at the start
    /// the angle shown), to hold the curve's control points to what is written
    /// ([`State::rewrapped`]).
    written: Pos,
    /// The machine was moved by hand (jog, handle) between the curve's blocks
    /// (`Interpreter::moved_to`): the curve's next block is PS5117.
    pub(super) moved_by_hand: bool,
}

impl State {
    /// A G06.2 block in a state whose NURBS interpolation fivex does not perform is refused
    /// like a function not built (before the block changes anything): under cutter
    /// compensation, polar coordinates (G16), inverse time feed (G93) or feed per revolution
    /// (G95), polar coordinate interpolation (G12.1), or a modal macro call. The 15i-MA manual
    /// (NURBS, alarm 1006) raises an alarm for G06.2 in G41/G42, G93/G95 and G12.1 alike.
    pub(super) fn refuse_unbuilt_nurbs(&self, w: &Words) -> Result<(), AlarmId> {
        if !w.gcodes().contains(&code::G06_2) {
            return Ok(());
        }
        if self.after_block(w, group::CUTTER_COMP) != code::G40
            || self.after_block(w, group::POLAR) == code::G16
            || matches!(self.after_block(w, group::FEED_MODE), code::G93 | code::G95)
            || self.after_block(w, group::POLAR_INTERPOLATION) == code::G12_1
            || !self.modal_calls.is_empty()
            || w.gcodes().iter().any(|&c| c == code::G66 || c == code::G66_1)
        {
            return Err(AlarmId::GCodeNotBuilt);
        }
        Ok(())
    }

    /// NURBS interpolation mode lasts as long as G06.2 is the group-01 code (15i-MA: it "ends
    /// when a G code of group 01 other than G06.2 … is specified"), and "in NURBS interpolation
    /// mode, commands (such as auxiliary functions) other than NURBS interpolation cannot be
    /// specified"; the functions used with it are given before the mode and cancelled after it
    /// ends. So a block of NC words in the mode that neither starts a curve (G06.2) nor ends
    /// the mode (another group-01 code) is PS5116, whatever it holds (M, S, T, G04, G43/G49,
    /// G68/G69, G50/G51, G92, G10, G28, G53, F, G90/G91 …), and so is a G06.2 block with
    /// another function than the curve's (only G90/G91, P, K, R, F and axis words). Inside a
    /// curve `nurbs_block` answers first. A mode interlock that also refuses the block
    /// (`interp::modes`: G49 under TCP in G06.2 mode, PS5421), or G06.2 in a mode it is not
    /// built for (PS0010, `refuse_unbuilt_nurbs`), is the more precise alarm.
    pub(super) fn refuse_in_nurbs_mode(&self, w: &Words) -> Result<(), AlarmId> {
        let dialect = self.cfg.dialect;
        let motion =
            w.gcodes().iter().copied().find(|&c| gcode::lookup(c, dialect).is_some_and(|d| d.group == group::MOTION));
        let starts = motion == Some(code::G06_2);
        if !(starts || motion.is_none() && self.modes[group::MOTION] == code::G06_2) {
            return Ok(());
        }
        let foreign = if starts {
            w.gcodes().iter().any(|&c| !matches!(c, code::G06_2 | code::G90 | code::G91))
                || w.letters().any(|l| !matches!(l, b'G' | b'P' | b'K' | b'R' | b'F') && self.axis_of(l).is_none())
        } else {
            w.letters().next().is_some()
        };
        if foreign {
            modes::check(self, w)?;
            if self.cfg.refuse_unbuilt {
                self.refuse_unbuilt_nurbs(w)?;
            }
            return Err(AlarmId::NurbsBlock);
        }
        Ok(())
    }

    /// Whether a control point `to` of a rollover axis is not what its block writes: an
    /// absolute angle of a rollover axis is an angle modulo 360, which `target` turns into a
    /// travel from the previous control point `from` by the axis's positioning rule (the
    /// shorter way, FANUC No.1008 RAB = 0; or the command's sign). A control point is not a
    /// point the axis travels to, and a curve through re-wrapped points is another curve (0,
    /// 190, 270, 360 taken the shorter way is 0, −170, −90, 0: C turns backwards). The manual
    /// is silent, so fivex takes a rollover axis's control point only where the rule leaves the
    /// step the program writes, from the previous control point's written angle (`written`,
    /// updated), and refuses it otherwise (PS5115, decision, `docs/dialects.md`). Incremental
    /// control points are steps already.
    fn rewrapped(&self, w: &Words, written: &mut Pos, from: &Pos, to: &Pos) -> bool {
        if self.modes[group::DISTANCE] == code::G91 {
            return false;
        }
        let mut moved = false;
        for (i, axis) in self.cfg.machine.axes.iter().enumerate().filter(|(_, a)| a.rollover) {
            if let Some(v) = self.value(w, axis.name as u8) {
                moved |= ((to[i] - from[i]) - (v - written[i])).abs() > 1e-9;
                written[i] = v;
            }
        }
        moved
    }

    /// The axes a block names, a bit per axis index.
    fn axes_named(&self, w: &Words) -> u32 {
        w.letters().filter_map(|l| self.axis_of(l)).fold(0, |m, i| m | 1 << i)
    }

    /// The control point of a block: its axis words from the previous control point `from`
    /// (omitted axes keep its value; G91 counts from it), in programmed coordinates.
    fn control_point(&mut self, w: &Words, from: Pos) -> Pos {
        let here = self.xf.programmed;
        self.xf.programmed = from;
        let p = self.target(w);
        self.xf.programmed = here;
        p
    }

    /// The G06.2 block: rank P (2–4, default 4), the first knot K (the second block's when
    /// omitted), the first control point (the current position: PS5117 otherwise; omitted axes
    /// are the current position) and its weight R (default 1).
    pub(super) fn nurbs_start(&mut self, w: &Words) -> Result<(), AlarmId> {
        let rank = match w.number(b'P') {
            None => DEFAULT_RANK,
            Some(p) if p.fract() == 0.0 && (2.0..=4.0).contains(&p) => p as usize,
            Some(_) => return Err(AlarmId::NurbsFormat),
        };
        // Without K here the first knot is the second block's (FANUC 15i-MA §4.17: NaN marks it).
        let knot = w.number(b'K').unwrap_or(f64::NAN);
        let weight = w.number(b'R').unwrap_or(1.0);
        self.check_feed()?;
        let here = self.xf.programmed;
        let first = self.control_point(w, here);
        if first.iter().zip(&here).any(|(a, b)| (a - b).abs() > CHORD_TOLERANCE_MM) {
            return Err(AlarmId::NurbsStart);
        }
        let mut written = here.map(crate::angle::basic);
        self.rewrapped(w, &mut written, &here, &first);
        self.nurbs = Some(Box::new(Builder {
            rank,
            knots: vec![knot],
            points: vec![here],
            weights: vec![weight],
            closing: 0,
            written,
            axes: Some(self.axes_named(w)).filter(|&axes| axes != 0),
            moved_by_hand: false,
        }));
        Ok(())
    }

    /// A block while a curve is being given: a control point with its knot (`K X Y Z [R]`) or
    /// a knot alone (`K`); anything else ends the curve with an alarm.
    pub(super) fn nurbs_block(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        if self.nurbs.as_deref().is_some_and(|b| b.moved_by_hand) {
            return Err(AlarmId::NurbsStart);
        }
        let dialect = self.cfg.dialect;
        if w.gcodes().iter().any(|&c| gcode::lookup(c, dialect).is_some_and(|d| d.group == group::MOTION)) {
            // A group-01 code ends NURBS mode before the curve's last knot.
            return Err(AlarmId::NurbsFormat);
        }
        if !w.gcodes().is_empty()
            || !w.mcodes().is_empty()
            || w.letters().any(|l| !matches!(l, b'K' | b'R') && self.axis_of(l).is_none())
        {
            return Err(AlarmId::NurbsBlock);
        }
        if w.letters().next().is_none() {
            return Ok(());
        }
        let knot = w.number(b'K').ok_or(AlarmId::NurbsFormat)?;
        let point = w.has(b'R') || w.letters().any(|l| self.axis_of(l).is_some());
        let b = self.nurbs.as_deref_mut().expect("a curve in progress");
        if b.knots[0].is_nan() {
            b.knots[0] = knot;
        }
        let b = self.nurbs.as_deref().expect("a curve in progress");
        if point {
            if b.closing > 0 {
                // A control point after the closing knots: the knot count is wrong.
                return Err(AlarmId::NurbsFormat);
            }
            let named = self.axes_named(w);
            if b.axes.is_some_and(|axes| named & !axes != 0) {
                return Err(AlarmId::NurbsFormat);
            }
            self.five = modes::check(self, w)?;
            let (last, mut written) = (*b.points.last().expect("the first control point"), b.written);
            let p = self.control_point(w, last);
            if self.rewrapped(w, &mut written, &last, &p) {
                return Err(AlarmId::NurbsFormat);
            }
            let weight = w.number(b'R').unwrap_or(1.0);
            let b = self.nurbs.as_deref_mut().expect("a curve in progress");
            b.written = written;
            b.axes.get_or_insert(named);
            b.points.push(p);
            b.knots.push(knot);
            b.weights.push(weight);
            return Ok(());
        }
        let b = self.nurbs.as_deref_mut().expect("a curve in progress");
        b.knots.push(knot);
        b.closing += 1;
        if b.closing < b.rank {
            return Ok(());
        }
        let b = *self.nurbs.take().expect("a curve in progress");
        self.nurbs_emit(b, out)
    }

    /// The complete curve: checked, cut into chords, emitted from this block.
    fn nurbs_emit(&mut self, b: Builder, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let last = *b.points.last().expect("a control point");
        // NURBS curves are invariant under affine maps: the programming transforms (G68
        // rotation, G51 scaling, G51.1 mirror image) move the control points.
        let points: Vec<Pos> = b.points.iter().map(|p| self.xf.forward(p)).collect();
        let (start, end) = (points[0], *points.last().expect("a control point"));
        let curve = Curve::<MAX_AXES>::new(b.rank, b.knots, points, b.weights).map_err(|_| AlarmId::NurbsFormat)?;
        let linear: [bool; MAX_AXES] =
            std::array::from_fn(|i| self.cfg.machine.axes.get(i).is_none_or(|a| a.kind == AxisKind::Linear));
        let chords = curve.chords(&linear).map_err(|_| AlarmId::NurbsFormat)?;
        let n = chords.len();
        let axis = |f: fn(&crate::machine::Axis) -> f64| -> [f64; MAX_AXES] {
            std::array::from_fn(|i| self.cfg.machine.axes.get(i).map_or(f64::INFINITY, f))
        };
        let (accel, jerk) = (axis(crate::machine::Axis::max_accel), axis(crate::machine::Axis::max_jerk));
        // The curve starts at its first control point and ends exactly at its last.
        let mut vertices = Vec::with_capacity(n + 1);
        vertices.push(start);
        vertices.extend(chords.iter().enumerate().map(|(i, (_, q))| if i + 1 == n { end } else { *q }));
        let corners: Vec<bool> = chords.iter().map(|(u, _)| curve.corner_at(*u)).collect();
        let caps = polygon_caps(&vertices, &corners, &linear, &accel, &jerk);
        for (q, cap) in vertices[1..].iter().zip(caps) {
            let first = out.len();
            if self.follows_tip() {
                self.tip_motion(MotionKind::Linear, *q, None, out)?;
            } else {
                self.push_motion(MotionKind::Linear, *q, None, out);
            }
            crate::canon::cap_speed(&mut out[first..], cap);
        }
        self.xf.programmed = last;
        Ok(())
    }
}

/// The speed cap of each chord of a polygon `vertices` (`corners[i]`: the curve has a corner at
/// the end of chord i) from the bending the polygon itself has, as FANUC's speed control along
/// a NURBS curve is modelled (`docs/motion.md`, "NURBS"): at the junction of two chords an axis
/// turns by the change of its direction over their mean length, x_ss = Δ(Δx/Δs)/((L₁ + L₂)/2)
/// (the second derivative by the path length s of a curve through the three vertices, exact
/// on a parabola), and a chord runs no faster than that bending leaves each axis's
/// acceleration at its two ends (`chords::bending_speed`) and than its change along the chord
/// leaves the jerk (`chords::bending_jerk_speed`). The machine runs the chords, not the curve:
/// a point where the curve alone bends sharply (a tiny weight, a control point a micrometre
/// off the tangent) between two vertices is not a speed limit of the straight chord across it.
/// A corner of the curve (`corners`) is a corner of the path, which the planner's corner rule
/// slows the tool for, not a bending; the curve's ends too are junctions with other blocks.
fn polygon_caps(
    vertices: &[Pos],
    corners: &[bool],
    linear: &[bool; MAX_AXES],
    accel: &[f64; MAX_AXES],
    jerk: &[f64; MAX_AXES],
) -> Vec<f64> {
    // Each chord's length (linear components) and its direction per mm of it.
    let legs: Vec<Option<(f64, Pos)>> = vertices
        .windows(2)
        .map(|w| {
            let d: Pos = std::array::from_fn(|c| w[1][c] - w[0][c]);
            let len = (0..MAX_AXES).filter(|&c| linear[c]).map(|c| d[c] * d[c]).sum::<f64>().sqrt();
            (len > 1e-12).then(|| (len, d.map(|x| x / len)))
        })
        .collect();
    // The bending at the end of chord i (the junction with chord i + 1).
    let bending: Vec<Option<Pos>> = (0..legs.len())
        .map(|i| match (legs[i], legs.get(i + 1).copied().flatten()) {
            (Some((l0, d0)), Some((l1, d1))) if !corners[i] => {
                Some(std::array::from_fn(|c| (d1[c] - d0[c]) / (0.5 * (l0 + l1))))
            }
            _ => None,
        })
        .collect();
    (0..legs.len())
        .map(|i| {
            let before = if i > 0 { bending[i - 1] } else { None };
            let after = bending[i];
            let mut cap = [before, after]
                .iter()
                .flatten()
                .map(|x| crate::chords::bending_speed(x, accel))
                .fold(f64::INFINITY, f64::min);
            if let (Some(x0), Some(x1), Some((len, _))) = (before, after, legs[i]) {
                cap = cap.min(crate::chords::bending_jerk_speed(&x0, &x1, len, jerk));
            }
            cap
        })
        .collect()
}
