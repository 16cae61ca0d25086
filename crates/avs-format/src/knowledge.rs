//! `kind: knowledge` — common sense about a kind of building.
//!
//! Room categories, object classes with sizes and detection / recognition distance ranges, the
//! door width range, and the numbers the conceptual map (`avs-concepts`) reasons with:
//! connectivity potentials φ_rc between the categories of rooms joined by a door, place-property
//! models P(value | category), Poisson rates λ of each object class per room category and per
//! landmark class and relation (Aydemir et al. 2011, eq. 1–2), the object-count observation
//! model, the placeholder-hypothesis parameters (§III-A.1) and the detector's sensor model.
//!
//! Every table indexed by room category lists its entries in the order of `room_categories`.
//! [`check`] reports every problem with the file, the field path and the fix.

use crate::diag::Diagnostic;
use crate::verifier::{NamedSensorModel, VerifierSpec, VerifierStrategy};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

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
    /// Prior P(category) of a room before any observation, in `room_categories` order; sums
    /// to 1. Absent: uniform.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub category_prior: Option<Vec<f64>>,
    /// Connectivity potentials φ_rc(a, b) between the categories of two rooms joined by a door:
    /// a symmetric K × K table of non-negative numbers (rows and columns in `room_categories`
    /// order). Absent: all ones (doors say nothing about categories).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub connectivity: Option<Vec<Vec<f64>>>,
    /// Place-property models P(value | category) (size, shape, appearance; discrete values).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub place_properties: Vec<PlaceProperty>,
    /// Poisson rate λ of each object class anywhere in a room (not on or in a known landmark),
    /// per room category: class name → K rates, in `room_categories` order.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub object_rates: BTreeMap<String, Vec<f64>>,
    /// Poisson rates λ of an object class in / on one landmark of a class, per room category.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub landmark_rates: Vec<LandmarkRate>,
    /// How counting the instances of a class in a room relates to the true count.
    #[serde(default)]
    pub object_count_observation: CountObservation,
    /// Parameters of the placeholder structure hypotheses.
    #[serde(default)]
    pub placeholder: PlaceholderModel,
    /// The object detector's sensor model.
    #[serde(default)]
    pub sensor: SensorModel,
    /// Trained sensor models of the detection verifier, by name (`avs verify train` writes
    /// one); classes name theirs in `verifier.model` ([`crate::verifier`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub sensor_models: Vec<NamedSensorModel>,
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
    /// Where its candidate detections go before one is reported ([`crate::verifier`]).
    /// Absent: the fixed `count` rule.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verifier: Option<VerifierSpec>,
}

/// A discrete place property (e.g. size, shape, appearance) and its model P(value | category).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlaceProperty {
    /// Property name (e.g. `shape`).
    pub name: String,
    /// The values the property classifier reports (e.g. `[elongated, square]`).
    pub values: Vec<String>,
    /// P(value | category): one row per room category (in `room_categories` order), one
    /// column per value; each row sums to 1.
    pub given_category: Vec<Vec<f64>>,
}

/// Where an object is relative to a landmark.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Relation {
    /// Inside (a cupboard, a shelf).
    In,
    /// On top of (a table, a counter).
    On,
}

/// The Poisson rate of `object` `relation` one `landmark`, per room category
/// ("a cereal box on a table in a kitchen").
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LandmarkRate {
    /// The object class searched for.
    pub object: String,
    /// `in` or `on`.
    pub relation: Relation,
    /// The landmark class (an object class with `landmark: true`).
    pub landmark: String,
    /// Expected number of `object`s per landmark, one rate per room category.
    pub rates: Vec<f64>,
}

/// The object-count observation model: the count seen in a room is Poisson with rate
/// `coverage · detection_probability · λ + false_positive_rate` (thinning of the true count,
/// plus spurious detections).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CountObservation {
    /// Probability that an object in the looked-at part of a room is counted, in (0, 1].
    #[serde(default = "default_count_detection")]
    pub detection_probability: f64,
    /// Expected number of spurious instances counted per room, ≥ 0.
    #[serde(default = "default_count_fp")]
    pub false_positive_rate: f64,
}

