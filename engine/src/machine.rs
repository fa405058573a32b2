//! The vendor-neutral machine description: its axes (kinds, strokes, speed, acceleration and jerk
//! limits, rollover) and its 5-axis mechanism (rotary axes, tool direction, offsets).
//!
//! `crate::kin` builds the kinematic model from it; `crate::vendor` maps FANUC and Syntec
//! parameter lists onto it and back. `docs/machine-config.md` documents every field.

use crate::alarm::AlarmId;
use serde::{Deserialize, Serialize};

/// At most this many controlled axes per machine.
pub const MAX_AXES: usize = 8;

#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "lowercase")]
pub enum AxisKind {
    Linear,
    Rotary,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Axis {
    /// Address letter: X Y Z U V W (linear) or A B C (rotary).
    #[cfg_attr(feature = "schema", schema(min_length = 1, max_length = 1))]
    pub name: char,
    pub kind: AxisKind,
    /// Rapid traverse rate, the axis's highest speed: mm/min or deg/min.
    pub rapid: f64,
    /// Highest acceleration, mm/s² or deg/s²; `None`: [`Axis::max_accel`]'s default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accel: Option<f64>,
    /// Highest jerk, mm/s³ or deg/s³; `None`: [`Axis::max_jerk`]'s default.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub jerk: Option<f64>,
    /// Stored stroke limit `[negative, positive]` in machine coordinates, mm or deg; `None`: none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub stroke: Option<[f64; 2]>,
    /// Rotary axes: positions roll over at 360° (shown and kept in [0, 360)).
    #[serde(default, skip_serializing_if = "is_false")]
    pub rollover: bool,
    /// Rollover axes: an absolute command takes the shorter way round; otherwise the sign of the
    /// command gives the direction.
    #[serde(default, skip_serializing_if = "is_false")]
    pub shortest: bool,
    /// The 2nd, 3rd and 4th reference positions in machine coordinates (G30 P2/P3/P4; FANUC
    /// No.1241–1243); the 1st (G28) is machine zero.
    #[serde(default, skip_serializing_if = "no_references")]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub references: [f64; 3],
    /// Rotary axes: how far nano smoothing for 5-axis machining (G05.1 Q3) may correct the
    /// axis's programmed positions, degrees; 0: the least input increment, 0.001° (FANUC
    /// No.19587).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub smoothing_tolerance: f64,
    /// Time constant of the acceleration/deceleration *after* interpolation of cutting feed,
    /// milliseconds (FANUC No.1622); 0: none. It acts only where look-ahead is off
    /// (`motion.look_ahead_by_command` before G05.1 Q1 or after G05.1 Q0): the axis's
    /// interpolated positions then pass through the filter of `motion.after_interpolation`
    /// (`docs/motion.md`, "Without look-ahead").
    #[serde(default, skip_serializing_if = "is_zero")]
    pub after_interpolation_ms: f64,
    /// Time constants of rapid traverse's acceleration/deceleration after interpolation,
    /// milliseconds: `[T1, T2]`, linear over T1 (FANUC No.1620), bell-shaped by T2 more
    /// (No.1621); `[0, 0]`: none. They act only on rapids without look-ahead (G05.1 Q0, or
    /// `motion.no_rapid_look_ahead`).
    #[serde(default, skip_serializing_if = "no_time_constants")]
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub rapid_after_interpolation_ms: [f64; 2],
}

fn no_time_constants(t: &[f64; 2]) -> bool {
    *t == [0.0; 2]
}

fn no_references(r: &[f64; 3]) -> bool {
    *r == [0.0; 3]
}

fn is_false(b: &bool) -> bool {
    !*b
}

/// How near its reference position an axis must stand for G27's check to pass, mm or degrees:
/// half the least input increment of IS-B (`docs/conventions.md`, "G27").
const REFERENCE_CHECK_WIDTH: f64 = 0.0005;

impl Axis {
    /// An axis with the default limits.
    pub fn new(name: char, kind: AxisKind, rapid: f64) -> Axis {
        Axis {
            name,
            kind,
            rapid,
            accel: None,
            jerk: None,
            stroke: None,
            rollover: false,
            shortest: false,
            references: [0.0; 3],
            smoothing_tolerance: 0.0,
            after_interpolation_ms: 0.0,
            rapid_after_interpolation_ms: [0.0; 2],
        }
    }

    /// Highest acceleration: the configured one, else 0.2 s from standstill to rapid.
    pub fn max_accel(&self) -> f64 {
        self.accel.unwrap_or(self.rapid / 60.0 / 0.2)
    }

    /// Highest jerk: the configured one, else the acceleration reached in 50 ms.
    pub fn max_jerk(&self) -> f64 {
        self.jerk.unwrap_or(self.max_accel() / 0.05)
    }

    /// Where a reference return (G28, G30, manual REF) from `from` ends on this axis, the
    /// reference being `reference` in machine coordinates: there on a linear-type axis; on a
    /// rollover axis, whose positions stay unwound in the engine, the reference's angle less
    /// than a turn away (`angle::reference_travel`, positive; the shorter way in the Haas
    /// dialect): the return does not unwind the turns made.
    pub fn reference_return_end(&self, from: f64, reference: f64, dialect: crate::Dialect) -> f64 {
        if self.rollover {
            from + crate::angle::reference_travel(from, reference, dialect == crate::Dialect::Haas)
        } else {
            reference
        }
    }

    /// Whether the machine coordinate `at` is the reference position `reference` (G27's
    /// check): within half the least input increment (0.0005 mm or degree), on a rollover axis
    /// in any turn.
    pub fn at_reference(&self, at: f64, reference: f64) -> bool {
        let off = at - reference;
        let off = if self.rollover { off - 360.0 * (off / 360.0).round() } else { off };
        off.abs() <= REFERENCE_CHECK_WIDTH
    }

    /// Where a move to the machine coordinate `command` (G53) from `from` ends on this axis:
    /// there on a linear-type axis; on a rollover axis the command's angle the way an absolute
    /// command takes (`angle::rollover_travel`), not back over the turns made.
    pub fn machine_command_end(&self, from: f64, command: f64) -> f64 {
        if self.rollover {
            from + crate::angle::rollover_travel(from, command, self.shortest)
        } else {
            command
        }
    }
}

/// A machine description that cannot work: the alarm the vendor's control raises for it (if
/// it is a mechanism error) and what exactly is wrong.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigError {
    pub alarm: Option<AlarmId>,
    pub detail: String,
}

impl ConfigError {
    /// An error of the file or parameter values themselves (refused at input).
    pub fn invalid(detail: impl Into<String>) -> ConfigError {
        ConfigError { alarm: None, detail: detail.into() }
    }

    /// A mechanism the control refuses with an alarm.
    pub fn alarm(alarm: AlarmId, detail: impl Into<String>) -> ConfigError {
        ConfigError { alarm: Some(alarm), detail: detail.into() }
    }

    /// The message for a given dialect: the vendor's code and text, then the detail.
    pub fn describe(&self, dialect: crate::Dialect) -> String {
        match &self.alarm {
            Some(id) => {
                let (code, message) = dialect.describe(id);
                format!("{code} {message}: {}", self.detail)
            }
            None => self.detail.clone(),
        }
    }
}

impl std::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.detail)
    }
}

/// Which part of the machine a rotary axis turns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// Tool side (head): turns the spindle.
    Head,
    /// Workpiece side (table): turns the part.
    Table,
}

/// Rotation sense about the axis direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "lowercase")]
pub enum Hand {
    Right,
    Left,
}

