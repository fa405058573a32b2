//! A controller's stored programs (O numbers): checked and stored, read, removed, and composed
//! into the text AUTO runs.

use std::sync::Arc;

use fivex_engine::lang::{self, is_header, parse_file, Source};
use fivex_engine::{AlarmId, Dialect};

use serde::{Deserialize, Serialize};

use super::ServiceError;
use crate::db;
use crate::host::stream::AlarmInfo;
use crate::host::Hosted;

/// The largest program text accepted, bytes.
pub const MAX_PROGRAM_BYTES: usize = 8 * 1024 * 1024;

/// A problem `check` finds in a program.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub line: u32,
    pub col: u32,
    /// The dialect's alarm code and message.
    pub code: String,
    pub message: String,
    /// What exactly is wrong.
    pub detail: String,
}

/// The problems `check` finds in `text` as a stored program. A call of another program
/// (M98/M198/G65/G66 P) is not one: the others are stored separately and found at cycle start
/// (a missing one still alarms then).
pub fn problems(text: &str, dialect: Dialect) -> Vec<Problem> {
    fivex_engine::check::check(parse_file(text), dialect)
        .into_iter()
        .filter(|d| d.id != AlarmId::ProgramNotFound)
        .map(|d| {
            let (code, message) = dialect.describe(&d.id);
            Problem { line: d.line, col: d.col, code, message, detail: d.detail }
        })
        .collect()
}

/// The number the text gives its first program (`O0555`, or `:0555`, the ISO form both
/// dialects read as O), by the engine's parser; `None` when the text starts without one. Only
/// the lines up to the first block are parsed (one at a time: a block never spans lines).
pub fn first_number(text: &str) -> Option<u32> {
    for line in text.lines() {
        // A blank, `%` or comment-only line gives no program or a header: look further.
        if let Some(program) = parse_file(line).programs.iter().find(|p| !is_header(p)) {
            return program.number;
        }
    }
    None
}

/// The text's own O number, if it has one, must be the slot it is stored in: the controller
/// finds a stored program by its slot (`M98 P102`), so a text that calls itself O0555 in slot
/// 102 would be stored and then not found.
fn matches_slot(text: &str, slot: u32) -> Result<(), ServiceError> {
    match first_number(text) {
        Some(given) if given != slot => Err(ServiceError::Invalid(
            format!(
                "the text is program O{given:04} but would be stored as O{slot:04}: store it under {given}, \
                 or make its O number {slot} (or leave it out)"
            ),
            Some(serde_json::json!({"slot": slot, "text_number": given})),
        )),
        _ => Ok(()),
    }
}

/// The programs of `text` (a header of comments before the first O number is none).
fn programs_in(text: &str) -> Vec<fivex_engine::lang::Program> {
    parse_file(text).programs.into_iter().filter(|p| !is_header(p)).collect()
}

/// A stored text is one program: on the control each O number is one program in memory, and
/// `M98 P18` must run what is stored as 18, never an `O0018` inside another slot's text (the
/// controller's text would hold two programs 18, and the first would win).
fn one_program(text: &str, slot: u32) -> Result<(), ServiceError> {
    match programs_in(text).get(1) {
        Some(second) => Err(ServiceError::Invalid(
            format!(
                "the text holds a second program{} at line {}: a stored program is one program; store each \
                 under its own number",
                second.number.map(|m| format!(" O{m:04}")).unwrap_or_default(),
                second.line
            ),
            Some(serde_json::json!({"slot": slot, "line": second.line, "text_number": second.number})),
        )),
        None => Ok(()),
    }
}

/// A program number in the dialect's range (O1–O9999).
pub fn number(n: u32) -> Result<u32, ServiceError> {
    if (1..=9999).contains(&n) {
        Ok(n)
    } else {
        Err(ServiceError::invalid(format!("program number {n} is outside 1–9999")))
    }
}

/// The stored programs' numbers and sizes, ascending.
pub async fn list(db: &db::Db, hosted: &Hosted) -> Result<Vec<(u32, usize)>, ServiceError> {
    Ok(db::list_programs(db, &hosted.id).await?)
}

/// What storing a program did.
#[derive(Debug, Clone, PartialEq)]
pub struct Stored {
    /// There was no program `n` before.
    pub new: bool,
    /// The text's size as stored, bytes (a byte order mark left out).
    pub size: usize,
    /// What `check` found (stored anyway: `force`).
    pub problems: Vec<Problem>,
}

