//! The agent's settings: [`AgentConfig`] (what a user sets: budgets, thresholds, costs, the
//! strategy) and [`Tuning`] (the executive's geometric and statistical constants, each with
//! the reason for its value), checked once by [`AgentConfig::check`].

use crate::AgentError;
use avs_map::places::PlaceMapParams;
use avs_plan::continual::ContinualOptions;
use avs_pomdp::{DecisionRewards, SessionOptions};
use serde::Serialize;

/// Settings of the agent.
#[derive(Debug, Clone)]
pub struct AgentConfig {
    /// Place map parameters (place spacing, door widths).
    pub places: PlaceMapParams,
    /// Continual planner settings (search, success threshold, assumption bound, and which
    /// plan to start: `planner.objective`, by default the plan with the most success per
    /// unit of cost, `avs_plan::continual::Objective::Ratio`, or the paper's fixed R,
    /// `Objective::Fixed`). With the rates of `unfound_landmarks`, the fixed R = 1000 makes a
    /// 1 % gain in p worth 10 m and the robot wanders between rooms of similar promise.
    pub planner: ContinualOptions,
    /// Count the landmarks not found yet in a room's probability of holding the object, and
    /// all a room behind a placeholder is expected to hold (`002` §III-A's whole hierarchy;
    /// `avs_concepts::ConceptualMap::set_unfound_landmarks`). On by default, with the ratio
    /// objective that it needs not to wander (BENCHMARKS.md, issue 17 sessions: the whole
    /// hierarchy of a room; the sequential verifier). It was off while the fixed `count`
    /// verification rule accepted the look-alikes on the desks and counters it sends the
    /// robot to first.
    pub unfound_landmarks: bool,
    /// View-cone POMDP session settings.
    pub session: SessionOptions,
    /// Give up after this many plans — or after `plans_per_room` plans for every room the
    /// robot knows, when that is more ([`AgentConfig::plan_budget`]).
    pub max_plans: usize,
    /// Plans the budget grows by for every room the robot knows (0: the budget is
    /// `max_plans` whatever the building). A building is searched room by room: entering a
    /// room settles the assumption the plan made about it (one replan), searching it and its
    /// landmarks fails or finds (another), and a false alarm or a violated assumption in it
    /// asks for a third. The fixed budgets were set on six-room floors, where the robot comes
    /// to know about ten rooms (corridor segments and rooms split at doors count): 30 plans
    /// and 250 actions are 3 and 25 per room. Fixed, they stopped the planner in the tenth
    /// room of a thirty-room floor (BENCHMARKS.md, *Budgets that grow with the building*).
    pub plans_per_room: usize,
    /// Give up after this many executed actions (the plans' actions; the coverage has its own
    /// budget, `max_cover_actions`) — or after `actions_per_room` for every room the robot
    /// knows, when that is more ([`AgentConfig::action_budget`]).
    pub max_actions: usize,
    /// Actions the budget grows by for every room the robot knows (0: `max_actions`
    /// whatever the building); see `plans_per_room`.
    pub actions_per_room: usize,
    /// Actions the coverage may take (the baselines' whole search, or the planner's coverage
    /// before giving up): moves, explorations and views.
    pub max_cover_actions: usize,
    /// Detections below this confidence are ignored.
    pub min_confidence: f64,
    /// Detections that confirm something count only from this confidence: a verification
    /// look (closer, centred and zoomed on a sighting), and the agreeing sightings that make a
    /// landmark in a look-around.
    pub confirm_min_confidence: f64,
    /// The robot's radius, metres (for the agent's own path planning on the known map).
    pub robot_radius: f64,
    /// Cost of processing one view cone, in the POMDP's reward unit.
    pub process_cost: f64,
    /// Travel cost per metre, in the POMDP's reward unit.
    pub travel_cost_per_m: f64,
    /// Rewards of a DT session's declarations, in the same unit as `process_cost` and
    /// `travel_cost_per_m`.
    pub session_rewards: DecisionRewards,
    /// Discount factor of a DT session's POMDP, in (0, 1).
    pub session_discount: f64,
    /// Largest number of view cones per location.
    pub max_cones: usize,
    /// How the agent decides where to go and look.
    pub strategy: Strategy,
    /// When the switching planner would give up (the most promising plan below
    /// `planner.min_success`, or `max_plans` spent), first cover what its searches have not
    /// looked at, exploring the placeholders left, as the uninformed strategy does but the
    /// likeliest room or placeholder per metre first by the conceptual map (module
    /// `strategy`); give up only when nothing is left. The
    /// probabilities then only order the search: knowledge that puts the target in the wrong
    /// room costs path, not the target. `false` gives up at once, as the paper's planner does
    /// (`002` §III), and then also when no plan is worth its cost by the paper's own objective
    /// (`planner.give_up_unless_worth_it` is turned on: the best plan for cost(π) + R·(1 − p(π))
    /// has p(π)·R ≤ cost(π), so stopping, whose objective is R, is no worse). That test compares
    /// a plan with stopping, and stopping is the alternative only when giving up ends the
    /// search: with coverage after it the alternative is the coverage, which on bench floors
    /// finds less per metre than the planner's own improbable plans (BENCHMARKS.md, issue 17
    /// session "a plan worth its cost").
    pub cover_before_giving_up: bool,
    /// Every look around on entering a room also runs the detector of the class searched for
    /// (`skills::look_around`): a target in view of the room's door is verified and reported
    /// then, before the planner searches the room's landmarks and the room. `false` looks
    /// for landmarks only, as the paper's robot, whose object detector ran only in the view
    /// cones of SEARCHFOROBJECT (`002` §IV); the Fig. 3 scenarios re-enact that robot.
    pub goal_in_look_around: bool,
    /// What a wrong report costs the `sequential` verifier, in failed searches (each the
    /// planner's reward R, `planner.search.reward`); a rejected real target costs one, and so
    /// does a wrong landmark (never reported). A failed search can go on (a target rejected
    /// once is found again from farther away in most runs); a wrong report ends it with an
    /// answer that sends whoever acts on it to the wrong object. At least 1; 10 by default.
    pub wrong_report_price: f64,
    /// Seed of the verification planners' sampled look sequences (combined with the
    /// candidate's number in the search, so the same seed gives the same trace).
    pub verifier_seed: u64,
    /// Whether every look for small objects runs the zoom pipeline (Sjöö et al. `004` §3:
    /// attention, zoom windows, the three-step search, recognition) on robots that have it;
    /// `false` asks the robot's one-shot detector ([`avs_robot::Robot::process_view_cone`]).
    pub zoom_pipeline: bool,
    /// The zoom pipeline's settings (image geometry, image budget per look, the paper's factors).
    pub zoom: avs_view::zoom::ZoomConfig,
    /// What the robot's looks measurably do per class (e.g. the zoom pipeline, calibrated on
    /// the simulator's images): a class listed here is looked for within its measured range,
    /// and its view-cone sessions use its measured miss and false-alarm rates instead of the
    /// knowledge's `detection_range` and `sensor`. Empty: the knowledge's.
    pub measured_sensing: Vec<MeasuredSensing>,
    /// The executive's constants (geometry of looking, verification, exploration).
    pub tuning: Tuning,
}

