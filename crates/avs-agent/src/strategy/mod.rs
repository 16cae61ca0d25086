//! The coverage strategies: the two baselines the benchmark compares the switching planner
//! with, and the same coverage as the planner's last resort. Both baselines use the same
//! robot, place map, view planning and detector as the planner, but no prior knowledge: no
//! conceptual map, no landmarks, no assumptions.
//!
//! * [`Strategy::Uninformed`] — the method of Sjöö et al. (`004`, §2–3) with a uniform prior
//!   over rooms: the nearest room (by path length on the known map) that is not yet covered is
//!   covered by view planning (CREATEVIEWCONES' greedy set cover over the room's points), its
//!   views processed in nearest-neighbour order; when every known room is covered, the nearest
//!   placeholder is explored to find more rooms.
//! * [`Strategy::Frontier`] — nearest-frontier exploration (Yamauchi 1997): the robot always
//!   goes to the nearest placeholder, and covers the room it stands in, the same way, the first
//!   time it finds itself in a room not yet covered.
//! * [`Strategy::Informed`] — a reference, not a method: told the floor of the room that holds
//!   the target ([`Goal::in_region`](crate::Goal::in_region)) and nothing else, it covers the
//!   known rooms that hold part of that floor, nearest first; while part of it is unseen it
//!   explores the placeholder minimising the path to it plus the straight line on to the
//!   room (A*'s estimate through the frontier); then it covers the rest as the uninformed
//!   strategy does. It covers as the planner's last resort does (two passes, furniture tops
//!   from a look-around), so that the planner's SPL can be read against what knowing the room
//!   buys.
//!
//! The same coverage loop is the switching planner's last resort: when the most promising plan
//! falls below the success threshold (or the plan budget is spent), the knowledge has been
//! wrong or the target is where it says little; with
//! [`AgentConfig::cover_before_giving_up`](crate::AgentConfig::cover_before_giving_up) the
//! agent then covers what its sessions have not looked at yet, and gives up only when nothing
//! is left (the reason names both). Unlike the baselines, the last resort has a conceptual
//! map, and it uses it: the next room to cover (or placeholder to explore) is the one with the
//! most chance of holding the target per metre of walking there and covering it — the index
//! rule of optimal search — chosen afresh after each batch of views, not the nearest (see
//! `coverage::likeliest_per_metre`). Nearest-first let a 30-room floor's corridor, where the
//! map puts almost no staplers, take 600 of the coverage's 1000 actions.
//!
//! Choices where the sources leave room: a detection counts only when the planner's own
//! verification step confirms it (a closer look centred on it,
//! [`verify`](crate::skills::verify)), so that all three strategies report on the same
//! evidence; a room counts as covered when `covered_share` (80%) of its points were in
//! processed views; its views are planned again for the points not yet covered (a room may
//! need more than the POMDP's [`AgentConfig::max_cones`](crate::AgentConfig::max_cones)) until
//! that holds or no view can see the rest; when no room is left uncovered and no placeholder
//! is left, known free space that no room holds (seen through a door never crossed) is
//! visited so that it becomes a room; then the search gives up. The heights looked at are the
//! floor and the tops of every surface class of the knowledge (the landmark classes anything
//! lies *on*: tables, counters, desks), not only those it puts the goal's class on — coverage
//! runs because the knowledge was wrong, and these are geometry of where small objects rest,
//! not where in the building they are. The planner's coverage also looks around in each room
//! it enters first and looks at the tops of the furniture it knows, including the part of a
//! top the laser never saw (it sees a table's edge: a stapler at the back of a table against
//! a wall lies at no known cell), with sight lines that pass over the furniture a point rests
//! on (`sight_clear`). On misleading bench floors 1–50, 7 of the 8 misses at c7306aa were such
//! objects: a stapler on a counter or table, a cereal box on a desk, a marker on a counter or
//! a table, most at the back. Views are planned with zoom where no unzoomed view reaches (the
//! floor, for a small object), and the budget is
//! [`AgentConfig::max_cover_actions`](crate::AgentConfig::max_cover_actions).

mod coverage;

pub(crate) use coverage::cover_all;

use crate::body::Body;
use crate::config::Strategy;
use crate::memory::Memory;
use crate::reason::GiveUpReason;
use crate::report::{Activity, FoundObject, Goal};
use crate::run::Run;
use crate::skills::Ctx;
use crate::AgentError;
use avs_robot::Robot;

/// The executive of the baselines: one coverage pass, no landmarks. The informed reference
/// covers as the planner's last resort does (`tuning.cover_passes` passes, looking around in
/// each room for the furniture whose tops it then looks at), so that its path is a reference
/// for the planner's, not a weaker searcher's.
pub(crate) fn baseline_loop<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    goal: &Goal,
    strategy: Strategy,
) -> Result<Result<FoundObject, GiveUpReason>, AgentError> {
    let (passes, look_around) = match strategy {
        Strategy::Informed => (cx.tuning().cover_passes, true),
        _ => (1, false),
    };
    body.with_activity(Activity::Coverage, |b| {
        cover_all(cx, mem, b, run, goal, strategy, passes, look_around)
    })
}
