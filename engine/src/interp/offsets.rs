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
}

impl Default for Offsets {
    fn default() -> Self {
        Offsets { work: vec![[0.0; MAX_AXES]; 7 + MAX_G54_1], tools: vec![ToolOffset::default(); MAX_TOOL_OFFSETS + 1] }
    }
}

impl Offsets {
    pub fn work(&self, index: usize) -> &Pos {
        &self.work[index]
    }

    pub fn work_mut(&mut self, index: usize) -> &mut Pos {
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
        self.tools.get_mut(number as usize)
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
