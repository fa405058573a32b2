//! The dialect layer: one place per vendor for alarm codes and messages.
//!
//! FANUC codes are the 30i's own (`PS0010`, `PS0112`…). Syntec's seed lists only its 5-axis
//! alarms (`COR-070`, `COR-153`, `MAR-406`…), the Syntec MACRO handbook a few of the interpreter's
//! (`COR-004`, `COR-052`); the codes neither prints are *constructed* in a range neither uses
//! and are marked so in `docs/dialects.md`. Haas codes are the NGC
//! mill alarm numbers (`313`, `314`…), with constructed `7xx` where no Haas source names one.

use crate::alarm::AlarmId;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "lowercase")]
pub enum Dialect {
    #[default]
    Fanuc,
    Syntec,
    /// Haas Next Generation Control (mill).
    Haas,
}

impl std::str::FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "fanuc" => Ok(Dialect::Fanuc),
            "syntec" => Ok(Dialect::Syntec),
            "haas" => Ok(Dialect::Haas),
            other => Err(format!("unknown dialect '{other}' (expected fanuc, syntec or haas)")),
        }
    }
}

impl Dialect {
    pub fn name(self) -> &'static str {
        match self {
            Dialect::Fanuc => "fanuc",
            Dialect::Syntec => "syntec",
            Dialect::Haas => "haas",
        }
    }

    /// The vendor's code and message for an alarm.
    pub fn describe(self, id: &AlarmId) -> (String, String) {
        match id {
            AlarmId::MacroAlarm { number, message } => match self {
                Dialect::Fanuc => (format!("MC{}", 3000 + number), message.clone()),
                // Haas: the user alarms are numbered 1000 + n (`docs/dialects.md`, "Haas").
                Dialect::Haas => (format!("{}", 1000 + number), message.clone()),
                Dialect::Syntec => (format!("MAR-{number:03}"), message.clone()),
            },
            // What happened (the budget ran out, not the program) and the likely cause: the
            // bare "BLOCK BUDGET EXCEEDED" read as the program's fault of an unknown kind.
            AlarmId::BlockBudgetExceeded { budget } => (
                "FX0001".into(),
                format!("BLOCK BUDGET EXCEEDED ({budget} BLOCKS RUN, PROGRAM NOT ENDED: ENDLESS LOOP?)"),
            ),
            AlarmId::TimeBudgetExceeded { budget_s } => {
                ("FX0002".into(), format!("TIME BUDGET EXCEEDED ({budget_s} S)"))
            }
            // FANUC's stroke limit check before movement; Syntec's code is constructed (MOT-).
            AlarmId::OverTravel { axis, positive, precheck } => {
                let sign = if *positive { '+' } else { '-' };
                match (self, positive) {
                    // Haas: 316–319 for X, Y, Z, A (its alarm list); the other axes constructed.
                    (Dialect::Haas, _) => {
                        let code = match axis {
                            'X' => "316",
                            'Y' => "317",
                            'Z' => "318",
                            'A' => "319",
                            _ => "725",
                        };
                        (code.into(), format!("{axis} OVER TRAVEL RANGE"))
                    }
                    // The check before movement; without it (G54.4) the stored stroke check 1 stops
                    // the axis on the way (the 30i's alarm list, not the seeds').
                    (Dialect::Fanuc, _) => {
                        let code = match (precheck, positive) {
                            (true, true) => "OT0510",
                            (true, false) => "OT0511",
                            (false, true) => "OT0500",
                            (false, false) => "OT0501",
                        };
                        let kind = if *precheck { "PRE-CHECK" } else { "SOFT 1" };
                        (code.into(), format!("{sign} OVERTRAVEL ( {kind} ) {axis}"))
                    }
                    (Dialect::Syntec, true) => {
                        ("MOT-001".into(), format!("{axis} axis exceeds positive software limit"))
                    }
                    (Dialect::Syntec, false) => {
                        ("MOT-002".into(), format!("{axis} axis exceeds negative software limit"))
                    }
                }
            }
            AlarmId::BlockOutputExceeded { limit } => {
                ("FX0003".into(), format!("BLOCK EXPANDS TO MORE THAN {limit} COMMANDS"))
            }
            plain => {
                let (fanuc, syntec) = codes(plain);
                let (code, message) = match self {
                    Dialect::Fanuc => fanuc,
                    Dialect::Syntec => syntec,
                    Dialect::Haas => haas(plain),
                };
                (code.into(), message.into())
            }
        }
    }
}

type Text = (&'static str, &'static str);