/// How the agent decides where to go and look: the switching planner, or one of the two
/// baselines the benchmark compares it with (module `strategy` of this crate).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Strategy {
    /// The switching planner: assumptive continual planning over the conceptual map, view-cone
    /// POMDP sessions, indirect search on landmarks (Aydemir et al. 2011).
    #[default]
    Planner,
    /// No prior knowledge: rooms covered nearest-first by view planning (Sjöö et al., `004`).
    Uninformed,
    /// Nearest-frontier exploration, searching each room as it is found.
    Frontier,
    /// A reference, not a method: told which room holds the target
    /// ([`Goal::in_region`](crate::Goal::in_region): the room's floor and nothing else), it
    /// explores towards that room, covers it as the uninformed strategy covers a room, and
    /// falls back to the uninformed coverage if the target is not there. Its path is what a
    /// searcher who knew the room would drive: a reference for the others that is not the
    /// straight line of SPL (not a bound: its coverage can miss, as every strategy's can).
    Informed,
}

impl std::str::FromStr for Strategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "planner" => Ok(Self::Planner),
            "uninformed" => Ok(Self::Uninformed),
            "frontier" => Ok(Self::Frontier),
            "informed" => Ok(Self::Informed),
            _ => Err(format!(
                "unknown strategy `{s}`; expected planner, uninformed, frontier or informed"
            )),
        }
    }
}

impl std::fmt::Display for Strategy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Planner => "planner",
            Self::Uninformed => "uninformed",
            Self::Frontier => "frontier",
            Self::Informed => "informed",
        })
    }
}

