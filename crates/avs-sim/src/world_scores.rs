//! The simulated robot's correlated detector over a world: the score the detector of a
//! knowledge class gives at a location, from [`crate::detector`]'s model, with the world's
//! objects as its features.
//!
//! [`crate::sim_robot::SimAgentRobot`] uses it for [`avs_robot::Robot::detector_scores`] and,
//! with [`crate::sim_robot::DetectorKind::Correlated`], for its detections of non-landmark
//! classes, so that a detection and a later score at the same spot come from the same feature
//! and the same nuisance field.
//!
//! ```
//! use avs_sim::world_scores::{FeatureKey, WorldScores};
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let world = avs_sim::World::load(&root.join("domains/environments/office.yaml")).unwrap();
//! let knowledge: avs_format::knowledge::Knowledge =
//!     avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let cereal = knowledge.class("cerealbox").unwrap();
//! let truth = world.objects_of_class("cerealbox").next().unwrap().pose.clone();
//! // At the cereal box: the object itself. Two metres off: clutter, keyed by its 0.5 m cell.
//! let at_box = WorldScores::locate(&world, cereal, [truth.x + 0.1, truth.y]);
//! assert!(matches!(at_box.key, FeatureKey::Object(_)) && at_box.feature.is_object);
//! let off = WorldScores::locate(&world, cereal, [truth.x + 2.0, truth.y]);
//! assert!(matches!(off.key, FeatureKey::Phantom(_)) && !off.feature.is_object);
//! // Its latent score seen from 1.5 m is fixed by the seed alone.
//! let robot = [truth.x - 1.5, truth.y];
//! let a = WorldScores::new(3).latent(cereal, &at_box, robot, 1.0).unwrap();
//! let b = WorldScores::new(3).latent(cereal, &at_box, robot, 1.0).unwrap();
//! assert_eq!(a, b);
//! ```
//!
//! # Model
//!
//! Every knowledge class `c` has its own [`CorrelatedDetector`] with the profile
//! [`ScoreProfile::for_class`]`(c.detection_range)` (the generic detector scaled to the class's
//! range). The feature that the detector of `c` responds to at a location `p` is
//! ([`WorldScores::locate`]):
//!
//! 1. the nearest object of class `c` (whatever its role) within [`MATCH_RADIUS`] of `p`
//!    (planar): an **object** feature at the object's position, facing its yaw;
//! 2. else, for a non-landmark class, the nearest object with `role: distractor` within
//!    [`MATCH_RADIUS`]: a **no-object** (look-alike) feature at its position, facing its yaw;
//! 3. else a **phantom** no-object feature (clutter) at `p` itself, facing +x.
//!
//! The vantage of a look from a robot at `(x, y)` with zoom `z` is the planar range from the
//! robot to the feature divided by `z` (a zoomed image sees as from nearer) and the aspect of
//! the robot relative to the feature's facing ([`WorldScores::vantage`]).
//!
//! # Choices where the paper is vague
//!
//! * **What a detector responds to.** Velez et al. verify candidate detections of doors and
//!   signs in a world they do not model; our world has objects, look-alikes (`role:
//!   distractor`) and nothing else. Anything that is neither is clutter: a location where the
//!   detector still gives a (no-object) score, from a field of its own. Look-alikes do not
//!   count for landmark classes (furniture is not mistaken for a mug), as in
//!   [`crate::sensors`].
//! * **Fields are keyed, not numbered.** A feature's nuisance field is drawn from a stream
//!   ([`FeatureKey::stream`]) of a seed of its own class ([`WorldScores::class_seed`]: the
//!   robot's seed mixed with a hash of the class name), so it is fixed for the robot's lifetime
//!   and the same whatever was asked before: an object is keyed by its index in the
//!   environment, clutter by the [`PHANTOM_CELL`] cell of the location asked about. Two
//!   locations in one cell away from every object share one clutter field (each is still seen
//!   from its own vantage).
//! * **White noise** comes from each class detector's own generator (stream 0 of the class
//!   seed), so scores (not latent values) depend on the order of looks of that class, and the
//!   rest of the simulation (motion, the independent detector) draws nothing for them.
//! * **Images and occlusion** are the caller's: this module scores one feature at a time and
//!   knows nothing of fields of view or walls.

