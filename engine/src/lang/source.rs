//! What a cycle start runs: one program's text and the stored programs it may call. A
//! controller's memory can hold thousands of programs of megabytes each; parsing all of them at
//! every cycle start for the few a program calls took seconds and gigabytes, so a stored
//! program is parsed only when a call reaches it (`interp::program::Slot`).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::ast::{File, Program};
use super::parser::parse_part;

/// A program to run (the text's first program: a second one in it is not loaded) and the
/// programs it can call.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Source {
    pub main: String,
    /// By ascending `first_line`, after the main text's lines; a call finds the first of a
    /// number (the main program's own number before all).
    pub library: Vec<Arc<Stored>>,
}

/// A stored program, unparsed. Its lines are numbered from `first_line` on, so that an alarm
/// in it has a line of one numbering shared with the main text (the host tells them apart).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Stored {
    pub number: u32,
    pub first_line: u32,
    /// The program's text (its first program only; with or without its own `O` line).
    pub text: String,
}

impl Source {
    /// The text of `line` (of the shared numbering), in the main text or a stored program.
    pub fn line(&self, line: u32) -> Option<&str> {
        let index = (line as usize).checked_sub(1)?;
        match self.library.iter().rev().find(|s| s.first_line <= line) {
            Some(stored) => stored.text.lines().nth((line - stored.first_line) as usize),
            None => self.main.lines().nth(index),
        }
    }

    /// Every text, the main one first.
    pub fn texts(&self) -> impl Iterator<Item = &str> {
        std::iter::once(self.main.as_str()).chain(self.library.iter().map(|s| s.text.as_str()))
    }
}

impl From<&str> for Source {
    fn from(text: &str) -> Source {
        Source { main: text.to_string(), library: Vec::new() }
    }
}

impl From<&String> for Source {
    fn from(text: &String) -> Source {
        text.as_str().into()
    }
}

impl From<String> for Source {
    fn from(main: String) -> Source {
        Source { main, library: Vec::new() }
    }
}

impl Stored {
    /// The program, parsed: the text's first program (a text stored before the store refused a
    /// second one keeps only its first), numbered `number` whether or not it has an `O` line.
    /// Parse errors are blocks that alarm when run, as in any text.
    pub fn parse(&self) -> Program {
        let File { programs, .. } = parse_part(&self.text, self.first_line, false);
        let mut program = programs.into_iter().next().unwrap_or_else(|| Program {
            number: None,
            line: self.first_line,
            blocks: Vec::new(),
        });
        program.number = Some(self.number);
        program
    }
}
