//! FANUC's operator-panel choice of the 5-axis manual feeds (S000-IV §2, spec
//! `fanuc-twp-wsec-manual-params.md` MAN-05…MAN-17, §6.7): the feed mode signals ALNGH, RGHTH,
//! RNDH and TB_BASE say which family the JOG signals ±Jn and the first handle (axis select code
//! HS1A–HS1E, compared with No.12310–12314) drive; what is not enabled is the ordinary feed of
//! the axis. Pure: the controller asks [`ManualSignals::jog_target`] and
//! [`ManualSignals::handle_target`] and moves (`docs/five-axis.md`, 5-axis manual operation).

use crate::kin::{Kinematics, ManualFeed};
use crate::machine::MachineConfig;

/// The panel signals of the 5-axis manual feeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ManualSignals {
    /// Tool axis direction feed mode (ALNGH).
    pub alngh: bool,
    /// Tool axis right-angle direction feed mode (RGHTH).
    pub rghth: bool,
    /// Tool tip centre rotation feed mode (RNDH).
    pub rndh: bool,
    /// Table base (TB_BASE): ALNGH / RGHTH select the table vertical / horizontal feeds.
    pub tb_base: bool,
    /// The first handle's axis select code HS1A–HS1E (0–31): an axis number, or a code of
    /// No.12310–12314; 0 selects nothing.
    pub handle_select: u8,
}

/// What a JOG signal or the handle moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ManualTarget {
    /// The axis (index) alone, the ordinary JOG / handle feed.
    Axis(usize),
    /// X/Y/Z along a 5-axis feed direction.
    Feed(ManualFeed),
    /// Tool tip centre rotation of the rotary axis (index).
    TipRotation(usize),
    /// Nothing: the handle selects no axis (its pulses are discarded).
    Nothing,
}

/// The one feed mode signal that is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Family {
    Along,
    RightAngle,
    Round,
}

impl ManualSignals {
    /// *Decision* (OQ-27, conflicts not described): two or three mode signals at once enable no
    /// 5-axis feed; the axes feed as without them.
    fn family(&self) -> Option<Family> {
        match (self.alngh, self.rghth, self.rndh) {
            (true, false, false) => Some(Family::Along),
            (false, true, false) => Some(Family::RightAngle),
            (false, false, true) => Some(Family::Round),
            _ => None,
        }
    }

    /// What ±J of axis `axis` (index) drives (MAN-06/08/12/15/17): with ALNGH the axis of
    /// No.19697's direction is the tool axis (TB_BASE 0) or table vertical (1) feed, with RGHTH
    /// the two perpendicular axes are direction 1 and 2 (OQ-26 for 19697 = 1, 2), with RNDH a
    /// rotary axis of the mechanism turns about the tool tip; the signals are chosen by No.19697
    /// alone, whatever RA/RB tilt the reference direction (TV-MAN-03e). Any other axis, or no
    /// kinematics: the ordinary JOG of the axis (*decision*: the manual only says when the
    /// 5-axis feed is enabled).
    pub fn jog_target(&self, kin: Option<&Kinematics>, axis: usize) -> ManualTarget {
        let (Some(kin), Some(family)) = (kin, self.family()) else { return ManualTarget::Axis(axis) };
        let linear = kin.linear.iter().position(|&i| i == Some(axis));
        match (family, linear) {
            (Family::Round, None) if is_rotary_joint(kin, axis) => ManualTarget::TipRotation(axis),
            (Family::Along | Family::RightAngle, Some(k)) => {
                let feed = kin.manual_feed_of_axis(k, self.tb_base);
                let along = matches!(feed, Some(ManualFeed::ToolAxis | ManualFeed::TableVertical));
                match feed {
                    Some(f) if along == (family == Family::Along) => ManualTarget::Feed(f),
                    _ => ManualTarget::Axis(axis),
                }
            }
            _ => ManualTarget::Axis(axis),
        }
    }

    /// What the first handle drives (MAN-05/07/11/14/16): with ALNGH the code of No.12310 the
    /// tool axis / table vertical feed, with RGHTH those of No.12311 and No.12312 direction 1
    /// and 2, with RNDH those of No.12313 and No.12314 tip rotation of the first and second
    /// rotary axis (OQ-25); otherwise the code is an axis number (1…), the ordinary handle feed
    /// of that axis, or nothing.
    pub fn handle_target(&self, kin: Option<&Kinematics>, machine: &MachineConfig) -> ManualTarget {
        let code = self.handle_select;
        if code == 0 {
            return ManualTarget::Nothing;
        }
        let codes = machine.manual.handle_codes;
        let five = kin.and_then(|_| self.family()).and_then(|family| {
            let table = self.tb_base;
            let feed =
                |first: ManualFeed, second: ManualFeed| Some(ManualTarget::Feed(if table { second } else { first }));
            match family {
                Family::Along if code == codes[0] => feed(ManualFeed::ToolAxis, ManualFeed::TableVertical),
                Family::RightAngle if code == codes[1] => feed(ManualFeed::RightAngle1, ManualFeed::TableHorizontal1),
                Family::RightAngle if code == codes[2] => feed(ManualFeed::RightAngle2, ManualFeed::TableHorizontal2),
                Family::Round => {
                    let k = [codes[3], codes[4]].iter().position(|&c| c == code)?;
                    let name = machine.rotary.get(k)?.axis;
                    let i = machine.axes.iter().position(|a| a.name == name)?;
                    Some(ManualTarget::TipRotation(i))
                }
                _ => None,
            }
        });
        five.unwrap_or_else(|| {
            let i = code as usize - 1;
            if i < machine.axes.len() {
                ManualTarget::Axis(i)
            } else {
                ManualTarget::Nothing
            }
        })
    }
}

/// Whether axis `i` is one of the mechanism's rotary axes.
fn is_rotary_joint(kin: &Kinematics, i: usize) -> bool {
    kin.head.iter().chain(&kin.table).any(|j| j.index == Some(i))
}

/// The axis (index) whose ±J signal drives `feed` (No.19697's mapping, MAN-06/08/15/17): the
/// axis whose No.1423 a 5-axis JOG feed with JFR runs at.
pub(super) fn signal_axis(kin: &Kinematics, feed: ManualFeed) -> Option<usize> {
    let table = matches!(feed, ManualFeed::TableVertical | ManualFeed::TableHorizontal1 | ManualFeed::TableHorizontal2);
    (0..3).find(|&k| kin.manual_feed_of_axis(k, table) == Some(feed)).and_then(|k| kin.linear[k])
}
