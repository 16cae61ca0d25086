//! Room segmentation of a complete map by door hypotheses.
//!
//! Sjöö et al. (`004_eb11ea0b2ea7be93.txt` §2) obtain rooms "by dividing the navigation graph
//! into subgraphs by cutting out all the door nodes", and assign every feature "to the room
//! which has the nearest navigation node". On a whole grid the same construction reads:
//!
//! 1. door hypotheses by [`crate::doors`] (critical points of the GVD with an opening in the
//!    door width range), treating every non-free cell of the complete map as a wall;
//! 2. cut each door: the free cells on the digital straight line (Bresenham) between its two
//!    jambs are removed — the grid analogue of cutting the door node;
//! 3. rooms are the 4-connected components of the remaining free cells;
//! 4. components smaller than [`SegmentParams::min_room_area`] are not rooms (niches cut off
//!    by spurious hypotheses, pockets behind furniture): their cells are released;
//! 5. every released or cut free cell joins the room with the geodesically nearest cell — a
//!    multi-source breadth-first wavefront through free space, the grid form of "the nearest
//!    navigation node";
//! 6. free pockets no room reaches through free space (the inside of a furniture outline, a
//!    cupboard) join the room nearest through walls when smaller than
//!    [`SegmentParams::enclosure_area`] — Sjöö et al. assign every map feature to the room of
//!    the nearest navigation node; larger ones are rooms of their own if they reach the
//!    minimum room area, and a map with no room at all leaves pockets below it unlabelled.
//!
//! A door hypothesis is reported as used when the rooms on its two sides differ after step 5.
//!
//! ```
//! use avs_map::grid::OccupancyGrid;
//! use avs_map::segment::{segment_rooms, SegmentParams};
//! // Two 2 m × 2 m rooms joined by a 0.9 m doorway (0.1 m cells).
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
//! let seg = segment_rooms(&grid, &SegmentParams::default()).unwrap();
//! assert_eq!(seg.rooms, 2);
//! assert_eq!(seg.doors.len(), 1);
//! assert_ne!(seg.labels[grid.index(5, 10)], seg.labels[grid.index(35, 10)]);
//! ```

use crate::doors::DoorHypothesis;
use crate::doors::{detect_cell_doors, to_world, CellDoor, ClearanceMap, DoorError, DoorParams};
use crate::grid::{Cell, OccupancyGrid};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// Errors of segmentation.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SegmentError {
    /// A door parameter is out of range.
    #[error(transparent)]
    Door(#[from] DoorError),
    /// A segmentation parameter is out of range.
    #[error("segment parameter {field}: got {value}; expected {expected}")]
    Invalid {
        /// The parameter.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// What is expected.
        expected: &'static str,
    },
}

/// Parameters of room segmentation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SegmentParams {
    /// Door hypothesis parameters.
    pub doors: DoorParams,
    /// Smallest room, in square metres (default 1.0 m²); smaller pieces join a neighbour.
    pub min_room_area: f64,
    /// Free pockets that no room reaches through free space and that are smaller than this
    /// (square metres, default 4.0 m²) join the nearest room through walls instead of
    /// forming rooms (the inside of furniture outlines, cupboards).
    pub enclosure_area: f64,
}

impl Default for SegmentParams {
    fn default() -> Self {
        Self {
            doors: DoorParams::default(),
            min_room_area: 1.0,
            enclosure_area: 4.0,
        }
    }
}

impl SegmentParams {
    /// Check every parameter, naming the first one out of range.
    pub fn validate(&self) -> Result<(), SegmentError> {
        self.doors.validate()?;
        if !(self.min_room_area.is_finite() && self.min_room_area >= 0.0) {
            return Err(SegmentError::Invalid {
                field: "min_room_area",
                value: self.min_room_area,
                expected: "a finite area ≥ 0 m²",
            });
        }
        if !(self.enclosure_area.is_finite() && self.enclosure_area >= 0.0) {
            return Err(SegmentError::Invalid {
                field: "enclosure_area",
                value: self.enclosure_area,
                expected: "a finite area ≥ 0 m²",
            });
        }
        Ok(())
    }
}

