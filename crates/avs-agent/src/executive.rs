//! The switching planner's executive (Aydemir et al. 2011, `002` §II-A): [`Agent::search`]
//! keeps the memory current from the body's feedback, asks the assumptive continual planner
//! for a plan, runs it step by step through the skills, monitors the rest of the plan after
//! every step and replans with the reason, and, when no plan clears the success threshold,
//! hands over to the coverage (module `strategy`) before it gives up.

use crate::binding::{check_domain, Action, Binding, PlaceArg, Probs};
use crate::body::Body;
use crate::config::{AgentConfig, Strategy};
use crate::memory::Memory;
use crate::reason::{GiveUpReason, ReplanReason};
use crate::report::{Activity, FoundObject, Goal, SearchReport};
use crate::run::{Run, StepEnd};
use crate::skills::enter::enter;
use crate::skills::look_around::{look_around, look_around_for_goal, looked_for};
use crate::skills::session::{dt_search, Search};
use crate::skills::sighted::{verify_sightings, Sighted};
use crate::skills::views::create_cones;
use crate::skills::Ctx;
use crate::strategy::{baseline_loop, cover_all};
use crate::trace::{Event, Outcome, TraceSink};
use crate::world_model::WorldModel;
use crate::AgentError;
use avs_concepts::ConceptualMap;
use avs_format::knowledge::Knowledge;
use avs_map::places::dist;
use avs_plan::continual::{ActivePlan, ContinualPlanner, Decision, Replan, Verdict};
use avs_plan::domain::Domain;
use avs_robot::Robot;
use std::collections::BTreeSet;
use std::time::Instant;

/// The agent: one per robot; [`Agent::search`] once per goal. The memory is kept between
/// goals.
#[derive(Debug, Clone)]
pub struct Agent {
    planner: ContinualPlanner,
    /// The same planner in fast mode: used when the configured search hits its limit.
    fallback: ContinualPlanner,
    knowledge: Knowledge,
    config: AgentConfig,
    memory: Option<Memory>,
}

/// How a search ends.
type End = Result<FoundObject, GiveUpReason>;

impl Agent {
    /// An agent for a planning domain and a knowledge file. Rejects a configuration value out
    /// of range, knowledge the conceptual map cannot use, and a domain without an operator,
    /// function, variable or relation the executive uses (the error names it).
    pub fn new(
        domain: Domain,
        knowledge: Knowledge,
        config: AgentConfig,
    ) -> Result<Self, AgentError> {
        config.check()?;
        check_domain(&domain)?;
        // Fail early on knowledge the conceptual map cannot use, and on a verifier block
        // whose model does not build.
        ConceptualMap::new("knowledge", &knowledge)?;
        for c in &knowledge.object_classes {
            if let Some(v) = c
                .verifier
                .as_ref()
                .filter(|v| v.strategy.uses_model() || v.model.is_some())
            {
                crate::skills::verify::check_verifier(&knowledge, &c.name, v)?;
            }
        }
        // A search that ends when the planner gives up stops once no plan is worth its cost
        // (`AgentConfig::cover_before_giving_up`).
        let mut planner_options = config.planner;
        planner_options.give_up_unless_worth_it |= !config.cover_before_giving_up;
        Ok(Self {
            fallback: ContinualPlanner::new(domain.clone(), {
                let mut o = planner_options;
                o.search.mode = avs_plan::Mode::Fast;
                o
            }),
            planner: ContinualPlanner::new(domain, planner_options),
            knowledge,
            config,
            memory: None,
        })
    }

    /// The agent's place map (places, paths, door hypotheses; its rooms by
    /// [`PlaceMap::rooms`](avs_map::places::PlaceMap::rooms)) as the last search left it, or
    /// `None` before the first search.
    pub fn place_map(&self) -> Option<&avs_map::places::PlaceMap> {
        self.memory.as_ref().map(|m| &m.wm.places)
    }

