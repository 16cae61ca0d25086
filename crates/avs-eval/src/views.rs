//! A room's view plan for several classes (`avs views`, Sjöö et al. `004` §2.1): the planning
//! problem read off an environment and a knowledge file, the plan, and its drawing.
//!
//! * **Cells** are the room's *occupied* 0.5 m cells, as the paper's (§2.1.1: the grid marks a
//!   cell occupied when it holds a feature; objects rest on furniture and stand against walls):
//!   every 0.5 m cell holding an occupied cell of the furnished map next to a free cell of the
//!   room — the walls around it and the furniture in it.
//! * **Standpoints** are a lattice over the room's free floor (`spacing` apart) where the
//!   robot's disc fits: the paper's navigation nodes, which a place map would give.
//! * **Limits**: a class is detected from the distance at which it fills the image to that at
//!   which it covers one vote cell (eq. 1, §3.2), times the view's zoom — or within its
//!   measured range when the request carries one ([`ViewsRequest::measured`]).
//! * **Heights**: a class is looked for between the lowest and highest of the heights the
//!   knowledge puts it at ([`avs_view::search_heights`]).
//! * **Line of sight**: walls and closed doors hide a cell; furniture does not (the paper's
//!   "occupied cells are not assumed … to obstruct field of view": the laser sees them low).

use crate::EvalError;
use avs_format::knowledge::Knowledge;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_robot::{Camera, ImageGeometry};
use avs_sim::World;
use avs_view::plan::{
    nearest_first, optimal_views, plan_views, PlanOptions, SoughtClass, ViewPlan, ViewProblem,
};
use avs_view::ObjectModel;
use serde::Serialize;
use std::collections::BTreeMap;

/// Side of the cells to cover, metres (§2.1.1: "a fixed cell size of 0.5 m is used").
pub const CELL: f64 = 0.5;

/// Branch-and-bound nodes the exact optimum may use unless told otherwise.
pub use avs_view::plan::optimal::DEFAULT_NODE_LIMIT;

/// Height steps closer than this are one search height (as the agent's).
const HEIGHT_STEP: f64 = 0.3;

/// What the room's view plan is asked for.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewsRequest {
    /// The room's name (`rooms[].name` of the environment).
    pub room: String,
    /// The classes sought (names of the knowledge's object classes).
    pub classes: Vec<String>,
    /// Each (class, cell) pair covered this many times.
    pub k: usize,
    /// Spacing of the standpoint lattice, metres.
    pub spacing: f64,
    /// Also compute the exact optimum, with at most this many branch-and-bound nodes.
    pub optimal: Option<u64>,
    /// Measured detection ranges ([`crate::zoom_sensing`]) of some classes, used instead of the
    /// limits eq. 1 and the vote cell give (empty: those limits for every class).
    pub measured: Vec<avs_agent::MeasuredSensing>,
}

/// One planned image, for people and tools.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewOut {
    /// Index of the standpoint.
    pub standpoint: usize,
    /// The standpoint `[x, y]`, metres.
    pub at: [f64; 2],
    /// Camera direction in the world, degrees.
    pub yaw_deg: f64,
    /// Tilt, degrees.
    pub tilt_deg: f64,
    /// Zoom.
    pub zoom: f64,
    /// The classes looked for.
    pub classes: Vec<String>,
}

/// The answer of `avs views`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ViewsReport {
    /// The room.
    pub room: String,
    /// Its floor area, m².
    pub area: f64,
    /// The cells to cover (their centres).
    pub cells: Vec<[f64; 2]>,
    /// The candidate standpoints.
    pub standpoints: Vec<[f64; 2]>,
    /// The standpoints the plan uses (indices).
    pub standpoints_used: Vec<usize>,
    /// The number of images (the paper's searches).
    pub searches: usize,
    /// Per class, the share of its (class, cell) pairs covered `k` times.
    pub coverage: BTreeMap<String, f64>,
    /// (class, cell) pairs no standpoint sees.
    pub uncoverable: usize,
    /// The images, in the order to take them (nearest standpoint first from the first one).
    pub views: Vec<ViewOut>,
    /// The exact optimum's number of images (with `--optimal`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal_searches: Option<usize>,
    /// Whether that optimum is proven (with `--optimal`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimal_proven: Option<bool>,
}