use crate::detector::{wrap_angle, CorrelatedDetector, Feature, ScoreProfile};
use crate::world::World;
use avs_format::environment::ObjectRole;
use avs_format::knowledge::ObjectClass;
use std::collections::{BTreeMap, HashMap};

/// How near (planar metres) an object must be to a location for the detector's score there to
/// be that object's.
pub const MATCH_RADIUS: f64 = 0.4;

/// Side of the square cells (metres) that key the clutter fields of locations with no object.
pub const PHANTOM_CELL: f64 = 0.5;

/// The stable name of a feature, which fixes its nuisance field.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FeatureKey {
    /// The object at this index of the environment's `objects` (an object of the class, or a
    /// look-alike).
    Object(usize),
    /// Clutter: the [`PHANTOM_CELL`] cell `[⌊x / 0.5⌋, ⌊y / 0.5⌋]` of a location with no object.
    Phantom([i64; 2]),
}

impl FeatureKey {
    /// The stream of the class seed the feature's field is drawn from: `index + 1` for an
    /// object (as [`CorrelatedDetector::new`] numbers its features); for clutter the top bit
    /// set and the cell's coordinates in the low 31 and 32 bits (cells more than 2³⁰ apart,
    /// over 500 000 km, would share a stream). Never 0, the white noise's.
    pub fn stream(&self) -> u64 {
        match *self {
            FeatureKey::Object(i) => (i as u64 + 1) & !(1 << 63),
            FeatureKey::Phantom([cx, cy]) => {
                (1 << 63) | ((cx as u64 & 0x7fff_ffff) << 32) | (cy as u64 & 0xffff_ffff)
            }
        }
    }

    /// The key of clutter at `p`: its [`PHANTOM_CELL`] cell.
    pub fn phantom(p: [f64; 2]) -> Self {
        FeatureKey::Phantom([
            (p[0] / PHANTOM_CELL).floor() as i64,
            (p[1] / PHANTOM_CELL).floor() as i64,
        ])
    }
}

/// The feature a class's detector responds to at a location: its key and its geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    /// The feature's stable name.
    pub key: FeatureKey,
    /// Position (the object's, or for clutter the location asked about), facing (the object's
    /// yaw, or 0 for clutter) and class (object of the class or not).
    pub feature: Feature,
}

/// The profile of a knowledge class ([`ScoreProfile::for_class`] of its detection range), or
/// why there is none: the message names the class's `detection_range`.
pub fn class_profile(class: &ObjectClass) -> Result<ScoreProfile, NoProfile> {
    let p = ScoreProfile::for_class(class.detection_range);
    p.check().map(|()| p).map_err(|e| {
        NoProfile(format!(
            "knowledge class `{}` detection_range {:?}: no correlated detector ({e}); expected a \
             positive maximum distance",
            class.name, class.detection_range
        ))
    })
}

/// A class whose detection range gives no correlated detector ([`class_profile`]): the message
/// names the class and the field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{0}")]
pub struct NoProfile(pub String);

/// One class's detector and the index of each of its features by key.
#[derive(Debug, Clone)]
struct ClassDetector {
    det: CorrelatedDetector,
    index: HashMap<FeatureKey, usize>,
}

/// The correlated detectors of every knowledge class over a world, created as the classes are
/// asked for (see the [module documentation](self)).
#[derive(Debug, Clone)]
pub struct WorldScores {
    seed: u64,
    classes: BTreeMap<String, ClassDetector>,
}

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

