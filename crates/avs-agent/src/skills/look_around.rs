//! Looking around on entering a room: a pan over the full circle for the landmark classes, at
//! the tilts that keep every landmark the robot can see in the central half of an image
//! ([`look_tilts`]); landmarks seen twice (or confirmed by views centred on them, [`Relook`])
//! in the same room become in/on locations, and their counts are object-count evidence on the
//! room's category (Aydemir et al. 2011, `002` §III-A, eq. 1, thinned by the look's coverage).
//!
//! The same images run the detector of the class searched for (a view lists every object
//! searched for in it: Sjöö et al., `004` §2.1.2). A sighting of it, confirmed as a landmark's
//! is (seen in two overlapping views, or again through a view centred on it), is kept among
//! the memory's sightings, and the executive verifies it before the plan goes on
//! ([`super::sighted`]): a target in plain view of a room's door is found on entering, not after
//! the planner has searched the landmarks and the room. A look around that sees none of the
//! goal is a look in vain at every point of the room it could see ([`looked_in_vain`]): the
//! room's rate of the goal is thinned by them and the looks are remembered, as a view-cone
//! session's are, so that the planner weighs the room by what is left and its next search
//! of the room plans views for the points not looked at yet. Without it the robot walked past
//! targets it had in view: on floors 1–40 of the 200-floor bench (seed 1) two thirds of a
//! search's path came after the robot first stood in the target's room (BENCHMARKS.md, issue 17 session "the goal
//! in the look around").

use super::session::record_looks;
use super::sighted::{verify_sightings, Sighted};
use super::views::cones_from;
use super::Ctx;
use crate::body::Body;
use crate::memory::{ConeLoc, Known, Memory};
use crate::report::{FoundObject, Goal};
use crate::run::Run;
use crate::trace::{CategoryBelief, Event, LandmarkCount};
use crate::AgentError;
use avs_concepts::{Location, RoomId};
use avs_robot::{Detection, Robot, ViewCone};
use avs_verify::sequential::BinaryLooks;
use std::collections::BTreeMap;

