//! The ground-truth world built from an environment file.

use avs_format::environment::{Environment, MapSource, Object, ObjectRole};
use avs_format::knowledge::Knowledge;
use avs_map::grid::{Cell, MapError, OccupancyGrid};
use avs_map::raycast::{line_of_sight, walk_segment};
use std::collections::VecDeque;
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
    /// The environment cannot be read or parsed, or fails the checks of `avs validate`
    /// ([`crate::check`]): every problem, each naming its file, field (and, when read from a
    /// file, line and column) and what is expected.
    #[error("{}", .0.iter().map(|d| d.to_string()).collect::<Vec<_>>().join("\n"))]
    Checks(Vec<avs_format::Diagnostic>),
}

/// The occupancy grid of an environment; `base_dir` is the folder of the environment file
/// (image paths are relative to it).
pub fn load_grid(env: &Environment, base_dir: &Path) -> Result<OccupancyGrid, SimError> {
    load_map(&env.map, base_dir)
}

/// The occupancy grid of a file's `map:` section (an image path is relative to `base_dir`).
pub fn load_map(map: &MapSource, base_dir: &Path) -> Result<OccupancyGrid, SimError> {
    Ok(match map {
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

/// The simulated world: the environment and the grids derived from it.
#[derive(Debug, Clone)]
pub struct World {
    /// The environment as written.
    pub env: Environment,
    /// Walls and closed doors only: what blocks the camera's line of sight.
    pub walls: OccupancyGrid,
    /// Walls, closed doors and furniture footprints: what blocks motion and the laser.
    pub truth: OccupancyGrid,
    /// Ground-truth room index of every cell (`None` for walls and unlabelled space), as
    /// [`OccupancyGrid::index`]; rooms are `env.rooms` in order.
    pub room_of_cell: Vec<Option<usize>>,
    /// Per door (`env.doors` order), the cells of its opening that are free in the map without
    /// doors: the cells a closed door occupies.
    door_openings: Vec<Vec<(usize, usize)>>,
}

impl World {
    /// Build the world from an environment; `base_dir` is the environment file's folder. The
    /// environment must pass the checks `avs validate` runs ([`crate::check`]; class names are
    /// not checked here, there being no knowledge): one gate for every command, so that a world
    /// that builds is one the simulator can run (a start off the map hung the search).
    pub fn new(env: Environment, base_dir: &Path) -> Result<Self, SimError> {
        Self::named("environment", env, base_dir)
    }

    /// [`World::new`] for an environment read from (or edited after) the file `file`, which
    /// the checks' messages name.
    pub fn named(file: &str, env: Environment, base_dir: &Path) -> Result<Self, SimError> {
        let diagnostics = crate::check::check_environment(file, &env, base_dir, None);
        if !diagnostics.is_empty() {
            return Err(SimError::Checks(diagnostics));
        }
        Self::build(env, base_dir)
    }

    /// [`World::new`] without the checks: for the checks themselves, which build the world to
    /// test what needs it.
    pub(crate) fn build(env: Environment, base_dir: &Path) -> Result<Self, SimError> {
        let mut walls = load_grid(&env, base_dir)?;
        let mut door_openings = Vec::with_capacity(env.doors.len());
        for (i, d) in env.doors.iter().enumerate() {
            if !(d.width.is_finite() && d.width > 0.0) {
                return Err(SimError::Invalid {
                    field: format!("doors[{i}].width"),
                    message: format!("got {}; expected a positive width in metres", d.width),
                });
            }
            let mut cells = door_cells(&walls, d);
            cells.retain(|&(col, row)| walls.get(col, row) == Cell::Free);
            door_openings.push(cells);
        }
        for (d, cells) in env.doors.iter().zip(&door_openings) {
            if !d.open {
                for &(col, row) in cells {
                    walls.set(col, row, Cell::Occupied);
                }
            }
        }
        let truth = furnished(&walls, &env);
        let room_of_cell = label_rooms(&walls, &env)?;
        Ok(Self {
            env,
            walls,
            truth,
            room_of_cell,
            door_openings,
        })
    }

    /// The cells of door `index`'s opening (`env.doors` order) that are free in the map without
    /// doors: the cells the door occupies when closed (see [`door_cells`]). Empty for an index
    /// out of range.
    pub fn door_opening(&self, index: usize) -> &[(usize, usize)] {
        self.door_openings.get(index).map_or(&[], Vec::as_slice)
    }

    /// The index in `env.doors` of the door named `name`.
    pub fn door_index(&self, name: &str) -> Option<usize> {
        self.env.doors.iter().position(|d| d.name == name)
    }

    /// Walls and closed doors plus furniture footprints (floor-standing landmarks): the grid
    /// that blocks motion and the laser, built from a walls grid of this world's geometry
    /// (e.g. [`World::walls`] with some doors opened or closed).
    pub fn furnish(&self, walls: &OccupancyGrid) -> OccupancyGrid {
        furnished(walls, &self.env)
    }

    /// Load an environment file and build its world.
    /// The file gets the checks of `avs validate` with their lines and columns.
    pub fn load(path: &Path) -> Result<Self, SimError> {
        Self::load_checked(path, None)
    }

    /// [`World::load`], also checking the environment's class names against `knowledge` (as
    /// `avs validate --knowledge` does).
    pub fn load_checked(path: &Path, knowledge: Option<&Knowledge>) -> Result<Self, SimError> {
        let env = Self::read_checked(path, knowledge)?;
        Self::build(env, path.parent().unwrap_or(Path::new(".")))
    }

    /// Read an environment file and run `avs validate`'s checks on it (class names too when
    /// `knowledge` is given), each problem with its line and column; the environment, for a
    /// caller that edits it before building its world (with [`World::named`]).
    pub fn read_checked(
        path: &Path,
        knowledge: Option<&Knowledge>,
    ) -> Result<Environment, SimError> {
        let file = path.display().to_string();
        let text = avs_format::read_text(path).map_err(|e| SimError::Checks(e.diagnostics))?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::read_checked_text(&file, &text, base, knowledge)
    }

    /// [`World::read_checked`] of an environment's `text` named `file` (e.g. one embedded in a
    /// program), with relative paths (a map image) resolved against `base_dir`.
    pub fn read_checked_text(
        file: &str,
        text: &str,
        base_dir: &Path,
        knowledge: Option<&Knowledge>,
    ) -> Result<Environment, SimError> {
        let env: Environment =
            avs_format::load_yaml_str(file, text).map_err(|e| SimError::Checks(e.diagnostics))?;
        let mut diagnostics = crate::check::check_environment(file, &env, base_dir, knowledge);
        if !diagnostics.is_empty() {
            avs_format::positions::locate(&mut diagnostics, text);
            return Err(SimError::Checks(diagnostics));
        }
        Ok(env)
    }

    /// The ground-truth room (index into `env.rooms`) at a world point.
    pub fn room_at(&self, x: f64, y: f64) -> Option<usize> {
        let (c, r) = self.walls.world_to_cell(x, y);
        if !self.walls.contains(c, r) {
            return None;
        }
        self.room_of_cell[self.walls.index(c as usize, r as usize)]
    }

    /// Free-space area of each ground-truth room, m².
    pub fn room_areas(&self) -> Vec<f64> {
        let mut a = vec![0.0; self.env.rooms.len()];
        let cell = self.walls.resolution().powi(2);
        for r in self.room_of_cell.iter().flatten() {
            a[*r] += cell;
        }
        a
    }

    /// Objects of a class.
    pub fn objects_of_class<'a>(&'a self, class: &'a str) -> impl Iterator<Item = &'a Object> + 'a {
        self.env.objects.iter().filter(move |o| o.class == class)
    }

    /// What a camera at `eye` (x, y, height) sees of the world's objects when looking along
    /// `yaw` (radians, world frame) and `tilt` (radians, negative down) with horizontal and
    /// vertical fields of view `hfov`, `vfov` (radians, already divided by the zoom).
    pub fn objects_in_view(&self, view: &CameraView) -> Vec<ViewedObject> {
        self.objects_in_view_through(&self.walls, view)
    }

    /// [`World::objects_in_view`] with line of sight checked on `walls` instead of
    /// [`World::walls`] (a grid of the same geometry in which doors may have opened or closed).
    pub fn objects_in_view_through(
        &self,
        walls: &OccupancyGrid,
        view: &CameraView,
    ) -> Vec<ViewedObject> {
        let mut out = Vec::new();
        for (i, o) in self.env.objects.iter().enumerate() {
            let top = o.pose.z + o.size[2] / 2.0;
            let at = view.off_axis([o.pose.x, o.pose.y, top]);
            if !at.in_image(view) {
                continue;
            }
            // Occlusion by walls and closed doors; the object's own cell is not an occluder.
            let visible = line_of_sight(
                walls,
                [view.eye[0], view.eye[1]],
                [o.pose.x, o.pose.y],
                false,
            );
            out.push(ViewedObject {
                index: i,
                distance: at.distance,
                bearing: at.bearing,
                elevation: at.elevation,
                visible,
            });
        }
        out
    }
}

/// `walls` with the footprints of the floor-standing landmarks of `env` marked occupied.
fn furnished(walls: &OccupancyGrid, env: &Environment) -> OccupancyGrid {
    let mut truth = walls.clone();
    for o in &env.objects {
        if o.role == ObjectRole::Landmark && o.pose.z <= 0.0 {
            rasterise_box(&mut truth, o, Cell::Occupied);
        }
    }
    truth
}

/// A camera's viewing geometry in the world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraView {
    /// Camera position: x, y, height above the floor (metres).
    pub eye: [f64; 3],
    /// Viewing direction in the plane, radians.
    pub yaw: f64,
    /// Tilt, radians (negative looks down).
    pub tilt: f64,
    /// Horizontal field of view, radians.
    pub hfov: f64,
    /// Vertical field of view, radians.
    pub vfov: f64,
}

impl CameraView {
    /// Where the point `p` (x, y, height) lies in the image: `(bearing, elevation)` off the
    /// optical axis (radians), and its ground and 3-D distances from the camera (metres).
    pub fn off_axis(&self, p: [f64; 3]) -> OffAxis {
        let (dx, dy, dz) = (p[0] - self.eye[0], p[1] - self.eye[1], p[2] - self.eye[2]);
        // Square roots rather than `hypot`: the detector's figures stay those it always had.
        let ground = (dx * dx + dy * dy).sqrt();
        OffAxis {
            bearing: wrap_angle(dy.atan2(dx) - self.yaw),
            elevation: dz.atan2(ground) - self.tilt,
            ground,
            distance: (ground * ground + dz * dz).sqrt(),
        }
    }
}

/// A point's place in a camera's image ([`CameraView::off_axis`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OffAxis {
    /// Angle off the optical axis in the plane, radians.
    pub bearing: f64,
    /// Angle above the optical axis, radians.
    pub elevation: f64,
    /// Distance in the plane, metres.
    pub ground: f64,
    /// Distance in space, metres.
    pub distance: f64,
}

