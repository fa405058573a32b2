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
    /// A decimal point at an address that takes none (FANUC: the dwell's P).
    IllegalDecimalPoint,
    /// A value with too many digits or out of the address's range.
    TooManyDigits,
    /// An unknown G code, or a G code not allowed in the current mode.
    ImproperGCode,
    /// A G code (or the mode an address value selects with it) of a function fivex does not
    /// carry out (`interp::unbuilt`): refused rather than run with a wrong tool path.
    GCodeNotBuilt,
    /// An address fivex reads but no function of it uses (`interp::unbuilt`).
    AddressNotBuilt,
    /// Haas: an M code whose function fivex does not carry out (`interp::unbuilt::haas_m_code`).
    MCodeNotBuilt,
    /// Two G codes in one block that cannot be combined (for example two group 00 codes).
    IllegalGCodeCombination,
    /// Cutting feed commanded while the feedrate is zero.
    FeedZero,
    /// Offset number (H, D, P of G10) out of range.
    IllegalOffsetNumber,
    /// A circle whose end point is not on it, or a bad radius.
    ArcRadiusTolerance,
    /// A circle given neither its radius R nor its centre (I, J, K of the plane).
    ArcCentreMissing,
    /// A plane change while cutter compensation is on.
    PlaneChangeInCompensation,
    /// Data setting (G10) with a wrong L or format (no L, an L no form has, an address twice).
    DataSettingFormat,
    /// G10 without the P or R its form needs, or a P out of the form's range, negative, with a
    /// fraction or (FANUC) written with a decimal point.
    IllegalG10Command,
    /// A tool offset value beyond the valid input range, set by G10 or by a system variable.
    IllegalOffsetValue,
    /// Canned cycle without the Q it needs (G73/G83).
    MissingQ,
    /// A Haas cycle's argument missing or out of its range: G12/G13 circular pocket (I, K, Q,
    /// L against the tool radius), G70–G72 bolt patterns (I, J, K, L), G103 P.
    CycleArgument,
    /// A canned cycle block that drills while no hole bottom (the drilling axis's word) was
    /// given since the cycle started: the manuals at hand do not say what depth the control
    /// takes (fivex's own code).
    CycleBottomMissing,
    /// A cutting block in G95 while the spindle stands (M05, or S0): the feed follows the
    /// spindle's turning, so the control waits for it without end (fivex's own code).
    FeedPerRevolutionSpindleStopped,
    /// Reference return commands not allowed in a canned cycle.
    ReferenceReturnInCycle,
    IllegalReferenceReturn,
    /// G27: an axis it names does not stand at the reference position after its move (raised
    /// after the move, `follows_motion`).
    ReferenceReturnCheck,
    /// A G code that is not allowed in the current 5-axis mode (FANUC PS5460 family).
    IllegalCommandInMode,
    // --- 5-axis mode interlocks (`interp::modes`) ------------------------------------------
    /// A G code or modal state not allowed with tool centre point control (G43.4/G43.5).
    IllegalCommandInTcp,
    /// A rotary axis word in tool centre point control type 2 (G43.5).
    RotaryCommandInTcpType2,
    /// I = J = K = 0 as the tool vector of a G43.5 block.
    ZeroToolVector,
    /// Incremental programming (G91) with G43.5.
    IncrementalInTcpType2,
    /// G53 in tool centre point control (or polar coordinate interpolation).
    MachineCoordinatesInTcp,
    /// G05 P10000 (high-speed machining) in tool centre point control.
    HpccInTcp,
    /// An axis outside the 5-axis set commanded in tool centre point control.
    AxisNotInTcp,
    /// Syntec's G05 in a form the manual calls a format error: P other than 10000 or 0, E not
    /// positive, the axis form of HPCC wrong (`interp::smoothing`).
    HpccFormat,
    /// The machine cannot do the 5-axis function (too few rotary axes).
    MachineParameter,
    /// No rotary axis solution for a tool direction fits the movement ranges.
    NoRotarySolution,
    /// A 5-axis move takes the first (master) / second (slave) rotary axis out of its range
    /// (Syntec Pr3009–3012).
    MasterOutOfRange,
    SlaveOutOfRange,
    /// Tool centre point control with machine settings it cannot work with (FANUC: rapids not
    /// of the linear type).
    TcpParameter,
    /// Cutting point control (FANUC G43.8/G43.9) cannot place the tool: `,L2 I0 J0 K0`, a
    /// block whose surface normals are opposite, a corner radius beyond the tool radius, or a
    /// rotary axis of the tool moved by hand (FANUC PS5464).
    CuttingPoint,
    /// Tool posture control on a circle would turn the tool to the other side of the plane
    /// (FANUC M-8).
    PostureCrossesPlane,
    // --- NURBS interpolation (G06.2, `crate::nurbs`) ----------------------------------------
    /// The rank, knots or weights of a NURBS curve break its rules (rank not 2–4, knots
    /// decreasing, a wrong number or run of equal knots, a missing knot, a weight not above
    /// zero), the curve is left before its last knot, or it needs too many chords.
    NurbsFormat,
    /// A block inside a NURBS curve that is neither a control point nor a knot, or a NURBS
    /// block after the curve ended without a new G06.2.
    NurbsBlock,
    /// The first control point of a NURBS curve is not the current position.
    NurbsStart,
    // --- Machine configuration (`crate::kin`, `crate::vendor`) -----------------------------
    /// Rotary axis settings that do not make a mechanism: missing or parallel axes, an axis
    /// name that does not match its direction.
    AxisSetting,
    /// The tool direction setting does not work with the rotary axes (the axis next to the tool
    /// on the head, or the table master, parallel to it).
    ToolDirectionSetting,
    /// The head axis of a mixed machine parallel to the tool direction.
    ToolAxisParallel,
    /// A 5-axis mechanism set on a path that cannot have one.
    MechanismConflict,
    /// G20/G21 in a mode that freezes the units.
    UnitChangeInMode,
    /// A circular command in the start-up or cancel block of cutter compensation.
    ArcInCompStartCancel,
    /// Cutter compensation C: a compensated block would run against its programmed direction
    /// (the interference check: a gouge).
    CutterInterference,
    /// Cutter compensation C: the offset paths of two blocks do not meet at their corner.
    CutterNoSolution,
    /// A move command in a G39 (corner circular interpolation) block.
    CornerArcWithMove,
    /// 5-axis cutter compensation in the table coordinate system (FANUC TBP = 1, WKP = 0)
    /// started while a setting it needs is missing (linear-type rapids, look-ahead for rapids
    /// and cutting feed).
    CrcTableParameter,
    /// Leading edge offset (G41.3): the block after G41.3 moves along the tool (θ between the
    /// tool and the move counts as 0° or 180°), so no offset plane is defined.
    LeadingEdgeAlongTool,
    /// A malformed tilted working plane command (G68.2/G68.3/G68.4).
    TwpFormat,
    /// A G code or modal state not allowed with the tilted working plane.
    TwpIllegalCommand,
    /// G53.1 in workpiece setting error compensation without tool direction compensation.
    AlignmentInWse,
    /// A malformed G54.4, or a G code not allowed in its mode.
    WseCommand,
    /// G54.4 in a modal state that does not allow it.
    WseModalState,
    /// G54.4 on a machine without the basic axes X, Y and Z.
    WseBasicAxes,
    /// Tool direction compensation of G54.4 cannot start (no rotary solution in the start block,
    /// or a setting it needs is missing).
    WseToolDirection,
    /// Tool direction compensation of G54.4 asks for a posture the machine cannot reach.
    WseUnreachable,
    /// P of a tool alignment (G53.1/G53.3/G53.6) outside 0, 1, 2.
    AlignmentP,
    /// G53.6 while cutter compensation is on.
    AlignmentInCompensation,
    /// G53.6 with tool number 0.
    AlignmentToolZero,
    /// G10 L5000 with a Q other than an integer 0..4.
    ChainQ,
    /// G10 L5000 while a 5-axis function is on.
    ChainSwitchInMode,
    /// G10 L5000 selects a mechanism chain (set or sub-chain) the machine does not have, or
    /// whose mechanism does not work.
    ChainNotConfigured,
    /// G10 L5000 with Q selects a set that is not of the spindle type.
    ChainNotSpindle,
    /// With a sub-chain 2–4 in use, a 5-axis command other than the few it supports.
    ChainCommand,
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
    /// Syntec: POW with a negative base, which FANUC takes with a whole exponent (the Syntec
    /// MACRO handbook's §9.2/§9.14: "`POW` 的基底不可为负值，否则触发 `COR-122`").
    NegativePowerBase,
    /// Syntec: a non-zero number without a decimal point, or a Long value, at an address read as
    /// a length or an angle, whose unit Syntec's Pr3241 (and Pr17) decide and fivex does not
    /// model (`docs/dialects.md`, "A number without a decimal point (Syntec)").
    UnitNotDecided,
    /// A result that is not a finite number.
    FloatOverflow,
    /// DO without its END.
    MissingEnd,
    /// A loop number other than 1, 2, 3, crossing ranges, or a jump into a loop.
    IllegalLoopNumber,
    /// GOTO to a sequence number that does not exist.
    IllegalSequenceNumber,
    /// A called program (M98/G65/G66) that does not exist.
    ProgramNotFound,
    /// A sequence number that a call or return names does not exist: M99 P, Haas M97 P.
    LineNotFound,
    /// A call (M98, G65, G66, Haas M97) without the P that names the program or line: an error
    /// of the block, where `ProgramNotFound` may be a program the file does not hold (Haas 313;
    /// FANUC and Syntec give both their not-found code).
    MissingP,
    /// Too many nested subprogram or macro calls.
    NestingTooDeep,
    /// FANUC: the text of a called program (M98, G65, G66) ended without M99, or that of the
    /// main program in memory operation without M02/M30 (an MDI program may end there): the
    /// control reads the end of record there and stops; fivex returned to the caller and ran
    /// on, or counted the run as completed.
    EndOfRecord,
    /// G used as a G65 argument.
    GAsArgument,
    /// A macro statement and an NC statement in one block.
    MixedStatements,
    /// `#3000 = n (MSG)`: the program's own alarm.
    MacroAlarm {
        number: u32,
        message: String,
    },
    /// G51 with a magnification of zero, or a negative common one.
    IllegalScaleRate,
    /// A circle outside the plane of the active coordinate rotation (G68), or another plane
    /// selected while it is on.
    IllegalPlaneInRotation,
    /// G68's angle R beyond ±360° (FANUC's range of the angle, No.5410's; its alarm for a
    /// larger R is not known: fivex's own code).
    RotationAngleOutOfRange,
    /// A mirror image, scaling or rotation started or cancelled out of FANUC's nesting order
    /// (mirror image → scaling → rotation, cancelled in reverse): fivex applies them in that
    /// order whatever the commands' order, and no manual says what the control does (fivex's
    /// own code).
    TransformOrder,
    /// A reference position return (G27–G30) or a coordinate system change (G52–G59, G92,
    /// another work system) while mirror image, scaling or rotation is on: FANUC's manuals
    /// forbid them there and name no alarm (fivex's own code).
    ReturnOrSystemInTransforms,
    // --- motion (`crate::motion`) ----------------------------------------------------------
    /// The block would take `axis` beyond its stored stroke limit: checked before it moves
    /// (`precheck`), or, where that check is not available (G54.4), reached during the move,
    /// which stops there.
    OverTravel {
        axis: char,
        positive: bool,
        precheck: bool,
    },
    // --- fivex's own guards ---------------------------------------------------------------
    /// The block budget was used up: an endless loop or endless recursion.
    BlockBudgetExceeded {
        budget: u64,
    },
    /// The simulated-time budget was used up.
    TimeBudgetExceeded {
        budget_s: f64,
    },
    /// One block expanded into more canonical commands than a block may (a canned cycle with a
    /// tiny peck depth, say): stopped before it exhausts memory.
    BlockOutputExceeded {
        limit: usize,
    },
    /// The emergency stop button was pressed (fivex's own code: FANUC shows it as a status).
    EmergencyStop,
    // --- program restart (`interp/restart.rs`, `controller/restart.rs`) --------------------
    /// The restart block's sequence number (or line) is not reached before the program ends.
    RestartBlockNotFound,
    /// P type without an automatic operation since power-on or the emergency stop.
    RestartPNoRun,
    /// P type after the coordinate system was set or changed since the interruption (G92,
    /// G52, G92.1, another work coordinate system selected).
    RestartPCoordinatesChanged,
    /// P type after the external work offset was changed since the interruption.
    RestartPExternalOffsetChanged,
    /// P type after the work offsets were changed since the interruption.
    RestartPOffsetChanged,
    /// An MDI operation between the restart's search and its cycle start.
    RestartMdi,
    /// The restart block lies in a mode the return cannot enter (fivex's decision).
    RestartInMode,
    /// A current position (#5021…, #5041…) read where a cutter compensation vector may stand
    /// at the current point: the control gives the tool's own position there (its offset
    /// included) and stops reading ahead, which fivex does not model (`interp::vars`).
    PositionInCompensation,
    /// A tool tip path (tool centre point control, the tilted working plane) after a manual
    /// intervention with manual absolute off turned a rotary axis: how the control carries
    /// the turn on such a path is not established (`controller::manual`, decision).
    RotaryShiftOnTipPath,
    // --- Haas 5-axis: TCPC G234, DWO G254/G255 (`interp::tcp`, `interp::dwo`) ---------------
    /// G234 with no tool length offset H given or in force.
    TcpcNoToolLength,
    /// A rotary axis of the mechanism commanded while G254 is on (or in its block).
    DwoRotaryMotion,
    /// A cutting move after G254 before X, Y and Z were all commanded.
    DwoXyzNotGiven,
    /// G254 with a work offset whose tilt axis value is not zero.
    DwoWorkOffsetTilt,
    /// G254 while G234 is on, or G234 while G254 is on.
    DwoWithTcpc,
    // --- Skip (`interp::skip`) ----------------------------------------------------------------
    /// G31 while cutter compensation is on.
    SkipInCutterComp,
    /// Haas M78: the last skip move touched.
    SkipSignalFound,
    /// Haas M79: the last skip move did not touch.
    SkipSignalNotFound,
    // --- Chamfering and corner R (`interp::chamfer`) -----------------------------------------
    /// The block after a `,C`/`,R` block is not a G01/G02/G03 move in the selected plane (or
    /// there is none).
    CornerNextBlock,
    /// The block after a `,C`/`,R` block is a rapid (G00) move.
    CornerNotG01,
    /// An element of a `,C`/`,R` corner is shorter than the chamfer or the arc's tangent length,
    /// no circle of the radius fits the corner, or the block does not move.
    CornerTooShort,
    // --- Haas G187 corner rounding (`interp::corner_blend`) ------------------------------------
    /// G187 rounds corners (a maximum corner rounding above 0) in a mode whose path the rounding
    /// is not built for: TCP, a tilted working plane or DWO, G54.4, cutter compensation,
    /// smoothing.
    CornerRoundingInMode,
    // --- Haas tool length compensation (`interp::nc`) ------------------------------------------
    /// Haas: G43/G44 in force after a block that selects it with no tool length offset H given
    /// in it or in force (none since power-on or a reset, or H0): the length would be 0.
    LengthCompWithoutH,
}