/// Look around from where the robot stands for landmark classes: found landmarks become
/// locations, and their counts are evidence on the room's category (§III-A, eq. 1). With
/// `goal`, the goal's class is looked for in the same images and its confirmed sightings are
/// kept in [`Memory::sightings`] for the caller to verify (module docs).
pub(crate) fn look_around<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: Option<&str>,
) -> Result<(), AgentError> {
    let (Some(place), Some(room)) = (mem.current_place(), mem.current_room()) else {
        return Ok(());
    };
    let t = cx.tuning();
    let confirm = cx.config.confirm_min_confidence;
    let classes: Vec<String> = cx
        .knowledge
        .object_classes
        .iter()
        .filter(|c| c.landmark)
        .map(|c| c.name.clone())
        .collect();
    let is_landmark = |c: &str| classes.iter().any(|l| l == c);
    let sought: Option<String> = goal.filter(|g| !is_landmark(g)).map(str::to_string);
    let asked: Vec<String> = classes.iter().cloned().chain(sought.clone()).collect();
    // A landmark stands on the floor: a sighting whose centre is not within its class's
    // height (give or take the noise two sightings of one landmark may differ by) is no
    // landmark.
    let stands = |d: &Detection| {
        sought.as_deref() == Some(d.class.as_str())
            || cx.knowledge.class(&d.class).is_some_and(|c| {
                (d.pose.z - c.size[2] / 2.0).abs() <= c.size[2] / 2.0 + t.look_cluster / 2.0
            })
    };
    let cam = body.camera();
    let tilts = look_tilts(cx.knowledge, &cam, cx.config.robot_radius);
    let pose = body.pose();
    let mut dets: Vec<Detection> = Vec::new();
    // Pans half a field of view apart: every direction is in two views, so that a real
    // landmark can collect the sightings that a false alarm rarely does.
    let n_views = pan_views(&cam);
    let mut failed = 0;
    for k in 0..n_views {
        let pan = cam
            .clamp_pan(-std::f64::consts::PI + std::f64::consts::TAU * k as f64 / n_views as f64);
        for &tilt in &tilts {
            match body.look(&ViewCone::new(pose, pan, tilt, 1.0), &asked) {
                Ok(r) => dets.extend(
                    r.detections
                        .into_iter()
                        .filter(|d| d.confidence >= confirm && stands(d)),
                ),
                Err(_) => failed += 1,
            }
        }
    }
    // One sighting per object: merge detections of a class within the cluster radius.
    let mut clusters: Vec<(Detection, usize)> = Vec::new();
    for d in dets {
        match clusters.iter_mut().find(|(c, _)| {
            c.class == d.class && c.pose.planar_distance(d.pose.x, d.pose.y) < t.look_cluster
        }) {
            Some((c, n)) => {
                *n += 1;
                if c.confidence < d.confidence {
                    *c = d;
                }
            }
            None => clusters.push((d, 1)),
        }
    }
    // The views overlap: a real landmark is seen more than once, a false alarm rarely. A
    // sighting seen once is looked at again through views centred on it (where the detector
    // is at its best), [`Again`]: a landmark's until a sequential test tells a real landmark
    // from a false alarm ([`Relook`]), a target's until it shows again (it is only a
    // candidate for the verifier). A false alarm shows again within the cluster radius of the
    // first only by chance.
    let landmark_test = Again::Landmark(Relook::new(
        cx.knowledge.sensor.false_negative,
        cx.knowledge.sensor.false_positive,
    ));
    let target_test = Again::Candidate {
        looks: relooks(cx.knowledge.sensor.false_negative),
    };
    for (d, n) in &clusters {
        tracing::debug!(class = %d.class, x = d.pose.x, y = d.pose.y, sightings = n, "look-around sighting");
    }
    let mut confirmed = Vec::new();
    for (d, n) in clusters {
        let shown = n >= t.look_min_sightings || {
            let test = if sought.as_deref() == Some(d.class.as_str()) {
                target_test
            } else {
                landmark_test
            };
            let (pan, tilt) = cam.aim(pose, d.pose);
            let (mut hits, mut misses) = (0, 0);
            loop {
                if let Some(real) = test.decide(hits, misses) {
                    break real;
                }
                let again = body
                    .look(
                        &ViewCone::new(pose, pan, tilt, 1.0),
                        std::slice::from_ref(&d.class),
                    )
                    .map(|r| {
                        r.detections.iter().any(|e| {
                            e.class == d.class
                                && e.confidence >= confirm
                                && stands(e)
                                && e.pose.planar_distance(d.pose.x, d.pose.y) < t.look_cluster
                        })
                    })
                    .unwrap_or(false);
                if again {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        };
        if shown {
            confirmed.push(d);
        }
    }
    // `counts`: the landmarks seen from here, known ones included (what the trace reports);
    // `new`: those no earlier look around counted, the count evidence (each instance counts
    // once, in the look that first saw it: `avs_concepts`' crate docs, *Object counts*).
    let mut counts: BTreeMap<String, u32> = classes.iter().map(|c| (c.clone(), 0)).collect();
    let mut new = counts.clone();
    // The goal's sightings are kept for the caller to verify; a look around whose every view
    // was taken and that confirmed none looked in vain.
    let (targets, mut confirmed): (Vec<Detection>, Vec<Detection>) = confirmed
        .into_iter()
        .partition(|d| sought.as_deref() == Some(d.class.as_str()));
    if let (Some(goal), true, 0) = (sought.as_deref(), targets.is_empty(), failed) {
        looked_in_vain(cx, mem, run, &cam, goal, room, [pose.x, pose.y])?;
    }
    mem.note_sightings(targets, cx.config.min_confidence);
    // A landmark stands on the floor and blocks the laser: where the laser map shows open
    // floor all around a sighting (every cell within half the cluster radius, the pose error a
    // sighting may have), nothing stands there, however often the camera saw it.
    confirmed.retain(|d| {
        let room_for_it = !mem.grid.free_within([d.pose.x, d.pose.y], 0.5 * t.look_cluster);
        if !room_for_it {
            tracing::debug!(class = %d.class, x = d.pose.x, y = d.pose.y, "landmark sighting on open floor");
        }
        room_for_it
    });
    for d in confirmed {
        if !mem.same_room([pose.x, pose.y], [d.pose.x, d.pose.y]) {
            tracing::debug!(class = %d.class, x = d.pose.x, y = d.pose.y, "landmark in another room");
            continue; // seen through a door: another room
        }
        *counts.entry(d.class.clone()).or_default() += 1;
        let near = mem.object_place([d.pose.x, d.pose.y]).unwrap_or(place);
        let known = mem
            .objects
            .iter_mut()
            .find(|o| o.class == d.class && o.pos.planar_distance(d.pose.x, d.pose.y) < 1.0);
        if let Some(o) = known {
            // Found by a search, it was never counted: a look around counts it now.
            if !std::mem::replace(&mut o.counted, true) {
                *new.entry(d.class.clone()).or_default() += 1;
            }
            continue;
        }
        *new.entry(d.class.clone()).or_default() += 1;
        let lm = mem.wm.found_landmark(near, &d.class)?;
        mem.objects.push(Known {
            class: d.class.clone(),
            pos: d.pose,
            place: near,
            landmark: Some(lm),
            on: None,
            counted: true,
            confidence: d.confidence,
        });
    }
    for (c, n) in &new {
        mem.wm.saw_objects(place, c, *n, t.look_coverage)?;
    }
    mem.looked.insert(room.0);
    let landmarks: Vec<LandmarkCount> = counts
        .iter()
        .filter(|(_, n)| **n > 0)
        .map(|(c, n)| LandmarkCount {
            class: c.clone(),
            count: *n,
        })
        .collect();
    let categories: Vec<CategoryBelief> = cx
        .knowledge
        .room_categories
        .iter()
        .filter_map(|c| {
            let p = mem.wm.concepts.p_category(room, c).ok()?;
            Some(CategoryBelief {
                category: c.clone(),
                p,
            })
        })
        .collect();
    run.emit(Event::LookedAround {
        room: room.0,
        at: [pose.x, pose.y],
        landmarks,
        failed_views: failed,
        categories,
    });
    Ok(())
}

/// A look around from `at` in `room` that saw no `goal`: every point of the room it looked at
/// (the unzoomed views a camera turning all round there needs for the points it can see,
/// [`cones_from`]) holds one more look in vain, and the room's rate of the goal is thinned by
/// the share those looks removed, as a view-cone session's are (`002` eq. 1 thinned by the
/// looked-at cells; [`record_looks`]). Said in the trace when it moves the room's P(ObjectAt).
fn looked_in_vain(
    cx: Ctx,
    mem: &mut Memory,
    run: &mut Run,
    cam: &avs_robot::Camera,
    goal: &str,
    room: RoomId,
    at: [f64; 2],
) -> Result<(), AgentError> {
    let loc = ConeLoc::Room(room.0);
    let Some(set) = cones_from(cx, mem, cam, goal, loc, at) else {
        return Ok(());
    };
    let location = Location::Room(room);
    let all: Vec<usize> = (0..set.views.len()).collect();
    let before = mem.wm.concepts.p_object_at(location, goal)?;
    let q = record_looks(cx, mem, goal, loc, location, &set, &all);
    if q > 0.0 {
        mem.wm.concepts.mark_searched(location, goal, q)?;
        let after = mem.wm.concepts.p_object_at(location, goal)?;
        run.observe(format!(
            "the look around saw no {goal} in {:.0}% of the room's points: P(ObjectAt) {before:.3} -> {after:.3}",
            100.0 * set.covered_share
        ));
    }
    Ok(())
}

/// The pans of a look-around: half a field of view apart over the full circle.
fn pan_views(cam: &avs_robot::Camera) -> usize {
    (std::f64::consts::TAU / (0.5 * cam.hfov).max(0.05)).ceil() as usize
}

/// The tilts of a look-around: every landmark centre the robot can see falls in the central
/// half of some image's vertical field, as the pans ([`pan_views`], half a field apart) put
/// it in the central half of some image's horizontal field. The detector is at its best near
/// the optical axis; a landmark at the edge of the only image that holds it is rarely counted.
///
/// The elevations to cover come from the knowledge and the robot, not from a room: a landmark
/// class stands on the floor with its centre at half its height, and is seen from between the
/// nearest the robot can stand to that centre (its radius plus half the class's shorter side,
/// and no nearer than the detection range begins) and the far end of the detection range.
/// Their band is spanned by the tilt rule of Sjöö et al. (`004` §2.1.5,
/// [`avs_view::plan::tilt_rule`]) with half the vertical field of view, inside the camera's
/// tilt limits. For the office knowledge and a camera 1.2 m high with a 35° field tilting to
/// −45°, that is −45°, −28° and −12°: a table 0.9 m away (centre 43° below the camera) sits
/// 2° off the lowest image's axis, where the two tilts this replaces (−9° and −29°, chosen by
/// hand) put it at the lower edge of the image.
pub(crate) fn look_tilts(
    knowledge: &avs_format::knowledge::Knowledge,
    cam: &avs_robot::Camera,
    robot_radius: f64,
) -> Vec<f64> {
    let mut band: Option<(f64, f64)> = None;
    for c in knowledge.object_classes.iter().filter(|c| c.landmark) {
        let centre = c.size[2] / 2.0 - cam.height;
        let nearest = (robot_radius + c.size[0].min(c.size[1]) / 2.0).max(c.detection_range[0]);
        let farthest = c.detection_range[1].max(nearest);
        let (e0, e1) = (centre.atan2(nearest), centre.atan2(farthest));
        let (lo, hi) = (e0.min(e1), e0.max(e1));
        band = Some(band.map_or((lo, hi), |(a, b)| (a.min(lo), b.max(hi))));
    }
    let (lo, hi) = band.unwrap_or((0.0, 0.0));
    avs_view::plan::tilt_rule(lo, hi, cam.vfov / 2.0, cam.tilt_limits)
}

/// How the centred looks at a sighting seen once decide whether it showed again.
///
/// A landmark's sighting, once confirmed, is a landmark of the map and evidence on its room's
/// category from the look around alone, so it must pass the sequential test ([`Relook`]). A
/// target's sighting is a candidate that the verifier then looks at from closer up with its
/// own model ([`super::verify`]); the look around only screens it, by one more sighting in
/// the [`relooks`] that a real one needs to show again with probability
/// [`SIGHTING_SHOWS_AGAIN`]. Screened by the sequential test too, targets in view of a room's
/// door were dropped for one more miss and found much later (30-room bench, seed 1: SPL
/// 0.301 → 0.220; floor 2's whiteboard marker 4 → 25 m, floor 12's cereal box 137 → 754 m).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Again {
    /// A landmark's sighting: the sequential test.
    Landmark(Relook),
    /// A target's sighting: shown again once in at most `looks`.
    Candidate {
        /// The most centred looks.
        looks: usize,
    },
}

impl Again {
    /// After `hits` and `misses` centred looks: `Some(true)` shown, `Some(false)` not, `None`
    /// look again.
    fn decide(&self, hits: usize, misses: usize) -> Option<bool> {
        match *self {
            Again::Landmark(t) => t.decide(hits, misses),
            Again::Candidate { looks } => {
                if hits > 0 {
                    Some(true)
                } else if misses >= looks {
                    Some(false)
                } else {
                    None
                }
            }
        }
    }
}

/// How likely a real target seen once in the look-around must be to show again in the
/// centred looks it is given ([`Again::Candidate`]): an expert's choice (the papers look
/// once). With one centred look (1 − FN = 0.8) a fifth of the real landmarks seen in one view
/// were lost — 25 of 229 on 60 bench floors — when landmarks were screened the same way.
const SIGHTING_SHOWS_AGAIN: f64 = 0.95;

/// The centred looks a target's sighting seen once gets: the fewest `k` with `1 − FN^k ≥`
/// [`SIGHTING_SHOWS_AGAIN`] (two for the knowledge's FN 0.2), at least one; one when the
/// detector never misses, and at most [`MAX_RELOOKS`] for a detector that nearly always does.
fn relooks(false_negative: f64) -> usize {
    if false_negative.is_nan() || false_negative <= 0.0 {
        return 1;
    }
    if false_negative >= 1.0 {
        return MAX_RELOOKS;
    }
    let k = ((1.0 - SIGHTING_SHOWS_AGAIN).ln() / false_negative.ln()).ceil();
    (k as usize).clamp(1, MAX_RELOOKS)
}

/// Wald's error rates for the centred looks' test of a sighting seen once ([`Relook`]): a
/// false alarm is confirmed with probability at most about `FALSE_LANDMARK` (the test's α),
/// a real landmark lost with about `LOST_LANDMARK` (β). Our choices (the papers look once).
/// The old rule, "shows again once in two looks", lost a real landmark with 0.04 but let a
/// false alarm through whenever another fell within the cluster radius in either look:
/// corridors read as kitchens from a counter that was not there (Fig. 3(a) with seed 2 on the
/// default and wide offices, Fig. 3(f) with seed 3 on the default and tall ones: about ten
/// false sightings per look around, each confirmed with up to 0.1).
const FALSE_LANDMARK: f64 = 0.01;
/// See [`FALSE_LANDMARK`].
const LOST_LANDMARK: f64 = 0.05;
/// The most centred looks one sighting gets (a truncated test).
const MAX_RELOOKS: usize = 8;

/// The centred looks at a sighting seen once, as Wald's sequential probability ratio test of
/// "a real landmark" (each look sees it with 1 − FN) against "a false alarm" (a look shows a
/// sighting of the class within the cluster radius with at most FP, the detector's whole
/// false-alarm rate per view): each hit multiplies the likelihood ratio by (1 − FN)/FP, each
/// miss by FN/(1 − FP); the sighting is confirmed when the ratio reaches
/// B = (1 − β)/α and given up when it falls to A = β/(1 − α) or the looks run out
/// ([`MAX_RELOOKS`]). By Ville's inequality a false alarm ever reaches B with probability at
/// most 1/B. For the knowledge's FN 0.2 and FP 0.05 two hits in a row confirm and two
/// misses in a row give up.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Relook {
    /// The looks' model: a hit with 1 − FN on a real landmark, with FP on a false alarm.
    looks: BinaryLooks,
    /// ln B.
    confirm: f64,
    /// ln A.
    give_up: f64,
}

