//! The two baselines the benchmark compares the switching planner with. Both use the same
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
//!
//! The same coverage loop is the switching planner's last resort: when the most promising plan
//! falls below the success threshold (or the plan budget is spent), the knowledge has been
//! wrong or the target is where it says little; with [`AgentConfig::cover_before_giving_up`]
//! the agent then covers, nearest first, what its sessions have not looked at yet, and gives
//! up only when nothing is left (the reason names both).
//!
//! Choices where the sources leave room: a detection counts only when the planner's own
//! verification step confirms it (a closer look centred on it, `Agent::verify`), so that all
//! three strategies report on the same evidence; a room counts as
//! covered when 80% (`COVERED_SHARE`) of its points were in processed views; its views are
//! planned again for the points not yet covered (a room may need more than the POMDP's
//! [`AgentConfig::max_cones`]) until that holds or no view can see the rest; when no room is
//! left uncovered and no placeholder is left, known free space that no room holds (seen through
//! a door never crossed) is visited so that it becomes a room; then the search gives up. The
//! heights looked at are the floor and the tops of every surface class of the knowledge (the
//! landmark classes anything lies *on*: tables, counters, desks), not only those it puts the
//! goal's class on — coverage runs because the knowledge was wrong, and these are geometry of
//! where small objects rest, not where in the building they are. The planner's coverage also
//! looks around in each room it enters first and looks at the tops of the furniture it knows,
//! including the part of a top the laser never saw (it sees a table's edge: a stapler at the
//! back of a table against a wall lies at no known cell), with sight lines that pass over the
//! furniture a point rests on (`sight_clear`). On misleading bench floors 1–50, 7 of the 8
//! misses at c7306aa were such objects: a stapler on a counter or table, a cereal box on a desk,
//! a marker on a counter or a table, most at the back. Views are planned with zoom where no
//! unzoomed view reaches (the floor, for a small object), and the budget is
//! [`AgentConfig::max_cover_actions`].

use super::*;

/// A room whose processed views covered this share of its points is done.
const COVERED_SHARE: f64 = 0.8;
/// Points are remembered as covered on this grid, metres.
const KEY_RES: f64 = 0.1;

/// The key of a point in the set of covered points.
pub(super) fn key(p: [f64; 3]) -> (i64, i64, i64) {
    (
        (p[0] / KEY_RES).round() as i64,
        (p[1] / KEY_RES).round() as i64,
        (p[2] / KEY_RES).round() as i64,
    )
}

/// What a baseline does next.
enum Next {
    Cover(RoomId),
    Explore(String, [f64; 2]),
    /// Go to known free space that no room holds (seen through a door that was never crossed,
    /// with no placeholder left to lead there), so that the place map makes a room of it.
    Visit([f64; 2]),
}

/// Known free space outside every room counts when at least this far from every place, metres.
const OUTSIDE_ROOMS_MIN: f64 = 1.5;

