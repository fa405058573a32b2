//! JSON forms of the CLI's streamed outputs (`docs/contracts.md`): canonical commands and trace
//! samples, written by hand into a buffered writer, since they are the hot path of `fivex
//! interp`/`run --trace`. The run summary is a typed wire format (`crate::wire`).

use fivex_engine::canon::{
    Canon, CanonKind, Coolant, CutterWord, FeedMode, Motion, MotionContext, MotionKind, Pos, SpindleState,
};
use fivex_engine::interp::gcode::{code, display};
use fivex_engine::run::Sample;
use std::io::Write;

/// Appending bytes to a line under construction. Formatting into a `Vec` (rather than through
/// `io::Write`) lets the many small constant copies inline; a whole batch is written at once.
type Out = Vec<u8>;

fn put(w: &mut Out, bytes: &[u8]) {
    w.extend_from_slice(bytes);
}

/// `,"state":"NAME"`.
fn state_field(w: &mut Out, name: &[u8]) {
    put(w, b",\"state\":\"");
    put(w, name);
    put(w, b"\"");
}

/// A number in its shortest form that reads back to the same f64 (`-0` prints as `0.0`).
fn num(w: &mut Out, x: f64) {
    if !x.is_finite() {
        return put(w, b"null");
    }
    let x = if x == 0.0 { 0.0 } else { x };
    if !short_decimal(w, x) {
        put(w, ryu::Buffer::new().format_finite(x).as_bytes());
    }
}

/// Two decimal digits of every number below 100.
const DIGIT_PAIRS: &[u8; 200] = b"0001020304050607080910111213141516171819\
2021222324252627282930313233343536373839\
4041424344454647484950515253545556575859\
6061626364656667686970717273747576777879\
8081828384858687888990919293949596979899";

/// Append `len` bytes of `buf` from `start` (`len ≤ 16`, `start + 16 ≤ N`) with a copy of fixed
/// size: short numbers then cost no `memcpy` call.
fn put_short<const N: usize>(w: &mut Out, buf: &[u8; N], start: usize, len: usize) {
    let at = w.len();
    let chunk: &[u8; 16] = buf[start..start + 16].try_into().expect("16 bytes");
    w.extend_from_slice(chunk);
    w.truncate(at + len);
}

/// Write `v` (< 10⁸) in decimal so that it ends just before `buf[end]`; returns where it starts.
fn digits_before(buf: &mut [u8; 32], end: usize, v: usize) -> usize {
    let (mut i, mut rest) = (end, v);
    while rest >= 100 {
        let pair = rest % 100;
        rest /= 100;
        i -= 2;
        buf[i..i + 2].copy_from_slice(&DIGIT_PAIRS[2 * pair..2 * pair + 2]);
    }
    if rest >= 10 {
        i -= 2;
        buf[i..i + 2].copy_from_slice(&DIGIT_PAIRS[2 * rest..2 * rest + 2]);
    } else {
        i -= 1;
        buf[i] = b'0' + rest as u8;
    }
    i
}

/// Fast path for the numbers NC programs are made of: at most four decimals and below 10⁷.
/// When `x` equals `r / 10⁴` for an integer `r`, that decimal is the shortest round-trip form,
/// so the text is the same `ryu` would print ("12.345", "5.0", "-0.5"); it is made with integer
/// arithmetic only. Returns false (and appends nothing) for other numbers.
fn short_decimal(w: &mut Out, x: f64) -> bool {
    let a = x.abs();
    if !(a == 0.0 || (1e-3..1e7).contains(&a)) {
        return false;
    }
    // Rounded by adding ½ and truncating (a is positive): `f64::round` is a library call here,
    // and a conversion to i64 is one instruction where one to u64 is a dozen.
    let r = (a * 1e4 + 0.5) as i64;
    if r as f64 / 1e4 != a {
        return false;
    }
    let (int, frac) = ((r / 10_000) as usize, (r % 10_000) as usize);
    // The integer part ends at POINT, the fraction follows it.
    const POINT: usize = 16;
    let mut buf = [0u8; 32];
    let mut start = digits_before(&mut buf, POINT, int);
    if x < 0.0 {
        start -= 1;
        buf[start] = b'-';
    }
    buf[POINT] = b'.';
    // Four fraction digits from two pairs, trailing zeros dropped (one zero stays).
    let (hi, lo) = (frac / 100, frac % 100);
    buf[POINT + 1..POINT + 3].copy_from_slice(&DIGIT_PAIRS[2 * hi..2 * hi + 2]);
    buf[POINT + 3..POINT + 5].copy_from_slice(&DIGIT_PAIRS[2 * lo..2 * lo + 2]);
    let decimals = match (hi, lo) {
        (_, 0) if hi % 10 == 0 => 1,
        (_, 0) => 2,
        _ if lo % 10 == 0 => 3,
        _ => 4,
    };
    put_short(w, &buf, start, POINT + 1 + decimals - start);
    true
}

