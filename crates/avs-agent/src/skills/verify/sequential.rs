//! The `sequential` verifier: closer looks at a sighting until the Bayes-optimal policy of a
//! binary detector decides (`avs_verify::sequential`).
//!
//! * **The detector.** A look detects the class within `confirm_radius` of the sighting or
//!   not, independently given the truth, with `P(hit | object) = 1 − FN` and
//!   `P(hit | none) = FP`: the knowledge's `sensor` (the view-cone POMDP's observation model,
//!   `002` §IV), or the measured rates of the class when the configuration has them
//!   ([`crate::AgentConfig::measured_sensing`]). Each rate is kept inside [`RATE_FLOOR`,
//!   1 − `RATE_FLOOR`], the floor the zoom pipeline's calibration also keeps: a rate of exactly
//!   0 would make one hit proof. (With the zoom pipeline's measured rates, no false alarm in 20
//!   looks per class, two hits then decide from a 1 % prior.)
//! * **Measured looks, where they are taken.** With the zoom pipeline's measurements kept
//!   ([`crate::MeasuredSensing::found_by_zoom`]), `P(hit | object)` of a look is the share of
//!   the calibration's looks that found the class at that look's zoom and distance
//!   ([`crate::MeasuredSensing::found_share`]), not the mean over the range: a floor marker
//!   seen from 1.7 m through zoom 4 (as near as the camera's tilt lets it look) is found about
//!   half the time, and two misses there had sunk real markers from a prior of 0.1 to 0.002
//!   at the mean's 0.87. And a look repeated from one vantage point (the same standpoint and
//!   zoom) is not a new draw: whether the pipeline finds an object depends on the side and
//!   the distance it is seen from, which a repeat shares. The calibration measures how much
//!   (`avs_eval::zoom_sensing`, "Repeated looks": the correlation ρ of a look's and its
//!   repeat's outcomes; 0.30 for the marker, whose end shows from some sides, 0.00 for the
//!   mug), and the vantage point's own chance is read as Beta-distributed around the share
//!   with that correlation: the next look from there finds the object with the posterior
//!   mean ([`crate::MeasuredSensing::found_next`]), which falls with every miss from there.
//!   The next look is priced at that chance; when a look from the nearest standpoint not yet
//!   looked from (a new draw at the share measured there) lowers the expected cost of
//!   deciding by more than the walk, the robot walks there first ([`fresh_stand`]; each
//!   standpoint once). Velez et al.'s point, for the pipeline: a second look from where the
//!   robot stands is worth less than the first.
//! * **What counts as a hit**: a detection of the class within `confirm_radius` of the
//!   sighting whose estimated distance lies in the class's recognition range (scaled by the
//!   look's zoom), where the detector recognises rather than guesses; the looks are centred
//!   on the sighting from inside that range ([`super::closer`]).
//! * **The prior** is the candidate's ([`super`] module docs): the map's, moved by what
//!   earlier failed verifications' looks said of the spot ("Earlier looks at the spot"); the
//!   sighting that made the candidate is not counted again (it is why there is a candidate
//!   at all).
//! * **Where the looks aim**: at the sighting, then at the most confident closer detection
//!   ([`super::closer`]); a real object off the look's centre is missed more often than the
//!   model's `1 − FN` says.
//! * **The prices.** A rejected target is priced as a failed search, the planner's reward R
//!   ([`avs_plan::SearchOptions::reward`], in metres of travel as the plans' costs are): it is
//!   remembered as a look-alike within the reach of the looks ([`crate::memory::Rejection`]),
//!   so that sightings there are not verified again. That price is an upper bound: a later
//!   sighting beyond the reach is a new candidate, and on 200 generated floors (BENCHMARKS.md,
//!   issue 17 session "a place behind a wall") 14 of the 15 runs that rejected their real
//!   target once still found it, 71 m later on average. A lower constant price was measured
//!   and not kept: it lost real targets whose prior is small. A wrong report ends the search
//!   with a wrong answer: it costs [`crate::AgentConfig::wrong_report_price`] failed searches
//!   (10 by default, see the field's docs: at 1, about one look-alike candidate in 600 was
//!   accepted, 1–2 wrong reports per 200 bench floors). A landmark is never reported:
//!   accepting a wrong one costs the searches made on it, priced as one failed search. A look costs what processing a view cone costs in metres
//!   (`process_cost / travel_cost_per_m`). With R = 1000 and 2 m per look, the policy looks
//!   until it is about 99.8 % sure that it is no object, and (at the default wrong-report
//!   price of 10) 99.98 % sure of an object, or its budget
//!   ([`crate::config::Tuning::sequential_max_looks`]) is spent, and then decides on the
//!   belief it has.
//! * **A detector whose errors follow the vantage point** (Velez et al. 2012; the knowledge's
//!   `sensor.correlation`, [`avs_format::knowledge::LookCorrelation`]): a second look from
//!   where the first was taken repeats it, and is no new evidence. With the correlation
//!   declared, every closer look comes from a vantage point — the range divided by the look's
//!   zoom, and the bearing around the sighting — at least one correlation length from the
//!   sighting's (made through an unzoomed view) and from every earlier look's
//!   ([`apart`]): through another zoom from where the robot stands, when one shows the
//!   sighting as from a new range within the ranges the look may be taken at
//!   ([`super::closer::Closer::fresh_zoom`]), else from the nearest standpoint that gives one
//!   ([`super::closer::Closer::walk_to_stand`]; the robot stops a little off a standpoint,
//!   and when no zoom gives a new vantage point from where it stopped, the next standpoint is
//!   tried, each once); when none is left the policy decides on the
//!   belief it has ("no new vantage point left"). Without it, looks from one standpoint are
//!   independent draws, as the simulator's default detector makes them.
//! * **Scores** (the class's verifier block names a `model`: `{ strategy: sequential, model:
//!   NAME }`). A detector that fires on look-alikes as readily as on objects may still score
//!   them lower (Velez et al. 2012). Each closer look then also reads the detector's score at
//!   the point it was centred on ([`avs_robot::Robot::detector_scores`], through the look's
//!   own view), and the belief moves by that sensor model (eq. 6 with eq. 9: the model at the
//!   class's scale, conditioned on the candidate's earlier looks, `avs_verify::planner::Candidate`),
//!   not by the hit or miss. The looks may then be taken at any range the detector scores the
//!   class at (the recognition range's near end to the detection range's far end), not only
//!   where a hit counts. The policy prices the next look by the binary detector hidden in its
//!   score (the score above or below the midpoint of the two hypotheses' means, at the vantage
//!   point the robot stands at, unconditioned: the next look comes from a new one;
//!   `avs_verify::sequential::BinaryLooks::quantised`): a quantised score says no more than
//!   the score, so the policy looks no longer than one that priced the score itself would.
//!   Priced at the conditioned model instead, a look from where the robot already stands is
//!   worth nothing, and real targets were rejected after one look (success 0.58 on 200
//!   floors). A robot whose detector gives no scores is verified by its hits (observed in the
//!   trace).
//! * **Where it is still wrong.** Binary looks carry little evidence against a look-alike
//!   that a correlated detector scores high from most sides. On 200 floors
//!   (`--detector correlated`) declaring the correlation cut wrong reports from 36 to 23
//!   (seed 1; success 0.82 → 0.88, SPL 0.286 → 0.239) and from 34 to 17 (seed 1001); the
//!   simulator's look-alikes fire from a fresh vantage point about a third of the time, not at
//!   the knowledge's FP of 0.05, and with that rate the wrong reports fell to 0 but the real
//!   targets could not pass the price of a wrong report in 8 looks (success 0.585). Scores,
//!   not hits, tell them apart: with the trained generic model named, 0 and 2 wrong reports on
//!   seeds 1 and 1001 (success 0.825 and 0.87). What is left is the detector's own
//!   correlation: an object's scores one correlation length apart still correlate at about
//!   0.6, the dynamic model says so, and an object whose field is low from every side it can
//!   be seen from is rejected at a belief of 0.2–0.9 (BENCHMARKS.md, issue 20 session "scores
//!   in the sequential verifier").