impl Agent {
    /// The executive of the baselines.
    pub(super) fn baseline_loop<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: &Goal,
        strategy: Strategy,
        run: &mut Run,
    ) -> Result<(Option<FoundObject>, String), AgentError> {
        Ok(
            match self.cover_all(robot, goal, strategy, 1, false, run)? {
                Ok(f) => {
                    let r = run.goal_reached(&f);
                    (Some(f), r)
                }
                Err(r) => (None, run.give_up(r)),
            },
        )
    }

    /// Cover rooms and explore placeholders by `strategy` until the goal's class is found
    /// (`Ok`) or nothing is left or the action budget is spent (`Err` with the reason). Points
    /// already in `run.covered` are not looked at again. With `look_around` (the planner's
    /// coverage; the baselines use no landmarks), each room entered for the first time is
    /// looked around, so that the furniture in it is known and its tops are looked on.
    pub(super) fn cover_all<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: &Goal,
        strategy: Strategy,
        passes: usize,
        look_around: bool,
        run: &mut Run,
    ) -> Result<Result<FoundObject, String>, AgentError> {
        let Some(class) = self.knowledge.class(&goal.class).cloned() else {
            return Ok(Err(format!("unknown class {}", goal.class)));
        };
        let mut pass = 1;
        loop {
            if run.metrics.actions >= self.config.max_cover_actions {
                return Ok(Err(format!(
                    "gave up after {} actions without finding a {}",
                    run.metrics.actions, goal.class
                )));
            }
            let next = self
                .baseline_next(robot, &class, strategy, &run.covered)
                .or_else(|| self.outside_rooms(robot, &run.visited).map(Next::Visit));
            let Some(next) = next else {
                if pass < passes {
                    pass += 1;
                    run.covered.clear();
                    run.emit(Event::Observed {
                        what: format!("every reachable room was covered: covering again (pass {pass} of {passes})"),
                    });
                    continue;
                }
                let times = match passes {
                    1 => String::new(),
                    2 => " twice".to_string(),
                    n => format!(" {n} times"),
                };
                return Ok(Err(format!(
                    "every reachable room was covered{times} and no placeholder is left: no {} found",
                    goal.class
                )));
            };
            match next {
                Next::Cover(room) => {
                    if let Some(f) = self.cover_room(robot, goal, room, run)? {
                        return Ok(Ok(f));
                    }
                }
                Next::Visit(pos) => {
                    let action = format!("VISIT ({:.2}, {:.2})", pos[0], pos[1]);
                    run.metrics.actions += 1;
                    run.visited.push(pos);
                    run.emit(Event::ActionStarted {
                        action: action.clone(),
                    });
                    let outcome = match self.go_to(robot, pos)? {
                        Ok(()) => "ok".to_string(),
                        Err(e) => e,
                    };
                    self.sync()?;
                    run.emit(Event::ActionFinished {
                        action,
                        outcome,
                        pose: pose3(robot.pose()),
                        path_length: robot.odometry(),
                    });
                    if look_around {
                        self.look_around_if_new(robot, run);
                    }
                }
                Next::Explore(name, pos) => {
                    let action = format!("EXPLORE {name}");
                    run.metrics.actions += 1;
                    run.emit(Event::ActionStarted {
                        action: action.clone(),
                    });
                    let snap = self.snapshot(&goal.class);
                    let from = self.current_room();
                    let outcome = match self.go_to(robot, pos)? {
                        Ok(()) => {
                            self.enter(robot, &name, &snap, from, run)?;
                            "ok".to_string()
                        }
                        Err(e) => {
                            // Unreachable or failed: never offered again (a failed motion
                            // leaves the robot nearer, and the next choice is made afresh).
                            self.mark_unreachable(&name, &snap, from);
                            e
                        }
                    };
                    run.emit(Event::ActionFinished {
                        action,
                        outcome,
                        pose: pose3(robot.pose()),
                        path_length: robot.odometry(),
                    });
                    if look_around {
                        self.look_around_if_new(robot, run);
                    }
                }
            }
        }
    }

    /// Look around in the room the robot is in unless that was done before.
    fn look_around_if_new<R: Robot + ?Sized>(&mut self, robot: &mut R, run: &mut Run) {
        if matches!(self.current_room(), Some(r) if !self.state().looked.contains(&r.0)) {
            if let Err(e) = self.look_around(robot, run) {
                run.emit(Event::Observed {
                    what: format!("looking around failed: {e}"),
                });
            }
        }
    }

    /// The share of room `r`'s points not yet covered, and the room's points.
    fn uncovered(
        &self,
        r: RoomId,
        class: &avs_format::knowledge::ObjectClass,
        covered: &BTreeSet<(i64, i64, i64)>,
    ) -> f64 {
        let pts = self.cover_points(r, class);
        if pts.is_empty() {
            return 0.0;
        }
        pts.iter().filter(|p| !covered.contains(&key(**p))).count() as f64 / pts.len() as f64
    }

    /// Path length from the robot to the nearest place of room `r` on the known map.
    fn room_distance(&self, from: [f64; 2], r: RoomId) -> Option<f64> {
        let st = self.state();
        let places = st.wm.rooms().find(|(id, _)| *id == r)?.1;
        let nearest = places
            .iter()
            .filter(|n| !st.blocked.contains(n))
            .filter_map(|&n| st.wm.places.graph.node_weight(n).map(|p| p.pos))
            .min_by(|a, b| dist(*a, from).total_cmp(&dist(*b, from)))?;
        self.path_len(from, nearest, true)
    }

    fn baseline_next<R: Robot + ?Sized>(
        &mut self,
        robot: &R,
        class: &avs_format::knowledge::ObjectClass,
        strategy: Strategy,
        covered: &BTreeSet<(i64, i64, i64)>,
    ) -> Option<Next> {
        let here = robot.pose();
        let at = [here.x, here.y];
        let rooms: Vec<RoomId> = self.state().wm.rooms().map(|(r, _)| r).collect();
        let pending: Vec<(RoomId, f64)> = rooms
            .into_iter()
            .filter(|&r| self.uncovered(r, class, covered) > 1.0 - COVERED_SHARE)
            .filter_map(|r| Some((r, self.room_distance(at, r)?)))
            .collect();
        tracing::debug!(
            rooms = ?self
                .state()
                .wm
                .rooms()
                .map(|(r, _)| (r.0, self.uncovered(r, class, covered), self.cover_points(r, class).len()))
                .collect::<Vec<_>>(),
            pending = ?pending,
            "coverage: rooms left"
        );
        let nearest_room = pending
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
            .map(|&(r, _)| r);
        let nearest_ph = {
            let st = self.state();
            st.phs
                .iter()
                .filter(|(k, _)| st.registry[*k].explored.is_none())
                .filter_map(|(k, c)| {
                    let l = self.path_len(at, c.pos, true)?;
                    Some((format!("placeholder{}", st.registry[*k].id), c.pos, l))
                })
                .min_by(|a, b| a.2.total_cmp(&b.2).then(a.0.cmp(&b.0)))
        };
        let here_room = self.current_room();
        match strategy {
            Strategy::Frontier => {
                if let Some(r) = here_room.filter(|r| pending.iter().any(|(p, _)| p == r)) {
                    return Some(Next::Cover(r));
                }
                nearest_ph
                    .map(|(n, p, _)| Next::Explore(n, p))
                    .or(nearest_room.map(Next::Cover))
            }
            _ => nearest_room
                .map(Next::Cover)
                .or(nearest_ph.map(|(n, p, _)| Next::Explore(n, p))),
        }
    }

    /// The nearest reachable known free cell that no room holds, at least
    /// [`OUTSIDE_ROOMS_MIN`] from every place and from every point in `visited`.
    fn outside_rooms<R: Robot + ?Sized>(
        &self,
        robot: &R,
        visited: &[[f64; 2]],
    ) -> Option<[f64; 2]> {
        let st = self.state();
        let places: Vec<[f64; 2]> = st.wm.places.graph.node_weights().map(|p| p.pos).collect();
        let here = robot.pose();
        let at = [here.x, here.y];
        let mut candidates: Vec<([f64; 2], f64)> = self
            .with_trav(false, |t| standable(&st.grid, t, POINT_SPACING))
            .into_iter()
            .filter(|&p| {
                self.room_at(p).is_none()
                    && !places
                        .iter()
                        .chain(visited)
                        .any(|q| dist(*q, p) < OUTSIDE_ROOMS_MIN)
            })
            .map(|p| (p, dist(at, p)))
            .collect();
        candidates.sort_by(|a, b| a.1.total_cmp(&b.1));
        candidates
            .into_iter()
            .map(|(p, _)| p)
            .find(|&p| self.path_len(at, p, false).is_some())
    }

    /// Cover room `r` by view planning and process its views nearest-neighbour first; a
    /// detection confirmed by a second look is the goal. The views are planned for the room's
    /// points not yet covered, again after each pass, until [`COVERED_SHARE`] of them are (or
    /// no view sees the rest, or a pass covers nothing: the rest is given up on).
    fn cover_room<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: &Goal,
        room: RoomId,
        run: &mut Run,
    ) -> Result<Option<FoundObject>, AgentError> {
        let label = goal.class.clone();
        let Some(class) = self.knowledge.class(&label).cloned() else {
            return Ok(None);
        };
        let loc = ConeLoc::Room(room.0);
        loop {
            let all = self.cover_points(room, &class);
            let todo: Vec<[f64; 3]> = all
                .iter()
                .copied()
                .filter(|p| !run.covered.contains(&key(*p)))
                .collect();
            if todo.len() as f64 <= (1.0 - COVERED_SHARE) * all.len() as f64 {
                return Ok(None);
            }
            let set = self
                .plan_cones(
                    robot,
                    &label,
                    loc,
                    Some(todo.clone()),
                    &view_zooms(robot.camera().max_zoom),
                )
                .filter(|s| !s.views.is_empty());
            let Some(set) = set else {
                // No view sees what is left: the room is done.
                run.covered.extend(todo.iter().map(|p| key(*p)));
                return Ok(None);
            };
            run.emit(Event::Observed {
                what: format!(
                    "covering room{} with {} view cones for {} of its {} points",
                    room.0,
                    set.views.len(),
                    todo.len(),
                    all.len()
                ),
            });
            let before = run.covered.len();
            if let Some(f) = self.process_views(robot, &label, room, &set, run)? {
                return Ok(Some(f));
            }
            if run.metrics.actions >= self.config.max_cover_actions {
                return Ok(None);
            }
            let truncated = set.views.len() >= self.config.max_cones;
            if run.covered.len() == before || !truncated {
                // Every view was planned and processed (or none got anywhere): what they did
                // not cover, no view can.
                run.covered.extend(todo.iter().map(|p| key(*p)));
                return Ok(None);
            }
        }
    }

    /// The points covering room `r` looks at for `class`: the room's known cells at the
    /// coverage's heights (the floor and every surface's top), and the cells on top of the
    /// known furniture in the room that the laser never saw into (it sees a table's edge, not
    /// its top: a box at the back of a table against a wall lies at no known cell), each at its
    /// surface's height. Both on the one lattice of [`POINT_SPACING`], so that a point keeps its
    /// key as the map grows.
    fn cover_points(&self, r: RoomId, class: &avs_format::knowledge::ObjectClass) -> Vec<[f64; 3]> {
        let mut pts = self.room_points(r.0, class, true);
        if class.landmark {
            return pts;
        }
        let grid = &self.state().grid;
        let step = lattice_step(grid);
        let surfaces: Vec<Surface> = self
            .surfaces()
            .into_iter()
            .filter(|s| s.room == Some(r))
            .collect();
        pts.extend(unseen_tops(grid, &surfaces, step, 0.5 * class.size[2]));
        pts
    }

    /// Process `set`'s views nearest-neighbour first, marking their points covered; the first
    /// detection a closer look confirms is returned.
    fn process_views<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        label: &str,
        room: RoomId,
        set: &ConeSet,
        run: &mut Run,
    ) -> Result<Option<FoundObject>, AgentError> {
        let mut todo: Vec<usize> = (0..set.views.len()).collect();
        while !todo.is_empty() {
            if run.metrics.actions >= self.config.max_cover_actions {
                return Ok(None);
            }
            let here = robot.pose();
            let (j, _) = todo
                .iter()
                .enumerate()
                .map(|(j, &v)| {
                    let p = set.views[v].pose;
                    (j, dist([p[0], p[1]], [here.x, here.y]))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("not empty");
            let v = todo.remove(j);
            let view = &set.views[v];
            run.metrics.actions += 1;
            let action = format!("PROCESSVIEWCONE {label} room{} {}", room.0, view_text(view));
            run.emit(Event::ActionStarted {
                action: action.clone(),
            });
            let moved = self.go_to(robot, [view.pose[0], view.pose[1]])?;
            let vc = ViewCone::new(
                Pose2D::new(view.pose[0], view.pose[1], view.pose[2]),
                view.pan,
                view.tilt,
                view.zoom,
            );
            let look = |agent: &Self, robot: &mut R| -> Option<avs_robot::Detection> {
                let r = robot.process_view_cone(&vc, &[label.to_string()]).ok()?;
                for d in &r.detections {
                    tracing::debug!(
                        class = %d.class,
                        x = d.pose.x,
                        y = d.pose.y,
                        confidence = d.confidence,
                        new = agent.is_new_sighting(d),
                        "coverage view"
                    );
                }
                // Any new sighting of the class counts, in the room being covered or not (a
                // view from near a door sees past it, and the goal is the object wherever it
                // is): verification decides.
                r.detections
                    .into_iter()
                    .filter(|d| d.class == label && d.confidence >= agent.config.min_confidence)
                    .filter(|d| agent.is_new_sighting(d))
                    .max_by(|a, b| a.confidence.total_cmp(&b.confidence))
            };
            let first = if moved.is_ok() {
                look(self, robot)
            } else {
                None
            };
            let confirmed = match first {
                Some(d) => self.verify(robot, label, &d, run)?,
                None => None,
            };
            self.state_mut().grid = robot.map_update().grid;
            if moved.is_ok() {
                run.covered
                    .extend(set.cells[v].iter().map(|&i| key(set.points[i])));
            }
            run.emit(Event::ActionFinished {
                action,
                outcome: match (&moved, &confirmed) {
                    (Err(e), _) => e.clone(),
                    (_, Some(_)) => "detected and confirmed".into(),
                    _ => "ok".into(),
                },
                pose: pose3(robot.pose()),
                path_length: robot.odometry(),
            });
            if let Some(d) = confirmed {
                let k = self.state().objects.len();
                let place = self
                    .object_place([d.pose.x, d.pose.y])
                    .or_else(|| self.current_place());
                if let Some(place) = place {
                    self.state_mut().objects.push(Known {
                        class: label.to_string(),
                        pos: d.pose,
                        place,
                        landmark: None,
                        on: None,
                    });
                }
                return Ok(Some(FoundObject {
                    name: format!("object{k}"),
                    class: label.to_string(),
                    pose: d.pose,
                    confidence: d.confidence,
                }));
            }
        }
        Ok(None)
    }
}
