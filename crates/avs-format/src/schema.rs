//! JSON Schemas of the file kinds this crate defines, generated from the Rust types (schemars),
//! so editors can check files as they are typed.

use crate::load::FileKind;

/// The JSON Schema (pretty-printed JSON) of a file kind, or `None` for kinds whose types live in
/// another crate (`domain` files belong to `avs-plan`).
pub fn schema_json(kind: FileKind) -> Option<String> {
    let schema = match kind {
        FileKind::Environment => schemars::schema_for!(crate::environment::Environment),
        FileKind::Knowledge => schemars::schema_for!(crate::knowledge::Knowledge),
        FileKind::Scenario => schemars::schema_for!(crate::scenario::Scenario),
        FileKind::Verification => {
            schemars::schema_for!(crate::verification::VerificationScenario)
        }
        FileKind::Domain => return None,
    };
    serde_json::to_string_pretty(&schema).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn environment_schema_requires_kind_map_and_robot() {
        let s: serde_json::Value =
            serde_json::from_str(&schema_json(FileKind::Environment).unwrap()).unwrap();
        let req: Vec<&str> = s["required"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|v| v.as_str())
            .collect();
        for f in ["kind", "name", "map", "robot"] {
            assert!(req.contains(&f), "{f} not required: {req:?}");
        }
        assert!(schema_json(FileKind::Domain).is_none());
    }
}
