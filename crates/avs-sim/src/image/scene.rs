//! The [`ImageScene`] a camera in a [`World`] looks at: the world's objects in view (not
//! through walls or closed doors) and the background's depth along the optical axis.
//!
//! # Choices where the environment is vague
//!
//! * **Faces.** An object is its class's box in the knowledge (`size`; the object's own `size`
//!   when its class is not in the knowledge), standing on its pose's height (the pose's height
//!   is the object's base: an object on a table has the table top's height), turned by the
//!   object's yaw. The face a camera sees is the side of the box that faces it best: the front
//!   or back (`size[0] × size[2]`, the face `avs_view::zoom::ObjectModel` reads) or a left or
//!   right side (`size[1] × size[2]`), so no view is more than 45° off a face. The recogniser's
//!   training images show the object from its four sides (the environments give objects a yaw
//!   but the knowledge no favoured side), and a keypoint's scale follows the object's pixels
//!   per metre whichever side it is on; a narrow side shows fewer pixels, and fewer features
//!   match there.
//! * **Look-alikes.** An object with `role: distractor` is a look-alike of every other class
//!   ([`SceneObject::lookalike`]), as in [`crate::world_scores`] (whose exclusion of landmark
//!   classes is not kept: the zoom pipeline searches for objects, not furniture). The
//!   correlated detector's clutter features (phantoms) are not objects here: the background's
//!   random field plays their part.
//! * **Background depth.** The distance along the optical axis to the first wall or closed
//!   door cell of the walls grid (to its near side, within a cell), or to the floor when the
//!   camera looks down and the axis meets the floor first; the grid's diagonal when neither is
//!   met.

use super::{face_image, Background, ImageScene, SceneObject};
use crate::world::World;
use avs_format::environment::ObjectRole;
use avs_format::knowledge::Knowledge;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::raycast::{line_of_sight, max_ray_length, walk_segment};
use avs_robot::{Camera, ImageGeometry, Point3, ViewCone};

/// The scene in an image taken through `cone` by `camera` in `world`, with line of sight on
/// `walls` (a grid of the world's geometry, doors as they are now): every object whose face
/// is in the image and not hidden by walls or closed doors, and a background of `clutter`
/// (0 a plain wall, 1 an office scene) at [`background_depth`]. Faces as in the
/// [module documentation](self).
pub fn world_scene(
    world: &World,
    walls: &OccupancyGrid,
    knowledge: &Knowledge,
    camera: &Camera,
    cone: &ViewCone,
    image: &ImageGeometry,
    clutter: f64,
) -> ImageScene {
    let eye = [cone.pose.x, cone.pose.y];
    let objects = world
        .env
        .objects
        .iter()
        .filter_map(|o| {
            let size = knowledge.class(&o.class).map_or(o.size, |c| c.size);
            // The side that faces the camera best (module docs): front and back are
            // `size[0]` wide, the left and right sides `size[1]`.
            let to_camera = (eye[1] - o.pose.y).atan2(eye[0] - o.pose.x);
            let off = avs_map::geometry::wrap_angle(to_camera - o.pose.yaw_deg.to_radians());
            let quarter = (off / std::f64::consts::FRAC_PI_2).round();
            let yaw = o.pose.yaw_deg.to_radians() + quarter * std::f64::consts::FRAC_PI_2;
            let width = if quarter.rem_euclid(2.0) == 0.0 {
                size[0]
            } else {
                size[1]
            };
            let object = SceneObject {
                class: o.class.clone(),
                centre: Point3 {
                    x: o.pose.x,
                    y: o.pose.y,
                    z: o.pose.z + size[2] / 2.0,
                },
                width,
                height: size[2],
                yaw: avs_map::geometry::wrap_angle(yaw),
                lookalike: o.role == ObjectRole::Distractor,
            };
            face_image(&object, camera, cone, image)?;
            line_of_sight(walls, eye, [o.pose.x, o.pose.y], false).then_some(object)
        })
        .collect();
    ImageScene {
        objects,
        background: Background {
            clutter,
            depth: background_depth(walls, camera, cone),
        },
    }
}

/// Distance along the optical axis of an image taken through `cone` to the first occupied
/// cell of `walls` (its near side, within a cell), or to the floor if the axis meets it first;
/// at most the grid's diagonal, at least 0.1 m.
pub fn background_depth(walls: &OccupancyGrid, camera: &Camera, cone: &ViewCone) -> f64 {
    let yaw = cone.camera_yaw();
    let eye = [cone.pose.x, cone.pose.y];
    let reach = max_ray_length(walls);
    let end = [eye[0] + reach * yaw.cos(), eye[1] + reach * yaw.sin()];
    let mut planar = reach;
    walk_segment(walls, eye, end, |c, r| {
        if walls.get_i(c, r) == Cell::Occupied {
            let (x, y) = walls.cell_center(c, r);
            planar = ((x - eye[0]).hypot(y - eye[1]) - walls.resolution() / 2.0).max(0.0);
            return false;
        }
        walls.contains(c, r)
    });
    let cos_t = cone.tilt.cos().max(1e-6);
    let mut depth = planar / cos_t;
    if cone.tilt < 0.0 {
        depth = depth.min(camera.height / (-cone.tilt).sin());
    }
    depth.clamp(0.1, reach.max(0.1))
}