impl Default for AgentConfig {
    fn default() -> Self {
        Self {
            places: PlaceMapParams::default(),
            planner: {
                let mut o = ContinualOptions::default();
                o.search.mode = avs_plan::Mode::Optimal;
                // An optimal plan not found in this many expansions (about a second) is not worth
                // the robot's waiting: the agent plans again in fast mode (greedy, h^FF). With
                // 200 000 a floor where every plan is improbable spent minutes planning.
                o.search.max_expansions = 50_000;
                // The paper's 0.01 gives up while unexplored rooms remain on floors with many
                // rooms: a plan into one unexplored room of several succeeds with ~0.01 (P(leads
                // to a kitchen) × P(counter) × P(object on it) × detection²). Give up only when
                // the best plan is well below that.
                o.min_success = 0.002;
                o.objective = avs_plan::continual::Objective::Ratio;
                o
            },
            unfound_landmarks: true,
            session: {
                // A smaller offline budget than the solver's default: a session over 24 cones
                // has 625 product states, and the online look-ahead refines the bounds anyway.
                let mut o = SessionOptions::default();
                o.offline.max_trials = 3;
                o.offline.init_iterations = 40;
                // Rooms have up to 24 cones: bound the session from below by sweeps over them.
                o.sweep_bounds = true;
                // A session is one search of the location, as SEARCHFOROBJECT's success model
                // (one pass at the detector's hit rate) says: each cone once, again only to
                // confirm a detection, in an order that counts the pass's travel (avs-pomdp
                // `rollout`). Under RTBSS over HSVI's loose bounds the sessions zigzagged
                // between the heaviest cones and made a second pass at the assumed prior:
                // travel between view cones was 53% of the bench's path.
                o.policy = avs_pomdp::SessionPolicy::OnePassRollout;
                o
            },
            max_plans: 30,
            plans_per_room: 3,
            max_actions: 250,
            actions_per_room: 25,
            // Covering a room for a small object takes many views: for a whiteboard marker on
            // the floor, about 50–70 zoomed views per office, so two passes over a floor of
            // seven rooms need about 800. 250 stopped the coverage after three or four rooms.
            max_cover_actions: 1000,
            // The detector's confidence is its detection probability at the estimated
            // geometry (at most 1 − FN = 0.8): at 0.5 a real object near the border of a
            // planned view or the far end of its range was dropped one look in three (the
            // uninformed baseline on bench floors 1–20: success 0.30 at 0.5, 0.55 at 0.3, 0.60
            // at 0.2). False alarms are not told apart by it (their confidence comes from the
            // same geometry); verification catches them.
            min_confidence: 0.2,
            // A verification look is centred on the sighting and made from inside the
            // recognition range, where a real object shows with confidence near 1 − FN = 0.8;
            // at 0.2 there, a look-alike on an office desk passed for the cerealbox. Landmarks
            // are large and seen well; faint sightings only split their clusters.
            confirm_min_confidence: 0.5,
            robot_radius: 0.25,
            process_cost: 1.0,
            travel_cost_per_m: 0.5,
            // The reference model's +10 / +5 / −20 (`viewcones2.POMDP`) were made for a few
            // cones: against the cost of processing and travelling between 24 cones, declaring
            // "absent" after one look was worth more than searching the room, and the planner
            // sent the robot back to the same room session after session. A found object is
            // worth 100 here (about 200 m of travel at 0.5 per metre), a right "absent" 20 and a
            // wrong declaration −50: a wrong "absent" only thins the room's rate (the planner
            // may come back) and a wrong "found" is caught by verification, so neither is the
            // disaster −20 against +10 makes it; with −200, one pass over the cones (which
            // leaves P(present) near 0.4 at a miss rate of 0.2) was never enough, and the
            // robot swept every room two or three times.
            session_rewards: DecisionRewards {
                found: 100.0,
                absent: 20.0,
                wrong: -50.0,
            },
            // With γ = 0.95 processing the cone the robot stands at forever costs only
            // −1 / (1 − γ) = −20, less than a wrong declaration: the session looked at one cone
            // until the step guard stopped it. At 0.99 that costs −100.
            session_discount: 0.99,
            max_cones: 24,
            strategy: Strategy::Planner,
            cover_before_giving_up: true,
            // On floors 1–40 of the 200-floor bench (seed 1) two thirds of a search's path
            // came after the robot first stood in the target's room; with the goal in the look
            // around the planner's SPL rose from 0.265 to 0.343 (BENCHMARKS.md, issue 17
            // session "the goal in the look around").
            goal_in_look_around: true,
            // Ten failed searches. At 1 (the old default) about one look-alike candidate in
            // 600 was accepted, 1–2 wrong reports per 200 bench floors; at 10 alone real
            // targets seen in fewer closer looks than the model's 1 − FN (looks centred on a
            // sighting 0.2–0.35 m off the object) were rejected more. With the closer looks
            // aimed at the best closer detection and earlier looks at a spot pooled
            // (`skills::verify`), 10 gave no wrong report on the five 200-floor benches with
            // success as at 1 in sum (BENCHMARKS.md, issue 17 session "earlier looks at a
            // spot"). A user who prefers a shorter search to a sure answer lowers it.
            wrong_report_price: 10.0,
            verifier_seed: 0,
            zoom_pipeline: false,
            zoom: avs_view::zoom::ZoomConfig::default(),
            measured_sensing: Vec::new(),
            tuning: Tuning::default(),
        }
    }
}

