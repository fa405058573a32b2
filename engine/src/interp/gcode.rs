//! The milling G-code set of the FANUC 30i-A5 (M series), grouped exactly as FANUC groups them,
//! with the Syntec-only and FANUC-only codes marked, and the Haas NGC's codes ([`HAAS_HAS`],
//! [`HAAS_TABLE`]). Which of them fivex performs: `unbuilt`.
//! A G code is held as its number ×10 (`G43.4` → 434), and named in code by [`code`]
//! (`code::G43_4`), a modal group by [`group`] (`group::LENGTH_COMP`).

use crate::dialect::Dialect;

/// Number of modal groups (FANUC numbers them 0..=33 on the 30i M series).
pub const GROUPS: usize = 34;

/// The groups by FANUC's numbers, as `State::modal` and the mode array index them.
pub mod group {
    /// The non-modal (one-shot) codes: G04, G10, G28, G53, G65 …
    pub const ONE_SHOT: usize = 0;
    /// G00, G01, G02, G03 … (interpolation).
    pub const MOTION: usize = 1;
    /// G17, G18, G19.
    pub const PLANE: usize = 2;
    /// G90, G91.
    pub const DISTANCE: usize = 3;
    /// G22, G23 (stored stroke check).
    pub const STROKE_CHECK: usize = 4;
    /// G93, G94, G95.
    pub const FEED_MODE: usize = 5;
    /// G20, G21.
    pub const UNITS: usize = 6;
    /// G40, G41, G42 and the 3-D forms.
    pub const CUTTER_COMP: usize = 7;
    /// G43, G44, G43.4, G43.5, G49 …
    pub const LENGTH_COMP: usize = 8;
    /// G80 and the canned cycles.
    pub const CYCLE: usize = 9;
    /// G98, G99.
    pub const RETURN_LEVEL: usize = 10;
    /// G50, G51.
    pub const SCALING: usize = 11;
    /// G66, G66.1, G67.
    pub const MODAL_CALL: usize = 12;
    /// G96, G97 (constant surface speed).
    pub const SURFACE_SPEED: usize = 13;
    /// G54–G59, G54.1 …
    pub const WORK_SYSTEM: usize = 14;
    /// G61, G62, G63, G64.
    pub const PATH_MODE: usize = 15;
    /// G68, G69, G68.2, G68.3, G68.4.
    pub const ROTATION: usize = 16;
    /// G15, G16.
    pub const POLAR: usize = 17;
    /// G40.1, G41.1, G42.1 (normal direction control).
    pub const NORMAL_DIRECTION: usize = 19;
    /// G160, G161 (in-feed control).
    pub const IN_FEED: usize = 20;
    /// G12.1, G13.1 (polar coordinate interpolation).
    pub const POLAR_INTERPOLATION: usize = 21;
    /// G50.1, G51.1.
    pub const MIRROR: usize = 22;
    /// G54.2 (rotary table dynamic fixture offset).
    pub const DYNAMIC_FIXTURE: usize = 23;
    /// G25, G26 (spindle speed fluctuation detection).
    pub const SPEED_FLUCTUATION: usize = 24;
    /// G80.5, G81.5 (electronic gear box synchronisation).
    pub const EGB: usize = 25;
    /// G54.4 (workpiece setting error compensation).
    pub const WSE: usize = 33;
}

