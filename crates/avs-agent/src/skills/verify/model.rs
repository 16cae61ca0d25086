//! The model verifiers: Velez et al.'s planned verifier (REPLANONNEWDETECTION, Fig. 7),
//! GREEDY(τ) and RTBSS (`avs-verify`), driving the robot to the vantage points they choose and
//! reading the detector's score at the candidate from each ([`Robot::detector_scores`]).
//!
//! One candidate at a time: the agent hands over each sighting as it ends a session or a
//! coverage look, and the search goes on (or ends) with the decision.
//!
//! # Choices where the paper is vague
//!
//! * **The model at the class's scale.** The class's `verifier.model` is scaled so that its
//!   `max_range` becomes the class's `detection_range[1]`
//!   ([`SensorModelSpec::scaled`](avs_format::verifier::SensorModelSpec::scaled)).
//!   `planned-disc` uses the disc model with `d_max` = 0.3 × that range (the paper's 3 m of a
//!   10 m door detector); RTBSS's vantage cells are 0.25 × that range (the paper's 2.5 m).
//! * **The first score comes from the image that fired**: one more image from where the robot
//!   stands, so that the sighting's own evidence enters the belief as the candidate's first
//!   look (the prior is the map's, without it).
//! * **The route goal** of the planned verifier's detour cost (eq. 1) is where the robot stood
//!   when it saw the candidate: the search resumes from there.
//! * **The price of a decision.** Velez et al. price a wrong decision at 16 m of travel (and
//!   a right one at −16 m) for their door-finding task. In a search, a wrong acceptance is a
//!   wrong report and a wrong rejection loses the target: either way the search gets a DT
//!   session's wrong declaration instead of its found reward. The agent prices that swing
//!   with the view-cone POMDP's own exchange rate between rewards and travel: a wrong
//!   decision costs `½ (found − wrong) / travel_cost_per_m` metres and a right one minus that
//!   (150 m by default, a swing of 300 m). On 20 generated floors a price of 100 m left real
//!   targets in rooms the map thought unlikely rejected after one look (success 0.65), 200 m
//!   0.75, 1000 m 0.85 at more path per search.
//! * **The zoom of the looks.** A zoomed image magnifies (Sjöö et al., `004` eq. 1): a robot
//!   `d` m away sees the candidate as from `d / zoom` ([`Candidate::with_zoom`]). The agent
//!   zooms so that the closest a robot looks from ([`avs_verify::field::MIN_RANGE`], 0.75 m)
//!   shows the candidate as from the shortest range the scaled model was trained at, within
//!   the camera's zoom: a class whose detector works only close up (a marker, up to 1.5 m:
//!   zoom 4) is then looked at from where the robot can stand, over the whole range its model
//!   knows; a cereal box (4 m) gets zoom 1.5. The camera is centred on the candidate. On 20
//!   and 60 generated floors this rule found the target as often as zoom 1 or 2 (0.75 and
//!   0.77 against 0.70–0.80; the differences are within a few floors); zoom 4 for every class
//!   did worse (0.60 on the 20).
//! * **Unreachable or blind vantage points.** A waypoint the robot cannot reach, or from which
//!   the detector returns no score (an occlusion the map does not show, a camera fault), gives
//!   no evidence and is not offered again ([`Candidate::unseen_from`]). The loop is bounded by
//!   the verifier's look limit plus as many failures, so a candidate on an impossible spot
//!   (inside furniture, behind a closed door) ends with the belief it has and a reason.
//! * **Sight lines** are the agent's own (`avs_view::sight_clear`: an object on a table top is
//!   seen over the table's edge, one beside furniture up to the footprint's slack), not the
//!   bare grid's: the laser map holds furniture footprints as occupied, and a bare grid line
//!   to an object on a table never arrives.
//! * **Legs longer than four times the farthest a look reaches** (the class's detection range
//!   times the zoom), beyond the way back to where the robot saw the candidate, count as
//!   unreachable for the planners (bounded path searches on a large map).

