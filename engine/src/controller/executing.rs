//! The block the machine is executing, as a panel shows it: its line, sequence number and modal
//! state. The interpreter reads ahead of the machine (look-ahead buffering, a held program's
//! next blocks), so its own modal state is the read-ahead block's; halfway through a G43.4 loop
//! it may already say G49. Each block read leaves its state here, tagged with a serial number
//! that its motion segments carry; the controller moves the shown block on when a segment of a
//! later block starts or when a block without motion is reached.
//!
//! A block that changed more than the motion group and F (`State::modal_part_changed`) also
//! leaves a copy of what it put in force (`ModalPart`): a reset puts the interpreter back in
//! the executed block's state, not the read-ahead's (`Controller::reset`).

use crate::interp::{ModalPart, ModalState, TiltedPlane};
use std::collections::VecDeque;

/// What one block left behind once read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BlockState {
    pub line: u32,
    pub n: Option<u32>,
    pub modal: ModalState,
    /// The tilted working plane in force.
    pub plane: Option<TiltedPlane>,
}

/// A block read ahead: its line and number (its modal state is in `Executing::modals`).
/// 16 bytes: hundreds are held while the planner looks ahead (`docs/performance.md`, memory).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ahead {
    serial: u64,
    line: u32,
    /// The sequence number, [`NO_N`] for none (an `Option<u32>` would take 8 bytes).
    n: u32,
}

/// `Ahead::n` of a block without a sequence number (N numbers have at most 8 digits).
const NO_N: u32 = u32::MAX;

/// Blocks read but not yet reached, and the one reached last.
#[derive(Debug, Clone)]
pub(super) struct Executing {
    /// Serial of the last block read (segments carry it as `Segment::block`; 0 = none).
    read: u64,
    /// The block shown and its serial.
    shown: (u64, BlockState),
    /// Blocks read after the shown one, in reading order.
    ahead: VecDeque<Ahead>,
    /// The modal states of the blocks ahead, each kept only where it differs from the block
    /// read before (a block's is that of the last entry at or before its serial, else the
    /// shown one's): the reading runs hundreds of blocks ahead of the machine (the planner's
    /// look-ahead) and a modal state is 104 bytes, mostly repeated.
    modals: VecDeque<(u64, ModalState)>,
    /// The tilted working planes of the blocks ahead, kept as `modals` (planes change rarely).
    planes: VecDeque<(u64, Option<TiltedPlane>)>,
    /// What the blocks ahead put in force, kept only for those that changed more than the
    /// motion group and F (most blocks of a program only move).
    parts: VecDeque<(u64, Box<ModalPart>)>,
    /// That of the block shown (or of the last block before it that left one).
    shown_part: Box<ModalPart>,
    /// The latest block reached in the reading while motion was still under way: it begins when
    /// that motion ends (unless a segment of its own begins it earlier).
    after_motion: Option<u64>,
    /// The last block read gave no command.
    last_silent: bool,
}

impl Executing {
    pub fn new(modal: ModalState, plane: Option<TiltedPlane>, part: ModalPart) -> Self {
        Self {
            read: 0,
            shown: (0, BlockState { line: 0, n: None, modal, plane }),
            ahead: VecDeque::new(),
            modals: VecDeque::new(),
            planes: VecDeque::new(),
            parts: VecDeque::new(),
            shown_part: Box::new(part),
            after_motion: None,
            last_silent: false,
        }
    }

