//! Vendor-neutral alarm identities. The dialect (`crate::dialect`) turns an [`AlarmId`] into the
//! vendor's code and message; everything below the dialect layer speaks only in `AlarmId`s.

use serde::Serialize;

/// What went wrong, independent of the vendor's numbering.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum AlarmId {
    // --- NC words and blocks -------------------------------------------------------------
    /// A character or word that is not valid NC syntax.
    Syntax,
    /// An address letter that means nothing here.
    ImproperAddress,
    /// An address without a value.
    NoDataAfterAddress,
    /// A value with too many digits or out of the address's range.
    TooManyDigits,
    /// An unknown G code, or a G code not allowed in the current mode.
    ImproperGCode,
    /// Two G codes in one block that cannot be combined (for example two group 00 codes).
    IllegalGCodeCombination,
    /// Cutting feed commanded while the feedrate is zero.
    FeedZero,
    /// Offset number (H, D, P of G10) out of range.
    IllegalOffsetNumber,
    /// A circle whose end point is not on it, or a bad radius.
    ArcRadiusTolerance,
    /// A plane change while cutter compensation is on.
    PlaneChangeInCompensation,
    /// Data setting (G10) with a wrong L/P or format.
    DataSettingFormat,
    /// Canned cycle without the Q it needs (G73/G83).
    MissingQ,
    /// Reference return commands not allowed in a canned cycle.
    ReferenceReturnInCycle,
    /// A G code that is not allowed in the current 5-axis mode (FANUC PS5460 family).
    IllegalCommandInMode,
    // --- custom macro ---------------------------------------------------------------------
    /// A macro statement that does not follow the grammar.
    MacroFormat,
    /// A variable number that does not exist.
    VariableOutOfRange,
    /// A write to a read-only variable (#0, read-only system variables).
    WriteProtectedVariable,
    /// Division by zero (also MOD 0).
    ZeroDivide,
    /// More than 5 nested brackets.
    BracketNesting,
    /// A function argument outside its domain.
    ArgumentOutOfRange,
    /// A result that is not a finite number.
    FloatOverflow,
    /// DO without its END.
    MissingEnd,
    /// A loop number other than 1, 2, 3, crossing ranges, or a jump into a loop.
    IllegalLoopNumber,
    /// GOTO to a sequence number that does not exist.
    IllegalSequenceNumber,
    /// A called program (M98/G65/G66) or a return sequence number (M99 P) that does not exist.
    ProgramNotFound,
    /// Too many nested subprogram or macro calls.
    NestingTooDeep,
    /// G used as a G65 argument.
    GAsArgument,
    /// A macro statement and an NC statement in one block.
    MixedStatements,
    /// `#3000 = n (MSG)`: the program's own alarm.
    MacroAlarm { number: u32, message: String },
    // --- fivex's own guards ---------------------------------------------------------------
    /// The block budget was used up: an endless loop or endless recursion.
    BlockBudgetExceeded { budget: u64 },
    /// The simulated-time budget was used up.
    TimeBudgetExceeded { budget_s: f64 },
}

/// An alarm as a user sees it: the dialect's code and message, where it happened.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Alarm {
    pub code: String,
    pub message: String,
    /// 1-based line in the program file.
    pub line: u32,
    /// Sequence number of the block, if it has one.
    pub n: Option<u32>,
}
