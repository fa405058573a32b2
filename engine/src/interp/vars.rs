//! Variable numbers: local, common, persistent and the system variables of `macro-b.md`.

use super::expr::{Ty, Value, Variables};
use super::gcode::{code, group};
use super::offsets::{g54_1_index, ToolOffset, MAX_G54_1};
use super::{gcode, State, LOCALS};
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind};
use crate::lang::Block;

/// Syntec: the type of each variable of a bank (`Ty`), two bits a variable: a Long, a Double,
/// or neither (not known). Tracked only for what a program assigns to a local variable (#1–#33,
/// its arguments) and to #100–#199, the Syntec local variables fivex keeps; the retained
/// #500–#999 and every other number read as not known. Bits, so that the controller's memory
/// (issue 18) grows by 16 bytes a bank, not a byte a variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Types<const W: usize> {
    long: [u64; W],
    double: [u64; W],
}

impl<const W: usize> Default for Types<W> {
    fn default() -> Self {
        Types { long: [0; W], double: [0; W] }
    }
}

impl<const W: usize> Types<W> {
    pub(super) fn get(&self, i: usize) -> Ty {
        let (w, bit) = (i / 64, 1u64 << (i % 64));
        if self.long[w] & bit != 0 {
            Ty::Long
        } else if self.double[w] & bit != 0 {
            Ty::Double
        } else {
            Ty::Unknown
        }
    }

    pub(super) fn set(&mut self, i: usize, t: Ty) {
        let (w, bit) = (i / 64, 1u64 << (i % 64));
        self.long[w] &= !bit;
        self.double[w] &= !bit;
        match t {
            Ty::Long => self.long[w] |= bit,
            Ty::Double => self.double[w] |= bit,
            Ty::Unknown => {}
        }
    }
}

/// One macro level's local variables #1–#33 and their Syntec types.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Locals {
    pub v: [Value; LOCALS],
    pub ty: Types<1>,
    /// Syntec G66: bit `i` set while #(i+1) holds a value the handbook leaves open in this call
    /// (`Locals::shared_call`); reading it is refused until the call writes it.
    pub unsettled: u64,
}

impl Default for Locals {
    fn default() -> Locals {
        Locals { v: [None; LOCALS], ty: Types::default(), unsettled: 0 }
    }
}

impl Locals {
    /// Syntec: the locals a call of a G66 runs on, `shared` by its calls until G67 (the Syntec
    /// MACRO handbook §2.3, §5.1: "从 `G66` 到 `G67` 期间共用"). The handbook says a G65 call
    /// writes its arguments into #1–#26 (§2.3), of G66 only that the locals are shared: whether
    /// each call writes the G66 block's `args` again is not said. A variable holding an argument
    /// that an earlier call changed (its value or type) reads otherwise under the two readings,
    /// so it is unsettled; the others read the same under both (the first call's are its
    /// arguments).
    pub(super) fn shared_call(shared: &Locals, args: &Locals) -> Locals {
        let mut locals = Locals { unsettled: 0, ..*shared };
        for i in 0..LOCALS {
            let changed = shared.v[i] != args.v[i] || shared.ty.get(i) != args.ty.get(i);
            if args.v[i].is_some() && changed {
                locals.unsettled |= 1 << i;
            }
        }
        locals
    }
}

/// Where a variable number lives.
enum Slot {
    Vacant,
    Local(usize),
    Common(usize),
    Persistent(usize),
    /// #100000–#199999, #500000–#999999 (`State::extended`).
    Extended(u32),
    Tool {
        number: u32,
        field: ToolField,
    },
    /// Work offset memory index and axis.
    Work {
        index: usize,
        axis: usize,
    },
    System(u32),
    /// Haas: #4001–#4021, the last block's code of the NGC's group `n - 4000`.
    HaasGroup(u32),
    /// Haas: #5201–#5206, the G52 offset (fivex's local coordinate system), read only.
    HaasG52(usize),
    /// A variable the dialect's control has but fivex does not model (`haas_slot`), or has with
    /// another meaning than fivex's (`syntec_differs`): refused when read or written, never a
    /// silent value.
    NotModelled,
}

