//! FANUC nano smoothing, G05.1 Q3, and Syntec STCP and HPCC (`docs/motion.md`, "Nano
//! smoothing"): `G05.1 Q3 X0 Y0 Z0 [α0 β0]` names the axes smoothed — the linear group and at
//! most two rotary axes (nano smoothing for 5-axis machining, also under G43.4) — and turns
//! look-ahead on; `G05.1 Q0` (or Q1) ends it. STCP (`G43.4 L1`, or G43.4 with Pr3051 = 1)
//! smooths the five RTCP axes within Pr407 and Pr3052/3053 until G49 or `G43.4 L0`. HPCC
//! (`G05 P10000 [X0 Y0 Z0 α β]`) smooths X, Y, Z, or the axes its arguments name, with the same
//! tolerances until G05 P0, M02/M30 or a reset. In the mode, a G01
//! block of axis words and F alone is a point of the curve (`crate::smoothing` builds it and
//! says which spans are ready); any other block first moves every span held, then runs as it
//! always does. A span's chords are emitted as that block's
//! motions (its line, sequence number and F) through the tip path under TCP.

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, MotionKind};
use crate::machine::{AxisKind, MAX_AXES, STCP_PATH_TOLERANCE_MM, STCP_ROTARY_TOLERANCE_DEG};
use crate::smoothing::{Settings, Smoother, Span};

use super::BlockTag as Tag;

/// The least input increment of a rotary axis (IS-B), the tolerance No.19587 = 0 gives.
const LEAST_INCREMENT_DEG: f64 = 0.001;

/// Which function smooths.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Source {
    /// FANUC G05.1 Q3.
    Nano,
    /// Syntec STCP.
    Stcp,
    /// Syntec HPCC (G05 P10000).
    Hpcc,
}

/// Nano smoothing, STCP or HPCC in force.
#[derive(Debug, Clone)]
pub(super) struct Smoothing {
    source: Source,
    settings: Settings<MAX_AXES>,
    /// The run being built (`None` until its first point: it starts where the tool is then).
    run: Option<Smoother<Tag, MAX_AXES>>,
    /// The block being executed is a point of the curve.
    point: bool,
}

impl State {
    /// G05.1 (a one-shot code whose axis words name axes): Q1 look-ahead on, Q0 off, Q3 nano
    /// smoothing on (and look-ahead with it). The block is not a point of the curve, so what
    /// was held has been moved before it.
    pub(super) fn g05_1(&mut self, w: &Words) -> Result<(), AlarmId> {
        let q = w.integer(b'Q');
        if self.cfg.dialect != crate::Dialect::Fanuc {
            // Syntec's G05.1 (Q0–Q2 with E) is not FANUC's: its Q3 is refused (`unbuilt`), or
            // run for its mode rules alone when refusals are off.
            self.look_ahead = q == Some(1.0);
            return Ok(());
        }
        self.smoothing = None;
        self.look_ahead = q == Some(1.0) || q == Some(3.0);
        if q == Some(3.0) {
            let settings = self.smoothing_settings(w)?;
            self.smoothing = Some(Box::new(Smoothing { source: Source::Nano, settings, run: None, point: false }));
        }
        Ok(())
    }

    /// Syntec's G05 (its axis words are its arguments, `GDef::owns_axes`): P10000 turns HPCC on
    /// with the axes of [`State::g05_form`], P0 ends it (a G05 P10000 in HPCC starts it again
    /// with its own axes). The block is not a point of the curve: what was held has been moved
    /// before it. FANUC's G05 P0 does nothing (its other forms are refused, `unbuilt`).
    pub(super) fn g05(&mut self, w: &Words) -> Result<(), AlarmId> {
        if self.cfg.dialect != crate::Dialect::Syntec {
            return Ok(());
        }
        let settings = self.g05_form(w)?;
        self.hpcc_end();
        if let Some(settings) = settings {
            self.smoothing = Some(Box::new(Smoothing { source: Source::Hpcc, settings, run: None, point: false }));
        }
        Ok(())
    }