use super::closer::approach;
use super::{CandidateRef, Verdict};
use crate::body::Body;
use crate::memory::Memory;
use crate::run::Run;
use crate::skills::Ctx;
use crate::AgentError;
use avs_robot::{FailureReason, Robot, ViewCone};
use avs_verify::sequential::{decide, solve, BinaryLooks, Decision, StopCosts};

/// A look's hit rates are kept at least this far from 0 and 1.
const RATE_FLOOR: f64 = 1e-3;

/// The detector model and the prices of [`sequential`] for class `label` (module docs).
fn model(cx: Ctx, label: &str) -> (BinaryLooks, StopCosts) {
    let (miss, false_alarm) = crate::skills::session::sensing(cx, label);
    let clamp = |p: f64| p.clamp(RATE_FLOOR, 1.0 - RATE_FLOOR);
    let looks = BinaryLooks {
        hit_if_object: clamp(1.0 - miss),
        hit_if_not: clamp(false_alarm),
    };
    let failure = cx.config.planner.search.reward;
    // A landmark is never reported: a wrong one costs the searches made on it.
    let reported = !cx.knowledge.class(label).is_some_and(|c| c.landmark);
    let costs = StopCosts {
        look: cx.config.process_cost / cx.config.travel_cost_per_m,
        wrong_accept: if reported {
            cx.config.wrong_report_price * failure
        } else {
            failure
        },
        wrong_reject: failure,
    };
    (looks, costs)
}

/// `model` for a look through zoom `zoom` at the sighting `away` metres (3-D) from the
/// camera, after `earlier` = (hits, looks) from the same vantage point: with the zoom
/// pipeline's shares found kept, P(hit | object) is the share measured at that zoom and
/// distance ([`crate::MeasuredSensing::found_share`]), moved by the earlier looks from there
/// by the measured correlation of repeated looks ([`crate::MeasuredSensing::found_next`];
/// module docs, "Measured looks, where they are taken"), else `model`'s.
fn at_look(
    cx: Ctx,
    label: &str,
    model: BinaryLooks,
    (zoom, away): (f64, f64),
    (hits, looks): (usize, usize),
) -> BinaryLooks {
    let Some(m) = cx.config.sensing(label) else {
        return model;
    };
    match m.found_share(zoom, away) {
        Some(p) => BinaryLooks {
            hit_if_object: m
                .found_next(p, hits, looks)
                .clamp(RATE_FLOOR, 1.0 - RATE_FLOOR),
            ..model
        },
        None => model,
    }
}