/// An NC text (a program to store, MDI's blocks, a fleet run's program) holds no NUL: no NC
/// text does (binary data sent by mistake), and PostgreSQL's text cannot hold one (a 500 there,
/// stored on SQLite: one answer on both).
pub fn no_nul(text: &str) -> Result<(), ServiceError> {
    if text.contains('\0') {
        return Err(ServiceError::invalid("the program contains NUL bytes (binary data?)"));
    }
    Ok(())
}

/// Stores `bytes` as program `n` once it is NC text whose O number, if any, is `n` and in which
/// `check` finds no problem (or `force`: stored with them). `n` is checked first.
pub async fn store(db: &db::Db, hosted: &Hosted, n: u32, bytes: &[u8], force: bool) -> Result<Stored, ServiceError> {
    let text =
        std::str::from_utf8(bytes).map_err(|e| ServiceError::invalid(format!("the program is not UTF-8 text: {e}")))?;
    // The byte order mark an editor may put first (Windows Notepad's UTF-8) is no character of
    // the program: left out, not refused as "unexpected character 'ï'".
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    no_nul(text)?;
    matches_slot(text, n)?;
    one_program(text, n)?;
    let found = problems(text, hosted.dialect);
    if !found.is_empty() && !force {
        let details = serde_json::to_value(found.iter().map(problem_json).collect::<Vec<_>>()).ok();
        return Err(ServiceError::Invalid(
            format!("check found {} problem(s); store anyway with ?force=true", found.len()),
            details,
        ));
    }
    not_in_use(hosted, n)?;
    let new = db::put_program(db, &hosted.id, n, text).await?;
    Ok(Stored { new, size: text.len(), problems: found })
}

/// A problem as the refusal's `details` list it (the fields of the API's `Diagnostic`).
fn problem_json(p: &Problem) -> serde_json::Value {
    serde_json::json!({"line": p.line, "col": p.col, "code": p.code, "message": p.message, "detail": p.detail})
}

/// Program `n`'s text.
pub async fn text(db: &db::Db, hosted: &Hosted, n: u32) -> Result<String, ServiceError> {
    db::program(db, &hosted.id, n).await?.ok_or_else(|| ServiceError::NotFound(format!("no program O{n}")))
}

/// Program `n` is not one a run under way reads (`Station::programs_in_use`): replaced or
/// removed under it, its run would go on with the old text (read at the cycle start) while the
/// status, the stream and the alarms gave lines of a text that no longer is (on the control the
/// program being executed cannot be edited either).
/// Nor the one a program restart's search holds (`Station::program_searched`).
fn not_in_use(hosted: &Hosted, n: u32) -> Result<(), ServiceError> {
    let station = hosted.station();
    if station.programs_in_use().contains(&Some(n)) {
        return Err(ServiceError::Conflict(format!(
            "program O{n:04} is in use by the run under way: it can change once the run is over (its end, or a reset)"
        )));
    }
    if station.program_searched() == Some(n) {
        return Err(ServiceError::Conflict(format!(
            "program O{n:04} is searched for a program restart: it can change once the restart has run (its cycle start) or is forgotten (a reset)"
        )));
    }
    Ok(())
}

/// Removes program `n`, unless a run under way reads it (409).
pub async fn remove(db: &db::Db, hosted: &Hosted, n: u32) -> Result<(), ServiceError> {
    not_in_use(hosted, n)?;
    if db::delete_program(db, &hosted.id, n).await? {
        Ok(())
    } else {
        Err(ServiceError::NotFound(format!("no program O{n}")))
    }
}

/// A text the controller runs, composed of stored programs, and where each lies in it.
/// What a cycle start or MDI runs: the selected text and every other stored program for it to
/// call (parsed only when called: `fivex_engine::lang::Source`), and where each one's lines lie
/// in their shared numbering.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Composed {
    pub source: Source,
    pub layout: Layout,
}

/// A text alone, calling no stored program.
impl From<&str> for Composed {
    fn from(text: &str) -> Composed {
        Composed { source: text.into(), layout: Layout::default() }
    }
}

impl From<String> for Composed {
    fn from(text: String) -> Composed {
        Composed { source: text.into(), layout: Layout::default() }
    }
}

