//! Door hypotheses from an occupancy grid: narrow openings between obstacles.
//!
//! The method is the *critical point* construction on the generalized Voronoi diagram (GVD) of
//! free space (Thrun, *Learning metric-topological maps for indoor mobile robot navigation*, AIJ
//! 1998, §3.2; used for room segmentation by Bormann et al., *Room segmentation: survey,
//! implementation, and analysis*, ICRA 2016, §III-C):
//!
//! 1. the exact Euclidean distance transform of free space with its feature transform (the
//!    nearest non-free cell of every cell), by the separable lower-envelope algorithm of
//!    Felzenszwalb & Huttenlocher (*Distance transforms of sampled functions*, ToC 2012,
//!    eq. 1 and Algorithm 1): `D(p) = min_q ‖p − q‖` over non-free cells `q`;
//! 2. a free cell lies on the GVD (the medial axis) where its nearest non-free cell and that
//!    of a 4-neighbour are different *basis points* on opposite sides of it — the angle
//!    they subtend at the cell is at least `acos(DoorParams::opposition_cos)`;
//! 3. a *critical point* is a GVD cell whose clearance is a local minimum (Thrun 1998, §3.2:
//!    critical points are the points of the Voronoi diagram that minimise clearance locally).
//!    Two conditions make this concrete on a grid:
//!    - *neck*: on both sides of the line joining the two basis points, within
//!      [`DoorParams::neck_depth`] along a fan of rays (±30° about its normal), free space
//!      widens: some free cell has a free run parallel to that line of at least
//!      [`DoorParams::neck_ratio`] times the jamb distance. Measuring width rather than
//!      clearance (our choice) keeps doors onto corridors narrower than the door, which the
//!      benchmark maps contain, while a uniform corridor still has no critical point;
//!    - *non-maximum suppression*: candidates are taken narrowest first (then by smallest
//!      clearance); one whose jamb-line midpoint lies within the half-width of an accepted
//!      door, or whose jamb line crosses an accepted one, is the same opening;
//! 4. the two basis points are the door's jambs; the opening width is the free gap between the
//!    jamb cells, `(‖a − b‖ − 1) · resolution`, and must lie in
//!    `[DoorParams::min_width, DoorParams::max_width]`.
//!
//! Unknown cells (and the space outside the grid) are not free, so they bound the clearance,
//! but they are not obstacles: a gap whose nearest non-free cell on either side is unknown is a
//! frontier, not a door, and is not reported; and the neck test lets free space widen into
//! unknown cells, so a doorway in a seen wall is a hypothesis before the room behind it is
//! seen (the place map confirms it when the robot passes through, [`DoorHypothesis::crossed_by`]). Whole-map segmentation ([`crate::segment`])
//! treats a complete map's non-free cells as walls.
//!
//! ```
//! use avs_map::doors::{detect_doors, DoorParams};
//! use avs_map::grid::OccupancyGrid;
//! // Two 2 m rooms joined by a 0.9 m gap in a wall (0.1 m cells).
//! let mut text = String::new();
//! for row in 0..22 {
//!     for col in 0..43 {
//!         let wall = row == 0 || row == 21 || col == 0 || col == 42
//!             || (col == 21 && !(7..16).contains(&row));
//!         text.push(if wall { '#' } else { '.' });
//!     }
//!     text.push('\n');
//! }
//! let grid = OccupancyGrid::from_ascii(&text, 0.1, [0.0, 0.0]).unwrap();
//! let doors = detect_doors(&grid, &DoorParams::default());
//! assert_eq!(doors.len(), 1);
//! assert!((doors[0].width - 0.9).abs() < 0.11);
//! ```

use crate::grid::{Cell, OccupancyGrid};
use serde::{Deserialize, Serialize};

/// Errors in door parameters.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DoorError {
    /// A parameter is out of range.
    #[error("door parameter {field}: got {value}; expected {expected}")]
    Invalid {
        /// The parameter.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
    /// A free-space mask does not match the grid size.
    #[error("free-space mask has {len} cells; expected width × height = {width} × {height}")]
    MaskSize {
        /// Grid width.
        width: usize,
        /// Grid height.
        height: usize,
        /// Cells in the mask.
        len: usize,
    },
}

