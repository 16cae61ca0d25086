//! Checks of doors against the walls of the map: a door sits across a gap in a wall, and the
//! gap is at least as wide as the door.
//!
//! Both checks walk straight lines from the door's centre through the grid, cell by cell, and
//! stop at the first occupied cell or the map's edge (or at a short distance), so each door costs
//! at most a few times the map's width plus height in cells.
//!
//! - **Orientation** (`doors[i].pose.yaw_deg`): `yaw_deg` is the direction of passage, so the
//!   straight line from the door's centre along it, ahead and behind, must stay out of walls for
//!   [`DOOR_CLEARANCE_M`] (half a metre) on each side. A door whose `yaw_deg` runs along its
//!   wall fails when its gap is narrower than a metre: that line meets the wall at the ends of
//!   the gap. (A door turned along the wall of a wider gap is not caught.)
//! - **Width** (`doors[i].width`): the free run through the door's centre across the direction
//!   of passage (the opening, from wall to wall) must be at least the door's width less one map
//!   cell (the simulator closes a door over its width plus a cell at each end).
//!
//! Doors whose centre is outside the map or inside a wall, or with non-finite numbers or a
//! width that is not positive, are skipped: other checks report them. The width is checked only
//! for a door whose orientation passed (across a wrongly turned door the "opening" is the room).
//!
//! [`check_environment`](crate::check_env::check_environment) runs these checks on ASCII maps
//! ([`AsciiWalls`]); any other grid can be checked through the [`Walls`] trait.

use crate::diag::Diagnostic;
use crate::environment::Environment;

/// The walls of an occupancy grid, as far as the door checks need them.
///
/// Cell `(col, row)` covers world `[ox + col·r, ox + (col+1)·r) × [oy + row·r, oy + (row+1)·r)`
/// with `r` the resolution and `[ox, oy]` the origin; row 0 is the bottom row (as in ROS and in
/// `avs_map::grid`).
pub trait Walls {
    /// Number of columns and rows.
    fn size(&self) -> (usize, usize);
    /// Metres per cell (positive and finite).
    fn resolution(&self) -> f64;
    /// World position of the lower-left corner of cell `(0, 0)`.
    fn origin(&self) -> [f64; 2];
    /// Whether cell `(col, row)` (inside the grid) is occupied.
    fn occupied(&self, col: usize, row: usize) -> bool;
}

/// The walls of an inline ASCII map (`#` occupied, `.` or space free, `?` unknown), read the way
/// the simulator reads it: first line is the top row.
#[derive(Debug, Clone)]
pub struct AsciiWalls<'a> {
    rows: Vec<&'a [u8]>,
    width: usize,
    resolution: f64,
    origin: [f64; 2],
}

impl<'a> AsciiWalls<'a> {
    /// The walls of `ascii`, or `None` when the map cannot be read as a rectangle of known
    /// characters (empty, rows of different lengths, other characters, a resolution or origin
    /// that is not a finite number, or a non-positive resolution): other checks report those.
    pub fn parse(ascii: &'a str, resolution: f64, origin: [f64; 2]) -> Option<Self> {
        if !(resolution.is_finite() && resolution > 0.0 && origin.iter().all(|v| v.is_finite())) {
            return None;
        }
        let rows: Vec<&[u8]> = ascii.lines().map(str::as_bytes).collect();
        let width = rows.first()?.len();
        let known = |b: &u8| matches!(b, b'#' | b'.' | b' ' | b'?');
        if width == 0
            || rows
                .iter()
                .any(|r| r.len() != width || !r.iter().all(known))
        {
            return None;
        }
        Some(Self {
            rows,
            width,
            resolution,
            origin,
        })
    }
}

impl Walls for AsciiWalls<'_> {
    fn size(&self) -> (usize, usize) {
        (self.width, self.rows.len())
    }
    fn resolution(&self) -> f64 {
        self.resolution
    }
    fn origin(&self) -> [f64; 2] {
        self.origin
    }
    fn occupied(&self, col: usize, row: usize) -> bool {
        let h = self.rows.len();
        row < h && self.rows[h - 1 - row].get(col) == Some(&b'#')
    }
}