/// Where the programs of a composed source lie in its line numbering: alarms and the status
/// give a line of the program it is in, as stored (the shared numbering is the service's, no
/// client sees it).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Layout {
    /// The first text's O number (`None`: an MDI text).
    first: Option<u32>,
    /// Each program after it: the composed line its own line 1 is on, and its O number;
    /// ascending.
    after: Vec<(u32, u32)>,
}

impl Layout {
    /// The program (`None`: MDI's own text) and its own line for `line` of the shared numbering
    /// (0, before any block, stays 0 of the first).
    pub fn locate(&self, line: u32) -> (Option<u32>, u32) {
        match self.after.iter().rev().find(|(start, _)| *start <= line) {
            Some(&(start, n)) => (Some(n), line - start + 1),
            None => (self.first, line),
        }
    }

    /// `alarm`, raised in the composed source, with its line in the program it is in.
    pub fn relocate(&self, alarm: AlarmInfo) -> AlarmInfo {
        let (program, line) = self.locate(alarm.line);
        AlarmInfo { program, line, ..alarm }
    }
}

/// What AUTO runs for stored program `n`: that program (its lines keep their numbers), and
/// every other stored program under its number, for M98/G65.
pub async fn composed(db: &db::Db, hosted: &Hosted, n: u32) -> Result<Composed, ServiceError> {
    let programs = db::programs(db, &hosted.id).await?;
    compose(n, &programs).ok_or_else(|| ServiceError::NotFound(format!("no program O{n}")))
}

/// The stored programs, for an MDI text to call (`compose_mdi`).
pub async fn all(db: &db::Db, hosted: &Hosted) -> Result<Vec<(u32, String)>, ServiceError> {
    Ok(db::programs(db, &hosted.id).await?)
}

fn compose(number: u32, programs: &[(u32, String)]) -> Option<Composed> {
    let main = programs.iter().find(|(n, _)| *n == number)?;
    Some(followed_by_the_others(Some(number), &main.1, programs.iter().filter(|(n, _)| *n != number)))
}

/// What MDI runs: the MDI blocks (their lines keep their numbers), and every stored program
/// under its number, so that `M98 P1` in MDI calls program 1 from memory as on the control.
pub fn compose_mdi(mdi: &str, programs: &[(u32, String)]) -> Composed {
    followed_by_the_others(None, mdi, programs.iter())
}

/// `first` (program `number`; the engine loads its first program only), then each of `others`,
/// numbered after it. Nothing is parsed here: a stored program is parsed when a call reaches
/// it, so a cycle start costs the selected program, not the whole memory.
fn followed_by_the_others<'a>(
    number: Option<u32>,
    first: &str,
    others: impl Iterator<Item = &'a (u32, String)>,
) -> Composed {
    let mut layout = Layout { first: number, after: Vec::new() };
    let mut source = Source::from(first);
    // The line after the first text's last (which may have no line end).
    let mut line = newlines(first) + 2;
    for (n, text) in others {
        layout.after.push((line, *n));
        source.library.push(Arc::new(lang::Stored { number: *n, first_line: line, text: text.clone() }));
        line += newlines(text) + 1;
    }
    Composed { source, layout }
}

