//! Offset memory: work coordinate offsets and tool offset memory C (H/D, geometry/wear).

use crate::canon::Pos;
use crate::machine::MAX_AXES;

/// Tool offset numbers 1..=MAX_TOOL_OFFSETS.
pub const MAX_TOOL_OFFSETS: usize = 999;
/// The Haas NGC mill's 200 tool offsets (its variables #2001–#2800 hold 200 of each kind, and D
/// is "between 0 and 200"): H, D and G10's P beyond are its RANGE ERROR, not a length of 0.
pub const HAAS_TOOL_OFFSETS: usize = 200;

/// The last tool offset number a program of `dialect` may select.
pub fn max_tool_offset(dialect: crate::Dialect) -> usize {
    match dialect {
        crate::Dialect::Haas => HAAS_TOOL_OFFSETS,
        _ => MAX_TOOL_OFFSETS,
    }
}
/// The largest magnitude of a tool offset value in the input unit (`inch`: G20): the valid
/// input range of tool compensation values for IS-B, geometry ±999.999 mm / ±99.9999 inch, wear
/// ±99.999 mm / ±9.9999 inch (FANUC Series 16i-LA operator's manual B-63194EN §12.4, Table
/// 12.4(a); the 30i's own table was not at hand, `docs/conventions.md`, "Tool offset values").
/// One limit for every way an offset is set: G10, the system variables, and the service's API,
/// a fleet run's `tools` and the `--tools` file (in mm), so no offset a program could not set
/// reaches a run.
pub fn tool_value_limit(wear: bool, inch: bool) -> f64 {
    match (wear, inch) {
        (false, false) => 999.999,
        (false, true) => 99.9999,
        (true, false) => 99.999,
        (true, true) => 9.9999,
    }
}

/// Whether a tool offset value may be set (G10 L1/L10–L13, `#2001…`/`#10001…`–`#13999`, and
/// from outside the program): its magnitude within [`tool_value_limit`]; not a number is not
/// within it. Beyond is FANUC's PS0032 ILLEGAL OFFSET VALUE IN G10 ("in setting an offset
/// amount by G10 or in writing an offset amount by system variables, the offset amount was
/// excessive"): a probing macro's bad reading otherwise became a tool length of metres, found
/// later as an overtravel or not at all. A tolerance of 1e-9 input units keeps a sum of
/// increments (G91) that reaches the limit exactly inside it.
pub fn tool_value_fits(value: f64, wear: bool, inch: bool) -> bool {
    value.abs() <= tool_value_limit(wear, inch) + 1e-9
}

/// The largest magnitude of a work offset value, in the input unit: nine digits of IS-B's least
/// input increment, ±999999.999 mm / ±99999.9999 inch (FANUC's range of the workpiece origin
/// offsets, No.1221–1226, and of any number the lexer reads: `docs/dialects.md`, "Too many
/// digits").
pub fn work_value_limit(inch: bool) -> f64 {
    if inch {
        99999.9999
    } else {
        999999.999
    }
}

/// Whether a work offset value may be set by G10 L2/L20 (under G91 the sum) or a system
/// variable (`#5201…`, `#7001…`, `#14001…`): beyond [`work_value_limit`] it is PS0032, as a
/// tool offset's (a macro's bad reading became a workpiece zero a kilometre away, which a
/// machine without stroke limits ran to). 1e-9 input units of tolerance as for the tools.
pub fn work_value_fits(value: f64, inch: bool) -> bool {
    value.abs() <= work_value_limit(inch) + 1e-9
}

/// G54.1 P1..=MAX_G54_1.
pub const MAX_G54_1: usize = 300;

/// What the P of a block that selects G54–G59 is (`docs/conventions.md`, "G54 P").
#[derive(Debug, Clone, PartialEq)]
pub enum WorkP {
    /// No P, or the P of another code of the block: a plain selection.
    NotOurs,
    /// FANUC's `G54 Pn`: the additional workpiece system G54.1 Pn.
    Additional,
    /// Refused with this alarm: a P no manual at hand gives a meaning (dropping it ran the
    /// program in another work system than the one it named), or a P that both G54 and another
    /// code of the block would take.
    Refused(crate::alarm::AlarmId),
}

/// The meaning of P in a block selecting `code` (G54…G59, ×10) in `dialect`, given whether the
/// block has a P and whether another code of it (or the canned cycle in force) takes one
/// (`gcode::code::TAKE_P`, the cycles, M98/M198/M99). FANUC's "G54.1 Pn ; or G54 Pn ;" (30i
/// operator's manual, "Additional workpiece coordinate systems") is the only format at hand.
pub fn work_system_p(dialect: crate::Dialect, code: u16, p: bool, p_elsewhere: bool) -> WorkP {
    use crate::alarm::AlarmId;
    let fanuc_g54 = dialect == crate::Dialect::Fanuc && code == super::gcode::code::G54;
    match (p, p_elsewhere, fanuc_g54) {
        (false, _, _) | (true, true, false) => WorkP::NotOurs,
        (true, false, true) => WorkP::Additional,
        (true, true, true) => WorkP::Refused(AlarmId::IllegalGCodeCombination),
        (true, false, false) => WorkP::Refused(AlarmId::AddressNotBuilt),
    }
}