fn uint(w: &mut Out, v: u64) {
    if v < 100_000_000 {
        let mut buf = [0u8; 32];
        let start = digits_before(&mut buf, 16, v as usize);
        return put_short(w, &buf, start, 16 - start);
    }
    put(w, v.to_string().as_bytes());
}

fn axes_map(w: &mut Out, p: &Pos, axes: &[char]) {
    put(w, b"{");
    for (i, a) in axes.iter().enumerate() {
        if i > 0 {
            put(w, b",");
        }
        put(w, &[b'"', *a as u8, b'"', b':']);
        num(w, p[i]);
    }
    put(w, b"}");
}

fn opt_u32(w: &mut Out, n: Option<u32>) {
    match n {
        Some(n) => uint(w, n as u64),
        None => put(w, b"null"),
    }
}

fn json_string(w: &mut Out, s: &str) {
    put(w, serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into()).as_bytes());
}

/// Writes canonical commands as JSON lines (`fivex interp`). It remembers the last motion
/// context and its text: consecutive motions almost always share their context.
pub struct CanonWriter {
    axes: Vec<char>,
    context: Option<(MotionContext, Vec<u8>)>,
}

impl CanonWriter {
    pub fn new(axes: Vec<char>) -> CanonWriter {
        CanonWriter { axes, context: None }
    }