#[derive(Clone, Copy)]
enum ToolField {
    HWear,
    HGeometry,
    DWear,
    DGeometry,
}

impl ToolField {
    fn get(self, t: &ToolOffset) -> f64 {
        match self {
            ToolField::HWear => t.h_wear,
            ToolField::HGeometry => t.h_geometry,
            ToolField::DWear => t.d_wear,
            ToolField::DGeometry => t.d_geometry,
        }
    }

    fn get_mut(self, t: &mut ToolOffset) -> &mut f64 {
        match self {
            ToolField::HWear => &mut t.h_wear,
            ToolField::HGeometry => &mut t.h_geometry,
            ToolField::DWear => &mut t.d_wear,
            ToolField::DGeometry => &mut t.d_geometry,
        }
    }
}

fn slot(n: u32, axes: usize) -> Slot {
    let axis_ok = |i: u32| (i as usize) < axes;
    match n {
        0 => Slot::Vacant,
        1..=33 => Slot::Local(n as usize - 1),
        100..=199 => Slot::Common(n as usize - 100),
        500..=999 => Slot::Persistent(n as usize - 500),
        100_000..=199_999 | 500_000..=999_999 => Slot::Extended(n),
        2001..=2200 => Slot::Tool { number: n - 2000, field: ToolField::HWear },
        2201..=2400 => Slot::Tool { number: n - 2200, field: ToolField::HGeometry },
        10001..=10999 => Slot::Tool { number: n - 10000, field: ToolField::HWear },
        11001..=11999 => Slot::Tool { number: n - 11000, field: ToolField::HGeometry },
        12001..=12999 => Slot::Tool { number: n - 12000, field: ToolField::DWear },
        13001..=13999 => Slot::Tool { number: n - 13000, field: ToolField::DGeometry },
        5201..=5340 if axis_ok((n - 5201) % 20) => {
            Slot::Work { index: ((n - 5201) / 20) as usize, axis: ((n - 5201) % 20) as usize }
        }
        7001..=7960 if axis_ok((n - 7001) % 20) => {
            Slot::Work { index: g54_1_index(((n - 7001) / 20) as usize + 1), axis: ((n - 7001) % 20) as usize }
        }
        14001..=19999 if axis_ok((n - 14001) % 20) && ((n - 14001) / 20) < MAX_G54_1 as u32 => {
            Slot::Work { index: g54_1_index(((n - 14001) / 20) as usize + 1), axis: ((n - 14001) % 20) as usize }
        }
        _ => Slot::System(n),
    }
}

