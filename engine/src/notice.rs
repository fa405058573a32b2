//! Notices: what a run reports besides alarms and operator messages — a block fivex carried out
//! by a rule of its own, where the manuals do not say what the control does, or ran as
//! programmed though it looks like a mistake a control may refuse. The program still
//! completes (a real control may do otherwise, or alarm); the notice says where and how the
//! motion differs from what the block asked for, so that a user deciding whether a program is
//! safe does not take fivex's rule for the control's (`docs/five-axis.md`, "Notices").
//!
//! Codes are fivex's own (`FX1…`, alarms are `FX0…`) and the same in every dialect.

use crate::canon::{Canon, CanonKind};
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

/// What the interpreter marks on a motion of a block it ran as programmed where the manuals
/// do not say the control does (a real control may alarm): the run reports it when the motion
/// is queued ([`Notice::of_command`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BlockNotice {
    /// A canned cycle's point R lies beyond its point Z on the side the cycle cuts toward:
    /// below the hole bottom (above the top of G87's back bore). Marked on the hole's first
    /// cutting feed.
    CycleRBeyondZ,
    /// G20/G21 switched the unit after the program had moved (its line and sequence number):
    /// marked on the next motion.
    UnitSwitched { line: u32, n: Option<u32> },
}

impl Notice {
    /// What a motion's block has to report, if anything (`BlockNotice`).
    pub fn of_command(c: &Canon) -> Option<Notice> {
        let CanonKind::Motion(m) = &c.kind else { return None };
        let (code, message, line, n) = match m.notice? {
            BlockNotice::CycleRBeyondZ => (
                "FX1004",
                "canned cycle: point R lies beyond point Z on the side the cycle cuts toward (below the hole \
                 bottom; above the top of a G87 back bore): the tool reaches R at rapid past Z and cuts back \
                 toward it, as programmed",
                c.line,
                c.n,
            ),
            BlockNotice::UnitSwitched { line, n } => (
                "FX1005",
                "inch/metric input switched after the program had moved: the manuals give G20/G21 at the \
                 program's start (FANUC: they must not be switched during a program) and do not say what the \
                 control does then; fivex reads every later word in the new unit, offsets and positions kept",
                line,
                n,
            ),
        };
        Some(Notice { code: code.into(), message: message.into(), line, n })
    }

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