/// Another code of a block takes its P: one of `gcode::code::TAKE_P`, a canned cycle (in the
/// block, or `cycle_in_force`), a subprogram call or return.
pub fn p_taken_elsewhere(dialect: crate::Dialect, codes: &[u16], mcodes: &[u32], cycle_in_force: bool) -> bool {
    use super::gcode::{code, group, lookup};
    let cycle = |c: u16| c != code::G80 && lookup(c, dialect).is_some_and(|d| d.group == group::CYCLE);
    cycle_in_force
        || codes.iter().any(|&c| code::TAKE_P.contains(&c) || cycle(c))
        || mcodes.iter().any(|&m| super::mcode::call_or_return(m))
}

/// Index 0: external offset; 1..=6: G54..G59; 7..: G54.1 P1…
pub fn g54_1_index(p: usize) -> usize {
    6 + p
}

#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ToolOffset {
    pub h_geometry: f64,
    pub h_wear: f64,
    pub d_geometry: f64,
    pub d_wear: f64,
    /// The tool's corner radius (FANUC's corner-R offset data): cutting point control
    /// (G43.8/G43.9) reads the tool as a ball end mill when it equals the radius (D), a square
    /// end mill when 0, a bull-nose (radius end) mill otherwise.
    pub corner_radius: f64,
}

/// Every slot exists and reads zero until written; only the slots up to the highest one
/// written are stored (a controller mostly uses a few tools and G54–G59, and a thousand hosted
/// controllers would otherwise hold 50 kB of zeros each).
#[derive(Debug, Clone)]
pub struct Offsets {
    /// Work offset slots up to the highest written.
    work: Vec<Pos>,
    /// Tool offsets up to the highest number written; index 0 is offset number 0, always zero.
    tools: Vec<ToolOffset>,
    /// Which entries were handed out for writing since the last [`Offsets::take_touched`]: what
    /// a host has to save, without keeping a second copy of every offset to compare with.
    touched_work: [u64; WORK_WORDS],
    touched_tools: [u64; TOOL_WORDS],
}

/// Work offset slots (external, G54–G59, G54.1 P1…) and the words of their touched bits.
const WORK_SLOTS: usize = 7 + MAX_G54_1;
const WORK_WORDS: usize = WORK_SLOTS.div_ceil(64);
const TOOL_WORDS: usize = (MAX_TOOL_OFFSETS + 1).div_ceil(64);
/// What a slot never written holds.
const ZERO_WORK: Pos = [0.0; MAX_AXES];
const ZERO_TOOL: ToolOffset =
    ToolOffset { h_geometry: 0.0, h_wear: 0.0, d_geometry: 0.0, d_wear: 0.0, corner_radius: 0.0 };

impl Default for Offsets {
    fn default() -> Self {
        Offsets { work: Vec::new(), tools: Vec::new(), touched_work: [0; WORK_WORDS], touched_tools: [0; TOOL_WORDS] }
    }
}

/// The indices whose bits are set, and the bits cleared.
fn take_bits(words: &mut [u64]) -> Vec<usize> {
    let mut out = Vec::new();
    for (w, word) in words.iter_mut().enumerate() {
        let mut bits = std::mem::take(word);
        while bits != 0 {
            out.push(w * 64 + bits.trailing_zeros() as usize);
            bits &= bits - 1;
        }
    }
    out
}

impl Offsets {
    /// Work offset slot `index` (below `g54_1_index(MAX_G54_1) + 1`).
    /// The work offsets written so far (program restart's P type compares them with a later
    /// copy: [`Offsets::same_work`]).
    pub fn work_copy(&self) -> Vec<Pos> {
        self.work.clone()
    }

    /// Whether every work offset equals `copy` (slots beyond either are zero).
    pub fn same_work(&self, copy: &[Pos]) -> bool {
        (0..self.work.len().max(copy.len())).all(|i| self.work(i) == copy.get(i).unwrap_or(&ZERO_WORK))
    }

    /// Whether the external work offset (slot 0, FANUC's EXT) equals `copy`'s.
    pub fn same_external(&self, copy: &[Pos]) -> bool {
        self.work(0) == copy.first().unwrap_or(&ZERO_WORK)
    }

    pub fn work(&self, index: usize) -> &Pos {
        assert!(index < WORK_SLOTS, "work offset slot {index} out of range");
        self.work.get(index).unwrap_or(&ZERO_WORK)
    }