/// Declares the G-code constants, each with the group it claims; the claims are held to
/// [`TABLE`] by a test, so a constant with a wrong number cannot hide behind its name.
macro_rules! codes {
    ($($(#[$doc:meta])* $name:ident = $value:literal in $group:ident;)*) => {
        $($(#[$doc])* pub const $name: u16 = $value;)*

        /// Every constant above: its name, its code and the group it claims.
        #[cfg(test)]
        pub(super) const CLAIMS: &[(&str, u16, usize)] =
            &[$((stringify!($name), $name, super::group::$group)),*];
    };
}

/// The G codes the interpreter names, held as their number ×10 (`G43_4` is G43.4, 434), and the
/// sets of them that recur.
pub mod code {
    codes! {
        G00 = 0 in MOTION;
        G01 = 10 in MOTION;
        G02 = 20 in MOTION;
        /// Involute interpolation CW.
        G02_2 = 22 in MOTION;
        G03 = 30 in MOTION;
        /// Involute interpolation CCW.
        G03_2 = 32 in MOTION;
        /// Dwell.
        G04 = 40 in ONE_SHOT;
        /// High-speed cycle machining; Syntec: HPCC, `G05 P10000` on, `G05 P0` off.
        G05 = 50 in ONE_SHOT;
        /// AI contour control / nano smoothing (Q0, Q1, Q3).
        G05_1 = 51 in ONE_SHOT;
        /// NURBS interpolation.
        G06_2 = 62 in MOTION;
        /// Hypothetical axis interpolation.
        G07 = 70 in ONE_SHOT;
        /// Cylindrical interpolation.
        G07_1 = 71 in ONE_SHOT;
        /// Exact stop (one block).
        G09 = 90 in ONE_SHOT;
        /// Programmable data input.
        G10 = 100 in ONE_SHOT;
        G11 = 110 in ONE_SHOT;
        /// Haas: circular pocket milling clockwise.
        G12 = 120 in ONE_SHOT;
        /// Haas: circular pocket milling counter-clockwise.
        G13 = 130 in ONE_SHOT;
        /// Polar coordinate interpolation.
        G12_1 = 121 in POLAR_INTERPOLATION;
        G13_1 = 131 in POLAR_INTERPOLATION;
        G15 = 150 in POLAR;
        G16 = 160 in POLAR;
        G17 = 170 in PLANE;
        G18 = 180 in PLANE;
        G19 = 190 in PLANE;
        G20 = 200 in UNITS;
        G21 = 210 in UNITS;
        G22 = 220 in STROKE_CHECK;
        G23 = 230 in STROKE_CHECK;
        G25 = 250 in SPEED_FLUCTUATION;
        G27 = 270 in ONE_SHOT;
        G28 = 280 in ONE_SHOT;
        G28_2 = 282 in ONE_SHOT;
        G29 = 290 in ONE_SHOT;
        G30 = 300 in ONE_SHOT;
        G30_1 = 301 in ONE_SHOT;
        /// Skip.
        G31 = 310 in ONE_SHOT;
        G31_8 = 318 in ONE_SHOT;
        G31_9 = 319 in ONE_SHOT;
        /// Threading.
        G33 = 330 in MOTION;
        G37 = 370 in ONE_SHOT;
        G38 = 380 in ONE_SHOT;
        G39 = 390 in ONE_SHOT;
        G40 = 400 in CUTTER_COMP;
        G40_1 = 401 in NORMAL_DIRECTION;
        G41 = 410 in CUTTER_COMP;
        G41_1 = 411 in NORMAL_DIRECTION;
        /// 3-D cutter compensation left, type 1.
        G41_2 = 412 in CUTTER_COMP;
        /// Leading edge offset.
        G41_3 = 413 in CUTTER_COMP;
        /// Left, type 1 (FS16i compatible).
        G41_4 = 414 in CUTTER_COMP;
        G41_5 = 415 in CUTTER_COMP;
        /// Left, type 2.
        G41_6 = 416 in CUTTER_COMP;
        G42 = 420 in CUTTER_COMP;
        G42_1 = 421 in NORMAL_DIRECTION;
        G42_2 = 422 in CUTTER_COMP;
        G42_4 = 424 in CUTTER_COMP;
        G42_5 = 425 in CUTTER_COMP;
        G42_6 = 426 in CUTTER_COMP;
        G43 = 430 in LENGTH_COMP;
        /// Tool length compensation in the tool axis direction.
        G43_1 = 431 in LENGTH_COMP;
        /// Tool centre point control type 1 (Syntec RTCP).
        G43_4 = 434 in LENGTH_COMP;
        /// Tool centre point control type 2.
        G43_5 = 435 in LENGTH_COMP;
        /// Cutting point command type 1.
        G43_8 = 438 in LENGTH_COMP;
        /// Cutting point command type 2.
        G43_9 = 439 in LENGTH_COMP;
        G44 = 440 in LENGTH_COMP;
        G45 = 450 in ONE_SHOT;
        G46 = 460 in ONE_SHOT;
        G47 = 470 in ONE_SHOT;
        G48 = 480 in ONE_SHOT;
        G49 = 490 in LENGTH_COMP;
        G49_1 = 491 in LENGTH_COMP;
        /// Scaling cancel.
        G50 = 500 in SCALING;
        /// Mirror image cancel.
        G50_1 = 501 in MIRROR;
        G51 = 510 in SCALING;
        G51_1 = 511 in MIRROR;
        /// Local coordinate system.
        G52 = 520 in ONE_SHOT;
        /// Machine coordinate system.
        G53 = 530 in ONE_SHOT;
        /// Tool axis direction control.
        G53_1 = 531 in ONE_SHOT;
        /// Alignment plus positioning (Syntec).
        G53_3 = 533 in ONE_SHOT;
        /// Tool centre point retention type tool axis direction control.
        G53_6 = 536 in ONE_SHOT;
        G54 = 540 in WORK_SYSTEM;
        /// Additional workpiece coordinate systems (P1…).
        G54_1 = 541 in WORK_SYSTEM;
        G54_2 = 542 in DYNAMIC_FIXTURE;
        /// Workpiece setting error compensation.
        G54_4 = 544 in WSE;
        G55 = 550 in WORK_SYSTEM;
        G56 = 560 in WORK_SYSTEM;
        G57 = 570 in WORK_SYSTEM;
        G58 = 580 in WORK_SYSTEM;
        G59 = 590 in WORK_SYSTEM;
        G60 = 600 in ONE_SHOT;
        /// Exact stop mode.
        G61 = 610 in PATH_MODE;
        G62 = 620 in PATH_MODE;
        /// Tapping mode.
        G63 = 630 in PATH_MODE;
        G64 = 640 in PATH_MODE;
        /// Macro call.
        G65 = 650 in ONE_SHOT;
        /// Macro modal call A (after each move).
        G66 = 660 in MODAL_CALL;
        /// Macro modal call B (every block).
        G66_1 = 661 in MODAL_CALL;
        G67 = 670 in MODAL_CALL;
        /// Coordinate system rotation.
        G68 = 680 in ROTATION;
        /// Tilted working plane.
        G68_2 = 682 in ROTATION;
        /// Tilted working plane by the tool axis.
        G68_3 = 683 in ROTATION;
        /// Tilted working plane, incremental.
        G68_4 = 684 in ROTATION;
        G69 = 690 in ROTATION;
        G69_1 = 691 in ROTATION;
        /// Haas: bolt hole circle.
        G70 = 700 in ONE_SHOT;
        /// Haas: bolt hole arc.
        G71 = 710 in ONE_SHOT;
        /// Haas: bolt holes along an angle.
        G72 = 720 in ONE_SHOT;
        /// Figure copy, rotary.
        G72_1 = 721 in ONE_SHOT;
        /// Figure copy, linear.
        G72_2 = 722 in ONE_SHOT;
        /// High-speed peck drilling.
        G73 = 730 in CYCLE;
        /// Left-hand tapping.
        G74 = 740 in CYCLE;
        /// Fine boring.
        G76 = 760 in CYCLE;
        G80 = 800 in CYCLE;
        /// EGB synchronisation cancel.
        G80_5 = 805 in EGB;
        G81 = 810 in CYCLE;
        G82 = 820 in CYCLE;
        G83 = 830 in CYCLE;
        G84 = 840 in CYCLE;
        /// Rigid tapping (FS10/11 format).
        G84_2 = 842 in CYCLE;
        /// Left-hand rigid tapping.
        G84_3 = 843 in CYCLE;
        G85 = 850 in CYCLE;
        G86 = 860 in CYCLE;
        /// Back boring.
        G87 = 870 in CYCLE;
        G88 = 880 in CYCLE;
        G89 = 890 in CYCLE;
        G90 = 900 in DISTANCE;
        G91 = 910 in DISTANCE;
        /// Workpiece coordinate system setting.
        G92 = 920 in ONE_SHOT;
        G92_1 = 921 in ONE_SHOT;
        /// Inverse time feed.
        G93 = 930 in FEED_MODE;
        G94 = 940 in FEED_MODE;
        G95 = 950 in FEED_MODE;
        G96 = 960 in SURFACE_SPEED;
        G97 = 970 in SURFACE_SPEED;
        G98 = 980 in RETURN_LEVEL;
        G99 = 990 in RETURN_LEVEL;
        /// Haas: block look-ahead limit (P0–P15).
        G100 = 1000 in MIRROR;
        G101 = 1010 in MIRROR;
        G103 = 1030 in ONE_SHOT;
        /// Haas: general purpose pocket milling.
        G150 = 1500 in ONE_SHOT;
        /// In-feed control cancel.
        G160 = 1600 in IN_FEED;
        /// Haas tool center point control (TCPC): type 1 tool centre point control in the
        /// work coordinate system fixed to the table (`interp::tcp`).
        G234 = 2340 in LENGTH_COMP;
        /// Haas dynamic work offset (DWO) and its cancel (`interp::dwo`).
        G254 = 2540 in DYNAMIC_FIXTURE;
        G255 = 2550 in DYNAMIC_FIXTURE;
        /// Haas: smoothness level.
        G187 = 1870 in ONE_SHOT;
    }

    /// Tool centre point control, type 1 and type 2, alone or with cutting point control.
    /// Haas G234 (TCPC) is type 1.
    pub const TCP: [u16; 5] = [G43_4, G43_5, G43_8, G43_9, G234];
    /// Tool centre point control whose tool direction is a vector I, J, K (type 2).
    pub const TCP_TYPE2: [u16; 2] = [G43_5, G43_9];
    /// The tapping cycles (FANUC G74/G84; G84.2/G84.3 rigid tapping of the FS10/11 format):
    /// their feed override, and the spindle override and feed hold while the tap is in the
    /// hole, do not act (`docs/conventions.md`, "Canned cycles").
    pub const TAPPING: [u16; 4] = [G74, G84, G84_2, G84_3];
    /// The tool length compensation cancels.
    pub const LENGTH_CANCEL: [u16; 2] = [G49, G49_1];
    /// The tool alignments (tool axis direction control).
    pub const ALIGNMENTS: [u16; 3] = [G53_1, G53_3, G53_6];
    /// The tilted working plane definitions.
    pub const TILTED_PLANES: [u16; 3] = [G68_2, G68_3, G68_4];
    /// The cutter compensations a path stage performs (`crate::stage`): C (G41/G42), the
    /// 5-axis tool side offset of type 1 (G41.2/G42.2, and G41.4/G42.4, G41.5/G42.5 where
    /// SPG selects them) and type 2 (G41.6/G42.6), and the leading edge offset (G41.3).
    pub const COMPENSATED_BY_STAGES: [u16; 11] =
        [G41, G42, G41_2, G42_2, G41_4, G42_4, G41_5, G42_5, G41_6, G42_6, G41_3];
    /// The 5-axis tool side offset (`stage::tool_side`), type 1 and type 2.
    pub const TOOL_SIDE: [u16; 8] = [G41_2, G42_2, G41_4, G42_4, G41_5, G42_5, G41_6, G42_6];
    /// The tool side offset of type 1 (the tool direction by the rotary axes): G41.2/G42.2 on
    /// every machine, or by mechanism (FANUC SPG = 1) G41.4/G42.4 (table), G41.5/G42.5 (mixed).
    pub const TOOL_SIDE_TYPE1: [u16; 6] = [G41_2, G42_2, G41_4, G42_4, G41_5, G42_5];
    /// The tool side offset's codes that put the tool right of the path.
    pub const TOOL_SIDE_RIGHT: [u16; 4] = [G42_2, G42_4, G42_5, G42_6];
    /// The macro calls, single and modal.
    pub const MACRO_CALLS: [u16; 3] = [G65, G66, G66_1];
    /// The codes with a P of their own in their format (besides the canned cycles, group 09,
    /// and G54.1): a P in a block with one of them is not G54's (`offsets::work_system_p`).
    pub const TAKE_P: [u16; 22] = [
        G04, G05, G05_1, G06_2, G10, G31, G43_4, G43_5, G51, G53_1, G53_3, G53_6, G54_2, G54_4, G65, G66, G66_1, G68_2,
        G68_3, G68_4, G150, G187,
    ];
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GDef {
    pub code: u16,
    pub group: usize,
    /// The block's axis words belong to this code rather than to the group-01 motion
    /// (G04, G10, G28, G52, G53, G92 …).
    pub takes_axes: bool,
    pub syntec_only: bool,
    /// A FANUC code the Syntec manual does not have (COR-070 in the Syntec dialect).
    pub fanuc_only: bool,
}

impl GDef {
    /// The block's axis words belong to this code in `dialect`: `takes_axes`, and Syntec's G05,
    /// whose axis words name the axes HPCC smooths (`G05 P10000 X0 Y0 Z0 B1. C1.`); FANUC's
    /// G05 takes none.
    pub fn owns_axes(&self, dialect: Dialect) -> bool {
        self.takes_axes || self.code == code::G05 && dialect == Dialect::Syntec
    }
}

const fn g(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: false, syntec_only: false, fanuc_only: false }
}
const fn gx(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: true, syntec_only: false, fanuc_only: false }
}
const fn gs(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: false, syntec_only: true, fanuc_only: false }
}
const fn gsx(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: true, syntec_only: true, fanuc_only: false }
}
/// FANUC's 5-axis codes that the Syntec 5-axis manual does not list (its 5-axis functions are
/// RTCP/STCP G43.4/G43.5, G68.2/G68.3, the tool alignments G53.1/G53.3/G53.6 and the chains
/// G10 L5000): 3-D cutter compensation, cutting point command, G54.4, G68.4. Not codes of the
/// Syntec dialect (COR-070), rather than FANUC's behaviour under a Syntec name.
const fn gf(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: false, syntec_only: false, fanuc_only: true }
}

