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

    /// The rate of `object`, per category, in a room none of whose landmarks is known yet (a
    /// room behind a placeholder): its own rate plus those of all its subordinate locations,
    /// as §III-A of `002` has it ("the λ values for a location and all its subordinate
    /// locations can simply be added together"), returned as the effective λ_k with
    /// P(at least one) = 1 − e^{−λ_k} (eq. 2).
    ///
    /// The landmarks of an unseen room are themselves unknown: a room of category k holds a
    /// Poisson(μ_k) number of landmarks of a class (μ = that class's `room_rates`), each with a
    /// Poisson(ν_k) number of the object on or in it (ν = the `landmark_rates` entry). The
    /// object's count over them is compound Poisson with P(none) = exp(−μ_k (1 − e^{−ν_k}))
    /// (the probability generating function of the landmark count at e^{−ν_k}), so each
    /// (relation, landmark class) adds μ_k (1 − e^{−ν_k}) to the room's own λ. For small ν
    /// this is the paper's plain sum μ_k ν_k; for ν near 1 or above it does not count one
    /// landmark's many objects as many landmarks' worth of chances.
    pub fn unseen_room_rates(&self, object: usize) -> Vec<f64> {
        let mut out = self
            .room_rates
            .get(object)
            .cloned()
            .unwrap_or_else(|| vec![0.0; self.num_categories()]);
        for (lm, hold) in self.landmark_holds(object) {
            for ((r, mu), h) in out.iter_mut().zip(&self.room_rates[lm]).zip(hold) {
                *r += mu * h;
            }
        }
        out
    }

    /// For each (relation, landmark class) with a rate of `object`: the landmark class and,
    /// per category, the chance 1 − e^{−ν_k} that one instance holds at least one `object`
    /// (what each of a Poisson number of unseen landmarks adds to a room's rate; see
    /// [`Model::unseen_room_rates`]).
    pub fn landmark_holds(&self, object: usize) -> impl Iterator<Item = (usize, Vec<f64>)> + '_ {
        self.landmark_rates
            .iter()
            .filter(move |((o, _, lm), _)| *o == object && *lm < self.room_rates.len())
            .map(|((_, _, lm), nu)| (*lm, nu.iter().map(|n| 1.0 - (-n).exp()).collect()))
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

    #[test]
    fn an_unseen_room_holds_the_object_also_on_and_in_the_landmarks_it_is_expected_to_have() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../knowledge/office.yaml");
        let k: Knowledge = avs_format::load_yaml(&path).unwrap();
        let m = Model::from_knowledge("office.yaml", &k).unwrap();
        let cereal = m.class("cerealbox").unwrap();
        let kitchen = m.category("kitchen").unwrap();
        let got = m.unseen_room_rates(cereal)[kitchen];
        // Independently, from the knowledge file's numbers: loose 0.10; tables 1.0 per
        // kitchen with 0.40 each on top; counters 1.5 with 0.30; shelves 0.3 with 0.20 inside.
        let want = 0.10
            + 1.0 * (1.0 - (-0.40f64).exp())
            + 1.5 * (1.0 - (-0.30f64).exp())
            + 0.3 * (1.0 - (-0.20f64).exp());
        assert!((got - want).abs() < 1e-12, "{got} vs {want}");
        // Monte Carlo of the generative model: P(no cerealbox anywhere in a kitchen).
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let poisson = |rng: &mut rand_chacha::ChaCha8Rng, l: f64| {
            // Knuth's method (small λ).
            let (lim, mut p, mut k) = ((-l).exp(), 1.0, 0u32);
            loop {
                p *= rng.gen::<f64>();
                if p <= lim {
                    return k;
                }
                k += 1;
            }
        };
        let n = 200_000;
        let mut none = 0;
        for _ in 0..n {
            let mut count = poisson(&mut rng, 0.10);
            for (mu, nu) in [(1.0, 0.40), (1.5, 0.30), (0.3, 0.20)] {
                for _ in 0..poisson(&mut rng, mu) {
                    count += poisson(&mut rng, nu);
                }
            }
            none += u32::from(count == 0);
        }
        let p_none = f64::from(none) / f64::from(n);
        assert!(
            (p_none - (-got).exp()).abs() < 0.005,
            "{p_none} vs {}",
            (-got).exp()
        );
        // A landmark class has no subordinate locations: its own rate.
        let table = m.class("table").unwrap();
        assert_eq!(m.unseen_room_rates(table), m.room_rates[table]);
    }
}
