//! [`Body`]: the only code that moves the robot, points its camera and reads its laser map.
//! Every motion goes along the agent's own shortest path on the known map, in short
//! waypoints, so that the place map sees every door crossing; after each, the map update is
//! written into the [`Memory`] and the memory synced.

use crate::memory::Memory;
use crate::reason::MoveFailure;
use crate::report::{Activity, PathBreakdown};
use crate::AgentError;
use avs_map::nav::shortest_path;
use avs_map::places::dist;
use avs_robot::{
    ActionFailure, ActionResult, Camera, Detection, FailureReason, PlaceReading, Pose2D, Robot,
    ViewCone, ViewReport,
};
use avs_view::zoom::{three_step_search, ObjectModel, ZoomConfig, ZoomError, ZoomImage};
use petgraph::graph::NodeIndex;

/// The robot as the agent drives it.
pub(crate) struct Body<'r, R: Robot + ?Sized> {
    robot: &'r mut R,
    /// What the motions are for now.
    activity: Activity,
    /// Metres driven per activity.
    path: PathBreakdown,
    /// Motions in a row the robot refused or aborted without moving, and the last refusal.
    stuck: (usize, String),
    /// The zoom pipeline, when looks run it: its settings and the models of the classes it
    /// looks for (the small ones); `None` when off, or once the robot said it has none.
    zoom: Option<(ZoomConfig, Vec<ObjectModel>)>,
    /// The zoom pipeline's images since [`Body::take_zoom_images`], for the trace.
    zoom_log: Vec<ZoomImage>,
    /// Images processed by looks, those of them the zoom pipeline added, and its seconds.
    images: (usize, usize, f64),
    /// Classes every look also runs the detector for (the later goals of a
    /// [`Goal::find_all`](crate::Goal::find_all)); their detections go to `sighted`, not to
    /// the caller of the look.
    watch: Vec<String>,
    /// Detections of `watch` classes since [`Body::take_sightings`].
    sighted: Vec<Detection>,
}

/// The confidence of a recognition with `matches` of a model's `features` matched: `s / (s +
/// RECOGNITION_SHARE)` for the matched share `s` — one half at the paper's 5 % threshold
/// (§3.5), rising towards one with more matches.
fn recognition_confidence(matches: usize, features: u32) -> f64 {
    if features == 0 {
        return 0.0;
    }
    let s = matches as f64 / f64::from(features);
    s / (s + avs_view::zoom::RECOGNITION_SHARE)
}

/// A failed motion that moved the robot less than this (metres) left it where it stood.
const STUCK_M: f64 = 0.05;

impl<'r, R: Robot + ?Sized> Body<'r, R> {
    /// The body of `robot`.
    pub fn new(robot: &'r mut R) -> Self {
        Self {
            robot,
            activity: Activity::default(),
            path: PathBreakdown::default(),
            stuck: (0, String::new()),
            zoom: None,
            zoom_log: Vec::new(),
            images: (0, 0, 0.0),
            watch: Vec::new(),
            sighted: Vec::new(),
        }
    }

    /// Every look also runs the detector for `classes` (sought by later goals); what it sees
    /// of them is kept for [`Body::take_sightings`].
    pub fn watching(mut self, classes: Vec<String>) -> Self {
        self.watch = classes;
        self
    }

    /// The detections of the watched classes since the last call.
    pub fn take_sightings(&mut self) -> Vec<Detection> {
        std::mem::take(&mut self.sighted)
    }

    /// Looks run the zoom pipeline for `models`' classes (the others go to the one-shot
    /// detector).
    pub fn with_zoom(mut self, config: ZoomConfig, models: Vec<ObjectModel>) -> Self {
        self.zoom = Some((config, models));
        self
    }

    /// The zoom pipeline's images since the last call (the first image of each look is the
    /// look itself and is not among them).
    pub fn take_zoom_images(&mut self) -> Vec<ZoomImage> {
        std::mem::take(&mut self.zoom_log)
    }

    /// Images processed by looks, those of them the zoom pipeline added, and the pipeline's
    /// processing seconds.
    pub fn images(&self) -> (usize, usize, f64) {
        self.images
    }

