//! Occupancy grids.
//!
//! Cell `(col, row)` covers world `[ox + col·r, ox + (col+1)·r) × [oy + row·r, oy + (row+1)·r)`;
//! row 0 is the bottom row (y grows upwards), as in ROS. Images and ASCII text list the top row
//! first; the loaders flip them.

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// State of one grid cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Cell {
    /// Known free space.
    Free,
    /// Known obstacle.
    Occupied,
    /// Not (yet) known.
    Unknown,
}

/// Errors reading a map.
#[derive(Debug, thiserror::Error)]
pub enum MapError {
    /// The descriptor or image could not be read.
    #[error("cannot read {path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The map_server descriptor could not be read as YAML: too large, too deeply nested, or
    /// fields of the wrong shape (`FILE:LINE:COLUMN: field: problem; expected …`).
    #[error(transparent)]
    Descriptor(#[from] avs_format::LoadError),
    /// The image could not be decoded.
    #[error("{path}: cannot decode image: {message}")]
    Image {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        message: String,
    },
    /// A parameter is out of range.
    #[error("{field}: {message}")]
    Invalid {
        /// The parameter.
        field: &'static str,
        /// What is wrong and what is expected.
        message: String,
    },
}

/// A ROS map_server descriptor (`image`, `resolution`, `origin`, `negate`, thresholds).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MapServerDescriptor {
    /// Image file, relative to the descriptor.
    pub image: String,
    /// Metres per pixel.
    pub resolution: f64,
    /// `[x, y, yaw]` of the lower-left pixel.
    pub origin: [f64; 3],
    /// 1 if white means occupied.
    #[serde(default)]
    pub negate: u8,
    /// Occupancy probability above which a pixel is occupied.
    pub occupied_thresh: f64,
    /// Occupancy probability below which a pixel is free.
    pub free_thresh: f64,
    /// Ignored map_server fields.
    #[serde(default)]
    pub mode: Option<String>,
}

/// Most cells of a grid (and pixels of an image read as one, [`crate::image_io`]): 64 M, an
/// 8000 × 8000 grid, a 400 m × 400 m floor at 5 cm per cell.
pub const MAX_CELLS: usize = 64_000_000;

/// A 2-D occupancy grid.
#[derive(Debug, Clone, PartialEq)]
pub struct OccupancyGrid {
    width: usize,
    height: usize,
    resolution: f64,
    origin: [f64; 2],
    cells: Vec<Cell>,
}