/// Sorted by code, for binary search.
pub const TABLE: &[GDef] = &[
    g(0, 1),     // positioning
    g(10, 1),    // linear interpolation
    g(20, 1),    // circular/helical CW
    g(22, 1),    // involute CW
    g(23, 1),    // exponential CW
    g(24, 1),    // 3-D circular
    g(30, 1),    // circular/helical CCW
    g(32, 1),    // involute CCW
    g(33, 1),    // exponential CCW
    g(34, 1),    // 3-D circular
    gx(40, 0),   // dwell
    g(41, 0),    // G04.1 prevent buffering
    g(50, 0),    // G05 high-speed cycle / HPCC (Syntec: its axis words name the axes, `GDef::owns_axes`)
    gx(51, 0),   // G05.1 AI contour / nano smoothing (Q3's axis words name the axes smoothed)
    g(54, 0),    // G05.4 HRV3
    g(62, 1),    // G06.2 NURBS
    g(70, 0),    // G07 hypothetical axis interpolation
    g(71, 0),    // G07.1 cylindrical interpolation
    g(80, 0),    // G08 advanced preview control
    g(90, 0),    // G09 exact stop
    gx(100, 0),  // G10 programmable data input
    g(106, 0),   // G10.6 tool retract and recover
    g(110, 0),   // G11 data input cancel
    g(121, 21),  // G12.1 polar coordinate interpolation
    g(131, 21),  // G13.1 cancel
    g(150, 17),  // G15 polar coordinates cancel
    g(160, 17),  // G16 polar coordinates
    g(170, 2),   // G17 XY plane
    g(171, 2),   // G17.1 plane conversion
    g(180, 2),   // G18 ZX plane
    g(190, 2),   // G19 YZ plane
    g(200, 6),   // G20 inch
    g(210, 6),   // G21 mm
    gx(220, 4),  // G22 stored stroke check on
    g(230, 4),   // G23 off
    g(250, 24),  // G25 spindle speed fluctuation detection off
    g(260, 24),  // G26 on
    gx(270, 0),  // G27 reference position return check
    gx(280, 0),  // G28 reference position return
    gx(282, 0),  // G28.2
    gx(290, 0),  // G29 return from reference position
    gx(300, 0),  // G30 2nd-4th reference position return
    gx(301, 0),  // G30.1 floating reference position return
    gx(310, 0),  // G31 skip
    gx(318, 0),  // G31.8 EGB skip
    gx(319, 0),  // G31.9 continuous high-speed skip
    g(330, 1),   // G33 threading
    g(340, 1),   // G34 variable lead threading
    g(350, 1),   // G35 circular threading CW
    g(360, 1),   // G36 circular threading CCW
    gx(370, 0),  // G37 automatic tool length measurement
    g(380, 0),   // G38 cutter compensation: preserve vector
    gx(390, 0),  // G39 corner circular interpolation (I/J/K: direction; no move command)
    g(400, 7),   // G40 cutter compensation cancel
    g(401, 19),  // G40.1 normal direction control cancel
    g(410, 7),   // G41 left
    g(411, 19),  // G41.1 normal direction control left
    gf(412, 7),  // G41.2 3-D cutter compensation left, type 1
    gf(413, 7),  // G41.3 leading edge offset
    gf(414, 7),  // G41.4 left, type 1 (FS16i compatible)
    gf(415, 7),  // G41.5 left, type 1 (FS16i compatible)
    gf(416, 7),  // G41.6 left, type 2
    g(420, 7),   // G42 right
    g(421, 19),  // G42.1 normal direction control right
    gf(422, 7),  // G42.2 right, type 1
    gf(424, 7),  // G42.4 right, type 1 (FS16i compatible)
    gf(425, 7),  // G42.5 right, type 1 (FS16i compatible)
    gf(426, 7),  // G42.6 right, type 2
    g(430, 8),   // G43 tool length compensation +
    g(431, 8),   // G43.1 tool length compensation in tool axis direction
    g(434, 8),   // G43.4 tool center point control type 1
    g(435, 8),   // G43.5 tool center point control type 2
    g(437, 8),   // G43.7 tool offset
    gf(438, 8),  // G43.8 cutting point command type 1
    gf(439, 8),  // G43.9 cutting point command type 2
    g(440, 8),   // G44 tool length compensation -
    gx(450, 0),  // G45 tool offset increase
    gx(460, 0),  // G46 decrease
    gx(470, 0),  // G47 double increase
    gx(480, 0),  // G48 double decrease
    g(490, 8),   // G49 tool length compensation cancel
    g(491, 8),   // G49.1
    g(500, 11),  // G50 scaling cancel
    g(501, 22),  // G50.1 programmable mirror image cancel
    g(510, 11),  // G51 scaling
    g(511, 22),  // G51.1 programmable mirror image
    gx(520, 0),  // G52 local coordinate system
    gx(530, 0),  // G53 machine coordinate system
    g(531, 0),   // G53.1 tool axis direction control
    gsx(533, 0), // G53.3 alignment plus positioning (Syntec)
    g(536, 0),   // G53.6 tool center point retention type tool axis direction control
    g(540, 14),  // G54
    g(541, 14),  // G54.1 additional workpiece coordinate systems
    g(542, 23),  // G54.2 rotary table dynamic fixture offset
    gf(544, 33), // G54.4 workpiece setting error compensation
    g(550, 14),  // G55
    g(560, 14),  // G56
    g(570, 14),  // G57
    g(580, 14),  // G58
    g(590, 14),  // G59
    gs(591, 14), // G59.1 extended work coordinate system (Syntec; not built)
    gx(600, 0),  // G60 single direction positioning
    g(610, 15),  // G61 exact stop mode
    g(620, 15),  // G62 automatic corner override
    g(630, 15),  // G63 tapping mode
    g(640, 15),  // G64 cutting mode
    g(650, 0),   // G65 macro call
    g(660, 12),  // G66 macro modal call A
    g(661, 12),  // G66.1 macro modal call B
    g(670, 12),  // G67 macro modal call cancel
    g(680, 16),  // G68 coordinate system rotation
    g(682, 16),  // G68.2 tilted working plane
    g(683, 16),  // G68.3 tilted working plane by tool axis
    gf(684, 16), // G68.4 tilted working plane, incremental
    g(690, 16),  // G69 cancel
    g(691, 16),  // G69.1
    g(721, 0),   // G72.1 figure copy, rotary
    g(722, 0),   // G72.2 figure copy, linear
    g(730, 9),   // G73 high-speed peck drilling
    g(740, 9),   // G74 left-hand tapping
    g(760, 9),   // G76 fine boring
    g(800, 9),   // G80 canned cycle cancel
    g(805, 25),  // G80.5 EGB synchronisation cancel
    g(810, 9),   // G81 drilling
    g(811, 0),   // G81.1 chopping
    g(815, 25),  // G81.5 EGB synchronisation start
    g(820, 9),   // G82 drilling with dwell
    g(830, 9),   // G83 peck drilling
    g(840, 9),   // G84 tapping
    g(842, 9),   // G84.2 rigid tapping (FS10/11 format)
    g(843, 9),   // G84.3 left-hand rigid tapping
    g(850, 9),   // G85 boring
    g(860, 9),   // G86 boring, spindle stop
    g(870, 9),   // G87 back boring
    g(880, 9),   // G88 boring, manual retract
    g(890, 9),   // G89 boring with dwell
    g(900, 3),   // G90 absolute
    g(910, 3),   // G91 incremental
    gx(920, 0),  // G92 workpiece coordinate system setting
    gx(921, 0),  // G92.1 workpiece coordinate system preset
    g(930, 5),   // G93 inverse time feed
    g(940, 5),   // G94 feed per minute
    g(950, 5),   // G95 feed per revolution
    g(960, 13),  // G96 constant surface speed
    g(970, 13),  // G97 cancel
    g(980, 10),  // G98 return to initial level
    g(990, 10),  // G99 return to R level
    gs(1201, 0), // G120.1 smoothing as Autodesk's SYIL post writes it (Syntec; not built)
    gs(1210, 0), // G121 its cancel (Syntec; not built)
    g(1600, 20), // G160 in-feed control cancel
    g(1610, 20), // G161 in-feed control
];