const PS5459: Text = ("PS5459", "MACHINE PARAMETER INCORRECT");
const PS5421: Text = ("PS5421", "ILLEGAL COMMAND IN G43.4/G43.5");
const COR100: Text = ("COR-100", "Unsupported G code command or option software is not activated");
/// fivex's own, in every dialect: no vendor names an alarm for it (`AlarmId::PositionInCompensation`).
const POSITION_IN_COMPENSATION: Text = ("FX0006", "POSITION READ IN CUTTER COMPENSATION NOT BUILT");
/// fivex's own, in every dialect (`AlarmId::RotaryShiftOnTipPath`).
const ROTARY_SHIFT_ON_TIP_PATH: Text = ("FX0007", "MANUAL ROTARY SHIFT ON TOOL TIP PATH NOT BUILT");
/// fivex's own, in every dialect: no vendor alarm names a missing hole bottom (FANUC's PS0045
/// is Q's alone), and no manual at hand says what the control does (`AlarmId::CycleBottomMissing`).
const CYCLE_BOTTOM_MISSING: Text = ("FX0008", "CANNED CYCLE WITHOUT HOLE BOTTOM");
/// fivex's own, in every dialect: a real control raises nothing, it waits for the spindle
/// (feed per revolution follows the position coder), which a run cannot show
/// (`AlarmId::FeedPerRevolutionSpindleStopped`).
const SPINDLE_STOPPED_IN_G95: Text = ("FX0009", "FEED PER REVOLUTION WITH THE SPINDLE STOPPED");
/// fivex's own, in every dialect: the manuals at hand give G68's R the range ±360° but no
/// alarm for one beyond it (`AlarmId::RotationAngleOutOfRange`).
const ROTATION_ANGLE_OUT_OF_RANGE: Text = ("FX0010", "ROTATION ANGLE OUT OF RANGE");
/// fivex's own, in every dialect: the manuals ask for mirror image → scaling → rotation and
/// the reverse to cancel, but name no alarm for another order (`AlarmId::TransformOrder`).
const TRANSFORM_ORDER: Text = ("FX0011", "MIRROR/SCALING/ROTATION OUT OF ORDER");
/// fivex's own, in every dialect: the manuals forbid G27–G30, G52–G59 and G92 while mirror
/// image, scaling or rotation is on, but name no alarm (`AlarmId::ReturnOrSystemInTransforms`).
const RETURN_OR_SYSTEM_IN_TRANSFORMS: Text = ("FX0012", "RETURN OR COORDINATE CHANGE IN MIRROR/SCALING/ROTATION");

/// Every alarm that carries no data (for documentation checks and exhaustive tests).
pub const PLAIN_ALARMS: &[AlarmId] = &[
    AlarmId::IllegalScaleRate,
    AlarmId::IllegalPlaneInRotation,
    AlarmId::Syntax,
    AlarmId::ImproperAddress,
    AlarmId::NoDataAfterAddress,
    AlarmId::IllegalDecimalPoint,
    AlarmId::TooManyDigits,
    AlarmId::ImproperGCode,
    AlarmId::GCodeNotBuilt,
    AlarmId::AddressNotBuilt,
    AlarmId::MCodeNotBuilt,
    AlarmId::IllegalGCodeCombination,
    AlarmId::FeedZero,
    AlarmId::IllegalOffsetNumber,
    AlarmId::ArcRadiusTolerance,
    AlarmId::ArcCentreMissing,
    AlarmId::PlaneChangeInCompensation,
    AlarmId::DataSettingFormat,
    AlarmId::IllegalG10Command,
    AlarmId::IllegalOffsetValue,
    AlarmId::MissingQ,
    AlarmId::ReferenceReturnInCycle,
    AlarmId::IllegalReferenceReturn,
    AlarmId::ReferenceReturnCheck,
    AlarmId::IllegalCommandInMode,
    AlarmId::IllegalCommandInTcp,
    AlarmId::RotaryCommandInTcpType2,
    AlarmId::ZeroToolVector,
    AlarmId::IncrementalInTcpType2,
    AlarmId::MachineCoordinatesInTcp,
    AlarmId::HpccInTcp,
    AlarmId::AxisNotInTcp,
    AlarmId::HpccFormat,
    AlarmId::MachineParameter,
    AlarmId::NoRotarySolution,
    AlarmId::MasterOutOfRange,
    AlarmId::SlaveOutOfRange,
    AlarmId::PostureCrossesPlane,
    AlarmId::NurbsFormat,
    AlarmId::NurbsBlock,
    AlarmId::NurbsStart,
    AlarmId::TcpParameter,
    AlarmId::CuttingPoint,
    AlarmId::AxisSetting,
    AlarmId::ToolDirectionSetting,
    AlarmId::ToolAxisParallel,
    AlarmId::MechanismConflict,
    AlarmId::UnitChangeInMode,
    AlarmId::ArcInCompStartCancel,
    AlarmId::CutterInterference,
    AlarmId::CutterNoSolution,
    AlarmId::CornerArcWithMove,
    AlarmId::CrcTableParameter,
    AlarmId::LeadingEdgeAlongTool,
    AlarmId::TwpFormat,
    AlarmId::TwpIllegalCommand,
    AlarmId::AlignmentInWse,
    AlarmId::WseCommand,
    AlarmId::WseModalState,
    AlarmId::WseBasicAxes,
    AlarmId::WseToolDirection,
    AlarmId::WseUnreachable,
    AlarmId::AlignmentP,
    AlarmId::AlignmentInCompensation,
    AlarmId::AlignmentToolZero,
    AlarmId::ChainQ,
    AlarmId::ChainSwitchInMode,
    AlarmId::ChainNotConfigured,
    AlarmId::ChainNotSpindle,
    AlarmId::ChainCommand,
    AlarmId::MacroFormat,
    AlarmId::VariableOutOfRange,
    AlarmId::WriteProtectedVariable,
    AlarmId::ZeroDivide,
    AlarmId::BracketNesting,
    AlarmId::ArgumentOutOfRange,
    AlarmId::NegativePowerBase,
    AlarmId::UnitNotDecided,
    AlarmId::FloatOverflow,
    AlarmId::MissingEnd,
    AlarmId::IllegalLoopNumber,
    AlarmId::IllegalSequenceNumber,
    AlarmId::ProgramNotFound,
    AlarmId::LineNotFound,
    AlarmId::MissingP,
    AlarmId::NestingTooDeep,
    AlarmId::EndOfRecord,
    AlarmId::GAsArgument,
    AlarmId::MixedStatements,
    AlarmId::EmergencyStop,
    AlarmId::RestartBlockNotFound,
    AlarmId::RestartPNoRun,
    AlarmId::RestartPCoordinatesChanged,
    AlarmId::RestartPExternalOffsetChanged,
    AlarmId::RestartPOffsetChanged,
    AlarmId::RestartMdi,
    AlarmId::RestartInMode,
    AlarmId::PositionInCompensation,
    AlarmId::RotaryShiftOnTipPath,
    AlarmId::CycleBottomMissing,
    AlarmId::FeedPerRevolutionSpindleStopped,
    AlarmId::RotationAngleOutOfRange,
    AlarmId::TransformOrder,
    AlarmId::ReturnOrSystemInTransforms,
    AlarmId::TcpcNoToolLength,
    AlarmId::DwoRotaryMotion,
    AlarmId::DwoXyzNotGiven,
    AlarmId::DwoWorkOffsetTilt,
    AlarmId::DwoWithTcpc,
    AlarmId::CycleArgument,
    AlarmId::SkipInCutterComp,
    AlarmId::SkipSignalFound,
    AlarmId::SkipSignalNotFound,
    AlarmId::CornerNextBlock,
    AlarmId::CornerNotG01,
    AlarmId::CornerTooShort,
    AlarmId::CornerRoundingInMode,
    AlarmId::LengthCompWithoutH,
];

