//! `--machine FILE.json` (and the API's machine bodies): a machine model, or a vendor parameter
//! list `{"name", "dialect", "parameters"}` (`docs/machine-config.md`).

use crate::machine::MachineConfig;
use crate::vendor::{self, ParamFile};

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

/// What of the machine a JSON text describes fivex keeps but does not carry out (issue 17,
/// item 1; `docs/machine-config.md`): unread vendor parameters and bits, model settings kept
/// without effect. Empty for a text that describes no machine.
pub fn unmodelled(text: &str) -> Vec<vendor::unmodelled::Unmodelled> {
    let Ok(value) = serde_json::from_str::<serde_json::Value>(text) else { return Vec::new() };
    if value.get("parameters").is_some() {
        match serde_json::from_value::<ParamFile>(value) {
            Ok(file) => vendor::unmodelled::of_params(file.dialect, &file.parameters),
            Err(_) => Vec::new(),
        }
    } else {
        let Ok(m) = serde_json::from_value::<MachineConfig>(value.clone()) else { return Vec::new() };
        let mut out = unknown_fields(&value, &m);
        out.extend(vendor::unmodelled::of_model(&m));
        out
    }
}

/// Fields of a model document that no model field takes (the model and its axes and rotary
/// links accept and drop them): a field is unknown when the document without it, and with it
/// set to a value no field's type takes, reads to the same machine.
fn unknown_fields(doc: &serde_json::Value, m: &MachineConfig) -> Vec<vendor::unmodelled::Unmodelled> {
    let same =
        |changed: &serde_json::Value| serde_json::from_value::<MachineConfig>(changed.clone()).is_ok_and(|c| c == *m);
    // (path of the object in the document, its JSON pointer)
    let mut objects = vec![(String::new(), String::new())];
    for list in ["axes", "rotary"] {
        let n = doc.get(list).and_then(|v| v.as_array()).map_or(0, Vec::len);
        objects.extend((0..n).map(|i| (format!("{list}[{i}]."), format!("/{list}/{i}"))));
    }
    // The rotary links of the further mechanism chains (the chains themselves refuse unknown
    // fields, as the option objects do).
    let chains = doc.get("chains").and_then(|v| v.as_array()).map_or(&[][..], Vec::as_slice);
    for (c, chain) in chains.iter().enumerate() {
        let n = chain.get("rotary").and_then(|v| v.as_array()).map_or(0, Vec::len);
        objects.extend((0..n).map(|i| (format!("chains[{c}].rotary[{i}]."), format!("/chains/{c}/rotary/{i}"))));
    }
    let mut out = Vec::new();
    for (path, pointer) in objects {
        let Some(object) = doc.pointer(&pointer).and_then(|v| v.as_object()) else { continue };
        for key in object.keys() {
            let with = |value: Option<serde_json::Value>| {
                let mut d = doc.clone();
                if let Some(o) = d.pointer_mut(&pointer).and_then(|v| v.as_object_mut()) {
                    match value {
                        Some(v) => o.insert(key.clone(), v),
                        None => o.remove(key),
                    };
                }
                d
            };
            if same(&with(None)) && same(&with(Some(serde_json::json!({"fivex-probe": [null]})))) {
                out.push(vendor::unmodelled::Unmodelled {
                    parameter: format!("{path}{key}"),
                    reason: "no field of the machine model: ignored".into(),
                });
            }
        }
    }
    out
}

/// The warnings of [`unmodelled`] for the command line's stderr, one per line, naming `file`.
pub fn warnings(file: &str, text: &str) -> Vec<String> {
    unmodelled(text)
        .into_iter()
        .map(|u| format!("warning: {file}: {} is not modelled: {}", u.parameter, u.reason))
        .collect()
}

/// The dialect a parameter list is written in (`None` for a model file or bad JSON).
pub fn dialect_of(text: &str) -> Option<crate::Dialect> {
    let value: serde_json::Value = serde_json::from_str(text).ok()?;
    value.get("parameters")?;
    serde_json::from_value(value.get("dialect")?.clone()).ok()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Dialect;

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
        // A key a parameter list does not have is refused, not dropped: `motion` beside
        // `parameters` ran the machine in mm without a word.
        let e = parse(r#"{"name": "x", "dialect": "fanuc", "parameters": {}, "motion": {"power_on_inch": true}}"#)
            .unwrap_err();
        assert!(e.contains("unknown field `motion`"), "{e}");
    }

    #[test]
    fn a_chain_refuses_unknown_fields_and_its_links_report_them() {
        let mut doc = serde_json::to_value(MachineConfig::preset("head-bc").unwrap()).unwrap();
        let links = doc["rotary"].clone();
        doc["chains"] = serde_json::json!([{"set": 2, "rotary": links, "holder": 150.0}]);
        assert!(parse(&doc.to_string()).is_ok());
        doc["chains"][0]["rotary"][0]["bogus"] = 1.into();
        let names: Vec<String> = unmodelled(&doc.to_string()).into_iter().map(|u| u.parameter).collect();
        assert_eq!(names, ["chains[0].rotary[0].bogus"]);
        doc["chains"][0]["typo"] = 1.into();
        assert!(parse(&doc.to_string()).unwrap_err().contains("typo"));
    }
}
