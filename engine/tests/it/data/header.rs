//! A data fixture's header: the options of its first line's `(fivex: …)` comment, the
//! `(expect: …)` expectations and the `(skip: …)` exemptions from an invariant, anywhere in the
//! file (`tests/README.md`, "Data fixtures").

use fivex_engine::Dialect;

/// What a fixture selects and expects.
#[derive(Debug, Default)]
pub struct Header {
    /// `--preset` (default mill3).
    pub preset: String,
    /// `--machine FILE` (relative to the fixture): this machine file instead of the preset.
    pub machine: Option<String>,
    /// `--dialect fanuc,syntec`: every dialect the program runs in (default FANUC).
    pub dialects: Vec<Dialect>,
    /// `--tools FILE` (relative to the fixture): these offsets instead of the default 1–99.
    pub tools: Option<String>,
    /// `--workpiece FILE` (relative to the fixture): the boxes on the table a G31 probe touches.
    pub workpiece: Option<String>,
    pub max_blocks: Option<u64>,
    pub block_delete: bool,
    pub optional_stop: bool,
    /// Data fixtures only: FANUC parameter NAT (`Config::nat`).
    pub nat: bool,
    /// Data fixtures only: the functions not built are not refused (`Config::refuse_unbuilt`
    /// off), for the interlocks of those functions (`engine/tests/it/modes.rs`).
    pub allow_unbuilt: bool,
    pub expects: Vec<Expect>,
    pub skips: Vec<Skip>,
}

/// `key=value` or `key[dialect]=value`.
#[derive(Debug, Clone)]
pub struct Expect {
    pub key: String,
    pub dialect: Option<Dialect>,
    pub value: String,
}

impl Expect {
    pub fn applies_to(&self, d: Dialect) -> bool {
        self.dialect.is_none_or(|x| x == d)
    }
}

/// `(skip: INVARIANT[@LINE] reason…)`: the invariant does not hold (on that line), and why.
#[derive(Debug, Clone)]
pub struct Skip {
    pub invariant: String,
    pub line: Option<u32>,
    /// The comment's text, for the message when it is not needed.
    pub text: String,
}

pub const INVARIANTS: &[&str] = &["limits", "tip"];

pub use fivex_e2e::header::{split_words, tagged_comments};

pub fn parse(text: &str) -> Result<Header, String> {
    let mut h = Header { preset: "mill3".into(), dialects: vec![Dialect::Fanuc], ..Header::default() };
    let first = text.lines().next().unwrap_or("");
    if tagged_comments(text, "fivex").len() > tagged_comments(first, "fivex").len() {
        return Err("a (fivex: …) comment after the first line selects nothing".into());
    }
    if let Some(opts) = tagged_comments(first, "fivex").into_iter().next() {
        let words = split_words(opts);
        let mut it = words.iter();
        while let Some(w) = it.next() {
            let mut value = || it.next().cloned().ok_or(format!("option {w} needs a value"));
            match w.as_str() {
                "--preset" => h.preset = value()?,
                "--dialect" => {
                    h.dialects = value()?.split(',').map(str::parse).collect::<Result<_, _>>()?;
                }
                "--tools" => h.tools = Some(value()?),
                "--workpiece" => h.workpiece = Some(value()?),
                "--machine" => h.machine = Some(value()?),
                "--max-blocks" => h.max_blocks = Some(value()?.parse().map_err(|e| format!("--max-blocks: {e}"))?),
                "--block-delete" => h.block_delete = true,
                "--optional-stop" => h.optional_stop = true,
                "--nat" => h.nat = true,
                "--allow-unbuilt" => h.allow_unbuilt = true,
                other => return Err(format!("unknown fixture option {other:?}")),
            }
        }
    }
    for body in tagged_comments(text, "expect") {
        for item in split_words(body) {
            let (k, value) = item.split_once('=').ok_or(format!("expectation {item:?} is not key=value"))?;
            let (key, dialect) = match k.split_once('[') {
                Some((key, d)) => {
                    let d: Dialect = d.strip_suffix(']').ok_or(format!("{k}: no closing ]"))?.parse()?;
                    if !h.dialects.contains(&d) {
                        return Err(format!("{k}: the fixture does not run in {}", d.name()));
                    }
                    (key, Some(d))
                }
                None => (k, None),
            };
            h.expects.push(Expect { key: key.into(), dialect, value: value.into() });
        }
    }
    for body in tagged_comments(text, "skip") {
        let (what, reason) = body.split_once(char::is_whitespace).unwrap_or((body, ""));
        if reason.trim().len() < 10 {
            return Err(format!("(skip: {body}) must give its reason"));
        }
        let (invariant, line) = match what.split_once('@') {
            Some((i, l)) => (i, Some(l.parse().map_err(|e| format!("skip line {l:?}: {e}"))?)),
            None => (what, None),
        };
        if !INVARIANTS.contains(&invariant) {
            return Err(format!("(skip: {invariant}): no such invariant (known: {INVARIANTS:?})"));
        }
        h.skips.push(Skip { invariant: invariant.into(), line, text: body.into() });
    }
    Ok(h)
}

/// The invariant is skipped for the whole fixture.
pub fn skips_all(skips: &[Skip], invariant: &str) -> bool {
    skips.iter().any(|s| s.invariant == invariant && s.line.is_none())
}

/// Lines on which the invariant is skipped.
pub fn skipped_lines(skips: &[Skip], invariant: &str) -> Vec<u32> {
    skips.iter().filter(|s| s.invariant == invariant).filter_map(|s| s.line).collect()
}
