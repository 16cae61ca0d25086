//! The knowledge file turned into dense tables the conceptual map computes with.

use crate::ConceptError;
use avs_format::knowledge::{Knowledge, Relation};
use std::collections::BTreeMap;

/// A place-property model P(value | category), dense.
#[derive(Debug, Clone, PartialEq)]
pub struct PropertyModel {
    /// Property name.
    pub name: String,
    /// Its values.
    pub values: Vec<String>,
    /// `given_category[k][v]` = P(value v | category k).
    pub given_category: Vec<Vec<f64>>,
}

/// Dense common-sense knowledge: categories and classes are indices.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    /// Room category names.
    pub categories: Vec<String>,
    /// Prior P(category).
    pub prior: Vec<f64>,
    /// φ_rc(a, b) at `connectivity[a][b]`.
    pub connectivity: Vec<Vec<f64>>,
    /// Place-property models.
    pub properties: Vec<PropertyModel>,
    /// Object class names.
    pub classes: Vec<String>,
    /// Whether each class is a landmark.
    pub landmark: Vec<bool>,
    /// `room_rates[c][k]`: λ of class c anywhere in a room of category k (0 when not given).
    pub room_rates: Vec<Vec<f64>>,
    /// λ per category of (object class, relation, landmark class).
    pub landmark_rates: BTreeMap<(usize, Relation, usize), Vec<f64>>,
    /// P(an object in the looked-at part is counted).
    pub count_detection: f64,
    /// Spurious counts per room (scaled by the looked-at share).
    pub count_false_positive: f64,
    /// Placeholder-hypothesis parameters.
    pub placeholder: avs_format::knowledge::PlaceholderModel,
    /// Detector sensor model.
    pub sensor: avs_format::knowledge::SensorModel,
}

impl Model {
    /// Check `k` (as `avs validate` does) and build the dense model. `file` names the source
    /// in the error.
    pub fn from_knowledge(file: &str, k: &Knowledge) -> Result<Self, ConceptError> {
        let diags = avs_format::knowledge::validate(file, k);
        if !diags.is_empty() {
            return Err(ConceptError::Knowledge(
                diags
                    .iter()
                    .map(|d| d.to_string())
                    .collect::<Vec<_>>()
                    .join("\n"),
            ));
        }
        let kc = k.room_categories.len();
        let classes: Vec<String> = k.object_classes.iter().map(|c| c.name.clone()).collect();
        let ci = |n: &str| classes.iter().position(|c| c == n).expect("validated");
        let mut room_rates = vec![vec![0.0; kc]; classes.len()];
        for (name, r) in &k.object_rates {
            room_rates[ci(name)] = r.clone();
        }
        let landmark_rates = k
            .landmark_rates
            .iter()
            .map(|l| {
                (
                    (ci(&l.object), l.relation, ci(&l.landmark)),
                    l.rates.clone(),
                )
            })
            .collect();
        Ok(Model {
            categories: k.room_categories.clone(),
            prior: k
                .category_prior
                .clone()
                .unwrap_or_else(|| vec![1.0 / kc as f64; kc]),
            connectivity: k
                .connectivity
                .clone()
                .unwrap_or_else(|| vec![vec![1.0; kc]; kc]),
            properties: k
                .place_properties
                .iter()
                .map(|p| PropertyModel {
                    name: p.name.clone(),
                    values: p.values.clone(),
                    given_category: p.given_category.clone(),
                })
                .collect(),
            landmark: k.object_classes.iter().map(|c| c.landmark).collect(),
            classes,
            room_rates,
            landmark_rates,
            count_detection: k.object_count_observation.detection_probability,
            count_false_positive: k.object_count_observation.false_positive_rate,
            placeholder: k.placeholder.clone(),
            sensor: k.sensor.clone(),
        })
    }

    /// Number of room categories.
    pub fn num_categories(&self) -> usize {
        self.categories.len()
    }

    /// Index of a category.
    pub fn category(&self, name: &str) -> Result<usize, ConceptError> {
        self.categories
            .iter()
            .position(|c| c == name)
            .ok_or_else(|| ConceptError::Unknown {
                what: "room category",
                name: name.into(),
                known: self.categories.join(", "),
            })
    }

    /// Index of an object class.
    pub fn class(&self, name: &str) -> Result<usize, ConceptError> {
        self.classes
            .iter()
            .position(|c| c == name)
            .ok_or_else(|| ConceptError::Unknown {
                what: "object class",
                name: name.into(),
                known: self.classes.join(", "),
            })
    }

    /// Index of a place property.
    pub fn property(&self, name: &str) -> Result<usize, ConceptError> {
        self.properties
            .iter()
            .position(|p| p.name == name)
            .ok_or_else(|| ConceptError::Unknown {
                what: "place property",
                name: name.into(),
                known: self
                    .properties
                    .iter()
                    .map(|p| p.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }

    /// λ of `object` `relation` one `landmark`, per category (zeros when not given).
    pub fn landmark_rate(&self, object: usize, relation: Relation, landmark: usize) -> Vec<f64> {
        self.landmark_rates
            .get(&(object, relation, landmark))
            .cloned()
            .unwrap_or_else(|| vec![0.0; self.num_categories()])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_knowledge_files_are_valid() {
        for f in ["office.yaml", "home.yaml"] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../knowledge")
                .join(f);
            let text = std::fs::read_to_string(&path).unwrap();
            let d = avs_format::knowledge::check(f, &text);
            assert!(d.is_empty(), "{f}: {d:?}");
            let k: Knowledge = avs_format::load_yaml_str(f, &text).unwrap();
            let m = Model::from_knowledge(f, &k).unwrap();
            assert_eq!(m.prior.len(), m.categories.len());
        }
    }
}