impl AgentConfig {
    /// Check every value; the error names the first field out of range and what is expected.
    pub fn check(&self) -> Result<(), AgentError> {
        const NON_NEGATIVE: &str = "a finite non-negative number";
        const POSITIVE: &str = "a finite positive number";
        const PROBABILITY: &str = "a probability in [0, 1]";
        let r = self.session_rewards;
        let t = &self.tuning;
        let finite_pos = |x: f64| x.is_finite() && x > 0.0;
        let finite_nonneg = |x: f64| x.is_finite() && x >= 0.0;
        let prob = |x: f64| (0.0..=1.0).contains(&x);
        let checks: [(&'static str, f64, bool, &'static str); 34] = [
            (
                "min_confidence",
                self.min_confidence,
                prob(self.min_confidence),
                PROBABILITY,
            ),
            (
                "confirm_min_confidence",
                self.confirm_min_confidence,
                prob(self.confirm_min_confidence),
                PROBABILITY,
            ),
            (
                "robot_radius",
                self.robot_radius,
                finite_nonneg(self.robot_radius),
                NON_NEGATIVE,
            ),
            (
                "process_cost",
                self.process_cost,
                finite_nonneg(self.process_cost),
                NON_NEGATIVE,
            ),
            (
                "travel_cost_per_m",
                self.travel_cost_per_m,
                finite_nonneg(self.travel_cost_per_m),
                NON_NEGATIVE,
            ),
            (
                "session_rewards.wrong",
                r.wrong,
                r.wrong.is_finite(),
                "a finite number",
            ),
            (
                "session_rewards.found",
                r.found,
                r.found.is_finite() && r.found > r.wrong,
                "a finite number above session_rewards.wrong",
            ),
            (
                "session_rewards.absent",
                r.absent,
                r.absent.is_finite() && r.absent > r.wrong,
                "a finite number above session_rewards.wrong",
            ),
            (
                "wrong_report_price",
                self.wrong_report_price,
                self.wrong_report_price.is_finite() && self.wrong_report_price >= 1.0,
                "a finite number of at least 1",
            ),
            (
                "session_discount",
                self.session_discount,
                self.session_discount > 0.0 && self.session_discount < 1.0,
                "a number in (0, 1)",
            ),
            (
                "tuning.min_open_area",
                t.min_open_area,
                finite_nonneg(t.min_open_area),
                NON_NEGATIVE,
            ),
            (
                "tuning.at_place",
                t.at_place,
                finite_pos(t.at_place),
                POSITIVE,
            ),
            (
                "tuning.detour_factor",
                t.detour_factor,
                t.detour_factor.is_finite() && t.detour_factor >= 1.0,
                "a finite number of at least 1",
            ),
            (
                "tuning.look_cluster",
                t.look_cluster,
                finite_pos(t.look_cluster),
                POSITIVE,
            ),
            (
                "tuning.unvisited_distance",
                t.unvisited_distance,
                finite_pos(t.unvisited_distance),
                POSITIVE,
            ),
            (
                "tuning.unvisited_spacing",
                t.unvisited_spacing,
                finite_pos(t.unvisited_spacing),
                POSITIVE,
            ),
            (
                "tuning.look_coverage",
                t.look_coverage,
                t.look_coverage > 0.0 && t.look_coverage <= 1.0,
                "a number in (0, 1]",
            ),
            (
                "tuning.enter_depth",
                t.enter_depth,
                finite_pos(t.enter_depth),
                POSITIVE,
            ),
            (
                "tuning.point_spacing",
                t.point_spacing,
                finite_pos(t.point_spacing),
                POSITIVE,
            ),
            (
                "tuning.pose_spacing",
                t.pose_spacing,
                finite_pos(t.pose_spacing),
                POSITIVE,
            ),
            (
                "tuning.cover_range_share",
                t.cover_range_share,
                t.cover_range_share > 0.0 && t.cover_range_share <= 1.0,
                "a number in (0, 1]",
            ),
            (
                "tuning.cover_fov_share",
                t.cover_fov_share,
                t.cover_fov_share > 0.0 && t.cover_fov_share <= 1.0,
                "a number in (0, 1]",
            ),
            (
                "tuning.los_slack",
                t.los_slack,
                finite_nonneg(t.los_slack),
                NON_NEGATIVE,
            ),
            (
                "tuning.assumed_prior",
                t.assumed_prior,
                prob(t.assumed_prior),
                PROBABILITY,
            ),
            (
                "tuning.confirm_radius",
                t.confirm_radius,
                finite_pos(t.confirm_radius),
                POSITIVE,
            ),
            (
                "tuning.verify_hits",
                t.verify_hits as f64,
                t.verify_hits >= 1 && t.verify_hits <= t.verify_looks,
                "at least 1 and at most tuning.verify_looks",
            ),
            (
                "tuning.sequential_max_looks",
                t.sequential_max_looks as f64,
                (1..=64).contains(&t.sequential_max_looks),
                "at least 1 and at most 64",
            ),
            (
                "tuning.verify_bearings",
                t.verify_bearings as f64,
                t.verify_bearings >= 1,
                "at least 1",
            ),
            (
                "tuning.cover_passes",
                t.cover_passes as f64,
                t.cover_passes >= 1,
                "at least 1",
            ),
            (
                "tuning.covered_share",
                t.covered_share,
                t.covered_share > 0.0 && t.covered_share <= 1.0,
                "a number in (0, 1]",
            ),
            (
                "tuning.cover_key_resolution",
                t.cover_key_resolution,
                finite_pos(t.cover_key_resolution),
                POSITIVE,
            ),
            (
                "tuning.p_min",
                t.p_min,
                t.p_min > 0.0 && t.p_min < 1.0,
                "a number in (0, 1)",
            ),
            (
                "tuning.look_min_sightings",
                t.look_min_sightings as f64,
                t.look_min_sightings >= 1,
                "at least 1",
            ),
            (
                "tuning.stuck_motions",
                t.stuck_motions as f64,
                t.stuck_motions >= 1,
                "at least 1",
            ),
        ];
        for (field, value, ok, expected) in checks {
            if !ok {
                return Err(AgentError::Config {
                    field,
                    value,
                    expected,
                });
            }
        }
        Ok(())
    }
}

