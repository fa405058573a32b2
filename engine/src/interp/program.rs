//! A parsed program prepared for execution: its sequence-number index and the DO/END pairing.

use crate::alarm::AlarmId;
use crate::lang::{BlockKind, Program};
use std::collections::HashMap;

const NONE: u32 = u32::MAX;

#[derive(Debug, Clone)]
pub struct Loaded {
    pub program: Program,
    /// Sequence number → block indices, in order.
    labels: HashMap<u32, Vec<u32>>,
    /// For a DO block its END, for an END block its DO; NONE otherwise.
    pub pair: Vec<u32>,
    /// Innermost DO whose range (DO, END] holds the block; NONE outside loops.
    enclosing: Vec<u32>,
    /// A loop-structure alarm a block raises when executed.
    pub loop_error: HashMap<u32, AlarmId>,
}

impl Loaded {
    pub fn new(program: Program) -> Loaded {
        let len = program.blocks.len();
        let mut labels: HashMap<u32, Vec<u32>> = HashMap::new();
        let mut pair = vec![NONE; len];
        let mut enclosing = vec![NONE; len];
        let mut loop_error = HashMap::new();
        // Open DOs: (id, block index).
        let mut open: Vec<(u8, u32)> = Vec::new();
        // DOs whose END came while the listed inner DOs were still open.
        let mut crossed: Vec<(u32, Vec<u32>)> = Vec::new();
        for (i, block) in program.blocks.iter().enumerate() {
            let i = i as u32;
            if let Some(n) = block.n {
                labels.entry(n).or_default().push(i);
            }
            enclosing[i as usize] = open.last().map_or(NONE, |&(_, d)| d);
            match &block.kind {
                BlockKind::Do { id, .. } => {
                    let bad_id = !(1..=3).contains(id) || open.iter().any(|&(o, _)| o == *id) || open.len() >= 3;
                    if bad_id {
                        loop_error.insert(i, AlarmId::IllegalLoopNumber);
                    }
                    open.push((*id, i));
                }
                BlockKind::End { id } => match open.last() {
                    Some(&(top, d)) if top == *id => {
                        open.pop();
                        pair[d as usize] = i;
                        pair[i as usize] = d;
                    }
                    _ => {
                        loop_error.insert(i, AlarmId::IllegalLoopNumber);
                        // An END of an outer DO while an inner DO is open: if the inner one is
                        // closed later, the ranges cross (decided after the scan).
                        if let Some(k) = open.iter().rposition(|&(o, _)| o == *id) {
                            let inner: Vec<u32> = open[k + 1..].iter().map(|&(_, d)| d).collect();
                            let (_, d) = open.remove(k);
                            crossed.push((d, inner));
                        }
                    }
                },
                _ => {}
            }
        }
        for (_, d) in open {
            loop_error.entry(d).or_insert(AlarmId::MissingEnd);
        }
        for (d, inner) in crossed {
            if inner.iter().any(|&i| pair[i as usize] != NONE) {
                loop_error.insert(d, AlarmId::IllegalLoopNumber);
            }
        }
        Loaded { program, labels, pair, enclosing, loop_error }
    }

    pub fn number(&self) -> Option<u32> {
        self.program.number
    }

    pub fn len(&self) -> usize {
        self.program.blocks.len()
    }

    /// The block with sequence number `n`: the first after `from`, else the first from the top.
    pub fn find_label(&self, n: u32, from: usize) -> Option<usize> {
        let list = self.labels.get(&n)?;
        list.iter().find(|&&i| i as usize > from).or(list.first()).map(|&i| i as usize)
    }

    /// A jump from `from` to `to` must not enter a DO range it is not already inside.
    pub fn jump_enters_loop(&self, from: usize, to: usize) -> bool {
        let mut d = self.enclosing[to];
        while d != NONE {
            if !self.is_inside(from, d) {
                return true;
            }
            d = self.enclosing[d as usize];
        }
        false
    }

    fn is_inside(&self, block: usize, do_block: u32) -> bool {
        let end = self.pair[do_block as usize];
        end != NONE && block > do_block as usize && block <= end as usize
    }

    pub fn pair_of(&self, i: usize) -> Option<usize> {
        let p = self.pair[i];
        (p != NONE).then_some(p as usize)
    }
}
