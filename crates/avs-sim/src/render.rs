//! Pictures of a world: the map, rooms coloured, doors, objects, the robot, and — for a partly
//! explored state — the place map (places, paths, door hypotheses, placeholders).

use crate::explore::Explorer;
use crate::world::World;
use avs_format::environment::ObjectRole;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::places::PlaceMap;
use svg::node::element::{Circle, Group, Line, Rectangle, Text, Title};
use svg::Document;

/// Pixels per metre.
const SCALE: f64 = 50.0;

const PALETTE: [&str; 10] = [
    "#8dd3c7", "#ffffb3", "#bebada", "#fb8072", "#80b1d3", "#fdb462", "#b3de69", "#fccde5",
    "#bc80bd", "#ccebc5",
];

struct Frame {
    origin: [f64; 2],
    height_m: f64,
}

impl Frame {
    fn new(g: &OccupancyGrid) -> Self {
        Self {
            origin: g.origin(),
            height_m: g.height() as f64 * g.resolution(),
        }
    }
    fn x(&self, x: f64) -> f64 {
        (x - self.origin[0]) * SCALE
    }
    fn y(&self, y: f64) -> f64 {
        (self.height_m - (y - self.origin[1])) * SCALE
    }
}

/// Draw the grid as horizontal runs of equal colour; `colour(col, row)` names each cell's fill
/// (`None` leaves the background).
fn grid_runs(
    g: &OccupancyGrid,
    f: &Frame,
    colour: impl Fn(usize, usize) -> Option<&'static str>,
) -> Group {
    let mut group = Group::new().set("shape-rendering", "crispEdges");
    let r = g.resolution();
    for row in 0..g.height() {
        let mut col = 0;
        while col < g.width() {
            let c = colour(col, row);
            let start = col;
            while col < g.width() && colour(col, row) == c {
                col += 1;
            }
            if let Some(fill) = c {
                let (x0, y0) = g.cell_center(start as i64, row as i64);
                group = group.add(
                    Rectangle::new()
                        .set("x", f.x(x0 - r / 2.0))
                        .set("y", f.y(y0 + r / 2.0))
                        .set("width", (col - start) as f64 * r * SCALE)
                        .set("height", r * SCALE)
                        .set("fill", fill),
                );
            }
        }
    }
    group
}

fn cell_colour(c: Cell) -> Option<&'static str> {
    match c {
        Cell::Occupied => Some("#222"),
        Cell::Unknown => Some("#bbb"),
        Cell::Free => None,
    }
}

fn document(g: &OccupancyGrid, title: &str) -> Document {
    let w = g.width() as f64 * g.resolution() * SCALE;
    let h = g.height() as f64 * g.resolution() * SCALE;
    Document::new()
        .set("viewBox", (0, 0, w, h))
        .set("width", w)
        .set("height", h)
        .add(Title::new(title))
        .add(
            Rectangle::new()
                .set("width", w)
                .set("height", h)
                .set("fill", "white"),
        )
}

fn objects_and_robot(world: &World, f: &Frame, robot: [f64; 3]) -> Group {
    let mut g = Group::new();
    for o in &world.env.objects {
        let (fill, stroke) = match o.role {
            ObjectRole::Landmark => ("#c8a165", "#6b4f1d"),
            ObjectRole::Target => ("#2ca02c", "#0b4f0b"),
            ObjectRole::Distractor => ("#d62728", "#6b0b0b"),
        };
        let yaw = o.pose.yaw_deg;
        g = g.add(
            Rectangle::new()
                .set("x", f.x(o.pose.x) - o.size[0] * SCALE / 2.0)
                .set("y", f.y(o.pose.y) - o.size[1] * SCALE / 2.0)
                .set("width", (o.size[0] * SCALE).max(4.0))
                .set("height", (o.size[1] * SCALE).max(4.0))
                .set("fill", fill)
                .set("stroke", stroke)
                .set(
                    "transform",
                    format!("rotate({} {} {})", -yaw, f.x(o.pose.x), f.y(o.pose.y)),
                )
                .add(Title::new(format!("{} ({})", o.id, o.class))),
        );
        if o.role != ObjectRole::Landmark {
            g = g.add(
                Text::new(o.id.clone())
                    .set("x", f.x(o.pose.x) + 4.0)
                    .set("y", f.y(o.pose.y) - 4.0)
                    .set("font-size", 10)
                    .set("font-family", "sans-serif"),
            );
        }
    }
    let (x, y) = (f.x(robot[0]), f.y(robot[1]));
    let r = world.env.robot.radius * SCALE;
    g.add(
        Circle::new()
            .set("cx", x)
            .set("cy", y)
            .set("r", r)
            .set("fill", "#1f77b4")
            .set("fill-opacity", 0.6),
    )
    .add(
        Line::new()
            .set("x1", x)
            .set("y1", y)
            .set("x2", x + r * robot[2].cos())
            .set("y2", y - r * robot[2].sin())
            .set("stroke", "black")
            .set("stroke-width", 2),
    )
}

