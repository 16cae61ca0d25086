//! The ground-truth world built from an environment file.

use avs_format::environment::{Environment, MapSource};
use avs_map::grid::{MapError, OccupancyGrid};
use std::path::Path;

/// Errors building or running the simulated world.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The environment's map could not be loaded.
    #[error("map: {0}")]
    Map(#[from] MapError),
    /// The environment refers to something that does not exist or is inconsistent.
    #[error("{field}: {message}")]
    Invalid {
        /// Dotted path of the field.
        field: String,
        /// What is wrong and what is expected.
        message: String,
    },
}

/// The occupancy grid of an environment; `base_dir` is the folder of the environment file
/// (image paths are relative to it).
pub fn load_grid(env: &Environment, base_dir: &Path) -> Result<OccupancyGrid, SimError> {
    Ok(match &env.map {
        MapSource::Ascii(a) => OccupancyGrid::from_ascii(&a.ascii, a.resolution, a.origin)?,
        MapSource::Ros(r) => OccupancyGrid::from_image(
            &base_dir.join(&r.image),
            r.resolution,
            [r.origin[0], r.origin[1]],
            r.negate != 0,
            r.occupied_thresh,
            r.free_thresh,
        )?,
    })
}
