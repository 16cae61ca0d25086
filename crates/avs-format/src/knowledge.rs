//! `kind: knowledge` — common sense about a kind of building.
//!
//! First version: room categories, object classes with sizes and detection / recognition
//! distance ranges, and the door width range. The conceptual map extends it with
//! connectivity potentials, place-property models, Poisson rates and sensor models.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Common-sense knowledge.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Knowledge {
    /// Must be `knowledge`.
    pub kind: KnowledgeKind,
    /// A short name.
    pub name: String,
    /// Room categories (e.g. corridor, kitchen, office).
    pub room_categories: Vec<String>,
    /// Object classes.
    pub object_classes: Vec<ObjectClass>,
    /// Door width range `[min, max]`, metres (Sjöö et al. use 0.7–1.2 m).
    #[serde(default = "default_door_width")]
    pub door_width: [f64; 2],
}

fn default_door_width() -> [f64; 2] {
    [0.7, 1.2]
}

/// The literal `knowledge`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum KnowledgeKind {
    /// `kind: knowledge`
    Knowledge,
}

/// An object class.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectClass {
    /// Class name (e.g. `cerealbox`).
    pub name: String,
    /// Typical bounding box `[length, width, height]`, metres.
    pub size: [f64; 3],
    /// Distances `[min, max]` at which the detector finds it at zoom 1, metres.
    pub detection_range: [f64; 2],
    /// Distances `[min, max]` at which it is recognised reliably, metres.
    pub recognition_range: [f64; 2],
    /// Whether other objects are searched on / in it (table, counter, shelf).
    #[serde(default)]
    pub landmark: bool,
}

impl Knowledge {
    /// Look up an object class by name.
    pub fn class(&self, name: &str) -> Option<&ObjectClass> {
        self.object_classes.iter().find(|c| c.name == name)
    }
}

/// Parse and check a knowledge file's text, returning every problem found (empty when valid).
pub fn check(file: &str, text: &str) -> Vec<crate::Diagnostic> {
    match crate::load_yaml_str::<Knowledge>(file, text) {
        Ok(_) => Vec::new(),
        Err(e) => e.diagnostics,
    }
}
