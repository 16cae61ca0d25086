//! Why the executive replans ([`ReplanReason`]) and why a search ends without the object
//! ([`GiveUpReason`]), as values. Their `Display` is the text of the plan trace (the `reason`
//! of a `plan_made` event, the `reason` of `gave_up`), so the trace reads as before while code
//! matches on the variants, not on the text.

use avs_plan::continual::{GiveUp, Replan};
use avs_robot::{ActionFailure, FailureReason};
use std::fmt;

/// A motion the body could not complete.
#[derive(Debug, Clone, PartialEq)]
pub enum MoveFailure {
    /// The robot reported a failure.
    Robot(ActionFailure),
    /// A waypoint cost far more than its straight line (the known map had no path there): the
    /// robot stopped after the detour.
    Detour {
        /// Where the motion was going.
        target: [f64; 2],
    },
}

impl MoveFailure {
    /// Whether the target cannot be reached (as opposed to a motion that broke off).
    pub fn is_unreachable(&self) -> bool {
        match self {
            Self::Robot(e) => e.reason == FailureReason::Unreachable,
            Self::Detour { .. } => true,
        }
    }
}

impl fmt::Display for MoveFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Robot(e) => write!(f, "action failed: {e}"),
            Self::Detour { target } => write!(
                f,
                "action failed: Unreachable: the known map has no path to ({:.2}, {:.2}); the robot stopped after a detour",
                target[0], target[1]
            ),
        }
    }
}

/// Why the executive makes a new plan.
#[derive(Debug, Clone, PartialEq)]
pub enum ReplanReason {
    /// The search's first plan.
    Initial,
    /// Every step ran, and the goal does not hold.
    PlanEnded,
    /// The monitor found the goal holds.
    GoalHolds,
    /// The continual planner's monitor asks for a new plan (a precondition failed, an
    /// assumption was contradicted or became unlikely).
    Monitor(Replan),
    /// The monitor could not check the plan against the world as now known.
    MapChanged(String),
    /// The world model refused a map update during the step.
    WorldModelRefused(String),
    /// A motion failed.
    ActionFailed(MoveFailure),
    /// A place of the plan is no longer on the map.
    GoneFromMap {
        /// The place's plan name.
        place: String,
    },
    /// A room of the plan is no longer a room.
    NoLongerARoom {
        /// The room's plan name.
        room: String,
    },
    /// An object of the plan is not one the agent knows.
    UnknownObject {
        /// The object's plan name.
        object: String,
    },
    /// The plan reports an object that was not found.
    NotFound {
        /// The object's plan name.
        object: String,
    },
    /// The plan has a step the executive does not execute.
    CannotExecute {
        /// The step's listing line.
        step: String,
    },
    /// The view-cone POMDP could not be set up.
    SessionFailed(String),
    /// A sighting a closer look did not confirm.
    NotConfirmed {
        /// The class.
        class: String,
        /// The view cone it was seen in.
        cone: usize,
    },
    /// A virtual object of the plan turned out to be a real one.
    Matched {
        /// The virtual object's plan name.
        virtual_object: String,
        /// Its class.
        class: String,
        /// The real object's plan name.
        object: String,
    },
    /// An object (not the goal) was found.
    FoundObject {
        /// Its class.
        class: String,
        /// Its plan name.
        object: String,
    },
    /// A search session found nothing; the location's probability was thinned.
    SearchedInVain {
        /// The class.
        class: String,
        /// The SEARCHFOROBJECT listing line.
        search: String,
        /// P(ObjectAt L) before.
        before: f64,
        /// P(ObjectAt L) after.
        after: f64,
    },
    /// A search made no progress: it looked at none of the location's points (no view cones, or
    /// none that sees a point), so the belief is unchanged. The search is not planned again
    /// until the location's known map grows.
    NoProgress {
        /// The class.
        class: String,
        /// The SEARCHFOROBJECT listing line.
        search: String,
        /// How many view cones there were.
        cones: usize,
    },
    /// The robot stands on no place of the map.
    OnNoPlace,
    /// The plan searches on an object that is not a landmark.
    NotALandmark {
        /// The object's plan name.
        object: String,
    },
}

