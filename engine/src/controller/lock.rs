//! Machine lock, all axes (FANUC MLK), and Z-axis neglect (FANUC ZNG: the lock of the Z axis
//! alone): the program runs — blocks, the workpiece position and the time go on as without it
//! — but a locked axis does not move: its machine position, and the tool tip read from the
//! machine axes by forward kinematics, stay where the machine stood when the lock was switched
//! on. Manual moves under the lock move the positions shown, not the locked axes.
//!
//! After the lock is switched off the axis stays where it is and the program's coordinates stay
//! where the locked run left them: the two disagree by [`Lock::offset`], added where positions
//! leave the controller ([`Controller::machine_now`]), until the reference return sets them
//! equal again (as on the real control, where the coordinates no longer match the machine
//! after a machine-locked run; `docs/dialects.md`, "The operator's switches and counters").

use super::{Controller, Refusal};
use crate::canon::Pos;
use crate::machine::MAX_AXES;
use crate::Dialect;

#[derive(Debug, Default)]
pub(super) struct Lock {
    /// Per axis: locked, and where it stands.
    pub(super) held: [Option<f64>; MAX_AXES],
    /// Machine minus the program's machine coordinates after a locked run, per axis.
    pub(super) offset: Pos,
}

impl Controller {
    /// Machine lock (all axes) on or off. Changed only while nothing moves or is queued (idle,
    /// or at a single-block / M00 stop), like dry run: a plan under way was made for a moving
    /// machine.
    pub fn set_machine_lock(&mut self, on: bool) -> Result<(), Refusal> {
        self.set_locks(on, self.panel.z_neglect)
    }

    /// Z-axis neglect (FANUC only; the Syntec manual followed describes no such switch) on or
    /// off, under the same rule as machine lock.
    pub fn set_z_neglect(&mut self, on: bool) -> Result<(), Refusal> {
        if on && !self.can_neglect_z() {
            return Err(Refusal::NoAxis);
        }
        self.set_locks(self.panel.machine_lock, on)
    }

    /// Whether this controller has Z-axis neglect: a FANUC one with a Z axis.
    pub fn can_neglect_z(&self) -> bool {
        self.interp.config().dialect == Dialect::Fanuc && self.axis('Z').is_ok()
    }

    /// Nothing moves or is planned (idle, at a single-block or M00/M01 stop, before a start):
    /// where dry run, machine lock and Z-axis neglect may change.
    pub fn at_block_boundary(&self) -> bool {
        !(self.exec.is_moving() || self.exec.has_queued() || self.interrupt.moving.is_some())
    }

    fn set_locks(&mut self, all: bool, z: bool) -> Result<(), Refusal> {
        if (all, z) == (self.panel.machine_lock, self.panel.z_neglect) {
            return Ok(());
        }
        if !self.at_block_boundary() {
            return Err(Refusal::Busy);
        }
        let (now, moved) = (self.machine_now(), self.moved_machine());
        let z_axis = self.axis('Z').ok();
        for i in 0..MAX_AXES {
            let lock = all || (z && z_axis == Some(i));
            match (self.lock.held[i], lock) {
                (None, true) => self.lock.held[i] = Some(now[i]),
                (Some(held), false) => {
                    self.lock.held[i] = None;
                    self.lock.offset[i] = held - moved[i];
                }
                _ => {}
            }
        }
        (self.panel.machine_lock, self.panel.z_neglect) = (all, z);
        self.tell_machine_view();
        Ok(())
    }

    /// Tell the interpreter where the real axes stand beside the program's machine coordinates
    /// (locked axes, a locked run's offset, the handle interruption's shift once its move has
    /// ended), for the probe of a skip move read from now on (`interp::skip`).
    pub(super) fn tell_machine_view(&mut self) {
        let shift = self.interrupt.last();
        let offset = std::array::from_fn(|i| self.lock.offset[i] + shift[i]);
        self.interp.set_machine_view(crate::interp::MachineView { held: self.lock.held, offset });
    }

    /// How far the machine stands from where the program's coordinates put it, per axis: what
    /// a locked run left, or while locked what the lock has kept from moving (zero when they
    /// agree).
    pub fn lock_offset(&self) -> Pos {
        let moved = self.moved_machine();
        std::array::from_fn(|i| self.lock.held[i].map_or(self.lock.offset[i], |held| held - moved[i]))
    }

    /// Where the machine stands now: a locked axis where the lock holds it, the others where
    /// the program and the manual moves put them plus what a locked run left.
    pub(super) fn machine_now(&self) -> Pos {
        let moved = self.moved_machine();
        if self.lock.offset == [0.0; MAX_AXES] && self.lock.held.iter().all(Option::is_none) {
            return moved;
        }
        std::array::from_fn(|i| self.lock.held[i].unwrap_or(moved[i] + self.lock.offset[i]))
    }

    /// The reference return sets the coordinates to the machine again: the offset a locked run
    /// left becomes where the controller's coordinates start from (a locked axis does not move,
    /// so it keeps its offset to come).
    pub(super) fn clear_lock_offset(&mut self) {
        if self.lock.offset == [0.0; MAX_AXES] {
            return;
        }
        let offset = std::mem::take(&mut self.lock.offset);
        for (x, d) in self.exec.here.machine.iter_mut().zip(&offset) {
            *x += d;
        }
        self.stand_here();
        self.tell_machine_view();
    }
}