/// Highest code in the table, ×10.
const MAX_CODE: usize = 1610;

/// `TABLE` index + 1 by code (0 = no such code): one array access per G word.
static INDEX: [u8; MAX_CODE + 1] = {
    let mut index = [0u8; MAX_CODE + 1];
    let mut i = 0;
    while i < TABLE.len() {
        index[TABLE[i].code as usize] = i as u8 + 1;
        i += 1;
    }
    index
};

/// The FANUC codes of [`TABLE`] that the Haas NGC mill has with the same function (the NGC's
/// G-code list, `docs/dialects.md`, "Haas"). Every other FANUC code is not a code of the Haas
/// dialect (alarm 310 INVALID G CODE); the NGC's own codes are [`HAAS_TABLE`]. Sorted.
pub const HAAS_HAS: &[u16] = &[
    0, 10, 20, 30, 40, 90, 100, 170, 180, 190, 200, 210, 280, 290, 310, 400, 410, 420, 430, 440, 490, 500, 510, 520,
    530, 540, 550, 560, 570, 580, 590, 600, 610, 640, 650, 680, 690, 730, 740, 760, 800, 810, 820, 830, 840, 850, 860,
    870, 880, 890, 900, 910, 920, 930, 940, 950, 980, 990,
];

const fn h(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: false, syntec_only: false, fanuc_only: false }
}
const fn hx(code: u16, group: usize) -> GDef {
    GDef { code, group, takes_axes: true, syntec_only: false, fanuc_only: false }
}

