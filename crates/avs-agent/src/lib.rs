//! # avs-agent
//!
//! The agent of avs: the switching planner's executive ([`Agent`], Aydemir et al. 2011, `002`
//! §II-A) over a robot behind the [`Robot`] trait (crate `avs-robot`, re-exported here), the
//! agent's [`world_model`] (place map and conceptual map in step) and the plan [`trace`]. A
//! real robot implements [`Robot`] with its own drivers; the simulator (`avs-sim`) implements
//! it with the knowledge file's sensor models; [`ScriptedRobot`] is a test double. The agent
//! never reads ground truth: everything it learns comes through the trait, as a real robot
//! would report it (its pose estimate, the laser map, detections with estimated poses and
//! confidences, and action outcomes, including failures with a reason).
//!
//! ## Where things live
//!
//! | module | what it holds |
//! |---|---|
//! | [`executive`] | [`Agent`]: the loop that plans, executes, monitors and replans |
//! | `memory` | what the agent knows between goals: world model, laser map, placeholders under stable names, found objects, view cones, rejected sightings; room and path queries; the sync with the map |
//! | `body` | the only code that moves the robot, points the camera and reads the laser map |
//! | `binding` | the planning problem built from memory, plan names ⇄ typed values, plan steps read once into typed actions, the domain check at [`Agent::new`], the domain's functions from the conceptual map |
//! | `skills` | one module per skill: look-around, enter, view planning (CREATEVIEWCONES), the view-cone session (SEARCHFOROBJECT), verification |
//! | `strategy` | the coverage: the two baselines and the planner's last resort |
//! | [`config`] | [`AgentConfig`], [`Strategy`], [`Tuning`] (every constant of the executive, with its reason) |
//! | [`reason`] | [`ReplanReason`], [`GiveUpReason`]: why it replans, why it gives up |
//! | [`report`], [`trace`] | what a search returns; the plan trace as events, text and JSON lines |
//! | [`beliefs`] | what the agent believes now (rooms, placeholders, doors, objects, P(ObjectAt L)), as plain data |
//!
//! One call per goal: [`Agent::search`] keeps the maps current from robot feedback, asks the
//! assumptive continual planner (`avs-plan`) for the plan minimising cost(π) + R·(1 − p(π)),
//! executes it step by step, runs a view-cone POMDP session (`avs-pomdp`) on every
//! SEARCHFOROBJECT, monitors the rest of the plan after every step and replans with the reason,
//! and, when no plan's success probability clears the threshold, covers what its searches have
//! not looked at before it gives up. The agent keeps its maps between goals.
//!
//! ```
//! use avs_agent::{Agent, AgentConfig, Camera, Detection, Goal, Point3, Pose2D, ScriptedRobot};
//! use avs_map::grid::OccupancyGrid;
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let knowledge: avs_format::knowledge::Knowledge =
//!     avs_format::load_yaml(&root.join("knowledge/office.yaml")).unwrap();
//! let domain = avs_plan::domain::Domain::load(&root.join("domains/object_search.yaml")).unwrap();
//! // A 4 m × 3 m room the laser knows whole, with a cereal box on the floor in a corner.
//! let mut map = String::from("##########\n");
//! for _ in 0..6 {
//!     map.push_str("#........#\n");
//! }
//! map.push_str("##########");
//! let grid = OccupancyGrid::from_ascii(&map, 0.5, [0.0, 0.0]).unwrap();
//! let mut robot = ScriptedRobot::new(grid, Pose2D::new(1.25, 1.25, 0.0), Camera::default());
//! robot.place(Detection {
//!     class: "cerealbox".into(),
//!     pose: Point3 { x: 3.6, y: 2.6, z: 0.14 },
//!     confidence: 0.8,
//! });
//! let mut agent = Agent::new(domain, knowledge, AgentConfig::default()).unwrap();
//! let report = agent.search(&mut robot, Goal::find("cerealbox")).unwrap();
//! let found = report.found.expect("the room is covered and the box verified");
//! assert!(found.pose.planar_distance(3.6, 2.6) < 0.1);
//! print!("{}", avs_agent::trace::render_text(&report.trace));
//! ```
//!
//! ## Design choices
//!
//! * **Camera requests are view cones.** A view cone (Aydemir et al. 2011, §I-A: a sensing
//!   action `s(x_c, y_c, z_c, p, t, f, a)`) is given by the robot pose from which it is taken
//!   and the camera's pan, tilt and zoom ([`ViewCone`]); the camera height is the robot's own
//!   ([`Robot::camera`]). Zoom divides the fields of view and multiplies the detection
//!   distances (Sjöö, Gálvez López et al., §2.1.3 and §3.4 eq. 1).
//! * **Places are the agent's.** The robot moves to metric poses; the agent maps its places to
//!   poses. A robot that cannot reach a pose reports [`FailureReason::Unreachable`].
//! * **Failures are outcomes, not errors.** Every action returns an [`ActionResult`]; a failed
//!   action says why ([`ActionFailure`]) so the agent can monitor and replan.
//! * **Map updates are whole grids.** [`MapUpdate`] carries the robot's current laser map as an
//!   [`OccupancyGrid`](avs_map::grid::OccupancyGrid) plus how many cells became known since
//!   the previous update, so an agent can skip re-segmenting when nothing changed.
//!
//! ### Executive choices where the paper is vague
//!
//! * **Planning problem from the maps.** Places of the place map are `place<N>` (node index),
//!   door places belong to their neighbouring room of smallest id; placeholders get stable names
//!   `placeholder<K>` (matched by position within 1 m between map updates; those with less than
//!   1 m² of open space around them, unknown or seen but unvisited, are ignored); rooms are `room<id>` with category
//!   `unknown` (categories stay probabilistic); found objects are `object<K>` with
//!   `found = yes`. Explored placeholders stay in the problem with `leads-to` set to the room they
//!   led to (or `none`), so the monitor can confirm or contradict ASSUME-LEADS-TO-ROOM. Only the
//!   classes that can lead to the goal (its own, and the landmarks it may lie on or in,
//!   transitively) are labels, and only found objects of those classes (and what they lie on)
//!   are objects: nothing else can take part in a plan for the goal, and on 30-room floors the
//!   other objects were most of what each plan grounded.
//! * **Probabilities** come from the conceptual map: P_category(placeholder) for
//!   `p-leads-to-room`, the room posterior for `p-category`, P(n ≥ 1) = 1 − e^{−λ} per category
//!   for `p-object-in`/`p-object-on`/`p-object-inside` (Aydemir et al. 2011, §III-A, eq. 1–2; rates thinned by
//!   failed searches). With `AgentConfig::unfound_landmarks` a room's rate is that of its
//!   whole hierarchy, as §III-A adds the λ of a location and its subordinate locations: its
//!   open space, the landmarks found in it, and the landmarks not found yet (each landmark
//!   class's expected unfound instances, thinned by the looks that counted that class, each
//!   holding the object with 1 − e^{−ν}; see `avs_concepts::Model::unseen_room_rates`); a
//!   room behind a placeholder then holds a cereal box with 0.58 with the shipped knowledge,
//!   not the 0.095 of its open space alone. On by default, with the planner's ratio objective
//!   (`avs_plan::continual::Objective::Ratio`, also the default); BENCHMARKS.md has both
//!   measured, and `unfound_landmarks = false` with the `fixed` objective is the paper's model.
//!   1 − false-negative rate for `p-detect` and `p-detect-in`. A search of a
//!   room that made no progress — no view cone saw any of its points, so nothing was learnt and
//!   the belief is unchanged — is a monitored failure ([`ReplanReason::NoProgress`]): its cones
//!   are dropped and `p-detect-in` of that class and room is 0 until the room's known map grows
//!   (more known cells can give cones that see something), so the next plan differs instead of
//!   repeating the same search until the plan budget runs out. A landmark searched in vain for
//!   the goal class is left out of later problems (the domain's `p-object-on` names classes, not
//!   instances; one left out after a search ON it is left out for a search IN it too, and the
//!   other way round). Only the goal's class and the landmark classes it lies on or in
//!   (transitively, with a positive `on` or `in` rate in some category) may be assumed to
//!   exist; the others get probability 0
//!   and are not grounded. An assumed mug cannot help to find a cereal box, but free assumptions
//!   with p ≈ 0.5 barely raise the objective when every plan is unlikely, so the optimal search
//!   expanded every subset of them: on the default office search the hard plans took ~1800
//!   expansions with them and ~50–100 without, the same plans.
//! * **Searches are priced by the views they will take** (`skills::views::price_searches`).
//!   The paper gives SEARCHFOROBJECT a cost but not its value; a flat one (20 for a room, 5
//!   for a landmark) made a corridor's 24 cones and a kitchenette's 5 the same price, and the
//!   office table beside the robot a better search per metre than the kitchen down the
//!   corridor (Fig. 3(b) searched office2 first on all three layouts). Before each plan every
//!   known room and every known landmark's top is priced, for each class that can lead to the
//!   goal, by the views the next CREATEVIEWCONES there would plan (for the points not looked
//!   at yet, as it plans them): `process_cost` per view, in metres at `travel_cost_per_m`,
//!   plus the walk between their standpoints, nearest next (the domain's `search-cost-in` and
//!   `search-cost-on`). `p-detect-in` is the detector's hit rate times the share of the
//!   room's points those views cover (a corridor covered to 86 % by its 24 capped cones is
//!   searched with 0.86 × 0.8). A room behind a placeholder, not known yet, is priced as the
//!   views of an empty square room of the knowledge's `placeholder.room_area_m2` (the room a
//!   placeholder is expected to lead to; planned over at most 100 m², a larger one seeing a
//!   share smaller by the areas), and searched with the share of it they cover; a
//!   known room no view sees yet (a few cells seen through its door) as such a room too; a
//!   landmark's top no standpoint sees yet keeps the flat 5. (With the share left out for
//!   rooms not known yet, a whiteboard marker's search on a 30-room floor went from new room
//!   to new room, each fully credited, searching only their tables, for 1214 m.) A price is computed again only when what it depends on changed: the room's known
//!   cells, its points looked at for the class, its known landmarks (for a landmark's top,
//!   those of its room). A search *inside* a landmark keeps the flat 5: its points are a
//!   square over the landmark's longest side at each level (a found landmark has no
//!   orientation), half of it in the wall behind a cupboard, and priced by that view plan a
//!   1.8 m cupboard's interior cost 18–27 m for views covering half of it — more than the
//!   kitchenette around it. Pricing it waits for landmarks with a footprint.
//! * **ENTER a placeholder** = drive towards it and stop 1.5 m past the last door hypothesis
//!   on the way that the robot has never been through (`executive::entry_point`; past a door
//!   it came through, a corridor's far end would be filed as explored from its first metre);
//!   go on 1.5 m into the space beyond (on a short known
//!   path) only where that reveals at least `min_open_area` of unknown space, and turn around.
//!   The unknown space a point reveals is `avs_map::explore::new_area`'s polar integral over
//!   the rays, not a count of the cells they touch: counted in cells, a shadow behind a desk
//!   grew with the map's cell size and the same office sent the robot on at 0.25 m cells and
//!   not at 0.125 m (`avs-eval/tests/resolution.rs`).
//!   A placeholder is a frontier — where the laser, looking in from outside, last saw free
//!   space, often the room's far wall — and a robot a step inside the door sees the room
//!   (laser all around, the look-around's pan). The first version drove to the frontier, on
//!   into the space beyond, and then visited up to three of the new room's own frontiers
//!   before looking around, and walked back out of the room's far end. Entering at the door,
//!   on 200 bench floors the mean exploration path fell 68 → 54 m and SPL rose 0.168 → 0.221
//!   (success 0.980 either way; BENCHMARKS.md). The room's own frontiers are placeholders like
//!   any other, for the planner to weigh.
//! * **A run of MOVE steps is a route.** The plan's MOVEs follow the place graph, whose edges
//!   join places in the order the robot first drove between them, so the route from one room
//!   to the next may pass the place where the search started, metres off the straight way (and
//!   where places fall, and so how far, depends on the grid). Nothing is done at the places
//!   between, so a MOVE followed by more MOVEs drives along the shortest known path to the
//!   run's last target and ends where that path passes its own place; the plan is monitored
//!   there as after any step (`executive::passing_point`). On 200 bench floors SPL went 0.161 →
//!   0.168. Goals are reached on their own side of a wall: a goal the robot cannot stand on
//!   snaps to the nearest cell it can through free space, not in a straight line
//!   (`avs_map::nav::Traversability::nearest_ok`); a placeholder just inside a kitchen, nearer
//!   the robot's radius to the wall than it may stand, used to snap into the corridor behind
//!   the wall at 0.25 m cells (not at 0.125 m), and the robot never entered the kitchen.
//! * **Looking around** on entering a room: a pan over the full circle for the landmark
//!   classes, at the tilts that hold every landmark the robot can see in the central half of
//!   an image (`skills::look_around::look_tilts`, the tilt rule of `004` §2.1.5 over the
//!   elevations of the landmark classes' centres); new landmarks seen in the same room become in/on locations, and the
//!   counts of instances no earlier look around counted are object-count evidence on the
//!   room's category with a coverage of 0.8 (eq. 1 thinned, and thinned again by the earlier
//!   looks: `avs_concepts`' *Object counts*). A sighting is in the same room when the sight
//!   line crosses no door hypothesis and the floor where it leaves the sighting (the first
//!   known free cell back towards the robot) is the robot's room: a counter seen over a table
//!   is, one seen through a doorway is not. (A sight line checked on the planar map, where the
//!   table is an obstacle, took the counter for one in another room and the kitchen for a
//!   corridor.) A landmark stands on the floor and blocks the laser: a sighting where the
//!   laser map shows open floor all around (every cell within half the sighting cluster's
//!   radius known free) is a false alarm, however often seen. On the 200 bench floors of
//!   seed 1, 132 of the 794 landmarks the look-arounds confirmed in the robot's room were
//!   false alarms, half of them on open floor; the rule drops those and 2 real ones (centres
//!   estimated 0.7 m off), and mean SPL rose 0.254 → 0.262 (BENCHMARKS.md). Most of the
//!   other false ones lie at or beyond a wall, where the planar map cannot tell a wall from
//!   a counter standing at it.
//! * **Search IN a landmark** (`002` §II-B.1's related space L_o, the `in` rates of the
//!   knowledge): `ASSUME-OBJECT-EXISTS l IN lm lc c`, `CREATEVIEWCONES l IN lm` and
//!   `SEARCHFOROBJECT l IN lm o` on a found landmark, with the cones planned over a grid of its
//!   footprint at the centre heights of its levels (`skills::views`: the paper names the
//!   interior but not its levels; a level every 0.4 m from the floor is our choice). The
//!   simulated camera sees into a landmark as into an open shelf (no doors to open). With the
//!   `in` rates relevant the planner has more hypotheses to chase; on 50 bench floors success
//!   stayed 1.00, SPL went 0.097 → 0.095 and the mean path 208 → 230 m.
//! * **SEARCHFOROBJECT** runs a closed-loop view-cone POMDP session (`002` §II-A.2) over the
//!   cones of CREATEVIEWCONES (greedy coverage, Sjöö et al. `004` §2.1, weighted: the most new
//!   points per unit of `process_cost` plus `travel_cost_per_m` × the walk from the nearest
//!   standpoint already chosen, or the robot — the paper's greedy counts views alone and put a
//!   room's cones on 6–8 standpoints; on 200 bench floors the weighting took the view-cone
//!   travel from 103 to 62 m per run and SPL from 0.109 to 0.147 — with line of sight on
//!   the known map stopping short of furniture footprints, or, for a point resting on known
//!   furniture, where the line reaches the disc its footprint may cover: the camera looks over
//!   a table's edge onto its top — a 2½-D sight line, our choice, the papers' maps are
//!   planar). A landmark's top or interior is looked at from standpoints in the room whose
//!   floor surrounds it (`Memory::room_around`): the disc reaches through the wall behind a
//!   counter standing against it, and a standpoint in the next room cost a walk out and back
//!   for a view that saw nothing. A room's points are its known cells on a
//!   lattice at the class's search heights, and the tops of the landmarks found in it: a laser
//!   sees a table's edge, not the cells under it, which stay unknown, so without them a room
//!   search never looked at what lies on its furniture, and a cerealbox a table search had
//!   missed was not looked at again. A table the look around missed has a top too: the
//!   room's *pockets* (`avs_map::pockets`: unknown space walled in by the room alone and no
//!   larger than twice the knowledge's largest landmark footprint, nor wider than its diagonal)
//!   are searched at the
//!   surfaces' heights and seen over their rim as the top of the lowest surface class; before,
//!   Fig. 3(f) with seed 3 searched office2 three times around the unreported table that held
//!   the marker and gave up. The prior P(ObjectAt L) is spread
//!   uniformly over the location's points the cones cover (spread over all points, a room
//!   covered to 40% was declared empty after one look, hardly thinned, and searched again and
//!   again until the plan budget ran out); for an object the plan assumes, it is floored at 0.8
//!   (the plan runs the session because it assumes the object there). A failed search thins the
//!   location's rate by q = (1 − FN) × covered share. View planning counts a point as covered
//!   only in the central 75% of the image (towards the border the detector's confidence falls)
//!   and within the nearer 80% of the class's detection range; on a landmark it tries poses
//!   every 0.35 m instead of 0.7 m. The session's declarations are worth
//!   +100 (found), +20 (absent) and −50 (wrong) with γ = 0.99, not the reference model's
//!   +10 / +5 / −20 with γ = 0.95: with those a room of 24 cones was declared empty after one
//!   look, and at γ = 0.95 looking at the same cone forever (−20) beat the risk of a wrong
//!   declaration. A wrong "absent" only thins the room's rate and a wrong "found" is caught by
//!   verification, so the penalty is moderate: with −200 one pass over a room (which leaves
//!   P(present) near 0.4) was never enough. A session is one search of the location, as
//!   SEARCHFOROBJECT's success model (one pass at the detector's hit rate) says: each cone is
//!   processed once, and again only to confirm a detection there; "found" may be declared only
//!   where the last look detected; the planner decides whether the location deserves another
//!   pass. The session decides by a two-step expectimax whose leaves are the exact value of a
//!   nearest-neighbour pass over the cones left ([`avs_pomdp::SessionPolicy::OnePassRollout`],
//!   Bertsekas' rollout: never worse than that pass). Before, RTBSS over HSVI bounds (still
//!   available as [`avs_pomdp::SessionPolicy::Rtbss`]) zigzagged between the heaviest cones and
//!   looked at cones it had emptied; on 50 bench floors the rollout cut the mean path from 230 m
//!   to 164 m (view-cone travel 122 → 89 m) and the bench's compute by half.
//! * **Verification.** A sighting the DT session declares found, and a baseline's first
//!   sighting, is a candidate for the verifier its class names in the knowledge file
//!   (`verifier: { strategy, model }`): Velez et al.'s planned verifier, GREEDY or RTBSS over
//!   the detector's scores at the candidate (`avs-verify`, driven by the `skills::verify`
//!   module's `model.rs`, whose docs give the choices), the `sequential` rule below — the
//!   default, and the fallback for a robot whose detector gives no scores — or the fixed
//!   `count` rule. Each candidate is a `candidate created` and a `verification decision` trace
//!   event.
//!   Both closer-look rules look at the candidate again from the reachable point nearest the
//!   robot in the middle of the class's recognition range (but no nearer than the camera can
//!   tilt onto it: a small object on the floor, 1.2 m below a camera that tilts 45° down, is
//!   looked at from at least 1.2 m), through views centred on it and zoomed so that its (3-D)
//!   distance lies mid-recognition-range. The `sequential` rule (`skills::verify::sequential`,
//!   `avs_verify::sequential`) looks until the Bayes-optimal policy of the knowledge's binary
//!   detector decides: from the candidate's prior, each hit in the recognition range multiplies
//!   the odds by (1 − FN)/FP = 16, each miss by FN/(1 − FP) ≈ 0.21; a rejected target costs the
//!   planner's price of failure (R = 1000 m), a wrong report ten times that
//!   (`AgentConfig::wrong_report_price`), against 2 m a look, so it accepts at about 99.98 %
//!   (five or six hits from a 1–5 % prior) within eight looks, or on the belief it has when
//!   they are spent; its looks aim at the best closer detection so far, and a later candidate
//!   within reach of a rejected one starts from the evidence of that one's looks. The `count`
//!   rule (Masuzawa & Miura `001` §4, reduced to one viewpoint) accepts two detections within 0.6 m in at most
//!   three looks whatever the prior: a real object passes with 0.90, a look-alike in reach one
//!   verification in about 55 (the wrong reports of the benches before the `sequential` rule).
//!   A rejected sighting is remembered with the reach of its looks (half the image's width at
//!   it): a later sighting within that reach of two rejections is the same look-alike and
//!   ignored; an object beside it is not. A sighting not confirmed ends the session
//!   as a false alarm and the agent replans without thinning the location.
//! * **A robot that cannot move** gives up at once, naming the robot's last refusal
//!   ([`GiveUpReason::CannotMove`]): after [`Tuning::stuck_motions`] motions in a row that
//!   started and failed where the robot stood (an unreachable target does not count: that is
//!   the map, and the next plan goes elsewhere). Before, it spent the plan budget and a whole
//!   coverage of refused motions and said "every reachable room was covered twice".
//! * **A give-up names its cause** ([`GiveUpReason::Hindered`], [`Hindrances`]): after the
//!   reason the search stopped (the plan budget, the success threshold, the coverage), the
//!   closed doors that cut the robot off from space it could not search (a door the robot
//!   reports seen closed, [`avs_robot::MapUpdate::doors`], with known free space the robot can
//!   reach on one side and space it cannot reach on the other), how many actions failed and
//!   the last failure, and how many sightings of the goal's class a closer look did not
//!   confirm. The trace shows a door the moment it is first seen closed, opens or closes
//!   ([`Event::DoorSeen`]). A robot without a door detector reports no doors, and a closed
//!   door is then only a wall: the reason cannot name what the robot cannot perceive.
//! * **Monitoring** uses the continual planner's monitor after every physical step; a move onto
//!   a placeholder and the EXPLORE-PLACEHOLDER that follows run together (the frontier may vanish
//!   on arrival). After every DT session the agent replans (the virtual object was matched to the
//!   real one found, or the assumption failed).
//! * **Unvisited areas.** Rooms exist only where the robot has been (rooms are components of
//!   the place graph), so a room seen through its door but not entered would be invisible to
//!   the planner. Known free space more than 2.5 m from every place gets a placeholder (one per
//!   3 m; a place counts only if it sees the point, not through a wall), attached to whichever
//!   of the four nearest places has the shortest known path to it, and set in the conceptual map
//!   with the unvisited area around it as its open area. Frontier placeholders without a short
//!   path on the known map from their place are dropped as artefacts.
//! * **Room extents.** What "the room" is for view planning, for filing a sighting under a room
//!   and for checking that a detection lies in the searched room comes from
//!   [`PlaceMap::cell_rooms`](avs_map::places::PlaceMap::cell_rooms): every known cell takes the
//!   room of the place nearest to it through known free space, with door openings closed. The
//!   nearest place in a straight line (the first choice) handed the far half of a room entered
//!   only at its door to the corridor's places, so searches of the room missed it and a desk
//!   seen there was filed under the corridor.
//! * **Looking around** pans half a field of view at a time (every direction is in two views),
//!   at tilts that likewise hold every landmark centre the robot can see in the central half
//!   of some image's height (the tilt rule over the elevations the knowledge's landmark
//!   classes can take; two tilts set by hand, −9° and −29°, put a table 0.9 m away at the
//!   lower border of the lower image, and it was never counted), and counts a landmark only
//!   when two sightings agree within 0.7 m; a landmark seen once is looked at again through
//!   views centred on it, a sequential test (Wald's, α 0.01, β 0.05) of a real landmark (seen
//!   with 1 − FN) against a false alarm (with at most FP): for FN 0.2 and FP 0.05 two hits in
//!   a row confirm it, two misses drop it. The earlier rule, one more sighting in two looks,
//!   let about a tenth of the false alarms through when another fell within 0.7 m, and a
//!   corridor with a counter that was not there read as a kitchen (on 30 bench floors: 21
//!   counted landmarks more than the rooms held, 7 with the test). A goal's sighting is only
//!   screened by that earlier rule, since the verifier looks at it again (`skills::look_around`,
//!   `Again`).
//! * **The goal in the look around** ([`AgentConfig::goal_in_look_around`], on by default).
//!   The look around's images also run the detector of the class searched for (a view lists
//!   every object searched for in it, `004` §2.1.2); a sighting of the goal confirmed as a
//!   landmark's is (two overlapping views, or a centred look again) is verified before the
//!   plan goes on, and reported when accepted; a look around that sees none thins the room's
//!   rate of the goal by the points it looked at, as a session in vain does. On 40 generated
//!   floors two thirds of a search's path came after the robot first stood in the target's
//!   room: it looked around there for furniture with the target in view, left when the
//!   room's landmarks said office, or searched the furniture first. With both, the planner's
//!   SPL on 200 floors rose from 0.265 to 0.34 (BENCHMARKS.md). Off, the look around looks
//!   for landmarks only, as the paper's robot did (its detector ran only in
//!   SEARCHFOROBJECT's view cones); the Fig. 3 scenarios re-enact that robot.
//! * **Motion** follows the agent's own shortest path on the known map, in 0.5 m waypoints, so the
//!   place map sees every door crossing; a waypoint that costs more than three times its straight
//!   length (plus 1 m) means the known map was wrong, and the robot stops there (a failure).
//! * **Planner mode.** The agent plans optimally (A* with h^max on cost and on −ln p, the
//!   planner's exact objective) with a budget of 50 000 expansions (about a second), and plans again in fast mode
//!   (greedy best-first with h^FF) when the budget runs out. The greedy mode alone made worse
//!   choices (searching the corridor before going to a likely kitchen). Assumptions a plan was
//!   made with although already below the monitor's bound do not trigger a replan later (the
//!   planner would return the same plan).
//! * **Giving up.** The threshold on a plan's success probability is 0.002, not the paper's
//!   0.01: on floors with several unexplored rooms a plan into any one of them succeeds with
//!   about 0.01 (P(leads to a kitchen) × P(counter) × P(object on it) × detection²), so 0.01
//!   gave up with most of the floor unexplored.
//! * **Coverage before giving up** ([`AgentConfig::cover_before_giving_up`], on by default).
//!   When the planner would give up (no plan clears the threshold, or the plan budget is
//!   spent), the knowledge was wrong or the target lies where it says little: the agent then
//!   covers the points no processed view has seen, exploring the placeholders left and
//!   visiting known free space that no room holds, as the `uninformed` baseline does, but the
//!   likeliest room (or placeholder) per metre first by the conceptual map, not the nearest,
//!   twice over (one look finds an object inside its planned view with about
//!   0.6–0.8, so one pass missed the target on about one floor in four), and gives up only when
//!   nothing is left; the reason names both ("… below the threshold 0.002; then every reachable
//!   room was covered twice …"). With knowledge that puts the target in an unlikely room,
//!   giving up at the threshold (the paper's rule) lost it in most runs: the planner stopped
//!   with rooms never entered. Off, the agent gives up at once, as in the paper, and also as
//!   soon as no plan is worth its cost by the paper's objective (p(π)·R ≤ cost(π) for the plan
//!   best for R = `planner.search.reward`, 1000: stopping, whose objective is R, is then no
//!   worse). With the threshold on p alone (0.002, set low for large floors) such a search
//!   spent its 30 plans on cheap searches of leftover points in rooms already searched (the
//!   Fig. 3(c) runs on the tall and wide offices) instead of giving up. With coverage on the
//!   rule stays off: giving up then does not stop, it covers, and on bench floors coverage
//!   found less per metre than the planner's own improbable plans (30-room floor 107 of seed
//!   101: given up at p 0.058 for 58.6 m, then lost after 409 m of coverage; found by the
//!   planner without the rule).
//! * **Search heights.** A small object is looked for in a room at the tops of the landmark
//!   classes the knowledge puts it on (lowest and highest, plus half its height; heights less
//!   than 0.2 m apart are one, their middle: 0.97 m for a cereal box on tables and counters),
//!   not at one table height: views planned for 0.8 m put a cereal box on a counter at the
//!   upper border of the image, where the detector's confidence falls. Coverage (the baselines
//!   and the coverage before giving up) looks on the floor and on the tops of every surface
//!   class (tables, counters, desks), not only those the knowledge puts the class on; the
//!   coverage before giving up also looks around in the rooms it enters first, and looks at
//!   the parts of known furniture tops the laser never saw (module `strategy`).
//! * **Detections** count from confidence 0.2 (`min_confidence`). The simulated detector's
//!   confidence is its detection probability at the estimated geometry, at most 1 − FN = 0.8;
//!   at 0.5 a real object near the border of a view or the far end of the range was dropped one
//!   look in three (uninformed baseline, bench floors 1–20: success 0.30 at 0.5, 0.60 at 0.2).
//!   A false alarm's confidence comes from the same geometry, so the threshold never told them
//!   apart; verification does, and its looks (centred, from inside the recognition range,
//!   where a real object shows with about 0.8) count only from 0.5 (`confirm_min_confidence`):
//!   at 0.2 a mug on an office desk passed for the cerealbox. So do the sightings that make a
//!   landmark in a look-around (faint ones only split the clusters).
//! * **Budgets:** at most 30 plans and 250 actions per goal — or 3 plans and 25 actions for
//!   every room the robot knows, when that is more (`plans_per_room`, `actions_per_room`: a
//!   building is searched room by room, and the fixed figures, set on floors where the robot
//!   comes to know about ten rooms, stopped the planner in the tenth room of a thirty-room
//!   floor) — and 1000 more actions for the coverage before giving up (`max_cover_actions`;
//!   also the baselines' budget); then it gives up and says so. (With 60 plans, misleading floors spent about 500 m re-searching
//!   the likely rooms before the coverage began; with 250 coverage actions, covering the
//!   floor for a whiteboard marker stopped after three or four rooms.)
//! * **Zoom in view planning.** The plan's room and landmark searches plan unzoomed views, as
//!   the paper does (`004` §2.1, §3.2). The coverage also looks at the floor, which a small
//!   object's unzoomed detection range does not reach wherever the camera can tilt; it plans
//!   at zoom levels 1, 2, 4, … up to the camera's maximum, each level only for the points the
//!   lower ones cannot cover ([`avs_view::create_view_cones_zoomed`]; at zoom `z` the fields
//!   of view shrink and the detection range grows by `z`, `004` §3.4).
//! * **Look-alikes.** A sighting that verification rejected is remembered (class, position);
//!   later sightings of that class within 0.6 m of a place rejected twice are ignored. After
//!   one rejection a new sighting there is verified again: a real object fails one
//!   verification in ten, and when one failure sufficed the target could be lost for good
//!   (bench floor 4: the cereal box on the kitchen counter, rejected after two missed looks,
//!   was seen again but never looked at, and the search gave up after 650 m).
//! * **Baselines** ([`Strategy`]): `uninformed` covers the nearest room not yet covered
//!   by view planning (Sjöö et al. `004`), `frontier` goes to the nearest frontier and covers
//!   each room it finds itself in; both use the same robot, place map, view planning and
//!   verification and no prior knowledge (module `strategy`).
//! * **Determinism.** Trace events carry no wall-clock times; with the planner's default expansion
//!   budgets and a seeded robot, the same seed gives byte-identical JSON lines.
pub mod beliefs;
mod binding;
mod body;
pub mod config;
mod error;
pub mod executive;
mod memory;
pub mod reason;
pub mod report;
mod run;
mod skills;
mod strategy;
pub mod trace;
pub mod world_model;

pub use beliefs::Beliefs;
pub use config::{AgentConfig, FoundByDistance, MeasuredSensing, Strategy, Tuning};
pub use error::AgentError;
pub use executive::Agent;
pub use reason::{FailedActions, GiveUpReason, Hindrances, MoveFailure, ReplanReason};
pub use report::{Activity, FoundObject, Goal, Metrics, PathBreakdown, SearchReport};
pub use trace::{Event, Outcome, SessionOutcome, TraceSink, View};

/// The robot boundary (trait, plain data, scripted double), re-exported.
pub use avs_robot;
pub use avs_robot::{
    ActionFailure, ActionResult, Camera, Detection, FailureReason, MapUpdate, MoveReport, Point3,
    Pose2D, Robot, ScriptedRobot, ViewCone, ViewReport,
};