/// The executive's constants: where the papers leave a number open, the value chosen and why.
/// The defaults are what every figure in BENCHMARKS.md was measured with.
#[derive(Debug, Clone, PartialEq)]
pub struct Tuning {
    /// Placeholders with less unknown open area behind them cannot hide a room and are
    /// ignored, m².
    pub min_open_area: f64,
    /// The robot stands at a place when within this distance of it, metres.
    pub at_place: f64,
    /// A waypoint whose motion is this many times longer than the straight line (plus 1 m)
    /// means the known map was wrong: the robot stops there.
    pub detour_factor: f64,
    /// Sightings of one class closer than this are one object, metres (the pose noise of a
    /// few metres' range is a few tenths of a metre; false alarms fall anywhere in the view).
    pub look_cluster: f64,
    /// Sightings (in overlapping views of one look-around) that make a landmark.
    pub look_min_sightings: usize,
    /// Known free space farther than this from every place is unvisited, metres.
    pub unvisited_distance: f64,
    /// Places (nearest first) an unvisited area may be attached to.
    pub attach_candidates: usize,
    /// Spacing of unvisited-area placeholders, metres.
    pub unvisited_spacing: f64,
    /// Share of a room a look-around from one place is taken to cover (the count evidence of
    /// `observe_objects` is thinned by it).
    pub look_coverage: f64,
    /// How far past the door a robot entering a placeholder stops, and how far it may then go
    /// on into the space beyond, metres.
    pub enter_depth: f64,
    /// Height of small objects searched in a room when the knowledge puts them on no
    /// landmark class, metres (table height plus a few centimetres).
    pub small_object_z: f64,
    /// Passes of the coverage before giving up: one view sees an object inside its planned
    /// coverage with about 0.6–0.8 (miss rate 0.2, less towards the image border), so one
    /// pass missed the target on about one floor in four; two miss it on about one in twelve.
    pub cover_passes: usize,
    /// Search heights closer than this are one (their middle), metres: from 1 m away, 0.1 m
    /// of height is under 6°, inside the margin the view planning keeps at the image border;
    /// two heights for a cereal box (0.89 and 1.04 m) doubled the view planning of the default
    /// run.
    pub height_step: f64,
    /// Spacing of the points of a room searched by view cones, metres.
    pub point_spacing: f64,
    /// Tilt limits beyond this (radians, 80°) count as this where the verification
    /// standpoint's distance is worked out (`|dz| / tan(limit)`, which vanishes towards
    /// straight down).
    pub verify_max_tilt: f64,
    /// Spacing of candidate view poses, metres.
    pub pose_spacing: f64,
    /// Looks a DT session may take beyond one per cone (second looks at detections).
    pub session_extra_looks: usize,
    /// Share of a class's detection range from the knowledge (from its near end) within which
    /// view planning counts a point as covered (a measured range counts whole: it ends where
    /// the detector finds the object half the time).
    pub cover_range_share: f64,
    /// Share of the camera's field of view in which view planning counts a point as covered.
    pub cover_fov_share: f64,
    /// Sight lines stop this short of the target point (furniture footprints are in the
    /// grid), metres.
    pub los_slack: f64,
    /// A point counts as resting on a surface down to this far below its top, metres (pose
    /// estimates of sightings are noisy in height too).
    pub surface_z_tolerance: f64,
    /// Slack around a landmark's footprint for detections "on" it, metres.
    pub on_slack: f64,
    /// Floor of the DT session's prior for an object the plan assumes in the location.
    pub assumed_prior: f64,
    /// A verifying look confirms a sighting when it sees the class this close to it, metres.
    pub confirm_radius: f64,
    /// Looks at most of the `count` verification rule.
    pub verify_looks: usize,
    /// Detections the `count` rule needs to confirm a sighting (within `verify_looks`).
    pub verify_hits: usize,
    /// Looks at most of the `sequential` verifier (the default one): it stops earlier once it
    /// is sure (about 99.8 % either way at the default prices), and decides on the belief it
    /// has when they are spent. 8: from a 1 % prior the knowledge's detector (hits 16 times
    /// likelier on an object, misses 4.75 times likelier on none) needs four or five hits;
    /// eight looks leave room for two or three misses on a real object.
    pub sequential_max_looks: usize,
    /// Sightings of a class where verification failed this many times are ignored from then
    /// on (a look-alike). One failure is not enough: a real object fails a verification one
    /// time in ten, and ignoring it for good lost targets for good (see the crate docs,
    /// "Look-alikes").
    pub rejections_to_ignore: usize,
    /// Bearings around a sighting tried as verification viewpoints.
    pub verify_bearings: usize,
    /// Guard on the number of DT decisions per session.
    pub max_dt_steps: usize,
    /// Give up when this many motions in a row failed without moving the robot (refused, or
    /// aborted where it stood): a robot that cannot move is told so at once instead of after
    /// the plan budget and a whole coverage of failed motions. 5: a blocked path fails one
    /// motion and the next plan goes elsewhere; five refusals in a row from different plans
    /// and targets are the robot, not the map.
    pub stuck_motions: usize,
    /// Probabilities from the conceptual map are kept at least this large (a posterior that
    /// rounds to nothing still allows a plan); an exact 0 (a rate of 0 in the knowledge, a
    /// class that cannot lead to the goal, a placeholder known to lead nowhere) stays 0 and
    /// the operator is not grounded.
    pub p_min: f64,
    /// The coverage counts a room as done when its processed views covered this share of its
    /// points.
    pub covered_share: f64,
    /// The coverage remembers points as covered on a grid of this resolution, metres.
    pub cover_key_resolution: f64,
    /// Known free space outside every room counts for the coverage when at least this far
    /// from every place, metres.
    pub outside_rooms_min: f64,
}