/// The Haas NGC mill's own codes: numbers FANUC does not have, or has with another function
/// (G35, G36, G37, G47, G161). Groups are fivex's (FANUC's numbers): the NGC's group 12 (work
/// offsets) is [`group::WORK_SYSTEM`]. Which of them fivex performs: `unbuilt` (G110–G129 and
/// G154 are the G54.1 P work offsets). Sorted by code.
pub const HAAS_TABLE: &[GDef] = &[
    hx(120, 0),  // G12 circular pocket milling CW
    hx(130, 0),  // G13 circular pocket milling CCW
    hx(350, 0),  // G35 automatic tool diameter measurement (probe)
    hx(360, 0),  // G36 automatic work offset measurement (probe)
    hx(370, 0),  // G37 automatic tool offset measurement (probe)
    h(470, 0),   // G47 text engraving
    hx(700, 0),  // G70 bolt hole circle
    hx(710, 0),  // G71 bolt hole arc
    hx(720, 0),  // G72 bolt holes along an angle
    h(770, 9),   // G77 back bore canned cycle
    h(1000, 22), // G100 mirror image cancel (of the axes named, or all)
    h(1010, 22), // G101 mirror image
    h(1030, 0),  // G103 limit block buffering
    h(1070, 0),  // G107 cylindrical mapping
    h(1100, 14), // G110 … G129: G154 P1 … P20
    h(1110, 14),
    h(1120, 14),
    h(1130, 14),
    h(1140, 14),
    h(1150, 14),
    h(1160, 14),
    h(1170, 14),
    h(1180, 14),
    h(1190, 14),
    h(1200, 14),
    h(1210, 14),
    h(1220, 14),
    h(1230, 14),
    h(1240, 14),
    h(1250, 14),
    h(1260, 14),
    h(1270, 14),
    h(1280, 14),
    h(1290, 14),
    h(1360, 0),  // G136 automatic work offset center measurement (probe)
    h(1410, 7),  // G141 3D+ cutter compensation
    h(1430, 8),  // G143 5-axis tool length compensation
    hx(1500, 0), // G150 general purpose pocket milling
    h(1530, 9),  // G153 5-axis high speed peck drilling
    h(1540, 14), // G154 P1–P99 work offsets
    h(1550, 9),  // G155 5-axis reverse tap
    h(1610, 9),  // G161 5-axis drill
    h(1620, 9),  // G162 5-axis spot drill
    h(1630, 9),  // G163 5-axis normal peck drilling
    h(1640, 9),  // G164 5-axis tapping
    h(1650, 9),  // G165 5-axis boring
    h(1660, 9),  // G166 5-axis bore and stop
    h(1690, 9),  // G169 5-axis bore and dwell
    h(1740, 0),  // G174 CCW non-vertical rigid tap
    h(1840, 0),  // G184 CW non-vertical rigid tap
    h(1870, 0),  // G187 smoothness level
    h(2340, 8),  // G234 tool center point control
    h(2530, 0),  // G253 orient spindle normal to the feature coordinate system
    h(2540, 23), // G254 dynamic work offset
    h(2550, 23), // G255 dynamic work offset cancel
    hx(2660, 0), // G266 visible axes linear rapid motion
    h(2680, 16), // G268 feature coordinate system
    h(2690, 16), // G269 feature coordinate system cancel
];

