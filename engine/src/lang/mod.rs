//! The NC language: source text → programs of blocks, with every diagnostic and its position.
//!
//! Parsing never stops at the first error: a block that cannot be parsed becomes
//! [`ast::BlockKind::Error`] carrying its diagnostic, so `fivex check` can list them all and the
//! interpreter raises the alarm only when execution reaches that block, as a real control does.

pub mod ast;
pub mod diag;
mod lexer;
mod parser;
mod source;

pub use ast::*;
pub use diag::Diagnostic;
pub use parser::{has_macro_format_line, is_header, is_header_block, parse_file, parse_part};
pub use source::{Source, Stored};
