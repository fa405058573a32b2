//! G31, the skip function: a straight feed move that ends where the probe touches what is on
//! the table (`crate::workpiece`), or at its end point when it touches nothing; `#5061…` hold
//! where it ended and the Haas M78/M79 alarm on whether it touched (`docs/conventions.md`,
//! "Workpiece and probing").
//!
//! The contact is found when the block is read, from the geometry alone: the machine axes at
//! the start and at the end of the move, the tool tip and direction there by forward
//! kinematics (in the table frame, where the boxes are), and the probe's stylus as a ball of the
//! radius of the D offset in effect whose lowest point along the tool is the tip. The move is
//! cut at the first contact, so the machine stops there, as a probe's signal stops a real one
//! (the stop distance after the signal is not modelled: the position recorded is the contact).
//! The machine's own state enters as [`MachineView`]: a locked axis does not move the probe,
//! and where the machine stands off the program's coordinates it probes from there.

use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::{Canon, CanonKind, MotionKind, Pos};
use crate::kin::Vec3;
use crate::machine::{AxisKind, MAX_AXES};

/// The last G31's result.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct Skip {
    /// Where it ended (the contact, or its end point), workpiece coordinates.
    pub pos: Pos,
    /// The probe touched something.
    pub found: bool,
}

/// Where the machine's axes really are beside the program's machine coordinates, as the
/// controller knows it (machine lock, Z-axis neglect, what a locked run left, a handle
/// interruption's shift): the probe moves with the real axes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MachineView {
    /// Per axis: locked at this machine position.
    pub held: [Option<f64>; MAX_AXES],
    /// Real minus program machine position of the axes that move.
    pub offset: Pos,
}

impl MachineView {
    pub(super) fn real(&self, program: &Pos) -> Pos {
        std::array::from_fn(|i| self.held[i].unwrap_or(program[i] + self.offset[i]))
    }
}

impl State {
    /// A G31 block's move: to its end point, or to where the probe touches the workpiece.
    pub(super) fn skip_move(&mut self, w: &Words, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        // The NGC's rule: the G31 line must have a feed (its G31 page).
        if self.cfg.dialect == crate::Dialect::Haas && !w.has(b'F') {
            return Err(AlarmId::FeedZero);
        }
        self.check_feed()?;
        if self.modes[group::CUTTER_COMP] != code::G40 {
            return Err(AlarmId::SkipInCutterComp);
        }
        // The control cannot blend a skip block into the next: it does not know where it ends.
        self.exact_stop = true;
        let from = self.xf.programmed;
        let target = self.target(w);
        let contact = match self.cfg.workpiece.is_empty() {
            true => None,
            false => {
                // The whole move made on a copy of the state gives the machine axes at its end,
                // in whatever mode the block is read (TCP, a tilted plane, DWO…).
                let mut whole = self.clone();
                let mut scratch = Vec::new();
                whole.straight_move(target, &mut scratch)?;
                let end = scratch.iter().rev().find_map(|c| match &c.kind {
                    CanonKind::Motion(m) => Some(m.machine),
                    _ => None,
                });
                match end {
                    Some(end) => self.contact_on_the_way(&end)?,
                    None => None,
                }
            }
        };
        let end = match contact {
            Some(t) => std::array::from_fn(|i| from[i] + (target[i] - from[i]) * t),
            None => target,
        };
        self.straight_move(end, out)?;
        self.skip = Skip { pos: self.pos, found: contact.is_some() };
        Ok(())
    }

    /// A straight feed move to `programmed`: along the tip under TCP, in a tilted plane and the
    /// other modes that follow it, else as a plain move.
    fn straight_move(&mut self, programmed: Pos, out: &mut Vec<Canon>) -> Result<(), AlarmId> {
        if !self.follows_tip() {
            self.move_to(MotionKind::Linear, programmed, out);
            return Ok(());
        }
        let target = self.xf.forward(&programmed);
        self.tip_motion(MotionKind::Linear, target, None, out)?;
        self.xf.programmed = programmed;
        Ok(())
    }

    /// The fraction of the move from where the machine stands to the machine axes `end` at which
    /// the probe first touches the workpiece. The programmed point and the tip move in
    /// proportion while no rotary axis turns (every transform between them is then affine); a
    /// move that turns one toward a workpiece is not built.
    fn contact_on_the_way(&self, end: &Pos) -> Result<Option<f64>, AlarmId> {
        let workpiece = &self.cfg.workpiece;
        let view = &self.machine_view;
        let start = view.real(&self.machine_position());
        let end = view.real(end);
        let machine = &self.cfg.machine;
        let turns = machine.axes.iter().enumerate().any(|(i, a)| a.kind == AxisKind::Rotary && start[i] != end[i]);
        // Without length compensation fivex knows no tool length to place the probe by (the
        // tool table holds offsets, not the tool's real length): the spindle nose would be
        // taken for the stylus, the tool setter's case among them.
        let no_length = code::LENGTH_CANCEL.contains(&self.modes[group::LENGTH_COMP]);
        if turns || no_length {
            return Err(AlarmId::GCodeNotBuilt);
        }
        let basis = self.tip_basis();
        let kin = machine.kinematics_of(basis.chain).map(|k| &**k);
        let radius = self.offsets.radius(self.d).max(0.0);
        let centre = |m: &Pos| {
            let tip = crate::tip::locate(kin, m, &basis);
            Vec3::from(tip.table) + Vec3::from(tip.tool) * radius
        };
        Ok(workpiece.first_contact(centre(&start), centre(&end), radius))
    }
}