/// The definition of a G code, if the dialect has it.
pub fn lookup(code: u16, dialect: Dialect) -> Option<&'static GDef> {
    if dialect == Dialect::Haas {
        if let Ok(i) = HAAS_TABLE.binary_search_by_key(&code, |d| d.code) {
            return HAAS_TABLE.get(i);
        }
        // G54.1 is how fivex holds G154 P / G110–G129 (`haas_work_offset`); written, it is
        // refused (`written`).
        if code != code::G54_1 {
            HAAS_HAS.binary_search(&code).ok()?;
        }
    }
    let i = *INDEX.get(code as usize)?;
    let def = TABLE.get((i as usize).checked_sub(1)?)?;
    if def.syntec_only && dialect != Dialect::Syntec || def.fanuc_only && dialect == Dialect::Syntec {
        return None;
    }
    Some(def)
}

/// The definition of a G code as a program writes it: [`lookup`], except that the Haas dialect
/// has no G54.1 (its extra work offsets are G154 P and G110–G129), and that the Syntec dialect
/// reads G70/G71 as inch/metric input, G20/G21 (its definition's `code`: the block holds G20/G21).
pub fn written(code: u16, dialect: Dialect) -> Option<&'static GDef> {
    match (dialect, code) {
        (Dialect::Haas, code::G54_1) => None,
        // *Decision*, inferred: the Syntec 5-axis manual's worked program (§4.7.2) starts with
        // G71 where a metric program sets its units; no Syntec G-code list is among the sources
        // (`docs/dialects.md`, its opening paragraph).
        (Dialect::Syntec, code::G70) => lookup(code::G20, dialect),
        (Dialect::Syntec, code::G71) => lookup(code::G21, dialect),
        _ => lookup(code, dialect),
    }
}