    /// What the agent believes now, with object probabilities for `class` (see
    /// [`Beliefs`](crate::Beliefs)); `None` before the first search. Between searches these are
    /// the beliefs the last search left; during one, a [`TraceSink`] that
    /// [wants them](TraceSink::wants_beliefs) is handed them before every plan.
    pub fn beliefs(&self, class: Option<&str>) -> Option<crate::Beliefs> {
        self.memory
            .as_ref()
            .map(|m| crate::beliefs::beliefs_of(m, &self.knowledge, class))
    }

    /// Search for `goal` with `robot`; the trace is returned in the report.
    pub fn search<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: Goal,
    ) -> Result<SearchReport, AgentError> {
        let mut sink = |_: &Event| {};
        self.search_with(robot, goal, &mut sink)
    }

    /// Search for each of `goals` in turn with the same memory (the goals of
    /// [`Goal::find_all`]: every look runs the detector for the classes still sought, and a
    /// later goal first verifies what earlier looks saw of its class); one report per goal,
    /// in order.
    pub fn search_all<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goals: Vec<Goal>,
    ) -> Result<Vec<SearchReport>, AgentError> {
        goals.into_iter().map(|g| self.search(robot, g)).collect()
    }

    /// Search for `goal`, handing every trace event to `sink` as it happens.
    pub fn search_with<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: Goal,
        sink: &mut dyn TraceSink,
    ) -> Result<SearchReport, AgentError> {
        if let Some(class) = std::iter::once(&goal.class)
            .chain(&goal.also)
            .find(|c| self.knowledge.class(c).is_none())
        {
            return Err(AgentError::UnknownClass {
                class: class.clone(),
                known: self
                    .knowledge
                    .object_classes
                    .iter()
                    .map(|c| c.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        }
        if self.config.strategy == Strategy::Informed
            && (goal.region.is_empty() || goal.region.iter().flatten().any(|x| !x.is_finite()))
        {
            return Err(AgentError::Config {
                field: "strategy",
                value: goal.region.len() as f64,
                expected: "a goal told its room (Goal::in_region with finite points) for the \
                           informed strategy",
            });
        }
        let mut body = Body::new(robot).watching(
            goal.also
                .iter()
                .filter(|c| **c != goal.class)
                .cloned()
                .collect(),
        );
        if self.config.zoom_pipeline {
            // The small objects go through the zoom pipeline; furniture fills an unzoomed
            // image and stays with the one-shot detector.
            let models = self
                .knowledge
                .object_classes
                .iter()
                .filter(|c| !c.landmark)
                .map(avs_view::zoom::ObjectModel::from_class)
                .collect();
            body = body.with_zoom(self.config.zoom, models);
        }
        let start_odo = body.odometry();
        // A new goal's plans start from the configured reward, not from the last goal's.
        self.planner.reset_objective();
        self.fallback.reset_objective();
        let mut run = Run::new(sink, self.config.tuning.cover_key_resolution);
        run.emit(Event::Started {
            goal: goal.class.clone(),
            pose: body.pose3(),
        });
        let cx = Ctx {
            knowledge: &self.knowledge,
            config: &self.config,
        };
        let mem = match &mut self.memory {
            Some(m) => m,
            slot => {
                let mut wm = WorldModel::new("knowledge", cx.knowledge, cx.config.places.clone())?;
                wm.concepts
                    .set_unfound_landmarks(cx.config.unfound_landmarks);
                let grid = body.laser_map();
                let mem = slot.insert(Memory::new(
                    wm,
                    grid,
                    cx.config.robot_radius,
                    crate::memory::pocket_size(cx.knowledge),
                    cx.config.tuning.clone(),
                ));
                body.survey(mem)?;
                mem
            }
        };
        let rejected_before = mem.rejected.len();
        // What earlier looks saw of the goal's class first, then what the look around sees.
        let mut sighted =
            verify_sightings(cx, mem, &mut body, &mut run, &goal.class, Sighted::Before)?;
        if sighted.is_none() {
            look_around(cx, mem, &mut body, &mut run, looked_for(cx, &goal))?;
            sighted = verify_sightings(
                cx,
                mem,
                &mut body,
                &mut run,
                &goal.class,
                Sighted::LookAround,
            )?;
        }
        let end = match (sighted, cx.config.strategy) {
            (Some(f), _) => Ok(f),
            (None, Strategy::Planner) => {
                let planners = Planners {
                    planner: &self.planner,
                    fallback: &self.fallback,
                };
                main_loop(cx, planners, mem, &mut body, &mut run, &goal)?
            }
            (None, s) => baseline_loop(cx, mem, &mut body, &mut run, &goal, s)?,
        };
        mem.note_sightings(body.take_sightings(), cx.config.min_confidence);
        run.beliefs(mem, cx.knowledge, &goal.class);
        let (found, reason, gave_up) = match end {
            Ok(f) => {
                let r = run.goal_reached(&f);
                (Some(f), r, None)
            }
            Err(GiveUpReason::GoalAlreadyHolds) => (
                None,
                GiveUpReason::GoalAlreadyHolds.to_string(),
                Some(GiveUpReason::GoalAlreadyHolds),
            ),
            Err(g) => {
                let g = g.hindered(
                    mem,
                    body.at(),
                    run.failed_actions(),
                    &goal.class,
                    rejected_before,
                );
                run.doors(mem);
                run.give_up(&g);
                (None, g.to_string(), Some(g))
            }
        };
        run.metrics.path_length = body.odometry() - start_odo;
        run.metrics.path_by_activity = body.path_by_activity();
        run.zoomed(body.take_zoom_images());
        (
            run.metrics.images,
            run.metrics.zoom_images,
            run.metrics.image_s,
        ) = body.images();
        Ok(SearchReport {
            found,
            reason,
            gave_up,
            trace: run.events,
            metrics: run.metrics,
        })
    }
}

/// The continual planner and its fast-mode fallback.
#[derive(Clone, Copy)]
struct Planners<'a> {
    planner: &'a ContinualPlanner,
    fallback: &'a ContinualPlanner,
}

/// Plan, execute and monitor until the goal is reached or the planner gives up.
fn main_loop<R: Robot + ?Sized>(
    cx: Ctx,
    planners: Planners,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: &Goal,
) -> Result<End, AgentError> {
    let mut reason = ReplanReason::Initial;
    let (fnr, p_min) = (cx.knowledge.sensor.false_negative, cx.tuning().p_min);
    loop {
        if run.stop_requested() {
            return Ok(Err(GiveUpReason::Cancelled));
        }
        if let Some(r) = body.cannot_move(cx.tuning().stuck_motions) {
            return Ok(Err(r));
        }
        if run.metrics.plans >= cx.config.plan_budget(mem.wm.rooms().count()) {
            let r = GiveUpReason::PlanBudget {
                plans: run.metrics.plans,
                class: goal.class.clone(),
            };
            return last_resort(cx, mem, body, run, goal, r);
        }
        run.beliefs(mem, cx.knowledge, &goal.class);
        crate::skills::views::price_searches(cx, mem, &body.camera(), &goal.class);
        let binding = Binding::of(mem, cx.knowledge, &goal.class);
        let t0 = Instant::now();
        let decision = {
            let f = Probs::new(&binding, &mem.wm.concepts, fnr, p_min);
            match planners.planner.plan(&binding.problem, &f) {
                Err(avs_plan::PlanError::SearchLimit(n)) => {
                    tracing::debug!(expansions = n, "planning again in fast mode");
                    planners.fallback.plan(&binding.problem, &f)
                }
                other => other,
            }
        };
        run.metrics.plan_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        let plan = match decision {
            Ok(Decision::Plan(p)) => p,
            Ok(Decision::GoalReached) => return Ok(Err(GiveUpReason::GoalAlreadyHolds)),
            Ok(Decision::GiveUp(g)) => {
                return last_resort(cx, mem, body, run, goal, GiveUpReason::Planner(g));
            }
            Err(e) => return Ok(Err(GiveUpReason::PlannerFailed(e.to_string()))),
        };
        run.metrics.plans += 1;
        run.emit(Event::PlanMade {
            plan: run.metrics.plans,
            reason: reason.to_string(),
            steps: plan.steps.iter().map(|s| s.display.clone()).collect(),
            cost: plan.cost,
            probability: plan.probability,
        });
        reason = ReplanReason::PlanEnded;
        let accepted = accepted_assumptions(
            planners.planner,
            &plan,
            &binding,
            &Probs::new(&binding, &mem.wm.concepts, fnr, p_min),
        );
        // Each step read once into a typed action over the binding's values.
        let actions: Vec<Result<Action, ReplanReason>> =
            plan.steps.iter().map(|s| binding.action(s)).collect();
        let mut i = 0;
        while i < plan.steps.len() {
            let action = match &actions[i] {
                Ok(Action::Assume) => {
                    i += 1;
                    continue;
                }
                a => a.clone(),
            };
            let step = &plan.steps[i];
            if run.stop_requested() {
                return Ok(Err(GiveUpReason::Cancelled));
            }
            if run.metrics.actions >= cx.config.action_budget(mem.wm.rooms().count()) {
                return Ok(Err(GiveUpReason::ActionBudget {
                    actions: run.metrics.actions,
                    class: goal.class.clone(),
                }));
            }
            run.metrics.actions += 1;
            run.emit(Event::ActionStarted {
                action: step.display.clone(),
            });
            // A map update the world model refuses (e.g. a room renamed under a search)
            // ends the step, not the search: the agent replans from what it knows.
            // A MOVE followed by more MOVEs is a waypoint of a route: drive along the route's
            // shortest path on the map and pass the place there.
            let action = match action {
                Ok(Action::Move { to, pos }) => Ok(Action::Move {
                    pos: route_end(&actions[i + 1..])
                        .map_or(pos, |end| passing_point(mem, body.pose(), pos, end)),
                    to,
                }),
                a => a,
            };
            let end = match action {
                Err(r) => StepEnd::Replan(r),
                Ok(a) => execute(cx, mem, body, run, &plan, i, a, goal).unwrap_or_else(|e| {
                    StepEnd::Replan(ReplanReason::WorldModelRefused(e.to_string()))
                }),
            };
            let outcome = match &end {
                StepEnd::Replan(ReplanReason::ActionFailed(f)) => Outcome::Failed(f.to_string()),
                _ => Outcome::Ok,
            };
            run.finished(step.display.clone(), outcome, body, mem);
            match end {
                StepEnd::Found(f) => {
                    // The plan's own REPORTPOSITION step is already in the trace.
                    if !matches!(actions[i], Ok(Action::Report { .. })) {
                        run.emit(Event::ActionStarted {
                            action: format!("REPORTPOSITION {}", f.name),
                        });
                    }
                    return Ok(Ok(f));
                }
                StepEnd::Replan(r) => {
                    reason = r;
                    break;
                }
                StepEnd::Continue => {}
            }
            // A move onto a placeholder and its exploration go together: the frontier may
            // vanish on arrival, before the plan's EXPLORE-PLACEHOLDER step.
            if let (Ok(Action::Move { to, .. }), Some(Ok(Action::Explore { ph }))) =
                (&actions[i], actions.get(i + 1))
            {
                if to.name == ph.name {
                    i += 1;
                    continue;
                }
            }
            if let Some(f) = look_around_for_goal(cx, mem, body, run, goal)? {
                run.emit(Event::ActionStarted {
                    action: format!("REPORTPOSITION {}", f.name),
                });
                return Ok(Ok(f));
            }
            // Monitor the rest of the plan against the world as now known.
            let now = Binding::of(mem, cx.knowledge, &goal.class);
            let f = Probs::new(&now, &mem.wm.concepts, fnr, p_min);
            let verdict = planners.planner.monitor(&plan, i + 1, &now.problem, &f);
            match verdict {
                Ok(Verdict::Continue) => i += 1,
                Ok(Verdict::GoalReached) => {
                    reason = ReplanReason::GoalHolds;
                    break;
                }
                Ok(Verdict::Replan(Replan::AssumptionUnlikely { action, .. }))
                    if accepted.contains(&action) =>
                {
                    i += 1;
                }
                Ok(Verdict::Replan(r)) => {
                    if let Replan::AssumptionContradicted { action, .. }
                    | Replan::AssumptionUnlikely { action, .. } = &r
                    {
                        run.emit(Event::AssumptionViolated {
                            assumption: action.clone(),
                            reason: r.to_string(),
                        });
                    }
                    reason = ReplanReason::Monitor(r);
                    break;
                }
                Err(e) => {
                    reason = ReplanReason::MapChanged(e.to_string());
                    break;
                }
            }
        }
    }
}

/// Assumptions the planner chose although already below the monitor's bound: not a reason
/// to replan later (the planner would return the same plan).
fn accepted_assumptions(
    planner: &ContinualPlanner,
    plan: &ActivePlan,
    binding: &Binding,
    f: &Probs,
) -> BTreeSet<String> {
    let mut acc = BTreeSet::new();
    let mut probe = plan.clone();
    for _ in 0..plan.steps.len() {
        match planner.monitor(&probe, 0, &binding.problem, f) {
            Ok(Verdict::Replan(Replan::AssumptionUnlikely { step, action, .. })) => {
                acc.insert(action);
                // Look for more: drop that step from the probe's check.
                probe.steps[step].probability = 1.0;
                probe.steps.remove(step);
            }
            _ => break,
        }
    }
    acc
}

/// The planner would give up for `reason`: with
/// [`AgentConfig::cover_before_giving_up`], cover what is left first ([`crate::strategy`]);
/// the search's end either way.
fn last_resort<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: &Goal,
    reason: GiveUpReason,
) -> Result<End, AgentError> {
    if !cx.config.cover_before_giving_up {
        return Ok(Err(reason));
    }
    run.observe(format!(
        "{reason}: covering what no search has looked at, the likeliest room per metre first"
    ));
    // The coverage has an action budget of its own.
    let spent = run.metrics.actions;
    run.metrics.actions = 0;
    let passes = cx.tuning().cover_passes;
    let end = body.with_activity(Activity::Coverage, |b| {
        cover_all(cx, mem, b, run, goal, Strategy::Planner, passes, true)
    });
    run.metrics.actions += spent;
    Ok(end?.map_err(|e| GiveUpReason::AfterCoverage {
        planner: Box::new(reason),
        coverage: Box::new(e),
    }))
}

