//! JSON forms of the CLI's outputs (`CONTRACTS.md`). Canonical commands and trace samples are
//! written by hand into a buffered writer: they are the hot path of `fivex interp`/`run --trace`.

use fivex_engine::canon::{Canon, CanonKind, Coolant, FeedMode, Motion, MotionContext, MotionKind, Pos, SpindleState};
use fivex_engine::interp::gcode::display;
use fivex_engine::run::{RunResult, Sample};
use serde_json::{json, Map, Value};
use std::io::{self, Write};

/// A number in its shortest form that reads back to the same f64 (`-0` prints as `0.0`).
fn num(w: &mut impl Write, x: f64) -> io::Result<()> {
    if !x.is_finite() {
        return w.write_all(b"null");
    }
    let x = if x == 0.0 { 0.0 } else { x };
    let mut buf = [0u8; 32];
    match short_decimal(x, &mut buf) {
        Some(text) => w.write_all(text),
        None => w.write_all(ryu::Buffer::new().format_finite(x).as_bytes()),
    }
}

/// Fast path for the numbers NC programs are made of: at most four decimals. When `x` equals
/// `r / 10⁴` for an integer `r`, that decimal is the shortest round-trip form, so the text is the
/// same `ryu` would print ("12.345", "5.0", "-0.5"), made with integer arithmetic only.
fn short_decimal(x: f64, buf: &mut [u8; 32]) -> Option<&[u8]> {
    let a = x.abs();
    if !(a == 0.0 || (1e-3..1e11).contains(&a)) {
        return None;
    }
    let r = (a * 1e4).round();
    if r / 1e4 != a {
        return None;
    }
    let r = r as u64;
    let (mut int, mut frac) = (r / 10_000, r % 10_000);
    // Written backwards from the end of the buffer.
    let mut i = buf.len();
    let mut put = |i: &mut usize, c: u8| {
        *i -= 1;
        buf[*i] = c;
    };
    if frac == 0 {
        put(&mut i, b'0');
    } else {
        let mut width = 4;
        while frac % 10 == 0 {
            frac /= 10;
            width -= 1;
        }
        for _ in 0..width {
            put(&mut i, b'0' + (frac % 10) as u8);
            frac /= 10;
        }
    }
    put(&mut i, b'.');
    loop {
        put(&mut i, b'0' + (int % 10) as u8);
        int /= 10;
        if int == 0 {
            break;
        }
    }
    if x < 0.0 {
        put(&mut i, b'-');
    }
    Some(&buf[i..])
}

fn uint(w: &mut impl Write, mut v: u64) -> io::Result<()> {
    let mut buf = [0u8; 20];
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = b'0' + (v % 10) as u8;
        v /= 10;
        if v == 0 {
            break;
        }
    }
    w.write_all(&buf[i..])
}

fn axes_map(w: &mut impl Write, p: &Pos, axes: &[char]) -> io::Result<()> {
    w.write_all(b"{")?;
    for (i, a) in axes.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        w.write_all(&[b'"', *a as u8, b'"', b':'])?;
        num(w, p[i])?;
    }
    w.write_all(b"}")
}

fn opt_u32(w: &mut impl Write, n: Option<u32>) -> io::Result<()> {
    match n {
        Some(n) => uint(w, n as u64),
        None => w.write_all(b"null"),
    }
}

fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".into())
}

/// One canonical command as one JSON line.
pub fn write_canon(w: &mut impl Write, c: &Canon, axes: &[char]) -> io::Result<()> {
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
    };
    w.write_all(b"{\"type\":\"")?;
    w.write_all(kind.as_bytes())?;
    w.write_all(b"\",\"line\":")?;
    uint(w, c.line as u64)?;
    w.write_all(b",\"n\":")?;
    opt_u32(w, c.n)?;
    match &c.kind {
        CanonKind::Motion(m) => motion(w, m, axes)?,
        CanonKind::Dwell { seconds } => {
            w.write_all(b",\"seconds\":")?;
            num(w, *seconds)?;
        }
        CanonKind::ToolSelect { tool } | CanonKind::ToolChange { tool } => write!(w, ",\"tool\":{tool}")?,
        CanonKind::Spindle { state, speed } => {
            let state = match state {
                SpindleState::Cw => "cw",
                SpindleState::Ccw => "ccw",
                SpindleState::Stop => "stop",
            };
            write!(w, ",\"state\":\"{state}\",\"speed\":")?;
            num(w, *speed)?;
        }
        CanonKind::Coolant(c) => {
            let state = match c {
                Coolant::Mist => "mist",
                Coolant::Flood => "flood",
                Coolant::Off => "off",
            };
            write!(w, ",\"state\":\"{state}\"")?;
        }
        CanonKind::Aux { m } => write!(w, ",\"m\":{m}")?,
        CanonKind::Stop { optional, message } => {
            write!(w, ",\"optional\":{optional},\"message\":")?;
            match message {
                Some(m) => w.write_all(json_string(m).as_bytes())?,
                None => w.write_all(b"null")?,
            }
        }
        CanonKind::Print { text } => write!(w, ",\"text\":{}", json_string(text))?,
        CanonKind::ProgramEnd { m } => write!(w, ",\"m\":{m}")?,
    }
    w.write_all(b"}\n")
}

