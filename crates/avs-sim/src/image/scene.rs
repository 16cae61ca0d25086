//! The [`ImageScene`] a camera in a [`World`] looks at: the world's objects in view (not
//! through walls or closed doors) and the background's depth along the optical axis.
//!
//! # Choices where the environment is vague
//!
//! * **Faces.** An object is its class's box in the knowledge (`size`; the object's own `size`
//!   when its class is not in the knowledge), standing on its pose's height (the pose's height
//!   is the object's base: an object on a table has the table top's height), turned by the
//!   object's yaw. The recogniser's training images show the object from its four sides (the
//!   environments give objects a yaw but the knowledge no favoured side): the front or back
//!   (`size[0] × size[2]`, the face `avs_view::zoom::ObjectModel` reads) and the left or right
//!   (`size[1] × size[2]`). A camera sees two of them, one of each pair, turned by angles
//!   that add up to 90°; the face in the image is the one of the two on which the recogniser
//!   matches the larger share of its model ([`ImageModel::match_share`]: apparent size and
//!   angle), as a recogniser matching against four training views reports its best; when it
//!   matches neither (too far, too small), the one facing the camera more squarely
//!   ([`BoxObject::seen_face`]). A keypoint's scale follows the object's pixels per metre
//!   whichever side it is on. So a long, thin object (a marker: 13 × 2 cm) is recognised by
//!   its long side until it is seen nearly end-on (until its long side's angle nears
//!   [`ImageModel::max_view_angle`]), not only within 45° of it: the side nearest in angle
//!   alone made a marker 2 cm wide from half the directions. The zoom pipeline's calibration
//!   (`avs_eval::zoom_sensing`) turns its objects every way through the same rule.
//! * **Look-alikes.** An object with `role: distractor` is a look-alike of every other class
//!   ([`SceneObject::lookalike`]), as in [`crate::world_scores`] (whose exclusion of landmark
//!   classes is not kept: the zoom pipeline searches for objects, not furniture). The
//!   correlated detector's clutter features (phantoms) are not objects here: the background's
//!   random field plays their part.
//! * **Containers.** A face stands in the middle of its box, so a shelf's face was as near
//!   the camera as what lies in it, and whichever of the two was nearer by a few centimetres
//!   was painted over the other: the attention saw a cereal box in a shelf in 30 of 80 images
//!   from 1.2 m (floor 172 of the 200-floor bench, seed 1), against 80 of 80 with the shelf
//!   taken away. A shelf is open at the front: the camera sees its contents against its back
//!   panel. So the face of an open container — a landmark class the knowledge puts objects
//!   *in*, or the class of an object the world puts something in — stands at the back of its
//!   box (half the box's extent behind the middle, along the face's normal), and its contents
//!   are painted over it. Tables, counters and desks need nothing of the kind: what stands on
//!   them is above their faces.
//! * **Background depth.** The distance along the optical axis to the first wall or closed
//!   door cell of the walls grid (to its near side, within a cell), or to the floor when the
//!   camera looks down and the axis meets the floor first; the grid's diagonal when neither is
//!   met.

use super::{face_image, Background, ImageModel, ImageScene, SceneObject};
use crate::sim_robot::ImageConfig;
use crate::world::World;
use avs_format::environment::ObjectRole;
use avs_format::knowledge::{Knowledge, Relation};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::raycast::{line_of_sight, max_ray_length, walk_segment};
use avs_robot::{Camera, ImageGeometry, Point3, ViewCone};
use std::collections::BTreeSet;

/// The scene in an image taken through `cone` by `camera` in `world`, with line of sight on
/// `walls` (a grid of the world's geometry, doors as they are now): every object whose face
/// is in the image and not hidden by walls or closed doors, and a background of `config`'s
/// clutter (0 a plain wall, 1 an office scene) at [`background_depth`]; the image's geometry
/// and model are `config`'s too. Faces as in the [module documentation](self).
pub fn world_scene(
    world: &World,
    walls: &OccupancyGrid,
    knowledge: &Knowledge,
    camera: &Camera,
    cone: &ViewCone,
    config: &ImageConfig,
) -> ImageScene {
    let (model, image) = (&config.model, &config.geometry);
    let eye = [cone.pose.x, cone.pose.y];
    let containers = open_containers(world, knowledge);
    let objects = world
        .env
        .objects
        .iter()
        .filter_map(|o| {
            let object = BoxObject {
                class: o.class.clone(),
                base: Point3 {
                    x: o.pose.x,
                    y: o.pose.y,
                    z: o.pose.z,
                },
                yaw: o.pose.yaw_deg.to_radians(),
                size: knowledge.class(&o.class).map_or(o.size, |c| c.size),
                lookalike: o.role == ObjectRole::Distractor,
            }
            .seen_face(model, camera, cone, image)?;
            let object = if containers.contains(o.class.as_str()) {
                back_panel(object, knowledge.class(&o.class).map_or(o.size, |c| c.size))
            } else {
                object
            };
            line_of_sight(walls, eye, [o.pose.x, o.pose.y], false).then_some(object)
        })
        .collect();
    ImageScene {
        objects,
        background: Background {
            clutter: config.clutter,
            depth: background_depth(walls, camera, cone),
        },
    }
}

