//! A simulated place classifier: the size, shape and appearance classifiers of Pronobis et al.
//! (ref. \[12\] of Aydemir et al. 2011, `002` §III), whose outputs are the place-property
//! evidence of the conceptual map's chain graph (Fig. 2 of `002`).
//!
//! The model, generatively, is the chain graph's own:
//!
//! 1. every place of a room of category k has, for each property of the knowledge file's
//!    `place_properties`, a *true value* v drawn from `P(v | k)` (`given_category`). A place
//!    is a square tile of [`PlaceClassifierConfig::tile_m`] metres of the ground-truth room; its
//!    value is drawn once, from a generator seeded by (run seed, room, tile, property), so the
//!    same place has the same value every time it is classified;
//! 2. the classifier reports the true value with probability
//!    [`PlaceClassifierConfig::accuracy`] and otherwise one of the other values, uniformly (a
//!    symmetric confusion; draws from the run's own classifier generator);
//! 3. the reading carries the confusion as soft evidence: `P(output | v) = accuracy` for the
//!    value output and `(1 − accuracy) / (n − 1)` for each other value.
//!
//! Off by default: on 50 bench floors (`avs bench --generate 50 --seed 1`) turning it on
//! lowered the planner's success from 1.0 to 0.92 and lengthened its mean path from 208 m to
//! 310 m (SPL 0.097 → 0.081): sharper room categories make the switching planner hunt landmarks
//! and search more rooms it believes are offices, at a flat search cost that does not reflect a
//! session's real travel (issue 17, item 2). The scenario suite's Fig. 3(c) start also changes:
//! one corridor place read as square and office-like makes the planner search the corridor
//! first. `avs search --place-classifier` and `avs bench --place-classifier` turn it on.
//!
//! Choices where the papers are vague: `002` names the properties and the chain graph but not
//! the classifiers' accuracy; 0.8 is our judgement for laser-based shape and size and
//! vision-based appearance classifiers of that work (Pronobis et al. report 80–90 % for
//! their room-category classifiers). A tile of 1 m is the place map's spacing.
//!
//! ```
//! use avs_sim::place_classifier::{PlaceClassifier, PlaceClassifierConfig};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let knowledge: avs_format::knowledge::Knowledge =
//!     avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let on = PlaceClassifierConfig { enabled: true, ..Default::default() };
//! let mut c = PlaceClassifier::new(&knowledge, on, 1).unwrap();
//! let readings = c.classify(&world, 2.0, 5.0); // inside office1
//! assert_eq!(readings.len(), knowledge.place_properties.len());
//! assert!(readings.iter().all(|r| r.likelihood.len() >= 2));
//! ```

use crate::sensors::SensorError;
use crate::World;
use avs_format::knowledge::{Knowledge, PlaceProperty};
use avs_robot::PlaceReading;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Settings of the simulated place classifier. Off by default (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaceClassifierConfig {
    /// Whether the robot has place classifiers at all (without, room categories come from
    /// objects alone).
    pub enabled: bool,
    /// Probability that a reading is the place's true value, in [0, 1].
    pub accuracy: f64,
    /// Side of the square tile that is one place of the ground truth, metres (> 0).
    pub tile_m: f64,
}

impl Default for PlaceClassifierConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            accuracy: 0.8,
            tile_m: 1.0,
        }
    }
}

/// The simulated place classifier of one run.
#[derive(Debug, Clone)]
pub struct PlaceClassifier {
    properties: Vec<PlaceProperty>,
    categories: Vec<String>,
    config: PlaceClassifierConfig,
    seed: u64,
    rng: ChaCha8Rng,
}

