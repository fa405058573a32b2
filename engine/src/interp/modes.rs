//! Mode interlocks of the 5-axis functions: which G codes and words a block may give in each
//! mode — 5-axis cutter compensation (group 07), tool centre point control (group 08), tilted
//! working plane (group 16), workpiece setting error compensation (G54.4) — in FANUC's and in
//! Syntec's rules. Geometry (frames, tool vectors, rotary solutions) is not checked here.
//!
//! [`check`] runs on every NC block after its words are evaluated and before any of its G codes
//! is applied, so a forbidden block changes nothing. It sees the modes before the block and the
//! modes the block's G codes would leave, and returns the bookkeeping that the modal groups do not
//! hold ([`FiveAxisModes`]: nesting order, definition sequences), which the caller stores.
//!
//! The rules are one table, [`RULES`], tried in order; the first that holds gives the alarm. Each
//! row names the rule it implements (`crc` cutter compensation, `tcp` tool centre point control,
//! `twp` tilted plane / G54.4 / manual, `syn` Syntec, `haas` the Haas NGC manual's G234/G254
//! pages; `docs/references.md`) and the
//! dialect it belongs to: a rule one vendor states and the other does not is not applied to the
//! other. Decisions where the extracts leave a choice are in `docs/conventions.md` ("Mode
//! interlocks"). Order: block formats, then rules naming one combination, then the lists of G
//! codes allowed in a mode, then the lists of modal states a mode may start in.

use super::gcode::code::*;
use super::gcode::{self, group, GROUPS};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::dialect::Dialect;
use crate::machine::{AxisKind, MachineConfig};

/// What the modal groups do not hold about the 5-axis modes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(super) struct FiveAxisModes {
    /// The set of the active G54.4 (1–7); 0 = workpiece setting error compensation off.
    wse: u8,
    /// Tool centre point control was started inside 5-axis cutter compensation (it must end
    /// first), or the other way round.
    tcp_inside_crc: bool,
    crc_inside_tcp: bool,
    /// The last block was G41.3: this one must move.
    g41_3_move_due: bool,
    /// The last block started G41.2/G42.2 perpendicular to the next movement (No.5003#1 SUV,
    /// type C): this one must move by G00–G03.
    suv_move_due: bool,
    /// A G68.2 P2/P3 definition in progress: 20 = P2 after Q0, 21/22 = P2 after Q1/Q2,
    /// 31 = P3 after Q1; 0 = none.
    twp_seq: u8,
    /// Syntec: a tool alignment (G53.1/G53.3/G53.6) was done in the tilted plane.
    aligned: bool,
    /// Syntec STCP (`G43.4 … L1`).
    stcp: bool,
    /// FANUC tool posture control (`G43.4/G43.5 … P1`).
    posture: bool,
    /// FANUC 5-axis nano smoothing (G05.1 Q3) started inside tool centre point control.
    nano_in_tcp: bool,
}

impl FiveAxisModes {
    /// The tilted working plane was cancelled outside a block (reset): no definition sequence
    /// or alignment is pending.
    pub(super) fn plane_ended(&mut self) {
        self.twp_seq = 0;
        self.aligned = false;
    }

    /// A reset put group 07 back to G40 (CRC-44): no nesting with TCP, no G41.3 move due.
    pub(super) fn compensation_ended(&mut self) {
        self.tcp_inside_crc = false;
        self.crc_inside_tcp = false;
        self.g41_3_move_due = false;
        self.suv_move_due = false;
    }

    /// A reset ended G54.4 (WSE-21).
    pub(super) fn clear_wse(&mut self) {
        self.wse = 0;
    }