/// The name a panel of `dialect` shows for `code` in force in its group: the dialect's own name
/// (the Haas NGC shows G154 where fivex holds G54.1 P), or `None` when the code is no code of
/// the dialect (the power-on state of a group the dialect does not have, such as FANUC's G15 or
/// G67 on a Haas control): a panel must not show a code its control does not have.
pub fn shown(code: u16, dialect: Dialect) -> Option<String> {
    match (dialect, code) {
        (Dialect::Haas, code::G54_1) => Some("G154".into()),
        // fivex holds the Haas mirror image as FANUC's programmable mirror image (`frames`).
        (Dialect::Haas, code::G51_1) => Some("G101".into()),
        (Dialect::Haas, code::G50_1) => Some("G100".into()),
        _ => written(code, dialect).map(|_| display(code)),
    }
}

/// The Haas work offset a code selects as G54.1's P: G154 (P given) → None, G110 … G129 →
/// Some(1 … 20) (the NGC's G110–G129 are G154 P1–P20).
pub fn haas_work_offset(code: u16) -> Option<Option<u16>> {
    match code {
        1540 => Some(None),
        1100..=1290 if code.is_multiple_of(10) => Some(Some((code - 1100) / 10 + 1)),
        _ => None,
    }
}

/// The G code value of a word as ×10, if it is an exact tenth (`G43.4` yes, `G43.45` no).
pub fn code_of(value: f64) -> Option<u16> {
    let x = value * 10.0;
    if !(-0.5..=9999.5).contains(&x) {
        return None;
    }
    // Rounded by adding ½ and truncating (x + ½ is not negative): `f64::round` is a library
    // call, and this runs for every G word.
    let r = (x + 0.5) as u16;
    if (x - r as f64).abs() > 1e-6 || r > 9999 {
        return None;
    }
    Some(r)
}

/// Power-on modal state (FANUC defaults with the usual parameter settings). Groups 23 (G54.2)
/// and 33 (G54.4) hold 0 while off: neither has a cancel code.
pub fn initial_modes() -> [u16; GROUPS] {
    use code::*;
    let mut m = [0u16; GROUPS];
    m[group::MOTION] = G00;
    m[group::PLANE] = G17;
    m[group::DISTANCE] = G90;
    m[group::STROKE_CHECK] = G22;
    m[group::FEED_MODE] = G94;
    m[group::UNITS] = G21;
    m[group::CUTTER_COMP] = G40;
    m[group::LENGTH_COMP] = G49;
    m[group::CYCLE] = G80;
    m[group::RETURN_LEVEL] = G98;
    m[group::SCALING] = G50;
    m[group::MODAL_CALL] = G67;
    m[group::SURFACE_SPEED] = G97;
    m[group::WORK_SYSTEM] = G54;
    m[group::PATH_MODE] = G64;
    m[group::ROTATION] = G69;
    m[group::POLAR] = G15;
    m[group::NORMAL_DIRECTION] = G40_1;
    m[group::IN_FEED] = G160;
    m[group::POLAR_INTERPOLATION] = G13_1;
    m[group::MIRROR] = G50_1;
    m[group::DYNAMIC_FIXTURE] = 0;
    m[group::SPEED_FLUCTUATION] = G25;
    m[group::EGB] = G80_5;
    m[group::WSE] = 0;
    m
}

/// `#4001`-style value of a stored code: 43.4 for 434.
pub fn as_number(code: u16) -> f64 {
    code as f64 / 10.0
}