use super::{CandidateRef, Verdict};
use crate::body::Body;
use crate::memory::Memory;
use crate::run::Run;
use crate::skills::Ctx;
use crate::trace::{Event, View};
use crate::AgentError;
use avs_format::verifier::{ModelKind, VerifierSpec, VerifierStrategy, DEFAULT_GREEDY_THRESHOLD};
use avs_robot::{FailureReason, Robot, ViewCone};
use avs_verify::pbd::DecisionCosts;
use avs_verify::planner::greedy::GreedyConfig;
use avs_verify::planner::planned::PlannedConfig;
use avs_verify::planner::rtbss::RtbssConfig;
use avs_verify::planner::{Candidate, GridTerrain, Step, Terrain, Verifier};
use avs_verify::sensor::SensorModel;
use avs_view::{sight_clear, SightLine};
use rand::SeedableRng;

/// `planned-disc`'s disc radius as a share of the class's detection range.
const DISC_SHARE: f64 = 0.3;
/// RTBSS's vantage cell as a share of the class's detection range.
const RTBSS_CELL_SHARE: f64 = 0.25;
/// Planner legs longer than this many reaches of a look (detection range × zoom) count as
/// unreachable.
const LEG_RANGES: f64 = 4.0;

/// How a model verifier ended.
pub(super) enum Outcome {
    /// It decided.
    Decided(Verdict),
    /// The robot's detector gives no scores (the reason): nothing was decided.
    NoScores(String),
}

/// A class's model verifier, ready to plan.
#[derive(Debug)]
pub(crate) struct Built {
    /// The sensor model, scaled to the class.
    pub model: SensorModel,
    /// The verification planner with its settings.
    pub verifier: Verifier,
    /// The shortest vantage range (metres) of the scaled model's training points.
    pub min_trained: f64,
}

/// The class's sensor model and verifier, ready to plan (the model scaled to the class).
/// `fov` is the camera's horizontal field of view, radians; `costs` the price of decisions.
pub(crate) fn build(
    knowledge: &avs_format::knowledge::Knowledge,
    label: &str,
    spec: &VerifierSpec,
    fov: f64,
    costs: DecisionCosts,
) -> Result<Built, AgentError> {
    let bad = |message: String| AgentError::Verifier {
        class: label.to_string(),
        message,
    };
    let name = spec.model.as_deref().ok_or_else(|| {
        bad(format!(
            "the `{}` verifier needs a model",
            spec.strategy.name()
        ))
    })?;
    let (mut scaled, range) = scaled_spec(knowledge, label, name)?;
    let verifier = match spec.strategy {
        VerifierStrategy::Count | VerifierStrategy::Sequential => {
            return Err(bad(format!(
                "the `{}` verifier uses no sensor model",
                spec.strategy.name()
            )));
        }
        VerifierStrategy::Planned => Verifier::Planned(PlannedConfig {
            fov,
            costs,
            ..PlannedConfig::default()
        }),
        VerifierStrategy::PlannedDisc => {
            scaled.kind = ModelKind::Disc {
                d_max: DISC_SHARE * range,
            };
            Verifier::Planned(PlannedConfig {
                fov,
                costs,
                ..PlannedConfig::default()
            })
        }
        VerifierStrategy::Greedy => Verifier::Greedy(GreedyConfig {
            threshold: spec.threshold.unwrap_or(DEFAULT_GREEDY_THRESHOLD),
            ..GreedyConfig::default()
        }),
        VerifierStrategy::Rtbss => Verifier::Rtbss(RtbssConfig {
            cell: RTBSS_CELL_SHARE * range,
            costs,
            ..RtbssConfig::default()
        }),
    };
    let (model, min_trained) = from_scaled(label, &scaled)?;
    Ok(Built {
        model,
        verifier,
        min_trained,
    })
}

