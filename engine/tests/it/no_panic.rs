//! Property tests: bad input never panics (BRIEF: "Bad input never panics").
//!
//! The parser, the static checks, the interpreter (`Interpreter::run`) and the ideal executor
//! (`run::run`) are fed (a) arbitrary strings and bytes, (b) strings built from an NC-ish alphabet
//! and from a small random grammar of blocks, and (c) random mutations of a valid macro program.
//! And (d) random block sequences of the 5-axis compensations (G41.2…G42.6, G41.3, with TCP)
//! on every mechanism type. Every run has a small block budget, so loops end, and a box on the
//! table, so that skip moves touch something. Case counts keep
//! the file to a few seconds in a debug build; `PROPTEST_CASES=N` raises them all for a longer
//! local run.
//!
//! Inputs are kept short (a few hundred characters): very long lines overflow the stack in the
//! parser and the evaluator (see `tests/tests/cli.rs`, `deep_expressions_do_not_crash`), which
//! aborts the process rather than panicking and would take the whole test binary down.

use fivex_engine::check::check;
use fivex_engine::interp::{Config, Interpreter};
use fivex_engine::lang::parse_file;
use fivex_engine::machine::MachineConfig;
use fivex_engine::run::{run, RunOptions};
use fivex_engine::Dialect;
use proptest::prelude::*;
use proptest::test_runner::Config as PtConfig;

const MAX_BLOCKS: u64 = 10_000;

fn interpreter(text: &str, preset: &str, dialect: Dialect) -> Interpreter {
    let mut cfg = Config::new(MachineConfig::preset(preset).expect("preset"), dialect);
    cfg.max_blocks = MAX_BLOCKS;
    // Something on the table, so that skip moves find contacts (`interp::skip`).
    cfg.workpiece = fivex_engine::workpiece::Workpiece {
        boxes: vec![fivex_engine::workpiece::Cuboid { min: [-50.0, -50.0, -40.0], max: [50.0, 50.0, 0.0] }],
    }
    .into();
    let mut interp = Interpreter::new(parse_file(text), cfg);
    for n in 1..=99 {
        let t = interp.state.offsets.tool_mut(n).expect("offset");
        t.h_geometry = 100.0;
        t.d_geometry = 5.0;
    }
    interp
}

/// Everything the CLI does with a program, minus the printing.
fn exercise(text: &str) {
    let file = parse_file(text);
    for d in &file.diagnostics {
        assert!(d.line >= 1, "diagnostic lines are 1-based: {d:?}");
    }
    for dialect in [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas] {
        let _ = check(file.clone(), dialect);
    }
    // `fivex run` on mill3 (FANUC and Haas) and on head-bc (Syntec).
    for (preset, dialect) in [("mill3", Dialect::Fanuc), ("head-bc", Dialect::Syntec), ("mill3", Dialect::Haas)] {
        let mut interp = interpreter(text, preset, dialect);
        let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
        assert!(r.blocks <= MAX_BLOCKS + 1, "block budget not enforced: {} blocks", r.blocks);
        assert!(r.cycle_time_s >= 0.0 && r.cycle_time_s.is_finite(), "cycle time {}", r.cycle_time_s);
        // Never a confident wrong answer: where the machine ends is a number.
        assert!(r.machine.iter().all(|x| x.is_finite()), "the run ends at {:?} ({:?})", r.machine, r.alarms);
        for a in &r.alarms {
            assert!(!a.code.is_empty(), "alarm without a code: {a:?}");
        }
    }
    // `fivex interp` on table-ac (FANUC).
    let mut interp = interpreter(text, "table-ac", Dialect::Fanuc);
    let mut n = 0u64;
    let _ = interp.run(|_| n += 1);
}

// --- (b) an NC-ish alphabet -------------------------------------------------------------------

