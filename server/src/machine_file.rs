//! `--machine FILE.json` (and the API's machine bodies): a machine model, or a vendor parameter
//! list `{"name", "dialect", "parameters"}` (`docs/machine-config.md`).

use fivex_engine::machine::MachineConfig;
use fivex_engine::vendor::{self, ParamFile};

/// The machine a JSON text describes, checked; the error says what is wrong (with the vendor's
/// alarm for a parameter list whose mechanism cannot work).
pub fn parse(text: &str) -> Result<MachineConfig, String> {
    let value: serde_json::Value = serde_json::from_str(text).map_err(|e| e.to_string())?;
    let m = if value.get("parameters").is_some() {
        let file: ParamFile = serde_json::from_value(value).map_err(|e| e.to_string())?;
        vendor::machine_from(file.dialect, &file.name, &file.parameters).map_err(|e| e.describe(file.dialect))?
    } else {
        serde_json::from_value::<MachineConfig>(value).map_err(|e| e.to_string())?
    };
    m.validate()?;
    Ok(m)
}

/// The dialect a parameter list is written in (`None` for a model file or bad JSON).
pub fn dialect_of(text: &str) -> Option<fivex_engine::Dialect> {
    let value: serde_json::Value = serde_json::from_str(text).ok()?;
    value.get("parameters")?;
    serde_json::from_value(value.get("dialect")?.clone()).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use fivex_engine::Dialect;

    #[test]
    fn a_parameter_list_and_a_model_give_the_same_machine() {
        let preset = MachineConfig::preset("table-ac").unwrap();
        for dialect in [Dialect::Fanuc, Dialect::Syntec] {
            let parameters = vendor::params_of(dialect, &preset).unwrap();
            let file = ParamFile { name: "t".into(), dialect, parameters };
            let m = parse(&serde_json::to_string(&file).unwrap()).unwrap();
            let mechanism = |m: &MachineConfig| {
                m.rotary.iter().map(|l| (l.axis, l.side, l.direction, l.hand, l.point)).collect::<Vec<_>>()
            };
            assert_eq!(mechanism(&m), mechanism(&preset), "{dialect:?}");
        }
        let model = parse(&serde_json::to_string(&preset).unwrap()).unwrap();
        assert_eq!(model, preset);
    }

    #[test]
    fn bad_files_say_why() {
        assert!(parse("{").is_err());
        assert!(parse(r#"{"name": "x", "axes": []}"#).unwrap_err().contains("axes"));
        let e =
            parse(r#"{"name": "x", "dialect": "syntec", "parameters": {"321": 1, "21": 1, "3001": 1}}"#).unwrap_err();
        assert!(e.starts_with("COR-155"), "{e}");
        let e = parse(r#"{"name": "x", "dialect": "fanuc", "parameters": {"1020": "X"}}"#).unwrap_err();
        assert!(e.contains("1020") || e.contains("untagged"), "{e}");
    }
}
