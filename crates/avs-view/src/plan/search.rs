//! A room searched for several objects at once (Sjöö et al. `004` §2.1.4 with §3, the §4.4
//! experiment): the view plan executed nearest standpoint first, every view processed by the
//! three-step zoom search for the classes still sought in it, a unique class dropped from the
//! plan once it is recognised.
//!
//! ## Choices where the paper is vague
//! * **Pan and tilt.** A view's world direction becomes the camera's pan from the robot's
//!   heading at the standpoint (the robot is asked to face the direction, so the pan is 0
//!   unless the robot ends up turned); the tilt and zoom are the view's, kept within the
//!   camera's limits.
//! * **Recognised where?** A recognition counts for the class wherever it places the object;
//!   the plan's cells only decide where to look.
//! * **Failures.** A standpoint the robot cannot reach loses its views (noted); a view whose
//!   search fails is noted and the plan goes on.

use super::{drop_class, nearest_first, ViewPlan, ViewProblem};
use crate::zoom::{three_step_search, ObjectModel, Recognised, ZoomConfig, ZoomError};
use avs_robot::{Pose2D, Robot, ViewCone};
use serde::Serialize;

/// What a room search found and cost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoomSearch {
    /// The objects recognised, in the order found (one per unique class).
    pub found: Vec<Recognised>,
    /// Views processed.
    pub views: usize,
    /// Camera images taken by their three-step searches.
    pub images: usize,
    /// Metres driven.
    pub travelled: f64,
    /// Processing seconds of the images, as the robot reports them.
    pub seconds: f64,
    /// What went wrong on the way (unreachable standpoints, failed views), in words.
    pub notes: Vec<String>,
}

/// Search the room of `problem` for its classes with `plan`, from where `robot` stands:
/// `models` are the classes' models (by name, as `problem.classes`), `config` the zoom
/// search's settings. Errors only when the robot has no zoom pipeline at all.
pub fn search_room<R: Robot + ?Sized>(
    robot: &mut R,
    problem: &ViewProblem,
    plan: &ViewPlan,
    models: &[ObjectModel],
    config: &ZoomConfig,
) -> Result<RoomSearch, ZoomError> {
    let mut plan = plan.clone();
    let mut out = RoomSearch {
        found: Vec::new(),
        views: 0,
        images: 0,
        travelled: 0.0,
        seconds: 0.0,
        notes: Vec::new(),
    };
    let camera = robot.camera();
    let straight = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let mut unreachable: Vec<[f64; 2]> = Vec::new();
    loop {
        let here = robot.pose();
        let order = nearest_first(&plan, [here.x, here.y], straight);
        let Some(&next) = order
            .iter()
            .find(|&&i| !unreachable.contains(&plan.views[i].at))
        else {
            break;
        };
        let view = plan.views[next].clone();
        // Face the view's direction at its standpoint.
        let goal = Pose2D::new(view.at[0], view.at[1], view.yaw);
        let at = match robot.move_to(goal) {
            Ok(m) => {
                out.travelled += m.travelled;
                m.pose
            }
            Err(e) => {
                out.notes.push(format!(
                    "standpoint ({:.2}, {:.2}): {e}",
                    view.at[0], view.at[1]
                ));
                unreachable.push(view.at);
                continue;
            }
        };
        let pan = camera.clamp_pan(avs_map::geometry::wrap_angle(view.yaw - at.yaw));
        let cone = ViewCone::new(
            at,
            pan,
            camera.clamp_tilt(view.tilt),
            view.zoom.clamp(1.0, camera.max_zoom.max(1.0)),
        );
        let wanted: Vec<ObjectModel> = view
            .classes
            .iter()
            .filter_map(|&c| {
                let name = &problem.classes[c].class;
                models.iter().find(|m| &m.class == name).cloned()
            })
            .collect();
        out.views += 1;
        // The view is done whatever the search says.
        plan.views.remove(next);
        if wanted.is_empty() {
            continue;
        }
        match three_step_search(robot, &cone, &wanted, config) {
            Ok(o) => {
                out.images += o.images.len();
                out.seconds += o.seconds;
                out.travelled += o.travelled;
                for r in o.found {
                    if let Some(c) = problem.classes.iter().position(|k| k.class == r.class) {
                        if problem.classes[c].unique {
                            drop_class(&mut plan, c);
                        }
                    }
                    if !out.found.iter().any(|f| f.class == r.class) {
                        out.found.push(r);
                    }
                }
            }
            Err(e @ ZoomError::Unsupported { .. }) => return Err(e),
            Err(e) => out.notes.push(format!("view {}: {e}", out.views)),
        }
    }
    Ok(out)
}