/// Walk to the nearest standpoint not looked from or walked to yet (`walked`) when a look
/// from there pays for the walk: the least expected cost of deciding from belief `belief`
/// with `left` looks of the model there (a look from a new vantage point, [`at_look`]) plus
/// the walk, below that with the looks `here` (the next look from where the robot stands).
/// Whether the robot walked.
#[allow(clippy::too_many_arguments)]
fn fresh_stand<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    closer: &super::closer::Closer,
    (label, model, costs): (&str, BinaryLooks, StopCosts),
    belief: f64,
    left: usize,
    here: BinaryLooks,
    taken: &Vantages,
    walked: &mut Vec<[f64; 2]>,
) -> Result<bool, AgentError> {
    if !cx
        .config
        .sensing(label)
        .is_some_and(|m| m.repeat_correlation > 0.0)
    {
        return Ok(false);
    }
    let now = body.pose();
    let near = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]) <= SAME_STANDPOINT;
    let new = |p: [f64; 2]| {
        !near(p, [now.x, now.y]) && !walked.iter().any(|&w| near(p, w)) && !taken.looked_from(p)
    };
    let Some((p, walk)) = closer.nearest_stand(cx, mem, body, new) else {
        return Ok(false);
    };
    let cam = body.camera();
    let there = closer.next_look(cx, &cam, avs_robot::Pose2D::new(p[0], p[1], now.yaw));
    let fresh = at_look(cx, label, model, there, (0, 0));
    let (cost_there, step) = solve(belief, left, fresh, costs);
    let (cost_here, _) = solve(belief, left, here, costs);
    if step != Decision::Look || walk + cost_there >= cost_here {
        return Ok(false);
    }
    walked.push(p);
    closer.go_to_stand(mem, body, run, p)?;
    Ok(true)
}

/// Two standpoints this close (metres) are one vantage point.
const SAME_STANDPOINT: f64 = 0.05;

/// The closer looks taken so far, by vantage point (module docs, "Measured looks, where they
/// are taken").
#[derive(Default)]
struct Vantages(Vec<Vantage>);

/// One vantage point's looks: a standpoint and a zoom, with the hits and looks from there.
struct Vantage {
    at: [f64; 2],
    zoom: f64,
    hits: usize,
    looks: usize,
}

impl Vantage {
    /// Whether its standpoint is `at`.
    fn stands_at(&self, at: [f64; 2]) -> bool {
        (self.at[0] - at[0]).hypot(self.at[1] - at[1]) <= SAME_STANDPOINT
    }

    /// Whether it is the vantage point of standpoint `at` and zoom `zoom`.
    fn is(&self, at: [f64; 2], zoom: f64) -> bool {
        self.stands_at(at) && (self.zoom - zoom).abs() < 1e-9
    }
}

impl Vantages {
    /// The (hits, looks) from standpoint `at` through zoom `zoom`.
    fn tally(&self, at: [f64; 2], zoom: f64) -> (usize, usize) {
        self.0
            .iter()
            .find(|v| v.is(at, zoom))
            .map_or((0, 0), |v| (v.hits, v.looks))
    }

    /// Count a look from `at` through `zoom` that found the object or not.
    fn record(&mut self, at: [f64; 2], zoom: f64, hit: bool) {
        match self.0.iter_mut().find(|v| v.is(at, zoom)) {
            Some(v) => {
                v.hits += usize::from(hit);
                v.looks += 1;
            }
            None => self.0.push(Vantage {
                at,
                zoom,
                hits: usize::from(hit),
                looks: 1,
            }),
        }
    }

    /// Whether a look was taken from standpoint `p`, through any zoom.
    fn looked_from(&self, p: [f64; 2]) -> bool {
        self.0.iter().any(|v| v.stands_at(p))
    }
}