/// One rotary axis in the mechanism chain.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct RotaryLink {
    /// The axis letter (must be a rotary axis of `axes`).
    #[cfg_attr(feature = "schema", schema(min_length = 1, max_length = 1))]
    pub axis: char,
    pub side: Side,
    /// Direction the axis turns about, machine coordinates at zero angles (normalised on use).
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub direction: [f64; 3],
    pub hand: Hand,
    /// A point on the axis line at zero angles, mm: relative to the carriage reference point
    /// (the X/Y/Z position) for a head axis, in machine coordinates for a table axis.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub point: [f64; 3],
    /// Added to the commanded angle (the axis's zero-point error), degrees.
    #[serde(default)]
    pub zero_offset: f64,
    /// The angle of a hypothetical axis (one the machine does not have as a controlled axis).
    #[serde(default)]
    pub fixed: Option<f64>,
    /// Movement range `[low, high]` of commanded angles, degrees.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub range: Option<[f64; 2]>,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct MachineConfig {
    pub name: String,
    pub axes: Vec<Axis>,
    /// Rotary axes from the machine base outward: head links from the column to the spindle,
    /// table links from the bed to the table top (so the master axis comes first on each side).
    #[serde(default)]
    pub rotary: Vec<RotaryLink>,
    /// Tool direction (tip → holder) with every head axis at zero, machine coordinates.
    #[serde(default = "plus_z")]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub tool_axis: [f64; 3],
    /// The spindle nose (gauge point) relative to the carriage reference point at zero angles,
    /// mm (e.g. `-pivot · tool_axis` when X/Y/Z locate the head's pivot).
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub nose: [f64; 3],
    /// Tool holder offset, mm: from the spindle nose along the tool direction to the head's
    /// controlled point (FANUC No.19666, Syntec Pr3013). The mechanism's geometry is all in
    /// `nose` and the axis points; this records how the vendor's parameters split it.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub holder: f64,
    /// Sub-chains 2–4 of this main mechanism (Syntec `G10 L5000 P1 Q2..Q4`; a spindle-type
    /// mechanism only): head attachments. Absent: none (`docs/machine-config.md`, chains).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sub_chains: Vec<SubChain>,
    /// Further mechanism chains, Syntec's sets 2–4 (`G10 L5000 P2..P4`), each a whole mechanism
    /// as the fields above describe the main one, set 1. Absent: the one chain above.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub chains: Vec<ChainSet>,
    /// How the control interpolates (`docs/motion.md`).
    #[serde(default, skip_serializing_if = "MotionOptions::is_default")]
    pub motion: MotionOptions,
    /// How the 5-axis functions behave (`docs/five-axis.md`).
    #[serde(default, skip_serializing_if = "FiveAxisOptions::is_default")]
    pub five_axis: FiveAxisOptions,
    /// How the 5-axis manual feeds behave (`docs/five-axis.md`, 5-axis manual operation).
    #[serde(default, skip_serializing_if = "ManualOptions::is_default")]
    pub manual: ManualOptions,
    /// The canned cycles' settings (`docs/conventions.md`, canned cycles).
    #[serde(default, skip_serializing_if = "CycleOptions::is_default")]
    pub cycles: CycleOptions,
}

/// The canned cycles' machine settings.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct CycleOptions {
    /// G73's retract after each peck, mm (FANUC No.5114).
    #[serde(default = "default_peck_distance")]
    pub peck_retract: f64,
    /// G83's clearance: the rapid back into the hole stops this far above the last peck's
    /// bottom, mm (FANUC No.5115).
    #[serde(default = "default_peck_distance")]
    pub peck_clearance: f64,
    /// The direction of G76's and G87's shift Q, as in G17 (FANUC No.5101#4 RD1, #5 RD2).
    #[serde(default)]
    pub bore_shift: BoreShift,
}

/// G73's retract and G83's clearance when a machine does not set them, mm.
pub const DEFAULT_PECK_DISTANCE: f64 = 0.5;

/// The largest G73 retract or G83 clearance a machine may set, mm (FANUC's real parameters
/// take far more; beyond this it is a typing error, not a clearance).
pub const MAX_PECK_DISTANCE: f64 = 100.0;

fn default_peck_distance() -> f64 {
    DEFAULT_PECK_DISTANCE
}

impl Default for CycleOptions {
    fn default() -> Self {
        CycleOptions {
            peck_retract: DEFAULT_PECK_DISTANCE,
            peck_clearance: DEFAULT_PECK_DISTANCE,
            bore_shift: BoreShift::default(),
        }
    }
}

impl CycleOptions {
    fn is_default(&self) -> bool {
        *self == CycleOptions::default()
    }
}

/// The direction of G76's and G87's shift, named as in G17; in G18 and G19 the plane's first
/// and second axes take X's and Y's place (FANUC: +X/−X/+Y/−Y in G17 are +Z/−Z/+X/−X in G18 and
/// +Y/−Y/+Z/−Z in G19).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub enum BoreShift {
    #[default]
    #[serde(rename = "+x")]
    PlusX,
    #[serde(rename = "-x")]
    MinusX,
    #[serde(rename = "+y")]
    PlusY,
    #[serde(rename = "-y")]
    MinusY,
}

impl BoreShift {
    /// Whether the shift is along the plane's second axis, and its sign.
    pub fn in_plane(self) -> (bool, f64) {
        match self {
            BoreShift::PlusX => (false, 1.0),
            BoreShift::MinusX => (false, -1.0),
            BoreShift::PlusY => (true, 1.0),
            BoreShift::MinusY => (true, -1.0),
        }
    }
}

/// A further mechanism chain (Syntec set 2, 3 or 4, type parameter Pr3101 / Pr5501 / Pr5601):
/// the rotary mechanism described as the main fields of [`MachineConfig`] describe set 1. The
/// machine's axes are shared: a chain names which of them it turns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct ChainSet {
    /// The set number, 2 to 4 (`G10 L5000 P_`).
    pub set: u8,
    /// As [`MachineConfig::rotary`]; at least one link (a set without is not configured).
    pub rotary: Vec<RotaryLink>,
    #[serde(default = "plus_z")]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub tool_axis: [f64; 3],
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub nose: [f64; 3],
    #[serde(default, skip_serializing_if = "is_zero")]
    pub holder: f64,
    /// This set's sub-chains 2–4 (spindle type only), as [`MachineConfig::sub_chains`].
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sub_chains: Vec<SubChain>,
}

/// A sub-kinematic chain of a spindle-type set (Syntec `G10 L5000 P_ Q2..Q4`): a head
/// attachment carried after the set's last head axis, so it changes only what is beyond that
/// axis — the tool direction, the spindle nose and the holder offset; the rotary links stay the
/// set's. *Decision* (spec Q-21: the manual does not describe sub-chains): Q0 and Q1 are the set
/// as described, Q2–Q4 the listed attachments.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct SubChain {
    /// The Q that selects it, 2 to 4.
    pub q: u8,
    #[serde(default = "plus_z")]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub tool_axis: [f64; 3],
    #[serde(default)]
    #[cfg_attr(feature = "schema", schema(min_items = 3, max_items = 3))]
    pub nose: [f64; 3],
    #[serde(default, skip_serializing_if = "is_zero")]
    pub holder: f64,
}

/// Which mechanism chain is in use: Syntec's set (1–4) and sub-chain (1: the set as described,
/// 2–4 an attachment), chosen by `G10 L5000 P_ [Q_]`; set 1, sub-chain 1 at power-on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub struct Chain {
    pub set: u8,
    pub sub: u8,
}

impl Chain {
    /// Set 1 as described: the machine's main mechanism.
    pub const MAIN: Chain = Chain { set: 1, sub: 1 };
}

impl Default for Chain {
    fn default() -> Chain {
        Chain::MAIN
    }
}

/// Which coordinate system the X/Y/Z of a tool centre point control program are in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "kebab-case")]
pub enum TcpCoordinates {
    /// Fixed on the table as it stands when G43.4/G43.5 starts (FANUC WKP = 0, INZ = 0;
    /// Syntec Pr3055 = 0).
    #[default]
    TableAtStart,
    /// Fixed on the table as it stands with the table axes at program zero (FANUC INZ = 1;
    /// Syntec Pr3055 = 1, the rotary axes' work offsets).
    TableAtZero,
    /// The workpiece coordinate system, not turning with the table (FANUC WKP = 1).
    Workpiece,
}