impl Default for Tuning {
    fn default() -> Self {
        Self {
            min_open_area: 1.0,
            at_place: 0.6,
            detour_factor: 3.0,
            look_cluster: 0.7,
            look_min_sightings: 2,
            unvisited_distance: 2.5,
            attach_candidates: 4,
            unvisited_spacing: 3.0,
            look_coverage: 0.8,
            enter_depth: 1.5,
            small_object_z: 0.8,
            cover_passes: 2,
            height_step: 0.2,
            point_spacing: 0.4,
            verify_max_tilt: 1.4,
            pose_spacing: 0.7,
            session_extra_looks: 3,
            cover_range_share: 0.8,
            cover_fov_share: 0.75,
            los_slack: 0.45,
            surface_z_tolerance: 0.1,
            on_slack: 0.3,
            assumed_prior: 0.8,
            confirm_radius: 0.6,
            verify_looks: 3,
            verify_hits: 2,
            sequential_max_looks: 8,
            rejections_to_ignore: 2,
            verify_bearings: 16,
            max_dt_steps: 60,
            stuck_motions: 5,
            p_min: 1e-6,
            covered_share: 0.8,
            cover_key_resolution: 0.1,
            outside_rooms_min: 1.5,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_configuration_passes_its_own_check() {
        assert!(AgentConfig::default().check().is_ok());
    }

    #[test]
    fn an_out_of_range_tuning_value_is_named_in_the_error() {
        let mut c = AgentConfig::default();
        c.tuning.verify_hits = 5;
        let e = c.check().unwrap_err().to_string();
        assert!(e.contains("tuning.verify_hits"), "{e}");
        let mut c = AgentConfig::default();
        c.tuning.cover_fov_share = 0.0;
        let e = c.check().unwrap_err().to_string();
        assert!(e.contains("tuning.cover_fov_share"), "{e}");
    }

    /// Shares found through `zoom`, measured at 0.25, 0.5, … m times the zoom (the
    /// calibration's distances) with `looks` looks each.
    fn shares(zoom: f64, found: Vec<f64>, looks: usize) -> FoundByDistance {
        FoundByDistance {
            zoom,
            distances: (1..=found.len()).map(|i| 0.25 * i as f64 * zoom).collect(),
            found,
            looks,
        }
    }

    /// Sensing of `class` measured at `ranges_by_zoom`, without kept shares.
    fn sensing(class: &str, ranges_by_zoom: Vec<(f64, [f64; 2])>) -> MeasuredSensing {
        MeasuredSensing {
            class: class.into(),
            detection_range: ranges_by_zoom[0].1,
            ranges_by_zoom,
            false_negative: 0.1,
            false_positive: 0.001,
            found_by_zoom: Vec::new(),
            repeat_correlation: 0.0,
        }
    }

    #[test]
    fn with_the_shares_kept_a_distance_is_looked_at_through_the_level_that_found_most_there() {
        let mut m = sensing(
            "cerealbox",
            vec![(1.0, [0.25, 2.45]), (2.0, [0.5, 3.42]), (4.0, [1.0, 7.14])],
        );
        // Without shares: the level that holds 1.25 m nearest its middle.
        assert_eq!(m.zoom_at(1.25), Some(1.0));
        // With them: zoom 4 found it at 1 and 2 m more often than zoom 1 or 2 did at 1.25 m.
        m.found_by_zoom = vec![
            shares(1.0, vec![1.0, 1.0, 0.95, 0.95, 0.9, 1.0], 20),
            shares(2.0, vec![1.0, 0.95, 0.8, 0.6], 20),
            shares(4.0, vec![0.95, 1.0, 1.0, 1.0], 20),
        ];
        assert_eq!(m.zoom_at(1.25), Some(4.0));
        // Where only one level reaches, that one.
        assert_eq!(m.zoom_at(0.4), Some(1.0));
        assert_eq!(m.zoom_at(5.0), Some(4.0));
    }

    #[test]
    fn a_looks_chance_to_find_is_the_share_measured_at_its_distance_through_the_nearest_level() {
        let m = MeasuredSensing {
            false_negative: 0.13,
            found_by_zoom: vec![
                shares(1.0, vec![0.9, 0.85, 0.55, 0.1], 0),
                shares(4.0, vec![0.9, 0.35, 0.05], 0),
            ],
            ..sensing(
                "whiteboardmarker",
                vec![(1.0, [0.25, 0.75]), (4.0, [1.0, 1.73])],
            )
        };
        let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() < 1e-12);
        // Between the measured distances: linear (zoom 4 measured at 1, 2 and 3 m).
        assert!(close(m.found_share(4.0, 1.5), 0.625));
        // Near the far end of zoom 4's range a look finds the marker about half the time,
        // far below the range's mean 1 − FN = 0.87.
        assert!(m
            .found_share(4.0, 1.73)
            .is_some_and(|p| (0.45..0.55).contains(&p)));
        // A zoom between levels reads the nearest level; outside the measured distances the
        // nearest measured share.
        assert!(close(m.found_share(3.3, 1.0), 0.9));
        assert!(close(m.found_share(1.0, 0.1), 0.9));
        assert!(close(m.found_share(1.0, 9.0), 0.1));
        // Shares of 20 looks each, by the rule of succession: 20 of 20 is 21 / 22, not 1.
        let mut counted = m.clone();
        counted.found_by_zoom[0].looks = 20;
        counted.found_by_zoom[0].found[0] = 1.0;
        assert!(close(counted.found_share(1.0, 0.25), 21.0 / 22.0));
        assert!(close(counted.found_share(1.0, 1.0), 3.0 / 22.0));
        // Without kept shares: none.
        let bare = MeasuredSensing {
            found_by_zoom: Vec::new(),
            ..m
        };
        assert_eq!(bare.found_share(1.0, 0.5), None);
    }

    #[test]
    fn the_zoom_for_a_distance_is_the_measured_level_that_holds_it_nearest_its_middle() {
        let m = sensing(
            "whiteboardmarker",
            vec![(1.0, [0.25, 0.75]), (2.0, [0.5, 1.0]), (4.0, [1.0, 2.0])],
        );
        assert_eq!(m.zoom_at(0.4), Some(1.0));
        // 0.7 m: inside zoom 1's range near its end, in the middle of zoom 2's.
        assert_eq!(m.zoom_at(0.7), Some(2.0));
        assert_eq!(m.zoom_at(1.6), Some(4.0));
        assert_eq!(m.zoom_at(0.1), None);
        assert_eq!(m.zoom_at(2.5), None);
        // The level comes with its measured range (where a verification look recognises).
        assert_eq!(m.level_at(1.6), Some((4.0, [1.0, 2.0])));
        assert_eq!(m.level_at(0.7), Some((2.0, [0.5, 1.0])));
        assert_eq!(m.level_at(2.5), None);
    }

    #[test]
    fn strategies_parse_from_and_print_as_their_names() {
        for s in [Strategy::Planner, Strategy::Uninformed, Strategy::Frontier] {
            assert_eq!(s.to_string().parse::<Strategy>(), Ok(s));
        }
        assert!("random".parse::<Strategy>().is_err());
    }
}

/// One class's sensing as measured (see [`AgentConfig::measured_sensing`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MeasuredSensing {
    /// The object class.
    pub class: String,
    /// The distances `[min, max]` (metres, zoom 1) at which one look finds the object at
    /// least half the time.
    pub detection_range: [f64; 2],
    /// The same at other zoom levels, `(zoom, [min, max])` (a zoomed look's range is not
    /// simply the zoom times the unzoomed one: a farther scene has more clutter).
    pub ranges_by_zoom: Vec<(f64, [f64; 2])>,
    /// P(a look misses the object | it is in view within the range).
    pub false_negative: f64,
    /// P(a look reports the class | nothing of it is in view).
    pub false_positive: f64,
    /// The shares found that the ranges were derived from, per zoom level: what one look
    /// through a level finds at each distance ([`Self::found_share`]). Empty for sensing
    /// stated without them; then every look in range finds the object at `1 −
    /// false_negative`.
    #[serde(default)]
    pub found_by_zoom: Vec<FoundByDistance>,
    /// The correlation of two looks' outcomes from one vantage point (the same standpoint,
    /// zoom and side of the object) when the object is there: 0 when a repeated look is a
    /// new draw, towards 1 when it repeats the first ([`Self::found_next`]).
    #[serde(default)]
    pub repeat_correlation: f64,
}