/// Where the run of MOVE steps that starts the rest of a plan ends, when there is one:
/// the target of its last MOVE (or of a MOVE into a placeholder), assumptions skipped.
fn route_end(rest: &[Result<Action, ReplanReason>]) -> Option<[f64; 2]> {
    let mut end = None;
    for a in rest {
        match a {
            Ok(Action::Assume) => {}
            Ok(Action::Move { pos, .. } | Action::Enter { pos, .. }) => end = Some(*pos),
            _ => break,
        }
    }
    end
}

/// Where a robot at `here`, passing the place at `via` on its way to `end`, stops for the
/// MOVE to `via`: the point of the shortest known path to `end` nearest `via`.
///
/// The plan's MOVEs follow the place graph, whose edges join places in the order the robot
/// first drove between them: a route from one room to the next may pass the place where the
/// search started, metres off the straight way (and how far depends on where the places
/// fell, so on the grid). The places between are not visited for themselves (nothing is done
/// at them), so the robot takes the shortest path to the route's end and ends each MOVE
/// where that path passes its place; the plan is monitored there as before. Without a known
/// path, the place itself.
fn passing_point(mem: &Memory, here: avs_robot::Pose2D, via: [f64; 2], end: [f64; 2]) -> [f64; 2] {
    mem.known_path([here.x, here.y], end)
        .and_then(|p| {
            p.points
                .into_iter()
                .min_by(|a, b| dist(*a, via).total_cmp(&dist(*b, via)))
        })
        .unwrap_or(via)
}

