//! Variable numbers: local, common, persistent and the system variables of `macro-b.md`.

use super::expr::{Value, Variables};
use super::gcode::{code, group};
use super::offsets::{g54_1_index, ToolOffset, MAX_G54_1};
use super::{gcode, State, LOCALS};
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind};
use crate::lang::Block;

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

impl Variables for State {
    fn read(&self, n: u32) -> Result<Value, AlarmId> {
        Ok(match slot(n, self.cfg.machine.axes.len()) {
            Slot::Vacant => None,
            Slot::Local(i) => self.locals[self.level()][i],
            Slot::Common(i) => self.common[i],
            Slot::Persistent(i) => self.persistent[i],
            Slot::Extended(n) => self.extended.get(&n).copied(),
            Slot::Tool { number, field } => {
                Some(field.get(self.offsets.tool(number).ok_or(AlarmId::VariableOutOfRange)?))
            }
            Slot::Work { index, axis } => Some(self.offsets.work(index)[axis]),
            Slot::System(n) => Some(self.read_system(n)?),
        })
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

impl State {
    /// #3002, the hour timer (retained through power off).
    pub(super) fn hour_timer(&self) -> f64 {
        self.clock_s / 3600.0 - self.timer_h_base
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
            3011 => self.cfg.date,
            3012 => self.cfg.time,
            3901 => self.parts_done,
            3902 => self.parts_required,
            4001..=4030 => gcode::as_number(self.modes[(n - 4000) as usize]),
            4201..=4230 => gcode::as_number(self.modes[(n - 4200) as usize]),
            4101..=4130 => self.modal_address(n - 4100),
            4301..=4330 => self.modal_address(n - 4300),
            5001..=5020 => self.in_input_unit(axis(5001)?, self.pos),
            5021..=5040 => self.in_input_unit(axis(5021)?, self.machine_position()),
            // The current point in the WCS, also under G54.4 (WSE-20).
            5041..=5060 => self.in_input_unit(axis(5041)?, self.wcs_position()),
            26000..=26099 => self.setting_errors.variable(n).ok_or(AlarmId::VariableOutOfRange)?,
            5061..=5080 => self.in_input_unit(axis(5061)?, self.pos),
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
        let a = &self.cfg.machine.axes[axis];
        if a.kind == crate::machine::AxisKind::Linear && self.modes[group::UNITS] == code::G20 {
            p[axis] / 25.4
        } else if a.rollover {
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
            9 => self.f,
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

    /// Assign `value` to variable `n` (the block supplies `#3000`/`#3006` messages).
    pub(super) fn write(&mut self, n: u32, value: Value, block: &Block, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        match slot(n, self.cfg.machine.axes.len()) {
            Slot::Vacant => return Err(AlarmId::WriteProtectedVariable),
            Slot::Local(i) => {
                let level = self.level();
                self.locals[level][i] = value;
            }
            Slot::Common(i) => self.common[i] = value,
            Slot::Persistent(i) => self.persistent[i] = value,
            Slot::Extended(n) => self.set_extended(n, value),
            Slot::Tool { number, field } => {
                let t = self.offsets.tool_mut(number).ok_or(AlarmId::VariableOutOfRange)?;
                // Like G10, a new value takes effect at the next H selection.
                *field.get_mut(t) = value.unwrap_or(0.0);
            }
            Slot::Work { index, axis } => self.offsets.work_mut(index)[axis] = value.unwrap_or(0.0),
            Slot::System(n) => {
                let v = value.unwrap_or(0.0);
                match n {
                    3000 => {
                        let number = v.round().clamp(0.0, 999.0) as u32;
                        let message = block.comment.clone().unwrap_or_default();
                        return Err(AlarmId::MacroAlarm { number, message });
                    }
                    3001 => self.timer_ms_base = self.clock_s * 1000.0 - v,
                    3002 => self.timer_h_base = self.clock_s / 3600.0 - v,
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
                    26000..=26099 => *self.setting_errors.variable_mut(n).ok_or(AlarmId::VariableOutOfRange)? = v,
                    3902 => self.parts_required = v,
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
    pub(super) fn empty_locals() -> Box<[Value; LOCALS]> {
        Box::new([None; LOCALS])
    }
}