/// Parameters of door detection (lengths in metres).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DoorParams {
    /// Narrowest opening that counts as a door (default 0.7 m).
    pub min_width: f64,
    /// Widest opening that counts as a door (default 1.2 m).
    pub max_width: f64,
    /// How far on each side of the door line the clearance is examined (default 1.0 m).
    pub neck_depth: f64,
    /// On both sides within `neck_depth`, free space must widen to at least this multiple of
    /// the jamb distance, measured parallel to the door line (default 1.3); a uniform corridor
    /// is not a door.
    pub neck_ratio: f64,
    /// Cosine of the smallest angle the two jambs subtend at a GVD cell (default −0.7, i.e.
    /// about 134°): the jambs must lie on opposite sides of the opening.
    pub opposition_cos: f64,
}

impl Default for DoorParams {
    fn default() -> Self {
        Self {
            min_width: 0.7,
            max_width: 1.2,
            neck_depth: 1.0,
            neck_ratio: 1.3,
            opposition_cos: -0.7,
        }
    }
}

impl DoorParams {
    /// Check every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<(), DoorError> {
        let check = |field, value: f64, ok: bool, expected| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(DoorError::Invalid {
                    field,
                    value,
                    expected,
                })
            }
        };
        check(
            "min_width",
            self.min_width,
            self.min_width >= 0.0,
            "a finite width ≥ 0 m",
        )?;
        check(
            "max_width",
            self.max_width,
            self.max_width >= self.min_width && self.max_width > 0.0,
            "a finite width > 0 m and ≥ min_width",
        )?;
        check(
            "neck_depth",
            self.neck_depth,
            self.neck_depth > 0.0,
            "a finite length > 0 m",
        )?;
        check(
            "neck_ratio",
            self.neck_ratio,
            self.neck_ratio >= 1.0,
            "a finite ratio ≥ 1",
        )?;
        check(
            "opposition_cos",
            self.opposition_cos,
            (-1.0..=0.0).contains(&self.opposition_cos),
            "a cosine in [−1, 0]",
        )
    }
}

/// A door hypothesis, in world metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DoorHypothesis {
    /// Midpoint between the jambs.
    pub center: [f64; 2],
    /// Centres of the two jamb cells (the nearest obstacles on either side of the opening).
    pub jambs: [[f64; 2]; 2],
    /// Free width of the opening.
    pub width: f64,
}

impl DoorHypothesis {
    /// The unit vector along the door line, from the first jamb to the second; `None` when
    /// the jambs coincide.
    pub fn axis(&self) -> Option<[f64; 2]> {
        let [a, b] = self.jambs;
        let len = crate::geometry::dist(a, b);
        (len > 0.0).then(|| [(b[0] - a[0]) / len, (b[1] - a[1]) / len])
    }

    /// Whether the straight move `from → to` crosses the door line between the jambs — how a
    /// place map confirms a hypothesis when the robot passes through it.
    pub fn crossed_by(&self, from: [f64; 2], to: [f64; 2]) -> bool {
        let [a, b] = self.jambs;
        let cross = |o: [f64; 2], p: [f64; 2], q: [f64; 2]| {
            (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])
        };
        let d1 = cross(a, b, from);
        let d2 = cross(a, b, to);
        let d3 = cross(from, to, a);
        let d4 = cross(from, to, b);
        // Half-open on the door line: a move that ends exactly on the line counts as crossing,
        // the next one leaving it does not, so a path through waypoints on the line (cell
        // centres often are) crosses once.
        let sides_differ = (d1 < 0.0 && d2 >= 0.0) || (d1 >= 0.0 && d2 < 0.0);
        sides_differ && d3 * d4 <= 0.0 && !(d3 == 0.0 && d4 == 0.0)
    }
}