/// Where a robot at `here` entering the placeholder at `target` stops: `depth` metres along
/// its shortest known path past the last door hypothesis that path crosses, when the robot has
/// never been through that door (the space behind it is new); else the placeholder itself (no
/// door on the way, a door into space the robot has been in — a frontier at the far end of a
/// corridor it came along — or the placeholder nearer than that).
///
/// A placeholder is a frontier: where the laser, looking through the door from outside, last
/// saw free space — often the far wall of the room behind. The room is what the MOVE is for,
/// and a robot a step inside its door sees it (the laser all around, the look-around's pan);
/// driving on to the far wall and back out is travel the plan's cost never meant. The
/// entering skill ([`enter`]) goes on from there into the space that reveals most.
///
/// A door the robot has been through (`MapDoor::confirmed`) does not count: stopping past it
/// would stop a step into a corridor the robot came along and file the placeholder at the
/// corridor's far end as explored from its first metre.
fn entry_point(mem: &Memory, here: [f64; 2], target: [f64; 2], depth: f64) -> [f64; 2] {
    let Some(path) = mem.known_path(here, target) else {
        return target;
    };
    let pts = &path.points;
    let doors = &mem.wm.places.doors;
    let crossed = |k: usize| {
        doors
            .iter()
            .filter(move |d| d.hypothesis.crossed_by(pts[k - 1], pts[k]))
    };
    let Some(k) = (1..pts.len()).rev().find(|&k| crossed(k).next().is_some()) else {
        return target;
    };
    if crossed(k).all(|d| d.confirmed) {
        return target;
    }
    let mut along = 0.0;
    for w in pts[k - 1..].windows(2) {
        along += dist(w[0], w[1]);
        if along >= depth {
            return w[1];
        }
    }
    target
}

