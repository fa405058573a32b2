//! The block the machine is executing, as a panel shows it: its line, sequence number and modal
//! state. The interpreter reads ahead of the machine (look-ahead buffering, a held program's
//! next blocks), so its own modal state is the read-ahead block's; halfway through a G43.4 loop
//! it may already say G49. Each block read leaves its state here, tagged with a serial number
//! that its motion segments carry; the controller moves the shown block on when a segment of a
//! later block starts or when a block without motion is reached.

use crate::interp::ModalState;
use std::collections::VecDeque;

/// What one block left behind once read.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BlockState {
    pub line: u32,
    pub n: Option<u32>,
    pub modal: ModalState,
}

/// Blocks read but not yet reached, and the one reached last.
#[derive(Debug, Clone)]
pub(super) struct Executing {
    /// Serial of the last block read (segments carry it as `Segment::block`; 0 = none).
    read: u64,
    /// The block shown and its serial.
    shown: (u64, BlockState),
    /// Blocks read after the shown one, in reading order.
    ahead: VecDeque<(u64, BlockState)>,
    /// The latest block reached in the reading while motion was still under way: it begins when
    /// that motion ends (unless a segment of its own begins it earlier).
    after_motion: Option<u64>,
    /// The last block read gave no command.
    last_silent: bool,
}

impl Executing {
    pub fn new(modal: ModalState) -> Self {
        Self {
            read: 0,
            shown: (0, BlockState { line: 0, n: None, modal }),
            ahead: VecDeque::new(),
            after_motion: None,
            last_silent: false,
        }
    }

    /// A block was read; its serial. `silent`: it gave no command (a macro statement, a modal
    /// change). A run of silent blocks read while motion is under way keeps only its last entry,
    /// so a long macro loop ahead of a move does not grow the list: none of them has a segment
    /// of its own to be shown by, and the motion's end shows the last one read.
    pub fn read(&mut self, block: BlockState, silent: bool) -> u64 {
        self.read += 1;
        if silent && self.last_silent && !self.ahead.is_empty() {
            self.ahead.pop_back();
        }
        self.last_silent = silent;
        self.ahead.push_back((self.read, block));
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
        while let Some(&(s, block)) = self.ahead.front() {
            if s > serial {
                break;
            }
            self.ahead.pop_front();
            self.shown = (s, block);
        }
        if self.after_motion.is_some_and(|s| s <= serial) {
            self.after_motion = None;
        }
        Some(self.shown.1)
    }

    /// Everything read is dropped or done (reset, a fresh start): show `modal` from now on.
    pub fn settle(&mut self, modal: ModalState) {
        self.ahead.clear();
        self.after_motion = None;
        self.shown = (self.read, BlockState { modal, ..self.shown.1 });
    }

    pub fn shown(&self) -> &BlockState {
        &self.shown.1
    }
}