/// (FANUC, Syntec) code and message of every alarm that carries no data.
fn codes(id: &AlarmId) -> (Text, Text) {
    use AlarmId::*;
    match id {
        Syntax => (("PS0004", "INVALID BREAK POINT OF WORDS"), ("COR-001", "Syntax error")),
        ImproperAddress => (("PS0009", "IMPROPER NC-ADDRESS"), ("COR-002", "Illegal address")),
        NoDataAfterAddress => (("PS0005", "NO DATA AFTER ADDRESS"), ("COR-003", "Missing value after address")),
        // Raised in the FANUC dialect only; Syntec's column for completeness.
        IllegalDecimalPoint => (("PS0007", "ILLEGAL USE OF DECIMAL POINT"), ("COR-001", "Syntax error")),
        // (Syntec: constructed; COR-004 is the handbook's operation domain error, below.)
        TooManyDigits => (("PS0003", "TOO MANY DIGITS"), ("COR-042", "Value out of range")),
        ImproperGCode => (("PS0010", "IMPROPER G-CODE"), ("COR-070", "Invalid G Code")),
        // FANUC's alarms for a G code / an address of a function the control does not have;
        // Syntec's COR-100 names the option not activated (both from the manuals' alarm lists).
        GCodeNotBuilt => (("PS0010", "IMPROPER G-CODE"), COR100),
        AddressNotBuilt => (("PS0009", "IMPROPER NC-ADDRESS"), COR100),
        // Raised in the Haas dialect only; FANUC's and Syntec's columns for completeness.
        MCodeNotBuilt => (("PS0009", "IMPROPER NC-ADDRESS"), COR100),
        IllegalGCodeCombination => (("PS0010", "IMPROPER G-CODE"), ("COR-070", "Invalid G Code")),
        FeedZero => (("PS0011", "FEED ZERO ( COMMAND )"), ("COR-010", "Feedrate is zero")),
        IllegalOffsetNumber => (("PS0030", "ILLEGAL OFFSET NUMBER"), ("COR-011", "Illegal offset number")),
        ArcRadiusTolerance => (("PS0020", "OVER TOLERANCE OF RADIUS"), ("COR-012", "Arc end point not on the arc")),
        ArcCentreMissing => (("PS0022", "R OR I,J,K COMMAND NOT FOUND"), ("COR-017", "Arc radius or centre missing")),
        PlaneChangeInCompensation => {
            (("PS0037", "CAN NOT CHANGE PLANE IN G41/G42"), ("COR-013", "Plane change in cutter compensation"))
        }
        DataSettingFormat => (("PS1144", "G10 FORMAT ERROR"), ("COR-014", "G10 format error")),
        // The 30i alarm list's (`docs/dialects.md`, "G10 data checks"); Syntec's constructed.
        IllegalG10Command => (("PS0031", "ILLEGAL P COMMAND IN G10"), ("COR-046", "Illegal P or R command in G10")),
        IllegalOffsetValue => (("PS0032", "ILLEGAL OFFSET VALUE IN G10"), ("COR-047", "Offset value out of range")),
        MissingQ => (("PS0045", "ADDRESS Q NOT FOUND (G73/G83)"), ("COR-015", "Peck depth Q missing")),
        // Raised by the Haas cycles alone (G12/G13, G70–G72, G103: not codes of the other
        // dialects); the columns are the other dialects' alarms for a wrong address value.
        CycleArgument => (("PS0009", "IMPROPER NC-ADDRESS"), ("COR-002", "Illegal address")),
        ReferenceReturnInCycle => {
            // (Syntec: constructed; COR-016 is the handbook's illegal variable access.)
            (("PS0044", "G27-G30 NOT ALLOWED IN FIXED CYC"), ("COR-043", "Reference return in canned cycle"))
        }
        IllegalCommandInMode => (
            ("PS5460", "ILLEGAL COMMAND IN 5-AXIS MODE"),
            ("COR-100", "Unsupported G code command or option software is not activated"),
        ),
        IllegalCommandInTcp => (PS5421, COR100),
        RotaryCommandInTcpType2 => {
            (PS5421, ("COR-158", "Prohibit the 1st and 2nd rotary axis commands in the G43.5 mode"))
        }
        ZeroToolVector => (PS5421, ("COR-159", "Illegal tool vector")),
        IncrementalInTcpType2 => (PS5421, ("COR-305", "Relative position input method is forbidden in current mode")),
        MachineCoordinatesInTcp => (PS5421, ("COR-118", "Prohibit G53 commands in tool tip control mode")),
        HpccInTcp => (PS5421, ("COR-140", "Prohibit G05 in tool tip control mode")),
        AxisNotInTcp => (PS5421, ("COR-107", "G5.1/G05 command format error")),
        // Syntec only: FANUC refuses its G05 other than P0 as not built (PS0010).
        HpccFormat => (("PS0010", "IMPROPER G-CODE"), ("COR-107", "G5.1/G05 command format error")),
        MachineParameter => (PS5459, ("COR-154", "No 5-axis function")),
        NoRotarySolution => (PS5459, ("COR-153", "Tool direction unknown")),
        // Syntec only: FANUC's movement ranges only choose among solutions (No.19741–19744).
        MasterOutOfRange => (PS5459, ("COR-151", "1st rotation axis entering illegal range")),
        SlaveOutOfRange => (PS5459, ("COR-152", "2nd rotation axis entering illegal range")),
        // FANUC only (Syntec turns the tool on the great circle on arcs too).
        PostureCrossesPlane => (("PS0432", "UNAVAILABLE POSTURE IN TPC"), COR100),
        // FANUC 30i's NURBS alarms, numbers from memory of its alarm list (no seed holds them,
        // `docs/dialects.md`); Syntec refuses G06.2 (COR-100) and never raises them.
        NurbsFormat => (("PS5115", "SPL : ERROR"), COR100),
        NurbsBlock => (("PS5116", "SPL : ERROR"), COR100),
        NurbsStart => (("PS5117", "SPL : ERROR"), COR100),
        TcpParameter => (("PS5420", "ILLEGAL PARAMETER IN G43.4/G43.5"), COR100),
        // The number is the 5-axis manual's (§2.3.20, §2.3.21), the text fivex's; G43.8/G43.9
        // are not Syntec codes.
        CuttingPoint => (("PS5464", "ILLEGAL COMMAND IN CUTTING POINT CONTROL"), COR100),
        AxisSetting => (PS5459, ("COR-156", "5-axis axial direction error")),
        ToolDirectionSetting => (PS5459, ("COR-155", "5-axis tool direction error")),
        ToolAxisParallel => {
            (PS5459, ("COR-157", "Incompatible direction of 5-axis tool direction and this of rotation axis"))
        }
        MechanismConflict => (PS5459, ("OP-032", "Mechanism type configuration conflicted")),
        UnitChangeInMode => (("PS5000", "G20/G21 NOT ALLOWED IN 5-AXIS MODE"), COR100),
        ArcInCompStartCancel => (("PS0034", "NO CIRC ALLOWED IN ST-UP/EXT BLK"), COR100),
        // The 30i's numbers and texts; no Syntec source names its cutter compensation alarms.
        CutterInterference => (("PS0041", "INTERFERENCE IN CRC"), COR100),
        CutterNoSolution => (("PS0033", "NO SOLUTION AT CRC"), COR100),
        // The number is the 15i-MA manual's (§14.4.9), the text fivex's.
        CornerArcWithMove => (("PS0273", "MOVE COMMAND IN G39 BLOCK"), COR100),
        // The number is the 5-axis manual's (§3.2.2, §3.3.2), the text fivex's (modelled on
        // PS5420's); Syntec has no table coordinate system for its cutter compensation.
        CrcTableParameter => (("PS5483", "ILLEGAL PARAMETER IN 3-D CUTTER COMPENSATION"), COR100),
        // The number is the 5-axis manual's (§3.1.4), the text fivex's; G41.3 is not a Syntec code.
        LeadingEdgeAlongTool => (("PS5408", "G41.3 MOVE ALONG THE TOOL AXIS"), COR100),
        TwpFormat => (("PS5457", "G68.2/G68.3 FORMAT ERROR"), ("COR-141", "G68.3 command format error")),
        TwpIllegalCommand => (("PS5462", "ILLEGAL COMMAND (G68.2/G69)"), COR100),
        AlignmentInWse => (("PS5458", "G53.1 NOT ALLOWED IN G54.4 MODE"), COR100),
        WseCommand => (("PS0437", "ILLEGAL COMMAND IN G54.4"), COR100),
        WseModalState => (("PS0439", "G54.4 NOT ALLOWED IN THIS MODAL STATE"), COR100),
        // The extract gives the numbers of these three, not FANUC's texts.
        WseBasicAxes => (("PS0436", "BASIC AXES X, Y, Z NOT SET (G54.4)"), COR100),
        WseToolDirection => (("PS0438", "ILLEGAL COMMAND IN G54.4 (TOOL DIRECTION)"), COR100),
        WseUnreachable => (("DS0030", "G54.4 TOOL DIRECTION NOT REACHABLE"), COR100),
        AlignmentP => (("PS5457", "G68.2/G68.3 FORMAT ERROR"), ("COR-149", "G53.1/G53.6 P Argument over range")),
        AlignmentInCompensation => {
            (("PS5460", "ILLEGAL COMMAND IN 5-AXIS MODE"), ("MAR-406", "G53.6 must be enabled in G40 mode"))
        }
        AlignmentToolZero => {
            (("PS0030", "ILLEGAL OFFSET NUMBER"), ("MAR-407", "Tool number can not be 0 while using G53.6"))
        }
        ChainQ => {
            (("PS1144", "G10 FORMAT ERROR"), ("COR-163", "Multi-kinematic chain command Q argument setting error"))
        }
        ChainSwitchInMode => (
            ("PS1144", "G10 FORMAT ERROR"),
            ("COR-160", "5-axis mechanism chain switched when the 5-axis function is ON"),
        ),
        // FANUC has no G10 L5000 (its G10 refuses the L): these three are Syntec's alone.
        ChainNotConfigured => {
            (("PS1144", "G10 FORMAT ERROR"), ("COR-161", "Selected 5-axis mechanism chain is not ON"))
        }
        ChainNotSpindle => (
            ("PS1144", "G10 FORMAT ERROR"),
            ("COR-164", "Multi-kinematic chain command related 5-Axis mechanism setting error"),
        ),
        ChainCommand => {
            (("PS5460", "ILLEGAL COMMAND IN 5-AXIS MODE"), ("COR-165", "Multi-kinematic chain command not illegal"))
        }
        IllegalReferenceReturn => {
            (("PS0046", "ILLEGAL REFERENCE RETURN COMMAND"), ("COR-036", "Illegal reference position number"))
        }
        // (FANUC's number and text as the 0i/16i lists give them, to check against the 30i's;
        // Syntec: constructed, its G27 is not built.)
        ReferenceReturnCheck => {
            (("PS0092", "ZERO RETURN CHECK (G27) ERROR"), ("COR-050", "Reference position return check error"))
        }
        // (Syntec: constructed; COR-034 is the handbook's missing path-extension argument.)
        IllegalScaleRate => (("PS0142", "ILLEGAL SCALE RATE"), ("COR-045", "Illegal scaling magnification")),
        IllegalPlaneInRotation => (("PS0144", "ILLEGAL PLANE SELECTED"), ("COR-035", "Arc outside the rotation plane")),
        MacroFormat => (("PS0125", "MACRO STATEMENT FORMAT ERROR"), ("COR-020", "Macro statement format error")),
        // Syntec: the handbook's "不合法的变数存取" (§2.8, §9.14: a variable outside the open
        // ranges, or not allowed where it is used).
        VariableOutOfRange => (("PS0115", "VARIABLE NO. OUT OF RANGE"), ("COR-016", "Illegal variable access")),
        WriteProtectedVariable => (("PS0116", "WRITE PROTECTED VARIABLE"), ("COR-022", "Variable is read-only")),
        // Syntec: the Syntec MACRO handbook's §9.14 alarm table names COR-004 "运算域错误" (an
        // operation's domain error, its example ATAN2(0,0)): the code of the arguments a function
        // is not defined for, and (constructed: the handbook names no code for it) of a zero
        // divisor, the same class. Its COR-023 is a semantic error (a wrong argument type).
        ZeroDivide => (("PS0112", "ZERO DIVIDE"), ("COR-004", "Operation domain error: division by zero")),
        BracketNesting => (("PS0118", "PARENTHESIS NESTING LEVEL"), ("COR-024", "Too many nested brackets")),
        ArgumentOutOfRange => (("PS0119", "ARGUMENT VALUE OUT OF RANGE"), ("COR-004", "Operation domain error")),
        // Raised in the Syntec dialect only (the handbook's §9.14 code; the message is fivex's).
        NegativePowerBase => (("PS0119", "ARGUMENT VALUE OUT OF RANGE"), ("COR-122", "POW with a negative base")),
        // Raised in the Syntec dialect only (constructed; FANUC and Haas read such a number in
        // least increments: their columns are for completeness).
        UnitNotDecided => (
            ("PS0007", "ILLEGAL USE OF DECIMAL POINT"),
            ("COR-048", "Length or angle without a decimal point: write X10. or X[1.0*#1]"),
        ),
        FloatOverflow => (("PS0111", "OVERFLOW :FLOAT"), ("COR-026", "Calculation overflow")),
        // (Syntec: constructed; COR-027 is the handbook's ALARM() macro alarm.)
        MissingEnd => (("PS0124", "MISSING END STATEMENT"), ("COR-044", "DO without END")),
        IllegalLoopNumber => (("PS0126", "ILLEGAL LOOP NUMBER"), ("COR-028", "Illegal loop number")),
        IllegalSequenceNumber => (("PS0128", "ILLEGAL MACRO SEQUENCE NUMBER"), ("COR-029", "GOTO target not found")),
        ProgramNotFound => (("PS0078", "NUMBER NOT FOUND"), ("COR-030", "Program or sequence number not found")),
        // FANUC and Syntec raise their "not found" alarm for a line (PS0078 / COR-030), as before
        // the Haas dialect split it out; FANUC for a missing P too.
        LineNotFound => (("PS0078", "NUMBER NOT FOUND"), ("COR-030", "Program or sequence number not found")),
        // Syntec: raised by M198 without P only, the handbook's code for it (call semantics
        // pack §2.2: "`M198 P_ H_ L_` 必须有 `P`；缺失时会触发 `COR-052`"); its message is fivex's.
        MissingP => (("PS0078", "NUMBER NOT FOUND"), ("COR-052", "Program number P missing")),
        NestingTooDeep => (("PS0077", "TOO MANY SUB,MACRO NESTING"), ("COR-031", "Too many nested calls")),
        // Raised in the FANUC dialect only (Syntec and Haas return at the end of a called
        // program's text: no source of theirs says otherwise); the others' codes are constructed.
        EndOfRecord => (("PS5010", "END OF RECORD"), ("COR-049", "End of record")),
        GAsArgument => (("PS0129", "USE 'G' AS ARGUMENT"), ("COR-032", "G used as macro argument")),
        MixedStatements => {
            (("PS0127", "DUPLICATE NC, MACRO STATEMENT"), ("COR-033", "NC and macro statement in one block"))
        }
        EmergencyStop => (("FX0004", "EMERGENCY STOP"), ("FX0004", "EMERGENCY STOP")),
        // Program restart (FANUC only: the Syntec manuals fivex follows do not describe it).
        RestartBlockNotFound => (("PS0071", "DATA NOT FOUND"), ("COR-037", "Restart block not found")),
        RestartPNoRun => (("PS0097", "P TYPE NOT ALLOWED (AUTO EXEC)"), ("COR-038", "Restart type P not allowed")),
        // Syntec: constructed (never shown, the restart is refused first).
        RestartPCoordinatesChanged => {
            (("PS0094", "P TYPE NOT ALLOWED (COORD CHG)"), ("COR-039", "Restart type P not allowed"))
        }
        RestartPExternalOffsetChanged => {
            (("PS0095", "P TYPE NOT ALLOWED (EXT OFS CHG)"), ("COR-039", "Restart type P not allowed"))
        }
        RestartPOffsetChanged => {
            (("PS0096", "P TYPE NOT ALLOWED (WRK OFS CHG)"), ("COR-039", "Restart type P not allowed"))
        }
        RestartMdi => (("PS0099", "MDI EXEC NOT ALLOWED AFT. SEARCH"), ("COR-040", "MDI after restart search")),
        RestartInMode => {
            (("FX0005", "RESTART NOT ALLOWED IN THIS MODE"), ("FX0005", "RESTART NOT ALLOWED IN THIS MODE"))
        }
        PositionInCompensation => (POSITION_IN_COMPENSATION, POSITION_IN_COMPENSATION),
        RotaryShiftOnTipPath => (ROTARY_SHIFT_ON_TIP_PATH, ROTARY_SHIFT_ON_TIP_PATH),
        CycleBottomMissing => (CYCLE_BOTTOM_MISSING, CYCLE_BOTTOM_MISSING),
        FeedPerRevolutionSpindleStopped => (SPINDLE_STOPPED_IN_G95, SPINDLE_STOPPED_IN_G95),
        RotationAngleOutOfRange => (ROTATION_ANGLE_OUT_OF_RANGE, ROTATION_ANGLE_OUT_OF_RANGE),
        TransformOrder => (TRANSFORM_ORDER, TRANSFORM_ORDER),
        ReturnOrSystemInTransforms => (RETURN_OR_SYSTEM_IN_TRANSFORMS, RETURN_OR_SYSTEM_IN_TRANSFORMS),
        // Haas G234/G254 are not codes of FANUC or Syntec (their improper G code alarm); the
        // Haas codes are constructed in `haas`.
        TcpcNoToolLength | DwoRotaryMotion | DwoXyzNotGiven | DwoWorkOffsetTilt | DwoWithTcpc => {
            (("PS0010", "IMPROPER G-CODE"), ("COR-070", "Invalid G Code"))
        }
        // FANUC's from its alarm list (G31 in cutter compensation C); Syntec's constructed.
        SkipInCutterComp => (("PS0035", "CAN NOT COMMANDED G31"), ("COR-041", "G31 in cutter compensation")),
        // Haas M78/M79 are no M codes of FANUC or Syntec: never raised there.
        SkipSignalFound | SkipSignalNotFound => (("PS0010", "IMPROPER G-CODE"), ("COR-070", "Invalid G Code")),
        // The numbers and texts of the FANUC 30i alarm list (`docs/dialects.md`, "Chamfering
        // and corner R"); Syntec's ,C/,R are refused as not built, so never raised there.
        CornerNextBlock => (("PS0051", "MISSING MOVE AFTER CNR/CHF"), COR100),
        CornerNotG01 => (("PS0052", "CODE IS NOT G01 AFTER CNR/CHF"), COR100),
        CornerTooShort => (("PS0055", "MISSING MOVE VALUE IN CHF/CNR"), COR100),
        // Raised in the Haas dialect only (G187 is the NGC's); the columns for completeness.
        CornerRoundingInMode => (("PS0010", "IMPROPER G-CODE"), COR100),
        // Raised in the Haas dialect only (FANUC and Syntec run G43 with the H in force, H0 a
        // length of 0); the columns are their alarms for a wrong offset number.
        LengthCompWithoutH => (("PS0030", "ILLEGAL OFFSET NUMBER"), ("COR-011", "Illegal offset number")),
        // Alarms with data are described in `Dialect::describe`; this arm is never taken.
        MacroAlarm { .. }
        | BlockBudgetExceeded { .. }
        | TimeBudgetExceeded { .. }
        | BlockOutputExceeded { .. }
        | OverTravel { .. } => (("FX0000", "ALARM"), ("FX0000", "ALARM")),
    }
}

