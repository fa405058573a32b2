//! G06.2 NURBS interpolation (FANUC's format; `docs/dialects.md`, "NURBS interpolation"). The
//! curve spans several blocks: the G06.2 block starts a [`Builder`] with the first control
//! point, each later block adds a control point with its knot or a knot alone, and the block
//! with the `rank`-th knot-only word completes it: the curve is checked (`crate::nurbs`) and
//! emitted there as straight chords within `nurbs::CHORD_TOLERANCE_MM` of it, at the feed in
//! force, through the tip path under tool centre point control, each no faster than the curve's
//! bending leaves the axes' acceleration and jerk (`chords::bending_speed`).

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
        self.nurbs = Some(Box::new(Builder {
            rank,
            knots: vec![knot],
            points: vec![here],
            weights: vec![weight],
            closing: 0,
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
            let last = *b.points.last().expect("the first control point");
            let p = self.control_point(w, last);
            let weight = w.number(b'R').unwrap_or(1.0);
            let b = self.nurbs.as_deref_mut().expect("a curve in progress");
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
        let end = *points.last().expect("a control point");
        let curve = Curve::<MAX_AXES>::new(b.rank, b.knots, points, b.weights).map_err(|_| AlarmId::NurbsFormat)?;
        let linear: [bool; MAX_AXES] =
            std::array::from_fn(|i| self.cfg.machine.axes.get(i).is_none_or(|a| a.kind == AxisKind::Linear));
        let chords = curve.chords(&linear).map_err(|_| AlarmId::NurbsFormat)?;
        let n = chords.len();
        let axis = |f: fn(&crate::machine::Axis) -> f64| -> [f64; MAX_AXES] {
            std::array::from_fn(|i| self.cfg.machine.axes.get(i).map_or(f64::INFINITY, f))
        };
        let (accel, jerk) = (axis(crate::machine::Axis::max_accel), axis(crate::machine::Axis::max_jerk));
        let bending = |at: f64| {
            let [c, d1, d2] = curve.derivatives(at);
            (c, crate::chords::by_length(&d1, &d2, &linear))
        };
        let mut u0 = curve.domain().0;
        for (i, (u, q)) in chords.into_iter().enumerate() {
            // The curve ends exactly at its last control point.
            let q = if i + 1 == n { end } else { q };
            let first = out.len();
            if self.follows_tip() {
                self.tip_motion(MotionKind::Linear, q, None, out)?;
            } else {
                self.push_motion(MotionKind::Linear, q, None, out);
            }
            // No faster than the curve's bending leaves the axes' acceleration (at the chord's
            // ends and middle) and jerk (its change along the chord: the curve's derivatives
            // are exact, so the difference is the curve's).
            let ends = [bending(u0), bending(0.5 * (u0 + u)), bending(u)];
            let mut cap = ends
                .iter()
                .filter_map(|(_, x)| x.map(|x| crate::chords::bending_speed(&x, &accel)))
                .fold(f64::INFINITY, f64::min);
            if let ((c0, Some(x0)), (c1, Some(x1))) = (ends[0], ends[2]) {
                let ds = (0..MAX_AXES).filter(|&i| linear[i]).map(|i| (c1[i] - c0[i]).powi(2)).sum::<f64>().sqrt();
                cap = cap.min(crate::chords::bending_jerk_speed(&x0, &x1, ds, &jerk));
            }
            crate::canon::cap_speed(&mut out[first..], cap);
            u0 = u;
        }
        self.xf.programmed = last;
        Ok(())
    }
}