/// Verify candidate `c` from its prior (module docs); with `scored`, the name of the sensor
/// model that weighs each look's score (module docs, "Scores").
pub(crate) fn sequential<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    c: &CandidateRef,
    scored: Option<&str>,
) -> Result<Verdict, AgentError> {
    let (label, d, prior) = (c.label, c.sighting, c.prior);
    let (model, costs) = model(cx, label);
    let scorer = match scored {
        Some(name) => Some(match mem.score_models.get(label) {
            Some(m) => m.clone(),
            None => {
                let m = std::sync::Arc::new(super::model::score_model(cx.knowledge, label, name)?);
                mem.score_models.insert(label.to_string(), m.clone());
                m
            }
        }),
        None => None,
    };
    let mut scores = scorer
        .as_ref()
        .map(|m| avs_verify::planner::Candidate::new([d.pose.x, d.pose.y], None, m, prior));
    // A detector that fires as often on nothing as on the object proves nothing: no looks.
    let budget = if model.is_valid() {
        cx.tuning().sequential_max_looks
    } else {
        0
    };
    // Nothing to walk for when the prior alone decides.
    let first = decide(prior, budget, model, costs);
    if first != Decision::Look {
        let reason = if model.is_valid() {
            format!("decided on the prior {prior:.3}")
        } else {
            "the detector's hit rates carry no evidence; decided on the prior".into()
        };
        return Ok(Verdict {
            confirmed: (first == Decision::Accept).then(|| d.clone()),
            belief: Some(prior),
            looks: 0,
            reason,
            reach: None,
        });
    }
    // Where the sighting was made from: the robot has not moved since it saw it. (A sighting
    // an earlier search made is verified from wherever the robot is: the vantage point kept
    // out is then merely one more.)
    let sighted_from = {
        let p = body.pose();
        [p.x, p.y]
    };
    let Some(mut closer) = approach(cx, mem, body, run, c)? else {
        return Ok(Verdict::rejected("the class is not in the knowledge file"));
    };
    // With a correlated detector, each look from a vantage point of its own (module docs).
    let lengths = cx.knowledge.sensor.correlation.map(|k| {
        let range = cx
            .knowledge
            .class(label)
            .map_or(1.0, |c| c.detection_range[1]);
        [k.range_share * range, k.aspect_deg.to_radians()]
    });
    // The ranges (as the detector sees them) a fresh vantage point may be taken at: where a
    // hit counts (the recognition range), or with scores wherever the detector scores the
    // class (module docs, "Scores").
    let window = cx.knowledge.class(label).map_or([0.0, 0.0], |k| {
        let [lo, hi] = k.recognition_range;
        if scores.is_some() {
            [lo, k.detection_range[1].max(hi)]
        } else {
            [lo, hi]
        }
    });
    // The views that make sightings are unzoomed (the paper's view cones).
    let mut vantages = vec![closer.vantage_at_zoom(sighted_from, 1.0)];
    let (mut hits, mut looks) = (0, 0);
    let mut taken = Vantages::default();
    let mut walked: Vec<[f64; 2]> = Vec::new();
    let mut belief = prior;
    let mut note = "";
    let accepted = loop {
        // A scored look is priced by the binary detector hidden in its score, at the vantage
        // point the robot stands at (module docs, "Scores").
        let priced = match &scores {
            Some(cand) => {
                let here = body.pose();
                let v = cand.vantage([here.x, here.y]);
                quantised(cand, &v).unwrap_or(model)
            }
            None => {
                let here = body.pose();
                let (zoom, away) = closer.next_look(cx, &body.camera(), here);
                let earlier = taken.tally([here.x, here.y], zoom);
                let priced = at_look(cx, label, model, (zoom, away), earlier);
                // Looks repeated from here may say less than one from a standpoint not looked
                // from yet: walk there when that pays (module docs, "Measured looks").
                if lengths.is_none()
                    && fresh_stand(
                        cx,
                        mem,
                        body,
                        run,
                        &closer,
                        (label, model, costs),
                        belief,
                        budget - looks,
                        priced,
                        &taken,
                        &mut walked,
                    )?
                {
                    continue;
                }
                priced
            }
        };
        match decide(belief, budget - looks, priced, costs) {
            Decision::Accept => break true,
            Decision::Reject => break false,
            Decision::Look => {
                let mut zoom = None;
                if let Some(l) = lengths {
                    let fresh = |v: [f64; 2]| vantages.iter().all(|&u| apart(u, v, l));
                    zoom = closer.to_fresh_vantage(cx, mem, body, run, window, fresh)?;
                    let Some(z) = zoom else {
                        // No vantage point left that says anything new: decide now.
                        note = "; no new vantage point left";
                        break decide(belief, 0, model, costs) == Decision::Accept;
                    };
                    let here = body.pose();
                    vantages.push(closer.vantage_at_zoom([here.x, here.y], z));
                }
                looks += 1;
                let seen = closer.look_through(cx, body, run, true, zoom).is_some();
                hits += usize::from(seen);
                // The look as it was taken: its zoom, its distance and the earlier looks
                // from its vantage point decide what a miss says.
                let looked = match (closer.last(), closer.last_look(body.camera().height)) {
                    (Some((cone, _)), Some(look)) => {
                        let at = [cone.pose.x, cone.pose.y];
                        let earlier = taken.tally(at, look.0);
                        taken.record(at, look.0, seen);
                        at_look(cx, label, model, look, earlier)
                    }
                    _ => model,
                };
                match scores.as_mut() {
                    Some(cand) => match read_score(body, run, label, &closer)? {
                        Read::Score(z, cone) => belief = weigh(run, label, cand, z, &cone)?,
                        Read::Unseen => {}
                        Read::Unsupported(why) => {
                            run.observe(format!(
                                "{why}: the {label} is verified by its closer looks' detections instead"
                            ));
                            scores = None;
                            belief = looked.update(belief, seen);
                        }
                    },
                    None => belief = looked.update(belief, seen),
                }
            }
        }
    };
    body.refresh_map(mem);
    let reason = format!("{hits} of {looks} closer looks detected it; belief {belief:.3}{note}");
    // An object accepted without a closer detection (a prior high enough that misses did not
    // sink it) is reported where it was sighted.
    let confirmed = accepted.then(|| closer.best().unwrap_or(d).clone());
    Ok(Verdict {
        confirmed,
        belief: Some(belief),
        looks,
        reason,
        reach: closer.reach(),
    })
}

/// What reading the detector's score at the last look's centre gave.
enum Read {
    /// The score, and the view it was read through.
    Score(f64, ViewCone),
    /// The detector could not see the point from there (no evidence).
    Unseen,
    /// The robot's detector gives no scores (the reason).
    Unsupported(String),
}