/// 5-axis function settings of the control (vendor bits, `docs/five-axis.md`).
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct FiveAxisOptions {
    /// The programming coordinate system of tool centre point control.
    #[serde(default)]
    pub tcp_coordinates: TcpCoordinates,
    /// Tool posture control when G43.4/G43.5 has no P (FANUC No.19604#0 TPC; Syntec Pr3054 = 1
    /// tool-vector interpolation).
    #[serde(default)]
    pub posture_control: bool,
    /// Judge the second rotary axis's movement first when choosing angles (FANUC No.19608#5 PRI).
    #[serde(default)]
    pub second_axis_first: bool,
    /// Rotary-only moves under tool centre point control run at F (FANUC No.19696#6 RFC = 1);
    /// otherwise as fast as the axes go.
    #[serde(default)]
    pub rotary_feed: bool,
    /// G68.2 and G68.4 may be given while a tilted working plane is active (FANUC No.11221#0
    /// MTW: multiple tilted working planes); otherwise they raise the mode alarm there.
    #[serde(default)]
    pub multiple_planes: bool,
    /// The least distance, mm, of each of the three points of G68.2 P2 from the line through
    /// the other two (FANUC No.11220, "unstable plane"); 0: only points on one line are refused.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub plane_min_distance: f64,
    /// What a reset does to a tilted working plane.
    #[serde(default)]
    pub plane_after_reset: PlaneAfterReset,
    /// G54.4 tool direction compensation: the rotary axes keep the programmed tool direction
    /// relative to the displaced workpiece (FANUC No.11200#0 RCM).
    #[serde(default)]
    pub tool_direction_compensation: bool,
    /// Angle to the singular posture within which G54.4 takes the tool as singular, degrees
    /// (FANUC No.11204; 0: exact test).
    #[serde(default)]
    pub singular_tolerance_deg: f64,
    /// Type 2 with tool posture control: a line whose posture passes nearer the singular
    /// posture than this angle (degrees) ends through it instead (FANUC No.19738; 0: never).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub singular_angle: f64,
    /// The largest workpiece-side deviation (degrees) that change may make (FANUC No.19739).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub singular_tolerance: f64,
    /// A refused change raises an alarm instead of running the block unchanged (FANUC
    /// No.19696#3 NPC).
    #[serde(default)]
    pub singular_alarm: bool,
    /// Type 2: the programmable mirror image of the linear axes mirrors I, J, K too (FANUC
    /// No.19608#6 MIR).
    #[serde(default)]
    pub mirror_direction: bool,
    /// With Π fixed on the table, the absolute position shows the tool tip in the workpiece
    /// system instead of in Π (FANUC No.19608#2 DET).
    #[serde(default)]
    pub display_workpiece: bool,
    /// Lower the speed of tool centre point moves so that the tip's path deviation stays within
    /// `rapid_deviation` / `cutting_deviation` (FANUC No.19746#6 CRS; `docs/five-axis.md`).
    #[serde(default)]
    pub deviation_clamp: bool,
    /// mm; 0: the least input increment (0.001 mm); negative: no clamp (FANUC No.19751).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rapid_deviation: f64,
    /// The same for cutting feed (FANUC No.19752).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cutting_deviation: f64,
    // --- G54.4 (workpiece setting error compensation), `docs/five-axis.md` ----------------
    /// Tool length offsets move the axes instead of shifting the coordinate system (FANUC
    /// No.5006#6 TOS = 0): a G43/G44/G49 or H block moves the axis by the offset. False (TOS =
    /// 1): such a block moves nothing by itself (`docs/five-axis.md`, "TOS"). G54.4 refuses a
    /// tool length offset or TCP started inside it with this setting (PS0438, WSE-24).
    #[serde(default, skip_serializing_if = "is_false")]
    pub length_offset_by_motion: bool,
    /// The tool side offset's interference check at a change of the compensation plane looks at
    /// corners where the tool turns by this angle or more, degrees (FANUC No.19635; 0: 45°).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub plane_change_angle: f64,
    /// The leading edge offset counts the angle between the tool and the next move as 0°, 90°
    /// or 180° within this many degrees of them (FANUC No.19631, Δθ; 0: exact).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub leading_edge_tolerance: f64,
    /// Cutting point control (G43.8/G43.9) counts a square or bull-nose end mill as near its
    /// singular posture when the tool is within this angle of the surface normal, degrees, and
    /// then holds the vector from the cutting point to the tool tip (FANUC No.11262, 0 to 90;
    /// 0: no singular posture).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cutting_point_singular_angle: f64,
    /// On a machine with a rotary table, 5-axis cutter compensation takes the table coordinate
    /// system as its programming coordinate system when tool centre point control does (FANUC
    /// No.19746#4 TBP = 1 with WKP = 0, CRC-38); otherwise the workpiece system (TBP = 0,
    /// CRC-39). fivex performs it under TCP only (`docs/cutter-compensation.md`, rule 8).
    #[serde(default, skip_serializing_if = "is_false")]
    pub crc_table_coordinates: bool,
    /// The tool side offset's G codes follow the mechanism (FANUC No.19607#1 SPG = 1): G41.4/
    /// G42.4 on a table rotation machine, G41.5/G42.5 on a mixed one, G41.2/G42.2 on a head
    /// machine; off (SPG = 0): G41.2/G42.2 on every machine (CRC-31, CRC-32, TV-17).
    #[serde(default, skip_serializing_if = "is_false")]
    pub crc_codes_by_mechanism: bool,
    /// The tool side offset's interference check is made in the compensation plane (the plane
    /// perpendicular to the tool) on every machine type (FANUC No.19608#1 NI5 = 1, CRC-40, §3.4);
    /// off (NI5 = 0): the §3.5.1 check on the programmed positions and the vectors in 3-D
    /// (CRC-43), under which the tool side offset does not avoid interference
    /// (`docs/cutter-compensation.md`, "Tool side offset", rule 12).
    #[serde(default, skip_serializing_if = "is_false")]
    pub crc_check_in_plane: bool,
    /// Interference avoidance of the tool side offset: the largest angle, degrees, between the
    /// tool at the end of the block before the interfering ones and at the start of the block
    /// after them for which the avoidance vector is made (FANUC No.19636, CRC-41; 0 to 180);
    /// a larger turn keeps the plain vectors. 0 (a cleared parameter): the tool must not turn.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub avoidance_max_tool_angle: f64,
    /// Which FANUC control's 3-D cutter compensation the tool side offset follows: the 30i's
    /// (the default) or, as a compatibility setting, the 16i-MA/MB's (A-78438E; FANUC lists: a
    /// list holding No.19605 or No.19630 is a 16i's). `docs/cutter-compensation.md`, "16i
    /// variant".
    #[serde(default, skip_serializing_if = "CrcVariant::is_30i")]
    pub crc_variant: CrcVariant,
    /// 16i only: the tool side offset skips its interference check at a change of the
    /// compensation plane (FANUC 16i No.19605#5 NIC = 1).
    #[serde(default, skip_serializing_if = "is_false")]
    pub plane_change_check_off: bool,
    /// 16i only: a block whose move in its compensation plane is this short or shorter, mm,
    /// counts as a block without movement in the tool side offset's intersection calculation (FANUC
    /// 16i No.19630; 0: only a block that does not move in the plane).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub non_movement_limit: f64,
    /// The tool side offset (G41.2/G42.2) places its vectors at the cutting point this far
    /// along the tool from the programmed (pivot) point, mm (FANUC No.19632, CRC-30: the
    /// point is Q + d·(tool direction, tip → holder), the manual's formula); 0: at the
    /// programmed point.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cutting_point_distance: f64,
    /// G54.4: the rapid portions of hole-machining canned cycles run as cutting moves at this
    /// feed, mm/min (FANUC No.5412, WSE-19); 0: at the dry run rate (`manual.dry_run_feed`,
    /// No.1410); both 0: they stay rapids.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub wse_cycle_feed: f64,
    /// G54.4 with tool direction compensation: the rotary axes of a compensated cutting move
    /// (rapid) turn at most this percentage of their rate (FANUC No.11202 / No.11203, WSE-24;
    /// 0: not clamped).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub wse_feed_clamp_pct: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub wse_rapid_clamp_pct: f64,
    /// G54.4: the absolute position shows the workpiece coordinate system instead of the
    /// workpiece setting coordinate system (FANUC No.3106#6 DAK = 1, WSE-18).
    #[serde(default, skip_serializing_if = "is_false")]
    pub wse_display_wcs: bool,
    // --- Syntec STCP (smooth tool centre point control, SYN-09) ---------------------------------
    /// STCP is on with G43.4 without L (Syntec Pr3051 = 1; `L0` turns it off): RTCP whose tip
    /// path and tool orientation are smoothed (`docs/motion.md`, "Nano smoothing").
    #[serde(default, skip_serializing_if = "is_false")]
    pub smooth_tcp: bool,
    /// STCP's rotary axis tolerances, degrees, master / slave (Syntec Pr3052 / Pr3053; absent:
    /// the control's default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schema(min_items = 2, max_items = 2))]
    pub smooth_tolerance: Option<[f64; 2]>,
    /// STCP's tip path tolerance, mm (Syntec Pr407, "HPCC smoothing tolerance", 2–20 µm;
    /// absent: the control's default 3 µm).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub smooth_path_tolerance: Option<f64>,
}

/// Syntec's defaults of Pr3052/3053 (0.5°) and Pr407 (3 µm).
pub const STCP_ROTARY_TOLERANCE_DEG: f64 = 0.5;
pub const STCP_PATH_TOLERANCE_MM: f64 = 0.003;

/// The FANUC control whose 3-D cutter compensation (tool side offset) is followed
/// (`five_axis.crc_variant`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
pub enum CrcVariant {
    /// FANUC 30i-A: the interference check by No.19608#1 NI5, avoidance by No.19607#5 CAV
    /// with No.19636.
    #[default]
    #[serde(rename = "30i")]
    Fanuc30i,
    /// FANUC 16i-MA/MB (A-78438E): the check always in the compensation plane, no avoidance,
    /// No.19605#5 NIC and No.19630.
    #[serde(rename = "16i")]
    Fanuc16i,
}