/// SplitMix64's finaliser: a well-mixed 64-bit hash of `x`.
fn mix(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// An index drawn from the discrete distribution `p` (non-negative, not all zero).
fn draw(p: &[f64], rng: &mut ChaCha8Rng) -> usize {
    let total: f64 = p.iter().sum();
    let mut u = rng.gen::<f64>() * total;
    for (i, &w) in p.iter().enumerate() {
        if u < w {
            return i;
        }
        u -= w;
    }
    p.iter().rposition(|&w| w > 0.0).unwrap_or(0)
}

impl PlaceClassifier {
    /// The classifier of a run seeded by `seed`, over `knowledge`'s place properties. Errors
    /// name the configuration field out of range.
    pub fn new(
        knowledge: &Knowledge,
        config: PlaceClassifierConfig,
        seed: u64,
    ) -> Result<Self, SensorError> {
        if !(0.0..=1.0).contains(&config.accuracy) {
            return Err(SensorError::Config {
                field: "place_classifier.accuracy",
                value: config.accuracy,
                expected: "a probability in [0, 1]",
            });
        }
        if !(config.tile_m.is_finite() && config.tile_m > 0.0) {
            return Err(SensorError::Config {
                field: "place_classifier.tile_m",
                value: config.tile_m,
                expected: "a finite length > 0 (metres)",
            });
        }
        Ok(Self {
            properties: knowledge.place_properties.clone(),
            categories: knowledge.room_categories.clone(),
            config,
            seed,
            // A stream of its own: turning the classifier on or off leaves every other draw
            // of the run as it was.
            rng: ChaCha8Rng::seed_from_u64(mix(seed ^ 0x5EED_C1A5_51F1_E700)),
        })
    }

    /// The settings.
    pub fn config(&self) -> PlaceClassifierConfig {
        self.config
    }

    /// The true value (index) of property `prop` at the place of room `room` (of category
    /// index `category`) that holds the point (`x`, `y`): drawn once per place.
    pub fn true_value(&self, room: usize, category: usize, x: f64, y: f64, prop: usize) -> usize {
        let tile = |v: f64| (v / self.config.tile_m).floor() as i64 as u64;
        let key = [self.seed, room as u64, tile(x), tile(y), prop as u64]
            .iter()
            .fold(0u64, |h, &k| mix(h ^ k));
        let mut rng = ChaCha8Rng::seed_from_u64(key);
        draw(&self.properties[prop].given_category[category], &mut rng)
    }

    /// Readings at the point (`x`, `y`) of `world`: one per property, none outside every
    /// ground-truth room (in a doorway), for a room whose category the knowledge does not
    /// have, or when the classifier is disabled.
    pub fn classify(&mut self, world: &World, x: f64, y: f64) -> Vec<PlaceReading> {
        if !self.config.enabled {
            return Vec::new();
        }
        let Some(room) = world.room_at(x, y) else {
            return Vec::new();
        };
        let name = &world.env.rooms[room].category;
        let Some(category) = self.categories.iter().position(|c| c == name) else {
            return Vec::new();
        };
        let acc = self.config.accuracy;
        (0..self.properties.len())
            .filter_map(|p| {
                let prop = &self.properties[p];
                let n = prop.values.len();
                if n == 0 || prop.given_category.get(category).is_none() {
                    return None;
                }
                let truth = self.true_value(room, category, x, y, p);
                let out = if n == 1 || self.rng.gen::<f64>() < acc {
                    truth
                } else {
                    // One of the other values, uniformly.
                    let k = self.rng.gen_range(0..n - 1);
                    if k >= truth {
                        k + 1
                    } else {
                        k
                    }
                };
                let other = if n > 1 {
                    (1.0 - acc) / (n - 1) as f64
                } else {
                    1.0
                };
                let likelihood = (0..n)
                    .map(|v| if v == out { acc.max(0.0) } else { other })
                    .collect();
                Some(PlaceReading {
                    property: prop.name.clone(),
                    value: prop.values[out].clone(),
                    likelihood,
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn on() -> PlaceClassifierConfig {
        PlaceClassifierConfig {
            enabled: true,
            ..Default::default()
        }
    }

    fn setup() -> (World, Knowledge) {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let world = World::load(&root.join("domains/environments/office.yaml")).unwrap();
        let k = avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
        (world, k)
    }

    #[test]
    fn a_place_keeps_its_true_value_and_readings_follow_it_at_the_configured_accuracy() {
        let (world, k) = setup();
        let mut c = PlaceClassifier::new(&k, on(), 3).unwrap();
        let (x, y) = (2.0, 5.0);
        let room = world.room_at(x, y).unwrap();
        let cat = k
            .room_categories
            .iter()
            .position(|n| *n == world.env.rooms[room].category)
            .unwrap();
        let truth: Vec<usize> = (0..k.place_properties.len())
            .map(|p| c.true_value(room, cat, x, y, p))
            .collect();
        let runs = 4000;
        let mut right = 0;
        for _ in 0..runs {
            for (p, r) in c.classify(&world, x, y).iter().enumerate() {
                let prop = &k.place_properties[p];
                assert_eq!(r.property, prop.name);
                assert_eq!(r.likelihood.len(), prop.values.len());
                let out = prop.values.iter().position(|v| *v == r.value).unwrap();
                // The likelihood is largest at the value output.
                assert!(r.likelihood.iter().all(|&l| l <= r.likelihood[out]));
                right += usize::from(out == truth[p]);
            }
        }
        let share = right as f64 / (runs * truth.len()) as f64;
        assert!((share - 0.8).abs() < 0.02, "right {share}");
    }

    #[test]
    fn true_values_over_many_places_follow_the_category_distribution() {
        let (_, k) = setup();
        let c = PlaceClassifier::new(&k, PlaceClassifierConfig::default(), 5).unwrap();
        // Shape in an office: P(elongated) = 0.30 in office.yaml.
        let prop = k
            .place_properties
            .iter()
            .position(|p| p.name == "shape")
            .unwrap();
        let office = k
            .room_categories
            .iter()
            .position(|c| c == "office")
            .unwrap();
        let n = 20_000;
        let elongated = (0..n)
            .filter(|&i| c.true_value(0, office, i as f64, 0.5, prop) == 0)
            .count();
        let share = elongated as f64 / n as f64;
        let want = k.place_properties[prop].given_category[office][0];
        assert!((share - want).abs() < 0.015, "{share} vs {want}");
    }

    #[test]
    fn no_reading_in_a_doorway_or_when_off_as_by_default() {
        let (world, k) = setup();
        let mut c = PlaceClassifier::new(&k, PlaceClassifierConfig::default(), 1).unwrap();
        assert!(c.classify(&world, 2.0, 5.0).is_empty());
        let mut c = PlaceClassifier::new(&k, on(), 1).unwrap();
        assert!(c.classify(&world, -5.0, -5.0).is_empty());
    }

    #[test]
    fn an_accuracy_out_of_range_is_an_error_naming_the_field() {
        let (_, k) = setup();
        let bad = PlaceClassifierConfig {
            accuracy: 1.5,
            ..Default::default()
        };
        let e = PlaceClassifier::new(&k, bad, 1).unwrap_err().to_string();
        assert!(e.contains("place_classifier.accuracy"), "{e}");
    }
}
