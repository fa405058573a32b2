//! A parsed program prepared for execution: its sequence-number index and the DO/END pairing.

use super::gcode::code;
use super::mcode;
use crate::alarm::AlarmId;
use crate::lang::{Block, BlockKind, Program, Stored};
use std::collections::HashMap;
use std::ops::{Deref, DerefMut};
use std::sync::{Arc, OnceLock};

const NONE: u32 = u32::MAX;

/// A program of the interpreter: loaded with the text, or a stored program loaded the first
/// time a call reaches it (`lang::Source`). It reads as its [`Loaded`] either way.
#[derive(Debug, Clone)]
pub struct Slot {
    loaded: OnceLock<Loaded>,
    stored: Option<Arc<Stored>>,
}

impl Slot {
    pub fn stored(stored: Arc<Stored>) -> Slot {
        Slot { loaded: OnceLock::new(), stored: Some(stored) }
    }

    /// Loaded already: not a stored program waiting for its first call.
    pub fn is_loaded(&self) -> bool {
        self.loaded.get().is_some()
    }

    fn get(&self) -> &Loaded {
        self.loaded.get_or_init(|| {
            let stored = self.stored.as_ref().expect("a slot is loaded or stored");
            Loaded::new(stored.parse())
        })
    }
}

impl From<Loaded> for Slot {
    fn from(loaded: Loaded) -> Slot {
        Slot { loaded: OnceLock::from(loaded), stored: None }
    }
}

impl Deref for Slot {
    type Target = Loaded;
    fn deref(&self) -> &Loaded {
        self.get()
    }
}

impl DerefMut for Slot {
    fn deref_mut(&mut self) -> &mut Loaded {
        self.get();
        self.loaded.get_mut().expect("loaded by get")
    }
}

#[derive(Debug, Clone)]
pub struct Loaded {
    /// The `O` number and line; the blocks are in `chunks`.
    pub program: Program,
    /// The blocks, in the parts they arrived in (kept as they came: appending a part to one
    /// vector would copy every block once more).
    chunks: Vec<Vec<Block>>,
    /// Index of the first block of each chunk.
    starts: Vec<u32>,
    len: usize,
    /// Sequence number → block indices, in order.
    labels: HashMap<u32, Vec<u32>>,
    /// For a DO block its END, for an END block its DO; NONE otherwise.
    pub pair: Vec<u32>,
    /// Innermost DO whose range (DO, END] holds the block; NONE outside loops.
    enclosing: Vec<u32>,
    /// A loop-structure alarm a block raises when executed.
    pub loop_error: HashMap<u32, AlarmId>,
    /// The first of its blocks that refuses the whole file in the Syntec dialect (`%@MACRO`,
    /// `lang::SyntecOnly::whole_file`): a run of the file, or a call of the program, starts there.
    pub macro_format: Option<u32>,
    /// Open DOs while blocks are still being added: (id, block index).
    open: Vec<(u8, u32)>,
    /// DOs whose END came while the listed inner DOs were still open.
    crossed: Vec<(u32, Vec<u32>)>,
    /// No more blocks will come: the loop structure is final.
    pub finished: bool,
    /// Per block: it may jump, loop, call or return, so while blocks are still arriving it must
    /// wait for the whole file (an M or G code given by an expression could be one of those).
    pub reaches_beyond: Vec<bool>,
}

/// Whether the words of a `[cond] words` block are the Haas NGC's conditional M99: a literal
/// M99 and a P, nothing else (`[cond] M99 P<n>`, the one form the NGC manual gives).
pub(crate) fn is_conditional_m99(words: &crate::lang::Words) -> bool {
    use crate::lang::WordValue;
    let m99 =
        |w: &crate::lang::Word| w.letter == b'M' && matches!(w.value, WordValue::Number { value, .. } if value == 99.0);
    words.len() == 2 && words.iter().filter(|w| m99(w)).count() == 1 && words.iter().any(|w| w.letter == b'P')
}

/// Whether a block may jump, loop, call or return (see `Loaded::reaches_beyond`).
fn reaches_beyond(block: &Block) -> bool {
    use crate::lang::{Expr, WordValue};
    match &block.kind {
        BlockKind::Empty | BlockKind::Error(_) | BlockKind::Assign { .. } | BlockKind::IfThen { .. } => false,
        BlockKind::SyntecOnly(_) => false,
        BlockKind::Output(_) => false,
        BlockKind::Goto(_) | BlockKind::IfGoto { .. } | BlockKind::Do { .. } | BlockKind::End { .. } => true,
        BlockKind::IfWords { .. } => true,
        BlockKind::Words(words) => words.iter().any(|w| match (&w.letter, &w.value) {
            (b'M', WordValue::Number { value, .. }) => {
                matches!(*value as u32, mcode::M97 | mcode::M98 | mcode::M99 | mcode::M198)
            }
            (b'G', WordValue::Number { value, .. }) => {
                // Haas G150 reads its outline from another block or program.
                super::gcode::code_of(*value).is_some_and(|c| code::MACRO_CALLS.contains(&c) || c == code::G150)
            }
            (b'M' | b'G', WordValue::Expr(e)) => !matches!(**e, Expr::Num { .. }),
            _ => false,
        }),
    }
}

