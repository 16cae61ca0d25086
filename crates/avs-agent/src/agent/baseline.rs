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
//! Choices where the sources leave room: a detection counts only when the planner's own
//! verification step confirms it (a closer look centred on it, `Agent::verify`), so that all
//! three strategies report on the same evidence; a room counts as
//! covered when 80% (`COVERED_SHARE`) of its points were in processed views (or no view can see
//! the rest); the search gives up when no room is left uncovered and no placeholder is left.

use super::*;

/// A room whose processed views covered this share of its points is done.
const COVERED_SHARE: f64 = 0.8;
/// Points are remembered as covered on this grid, metres.
const KEY_RES: f64 = 0.1;

fn key(p: [f64; 3]) -> (i64, i64) {
    (
        (p[0] / KEY_RES).round() as i64,
        (p[1] / KEY_RES).round() as i64,
    )
}

/// What a baseline does next.
enum Next {
    Cover(RoomId),
    Explore(String, [f64; 2]),
}

impl Agent {
    /// The executive of the baselines.
    pub(super) fn baseline_loop<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: &Goal,
        strategy: Strategy,
        run: &mut Run,
    ) -> Result<(Option<FoundObject>, String), AgentError> {
        let Some(class) = self.knowledge.class(&goal.class).cloned() else {
            return Ok((None, format!("unknown class {}", goal.class)));
        };
        let mut covered: BTreeSet<(i64, i64)> = BTreeSet::new();
        loop {
            if run.metrics.actions >= self.config.max_actions {
                let r = format!(
                    "gave up after {} actions without finding a {}",
                    run.metrics.actions, goal.class
                );
                return Ok((None, run.give_up(r)));
            }
            let Some(next) = self.baseline_next(robot, &class, strategy, &covered) else {
                let r = format!(
                    "every reachable room was covered and no placeholder is left: no {} found",
                    goal.class
                );
                return Ok((None, run.give_up(r)));
            };
            match next {
                Next::Cover(room) => {
                    if let Some(f) = self.cover_room(robot, goal, room, &mut covered, run)? {
                        let r = run.goal_reached(&f);
                        return Ok((Some(f), r));
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
                }
            }
        }
    }

    /// The share of room `r`'s points not yet covered, and the room's points.
    fn uncovered(
        &self,
        r: RoomId,
        class: &avs_format::knowledge::ObjectClass,
        covered: &BTreeSet<(i64, i64)>,
    ) -> f64 {
        let pts = self.room_points(r.0, class);
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
        covered: &BTreeSet<(i64, i64)>,
    ) -> Option<Next> {
        let here = robot.pose();
        let at = [here.x, here.y];
        let rooms: Vec<RoomId> = self.state().wm.rooms().map(|(r, _)| r).collect();
        let pending: Vec<(RoomId, f64)> = rooms
            .into_iter()
            .filter(|&r| self.uncovered(r, class, covered) > 1.0 - COVERED_SHARE)
            .filter_map(|r| Some((r, self.room_distance(at, r)?)))
            .collect();
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

    /// Cover room `r` by view planning and process its views nearest-neighbour first; a
    /// detection confirmed by a second look is the goal.
    fn cover_room<R: Robot + ?Sized>(
        &mut self,
        robot: &mut R,
        goal: &Goal,
        room: RoomId,
        covered: &mut BTreeSet<(i64, i64)>,
        run: &mut Run,
    ) -> Result<Option<FoundObject>, AgentError> {
        let label = goal.class.clone();
        let loc = ConeLoc::Room(room.0);
        self.create_cones(robot, &label, loc, run);
        let set = self.state().cones[&(label.clone(), loc)].clone();
        let mut todo: Vec<usize> = (0..set.views.len())
            .filter(|&v| {
                set.cells[v]
                    .iter()
                    .any(|&i| !covered.contains(&key(set.points[i])))
            })
            .collect();
        run.emit(Event::Observed {
            what: format!(
                "covering room{} with {} of {} view cones",
                room.0,
                todo.len(),
                set.views.len()
            ),
        });
        while !todo.is_empty() {
            if run.metrics.actions >= self.config.max_actions {
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
            let action = format!(
                "PROCESSVIEWCONE {label} room{} from ({:.2}, {:.2}) pan {:.2} tilt {:.2}",
                room.0, view.pose[0], view.pose[1], view.pan, view.tilt
            );
            run.emit(Event::ActionStarted {
                action: action.clone(),
            });
            let moved = self.go_to(robot, [view.pose[0], view.pose[1]])?;
            let vc = ViewCone::new(
                Pose2D::new(view.pose[0], view.pose[1], view.pose[2]),
                view.pan,
                view.tilt,
                1.0,
            );
            let look = |agent: &Self, robot: &mut R| -> Option<crate::robot::Detection> {
                let r = robot
                    .process_view_cone(&vc, std::slice::from_ref(&label))
                    .ok()?;
                for d in &r.detections {
                    tracing::debug!(
                        class = %d.class,
                        x = d.pose.x,
                        y = d.pose.y,
                        confidence = d.confidence,
                        inside = agent.detection_in(d, loc, r.pose),
                        "baseline view"
                    );
                }
                r.detections
                    .into_iter()
                    .filter(|d| d.class == label && d.confidence >= agent.config.min_confidence)
                    .filter(|d| agent.detection_in(d, loc, r.pose))
                    .max_by(|a, b| a.confidence.total_cmp(&b.confidence))
            };
            let first = if moved.is_ok() {
                look(self, robot)
            } else {
                None
            };
            let confirmed = match first {
                Some(d) => self.verify(robot, &label, &d, run)?,
                None => None,
            };
            self.state_mut().grid = robot.map_update().grid;
            if moved.is_ok() {
                covered.extend(set.cells[v].iter().map(|&i| key(set.points[i])));
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
                        class: label.clone(),
                        pos: d.pose,
                        place,
                        landmark: None,
                        on: None,
                    });
                }
                return Ok(Some(FoundObject {
                    name: format!("object{k}"),
                    class: label,
                    pose: d.pose,
                    confidence: d.confidence,
                }));
            }
        }
        // What no view can see is given up on: the room is done.
        covered.extend(set.points.iter().map(|p| key(*p)));
        Ok(None)
    }
}
