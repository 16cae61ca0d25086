//! SEARCHFOROBJECT: a closed-loop view-cone POMDP session over the location's cones (`002`
//! §II-A.2). The prior P(ObjectAt L) of the conceptual map is spread over the points the
//! cones cover; the session looks, observes, and declares found or absent; a declared
//! sighting is verified ([`super::verify`]); a search in vain thins the location's rate by
//! what was looked at.

use super::views::{create_cones, location_points, view_text};
use super::{verify::verify, Ctx};
use crate::binding::{names, ObjArg};
use crate::body::Body;
use crate::memory::{ConeLoc, ConeSet, Known, Memory};
use crate::reason::ReplanReason;
use crate::report::{Activity, FoundObject, Goal};
use crate::run::{PointKey, Run, StepEnd};
use crate::trace::{Event, SessionOutcome, View};
use crate::AgentError;
use avs_concepts::{Location, RoomId};
use avs_pomdp::{
    cone_priors, euclidean_travel, SessionOptions, ViewConeAction, ViewConeProblem, ViewConeSession,
};
use avs_robot::{Detection, Pose2D, Robot, ViewCone};
use std::collections::BTreeSet;
use std::time::Instant;

/// One SEARCHFOROBJECT step of a plan.
pub(crate) struct Search<'a> {
    /// The class looked for.
    pub label: &'a str,
    /// Where.
    pub loc: ConeLoc,
    /// The object of the plan it looks for.
    pub obj: &'a ObjArg,
    /// The step's listing line.
    pub display: &'a str,
    /// The listing line of the last assumption of the plan about `obj`, if any.
    pub assumption: Option<String>,
}