const TOKENS: &[&str] = &[
    "G", "M", "X", "Y", "Z", "A", "B", "C", "I", "J", "K", "R", "Q", "P", "L", "F", "S", "T", "H", "D", "N", "O", "E",
    "U", "W", "0", "1", "2", "3", "5", "9", "10", "99", "100", ".", "-", "+", "*", "/", "#", "[", "]", "=", ";", "(",
    ")", "%", " ", "\n", "\n", ",", "WHILE", "DO", "END", "IF", "GOTO", "THEN", "SIN", "COS", "TAN", "ATAN", "ASIN",
    "ACOS", "SQRT", "ABS", "ROUND", "FIX", "FUP", "LN", "EXP", "POW", "BIN", "BCD", "ADP", "MOD", "AND", "OR", "XOR",
    "EQ", "NE", "GT", "GE", "LT", "LE", "POPEN", "PCLOS", "DPRNT", "BPRNT", "G65", "G66", "G66.1", "G67", "M98", "M99",
    "M30", "M97", "G154", "G110", "#10100", "#2401", "G01", "G02", "G03", "G00", "G81", "G83", "G73", "G84", "G76",
    "G80", "G98", "G99", "G10", "L2", "L20", "G52", "G92", "G28", "G53", "G43", "G49", "G54.1", "G17", "G18", "G19",
    "G90", "G91", "G20", "G21", "G04", "#0", "#1", "#100", "#3000", "#3006", "#5001", "#4001", "#[", "O1", "O2", "/",
    "N10", "GOTO10", "99999999", "1E5", "0.0001", "1.", "-0", "\t",
];

fn nc_soup() -> impl Strategy<Value = String> {
    prop::collection::vec(prop::sample::select(TOKENS), 0..120).prop_map(|t| t.concat())
}

// --- (b') a small random grammar of blocks ---------------------------------------------------

fn expr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        (-1000i32..1000).prop_map(|n| n.to_string()),
        (-1000.0f64..1000.0).prop_map(|x| format!("{x:.3}")),
        prop::sample::select(vec![
            0u32, 1, 2, 3, 24, 26, 33, 100, 101, 150, 500, 999, 3000, 4001, 5001, 5021, 1000, 34
        ])
        .prop_map(|n| format!("#{n}")),
    ];
    leaf.prop_recursive(4, 24, 2, |inner| {
        prop_oneof![
            (
                inner.clone(),
                prop::sample::select(vec!["+", "-", "*", "/", " MOD ", " AND ", " OR ", " XOR "]),
                inner.clone()
            )
                .prop_map(|(a, op, b)| format!("{a}{op}{b}")),
            inner.clone().prop_map(|a| format!("[{a}]")),
            inner.clone().prop_map(|a| format!("-{a}")),
            inner.clone().prop_map(|a| format!("#[{a}]")),
            (
                prop::sample::select(vec![
                    "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "SQRT", "ABS", "ROUND", "FIX", "FUP", "LN", "EXP",
                    "BIN", "BCD"
                ]),
                inner.clone()
            )
                .prop_map(|(f, a)| format!("{f}[{a}]")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("ATAN[{a}]/[{b}]")),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| format!("POW[{a},{b}]")),
        ]
    })
}

fn cond() -> impl Strategy<Value = String> {
    (expr(), prop::sample::select(vec!["EQ", "NE", "GT", "GE", "LT", "LE"]), expr())
        .prop_map(|(a, op, b)| format!("{a}{op}{b}"))
}

fn var() -> impl Strategy<Value = String> {
    prop::sample::select(vec!["#1", "#2", "#24", "#100", "#101", "#500", "#3000", "#3006", "#0", "#5001", "#[#1]"])
        .prop_map(String::from)
}