/// Exact Euclidean distance and feature transform of a grid's free space (in cells).
///
/// For every cell, the squared distance to the nearest non-free cell and that cell; cells
/// outside the grid count as non-free. Felzenszwalb & Huttenlocher 2012, Algorithm 1 applied
/// to columns then rows; the feature transform keeps the argmin of the lower envelope.
#[derive(Debug, Clone)]
pub struct ClearanceMap {
    width: usize,
    height: usize,
    /// Squared distance in cells to the nearest non-free cell (0 on non-free cells).
    dist2: Vec<i64>,
    /// Nearest non-free cell as (col, row); may lie one cell outside the grid.
    feature: Vec<(i32, i32)>,
}

impl ClearanceMap {
    /// Compute the transform; `free[i]` says whether cell `i` (grid index order) is free.
    pub fn new(width: usize, height: usize, free: &[bool]) -> Result<Self, DoorError> {
        if width.checked_mul(height) != Some(free.len()) {
            return Err(DoorError::MaskSize {
                width,
                height,
                len: free.len(),
            });
        }
        Ok(Self::from_mask(width, height, free))
    }

    pub(crate) fn from_mask(width: usize, height: usize, free: &[bool]) -> Self {
        // Padded frame: one non-free ring around the grid.
        let (pw, ph) = (width + 2, height + 2);
        let is_site = |x: usize, y: usize| -> bool {
            x == 0 || y == 0 || x == pw - 1 || y == ph - 1 || !free[(y - 1) * width + (x - 1)]
        };
        // Column pass: nearest site row in the same column, swept row by row (cache-friendly).
        let mut near_row = vec![0i32; pw * ph];
        let mut up = vec![-1i32; pw];
        for y in 0..ph {
            for (x, u) in up.iter_mut().enumerate() {
                if is_site(x, y) {
                    *u = y as i32;
                }
                near_row[y * pw + x] = *u;
            }
        }
        let mut down = vec![i32::MAX; pw];
        for y in (0..ph).rev() {
            for (x, d) in down.iter_mut().enumerate() {
                if is_site(x, y) {
                    *d = y as i32;
                }
                let u = near_row[y * pw + x];
                if u < 0 || (*d != i32::MAX && (*d - y as i32) < (y as i32 - u)) {
                    near_row[y * pw + x] = *d;
                }
            }
        }
        // Row pass: lower envelope of parabolas (x − q)² + g(q)².
        let mut dist2 = vec![0i64; width * height];
        let mut feature = vec![(0i32, 0i32); width * height];
        let mut v = vec![0usize; pw];
        let mut z = vec![0f64; pw + 1];
        let mut f = vec![0i64; pw];
        for y in 1..ph - 1 {
            for (q, fq) in f.iter_mut().enumerate() {
                let g = (near_row[y * pw + q] as i64 - y as i64).abs();
                *fq = g * g;
            }
            let mut k = 0usize;
            v[0] = 0;
            z[0] = f64::NEG_INFINITY;
            z[1] = f64::INFINITY;
            for q in 1..pw {
                loop {
                    let p = v[k];
                    let s = ((f[q] + (q * q) as i64) - (f[p] + (p * p) as i64)) as f64
                        / (2.0 * (q as f64 - p as f64));
                    if s <= z[k] && k > 0 {
                        k -= 1;
                    } else {
                        k += 1;
                        v[k] = q;
                        z[k] = s;
                        z[k + 1] = f64::INFINITY;
                        break;
                    }
                }
            }
            k = 0;
            for x in 1..pw - 1 {
                while z[k + 1] < x as f64 {
                    k += 1;
                }
                let q = v[k];
                let dx = x as i64 - q as i64;
                let i = (y - 1) * width + (x - 1);
                dist2[i] = dx * dx + f[q];
                feature[i] = (q as i32 - 1, near_row[y * pw + q] - 1);
            }
        }
        Self {
            width,
            height,
            dist2,
            feature,
        }
    }

    /// Distance in cells from cell `i` to the nearest non-free cell.
    pub fn distance(&self, i: usize) -> f64 {
        (self.dist2[i] as f64).sqrt()
    }

    /// Nearest non-free cell of cell `i` as signed `(col, row)` (may be just outside the grid).
    pub fn feature(&self, i: usize) -> (i32, i32) {
        self.feature[i]
    }

