//! `kind: environment` — a world for the simulator (or the prior map of a real site).
//!
//! Units: metres, degrees for angles in files (`*_deg`). World frame: x right, y up; the map's
//! `origin` is the world position of the lower-left corner of the grid, as in ROS map_server.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// A world: map, ground-truth rooms, doors, objects, the robot and its sensors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Environment {
    /// Must be `environment`.
    pub kind: EnvironmentKind,
    /// A short name, used in traces.
    pub name: String,
    /// The occupancy map.
    pub map: MapSource,
    /// Ground-truth rooms.
    #[serde(default)]
    pub rooms: Vec<Room>,
    /// Doors between rooms.
    #[serde(default)]
    pub doors: Vec<Door>,
    /// Furniture (landmarks), targets and distractors.
    #[serde(default)]
    pub objects: Vec<Object>,
    /// The robot: start pose and footprint.
    pub robot: Robot,
    /// The laser range finder.
    #[serde(default)]
    pub laser: Laser,
    /// The pan-tilt-zoom camera.
    #[serde(default)]
    pub camera: Camera,
}

/// The literal `environment`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EnvironmentKind {
    /// `kind: environment`
    Environment,
}

/// Where the occupancy grid comes from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum MapSource {
    /// A ROS map_server descriptor inline (the image path is relative to this YAML file).
    Ros(RosMap),
    /// An ASCII grid: `#` occupied, `.` or space free, `?` unknown; the first line is the top row.
    Ascii(AsciiMap),
}

/// A ROS map_server map descriptor.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RosMap {
    /// Image file (PGM or PNG), relative to the YAML file.
    pub image: String,
    /// Metres per pixel.
    pub resolution: f64,
    /// World pose of the lower-left pixel: `[x, y, yaw]` (yaw is ignored, as map_server does).
    #[serde(default = "zero3")]
    pub origin: [f64; 3],
    /// 1 if white means occupied.
    #[serde(default)]
    pub negate: u8,
    /// Occupancy probability above which a pixel is occupied.
    #[serde(default = "default_occ")]
    pub occupied_thresh: f64,
    /// Occupancy probability below which a pixel is free.
    #[serde(default = "default_free")]
    pub free_thresh: f64,
}

fn zero3() -> [f64; 3] {
    [0.0; 3]
}
fn default_occ() -> f64 {
    0.65
}
fn default_free() -> f64 {
    0.196
}

/// An inline ASCII map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AsciiMap {
    /// The grid rows, top row first.
    pub ascii: String,
    /// Metres per character cell.
    pub resolution: f64,
    /// World position of the lower-left cell corner.
    #[serde(default)]
    pub origin: [f64; 2],
}

/// A ground-truth room.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Room {
    /// Unique room name (e.g. `kitchen1`).
    pub name: String,
    /// Room category, one of the knowledge file's `room_categories`.
    pub category: String,
    /// A point inside the room; the room is the free space reachable from it without crossing a door.
    #[serde(default)]
    pub seed: Option<Point>,
    /// Or the room's outline as a polygon.
    #[serde(default)]
    pub polygon: Option<Vec<Point>>,
}

/// A point in the world frame, metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Point {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
}

/// A planar pose in the world frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Pose {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// Height above the floor, metres (objects only; 0 for the floor).
    #[serde(default)]
    pub z: f64,
    /// Heading, degrees counter-clockwise from +x.
    #[serde(default)]
    pub yaw_deg: f64,
}

/// A door: an opening in a wall that separates two rooms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Door {
    /// Unique door name.
    pub name: String,
    /// Centre of the opening; `yaw_deg` is the direction of passage.
    pub pose: Pose,
    /// Width of the opening, metres.
    pub width: f64,
    /// Whether the door is open.
    #[serde(default = "yes")]
    pub open: bool,
    /// The two rooms it joins (optional; derived from the map when absent).
    #[serde(default)]
    pub rooms: Vec<String>,
}

fn yes() -> bool {
    true
}

/// What an object is there for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ObjectRole {
    /// Furniture that other objects stand on or lie in (table, counter, shelf, desk).
    Landmark,
    /// Something the robot may be asked to find.
    Target,
    /// Something that looks like a target to a detector (fires false positives).
    Distractor,
}

/// An object in the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// Unique id (e.g. `table1`).
    pub id: String,
    /// Object class, one of the knowledge file's `object_classes`.
    pub class: String,
    /// Role of the object.
    pub role: ObjectRole,
    /// Pose of the object's centre (its base for landmarks).
    pub pose: Pose,
    /// Bounding box `[length, width, height]`, metres.
    pub size: [f64; 3],
    /// The room it is in.
    pub room: String,
    /// The id of the object it stands on.
    #[serde(default)]
    pub on: Option<String>,
    /// The id of the object it lies in.
    #[serde(default)]
    pub r#in: Option<String>,
}

/// The robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Robot {
    /// Start pose.
    pub start: Pose,
    /// Footprint radius, metres.
    #[serde(default = "default_radius")]
    pub radius: f64,
    /// Travel speed, metres per second (for time estimates).
    #[serde(default = "default_speed")]
    pub speed: f64,
}

fn default_radius() -> f64 {
    0.25
}
fn default_speed() -> f64 {
    0.5
}

/// A planar laser range finder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Laser {
    /// Maximum range, metres.
    pub range: f64,
    /// Field of view, degrees, centred on the robot's heading.
    pub fov_deg: f64,
    /// Number of beams.
    pub beams: usize,
}

impl Default for Laser {
    fn default() -> Self {
        Laser {
            range: 8.0,
            fov_deg: 360.0,
            beams: 360,
        }
    }
}

/// A pan-tilt-zoom camera.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    /// Horizontal field of view at zoom 1, degrees.
    pub hfov_deg: f64,
    /// Vertical field of view at zoom 1, degrees.
    pub vfov_deg: f64,
    /// Pan limits `[min, max]`, degrees relative to the robot's heading.
    pub pan_deg: [f64; 2],
    /// Tilt limits `[min, max]`, degrees (negative looks down).
    pub tilt_deg: [f64; 2],
    /// Largest zoom factor.
    pub max_zoom: f64,
    /// Height of the camera above the floor, metres.
    pub height: f64,
}

impl Default for Camera {
    fn default() -> Self {
        Camera {
            hfov_deg: 45.0,
            vfov_deg: 35.0,
            pan_deg: [-180.0, 180.0],
            tilt_deg: [-45.0, 30.0],
            max_zoom: 4.0,
            height: 1.2,
        }
    }
}
