//! Canonical commands: what the interpreter hands to motion, one per action, in program order.
//!
//! Positions are full axis vectors in the machine's axis order (`[f64; MAX_AXES]`, unused slots
//! zero). `target` is in programming coordinates (the active workpiece system after G52/G92);
//! `machine` is the same point in machine coordinates with work and tool length offsets applied.

use crate::geom::Rigid;
use crate::kin::Vec3;
use crate::machine::MAX_AXES;

pub type Pos = [f64; MAX_AXES];

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MotionKind {
    /// G00
    Rapid,
    /// G01 (and, until their own interpolators exist, the other group-01 codes)
    Linear,
    /// G02
    ArcCw,
    /// G03
    ArcCcw,
    /// G53: rapid in machine coordinates
    MachineRapid,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FeedMode {
    /// G93: F is 1/min, the block takes 1/F minutes.
    InverseTime,
    /// G94: mm/min (deg/min for rotary-only moves)
    PerMinute,
    /// G95: mm per spindle revolution
    PerRevolution,
}

/// A circular or helical move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    /// Center in programming coordinates (only the plane's two axes are meaningful).
    pub center: Pos,
    /// The plane's first and second axis index and the helix axis index.
    pub plane_axes: (usize, usize, usize),
    pub radius: f64,
    /// Signed swept angle in degrees (positive = counter-clockwise seen from the plane normal).
    pub sweep_deg: f64,
}

/// The modal context a motion is executed in, as G-code numbers ×10 (G43.4 → 434).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotionContext {
    pub plane: u16,
    pub wcs: u16,
    /// P of G54.1 (0 otherwise).
    pub wcs_p: u16,
    pub length_comp: u16,
    pub h: u32,
    pub tool_length: f64,
    pub cutter_comp: u16,
    pub d: u32,
    pub cutter_radius: f64,
    pub path_mode: u16,
    /// The motion ends in an exact stop (G09 in its block, or G61).
    pub exact_stop: bool,
    /// The feed override does not act (G63 tapping mode, the tapping cycles G74/G84).
    pub fixed_feed: bool,
    /// A tapping cycle's feed into the hole or back out of it: a feed hold takes effect at the
    /// end of the feed out, the spindle override does not act (`docs/motion.md`, "The
    /// controller").
    pub tapping: Tapping,
    /// A canned cycle's single-block stop point (FANUC: the end of the positioning, of the
    /// rapid to point R and of the hole, operations 1, 2 and 6): under single block the
    /// machine stops after this motion and the commands without motion that follow it.
    pub cycle_stop: bool,
    pub rotation: u16,
    /// The stored stroke limits are not checked before the motion moves (G54.4): an axis that
    /// reaches one stops there (`motion::stroke_stop`).
    pub no_stroke_precheck: bool,
}

/// Where a motion stands in a tapping cycle ([`MotionContext::tapping`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tapping {
    #[default]
    No,
    /// The feed into the hole, to the bottom.
    In,
    /// The feed back out of the hole, to point R: the tap is out at its end.
    Out,
}