    /// Run `f` with its motions booked to `activity` (the one before is restored after).
    pub fn with_activity<T>(&mut self, activity: Activity, f: impl FnOnce(&mut Self) -> T) -> T {
        let before = std::mem::replace(&mut self.activity, activity);
        let r = f(self);
        self.activity = before;
        r
    }

    /// The reason to give up when at least `limit` motions in a row failed without moving the
    /// robot (refused, or aborted where it stood): a robot that cannot move is told apart from
    /// a search that has not found its target yet.
    pub fn cannot_move(&self, limit: usize) -> Option<crate::reason::GiveUpReason> {
        (self.stuck.0 >= limit).then(|| crate::reason::GiveUpReason::CannotMove {
            failures: self.stuck.0,
            last: self.stuck.1.clone(),
        })
    }

    /// Metres driven so far through this body, per activity.
    pub fn path_by_activity(&self) -> PathBreakdown {
        self.path
    }

    /// Book the odometry since `before` to the current activity.
    fn book(&mut self, before: f64) {
        let moved = self.robot.odometry() - before;
        if moved > 0.0 {
            self.path.add(self.activity, moved);
        }
    }

    /// The robot's pose estimate.
    pub fn pose(&self) -> Pose2D {
        self.robot.pose()
    }

    /// The robot's planar position.
    pub fn at(&self) -> [f64; 2] {
        let p = self.robot.pose();
        [p.x, p.y]
    }

    /// The robot's pose as `[x, y, yaw]` (for the trace).
    pub fn pose3(&self) -> [f64; 3] {
        let p = self.robot.pose();
        [p.x, p.y, p.yaw]
    }

    /// The robot's camera.
    pub fn camera(&self) -> Camera {
        self.robot.camera()
    }

    /// Odometry so far, metres.
    pub fn odometry(&self) -> f64 {
        self.robot.odometry()
    }

    /// The laser map as the robot knows it now (doors the robot reports are not filed: for a
    /// memory's first map, before there is a memory).
    pub fn laser_map(&mut self) -> avs_map::grid::OccupancyGrid {
        self.robot.map_update().grid
    }

    /// The robot's map update: its doors filed in `mem` ([`Memory::note_doors`]), its laser
    /// map returned. The one place the agent reads the robot's map.
    fn read_map(&mut self, mem: &mut Memory) -> avs_map::grid::OccupancyGrid {
        let update = self.robot.map_update();
        mem.note_doors(update.doors);
        update.grid
    }

    /// Write the robot's current laser map into `mem` (no sync).
    pub fn refresh_map(&mut self, mem: &mut Memory) {
        mem.grid = self.read_map(mem);
    }