impl Relook {
    fn new(false_negative: f64, false_positive: f64) -> Self {
        Self {
            looks: BinaryLooks {
                hit_if_object: 1.0 - false_negative.clamp(0.0, 1.0),
                hit_if_not: false_positive.clamp(0.0, 1.0),
            },
            confirm: ((1.0 - LOST_LANDMARK) / FALSE_LANDMARK).ln(),
            give_up: (LOST_LANDMARK / (1.0 - FALSE_LANDMARK)).ln(),
        }
    }

    /// After `hits` and `misses` centred looks: `Some(true)` confirmed, `Some(false)` given
    /// up, `None` look again. A NaN ratio (a detector that never misses and never errs,
    /// contradicted) gives up.
    fn decide(&self, hits: usize, misses: usize) -> Option<bool> {
        let llr = self.looks.log_likelihood_ratio(hits, misses);
        if llr >= self.confirm {
            Some(true)
        } else if llr.is_nan() || llr <= self.give_up || hits + misses >= MAX_RELOOKS {
            Some(false)
        } else {
            None
        }
    }
}

/// Look around in the room the robot is in unless that was done before ([`look_around`],
/// with the goal's class `goal`); a failure is noted in the trace, not an error.
pub(crate) fn look_around_if_new<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: Option<&str>,
) {
    if matches!(mem.current_room(), Some(r) if !mem.looked.contains(&r.0)) {
        if let Err(e) = look_around(cx, mem, body, run, goal) {
            run.observe(format!("looking around failed: {e}"));
        }
    }
}