/// The classes of the world's open containers (module docs, "Containers"): the landmark
/// classes the knowledge puts objects *in*, and those of the objects the world puts some
/// object in.
fn open_containers<'a>(world: &'a World, knowledge: &'a Knowledge) -> BTreeSet<&'a str> {
    let by_knowledge = knowledge
        .landmark_rates
        .iter()
        .filter(|r| r.relation == Relation::In)
        .map(|r| r.landmark.as_str());
    let by_world = world
        .env
        .objects
        .iter()
        .filter_map(|o| o.r#in.as_deref())
        .filter_map(|id| world.env.objects.iter().find(|c| c.id == id))
        .map(|c| c.class.as_str());
    by_knowledge.chain(by_world).collect()
}

/// The face `face` of an open container of `size` (width, depth, height) moved from the box's
/// middle to its back, half the box's extent along the face's normal away from the camera:
/// what the camera sees of a shelf is its back panel, with the shelf's contents in front.
fn back_panel(face: SceneObject, size: [f64; 3]) -> SceneObject {
    // The face's width is the box's width (front or back) or its depth (a side); the extent
    // behind it is the other one.
    let extent = if (face.width - size[0]).abs() < 1e-12 {
        size[1]
    } else {
        size[0]
    };
    let back = 0.5 * extent;
    SceneObject {
        centre: Point3 {
            x: face.centre.x - back * face.yaw.cos(),
            y: face.centre.y - back * face.yaw.sin(),
            ..face.centre
        },
        ..face
    }
}

/// An object before the image chooses its face: its class's box (`size`: width, depth,
/// height) standing on `base` (the centre of its bottom), its front turned towards `yaw`.
#[derive(Debug, Clone, PartialEq)]
pub struct BoxObject {
    /// The object's class.
    pub class: String,
    /// The centre of the box's bottom, world frame.
    pub base: Point3,
    /// The direction the front faces, radians.
    pub yaw: f64,
    /// Width (front and back), depth (left and right sides) and height, metres.
    pub size: [f64; 3],
    /// A look-alike of every other class ([`SceneObject::lookalike`]).
    pub lookalike: bool,
}

impl BoxObject {
    /// The face of the box in an image taken through `cone` (module docs, "Faces"): of the
    /// two sides turned most towards the camera — the nearer of front and back (`size[0]`
    /// wide) and the nearer of left and right (`size[1]`) — the one on which the recogniser
    /// matches the larger share of its model ([`ImageModel::match_share`]); when it matches
    /// neither, the one facing the camera more squarely. `None` when the face is not in the
    /// image.
    pub fn seen_face(
        &self,
        model: &ImageModel,
        camera: &Camera,
        cone: &ViewCone,
        image: &ImageGeometry,
    ) -> Option<SceneObject> {
        use std::f64::consts::FRAC_PI_2;
        let to_camera = (cone.pose.y - self.base.y).atan2(cone.pose.x - self.base.x);
        let off = avs_map::geometry::wrap_angle(to_camera - self.yaw);
        // The nearer of front (quarter 0) and back (2), and the nearer side (1 or −1).
        let front = if off.abs() <= FRAC_PI_2 { 0.0 } else { 2.0 };
        let side = if off >= 0.0 { 1.0 } else { -1.0 };
        let scored = |quarter: f64| {
            let face = SceneObject {
                class: self.class.clone(),
                centre: Point3 {
                    z: self.base.z + self.size[2] / 2.0,
                    ..self.base
                },
                width: if quarter == 0.0 || quarter == 2.0 {
                    self.size[0]
                } else {
                    self.size[1]
                },
                height: self.size[2],
                yaw: avs_map::geometry::wrap_angle(self.yaw + quarter * FRAC_PI_2),
                lookalike: self.lookalike,
            };
            let seen = face_image(&face, camera, cone, image)?;
            Some((
                model.match_share(seen.size_px(), seen.view_angle),
                seen.view_angle,
                face,
            ))
        };
        match (scored(front), scored(side)) {
            (Some(a), Some(b)) => {
                let a_better = a.0 > b.0 || (a.0 == b.0 && a.1 <= b.1);
                Some(if a_better { a.2 } else { b.2 })
            }
            (a, b) => a.or(b).map(|x| x.2),
        }
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
