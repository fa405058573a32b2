//! What a G10 block may hold (`docs/conventions.md`, "G10"): G10 takes the block's words as its
//! data, so every other command of the block would be dropped without a word — the H of
//! `G10 L2 P1 X5. G43 H1`, the move of `G10 L5000 P2 G01 X10.`, the tool length of the RTCP
//! that `G10 L5000 P2 G43.4 H1` starts on the chain before the switch. fivex never drops a
//! command (decision; no manual gives G10 a companion beyond its format lines): besides its data
//! a G10 block holds N and G90/G91 (the absolute/incremental input of its values), and anything
//! else is refused at the block. The interpreter (`nc`) and `fivex check` (`crate::check`) ask
//! the same functions.

use super::gcode::{self, code, group};
use crate::alarm::AlarmId;
use crate::dialect::Dialect;

/// The data a G10 form takes (its L), besides L and P.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Form {
    /// L2 (work offsets, Haas P0 the G52 offset) and L20 (G54.1 P): axis words.
    WorkOffset,
    /// L1, L10–L13 (tool offset memory C): R.
    ToolOffset,
    /// Syntec L5000 (the mechanism chain): Q.
    Chain,
}

/// G10's P as a number (`p`: its value, a variable's rounded; `pointed`: written with a
/// decimal point). FANUC's PS0031 is the alarm of a G10 whose "sign or decimal point of the
/// specified address is in error, or the specified address is out of range", or without "a
/// data setting address such as P or R" (30i alarm list): so a missing, negative or fractional P
/// and, in FANUC, one written with a point. Syntec and Haas read `P2.` as P2, as their L. The
/// range of P is the form's (`nc`'s `data_setting`); Syntec's L5000 keeps its own alarms.
pub(crate) fn p_number(p: Option<f64>, pointed: bool, form: Form, dialect: Dialect) -> Result<usize, AlarmId> {
    let wrong = if form == Form::Chain { AlarmId::DataSettingFormat } else { AlarmId::IllegalG10Command };
    let p = p.ok_or(wrong.clone())?;
    if p < 0.0 || p.fract() != 0.0 || (pointed && dialect == Dialect::Fanuc && form != Form::Chain) {
        return Err(wrong);
    }
    Ok(p as usize)
}

/// The form of `G10 L<l>`; a value no form has (an L with a fraction, `L5000` outside the
/// Syntec dialect) is the G10 format alarm. `pointed`: L was written with a decimal point,
/// which FANUC's L does not take (PS0007, as its other addresses without one); Syntec and Haas
/// read a whole value either way.
pub(crate) fn form(l: f64, pointed: bool, dialect: Dialect) -> Result<Form, AlarmId> {
    if pointed && dialect == Dialect::Fanuc {
        return Err(AlarmId::IllegalDecimalPoint);
    }
    if l.fract() != 0.0 {
        return Err(AlarmId::DataSettingFormat);
    }
    match l {
        2.0 | 20.0 => Ok(Form::WorkOffset),
        1.0 | 10.0..=13.0 => Ok(Form::ToolOffset),
        5000.0 if dialect == Dialect::Syntec => Ok(Form::Chain),
        _ => Err(AlarmId::DataSettingFormat),
    }
}

/// Why a G code other than G10 may not stand in a G10 block, if it may not. Syntec's
/// `G10 L5000` beside a code that turns a 5-axis function on is its COR-160 ("make sure 5-axis
/// function is disabled for the alarmed block", the alarm's solution); any other code is the
/// dialect's alarm for codes that cannot share a block.
pub(crate) fn g_code(code: u16, form: Option<Form>, dialect: Dialect) -> Option<(AlarmId, &'static str)> {
    if code == code::G10 || gcode::lookup(code, dialect).is_some_and(|d| d.group == group::DISTANCE) {
        return None;
    }
    let five_axis =
        code::TCP.contains(&code) || code::TILTED_PLANES.contains(&code) || code::ALIGNMENTS.contains(&code);
    if form == Some(Form::Chain) && five_axis {
        return Some((AlarmId::ChainSwitchInMode, "G10 L5000 in the block that turns a 5-axis function on"));
    }
    Some((AlarmId::IllegalGCodeCombination, "a G10 block takes no G code but G90/G91"))
}

/// Why an address may not stand in a G10 block of `form`, if it may not (`axis`: the letter
/// is an axis's). G and N are the block's own; M, F, S, T, H, D … would be dropped.
pub(crate) fn address(letter: u8, axis: bool, form: Form) -> Option<&'static str> {
    let data = match form {
        Form::WorkOffset => axis,
        Form::ToolOffset => letter == b'R',
        Form::Chain => letter == b'Q',
    };
    (!data && !matches!(letter, b'G' | b'N' | b'L' | b'P')).then_some(match form {
        Form::WorkOffset => "G10 L2/L20 takes P and axis words only",
        Form::ToolOffset => "G10 L1/L10–L13 takes P and R only",
        Form::Chain => "G10 L5000 takes P and Q only",
    })
}