fn motion(w: &mut impl Write, m: &Motion, axes: &[char]) -> io::Result<()> {
    let kind = match m.kind {
        MotionKind::Rapid => "rapid",
        MotionKind::Linear => "linear",
        MotionKind::ArcCw => "arc_cw",
        MotionKind::ArcCcw => "arc_ccw",
        MotionKind::MachineRapid => "machine_rapid",
    };
    let feed_mode = match m.feed_mode {
        FeedMode::InverseTime => "G93",
        FeedMode::PerMinute => "G94",
        FeedMode::PerRevolution => "G95",
    };
    w.write_all(b",\"motion\":\"")?;
    w.write_all(kind.as_bytes())?;
    w.write_all(b"\",\"target\":")?;
    // Without offsets the machine point is the target: format it once (on the stack).
    let mut buf = [0u8; 512];
    let mut cursor = io::Cursor::new(&mut buf[..]);
    axes_map(&mut cursor, &m.target, axes)?;
    let len = cursor.position() as usize;
    let target = &buf[..len];
    w.write_all(target)?;
    w.write_all(b",\"machine\":")?;
    if m.machine == m.target {
        w.write_all(target)?;
    } else {
        axes_map(w, &m.machine, axes)?;
    }
    w.write_all(b",\"feed\":")?;
    num(w, m.feed)?;
    w.write_all(b",\"feed_mode\":\"")?;
    w.write_all(feed_mode.as_bytes())?;
    w.write_all(b"\"")?;
    if let Some(arc) = &m.arc {
        w.write_all(b",\"arc\":{\"center\":")?;
        axes_map(w, &arc.center, axes)?;
        w.write_all(b",\"radius\":")?;
        num(w, arc.radius)?;
        w.write_all(b",\"sweep_deg\":")?;
        num(w, arc.sweep_deg)?;
        w.write_all(b"}")?;
    }
    write_context(w, &m.context)
}

thread_local! {
    /// The last context and its JSON: consecutive motions almost always share their context.
    static CONTEXT: std::cell::RefCell<Option<(MotionContext, String)>> = const { std::cell::RefCell::new(None) };
}

fn write_context(w: &mut impl Write, c: &MotionContext) -> io::Result<()> {
    CONTEXT.with(|cell| {
        let mut cache = cell.borrow_mut();
        if let Some((last, text)) = cache.as_ref() {
            if last == c {
                return w.write_all(text.as_bytes());
            }
        }
        let mut v = Vec::with_capacity(200);
        let wcs = if c.wcs == 541 { format!("G54.1 P{}", c.wcs_p) } else { display(c.wcs) };
        let _ = write!(
            v,
            ",\"context\":{{\"plane\":\"{}\",\"wcs\":\"{wcs}\",\"length_comp\":\"{}\",\"h\":{},\"tool_length\":",
            display(c.plane),
            display(c.length_comp),
            c.h
        );
        let _ = num(&mut v, c.tool_length);
        let _ = write!(v, ",\"cutter_comp\":\"{}\",\"d\":{},\"cutter_radius\":", display(c.cutter_comp), c.d);
        let _ = num(&mut v, c.cutter_radius);
        let _ = write!(v, ",\"path_mode\":\"{}\",\"rotation\":\"{}\"}}", display(c.path_mode), display(c.rotation));
        let text = String::from_utf8(v).unwrap_or_default();
        w.write_all(text.as_bytes())?;
        *cache = Some((*c, text));
        Ok(())
    })
}

/// One trace sample as one JSON line.
pub fn write_sample(w: &mut impl Write, s: &Sample, axes: &[char]) -> io::Result<()> {
    w.write_all(b"{\"t\":")?;
    num(w, s.t)?;
    w.write_all(b",\"line\":")?;
    uint(w, s.line as u64)?;
    w.write_all(b",\"n\":")?;
    opt_u32(w, s.n)?;
    w.write_all(b",\"machine\":")?;
    axes_map(w, &s.machine, axes)?;
    w.write_all(b",\"tip\":[")?;
    for (i, x) in s.tip.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        num(w, *x)?;
    }
    w.write_all(b"],\"tool\":[")?;
    for (i, x) in s.tool.iter().enumerate() {
        if i > 0 {
            w.write_all(b",")?;
        }
        num(w, *x)?;
    }
    w.write_all(b"],\"feed\":")?;
    num(w, s.feed)?;
    w.write_all(b"}\n")
}

fn position(p: &Pos, axes: &[char]) -> Value {
    let map: Map<String, Value> = axes.iter().enumerate().map(|(i, a)| (a.to_string(), json!(p[i]))).collect();
    Value::Object(map)
}

/// The `fivex run` summary object.
pub fn summary(r: &RunResult, axes: &[char]) -> Value {
    let alarms: Vec<Value> =
        r.alarms.iter().map(|a| json!({"code": a.code, "message": a.message, "line": a.line, "n": a.n})).collect();
    let variables: Map<String, Value> = r.variables.iter().map(|(n, v)| (format!("#{n}"), json!(v))).collect();
    json!({
        "status": if r.completed() { "completed" } else { "alarm" },
        "alarms": alarms,
        "blocks": r.blocks,
        "cycle_time_s": r.cycle_time_s,
        "position": {"machine": position(&r.machine, axes), "workpiece": position(&r.workpiece, axes)},
        "variables": Value::Object(variables),
        "messages": r.messages,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn text(x: f64) -> String {
        let mut v = Vec::new();
        num(&mut v, x).unwrap();
        String::from_utf8(v).unwrap()
    }

    #[test]
    fn fast_numbers_print_exactly_as_ryu() {
        for x in [0.0, -0.0, 5.0, -0.5, 12.345, 0.001, 0.0015, 1234567.125, 99999.9999, 1e10, 3.0001, -7.05] {
            let expected = ryu::Buffer::new().format_finite(if x == 0.0 { 0.0 } else { x }).to_string();
            assert_eq!(text(x), expected, "{x}");
        }
        assert_eq!(text(0.1 + 0.2), "0.30000000000000004");
        assert_eq!(text(f64::NAN), "null");
    }
}