impl OffAxis {
    /// Whether the point is inside the image of `view` (within half of each field of view).
    pub fn in_image(&self, view: &CameraView) -> bool {
        self.bearing.abs() <= view.hfov / 2.0 && self.elevation.abs() <= view.vfov / 2.0
    }
}

/// One object inside a camera's field of view.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewedObject {
    /// Index into `env.objects`.
    pub index: usize,
    /// Distance from the camera to the object's top centre, metres.
    pub distance: f64,
    /// Angle off the optical axis in the plane, radians.
    pub bearing: f64,
    /// Angle off the optical axis vertically, radians.
    pub elevation: f64,
    /// Whether no wall or closed door blocks the line of sight.
    pub visible: bool,
}

pub use avs_map::geometry::wrap_angle;

/// The grid cells of a door's opening: a segment across the direction of passage, `width` long
/// plus a cell at each end, three cells thick along the passage so 8-connected motion cannot
/// slip through diagonally. Cells outside the grid are left out.
pub fn door_cells(grid: &OccupancyGrid, d: &avs_format::environment::Door) -> Vec<(usize, usize)> {
    let yaw = d.pose.yaw_deg.to_radians();
    // The opening runs perpendicular to the direction of passage. A door wider than the map is
    // cut to the map (the walk along it stays bounded).
    let (ux, uy) = (-yaw.sin(), yaw.cos());
    let diag = (grid.width() + grid.height()) as f64 * grid.resolution();
    let h = (d.width / 2.0 + grid.resolution()).min(diag);
    let a = [d.pose.x - ux * h, d.pose.y - uy * h];
    let b = [d.pose.x + ux * h, d.pose.y + uy * h];
    let mut line = Vec::new();
    walk_segment(grid, a, b, |col, row| {
        line.push((col, row));
        true
    });
    let (px, py) = (yaw.cos(), yaw.sin());
    let mut out = Vec::new();
    for (col, row) in line {
        let (x, y) = grid.cell_center(col, row);
        for s in [-1.0, 0.0, 1.0] {
            let (cc, rr) = grid.world_to_cell(
                x + px * s * grid.resolution(),
                y + py * s * grid.resolution(),
            );
            if grid.contains(cc, rr) {
                out.push((cc as usize, rr as usize));
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

/// Mark the free cells of a door's opening (see [`door_cells`]) as `c`.
pub fn rasterise_door(grid: &mut OccupancyGrid, d: &avs_format::environment::Door, c: Cell) {
    for (col, row) in door_cells(grid, d) {
        if grid.get(col, row) == Cell::Free {
            grid.set(col, row, c);
        }
    }
}

/// Mark the footprint of an object's (yawed) bounding box.
pub fn rasterise_box(grid: &mut OccupancyGrid, o: &Object, c: Cell) {
    let yaw = o.pose.yaw_deg.to_radians();
    let (hl, hw) = (o.size[0] / 2.0, o.size[1] / 2.0);
    let rad = (hl * hl + hw * hw).sqrt();
    // Only the part of the bounding square that lies on the grid is visited.
    let (c0, r0) = grid.world_to_cell(o.pose.x - rad, o.pose.y - rad);
    let (c1, r1) = grid.world_to_cell(o.pose.x + rad, o.pose.y + rad);
    let (c0, r0) = (c0.max(0), r0.max(0));
    let (c1, r1) = (
        c1.min(grid.width() as i64 - 1),
        r1.min(grid.height() as i64 - 1),
    );
    for row in r0..=r1 {
        for col in c0..=c1 {
            let (x, y) = grid.cell_center(col, row);
            let (dx, dy) = (x - o.pose.x, y - o.pose.y);
            let u = dx * yaw.cos() + dy * yaw.sin();
            let v = -dx * yaw.sin() + dy * yaw.cos();
            if u.abs() <= hl && v.abs() <= hw && grid.contains(col, row) {
                grid.set(col as usize, row as usize, c);
            }
        }
    }
}

/// Label free cells with ground-truth rooms: polygon rooms by containment, seeded rooms by flood
/// fill from the seed that does not cross door openings (rasterised as barriers for labelling).
fn label_rooms(walls: &OccupancyGrid, env: &Environment) -> Result<Vec<Option<usize>>, SimError> {
    let mut barrier = walls.clone();
    for d in &env.doors {
        rasterise_door(&mut barrier, d, Cell::Occupied);
    }
    let mut labels: Vec<Option<usize>> = vec![None; walls.width() * walls.height()];
    for (i, room) in env.rooms.iter().enumerate() {
        if let Some(poly) = &room.polygon {
            for row in 0..walls.height() {
                for col in 0..walls.width() {
                    let (x, y) = walls.cell_center(col as i64, row as i64);
                    if walls.get(col, row) == Cell::Free && point_in_polygon(x, y, poly) {
                        labels[walls.index(col, row)] = Some(i);
                    }
                }
            }
        } else if let Some(seed) = room.seed {
            let (c, r) = walls.world_to_cell(seed.x, seed.y);
            if !walls.contains(c, r) || barrier.get_i(c, r) != Cell::Free {
                return Err(SimError::Invalid {
                    field: format!("rooms[{i}].seed"),
                    message: format!(
                        "({}, {}) is not in free space; expected a point inside room `{}`",
                        seed.x, seed.y, room.name
                    ),
                });
            }
            let mut q = VecDeque::from([(c, r)]);
            while let Some((c, r)) = q.pop_front() {
                if !barrier.contains(c, r) || barrier.get_i(c, r) != Cell::Free {
                    continue;
                }
                let k = walls.index(c as usize, r as usize);
                if labels[k].is_some() {
                    continue;
                }
                labels[k] = Some(i);
                q.extend([(c + 1, r), (c - 1, r), (c, r + 1), (c, r - 1)]);
            }
        } else {
            return Err(SimError::Invalid {
                field: format!("rooms[{i}]"),
                message: format!(
                    "room `{}` has neither `seed` nor `polygon`; expected one of them",
                    room.name
                ),
            });
        }
    }
    // Door cells belong to the room on either side; give them to the nearest labelled neighbour.
    for d in &env.doors {
        for (col, row) in door_cells(walls, d) {
            let k = walls.index(col, row);
            if walls.get(col, row) != Cell::Free || labels[k].is_some() {
                continue;
            }
            'search: for rad in 1..6i64 {
                for (dc, dr) in [(rad, 0), (-rad, 0), (0, rad), (0, -rad)] {
                    let (cc, rr) = (col as i64 + dc, row as i64 + dr);
                    if walls.contains(cc, rr) {
                        if let Some(l) = labels[walls.index(cc as usize, rr as usize)] {
                            labels[k] = Some(l);
                            break 'search;
                        }
                    }
                }
            }
        }
    }
    Ok(labels)
}

fn point_in_polygon(x: f64, y: f64, poly: &[avs_format::environment::Point]) -> bool {
    let mut inside = false;
    let n = poly.len();
    let mut j = n.wrapping_sub(1);
    for i in 0..n {
        let (pi, pj) = (poly[i], poly[j]);
        if (pi.y > y) != (pj.y > y) && x < (pj.x - pi.x) * (y - pi.y) / (pj.y - pi.y) + pi.x {
            inside = !inside;
        }
        j = i;
    }
    inside
}