/// The fully known world: walls, ground-truth rooms coloured, doors, objects, the robot's start.
pub fn render_world(world: &World) -> String {
    render_world_document(world, &world.env.name).0.to_string()
}

/// The document of [`render_world`] (titled `title`) and its frame, for pictures drawn over it.
fn render_world_document(world: &World, title: &str) -> (Document, Frame) {
    let g = &world.truth;
    let f = Frame::new(g);
    let rooms = grid_runs(g, &f, |c, r| match g.get(c, r) {
        Cell::Free => world.room_of_cell[g.index(c, r)].map(|k| PALETTE[k % PALETTE.len()]),
        other => cell_colour(other),
    });
    let mut doors = Group::new();
    for d in &world.env.doors {
        let yaw = d.pose.yaw_deg.to_radians();
        let (ux, uy) = (-yaw.sin() * d.width / 2.0, yaw.cos() * d.width / 2.0);
        doors = doors.add(
            Line::new()
                .set("x1", f.x(d.pose.x - ux))
                .set("y1", f.y(d.pose.y - uy))
                .set("x2", f.x(d.pose.x + ux))
                .set("y2", f.y(d.pose.y + uy))
                .set("stroke", if d.open { "#2b8cbe" } else { "#e6550d" })
                .set("stroke-width", 4)
                .add(Title::new(format!(
                    "{} ({})",
                    d.name,
                    if d.open { "open" } else { "closed" }
                ))),
        );
    }
    let mut labels = Group::new();
    for (i, room) in world.env.rooms.iter().enumerate() {
        if let Some(s) = room.seed {
            labels = labels.add(
                Text::new(format!("{} ({})", room.name, room.category))
                    .set("x", f.x(s.x))
                    .set("y", f.y(s.y))
                    .set("font-size", 14)
                    .set("font-family", "sans-serif")
                    .set("fill", if i % 2 == 0 { "#333" } else { "#000" }),
            );
        }
    }
    let s = world.env.robot.start;
    let doc = document(g, title)
        .add(rooms)
        .add(doors)
        .add(objects_and_robot(
            world,
            &f,
            [s.x, s.y, s.yaw_deg.to_radians()],
        ))
        .add(labels);
    (doc, f)
}

/// A search run over the fully known world: the robot's `trail` (a polyline from its start),
/// the position the agent reported (a ring: green when within `success_radius` of an object
/// of `goal`, red otherwise) and the true objects of the goal class (labelled like every
/// object).
pub fn render_search(
    world: &World,
    goal: &str,
    trail: &[[f64; 2]],
    reported: Option<[f64; 3]>,
    success_radius: f64,
) -> String {
    let (mut doc, f) = render_world_document(world, &format!("search for {goal}"));
    if trail.len() >= 2 {
        let points: Vec<String> = trail
            .iter()
            .map(|p| format!("{:.1},{:.1}", f.x(p[0]), f.y(p[1])))
            .collect();
        doc = doc.add(
            svg::node::element::Polyline::new()
                .set("points", points.join(" "))
                .set("fill", "none")
                .set("stroke", "#1f77b4")
                .set("stroke-width", 2)
                .set("stroke-opacity", 0.7)
                .add(Title::new("robot trail")),
        );
    }
    if let Some(r) = reported {
        let ok = world
            .objects_of_class(goal)
            .any(|o| (o.pose.x - r[0]).hypot(o.pose.y - r[1]) <= success_radius);
        doc = doc.add(
            Circle::new()
                .set("cx", f.x(r[0]))
                .set("cy", f.y(r[1]))
                .set("r", 0.3 * SCALE)
                .set("fill", "none")
                .set("stroke", if ok { "#2ca02c" } else { "#d62728" })
                .set("stroke-width", 3)
                .add(Title::new(format!(
                    "reported {goal} at ({:.2}, {:.2}, {:.2})",
                    r[0], r[1], r[2]
                ))),
        );
    }
    doc.to_string()
}