/// What a cutter compensation block's G38, G39, I/J/K or Q say to the compensation stages
/// (`stage::cutter`, `docs/cutter-compensation.md`). Directions are in programming coordinates
/// (I along X, J along Y, K along Z; the stage reads the two of its plane).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CutterWord {
    /// G39 corner circular interpolation: the motion that follows (it does not move) becomes
    /// an arc of the offset radius about the corner, ending at the vector perpendicular to this
    /// direction (`None`: to the next block at its start).
    CornerArc(Option<[f64; 3]>),
    /// G40 with I/J/K: the block before the cancel ends where its offset path meets the line
    /// along this direction from its programmed end, offset on the same side.
    CancelDirection([f64; 3]),
    /// G38 vector hold: the motion that follows (a straight move, or one that does not move in
    /// the plane) ends at its programmed point plus the vector where it starts (no corner with
    /// the block after it), or plus the offset value along this direction.
    VectorHold(Option<[f64; 3]>),
    /// Q1/Q2/Q3 in a block of the tool side offset (G41.2/G42.2, `stage::tool_side`): where
    /// the interference check at a change of the compensation plane finds the block's end in
    /// the way, it ends at its perpendicular vector (1), at the first of its corner vectors
    /// (2), or at all of them (3), without the alarm.
    PlaneChange(u8),
    /// G41/G42 (or G41.2/G42.2) given again in its own mode: the block before ends at its
    /// perpendicular vector.
    Perpendicular,
    /// A block in offset mode that counts among the blocks without movement the compensation
    /// reads ahead (FANUC 30i §6.6.3): one that gave no command of its own (a G code alone, F,
    /// S with the spindle stopped, G10), and a second one after a block whose move is zero.
    /// The stages count it; the pipeline drops it (the executor never sees it).
    WithoutMotion,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Motion {
    pub kind: MotionKind,
    pub target: Pos,
    pub machine: Pos,
    /// Boxed: most motions are straight, and a small `Motion` is cheap to move.
    pub arc: Option<Box<Arc>>,
    /// Under tool centre point control or in a tilted working plane: the tool tip's path
    /// relative to the table, which the axes follow through the kinematics (`arc` is then
    /// `None`; the tip path carries its own circle).
    pub tip: Option<Box<TipMove>>,
    /// F in the unit of `feed_mode` (converted to mm). A FANUC arc in G93 carries the feed
    /// per minute its inverse time gives (FRN × radius, `interp::nc`'s `feed_of`).
    pub feed: f64,
    pub feed_mode: FeedMode,
    /// Spindle speed at the time (for G95).
    pub spindle: f64,
    pub context: MotionContext,
    /// No look-ahead (acceleration/deceleration before interpolation): FANUC AI contour control
    /// off (G05.1 Q0, or not yet G05.1 Q1 with No.1604#0 SHP = 0), or none set up for this kind
    /// of motion (cutting feed: No.1660 = 0; rapids: No.19501#5 FRP = 0 or No.1671 = 0); false
    /// (look-ahead) for manual moves. Beside the
    /// context rather than in it: there it would grow every canonical command by 8 bytes.
    pub no_look_ahead: bool,
    /// Haas G103 P: the planner looks at most this many blocks ahead of this motion's end
    /// (0: as far as its look-ahead goes; `motion::planner`).
    pub block_limit: u8,
    /// The highest speed along the path, mm/s, that the curve this motion is a chord of allows
    /// the axes (its bending against their acceleration: NURBS and nano smoothing,
    /// `crate::chords::bending_speed`); infinite for any other motion. Not scaled by the feed override.
    /// (f32: it fits beside the small fields, keeping `Canon` within its size.)
    pub speed_cap: f32,
    /// Moved off its programmed path by a cutter compensation stage (G41/G42, G41.2…G42.6,
    /// G41.3): what the trace's cutting point is read from. `None` outside compensation.
    pub offset: Option<Box<Offset>>,
    /// What the run tells about this motion's block, where the interpreter ran it as
    /// programmed though the manuals do not say the control does (`crate::notice`).
    pub notice: Option<crate::notice::BlockNotice>,
}

/// A motion a cutter compensation stage moved: where the block put the machine before it was
/// moved (the tip there is its programmed contour's end), and how the tool meets the contour
/// (`motion::contact`, `docs/conventions.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Offset {
    /// The machine axes at the motion's end as the block programmed them. An inserted move
    /// (a corner's, a start-up's) has those of the block it belongs to: the corner it turns
    /// about, the point it starts from.
    pub programmed_machine: Pos,
    /// The tool's radius: the magnitude of the offset value in effect.
    pub radius: f64,
    pub touch: Touch,
}

/// Which point of the tool a compensation puts on the contour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Touch {
    /// Its side (cutter compensation C, the tool side offset), the vectors placed `along` up
    /// the tool from the tip (FANUC No.19632; 0 elsewhere).
    Side { along: f64 },
    /// The leading edge of its end (FANUC G41.3): the end's edge toward the move.
    LeadingEdge,
}

impl Motion {
    /// A straight move outside any program mode: every axis linear to `machine` (`target` in
    /// the workpiece system), at `feed` mm/min or as a rapid, no spindle, default context.
    pub fn straight(rapid: bool, target: Pos, machine: Pos, feed: f64) -> Motion {
        Motion {
            kind: if rapid { MotionKind::Rapid } else { MotionKind::Linear },
            target,
            machine,
            arc: None,
            tip: None,
            feed,
            feed_mode: FeedMode::PerMinute,
            spindle: 0.0,
            context: MotionContext::default(),
            speed_cap: f32::INFINITY,
            offset: None,
            no_look_ahead: false,
            block_limit: 0,
            notice: None,
        }
    }

