//! Syntec's multi-kinematic chain `G10 L5000 P_ [Q_]` (SYN-26): which of the machine's mechanism
//! chains the blocks that follow are made with (`MachineConfig::chains`, `docs/five-axis.md`).
//!
//! The switch replaces the interpreter's machine by the same machine in the chosen chain
//! (`Machine::with_chain`), so everything that reads the mechanism — TCP, the tilted working
//! plane, the tool alignments, the mode rules — reads the new one, and emits
//! `CanonKind::Chain` so that the executor and the controller's manual feeds follow in program
//! order; every command after it carries the chain in its tip basis, so the trace's tip is read
//! through it. The block's Q and its modes were checked by `modes` (COR-163, COR-160) before.

use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind};
use crate::kin::MachineKind;
use crate::machine::Chain;

impl State {
    /// `G10 L5000 P<set>` with `set` read by the caller (a whole number; P is required, as for
    /// every G10: the manual's `[P_]` gives no meaning to its absence).
    pub(super) fn switch_chain(&mut self, w: &Words, set: usize, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        // Decision (spec Q-21): P counts the sets as the manual's alarm texts do, 1st to 4th.
        let set = u8::try_from(set).ok().filter(|s| (1..=4).contains(s)).ok_or(AlarmId::ChainNotConfigured)?;
        let q = w.integer(b'Q');
        // `modes` refused it already (COR-163); kept here so that no Q is ever read as another.
        if q.is_some_and(|q| q.fract() != 0.0 || !(0.0..=4.0).contains(&q)) {
            return Err(AlarmId::ChainQ);
        }
        // Q0 and Q1 are the set as described; Q2–Q4 its listed sub-chains.
        let sub = q.map_or(1, |q| (q as u8).max(1));
        // A set without rotary axes is type 0, not on (a 3-axis machine's set 1).
        let set_alone = self.cfg.machine.with_chain(Chain { set, sub: 1 }).filter(|m| !m.rotary.is_empty());
        let set_alone = set_alone.ok_or(AlarmId::ChainNotConfigured)?;
        let spindle = set_alone.kinematics().is_some_and(|k| k.kind == MachineKind::HeadHead);
        if q.is_some() && !spindle {
            return Err(AlarmId::ChainNotSpindle);
        }
        let machine = match sub {
            1 => set_alone,
            _ => self.cfg.machine.with_chain(Chain { set, sub }).ok_or(AlarmId::ChainNotConfigured)?,
        };
        let machine = std::sync::Arc::new(machine);
        self.kinematics = machine.kinematics().cloned();
        self.wse_kinematics = super::wse::compensation_kinematics(&machine, self.kinematics.as_ref());
        self.cfg.machine = machine;
        self.emit(out, CanonKind::Chain(Chain { set, sub }));
        Ok(())
    }
}