    /// Syntec's G05 format (5-axis manual §3.1, COR-107), which the mode interlocks check before
    /// the block changes anything: P is 10000 (HPCC on, with these settings) or 0 (off: `None`);
    /// an E given is positive (and then refused as not built: `unbuilt`). `G05 P10000` smooths
    /// X, Y, Z within Pr407; `G05 P10000 X0 Y0 Z0 α β` the geometry axes given (each 0) within
    /// Pr407 and the rotary ones given (one or two of the mechanism's, each positive) within
    /// Pr3052 / Pr3053: both kinds or neither, so five axes at most. Any other axis word, or one
    /// in a G05 P0 block, is a format error too (the readings: `docs/motion.md`, "Syntec HPCC").
    pub(super) fn g05_form(&self, w: &Words) -> Result<Option<Settings<MAX_AXES>>, AlarmId> {
        let bad = Err(AlarmId::HpccFormat);
        if w.number(b'E').is_some_and(|e| e <= 0.0) {
            return bad;
        }
        let m = &self.cfg.machine;
        let named = m.axes.iter().any(|a| w.has(a.name as u8));
        match w.number(b'P') {
            Some(10000.0) => {}
            Some(0.0) if !named => return Ok(None),
            _ => return bad,
        }
        // STCP's axes and tolerances: X, Y, Z within Pr407, the master and slave within
        // Pr3052 / Pr3053.
        let mut s = self.stcp_settings();
        if !named {
            s.rotary = [None; MAX_AXES];
            return Ok(Some(s));
        }
        let (mut geometry, mut rotary) = (0, 0);
        for (i, axis) in m.axes.iter().enumerate() {
            let Some(v) = w.number(axis.name as u8) else {
                (s.linear[i], s.rotary[i]) = (false, None);
                continue;
            };
            if s.linear[i] && v == 0.0 {
                geometry += 1;
            } else if s.rotary[i].is_some() && v > 0.0 {
                rotary += 1;
            } else {
                return bad;
            }
        }
        if geometry == 0 || rotary == 0 {
            return bad;
        }
        Ok(Some(s))
    }

    /// Syntec's HPCC is on.
    pub(super) fn hpcc_on(&self) -> bool {
        self.smoothing.as_deref().is_some_and(|s| s.source == Source::Hpcc)
    }

    /// HPCC ends (G05 P0, M02/M30, the end of the program's text, a reset): what it held has
    /// been moved first, or dropped by the reset.
    pub(super) fn hpcc_end(&mut self) {
        if self.hpcc_on() {
            self.smoothing = None;
        }
    }

    /// STCP follows the mode a block leaves (the block's own motion is not smoothed: what was
    /// held has been moved before it): on, the five RTCP axes are smoothed — X, Y, Z within
    /// Pr407 of their 3-D path, the master and slave rotary axes within Pr3052 / Pr3053 —
    /// with nano smoothing's conditions for blocks and corners (`motion.nano_smoothing`:
    /// Syntec's manual gives none); off, it ends.
    pub(super) fn follow_stcp(&mut self) {
        let stcp = self.five.stcp_on() && self.cfg.dialect == crate::Dialect::Syntec;
        let active = self.smoothing.as_deref().is_some_and(|s| s.source == Source::Stcp);
        if stcp == active {
            return;
        }
        self.smoothing = None;
        if stcp {
            let settings = self.stcp_settings();
            self.smoothing = Some(Box::new(Smoothing { source: Source::Stcp, settings, run: None, point: false }));
        }
    }

    /// STCP's axes and tolerances: X, Y, Z and the mechanism's two rotary axes.
    fn stcp_settings(&self) -> Settings<MAX_AXES> {
        let m = &self.cfg.machine;
        let f = &m.five_axis;
        let [master, slave] = f.smooth_tolerance.unwrap_or([STCP_ROTARY_TOLERANCE_DEG; 2]);
        let mut linear = [false; MAX_AXES];
        let mut rotary = [None; MAX_AXES];
        let mut mm = [false; MAX_AXES];
        for (i, axis) in m.axes.iter().enumerate() {
            mm[i] = axis.kind == AxisKind::Linear;
            linear[i] = matches!(axis.name, 'X' | 'Y' | 'Z') && axis.kind == AxisKind::Linear;
            let link = m.rotary.iter().position(|l| l.axis == axis.name && l.fixed.is_none());
            rotary[i] = link.map(|k| if k == 0 { master } else { slave });
        }
        let tolerance = f.smooth_path_tolerance.unwrap_or(STCP_PATH_TOLERANCE_MM);
        Settings { linear, rotary, tolerance, ..self.smoothing_conditions(mm) }
    }