/// The Haas NGC mill's variable map (`docs/dialects.md`, "Haas: variables"): the general
/// purpose variables and their NGC aliases #10000 + n, tool offsets #2001–#2800 (length
/// geometry, length wear, diameter geometry, diameter wear: the NGC's order, not FANUC's),
/// the work offsets #5221… (G54–G59), #7001… (G110–G129 = G154 P1–P20), #14001… (G154 P1–P99),
/// and the system variables fivex models; every other number the NGC lists is `NotModelled`.
fn haas_slot(n: u32, axes: usize) -> Slot {
    let axis_ok = |i: u32| (i as usize) < axes;
    let general = |k: u32| match k {
        100..=199 => Some(Slot::Common(k as usize - 100)),
        500..=699 | 800..=999 => Some(Slot::Persistent(k as usize - 500)),
        _ => None,
    };
    if let Some(slot) = general(n) {
        return slot;
    }
    match n {
        0 => Slot::Vacant,
        1..=33 => Slot::Local(n as usize - 1),
        // The NGC's names of #100–#199, #500–#699, #800–#999, and its own general purpose
        // variables #10000–#10099, #10200–#10499, #10700–#10799.
        10_000..=10_999 => general(n - 10_000).unwrap_or(Slot::Extended(n)),
        2001..=2200 => Slot::Tool { number: n - 2000, field: ToolField::HGeometry },
        2201..=2400 => Slot::Tool { number: n - 2200, field: ToolField::HWear },
        2401..=2600 => Slot::Tool { number: n - 2400, field: ToolField::DGeometry },
        2601..=2800 => Slot::Tool { number: n - 2600, field: ToolField::DWear },
        4001..=4021 => Slot::HaasGroup(n - 4000),
        5201..=5206 if axis_ok(n - 5201) => Slot::HaasG52((n - 5201) as usize),
        5221..=5340 if axis_ok((n - 5221) % 20) => {
            Slot::Work { index: ((n - 5201) / 20) as usize, axis: ((n - 5201) % 20) as usize }
        }
        7001..=7386 if axis_ok((n - 7001) % 20) => {
            Slot::Work { index: g54_1_index(((n - 7001) / 20) as usize + 1), axis: ((n - 7001) % 20) as usize }
        }
        14_001..=15_966 if axis_ok((n - 14_001) % 20) => {
            Slot::Work { index: g54_1_index(((n - 14_001) / 20) as usize + 1), axis: ((n - 14_001) % 20) as usize }
        }
        3000..=3004 | 3006 | 3011 | 3012 | 3026 | 3027 | 3901 | 4101..=4126 => Slot::System(n),
        // The timers and the panel's switches (`State::haas_timer`, `haas_switch`).
        3020..=3025 | 3030..=3033 => Slot::System(n),
        5001..=5006 | 5021..=5026 | 5041..=5046 | 5061..=5069 | 5081..=5086 => Slot::System(n),
        // Everything else: what the NGC lists and fivex does not model (hidden variables,
        // discrete and analog inputs/outputs #1000…/#11000…, axis loads, flutes, vibrations, actual
        // diameters, coolant positions, M30 count 2 #3902, the pallets loaded #3028 (fivex
        // has no pallet changer), servo deviations, tool life and load monitors #5401…,
        // settings and parameters #6001…/#20000…/#30000…, ATM and tool data, tool table
        // #50001…; `docs/dialects.md` lists the ranges), or no NGC variable at all.
        _ => Slot::NotModelled,
    }
}

/// Syntec: the numbers whose meaning on a Syntec control is not the one fivex gives them
/// (FANUC's), or is not known, after the Syntec MACRO syntax handbook (§2.1, §2.3, §2.6, §1.10,
/// the cross-vendor notes §2, §4.1; `docs/dialects.md`, "The Syntec macro language"). fivex
/// keeps only what both share: #0, the locals #1–#33, #100–#199 outside a macro call (Syntec's
/// locals of the main program and its M98 subprograms; in a G65/G66 call that call's own, fivex's
/// common ones) and #500–#999 (Syntec's retained axis-group user variables #401–#999). Every other
/// number is refused: Syntec's locals #34–#99 and #200–#400, its modal state and modal variables
/// #1000–#3100, its user parameters #4001–#5500, and what the handbook does not list at all,
/// where fivex's FANUC meaning would be a guess: the part counts #3901/#3902, the G54.1 P
/// offsets #7001…/#14001…, the tool offsets #10001–#13999 (the handbook's one mention, a
/// FANUC converter's `#11000+n`, does not say which length it is), the G54.4 data #26000…, the
/// extended common variables #100000….
pub(crate) fn syntec_differs(n: u32, in_macro_call: bool) -> bool {
    match n {
        100..=199 => in_macro_call,
        0..=33 | 500..=999 => false,
        _ => true,
    }
}

/// The NGC's modal groups as fivex's (FANUC's numbers): the same but the work offsets, which
/// the NGC calls group 12 (FANUC's 12 is the modal macro call, which the NGC does not have).
fn haas_group(g: u32) -> Option<usize> {
    match g {
        1 | 2 | 3 | 5 | 6 | 7 | 8 | 9 | 10 | 11 | 15 | 16 => Some(g as usize),
        12 => Some(group::WORK_SYSTEM),
        _ => None,
    }
}

impl State {
    fn slot(&self, n: u32) -> Slot {
        let axes = self.cfg.machine.axes.len();
        match self.cfg.dialect {
            crate::Dialect::Haas => haas_slot(n, axes),
            crate::Dialect::Syntec if syntec_differs(n, self.level() > 0) => Slot::NotModelled,
            _ => slot(n, axes),
        }
    }

    /// mm in one input unit: 25.4 under G20 (Syntec's G70), else 1.
    pub(super) fn mm_per_input_unit(&self) -> f64 {
        if self.modes[group::UNITS] == code::G20 {
            25.4
        } else {
            1.0
        }
    }