    /// Grid width in cells.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Grid height in cells.
    pub fn height(&self) -> usize {
        self.height
    }
}

/// A detected door in cell coordinates, as used by segmentation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct CellDoor {
    /// The critical GVD cell.
    pub(crate) critical: (i32, i32),
    /// The two jamb cells.
    pub(crate) jambs: [(i32, i32); 2],
    /// Free width in cells.
    pub(crate) width_cells: f64,
}

/// Door hypotheses of a grid (see the module docs for the method). Invalid parameters yield no
/// doors and a warning; use [`DoorParams::validate`] to get the error.
pub fn detect_doors(grid: &OccupancyGrid, params: &DoorParams) -> Vec<DoorHypothesis> {
    if let Err(e) = params.validate() {
        tracing::warn!("detect_doors: {e}; no doors reported");
        return Vec::new();
    }
    let free: Vec<bool> = grid.cells().iter().map(|&c| c == Cell::Free).collect();
    let clearance = ClearanceMap::from_mask(grid.width(), grid.height(), &free);
    detect_cell_doors(grid, &free, &clearance, params)
        .into_iter()
        .map(|d| to_world(grid, &d))
        .collect()
}

/// World-coordinate hypothesis of a cell door.
pub(crate) fn to_world(grid: &OccupancyGrid, d: &CellDoor) -> DoorHypothesis {
    let c = |(x, y): (i32, i32)| {
        let (wx, wy) = grid.cell_center(x as i64, y as i64);
        [wx, wy]
    };
    let a = c(d.jambs[0]);
    let b = c(d.jambs[1]);
    DoorHypothesis {
        center: [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0],
        jambs: [a, b],
        width: d.width_cells * grid.resolution(),
    }
}

/// Critical points of the GVD whose opening lies in the width range (cell coordinates).
pub(crate) fn detect_cell_doors(
    grid: &OccupancyGrid,
    free: &[bool],
    clearance: &ClearanceMap,
    params: &DoorParams,
) -> Vec<CellDoor> {
    let (w, h) = (grid.width(), grid.height());
    let res = grid.resolution();
    let min_w = params.min_width / res;
    let max_w = params.max_width / res;
    // A door's critical cell has clearance at most about half the widest opening.
    let max_clear2 = ((max_w + 2.0) / 2.0).powi(2).ceil() as i64;
    let is_obstacle =
        |(x, y): (i32, i32)| x >= 0 && y >= 0 && grid.get(x as usize, y as usize) == Cell::Occupied;
    let mut candidates: Vec<(f64, i64, CellDoor)> = Vec::new();
    for row in 0..h {
        for col in 0..w {
            let i = row * w + col;
            if !free[i] || clearance.dist2[i] > max_clear2 {
                continue;
            }
            let a = clearance.feature[i];
            let (cx, cy) = (col as f64, row as f64);
            let neighbours = [(col + 1 < w).then(|| i + 1), (row + 1 < h).then(|| i + w)];
            for n in neighbours.into_iter().flatten() {
                if !free[n] {
                    continue;
                }
                let b = clearance.feature[n];
                if a == b {
                    continue;
                }
                let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
                let width = (dx * dx + dy * dy).sqrt() - 1.0;
                if width < min_w || width > max_w {
                    continue;
                }
                let (ax, ay) = (a.0 as f64 - cx, a.1 as f64 - cy);
                let (bx, by) = (b.0 as f64 - cx, b.1 as f64 - cy);
                let na = (ax * ax + ay * ay).sqrt();
                let nb = (bx * bx + by * by).sqrt();
                if na == 0.0 || nb == 0.0 || (ax * bx + ay * by) / (na * nb) > params.opposition_cos
                {
                    continue;
                }
                if !(is_obstacle(a) && is_obstacle(b)) {
                    continue;
                }
                let door = CellDoor {
                    critical: (col as i32, row as i32),
                    jambs: [a, b],
                    width_cells: width,
                };
                candidates.push((width, clearance.dist2[i], door));
            }
        }
    }
    // Narrowest first; ties by clearance (the critical cell is the clearance minimum).
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
    let depth = (params.neck_depth / res).max(1.0);
    let mut doors: Vec<CellDoor> = Vec::new();
    for (width, _, door) in candidates {
        // Non-maximum suppression: a candidate is the same opening as an accepted (narrower)
        // door when its midpoint lies within that door's half-width or the two lines cross.
        if doors.iter().any(|d| {
            let (mx, my) = midpoint(d);
            let (ox, oy) = midpoint(&door);
            let r = (d.width_cells + 1.0) / 2.0;
            (mx - ox).powi(2) + (my - oy).powi(2) < r * r || lines_cross(d, &door)
        }) {
            continue;
        }
        if !is_neck(grid, &door, width, depth, params.neck_ratio) {
            continue;
        }
        doors.push(door);
    }
    doors
}