/// The detector's score of `label` at the point the last closer look was centred on, through
/// that look's view (module docs, "Scores").
fn read_score<R: Robot + ?Sized>(
    body: &mut Body<R>,
    run: &mut Run,
    label: &str,
    closer: &super::closer::Closer,
) -> Result<Read, AgentError> {
    let Some(&(cone, centre)) = closer.last() else {
        return Ok(Read::Unseen);
    };
    Ok(
        match body.scores(&cone, label, std::slice::from_ref(&centre)) {
            Err(e) if e.reason == FailureReason::Unsupported => Read::Unsupported(e.message),
            Err(e) => {
                run.observe(format!("reading the {label}'s score failed: {e}"));
                Read::Unseen
            }
            Ok(r) => {
                run.metrics.verification_detector_s += r.detector_seconds;
                match r.scores.first().copied().flatten() {
                    Some(z) => Read::Score(z, cone),
                    None => Read::Unseen,
                }
            }
        },
    )
}

/// Move candidate `cand`'s belief by score `z` of a look through `cone` (module docs,
/// "Scores"), noted in the trace; the new belief.
fn weigh(
    run: &mut Run,
    label: &str,
    cand: &mut avs_verify::planner::Candidate,
    z: f64,
    cone: &ViewCone,
) -> Result<f64, AgentError> {
    cand.zoom = cone.zoom.max(1.0);
    cand.observe([cone.pose.x, cone.pose.y], z)
        .map_err(|e| AgentError::Verifier {
            class: label.to_string(),
            message: e.to_string(),
        })?;
    let belief = cand.belief;
    run.observe(format!(
        "the {label}'s score {z:.2} (zoom {:.1}): belief {belief:.3}",
        cone.zoom
    ));
    Ok(belief)
}

/// The binary detector hidden in a scored look at candidate `cand` from vantage `v`
/// ([`BinaryLooks::quantised`]), kept inside [`RATE_FLOOR`, 1 − `RATE_FLOOR`]; `None` where
/// the model cannot see the candidate. The model is not conditioned on the candidate's looks:
/// the next look comes from a new vantage point (module docs), and the one the robot stands at
/// before it walks there is only where the policy is asked.
fn quantised(
    cand: &avs_verify::planner::Candidate,
    v: &avs_verify::vantage::Vantage,
) -> Option<BinaryLooks> {
    let look = cand.model.condition(&[]).ok()?.at(v)?;
    let b = BinaryLooks::quantised(&look);
    let clamp = |p: f64| p.clamp(RATE_FLOOR, 1.0 - RATE_FLOOR);
    Some(BinaryLooks {
        hit_if_object: clamp(b.hit_if_object),
        hit_if_not: clamp(b.hit_if_not),
    })
}

/// Whether two vantage points `(range, bearing)` are at least one correlation length apart
/// (`lengths`: range metres, bearing radians), `√((Δr/ℓ_r)² + (Δφ/ℓ_φ)²) ≥ 1` with the bearing
/// difference wrapped to `[0, π]`: looks from them are independent draws of a correlated
/// detector.
fn apart(a: [f64; 2], b: [f64; 2], lengths: [f64; 2]) -> bool {
    let dr = (a[0] - b[0]) / lengths[0];
    let dphi = avs_map::geometry::wrap_angle(a[1] - b[1]).abs() / lengths[1];
    dr.hypot(dphi) >= 1.0
}

#[cfg(test)]
mod tests {
    use crate::memory::Rejection;
    use crate::skills::testing::{self, object, Verified};
    use crate::trace::Event;
    use avs_robot::{ActionResult, ScriptedRobot};

    /// A cerealbox sighting verified by the default verifier (the shipped knowledge has no
    /// verifier block); `prepare` sets the robot up.
    fn verdict(prepare: impl FnOnce(&mut ScriptedRobot)) -> (Verified, Vec<bool>) {
        let v = testing::verify_cerealbox(&testing::knowledge(), prepare);
        let looks = hits(&v);
        (v, looks)
    }

    /// Whether each closer look of a verification detected the candidate, in order.
    fn hits(v: &Verified) -> Vec<bool> {
        v.events
            .iter()
            .filter_map(|e| match e {
                Event::DtAction {
                    action, detected, ..
                } if action.starts_with("VERIFY") => *detected,
                _ => None,
            })
            .collect()
    }

    fn decision(v: &Verified) -> (bool, Option<f64>, String) {
        v.events
            .iter()
            .find_map(|e| match e {
                Event::VerificationDecision {
                    accepted,
                    belief,
                    reason,
                    ..
                } => Some((*accepted, *belief, reason.clone())),
                _ => None,
            })
            .expect("a decision in the trace")
    }

    /// The standpoints of the closer looks of a cerealbox verification under knowledge `k`
    /// (the object placed, so every look hits), with the decision.
    fn standpoints(k: &avs_format::knowledge::Knowledge) -> (Vec<[f64; 3]>, bool, String) {
        let v = testing::verify_cerealbox(k, |r| r.place(object("cerealbox", 4.5, 2.0, 0.14)));
        let at = v
            .events
            .iter()
            .filter_map(|e| match e {
                Event::DtAction {
                    action,
                    view: Some(view),
                    ..
                } if action.starts_with("VERIFY") => Some([view.x, view.y, view.zoom]),
                _ => None,
            })
            .collect();
        let (accepted, _, reason) = decision(&v);
        (at, accepted, reason)
    }