/// The cell containing world point `(x, y)`, if inside the grid.
fn cell_of(w: &impl Walls, x: f64, y: f64) -> Option<(usize, usize)> {
    let [ox, oy] = w.origin();
    let r = w.resolution();
    let (c, rr) = (((x - ox) / r).floor(), ((y - oy) / r).floor());
    let (cols, rows) = w.size();
    (c >= 0.0 && rr >= 0.0 && c < cols as f64 && rr < rows as f64)
        .then_some((c as usize, rr as usize))
}

/// Distance in metres from `(x, y)` along the unit direction `(dx, dy)` to the first cell that is
/// occupied or outside the grid, at most `limit`. A grid traversal (Amanatides–Woo): it visits
/// each cell the ray crosses once, so it takes at most `limit / resolution × 2 + 2` steps.
fn free_run(w: &impl Walls, x: f64, y: f64, dx: f64, dy: f64, limit: f64) -> f64 {
    let [ox, oy] = w.origin();
    let r = w.resolution();
    let (cols, rows) = w.size();
    let (gx, gy) = ((x - ox) / r, (y - oy) / r);
    let (mut c, mut rr) = (gx.floor() as i64, gy.floor() as i64);
    let blocked = |c: i64, rr: i64| {
        c < 0
            || rr < 0
            || c >= cols as i64
            || rr >= rows as i64
            || w.occupied(c as usize, rr as usize)
    };
    if blocked(c, rr) {
        return 0.0;
    }
    // Parameters in cell units along the ray: where it crosses the next column / row boundary.
    let axis = |g: f64, d: f64| -> (i64, f64, f64) {
        if d > 0.0 {
            (1, (g.floor() + 1.0 - g) / d, 1.0 / d)
        } else if d < 0.0 {
            (-1, (g - g.floor()) / -d, -1.0 / d)
        } else {
            (0, f64::INFINITY, f64::INFINITY)
        }
    };
    let (sx, mut tx, ddx) = axis(gx, dx);
    let (sy, mut ty, ddy) = axis(gy, dy);
    let limit_cells = limit / r;
    let max_steps = (limit_cells * 2.0).ceil().min(1e9) as u64 + 2;
    for _ in 0..max_steps {
        let t = tx.min(ty);
        if t >= limit_cells {
            return limit;
        }
        // A ray through a cell corner goes on diagonally: the two cells it only touches at
        // that corner do not stop it.
        if (tx - ty).abs() <= 1e-9 * t.max(1.0) {
            c += sx;
            tx += ddx;
            rr += sy;
            ty += ddy;
        } else if tx < ty {
            c += sx;
            tx += ddx;
        } else {
            rr += sy;
            ty += ddy;
        }
        if blocked(c, rr) {
            return t * r;
        }
    }
    limit
}

/// How far the line along a door's direction of passage must stay out of walls on each side of
/// its centre, metres. Half a metre: enough to cross any ordinary wall, and more than half of a
/// usual door's gap, so a door turned along its wall meets the wall at the gap's ends.
pub const DOOR_CLEARANCE_M: f64 = 0.5;

/// Most grid cells all door walks of one environment may visit. A walk of `l` metres visits at
/// most `2 l / resolution + 2` cells; ordinary floors need a few hundred in all, and a file
/// with so many doors, so wide, that the bound is reached gets one diagnostic instead of a
/// long wait.
pub const MAX_DOOR_WALK_CELLS: f64 = 1e8;

/// `v` rounded to millimetres, for messages.
fn mm(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}