    /// Point the camera along `cone` (moving to its pose first if needed) and run the detector
    /// for `classes` — and for the watched classes ([`Body::watching`]), whose detections are
    /// kept aside: the report holds those of `classes` only.
    pub fn look(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<ViewReport> {
        let before = self.robot.odometry();
        let extra: Vec<&String> = self.watch.iter().filter(|w| !classes.contains(w)).collect();
        let r = if extra.is_empty() {
            self.look_with_zoom(cone, classes)
        } else {
            let asked: Vec<String> = classes.iter().chain(extra).cloned().collect();
            self.look_with_zoom(cone, &asked).map(|mut r| {
                let (own, other) = r
                    .detections
                    .into_iter()
                    .partition(|d| classes.contains(&d.class));
                r.detections = own;
                self.sighted.extend(other);
                r
            })
        };
        self.book(before);
        r
    }

    /// The one-shot detector's look: one image, counted when the robot took it (a view the
    /// robot refused or failed processed no image).
    fn one_shot(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<ViewReport> {
        let r = self.robot.process_view_cone(cone, classes);
        if r.is_ok() {
            self.images.0 += 1;
        }
        r
    }

    /// [`Body::look`] without the booking: the zoom pipeline for the classes it has models of
    /// (Sjöö et al. `004` §3), the one-shot detector for the rest; a robot without the
    /// pipeline's images (`Unsupported`) gets the one-shot detector from then on.
    fn look_with_zoom(&mut self, cone: &ViewCone, classes: &[String]) -> ActionResult<ViewReport> {
        let Some((config, models)) = &self.zoom else {
            return self.one_shot(cone, classes);
        };
        let (zoomed, rest): (Vec<&String>, Vec<&String>) = classes
            .iter()
            .partition(|c| models.iter().any(|m| &m.class == *c));
        if zoomed.is_empty() {
            return self.one_shot(cone, classes);
        }
        let wanted: Vec<ObjectModel> = models
            .iter()
            .filter(|m| zoomed.contains(&&m.class))
            .cloned()
            .collect();
        let config = *config;
        let outcome = match three_step_search(self.robot, cone, &wanted, &config) {
            Ok(o) => o,
            Err(ZoomError::Unsupported { message, .. }) => {
                tracing::info!(%message, "the robot has no zoom pipeline: one-shot detector from now on");
                self.zoom = None;
                return self.one_shot(cone, classes);
            }
            Err(ZoomError::Robot(f)) => return Err(f),
            Err(e) => {
                return Err(ActionFailure::new(
                    FailureReason::ExecutionFailed,
                    format!("zoom pipeline: {e}"),
                ))
            }
        };
        self.images.0 += outcome.images.len();
        self.images.1 += outcome.images.len().saturating_sub(1);
        self.images.2 += outcome.seconds;
        self.zoom_log.extend(outcome.images.iter().skip(1).cloned());
        let mut detections: Vec<Detection> = outcome
            .found
            .iter()
            .map(|r| Detection {
                class: r.class.clone(),
                pose: r.position,
                confidence: recognition_confidence(r.matches, r.model_features),
            })
            .collect();
        let mut travelled = outcome.travelled;
        if !rest.is_empty() {
            let rest: Vec<String> = rest.into_iter().cloned().collect();
            let other = self.one_shot(cone, &rest)?;
            detections.extend(other.detections);
            travelled += other.travelled;
        }
        Ok(ViewReport {
            pose: self.robot.pose(),
            detections,
            travelled,
        })
    }

    /// Point the camera along `cone` (moving to its pose first if needed) and read the
    /// detector's scores for `class` at the locations `at`.
    pub fn scores(
        &mut self,
        cone: &ViewCone,
        class: &str,
        at: &[avs_robot::Point3],
    ) -> ActionResult<avs_robot::ScoreReport> {
        let before = self.robot.odometry();
        let r = self.robot.detector_scores(cone, class, at);
        self.book(before);
        r
    }

    /// The first survey of a new memory: turn in place so the laser sees all around, drop the
    /// first place and sync.
    pub fn survey(&mut self, mem: &mut Memory) -> Result<(), AgentError> {
        let p = self.robot.pose();
        let before = self.robot.odometry();
        let _ = self
            .robot
            .move_to(Pose2D::new(p.x, p.y, p.yaw + std::f64::consts::PI));
        let _ = self.robot.move_to(p);
        self.book(before);
        let grid = self.read_map(mem);
        mem.wm.places.robot_moved(&grid, [p.x, p.y], [p.x, p.y]);
        mem.grid = grid;
        mem.sync()?;
        self.classify_here(mem);
        Ok(())
    }

    /// Turn in place so that the laser sees all around, and update the maps.
    pub fn turn_around(&mut self, mem: &mut Memory) -> Result<(), AgentError> {
        let here = self.robot.pose();
        let before = self.robot.odometry();
        let _ = self
            .robot
            .move_to(Pose2D::new(here.x, here.y, here.yaw + std::f64::consts::PI));
        let _ = self.robot.move_to(here);
        self.book(before);
        let grid = self.read_map(mem);
        mem.wm.places.update(&grid);
        mem.grid = grid;
        mem.sync()?;
        self.classify_here(mem);
        Ok(())
    }

    /// Run the robot's place classifiers at the place the robot stands on (within
    /// `tuning.at_place` of it), once per place: the readings, to be filed with
    /// [`Body::file_place_readings`] once the place has a room (after the next sync). A robot
    /// without classifiers returns no reading; a failed classification is logged and skipped
    /// (the room's category then rests on the other evidence).
    fn read_place(&mut self, mem: &mut Memory) -> Option<(NodeIndex, Vec<PlaceReading>)> {
        let place = mem.wm.places.current_place()?;
        let pos = mem.wm.places.graph.node_weight(place)?.pos;
        if mem.classified.contains(&place) || dist(pos, self.at()) > mem.tuning.at_place {
            return None;
        }
        mem.classified.insert(place);
        match self.robot.classify_place() {
            Ok(r) => Some((place, r)),
            Err(e) => {
                tracing::debug!(place = place.index(), error = %e, "place classification failed");
                None
            }
        }
    }

    /// File place readings as soft evidence on the category of each place's room
    /// (`002` §III). A place in no room (a door place) or a property the knowledge does not
    /// have is logged and skipped.
    fn file_place_readings(mem: &mut Memory, readings: Vec<(NodeIndex, Vec<PlaceReading>)>) {
        for (place, rs) in readings {
            for r in rs {
                let (p, property) = (place.index(), &r.property);
                tracing::debug!(place = p, %property, value = %r.value, "place property");
                if let Err(e) = mem.wm.saw_place_property(place, property, &r.likelihood) {
                    tracing::debug!(place = p, %property, error = %e, "place reading ignored");
                }
            }
        }
    }

    /// Classify the place the robot stands on and file the readings (the memory is synced).
    fn classify_here(&mut self, mem: &mut Memory) {
        let read = self.read_place(mem);
        Self::file_place_readings(mem, read.into_iter().collect());
    }

    /// Drive to `target` along a path on the known map, updating the place map on the way.
    /// The inner result says whether the motion arrived.
    pub fn go_to(
        &mut self,
        mem: &mut Memory,
        target: [f64; 2],
    ) -> Result<Result<(), MoveFailure>, AgentError> {
        let here = self.robot.pose();
        let from = [here.x, here.y];
        let path = mem
            .known_path(from, target)
            .or_else(|| mem.with_trav(true, |t| shortest_path(t, from, target, 1.0)));
        let mut wps: Vec<[f64; 2]> = match &path {
            Some(p) => p.points.iter().skip(1).step_by(5).copied().collect(),
            None => Vec::new(),
        };
        // The path ends at the traversable cell nearest the target (the goal snaps to it).
        wps.push(
            path.as_ref()
                .and_then(|p| p.points.last().copied())
                .unwrap_or(target),
        );
        let detour_factor = mem.tuning.detour_factor;
        let mut result = Ok(());
        let mut prev = [here.x, here.y];
        let mut readings = Vec::new();
        for w in wps {
            if dist(prev, w) < 1e-6 {
                continue;
            }
            let yaw = (w[1] - prev[1]).atan2(w[0] - prev[0]);
            let odo = self.robot.odometry();
            let r = self.robot.move_to(Pose2D::new(w[0], w[1], yaw));
            self.book(odo);
            let moved = self.robot.odometry() - odo;
            let detour = moved > detour_factor * dist(prev, w) + 1.0;
            let now = self.robot.pose();
            let grid = self.read_map(mem);
            // Doors first, from the map as this step left it: a doorway seen only from inside
            // it is crossed on this very step, and a door missing from the list here is never
            // confirmed (its room stays joined to the one the robot came from). Then the
            // places, then the placeholders that hang off them.
            mem.wm.places.refresh_doors(&grid);
            mem.wm.places.robot_moved(&grid, prev, [now.x, now.y]);
            mem.wm.places.update(&grid);
            mem.grid = grid;
            mem.at = [now.x, now.y];
            prev = [now.x, now.y];
            readings.extend(self.read_place(mem));
            if let Err(e) = r {
                // Only a motion that started and failed where it stood says the robot cannot
                // move; an unreachable target says something about the map.
                if e.reason == avs_robot::FailureReason::ExecutionFailed && moved < STUCK_M {
                    self.stuck = (self.stuck.0 + 1, e.to_string());
                } else {
                    self.stuck.0 = 0;
                }
                result = Err(MoveFailure::Robot(e));
                break;
            }
            if moved >= STUCK_M {
                self.stuck.0 = 0;
            }
            if detour {
                result = Err(MoveFailure::Detour { target });
                break;
            }
        }
        mem.sync()?;
        Self::file_place_readings(mem, readings);
        self.classify_here(mem);
        Ok(result)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skills::testing;
    use crate::AgentConfig;
    use avs_format::knowledge::Knowledge;
    use avs_robot::{Call, PlaceReading};

    /// A reading of `property` = `value` from a classifier right with probability `acc`
    /// (the confusion of the simulated classifier).
    fn reading(k: &Knowledge, property: &str, value: &str, acc: f64) -> PlaceReading {
        let prop = k
            .place_properties
            .iter()
            .find(|p| p.name == property)
            .expect("the shipped knowledge has the property");
        let n = prop.values.len() as f64;
        PlaceReading {
            property: property.into(),
            value: value.into(),
            likelihood: prop
                .values
                .iter()
                .map(|v| {
                    if v == value {
                        acc
                    } else {
                        (1.0 - acc) / (n - 1.0)
                    }
                })
                .collect(),
        }
    }

    /// P(category) of the robot's room after a survey and walks to x = 2.5, 4, 5.5 m and
    /// back, each new place classified with the next of `readings`: one value after each walk.
    fn posterior_along(readings: &[(&str, &str)], category: &str) -> (Vec<f64>, usize) {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(testing::room(7.0, 3.0), [1.0, 1.5]);
        for &(property, value) in readings {
            robot.script_place(vec![reading(&k, property, value, 0.8)]);
        }
        let mut ps = Vec::new();
        let mut mem = testing::memory(&config, &k, &mut robot);
        let p = |mem: &Memory| {
            let room = mem.current_room().expect("the robot stands in a room");
            mem.wm.concepts.p_category(room, category).unwrap()
        };
        ps.push(p(&mem));
        let mut body = Body::new(&mut robot);
        for x in [2.5, 4.0, 5.5, 1.0] {
            body.go_to(&mut mem, [x, 1.5]).unwrap().unwrap();
            ps.push(p(&mem));
        }
        let calls = robot
            .calls()
            .iter()
            .filter(|c| **c == Call::ClassifyPlace)
            .count();
        (ps, calls)
    }

    #[test]
    fn a_view_the_robot_refused_processed_no_image() {
        let mut robot = testing::robot(testing::room(4.0, 3.0), [1.0, 1.5]);
        robot.script_view(Err(ActionFailure::new(
            FailureReason::ExecutionFailed,
            "camera fault",
        )));
        let mut body = Body::new(&mut robot);
        let cone = ViewCone::new(Pose2D::new(1.0, 1.5, 0.0), 0.0, 0.0, 1.0);
        let classes = ["mug".to_string()];
        assert!(body.look(&cone, &classes).is_err());
        assert_eq!(body.images().0, 0);
        assert!(body.look(&cone, &classes).is_ok());
        assert_eq!(body.images().0, 1);
    }

    #[test]
    fn a_room_with_no_object_seen_is_classified_from_its_place_properties() {
        let prior = posterior_along(&[], "kitchen").0;
        // With no reading, nothing moves the room's category.
        assert!(
            prior.windows(2).all(|w| (w[0] - w[1]).abs() < 1e-9),
            "{prior:?}"
        );
        let kitchen_like = [("appearance", "kitchen_like"); 4];
        let (up, calls) = posterior_along(&kitchen_like, "kitchen");
        // Each kitchen-like place raises P(kitchen) (office.yaml: P(kitchen_like | kitchen)
        // = 0.5 against 0.1 and 0.2 for the other categories).
        for w in up[..4].windows(2) {
            assert!(w[1] > w[0] + 0.01, "P(kitchen) along the walk: {up:?}");
        }
        assert!(up[3] > prior[3] + 0.2, "{up:?} vs {prior:?}");
        // Back at the first place: classified once per place, nothing new.
        assert_eq!(calls, 4, "one classification per place");
        assert!((up[4] - up[3]).abs() < 1e-9, "{up:?}");
        let office_like = [("appearance", "office_like"); 4];
        let (down, _) = posterior_along(&office_like, "kitchen");
        for w in down[..4].windows(2) {
            assert!(w[1] < w[0], "P(kitchen) along the walk: {down:?}");
        }
        let (office, _) = posterior_along(&office_like, "office");
        assert!(
            office[3] > posterior_along(&[], "office").0[3] + 0.1,
            "{office:?}"
        );
    }
}