/// A room segmentation of a grid.
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    /// Grid width in cells.
    pub width: usize,
    /// Grid height in cells.
    pub height: usize,
    /// Room of every cell (`OccupancyGrid::index` order): 1..=`rooms`, 0 = no room.
    pub labels: Vec<u32>,
    /// Number of rooms.
    pub rooms: usize,
    /// The door hypotheses that separate two different rooms.
    pub doors: Vec<DoorHypothesis>,
}

/// Segment a complete map into rooms (see the module docs). Every non-free cell is a wall.
pub fn segment_rooms(
    grid: &OccupancyGrid,
    params: &SegmentParams,
) -> Result<Segmentation, SegmentError> {
    params.validate()?;
    let (w, h) = (grid.width(), grid.height());
    let free: Vec<bool> = grid.cells().iter().map(|&c| c == Cell::Free).collect();
    // The complete map: whatever is not free is a wall.
    let mut walls = grid.clone();
    for (i, _) in free.iter().enumerate().filter(|(_, &f)| !f) {
        walls.set(i % w, i / w, Cell::Occupied);
    }
    let clearance = ClearanceMap::from_mask(w, h, &free);
    let cell_doors = detect_cell_doors(&walls, &free, &clearance, &params.doors);

    // Step 2: cut the doors.
    let mut open = free.clone();
    for d in &cell_doors {
        for (x, y) in line_cells(d.jambs[0], d.jambs[1]) {
            if x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h {
                open[y as usize * w + x as usize] = false;
            }
        }
    }

    // Step 3: components; step 4: drop small ones.
    let min_cells =
        (params.min_room_area / (grid.resolution() * grid.resolution())).ceil() as usize;
    let (mut labels, sizes) = components(w, h, &open);
    let keep: Vec<bool> = sizes.iter().map(|&s| s >= min_cells.max(1)).collect();
    for l in labels.iter_mut() {
        if *l != 0 && !keep[*l as usize] {
            *l = 0;
        }
    }

    // Step 5: geodesic wavefront from the rooms through all free cells.
    grow(w, h, &free, &mut labels);
    let (rest, rest_sizes) = {
        let unlabelled: Vec<bool> = (0..w * h).map(|i| free[i] && labels[i] == 0).collect();
        components(w, h, &unlabelled)
    };
    // Free pockets no room reaches: small ones (inside furniture outlines, cupboards) join the
    // room nearest through walls, as Sjöö et al. assign every feature to the room of the
    // nearest navigation node; large ones are rooms of their own.
    let enclosure_cells =
        (params.enclosure_area / (grid.resolution() * grid.resolution())).ceil() as usize;
    let any_room = labels.iter().any(|&l| l != 0);
    let nearest = if any_room && rest_sizes.iter().skip(1).any(|&s| s < enclosure_cells) {
        let mut near = labels.clone();
        grow(w, h, &vec![true; w * h], &mut near);
        near
    } else {
        Vec::new()
    };
    let mut next = sizes.len() as u32;
    let mut rest_map: Vec<Option<u32>> = vec![None; rest_sizes.len()];
    for (k, &s) in rest_sizes.iter().enumerate().skip(1) {
        if !(any_room && s < enclosure_cells) && s >= min_cells.max(1) {
            rest_map[k] = Some(next);
            next += 1;
        } else if !(any_room && s < enclosure_cells) {
            rest_map[k] = Some(0);
        }
    }
    for (i, &r) in rest.iter().enumerate() {
        if r != 0 {
            let r = r as usize;
            if rest_map[r].is_none() {
                // The whole pocket joins the room nearest to its first cell.
                rest_map[r] = Some(nearest.get(i).copied().unwrap_or(0));
            }
            labels[i] = rest_map[r].unwrap_or(0);
        }
    }

    // Renumber 1..=rooms in scan order.
    let mut renumber = vec![0u32; next as usize];
    let mut rooms = 0u32;
    for l in labels.iter_mut() {
        if *l != 0 {
            if renumber[*l as usize] == 0 {
                rooms += 1;
                renumber[*l as usize] = rooms;
            }
            *l = renumber[*l as usize];
        }
    }

    let doors = cell_doors
        .iter()
        .filter(|d| separates(w, h, &free, &labels, d))
        .map(|d| to_world(grid, d))
        .collect();
    tracing::debug!(
        hypotheses = cell_doors.len(),
        rooms,
        "segmented {w}×{h} grid"
    );
    Ok(Segmentation {
        width: w,
        height: h,
        labels,
        rooms: rooms as usize,
        doors,
    })
}