/// The view-planning problem of `request` in `world` with `knowledge`'s classes.
pub fn room_problem(
    world: &World,
    knowledge: &Knowledge,
    request: &ViewsRequest,
) -> Result<(ViewProblem, f64), EvalError> {
    let field = |field: &str, message: String| EvalError::Field {
        file: "views request".into(),
        field: field.into(),
        message,
    };
    let names: Vec<&str> = world.env.rooms.iter().map(|r| r.name.as_str()).collect();
    let room = names
        .iter()
        .position(|n| *n == request.room)
        .ok_or_else(|| {
            field(
                "room",
                format!(
                    "no room `{}` in the environment; its rooms are {}",
                    request.room,
                    names.join(", ")
                ),
            )
        })?;
    if request.classes.is_empty() {
        return Err(field("classes", "name at least one class".into()));
    }
    if !(request.spacing.is_finite() && request.spacing >= 0.1) {
        return Err(field(
            "spacing",
            format!(
                "expected a spacing of at least 0.1 m, got {}",
                request.spacing
            ),
        ));
    }
    if request.k == 0 {
        return Err(field("k", "expected k ≥ 1".into()));
    }
    let camera = Camera::from(&world.env.camera);
    let image = ImageGeometry::default();
    let mut classes = Vec::new();
    for name in &request.classes {
        let class = knowledge.class(name).ok_or_else(|| {
            let known: Vec<&str> = knowledge
                .object_classes
                .iter()
                .map(|c| c.name.as_str())
                .collect();
            field(
                "classes",
                format!(
                    "unknown class `{name}`; the knowledge has {}",
                    known.join(", ")
                ),
            )
        })?;
        let zs = avs_view::search_heights(knowledge, class, false, HEIGHT_STEP, 0.75);
        let lo = zs.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = zs.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut sought =
            SoughtClass::from_model(&ObjectModel::from_class(class), &camera, &image, [lo, hi]);
        if let Some(m) = request.measured.iter().find(|m| m.class == class.name) {
            let range = |r: [f64; 2]| avs_view::DetectionRange {
                min: r[0],
                max: r[1],
            };
            sought.range = range(m.detection_range);
            sought.zoom_ranges = m
                .ranges_by_zoom
                .iter()
                .map(|&(z, r)| (z, range(r)))
                .collect();
        }
        classes.push(sought);
    }
    let grid = &world.truth;
    let in_room = |c: i64, r: i64| {
        c >= 0
            && r >= 0
            && (c as usize) < grid.width()
            && (r as usize) < grid.height()
            && world.room_of_cell[grid.index(c as usize, r as usize)] == Some(room)
            && grid.get(c as usize, r as usize) == Cell::Free
    };
    // Occupied cells next to the room's free floor, bucketed into 0.5 m cells.
    let mut buckets: BTreeMap<(i64, i64), ()> = BTreeMap::new();
    let mut floor = 0usize;
    for r in 0..grid.height() as i64 {
        for c in 0..grid.width() as i64 {
            if in_room(c, r) {
                floor += 1;
                continue;
            }
            if grid.get_i(c, r) != Cell::Occupied {
                continue;
            }
            let borders = (-1..=1).any(|dr| (-1..=1).any(|dc| in_room(c + dc, r + dr)));
            if borders {
                let (x, y) = grid.cell_center(c, r);
                buckets.insert(((x / CELL).floor() as i64, (y / CELL).floor() as i64), ());
            }
        }
    }
    let cells: Vec<[f64; 2]> = buckets
        .keys()
        .map(|&(i, j)| [(i as f64 + 0.5) * CELL, (j as f64 + 0.5) * CELL])
        .collect();
    let standpoints = standpoint_lattice(grid, &in_room, world.env.robot.radius, request.spacing);
    let area = floor as f64 * grid.resolution() * grid.resolution();
    Ok((
        ViewProblem {
            cells,
            standpoints,
            classes,
            camera,
            options: PlanOptions {
                k: request.k,
                ..PlanOptions::default()
            },
        },
        area,
    ))
}

/// Standpoints: a lattice `spacing` apart over the room's free cells whose disc of `radius`
/// holds no occupied cell.
fn standpoint_lattice(
    grid: &OccupancyGrid,
    in_room: &impl Fn(i64, i64) -> bool,
    radius: f64,
    spacing: f64,
) -> Vec<[f64; 2]> {
    let res = grid.resolution();
    let reach = (radius / res).ceil() as i64;
    let step = ((spacing / res).round() as i64).max(1);
    let mut out = Vec::new();
    for r in (0..grid.height() as i64).step_by(step as usize) {
        for c in (0..grid.width() as i64).step_by(step as usize) {
            if !in_room(c, r) {
                continue;
            }
            let clear = (-reach..=reach).all(|dr| {
                (-reach..=reach).all(|dc| {
                    (dr * dr + dc * dc) as f64 * res * res > radius * radius
                        || grid.get_i(c + dc, r + dr) == Cell::Free
                })
            });
            if clear {
                let (x, y) = grid.cell_center(c, r);
                out.push([x, y]);
            }
        }
    }
    out
}

