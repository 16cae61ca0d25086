//! ENTER (and EXPLORE) a placeholder: the robot stands a step inside the door on the way to
//! it (`executive::entry_point`); it goes on into the space beyond only where that reveals
//! enough to hide a room, and turns around; the placeholder then leads to the room the robot
//! stands in if that is another room than the one it came from, else nowhere new. What is
//! left of the room (its own frontiers) is the planner's to weigh, like any placeholder.

use super::Ctx;
use crate::binding::PlaceArg;
use crate::body::Body;
use crate::memory::{Memory, Target};
use crate::run::Run;
use crate::AgentError;
use avs_concepts::RoomId;
use avs_map::places::dist;
use avs_robot::Robot;

/// Enter the placeholder `ph` (the robot stands at it or a step inside the door on the way
/// to it), coming from room `from_room`.
pub(crate) fn enter<R: Robot + ?Sized>(
    cx: Ctx,
    mem: &mut Memory,
    body: &mut Body<R>,
    run: &mut Run,
    ph: &PlaceArg,
    from_room: Option<RoomId>,
) -> Result<(), AgentError> {
    let t = cx.tuning();
    let id = match ph.target {
        Target::Placeholder(id) => Some(id),
        Target::Place(_) => None,
    };
    let explored_led = id.and_then(|id| mem.explored_led(id));
    let beyond = match explored_led {
        Some(n) => mem.wm.places.graph.node_weight(n).map(|p| p.pos),
        None => {
            let Some(pos) = ph.pos else {
                return Ok(());
            };
            let from = ph.attach.unwrap_or(pos);
            let here = body.pose();
            let (dx, dy) = (pos[0] - from[0], pos[1] - from[1]);
            let (dx, dy) = if dx.hypot(dy) > 0.2 {
                (dx, dy)
            } else {
                (here.yaw.cos(), here.yaw.sin())
            };
            let n = dx.hypot(dy).max(1e-9);
            let (ux, uy) = (dx / n, dy / n);
            // Into the space beyond: of the points `enter_depth` away with a short known
            // path, the one that reveals most (exploration utility's new area, Masuzawa &
            // Miura eq. 6) and lies farthest from where the placeholder hangs off — if any
            // reveals as much as a placeholder needs to hide a room (`min_open_area`): a
            // room the robot already sees whole from inside its door is not driven into.
            let grid = mem.grid.clone();
            (0..12)
                .map(|k| {
                    let a = std::f64::consts::TAU * k as f64 / 12.0;
                    let (c, s) = (a.cos(), a.sin());
                    let (vx, vy) = (c * ux - s * uy, s * ux + c * uy);
                    [here.x + t.enter_depth * vx, here.y + t.enter_depth * vy]
                })
                .filter(|b| {
                    mem.path_len_within([here.x, here.y], *b, false, 1.5 * t.enter_depth)
                        .is_some()
                })
                .filter_map(|b| {
                    let area = avs_map::explore::new_area(&grid, b, t.enter_depth * 2.0);
                    tracing::debug!(
                        ?b,
                        area,
                        "ENTER: unknown area seen from a point beyond the door"
                    );
                    (area >= t.min_open_area).then_some((b, area + dist(b, from)))
                })
                .fold(None, |best: Option<([f64; 2], f64)>, (b, sc)| match best {
                    Some((_, bs)) if bs >= sc - 1e-9 => best,
                    _ => Some((b, sc)),
                })
                .map(|(b, _)| b)
        }
    };
    if let Some(b) = beyond {
        if let Err(e) = body.go_to(mem, b)? {
            run.observe(format!("could not go beyond {}: {e}", ph.name));
        }
    }
    body.turn_around(mem)?;
    let now = mem.current_room();
    let led = match (now, from_room) {
        (Some(n), Some(f)) if n != f => mem.current_place(),
        (Some(_), None) => mem.current_place(),
        _ => None,
    };
    if let Some(id) = id {
        mem.set_explored(id, ph.pos, from_room.map_or(0, |r| r.0), led);
    }
    mem.sync()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::binding::Binding;
    use crate::skills::testing;
    use crate::AgentConfig;
    use avs_robot::{Camera, Pose2D, ScriptedRobot};

    #[test]
    fn entering_a_placeholder_through_a_door_goes_beyond_it_and_files_where_it_led() {
        let (config, k) = (AgentConfig::default(), testing::knowledge());
        let truth = testing::two_rooms();
        let mut robot =
            ScriptedRobot::with_laser(truth, 3.5, Pose2D::new(2.0, 2.0, 0.0), Camera::default());
        let mut mem = testing::memory(&config, &k, &mut robot);
        let from = mem.current_room().expect("the robot stands in a room");
        let binding = Binding::of(&mem, &k, "cerealbox");
        let id = mem
            .phs
            .iter()
            .map(|(i, c)| (mem.registry[*i].id, c.pos))
            .filter(|(_, p)| p[0] > 4.2)
            .min_by(|a, b| a.1[0].total_cmp(&b.1[0]))
            .map(|(id, _)| id)
            .unwrap_or_else(|| panic!("no placeholder beyond the door: {:?}", mem.phs));
        let ph = binding.placeholder_arg(id);
        let mut sink = testing::sink();
        let mut run = testing::run(&mut sink);
        let cx = testing::ctx(&k, &config);
        let mut body = Body::new(&mut robot);
        body.go_to(&mut mem, ph.pos.expect("in the problem"))
            .unwrap()
            .expect("the door is open");
        enter(cx, &mut mem, &mut body, &mut run, &ph, Some(from)).unwrap();
        assert!(body.at()[0] > 4.2, "the robot went beyond: {:?}", body.at());
        let e = mem
            .registry
            .iter()
            .find(|e| e.id == id)
            .expect("still tracked");
        let (origin, led) = e.explored.expect("explored");
        assert_eq!(origin, from.0);
        let led = led.expect("it led to a room");
        assert_ne!(mem.wm.room_of(led), Some(from), "{}", testing::text(&run));
    }
}