/// Cells of the 8-connected digital line from `a` to `b` (Bresenham).
pub(crate) fn line_cells(a: (i32, i32), b: (i32, i32)) -> Vec<(i32, i32)> {
    let (mut x, mut y) = a;
    let dx = (b.0 - a.0).abs();
    let dy = -(b.1 - a.1).abs();
    let sx = if a.0 < b.0 { 1 } else { -1 };
    let sy = if a.1 < b.1 { 1 } else { -1 };
    let mut err = dx + dy;
    let mut out = Vec::with_capacity((dx - dy + 1) as usize);
    loop {
        out.push((x, y));
        if (x, y) == b {
            break;
        }
        let e2 = 2 * err;
        if e2 >= dy {
            err += dy;
            x += sx;
        }
        if e2 <= dx {
            err += dx;
            y += sy;
        }
    }
    out
}

/// 4-connected components of `mask`: labels (0 outside the mask) and sizes by label (index 0
/// unused).
fn components(w: usize, h: usize, mask: &[bool]) -> (Vec<u32>, Vec<usize>) {
    let mut labels = vec![0u32; w * h];
    let mut sizes = vec![0usize];
    let mut stack = Vec::new();
    for start in 0..w * h {
        if !mask[start] || labels[start] != 0 {
            continue;
        }
        let id = sizes.len() as u32;
        let mut size = 0;
        labels[start] = id;
        stack.push(start);
        while let Some(i) = stack.pop() {
            size += 1;
            for n in neighbours4(w, h, i) {
                if n != usize::MAX && mask[n] && labels[n] == 0 {
                    labels[n] = id;
                    stack.push(n);
                }
            }
        }
        sizes.push(size);
    }
    (labels, sizes)
}

/// The 4-neighbours of cell `i` (up to four; unused slots are `usize::MAX`).
#[inline]
fn neighbours4(w: usize, h: usize, i: usize) -> [usize; 4] {
    let (x, y) = (i % w, i / w);
    [
        if x > 0 { i - 1 } else { usize::MAX },
        if x + 1 < w { i + 1 } else { usize::MAX },
        if y > 0 { i - w } else { usize::MAX },
        if y + 1 < h { i + w } else { usize::MAX },
    ]
}

/// Multi-source breadth-first growth of nonzero labels into unlabelled free cells.
fn grow(w: usize, h: usize, free: &[bool], labels: &mut [u32]) {
    let open = |n: usize, labels: &[u32]| n != usize::MAX && free[n] && labels[n] == 0;
    // Seeds: labelled cells on the border of the unlabelled free space.
    let mut queue: VecDeque<usize> = (0..w * h)
        .filter(|&i| labels[i] != 0 && neighbours4(w, h, i).iter().any(|&n| open(n, labels)))
        .collect();
    while let Some(i) = queue.pop_front() {
        let l = labels[i];
        for n in neighbours4(w, h, i) {
            if open(n, labels) {
                labels[n] = l;
                queue.push_back(n);
            }
        }
    }
}

/// Whether the rooms just beyond either side of a door differ.
fn separates(w: usize, h: usize, free: &[bool], labels: &[u32], d: &CellDoor) -> bool {
    let [a, b] = d.jambs;
    let (dx, dy) = ((b.0 - a.0) as f64, (b.1 - a.1) as f64);
    let len = (dx * dx + dy * dy).sqrt().max(1e-9);
    let (nx, ny) = (-dy / len, dx / len);
    let (mx, my) = ((a.0 + b.0) as f64 / 2.0, (a.1 + b.1) as f64 / 2.0);
    let side = |s: f64| -> u32 {
        let mut t = 1.5;
        while t <= len.max(4.0) {
            let x = (mx + s * t * nx).round() as i64;
            let y = (my + s * t * ny).round() as i64;
            if x < 0 || y < 0 || x as usize >= w || y as usize >= h {
                return 0;
            }
            let i = y as usize * w + x as usize;
            if free[i] && labels[i] != 0 {
                return labels[i];
            }
            t += 0.5;
        }
        0
    };
    let (l, r) = (side(1.0), side(-1.0));
    l != 0 && r != 0 && l != r
}