/// Run the session of `search`.
pub(crate) fn dt_search<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    search: &Search,
    goal: &Goal,
) -> Result<StepEnd, AgentError> {
    let t = cx.tuning();
    let Search {
        label,
        loc,
        obj,
        display,
        ..
    } = *search;
    if !mem.cones.contains_key(&(label.to_string(), loc)) {
        let cam = body.camera();
        create_cones(cx, mem, &cam, run, label, loc);
    }
    let set = mem.cones[&(label.to_string(), loc)].clone();
    let location = match loc {
        ConeLoc::Room(r) => Location::Room(RoomId(r)),
        ConeLoc::On(k) | ConeLoc::In(k) => match (mem.objects[k].landmark, loc.relation()) {
            (Some(l), Some(relation)) => Location::Landmark(l, relation),
            _ => {
                return Ok(StepEnd::Replan(ReplanReason::NotALandmark {
                    object: names::object(k),
                }))
            }
        },
    };
    let p_map = mem.wm.concepts.p_object_at(location, label)?;
    // The plan runs this session because it assumes the object there: the session's prior
    // is the map's P(ObjectAt L), floored so that an assumed object is looked for at all.
    let p_loc = if obj.assumed {
        p_map.max(t.assumed_prior)
    } else {
        p_map
    };
    run.metrics.dt_sessions += 1;
    run.emit(Event::DtSessionStarted {
        search: display.to_string(),
        cones: set.views.len(),
        p_location: p_loc,
    });
    let mut outcome: Option<Detection> = None;
    let mut unconfirmed: Option<usize> = None;
    let mut steps = 0;
    // The cones processed, once per look.
    let mut processed: Vec<usize> = Vec::new();
    // The most confident detection of each cone, if it had one.
    let mut best: Vec<Option<Detection>> = vec![None; set.views.len()];
    if !set.views.is_empty() {
        // The prior is spread over the points the cones cover: the plan assumes the object
        // is in the location where a search finds it. Over all points, a room whose cones
        // covered 40% put 60% of the object in places no look can reach, the session
        // declared "absent" after one look, the rate was hardly thinned, and the planner
        // sent the robot to the same session again until its plan budget ran out.
        // Within them, a point already looked at `n` times in vain holds the object with
        // weight (1 − p_d)^n (Bayes over independent looks; 1 for a point never looked at).
        let (miss, false_alarm) = sensing(cx, label);
        let mut weights = vec![0.0; set.n_points];
        for &i in set.cells.iter().flatten() {
            if let Some(w) = weights.get_mut(i) {
                *w = miss.powi(mem.looks_at(label, set.points[i]) as i32);
            }
        }
        let prior = cone_priors(&set.cells, &weights, p_loc.clamp(0.0, 1.0));
        let positions: Vec<[f64; 2]> = set.views.iter().map(|v| [v.pose[0], v.pose[1]]).collect();
        let (from_start, travel) =
            euclidean_travel(body.at(), &positions, cx.config.travel_cost_per_m);
        let session = prior.and_then(|cone_prior| {
            ViewConeSession::new(
                &ViewConeProblem {
                    cone_prior,
                    travel_from_start: from_start,
                    travel,
                    process_cost: cx.config.process_cost,
                    false_negative: miss,
                    false_positive: false_alarm,
                    rewards: cx.config.session_rewards,
                    discount: cx.config.session_discount,
                },
                SessionOptions {
                    // One pass: at most as many looks as cones, plus a few second looks at
                    // detections; then the session declares by the immediate rewards and the
                    // planner decides whether the location deserves another pass.
                    max_steps: cx
                        .config
                        .session
                        .max_steps
                        .min(set.views.len() + t.session_extra_looks),
                    ..cx.config.session.clone()
                },
            )
        });
        let mut session = match session {
            Ok(s) => s,
            Err(e) => {
                run.emit(Event::DtSessionEnded {
                    outcome: SessionOutcome::Failed(e.to_string()),
                    steps: 0,
                });
                return Ok(StepEnd::Replan(ReplanReason::SessionFailed(e.to_string())));
            }
        };
        for _ in 0..t.max_dt_steps {
            let t0 = Instant::now();
            let a = session.next_action();
            run.metrics.dt_ms.push(t0.elapsed().as_secs_f64() * 1e3);
            match a {
                Ok(ViewConeAction::Process { cone }) => {
                    let v = &set.views[cone];
                    processed.push(cone);
                    if matches!(loc, ConeLoc::Room(_)) && label == goal.class {
                        run.cover(set.cells[cone].iter().map(|&k| set.points[k]));
                    }
                    let to = [v.pose[0], v.pose[1]];
                    if let Err(e) = body.with_activity(Activity::ViewCones, |b| b.go_to(mem, to))? {
                        run.observe(format!("on the way to view cone {cone}: {e}"));
                    }
                    let vc = ViewCone::new(
                        Pose2D::new(v.pose[0], v.pose[1], v.pose[2]),
                        v.pan,
                        v.tilt,
                        v.zoom,
                    );
                    let classes = [label.to_string()];
                    let mut rep =
                        body.with_activity(Activity::ViewCones, |b| b.look(&vc, &classes));
                    if rep.is_err() {
                        rep = body.with_activity(Activity::ViewCones, |b| b.look(&vc, &classes));
                    }
                    body.refresh_map(mem);
                    let det = match rep {
                        Ok(r) => r
                            .detections
                            .into_iter()
                            .filter(|d| {
                                d.class == label && d.confidence >= cx.config.min_confidence
                            })
                            .filter(|d| detection_in(cx, mem, d, loc, r.pose))
                            .max_by(|a, b| a.confidence.total_cmp(&b.confidence)),
                        Err(_) => None,
                    };
                    let detected = det.is_some();
                    if let Some(d) = det {
                        if best[cone]
                            .as_ref()
                            .is_none_or(|b| b.confidence < d.confidence)
                        {
                            best[cone] = Some(d);
                        }
                    }
                    run.emit(Event::DtAction {
                        action: format!("PROCESSVIEWCONE {cone} {}", view_text(v)),
                        detected: Some(detected),
                        view: Some(View::new([v.pose[0], v.pose[1]], v.pan, v.tilt, v.zoom)),
                        target: None,
                    });
                    run.zoomed(body.take_zoom_images());
                    steps += 1;
                    if session.observe(detected).is_err() {
                        break;
                    }
                }
                Ok(ViewConeAction::DeclareFound { cone }) => {
                    run.emit(Event::DtAction {
                        action: format!("DECLARE-FOUND cone {cone}"),
                        detected: None,
                        view: None,
                        target: None,
                    });
                    if let Some(d) = best[cone].clone() {
                        let checked = body.with_activity(Activity::Verification, |b| {
                            verify(cx, mem, b, run, label, &d)
                        });
                        match checked? {
                            Some(v) => outcome = Some(v),
                            None => unconfirmed = Some(cone),
                        }
                    }
                    break;
                }
                Ok(ViewConeAction::DeclareAbsent) => {
                    run.emit(Event::DtAction {
                        action: "DECLARE-ABSENT".into(),
                        detected: None,
                        view: None,
                        target: None,
                    });
                    break;
                }
                Err(e) => {
                    // The session cannot decide (a solver error): treated as "absent",
                    // and the trace says why.
                    run.observe(format!("the view-cone POMDP failed: {e}"));
                    break;
                }
            }
        }
        mem.sync()?;
        if steps == 0 {
            // Declared absent without looking: the DT planner's judgement stands for one
            // look through each of its cones.
            processed = (0..set.views.len()).collect();
        }
    }
    run.emit(Event::DtSessionEnded {
        outcome: match (&outcome, unconfirmed) {
            (Some(_), _) => SessionOutcome::Found,
            (None, Some(_)) => SessionOutcome::FalseAlarm,
            (None, None) => SessionOutcome::Absent,
        },
        steps,
    });
    if let (None, Some(cone)) = (&outcome, unconfirmed) {
        // A sighting a closer look did not confirm says nothing either way about the rest
        // of the location: replan without thinning its probability. The cones looked through
        // in vain before it are remembered as looked at (the next search of the location
        // weighs their points by their misses); a cone that detected something is not
        // counted as a miss. Before, none of the session's looks were remembered, and the
        // next session weighed a cone with an unconfirmed hit like any other (issue 17
        // session "earlier looks at a spot": success summed over five 200-floor benches
        // 4.870 → 4.895).
        let missed: Vec<usize> = processed
            .iter()
            .copied()
            .filter(|&c| best[c].is_none())
            .collect();
        record_looks(cx, mem, label, loc, location, &set, &missed);
        return Ok(StepEnd::Replan(ReplanReason::NotConfirmed {
            class: label.to_string(),
            cone,
        }));
    }
    match outcome {
        Some(d) => {
            let place = mem
                .object_place([d.pose.x, d.pose.y])
                .or_else(|| mem.current_place());
            let Some(place) = place else {
                return Ok(StepEnd::Replan(ReplanReason::OnNoPlace));
            };
            let k = mem.objects.len();
            let landmark = if cx.knowledge.class(label).is_some_and(|c| c.landmark) {
                Some(mem.wm.found_landmark(place, label)?)
            } else {
                None
            };
            let on = match loc {
                ConeLoc::On(j) => Some(j),
                ConeLoc::Room(_) | ConeLoc::In(_) => None,
            };
            mem.objects.push(Known {
                class: label.to_string(),
                pos: d.pose,
                place,
                landmark,
                on,
                counted: false,
                confidence: d.confidence,
            });
            let name = names::object(k);
            if let Some(a) = &search.assumption {
                run.emit(Event::AssumptionConfirmed {
                    assumption: a.clone(),
                    evidence: format!(
                        "{} is {name}, a {label} seen with confidence {:.2}",
                        obj.name, d.confidence
                    ),
                });
            }
            if label == goal.class {
                return Ok(StepEnd::Found(FoundObject {
                    name,
                    class: label.into(),
                    pose: d.pose,
                    confidence: d.confidence,
                }));
            }
            Ok(StepEnd::Replan(if obj.assumed {
                ReplanReason::Matched {
                    virtual_object: obj.name.clone(),
                    class: label.to_string(),
                    object: name,
                }
            } else {
                ReplanReason::FoundObject {
                    class: label.to_string(),
                    object: name,
                }
            }))
        }
        None => {
            // The place map may have re-drawn the rooms while the robot moved between the
            // cones (a door found or lost): the searched room is then the room that holds
            // most of the searched points now.
            let location = match location {
                Location::Room(r) if !mem.wm.rooms().any(|(id, _)| id == r) => {
                    match mem.majority_room(&set.points) {
                        Some(now) => Location::Room(now),
                        None => location,
                    }
                }
                l => l,
            };
            let q = record_looks(cx, mem, label, loc, location, &set, &processed);
            // The next search here plans its cones afresh, for what these did not see.
            mem.cones.remove(&(label.to_string(), loc));
            if q > 0.0 {
                mem.wm.concepts.mark_searched(location, label, q)?;
            } else if let Location::Room(RoomId(r)) = location {
                // Nothing was looked at, so nothing was learnt: a monitored failure. The same
                // search would do the same until the room's known map grows; its cones are
                // dropped so that a later search plans them on the grown map.
                mem.cones.remove(&(label.to_string(), loc));
                mem.stalled
                    .insert((label.to_string(), r), mem.room_known_cells(r));
                return Ok(StepEnd::Replan(ReplanReason::NoProgress {
                    class: label.to_string(),
                    search: display.to_string(),
                    cones: set.views.len(),
                }));
            }
            if let Some(k) = loc.landmark() {
                mem.exhausted.insert((k, label.to_string()));
            }
            let p_now = mem.wm.concepts.p_object_at(location, label).unwrap_or(0.0);
            let why = ReplanReason::SearchedInVain {
                class: label.to_string(),
                search: display.to_string(),
                before: p_map,
                after: p_now,
            };
            if let Some(a) = &search.assumption {
                run.emit(Event::AssumptionViolated {
                    assumption: a.clone(),
                    reason: why.to_string(),
                });
            }
            Ok(StepEnd::Replan(why))
        }
    }
}