    fn linear_axis(&self, axis: usize) -> bool {
        self.cfg.machine.axes[axis].kind == crate::machine::AxisKind::Linear
    }

    /// mm in one unit of what an offset variable holds: the lengths (tool offsets, work offsets
    /// and the Haas G52 of linear axes, the shifts of G54.4's error data) are read and written
    /// in the input unit, as G10 and the axis words take them and `#5001…` show positions, so
    /// `#5241 = #5221` and `G10 L2 P3 X#5221` set the same offset under G20 (decision,
    /// `docs/conventions.md`, "Units and numbers"). Angles and numbers: 1. The position
    /// variables convert themselves (`in_input_unit`).
    fn slot_unit(&self, slot: &Slot) -> f64 {
        let length = match *slot {
            Slot::Tool { .. } => true,
            Slot::Work { axis, .. } | Slot::HaasG52(axis) => self.linear_axis(axis),
            Slot::System(n) => crate::wse::is_shift_variable(n),
            _ => false,
        };
        if length {
            self.mm_per_input_unit()
        } else {
            1.0
        }
    }

    /// Haas #4001–#4021: the code of the group, as the NGC names it (G154 for a G154 P or
    /// G110–G129 offset: fivex keeps them as G54.1 P).
    fn haas_group_code(&self, g: u32) -> Result<f64, AlarmId> {
        let group = haas_group(g).ok_or(AlarmId::VariableOutOfRange)?;
        Ok(match self.modes[group] {
            code::G54_1 => 154.0,
            c => gcode::as_number(c),
        })
    }
}

impl Variables for State {
    fn read(&self, n: u32) -> Result<Value, AlarmId> {
        let slot = self.slot(n);
        let unit = self.slot_unit(&slot);
        let value = match slot {
            Slot::HaasGroup(g) => Some(self.haas_group_code(g)?),
            Slot::HaasG52(axis) => Some(self.local[axis]),
            Slot::NotModelled => return Err(AlarmId::VariableOutOfRange),
            Slot::Vacant => None,
            Slot::Local(i) => {
                let locals = &self.locals[self.level()];
                if locals.unsettled & 1 << i != 0 {
                    // A Syntec G66's argument an earlier call changed (`Locals::shared_call`).
                    return Err(AlarmId::GCodeNotBuilt);
                }
                locals.v[i]
            }
            Slot::Common(i) => self.common[i],
            Slot::Persistent(i) => self.persistent[i],
            Slot::Extended(n) => self.extended.get(&n).copied(),
            Slot::Tool { number, field } => {
                Some(field.get(self.offsets.tool(number).ok_or(AlarmId::VariableOutOfRange)?))
            }
            Slot::Work { index, axis } => Some(self.offsets.work(index)[axis]),
            Slot::System(n) => Some(self.read_system(n)?),
        };
        Ok(value.map(|v| v / unit))
    }

    fn ty(&self, n: u32) -> Ty {
        match self.slot(n) {
            Slot::Local(i) => self.locals[self.level()].ty.get(i),
            Slot::Common(i) => self.common_types.get(i),
            _ => Ty::Unknown,
        }
    }
}

/// The interface signals between the macro executor and the machine's PLC (FANUC custom
/// macro "interface signals", 30i numbering): four 32-bit groups each way. Inputs UI000–UI031,
/// UI100…, UI200…, UI300… are #1000–#1031 (bits of group 0) and #1032–#1035 (the groups as
/// whole numbers); outputs UO000… likewise #1100–#1131 and #1132–#1135. A virtual machine has
/// no PLC: the inputs are what its host sets (0 at power on), the outputs what programs write.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct InterfaceSignals {
    pub inputs: [u32; 4],
    pub outputs: [u32; 4],
}

impl InterfaceSignals {
    /// Variable `n` of the signal ranges, if it is one.
    pub fn read(&self, n: u32) -> Option<f64> {
        let (groups, base) = match n {
            1000..=1035 => (&self.inputs, 1000),
            1100..=1135 => (&self.outputs, 1100),
            _ => return None,
        };
        let k = n - base;
        Some(if k < 32 { f64::from((groups[0] >> k) & 1) } else { f64::from(groups[(k - 32) as usize]) })
    }