/// A partly explored state: the known grid, free cells coloured by the place-map room of their
/// nearest place, paths, places (door places square), door hypotheses (confirmed solid,
/// hypothesised dashed), placeholders (open circles), objects and the robot.
pub fn render_exploration(ex: &Explorer) -> String {
    let world = ex.robot.world();
    let known = &ex.robot.known;
    let f = Frame::new(known);
    let map = &ex.places;
    let rooms = map.rooms();
    let room_of_node: Vec<Option<usize>> =
        map.graph.node_indices().map(|n| rooms.room_of(n)).collect();
    let nearest_room = |c: usize, r: usize| -> Option<&'static str> {
        let (x, y) = known.cell_center(c as i64, r as i64);
        let n = nearest_within(map, [x, y], 1.2)?;
        room_of_node[n].map(|k| PALETTE[k % PALETTE.len()])
    };
    let cells = grid_runs(known, &f, |c, r| match known.get(c, r) {
        Cell::Free => nearest_room(c, r),
        other => cell_colour(other),
    });
    let mut graph = Group::new();
    for (a, b, e) in map.paths() {
        let (pa, pb) = (map.graph[a].pos, map.graph[b].pos);
        graph = graph.add(
            Line::new()
                .set("x1", f.x(pa[0]))
                .set("y1", f.y(pa[1]))
                .set("x2", f.x(pb[0]))
                .set("y2", f.y(pb[1]))
                .set("stroke", "#555")
                .set("stroke-width", if e.traversed { 2 } else { 1 })
                .set("stroke-dasharray", if e.traversed { "none" } else { "3,3" }),
        );
    }
    for n in map.graph.node_indices() {
        let p = map.graph[n].pos;
        graph = if map.graph[n].door.is_some() {
            graph.add(
                Rectangle::new()
                    .set("x", f.x(p[0]) - 5.0)
                    .set("y", f.y(p[1]) - 5.0)
                    .set("width", 10)
                    .set("height", 10)
                    .set("fill", "#2b8cbe")
                    .add(Title::new(format!("door place {}", n.index()))),
            )
        } else {
            graph.add(
                Circle::new()
                    .set("cx", f.x(p[0]))
                    .set("cy", f.y(p[1]))
                    .set("r", 4)
                    .set("fill", "#333")
                    .add(Title::new(format!("place {}", n.index()))),
            )
        };
    }
    for d in &map.doors {
        let [a, b] = d.hypothesis.jambs;
        graph = graph.add(
            Line::new()
                .set("x1", f.x(a[0]))
                .set("y1", f.y(a[1]))
                .set("x2", f.x(b[0]))
                .set("y2", f.y(b[1]))
                .set("stroke", "#2b8cbe")
                .set("stroke-width", 3)
                .set("stroke-dasharray", if d.confirmed { "none" } else { "4,3" }),
        );
    }
    for (i, ph) in map.placeholders.iter().enumerate() {
        graph = graph.add(
            Circle::new()
                .set("cx", f.x(ph.pos[0]))
                .set("cy", f.y(ph.pos[1]))
                .set("r", 6)
                .set("fill", "none")
                .set("stroke", "#ff7f00")
                .set("stroke-width", 2)
                .add(Title::new(format!(
                    "placeholder {i}: open area {:.1} m², door {}",
                    ph.open_area,
                    ph.door_distance
                        .map_or("none".into(), |d| format!("{d:.1} m"))
                ))),
        );
    }
    document(
        known,
        &format!("{} after {} exploration steps", world.env.name, ex.steps),
    )
    .add(cells)
    .add(graph)
    .add(objects_and_robot(world, &f, ex.robot.pose))
    .to_string()
}

fn nearest_within(map: &PlaceMap, p: [f64; 2], max: f64) -> Option<usize> {
    map.graph
        .node_indices()
        .filter(|&n| map.graph[n].door.is_none())
        .map(|n| (n.index(), avs_map::places::dist(map.graph[n].pos, p)))
        .filter(|&(_, d)| d <= max)
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(n, _)| n)
}