fn default_count_detection() -> f64 {
    0.8
}
fn default_count_fp() -> f64 {
    0.05
}

impl Default for CountObservation {
    fn default() -> Self {
        Self {
            detection_probability: default_count_detection(),
            false_positive_rate: default_count_fp(),
        }
    }
}

/// Parameters of the six placeholder structure hypotheses (Aydemir et al. 2011, §III-A.1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlaceholderModel {
    /// Open-area scale a₀ (m²): P(no new places) = exp(−A / a₀) for open area A behind it.
    #[serde(default = "default_no_places_area")]
    pub no_places_area_m2: f64,
    /// Room-area scale a_r (m²): P(places lead to a room | new places) = 1 − exp(−A / a_r).
    #[serde(default = "default_room_area")]
    pub room_area_m2: f64,
    /// Door-distance scale d₀ (m): P(a new room directly | new places) = exp(−d / d₀) for the
    /// distance d to the nearest door hypothesis (0 without one).
    #[serde(default = "default_door_distance")]
    pub door_distance_m: f64,
    /// P(a hypothesised room leads on to another room), in [0, 1].
    #[serde(default = "default_another_room")]
    pub another_room: f64,
}

fn default_no_places_area() -> f64 {
    2.0
}
fn default_room_area() -> f64 {
    12.0
}
fn default_door_distance() -> f64 {
    1.0
}
fn default_another_room() -> f64 {
    0.3
}

impl Default for PlaceholderModel {
    fn default() -> Self {
        Self {
            no_places_area_m2: default_no_places_area(),
            room_area_m2: default_room_area(),
            door_distance_m: default_door_distance(),
            another_room: default_another_room(),
        }
    }
}

/// The object detector's per-view sensor model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorModel {
    /// P(no detection | object in view), in [0, 1). Default 0.2 (Aydemir et al. 2011, §II-C).
    #[serde(default = "default_fn")]
    pub false_negative: f64,
    /// P(detection | no object in view), in [0, 1). Default 0.05 (Aydemir et al. 2011, §II-C).
    #[serde(default = "default_fp")]
    pub false_positive: f64,
    /// How the detector's errors follow the vantage point (Velez et al. 2012): looks at a spot
    /// from vantage points closer than these lengths repeat one another and are one look's
    /// evidence. Absent (the default): every look is an independent draw, as the simulator's
    /// default detector makes it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation: Option<LookCorrelation>,
}

/// The lengths over which a detector's errors at one spot stay alike
/// ([`SensorModel::correlation`]): two vantage points closer than one length of range *and*
/// aspect (in the normalised distance `√((Δr/ℓ_r)² + (Δφ/ℓ_φ)²) < 1`) see the same thing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LookCorrelation {
    /// The range length as a share of the class's `detection_range[1]` (a detector's working
    /// distances scale with the object's size), > 0.
    pub range_share: f64,
    /// The aspect length: the angle around the spot between two vantage points, degrees, in
    /// (0, 180].
    pub aspect_deg: f64,
}

fn default_fn() -> f64 {
    0.2
}
fn default_fp() -> f64 {
    0.05
}

impl Default for SensorModel {
    fn default() -> Self {
        Self {
            false_negative: default_fn(),
            false_positive: default_fp(),
            correlation: None,
        }
    }
}

impl Knowledge {
    /// Look up an object class by name.
    pub fn class(&self, name: &str) -> Option<&ObjectClass> {
        self.object_classes.iter().find(|c| c.name == name)
    }

    /// Look up a sensor model of `sensor_models` by name.
    pub fn sensor_model(&self, name: &str) -> Option<&crate::verifier::SensorModelSpec> {
        self.sensor_models
            .iter()
            .find(|m| m.name == name)
            .map(|m| &m.model)
    }

    /// Index of a room category by name.
    pub fn category_index(&self, name: &str) -> Option<usize> {
        self.room_categories.iter().position(|c| c == name)
    }
}

/// Parse and check a knowledge file's text, returning every problem found (empty when valid).
pub fn check(file: &str, text: &str) -> Vec<Diagnostic> {
    match crate::load::load_yaml_str_explained::<Knowledge>(file, text) {
        Ok(k) => validate(file, &k),
        Err(e) => e.diagnostics,
    }
}