    /// Set variable `n` of the signal ranges: a bit takes 0 or 1, a group a whole number
    /// 0 … 2³²−1. `inputs` chooses which side may be written.
    fn set(&mut self, n: u32, value: f64, inputs: bool) -> Result<(), AlarmId> {
        let (groups, base) = if inputs { (&mut self.inputs, 1000) } else { (&mut self.outputs, 1100) };
        let k = n.checked_sub(base).filter(|&k| k <= 35).ok_or(AlarmId::WriteProtectedVariable)?;
        if k < 32 {
            if value != 0.0 && value != 1.0 {
                return Err(AlarmId::VariableOutOfRange);
            }
            groups[0] = groups[0] & !(1 << k) | (value as u32) << k;
        } else {
            if !(0.0..=u32::MAX as f64).contains(&value) || value.fract() != 0.0 {
                return Err(AlarmId::VariableOutOfRange);
            }
            groups[(k - 32) as usize] = value as u32;
        }
        Ok(())
    }

    /// The host (the machine's PLC side) sets input `n` (#1000–#1035).
    pub fn set_input(&mut self, n: u32, value: f64) -> Result<(), AlarmId> {
        self.set(n, value, true)
    }
}

/// `#3000 = n (MESSAGE)`: the program's alarm n, rounded to a whole number, 0–999 (FANUC
/// MC3000–MC3999, Syntec MAR-000–999, Haas 1000–1999) with the block's comment. An n out of that
/// range, or vacant, is PS0115 rather than an alarm number fivex would invent (decision,
/// `docs/dialects.md`, "Macro alarms").
fn macro_alarm(value: Value, block: &Block) -> AlarmId {
    match value.map(f64::round) {
        Some(n) if (0.0..=999.0).contains(&n) => {
            AlarmId::MacroAlarm { number: n as u32, message: block.comment.clone().unwrap_or_default() }
        }
        _ => AlarmId::VariableOutOfRange,
    }
}

impl State {
    /// #3002, the hour timer (retained through power off).
    pub(super) fn hour_timer(&self) -> f64 {
        self.clock_s / 3600.0 - self.timer_h_base
    }

    /// Haas #3020–#3025, seconds (`docs/dialects.md`, "Haas: the dialect's core"): the
    /// power-on timer (the interpreter's clock, from its making), the cycle start timer (the
    /// automatic operation counted), the feed timer (the part of it along cutting feeds), the
    /// present part's operating time, the last complete part's and the one before it.
    fn haas_timer(&self, n: u32) -> f64 {
        match n {
            3020 => self.clock_s,
            3021 => self.operating_s - self.cycle_timer_base,
            3022 => self.cutting_s - self.feed_timer_base,
            3023 => self.operating_s - self.part_start_s,
            3024 => self.last_part_s,
            _ => self.previous_part_s,
        }
    }

    /// Haas #3030–#3033: single block, dry run, block delete, optional stop (1 on, 0 off), as
    /// the interpreter reads the blocks now (the panel's state when it reads ahead).
    fn haas_switch(&self, n: u32) -> f64 {
        let on = match n {
            3030 => self.single_block,
            3031 => self.dry_run,
            3032 => self.cfg.block_delete,
            _ => self.cfg.optional_stop,
        };
        f64::from(u8::from(on))
    }

