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
    /// Whoever started the search asked it to stop ([`crate::TraceSink::stop_requested`]).
    Cancelled,
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
    /// The search gave up for `reason`, and what stood in its way: the cause named (issue 18).
    Hindered {
        /// Why the search stopped.
        reason: Box<GiveUpReason>,
        /// What stood in its way.
        by: Hindrances,
    },
    /// The planner would have given up for `planner`; the coverage then ended for `coverage`.
    AfterCoverage {
        /// Why the planner stopped.
        planner: Box<GiveUpReason>,
        /// Why the coverage stopped.
        coverage: Box<GiveUpReason>,
    },
}

/// The actions of a search that failed: how many, of how many, and the last failure.
#[derive(Debug, Clone, PartialEq)]
pub struct FailedActions {
    /// Actions that failed.
    pub failed: usize,
    /// Actions executed.
    pub actions: usize,
    /// The last failed action and its failure, as the trace says them.
    pub last: String,
}

/// What stood in the way of a search that gave up: the causes a give-up names.
#[derive(Debug, Clone, PartialEq)]
pub struct Hindrances {
    /// Closed doors that cut the robot off from space it could not search, by the robot's
    /// names, with the centres of their openings: doors last seen closed with known free space
    /// the robot can reach 1 m from the door on one side, and none it can reach on the other.
    pub closed_doors: Vec<(String, [f64; 2])>,
    /// The actions of the search that failed, when any did.
    pub failed_actions: Option<FailedActions>,
    /// Sightings of the goal's class that a closer look did not confirm (false alarms,
    /// look-alikes).
    pub unconfirmed: usize,
    /// The goal's class.
    pub class: String,
}

impl Hindrances {
    /// Whether nothing stood in the way.
    pub fn is_empty(&self) -> bool {
        self.closed_doors.is_empty() && self.failed_actions.is_none() && self.unconfirmed == 0
    }
}

impl fmt::Display for Hindrances {
    /// Each cause as `; …`, to follow the reason it explains.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if !self.closed_doors.is_empty() {
            let names: Vec<String> = self
                .closed_doors
                .iter()
                .map(|(name, at)| format!("{name} at ({:.2}, {:.2})", at[0], at[1]))
                .collect();
            let (door, cuts) = if self.closed_doors.len() == 1 {
                ("door", "cuts")
            } else {
                ("doors", "cut")
            };
            write!(
                f,
                "; the closed {door} {} {cuts} the robot off from space it could not search",
                names.join(", ")
            )?;
        }
        if let Some(a) = &self.failed_actions {
            write!(
                f,
                "; {} of {} actions failed (the last: {})",
                a.failed, a.actions, a.last
            )?;
        }
        let class = &self.class;
        match self.unconfirmed {
            0 => Ok(()),
            1 => write!(
                f,
                "; 1 sighting of a {class} was not confirmed by a closer look"
            ),
            n => write!(
                f,
                "; {n} sightings of a {class} were not confirmed by a closer look"
            ),
        }
    }
}

impl GiveUpReason {
    /// This reason with what stood in the search's way: the closed doors that cut the robot
    /// (at `at`) off from space it could not search, the actions that failed, and the sightings of the
    /// goal's `class` that a closer look did not confirm (those after the first
    /// `rejected_before` of the memory's rejected sightings: the search's own). Unchanged when
    /// nothing did, or when the search did not fail (the goal already held, the class is
    /// unknown); a robot that cannot move names its failures itself.
    pub(crate) fn hindered(
        self,
        mem: &crate::memory::Memory,
        at: [f64; 2],
        failed_actions: Option<FailedActions>,
        class: &str,
        rejected_before: usize,
    ) -> Self {
        if matches!(self, Self::GoalAlreadyHolds | Self::UnknownClass(_)) {
            return self;
        }
        let by = Hindrances {
            closed_doors: mem
                .closed_doors_cutting_off(at)
                .into_iter()
                .map(|d| (d.name.clone(), [d.x, d.y]))
                .collect(),
            failed_actions: failed_actions.filter(|_| !self.cannot_move()),
            unconfirmed: mem
                .rejected
                .iter()
                .skip(rejected_before)
                .filter(|r| r.class == class)
                .count(),
            class: class.to_string(),
        };
        if by.is_empty() {
            self
        } else {
            Self::Hindered {
                reason: Box::new(self),
                by,
            }
        }
    }

    /// What stood in the way of the search, when the reason names it.
    pub fn hindrances(&self) -> Option<&Hindrances> {
        match self {
            Self::Hindered { by, .. } => Some(by),
            _ => None,
        }
    }

    /// Whether the search gave up because the robot cannot move (at any level of the reason).
    pub fn cannot_move(&self) -> bool {
        match self {
            Self::CannotMove { .. } => true,
            Self::Hindered { reason, .. } => reason.cannot_move(),
            Self::AfterCoverage { planner, coverage } => {
                planner.cannot_move() || coverage.cannot_move()
            }
            _ => false,
        }
    }
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
            Self::Cancelled => f.write_str("the search was cancelled"),
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
            Self::Hindered { reason, by } => write!(f, "{reason}{by}"),
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

    #[test]
    fn a_hindered_give_up_names_each_cause_after_the_reason() {
        let reason = || {
            Box::new(GiveUpReason::Covered {
                passes: 1,
                class: "mug".into(),
            })
        };
        let by = Hindrances {
            closed_doors: vec![("door_kitchen".into(), [6.05, 2.6])],
            failed_actions: Some(FailedActions {
                failed: 3,
                actions: 40,
                last: "MOVE placeholder2: action failed: Unreachable: no path".into(),
            }),
            unconfirmed: 2,
            class: "mug".into(),
        };
        let g = GiveUpReason::Hindered {
            reason: reason(),
            by: by.clone(),
        };
        assert_eq!(
            g.to_string(),
            "every reachable room was covered and no placeholder is left: no mug found; \
             the closed door door_kitchen at (6.05, 2.60) cuts the robot off from space it could \
             not search; 3 of 40 actions failed (the last: MOVE placeholder2: action failed: \
             Unreachable: no path); 2 sightings of a mug were not confirmed by a closer look"
        );
        assert_eq!(g.hindrances(), Some(&by));
        assert!(!g.cannot_move());
        let two_doors = GiveUpReason::Hindered {
            reason: reason(),
            by: Hindrances {
                closed_doors: vec![("a".into(), [0.0, 0.0]), ("b".into(), [1.0, 0.0])],
                failed_actions: None,
                unconfirmed: 0,
                class: "mug".into(),
            },
        };
        assert!(two_doors
            .to_string()
            .ends_with("; the closed doors a at (0.00, 0.00), b at (1.00, 0.00) cut the robot off from space it could not search"));
        let stuck = GiveUpReason::AfterCoverage {
            planner: reason(),
            coverage: Box::new(GiveUpReason::CannotMove {
                failures: 5,
                last: "drive fault".into(),
            }),
        };
        assert!(stuck.cannot_move());
    }
}