impl Loaded {
    pub fn new(program: Program) -> Loaded {
        let mut loaded = Loaded::open(program.clone_header());
        loaded.extend(program.blocks);
        loaded.finish();
        loaded
    }

    /// A program that more blocks may follow ([`Loaded::extend`], then [`Loaded::finish`]).
    pub fn new_open(program: Program) -> Loaded {
        let mut loaded = Loaded::open(program.clone_header());
        loaded.extend(program.blocks);
        loaded
    }

    /// A program whose blocks arrive later ([`Loaded::extend`], then [`Loaded::finish`]).
    pub fn open(header: Program) -> Loaded {
        Loaded {
            program: header,
            chunks: Vec::new(),
            starts: Vec::new(),
            len: 0,
            labels: HashMap::new(),
            pair: Vec::new(),
            enclosing: Vec::new(),
            loop_error: HashMap::new(),
            macro_format: None,
            open: Vec::new(),
            crossed: Vec::new(),
            finished: false,
            reaches_beyond: Vec::new(),
        }
    }

    /// Add blocks at the end, indexing their sequence numbers and DO/END structure.
    pub fn extend(&mut self, blocks: Vec<Block>) {
        if blocks.is_empty() {
            return;
        }
        self.reaches_beyond.reserve(blocks.len());
        self.pair.reserve(blocks.len());
        self.enclosing.reserve(blocks.len());
        for (i, block) in (self.len as u32..).zip(&blocks) {
            if let Some(n) = block.n {
                self.labels.entry(n).or_default().push(i);
            }
            self.pair.push(NONE);
            self.enclosing.push(self.open.last().map_or(NONE, |&(_, d)| d));
            match &block.kind {
                BlockKind::Do { id, .. } => {
                    let open = &self.open;
                    let bad_id = !(1..=3).contains(id) || open.iter().any(|&(o, _)| o == *id) || open.len() >= 3;
                    if bad_id {
                        self.loop_error.insert(i, AlarmId::IllegalLoopNumber);
                    }
                    self.open.push((*id, i));
                }
                BlockKind::SyntecOnly(s) if s.whole_file && self.macro_format.is_none() => self.macro_format = Some(i),
                BlockKind::End { id } => match self.open.last() {
                    Some(&(top, d)) if top == *id => {
                        self.open.pop();
                        self.pair[d as usize] = i;
                        self.pair[i as usize] = d;
                    }
                    _ => {
                        self.loop_error.insert(i, AlarmId::IllegalLoopNumber);
                        // An END of an outer DO while an inner DO is open: if the inner one is
                        // closed later, the ranges cross (decided when the program is finished).
                        if let Some(k) = self.open.iter().rposition(|&(o, _)| o == *id) {
                            let inner: Vec<u32> = self.open[k + 1..].iter().map(|&(_, d)| d).collect();
                            let (_, d) = self.open.remove(k);
                            self.crossed.push((d, inner));
                        }
                    }
                },
                _ => {}
            }
            self.reaches_beyond.push(reaches_beyond(block));
        }
        self.starts.push(self.len as u32);
        self.len += blocks.len();
        self.chunks.push(blocks);
    }

    /// No more blocks: DOs still open miss their END, crossed ranges are known.
    pub fn finish(&mut self) {
        if self.finished {
            return;
        }
        self.finished = true;
        for (_, d) in self.open.drain(..) {
            self.loop_error.entry(d).or_insert(AlarmId::MissingEnd);
        }
        for (d, inner) in self.crossed.drain(..) {
            if inner.iter().any(|&i| self.pair[i as usize] != NONE) {
                self.loop_error.insert(d, AlarmId::IllegalLoopNumber);
            }
        }
    }

    pub fn number(&self) -> Option<u32> {
        self.program.number
    }

    pub fn len(&self) -> usize {
        self.len
    }

    /// Block `i` (`i < len()`).
    pub fn block(&self, i: usize) -> &Block {
        // Few chunks (one per part of a few hundred kilobytes), and the interpreter mostly runs
        // in one of the last, which arrived most recently: search from the end.
        let c = self.starts.iter().rposition(|&s| s as usize <= i).expect("block index in range");
        &self.chunks[c][i - self.starts[c] as usize]
    }

    /// Comments before the first O number are a file header, not a program.
    pub fn is_header(&self) -> bool {
        self.program.number.is_none() && self.blocks().all(crate::lang::is_header_block)
    }

    /// The blocks in order.
    pub fn blocks(&self) -> impl Iterator<Item = &Block> {
        self.chunks.iter().flatten()
    }

    /// The block with sequence number `n`: the first after `from`, else the first from the top.
    pub fn find_label(&self, n: u32, from: usize) -> Option<usize> {
        let list = self.labels.get(&n)?;
        list.iter().find(|&&i| i as usize > from).or(list.first()).map(|&i| i as usize)
    }

    /// The first block of the program with sequence number `n` (a Syntec GOTO: "if the program
    /// holds the same N number twice, the first one counts").
    pub fn first_label(&self, n: u32) -> Option<usize> {
        self.labels.get(&n)?.first().map(|&i| i as usize)
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