    /// A block was read; its serial. `silent`: it gave no command (a macro statement, a modal
    /// change). A run of silent blocks read while motion is under way keeps only its last entry,
    /// so a long macro loop ahead of a move does not grow the list: none of them has a segment
    /// of its own to be shown by, and the motion's end shows the last one read. `part`: what the
    /// block put in force, if it changed more than the motion group and F.
    pub fn read(&mut self, block: BlockState, silent: bool, mut part: Option<Box<ModalPart>>) -> u64 {
        self.read += 1;
        if silent && self.last_silent {
            if let Some(dropped) = self.ahead.pop_back() {
                if self.parts.back().is_some_and(|p| p.0 == dropped.serial) {
                    // Still in force after this block unless it left its own.
                    let kept = self.parts.pop_back().map(|p| p.1);
                    part = part.or(kept);
                }
                if self.modals.back().is_some_and(|m| m.0 == dropped.serial) {
                    self.modals.pop_back();
                }
                if self.planes.back().is_some_and(|p| p.0 == dropped.serial) {
                    self.planes.pop_back();
                }
            }
        }
        self.last_silent = silent;
        let before = self.modals.back().map_or(&self.shown.1.modal, |m| &m.1);
        if !same(before, &block.modal) {
            self.modals.push_back((self.read, block.modal));
        }
        if self.planes.back().map_or(&self.shown.1.plane, |p| &p.1) != &block.plane {
            self.planes.push_back((self.read, block.plane));
        }
        if let Some(part) = part {
            self.parts.push_back((self.read, part));
        }
        self.ahead.push_back(Ahead { serial: self.read, line: block.line, n: block.n.unwrap_or(NO_N) });
        self.read
    }

    /// The reading reached block `serial` (its marker): at once when nothing moves, else when the
    /// motion before it ends.
    pub fn reached(&mut self, serial: u64, motion_pending: bool) -> Option<BlockState> {
        if motion_pending {
            self.after_motion = Some(serial);
            None
        } else {
            self.begin(serial)
        }
    }

    /// The motion queued before the blocks reached has ended.
    pub fn motion_ended(&mut self) -> Option<BlockState> {
        self.after_motion.take().and_then(|serial| self.begin(serial))
    }

    /// Block `serial` begins (a segment of it started, or it was reached with nothing moving);
    /// the block state now shown, if it changed.
    pub fn begin(&mut self, serial: u64) -> Option<BlockState> {
        if serial <= self.shown.0 {
            return None;
        }
        while let Some(&Ahead { serial: s, line, n }) = self.ahead.front() {
            if s > serial {
                break;
            }
            self.ahead.pop_front();
            let mut modal = self.shown.1.modal;
            while self.modals.front().is_some_and(|m| m.0 <= s) {
                modal = self.modals.pop_front().map_or(modal, |m| m.1);
            }
            let mut plane = self.shown.1.plane;
            while self.planes.front().is_some_and(|p| p.0 <= s) {
                plane = self.planes.pop_front().map_or(plane, |p| p.1);
            }
            while self.parts.front().is_some_and(|p| p.0 <= s) {
                if let Some((_, part)) = self.parts.pop_front() {
                    self.shown_part = part;
                }
            }
            self.shown = (s, BlockState { line, n: (n != NO_N).then_some(n), modal, plane });
        }
        if self.after_motion.is_some_and(|s| s <= serial) {
            self.after_motion = None;
        }
        Some(self.shown.1)
    }

    /// Everything read is dropped or done (reset, a fresh start): show `modal` and `plane` from
    /// now on.
    pub fn settle(&mut self, modal: ModalState, plane: Option<TiltedPlane>, part: ModalPart) {
        self.ahead.clear();
        self.modals.clear();
        self.planes.clear();
        self.parts.clear();
        *self.shown_part = part;
        self.after_motion = None;
        self.shown = (self.read, BlockState { modal, plane, ..self.shown.1 });
    }

    pub fn shown(&self) -> &BlockState {
        &self.shown.1
    }

    /// What the block shown put in force (with its modal state: `ModalPart`).
    pub fn shown_part(&self) -> &ModalPart {
        &self.shown_part
    }
}

/// Equal bit for bit (a feed of -0.0 is not 0.0's), so that a block shows the state it was read
/// with exactly.
fn same(a: &ModalState, b: &ModalState) -> bool {
    a == b && a.words.f.to_bits() == b.words.f.to_bits() && a.words.s.to_bits() == b.words.s.to_bits()
}