impl CrcVariant {
    pub fn is_30i(&self) -> bool {
        *self == CrcVariant::Fanuc30i
    }
}

/// What a reset (and a restart of the controller) does to the tilted working plane.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "kebab-case")]
pub enum PlaneAfterReset {
    /// Reset cancels it as G69 does (FANUC No.5400#2 D3R = 0; Syntec Pr3014 = 0).
    #[default]
    Cancelled,
    /// It stays through reset; only G69 ends it (D3R = 1; Pr3014 = 1).
    Kept,
    /// It stays through reset and through a restart of the controller (Syntec Pr3014 = 2).
    KeptOverRestart,
}

impl FiveAxisOptions {
    fn is_default(&self) -> bool {
        *self == FiveAxisOptions::default()
    }
}

/// Interpolation choices the vendors make by parameter.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct MotionOptions {
    /// Helical interpolation: F is the speed along the whole tool path, the linear axes
    /// included (FANUC No.1403#5 HTG = 1), instead of along the arc (HTG = 0, the default).
    #[serde(default)]
    pub helical_feed_on_path: bool,
    /// Rapids move every axis at its own rapid rate, each starting and stopping on its own
    /// (FANUC No.1401#1 LRP = 0: non-linear type); by default the rapid is a straight line in
    /// axis space (LRP = 1, which the 5-axis functions require).
    #[serde(default)]
    pub nonlinear_rapid: bool,
    /// Seconds an M06 tool change takes (the machine's changer and PMC, not a CNC parameter;
    /// neither vendor's parameter list carries it).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tool_change_s: f64,
    // --- acceleration/deceleration before interpolation (look-ahead) ----------------------
    // Where look-ahead is off by these, cutting feed moves through the filter after
    // interpolation if the axes have time constants (`Axis::after_interpolation_ms`;
    // `docs/motion.md`, "Without look-ahead"), otherwise with look-ahead as on every machine;
    // either way the functions needing look-ahead refuse (G54.4 with tool direction
    // compensation: PS0438, `docs/five-axis.md`).
    /// Look-ahead is on only between G05.1 Q1 and G05.1 Q0 (FANUC AI contour control with
    /// No.1604#0 SHP = 0); by default it is on from power-on (SHP = 1).
    #[serde(default, skip_serializing_if = "is_false")]
    pub look_ahead_by_command: bool,
    /// Cutting feed has no acceleration/deceleration before interpolation (FANUC No.1660 = 0
    /// on every axis).
    #[serde(default, skip_serializing_if = "is_false")]
    pub no_feed_look_ahead: bool,
    /// Rapid traverse has none (FANUC No.19501#5 FRP = 0, or No.1671 = 0 on every axis).
    #[serde(default, skip_serializing_if = "is_false")]
    pub no_rapid_look_ahead: bool,
    /// Programs start in inch (G20) at power on and after a restart, instead of mm (G21)
    /// (FANUC No.0000#2 INI, the setting of the input unit).
    #[serde(default, skip_serializing_if = "is_false")]
    pub power_on_inch: bool,
    /// FANUC: a reset keeps the common variables #100–#199 (and #100000–#199999) instead of
    /// clearing them to vacant (No.6001#6 CCV = 1; 0, the default, clears them). The Haas
    /// NGC keeps them always; on Syntec they are a program's locals, vacant at each start.
    #[serde(default, skip_serializing_if = "is_false")]
    pub commons_kept_at_reset: bool,
    /// Cutter compensation C starts up and cancels by type B (FANUC No.5003#0 SUP = 1): at an
    /// outside corner the start-up block ends at the vector perpendicular to itself and the
    /// cancel block starts at the vector perpendicular to itself, the corner's own vectors
    /// between; by default type A (SUP = 0). `docs/cutter-compensation.md`.
    #[serde(default, skip_serializing_if = "is_false")]
    pub cutter_startup_type_b: bool,
    /// Cutter compensation C starts up and cancels "perpendicular to the next movement"
    /// (FANUC No.5003#1 SUV = 1): a G41/G42 block in G00/G01 without an axis word of the plane
    /// is followed by a straight move of the offset value perpendicular to the next block's
    /// start; a G40 block in G00/G01 without an axis word moves straight back from the vector
    /// perpendicular to the block before. A start-up or cancel block that moves in the plane
    /// starts up or cancels by type A or B (`cutter_startup_type_b`).
    /// `docs/cutter-compensation.md`.
    #[serde(default, skip_serializing_if = "is_false")]
    pub cutter_startup_perpendicular: bool,
    /// Cutter compensation C avoids an interference instead of stopping with PS0041 (FANUC
    /// No.19607#5 CAV = 1): a block whose compensated path runs against its programmed one is
    /// given no vector of its own, and the block before it ends where its offset path crosses
    /// the offset path of the block after it (of the next good block, over two consecutive
    /// interfering blocks); where they do not cross, or the new path would come within the
    /// radius of the blocks it replaced, PS0041 at the block before (or at the block that would
    /// come within it); three consecutive interfering blocks: PS0041 at the first. `docs/cutter-compensation.md`.
    #[serde(default, skip_serializing_if = "is_false")]
    pub cutter_interference_avoidance: bool,
    /// How nano smoothing (G05.1 Q3) builds its curve (`docs/motion.md`, "Nano smoothing").
    #[serde(default, skip_serializing_if = "NanoSmoothing::is_default")]
    pub nano_smoothing: NanoSmoothing,
    /// The type of cutting feed's acceleration/deceleration after interpolation, whose time
    /// constants are the axes' `after_interpolation_ms` (FANUC No.1610#0 CTL, #1 CTB; both 0,
    /// FANUC's default: exponential).
    #[serde(default, skip_serializing_if = "AfterInterpolation::is_default")]
    pub after_interpolation: AfterInterpolation,
}

/// An axis's rapid rate, mm/min or °/min: fivex's bounds, far beyond any machine either way
/// (10 km/min), inside which the planner's arithmetic holds. The defaults an axis's
/// acceleration and jerk take from it stay inside theirs.
pub const RAPID_RANGE: (f64, f64) = (1.0, 1e7);
/// An axis's acceleration, mm/s² or °/s² (fivex's bounds, as [`RAPID_RANGE`]).
pub const ACCEL_RANGE: (f64, f64) = (0.01, 1e8);
/// An axis's jerk, mm/s³ or °/s³ (fivex's bounds, as [`RAPID_RANGE`]).
pub const JERK_RANGE: (f64, f64) = (0.01, 1e10);

/// Highest time constant of acceleration/deceleration after interpolation, ms (fivex's bound:
/// the filter keeps one position per millisecond of it).
pub const MAX_AFTER_INTERPOLATION_MS: f64 = 4000.0;

/// The filter of acceleration/deceleration after interpolation (`motion::after`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "kebab-case")]
pub enum AfterInterpolation {
    /// First order: each step of the axis's speed is followed as 1 − e^(−t/T) (No.1610 CTL = 0,
    /// CTB = 0).
    #[default]
    Exponential,
    /// The speed follows a step linearly over T: a moving average of the positions over T
    /// (CTL = 1).
    Linear,
    /// Bell-shaped: the speed reaches half the step at T/2 along a parabola, all of it at T:
    /// two moving averages over T/2 (CTB = 1).
    Bell,
}

impl AfterInterpolation {
    fn is_default(&self) -> bool {
        *self == AfterInterpolation::default()
    }
}

/// The settings of nano smoothing (FANUC G05.1 Q3) for the linear axes: fivex's, as FANUC's
/// numbers and defaults for the conventional function are not in its sources (the rotary
/// axes' tolerance is FANUC No.19587, [`Axis::smoothing_tolerance`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields, default)]
pub struct NanoSmoothing {
    /// How far a programmed point may be corrected, and the tool path leave the programmed
    /// segments (3-D distance of the linear axes, mm, > 0).
    pub tolerance: f64,
    /// Blocks shorter than this (mm) are not smoothed.
    pub min_block: f64,
    /// Blocks longer than this (mm) are not smoothed.
    pub max_block: f64,
    /// A point where the path turns by more than this (degrees) is a corner, kept.
    pub corner_angle: f64,
    /// A point between blocks whose lengths differ by more than this factor is kept.
    pub spacing_ratio: f64,
}

impl Default for NanoSmoothing {
    fn default() -> Self {
        NanoSmoothing { tolerance: 0.01, min_block: 0.0, max_block: 5.0, corner_angle: 30.0, spacing_ratio: 5.0 }
    }
}

impl NanoSmoothing {
    fn is_default(&self) -> bool {
        *self == NanoSmoothing::default()
    }
}

impl FiveAxisOptions {
    /// 5-axis cutter compensation works in the table coordinate system (TBP = 1, WKP = 0, on a
    /// machine with a rotary table: the caller checks the mechanism).
    pub fn crc_in_table(&self) -> bool {
        self.crc_table_coordinates && self.tcp_coordinates != TcpCoordinates::Workpiece
    }
}