    /// A detector whose errors follow the vantage point (`sensor.correlation`) repeats itself
    /// from one spot: every closer look comes from a vantage point at least one correlation
    /// length from the sighting's and from every earlier look's; without the correlation the
    /// looks are independent and all come from the one nearest standpoint.
    #[test]
    fn a_correlated_detector_is_looked_through_from_a_new_vantage_point_each_time() {
        let k = testing::knowledge();
        let (same, accepted, _) = standpoints(&k);
        assert!(accepted && same.len() >= 3, "{same:?}");
        assert!(same.windows(2).all(|w| w[0] == w[1]), "{same:?}");
        let mut kc = k.clone();
        kc.sensor.correlation = Some(avs_format::knowledge::LookCorrelation {
            range_share: 0.2,
            aspect_deg: 30.0,
        });
        let (moved, accepted, reason) = standpoints(&kc);
        let lengths = [
            0.2 * k.class("cerealbox").unwrap().detection_range[1],
            30f64.to_radians(),
        ];
        // Distance over the zoom, and bearing, from the sighting at (4.5, 2.0), which was made
        // from (1, 2) through an unzoomed view.
        let vantage = |p: [f64; 2], zoom: f64| {
            [
                (p[0] - 4.5).hypot(p[1] - 2.0) / zoom,
                (p[1] - 2.0).atan2(p[0] - 4.5),
            ]
        };
        let mut seen = vec![vantage([1.0, 2.0], 1.0)];
        for &[x, y, zoom] in &moved {
            let v = vantage([x, y], zoom);
            assert!(
                seen.iter().all(|&u| super::apart(u, v, lengths)),
                "{moved:?}"
            );
            seen.push(v);
        }
        // The room is 6 m × 4 m: some bearings are left for as many looks as an object needs,
        // or the decision says none was.
        assert!(
            accepted || reason.contains("no new vantage point"),
            "{reason}"
        );
        assert!(moved.len() >= 2, "{moved:?}");
    }

    #[test]
    fn vantage_points_are_apart_by_range_or_bearing_and_the_bearing_wraps() {
        let l = [1.0, 0.5];
        assert!(!super::apart([2.0, 0.0], [2.5, 0.2], l));
        assert!(super::apart([2.0, 0.0], [3.1, 0.0], l));
        assert!(super::apart([2.0, 0.0], [2.0, 0.6], l));
        // Across ±π the bearings are 0.2 rad apart.
        assert!(!super::apart([2.0, 3.04], [2.0, -3.04], l));
    }

    #[test]
    fn a_real_object_is_looked_at_until_the_belief_passes_the_price_of_a_wrong_report() {
        let (v, looks) = verdict(|r| r.place(object("cerealbox", 4.5, 2.0, 0.14)));
        assert!(v.confirmed.is_some());
        let (accepted, belief, _) = decision(&v);
        // Every look hits (the scripted detector never misses): as many looks as the prior
        // needs to pass 1 − (look cost / failure cost), more than the count rule's two.
        assert!(accepted && looks.iter().all(|&h| h));
        assert!(belief.unwrap() > 0.99, "{belief:?}");
        assert!(looks.len() >= 3, "{looks:?}");
        assert!(v.rejected.is_empty());
    }

    /// A wrong report priced at ten failed searches asks for more hits before a real object
    /// is accepted than one priced at one; both accept it.
    #[test]
    fn a_dearer_wrong_report_asks_for_more_hits_before_accepting() {
        let looks_at = |price: f64| {
            let config = crate::AgentConfig {
                wrong_report_price: price,
                ..crate::AgentConfig::default()
            };
            let v = testing::verify_cerealbox_with(&testing::knowledge(), &config, |r| {
                r.place(object("cerealbox", 4.5, 2.0, 0.14))
            });
            let (accepted, belief, _) = decision(&v);
            assert!(accepted && v.confirmed.is_some(), "price {price}");
            (v.metrics.verification_looks, belief.unwrap())
        };
        let (cheap, b1) = looks_at(1.0);
        let (dear, b10) = looks_at(10.0);
        assert!(dear > cheap, "{dear} looks at price 10, {cheap} at 1");
        assert!(b10 > b1, "belief {b10} at price 10, {b1} at 1");
    }

    #[test]
    fn a_sighting_no_closer_look_repeats_is_rejected_after_the_misses_it_needs() {
        let (v, looks) = verdict(|_| {});
        assert!(v.confirmed.is_none());
        let (accepted, belief, reason) = decision(&v);
        assert!(!accepted && looks.iter().all(|&h| !h));
        assert!(belief.unwrap() < 0.01, "{belief:?}");
        // Not the whole budget: a few misses settle a prior this low.
        assert!(looks.len() < 8, "{looks:?}");
        assert!(
            reason.contains(&format!("0 of {}", looks.len())),
            "{reason}"
        );
        assert_eq!(v.rejected, vec![("cerealbox".to_string(), [4.5, 2.0])]);
    }