impl OccupancyGrid {
    /// A grid of `width × height` cells, all `fill`.
    pub fn new(
        width: usize,
        height: usize,
        resolution: f64,
        origin: [f64; 2],
        fill: Cell,
    ) -> Result<Self, MapError> {
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(MapError::Invalid {
                field: "resolution",
                message: format!(
                    "got {resolution}; expected a positive finite number of metres per cell"
                ),
            });
        }
        if !(origin[0].is_finite() && origin[1].is_finite()) {
            return Err(MapError::Invalid {
                field: "origin",
                message: "expected finite coordinates".into(),
            });
        }
        if width == 0 || height == 0 || width.saturating_mul(height) > MAX_CELLS {
            return Err(MapError::Invalid {
                field: "size",
                message: format!("{width}×{height} cells; expected between 1 and 64 million cells"),
            });
        }
        Ok(Self {
            width,
            height,
            resolution,
            origin,
            cells: vec![fill; width * height],
        })
    }

    /// Parse an ASCII grid: `#` occupied, `.` or space free, `?` unknown; top row first. Short
    /// rows are padded with unknown cells.
    pub fn from_ascii(text: &str, resolution: f64, origin: [f64; 2]) -> Result<Self, MapError> {
        let rows: Vec<&str> = text.lines().collect();
        let height = rows.len();
        let width = rows.iter().map(|r| r.chars().count()).max().unwrap_or(0);
        let mut g = Self::new(width, height, resolution, origin, Cell::Unknown)?;
        for (i, line) in rows.iter().enumerate() {
            let row = height - 1 - i;
            for (col, ch) in line.chars().enumerate() {
                let c = match ch {
                    '#' => Cell::Occupied,
                    '.' | ' ' => Cell::Free,
                    '?' => Cell::Unknown,
                    other => {
                        return Err(MapError::Invalid {
                            field: "ascii",
                            message: format!(
                                "character {other:?} at line {}, column {}; expected `#` (occupied), `.` or space (free), `?` (unknown)",
                                i + 1,
                                col + 1
                            ),
                        })
                    }
                };
                g.set(col, row, c);
            }
        }
        Ok(g)
    }

    /// Load a ROS map_server map from its YAML descriptor.
    ///
    /// The descriptor is read like every avs YAML file, by [`avs_format::load_yaml_str`]: at
    /// most [`avs_format::load::MAX_FILE_BYTES`], [`avs_format::positions::MAX_DEPTH`] levels
    /// of nesting and a bounded alias expansion, checked before anything is built (a value
    /// nested 100,000 deep took serde_yaml over a minute), with located diagnostics
    /// ([`MapError::Descriptor`]).
    pub fn from_map_server_yaml(path: &Path) -> Result<Self, MapError> {
        let text = avs_format::load::read_text(path)?;
        let d: MapServerDescriptor = avs_format::load_yaml_str(&path.display().to_string(), &text)?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::from_image(
            &base.join(&d.image),
            d.resolution,
            [d.origin[0], d.origin[1]],
            d.negate != 0,
            d.occupied_thresh,
            d.free_thresh,
        )
    }

    /// Load an image (PGM/PNG) with map_server's trinary interpretation: p = (255 − v) / 255
    /// (or v / 255 when negated); p > occupied_thresh → occupied, p < free_thresh → free,
    /// otherwise unknown. The image is read within the limits of [`crate::image_io`] (at most
    /// [`MAX_CELLS`] pixels, checked before decoding).
    pub fn from_image(
        path: &Path,
        resolution: f64,
        origin: [f64; 2],
        negate: bool,
        occupied_thresh: f64,
        free_thresh: f64,
    ) -> Result<Self, MapError> {
        if !(0.0..=1.0).contains(&free_thresh)
            || !(0.0..=1.0).contains(&occupied_thresh)
            || free_thresh > occupied_thresh
        {
            return Err(MapError::Invalid {
                field: "free_thresh/occupied_thresh",
                message: format!("got {free_thresh}/{occupied_thresh}; expected 0 ≤ free_thresh ≤ occupied_thresh ≤ 1"),
            });
        }
        let img = crate::image_io::open_image(path).map_err(|e| match e {
            crate::image_io::ImageReadError::Io(source) => MapError::Io {
                path: path.to_path_buf(),
                source,
            },
            other => MapError::Image {
                path: path.to_path_buf(),
                message: other.to_string(),
            },
        })?;
        let luma = img.to_luma8();
        let (w, h) = (luma.width() as usize, luma.height() as usize);
        let mut g = Self::new(w, h, resolution, origin, Cell::Unknown)?;
        for (x, y, p) in luma.enumerate_pixels() {
            let v = p.0[0] as f64;
            let occ = if negate {
                v / 255.0
            } else {
                (255.0 - v) / 255.0
            };
            let c = if occ > occupied_thresh {
                Cell::Occupied
            } else if occ < free_thresh {
                Cell::Free
            } else {
                Cell::Unknown
            };
            g.set(x as usize, h - 1 - y as usize, c);
        }
        Ok(g)
    }

    /// Width in cells.
    pub fn width(&self) -> usize {
        self.width
    }
    /// Height in cells.
    pub fn height(&self) -> usize {
        self.height
    }
    /// Metres per cell.
    pub fn resolution(&self) -> f64 {
        self.resolution
    }
    /// World position of the lower-left corner.
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }
    /// All cells, row-major from the bottom row.
    pub fn cells(&self) -> &[Cell] {
        &self.cells
    }

    /// Cell at `(col, row)`; outside the grid is [`Cell::Unknown`], so callers decide.
    pub fn get(&self, col: usize, row: usize) -> Cell {
        if col < self.width && row < self.height {
            self.cells[row * self.width + col]
        } else {
            Cell::Unknown
        }
    }

    /// Cell at signed coordinates; outside the grid is [`Cell::Unknown`].
    pub fn get_i(&self, col: i64, row: i64) -> Cell {
        if col < 0 || row < 0 {
            Cell::Unknown
        } else {
            self.get(col as usize, row as usize)
        }
    }

    /// Set the cell at `(col, row)`; out of bounds is ignored.
    pub fn set(&mut self, col: usize, row: usize, c: Cell) {
        if col < self.width && row < self.height {
            self.cells[row * self.width + col] = c;
        }
    }

    /// Whether `(col, row)` lies inside the grid.
    pub fn contains(&self, col: i64, row: i64) -> bool {
        col >= 0 && row >= 0 && (col as usize) < self.width && (row as usize) < self.height
    }

    /// The cell containing world point `(x, y)` (may lie outside the grid).
    pub fn world_to_cell(&self, x: f64, y: f64) -> (i64, i64) {
        (
            ((x - self.origin[0]) / self.resolution).floor() as i64,
            ((y - self.origin[1]) / self.resolution).floor() as i64,
        )
    }

    /// World position of the centre of cell `(col, row)`.
    pub fn cell_center(&self, col: i64, row: i64) -> (f64, f64) {
        (
            self.origin[0] + (col as f64 + 0.5) * self.resolution,
            self.origin[1] + (row as f64 + 0.5) * self.resolution,
        )
    }

    /// Index of `(col, row)` in [`Self::cells`].
    pub fn index(&self, col: usize, row: usize) -> usize {
        row * self.width + col
    }

    /// Number of cells in state `c`.
    pub fn count(&self, c: Cell) -> usize {
        self.cells.iter().filter(|&&x| x == c).count()
    }

    /// Whether every cell whose centre lies within `radius` of `p` is known free (the cell
    /// holding `p` always counts; outside the grid is unknown): the laser has seen open floor
    /// all around `p`, so nothing that stands on the floor and blocks the laser is there.
    pub fn free_within(&self, p: [f64; 2], radius: f64) -> bool {
        let (c0, r0) = self.world_to_cell(p[0], p[1]);
        if self.get_i(c0, r0) != Cell::Free {
            return false;
        }
        let k = (radius.max(0.0) / self.resolution).ceil() as i64;
        (-k..=k).all(|dr| {
            (-k..=k).all(|dc| {
                let (x, y) = self.cell_center(c0 + dc, r0 + dr);
                (x - p[0]).hypot(y - p[1]) > radius || self.get_i(c0 + dc, r0 + dr) == Cell::Free
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_within_holds_only_where_every_cell_in_the_disc_is_known_free() {
        // 0.5 m cells: a wall along the top row, unknown space in the bottom-left corner.
        let g =
            OccupancyGrid::from_ascii("######\n......\n......\n......\n??....", 0.5, [0.0, 0.0])
                .unwrap();
        // Row 2 from the top is y 1.0–1.5; the middle of the grid is open floor for a metre.
        assert!(g.free_within([1.75, 1.25], 0.5));
        // A disc that reaches the wall row (y ≥ 2.0) or the unknown corner is not.
        assert!(!g.free_within([1.75, 1.75], 0.5));
        assert!(!g.free_within([0.75, 0.75], 0.5));
        // Radius 0 asks about the cell holding the point alone; beyond the grid is unknown.
        assert!(g.free_within([1.75, 1.75], 0.0));
        assert!(!g.free_within([-1.0, 1.0], 0.0));
    }

    /// Issue 18 reproducer: a map descriptor with a value nested 100,000 deep took serde_yaml
    /// over a minute; the descriptor is now read with the avs YAML loader's bounds and the
    /// error names the line and column where the nesting passes the cap.
    #[test]
    fn a_deeply_nested_descriptor_is_refused_with_its_position() {
        let dir = std::env::temp_dir().join(format!("avs-descriptor-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("deep.yaml");
        let deep = format!("image: {}x{}\n", "[".repeat(100_000), "]".repeat(100_000));
        std::fs::write(&path, deep).unwrap();
        let e = OccupancyGrid::from_map_server_yaml(&path).unwrap_err();
        let MapError::Descriptor(load) = &e else {
            panic!("expected a descriptor error, got {e:?}");
        };
        let d = &load.diagnostics[0];
        assert_eq!(d.file, path.display().to_string());
        assert_eq!(d.line, Some(1), "{d}");
        assert!(d.message.contains("nest"), "{d}");
        // A sound descriptor with a wrong field is located too.
        std::fs::write(&path, "image: x.png\nresolution: fine\n").unwrap();
        let e = OccupancyGrid::from_map_server_yaml(&path).unwrap_err();
        let MapError::Descriptor(load) = &e else {
            panic!("expected a descriptor error, got {e:?}");
        };
        assert_eq!(load.diagnostics[0].path, "resolution");
        assert_eq!(load.diagnostics[0].line, Some(2));
        std::fs::remove_dir_all(&dir).ok();
    }
}