/// Haas NGC code and message of every alarm that carries no data. The numbers 1xx–5xx are the
/// Haas mill alarm list's (program 3xx, macro 5xx); 7xx are **constructed** for conditions no
/// Haas source names, in a range the list does not use (`docs/dialects.md`, "Haas").
fn haas(id: &AlarmId) -> Text {
    use AlarmId::*;
    const INVALID_G: Text = ("310", "INVALID G CODE");
    const UNKNOWN: Text = ("311", "UNKNOWN CODE");
    const RANGE: Text = ("331", "RANGE ERROR");
    const FIVE_AXIS: Text = ("730", "ILLEGAL COMMAND IN 5-AXIS MODE");
    const TCP: Text = ("731", "ILLEGAL COMMAND IN TCPC");
    const SETTING: Text = ("732", "MACHINE SETTING INCORRECT FOR 5-AXIS");
    const PLANE: Text = ("733", "ILLEGAL COMMAND IN TILTED PLANE");
    const WSE: Text = ("734", "ILLEGAL COMMAND IN WORK SETTING ERROR COMP");
    const NURBS: Text = ("735", "NURBS FORMAT ERROR");
    const RESTART: Text = ("740", "RESTART NOT POSSIBLE");
    match id {
        Syntax | ImproperAddress | AddressNotBuilt => UNKNOWN,
        NoDataAfterAddress => ("701", "NO VALUE AFTER ADDRESS"),
        // Raised in the FANUC dialect only (a Haas P with a point is seconds).
        IllegalDecimalPoint => ("311", "UNKNOWN CODE"),
        TooManyDigits | IllegalOffsetNumber | IllegalG10Command | IllegalOffsetValue => RANGE,
        ImproperGCode | GCodeNotBuilt => INVALID_G,
        MCodeNotBuilt => ("329", "UNDEFINED M CODE"),
        IllegalGCodeCombination => ("339", "MULTIPLE CODES"),
        FeedZero => ("320", "NO FEED RATE SPECIFIED"),
        ArcRadiusTolerance | ArcCentreMissing => ("338", "INVALID IJK AND XYZ IN G02 OR G03"),
        PlaneChangeInCompensation => ("702", "PLANE CHANGE IN CUTTER COMP"),
        DataSettingFormat => ("703", "G10 FORMAT ERROR"),
        MissingQ => ("305", "INVALID Q IN CANNED CYCLE"),
        ReferenceReturnInCycle => ("704", "G28 NOT ALLOWED IN CANNED CYCLE"),
        IllegalReferenceReturn => ("705", "ILLEGAL REFERENCE RETURN"),
        ReferenceReturnCheck => ("756", "G27 REFERENCE RETURN CHECK ERROR"),
        IllegalScaleRate => ("706", "ILLEGAL SCALE FACTOR"),
        IllegalPlaneInRotation => ("707", "ILLEGAL PLANE IN ROTATION"),
        UnitChangeInMode => ("708", "G20/G21 NOT ALLOWED IN THIS MODE"),
        ArcInCompStartCancel => ("340", "CUTTER COMP BEGIN WITH G02 OR G03"),
        CutterInterference => ("367", "CUTTER COMP INTERFERENCE"),
        CutterNoSolution => ("342", "CUTTER COMP PATH TOO SMALL"),
        CornerArcWithMove | CrcTableParameter | LeadingEdgeAlongTool => INVALID_G,
        IllegalCommandInMode | ChainSwitchInMode | ChainCommand | AlignmentInCompensation => FIVE_AXIS,
        IllegalCommandInTcp | RotaryCommandInTcpType2 | ZeroToolVector | IncrementalInTcpType2 => TCP,
        MachineCoordinatesInTcp | HpccInTcp | AxisNotInTcp | TcpParameter | CuttingPoint => TCP,
        HpccFormat => INVALID_G,
        MachineParameter | AxisSetting | ToolDirectionSetting | ToolAxisParallel | MechanismConflict => SETTING,
        ChainQ | ChainNotConfigured | ChainNotSpindle => SETTING,
        NoRotarySolution => ("736", "NO ROTARY AXIS SOLUTION"),
        MasterOutOfRange | SlaveOutOfRange => ("737", "ROTARY AXIS OUT OF RANGE"),
        PostureCrossesPlane => TCP,
        NurbsFormat | NurbsBlock | NurbsStart => NURBS,
        TwpFormat | TwpIllegalCommand | AlignmentP | AlignmentToolZero => PLANE,
        AlignmentInWse | WseCommand | WseModalState | WseBasicAxes | WseToolDirection | WseUnreachable => WSE,
        MacroFormat => ("540", "MACRO SYNTAX NOT ALLOWED"),
        VariableOutOfRange => ("503", "ILLEGAL MACRO VARIABLE REFERENCE"),
        WriteProtectedVariable => ("522", "ILLEGAL ASSIGNMENT VAR OR VALUE"),
        ZeroDivide => ("508", "DIVISION BY ZERO"),
        BracketNesting => ("504", "UNBALANCED PAREN. IN EXPRESSION"),
        ArgumentOutOfRange | NegativePowerBase => ("521", "ILLEGAL FUNCTIONAL PARAMETER"),
        UnitNotDecided => ("311", "UNKNOWN CODE"),
        FloatOverflow => ("709", "CALCULATION OVERFLOW"),
        MissingEnd => ("538", "MATCHING END NOT FOUND"),
        IllegalLoopNumber => ("534", "DO OR END ALREADY IN USE"),
        IllegalSequenceNumber | LineNotFound => ("337", "GOTO OR P LINE NOT FOUND"),
        ProgramNotFound => ("314", "SUBPROGRAM NOT IN MEMORY"),
        MissingP => ("313", "NO P CODE IN M97, M98 OR G65"),
        NestingTooDeep => ("307", "SUBROUTINE NESTING TOO DEEP"),
        EndOfRecord => ("755", "END OF RECORD"),
        GAsArgument => ("529", "ILLEGAL G65 PARAMETER"),
        MixedStatements => ("710", "NC AND MACRO STATEMENT IN ONE BLOCK"),
        EmergencyStop => ("107", "EMERGENCY OFF"),
        RestartBlockNotFound
        | RestartPNoRun
        | RestartPCoordinatesChanged
        | RestartPExternalOffsetChanged
        | RestartPOffsetChanged
        | RestartMdi => RESTART,
        RestartInMode => ("FX0005", "RESTART NOT ALLOWED IN THIS MODE"),
        PositionInCompensation => POSITION_IN_COMPENSATION,
        RotaryShiftOnTipPath => ROTARY_SHIFT_ON_TIP_PATH,
        CycleBottomMissing => CYCLE_BOTTOM_MISSING,
        FeedPerRevolutionSpindleStopped => SPINDLE_STOPPED_IN_G95,
        RotationAngleOutOfRange => ROTATION_ANGLE_OUT_OF_RANGE,
        TransformOrder => TRANSFORM_ORDER,
        ReturnOrSystemInTransforms => RETURN_OR_SYSTEM_IN_TRANSFORMS,
        // The manual's rules for G234/G254 (`docs/dialects.md`, "Haas 5-axis"): constructed.
        // A bad argument of a Haas cycle (G12/G13, G70–G72): constructed.
        CycleArgument => ("746", "INVALID CYCLE ARGUMENT"),
        TcpcNoToolLength => ("741", "G234 WITHOUT TOOL LENGTH OFFSET (H)"),
        DwoRotaryMotion => ("742", "ROTARY MOTION NOT ALLOWED WITH G254"),
        DwoXyzNotGiven => ("743", "X, Y AND Z NOT COMMANDED AFTER G254"),
        DwoWorkOffsetTilt => ("744", "G254 WORK OFFSET TILT AXIS NOT ZERO"),
        DwoWithTcpc => ("745", "G254 AND G234 CANNOT BE COMBINED"),
        SkipInCutterComp => ("747", "G31 NOT ALLOWED WITH CUTTER COMPENSATION"),
        SkipSignalFound => ("748", "SKIP SIGNAL FOUND (M78)"),
        SkipSignalNotFound => ("749", "SKIP SIGNAL NOT FOUND (M79)"),
        // No Haas source names the alarms of ,C/,R: constructed.
        CornerNextBlock => ("750", "NO LINEAR MOVE AFTER CHAMFER OR CORNER R"),
        CornerNotG01 => ("751", "RAPID MOVE AFTER CHAMFER OR CORNER R"),
        CornerTooShort => ("752", "MOVE TOO SHORT FOR CHAMFER OR CORNER R"),
        // Constructed: fivex's refusal, not the NGC's (which was `310 INVALID G CODE`, calling the
        // valid G254 or G234 invalid).
        CornerRoundingInMode => ("753", "G187 CORNER ROUNDING NOT BUILT IN THIS MODE"),
        // Constructed: no Haas source says what the NGC does with G43/G44 and no H
        // (`docs/dialects.md`, "Haas: the dialect's core"), so fivex refuses it.
        LengthCompWithoutH => ("754", "G43/G44 WITHOUT TOOL LENGTH OFFSET (H)"),
        // Alarms with data are described in `Dialect::describe`; this arm is never taken.
        MacroAlarm { .. }
        | BlockBudgetExceeded { .. }
        | TimeBudgetExceeded { .. }
        | BlockOutputExceeded { .. }
        | OverTravel { .. } => ("FX0000", "ALARM"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fanuc_and_syntec_codes_differ_per_dialect() {
        assert_eq!(Dialect::Fanuc.describe(&AlarmId::ImproperGCode).0, "PS0010");
        assert_eq!(Dialect::Syntec.describe(&AlarmId::ImproperGCode).0, "COR-070");
        assert_eq!(Dialect::Fanuc.describe(&AlarmId::ZeroDivide).0, "PS0112");
    }

    #[test]
    fn docs_list_every_alarm_code() {
        // The table of docs/dialects.md, row for row; on a mismatch the message shows it whole.
        let table: String = PLAIN_ALARMS
            .iter()
            .map(|id| {
                let (fc, fm) = Dialect::Fanuc.describe(id);
                let (sc, sm) = Dialect::Syntec.describe(id);
                let (hc, hm) = Dialect::Haas.describe(id);
                format!("| `{id:?}` | `{fc}` {fm} | `{sc}` {sm} | `{hc}` {hm} |\n")
            })
            .collect();
        let docs = include_str!("../../docs/dialects.md");
        assert!(docs.contains(&table), "docs/dialects.md must contain this alarm table:\n{table}");
    }

    #[test]
    fn macro_alarm_numbering() {
        let id = AlarmId::MacroAlarm { number: 12, message: "TOOL BROKEN".into() };
        assert_eq!(Dialect::Fanuc.describe(&id), ("MC3012".into(), "TOOL BROKEN".into()));
        assert_eq!(Dialect::Syntec.describe(&id), ("MAR-012".into(), "TOOL BROKEN".into()));
        assert_eq!(Dialect::Haas.describe(&id), ("1012".into(), "TOOL BROKEN".into()));
    }

    #[test]
    fn haas_program_alarms() {
        let code = |id: AlarmId| Dialect::Haas.describe(&id);
        assert_eq!(code(AlarmId::MissingP), ("313".into(), "NO P CODE IN M97, M98 OR G65".into()));
        assert_eq!(code(AlarmId::ProgramNotFound).0, "314");
        assert_eq!(code(AlarmId::ImproperGCode), ("310".into(), "INVALID G CODE".into()));
        assert_eq!(code(AlarmId::LineNotFound).0, "337");
        // FANUC keeps its one "not found" alarm for all three.
        for id in [AlarmId::MissingP, AlarmId::LineNotFound, AlarmId::ProgramNotFound] {
            assert_eq!(Dialect::Fanuc.describe(&id).0, "PS0078");
        }
        let ot = AlarmId::OverTravel { axis: 'Z', positive: false, precheck: true };
        assert_eq!(Dialect::Haas.describe(&ot), ("318".into(), "Z OVER TRAVEL RANGE".into()));
    }
}