/// Execute step `i` of `plan`, read as `action`.
#[expect(
    clippy::too_many_arguments,
    reason = "the four parts of a search (settings, memory, body, run) plus the step"
)]
fn execute<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    plan: &ActivePlan,
    i: usize,
    action: Action,
    goal: &Goal,
) -> Result<StepEnd, AgentError> {
    match action {
        Action::Assume => Ok(StepEnd::Continue),
        Action::Move { to, pos } => go(cx, mem, body, run, &to, pos, false),
        Action::Enter { to, pos } => go(cx, mem, body, run, &to, pos, true),
        Action::Explore { ph } => {
            // Explore = look into the space behind it, as when entering: a room found there
            // enters the map (rooms exist where the robot has been).
            let room = mem.current_room();
            enter(cx, mem, body, run, &ph, room)?;
            Ok(StepEnd::Continue)
        }
        Action::CreateCones { label, loc } => {
            let cam = body.camera();
            create_cones(cx, mem, &cam, run, &label, loc);
            Ok(StepEnd::Continue)
        }
        Action::Search {
            label,
            loc,
            obj,
            display,
        } => {
            let assumption = plan.steps[..i]
                .iter()
                .filter(|s| s.assumption && s.args.contains(&obj.name))
                .map(|s| s.display.clone())
                .next_back();
            let search = Search {
                label: &label,
                loc,
                obj: &obj,
                display: &display,
                assumption,
            };
            dt_search(cx, mem, body, run, &search, goal)
        }
        // A known object of the goal's class (a landmark the look around found, an object an
        // earlier goal found) is reported where it is; nothing else can have been found.
        Action::Report { object, known } => Ok(
            match known
                .and_then(|k| mem.objects.get(k))
                .filter(|o| o.class == goal.class)
            {
                Some(o) => StepEnd::Found(FoundObject {
                    name: object,
                    class: o.class.clone(),
                    pose: o.pos,
                    confidence: o.confidence,
                }),
                None => StepEnd::Replan(ReplanReason::NotFound { object }),
            },
        ),
    }
}

/// MOVE to a place of the plan, or (`entering`) into a placeholder whose room the plan
/// assumes, entering it. A target found unreachable is marked so.
fn go<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    to: &PlaceArg,
    pos: [f64; 2],
    entering: bool,
) -> Result<StepEnd, AgentError> {
    let from_room = mem.current_room();
    let goal = if entering {
        let here = body.at();
        entry_point(mem, here, pos, cx.tuning().enter_depth)
    } else {
        pos
    };
    if let Err(e) = body.go_to(mem, goal)? {
        if e.is_unreachable() {
            mem.mark_unreachable(to.target, to.pos, from_room);
        }
        return Ok(StepEnd::Replan(ReplanReason::ActionFailed(e)));
    }
    if entering {
        mem.last_target = None;
        enter(cx, mem, body, run, to, from_room)?;
    } else {
        mem.last_target = Some((to.target, pos));
    }
    Ok(StepEnd::Continue)
}

#[cfg(test)]
mod tests;