fn word() -> impl Strategy<Value = String> {
    // No free Q or L: a canned cycle with a tiny peck depth Q over a deep hole, repeated L times,
    // expands into billions of motions inside ONE block (no budget stops it), which exhausts
    // memory instead of testing for panics. Q and L get bounded values of their own.
    let letter =
        prop::sample::select(vec!['X', 'Y', 'Z', 'B', 'C', 'I', 'J', 'K', 'R', 'P', 'F', 'S', 'T', 'H', 'D', 'E', 'A']);
    let value = prop_oneof![
        (-500i32..500).prop_map(|n| n.to_string()),
        (-500.0f64..500.0).prop_map(|x| format!("{x:.2}")),
        var(),
        expr().prop_map(|e| format!("[{e}]")),
    ];
    prop_oneof![
        8 => (letter, value).prop_map(|(l, v)| format!("{l}{v}")),
        1 => (1u32..50).prop_map(|q| format!("Q{q}.")),
        1 => (0u32..4).prop_map(|l| format!("L{l}")),
    ]
}

fn block() -> impl Strategy<Value = String> {
    let g = prop::sample::select(vec![
        "G00", "G01", "G02", "G03", "G04", "G10 L2", "G10 L20", "G10 L10", "G10 L11", "G10 L12", "G17", "G18", "G19",
        "G20", "G21", "G28", "G29", "G30", "G43", "G44", "G49", "G52", "G53", "G54", "G55", "G59", "G54.1", "G65",
        "G66", "G66.1", "G67", "G73", "G76", "G80", "G81", "G82", "G83", "G84", "G85", "G86", "G87", "G89", "G90",
        "G91", "G92", "G92.1", "G93", "G94", "G95", "G98", "G99", "G41", "G42", "G40", "G68", "G69", "G43.4", "G53.1",
        "G53.3", "G31", "G12", "G13", "G70", "G71", "G72", "G100", "G101", "G103", "G150", "G187", "G234", "G254",
        "G255",
    ]);
    let m = prop::sample::select(vec![
        "", "M03", "M05", "M06", "M08", "M98", "M99", "M00", "M01", "M30", "M02", "M19", "M78", "M79", "M97",
    ]);
    prop_oneof![
        4 => (prop::collection::vec(g, 0..3), prop::collection::vec(word(), 0..5), m)
            .prop_map(|(g, w, m)| format!("{} {} {m}", g.join(" "), w.join(" "))),
        2 => (var(), expr()).prop_map(|(v, e)| format!("{v}={e}")),
        1 => (cond(), 0u32..60).prop_map(|(c, n)| format!("IF[{c}]GOTO{n}")),
        1 => (cond(), var(), expr()).prop_map(|(c, v, e)| format!("IF[{c}]THEN{v}={e}")),
        1 => (cond(), 0u8..5).prop_map(|(c, m)| format!("WHILE[{c}]DO{m}")),
        1 => (0u8..5).prop_map(|m| format!("END{m}")),
        1 => (0u32..60).prop_map(|n| format!("GOTO{n}")),
        1 => (0u32..60).prop_map(|n| format!("N{n}")),
        1 => (1u32..4).prop_map(|n| format!("O{n}")),
        1 => (var(), var()).prop_map(|(a, b)| format!("DPRNT[A{a}[53]*B{b}[20]]")),
        1 => Just("%".to_string()),
        1 => (0u32..60, word()).prop_map(|(n, w)| format!("N{n} {w}")),
    ]
}

fn program() -> impl Strategy<Value = String> {
    prop::collection::vec(block(), 0..40).prop_map(|b| b.join("\n"))
}

// --- (c) mutations of a valid macro program --------------------------------------------------