impl MotionOptions {
    fn is_default(&self) -> bool {
        *self == MotionOptions::default()
    }

    /// Acceleration/deceleration before interpolation is set up for cutting feed and rapids.
    pub fn look_ahead_set_up(&self) -> bool {
        !self.no_feed_look_ahead && !self.no_rapid_look_ahead
    }
}

/// Settings of the 5-axis manual feeds (tool axis, right-angle, table directions, tool tip
/// centre rotation; FANUC S000-IV, `fanuc-twp-wsec-manual-params.md` MAN-05…MAN-17).
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(deny_unknown_fields)]
pub struct ManualOptions {
    /// Tool length the manual feeds use, mm (FANUC No.12318).
    #[serde(default)]
    pub tool_length: f64,
    /// Use the tool length offset data while an offset is active (FANUC No.19746#2 LOD).
    #[serde(default)]
    pub length_from_offset: bool,
    /// With `length_from_offset` and no offset active: length 0 instead of `tool_length`
    /// (FANUC No.19746#3 LOZ).
    #[serde(default)]
    pub zero_length_without_offset: bool,
    /// In a tilted working plane the feeds move along the feature coordinate system's axes
    /// (FANUC No.12320#0 TWD).
    #[serde(default)]
    pub plane_directions: bool,
    /// The right-angle and table horizontal feeds are longitude and latitude about `vertical`
    /// (FANUC No.12320#1 FLL).
    #[serde(default)]
    pub latitude_longitude: bool,
    /// The vertical (normal) axis of longitude/latitude (FANUC No.12321).
    #[serde(default)]
    pub vertical: ManualVertical,
    /// Within this angle of `vertical`, degrees, the tool counts as parallel to it and the
    /// fixed pair of directions is used (FANUC No.12322).
    #[serde(default)]
    pub parallel_deg: f64,
    /// JOG feeds at the jog feedrate instead of the dry run rate (FANUC No.12320#2 JFR).
    #[serde(default)]
    pub jog_feedrate: bool,
    /// Dry run rate, mm/min (FANUC No.1410); 0: not set, the jog feedrate is used.
    #[serde(default)]
    pub dry_run_feed: f64,
    /// Manual rapid traverse rate per axis (axis order), mm/min or deg/min: no axis of a manual
    /// feed moves faster (FANUC No.1424); a missing or 0 entry: the axis's rapid rate.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rapid: Vec<f64>,
    /// Jog feedrate per axis (axis order), mm/min or deg/min (FANUC No.1423): ordinary JOG of
    /// the axis, and with `jog_feedrate` the 5-axis JOG feeds its ±J signal drives; a missing or
    /// 0 entry: the panel's jog feed.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub jog_feed: Vec<f64>,
    /// The first handle's axis select codes (HS1A–HS1E) that choose the 5-axis handle feeds
    /// (FANUC No.12310–12314): tool axis / table vertical, right-angle / table horizontal
    /// direction 1, direction 2, tool tip centre rotation of the first and of the second rotary
    /// axis (OQ-25); 0: none (`controller::ManualSignals`).
    #[serde(default, skip_serializing_if = "no_codes")]
    #[cfg_attr(feature = "schema", schema(min_items = 5, max_items = 5))]
    pub handle_codes: [u8; 5],
}

fn no_codes(codes: &[u8; 5]) -> bool {
    codes.iter().all(|&c| c == 0)
}

/// FANUC No.12321: the vertical axis of the longitude/latitude feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(utoipa::ToSchema))]
#[serde(rename_all = "kebab-case")]
pub enum ManualVertical {
    /// The reference tool direction (tool axis feeds) / the tool direction (table feeds).
    #[default]
    Tool,
    X,
    Y,
    Z,
}

impl ManualOptions {
    fn is_default(&self) -> bool {
        *self == ManualOptions::default()
    }
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn plus_z() -> [f64; 3] {
    [0.0, 0.0, 1.0]
}

/// A preset's rotary axis along a coordinate axis through `point`.
fn link(axis: char, side: Side, point: [f64; 3], range: Option<[f64; 2]>) -> RotaryLink {
    let direction = match axis {
        'A' => [1.0, 0.0, 0.0],
        'B' => [0.0, 1.0, 0.0],
        _ => [0.0, 0.0, 1.0],
    };
    let hand = if side == Side::Head { Hand::Right } else { Hand::Left };
    RotaryLink { axis, side, direction, hand, point, zero_offset: 0.0, fixed: None, range }
}

impl MachineConfig {
    /// Positions as a control shows them: rollover axes modulo 360, in [0, 360) (the engine
    /// keeps them unwound so that travels stay plain differences).
    pub fn shown(&self, pos: &[f64; MAX_AXES]) -> [f64; MAX_AXES] {
        let mut out = *pos;
        for (p, axis) in out.iter_mut().zip(&self.axes) {
            if axis.rollover {
                *p = crate::angle::basic(*p);
            }
        }
        out
    }

    /// The axis index of an address letter, if the machine has that axis.
    pub fn axis_index(&self, letter: u8) -> Option<usize> {
        self.axes.iter().position(|a| a.name as u32 == letter as u32)
    }

    /// A built-in preset (see `docs/machine-config.md` for the machines and their dimensions).
    pub fn preset(name: &str) -> Option<MachineConfig> {
        // docs/contracts.md: head-bc has C master about Z and B slave about Y; table-ac A master about
        // X and C slave; table-bc B master about Y and C slave; mixed-bc B on the head, C on the
        // table. Head axes turn right-hand, table axes left-hand (ISO 841, both manuals).
        // Machine X/Y/Z locate the spindle nose at zero angles; the table frame's origin (machine
        // zero) is on the table top at the C axis.
        let (rotary, holder): (Vec<RotaryLink>, f64) = match name {
            "mill3" => (vec![], 0.0),
            // A fork head: the B pivot 150 mm above the nose, on the C axis.
            "head-bc" => (
                vec![
                    link('C', Side::Head, [0.0, 0.0, 150.0], None),
                    link('B', Side::Head, [0.0, 0.0, 150.0], Some([-110.0, 110.0])),
                ],
                150.0,
            ),
            // A trunnion: the A axis 120 mm below the table top, C turning about the table centre.
            "table-ac" => (
                vec![
                    link('A', Side::Table, [0.0, 0.0, -120.0], Some([-120.0, 120.0])),
                    link('C', Side::Table, [0.0, 0.0, 0.0], None),
                ],
                0.0,
            ),
            // A swivelling cradle: B 150 mm below the table top.
            "table-bc" => (
                vec![
                    link('B', Side::Table, [0.0, 0.0, -150.0], Some([-30.0, 110.0])),
                    link('C', Side::Table, [0.0, 0.0, 0.0], None),
                ],
                0.0,
            ),
            // A B head pivoting 200 mm above the nose, over a C rotary table.
            "mixed-bc" => (
                vec![
                    link('B', Side::Head, [0.0, 0.0, 200.0], Some([-100.0, 100.0])),
                    link('C', Side::Table, [0.0, 0.0, 0.0], None),
                ],
                200.0,
            ),
            _ => return None,
        };
        let linear = |name: char, stroke: [f64; 2]| Axis {
            accel: Some(4_000.0),
            jerk: Some(80_000.0),
            stroke: Some(stroke),
            ..Axis::new(name, AxisKind::Linear, 30_000.0)
        };
        let mut axes = vec![linear('X', [-600.0, 600.0]), linear('Y', [-450.0, 450.0]), linear('Z', [-500.0, 300.0])];
        // Rotary axes in address order (A, B, C), whatever their place in the chain.
        let mut by_name: Vec<&RotaryLink> = rotary.iter().collect();
        by_name.sort_by_key(|l| l.axis);
        for l in by_name {
            axes.push(Axis {
                accel: Some(1_800.0),
                jerk: Some(36_000.0),
                // A tilting axis stops at its movement range (stored stroke check).
                stroke: l.range,
                rollover: l.range.is_none(),
                shortest: l.range.is_none(),
                ..Axis::new(l.axis, AxisKind::Rotary, 10_800.0)
            });
        }
        Some(MachineConfig {
            name: name.to_string(),
            axes,
            rotary,
            tool_axis: plus_z(),
            nose: [0.0; 3],
            holder,
            // A typical arm-type changer, chip to chip.
            motion: MotionOptions { tool_change_s: 3.0, ..MotionOptions::default() },
            sub_chains: Vec::new(),
            chains: Vec::new(),
            five_axis: FiveAxisOptions::default(),
            manual: ManualOptions::default(),
            cycles: CycleOptions::default(),
        })
    }