/// The knowledge's sensor model `name` scaled to class `label` (module docs, "The model at
/// the class's scale"), with the class's detection range, metres.
fn scaled_spec(
    knowledge: &avs_format::knowledge::Knowledge,
    label: &str,
    name: &str,
) -> Result<(avs_format::verifier::SensorModelSpec, f64), AgentError> {
    let bad = |message: String| AgentError::Verifier {
        class: label.to_string(),
        message,
    };
    let class = knowledge
        .class(label)
        .ok_or_else(|| bad("the class is not in the knowledge file".into()))?;
    let trained = knowledge
        .sensor_model(name)
        .ok_or_else(|| bad(format!("no sensor model named `{name}`")))?;
    let range = class.detection_range[1];
    if !(range.is_finite() && range > 0.0) {
        return Err(bad(format!(
            "detection_range[1] = {range}: expected a positive range"
        )));
    }
    Ok((trained.scaled(range / trained.max_range), range))
}

/// The sensor model of a scaled spec, with the shortest vantage range of its training points.
fn from_scaled(
    label: &str,
    scaled: &avs_format::verifier::SensorModelSpec,
) -> Result<(SensorModel, f64), AgentError> {
    let model = SensorModel::from_spec(scaled).map_err(|e| AgentError::Verifier {
        class: label.to_string(),
        message: e.to_string(),
    })?;
    let min_trained = scaled
        .object
        .points
        .iter()
        .chain(&scaled.no_object.points)
        .map(|p| p[0])
        .fold(scaled.max_range, f64::min);
    Ok((model, min_trained))
}

/// The knowledge's sensor model `name` for class `label`, at the class's scale: what the
/// `sequential` verifier weighs scores with when its block names a model.
pub(crate) fn score_model(
    knowledge: &avs_format::knowledge::Knowledge,
    label: &str,
    name: &str,
) -> Result<SensorModel, AgentError> {
    let (scaled, _) = scaled_spec(knowledge, label, name)?;
    Ok(from_scaled(label, &scaled)?.0)
}

/// The planners' terrain in the agent: paths on the known map ([`GridTerrain`]) and the
/// agent's own sight lines, which see an object standing on or beside furniture (whose
/// footprint the laser map holds as occupied) as the other looks of the agent do.
struct Sighted<'a> {
    grid: GridTerrain<'a>,
    line: SightLine<'a>,
    /// The candidate's height, metres.
    z: f64,
}

impl Terrain for Sighted<'_> {
    fn can_view(&self, at: [f64; 2], target: [f64; 2]) -> bool {
        self.grid.stands(at) && sight_clear(&self.line, at, [target[0], target[1], self.z])
    }

    fn distance(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        self.grid.distance(a, b)
    }
}

/// The price of verification decisions, metres (module docs), kept within [1, 10⁶] m (free
/// travel, `travel_cost_per_m` = 0, makes a decision worth any number of looks: the
/// verifier's look limit then ends them).
pub(crate) fn decision_costs(config: &crate::AgentConfig) -> DecisionCosts {
    let r = config.session_rewards;
    let wrong = (0.5 * (r.found - r.wrong) / config.travel_cost_per_m).clamp(1.0, 1e6);
    let wrong = if wrong.is_nan() { 1e6 } else { wrong };
    DecisionCosts {
        wrong,
        right: -wrong,
    }
}

