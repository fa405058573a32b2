//! `fivex machine`: print a machine as a model file, or as a vendor parameter list — both are
//! valid `--machine` files (docs/machine-config.md).

use super::{load_machine, Fail, MachineArgs};
use clap::Args;
use fivex_engine::vendor::{self, ParamFile};
use fivex_engine::Dialect;

#[derive(Args, Debug)]
pub struct MachineShowArgs {
    #[command(flatten)]
    machine: MachineArgs,
    /// Print the vendor's parameter list (fanuc, syntec or haas) instead of the model.
    #[arg(long)]
    params: Option<Dialect>,
}

pub fn run(args: MachineShowArgs) -> Result<i32, Fail> {
    let (m, _) = load_machine(&args.machine, None)?;
    let text = match args.params {
        None => serde_json::to_string_pretty(&m)?,
        Some(dialect) => match vendor::params_of(dialect, &m) {
            Ok(parameters) => serde_json::to_string_pretty(&ParamFile { name: m.name.clone(), dialect, parameters })?,
            Err(e) => {
                eprintln!("fivex: {}", e.describe(dialect));
                return Ok(1);
            }
        },
    };
    println!("{text}");
    Ok(0)
}