    pub fn work_mut(&mut self, index: usize) -> &mut Pos {
        assert!(index < WORK_SLOTS, "work offset slot {index} out of range");
        if self.work.len() <= index {
            self.work.resize(index + 1, ZERO_WORK);
        }
        self.touched_work[index / 64] |= 1 << (index % 64);
        &mut self.work[index]
    }

    /// Tool offset `number` (0..=MAX_TOOL_OFFSETS; `None` beyond).
    pub fn tool(&self, number: u32) -> Option<&ToolOffset> {
        let n = number as usize;
        (n <= MAX_TOOL_OFFSETS).then(|| self.tools.get(n).unwrap_or(&ZERO_TOOL))
    }

    /// Offset number 0 cannot be written (it means "no offset").
    pub fn tool_mut(&mut self, number: u32) -> Option<&mut ToolOffset> {
        let n = number as usize;
        if n == 0 || n > MAX_TOOL_OFFSETS {
            return None;
        }
        if self.tools.len() <= n {
            self.tools.resize(n + 1, ZERO_TOOL);
        }
        self.touched_tools[n / 64] |= 1 << (n % 64);
        Some(&mut self.tools[n])
    }

    /// The tool offset numbers and work offset slots written (handed out by `tool_mut` /
    /// `work_mut`) since the last call, in order; the marks are cleared.
    pub fn take_touched(&mut self) -> (Vec<u32>, Vec<usize>) {
        let tools = take_bits(&mut self.touched_tools).into_iter().map(|n| n as u32).collect();
        (tools, take_bits(&mut self.touched_work))
    }

    /// Tool length (H): geometry plus wear.
    pub fn length(&self, h: u32) -> f64 {
        self.tool(h).map_or(0.0, |t| t.h_geometry + t.h_wear)
    }

    /// Cutter radius (D): geometry plus wear.
    pub fn radius(&self, d: u32) -> f64 {
        self.tool(d).map_or(0.0, |t| t.d_geometry + t.d_wear)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_entries_are_handed_out_once_in_order() {
        let mut o = Offsets::default();
        assert_eq!(o.take_touched(), (vec![], vec![]));
        o.tool_mut(999).unwrap().h_geometry = 1.0;
        o.tool_mut(64).unwrap().d_wear = 0.1;
        o.tool_mut(1).unwrap();
        assert!(o.tool_mut(0).is_none() && o.tool_mut(1000).is_none());
        o.work_mut(WORK_SLOTS - 1)[0] = 5.0;
        o.work_mut(0)[1] = 2.0;
        assert_eq!(o.take_touched(), (vec![1, 64, 999], vec![0, WORK_SLOTS - 1]));
        assert_eq!(o.take_touched(), (vec![], vec![]), "cleared");
        assert_eq!(o.length(999), 1.0, "the values stay");
    }

    #[test]
    fn tool_values_within_the_is_b_range_fit() {
        assert!(tool_value_fits(999.999, false, false) && tool_value_fits(-999.999, false, false));
        assert!(!tool_value_fits(1000.0, false, false) && !tool_value_fits(-999.9991, false, false));
        assert!(tool_value_fits(99.999, true, false) && !tool_value_fits(100.0, true, false));
        assert!(tool_value_fits(99.9999, false, true) && !tool_value_fits(100.0, false, true));
        assert!(tool_value_fits(-9.9999, true, true) && !tool_value_fits(10.0, true, true));
        assert!(tool_value_fits(999.0 + 0.999, false, false), "a sum that reaches the limit");
    }

    #[test]
    fn work_values_within_nine_digits_fit() {
        assert!(work_value_fits(999999.999, false) && work_value_fits(-999999.999, false));
        assert!(!work_value_fits(1.0e6, false) && !work_value_fits(f64::NAN, false));
        assert!(work_value_fits(99999.9999, true) && !work_value_fits(1.0e5, true));
    }

    #[test]
    fn slots_never_written_read_zero_and_are_not_stored() {
        let mut o = Offsets::default();
        assert_eq!(o.tool(999), Some(&ToolOffset::default()));
        assert_eq!(o.tool(1000), None);
        assert_eq!(o.work(WORK_SLOTS - 1), &[0.0; MAX_AXES]);
        assert!(o.tools.is_empty() && o.work.is_empty());
        o.tool_mut(3).unwrap().d_geometry = 5.0;
        o.work_mut(1)[0] = 10.0;
        assert_eq!((o.tools.len(), o.work.len()), (4, 2), "stored up to the highest written");
        assert_eq!((o.radius(3), o.radius(2), o.radius(500)), (5.0, 0.0, 0.0));
        assert_eq!((o.work(1)[0], o.work(0)[0], o.work(200)[0]), (10.0, 0.0, 0.0));
    }
}
