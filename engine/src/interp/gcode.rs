//! The milling G-code set of the FANUC 30i-A5 (M series), grouped exactly as FANUC groups them,
//! with the Syntec-only and FANUC-only codes marked. Which of them fivex performs: `unbuilt`. G codes are held as their number ×10 (`G43.4` → 434).

use crate::dialect::Dialect;

/// Number of modal groups (FANUC numbers them 0..=33 on the 30i M series).
pub const GROUPS: usize = 34;

/// The non-modal (one-shot) group.
pub const ONE_SHOT: u8 = 0;

/// The modal groups by FANUC's numbers, as `State::modal` and the mode array index them.
pub mod group {
    /// G00, G01, G02, G03 … (interpolation).
    pub const MOTION: usize = 1;
    /// G17, G18, G19.
    pub const PLANE: usize = 2;
    /// G90, G91.
    pub const DISTANCE: usize = 3;
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
    /// G66, G66.1, G67.
    pub const MODAL_CALL: usize = 12;
    /// G54–G59, G54.1, G54.4 …
    pub const WORK_SYSTEM: usize = 14;
    /// G61, G62, G63, G64.
    pub const PATH_MODE: usize = 15;
    /// G68, G69, G68.2, G68.3, G68.4.
    pub const ROTATION: usize = 16;
    /// G15, G16.
    pub const POLAR: usize = 17;
    /// G50.1, G51.1.
    pub const MIRROR: usize = 22;
}

/// The G codes the interpreter names in its rules, held as their number ×10.
pub mod code {
    pub const G00: u16 = 0;
    pub const G02: u16 = 20;
    pub const G03: u16 = 30;
    pub const G16: u16 = 160;
    pub const G20: u16 = 200;
    pub const G21: u16 = 210;
    pub const G40: u16 = 400;
    pub const G43: u16 = 430;
    pub const G43_4: u16 = 434;
    pub const G43_5: u16 = 435;
    pub const G44: u16 = 440;
    pub const G49: u16 = 490;
    pub const G49_1: u16 = 491;
    pub const G50_1: u16 = 501;
    pub const G51_1: u16 = 511;
    pub const G61: u16 = 610;
    pub const G63: u16 = 630;
    pub const G66: u16 = 660;
    pub const G66_1: u16 = 661;
    pub const G67: u16 = 670;
    pub const G68: u16 = 680;
    pub const G69: u16 = 690;
    pub const G74: u16 = 740;
    pub const G80: u16 = 800;
    pub const G84: u16 = 840;
    pub const G91: u16 = 910;
    pub const G93: u16 = 930;
    pub const G99: u16 = 990;
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GDef {
    pub code: u16,
    pub group: u8,
    /// The block's axis words belong to this code rather than to the group-01 motion
    /// (G04, G10, G28, G52, G53, G92 …).
    pub takes_axes: bool,
    pub syntec_only: bool,
    /// A FANUC code the Syntec manual does not have (COR-070 in the Syntec dialect).
    pub fanuc_only: bool,
}

const fn g(code: u16, group: u8) -> GDef {
    GDef { code, group, takes_axes: false, syntec_only: false, fanuc_only: false }
}
const fn gx(code: u16, group: u8) -> GDef {
    GDef { code, group, takes_axes: true, syntec_only: false, fanuc_only: false }
}
const fn gsx(code: u16, group: u8) -> GDef {
    GDef { code, group, takes_axes: true, syntec_only: true, fanuc_only: false }
}
/// FANUC's 5-axis codes that the Syntec 5-axis manual does not list (its 5-axis functions are
/// RTCP/STCP G43.4/G43.5, G68.2/G68.3, the tool alignments G53.1/G53.3/G53.6 and the chains
/// G10 L5000): 3-D cutter compensation, cutting point command, G54.4, G68.4. Not codes of the
/// Syntec dialect (COR-070), rather than FANUC's behaviour under a Syntec name.
const fn gf(code: u16, group: u8) -> GDef {
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
    g(50, 0),    // G05 high-speed cycle / HPCC
    g(51, 0),    // G05.1 AI contour / smooth interpolation
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
    g(390, 0),   // G39 corner circular interpolation
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

/// The definition of a G code, if the dialect has it.
pub fn lookup(code: u16, dialect: Dialect) -> Option<&'static GDef> {
    let i = *INDEX.get(code as usize)?;
    let def = TABLE.get((i as usize).checked_sub(1)?)?;
    if def.syntec_only && dialect != Dialect::Syntec || def.fanuc_only && dialect != Dialect::Fanuc {
        return None;
    }
    Some(def)
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

/// Power-on modal state (FANUC defaults with the usual parameter settings).
pub fn initial_modes() -> [u16; GROUPS] {
    let mut m = [0u16; GROUPS];
    m[1] = 0; // G00
    m[2] = 170;
    m[3] = 900;
    m[4] = 220;
    m[5] = 940;
    m[6] = 210;
    m[7] = 400;
    m[8] = 490;
    m[9] = 800;
    m[10] = 980;
    m[11] = 500;
    m[12] = 670;
    m[13] = 970;
    m[14] = 540;
    m[15] = 640;
    m[16] = 690;
    m[17] = 150;
    m[19] = 401;
    m[20] = 1600;
    m[21] = 1310;
    m[22] = 501;
    m[23] = 0;
    m[24] = 250;
    m[25] = 805;
    m[33] = 0;
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