/// The line ends in `text` (the parser's lines end at `\n`).
fn newlines(text: &str) -> u32 {
    text.bytes().filter(|&b| b == b'\n').count() as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs `composed` in an interpreter of the default machine: the lines the run passed, in
    /// the program they are in, and its alarm.
    fn run(composed: &Composed) -> (Vec<(Option<u32>, u32)>, Option<String>) {
        run_as(composed, false)
    }

    /// [`run`] of what MDI runs (`compose_mdi`): its text may end without M30.
    fn run_mdi(composed: &Composed) -> (Vec<(Option<u32>, u32)>, Option<String>) {
        run_as(composed, true)
    }

    fn run_as(composed: &Composed, mdi: bool) -> (Vec<(Option<u32>, u32)>, Option<String>) {
        let machine = fivex_engine::machine::MachineConfig::preset("mill3").unwrap();
        let cfg = fivex_engine::interp::Config::new(machine, Dialect::Fanuc);
        let mut interp = fivex_engine::interp::Interpreter::new(parse_file(""), cfg);
        interp.load_source(&composed.source);
        interp.set_mdi_operation(mdi);
        let mut lines = Vec::new();
        loop {
            let mut out = Vec::new();
            match interp.step(&mut out) {
                Ok(fivex_engine::interp::Step::Continue) => {}
                Ok(_) => return (lines, None),
                Err(alarm) => return (lines, Some(alarm.code)),
            }
            lines.extend(out.iter().map(|c| composed.layout.locate(c.line)));
        }
    }

    #[test]
    fn the_selected_program_runs_and_calls_the_others_by_their_numbers() {
        let programs = vec![
            (1, "G00 X1.\nM98 P2\nM98 P3\nM30\n".to_string()),
            (2, "O0002\nX2.\nM99\n".into()),
            (3, "(sub)\n:0003\nX3.\nM99".into()),
        ];
        let composed = compose(1, &programs).unwrap();
        assert_eq!(run(&composed), (vec![(Some(1), 1), (Some(2), 2), (Some(3), 3)], None));
        assert!(compose(4, &programs).is_none());
        // The parser's rules for the text's own number: after `%` lines, blanks and comment
        // lines, `O` or the ISO `:`; a comment naming a number is not one.
        assert_eq!(first_number("%\n\nO12 (x)\n"), Some(12));
        assert_eq!(first_number("(header)\n  :0555\nM99\n"), Some(555));
        assert_eq!(first_number("(O1)\nG01\nO0002\n"), None);
        assert_eq!(first_number(""), None);
    }

    #[test]
    fn a_selected_text_without_blocks_runs_nothing_and_a_second_program_in_a_text_is_left_out() {
        let others = vec![(2, "O0002\nG0 Y7.\nM30\n".to_string())];
        for empty in ["", "%\n%\n", "(only a comment)\n", "\n\n"] {
            let mut programs = others.clone();
            programs.push((1, empty.to_string()));
            // A comment only is a program of no block, whose end of record a FANUC control in
            // memory operation reads at once (PS5010); the other texts hold no program at all.
            let alarm = empty.contains('(').then(|| "PS5010".to_string());
            assert_eq!(run(&compose(1, &programs).unwrap()), (vec![], alarm), "{empty:?}");
            assert_eq!(run_mdi(&compose_mdi(empty, &others)), (vec![], None), "{empty:?}");
        }
        // Texts stored before the store refused a second program: only their first is loaded.
        let hidden =
            vec![(1, "M98 P17\nM98 P19\nM30\nO0019\nM99\n".to_string()), (17, "O0017\nM99\nO0018\nM99\n".into())];
        assert_eq!(run(&compose(1, &hidden).unwrap()).1, Some("PS0078".into()));
        assert_eq!(run_mdi(&compose_mdi("M98 P18\n", &hidden)).1, Some("PS0078".into()));
        assert_eq!(run_mdi(&compose_mdi("M98 P17\nG0 X1.\n", &hidden)), (vec![(None, 2)], None));
    }

    #[test]
    fn a_line_of_the_composed_source_is_located_in_its_own_program() {
        // Program 2 has its number (after a header comment), 3 has none, 1 has no line end.
        let programs = vec![
            (1, "G01 X1.\nM98 P2\nM30".to_string()),
            (2, "(sub)\nO0002\nX2.\nM99\n".into()),
            (3, "X3.\r\n#3000=1\n".into()),
        ];
        let composed = compose(1, &programs).unwrap();
        let source = &composed.source;
        let count = (1..200).filter(|&l| source.line(l).is_some()).count();
        assert_eq!(count, 3 + 4 + 2, "every line of every text, once");
        for (program, line, block) in [(1, 2, "M98 P2"), (1, 3, "M30"), (2, 3, "X2."), (2, 4, "M99"), (3, 2, "#3000=1")]
        {
            let at: Vec<u32> = (1..200).filter(|&l| source.line(l) == Some(block)).collect();
            assert_eq!(at.len(), 1, "{block}");
            assert_eq!(composed.layout.locate(at[0]), (Some(program), line), "{block}");
        }
        assert_eq!(composed.layout.locate(0), (Some(1), 0));
        let mdi = compose_mdi("G0 X1.\nM98 P3\n", &programs);
        assert_eq!(mdi.layout.locate(2), (None, 2));
        let at = (1..200).find(|&l| mdi.source.line(l) == Some("#3000=1")).unwrap();
        assert_eq!(mdi.layout.locate(at), (Some(3), 2));
    }
}