    /// An agent configuration with measured sensing of the cerealbox: one look within
    /// 0.25–4 m finds it with probability 0.8, and a look repeated from one vantage point
    /// repeats the first with correlation `rho`.
    fn measured(rho: f64) -> crate::AgentConfig {
        crate::AgentConfig {
            measured_sensing: vec![crate::MeasuredSensing {
                class: "cerealbox".into(),
                detection_range: [0.25, 4.0],
                ranges_by_zoom: vec![(1.0, [0.25, 4.0])],
                false_negative: 0.2,
                false_positive: 0.01,
                found_by_zoom: vec![crate::FoundByDistance {
                    zoom: 1.0,
                    distances: vec![0.25, 6.0],
                    found: vec![0.8, 0.8],
                    looks: 0,
                }],
                repeat_correlation: rho,
            }],
            ..crate::AgentConfig::default()
        }
    }

    /// The standpoints of a verification's closer looks, each once, in order.
    fn stands(v: &Verified) -> Vec<[f64; 2]> {
        let mut out: Vec<[f64; 2]> = Vec::new();
        for e in &v.events {
            if let Event::DtAction {
                action,
                view: Some(view),
                ..
            } = e
            {
                let p = [view.x, view.y];
                if action.starts_with("VERIFY") && !out.iter().any(|q| q == &p) {
                    out.push(p);
                }
            }
        }
        out
    }

    /// Where repeated looks say little new (the measured correlation of looks from one
    /// vantage point), a miss sends the robot to a standpoint it has not looked from, and
    /// misses from one spot move the belief less than independent ones would; where they are
    /// new draws, every look comes from the one standpoint.
    #[test]
    fn looks_that_repeat_each_other_from_one_standpoint_send_the_robot_to_another() {
        let k = testing::knowledge();
        let nothing_there = |rho: f64| testing::verify_cerealbox_with(&k, &measured(rho), |_| {});
        let independent = nothing_there(0.0);
        assert_eq!(stands(&independent).len(), 1, "{:?}", stands(&independent));
        let correlated = nothing_there(0.8);
        let (accepted, belief, _) = decision(&correlated);
        assert!(!accepted, "{belief:?}");
        assert!(stands(&correlated).len() >= 2, "{:?}", stands(&correlated));
        // Every standpoint walked to is looked from: no walking in circles.
        let looks = hits(&correlated).len();
        assert!(looks >= stands(&correlated).len(), "{looks}");
    }

    /// The likelihood of a verifier's looks with measured sensing: P(hit | object) is the
    /// share measured at the look's distance, moved by the earlier looks from its vantage
    /// point; a look from a new vantage point starts again from the share.
    #[test]
    fn a_look_from_a_vantage_point_already_looked_from_is_weighed_by_what_it_said() {
        let k = testing::knowledge();
        let config = measured(0.5);
        let cx = testing::ctx(&k, &config);
        let (base, _) = super::model(cx, "cerealbox");
        let p = |earlier| super::at_look(cx, "cerealbox", base, (1.0, 2.0), earlier).hit_if_object;
        assert!((p((0, 0)) - 0.8).abs() < 1e-12);
        // ρ = 0.5: α + β = 1; after one miss (0.8 · 1 + 0) / (1 + 1) = 0.4.
        assert!((p((0, 1)) - 0.4).abs() < 1e-12);
        assert!((p((1, 1)) - 0.9).abs() < 1e-12);
        // Without kept shares the class's constant rate.
        let plain = crate::AgentConfig::default();
        let cx = testing::ctx(&k, &plain);
        let (base, _) = super::model(cx, "cerealbox");
        let q = super::at_look(cx, "cerealbox", base, (1.0, 2.0), (0, 3));
        assert_eq!(q, base);
    }

    #[test]
    fn misses_after_a_hit_are_weighed_not_counted() {
        // One hit, then misses: the count rule's "2 of 3" would reject on the third look; the
        // sequential rule rejects only once the misses outweigh the hit and the prior.
        let (v, looks) = verdict(|r| {
            r.script_view(ActionResult::Ok(vec![object("cerealbox", 4.5, 2.0, 0.14)]));
            for _ in 0..10 {
                r.script_view(ActionResult::Ok(vec![]));
            }
        });
        assert_eq!(looks.first(), Some(&true));
        let (accepted, belief, _) = decision(&v);
        assert!(!accepted && belief.unwrap() < 0.01);
        assert!(looks.len() >= 3, "{looks:?}");
    }