/// Whether walls and closed doors leave the line from `a` to the cell at `b` open (the last
/// half cell, the cell's own wall, does not count).
fn wall_sight(walls: &OccupancyGrid, a: [f64; 2], b: [f64; 2]) -> bool {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let d = dx.hypot(dy);
    if d <= CELL {
        return true;
    }
    let s = (d - CELL) / d;
    avs_map::raycast::line_of_sight(walls, a, [a[0] + s * dx, a[1] + s * dy], false)
}

/// Plan the room's views (and the optimum with `request.optimal`).
pub fn plan_room(
    world: &World,
    knowledge: &Knowledge,
    request: &ViewsRequest,
) -> Result<(ViewProblem, ViewPlan, ViewsReport), EvalError> {
    let (problem, area) = room_problem(world, knowledge, request)?;
    let sight = |a: [f64; 2], b: [f64; 2]| wall_sight(&world.walls, a, b);
    let invalid = |e: avs_view::ViewError| EvalError::Sim(e.to_string());
    let plan = plan_views(&problem, sight).map_err(invalid)?;
    let (optimal_searches, optimal_proven) = match request.optimal {
        Some(nodes) => {
            let exact = optimal_views(&problem, sight, nodes).map_err(invalid)?;
            (Some(exact.plan.searches()), Some(exact.proven))
        }
        None => (None, None),
    };
    let start = plan.views.first().map_or([0.0, 0.0], |v| v.at);
    let straight = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let views = nearest_first(&plan, start, straight)
        .into_iter()
        .map(|i| {
            let v = &plan.views[i];
            ViewOut {
                standpoint: v.standpoint,
                at: v.at,
                yaw_deg: v.yaw.to_degrees(),
                tilt_deg: v.tilt.to_degrees(),
                zoom: v.zoom,
                classes: v
                    .classes
                    .iter()
                    .map(|&c| problem.classes[c].class.clone())
                    .collect(),
            }
        })
        .collect();
    let report = ViewsReport {
        room: request.room.clone(),
        area,
        cells: problem.cells.clone(),
        standpoints: problem.standpoints.clone(),
        standpoints_used: plan.standpoints_used(),
        searches: plan.searches(),
        coverage: problem
            .classes
            .iter()
            .zip(&plan.coverage)
            .map(|(c, v)| (c.class.clone(), *v))
            .collect(),
        uncoverable: plan.uncoverable.len(),
        views,
        optimal_searches,
        optimal_proven,
    };
    Ok((problem, plan, report))
}

/// The plan drawn over the world's map (`avs views --svg`).
pub fn render_svg(world: &World, problem: &ViewProblem, plan: &ViewPlan) -> String {
    let straight = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let start = plan.views.first().map_or([0.0, 0.0], |v| v.at);
    let images = nearest_first(plan, start, straight)
        .into_iter()
        .map(|i| {
            let v = &plan.views[i];
            // As far as the farthest cell it covers (its classes reach farther, through walls).
            let reach = v
                .pairs
                .iter()
                .map(|p| straight(v.at, problem.cells[p.cell]) + CELL / 2.0)
                .fold(0.0, f64::max);
            avs_sim::render::PlannedImage {
                at: v.at,
                yaw: v.yaw,
                hfov: problem.camera.hfov / v.zoom,
                reach,
            }
        })
        .collect();
    let classes: Vec<&str> = problem.classes.iter().map(|c| c.class.as_str()).collect();
    let picture = avs_sim::render::ViewPlanPicture {
        title: format!("{}: view plan for {}", world.env.name, classes.join(", ")),
        subtitle: format!(
            "{} searches from {} of {} standpoints; {} cells to cover",
            plan.searches(),
            plan.standpoints_used().len(),
            problem.standpoints.len(),
            problem.cells.len()
        ),
        cells: problem.cells.clone(),
        cell: CELL,
        standpoints: problem.standpoints.clone(),
        used: plan.standpoints_used(),
        images,
    };
    avs_sim::render::render_view_plan(world, &picture)
}