impl WorldScores {
    /// The detectors of a robot seeded with `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            classes: BTreeMap::new(),
        }
    }

    /// The seed of class `class`'s detector for robot seed `seed`: `seed` mixed with the
    /// 64-bit FNV-1a hash of the class name (stable across runs and platforms).
    pub fn class_seed(seed: u64, class: &str) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in class.bytes() {
            h ^= u64::from(b);
            h = h.wrapping_mul(0x0100_0000_01b3);
        }
        mix(seed ^ mix(h))
    }

    /// The feature of `world` the detector of `class` responds to at planar location `p` (see
    /// the [module documentation](self)).
    pub fn locate(world: &World, class: &ObjectClass, p: [f64; 2]) -> Located {
        let nearest = |keep: &dyn Fn(&avs_format::environment::Object) -> bool| {
            world
                .env
                .objects
                .iter()
                .enumerate()
                .filter(|(_, o)| keep(o))
                .map(|(i, o)| (i, (o.pose.x - p[0]).hypot(o.pose.y - p[1])))
                .filter(|&(_, d)| d <= MATCH_RADIUS)
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map(|(i, _)| i)
        };
        let found = nearest(&|o| o.class == class.name).or_else(|| {
            (!class.landmark)
                .then(|| nearest(&|o| o.role == ObjectRole::Distractor))
                .flatten()
        });
        match found {
            Some(i) => {
                Self::object(world, class, i).expect("an object of the class or a look-alike")
            }
            None => Located {
                key: FeatureKey::phantom(p),
                feature: Feature {
                    position: p,
                    facing: 0.0,
                    is_object: false,
                },
            },
        }
    }

    /// The feature of object `index` of `world` for the detector of `class`: an object feature
    /// when the object is of the class, a look-alike when it has `role: distractor` and the
    /// class is not a landmark class; `None` otherwise (or for an index out of range).
    pub fn object(world: &World, class: &ObjectClass, index: usize) -> Option<Located> {
        let o = world.env.objects.get(index)?;
        let is_object = o.class == class.name;
        if !is_object && (class.landmark || o.role != ObjectRole::Distractor) {
            return None;
        }
        Some(Located {
            key: FeatureKey::Object(index),
            feature: Feature {
                position: [o.pose.x, o.pose.y],
                facing: o.pose.yaw_deg.to_radians(),
                is_object,
            },
        })
    }

    /// The vantage point `(range, aspect)` of a look at `located` from a robot at `robot` with
    /// zoom `zoom`: the planar range divided by the zoom, and the aspect of the robot relative
    /// to the feature's facing, wrapped to `(−π, π]`.
    pub fn vantage(located: &Located, robot: [f64; 2], zoom: f64) -> (f64, f64) {
        let f = &located.feature;
        let (dx, dy) = (robot[0] - f.position[0], robot[1] - f.position[1]);
        (dx.hypot(dy) / zoom, wrap_angle(dy.atan2(dx) - f.facing))
    }

    /// The profile the detector of `class` scores with.
    /// An error when the class has no profile ([`class_profile`]).
    pub fn profile(&mut self, class: &ObjectClass) -> Result<&ScoreProfile, NoProfile> {
        Ok(self.detector(class)?.det.profile())
    }

    /// The detector of `class` and the index of `located`'s feature in it, each created on
    /// first use.
    fn feature(
        &mut self,
        class: &ObjectClass,
        located: &Located,
    ) -> Result<(&mut CorrelatedDetector, usize), NoProfile> {
        let cd = self.detector(class)?;
        let i = match cd.index.get(&located.key) {
            Some(&i) => i,
            None => {
                // Clutter is stored at its cell's centre: what was asked first does not matter.
                let mut f = located.feature.clone();
                if let FeatureKey::Phantom([cx, cy]) = located.key {
                    f.position = [
                        (cx as f64 + 0.5) * PHANTOM_CELL,
                        (cy as f64 + 0.5) * PHANTOM_CELL,
                    ];
                }
                let i = cd.det.add_feature(f, located.key.stream());
                cd.index.insert(located.key, i);
                i
            }
        };
        Ok((&mut cd.det, i))
    }

    fn detector(&mut self, class: &ObjectClass) -> Result<&mut ClassDetector, NoProfile> {
        let seed = self.seed;
        Ok(match self.classes.entry(class.name.clone()) {
            std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::btree_map::Entry::Vacant(e) => e.insert(ClassDetector {
                det: CorrelatedDetector::new(
                    class_profile(class)?,
                    Vec::new(),
                    Self::class_seed(seed, &class.name),
                ),
                index: HashMap::new(),
            }),
        })
    }

    /// The latent score (mean plus nuisance field, no white noise) of `located` for the
    /// detector of `class`, seen from `robot` with zoom `zoom`, whether or not the detector
    /// sees it there.
    /// An error when the class has no profile ([`class_profile`]).
    pub fn latent(
        &mut self,
        class: &ObjectClass,
        located: &Located,
        robot: [f64; 2],
        zoom: f64,
    ) -> Result<f64, NoProfile> {
        let (r, phi) = Self::vantage(located, robot, zoom);
        let (det, i) = self.feature(class, located)?;
        Ok(det.latent(i, r, phi))
    }

    /// One look's score of `located` for the detector of `class` from `robot` with zoom
    /// `zoom`: latent score plus white noise, or `None` (no noise drawn) when the profile does
    /// not see the feature from that vantage ([`ScoreProfile::sees`]).
    /// An error when the class has no profile ([`class_profile`]).
    pub fn score(
        &mut self,
        class: &ObjectClass,
        located: &Located,
        robot: [f64; 2],
        zoom: f64,
    ) -> Result<Option<f64>, NoProfile> {
        let (r, phi) = Self::vantage(located, robot, zoom);
        let (det, i) = self.feature(class, located)?;
        Ok(det.score_from(i, r, phi))
    }

    /// Whether the detector of `class` fires on `score` (above the profile's
    /// `fire_threshold`).
    /// An error when the class has no profile ([`class_profile`]).
    pub fn fires(&mut self, class: &ObjectClass, score: f64) -> Result<bool, NoProfile> {
        Ok(self.detector(class)?.det.fires(score))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feature_streams_are_never_the_noise_stream_and_objects_and_clutter_do_not_collide() {
        assert_eq!(FeatureKey::Object(0).stream(), 1);
        assert_eq!(FeatureKey::Object(41).stream(), 42);
        for c in [[0, 0], [-1, -1], [3, -7], [i64::from(i32::MAX), 5]] {
            let s = FeatureKey::Phantom(c).stream();
            assert!(s >> 63 == 1, "{c:?}");
            assert_ne!(s, 0);
        }
        assert_ne!(
            FeatureKey::Phantom([0, 1]).stream(),
            FeatureKey::Phantom([1, 0]).stream()
        );
        assert_ne!(
            FeatureKey::Phantom([-1, 0]).stream(),
            FeatureKey::Phantom([0, -1]).stream()
        );
        assert_eq!(
            FeatureKey::phantom([0.49, -0.01]),
            FeatureKey::Phantom([0, -1])
        );
    }

    #[test]
    fn class_seeds_differ_by_class_and_by_robot_seed() {
        let a = WorldScores::class_seed(1, "mug");
        assert_eq!(a, WorldScores::class_seed(1, "mug"));
        assert_ne!(a, WorldScores::class_seed(1, "cerealbox"));
        assert_ne!(a, WorldScores::class_seed(2, "mug"));
    }

    #[test]
    fn a_class_without_a_profile_is_an_error_naming_it_not_a_panic() {
        let class = ObjectClass {
            name: "ghost".into(),
            size: [0.1, 0.1, 0.1],
            detection_range: [0.0, 0.0],
            recognition_range: [0.0, 0.0],
            landmark: false,
            verifier: None,
        };
        let mut w = WorldScores::new(1);
        let e = w.fires(&class, 2.0).unwrap_err();
        assert!(e.to_string().contains("ghost") && e.to_string().contains("detection_range"));
        let located = Located {
            key: FeatureKey::phantom([0.0, 0.0]),
            feature: Feature {
                position: [0.0, 0.0],
                facing: 0.0,
                is_object: false,
            },
        };
        assert!(w.score(&class, &located, [1.0, 0.0], 1.0).is_err());
        assert!(w.profile(&class).is_err());
    }
}