/// Whether the jamb-to-jamb segments of two doors intersect (touching counts).
fn lines_cross(p: &CellDoor, q: &CellDoor) -> bool {
    let f = |(x, y): (i32, i32)| (f64::from(x), f64::from(y));
    let (a, b, c, d) = (f(p.jambs[0]), f(p.jambs[1]), f(q.jambs[0]), f(q.jambs[1]));
    let orient = |o: (f64, f64), p: (f64, f64), q: (f64, f64)| {
        (p.0 - o.0) * (q.1 - o.1) - (p.1 - o.1) * (q.0 - o.0)
    };
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0 && !(d1 == 0.0 && d2 == 0.0)
}

fn midpoint(d: &CellDoor) -> (f64, f64) {
    let [a, b] = d.jambs;
    ((a.0 + b.0) as f64 / 2.0, (a.1 + b.1) as f64 / 2.0)
}

/// Whether the free space widens on both sides of the door line within `depth` cells (unknown
/// cells count as open, obstacles do not): on each side, a fan of rays from the door's midpoint (within 30° of the normal of the jamb line,
/// until the first non-free cell past the jamb line) must reach a free cell whose free run
/// parallel to the jamb line is at least `ratio ×` the jamb distance. This is the
/// local-minimum condition of a critical point (Thrun 1998, §3.2) measured as opening width
/// rather than clearance, so that a door onto a corridor narrower than the door still counts.
fn is_neck(grid: &OccupancyGrid, door: &CellDoor, width: f64, depth: f64, ratio: f64) -> bool {
    let [a, b] = door.jambs;
    let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
    let len = (dx * dx + dy * dy).sqrt();
    let (ux, uy) = (dx / len, dy / len);
    let (nx, ny) = (-uy, ux);
    let (mx, my) = midpoint(door);
    let need = ratio * (width + 1.0);
    let w = grid.width() as i64;
    let cells = grid.cells();
    // Unknown space is not an obstacle: a door may open onto a room not yet seen.
    let free_at = |x: f64, y: f64| -> Option<bool> {
        let (x, y) = (x.round() as i64, y.round() as i64);
        grid.contains(x, y)
            .then(|| cells[(y * w + x) as usize] != Cell::Occupied)
    };
    // Free run through (px, py) along ±u, stopping once `need` is reached.
    let run = |px: f64, py: f64| -> f64 {
        let mut total = 1.0;
        for s in [1.0, -1.0] {
            let mut k = 1.0;
            while total < need && free_at(px + s * k * ux, py + s * k * uy) == Some(true) {
                total += 1.0;
                k += 1.0;
            }
        }
        total
    };
    let ray_widens = |rx: f64, ry: f64| -> bool {
        let mut t = 0.0;
        while t <= depth {
            let (px, py) = (mx + t * rx, my + t * ry);
            match free_at(px, py) {
                None => return false,
                Some(false) if t > 1.0 => return false,
                Some(false) => {}
                Some(true) => {
                    if run(px, py) >= need {
                        return true;
                    }
                }
            }
            t += 1.0;
        }
        false
    };
    [1.0f64, -1.0].iter().all(|&s| {
        (-2..=2).any(|k| {
            let phi = f64::from(k) * 15f64.to_radians();
            let (c, si) = (phi.cos(), phi.sin());
            ray_widens(s * (nx * c - ny * si), s * (nx * si + ny * c))
        })
    })
}