    /// The block and corner conditions of `motion.nano_smoothing` and the axes' acceleration,
    /// nothing smoothed yet.
    fn smoothing_conditions(&self, mm: [bool; MAX_AXES]) -> Settings<MAX_AXES> {
        let m = &self.cfg.machine;
        let n = &m.motion.nano_smoothing;
        Settings {
            linear: [false; MAX_AXES],
            rotary: [None; MAX_AXES],
            tolerance: n.tolerance,
            min_block: n.min_block,
            max_block: n.max_block,
            corner_cos: n.corner_angle.to_radians().cos(),
            spacing_ratio: n.spacing_ratio,
            mm,
            accel: std::array::from_fn(|i| m.axes.get(i).map_or(f64::INFINITY, crate::machine::Axis::max_accel)),
        }
    }

    /// The axes `G05.1 Q3` names (each with 0): one to three linear axes and at most two
    /// rotary ones; anything else is refused (PS0010).
    fn smoothing_settings(&self, w: &Words) -> Result<Settings<MAX_AXES>, AlarmId> {
        let m = &self.cfg.machine;
        let mut linear = [false; MAX_AXES];
        let mut rotary = [None; MAX_AXES];
        let mut mm = [false; MAX_AXES];
        for (i, axis) in m.axes.iter().enumerate() {
            mm[i] = axis.kind == AxisKind::Linear;
            let Some(value) = w.number(axis.name as u8) else { continue };
            if value != 0.0 {
                return Err(AlarmId::ImproperGCode);
            }
            match axis.kind {
                AxisKind::Linear => linear[i] = true,
                AxisKind::Rotary => {
                    let tol = axis.smoothing_tolerance;
                    rotary[i] = Some(if tol > 0.0 { tol } else { LEAST_INCREMENT_DEG });
                }
            }
        }
        let count = |named: &mut dyn Iterator<Item = bool>| named.filter(|&b| b).count();
        let (lin, rot) = (count(&mut linear.iter().copied()), count(&mut rotary.iter().map(Option::is_some)));
        if !(1..=3).contains(&lin) || rot > 2 {
            return Err(AlarmId::ImproperGCode);
        }
        Ok(Settings { linear, rotary, ..self.smoothing_conditions(mm) })
    }

    /// In nano smoothing, STCP or HPCC, before anything of the block is done: whether it is a
    /// point of the curve (a G01 block of axis words and F, in G94/G95, outside canned cycles
    /// and modal calls); if not, every span held is moved first. In nano smoothing, starting
    /// TCP, a tilted working plane or G54.4 is refused (G43.4 comes first, G05.1 Q0 before G49
    /// — NSM-05 — and the other two do not list G05.1 Q3 among their modal states); in HPCC,
    /// RTCP is refused by the mode interlocks (COR-140).
    pub(super) fn smoothing_block(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let Some(s) = self.smoothing.as_deref() else { return Ok(()) };
        let motion = match w.gcodes() {
            [] => self.modes[group::MOTION],
            [c] => *c,
            _ => 0,
        };
        let point = motion == code::G01
            && w.mcodes().is_empty()
            && self.modes[group::FEED_MODE] != code::G93
            && self.modes[group::CYCLE] == code::G80
            && self.modal_calls.is_empty()
            && w.letters().all(|l| l == b'G' || l == b'F' || self.axis_of(l).is_some());
        let nano = s.source == Source::Nano;
        if !point && s.run.is_some() {
            self.smoothing_flush(out)?;
        }
        if nano {
            let starts = |codes: &[u16]| w.gcodes().iter().any(|c| codes.contains(c));
            if starts(&[code::G43_4, code::G43_5]) {
                return Err(AlarmId::IllegalCommandInTcp);
            }
            if starts(&[code::G68_2, code::G68_3, code::G68_4, code::G53_1, code::G53_3, code::G53_6]) {
                return Err(AlarmId::TwpIllegalCommand);
            }
            if starts(&[code::G54_4]) && w.integer(b'P') != Some(0.0) {
                return Err(AlarmId::WseModalState);
            }
        }
        if let Some(s) = self.smoothing.as_deref_mut() {
            s.point = point;
        }
        Ok(())
    }