    /// One canonical command as one JSON line, appended to `w`.
    pub fn write(&mut self, w: &mut Out, c: &Canon) {
        let kind = match &c.kind {
            CanonKind::Motion(_) => "motion",
            CanonKind::Dwell { .. } => "dwell",
            CanonKind::ToolSelect { .. } => "tool_select",
            CanonKind::ToolChange { .. } => "tool_change",
            CanonKind::Spindle { .. } => "spindle",
            CanonKind::Coolant(_) => "coolant",
            CanonKind::Aux { .. } => "aux",
            CanonKind::Stop { .. } => "stop",
            CanonKind::Print { .. } => "print",
            CanonKind::ProgramEnd { .. } => "program_end",
            CanonKind::Cutter(_) => "cutter",
            CanonKind::Chain(_) => "chain",
        };
        put(w, b"{\"type\":\"");
        put(w, kind.as_bytes());
        put(w, b"\",\"line\":");
        uint(w, c.line as u64);
        put(w, b",\"n\":");
        opt_u32(w, c.n);
        match &c.kind {
            CanonKind::Motion(m) => self.motion(w, m),
            CanonKind::Dwell { seconds } => {
                put(w, b",\"seconds\":");
                num(w, *seconds);
            }
            CanonKind::ToolSelect { tool } | CanonKind::ToolChange { tool } => {
                put(w, b",\"tool\":");
                uint(w, *tool as u64);
            }
            CanonKind::Spindle { state, speed } => {
                let state: &[u8] = match state {
                    SpindleState::Cw => b"cw",
                    SpindleState::Ccw => b"ccw",
                    SpindleState::Stop => b"stop",
                };
                state_field(w, state);
                put(w, b",\"speed\":");
                num(w, *speed);
            }
            CanonKind::Coolant(c) => {
                let state: &[u8] = match c {
                    Coolant::Mist => b"mist",
                    Coolant::Flood => b"flood",
                    Coolant::Off => b"off",
                };
                state_field(w, state);
            }
            CanonKind::Aux { m } | CanonKind::ProgramEnd { m } => {
                put(w, b",\"m\":");
                uint(w, *m as u64);
            }
            CanonKind::Stop { optional, message } => {
                put(
                    w,
                    if *optional { b",\"optional\":true,\"message\":" } else { b",\"optional\":false,\"message\":" },
                );
                match message {
                    Some(m) => json_string(w, m),
                    None => put(w, b"null"),
                }
            }
            CanonKind::Chain(chain) => {
                put(w, b",\"set\":");
                uint(w, chain.set as u64);
                put(w, b",\"sub\":");
                uint(w, chain.sub as u64);
            }
            CanonKind::Print { text } => {
                put(w, b",\"text\":");
                json_string(w, text);
            }
            CanonKind::Cutter(word) => {
                // `"corner_arc": [I, J, K]` or `null` (G39 without I/J/K), `"cancel_direction":
                // [I, J, K]` (G40 with I/J/K), `"vector_hold"` as G39's, `"plane_change": Q`
                // (Q1/Q2/Q3 under G41.2/G42.2), `"perpendicular": null` (G41/G42, G41.2/G42.2
                // again), `"without_motion": null` (a block without movement in offset mode).
                let direction = |w: &mut Out, key: &[u8], d: Option<[f64; 3]>| {
                    put(w, key);
                    match d {
                        Some(d) => {
                            for (k, x) in d.iter().enumerate() {
                                put(w, if k == 0 { b"[" } else { b"," });
                                num(w, *x);
                            }
                            put(w, b"]");
                        }
                        None => put(w, b"null"),
                    }
                };
                match word {
                    CutterWord::CornerArc(d) => direction(w, b",\"corner_arc\":", *d),
                    CutterWord::CancelDirection(d) => direction(w, b",\"cancel_direction\":", Some(*d)),
                    CutterWord::VectorHold(d) => direction(w, b",\"vector_hold\":", *d),
                    CutterWord::PlaneChange(q) => {
                        put(w, b",\"plane_change\":");
                        uint(w, u64::from(*q));
                    }
                    CutterWord::Perpendicular => put(w, b",\"perpendicular\":null"),
                    CutterWord::WithoutMotion => put(w, b",\"without_motion\":null"),
                }
            }
        }
        put(w, b"}\n");
    }

    fn motion(&mut self, w: &mut Out, m: &Motion) {
        let axes = &self.axes[..];
        let kind: &[u8] = match m.kind {
            MotionKind::Rapid => b"rapid",
            MotionKind::Linear => b"linear",
            MotionKind::ArcCw => b"arc_cw",
            MotionKind::ArcCcw => b"arc_ccw",
            MotionKind::MachineRapid => b"machine_rapid",
        };
        let feed_mode: &[u8] = match m.feed_mode {
            FeedMode::InverseTime => b"G93",
            FeedMode::PerMinute => b"G94",
            FeedMode::PerRevolution => b"G95",
        };
        put(w, b",\"motion\":\"");
        put(w, kind);
        put(w, b"\",\"target\":");
        // Without offsets the machine point is the target: format it once and copy it.
        let start = w.len();
        axes_map(w, &m.target, axes);
        put(w, b",\"machine\":");
        if m.machine == m.target {
            let end = w.len() - b",\"machine\":".len();
            w.extend_from_within(start..end);
        } else {
            axes_map(w, &m.machine, axes);
        }
        put(w, b",\"feed\":");
        num(w, m.feed);
        put(w, b",\"feed_mode\":\"");
        put(w, feed_mode);
        put(w, b"\"");
        if let Some(arc) = &m.arc {
            put(w, b",\"arc\":{\"center\":");
            axes_map(w, &arc.center, axes);
            put(w, b",\"radius\":");
            num(w, arc.radius);
            put(w, b",\"sweep_deg\":");
            num(w, arc.sweep_deg);
            put(w, b"}");
        }
        self.write_context(w, &m.context);
    }