/// A look's miss and false-alarm rates for `label`: measured
/// ([`crate::AgentConfig::measured_sensing`]) when the configuration has them, the knowledge's
/// `sensor` otherwise.
pub(crate) fn sensing(cx: Ctx, label: &str) -> (f64, f64) {
    cx.config.sensing(label).map_or(
        (
            cx.knowledge.sensor.false_negative,
            cx.knowledge.sensor.false_positive,
        ),
        |m| (m.false_negative, m.false_positive),
    )
}

/// Record one look at every point of the processed cones (`processed`; a point once per
/// session however many of them held it) in [`Memory::looks`], and return the share `q` of
/// the location's rate the looks removed: with every point of the location weighted
/// `(1 − p_d)^looks` (a point's chance to hold the object after that many misses, the rate
/// being spread evenly over the points before any look), `q = 1 − Σ w_after / Σ w_before`
/// over the location's points now. For a first
/// search this is `p_d` × the share of the points looked at, the thinning of eq. 1 by the
/// looked-at cells (`002` §III-A); a second session's look at the same points removes less,
/// as it should, since they were likely empty already.
pub(crate) fn record_looks(
    cx: Ctx,
    mem: &mut Memory,
    label: &str,
    loc: ConeLoc,
    location: Location,
    set: &ConeSet,
    processed: &[usize],
) -> f64 {
    let (miss, _) = sensing(cx, label);
    let Some(class) = cx.knowledge.class(label) else {
        return 0.0;
    };
    let points = match (loc, location) {
        (ConeLoc::Room(_), Location::Room(RoomId(r))) => {
            location_points(cx, mem, class, ConeLoc::Room(r))
        }
        _ => location_points(cx, mem, class, loc),
    };
    let weight = |mem: &Memory| -> f64 {
        points
            .iter()
            .map(|&p| miss.powi(mem.looks_at(label, p) as i32))
            .sum()
    };
    let before = weight(mem);
    // One look per point per session: overlapping cones, and the same cone processed again,
    // look from nearly the same place, and a detector's misses from one vantage are not
    // independent (Velez et al., `000`), so they count once.
    let keys: BTreeSet<PointKey> = processed
        .iter()
        .flat_map(|&c| set.cells.get(c).into_iter().flatten())
        .filter_map(|&i| set.points.get(i))
        .map(|&p| mem.point_key(p))
        .collect();
    let looks = mem.looks.entry(label.to_string()).or_default();
    for k in keys {
        *looks.entry(k).or_default() += 1;
    }
    let after = weight(mem);
    if before > 0.0 {
        (1.0 - after / before).clamp(0.0, 0.99)
    } else {
        0.0
    }
}