impl AlarmId {
    /// An alarm of the program's own form or geometry, which any machine running it in its
    /// dialect raises at the same block: no axis, stroke, kinematics, parameter, position or
    /// workpiece decides it. `fivex check` without a machine reports these from its run on the
    /// default machine; every other alarm there may be only that machine's.
    pub fn is_the_programs(&self) -> bool {
        use AlarmId::*;
        matches!(
            self,
            Syntax
                | NoDataAfterAddress
                | IllegalDecimalPoint
                | TooManyDigits
                | IllegalGCodeCombination
                | FeedZero
                | IllegalOffsetNumber
                | ArcRadiusTolerance
                | ArcCentreMissing
                | PlaneChangeInCompensation
                | DataSettingFormat
                | IllegalG10Command
                | MissingQ
                | CycleArgument
                | CycleBottomMissing
                | FeedPerRevolutionSpindleStopped
                | ReferenceReturnInCycle
                | NurbsFormat
                | NurbsBlock
                | NurbsStart
                | UnitChangeInMode
                | ArcInCompStartCancel
                | CornerArcWithMove
                | MacroFormat
                | BracketNesting
                | UnitNotDecided
                | MissingEnd
                | IllegalLoopNumber
                | IllegalSequenceNumber
                | MissingP
                | NestingTooDeep
                | EndOfRecord
                | GAsArgument
                | MixedStatements
                | IllegalScaleRate
                | IllegalPlaneInRotation
                | RotationAngleOutOfRange
                | TransformOrder
                | ReturnOrSystemInTransforms
        )
    }

    /// An alarm about what the block's own move found (Haas M78/M79 after a G31 in the same
    /// block, G27's check): the move is made, then the alarm is raised. Every other alarm of a
    /// block comes before any of its motion (`Interpreter::step`).
    pub fn follows_motion(&self) -> bool {
        matches!(self, AlarmId::SkipSignalFound | AlarmId::SkipSignalNotFound | AlarmId::ReferenceReturnCheck)
    }
}

/// An alarm as a user sees it: the dialect's code and message, where it happened.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Alarm {
    pub code: String,
    pub message: String,
    /// 1-based line in the program file.
    pub line: u32,
    /// Sequence number of the block, if it has one.
    pub n: Option<u32>,
}