    /// Syntec STCP is on.
    pub(super) fn stcp_on(&self) -> bool {
        self.stcp
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum On {
    Both,
    Fanuc,
    Syntec,
    Haas,
}

struct Rule {
    on: On,
    /// The spec row, for the reader (and the failure message of a rule's test).
    #[cfg_attr(not(test), allow(dead_code))]
    src: &'static str,
    when: fn(&Ctx) -> bool,
    alarm: AlarmId,
}

const fn rule(on: On, src: &'static str, alarm: AlarmId, when: fn(&Ctx) -> bool) -> Rule {
    Rule { on, src, when, alarm }
}

use AlarmId as A;
use On::{Both, Fanuc, Haas, Syntec};

/// The rules, tried in order.
static RULES: &[Rule] = &[
    // --- block formats -----------------------------------------------------------------------
    rule(Fanuc, "twp WSE-01: G54.4 needs P0..P7", A::WseCommand, |c| {
        c.has(G54_4) && !c.word(b'P').is_some_and(|p| int_in(p, 0, 7))
    }),
    rule(Fanuc, "twp WSE-01: G54.4 alone (no other G code, no axis word)", A::WseCommand, |c| {
        c.has(G54_4) && (c.g.len() > 1 || c.any_axis())
    }),
    rule(Fanuc, "twp WSE-01: no G54.4 Pn (n≠0) while G54.4 is on", A::WseCommand, |c| {
        c.has(G54_4) && c.five.wse != 0 && c.word(b'P') != Some(0.0)
    }),
    rule(Fanuc, "twp WSE-26, §6.6: G54.4 P0 only after the modes nested inside it ended", A::WseCommand, |c| {
        c.has(G54_4) && c.five.wse != 0 && c.word(b'P') == Some(0.0) && c.wse_nests_a_mode()
    }),
    rule(Fanuc, "twp TWP-02: G68.2/G68.4 P1 Q in {123,132,213,321,231,312}", A::TwpFormat, |c| {
        c.twp_def() == Some(1) && c.word(b'Q').is_some_and(|q| ![123.0, 132.0, 213.0, 321.0, 231.0, 312.0].contains(&q))
    }),
    rule(Fanuc, "twp TWP-03: G68.2/G68.4 P2 needs Q0..Q3", A::TwpFormat, |c| {
        c.twp_def() == Some(2) && !c.word(b'Q').is_some_and(|q| int_in(q, 0, 3))
    }),
    rule(Fanuc, "twp TWP-04: G68.2/G68.4 P3 needs Q1/Q2", A::TwpFormat, |c| {
        c.twp_def() == Some(3) && !c.word(b'Q').is_some_and(|q| int_in(q, 1, 2))
    }),
    rule(Fanuc, "twp TWP-01..05: G68.2/G68.4 P is 0..4", A::TwpFormat, |c| c.twp_def().is_some_and(|p| p > 4)),
    rule(Fanuc, "twp TWP-03/04: P2 (Q1,Q2,Q3) and P3 (Q1,Q2) blocks consecutive", A::TwpFormat, |c| {
        twp_sequence(c).is_err()
    }),
    rule(Both, "twp TWP-06, syn SYN-23: G68.3 X Y Z all or none", A::TwpFormat, |c| {
        c.has(G68_3) && !matches!(c.count_letters(b"XYZ"), 0 | 3)
    }),
    rule(Syntec, "syn SYN-24: G68.3 P is 1", A::TwpFormat, |c| c.has(G68_3) && c.word(b'P').is_some_and(|p| p != 1.0)),
    rule(Syntec, "syn SYN-24, TV-24, COR-154: no G53.1/G68.3 with Pr3001 = 0", A::MachineParameter, |c| {
        c.any(&[G53_1, G68_3]) && c.st.cfg.machine.rotary.is_empty()
    }),
    rule(
        Syntec,
        "syn SYN-18, §4.1.3; SYN-07/08, §2.2.1/§2.3.1/§3.1.1: an address Syntec's G68.2/G43.4/G43.5 does not take",
        A::ImproperAddress,
        |c| c.w.letters().any(|l| syntec_improper_address(c.g, m_call(c.w), l, c.word(l)).is_some()),
    ),
    rule(
        Both,
        "twp TWP-07, syn §4.2.1 (decision): no rotary axis word in a tool alignment block",
        A::ImproperAddress,
        |c| c.any(&ALIGNMENTS) && c.any_rotary(),
    ),
    rule(Syntec, "syn SYN-22: P of G53.1/G53.3/G53.6 is 0, 1 or 2", A::AlignmentP, |c| {
        c.any(&ALIGNMENTS) && c.word(b'P').is_some_and(|p| !int_in(p, 0, 2))
    }),
    rule(Syntec, "syn §3.1, COR-107: G05 P10000 [X0 Y0 Z0 α β] / G05 P0, E positive", A::HpccFormat, |c| {
        c.has(G05) && c.st.g05_form(c.w).is_err()
    }),
    rule(Syntec, "syn SYN-26: G10 L5000 Q is an integer 0..4", A::ChainQ, |c| {
        c.chain_switch() && c.word(b'Q').is_some_and(|q| !int_in(q, 0, 4))
    }),
    rule(Syntec, "syn SYN-26: no G10 L5000 in RTCP or after a tool alignment", A::ChainSwitchInMode, |c| {
        c.chain_switch() && (c.tcp(c.before[group::LENGTH_COMP]) || c.five.aligned && c.twp(c.before[group::ROTATION]))
    }),
    rule(
        Syntec,
        "syn SYN-26, COR-165: with sub-chain Q2..Q4 only G43.4, G43.5, G68.2 + G53.1/G53.6, G68.3",
        A::ChainCommand,
        |c| c.st.cfg.machine.chain().sub >= 2 && c.g.iter().any(|g| chain_limited(*g)),
    ),
    // --- workpiece setting error compensation: combinations -----------------------------
    rule(Fanuc, "twp TWP-07, WSE-11: G53.1 in G54.4 mode needs RCM=1", A::AlignmentInWse, |c| {
        !c.rcm() && c.has(G53_1) && c.wse_during()
    }),
    rule(Fanuc, "twp WSE-11: G43.4/G43.5 in G54.4 mode needs RCM=1", A::IllegalCommandInTcp, |c| {
        !c.rcm() && c.wse_during() && c.starts(group::LENGTH_COMP, |c, m| c.tcp(m))
    }),
    rule(
        Fanuc,
        "twp WSE-25, §6.5, TV-WSE-20: G06.2/G28/G29/G30/G43.1/G53/G95 in G54.4 (RCM=1, table)",
        A::WseModalState,
        |c| c.wse_rcm_table() && c.wse_during() && c.any(&[G06_2, G28, G29, G30, G43_1, G53, G95]),
    ),
    rule(Fanuc, "twp WSE-25, §6.3, TV-WSE-20b: G54.4 Pn in G95 (RCM=1, table)", A::WseModalState, |c| {
        c.wse_rcm_table()
            && c.has(G54_4)
            && c.five.wse == 0
            && c.word(b'P') != Some(0.0)
            && c.before[group::FEED_MODE] == G95
    }),
    rule(
        Fanuc,
        "twp WSE-25, TV-WSE-20c: TCP or G68.2 in G54.4 with the table axes at 0 (RCM=1)",
        A::WseModalState,
        |c| {
            c.wse_rcm_table()
                && c.wse_during()
                && (c.starts(group::LENGTH_COMP, |c, m| c.tcp(m)) || c.any(&TILTED_PLANES))
                && c.table_axes_turned()
        },
    ),
    rule(
        Fanuc,
        "twp WSE-25, TV-WSE-20d: axes outside 5-axis machining in G54.4 (RCM=1, table)",
        A::WseModalState,
        |c| c.wse_rcm_table() && c.wse_during() && c.foreign_axis(),
    ),
    rule(
        Fanuc,
        "twp WSE-11, TV-WSE-19d: G54.4 Pn with RCM=1 needs look-ahead on (G05.1 Q1 / SHP), LRP, FRP, No.1660/1671",
        A::WseToolDirection,
        |c| c.rcm() && c.has(G54_4) && c.five.wse == 0 && c.word(b'P') != Some(0.0) && !c.st.wse_settings_ready(),
    ),
    rule(Fanuc, "twp WSE-11 [A]: look-ahead stays on in G54.4 with RCM=1 (no G05.1 Q0)", A::WseToolDirection, |c| {
        c.rcm() && c.wse_during() && c.has(G05_1) && c.word(b'Q') == Some(0.0)
    }),
    rule(Fanuc, "twp WSE-24, TV-WSE-19e: tool length offset or TCP in G54.4 needs TOS=1", A::WseToolDirection, |c| {
        c.st.cfg.machine.five_axis.length_offset_by_motion && c.wse_during() && c.any(&[G43, G43_1, G44, G43_4, G43_5])
    }),
    // --- 5-axis cutter compensation ----------------------------------------------------
    // SPG (No.19607#1) selects the tool side offset's code set (TV-17). The manual names SPG = 0
    // with G41.4 on a table machine and G41.5 on a mixed one PS0010; fivex extends it to every
    // machine (a decision: without SPG the codes are not selected anywhere).
    rule(Fanuc, "crc CRC-31/32, TV-17: G41.4/G42.4, G41.5/G42.5 with SPG=0", A::ImproperGCode, |c| {
        !c.spg() && c.any(&[G41_4, G42_4, G41_5, G42_5])
    }),
    rule(
        Fanuc,
        "crc CRC-31/32, TV-17: G41.2/G42.2 on a table or mixed machine with SPG=1",
        A::IllegalCommandInMode,
        |c| c.spg() && c.table_or_mixed() && c.any(&[G41_2, G42_2]),
    ),
    rule(
        Fanuc,
        "crc CRC-31, TV-17: G41.4/G42.4 on a machine other than table with SPG=1",
        A::IllegalCommandInMode,
        |c| c.spg() && c.mech() != Mech::Table && c.any(&[G41_4, G42_4]),
    ),
    rule(
        Fanuc,
        "crc CRC-32, TV-17: G41.5/G42.5 on a machine other than mixed with SPG=1",
        A::IllegalCommandInMode,
        |c| c.spg() && c.mech() != Mech::Mixed && c.any(&[G41_5, G42_5]),
    ),
    rule(Fanuc, "crc CRC-02, TV-18: G41.6/G42.6 needs two rotary axes", A::IllegalCommandInMode, |c| {
        c.any(&[G41_6, G42_6]) && c.rotary_axes() < 2
    }),
    rule(
        Fanuc,
        "crc CRC-35/37, §6.3: no G02/G03/G02.2/G03.2 in the start-up or cancel block (table/mixed)",
        A::ArcInCompStartCancel,
        |c| {
            c.table_or_mixed()
                && (c.starts(group::CUTTER_COMP, |c, m| c.crc5(m)) || c.crc_cancels())
                && matches!(c.after[group::MOTION], G02 | G03 | G02_2 | G03_2)
        },
    ),
    rule(
        Fanuc,
        "crc CRC-36, §6.3: only G00/G01 in 5-axis cutter compensation (table/mixed)",
        A::IllegalCommandInMode,
        |c| c.table_or_mixed() && c.crc5(c.after[group::CUTTER_COMP]) && !matches!(c.after[group::MOTION], G00 | G01),
    ),
    rule(Fanuc, "crc CRC-34, §6.3: no leading edge offset G41.3 (table/mixed)", A::IllegalCommandInMode, |c| {
        c.table_or_mixed() && c.has(G41_3)
    }),
    // Only in the G41.6/G42.6 block itself (§3.2.1: "I, J, and K can be specified in a
    // G41.6/G42.6 command block; in a table rotation type machine, however, they cannot"): the
    // blocks after it give the tool direction by I/J/K.
    rule(Fanuc, "crc CRC-33, §3.2.1: no I/J/K in the G41.6/G42.6 block (table)", A::IllegalCommandInMode, |c| {
        c.mech() == Mech::Table && (c.has(G41_6) || c.has(G42_6)) && c.count_letters(b"IJK") > 0
    }),
    rule(
        Fanuc,
        "crc CRC-21, §6.2: G41.3 only in G00/G01 mode, and only G00/G01 in G41.3 mode",
        A::IllegalCommandInMode,
        |c| c.crc5(G41_3) && c.after[group::CUTTER_COMP] == G41_3 && !matches!(c.after[group::MOTION], G00 | G01),
    ),
    rule(Fanuc, "crc CRC-21, §6.2: the G41.3 block and its G40 hold only D, O, N", A::IllegalCommandInMode, |c| {
        let g41_3 = c.crc5(G41_3) && (c.has(G41_3) || c.before[group::CUTTER_COMP] == G41_3 && c.has(G40));
        g41_3 && c.w.letters().any(|l| !matches!(l, b'G' | b'D' | b'N' | b'O'))
    }),
    rule(Fanuc, "crc CRC-21, TV-31: the block after G41.3 moves", A::IllegalCommandInMode, |c| {
        c.five.g41_3_move_due && !c.any_axis()
    }),
    rule(
        Fanuc,
        "crc CRC-48, TV-18: TCP type 1 with CRC type 1 only, type 2 with type 2",
        A::IllegalCommandInMode,
        |c| {
            let (crc, tcp) = (c.after[group::CUTTER_COMP], c.after[group::LENGTH_COMP]);
            c.crc5(crc) && c.tcp(tcp) && (tcp == G43_4 && is_crc_type2(crc) || tcp == G43_5 && is_crc_type1(crc))
        },
    ),
    rule(Fanuc, "crc CRC-48, TV-22: G40 before G49 when TCP started inside CRC", A::IllegalCommandInMode, |c| {
        c.five.tcp_inside_crc && c.crc_cancels() && c.tcp(c.after[group::LENGTH_COMP])
    }),
    rule(Fanuc, "crc CRC-48, TV-22: G49 before G40 when CRC started inside TCP", A::IllegalCommandInMode, |c| {
        c.five.crc_inside_tcp && c.tcp_cancels() && c.crc5(c.after[group::CUTTER_COMP])
    }),
    rule(
        Fanuc,
        "crc CRC-38, TV-20: CRC in the table system (TBP = 1, WKP = 0) needs LRP, FRP, No.1660/1671/1672",
        A::CrcTableParameter,
        |c| {
            let motion = &c.st.cfg.machine.motion;
            c.crc_in_table()
                && c.starts(group::CUTTER_COMP, |c, m| c.crc5(m))
                && (motion.nonlinear_rapid || !motion.look_ahead_set_up())
        },
    ),
    rule(
        Fanuc,
        "crc TV-24, §3.5.3: TCP with CRC on a table/mixed machine in one system (WKP = 1, or TBP = 1)",
        A::IllegalCommandInMode,
        |c| {
            let (crc, tcp) = (c.after[group::CUTTER_COMP], c.after[group::LENGTH_COMP]);
            let together = c.crc5(crc) && c.tcp(tcp);
            let starting =
                c.starts(group::CUTTER_COMP, |c, m| c.crc5(m)) || c.starts(group::LENGTH_COMP, |c, m| c.tcp(m));
            let five = &c.st.cfg.machine.five_axis;
            c.table_or_mixed()
                && together
                && starting
                && five.tcp_coordinates != crate::machine::TcpCoordinates::Workpiece
                && !five.crc_table_coordinates
        },
    ),
    rule(
        Fanuc,
        "crc CRC-49, TV-23: TCP before CRC in the table system, not in one block",
        A::IllegalCommandInMode,
        |c| {
            c.crc_in_table()
                && c.starts(group::CUTTER_COMP, |c, m| c.crc5(m))
                && c.starts(group::LENGTH_COMP, |c, m| c.tcp(m))
        },
    ),
    rule(
        Fanuc,
        "crc CRC-49, TV-25: no table rotary axis word in the G41.2 block (table system, TCP)",
        A::IllegalCommandInMode,
        |c| {
            c.crc_in_table()
                && c.tcp(c.before[group::LENGTH_COMP])
                && c.starts(group::CUTTER_COMP, |c, m| c.crc5(m))
                && c.table_axis_word()
        },
    ),
    rule(
        Fanuc,
        "crc CRC-49, TV-25: the table stands as at the TCP start when CRC starts (table system)",
        A::IllegalCommandInMode,
        |c| {
            c.crc_in_table()
                && c.tcp(c.before[group::LENGTH_COMP])
                && c.starts(group::CUTTER_COMP, |c, m| c.crc5(m))
                && c.st.table_turned_since_tcp_start()
        },
    ),
    rule(Fanuc, "crc CRC-46, TV-29: no G20/G21 in 5-axis cutter compensation", A::UnitChangeInMode, |c| {
        c.during(group::CUTTER_COMP, |c, m| c.crc5(m)) && c.any(&[G20, G21])
    }),
    rule(Fanuc, "crc CRC-02, TV-18: no rotary axis word in G41.6/G42.6", A::IllegalCommandInMode, |c| {
        c.crc5(c.after[group::CUTTER_COMP]) && is_crc_type2(c.after[group::CUTTER_COMP]) && c.any_rotary()
    }),
    // --- tool centre point control -------------------------------------------------------
    rule(Fanuc, "tcp TCP-08, TV-61: G43.5 needs two rotary axes", A::MachineParameter, |c| {
        c.any(&TCP_TYPE2) && c.rotary_axes() < 2
    }),
    rule(Fanuc, "tcp TCP-08, TV-58: no I/J/K in the G43.5 block (table/mixed)", A::IllegalCommandInTcp, |c| {
        c.table_or_mixed() && c.any(&TCP_TYPE2) && c.count_letters(b"IJK") > 0
    }),
    rule(
        Both,
        "tcp TCP-09/20, TV-62; syn SYN-08, TV-15: no rotary axis word in G43.5",
        A::RotaryCommandInTcpType2,
        |c| c.tcp(c.after[group::LENGTH_COMP]) && TCP_TYPE2.contains(&c.after[group::LENGTH_COMP]) && c.any_rotary(),
    ),
    rule(Syntec, "syn SYN-08, TV-12: I=J=K=0 in G43.5", A::ZeroToolVector, |c| {
        c.tcp(c.after[group::LENGTH_COMP]) && c.after[group::LENGTH_COMP] == G43_5 && {
            let ijk = [c.word(b'I'), c.word(b'J'), c.word(b'K')];
            ijk.iter().any(Option::is_some) && ijk.iter().all(|v| v.unwrap_or(0.0) == 0.0)
        }
    }),
    rule(Syntec, "syn SYN-08, TV-14: no G91 with G43.5 (either order)", A::IncrementalInTcpType2, |c| {
        c.tcp(c.after[group::LENGTH_COMP]) && c.after[group::LENGTH_COMP] == G43_5 && c.after[group::DISTANCE] == G91
    }),
    rule(Syntec, "syn SYN-07/33, TV-17: no G53 in G43.4/G43.5 or G12.1", A::MachineCoordinatesInTcp, |c| {
        c.has(G53)
            && (c.during(group::LENGTH_COMP, |c, m| c.tcp(m))
                || c.during(group::POLAR_INTERPOLATION, |_, m| m == G12_1))
    }),
    // The manual names no alarm, only "abnormal motion": fivex cannot know that motion, so it
    // refuses the block rather than run a return the control does not make; "G49 before" is
    // taken as a block before, so the G49 block itself is refused too (decisions,
    // `docs/five-axis.md`, Q-34).
    rule(Syntec, "syn SYN-07/08, §2.2.2 #4, §2.3.2 #5: G49 before G28/G29/G30", A::IllegalCommandInTcp, |c| {
        c.any(&[G28, G29, G30]) && (c.tcp(c.before[group::LENGTH_COMP]) || c.tcp(c.after[group::LENGTH_COMP]))
    }),
    rule(Syntec, "syn SYN-07/08/09, TV-16: no G05 P10000 in RTCP/STCP", A::HpccInTcp, |c| {
        c.has(G05) && c.word(b'P') == Some(10000.0) && c.during(group::LENGTH_COMP, |c, m| c.tcp(m))
    }),
    rule(
        Syntec,
        "syn SYN-07/08/09, TV-16 (decision: the other order): no RTCP/STCP started in HPCC",
        A::HpccInTcp,
        |c| {
            c.st.hpcc_on()
                && c.starts(group::LENGTH_COMP, |c, m| c.tcp(m))
                && !(c.has(G05) && c.word(b'P') == Some(0.0))
        },
    ),
    rule(Syntec, "syn SYN-09, TV-25: STCP moves only the five RTCP axes", A::AxisNotInTcp, |c| {
        c.five.stcp && c.during(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.other_axes() > 0
    }),
    rule(Fanuc, "tcp TCP-05, TV-57: at most 2 axes outside the 5-axis set in TCP", A::AxisNotInTcp, |c| {
        c.during(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.other_axes() > 2
    }),
    rule(
        Fanuc,
        "tcp TCP-05, Q-20: the 31i-A5 commands at most 5 axes in a block in TCP",
        A::IllegalCommandInTcp,
        |c| c.st.cfg.five_axes_per_block && c.during(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.axis_count() > 5,
    ),
    rule(Syntec, "syn SYN-07/23/33: no G68.3 in RTCP", A::IllegalCommandInMode, |c| {
        c.has(G68_3) && c.during(group::LENGTH_COMP, |c, m| c.tcp(m))
    }),
    rule(Syntec, "syn SYN-07/08: RTCP not with G41/G42", A::IllegalCommandInMode, |c| {
        c.during(group::LENGTH_COMP, |c, m| c.tcp(m)) && matches!(c.after[group::CUTTER_COMP], G41 | G42)
    }),
    rule(Syntec, "syn SYN-07/08: RTCP not with G43/G44 or the other RTCP type", A::IllegalCommandInMode, |c| {
        c.any(&TCP)
            && c.tcp(c.after[group::LENGTH_COMP])
            && !LENGTH_CANCEL.contains(&c.before[group::LENGTH_COMP])
            && c.before[group::LENGTH_COMP] != c.after[group::LENGTH_COMP]
    }),
    rule(Syntec, "syn SYN-07/08: no G43/G44 in RTCP (not ended by it)", A::IllegalCommandInMode, |c| {
        c.any(&[G43, G44]) && c.tcp(c.before[group::LENGTH_COMP])
    }),
    rule(Fanuc, "tcp TCP-17, §2.2.6: G49 in G00/G01 mode", A::IllegalCommandInTcp, |c| {
        c.tcp_cancels() && !matches!(c.after[group::MOTION], G00 | G01)
    }),
    rule(Fanuc, "crc NSM-05, TV-38: G05.1 Q3 not with G43.5 or tool posture control", A::IllegalCommandInTcp, |c| {
        c.has(G05_1)
            && c.word(b'Q') == Some(3.0)
            && c.during(group::LENGTH_COMP, |c, m| c.tcp(m))
            && (c.after[group::LENGTH_COMP] != G43_4 || c.posture())
    }),
    rule(Fanuc, "crc NRB-04: G06.2 not with G43.5 or tool posture control", A::IllegalCommandInTcp, |c| {
        c.after[group::MOTION] == G06_2
            && c.during(group::LENGTH_COMP, |c, m| c.tcp(m))
            && (c.after[group::LENGTH_COMP] != G43_4 || c.posture())
    }),
    rule(Fanuc, "crc §6.7, OQ-29: G05.1 Q0 before G49", A::IllegalCommandInTcp, |c| {
        c.five.nano_in_tcp && c.tcp_cancels() && !(c.has(G05_1) && c.word(b'Q') == Some(0.0))
    }),
    rule(Fanuc, "tcp TCP-10/M-4: G02/G03 in G43.5 by R", A::IllegalCommandInTcp, |c| {
        c.tcp(c.after[group::LENGTH_COMP])
            && c.after[group::LENGTH_COMP] == G43_5
            && c.arc()
            && c.any_axis()
            && c.word(b'R').is_none()
    }),
    rule(Fanuc, "tcp TCP-06/07/10: rotary-only moves in G00/G01 in TCP", A::IllegalCommandInTcp, |c| {
        c.during(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.arc() && c.any_rotary() && !c.any_linear()
    }),
    rule(Fanuc, "tcp TCP-41: cutting point control in G00/G01 only", A::IllegalCommandInTcp, |c| {
        c.tcp(c.after[group::LENGTH_COMP])
            && matches!(c.after[group::LENGTH_COMP], G43_8 | G43_9)
            && !matches!(c.after[group::MOTION], G00 | G01)
    }),
    // --- tilted working plane --------------------------------------------------------------
    // FANUC §1.3.1: the plane starts only from the modal states listed, and G68 is not among them
    // (TWP-11; the extract's "modes not in either list ⇒ PS5462"). fivex does not compose a coordinate rotation with the FCS, so the Syntec
    // dialect, whose manual says nothing of G68 there, refuses it too (*decision*).
    rule(Both, "twp TWP-11, §1.3.1: no G68.2/G68.3 while G68 rotation is on", A::TwpIllegalCommand, |c| {
        c.any(&TILTED_PLANES) && c.before[group::ROTATION] == G68
    }),
    rule(
        Fanuc,
        "twp TWP-14, TV-TWP-27, OQ-17: the tilted plane needs linear rapids (LRP = 1)",
        A::TwpIllegalCommand,
        |c| c.starts(group::ROTATION, |c, m| c.twp(m)) && c.st.cfg.machine.motion.nonlinear_rapid,
    ),
    rule(
        Both,
        "twp TWP-16, TV-TWP-21; syn SYN-18: tool length compensation off at G68.2/G68.3",
        A::TwpIllegalCommand,
        |c| c.any(&TILTED_PLANES) && !LENGTH_CANCEL.contains(&c.after[group::LENGTH_COMP]),
    ),
    rule(
        Both,
        "twp TWP-16, §1.3.2: a canned cycle ends (G80) inside the plane, before G69",
        A::TwpIllegalCommand,
        |c| c.has(G69) && c.twp(c.before[group::ROTATION]) && c.after[group::CYCLE] != G80,
    ),
    // FANUC §1.4 "Relationships with other modal commands" (TWP-16): cutter compensation, tool
    // length compensation and the mirror image are off before G69, as the cycle above. G43/G44
    // must end in a block before the G69 (*decision*): in one block fivex would end the plane
    // first and cancel the length along the machine Z instead of along the tilted tool, and the
    // manual gives no order within a block. Syntec's manual ends with `G69 G49` (§4.6.5): FANUC only.
    rule(Fanuc, "twp TWP-16, §1.4: G41/G42, G43/G44 and G51.1 off before G69", A::TwpIllegalCommand, |c| {
        c.has(G69)
            && c.twp(c.before[group::ROTATION])
            && (!LENGTH_CANCEL.contains(&c.before[group::LENGTH_COMP])
                || !LENGTH_CANCEL.contains(&c.after[group::LENGTH_COMP])
                || c.after[group::CUTTER_COMP] != G40
                || c.after[group::MIRROR] != G50_1)
    }),
    // Syntec names no nesting rule; a cycle spanning the plane's start would read its levels,
    // taken in the workpiece system, in the FCS (*decision*, docs/five-axis.md). FANUC's row is
    // the §6.1 list below.
    rule(Syntec, "twp TWP-16 (decision, Syntec): no canned cycle on at G68.2/G68.3", A::TwpIllegalCommand, |c| {
        c.starts(group::ROTATION, |c, m| c.twp(m)) && c.after[group::CYCLE] != G80
    }),
    rule(Syntec, "syn SYN-21, TV-20: G53.6 in G40 mode", A::AlignmentInCompensation, |c| {
        c.has(G53_6) && c.after[group::CUTTER_COMP] != G40
    }),
    rule(Syntec, "syn SYN-21, TV-19: G53.6 needs a tool (H, or the last H) other than 0", A::AlignmentToolZero, |c| {
        c.has(G53_6) && c.word(b'H').map_or(c.st.h == 0, |h| h == 0.0)
    }),
    // Syntec §4.2.3/§4.3.3/§4.4.3 #1 "can't be executed before G68.2" (no alarm named); FANUC's
    // G53.1 aligns to the FCS "after G68.2" (TWP-07) and names no alarm either. Without a plane
    // there is nothing to align to: the block would do nothing (G53.3 not even its move and
    // tool length), so it is refused (*decision*: PS5462 / COR-100, the mode interlocks' alarms).
    rule(
        Both,
        "twp TWP-07; syn SYN-19/20/21, §4.2.3 #1: a tool alignment only in the tilted plane",
        A::TwpIllegalCommand,
        |c| c.any(&ALIGNMENTS) && !c.twp(c.after[group::ROTATION]),
    ),
    // --- lists of G codes allowed in a mode (the mode before the block, or started by it) -------
    rule(Fanuc, "twp §6.4: G codes allowed in G54.4 mode", A::WseCommand, |c| {
        c.wse_during()
            && c.g.iter().any(|&g| !wse_allows(g) || g == G05_1 && !c.word(b'Q').is_some_and(|q| q == 0.0 || q == 1.0))
    }),
    rule(Fanuc, "twp TWP-12, §6.2: G codes allowed in the tilted working plane", A::TwpIllegalCommand, |c| {
        c.foreign(
            group::ROTATION,
            |c, m| c.twp(m),
            |c, g| {
                twp_allows(g)
                    || matches!(g, G68_2 | G68_4) && (c.st.cfg.machine.five_axis.multiple_planes || c.five.twp_seq != 0)
            },
        )
    }),
    // --- start-up and cancel perpendicular to the next movement (No.5003#1 SUV; the 16i's type C)
    // The 30i's NOTE (5-axis manual §3.1.1) and the 16i's (A-78438E p.7): "the following
    // conditions must always be satisfied". Neither names the alarm: fivex gives PS5460 of the
    // same family (`docs/cutter-compensation.md`, 3-D rule 2 and "16i variant" 4).
    rule(
        Fanuc,
        "crc CRC-08, TV-32: type C — the G41.2/G42.2/G40 block in G00/G01, without a move command",
        A::IllegalCommandInMode,
        |c| {
            let starts_or_cancels = c.starts(group::CUTTER_COMP, |c, m| c.crc5(m) && is_crc_type1(m))
                || c.crc5(c.before[group::CUTTER_COMP])
                    && is_crc_type1(c.before[group::CUTTER_COMP])
                    && c.after[group::CUTTER_COMP] == G40;
            c.st.cfg.machine.motion.cutter_startup_perpendicular
                && starts_or_cancels
                && (!matches!(c.after[group::MOTION], G00 | G01) || c.any_axis())
        },
    ),
    rule(
        Fanuc,
        "crc CRC-08, TV-32: type C — the block after G41.2/G42.2 moves by G00, G01, G02 or G03",
        A::IllegalCommandInMode,
        |c| c.five.suv_move_due && !(c.any_axis() && matches!(c.after[group::MOTION], G00 | G01 | G02 | G03)),
    ),
    // --- the 16i variant of 3-D cutter compensation (`five_axis.crc_variant`, A-78438E) ------
    // The 16i names no alarm number for these ("the alarm is issued"): fivex gives the 30i's
    // PS5460 of the same family (a decision, `docs/cutter-compensation.md`, "16i variant").
    rule(
        Fanuc,
        "crc 16i A-78438E §1.1: G41.6/G42.6, G41.4/G42.4, G41.5/G42.5 are not 16i codes",
        A::ImproperGCode,
        |c| c.crc16i() && c.any(&[G41_6, G42_6, G41_4, G42_4, G41_5, G42_5]),
    ),
    rule(
        Fanuc,
        "crc 16i A-78438E p.27-28: dwell, G05, NURBS, in-feed control, M/S/T with a move in the mode",
        A::IllegalCommandInMode,
        |c| {
            let mst_with_move = c.any_axis() && c.count_letters(b"MST") > 0;
            c.crc16i()
                && c.during(group::CUTTER_COMP, |c, m| c.crc5(m))
                && (c.any(&[G04, G05, G06_2, G160, G161_CODE]) || c.after[group::MOTION] == G06_2 || mst_with_move)
        },
    ),
    rule(
        Fanuc,
        "crc §6.1, CRC-47, TV-34: G codes forbidden in 5-axis cutter compensation",
        A::IllegalCommandInMode,
        |c| c.foreign(group::CUTTER_COMP, |c, m| c.crc5(m), |_, g| !crc5_forbids(g)),
    ),
    rule(
        Fanuc,
        "crc CRC-50, §3.5.3: G codes allowed in 5-axis cutter compensation in the table coordinate system",
        A::IllegalCommandInMode,
        |c| c.crc_in_table() && c.foreign(group::CUTTER_COMP, |c, m| c.crc5(m), |_, g| table_crc_allows(g)),
    ),
    rule(
        Fanuc,
        "crc CRC-51, §3.5.3: modal states 5-axis cutter compensation may start in (table coordinate system)",
        A::IllegalCommandInTcp,
        |c| {
            c.crc_in_table()
                && c.starts(group::CUTTER_COMP, |c, m| c.crc5(m))
                && c.state_outside(group::CUTTER_COMP, table_crc_state_allows)
        },
    ),
    rule(
        Fanuc,
        "crc §3.5.3: no axis outside the 5-axis set in 5-axis cutter compensation (table coordinate system)",
        A::IllegalCommandInMode,
        |c| c.crc_in_table() && c.during(group::CUTTER_COMP, |c, m| c.crc5(m)) && c.other_axes() > 0,
    ),
    rule(Fanuc, "tcp TCP-16; crc CRC-48, NSM-05, NRB-03: G codes allowed in TCP", A::IllegalCommandInTcp, |c| {
        c.foreign(
            group::LENGTH_COMP,
            |c, m| c.tcp(m),
            |c, g| tcp_allows(g) || matches!(g, G05_1 | G06_2) && c.after[group::LENGTH_COMP] == G43_4 && !c.posture(),
        )
    }),
    // --- Haas DWO (G254) and TCPC (G234): the manual's rules (`docs/dialects.md`) ----------
    rule(Haas, "haas G254: no rotary motion while DWO is on, nor in its block", A::DwoRotaryMotion, |c| {
        c.during(group::DYNAMIC_FIXTURE, |_, m| m == G254) && c.any_rotary()
    }),
    rule(Haas, "haas G254/G234: DWO and TCPC exclude each other", A::DwoWithTcpc, |c| {
        c.during(group::DYNAMIC_FIXTURE, |_, m| m == G254) && c.during(group::LENGTH_COMP, |_, m| m == G234)
    }),
    rule(Haas, "haas G254: not with a tilted working plane (decision)", A::IllegalCommandInMode, |c| {
        c.during(group::DYNAMIC_FIXTURE, |_, m| m == G254) && c.during(group::ROTATION, |c, m| c.twp(m))
    }),
    rule(Haas, "haas G254: a machine with rotary axes, all on the table (decision)", A::IllegalCommandInMode, |c| {
        c.starts(group::DYNAMIC_FIXTURE, |_, m| m == G254) && !c.st.dwo_mechanism_fits()
    }),
    rule(Haas, "haas G254: the work offset's tilt axis value is zero", A::DwoWorkOffsetTilt, |c| {
        c.starts(group::DYNAMIC_FIXTURE, |_, m| m == G254) && c.st.dwo_tilt_offset() != 0.0
    }),
    rule(Haas, "haas G254: X, Y and Z commanded before cutting", A::DwoXyzNotGiven, |c| {
        let due = if c.before[group::DYNAMIC_FIXTURE] == G254 { c.st.dwo_due() } else { 0b111 };
        c.after[group::DYNAMIC_FIXTURE] == G254 && c.cutting_move() && due & !c.st.xyz_given(c.w) != 0
    }),
    // The manual: G28/G29 do not apply DWO's rotation, and it strongly recommends not using
    // them under G254; which point an incremental intermediate point or G29's end is then
    // taken from it does not say, so fivex refuses them rather than guess (decision).
    rule(Haas, "haas G254: no G28/G29 while DWO is on (decision)", A::IllegalCommandInMode, |c| {
        c.any(&[G28, G29]) && c.during(group::DYNAMIC_FIXTURE, |_, m| m == G254)
    }),
    rule(Haas, "haas G234: the G codes allowed in TCPC (FANUC's TCP list)", A::IllegalCommandInTcp, |c| {
        c.foreign(group::LENGTH_COMP, |c, m| m == G234 && c.tcp(m), |_, g| tcp_allows(g))
    }),
    // --- lists of modal states a mode may start in ----------------------------------------
    rule(Fanuc, "twp §6.3, TV-WSE-16: modal states G54.4 may start in", A::WseModalState, |c| {
        c.has(G54_4) && c.five.wse == 0 && c.word(b'P') != Some(0.0) && c.state_outside(group::WSE, wse_state_allows)
    }),
    rule(Fanuc, "twp TWP-11, TWP-16, §6.1: modal states G68.2/G68.3 may start in", A::TwpIllegalCommand, |c| {
        c.starts(group::ROTATION, |c, m| c.twp(m)) && c.state_outside(group::ROTATION, twp_state_allows)
    }),
    rule(
        Fanuc,
        "tcp TCP-15, §2.3.2: TCP starts from G49 (G43/G44 are not in the list)",
        A::IllegalCommandInTcp,
        |c| c.starts(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.before[group::LENGTH_COMP] != G49,
    ),
    rule(Fanuc, "tcp TCP-15, §2.3.2: modal states TCP may start in", A::IllegalCommandInTcp, |c| {
        c.starts(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.state_outside(group::LENGTH_COMP, tcp_state_allows)
    }),
];

/// Check a block against the rules; on success, the bookkeeping after the block.
pub(super) fn check(st: &State, w: &Words) -> Result<FiveAxisModes, AlarmId> {
    if no_rule_applies(st, w.gcodes()) {
        return Ok(st.five);
    }
    check_rules(st, w)
}

/// Nothing applies while no 5-axis mode is on to a block whose G codes are all plain 3-axis
/// codes (the hot path of ordinary programs; `plain_blocks_need_no_rule` checks it).
pub(super) fn no_rule_applies(st: &State, g: &[u16]) -> bool {
    st.five == FiveAxisModes::default() && !any_mode(&st.modes) && g.iter().all(|&c| is_plain(c))
}

/// G codes no rule concerns while no 5-axis mode is active: motion, planes, units, distance and
/// feed modes, work systems, path modes, canned cycles, dwell, exact stop, plain length and
/// radius compensation.
fn is_plain(code: u16) -> bool {
    matches!(
        code,
        G00 | G01
            | G02
            | G03
            | G04
            | G09
            | G17
            | G18
            | G19
            | G20
            | G21
            | G40
            | G41
            | G42
            | G43
            | G44
            | G49
            | G54
            | G55
            | G56
            | G57
            | G58
            | G59
            | G61
            | G62
            | G63
            | G64
            | G73
            | G74
            | G76
            | G80
            | G81
            | G82
            | G83
            | G84
            | G85
            | G86
            | G87
            | G88
            | G89
            | G90
            | G91
            | G94
            | G95
            | G98
            | G99
    )
}

/// Every rule, in order (no fast path).
fn check_rules(st: &State, w: &Words) -> Result<FiveAxisModes, AlarmId> {
    let g = w.gcodes();
    let before = &st.modes;
    let dialect = st.cfg.dialect;
    let mut after = *before;
    for &code in g {
        if let Some(def) = gcode::lookup(code, dialect) {
            if def.group != group::ONE_SHOT {
                after[def.group] = code;
            }
        }
    }
    let mech = mechanism(&st.cfg.machine);
    let c = Ctx { st, w, g, before, after, five: st.five, dialect, mech };
    for r in RULES {
        let applies = match r.on {
            Both => true,
            Fanuc => dialect == Dialect::Fanuc,
            Syntec => dialect == Dialect::Syntec,
            Haas => dialect == Dialect::Haas,
        };
        if applies && (r.when)(&c) {
            return Err(r.alarm.clone());
        }
    }
    Ok(next(&c))
}

/// The bookkeeping after an accepted block.
fn next(c: &Ctx) -> FiveAxisModes {
    let mut n = c.five;
    if c.has(G54_4) {
        n.wse = c.word(b'P').map_or(0, |p| p as u8);
    }
    let (crc, tcp) = (c.crc5(c.after[group::CUTTER_COMP]), c.tcp(c.after[group::LENGTH_COMP]));
    if crc && tcp {
        n.tcp_inside_crc |= c.starts(group::LENGTH_COMP, |c, m| c.tcp(m)) && c.crc5(c.before[group::CUTTER_COMP]);
        n.crc_inside_tcp |= c.starts(group::CUTTER_COMP, |c, m| c.crc5(m)) && c.tcp(c.before[group::LENGTH_COMP]);
    } else {
        n.tcp_inside_crc = false;
        n.crc_inside_tcp = false;
    }
    n.g41_3_move_due = c.crc5(G41_3) && c.after[group::CUTTER_COMP] == G41_3 && c.before[group::CUTTER_COMP] != G41_3;
    n.suv_move_due = c.st.cfg.machine.motion.cutter_startup_perpendicular
        && c.starts(group::CUTTER_COMP, |c, m| c.crc5(m) && is_crc_type1(m));
    n.twp_seq = twp_sequence(c).unwrap_or(0);
    if c.twp(c.after[group::ROTATION]) {
        n.aligned |= c.any(&ALIGNMENTS);
    } else {
        n.aligned = false;
    }
    if c.starts(group::LENGTH_COMP, |c, m| c.tcp(m)) {
        // Syntec Pr3051 = 1: STCP without L (SYN-09, TV-25b).
        n.stcp = c.has(G43_4) && c.word(b'L').map_or(c.st.cfg.machine.five_axis.smooth_tcp, |l| l == 1.0);
        n.posture = c.word(b'P') == Some(1.0);
    }
    if !tcp {
        n.stcp = false;
        n.posture = false;
        n.nano_in_tcp = false;
    } else if c.has(G43_4) && c.word(b'L').is_some() {
        n.stcp = c.word(b'L') == Some(1.0);
    }
    if c.has(G05_1) {
        if c.word(b'Q') == Some(3.0) {
            n.nano_in_tcp = tcp;
        } else if c.word(b'Q') == Some(0.0) {
            n.nano_in_tcp = false;
        }
    }
    n
}

/// The G68.2/G68.4 P2/P3 sequence state after this block, or Err if the block breaks one.
fn twp_sequence(c: &Ctx) -> Result<u8, ()> {
    let prev = c.five.twp_seq;
    let q = c.word(b'Q').filter(|q| q.fract() == 0.0).map_or(-1, |q| q as i64);
    match (c.twp_def(), q) {
        (Some(2), 0) if prev != 31 => Ok(if matches!(prev, 21 | 22) { prev } else { 20 }),
        (Some(2), 1) if matches!(prev, 0 | 20) => Ok(21),
        (Some(2), 2) if prev == 21 => Ok(22),
        (Some(2), 3) if prev == 22 => Ok(0),
        (Some(3), 1) if prev == 0 => Ok(31),
        (Some(3), 2) if prev == 31 => Ok(0),
        (Some(2 | 3), _) => Err(()),
        _ if prev != 0 => Err(()),
        _ => Ok(0),
    }
}

/// The block and the modes around it, as the rules see them.
struct Ctx<'a> {
    st: &'a State,
    w: &'a Words,
    /// The block's G codes (×10).
    g: &'a [u16],
    before: &'a [u16; GROUPS],
    /// The modes the block's G codes leave.
    after: [u16; GROUPS],
    five: FiveAxisModes,
    dialect: Dialect,
    mech: Mech,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mech {
    /// No rotary axis.
    None,
    /// Tool rotation (FANUC No.19680 = 2).
    Head,
    /// Table rotation (12).
    Table,
    /// One tool and one table axis (21).
    Mixed,
}

/// The mechanism type (FANUC No.19680) from the sides the rotary links are on: all on the
/// head, all on the table, or one of each; a rotary axis without a link counts as a head.
fn mechanism(m: &MachineConfig) -> Mech {
    use crate::machine::Side;
    let (head, table) = (m.rotary.iter().any(|l| l.side == Side::Head), m.rotary.iter().any(|l| l.side == Side::Table));
    match (head, table) {
        (true, true) => Mech::Mixed,
        (false, true) => Mech::Table,
        _ if m.axes.iter().any(|a| a.kind == AxisKind::Rotary) => Mech::Head,
        _ => Mech::None,
    }
}

impl Ctx<'_> {
    fn has(&self, code: u16) -> bool {
        self.g.contains(&code)
    }

    fn any(&self, codes: &[u16]) -> bool {
        self.g.iter().any(|g| codes.contains(g))
    }

    fn word(&self, letter: u8) -> Option<f64> {
        self.w.number(letter)
    }

    fn count_letters(&self, letters: &[u8]) -> usize {
        letters.iter().filter(|&&l| self.w.has(l)).count()
    }

    fn mech(&self) -> Mech {
        self.mech
    }

    /// FANUC No.19607#1 SPG: the tool side offset's G codes by mechanism.
    fn spg(&self) -> bool {
        self.st.cfg.machine.five_axis.crc_codes_by_mechanism
    }

    fn table_or_mixed(&self) -> bool {
        matches!(self.mech(), Mech::Table | Mech::Mixed)
    }

    fn rotary_axes(&self) -> usize {
        self.st.cfg.machine.axes.iter().filter(|a| a.kind == AxisKind::Rotary).count()
    }

    fn axis_words(&self, kind: Option<AxisKind>) -> bool {
        self.st.cfg.machine.axes.iter().any(|a| kind.is_none_or(|k| a.kind == k) && self.w.has(a.name as u8))
    }

    fn any_axis(&self) -> bool {
        self.axis_words(None)
    }

    /// The block's axis words are data of one of its G codes (G04 dwell time, G10, G28 …, or a
    /// G51/G51.1/G68 transform), not the group-01 motion: such a block is no arc.
    fn axes_are_data(&self) -> bool {
        self.g.iter().any(|&g| {
            matches!(g, G51 | G51_1 | G68 | G101 | G100)
                || gcode::lookup(g, self.st.cfg.dialect)
                    .is_some_and(|d| d.owns_axes(self.st.cfg.dialect) && d.group == group::ONE_SHOT)
        })
    }

    /// The block is a G02/G03 arc: the group-01 mode is an arc and its axis words are the end point.
    fn arc(&self) -> bool {
        matches!(self.after[group::MOTION], G02 | G03) && !self.axes_are_data()
    }

    /// The block cuts: axis words in G01/G02/G03 or a canned cycle, not owned by a one-shot
    /// code (G28, G53 …).
    fn cutting_move(&self) -> bool {
        let owned = self.g.iter().any(|&g| gcode::lookup(g, self.dialect).is_some_and(|d| d.takes_axes));
        self.any_axis()
            && !owned
            && (matches!(self.after[group::MOTION], G01 | G02 | G03) || self.after[group::CYCLE] != G80)
    }

    fn any_rotary(&self) -> bool {
        self.axis_words(Some(AxisKind::Rotary))
    }

    fn any_linear(&self) -> bool {
        self.axis_words(Some(AxisKind::Linear))
    }

    /// Axis words in the block.
    fn axis_count(&self) -> usize {
        self.st.cfg.machine.axes.iter().filter(|a| self.w.has(a.name as u8)).count()
    }

    /// Axis words outside the 5-axis set (X, Y, Z and the first two rotary axes).
    fn other_axes(&self) -> usize {
        let mut rotary = 0;
        let mut n = 0;
        for a in &self.st.cfg.machine.axes {
            let five = match a.kind {
                AxisKind::Linear => matches!(a.name, 'X' | 'Y' | 'Z'),
                AxisKind::Rotary => {
                    rotary += 1;
                    rotary <= 2
                }
            };
            if !five && self.w.has(a.name as u8) {
                n += 1;
            }
        }
        n
    }

    /// The 5-axis modes exist only on a machine with a rotary axis: on a 3-axis machine G43.4 and
    /// G41.2 are tool length and cutter compensation (`docs/conventions.md`).
    fn five_axis(&self) -> bool {
        self.mech() != Mech::None
    }

    fn crc5(&self, m: u16) -> bool {
        (m == G41_3 || is_crc_type1(m) || is_crc_type2(m)) && self.five_axis()
    }

    /// The 16i variant of 3-D cutter compensation (`five_axis.crc_variant`).
    fn crc16i(&self) -> bool {
        !self.st.cfg.machine.five_axis.crc_variant.is_30i() && self.five_axis()
    }

    fn tcp(&self, m: u16) -> bool {
        TCP.contains(&m) && self.five_axis()
    }

    fn twp(&self, m: u16) -> bool {
        TILTED_PLANES.contains(&m)
    }

    fn posture(&self) -> bool {
        self.five.posture || self.starts(group::LENGTH_COMP, |c, m| c.tcp(m)) && self.word(b'P') == Some(1.0)
    }

    /// The mode of `group` is on during the block: on after it, or on before it and not
    /// cancelled by it (switching to another code of the group is a command in the mode).
    fn during(&self, group: usize, mode: fn(&Ctx, u16) -> bool) -> bool {
        let cancelled = match group {
            group::CUTTER_COMP => self.after[group] == G40,
            group::LENGTH_COMP => LENGTH_CANCEL.contains(&self.after[group]),
            group::ROTATION => matches!(self.after[group], G69 | G69_1),
            _ => self.after[group] == gcode::initial_modes()[group],
        };
        mode(self, self.after[group]) || mode(self, self.before[group]) && !cancelled
    }

    fn starts(&self, group: usize, mode: fn(&Ctx, u16) -> bool) -> bool {
        mode(self, self.after[group]) && !mode(self, self.before[group])
    }

    fn crc_cancels(&self) -> bool {
        self.crc5(self.before[group::CUTTER_COMP])
            && (self.after[group::CUTTER_COMP] == G40 || self.word(b'D') == Some(0.0))
    }

    fn tcp_cancels(&self) -> bool {
        self.tcp(self.before[group::LENGTH_COMP]) && LENGTH_CANCEL.contains(&self.after[group::LENGTH_COMP])
    }

    /// G54.4 tool direction compensation (FANUC No.11200#0 RCM).
    fn rcm(&self) -> bool {
        self.st.cfg.machine.five_axis.tool_direction_compensation
    }

    /// A mode that must open and close inside G54.4 is on (§6.6: cutter and tool length
    /// compensation, scaling, rotation and tilted planes, mirror image, canned cycles).
    fn wse_nests_a_mode(&self) -> bool {
        let off = gcode::initial_modes();
        let nested =
            [group::CUTTER_COMP, group::LENGTH_COMP, group::CYCLE, group::SCALING, group::ROTATION, group::MIRROR];
        nested.iter().any(|&g| self.before[g] != off[g] && !(g == group::LENGTH_COMP && self.before[g] == G49_1))
    }

    /// Tool direction compensation on a table-rotation or mixed machine (§6.5's rows).
    fn wse_rcm_table(&self) -> bool {
        self.rcm() && self.table_or_mixed()
    }

    /// A table rotary axis is off its absolute 0.
    fn table_axes_turned(&self) -> bool {
        let Some(kin) = &self.st.kinematics else { return false };
        kin.joints()
            .iter()
            .any(|j| j.side == crate::machine::Side::Table && j.index.is_some_and(|i| self.st.pos[i].abs() > 1e-9))
    }

    /// 5-axis cutter compensation works in the table coordinate system (TBP = 1, WKP = 0) on
    /// this machine (one with a rotary table).
    fn crc_in_table(&self) -> bool {
        self.table_or_mixed() && self.st.cfg.machine.five_axis.crc_in_table()
    }

    /// The block names a rotary axis of the table.
    fn table_axis_word(&self) -> bool {
        let Some(kin) = &self.st.kinematics else { return false };
        kin.joints().iter().any(|j| {
            j.side == crate::machine::Side::Table
                && j.index.is_some_and(|i| self.st.cfg.machine.axes.get(i).is_some_and(|a| self.w.has(a.name as u8)))
        })
    }

    /// The block names an axis that is neither X/Y/Z nor a rotary axis of the mechanism.
    fn foreign_axis(&self) -> bool {
        let Some(kin) = &self.st.kinematics else { return false };
        self.st.cfg.machine.axes.iter().enumerate().any(|(i, a)| {
            self.w.has(a.name as u8)
                && !kin.linear.contains(&Some(i))
                && !kin.joints().iter().any(|j| j.index == Some(i))
        })
    }

    fn wse_during(&self) -> bool {
        self.five.wse != 0 && !(self.has(G54_4) && self.word(b'P') == Some(0.0))
    }

    /// P of a G68.2/G68.4 block (0 when omitted).
    fn twp_def(&self) -> Option<i64> {
        if !self.any(&[G68_2, G68_4]) {
            return None;
        }
        let p = self.word(b'P').unwrap_or(0.0);
        Some(if p.fract() == 0.0 && (0.0..=4.0).contains(&p) { p as i64 } else { 5 })
    }

    fn chain_switch(&self) -> bool {
        self.has(G10) && self.word(b'L') == Some(5000.0)
    }

    /// A G code of the block that `allowed` refuses while the mode of `group` is on. The code that
    /// starts the mode is the start's business, not the list's.
    fn foreign(&self, group: usize, mode: fn(&Ctx, u16) -> bool, allowed: fn(&Ctx, u16) -> bool) -> bool {
        if !self.during(group, mode) {
            return false;
        }
        let starting = !mode(self, self.before[group]);
        self.g.iter().any(|&g| {
            let own = starting && gcode::lookup(g, self.dialect).is_some_and(|d| d.group == group);
            !own && !allowed(self, g)
        })
    }

    /// A modal state (after the block, other than `group`'s) outside a start list. The power-on
    /// code of every group counts as allowed (`docs/conventions.md`).
    fn state_outside(&self, group: usize, allowed: fn(usize, u16) -> bool) -> bool {
        let initial = gcode::initial_modes();
        (1..GROUPS).any(|g| g != group && self.after[g] != initial[g] && !allowed(g, self.after[g]))
    }
}

fn any_mode(m: &[u16; GROUPS]) -> bool {
    // The 3-D / 5-axis cutter compensations (G41.2…G41.6, G42.2…G42.6), not G42 itself.
    matches!(m[group::CUTTER_COMP], G41_2..=G41_6 | G42_2..=G42_6)
        || matches!(m[group::LENGTH_COMP], G43_4..=G43_9 | G234)
        || m[group::DYNAMIC_FIXTURE] == G254
        || TILTED_PLANES.contains(&m[group::ROTATION])
        || m[group::POLAR_INTERPOLATION] == G12_1
}

/// Why Syntec refuses the word `letter` (value `value`, when known) of a block whose G codes are
/// `codes`: its manual's formats are `G68.2 X_ Y_ Z_ I_ J_ K_` (Euler angles only, §4.1.3:
/// FANUC's P1…P4 forms and their Q/R are the teach screen's, not the block's), `G43.4 H_ [L_]`
/// with L1 / L0 (§3.1.1) and `G43.5 H_` (§2.3.1): FANUC's tool posture control P is no Syntec
/// address (the interpolation is Pr3054's). A word another code of the block takes is that
/// code's: a one-shot G code (G04, G05, G10, G53.1, G65 … P) or, with `m_call`, a subprogram
/// call or return (M98/M99 P, L). `fivex check` asks the same with the literal words.
pub(crate) fn syntec_improper_address(
    codes: &[u16],
    m_call: bool,
    letter: u8,
    value: Option<f64>,
) -> Option<&'static str> {
    let one_shot = |g: u16| gcode::lookup(g, Dialect::Syntec).is_some_and(|d| d.group == group::ONE_SHOT);
    if m_call || codes.iter().any(|&g| one_shot(g)) {
        return None;
    }
    codes.iter().find_map(|&code| match (code, letter) {
        (G68_2, b'P' | b'Q' | b'R') => Some("Syntec's G68.2 takes X Y Z I J K (Euler angles) only, no P, Q or R"),
        (G43_4 | G43_5, b'P') => Some("no P in Syntec's G43.4/G43.5 (tool posture control is FANUC's; Pr3054)"),
        (G43_4, b'L') if value.is_some_and(|l| l != 0.0 && l != 1.0) => Some("G43.4 L is L1 (STCP on) or L0 (off)"),
        _ => None,
    })
}

/// The block calls a subprogram or returns by an M code (its P and L are the call's).
fn m_call(w: &Words) -> bool {
    w.mcodes().iter().any(|&m| super::mcode::call_or_return(m))
}

/// G80 and the canned cycles (group 09).
fn in_group_09(g: u16) -> bool {
    gcode::lookup(g, Dialect::Fanuc).is_some_and(|d| d.group == group::CYCLE)
}

/// A 5-axis command that a sub-chain 2–4 does not support (COR-165). The manual's two lists
/// differ on G53.3 (§6.1 names G53.1/G53.3/G53.6, the §6.2 solution G53.1 and G53.6 only):
/// fivex follows the shorter, so G53.3 is refused (TV-22c).
fn chain_limited(g: u16) -> bool {
    let five_axis = TCP.contains(&g) || ALIGNMENTS.contains(&g) || TILTED_PLANES.contains(&g) || TOOL_SIDE.contains(&g);
    five_axis && ![G43_4, G43_5, G68_2, G68_3, G53_1, G53_6].contains(&g)
}

fn int_in(v: f64, lo: i64, hi: i64) -> bool {
    v.fract() == 0.0 && v >= lo as f64 && v <= hi as f64
}

/// 5-axis cutter compensation type 1 (G41.2/G42.2 and the FS16i-compatible G41.4/G41.5 forms).
fn is_crc_type1(m: u16) -> bool {
    TOOL_SIDE_TYPE1.contains(&m)
}

/// 5-axis cutter compensation type 2.
fn is_crc_type2(m: u16) -> bool {
    matches!(m, G41_6 | G42_6)
}

/// crc CRC-50 (§3.5.3): the G codes 5-axis cutter compensation takes in the table coordinate
/// system (any other: PS5460), and its own codes (a change of side, a decision: the manual's
/// list names G40 only).
fn table_crc_allows(g: u16) -> bool {
    matches!(
        g,
        G00 | G01
            | G04
            | G09
            | G10
            | G11
            | G17
            | G18
            | G19
            | G22
            | G23
            | G38
            | G39
            | G40
            | G49
            | G50
            | G51
            | G61
            | G62
            | G64
            | G65
            | G66
            | G66_1
            | G67
            | G90
            | G91
    ) || TOOL_SIDE.contains(&g)
}

/// crc CRC-51 (§3.5.3): the modal states it may start in (any other: PS5421) — those codes, the
/// cancels the manual lists (the milling ones), and tool centre point control, which must be on
/// before it (a decision: the list leaves G43.4/G43.5 out, §3.5.3 asks for them first).
fn table_crc_state_allows(_group: usize, g: u16) -> bool {
    table_crc_allows(g)
        || matches!(g, G13_1 | G15 | G20 | G21 | G54 | G55 | G56 | G57 | G58 | G59 | G69 | G80 | G94 | G97 | G98 | G99)
        || TCP.contains(&g)
}

/// G161 (in-feed control), which has no name of its own in `gcode::code`.
const G161_CODE: u16 = 1610;

/// crc §6.1: G codes that may not be given in any 5-axis cutter compensation mode.
fn crc5_forbids(g: u16) -> bool {
    matches!(
        g,
        G07 | G07_1
            | G12_1
            | G13_1
            | G15
            | G16
            | G27
            | G28
            | G28_2
            | G29
            | G30
            | G30_1
            | G31
            | G31_8
            | G31_9
            | G33
            | G37
            | G40_1
            | G41_1
            | G42_1
            | G39
            | G41
            | G42
            | G45
            | G46
            | G47
            | G48
            | G50_1
            | G51_1
            | G52
            | G53
            | G54
            | G54_1
            | G55
            | G56
            | G57
            | G58
            | G59
            | G54_2
            | G60
            | G62
            | G63
            | G68
            | G68_2
            | G68_3
            | G68_4
            | G69
            | G69_1
            | G72_1
            | G72_2
            | G73
            ..=G89 // canned cycles, G80, G80.5/G81.5 EGB, G81.1 chopping
            | G98 | G99
            | G92 | G92_1
            | G95 | G96 | G97
            | G06_2 // crc NRB-04
    )
}

/// tcp TCP-16: G codes allowed in tool centre point control (with crc CRC-48: the 5-axis cutter
/// compensation of either type, a type mismatch being its own rule; and G94, without which G93
/// could not be left, tcp Q-19).
fn tcp_allows(g: u16) -> bool {
    matches!(
        g,
        G00 | G01
            | G02
            | G03
            | G04
            | G09
            | G10
            | G11
            | G17
            | G18
            | G19
            | G22
            | G23
            | G38
            | G39
            | G40
            | G41
            | G42
            | G41_2
            | G42_2
            | G41_4
            | G42_4
            | G41_5
            | G42_5
            | G41_6
            | G42_6
            | G45
            | G46
            | G47
            | G48
            | G49
            | G49_1
            | G50
            | G51
            | G50_1
            | G51_1
            | G61
            | G62
            | G63
            | G64
            | G65
            | G66
            | G66_1
            | G67
            | G72_1
            | G72_2
            | G90
            | G91
            | G93
            | G94
    )
}

/// tcp TCP-15: modal states TCP may start in (besides the codes of [`tcp_allows`]).
fn tcp_state_allows(group: usize, g: u16) -> bool {
    // G54.4 (group 33): TCP nests inside it; its RCM=0 refusal is the WSE-11 row.
    group == group::WSE
        || tcp_allows(g)
        || matches!(g, G13_1 | G15 | G20 | G21 | G54 | G55 | G56 | G57 | G58 | G59 | G80 | G97 | G98 | G99 | G69 | G94)
}

/// twp §6.2 (TWP-12): G codes allowed in the tilted working plane (MTW=0).
fn twp_allows(g: u16) -> bool {
    matches!(
        g,
        G00 | G01
            | G02
            | G03
            | G04
            | G10
            | G11
            | G17
            | G18
            | G19
            | G28
            | G29
            | G30
            | G40
            | G41
            | G42
            | G43
            | G44
            | G49
            | G49_1
            | G53
            | G53_1
            | G65
            | G66
            | G66_1
            | G67
            | G90
            | G91
            | G98
            | G99
            | G45
            | G46
            | G47
            | G48
            | G50_1
            | G51_1
            | G69
            | G69_1
            | G94
            | G95
    ) || in_group_09(g)
}

/// twp §6.1 (TWP-11) with TWP-16: modal states G68.2/G68.3 may start in. G41/G42, G43/G44,
/// G51.1 and canned cycles must be off (they nest inside); G54.4 may be on (OQ-21).
fn twp_state_allows(group: usize, g: u16) -> bool {
    match group {
        group::CUTTER_COMP => g == G40,
        group::LENGTH_COMP => LENGTH_CANCEL.contains(&g),
        group::CYCLE => g == G80,
        group::MIRROR => g == G50_1,
        group::WSE => true,
        _ => {
            twp_allows(g)
                || matches!(g, G13_1 | G15 | G20 | G21 | G22 | G23 | G50 | G54 | G55 | G56 | G57 | G58 | G59)
                || matches!(g, G61 | G62 | G63 | G64 | G93 | G97)
        }
    }
}

/// twp §6.4: G codes allowed in G54.4 mode (G05.1 only with Q0/Q1, checked by the rule).
fn wse_allows(g: u16) -> bool {
    matches!(
        g,
        G00 | G01
            | G02
            | G03
            | G04
            | G05_1
            | G06_2
            | G10
            | G11
            | G17
            | G18
            | G19
            | G28
            | G29
            | G30
            | G40
            | G41
            | G41_2
            | G41_3
            | G41_4
            | G41_5
            | G41_6
            | G42
            | G42_2
            | G42_4
            | G42_5
            | G42_6
            | G43
            | G43_1
            | G43_4
            | G43_5
            | G44
            | G49
            | G49_1
            | G50
            | G51
            | G53
            | G53_1
            | G54_4
            | G65
            | G66
            | G67
            | G68
            | G68_2
            | G45
            | G46
            | G47
            | G48
            | G50_1
            | G51_1
            | G69
            | G90
            | G91
            | G94
            | G95
            | G98
            | G99
    ) || in_group_09(g)
}

/// twp §6.3: modal states G54.4 Pn may start in.
fn wse_state_allows(_group: usize, g: u16) -> bool {
    matches!(
        g,
        G00 | G01
            | G13_1
            | G15
            | G17
            | G18
            | G19
            | G20
            | G21
            | G23
            | G25
            | G40
            | G40_1
            | G49
            | G49_1
            | G50
            | G50_1
            | G54
            | G54_1
            | G55
            | G56
            | G57
            | G58
            | G59
            | G64
            | G67
            | G69
            | G80
            | G80_5
            | G90
            | G91
            | G94
            | G95
            | G97
            | G98
            | G99
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_rule_names_its_spec_row() {
        for r in RULES {
            let known = ["crc ", "tcp ", "twp ", "syn ", "haas "].iter().any(|p| r.src.starts_with(p));
            assert!(known && r.src.contains(':'), "rule without a spec row: {}", r.src);
        }
    }

    /// The fast path of `check` gives what the rules give, for every plain code with any common
    /// words, in both dialects, on every preset, from power-on modes.
    #[test]
    fn plain_blocks_need_no_rule() {
        use crate::interp::{Config, Interpreter};
        use crate::lang::{parse_file, BlockKind};
        use crate::machine::MachineConfig;
        let plain: Vec<u16> = gcode::TABLE.iter().map(|d| d.code).filter(|&c| is_plain(c)).collect();
        for preset in MachineConfig::PRESETS {
            for dialect in [Dialect::Fanuc, Dialect::Syntec] {
                let cfg = Config::new(MachineConfig::preset(preset).unwrap(), dialect);
                let interp = Interpreter::new(parse_file("M30\n"), cfg);
                let st = &interp.state;
                for &code in &plain {
                    for words in ["", " X1. Y2. Z3.", " X1. R5. F100", " P1 Q2. L3 H1 D1", " I1. J1. K1. B30. C40."] {
                        let text = format!("{}{words}", gcode::display(code));
                        let file = parse_file(&text);
                        let BlockKind::Words(ws) = &file.programs[0].blocks[0].kind else { panic!("{text}") };
                        let Ok(w) = st.collect(ws) else { continue };
                        assert_eq!(check(st, &w), check_rules(st, &w), "{preset} {dialect:?}: {text}");
                    }
                }
            }
        }
    }
}
