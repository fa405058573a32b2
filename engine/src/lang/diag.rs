//! Diagnostics with source positions.

use crate::alarm::AlarmId;

/// One problem found in the source, at a 1-based line and column.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    pub line: u32,
    pub col: u32,
    pub id: AlarmId,
    /// A human explanation of what exactly is wrong (the alarm message is the vendor's).
    pub detail: String,
}