/// The share of looks through one zoom level that found the object, per distance: a
/// measurement of the zoom pipeline (`avs_eval::zoom_sensing`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FoundByDistance {
    /// The zoom of the looks' first image.
    pub zoom: f64,
    /// The distances looked from, metres (3-D, increasing).
    pub distances: Vec<f64>,
    /// The share of looks that found the object, per distance.
    pub found: Vec<f64>,
    /// The looks per distance the shares were measured with (0: not known).
    #[serde(default)]
    pub looks: usize,
}

impl FoundByDistance {
    /// The share found at `distance`: linear between the measured distances next to it, the
    /// nearest measured share outside them; `None` without measurements.
    pub fn at(&self, distance: f64) -> Option<f64> {
        let n = self.distances.len().min(self.found.len());
        if n == 0 || !distance.is_finite() {
            return None;
        }
        let (ds, fs) = (&self.distances[..n], &self.found[..n]);
        let k = ds.partition_point(|&d| d < distance);
        Some(if k == 0 {
            fs[0]
        } else if k == n {
            fs[n - 1]
        } else {
            let t = (distance - ds[k - 1]) / (ds[k] - ds[k - 1]);
            fs[k - 1] + t * (fs[k] - fs[k - 1])
        })
    }
}

impl MeasuredSensing {
    /// The zoom to look through at an object `distance` metres away (3-D): of the measured
    /// levels whose range holds the distance, the one that holds it nearest the middle of its
    /// range (where a look finds the object most often); `None` when no level reaches it.
    pub fn zoom_at(&self, distance: f64) -> Option<f64> {
        self.level_at(distance).map(|(z, _)| z)
    }

