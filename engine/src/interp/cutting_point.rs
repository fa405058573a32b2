//! Cutting point control (FANUC G43.8 type 1, G43.9 type 2; 30i-A5 manual §2.2.4, §2.2.5,
//! §2.3.20, §2.3.21) in the interpreter: the tool from the D offset, the surface normal's
//! modal rules (`,L2 I J K`), and the restrictions. Tool centre point control (`super::tcp`)
//! carries the tool tip; the geometry that places the tip from the cutting point is
//! `crate::cutting_point`, shared with the path the axes follow (`motion::path`).

use super::expr::round_to;
use super::gcode::{code, group};
use super::nc::Words;
use super::State;
use crate::alarm::AlarmId;
use crate::canon::Pos;
use crate::cutting_point::Tool;
use crate::geom::Rigid;
use crate::kin::{Kinematics, Vec3};
use crate::machine::Side;

/// Cutting point control in force.
#[derive(Debug, Clone, Copy)]
pub(super) struct CuttingPoint {
    pub(super) tool: Tool,
    /// The surface normal where the machine stands, in the table frame (unit): a block without
    /// `,L2` keeps it, on the part, whatever Π does; `None` until the start block moves.
    surface: Option<Vec3>,
    /// The G43.8/G43.9 block's normal, or a later block's `,L2`, in Π, until a move takes it.
    pub(super) commanded: Option<Vec3>,
    /// Tool tip − cutting point where the machine stands (table frame).
    pub(super) vector: Vec3,
    /// A rotary axis that turns the tool was moved by hand (PS5464 at the next move,
    /// §2.3.21).
    pub(super) disturbed: bool,
}

impl CuttingPoint {
    /// The normals (table frame) a move starts and ends with, `frame` its Π; the one it ends
    /// with is kept.
    pub(super) fn take_normals(&mut self, frame: &Rigid) -> Result<(Vec3, Vec3), AlarmId> {
        let end = match (self.commanded.take(), self.surface) {
            (Some(n), _) => frame.r * n,
            (None, Some(kept)) => kept,
            // (The start block always has one: `cutting_begin`.)
            (None, None) => return Err(AlarmId::CuttingPoint),
        };
        let start = self.surface.unwrap_or(end);
        // Opposite normals leave no way to turn one into the other (a decision: PS5464).
        if start.dot(&end) < -1.0 + 1e-12 {
            return Err(AlarmId::CuttingPoint);
        }
        self.surface = Some(end);
        Ok((start, end))
    }
}

impl State {
    /// The G43.8/G43.9 block (`tcp_begin`): the tool of offset D and the first surface normal;
    /// `None` for G43.4/G43.5.
    pub(super) fn cutting_begin(&self, w: &Words) -> Result<Option<CuttingPoint>, AlarmId> {
        if !matches!(self.modes[group::LENGTH_COMP], code::G43_8 | code::G43_9) {
            return Ok(None);
        }
        // The tool radius R is D's geometry plus wear; the corner radius r is set beside its
        // geometry (0 ≤ r ≤ geometry), and a worn ball end mill stays a ball (r at most R).
        let offset = self.offsets.tool(self.d).copied().unwrap_or_default();
        let radius = self.offsets.radius(self.d);
        if radius < 0.0 || offset.corner_radius < 0.0 || offset.corner_radius > offset.d_geometry {
            return Err(AlarmId::CuttingPoint);
        }
        let tool = Tool { radius, corner: offset.corner_radius.min(radius) };
        // TCP-39: without `,L2` words the reference tool direction (No.19697–19699).
        let normal = match self.surface_normal(w, true)? {
            Some(n) => n,
            None => Vec3::from(self.cfg.machine.tool_axis).normalize(),
        };
        Ok(Some(CuttingPoint { tool, surface: None, commanded: Some(normal), vector: Vec3::zeros(), disturbed: false }))
    }

    /// A D word that selects another offset while cutting point control stays on (not in the
    /// G43.8/G43.9 block, which takes its D): PS5464. The manual places the tool from the
    /// radius and corner radius of D (§2.3.20) but says nothing of a D changed in the mode; the
    /// mode keeps the tool it started with, so running on would cut with the old tool's
    /// geometry while the new D is shown (decision, `docs/five-axis.md`).
    pub(super) fn refuse_d_change_in_cutting(&self, w: &Words) -> Result<(), AlarmId> {
        let in_mode = self.tcp.as_ref().is_some_and(|t| t.cutting.is_some());
        let stays = matches!(self.after_block(w, group::LENGTH_COMP), code::G43_8 | code::G43_9)
            && self.block_code(w, group::LENGTH_COMP).is_none();
        match w.integer(b'D') {
            Some(d) if in_mode && stays && d != self.d as f64 => Err(AlarmId::CuttingPoint),
            _ => Ok(()),
        }
    }

    /// A block's `,L2 I J K` (in Π, unit; omitted components 0), `None` when it has none.
    /// `,L` is `,L2` and belongs to cutting point control (`cutting`); I = J = K = 0 is PS5464
    /// (TCP-39).
    pub(super) fn surface_normal(&self, w: &Words, cutting: bool) -> Result<Option<Vec3>, AlarmId> {
        if !w.has(b'l') {
            return Ok(None);
        }
        if !cutting || w.integer(b'l') != Some(2.0) {
            return Err(AlarmId::ImproperAddress);
        }
        // As many decimals as the increment system (§2.3.20).
        let [i, j, k] = [b'i', b'j', b'k'].map(|l| self.value(w, l).map(|v| round_to(v, self.steps_of(l))));
        if i.is_none() && j.is_none() && k.is_none() {
            return Ok(None);
        }
        let n = Vec3::new(i.unwrap_or(0.0), j.unwrap_or(0.0), k.unwrap_or(0.0));
        n.try_normalize(0.0).map(Some).ok_or(AlarmId::CuttingPoint)
    }

    /// The machine was moved by hand under cutting point control: a rotary axis that turns the
    /// tool makes the next move PS5464 (§2.3.21); a table that turned leaves the tool at
    /// another angle to the surface, so the tip is taken as the tool's own vector away from
    /// the cutting point there (a decision: the held vector of a singular posture is let go).
    pub(super) fn cutting_moved_to(&mut self, kin: &Kinematics, machine: &Pos) {
        let Some(before) = self.follow_machine else { return };
        let Some(c) = self.tcp.as_mut().and_then(|t| t.cutting.as_mut()) else { return };
        let turned = |side: Side| {
            kin.joints().iter().any(|j| j.side == side && j.index.is_some_and(|i| before[i] != machine[i]))
        };
        if turned(Side::Head) {
            c.disturbed = true;
        } else if let (true, Some(n)) = (turned(Side::Table), c.surface) {
            c.vector = c.tool.vector(kin.forward(machine, 0.0).tool, n);
        }
    }
}