    fn write_context(&mut self, w: &mut Out, c: &MotionContext) {
        if let Some((last, text)) = &self.context {
            if last == c {
                return put(w, text);
            }
        }
        let mut v = Vec::with_capacity(200);
        let wcs = if c.wcs == code::G54_1 { format!("G54.1 P{}", c.wcs_p) } else { display(c.wcs) };
        let _ = write!(
            v,
            ",\"context\":{{\"plane\":\"{}\",\"wcs\":\"{wcs}\",\"length_comp\":\"{}\",\"h\":{},\"tool_length\":",
            display(c.plane),
            display(c.length_comp),
            c.h
        );
        num(&mut v, c.tool_length);
        let _ = write!(v, ",\"cutter_comp\":\"{}\",\"d\":{},\"cutter_radius\":", display(c.cutter_comp), c.d);
        num(&mut v, c.cutter_radius);
        let _ = write!(v, ",\"path_mode\":\"{}\",\"rotation\":\"{}\"}}", display(c.path_mode), display(c.rotation));
        put(w, &v);
        self.context = Some((*c, v));
    }
}

/// One trace sample as one JSON line, appended to `w`.
pub fn write_sample(w: &mut Out, s: &Sample, axes: &[char]) {
    put(w, b"{\"t\":");
    num(w, s.t);
    put(w, b",\"line\":");
    uint(w, s.line as u64);
    put(w, b",\"n\":");
    opt_u32(w, s.n);
    put(w, b",\"machine\":");
    axes_map(w, &s.machine, axes);
    put(w, b",\"tip\":");
    triple(w, &s.tip);
    put(w, b",\"tool\":");
    triple(w, &s.tool);
    put(w, b",\"feed\":");
    num(w, s.feed);
    put(w, b",\"programmed\":");
    triple(w, &s.programmed);
    put(w, b",\"programmed_in\":\"");
    put(w, s.programmed_in.name().as_bytes());
    put(w, b"\"");
    if let Some(c) = &s.cutting {
        put(w, b",\"cutting\":");
        triple(w, c);
    }
    put(w, b"}\n");
}

fn triple(w: &mut Out, v: &[f64; 3]) {
    put(w, b"[");
    for (i, x) in v.iter().enumerate() {
        if i > 0 {
            put(w, b",");
        }
        num(w, *x);
    }
    put(w, b"]");
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(x: f64) -> String {
        let mut v = Vec::new();
        num(&mut v, x);
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn integers_print_in_decimal() {
        for v in [0u64, 7, 10, 99, 100, 123_456, 9_999_999, 10_000_000, 99_999_999, 100_000_000, u64::MAX] {
            let mut out = Vec::new();
            uint(&mut out, v);
            assert_eq!(String::from_utf8(out).unwrap(), v.to_string());
        }
    }

    #[test]
    fn fast_numbers_print_exactly_as_ryu() {
        for x in [0.0, -0.0, 5.0, -0.5, 12.345, 0.001, 0.0015, 1234567.125, 99999.9999, 1e10, 3.0001, -7.05] {
            let expected = ryu::Buffer::new().format_finite(if x == 0.0 { 0.0 } else { x }).to_string();
            assert_eq!(text(x), expected, "{x}");
        }
        assert_eq!(text(0.1 + 0.2), "0.30000000000000004");
        // Every four-decimal number over a wide range, and the ends of the fast path.
        for r in (0..2_000_000u64).chain((0..100_000).map(|k| 99_000_000_000 + k * 7)) {
            for x in [r as f64 / 1e4, -(r as f64) / 1e4, r as f64 / 1e3 + 0.5] {
                let expected = ryu::Buffer::new().format_finite(if x == 0.0 { 0.0 } else { x }).to_string();
                assert_eq!(text(x), expected, "{x}");
            }
        }
        assert_eq!(text(f64::NAN), "null");
    }
}