    /// Record, before a compensation stage first moves this motion, where the block put it
    /// and the tool (`radius`, `touch`); a motion already moved keeps its record (an inserted
    /// move copied from a moved block stays with that block's programmed end). A motion
    /// without an offset value in effect (the cancel block, D0) has none: it does not cut at
    /// the tool's side.
    pub fn record_offset(&mut self, touch: Touch) {
        let radius = self.context.cutter_radius.abs();
        if self.offset.is_none() && radius > 0.0 {
            self.offset = Some(Box::new(Offset { programmed_machine: self.machine, radius, touch }));
        }
    }
}

/// The motions among `commands` (a curve's chord) go no faster than `cap` (mm/s,
/// [`Motion::speed_cap`]), rounded down to a power of 2^(1/8) (steps of 9 %): the chords of
/// one curve then share their limit over stretches, and the planner joins them into one run
/// (it parts a run where a segment's speed limit differs, and a chain of runs of one chord
/// each accelerates as if it stopped at every junction).
pub fn cap_speed(commands: &mut [Canon], cap: f64) {
    let cap = if cap.is_finite() && cap > 0.0 { ((8.0 * cap.log2()).floor() / 8.0).exp2() } else { cap };
    for c in commands {
        if let CanonKind::Motion(m) = &mut c.kind {
            m.speed_cap = cap as f32;
        }
    }
}

/// A motion whose axes follow a tool tip path (FANUC G43.4/G43.5, Syntec RTCP, G68.2 planes):
/// at each point of the path X/Y/Z are where the kinematics put the tip (`Kinematics::
/// carriage_for`), the rotary axes turn as `posture` says.
#[derive(Debug, Clone, PartialEq)]
pub struct TipMove {
    /// Tool tip at the start and at the end, table frame (`kin` module docs), mm.
    pub from: Vec3,
    pub to: Vec3,
    /// A circular or helical tip path; `None`: a straight line.
    pub arc: Option<TipArc>,
    pub tool_length: f64,
    /// Tool posture control (FANUC P1): the tool direction (table frame) turns on the great
    /// circle from the first to the second in proportion to the tip's travel. `None`: the rotary
    /// axes move in proportion to it (conventional control).
    pub posture: Option<(Vec3, Vec3)>,
    /// On a circle, tool posture control keeps the tool's angles to the centre and to the
    /// travel direction interpolated instead (FANUC M-8; Syntec uses the great circle).
    pub posture_on_arc: bool,
    /// The programming coordinate system as a frame in the table frame: the tip's coordinates
    /// in it are what the position display shows.
    pub frame: Rigid,
    /// The position display shows the tip in machine directions minus this (the workpiece
    /// system, FANUC DET = 1) instead of in `frame`.
    pub display_shift: Option<Vec3>,
    /// FANUC CRS: the largest path deviation (mm) of the tip between interpolation points the
    /// speed must keep to; `None`: no clamp.
    pub deviation: Option<f64>,
    /// The rotary axes move at F when the tip does not move (FANUC RFC = 1); otherwise at their
    /// highest speed.
    pub rotary_feed: bool,
    /// The rotary axes turn at most this fraction of their rate (FANUC No.11202/11203 under
    /// G54.4 tool direction compensation); `None`: their own limit.
    pub rotary_clamp: Option<f64>,
    /// G54.4 tool direction compensation recomputed all along the block; `None`: the rotary
    /// axes move in proportion between the end points (or as `posture` says).
    pub compensation: Option<Compensation>,
    /// Cutting point control (G43.8/G43.9): `from`, `to` (and `arc`) are the cutting point's
    /// path, and the tip is away from it as `crate::cutting_point` says, all along the block.
    pub cutting: Option<CuttingMove>,
    /// Without tool centre point control (5-axis cutter compensation in the table coordinate
    /// system, FANUC TBP = 1): `from`, `to` are the point the carriage and the table carry
    /// (`Kinematics::unturned_tip`), not the tool tip — a head axis turning swings the tip about
    /// it, as in any block without TCP; only the table's turn is followed.
    pub head_fixed: bool,
}