    pub const PRESETS: &'static [&'static str] = &["mill3", "head-bc", "table-ac", "table-bc", "mixed-bc"];

    /// Checks what the engine relies on: 1..=MAX_AXES axes, unique valid letters, rates within
    /// [`RAPID_RANGE`], [`ACCEL_RANGE`], [`JERK_RANGE`].
    pub fn validate(&self) -> Result<(), String> {
        if self.axes.is_empty() || self.axes.len() > MAX_AXES {
            return Err(format!("a machine needs 1 to {MAX_AXES} axes"));
        }
        for (i, a) in self.axes.iter().enumerate() {
            let ok = match a.kind {
                AxisKind::Linear => "XYZUVW".contains(a.name),
                AxisKind::Rotary => "ABC".contains(a.name),
            };
            if !ok {
                return Err(format!("axis '{}' cannot be {:?}", a.name, a.kind));
            }
            if self.axes[..i].iter().any(|b| b.name == a.name) {
                return Err(format!("axis '{}' appears twice", a.name));
            }
            // Far beyond any machine, but where the planner's arithmetic holds: a rapid rate of
            // 1e50 ran a move in 0 s, a jerk of 1e-20 never ended it.
            let within = |x: Option<f64>, (lo, hi): (f64, f64)| x.is_none_or(|x| (lo..=hi).contains(&x));
            if !(within(Some(a.rapid), RAPID_RANGE) && within(a.accel, ACCEL_RANGE) && within(a.jerk, JERK_RANGE)) {
                return Err(format!(
                    "axis '{}': rapid is {} to {} per minute, accel {} to {} per s², jerk {} to {} per s³",
                    a.name, RAPID_RANGE.0, RAPID_RANGE.1, ACCEL_RANGE.0, ACCEL_RANGE.1, JERK_RANGE.0, JERK_RANGE.1
                ));
            }
            if a.stroke.is_some_and(|[lo, hi]| !(lo.is_finite() && hi.is_finite() && lo <= hi)) {
                return Err(format!("axis '{}': the stroke is [negative, positive] with negative <= positive", a.name));
            }
            if (a.rollover && a.kind != AxisKind::Rotary) || (a.shortest && !a.rollover) {
                return Err(format!("axis '{}': rollover is for rotary axes, shortest path for rollover axes", a.name));
            }
            if !(a.smoothing_tolerance.is_finite() && a.smoothing_tolerance >= 0.0) {
                return Err(format!("axis '{}': smoothing_tolerance is 0 or more", a.name));
            }
            let time_constant = |t: f64| t.is_finite() && (0.0..=MAX_AFTER_INTERPOLATION_MS).contains(&t);
            if !a.rapid_after_interpolation_ms.iter().all(|t| time_constant(*t)) {
                return Err(format!(
                    "axis '{}': rapid_after_interpolation_ms are 0 to {MAX_AFTER_INTERPOLATION_MS}",
                    a.name
                ));
            }
            if !time_constant(a.after_interpolation_ms) {
                return Err(format!("axis '{}': after_interpolation_ms is 0 to {MAX_AFTER_INTERPOLATION_MS}", a.name));
            }
        }
        if !(self.motion.tool_change_s.is_finite() && self.motion.tool_change_s >= 0.0) {
            return Err("motion.tool_change_s is 0 or more seconds".into());
        }
        let n = &self.motion.nano_smoothing;
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !(positive(n.tolerance)
            && n.min_block.is_finite()
            && n.min_block >= 0.0
            && positive(n.max_block)
            && n.min_block <= n.max_block
            && (0.0..=180.0).contains(&n.corner_angle)
            && n.spacing_ratio.is_finite()
            && n.spacing_ratio >= 1.0)
        {
            return Err("motion.nano_smoothing: tolerance and max_block above 0, min_block 0 to max_block, \
                        corner_angle 0 to 180 degrees, spacing_ratio 1 or more"
                .into());
        }
        let c = &self.cycles;
        let distance = |x: f64| (0.0..=MAX_PECK_DISTANCE).contains(&x);
        if !(distance(c.peck_retract) && distance(c.peck_clearance)) {
            return Err(format!("cycles: peck_retract and peck_clearance are 0 to {MAX_PECK_DISTANCE} mm"));
        }
        let f = &self.five_axis;
        let percent = |x: f64| (0.0..=100.0).contains(&x);
        let cycle_feed = f.wse_cycle_feed.is_finite() && f.wse_cycle_feed >= 0.0;
        if !(cycle_feed && percent(f.wse_feed_clamp_pct) && percent(f.wse_rapid_clamp_pct)) {
            return Err("five_axis: wse_cycle_feed is 0 or more, the wse clamps percentages 0 to 100".into());
        }
        if !f.cutting_point_distance.is_finite() {
            return Err("five_axis: cutting_point_distance must be a finite number".into());
        }
        let angle = |x: f64| (0.0..=180.0).contains(&x);
        if !(angle(f.plane_change_angle) && angle(f.leading_edge_tolerance) && angle(f.avoidance_max_tool_angle)) {
            return Err(
                "five_axis: plane_change_angle, leading_edge_tolerance and avoidance_max_tool_angle are 0 to 180 degrees"
                    .into(),
            );
        }
        if f.smooth_tolerance.is_some_and(|t| !t.iter().all(|x| x.is_finite() && *x > 0.0 && *x <= 360.0)) {
            return Err("five_axis: smooth_tolerance is two angles above 0, at most 360 degrees".into());
        }
        if f.smooth_path_tolerance.is_some_and(|t| !(0.002..=0.020).contains(&t)) {
            return Err("five_axis: smooth_path_tolerance is 0.002 to 0.020 mm (Syntec Pr407, 2 to 20 µm)".into());
        }
        if !(f.non_movement_limit.is_finite() && f.non_movement_limit >= 0.0) {
            return Err("five_axis: non_movement_limit is 0 or more, mm".into());
        }
        if f.crc_variant.is_30i() && (f.plane_change_check_off || f.non_movement_limit != 0.0) {
            return Err("five_axis: plane_change_check_off (No.19605#5 NIC) and non_movement_limit (No.19630) \
                        are settings of the 16i variant (crc_variant \"16i\")"
                .into());
        }
        if !f.crc_variant.is_30i()
            && (f.crc_check_in_plane || f.avoidance_max_tool_angle != 0.0 || f.crc_codes_by_mechanism)
        {
            return Err("five_axis: crc_check_in_plane (No.19608#1 NI5), avoidance_max_tool_angle (No.19636) and \
                        crc_codes_by_mechanism (No.19607#1 SPG) are 30i settings: the 16i variant checks in the \
                        compensation plane, does not avoid and has G41.2/G42.2 only"
                .into());
        }
        if !(0.0..=90.0).contains(&f.cutting_point_singular_angle) {
            return Err("five_axis: cutting_point_singular_angle is 0 to 90 degrees".into());
        }
        self.validate_mechanism()?;
        self.validate_chains()
    }