    /// The G01 block being executed is a point of the curve (`smoothing_block`).
    pub(super) fn smoothing_point_block(&self) -> bool {
        self.smoothing.as_deref().is_some_and(|s| s.point)
    }

    /// The block's end point `target` (after the programming transforms): into the curve;
    /// the spans it completes are moved.
    pub(super) fn smoothing_point(&mut self, target: crate::canon::Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let tag = self.block_tag();
        let start = self.pos;
        let s = self.smoothing.as_deref_mut().expect("nano smoothing in force");
        let settings = s.settings;
        let run = s.run.get_or_insert_with(|| Smoother::new(settings, start));
        let mut spans = Vec::new();
        run.push(target, tag, &mut spans);
        self.emit_spans(spans, out)
    }

    /// Move every span held (the run ends at its last point).
    pub(super) fn smoothing_flush(&mut self, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        let Some(mut run) = self.smoothing.as_deref_mut().and_then(|s| s.run.take()) else { return Ok(()) };
        let mut spans = Vec::new();
        run.finish(&mut spans);
        self.emit_spans(spans, out)
    }

    /// A reset: what was held is dropped (the next run starts where the tool stands), and HPCC
    /// ends (decision: Syntec's manual does not say; its tolerance Pr407 takes effect at a
    /// reset, so a reset starts again from the cancelled state, as M02/M30 do).
    pub(super) fn smoothing_reset(&mut self) {
        if let Some(s) = self.smoothing.as_deref_mut() {
            s.run = None;
        }
        self.hpcc_end();
    }

    /// Each span's chords as motions of its block (its line, sequence number and F), no faster
    /// than the span's curve allows the axes.
    fn emit_spans(&mut self, spans: Vec<Span<Tag, MAX_AXES>>, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        for span in spans {
            let first = out.len();
            self.as_block(span.tag, |s| {
                for q in span.chords {
                    if s.follows_tip() {
                        // An alarm here names the block whose motion it is.
                        s.tip_motion(MotionKind::Linear, q, None, out)?;
                    } else {
                        s.push_motion(MotionKind::Linear, q, None, out);
                    }
                }
                Ok(())
            })?;
            crate::canon::cap_speed(&mut out[first..], span.speed_cap);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::interp::{Config, Interpreter};
    use crate::lang::parse_file;
    use crate::machine::MachineConfig;
    use crate::Dialect;

    /// Whether HPCC is on after `src`'s first `blocks` blocks (Syntec, mill3), and after a reset
    /// then.
    fn hpcc_after(src: &str, blocks: usize) -> (bool, bool) {
        let cfg = Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Syntec);
        let mut interp = Interpreter::new(parse_file(src), cfg);
        let mut out = Vec::new();
        for _ in 0..blocks {
            interp.step(&mut out).unwrap();
        }
        let on = interp.state.hpcc_on();
        interp.reset();
        (on, interp.state.hpcc_on())
    }

    #[test]
    fn g05_p0_m02_m30_the_end_and_a_reset_end_hpcc() {
        let on = "G05 P10000\nG01 X1. F1000\n";
        assert_eq!(hpcc_after(&format!("{on}X2. Y0.1\nM30\n"), 3), (true, false));
        for end in ["G05 P0\n", "M30\n", "M02\n"] {
            assert!(!hpcc_after(&format!("{on}{end}X3.\n"), 3).0, "{end}");
        }
        // The end of the program's text (an end step after the last block).
        assert!(!hpcc_after(on, 3).0);
        // G05 P10000 in HPCC keeps it on; FANUC's G05 is not HPCC.
        assert!(hpcc_after(&format!("{on}G05 P10000\n"), 3).0);
        let cfg = Config::new(MachineConfig::preset("mill3").unwrap(), Dialect::Fanuc);
        let mut interp = Interpreter::new(parse_file("G05 P10000\n"), Config { refuse_unbuilt: false, ..cfg });
        interp.step(&mut Vec::new()).unwrap();
        assert!(!interp.state.hpcc_on());
    }
}
