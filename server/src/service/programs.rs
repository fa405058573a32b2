//! A controller's stored programs (O numbers): checked and stored, read, removed, and composed
//! into the text AUTO runs.

use fivex_engine::lang::{is_header, parse_file};
use fivex_engine::{AlarmId, Dialect};

use super::ServiceError;
use crate::db;
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
    /// What `check` found (stored anyway: `force`).
    pub problems: Vec<Problem>,
}

/// Stores `bytes` as program `n` once it is NC text whose O number, if any, is `n` and in which
/// `check` finds no problem (or `force`: stored with them). `n` is checked first.
pub async fn store(db: &db::Db, hosted: &Hosted, n: u32, bytes: &[u8], force: bool) -> Result<Stored, ServiceError> {
    let text =
        std::str::from_utf8(bytes).map_err(|e| ServiceError::invalid(format!("the program is not UTF-8 text: {e}")))?;
    if text.contains('\0') {
        return Err(ServiceError::invalid("the program contains NUL bytes (binary data?)"));
    }
    matches_slot(text, n)?;
    let found = problems(text, hosted.dialect);
    if !found.is_empty() && !force {
        let details = serde_json::to_value(found.iter().map(problem_json).collect::<Vec<_>>()).ok();
        return Err(ServiceError::Invalid(
            format!("check found {} problem(s); store anyway with ?force=true", found.len()),
            details,
        ));
    }
    let new = db::put_program(db, &hosted.id, n, text).await?;
    Ok(Stored { new, problems: found })
}

/// A problem as the refusal's `details` list it (the fields of the API's `Diagnostic`).
fn problem_json(p: &Problem) -> serde_json::Value {
    serde_json::json!({"line": p.line, "col": p.col, "code": p.code, "message": p.message, "detail": p.detail})
}

/// Program `n`'s text.
pub async fn text(db: &db::Db, hosted: &Hosted, n: u32) -> Result<String, ServiceError> {
    db::program(db, &hosted.id, n).await?.ok_or_else(|| ServiceError::NotFound(format!("no program O{n}")))
}

/// Removes program `n`.
pub async fn remove(db: &db::Db, hosted: &Hosted, n: u32) -> Result<(), ServiceError> {
    if db::delete_program(db, &hosted.id, n).await? {
        Ok(())
    } else {
        Err(ServiceError::NotFound(format!("no program O{n}")))
    }
}

/// The text AUTO runs for stored program `n`: that program first (its lines keep their numbers
/// in alarms), then every other stored program, each under its O number, for M98/G65.
pub async fn composed(db: &db::Db, hosted: &Hosted, n: u32) -> Result<String, ServiceError> {
    let programs = db::programs(db, &hosted.id).await?;
    compose(n, &programs).ok_or_else(|| ServiceError::NotFound(format!("no program O{n}")))
}

fn compose(number: u32, programs: &[(u32, String)]) -> Option<String> {
    let main = programs.iter().find(|(n, _)| *n == number)?;
    let mut text = main.1.clone();
    for (n, t) in programs.iter().filter(|(n, _)| *n != number) {
        text.push('\n');
        // A text with its own O number (after `%` lines and comments; the store keeps it equal
        // to the slot) needs no other.
        if first_number(t).is_none() {
            text.push_str(&format!("O{n:04}\n"));
        }
        text.push_str(t);
    }
    Some(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_selected_program_comes_first_and_the_others_under_their_numbers() {
        let programs =
            vec![(1, "G01 X1.\nM98 P2\nM30\n".to_string()), (2, "O0002\nX2.\nM99\n".into()), (3, "X3.\nM99".into())];
        let text = compose(1, &programs).unwrap();
        assert!(text.starts_with("G01 X1.\n"), "{text}");
        assert!(text.contains("\nO0002\nX2.") && text.contains("\nO0003\nX3."), "{text}");
        assert!(compose(4, &programs).is_none());
        // The parser's rules for the text's own number: after `%` lines, blanks and comment
        // lines, `O` or the ISO `:`; a comment naming a number is not one.
        assert_eq!(first_number("%\n\nO12 (x)\n"), Some(12));
        assert_eq!(first_number("(header)\n  :0555\nM99\n"), Some(555));
        assert_eq!(first_number("(O1)\nG01\nO0002\n"), None);
        assert_eq!(first_number(""), None);
        // A text with its own number in the ISO form is not given another (two programs 2).
        let iso = vec![(1, "M98 P2\nM30\n".to_string()), (2, "(sub)\n:0002\nX2.\nM99\n".into())];
        let text = compose(1, &iso).unwrap();
        assert!(!text.contains("O0002"), "{text}");
        assert_eq!(fivex_engine::lang::parse_file(&text).programs.iter().filter(|p| p.number == Some(2)).count(), 1);
    }
}