const VALID: &str = "\
%
O0001 (MAIN)
#100=0
#1=1
G90 G17 G21 G54 G00 X0. Y0. Z50. S1000 M03
G43 H1 Z10.
WHILE[#1LE3]DO1
G65 P9001 A#1 R2. Z-5.
#1=#1+1
END1
IF[#100GT2]GOTO50
#3000=1(NOT REACHED)
N50 G99 G83 X10. Y10. Z-10. R2. Q4. F200.
X20.
G80
G02 X30. Y10. R5. F300.
G03 X20. Y10. I-5. J0.
M98 P1000 L2
G66 P9001 A5. R1. Z-2.
X40.
G67
#500=ATAN[1]/[1]+SQRT[16]*SIN[30]
DPRNT[R#500[53]]
G28 G91 Z0.
G49 G90
M30
O1000
G91 G01 X1. F100.
G90
M99
O9001
#100=#100+1
#[120+#100]=#1*#18
M99
%
";

#[derive(Debug, Clone)]
enum Mutation {
    Delete { at: usize, len: usize },
    Insert { at: usize, token: &'static str },
    Replace { at: usize, ch: char },
    DuplicateLine { line: usize },
    SwapLines { a: usize, b: usize },
    DropLine { line: usize },
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let any_char = prop_oneof![prop::char::range(' ', '~'), Just('\n'), prop::char::any()];
    prop_oneof![
        (any::<usize>(), 1usize..6).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), prop::sample::select(TOKENS)).prop_map(|(at, token)| Mutation::Insert { at, token }),
        (any::<usize>(), any_char).prop_map(|(at, ch)| Mutation::Replace { at, ch }),
        any::<usize>().prop_map(|line| Mutation::DuplicateLine { line }),
        (any::<usize>(), any::<usize>()).prop_map(|(a, b)| Mutation::SwapLines { a, b }),
        any::<usize>().prop_map(|line| Mutation::DropLine { line }),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut lines: Vec<&str> = text.lines().collect();
    let n = chars.len().max(1);
    match *m {
        Mutation::Delete { at, len } => {
            let at = at % n;
            let end = (at + len).min(chars.len());
            chars[..at].iter().chain(&chars[end..]).collect()
        }
        Mutation::Insert { at, token } => {
            let at = at % (chars.len() + 1);
            let mut s: String = chars[..at].iter().collect();
            s.push_str(token);
            s.extend(&chars[at..]);
            s
        }
        Mutation::Replace { at, ch } => {
            let mut c = chars;
            if !c.is_empty() {
                let i = at % c.len();
                c[i] = ch;
            }
            c.into_iter().collect()
        }
        Mutation::DuplicateLine { line } => {
            if !lines.is_empty() {
                let i = line % lines.len();
                lines.insert(i, lines[i]);
            }
            lines.join("\n")
        }
        Mutation::SwapLines { a, b } => {
            if !lines.is_empty() {
                let (a, b) = (a % lines.len(), b % lines.len());
                lines.swap(a, b);
            }
            lines.join("\n")
        }
        Mutation::DropLine { line } => {
            if !lines.is_empty() {
                lines.remove(line % lines.len());
            }
            lines.join("\n")
        }
    }
}

#[test]
fn the_valid_program_is_valid() {
    // The mutation base must itself run clean, or mutations test little.
    let file = parse_file(VALID);
    assert!(file.diagnostics.is_empty(), "{:?}", file.diagnostics);
    let mut interp = interpreter(VALID, "mill3", Dialect::Fanuc);
    let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
    assert!(r.completed(), "{:?}", r.alarms);
    assert!(r.variables.iter().any(|&(n, v)| n == 100 && v == 4.0), "{:?}", r.variables);
}

fn cases(n: u32) -> PtConfig {
    // PROPTEST_CASES (read by `Config::default()`) replaces the built-in count when set.
    if std::env::var_os("PROPTEST_CASES").is_some() {
        PtConfig::default()
    } else {
        PtConfig { cases: n, ..PtConfig::default() }
    }
}

proptest! {
    #![proptest_config(cases(300))]

    #[test]
    fn arbitrary_strings(s in "(?s).{0,300}") {
        exercise(&s);
    }

    #[test]
    fn arbitrary_bytes(b in prop::collection::vec(any::<u8>(), 0..300)) {
        exercise(&String::from_utf8_lossy(&b));
    }

    #[test]
    fn nc_alphabet_soup(s in nc_soup()) {
        exercise(&s);
    }

    #[test]
    fn random_block_programs(s in program()) {
        exercise(&s);
    }

    #[test]
    fn mutated_valid_program(ms in prop::collection::vec(mutation(), 1..6)) {
        let mut text = VALID.to_string();
        for m in &ms {
            text = apply(&text, m);
        }
        exercise(&text);
    }
}

/// A block of a 5-axis compensation program: a move (often degenerate: repeated points, moves
/// along the tool, rotary axes alone), a mode change, a word the mode refuses or answers.
fn compensation_block() -> impl Strategy<Value = String> {
    let coord = prop_oneof![
        3 => (-200.0f64..200.0).prop_map(|x| format!("{x:.3}")),
        1 => prop::sample::select(vec!["0", "0.", "1e3", "-0.", "0.001", "99999."]).prop_map(String::from),
    ];
    let axis = prop::sample::select(vec!['X', 'Y', 'Z', 'A', 'B', 'C']);
    let words = prop::collection::vec((axis, coord), 0..4)
        .prop_map(|w| w.into_iter().map(|(l, v)| format!("{l}{v}")).collect::<Vec<_>>().join(" "));
    let mode = prop::sample::select(vec![
        "",
        "",
        "",
        "G41.2 D1",
        "G42.2 D1",
        "G41.6 D1",
        "G42.6 D2",
        "G41.3 D1",
        "G40",
        "G43.4 H1",
        "G43.5 H1",
        "G49",
        "G02",
        "G03",
        "G00",
        "G01",
        "Q1",
        "Q2",
        "Q3",
        "Q7",
        "D0",
        "D3",
        "I0 J0 K1.",
        "I1. J0 K0",
        "I0 J0 K0",
        "R5.",
        "G17",
        "G19",
        "G43.8 H1 D4",
        "G43.9 H1 D5",
        "G43.8 H1 D1 ,L2 I1.",
        ",L2 I1.",
        ",L2 K1.",
        ",L2 I-1. J0.5 K1.",
        ",L2 I0 J0 K0",
        ",L2 K-1.",
        ",L3 I1.",
        ",C1.",
    ]);
    (mode, words).prop_map(|(m, w)| format!("{m} {w}"))
}

/// The 5-axis compensation stages (tool side offset, leading edge offset) and cutting point
/// control on every mechanism type: any block sequence ends in an alarm or a run whose end is a
/// number.
fn exercise_compensation(text: &str) {
    for preset in ["head-bc", "mixed-bc", "table-ac"] {
        let mut interp = interpreter(text, preset, Dialect::Fanuc);
        for (n, d) in [(2, -3.0), (3, 0.0)] {
            interp.state.offsets.tool_mut(n).expect("offset").d_geometry = d;
        }
        // Cutting point control's tools: a bull-nose end mill (4) and a square one (5).
        for (n, d, corner) in [(4, 6.0, 2.0), (5, 5.0, 0.0)] {
            let t = interp.state.offsets.tool_mut(n).expect("offset");
            (t.d_geometry, t.corner_radius) = (d, corner);
        }
        let r = run(&mut interp, &RunOptions { period_s: 0.0, ..RunOptions::default() }, |_| {});
        assert!(r.machine.iter().all(|x| x.is_finite()), "{preset}: ends at {:?} ({:?})", r.machine, r.alarms);
        assert!(r.cycle_time_s.is_finite(), "{preset}: cycle time {}", r.cycle_time_s);
    }
}

proptest! {
    #![proptest_config(cases(200))]

    #[test]
    fn random_five_axis_compensation_programs(
        blocks in prop::collection::vec(compensation_block(), 1..14),
    ) {
        let text = format!("G90 G01 F1000. X0 Y0 Z0\n{}\nM30\n", blocks.join("\n"));
        exercise_compensation(&text);
    }
}
