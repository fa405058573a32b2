//! Offset memory: work coordinate offsets and tool offset memory C (H/D, geometry/wear).

use crate::canon::Pos;
use crate::machine::MAX_AXES;

/// Tool offset numbers 1..=MAX_TOOL_OFFSETS.
pub const MAX_TOOL_OFFSETS: usize = 999;
/// G54.1 P1..=MAX_G54_1.
pub const MAX_G54_1: usize = 300;

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
}

#[derive(Debug, Clone)]
pub struct Offsets {
    work: Vec<Pos>,
    /// Index 0 is offset number 0, always zero.
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

impl Default for Offsets {
    fn default() -> Self {
        Offsets {
            work: vec![[0.0; MAX_AXES]; WORK_SLOTS],
            tools: vec![ToolOffset::default(); MAX_TOOL_OFFSETS + 1],
            touched_work: [0; WORK_WORDS],
            touched_tools: [0; TOOL_WORDS],
        }
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
    pub fn work(&self, index: usize) -> &Pos {
        &self.work[index]
    }

    pub fn work_mut(&mut self, index: usize) -> &mut Pos {
        self.touched_work[index / 64] |= 1 << (index % 64);
        &mut self.work[index]
    }

    pub fn tool(&self, number: u32) -> Option<&ToolOffset> {
        self.tools.get(number as usize)
    }

    /// Offset number 0 cannot be written (it means "no offset").
    pub fn tool_mut(&mut self, number: u32) -> Option<&mut ToolOffset> {
        if number == 0 {
            return None;
        }
        let slot = self.tools.get_mut(number as usize)?;
        self.touched_tools[number as usize / 64] |= 1 << (number % 64);
        Some(slot)
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
}