/// Tolerance on "sums to 1".
const SUM_TOL: f64 = 1e-6;

/// Check the meaning of parsed knowledge: sizes of tables, signs of rates, distributions that
/// sum to 1, names that refer to declared categories and classes. Empty when valid.
pub fn validate(file: &str, k: &Knowledge) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let mut err =
        |path: String, msg: String, fix: String| out.push(Diagnostic::new(file, path, msg, fix));
    let kc = k.room_categories.len();
    if kc == 0 {
        err(
            "room_categories".into(),
            "no room categories".into(),
            "list at least one category, e.g. [corridor, kitchen, office]".into(),
        );
    }
    for (i, c) in k.room_categories.iter().enumerate() {
        if k.room_categories[..i].contains(c) {
            err(
                format!("room_categories[{i}]"),
                format!("category `{c}` is listed twice"),
                "give each category once".into(),
            );
        }
    }
    for (i, c) in k.object_classes.iter().enumerate() {
        let p = format!("object_classes[{i}]");
        if k.object_classes[..i].iter().any(|o| o.name == c.name) {
            err(
                format!("{p}.name"),
                format!("class `{}` is declared twice", c.name),
                "declare each class once".into(),
            );
        }
        if c.size.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
            err(
                format!("{p}.size"),
                format!("size {:?} has a non-positive or non-finite entry", c.size),
                "give [length, width, height] in metres, each > 0".into(),
            );
        }
        for (name, r) in [
            ("detection_range", c.detection_range),
            ("recognition_range", c.recognition_range),
        ] {
            if !(r[0].is_finite() && r[1].is_finite() && r[0] >= 0.0 && r[0] <= r[1]) {
                err(
                    format!("{p}.{name}"),
                    format!("range {r:?} is not an interval of distances"),
                    "give [min, max] metres with 0 <= min <= max".into(),
                );
            }
        }
        if let Some(v) = &c.verifier {
            let vp = format!("{p}.verifier");
            if c.landmark {
                err(
                    vp.clone(),
                    format!(
                        "class `{}` is a landmark: landmarks are not verified",
                        c.name
                    ),
                    "remove the verifier block, or drop `landmark: true`".into(),
                );
            }
            match (&v.model, v.strategy.uses_model()) {
                (None, false) => {}
                (None, true) => err(
                    format!("{vp}.model"),
                    format!("the `{}` verifier needs a sensor model", v.strategy.name()),
                    "name one of `sensor_models` (e.g. trained by `avs verify train`), or use strategy `sequential` or `count`".into(),
                ),
                (Some(m), _) if k.sensor_model(m).is_none() => err(
                    format!("{vp}.model"),
                    format!("no sensor model named `{m}`"),
                    "name one of `sensor_models`".into(),
                ),
                (Some(_), false) if !v.strategy.accepts_model() => err(
                    format!("{vp}.model"),
                    format!("the `{}` verifier uses no sensor model", v.strategy.name()),
                    "remove `model`, or choose a sequential, planned, greedy or rtbss verifier"
                        .into(),
                ),
                _ => {}
            }
            match (v.threshold, v.strategy) {
                (Some(t), VerifierStrategy::Greedy) if !(t > 0.5 && t < 1.0) => err(
                    format!("{vp}.threshold"),
                    format!("threshold {t} is outside (0.5, 1)"),
                    "give GREEDY's belief threshold τ in (0.5, 1), e.g. 0.8".into(),
                ),
                (Some(_), s) if s != VerifierStrategy::Greedy => err(
                    format!("{vp}.threshold"),
                    format!("the `{}` verifier takes no threshold", s.name()),
                    "remove `threshold` (it is GREEDY's τ)".into(),
                ),
                _ => {}
            }
        }
    }
    if k.sensor_models.len() > crate::verifier::MAX_MODELS {
        err(
            "sensor_models".into(),
            format!("{} sensor models", k.sensor_models.len()),
            format!("give at most {} models", crate::verifier::MAX_MODELS),
        );
    }
    for (i, m) in k.sensor_models.iter().enumerate() {
        let p = format!("sensor_models[{i}]");
        if k.sensor_models[..i].iter().any(|o| o.name == m.name) {
            err(
                format!("{p}.name"),
                format!("sensor model `{}` is declared twice", m.name),
                "give each model a name of its own".into(),
            );
        }
        for (field, what) in m.model.problems() {
            err(
                format!("{p}.model.{field}"),
                "is out of range".into(),
                format!("give {what}"),
            );
        }
    }
    let dw = k.door_width;
    if !(dw[0].is_finite() && dw[1].is_finite() && dw[0] > 0.0 && dw[0] <= dw[1]) {
        err(
            "door_width".into(),
            format!("door width {dw:?} is not an interval of widths"),
            "give [min, max] metres with 0 < min <= max, e.g. [0.7, 1.2]".into(),
        );
    }
    let check_row = |path: String,
                     row: &[f64],
                     len: usize,
                     what: &str,
                     dist: bool,
                     out: &mut dyn FnMut(String, String, String)| {
        if row.len() != len {
            out(
                path.clone(),
                format!("has {} entries, expected {len} ({what})", row.len()),
                format!("give exactly {len} numbers"),
            );
            return;
        }
        for (j, v) in row.iter().enumerate() {
            if !v.is_finite() || *v < 0.0 {
                out(
                    format!("{path}[{j}]"),
                    format!("{v} is negative or not a number"),
                    "use a finite number >= 0".into(),
                );
                return;
            }
        }
        if dist {
            let s: f64 = row.iter().sum();
            if (s - 1.0).abs() > SUM_TOL {
                out(
                    path,
                    format!("the probabilities sum to {s}, not 1"),
                    "rescale the row so that it sums to 1".into(),
                );
            }
        }
    };
    let cat_list = k.room_categories.join(", ");
    if let Some(prior) = &k.category_prior {
        check_row(
            "category_prior".into(),
            prior,
            kc,
            &format!("one probability per room category ({cat_list})"),
            true,
            &mut err,
        );
    }
    if let Some(phi) = &k.connectivity {
        if phi.len() != kc {
            err(
                "connectivity".into(),
                format!("the table has {} rows, expected {kc}", phi.len()),
                format!("give one row per room category ({cat_list})"),
            );
        } else {
            for (i, row) in phi.iter().enumerate() {
                check_row(
                    format!("connectivity[{i}]"),
                    row,
                    kc,
                    &format!("one potential per room category ({cat_list})"),
                    false,
                    &mut err,
                );
            }
            if phi.iter().all(|r| r.len() == kc) {
                for (i, row) in phi.iter().enumerate() {
                    if row.iter().all(|v| *v == 0.0) {
                        err(
                            format!("connectivity[{i}]"),
                            "the row is all zeros: a room of this category could never have a door"
                                .into(),
                            "give at least one positive potential".into(),
                        );
                    }
                    for (j, (a, other)) in row.iter().zip(phi).take(i).enumerate() {
                        let b = other[i];
                        if (a - b).abs() > 1e-9 * (1.0 + a.abs()) {
                            err(
                                format!("connectivity[{i}][{j}]"),
                                format!("the table is not symmetric: {a} here, {b} at [{j}][{i}]"),
                                "doors are undirected; make the two entries equal".into(),
                            );
                        }
                    }
                }
            }
        }
    }
    for (pi, prop) in k.place_properties.iter().enumerate() {
        let p = format!("place_properties[{pi}]");
        if k.place_properties[..pi].iter().any(|o| o.name == prop.name) {
            err(
                format!("{p}.name"),
                format!("property `{}` is declared twice", prop.name),
                "declare each property once".into(),
            );
        }
        if prop.values.is_empty() {
            err(
                format!("{p}.values"),
                "no values".into(),
                "list the values the property takes".into(),
            );
        }
        for (i, v) in prop.values.iter().enumerate() {
            if prop.values[..i].contains(v) {
                err(
                    format!("{p}.values[{i}]"),
                    format!("value `{v}` is listed twice"),
                    "give each value once".into(),
                );
            }
        }
        if prop.given_category.len() != kc {
            err(
                format!("{p}.given_category"),
                format!(
                    "the table has {} rows, expected {kc}",
                    prop.given_category.len()
                ),
                format!("give one row P(value | category) per room category ({cat_list})"),
            );
        } else {
            for (i, row) in prop.given_category.iter().enumerate() {
                check_row(
                    format!("{p}.given_category[{i}]"),
                    row,
                    prop.values.len(),
                    &format!(
                        "P(value | {}) for the values {}",
                        k.room_categories[i],
                        prop.values.join(", ")
                    ),
                    true,
                    &mut err,
                );
            }
        }
    }
    let class_list = k
        .object_classes
        .iter()
        .map(|c| c.name.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    for (name, rates) in &k.object_rates {
        let p = format!("object_rates.{name}");
        if k.class(name).is_none() {
            err(
                p.clone(),
                format!("unknown object class `{name}`"),
                format!("use a class declared in object_classes ({class_list})"),
            );
        }
        check_row(
            p,
            rates,
            kc,
            &format!("one rate per room category ({cat_list})"),
            false,
            &mut err,
        );
    }
    for (i, lr) in k.landmark_rates.iter().enumerate() {
        let p = format!("landmark_rates[{i}]");
        if k.class(&lr.object).is_none() {
            err(
                format!("{p}.object"),
                format!("unknown object class `{}`", lr.object),
                format!("use a class declared in object_classes ({class_list})"),
            );
        }
        match k.class(&lr.landmark) {
            None => err(
                format!("{p}.landmark"),
                format!("unknown object class `{}`", lr.landmark),
                format!("use a class declared in object_classes ({class_list})"),
            ),
            Some(c) if !c.landmark => err(
                format!("{p}.landmark"),
                format!("class `{}` is not a landmark", lr.landmark),
                format!(
                    "set `landmark: true` on class `{}` or use a landmark class",
                    lr.landmark
                ),
            ),
            _ => {}
        }
        if k.landmark_rates[..i].iter().any(|o| {
            o.object == lr.object && o.landmark == lr.landmark && o.relation == lr.relation
        }) {
            err(
                p.clone(),
                "the same object, relation and landmark are given twice".into(),
                "give each (object, relation, landmark) once".into(),
            );
        }
        check_row(
            format!("{p}.rates"),
            &lr.rates,
            kc,
            &format!("one rate per room category ({cat_list})"),
            false,
            &mut err,
        );
    }
    let co = &k.object_count_observation;
    if !(co.detection_probability > 0.0 && co.detection_probability <= 1.0) {
        err(
            "object_count_observation.detection_probability".into(),
            format!(
                "{} is not a probability in (0, 1]",
                co.detection_probability
            ),
            "use a number in (0, 1], e.g. 0.8".into(),
        );
    }
    if !(co.false_positive_rate.is_finite() && co.false_positive_rate >= 0.0) {
        err(
            "object_count_observation.false_positive_rate".into(),
            format!("{} is negative or not a number", co.false_positive_rate),
            "use a rate >= 0, e.g. 0.05".into(),
        );
    }
    let ph = &k.placeholder;
    for (name, v) in [
        ("no_places_area_m2", ph.no_places_area_m2),
        ("room_area_m2", ph.room_area_m2),
        ("door_distance_m", ph.door_distance_m),
    ] {
        if !(v.is_finite() && v > 0.0) {
            err(
                format!("placeholder.{name}"),
                format!("{v} is not a positive scale"),
                "use a finite number > 0".into(),
            );
        }
    }
    if !(0.0..=1.0).contains(&ph.another_room) {
        err(
            "placeholder.another_room".into(),
            format!("{} is not a probability", ph.another_room),
            "use a number in [0, 1]".into(),
        );
    }
    for (name, v) in [
        ("false_negative", k.sensor.false_negative),
        ("false_positive", k.sensor.false_positive),
    ] {
        if !(0.0..1.0).contains(&v) {
            err(
                format!("sensor.{name}"),
                format!("{v} is not a probability in [0, 1)"),
                "use a number in [0, 1), e.g. 0.2 / 0.05".into(),
            );
        }
    }
    if let Some(c) = &k.sensor.correlation {
        if !(c.range_share.is_finite() && c.range_share > 0.0) {
            err(
                "sensor.correlation.range_share".into(),
                format!("{} is not a positive share", c.range_share),
                "use a finite number > 0, e.g. 0.2 (a fifth of the detection range)".into(),
            );
        }
        if !(c.aspect_deg > 0.0 && c.aspect_deg <= 180.0) {
            err(
                "sensor.correlation.aspect_deg".into(),
                format!("{} is not an angle in (0, 180] degrees", c.aspect_deg),
                "use a number of degrees in (0, 180], e.g. 30".into(),
            );
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
kind: knowledge
name: t
room_categories: [corridor, kitchen]
object_classes:
  - { name: table, size: [1, 1, 1], detection_range: [0.5, 4], recognition_range: [0.5, 3], landmark: true }
  - { name: cup, size: [0.1, 0.1, 0.1], detection_range: [0.5, 2], recognition_range: [0.5, 1] }
category_prior: [0.5, 0.5]
connectivity: [[1, 2], [2, 0.5]]
place_properties:
  - { name: shape, values: [long, square], given_category: [[0.8, 0.2], [0.3, 0.7]] }
object_rates: { cup: [0.1, 1.0] }
landmark_rates:
  - { object: cup, relation: on, landmark: table, rates: [0.05, 0.5] }
"#;

    #[test]
    fn a_complete_knowledge_file_is_valid() {
        assert_eq!(check("k.yaml", GOOD), vec![]);
    }

    #[test]
    fn a_minimal_first_version_file_is_still_valid() {
        let text = "kind: knowledge\nname: t\nroom_categories: [a]\nobject_classes: []\n";
        assert_eq!(check("k.yaml", text), vec![]);
    }

    fn diags(edit: (&str, &str)) -> Vec<Diagnostic> {
        assert!(GOOD.contains(edit.0), "test edit must apply");
        check("k.yaml", &GOOD.replace(edit.0, edit.1))
    }

    #[test]
    fn negative_rates_are_rejected_with_their_path() {
        let d = diags(("cup: [0.1, 1.0]", "cup: [-0.1, 1.0]"));
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "object_rates.cup[0]");
        assert_eq!(d[0].file, "k.yaml");
        assert!(d[0].expected.contains(">= 0"));
    }

    #[test]
    fn a_sensor_correlation_is_checked_field_by_field() {
        let with = |c: &str| {
            let text = format!("{GOOD}sensor: {{ false_negative: 0.2, correlation: {c} }}\n");
            check("k.yaml", &text)
        };
        assert_eq!(with("{ range_share: 0.2, aspect_deg: 30 }"), vec![]);
        let d = with("{ range_share: 0, aspect_deg: 181 }");
        let paths: Vec<&str> = d.iter().map(|d| d.path.as_str()).collect();
        assert_eq!(
            paths,
            [
                "sensor.correlation.range_share",
                "sensor.correlation.aspect_deg"
            ]
        );
        // A missing length is a parse error, not a silent default.
        let text = format!("{GOOD}sensor: {{ correlation: {{ aspect_deg: 30 }} }}\n");
        assert!(crate::load_yaml_str::<Knowledge>("k.yaml", &text).is_err());
    }

    #[test]
    fn tables_of_the_wrong_size_are_rejected() {
        let d = diags(("[[1, 2], [2, 0.5]]", "[[1, 2]]"));
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "connectivity");
        let d = diags(("rates: [0.05, 0.5]", "rates: [0.05]"));
        assert_eq!(d[0].path, "landmark_rates[0].rates");
    }

    #[test]
    fn distributions_must_sum_to_one() {
        let d = diags(("[[0.8, 0.2], [0.3, 0.7]]", "[[0.8, 0.3], [0.3, 0.7]]"));
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "place_properties[0].given_category[0]");
        assert!(d[0].message.contains("sum"));
        let d = diags(("category_prior: [0.5, 0.5]", "category_prior: [0.5, 0.6]"));
        assert_eq!(d[0].path, "category_prior");
    }

    #[test]
    fn unknown_classes_and_non_landmarks_are_rejected() {
        let d = diags(("object_rates: { cup:", "object_rates: { mug:"));
        assert_eq!(d[0].path, "object_rates.mug");
        assert!(d[0].expected.contains("table, cup"));
        let d = diags(("landmark: table, rates", "landmark: cup, rates"));
        assert_eq!(d[0].path, "landmark_rates[0].landmark");
    }

    #[test]
    fn asymmetric_connectivity_is_rejected() {
        let d = diags(("[[1, 2], [2, 0.5]]", "[[1, 2], [3, 0.5]]"));
        assert_eq!(d[0].path, "connectivity[1][0]");
    }

    /// GOOD with a sensor model and `cup` verified by `verifier` (a flow mapping).
    fn with_verifier(verifier: &str) -> String {
        let hyp = "{ mean: 1.0, kernel: { signal_variance: 0.5, length_scales: [1.0, 0.5] }, \
                   noise_variance: 0.01, spread: 0.3, points: [[1.0, 0.0, 1.2]], \
                   corr: { kernel: { signal_variance: 0.4, length_scales: [1.0, 0.3] }, noise_variance: 0.05 } }";
        let models = format!(
            "sensor_models:\n  - name: generic\n    model:\n      kind: {{ kind: dynamic, alpha_scale: 0.5 }}\n      \
             max_range: 6.0\n      aspect_limit: null\n      object: {hyp}\n      no_object: {hyp}\n"
        );
        GOOD.replace(
            "recognition_range: [0.5, 1] }",
            &format!("recognition_range: [0.5, 1], verifier: {verifier} }}"),
        ) + &models
    }

    #[test]
    fn a_verifier_block_naming_a_trained_model_is_valid() {
        let text = with_verifier("{ strategy: planned, model: generic }");
        assert_eq!(check("k.yaml", &text), vec![]);
        let text = with_verifier("{ strategy: greedy, model: generic, threshold: 0.9 }");
        assert_eq!(check("k.yaml", &text), vec![]);
        let text = with_verifier("{ strategy: count }");
        assert_eq!(check("k.yaml", &text), vec![]);
        let text = with_verifier("{ strategy: sequential }");
        assert_eq!(check("k.yaml", &text), vec![]);
        // The sequential verifier weighs its looks' scores with a model when it names one.
        let text = with_verifier("{ strategy: sequential, model: generic }");
        assert_eq!(check("k.yaml", &text), vec![]);
    }

    #[test]
    fn a_bad_verifier_block_is_rejected_with_the_field_named() {
        let path = |v: &str| {
            let d = check("k.yaml", &with_verifier(v));
            assert_eq!(d.len(), 1, "{v}: {d:?}");
            d[0].path.clone()
        };
        assert_eq!(
            path("{ strategy: planned, model: doors }"),
            "object_classes[1].verifier.model"
        );
        assert_eq!(
            path("{ strategy: planned }"),
            "object_classes[1].verifier.model"
        );
        // The counting rule reasons with no trained model; a sequential verifier's must exist.
        assert_eq!(
            path("{ strategy: sequential, model: doors }"),
            "object_classes[1].verifier.model"
        );
        assert_eq!(
            path("{ strategy: count, model: generic }"),
            "object_classes[1].verifier.model"
        );
        assert_eq!(
            path("{ strategy: greedy, model: generic, threshold: 1.5 }"),
            "object_classes[1].verifier.threshold"
        );
        assert_eq!(
            path("{ strategy: rtbss, model: generic, threshold: 0.8 }"),
            "object_classes[1].verifier.threshold"
        );
        // An unknown strategy is a parse error at its own path.
        let d = check(
            "k.yaml",
            &with_verifier("{ strategy: psychic, model: generic }"),
        );
        assert!(
            d[0].path.contains("object_classes[1].verifier.strategy"),
            "{d:?}"
        );
        // A model out of range is named down to its field.
        let text = with_verifier("{ strategy: planned, model: generic }").replacen(
            "spread: 0.3",
            "spread: -0.3",
            1,
        );
        let d = check("k.yaml", &text);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "sensor_models[0].model.object.spread");
    }
}