/// The class a look around looks for besides the landmarks: the goal's, unless the
/// configuration says otherwise ([`crate::AgentConfig::goal_in_look_around`]).
pub(crate) fn looked_for<'a>(cx: Ctx, goal: &'a Goal) -> Option<&'a str> {
    cx.config.goal_in_look_around.then_some(goal.class.as_str())
}

/// Look around in the room the robot is in unless that was done before
/// ([`look_around_if_new`], for the goal too when the configuration says so, [`looked_for`]),
/// then verify what it saw of the goal ([`verify_sightings`]): the goal's object, filed in the
/// memory, when a sighting is accepted.
pub(crate) fn look_around_for_goal<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: &Goal,
) -> Result<Option<FoundObject>, AgentError> {
    look_around_if_new(cx, mem, body, run, looked_for(cx, goal));
    verify_sightings(cx, mem, body, run, &goal.class, Sighted::LookAround)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skills::testing::{self, object};
    use crate::AgentConfig;
    use avs_robot::ScriptedRobot;

    /// A look around from (1.5, 2.0) in a room with a table at (3.5, 2.0), a cereal box on it
    /// when `with_box`, looking for `goal` besides the landmarks: the memory after it, the
    /// robot (for its calls), the trace's text and its events.
    fn looked_around(
        goal: Option<&str>,
        with_box: bool,
    ) -> (Memory, ScriptedRobot, String, Vec<Event>) {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(room_with_a_table(), [1.5, 2.0]);
        robot.place(object("table", 3.5, 2.0, 0.75));
        if with_box {
            robot.place(object("cerealbox", 3.4, 2.1, 0.89));
        }
        let mut mem = testing::memory(&config, &k, &mut robot);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        look_around(cx, &mut mem, &mut Body::new(&mut robot), &mut run, goal).unwrap();
        let text = testing::text(&run);
        (mem, robot, text, std::mem::take(&mut run.events))
    }

    /// With the goal's class, the look around keeps a confirmed sighting of it for the
    /// caller to verify (not a landmark, no count evidence); without, the detector is never
    /// asked for it.
    #[test]
    fn a_look_around_with_the_goal_keeps_its_sighting_and_counts_only_landmarks() {
        for goal in [Some("cerealbox"), None] {
            let (mem, robot, text, _) = looked_around(goal, true);
            assert_eq!(mem.objects.len(), 1, "{:?}", mem.objects);
            assert_eq!(mem.objects[0].class, "table");
            let kept: Vec<_> = mem.sightings.iter().map(|d| d.class.as_str()).collect();
            let asked = robot.calls().iter().any(|c| {
                matches!(c, avs_robot::Call::View(_, classes)
                    if classes.iter().any(|c| c == "cerealbox"))
            });
            match goal {
                Some(_) => {
                    assert_eq!(kept, ["cerealbox"], "{:?}", mem.sightings);
                    let d = &mem.sightings[0];
                    assert!(d.pose.planar_distance(3.4, 2.1) < 1e-9);
                    assert!(asked);
                }
                None => assert!(kept.is_empty() && !asked, "{kept:?}"),
            }
            assert!(text.contains("table x1"));
        }
    }

    /// A look around with the goal that sees none of it thins the room's rate of the goal by
    /// the points it looked at, and remembers the looks (so the room's next search plans for
    /// the rest); one that sees the goal leaves the room as it was (its sighting is verified
    /// next), and so does one without the goal.
    #[test]
    fn a_look_around_that_sees_no_goal_thins_the_room_by_what_it_looked_at() {
        let p = |mem: &Memory| {
            let room = mem.current_room().expect("a room");
            mem.wm
                .concepts
                .p_object_at(Location::Room(room), "cerealbox")
                .unwrap()
        };
        // The room's rate after a look around for landmarks only: the counted table raises it.
        let (landmarks_only, _, _, _) = looked_around(None, false);
        let unthinned = p(&landmarks_only);
        for (goal, in_view, thinned) in [
            (Some("cerealbox"), false, true),
            (Some("cerealbox"), true, false),
            (None, false, false),
        ] {
            let (mem, _, text, _) = looked_around(goal, in_view);
            let looked = mem.looks.get("cerealbox").map_or(0, |l| l.len());
            let said = text.contains("the look around saw no cerealbox");
            if thinned {
                assert!(looked > 0 && said, "{text}");
                assert!(p(&mem) < unthinned, "{} vs {unthinned}", p(&mem));
            } else {
                assert!(looked == 0 && !said, "{text}");
                assert!(
                    (p(&mem) - unthinned).abs() < 1e-12,
                    "{} vs {unthinned}",
                    p(&mem)
                );
            }
        }
    }

    #[test]
    fn a_table_seen_in_overlapping_views_becomes_a_landmark_of_the_room() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let (mem, robot, text, events) = looked_around(None, false);
        let room = mem.current_room().expect("the robot stands in a room");
        assert!(mem.looked.contains(&room.0));
        assert_eq!(mem.objects.len(), 1, "{:?}", mem.objects);
        assert_eq!(mem.objects[0].class, "table");
        assert!(mem.objects[0].landmark.is_some());
        assert!(text.contains("table x1"), "{text}");
        // The JSON event carries the same as numbers: the room, the counts, the categories.
        let looked = events.iter().find_map(|e| match e {
            Event::LookedAround {
                room: r,
                landmarks,
                categories,
                ..
            } => Some((*r, landmarks.clone(), categories.clone())),
            _ => None,
        });
        let (r, landmarks, categories) = looked.expect("a LookedAround event");
        assert_eq!(r, room.0);
        assert_eq!(
            landmarks,
            vec![LandmarkCount {
                class: "table".into(),
                count: 1
            }]
        );
        assert_eq!(categories.len(), k.room_categories.len());
        let total: f64 = categories.iter().map(|c| c.p).sum();
        assert!((total - 1.0).abs() < 1e-9, "{categories:?}");
        // Every view of the pan asked for the landmark classes only, at the look's tilts.
        let views = robot.views();
        assert!(views.len() >= 2 * 8, "{} views", views.len());
        let tilts = look_tilts(&k, &robot.camera(), config.robot_radius);
        assert!(views.iter().all(|v| tilts.contains(&v.tilt)));
    }

    /// A 5 m × 4 m room with a table's footprint (1.2 m × 0.8 m) at (3.5, 2.0) in its map.
    fn room_with_a_table() -> avs_map::grid::OccupancyGrid {
        testing::furnish(testing::room(5.0, 4.0), [3.5, 2.0], [1.2, 0.8])
    }

    /// A table the camera reports in every view of the pan, where the laser map shows open
    /// floor all around: a piece of furniture there would block the laser, so it is a false
    /// alarm, however often seen (most false landmarks of the bench floors were such). With the
    /// table's footprint in the map it is a landmark.
    #[test]
    fn a_landmark_sighting_on_open_floor_is_no_landmark_however_often_seen() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        for (grid, counted) in [
            (testing::room(5.0, 4.0), false),
            (room_with_a_table(), true),
        ] {
            let mut robot = testing::robot(grid, [1.5, 2.0]);
            robot.place(object("table", 3.5, 2.0, 0.4));
            let mut mem = testing::memory(&config, &k, &mut robot);
            let mut sink = testing::sink();
            let mut run = testing::run(&mut sink);
            let cx = testing::ctx(&k, &config);
            look_around(cx, &mut mem, &mut Body::new(&mut robot), &mut run, None).unwrap();
            assert_eq!(mem.objects.len(), usize::from(counted), "{:?}", mem.objects);
            assert_eq!(
                testing::text(&run).contains("table x1"),
                counted,
                "{}",
                testing::text(&run)
            );
        }
    }

    #[test]
    fn the_look_tilts_hold_every_landmark_the_robot_can_see_in_the_central_half_of_an_image() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut cam = testing::robot(testing::room(5.0, 4.0), [1.5, 2.0]).camera();
        for (height, vfov) in [(1.2, 35f64), (1.6, 35.0), (1.2, 20.0), (0.6, 50.0)] {
            cam.height = height;
            cam.vfov = vfov.to_radians();
            let tilts = look_tilts(&k, &cam, config.robot_radius);
            assert!(tilts.windows(2).all(|w| w[0] < w[1]), "{tilts:?}");
            assert!(tilts
                .iter()
                .all(|t| (cam.tilt_limits[0]..=cam.tilt_limits[1]).contains(t)));
            for c in k.object_classes.iter().filter(|c| c.landmark) {
                let nearest = (config.robot_radius + c.size[0].min(c.size[1]) / 2.0)
                    .max(c.detection_range[0]);
                for i in 0..=50 {
                    let d = nearest + (c.detection_range[1] - nearest) * f64::from(i) / 50.0;
                    let e = (c.size[2] / 2.0 - cam.height).atan2(d);
                    // Out of the camera's reach the nearest tilt is the limit.
                    let reach = e.clamp(cam.tilt_limits[0], cam.tilt_limits[1]);
                    let off = tilts
                        .iter()
                        .map(|t| (t - reach).abs())
                        .fold(f64::MAX, f64::min);
                    assert!(
                        off <= cam.vfov / 4.0 + 1e-9,
                        "{} at {d:.2} m ({:.1}°) is {:.1}° off the nearest of {:?} (camera {height} m, {vfov}°)",
                        c.name,
                        e.to_degrees(),
                        off.to_degrees(),
                        tilts.iter().map(|t| t.to_degrees()).collect::<Vec<_>>()
                    );
                }
            }
        }
        // The default camera: three tilts, the lowest at its limit.
        let cam = testing::robot(testing::room(5.0, 4.0), [1.5, 2.0]).camera();
        let tilts = look_tilts(&k, &cam, config.robot_radius);
        assert_eq!(tilts.len(), 3);
        assert_eq!(tilts[0], cam.tilt_limits[0]);
    }

    /// The pan's views, all scripted: the first sees `first`, the rest nothing; how many.
    fn script_pan(robot: &mut ScriptedRobot, first: Detection) -> usize {
        let (cam, config) = (robot.camera(), AgentConfig::default());
        let n =
            pan_views(&cam) * look_tilts(&testing::knowledge(), &cam, config.robot_radius).len();
        robot.script_view(Ok(vec![first]));
        for _ in 1..n {
            robot.script_view(Ok(Vec::new()));
        }
        n
    }

    #[test]
    fn a_sighting_that_does_not_stand_on_the_floor_is_no_landmark_however_often_seen() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        // A table seen in every view of the pan: at its own height it is counted; a metre
        // under the floor or two above it (where the detector's false alarms may fall) it is
        // not.
        for (z, counted) in [(0.4, true), (-1.0, false), (2.5, false)] {
            let mut robot = testing::robot(room_with_a_table(), [1.5, 2.0]);
            let mut mem = testing::memory(&config, &k, &mut robot);
            let cam = robot.camera();
            let n = pan_views(&cam) * look_tilts(&k, &cam, config.robot_radius).len();
            for _ in 0..n + 8 {
                robot.script_view(Ok(vec![object("table", 3.5, 2.0, z)]));
            }
            let mut sink = testing::sink();
            let mut run = testing::run(&mut sink);
            let cx = testing::ctx(&k, &config);
            look_around(cx, &mut mem, &mut Body::new(&mut robot), &mut run, None).unwrap();
            assert_eq!(
                mem.objects.len(),
                usize::from(counted),
                "z {z}: {:?}",
                mem.objects
            );
        }
    }

    /// The probability that the centred-look test confirms a sighting that each look shows
    /// with `p`, over every sequence of looks (the oracle: exact enumeration).
    fn p_confirmed(test: &Relook, p: f64) -> f64 {
        (0..1u32 << MAX_RELOOKS)
            .map(|bits| {
                let (mut hits, mut misses, mut prob) = (0, 0, 1.0);
                loop {
                    if let Some(real) = test.decide(hits, misses) {
                        // Each decided prefix is counted once: by the sequences whose
                        // remaining bits are all 0.
                        let rest = bits >> (hits + misses);
                        return if real && rest == 0 { prob } else { 0.0 };
                    }
                    if bits >> (hits + misses) & 1 == 1 {
                        hits += 1;
                        prob *= p;
                    } else {
                        misses += 1;
                        prob *= 1.0 - p;
                    }
                }
            })
            .sum()
    }

    #[test]
    fn centred_looks_test_a_landmark_sequentially_and_screen_a_target_by_one_more_sighting() {
        // The knowledge's FN 0.2 and FP 0.05: a hit is worth 16, a miss 0.21; B = 95, A ≈ 0.05.
        // A target's sighting is screened: two looks for the knowledge's 0.2 (1 − 0.2² = 0.96 ≥
        // 0.95), five for 0.5 (1 − 0.5⁵ ≈ 0.97, 1 − 0.5⁴ ≈ 0.94), one for a detector that
        // never misses.
        assert_eq!(relooks(0.2), 2);
        assert_eq!(relooks(0.5), 5);
        assert_eq!(relooks(0.0), 1);
        assert_eq!(relooks(f64::NAN), 1);
        assert_eq!(relooks(1.0), MAX_RELOOKS);
        let screen = Again::Candidate { looks: 2 };
        assert_eq!(screen.decide(0, 1), None);
        assert_eq!(screen.decide(1, 1), Some(true));
        assert_eq!(screen.decide(0, 2), Some(false));
        let test = Relook::new(0.2, 0.05);
        assert_eq!(test.decide(0, 0), None);
        assert_eq!(test.decide(1, 0), None);
        assert_eq!(test.decide(2, 0), Some(true), "two hits in a row confirm");
        assert_eq!(
            test.decide(0, 2),
            Some(false),
            "two misses in a row give up"
        );
        assert_eq!(test.decide(2, 1), None, "16² × 0.21 = 54 < 95");
        assert_eq!(test.decide(3, 1), Some(true));
        // Exact rates: a false alarm that showed again on every look with the detector's whole
        // false-alarm rate is confirmed at most with Ville's bound α/(1 − β); a real landmark
        // seen with 1 − FN is kept at least as often as the old rule's 0.96 less β's margin.
        let false_alarm = p_confirmed(&test, 0.05);
        let real = p_confirmed(&test, 0.8);
        assert!(
            false_alarm <= FALSE_LANDMARK / (1.0 - LOST_LANDMARK),
            "false alarms confirmed with {false_alarm}"
        );
        assert!(
            real >= 1.0 - LOST_LANDMARK - 0.01,
            "real landmarks kept with {real}"
        );
        // The old rule (one hit in two looks) confirmed the same false alarm with 1 − 0.95².
        assert!(
            false_alarm < (1.0 - 0.95f64.powi(2)) / 10.0,
            "{false_alarm}"
        );
        // Degenerate detectors decide without a panic or an endless test.
        let perfect = Relook::new(0.0, 0.0);
        assert_eq!(perfect.decide(1, 0), Some(true));
        assert_eq!(perfect.decide(0, 1), Some(false));
        assert_eq!(
            perfect.decide(1, 1),
            Some(false),
            "a contradiction gives up"
        );
        let blind = Relook::new(1.0, 0.05);
        assert_eq!(blind.decide(1, 0), Some(false));
        assert_eq!(blind.decide(0, MAX_RELOOKS), Some(false));
        for (fn_, fp) in [(0.5, 0.3), (0.9, 0.01), (f64::NAN, 0.05), (0.2, f64::NAN)] {
            let t = Relook::new(fn_, fp);
            assert!(t.decide(0, MAX_RELOOKS).is_some() && t.decide(MAX_RELOOKS, 0).is_some());
        }
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        assert_eq!(k.sensor.false_negative, 0.2);
        let table = object("table", 3.5, 2.0, 0.75);
        // A real table seen in one view of the pan and missed by the first centred look: the
        // next three show it (16³ × 0.21 ≥ 95; with one centred look it was lost).
        let mut robot = testing::robot(room_with_a_table(), [1.5, 2.0]);
        robot.place(table.clone());
        let mut mem = testing::memory(&config, &k, &mut robot);
        let pan = script_pan(&mut robot, table.clone());
        robot.script_view(Ok(Vec::new()));
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        let before = robot.views().len();
        look_around(cx, &mut mem, &mut Body::new(&mut robot), &mut run, None).unwrap();
        assert_eq!(mem.objects.len(), 1, "{:?}", mem.objects);
        assert_eq!(robot.views().len() - before, pan + 4, "four centred looks");
        // A false alarm seen once (nothing there): two centred looks miss, and it is dropped.
        let mut robot = testing::robot(testing::room(5.0, 4.0), [1.5, 2.0]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        assert_eq!(script_pan(&mut robot, table), pan);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let before = robot.views().len();
        look_around(cx, &mut mem, &mut Body::new(&mut robot), &mut run, None).unwrap();
        assert!(mem.objects.is_empty(), "{:?}", mem.objects);
        assert_eq!(robot.views().len() - before, pan + 2);
    }

    /// A second look around in a room (the start of a second goal, from another place) sees
    /// the landmarks found by the first again. Counted again, the same counter would be two
    /// counters' evidence; counted as a fresh look that found none, it was evidence against the
    /// room's own furniture (P(kitchen) 0.63 → 0.28 here). It adds no new instance, and a look
    /// that can only add what the first missed weighs little (0.63 → 0.51).
    #[test]
    fn looking_around_again_counts_no_known_landmark_twice_and_weighs_little() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let grid = testing::furnish(testing::room(6.0, 4.0), [4.5, 3.4], [2.0, 0.6]);
        let mut robot = testing::robot(grid, [1.5, 2.0]);
        robot.place(object("counter", 4.5, 3.4, 0.9));
        let mut mem = testing::memory(&config, &k, &mut robot);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        let mut body = Body::new(&mut robot);
        look_around(cx, &mut mem, &mut body, &mut run, None).unwrap();
        let room = mem.current_room().expect("a room");
        let first = mem.wm.concepts.p_category(room, "kitchen").unwrap();
        assert_eq!(mem.objects.len(), 1, "{:?}", mem.objects);
        // To another place of the same room, and look around there as a new goal does.
        body.go_to(&mut mem, [3.5, 1.0]).unwrap().unwrap();
        let moved = mem.current_place();
        assert_eq!(mem.current_room(), Some(room));
        mem.looked.clear();
        look_around(cx, &mut mem, &mut body, &mut run, None).unwrap();
        assert_eq!(mem.objects.len(), 1, "the known counter was added again");
        let second = mem.wm.concepts.p_category(room, "kitchen").unwrap();
        assert!(
            second <= first + 1e-9 && second > first - 0.2,
            "P(kitchen) {first} -> {second} after seeing the same counter again from {moved:?}"
        );
    }

    /// A counter at the far wall, seen over a table standing between it and the robot (the
    /// table's footprint is an obstacle of the planar map): the counter is in the robot's room,
    /// whose floor surrounds it. The planar sight line, stopped by the table, filed it under
    /// another room.
    #[test]
    fn a_landmark_seen_over_a_table_is_in_the_room() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        // A 6 m × 6 m room (the gaps beside the table are wider than a door).
        // A 1.2 m × 1.6 m table in the middle, between the robot and the counter.
        let grid = testing::furnish(testing::room(6.0, 6.0), [3.0, 3.0], [1.2, 1.6]);
        let grid = testing::furnish(grid, [5.3, 3.0], [0.6, 2.0]);
        let mut robot = testing::robot(grid, [1.5, 3.0]);
        robot.place(object("counter", 5.3, 3.0, 0.9));
        let mut mem = testing::memory(&config, &k, &mut robot);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        let mut body = Body::new(&mut robot);
        let room = mem.current_room().expect("a room");
        let before = mem.wm.concepts.p_category(room, "kitchen").unwrap();
        assert!(!avs_map::raycast::line_of_sight(
            &mem.grid,
            [1.5, 3.0],
            [5.3, 3.0],
            false
        ));
        look_around(cx, &mut mem, &mut body, &mut run, None).unwrap();
        assert!(
            mem.objects.iter().any(|o| o.class == "counter"),
            "the counter is a landmark of the room: {:?}",
            mem.objects
        );
        let after = mem.wm.concepts.p_category(room, "kitchen").unwrap();
        assert!(after > before, "P(kitchen) {before} -> {after}");
    }

    #[test]
    fn a_sighting_seen_once_and_not_again_up_close_is_no_landmark() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(testing::room(5.0, 4.0), [1.5, 2.0]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        // The first view of the pan reports a desk; no other view (nor the centred second
        // look) sees it again: a false alarm.
        robot.script_view(Ok(vec![object("desk", 3.0, 3.0, 0.75)]));
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        look_around(cx, &mut mem, &mut Body::new(&mut robot), &mut run, None).unwrap();
        assert!(mem.objects.is_empty(), "{:?}", mem.objects);
        assert!(testing::text(&run).contains("no landmarks"));
        // The second look was centred on the sighting.
        let last = *robot.views().last().unwrap();
        let bearing = (3.0f64 - 2.0).atan2(3.0 - 1.5);
        assert!((last.camera_yaw() - bearing).abs() < 1e-9, "{last:?}");
    }
}
