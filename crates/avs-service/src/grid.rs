//! Occupancy grids on the wire, in `nav_msgs/OccupancyGrid` conventions (without the header),
//! so that a ROS bridge fills them by field copy: `info.resolution`, `info.width`,
//! `info.height`, `info.origin` (a pose; must not be rotated), and `data`, row-major from the
//! origin with row 0 at the origin's y, `-1` unknown, `0`–`49` free, `50`–`100` occupied (the
//! usual map-server threshold of one half).

use avs_map::grid::{Cell, OccupancyGrid};
use serde::{Deserialize, Serialize};
use utoipa::ToSchema;

/// A `geometry_msgs/Point`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RosPoint {
    /// x, metres.
    pub x: f64,
    /// y, metres.
    pub y: f64,
    /// z, metres.
    #[serde(default)]
    pub z: f64,
}

/// A `geometry_msgs/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RosQuaternion {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
    /// w.
    pub w: f64,
}

impl Default for RosQuaternion {
    fn default() -> Self {
        Self {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            w: 1.0,
        }
    }
}

/// A `geometry_msgs/Pose`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize, ToSchema)]
#[serde(deny_unknown_fields)]
pub struct RosPose {
    /// Position, metres.
    pub position: RosPoint,
    /// Orientation (the identity for a grid avs can read).
    #[serde(default)]
    pub orientation: RosQuaternion,
}

/// A `nav_msgs/MapMetaData` without its load time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct MapInfo {
    /// Metres per cell.
    pub resolution: f64,
    /// Cells per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// The pose of cell (0, 0)'s corner.
    pub origin: RosPose,
}

/// A `nav_msgs/OccupancyGrid` without its header.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, ToSchema)]
pub struct RosGrid {
    /// The grid's geometry.
    pub info: MapInfo,
    /// Row-major cells from the origin: `-1` unknown, `0`–`49` free, `50`–`100` occupied.
    pub data: Vec<i8>,
}

/// What is wrong with a grid: the field and what is expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {message}")]
pub struct GridError {
    /// The field, e.g. `grid.data[12]`.
    pub field: String,
    /// What is wrong and what is expected.
    pub message: String,
}

impl RosGrid {
    /// The wire form of `g`.
    pub fn from_grid(g: &OccupancyGrid) -> Self {
        let [x, y] = g.origin();
        RosGrid {
            info: MapInfo {
                resolution: g.resolution(),
                width: g.width(),
                height: g.height(),
                origin: RosPose {
                    position: RosPoint { x, y, z: 0.0 },
                    orientation: RosQuaternion::default(),
                },
            },
            data: g
                .cells()
                .iter()
                .map(|c| match c {
                    Cell::Free => 0,
                    Cell::Occupied => 100,
                    Cell::Unknown => -1,
                })
                .collect(),
        }
    }

    /// The grid it describes; errors name the field (under `at`, e.g. `result.grid`).
    pub fn to_grid(&self, at: &str) -> Result<OccupancyGrid, GridError> {
        let bad = |field: &str, message: String| GridError {
            field: format!("{at}.{field}"),
            message,
        };
        let i = &self.info;
        let q = i.origin.orientation;
        let yaw_free = q.x.abs() < 1e-9 && q.y.abs() < 1e-9 && q.z.abs() < 1e-9;
        if !(yaw_free && (q.w.abs() - 1.0).abs() < 1e-9) {
            return Err(bad(
                "info.origin.orientation",
                format!(
                    "({}, {}, {}, {}): expected the identity (0, 0, 0, 1); avs reads unrotated grids",
                    q.x, q.y, q.z, q.w
                ),
            ));
        }
        let expected = i.width.checked_mul(i.height);
        if expected != Some(self.data.len()) {
            return Err(bad(
                "data",
                format!(
                    "{} cells; expected info.width × info.height = {} × {}",
                    self.data.len(),
                    i.width,
                    i.height
                ),
            ));
        }
        let origin = [i.origin.position.x, i.origin.position.y];
        let mut g = OccupancyGrid::new(i.width, i.height, i.resolution, origin, Cell::Unknown)
            .map_err(|e| bad("info", e.to_string()))?;
        for (k, &v) in self.data.iter().enumerate() {
            let c = match v {
                -1 => Cell::Unknown,
                0..=49 => Cell::Free,
                50..=100 => Cell::Occupied,
                _ => {
                    return Err(bad(
                        &format!("data[{k}]"),
                        format!("{v}; expected -1 (unknown) or 0..=100 (occupancy, %)"),
                    ))
                }
            };
            if c != Cell::Unknown {
                g.set(k % i.width, k / i.width, c);
            }
        }
        Ok(g)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_survives_the_wire_and_row_zero_is_the_origins_row() {
        // Top row first in ASCII: the bottom row (row 0) is "#.?".
        let g = OccupancyGrid::from_ascii("...\n#.?", 0.5, [1.0, -2.0]).unwrap();
        let w = RosGrid::from_grid(&g);
        assert_eq!(w.data[..3], [100, 0, -1]);
        assert_eq!(w.info.origin.position.x, 1.0);
        let back = w.to_grid("grid").unwrap();
        assert_eq!(back, g);
        // Through JSON as a client would send it.
        let json = serde_json::to_string(&w).unwrap();
        let again: RosGrid = serde_json::from_str(&json).unwrap();
        assert_eq!(again.to_grid("grid").unwrap(), g);
    }

    #[test]
    fn bad_grids_name_the_field() {
        let g = OccupancyGrid::from_ascii("..", 0.5, [0.0, 0.0]).unwrap();
        let mut w = RosGrid::from_grid(&g);
        w.data[1] = 101;
        assert_eq!(
            w.to_grid("result.grid").unwrap_err().field,
            "result.grid.data[1]"
        );
        w.data.pop();
        assert_eq!(w.to_grid("g").unwrap_err().field, "g.data");
        let mut w = RosGrid::from_grid(&g);
        w.info.origin.orientation = RosQuaternion {
            x: 0.0,
            y: 0.0,
            z: std::f64::consts::FRAC_1_SQRT_2,
            w: std::f64::consts::FRAC_1_SQRT_2,
        };
        assert!(w.to_grid("g").unwrap_err().field.ends_with("orientation"));
        let mut w = RosGrid::from_grid(&g);
        w.info.resolution = 0.0;
        assert_eq!(w.to_grid("g").unwrap_err().field, "g.info");
    }
}