    /// The mechanism fields (`rotary`, `tool_axis`, `nose`, `holder`) of the machine or of one
    /// chain's view of it.
    fn validate_mechanism(&self) -> Result<(), String> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.nose) || !self.holder.is_finite() || !finite(&self.tool_axis) {
            return Err("nose, holder and tool_axis must be finite numbers".into());
        }
        if self.tool_axis.iter().map(|x| x * x).sum::<f64>().sqrt() < 1e-9 {
            return Err("tool_axis needs a non-zero direction".into());
        }
        for (i, link) in self.rotary.iter().enumerate() {
            let is_rotary = self.axes.iter().any(|a| a.name == link.axis && a.kind == AxisKind::Rotary);
            if !is_rotary && link.fixed.is_none() {
                return Err(format!("rotary link '{}' is not a rotary axis of the machine", link.axis));
            }
            if self.rotary[..i].iter().any(|l| l.axis == link.axis) {
                return Err(format!("rotary link '{}' appears twice", link.axis));
            }
            let norm = link.direction.iter().map(|x| x * x).sum::<f64>().sqrt();
            if !(norm.is_finite() && norm > 1e-9) {
                return Err(format!("rotary link '{}' needs a non-zero direction", link.axis));
            }
            let numbers = [link.zero_offset, link.fixed.unwrap_or(0.0)].into_iter().chain(link.point);
            if !numbers.chain(link.range.into_iter().flatten()).all(f64::is_finite) {
                return Err(format!("rotary link '{}' has a number that is not finite", link.axis));
            }
        }
        Ok(())
    }

    /// Sets 2–4 and the sub-chains: numbered once each within their ranges, every set with a
    /// mechanism, sub-chains only on a spindle-type mechanism, each chain's mechanism valid.
    fn validate_chains(&self) -> Result<(), String> {
        for (i, c) in self.chains.iter().enumerate() {
            if !(2..=4).contains(&c.set) {
                return Err(format!("chains[{i}]: set is 2, 3 or 4 (set 1 is the machine's own mechanism)"));
            }
            if self.chains[..i].iter().any(|d| d.set == c.set) {
                return Err(format!("chains[{i}]: set {} appears twice", c.set));
            }
            if c.rotary.is_empty() {
                return Err(format!(
                    "chains[{i}]: set {} needs rotary axes (leave out a set that is not configured)",
                    c.set
                ));
            }
        }
        let sets = std::iter::once((1, &self.rotary, &self.sub_chains))
            .chain(self.chains.iter().map(|c| (c.set, &c.rotary, &c.sub_chains)));
        for (set, rotary, subs) in sets {
            let spindle = rotary.len() == 2 && rotary.iter().all(|l| l.side == Side::Head);
            if !subs.is_empty() && !spindle {
                return Err(format!("set {set}: sub_chains are for a spindle-type mechanism (two head axes)"));
            }
            for (i, sub) in subs.iter().enumerate() {
                if !(2..=4).contains(&sub.q) || subs[..i].iter().any(|o| o.q == sub.q) {
                    return Err(format!("set {set}: sub_chains[{i}]: q is 2, 3 or 4, each once"));
                }
            }
        }
        for chain in self.chain_list().into_iter().skip(1) {
            let view = self.chain_view(chain).expect("a listed chain has a view");
            view.validate_mechanism().map_err(|e| format!("set {} sub-chain {}: {e}", chain.set, chain.sub))?;
        }
        Ok(())
    }

    /// Every chain the machine describes, set 1 as described first (then its sub-chains, then
    /// the sets 2–4 in the file's order, each followed by its sub-chains).
    pub fn chain_list(&self) -> Vec<Chain> {
        let subs = |set: u8, subs: &[SubChain]| {
            std::iter::once(Chain { set, sub: 1 })
                .chain(subs.iter().map(move |s| Chain { set, sub: s.q }))
                .collect::<Vec<_>>()
        };
        let mut out = subs(1, &self.sub_chains);
        for c in &self.chains {
            out.extend(subs(c.set, &c.sub_chains));
        }
        out
    }

    /// The machine with `chain`'s mechanism as its own (`rotary`, `tool_axis`, `nose`, `holder`)
    /// and no further chains: what the kinematics and the 5-axis functions read while that chain
    /// is in use; set 1 as described is the machine itself. `None` when the machine does not
    /// describe the chain.
    pub fn chain_view(&self, chain: Chain) -> Option<MachineConfig> {
        if chain == Chain::MAIN {
            return Some(self.clone());
        }
        let (rotary, tool_axis, nose, holder, subs) = if chain.set == 1 {
            (&self.rotary, self.tool_axis, self.nose, self.holder, &self.sub_chains)
        } else {
            let c = self.chains.iter().find(|c| c.set == chain.set)?;
            (&c.rotary, c.tool_axis, c.nose, c.holder, &c.sub_chains)
        };
        let (tool_axis, nose, holder) = match chain.sub {
            1 => (tool_axis, nose, holder),
            q => subs.iter().find(|s| s.q == q).map(|s| (s.tool_axis, s.nose, s.holder))?,
        };
        Some(MachineConfig {
            rotary: rotary.clone(),
            tool_axis,
            nose,
            holder,
            sub_chains: Vec::new(),
            chains: Vec::new(),
            ..self.clone()
        })
    }
}

/// Per-axis limits in the units of the axis (mm or deg) per second.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisLimits {
    pub count: usize,
    pub v: [f64; MAX_AXES],
    pub a: [f64; MAX_AXES],
    pub j: [f64; MAX_AXES],
}

impl AxisLimits {
    pub fn of(m: &MachineConfig) -> AxisLimits {
        let mut l = AxisLimits { count: m.axes.len(), v: [0.0; MAX_AXES], a: [0.0; MAX_AXES], j: [0.0; MAX_AXES] };
        for (i, axis) in m.axes.iter().enumerate() {
            l.v[i] = axis.rapid / 60.0;
            l.a[i] = axis.max_accel();
            l.j[i] = axis.max_jerk();
        }
        l
    }
}

/// A machine as the engine runs it: its configuration with the mechanism compiled from it and
/// its axes' limits, built once and shared by `Arc` between the interpreter, the motion
/// executor, the controller and the server's station. It reads as its configuration (`Deref`);
/// only the settings that change neither the mechanism nor the limits can be edited in place.
///
/// A machine with several mechanism chains (`MachineConfig::chains`) compiles each once; it
/// reads as the view of the chain in use ([`MachineConfig::chain_view`]), and
/// [`Machine::with_chain`] gives the same machine in another chain.
#[derive(Debug, Clone)]
pub struct Machine {
    /// The configuration as the chain in use sees it (the configuration itself in set 1).
    config: MachineConfig,
    /// `None` when the kinematics refuses the configuration (its tip is read as a 3-axis one's).
    kinematics: Option<std::sync::Arc<crate::kin::Kinematics>>,
    limits: AxisLimits,
    /// The chain in use.
    chain: Chain,
    /// Every chain the configuration describes with its compiled mechanism, set 1 first;
    /// shared by every chain's view.
    chains: std::sync::Arc<[Compiled]>,
}

/// One chain of a machine, compiled.
#[derive(Debug)]
struct Compiled {
    chain: Chain,
    view: MachineConfig,
    kinematics: Option<std::sync::Arc<crate::kin::Kinematics>>,
}

impl Machine {
    pub fn new(config: MachineConfig) -> Machine {
        let kinematics = crate::kin::Kinematics::new(&config).ok().map(std::sync::Arc::new);
        // Only a machine with further chains compiles them (and keeps their views).
        let chains: Vec<Compiled> = match config.chains.is_empty() && config.sub_chains.is_empty() {
            true => Vec::new(),
            false => config
                .chain_list()
                .into_iter()
                .filter_map(|chain| {
                    let view = config.chain_view(chain)?;
                    let kinematics = match chain == Chain::MAIN {
                        true => kinematics.clone(),
                        false => crate::kin::Kinematics::new(&view).ok().map(std::sync::Arc::new),
                    };
                    Some(Compiled { chain, view, kinematics })
                })
                .collect(),
        };
        Machine { kinematics, limits: AxisLimits::of(&config), config, chain: Chain::MAIN, chains: chains.into() }
    }

    pub fn config(&self) -> &MachineConfig {
        &self.config
    }

    /// The mechanism of the chain in use (`None` when the configuration's is refused).
    pub fn kinematics(&self) -> Option<&std::sync::Arc<crate::kin::Kinematics>> {
        self.kinematics.as_ref()
    }

    /// The chain in use.
    pub fn chain(&self) -> Chain {
        self.chain
    }

    /// The mechanism of `chain` (a tip read in a block of that chain), whichever is in use.
    pub fn kinematics_of(&self, chain: Chain) -> Option<&std::sync::Arc<crate::kin::Kinematics>> {
        if chain == self.chain {
            return self.kinematics.as_ref();
        }
        self.chains.iter().find(|c| c.chain == chain).and_then(|c| c.kinematics.as_ref())
    }

    /// The same machine in `chain`, if the machine describes that chain and its mechanism works
    /// (Syntec COR-161 otherwise: the selected chain is not on).
    pub fn with_chain(&self, chain: Chain) -> Option<Machine> {
        if chain == self.chain {
            return self.kinematics.is_some().then(|| self.clone());
        }
        let c = self.chains.iter().find(|c| c.chain == chain)?;
        let kinematics = Some(c.kinematics.clone()?);
        let config = MachineConfig { manual: self.config.manual.clone(), ..c.view.clone() };
        Some(Machine { config, kinematics, limits: self.limits.clone(), chain, chains: self.chains.clone() })
    }

    /// Each axis's speed, acceleration and jerk per second.
    pub fn limits(&self) -> &AxisLimits {
        &self.limits
    }

    /// The 5-axis manual feed settings, to change as a parameter screen would (the mechanism
    /// and the limits do not depend on them).
    pub fn manual_mut(&mut self) -> &mut ManualOptions {
        &mut self.config.manual
    }
}

impl std::ops::Deref for Machine {
    type Target = MachineConfig;

    fn deref(&self) -> &MachineConfig {
        &self.config
    }
}

impl From<MachineConfig> for Machine {
    fn from(config: MachineConfig) -> Machine {
        Machine::new(config)
    }
}