    /// A failed verification is remembered with what its looks said (the log-odds its belief
    /// moved by), and a sighting within their reach starts from the map's prior moved by that
    /// much, with a line in the trace saying so.
    #[test]
    fn a_failed_verification_is_remembered_with_its_evidence_and_moves_the_next_prior() {
        use avs_verify::sequential::{from_log_odds, log_odds};
        let config = crate::AgentConfig::default();
        let k = testing::knowledge();
        let (mut robot, mut mem) = testing::verification_room(&config, &k);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let mut verify = |robot: &mut ScriptedRobot, run: &mut crate::run::Run, x: f64| {
            super::super::verify(
                testing::ctx(&k, &config),
                &mut mem,
                &mut crate::body::Body::new(robot),
                run,
                "cerealbox",
                &object("cerealbox", x, 2.0, 0.14),
            )
            .unwrap()
        };
        // Nothing there: every closer look misses, and the sighting is rejected.
        assert!(verify(&mut robot, &mut run, 4.5).is_none());
        // A second sighting 5 cm beside it, where the detector now fires at every look.
        robot.place(object("cerealbox", 4.55, 2.0, 0.14));
        verify(&mut robot, &mut run, 4.55);
        let priors: Vec<f64> = run
            .events
            .iter()
            .filter_map(|e| match e {
                Event::CandidateCreated { prior, .. } => Some(*prior),
                _ => None,
            })
            .collect();
        let beliefs: Vec<f64> = run
            .events
            .iter()
            .filter_map(|e| match e {
                Event::VerificationDecision { belief, .. } => *belief,
                _ => None,
            })
            .collect();
        let evidence = mem.rejected[0].evidence;
        assert!(
            (evidence - (log_odds(beliefs[0]) - log_odds(priors[0]))).abs() < 1e-9
                && evidence < -2.0,
            "the misses' evidence: {evidence}, beliefs {beliefs:?}, priors {priors:?}"
        );
        let floor = super::super::PRIOR_FLOOR;
        let moved = from_log_odds(log_odds(priors[0]) + evidence).clamp(floor, 1.0 - floor);
        assert!(
            (priors[1] - moved).abs() < 1e-12 && priors[1] < priors[0],
            "{priors:?} {evidence}"
        );
        assert!(
            run.events
                .iter()
                .any(|e| matches!(e, Event::Observed { what }
                if what.contains("1 earlier verification(s)"))),
            "the trace says why the prior moved"
        );
    }

    #[test]
    fn a_rejection_covers_only_what_its_looks_saw_beside_the_sighting() {
        let config = crate::AgentConfig::default();
        let k = testing::knowledge();
        let (mut robot, mut mem) = testing::verification_room(&config, &k);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let d = object("cerealbox", 4.5, 2.0, 0.14);
        let found = super::super::verify(
            testing::ctx(&k, &config),
            &mut mem,
            &mut crate::body::Body::new(&mut robot),
            &mut run,
            "cerealbox",
            &d,
        )
        .unwrap();
        assert!(found.is_none());
        let [Rejection { radius, .. }] = mem.rejected.as_slice() else {
            panic!("one rejection: {:?}", mem.rejected);
        };
        // The looks were zoomed onto the sighting from inside its recognition range: the
        // image's half width there is well under the radius a detection confirms within.
        assert!(
            *radius > 0.05 && *radius < config.tuning.confirm_radius,
            "{radius}"
        );
    }

    /// The shipped knowledge with the cerealbox verified by `sequential` weighing scores with
    /// the hand-written model of [`testing::knowledge_verified_by`] (objects score about 2,
    /// look-alikes about 0.8), and the detector's correlation declared.
    fn scored_knowledge() -> avs_format::knowledge::Knowledge {
        let mut k = testing::knowledge_verified_by(
            "cerealbox",
            avs_format::verifier::VerifierStrategy::Sequential,
        );
        k.sensor.correlation = Some(avs_format::knowledge::LookCorrelation {
            range_share: 0.2,
            aspect_deg: 30.0,
        });
        k
    }

    #[test]
    fn a_look_alike_that_fires_at_every_look_is_rejected_by_its_scores() {
        let k = scored_knowledge();
        let scored = testing::verify_cerealbox(&k, |r| {
            // Something at the sighting fires the detector at every look, and scores as a
            // look-alike does.
            r.place(object("cerealbox", 4.5, 2.0, 0.14));
            for _ in 0..40 {
                r.script_scores(Ok(vec![Some(0.8)]));
            }
        });
        let (accepted, belief, reason) = decision(&scored);
        assert!(!accepted && scored.confirmed.is_none(), "{reason}");
        assert!(belief.unwrap() < 0.01, "{belief:?} {reason}");
        // Every closer look detected it: hits alone would have accepted it.
        let looks = hits(&scored);
        assert!(!looks.is_empty() && looks.iter().all(|&h| h), "{reason}");
        let by_hits = testing::verify_cerealbox(&testing::knowledge(), |r| {
            r.place(object("cerealbox", 4.5, 2.0, 0.14))
        });
        assert!(by_hits.confirmed.is_some());
    }

    #[test]
    fn an_object_that_scores_as_objects_do_is_accepted_from_new_vantage_points() {
        let v = testing::verify_cerealbox(&scored_knowledge(), |r| {
            r.place(object("cerealbox", 4.5, 2.0, 0.14))
        });
        let (accepted, belief, reason) = decision(&v);
        assert!(accepted && v.confirmed.is_some(), "{reason}");
        assert!(belief.unwrap() > 0.99, "{belief:?} {reason}");
        // The scores were read at the sighting, once per closer look.
        let reads = v
            .robot
            .calls()
            .iter()
            .filter(|c| matches!(c, avs_robot::Call::Scores(..)))
            .count();
        assert_eq!(reads, v.metrics.verification_looks, "{reason}");
    }

    #[test]
    fn a_robot_without_scores_is_verified_by_its_hits_instead() {
        let v = testing::verify_cerealbox(&scored_knowledge(), |r| {
            *r = r.clone().without_scores();
            r.place(object("cerealbox", 4.5, 2.0, 0.14));
        });
        assert!(v.confirmed.is_some());
        assert!(v.events.iter().any(|e| matches!(e,
            Event::Observed { what } if what.contains("closer looks' detections instead"))));
    }
}