/// Display form: "G43.4", "G01".
pub fn display(code: u16) -> String {
    if code.is_multiple_of(10) {
        format!("G{:02}", code / 10)
    } else {
        format!("G{:02}.{}", code / 10, code % 10)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_sorted_unique_and_indexed() {
        assert!(TABLE.windows(2).all(|w| w[0].code < w[1].code));
        assert!(TABLE.len() < u8::MAX as usize);
        assert_eq!(TABLE.last().map(|d| d.code as usize), Some(MAX_CODE));
        for d in TABLE {
            let dialect = if d.fanuc_only { Dialect::Fanuc } else { Dialect::Syntec };
            assert_eq!(lookup(d.code, dialect), Some(d));
        }
    }

    /// Each `code::` constant is the code its name says (`G43_4` is 434), in the table (of
    /// either dialect) and in the group it claims, so a mistyped constant cannot hide.
    #[test]
    fn a_panel_shows_the_dialect_s_codes_only() {
        assert_eq!(shown(code::G54_1, Dialect::Haas).as_deref(), Some("G154"));
        assert_eq!(shown(code::G54_1, Dialect::Fanuc).as_deref(), Some("G54.1"));
        assert_eq!(shown(code::G01, Dialect::Haas).as_deref(), Some("G01"));
        assert_eq!(shown(code::G234, Dialect::Haas).as_deref(), Some("G234"));
        assert_eq!(shown(code::G50_1, Dialect::Haas).as_deref(), Some("G100"));
        // FANUC's power-on G15 and G67 are no codes of the NGC.
        let initial = initial_modes();
        for g in [group::POLAR, group::MODAL_CALL] {
            assert!(shown(initial[g], Dialect::Fanuc).is_some());
            assert_eq!(shown(initial[g], Dialect::Haas), None, "group {g}");
        }
    }

    #[test]
    fn code_constants_are_the_table_s() {
        assert!(code::CLAIMS.len() > 100);
        for &(name, value, claimed) in code::CLAIMS {
            assert_eq!(display(value), name.replace('_', "."), "{name} = {value}");
            let def = [Dialect::Fanuc, Dialect::Syntec, Dialect::Haas].into_iter().find_map(|d| lookup(value, d));
            assert_eq!(def.map(|d| d.group), Some(claimed), "{name}: not in TABLE, or in another group");
        }
    }

    #[test]
    fn fanuc_groups() {
        let group = |c| lookup(c, Dialect::Fanuc).unwrap().group;
        assert_eq!(group(434), 8);
        assert_eq!(group(412), 7);
        assert_eq!(group(682), 16);
        assert_eq!(group(544), 33);
        assert_eq!(group(62), 1);
        assert_eq!(group(531), 0);
        assert!(lookup(533, Dialect::Fanuc).is_none());
        assert!(lookup(533, Dialect::Syntec).is_some());
        assert!(lookup(1000, Dialect::Fanuc).is_none());
        assert!(lookup(412, Dialect::Syntec).is_none());
        assert!(lookup(439, Dialect::Syntec).is_none());
        // Haas-only codes: not codes of the other dialects.
        for c in [120, 130, 700, 710, 720, 1030, 1500, 1870] {
            assert!(lookup(c, Dialect::Fanuc).is_none() && lookup(c, Dialect::Syntec).is_none(), "{c}");
            assert_eq!(lookup(c, Dialect::Haas).map(|d| d.group), Some(0), "{c}");
        }
    }

    #[test]
    fn haas_codes() {
        assert!(HAAS_TABLE.windows(2).all(|w| w[0].code < w[1].code));
        assert!(HAAS_HAS.windows(2).all(|w| w[0] < w[1]));
        let haas = |c| lookup(c, Dialect::Haas).map(|d| d.group);
        // FANUC's codes the NGC has, and its own.
        assert_eq!(haas(10), Some(1));
        assert_eq!(haas(650), Some(0));
        assert_eq!(haas(1540), Some(group::WORK_SYSTEM));
        assert_eq!(haas(1290), Some(group::WORK_SYSTEM));
        assert_eq!(haas(2340), Some(group::LENGTH_COMP));
        // G35/G36 are probing (one-shot) on the NGC, circular threading (motion) on FANUC.
        assert_eq!(haas(350), Some(0));
        assert_eq!(lookup(350, Dialect::Fanuc).map(|d| d.group), Some(1));
        // FANUC codes the NGC does not have.
        for c in [434, 435, 682, 51, 62, 121, 150, 160, 220, 300, 660, 661, 670, 960, 1600, 412, 533, 544] {
            assert_eq!(haas(c), None, "{}", display(c));
        }
        // G54.1 is fivex's form of G154 P, not a code a Haas program may write.
        assert_eq!(written(541, Dialect::Haas), None);
        assert_eq!(written(1540, Dialect::Haas).map(|d| d.group), Some(group::WORK_SYSTEM));
        assert_eq!(written(541, Dialect::Fanuc), lookup(541, Dialect::Fanuc));
        // Haas codes FANUC and Syntec do not have.
        for c in [120, 700, 1030, 1540, 1870, 2340, 2540] {
            assert!(lookup(c, Dialect::Fanuc).is_none() && lookup(c, Dialect::Syntec).is_none(), "{}", display(c));
        }
        assert_eq!(haas_work_offset(1100), Some(Some(1)));
        assert_eq!(haas_work_offset(1290), Some(Some(20)));
        assert_eq!(haas_work_offset(1540), Some(None));
        assert_eq!(haas_work_offset(540), None);
    }

    #[test]
    fn codes_and_display() {
        assert_eq!(code_of(43.4), Some(434));
        assert_eq!(code_of(1.0), Some(10));
        assert_eq!(code_of(43.45), None);
        assert_eq!(code_of(-1.0), None);
        assert_eq!(display(434), "G43.4");
        assert_eq!(display(10), "G01");
    }

    #[test]
    fn codes_round_like_f64_round() {
        let reference = |value: f64| {
            let x = value * 10.0;
            let r = x.round();
            ((x - r).abs() <= 1e-6 && (0.0..=9999.0).contains(&r)).then_some(r as u16)
        };
        for k in -2_000..1_100_000 {
            for v in [k as f64 / 1000.0, k as f64 / 10.0 + 1e-7, k as f64 / 10.0 - 1e-7, k as f64 / 10.0 + 0.05] {
                assert_eq!(code_of(v), reference(v), "{v}");
            }
        }
        for v in [f64::NAN, f64::INFINITY, -0.0, 999.9, 999.95, 1000.0, -0.04] {
            assert_eq!(code_of(v), reference(v), "{v}");
        }
    }
}