    /// The measured level [`Self::zoom_at`] picks for `distance`: its zoom and its range
    /// `[min, max]` (metres, where one look through it finds the object at least half the
    /// time). Of the levels whose range holds the distance, the one whose looks found the
    /// object most often at that distance ([`Self::found_share`]) — a look is taken to find
    /// the object, and the calibration says which zoom does best there; where the shares were
    /// not kept (or tie), the one that holds the distance nearest the middle of its range.
    pub fn level_at(&self, distance: f64) -> Option<(f64, [f64; 2])> {
        self.ranges_by_zoom
            .iter()
            .filter(|(_, [lo, hi])| (*lo..=*hi).contains(&distance) && hi > lo)
            .map(|&(z, [lo, hi])| {
                let share = self.found_share(z, distance).unwrap_or(0.0);
                let off_middle = (distance - 0.5 * (lo + hi)).abs() / (hi - lo);
                ((z, [lo, hi]), share, off_middle)
            })
            .min_by(|a, b| {
                b.1.total_cmp(&a.1)
                    .then(a.2.total_cmp(&b.2))
                    .then(a.0 .0.total_cmp(&b.0 .0))
            })
            .map(|(level, _, _)| level)
    }

    /// P(one look through zoom `zoom` finds the object `distance` metres away (3-D)), as
    /// measured at the level nearest `zoom` ([`FoundByDistance::at`]); `None` when the
    /// shares were not kept. A look near the far end of a level's range finds the object
    /// about half the time, not at the range's mean `1 − false_negative`. A share of `n`
    /// looks is read by the rule of succession, `(k + 1) / (n + 2)` for `k` found (the
    /// posterior mean under a uniform prior): 20 of 20 looks do not make a miss impossible
    /// (a share of unknown looks is read as it is).
    pub fn found_share(&self, zoom: f64, distance: f64) -> Option<f64> {
        let m = self.found_by_zoom.iter().min_by(|a, b| {
            (a.zoom - zoom)
                .abs()
                .total_cmp(&(b.zoom - zoom).abs())
                .then(a.zoom.total_cmp(&b.zoom))
        })?;
        let n = m.looks as f64;
        m.at(distance).map(|share| {
            if m.looks == 0 {
                share
            } else {
                (share * n + 1.0) / (n + 2.0)
            }
        })
    }

    /// P(the next look from a vantage point finds the object | it is there), after `hits` of
    /// `looks` earlier looks from that vantage point found it, when one look there finds it
    /// with probability `share` ([`Self::found_share`]): the vantage point's own chance is
    /// Beta-distributed around `share` with the measured
    /// [`repeat_correlation`](Self::repeat_correlation) ρ (α + β = 1/ρ − 1), and this is its
    /// posterior mean `(α + hits) / (α + β + looks)` — with ρ = 0, `share` whatever the
    /// earlier looks said; with ρ near 1, the earlier looks from there decide.
    pub fn found_next(&self, share: f64, hits: usize, looks: usize) -> f64 {
        let rho = self.repeat_correlation;
        if looks == 0 || rho.is_nan() || rho <= 0.0 {
            return share;
        }
        let c = (1.0 / rho.min(0.99) - 1.0).max(1e-6);
        (share * c + hits as f64) / (c + looks as f64)
    }
}

impl AgentConfig {
    /// The plan budget when the robot knows `rooms` rooms: `max_plans`, or `plans_per_room`
    /// per room when that is more. It grows as the robot finds rooms, and stays bounded by
    /// the building.
    ///
    /// ```
    /// let c = avs_agent::AgentConfig::default();
    /// assert_eq!(c.plan_budget(4), c.max_plans);
    /// assert_eq!(c.plan_budget(40), 40 * c.plans_per_room);
    /// ```
    pub fn plan_budget(&self, rooms: usize) -> usize {
        self.max_plans
            .max(self.plans_per_room.saturating_mul(rooms))
    }

    /// The action budget when the robot knows `rooms` rooms: `max_actions`, or
    /// `actions_per_room` per room when that is more (see [`AgentConfig::plan_budget`]).
    pub fn action_budget(&self, rooms: usize) -> usize {
        self.max_actions
            .max(self.actions_per_room.saturating_mul(rooms))
    }

    /// The measured sensing of `class`, when there is one.
    pub fn sensing(&self, class: &str) -> Option<&MeasuredSensing> {
        self.measured_sensing.iter().find(|m| m.class == class)
    }
}
