//! Notices: what a run reports besides alarms and operator messages — a block fivex carried out
//! by a rule of its own, where the manuals do not say what the control does. The program still
//! completes (a real control may do otherwise, or alarm); the notice says where and how the
//! motion differs from what the block asked for, so that a user deciding whether a program is
//! safe does not take fivex's rule for the control's (`docs/five-axis.md`, "Notices").
//!
//! Codes are fivex's own (`FX1…`, alarms are `FX0…`) and the same in every dialect.

use crate::motion::path::{Fallback, PostureFallback};
use crate::motion::Segment;
use serde::{Deserialize, Serialize};

/// A block fivex ran by a rule of its own where the manuals do not say what the control does,
/// placed as an alarm is (`docs/five-axis.md`, "Notices").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Notice {
    #[cfg_attr(feature = "schema", schema(example = "FX1001"))]
    pub code: String,
    pub message: String,
    /// 1-based line in the program.
    pub line: u32,
    /// Sequence number of the block, if it has one.
    pub n: Option<u32>,
}

impl Notice {
    /// What a queued segment has to report, if anything.
    pub fn of(segment: &Segment) -> Option<Notice> {
        let (code, message) = match segment.fallback()? {
            Fallback::Posture(PostureFallback::Reach) => (
                "FX1001",
                "tool posture control: the tool's great circle leaves (or comes within 0.06° of the edge of) the \
                 directions the rotary axes reach; the rotary axes turn in proportion (conventional control)",
            ),
            Fallback::Posture(PostureFallback::Branch) => (
                "FX1002",
                "tool posture control: the rotary axes would have to jump to the other solution of the inverse \
                 kinematics; they turn in proportion (conventional control)",
            ),
            Fallback::Compensation => (
                "FX1003",
                "G54.4: the tool direction compensation cannot be followed along this block (an end at or near the \
                 singular posture, an axis held by the singular-posture rule, or a step of the rotary axes); they \
                 turn in proportion between its compensated ends, the tool up to more than 0.001° off the \
                 compensated direction",
            ),
        };
        Some(Notice { code: code.into(), message: message.into(), line: segment.line, n: segment.n })
    }

    /// Add `notice` to `list` unless it repeats the last one (a block queued as several
    /// segments: a split path's pieces, compensated corners).
    pub fn add(list: &mut Vec<Notice>, notice: Notice) {
        if list.last() != Some(&notice) {
            list.push(notice);
        }
    }
}