impl TipMove {
    /// A circular path's radius at its start (in its plane, a helix's rise left out).
    pub fn arc_radius(&self) -> Option<f64> {
        self.arc.as_ref().map(|a| {
            let v = self.from - a.center;
            (v - a.normal * v.dot(&a.normal)).norm()
        })
    }

    /// The carriage (X, Y, Z) that puts this path's point at `point` (table frame) with the
    /// rotary axes of `pos`.
    pub fn carriage_for(&self, kin: &crate::kin::Kinematics, pos: &[f64], point: Vec3) -> Vec3 {
        if self.head_fixed {
            kin.carriage_for_unturned(pos, point, self.tool_length)
        } else {
            kin.carriage_for(pos, point, self.tool_length)
        }
    }

    /// This path's point (table frame) with the axes at `pos`: the tip, or with `head_fixed`
    /// the unturned tip.
    pub fn point_at(&self, kin: &crate::kin::Kinematics, pos: &[f64]) -> Vec3 {
        if self.head_fixed {
            kin.unturned_tip(pos, self.tool_length)
        } else {
            kin.forward(pos, self.tool_length).tip
        }
    }
}

/// A block under cutting point control: what places the tool tip from the cutting point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CuttingMove {
    pub tool: crate::cutting_point::Tool,
    /// The surface normal (table frame, unit) at the block's start and end.
    pub normals: (Vec3, Vec3),
    /// FANUC No.11262, degrees (0: no singular posture).
    pub singular_deg: f64,
    /// The vector tip − cutting point (table frame) where the block starts.
    pub start: Vec3,
}

/// G54.4 tool direction compensation between a block's ends (FANUC §2.13.5: every
/// interpolation period): `u` of the way, the tool direction (table frame) is
/// `turn · t(from + u·(to − from))`, `t` the error-free tool direction of the programmed angles
/// (machine-like positions: the work offsets added), interpolated as programmed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Compensation {
    pub turn: nalgebra::Matrix3<f64>,
    pub from: Pos,
    pub to: Pos,
}

/// A circle (spiral within the arc tolerance, helix along `normal`) in the table frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TipArc {
    pub center: Vec3,
    /// Unit normal of the plane; the sweep turns right-handed about it.
    pub normal: Vec3,
    /// Signed swept angle, degrees.
    pub sweep_deg: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpindleState {
    Cw,
    Ccw,
    Stop,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coolant {
    Mist,
    Flood,
    Off,
}

#[derive(Debug, Clone, PartialEq)]
pub enum CanonKind {
    Motion(Motion),
    Dwell {
        seconds: f64,
    },
    /// T word: the tool is prepared.
    ToolSelect {
        tool: u32,
    },
    /// M06
    ToolChange {
        tool: u32,
    },
    Spindle {
        state: SpindleState,
        speed: f64,
    },
    Coolant(Coolant),
    /// Any other M code, for the machine's PLC.
    Aux {
        m: u32,
    },
    /// M00, M01 (`optional`: it stops only with the optional stop switch on where the machine
    /// reaches it; off, it is an M code the motion before waits for) or `#3006`.
    Stop {
        optional: bool,
        message: Option<String>,
    },
    /// DPRNT/BPRNT text.
    Print {
        text: String,
    },
    /// M02 or M30.
    ProgramEnd {
        m: u32,
    },
    /// Syntec `G10 L5000 P_ [Q_]`: the mechanism chain the following commands are made and read
    /// with (the executor follows it in program order, the controller's manual feeds too).
    Chain(crate::machine::Chain),
    /// For cutter compensation C, about the motion that follows it in the same block; the stage
    /// takes it (the executor never sees it).
    Cutter(CutterWord),
}

/// One canonical command with the block it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct Canon {
    pub line: u32,
    pub n: Option<u32>,
    pub kind: CanonKind,
    /// How the tool tip is read from the machine axes while this command is carried out
    /// (`crate::tip`): the block's tool length and workpiece system. Here rather than in the
    /// motion so that every command has it (the machine standing at a dwell too).
    pub tip_basis: crate::tip::Basis,
}