/// Verify candidate `c` (its sighting, class and prior) with the model verifier of `spec`;
/// `seed` seeds the planned verifier's sampling.
pub(super) fn verify_by_model<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    c: &CandidateRef,
    spec: &VerifierSpec,
    seed: u64,
) -> Result<Outcome, AgentError> {
    let (label, d, prior) = (c.label, c.sighting, c.prior);
    let cam = body.camera();
    let built = match mem.verifiers.get(label) {
        Some(b) => b.clone(),
        None => {
            let b = std::sync::Arc::new(build(
                cx.knowledge,
                label,
                spec,
                cam.hfov,
                decision_costs(cx.config),
            )?);
            mem.verifiers.insert(label.to_string(), b.clone());
            b
        }
    };
    let Built {
        model,
        verifier,
        min_trained,
    } = &*built;
    let min_trained = *min_trained;
    let target = [d.pose.x, d.pose.y];
    let home = body.at();
    let t = cx.tuning();
    let surfaces = mem.surfaces(cx.knowledge);
    let slack = mem.footprint_slack(cx.knowledge, label).min(t.los_slack);
    let zoom = (avs_verify::field::MIN_RANGE / min_trained).clamp(1.0, cam.max_zoom.max(1.0));
    let mut cand = Candidate::new(target, None, model, prior).with_zoom(zoom);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut looks = 0;
    let mut failures = 0;
    let budget = verifier.max_looks();
    // One look from where the robot stands, then as the verifier says.
    let mut next: Option<[f64; 2]> = Some(home);
    loop {
        if let Some(waypoint) = next.take() {
            if body.at() != waypoint {
                if let Err(e) = body.go_to(mem, waypoint)? {
                    run.observe(format!("on the way to look at the {label} again: {e}"));
                    cand.unseen_from(waypoint);
                    failures += 1;
                }
            }
            let pose = body.pose();
            let (pan, tilt) = cam.aim(pose, d.pose);
            let cone = ViewCone::new(pose, pan, tilt, zoom);
            let read = body.scores(&cone, label, std::slice::from_ref(&d.pose));
            let score = match read {
                Err(e) if e.reason == FailureReason::Unsupported => {
                    return Ok(Outcome::NoScores(e.message));
                }
                Err(e) => {
                    run.observe(format!("a look at the {label} failed: {e}"));
                    None
                }
                Ok(r) => {
                    run.metrics.verification_detector_s += r.detector_seconds;
                    r.scores.first().copied().flatten()
                }
            };
            let at = [pose.x, pose.y];
            match score {
                Some(z) => {
                    looks += 1;
                    cand.observe(at, z).map_err(|e| AgentError::Verifier {
                        class: label.to_string(),
                        message: e.to_string(),
                    })?;
                }
                None => {
                    failures += 1;
                    cand.unseen_from(at);
                }
            }
            run.emit(Event::DtAction {
                action: match score {
                    Some(z) => format!(
                        "VERIFY {label} at ({:.2}, {:.2}) from ({:.2}, {:.2}): score {z:.2}, belief {:.3}",
                        target[0], target[1], pose.x, pose.y, cand.belief
                    ),
                    None => format!(
                        "VERIFY {label} at ({:.2}, {:.2}) from ({:.2}, {:.2}): not seen",
                        target[0], target[1], pose.x, pose.y
                    ),
                },
                detected: None,
                view: Some(View::new([pose.x, pose.y], pan, tilt, zoom)),
                target: Some(target),
            });
        }
        if looks >= budget || failures > budget {
            break;
        }
        let here = body.at();
        let max_path = LEG_RANGES * model.max_range * zoom + avs_map::places::dist(here, home);
        let step = mem.with_trav(false, |trav| {
            let terrain = Sighted {
                grid: GridTerrain::new(&mem.grid, trav, false, max_path),
                line: SightLine {
                    grid: &mem.grid,
                    surfaces: &surfaces,
                    slack,
                    z_tolerance: t.surface_z_tolerance,
                    unknown_blocks: false,
                },
                z: d.pose.z,
            };
            verifier.next_step(std::slice::from_ref(&cand), here, home, &terrain, &mut rng)
        });
        match step.map_err(|e| AgentError::Verifier {
            class: label.to_string(),
            message: e.to_string(),
        })? {
            Step::Look { waypoint, .. } => next = Some(waypoint),
            Step::Decide | Step::Settle { .. } => break,
        }
    }
    body.refresh_map(mem);
    let belief = cand.belief;
    let accepted = belief > 0.5;
    let reason = if looks == 0 {
        format!("no look saw it ({failures} failed); decided on the prior")
    } else {
        format!(
            "belief {belief:.3} after {looks} look{}",
            if looks == 1 { "" } else { "s" }
        )
    };
    Ok(Outcome::Decided(Verdict {
        confirmed: accepted.then(|| d.clone()),
        belief: Some(belief),
        looks,
        reason,
        reach: None,
    }))
}

#[cfg(test)]
mod tests {
    use crate::skills::testing::{self, object, Verified as Outcome};
    use crate::trace::Event;
    use avs_format::verifier::VerifierStrategy;
    use avs_robot::ScriptedRobot;