    fn read_system(&self, n: u32) -> Result<f64, AlarmId> {
        let axes = self.cfg.machine.axes.len() as u32;
        let axis = |base: u32| -> Result<usize, AlarmId> {
            let i = n - base;
            if i < axes {
                Ok(i as usize)
            } else {
                Err(AlarmId::VariableOutOfRange)
            }
        };
        if let Some(v) = self.signals.read(n) {
            return Ok(v);
        }
        Ok(match n {
            3000 => 0.0,
            3001 => self.clock_s * 1000.0 - self.timer_ms_base,
            3002 => self.hour_timer(),
            3003 => self.sys3003,
            3004 => self.sys3004,
            3011 | 3012 => {
                let (date, time) = self.wall_clock.map_or((0.0, 0.0), |c| c.read(self.clock_s));
                if n == 3011 {
                    date
                } else {
                    time
                }
            }
            3901 => self.parts_done,
            // Haas: the tool in the spindle and the spindle speed (the commanded S while the
            // spindle turns, 0 stopped; the panel's spindle override is not the interpreter's).
            3026 if self.cfg.dialect == crate::Dialect::Haas => self.tool_in_spindle as f64,
            3020..=3025 if self.cfg.dialect == crate::Dialect::Haas => self.haas_timer(n),
            3030..=3033 if self.cfg.dialect == crate::Dialect::Haas => self.haas_switch(n),
            3027 if self.cfg.dialect == crate::Dialect::Haas => {
                if self.spindle == crate::canon::SpindleState::Stop {
                    0.0
                } else {
                    self.s
                }
            }
            3902 => self.parts_required,
            4001..=4030 => gcode::as_number(self.modes[(n - 4000) as usize]),
            4201..=4230 => gcode::as_number(self.modes[(n - 4200) as usize]),
            4101..=4130 => self.modal_address(n - 4100),
            4301..=4330 => self.modal_address(n - 4300),
            5001..=5020 => self.in_input_unit(axis(5001)?, self.pos),
            5021..=5060 if self.cutter_vector => return Err(AlarmId::PositionInCompensation),
            // Where the machine is: an axis under machine lock or Z-axis neglect stands still,
            // a handle interruption's shift is in it (as the status's machine position; it read
            // the program's machine coordinates, 30 mm off under a locked run).
            5021..=5040 => self.in_input_unit(axis(5021)?, self.machine_view.real(&self.machine_position())),
            // The current point in the WCS, also under G54.4 (WSE-20).
            5041..=5060 => self.in_input_unit(axis(5041)?, self.wcs_position()),
            26000..=26099 => self.setting_errors.variable(n).ok_or(AlarmId::VariableOutOfRange)?,
            // Where the last G31 ended (`skip`).
            5061..=5080 => self.in_input_unit(axis(5061)?, self.skip.pos),
            5081..=5100 => self.in_input_unit(axis(5081)?, self.tool_vec),
            5101..=5120 => {
                axis(5101)?;
                0.0
            }
            _ => return Err(AlarmId::VariableOutOfRange),
        })
    }

    /// Position variables read in the input unit: inch under G20 for linear axes.
    /// A position as the control shows it: inch under G20, rollover axes modulo 360.
    fn in_input_unit(&self, axis: usize, p: crate::canon::Pos) -> f64 {
        if self.linear_axis(axis) {
            p[axis] / self.mm_per_input_unit()
        } else if self.cfg.machine.axes[axis].rollover {
            crate::angle::basic(p[axis])
        } else {
            p[axis]
        }
    }

    /// `#4101`… : modal address values by letter position (A=1 … Z=26, P=30 for G54.1).
    fn modal_address(&self, i: u32) -> f64 {
        match i {
            7 => self.d as f64,
            8 => self.e,
            9 => self.modal_feed(),
            11 => self.h as f64,
            13 => self.last_m as f64,
            14 => self.last_n as f64,
            15 => self.frames.last().map_or(0.0, |f| f.number as f64),
            19 => self.s,
            20 => self.t as f64,
            30 => self.wcs_p as f64,
            _ => 0.0,
        }
    }

    /// `#4109`: the modal F as the program gives it: in/min (in/rev) under G20, so `F#4109`
    /// commands the same feed again (decision, `docs/conventions.md`, "Units and numbers");
    /// 1/min under G93, which has no unit to convert. Held in mm/min (`set_feed`).
    fn modal_feed(&self) -> f64 {
        if self.modes[group::FEED_MODE] == code::G93 {
            self.f
        } else {
            self.f / self.mm_per_input_unit()
        }
    }