impl fmt::Display for ReplanReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Initial => f.write_str("initial plan"),
            Self::PlanEnded => f.write_str("the plan ended without reaching the goal"),
            Self::GoalHolds => f.write_str("the goal holds"),
            Self::Monitor(r) => write!(f, "{r}"),
            Self::MapChanged(e) => write!(f, "the map changed under the plan ({e})"),
            Self::WorldModelRefused(e) => write!(f, "the world model refused an update: {e}"),
            Self::ActionFailed(m) => write!(f, "{m}"),
            Self::GoneFromMap { place } => write!(f, "{place} is no longer on the map"),
            Self::NoLongerARoom { room } => write!(f, "{room} is no longer a room"),
            Self::UnknownObject { object } => write!(f, "{object} is not a known object"),
            Self::NotFound { object } => write!(
                f,
                "{object} was not found, so its position cannot be reported"
            ),
            Self::CannotExecute { step } => write!(f, "the executive cannot execute `{step}`"),
            Self::SessionFailed(e) => write!(f, "the view-cone POMDP failed: {e}"),
            Self::NotConfirmed { class, cone } => write!(
                f,
                "the {class} seen in view cone {cone} was not confirmed by a closer look"
            ),
            Self::Matched {
                virtual_object,
                class,
                object,
            } => write!(f, "{virtual_object} matched to the real {class} {object}"),
            Self::FoundObject { class, object } => write!(f, "found {class} {object}"),
            Self::SearchedInVain {
                class,
                search,
                before,
                after,
            } => write!(
                f,
                "no {class} found by {search}; P(ObjectAt) {before:.3} -> {after:.3}"
            ),
            Self::NoProgress {
                class,
                search,
                cones,
            } => write!(
                f,
                "{search} made no progress: its {cones} view cones see none of the points where a {class} could be; not searched again until more of the room is known"
            ),
            Self::OnNoPlace => f.write_str("the robot is on no place"),
            Self::NotALandmark { object } => write!(f, "{object} is not a landmark"),
        }
    }
}

/// Why a search ended without reporting the object.
#[derive(Debug, Clone, PartialEq)]
pub enum GiveUpReason {
    /// The plan budget is spent.
    PlanBudget {
        /// Plans made.
        plans: usize,
        /// The goal class.
        class: String,
    },
    /// The action budget is spent.
    ActionBudget {
        /// Actions executed.
        actions: usize,
        /// The goal class.
        class: String,
    },
    /// The continual planner gives up: no plan clears the success threshold.
    Planner(GiveUp),
    /// The planner failed.
    PlannerFailed(String),
    /// The goal already holds (nothing to do).
    GoalAlreadyHolds,
    /// The coverage looked everywhere it could reach.
    Covered {
        /// How often every room was covered.
        passes: usize,
        /// The goal class.
        class: String,
    },
    /// The goal class is not in the knowledge.
    UnknownClass(String),
    /// The robot cannot move: motions in a row failed where it stood.
    CannotMove {
        /// Failed motions in a row.
        failures: usize,
        /// The robot's last refusal.
        last: String,
    },
    /// The planner would have given up for `planner`; the coverage then ended for `coverage`.
    AfterCoverage {
        /// Why the planner stopped.
        planner: Box<GiveUpReason>,
        /// Why the coverage stopped.
        coverage: Box<GiveUpReason>,
    },
}

impl fmt::Display for GiveUpReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::PlanBudget { plans, class } => {
                write!(f, "gave up after {plans} plans without finding a {class}")
            }
            Self::ActionBudget { actions, class } => {
                write!(
                    f,
                    "gave up after {actions} actions without finding a {class}"
                )
            }
            Self::Planner(g) => write!(f, "{g}"),
            Self::PlannerFailed(e) => write!(f, "the planner failed: {e}"),
            Self::GoalAlreadyHolds => f.write_str("the goal already holds"),
            Self::CannotMove { failures, last } => write!(
                f,
                "gave up: the robot cannot move ({failures} motions in a row failed where it stood; the last: {last})"
            ),
            Self::Covered { passes, class } => {
                let times = match passes {
                    1 => String::new(),
                    2 => " twice".to_string(),
                    n => format!(" {n} times"),
                };
                write!(
                    f,
                    "every reachable room was covered{times} and no placeholder is left: no {class} found"
                )
            }
            Self::UnknownClass(c) => write!(f, "unknown class {c}"),
            Self::AfterCoverage { planner, coverage } => write!(f, "{planner}; then {coverage}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_robot_failure_is_unreachable_only_when_the_robot_says_so() {
        let e = |r| MoveFailure::Robot(ActionFailure::new(r, "Unreachable in the text"));
        assert!(e(FailureReason::Unreachable).is_unreachable());
        assert!(!e(FailureReason::ExecutionFailed).is_unreachable());
        assert!(MoveFailure::Detour { target: [1.0, 2.0] }.is_unreachable());
    }

    #[test]
    fn reasons_read_as_the_trace_has_always_written_them() {
        let m = MoveFailure::Robot(ActionFailure::new(FailureReason::Unreachable, "door shut"));
        assert_eq!(m.to_string(), "action failed: Unreachable: door shut");
        let r = ReplanReason::SearchedInVain {
            class: "mug".into(),
            search: "SEARCHFOROBJECT mug IN room1 new-object1".into(),
            before: 0.5,
            after: 0.125,
        };
        assert_eq!(
            r.to_string(),
            "no mug found by SEARCHFOROBJECT mug IN room1 new-object1; P(ObjectAt) 0.500 -> 0.125"
        );
        let g = GiveUpReason::AfterCoverage {
            planner: Box::new(GiveUpReason::PlanBudget {
                plans: 30,
                class: "mug".into(),
            }),
            coverage: Box::new(GiveUpReason::Covered {
                passes: 2,
                class: "mug".into(),
            }),
        };
        assert_eq!(
            g.to_string(),
            "gave up after 30 plans without finding a mug; then every reachable room was covered twice and no placeholder is left: no mug found"
        );
    }
}