impl From<MachineConfig> for std::sync::Arc<Machine> {
    fn from(config: MachineConfig) -> std::sync::Arc<Machine> {
        std::sync::Arc::new(Machine::new(config))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn g27_checks_within_half_an_increment_and_any_turn_of_a_rollover_axis() {
        let mut a = MachineConfig::preset("head-bc").unwrap().axes[4].clone();
        assert!(a.rollover, "head-bc's C rolls over");
        assert!(a.at_reference(720.0004, 0.0) && a.at_reference(-359.9996, 0.0));
        assert!(!a.at_reference(0.001, 0.0) && !a.at_reference(180.0, 0.0));
        a.rollover = false;
        assert!(a.at_reference(-0.0005, 0.0) && !a.at_reference(360.0, 0.0));
    }

    #[test]
    fn every_preset_is_valid() {
        for name in MachineConfig::PRESETS {
            let m = MachineConfig::preset(name).unwrap();
            m.validate().unwrap();
        }
        assert_eq!(MachineConfig::preset("table-ac").unwrap().axis_index(b'A'), Some(3));
        // Axes in address order, whatever the chain order.
        assert_eq!(MachineConfig::preset("head-bc").unwrap().axis_index(b'C'), Some(4));
        assert!(MachineConfig::preset("nope").is_none());
    }

    /// A head-bc with set 2 an A/C head (A about X through the B pivot).
    fn two_chains() -> MachineConfig {
        let mut m = MachineConfig::preset("head-bc").unwrap();
        m.axes.insert(3, Axis::new('A', AxisKind::Rotary, 10_800.0));
        let rotary =
            vec![link('C', Side::Head, [0.0, 0.0, 150.0], None), link('A', Side::Head, [0.0, 0.0, 150.0], None)];
        m.chains =
            vec![ChainSet { set: 2, rotary, tool_axis: plus_z(), nose: [0.0; 3], holder: 150.0, sub_chains: vec![] }];
        m
    }

    #[test]
    fn chains_are_checked() {
        let m = two_chains();
        m.validate().unwrap();
        assert_eq!(m.chain_list(), [Chain::MAIN, Chain { set: 2, sub: 1 }]);
        // The view of set 2 is the machine with set 2's mechanism and no further chains.
        let view = m.chain_view(Chain { set: 2, sub: 1 }).unwrap();
        assert_eq!((view.rotary[1].axis, view.chains.len()), ('A', 0));
        assert!(m.chain_view(Chain { set: 3, sub: 1 }).is_none());
        let bad = |f: &dyn Fn(&mut MachineConfig), why: &str| {
            let mut m = two_chains();
            f(&mut m);
            let e = m.validate().expect_err(why);
            assert!(e.contains(why), "{e}");
        };
        bad(&|m| m.chains[0].set = 1, "set is 2, 3 or 4");
        bad(&|m| m.chains[0].set = 5, "set is 2, 3 or 4");
        bad(&|m| m.chains.push(m.chains[0].clone()), "set 2 appears twice");
        bad(&|m| m.chains[0].rotary.clear(), "needs rotary axes");
        bad(&|m| m.chains[0].rotary[1].axis = 'X', "not a rotary axis");
        bad(&|m| m.chains[0].tool_axis = [0.0; 3], "non-zero direction");
        bad(&|m| m.chains[0].nose[0] = f64::NAN, "finite");
        let sub = SubChain { q: 2, tool_axis: [1.0, 0.0, 0.0], nose: [0.0; 3], holder: 0.0 };
        bad(&|m| m.sub_chains = vec![SubChain { q: 1, ..sub }], "q is 2, 3 or 4");
        bad(&|m| m.sub_chains = vec![sub, sub], "q is 2, 3 or 4, each once");
        bad(&|m| m.chains[0].sub_chains = vec![SubChain { tool_axis: [0.0; 3], ..sub }], "set 2 sub-chain 2");
        // A table set cannot carry a head attachment.
        bad(
            &|m| {
                m.chains[0].rotary =
                    vec![link('A', Side::Table, [0.0; 3], None), link('C', Side::Table, [0.0; 3], None)];
                m.chains[0].sub_chains = vec![sub];
            },
            "spindle-type",
        );
    }

    #[test]
    fn a_machine_without_chains_reads_and_writes_as_before() {
        // No `chains` / `sub_chains` key is written for one chain, and the machine's view of
        // set 1 is itself.
        let m = MachineConfig::preset("head-bc").unwrap();
        let text = serde_json::to_string(&m).unwrap();
        assert!(!text.contains("chains"), "{text}");
        assert_eq!(m.chain_view(Chain::MAIN).unwrap(), m);
        let machine = Machine::new(m);
        assert_eq!(machine.chain(), Chain::MAIN);
        assert!(machine.with_chain(Chain { set: 2, sub: 1 }).is_none());
    }

    #[test]
    fn a_machine_switches_chains_and_keeps_every_one_compiled() {
        let machine = Machine::new(two_chains());
        let two = machine.with_chain(Chain { set: 2, sub: 1 }).unwrap();
        assert_eq!((two.chain(), two.rotary[1].axis), (Chain { set: 2, sub: 1 }, 'A'));
        // Set 2's mechanism turns A (axis 3); set 1's is still there by name.
        assert_eq!(two.kinematics().unwrap().head[1].index, Some(3));
        assert_eq!(two.kinematics_of(Chain::MAIN).unwrap().head[1].name, 'B');
        let back = two.with_chain(Chain::MAIN).unwrap();
        assert_eq!(back.config(), machine.config());
    }

    #[test]
    fn bad_rotary_links_are_refused() {
        let mut m = MachineConfig::preset("head-bc").unwrap();
        m.rotary[0].axis = 'X';
        assert!(m.validate().is_err());
        let mut m = MachineConfig::preset("head-bc").unwrap();
        m.rotary[1].direction = [0.0; 3];
        assert!(m.validate().is_err());
        let mut m = MachineConfig::preset("head-bc").unwrap();
        m.rotary[1].point[2] = f64::NAN;
        assert!(m.validate().is_err());
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.axes[0].rollover = true;
        assert!(m.validate().is_err());
        let mut m = MachineConfig::preset("mill3").unwrap();
        m.axes[1].stroke = Some([10.0, -10.0]);
        assert!(m.validate().is_err());
        for (feed, pct) in [(-1.0, 0.0), (f64::INFINITY, 0.0), (0.0, 101.0), (0.0, f64::NAN)] {
            let mut m = MachineConfig::preset("table-ac").unwrap();
            (m.five_axis.wse_cycle_feed, m.five_axis.wse_rapid_clamp_pct) = (feed, pct);
            assert!(m.validate().is_err(), "{feed} {pct}");
        }
        for bad in [-0.1, 100.1, f64::NAN, f64::INFINITY] {
            let mut m = MachineConfig::preset("mill3").unwrap();
            m.cycles.peck_clearance = bad;
            assert!(m.validate().unwrap_err().contains("peck_clearance"), "{bad}");
        }
        let mut m = MachineConfig::preset("mill3").unwrap();
        (m.cycles.peck_retract, m.cycles.peck_clearance) = (0.0, 100.0);
        m.validate().unwrap();
    }

    /// The audit's F10: a rapid rate of 1e50 ran a move in 0 s, an acceleration or jerk of
    /// 1e-20 ended in a budget alarm after 10⁶ s; a negative tool change time counted as 0.
    #[test]
    fn rates_outside_fivex_s_bounds_and_a_negative_tool_change_time_are_refused() {
        let with = |f: &dyn Fn(&mut MachineConfig)| {
            let mut m = MachineConfig::preset("head-bc").unwrap();
            f(&mut m);
            m.validate()
        };
        for rapid in [1e50, 1e7 * 1.001, 0.999, 1e-6, f64::INFINITY, f64::NAN, 0.0, -1.0] {
            assert!(
                with(&|m| m.axes[0].rapid = rapid).unwrap_err().contains("rapid is 1 to 10000000 per minute"),
                "{rapid}"
            );
        }
        for bad in [1e-20, 0.0099, 1.01e8, f64::NAN] {
            assert!(with(&|m| m.axes[1].accel = Some(bad)).is_err(), "accel {bad}");
        }
        for bad in [1e-20, 0.0099, 1.01e10, f64::INFINITY] {
            assert!(with(&|m| m.axes[2].jerk = Some(bad)).is_err(), "jerk {bad}");
        }
        // The bounds themselves, and the defaults they give at the ends of the rapid range.
        with(&|m| {
            m.axes[0].rapid = 1.0;
            m.axes[0].accel = None;
            m.axes[0].jerk = None;
            m.axes[1].rapid = 1e7;
            (m.axes[1].accel, m.axes[1].jerk) = (None, None);
            (m.axes[2].accel, m.axes[2].jerk) = (Some(0.01), Some(1e10));
        })
        .unwrap();
        for t in [-1.0, f64::NAN, f64::INFINITY] {
            assert!(with(&|m| m.motion.tool_change_s = t).unwrap_err().contains("tool_change_s"), "{t}");
        }
    }
}