/// Whether a detection lies in the searched location (and is not of an object the agent
/// already knows).
fn detection_in(cx: Ctx, mem: &Memory, d: &Detection, loc: ConeLoc, from: Pose2D) -> bool {
    let known = !mem.is_new_sighting(d);
    match loc {
        ConeLoc::On(k) | ConeLoc::In(k) => {
            let o = &mem.objects[k];
            let half = cx
                .knowledge
                .class(&o.class)
                .map_or(0.6, |c| 0.5 * c.size[0].max(c.size[1]));
            !known && o.pos.planar_distance(d.pose.x, d.pose.y) <= half + cx.tuning().on_slack
        }
        ConeLoc::Room(r) => {
            let here = [from.x, from.y];
            !known
                && mem.same_room(here, [d.pose.x, d.pose.y])
                && mem.room_at(here) == Some(RoomId(r))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::skills::testing::{self, object};
    use crate::AgentConfig;

    fn search_room(placed: bool) -> (StepEnd, Memory, String) {
        search_room_with(|robot| {
            if placed {
                // On a table's top (the search height of a cereal box), in the far half.
                robot.place(object("cerealbox", 3.6, 2.8, 0.965));
            }
        })
    }

    /// A search for a cereal box in a 5 × 4 m room, the robot set up by `prepare`.
    fn search_room_with(
        prepare: impl FnOnce(&mut avs_robot::ScriptedRobot),
    ) -> (StepEnd, Memory, String) {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
        prepare(&mut robot);
        let mut mem = testing::memory(&config, &k, &mut robot);
        let room = mem.current_room().expect("a room");
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        let obj = ObjArg {
            name: "new-object1".into(),
            assumed: true,
        };
        let display = format!(
            "SEARCHFOROBJECT cerealbox IN {} new-object1",
            names::room(room)
        );
        let search = Search {
            label: "cerealbox",
            loc: ConeLoc::Room(room.0),
            obj: &obj,
            display: &display,
            assumption: Some("ASSUME-OBJECT-EXISTS cerealbox IN room0 kitchen".into()),
        };
        let end = dt_search(
            cx,
            &mut mem,
            &mut Body::new(&mut robot),
            &mut run,
            &search,
            &Goal::find("cerealbox"),
        )
        .unwrap();
        let text = testing::text(&run);
        (end, mem, text)
    }

    /// A search for a cereal box in the room the robot stands in, over `mem`.
    fn search_again(
        config: &AgentConfig,
        k: &avs_format::knowledge::Knowledge,
        robot: &mut avs_robot::ScriptedRobot,
        mem: &mut Memory,
    ) -> StepEnd {
        let room = mem.current_room().expect("a room");
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = Ctx {
            knowledge: k,
            config,
        };
        let obj = ObjArg {
            name: "new-object1".into(),
            assumed: true,
        };
        let display = format!("SEARCHFOROBJECT cerealbox IN {}", names::room(room));
        let search = Search {
            label: "cerealbox",
            loc: ConeLoc::Room(room.0),
            obj: &obj,
            display: &display,
            assumption: None,
        };
        dt_search(
            cx,
            mem,
            &mut Body::new(robot),
            &mut run,
            &search,
            &Goal::find("cerealbox"),
        )
        .unwrap()
    }

    #[test]
    fn a_second_search_of_a_large_room_looks_where_the_first_did_not() {
        let k = testing::knowledge();
        // Two cones per search: the first cannot cover a 14 m room.
        let config = AgentConfig {
            max_cones: 2,
            ..AgentConfig::default()
        };
        let mut robot = testing::robot(testing::room(14.0, 3.0), [1.0, 1.5]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        let looked = |mem: &Memory| mem.looks.get("cerealbox").map_or(0, |l| l.len());
        let end = search_again(&config, &k, &mut robot, &mut mem);
        assert!(matches!(
            end,
            StepEnd::Replan(ReplanReason::SearchedInVain { .. })
        ));
        let first = looked(&mem);
        assert!(first > 0, "the first search looked at nothing");
        // The cones of a search in vain are dropped; the next are planned for the rest.
        assert!(mem.cones.is_empty());
        let room = mem.current_room().unwrap();
        let cx = testing::ctx(&k, &config);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        create_cones(
            cx,
            &mut mem,
            &robot.camera(),
            &mut run,
            "cerealbox",
            ConeLoc::Room(room.0),
        );
        let set = &mem.cones[&("cerealbox".to_string(), ConeLoc::Room(room.0))];
        assert!(!set.views.is_empty());
        assert!(
            set.points
                .iter()
                .all(|&p| mem.looks_at("cerealbox", p) == 0),
            "the second cones are planned for points already looked at"
        );
        assert!(testing::text(&run).contains("not looked at yet"));
        let StepEnd::Replan(ReplanReason::SearchedInVain { before, after, .. }) =
            search_again(&config, &k, &mut robot, &mut mem)
        else {
            panic!("the second search did not end in vain");
        };
        assert!(
            looked(&mem) > first,
            "the second search looked at nothing new"
        );
        assert!(after < before);
    }

    #[test]
    fn looking_again_at_the_same_points_thins_less_than_the_first_look() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 1.0]);
        let mut mem = testing::memory(&config, &k, &mut robot);
        let room = mem.current_room().unwrap();
        let loc = ConeLoc::Room(room.0);
        let cx = testing::ctx(&k, &config);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        create_cones(cx, &mut mem, &robot.camera(), &mut run, "cerealbox", loc);
        let set = mem.cones[&("cerealbox".to_string(), loc)].clone();
        let all: Vec<usize> = (0..set.views.len()).collect();
        let location = Location::Room(room);
        let q1 = record_looks(cx, &mut mem, "cerealbox", loc, location, &set, &all);
        // A first session thins by p_d times the share of the points it looked at (eq. 1
        // thinned by the looked-at cells), each point once however many cones held it.
        let p_d = 1.0 - k.sensor.false_negative;
        let n = location_points(cx, &mem, k.class("cerealbox").unwrap(), loc).len();
        let seen: BTreeSet<usize> = set.cells.iter().flatten().copied().collect();
        assert!(
            (q1 - p_d * seen.len() as f64 / n as f64).abs() < 1e-9,
            "{q1}: {} of {n} points",
            seen.len()
        );
        let q2 = record_looks(cx, &mut mem, "cerealbox", loc, location, &set, &all);
        assert!(q2 > 0.0 && q2 < q1, "{q1} then {q2}");
    }

    #[test]
    fn a_session_over_a_room_with_the_object_finds_and_verifies_it() {
        let (end, mem, text) = search_room(true);
        let StepEnd::Found(f) = end else {
            panic!("not found:\n{text}");
        };
        assert!(f.pose.planar_distance(3.6, 2.8) < 1e-9);
        assert_eq!(f.name, "object0");
        assert_eq!(mem.objects.len(), 1);
        assert!(text.contains("DT session ended: found"), "{text}");
        assert!(text.contains("+ assumption confirmed"), "{text}");
        assert!(text.contains("VERIFY cerealbox"), "{text}");
    }

    #[test]
    fn a_session_in_vain_thins_the_rooms_probability_and_says_by_how_much() {
        let (end, _, text) = search_room(false);
        let StepEnd::Replan(ReplanReason::SearchedInVain { before, after, .. }) = end else {
            panic!("not searched in vain:\n{text}");
        };
        assert!(after < before, "{before} -> {after}");
        assert!(text.contains("DT session ended: absent"), "{text}");
        assert!(text.contains("! assumption violated"), "{text}");
    }

    /// A session that ends on a sighting its verification rejects still looked through the
    /// cones before it in vain: those looks are remembered (the next search weighs those points
    /// less), the rejected sighting's cone is not counted as a miss, and the room's
    /// probability is not thinned.
    #[test]
    fn a_session_ended_by_a_rejected_sighting_remembers_the_looks_made_in_vain() {
        let (end, mem, text) = search_room_with(|robot| {
            for _ in 0..2 {
                robot.script_view(avs_robot::ActionResult::Ok(vec![]));
            }
            for _ in 0..2 {
                robot.script_view(avs_robot::ActionResult::Ok(vec![object(
                    "cerealbox",
                    3.6,
                    2.8,
                    0.965,
                )]));
            }
        });
        let StepEnd::Replan(ReplanReason::NotConfirmed { cone, .. }) = end else {
            panic!("not ended by a rejected sighting:\n{text}");
        };
        // The cones processed, from the trace, and the session's cone set (kept for the
        // next search of the room).
        let processed: BTreeSet<usize> = text
            .lines()
            .filter_map(|l| l.trim().strip_prefix("PROCESSVIEWCONE "))
            .filter_map(|l| l.split_whitespace().next()?.parse().ok())
            .collect();
        let room = mem.current_room().expect("a room");
        let set = &mem.cones[&("cerealbox".to_string(), ConeLoc::Room(room.0))];
        let points_of = |c: usize| set.cells[c].iter().map(|&i| set.points[i]);
        let missed: Vec<usize> = processed.iter().copied().filter(|&c| c != cone).collect();
        assert!(
            !missed.is_empty(),
            "a cone looked through in vain first:\n{text}"
        );
        // Every point of the cones looked through in vain holds one look ...
        for &c in &missed {
            assert!(
                points_of(c).all(|p| mem.looks_at("cerealbox", p) == 1),
                "cone {c}"
            );
        }
        // ... and the points only the detecting cone saw hold none.
        let only_hit: Vec<[f64; 3]> = points_of(cone)
            .filter(|p| !missed.iter().any(|&c| points_of(c).any(|q| q == *p)))
            .collect();
        assert!(
            !only_hit.is_empty(),
            "cone {cone} saw points of its own:\n{text}"
        );
        assert!(only_hit.iter().all(|&p| mem.looks_at("cerealbox", p) == 0));
        // The room's probability was not thinned.
        assert!(!text.contains("! assumption violated"), "{text}");
    }
}