/// Check every door of `env` against `walls` (see the module documentation). Diagnostics carry
/// field paths but no positions.
pub fn check_door_openings(file: &str, env: &Environment, walls: &impl Walls) -> Vec<Diagnostic> {
    let mut out = Vec::new();
    let res = walls.resolution();
    let (cols, rows) = walls.size();
    // No walk needs to go further than the grid's width plus height.
    let span = (cols + rows) as f64 * res;
    let walk = |l: f64| 2.0 * l.min(span) / res + 2.0;
    let work: f64 = env
        .doors
        .iter()
        .map(|d| {
            let w = if d.width.is_finite() {
                d.width.abs()
            } else {
                0.0
            };
            4.0 * walk(DOOR_CLEARANCE_M) + 2.0 * walk(w + res)
        })
        .sum();
    if work > MAX_DOOR_WALK_CELLS {
        out.push(Diagnostic::new(
            file,
            "doors",
            format!(
                "{} doors on a {cols} × {rows} map are too many to check against the walls",
                env.doors.len()
            ),
            format!(
                "at most {MAX_DOOR_WALK_CELLS:e} cell visits: fewer or narrower doors, or a coarser map"
            ),
        ));
        return out;
    }
    for (i, d) in env.doors.iter().enumerate() {
        let p = &d.pose;
        let sound = p.x.is_finite()
            && p.y.is_finite()
            && p.yaw_deg.is_finite()
            && d.width.is_finite()
            && d.width > 0.0;
        if !sound {
            continue;
        }
        match cell_of(walls, p.x, p.y) {
            Some((c, r)) if !walls.occupied(c, r) => {}
            _ => continue,
        }
        let yaw = p.yaw_deg.to_radians();
        let (px, py) = (yaw.cos(), yaw.sin());
        let need = DOOR_CLEARANCE_M.min(span);
        let ahead = free_run(walls, p.x, p.y, px, py, need);
        let behind = free_run(walls, p.x, p.y, -px, -py, need);
        if ahead < need || behind < need {
            let (side, dist) = if ahead < need {
                ("ahead", ahead)
            } else {
                ("behind", behind)
            };
            // Would the door pass turned a quarter?
            let (qx, qy) = (-py, px);
            let turned = free_run(walls, p.x, p.y, qx, qy, need) >= need
                && free_run(walls, p.x, p.y, -qx, -qy, need) >= need;
            let hint = if turned {
                format!(
                    " (yaw_deg {} passes through it)",
                    mm((p.yaw_deg + 90.0).rem_euclid(180.0))
                )
            } else {
                String::new()
            };
            out.push(Diagnostic::new(
                file,
                format!("doors[{i}].pose.yaw_deg"),
                format!(
                    "the direction of passage of door `{}` (yaw_deg {}) meets a wall {} m {side} of its centre",
                    d.name,
                    p.yaw_deg,
                    mm(dist)
                ),
                format!(
                    "yaw_deg pointing across the wall, through the gap: free space for {} m ahead of and behind the centre{hint}",
                    mm(need)
                ),
            ));
            continue;
        }
        // The opening: from wall to wall through the centre, across the direction of passage.
        // Each side is measured up to the full width, so a door that does not fit is measured
        // exactly.
        let reach = (d.width + res).min(span);
        let (wx, wy) = (-py, px);
        let gap =
            free_run(walls, p.x, p.y, wx, wy, reach) + free_run(walls, p.x, p.y, -wx, -wy, reach);
        if d.width > gap + res + 1e-9 {
            out.push(Diagnostic::new(
                file,
                format!("doors[{i}].width"),
                format!(
                    "door `{}` is {} m wide but the gap in the map's wall at its centre is {} m wide",
                    d.name,
                    d.width,
                    mm(gap)
                ),
                format!(
                    "a width of at most the gap ({} m, give or take one {} m cell), or a wider gap in the map",
                    mm(gap),
                    res
                ),
            ));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 6 m × 4 m floor at 0.5 m per cell with a wall at x ∈ [2.5, 3) and a one-cell gap at
    /// y ∈ [1.5, 2) (tests/validate/good/two_rooms.yaml).
    const TWO_ROOMS: &str = "############\n#....#.....#\n#....#.....#\n#....#.....#\n#..........#\n#....#.....#\n#....#.....#\n############\n";

    fn env_with_door(door: &str) -> Environment {
        let text = format!(
            "kind: environment\nname: t\nmap: {{ ascii: \"{}\", resolution: 0.5 }}\nrobot: {{ start: {{ x: 1.25, y: 0.75 }} }}\ndoors:\n  - {door}\n",
            TWO_ROOMS.replace('\n', "\\n")
        );
        crate::load_yaml_str("t.yaml", &text).unwrap()
    }

    fn check(door: &str) -> Vec<Diagnostic> {
        let env = env_with_door(door);
        let walls = AsciiWalls::parse(TWO_ROOMS, 0.5, [0.0, 0.0]).unwrap();
        check_door_openings("t.yaml", &env, &walls)
    }

    #[test]
    fn free_run_stops_at_the_first_wall_cell_boundary() {
        let walls = AsciiWalls::parse(TWO_ROOMS, 0.5, [0.0, 0.0]).unwrap();
        // From the gap's centre up and down: the gap spans y ∈ [1.5, 2).
        let up = free_run(&walls, 2.75, 1.75, 0.0, 1.0, 10.0);
        let down = free_run(&walls, 2.75, 1.75, 0.0, -1.0, 10.0);
        assert!(
            (up - 0.25).abs() < 1e-9 && (down - 0.25).abs() < 1e-9,
            "{up} {down}"
        );
        // Along the gap, east: through the gap and the kitchen to the east wall at x = 5.5.
        let east = free_run(&walls, 2.75, 1.75, 1.0, 0.0, 10.0);
        assert!((east - 2.75).abs() < 1e-9, "{east}");
        // Capped by the limit, and 0 inside a wall.
        assert_eq!(free_run(&walls, 2.75, 1.75, 1.0, 0.0, 1.0), 1.0);
        assert_eq!(free_run(&walls, 0.25, 0.25, 1.0, 0.0, 1.0), 0.0);
        // Diagonal, from a cell centre through cell corners: from (1.25, 1.25) at 45° the ray
        // runs through the centres of cells (2, 2), (3, 3), (4, 4) and enters the wall cell
        // (5, 5) at its corner (2.5, 2.5), 1.25·√2 m away; the cells it only touches at
        // corners do not stop it.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let diag = free_run(&walls, 1.25, 1.25, s, s, 100.0);
        assert!((diag - 1.25 * 2f64.sqrt()).abs() < 1e-9, "{diag}");
        // Along the wall line x ∈ [2.5, 3) from the gap's centre, north: the gap cell, then
        // wall at y = 2.
        let north = free_run(&walls, 2.75, 1.75, 0.0, 1.0, 100.0);
        assert!((north - 0.25).abs() < 1e-9, "{north}");
    }

    #[test]
    fn a_door_across_its_gap_passes() {
        assert_eq!(
            check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 0 }, width: 0.5 }"),
            vec![]
        );
        // The opposite heading is the same passage.
        assert_eq!(
            check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 180 }, width: 0.5 }"),
            vec![]
        );
    }

    #[test]
    fn a_door_turned_along_its_wall_is_an_error_with_the_turn_that_passes() {
        let d = check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 90 }, width: 0.5 }");
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "doors[0].pose.yaw_deg");
        assert!(
            d[0].message.contains("meets a wall 0.25 m ahead"),
            "{}",
            d[0]
        );
        assert!(d[0].expected.contains("yaw_deg 0 passes"), "{}", d[0]);
    }

    #[test]
    fn a_door_wider_than_its_gap_is_an_error_and_one_cell_of_slack_is_not() {
        let d = check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 0 }, width: 2.5 }");
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "doors[0].width");
        assert!(
            d[0].message.contains(
                "is 2.5 m wide but the gap in the map's wall at its centre is 0.5 m wide"
            ),
            "{}",
            d[0]
        );
        // 1 m = the gap plus one cell: accepted (door openings are drawn to the cell).
        assert_eq!(
            check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 0 }, width: 1.0 }"),
            vec![]
        );
        assert_eq!(
            check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 0 }, width: 1.01 }").len(),
            1
        );
    }

    #[test]
    fn doors_in_walls_outside_the_map_or_with_bad_numbers_are_left_to_other_checks() {
        for door in [
            "{ name: d, pose: { x: 2.75, y: 2.75, yaw_deg: 0 }, width: 0.5 }",
            "{ name: d, pose: { x: -2.75, y: 1.75, yaw_deg: 0 }, width: 0.5 }",
            "{ name: d, pose: { x: .nan, y: 1.75, yaw_deg: 0 }, width: 0.5 }",
            "{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: .inf }, width: 0.5 }",
            "{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 0 }, width: -1 }",
        ] {
            assert_eq!(check(door), vec![], "{door}");
        }
    }

    #[test]
    fn a_huge_door_costs_no_more_than_the_map() {
        // 1e12 m: the walks stop at the map's extent; the door is reported, quickly.
        let d = check("{ name: d, pose: { x: 2.75, y: 1.75, yaw_deg: 0 }, width: 1e12 }");
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].path, "doors[0].width");
    }

    #[test]
    fn too_many_wide_doors_are_one_diagnostic_not_a_long_wait() {
        // A 400 × 400 room at 0.1 m: each 1e9 m door may walk 4 × (2 × 0.5 / 0.1 + 2) +
        // 2 × (2 × 80 / 0.1 + 2) = 3252 cells (its walks are cut at the map's 80 m span).
        let n = 400;
        let mut ascii = String::new();
        for r in 0..n {
            let row: String = (0..n)
                .map(|c| {
                    if r == 0 || c == 0 || r == n - 1 || c == n - 1 {
                        '#'
                    } else {
                        '.'
                    }
                })
                .collect();
            ascii.push_str(&row);
            ascii.push('\n');
        }
        let text = "kind: environment\nname: t\nmap: { ascii: \"#\", resolution: 0.1 }\nrobot: { start: { x: 20, y: 20 } }\ndoors:\n  - { name: d, pose: { x: 20, y: 20 }, width: 1e9 }\n";
        let mut env: Environment = crate::load_yaml_str("t.yaml", text).unwrap();
        let walls = AsciiWalls::parse(&ascii, 0.1, [0.0, 0.0]).unwrap();
        let per_door = 3252.0;
        let door = env.doors[0].clone();
        env.doors = vec![door; (MAX_DOOR_WALK_CELLS / per_door) as usize - 1];
        assert!(check_door_openings("t.yaml", &env, &walls)
            .iter()
            .all(|d| d.path != "doors"));
        env.doors.push(env.doors[0].clone());
        env.doors.push(env.doors[0].clone());
        let t = std::time::Instant::now();
        let d = check_door_openings("t.yaml", &env, &walls);
        assert_eq!(d.len(), 1, "{:?}", &d[..d.len().min(3)]);
        assert_eq!(d[0].path, "doors");
        assert!(t.elapsed().as_secs_f64() < 0.1, "{:?}", t.elapsed());
    }

    #[test]
    fn ascii_walls_refuse_ragged_and_unknown_characters() {
        assert!(AsciiWalls::parse("###\n#.#\n###\n", 1.0, [0.0, 0.0]).is_some());
        assert!(AsciiWalls::parse("###\n#.\n###\n", 1.0, [0.0, 0.0]).is_none());
        assert!(AsciiWalls::parse("###\n#x#\n###\n", 1.0, [0.0, 0.0]).is_none());
        assert!(AsciiWalls::parse("", 1.0, [0.0, 0.0]).is_none());
        assert!(AsciiWalls::parse("###\n", 0.0, [0.0, 0.0]).is_none());
        // Row 0 is the bottom line.
        let w = AsciiWalls::parse("#..\n...\n", 1.0, [0.0, 0.0]).unwrap();
        assert!(w.occupied(0, 1) && !w.occupied(0, 0));
    }
}