    /// Assign `value`, of Syntec type `ty`, to variable `n` (the block supplies `#3000`/`#3006`
    /// messages).
    pub(super) fn write(
        &mut self,
        n: u32,
        (value, ty): (Value, Ty),
        block: &Block,
        out: &mut Vec<Canon>,
    ) -> Result<(), AlarmId> {
        let slot = self.slot(n);
        let unit = self.slot_unit(&slot);
        match slot {
            Slot::Vacant | Slot::HaasGroup(_) | Slot::HaasG52(_) => return Err(AlarmId::WriteProtectedVariable),
            Slot::NotModelled => return Err(AlarmId::VariableOutOfRange),
            Slot::Local(i) => {
                let level = self.level();
                self.locals[level].v[i] = value;
                self.locals[level].ty.set(i, ty);
                self.locals[level].unsettled &= !(1 << i);
            }
            Slot::Common(i) => {
                self.common[i] = value;
                self.common_types.set(i, ty);
            }
            Slot::Persistent(i) => self.persistent[i] = value,
            Slot::Extended(n) => self.set_extended(n, value),
            Slot::Tool { number, field } => {
                let v = value.unwrap_or(0.0);
                let wear = matches!(field, ToolField::HWear | ToolField::DWear);
                if !super::offsets::tool_value_fits(v, wear, self.modes[group::UNITS] == code::G20) {
                    return Err(AlarmId::IllegalOffsetValue);
                }
                let mm = v * unit;
                let t = self.offsets.tool_mut(number).ok_or(AlarmId::VariableOutOfRange)?;
                // Like G10, a new value takes effect at the next H selection.
                *field.get_mut(t) = mm;
            }
            Slot::Work { index, axis } => {
                let v = value.unwrap_or(0.0);
                // In the input unit: inch where the slot converts (a rotary axis counts degrees).
                if !super::offsets::work_value_fits(v, unit != 1.0) {
                    return Err(AlarmId::IllegalOffsetValue);
                }
                // As G10 L2/L20 sets it: the system shifts, no axis moves.
                let machine = self.machine_position();
                let mut set = *self.offsets.work(index);
                set[axis] = v * unit;
                self.set_work_offset(index, set, &machine);
            }
            Slot::System(n) => {
                let v = value.unwrap_or(0.0);
                match n {
                    3000 => return Err(macro_alarm(value, block)),
                    3001 => self.timer_ms_base = self.clock_s * 1000.0 - v,
                    3002 => self.timer_h_base = self.clock_s / 3600.0 - v,
                    // #3003 (single block stop, wait for FIN) and #3004 (feed hold, feed
                    // override, exact stop check) suppressed for the blocks after: not built, so
                    // a value that would suppress anything is refused, not stored and ignored
                    // (audit ops F5, `docs/dialects.md`, "Functions not built"); 0 keeps all.
                    3003 | 3004 if v != 0.0 => return Err(AlarmId::VariableOutOfRange),
                    3003 => self.sys3003 = v,
                    3004 => self.sys3004 = v,
                    3006 => {
                        let message = block.comment.clone();
                        self.emit(out, CanonKind::Stop { optional: false, message });
                    }
                    3901 => self.parts_done = v,
                    1100..=1135 => self.signals.set(n, v, false)?,
                    1000..=1035 => return Err(AlarmId::WriteProtectedVariable),
                    // G54.4 error data (WSE-08); COMMON has no Δa/Δb/Δc (#26003–#26005).
                    26000..=26099 => {
                        *self.setting_errors.variable_mut(n).ok_or(AlarmId::VariableOutOfRange)? = v * unit
                    }
                    3902 => self.parts_required = v,
                    // Haas: the cycle start and feed timers are set (as #3001), the power-on
                    // and part timers, the tool, the spindle speed and the switches are read only.
                    3021 if self.cfg.dialect == crate::Dialect::Haas => self.cycle_timer_base = self.operating_s - v,
                    3022 if self.cfg.dialect == crate::Dialect::Haas => self.feed_timer_base = self.cutting_s - v,
                    3020 | 3023..=3027 | 3030..=3033 if self.cfg.dialect == crate::Dialect::Haas => {
                        return Err(AlarmId::WriteProtectedVariable)
                    }
                    3011 | 3012 | 4001..=4030 | 4101..=4130 | 4201..=4230 | 4301..=4330 | 5001..=5120 => {
                        return Err(AlarmId::WriteProtectedVariable)
                    }
                    _ => return Err(AlarmId::VariableOutOfRange),
                }
            }
        }
        Ok(())
    }

    /// Fresh local variables for a macro call from its arguments.
    pub(super) fn empty_locals() -> Box<Locals> {
        Box::default()
    }
}