    /// A cerealbox sighting verified by `strategy` with the hand-written model.
    fn verify_with(
        strategy: VerifierStrategy,
        prepare: impl FnOnce(&mut ScriptedRobot),
    ) -> Outcome {
        let k = testing::knowledge_verified_by("cerealbox", strategy);
        testing::verify_cerealbox(&k, prepare)
    }

    fn decision(o: &Outcome) -> (bool, Option<f64>, usize, String) {
        o.events
            .iter()
            .find_map(|e| match e {
                Event::VerificationDecision {
                    accepted,
                    belief,
                    looks,
                    reason,
                    ..
                } => Some((*accepted, *belief, *looks, reason.clone())),
                _ => None,
            })
            .expect("a verification decision in the trace")
    }

    fn place_box(r: &mut ScriptedRobot) {
        r.place(object("cerealbox", 4.5, 2.0, 0.14));
    }

    #[test]
    fn a_real_object_is_accepted_by_each_model_verifier_with_its_belief_in_the_trace() {
        for s in [
            VerifierStrategy::Planned,
            VerifierStrategy::PlannedDisc,
            VerifierStrategy::Greedy,
            VerifierStrategy::Rtbss,
        ] {
            let o = verify_with(s, place_box);
            assert!(
                o.confirmed.is_some(),
                "{s:?}: {}",
                crate::trace::render_text(&o.events)
            );
            let created = o.events.iter().position(|e| {
                matches!(e, Event::CandidateCreated { verifier, prior, .. }
                    if verifier == s.name() && *prior > 0.0 && *prior < 1.0)
            });
            let decided = o
                .events
                .iter()
                .position(|e| matches!(e, Event::VerificationDecision { .. }));
            assert!(created.is_some() && created < decided, "{s:?}");
            let (accepted, belief, looks, _) = decision(&o);
            assert!(accepted && belief.unwrap() > 0.5 && looks >= 1, "{s:?}");
            assert_eq!(
                (
                    o.metrics.candidates,
                    o.metrics.candidates_accepted,
                    o.metrics.candidates_rejected
                ),
                (1, 1, 0)
            );
            assert_eq!(o.metrics.verification_looks, looks);
            // The scripted detector takes no time per image.
            assert_eq!(o.metrics.verification_detector_s, 0.0);
            assert!(o.rejected.is_empty());
        }
    }

    #[test]
    fn a_look_alike_is_rejected_and_remembered() {
        // Nothing there: the scripted detector scores 0 at the candidate, below a look-alike's.
        let o = verify_with(VerifierStrategy::Planned, |_| {});
        assert!(o.confirmed.is_none());
        let (accepted, belief, looks, _) = decision(&o);
        assert!(!accepted && belief.unwrap() < 0.5 && looks >= 1);
        assert_eq!(o.rejected, vec![("cerealbox".to_string(), [4.5, 2.0])]);
        assert_eq!(o.metrics.candidates_rejected, 1);
    }

    #[test]
    fn a_robot_whose_detector_gives_no_scores_is_verified_by_its_detections() {
        let o = verify_with(VerifierStrategy::Planned, |r| {
            place_box(r);
            *r = r.clone().without_scores();
        });
        assert!(o.confirmed.is_some());
        assert!(
            o.events.iter().any(|e| matches!(e,
            Event::Observed { what } if what.contains("verified by its closer looks' detections")))
        );
        // Decided by the sequential rule over detections: its belief, past the price of a
        // wrong report.
        let (accepted, belief, _, reason) = decision(&o);
        assert!(accepted && belief.unwrap() > 0.99, "{reason}");
    }

    #[test]
    fn a_candidate_no_look_can_see_is_decided_on_its_prior_with_a_reason() {
        // Every look returns no score (as for a candidate inside furniture): the loop ends
        // within the verifier's budget, never hangs, and says why.
        let o = verify_with(VerifierStrategy::Planned, |r| {
            for _ in 0..100 {
                r.script_scores(Ok(vec![None]));
            }
        });
        let (accepted, _, looks, reason) = decision(&o);
        assert_eq!(looks, 0);
        assert!(!accepted, "the office prior of a cerealbox is below ½");
        assert!(reason.contains("no look saw it"), "{reason}");
        assert!(o.confirmed.is_none());
    }
}
