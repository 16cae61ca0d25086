//! Pictures of a world: the map, rooms coloured, doors, objects, the robot; for a partly
//! explored state the place map (places, paths, door hypotheses, placeholders); and for a search
//! ([`render_search`]) what the robot did: its trail, every camera look as a view-cone wedge,
//! false alarms, the start, the end and the reported position, with a title, a legend and a
//! scale bar; and for a room's view plan ([`render_view_plan`]) the cells to cover, the
//! standpoints and the planned images.
//!
//! Labels (room names, furniture classes) are placed greedily, rooms first, each at the first
//! of a list of candidate positions where it overlaps no label or mark already placed, and
//! always inside the picture.
//!
//! The trail of a long search is made readable by time: it is drawn in [`TRAIL_PIECES`] pieces
//! whose colour runs from pale (the start) to dark (the end), on a white casing, with numbered
//! markers every few metres driven (the step chosen so that there are at most about ten), and a
//! colour ramp under the map says which end is which.

use crate::explore::Explorer;
use crate::world::World;
use avs_format::environment::ObjectRole;
use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::places::PlaceMap;
use std::fmt;
use svg::node::element::path::Data;
use svg::node::element::{
    Circle, ClipPath, Definitions, Group, Line, Path, Polyline, Rectangle, Text, Title,
};
use svg::Document;

mod labels;
mod legend;
mod search;
mod views;

use labels::*;
use legend::*;
#[cfg(test)]
use search::*;
pub use search::{render_search, Look, LookKind, RoomBelief, SearchOutcome, SearchPicture};
pub use views::{render_view_plan, PlannedImage, ViewPlanPicture};

/// Pixels per metre of world and exploration pictures.
const SCALE: f64 = 50.0;

/// Length of a view-cone wedge, metres.
pub const CONE_LENGTH_M: f64 = 2.0;

/// Pieces the trail is drawn in, each in its colour of the time ramp.
pub const TRAIL_PIECES: usize = 40;

const PALETTE: [&str; 10] = [
    "#8dd3c7", "#ffffb3", "#bebada", "#fb8072", "#80b1d3", "#fdb462", "#b3de69", "#fccde5",
    "#bc80bd", "#ccebc5",
];

/// Height of the title band above the map, pixels.
const HEADER: f64 = 52.0;
/// Height of the band under the map (scale bar, trail ramp), pixels.
const FOOTER: f64 = 44.0;
/// Narrowest legend column right of the map, pixels.
const LEGEND_W: f64 = 200.0;
const FONT: &str = "DejaVu Sans, Arial, Helvetica, sans-serif";

// Colours of the search marks.
const CONE_MISS: &str = "#3182bd";
const CONE_HIT: &str = "#e6550d";
const FALSE_ALARM: &str = "#d95f0e";
const START: &str = "#2ca02c";
const END: &str = "#54278f";
const REPORT_OK: &str = "#ffd700";
const REPORT_WRONG: &str = "#d62728";
const TRAIL_OLD: [f64; 3] = [158.0, 202.0, 225.0];
const TRAIL_NEW: [f64; 3] = [8.0, 48.0, 107.0];

struct Frame {
    origin: [f64; 2],
    height_m: f64,
    scale: f64,
}

impl Frame {
    fn new(g: &OccupancyGrid, scale: f64) -> Self {
        Self {
            origin: g.origin(),
            height_m: g.height() as f64 * g.resolution(),
            scale,
        }
    }
    fn x(&self, x: f64) -> f64 {
        (x - self.origin[0]) * self.scale
    }
    fn y(&self, y: f64) -> f64 {
        (self.height_m - (y - self.origin[1])) * self.scale
    }
    fn px(&self, p: [f64; 2]) -> (f64, f64) {
        (self.x(p[0]), self.y(p[1]))
    }
    /// An SVG line from world point `a` to world point `b` (style it with `.set`).
    fn segment(&self, a: [f64; 2], b: [f64; 2]) -> Line {
        Line::new()
            .set("x1", self.x(a[0]))
            .set("y1", self.y(a[1]))
            .set("x2", self.x(b[0]))
            .set("y2", self.y(b[1]))
    }
}

/// Draw the grid as horizontal runs of equal colour; `colour(col, row)` names each cell's fill
/// (`None` leaves the background).
fn grid_runs<'a>(
    g: &OccupancyGrid,
    f: &Frame,
    colour: impl Fn(usize, usize) -> Option<&'a str>,
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
                        .set("width", (col - start) as f64 * r * f.scale)
                        .set("height", r * f.scale)
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

/// `hex` (`#rrggbb`) mixed with white: `share` of white.
fn lighten(hex: &str, share: f64) -> String {
    let c = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).unwrap_or(0) as f64;
    let m = |v: f64| (v + (255.0 - v) * share).round() as u8;
    format!("#{:02x}{:02x}{:02x}", m(c(1)), m(c(3)), m(c(5)))
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

fn text(s: impl Into<String>, x: f64, y: f64, size: f64) -> Text {
    Text::new(s.into())
        .set("x", x)
        .set("y", y)
        .set("font-size", size)
        .set("font-family", FONT)
}

/// Estimated width of `s` in pixels at font size `size` (an average glyph of 0.6 em: generous
/// for sans-serif, so that estimated boxes contain the text).
fn text_width(s: &str, size: f64) -> f64 {
    s.chars().count() as f64 * size * 0.6
}

fn objects(world: &World, f: &Frame) -> Group {
    let mut g = Group::new().set("class", "objects");
    for o in &world.env.objects {
        let (fill, stroke) = object_colours(o.role);
        let yaw = o.pose.yaw_deg;
        g = g.add(
            Rectangle::new()
                .set("x", f.x(o.pose.x) - o.size[0] * f.scale / 2.0)
                .set("y", f.y(o.pose.y) - o.size[1] * f.scale / 2.0)
                .set("width", (o.size[0] * f.scale).max(4.0))
                .set("height", (o.size[1] * f.scale).max(4.0))
                .set("fill", fill)
                .set("stroke", stroke)
                .set(
                    "transform",
                    format!("rotate({} {} {})", -yaw, f.x(o.pose.x), f.y(o.pose.y)),
                )
                .add(Title::new(format!("{} ({})", o.id, o.class))),
        );
    }
    g
}

fn object_colours(role: ObjectRole) -> (&'static str, &'static str) {
    match role {
        ObjectRole::Landmark => ("#c8a165", "#6b4f1d"),
        ObjectRole::Target => ("#2ca02c", "#0b4f0b"),
        ObjectRole::Distractor => ("#d62728", "#6b0b0b"),
    }
}

fn robot_mark(world: &World, f: &Frame, robot: [f64; 3]) -> Group {
    let (x, y) = (f.x(robot[0]), f.y(robot[1]));
    let r = world.env.robot.radius * f.scale;
    Group::new()
        .add(
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

fn objects_and_robot(world: &World, f: &Frame, robot: [f64; 3]) -> Group {
    let mut g = objects(world, f);
    for o in world
        .env
        .objects
        .iter()
        .filter(|o| o.role != ObjectRole::Landmark)
    {
        g = g.add(text(
            o.id.clone(),
            f.x(o.pose.x) + 4.0,
            f.y(o.pose.y) - 4.0,
            10.0,
        ));
    }
    g.add(robot_mark(world, f, robot))
}

fn doors(world: &World, f: &Frame) -> Group {
    let mut doors = Group::new().set("class", "doors");
    for d in &world.env.doors {
        let yaw = d.pose.yaw_deg.to_radians();
        let (ux, uy) = (-yaw.sin() * d.width / 2.0, yaw.cos() * d.width / 2.0);
        doors = doors.add(
            f.segment(
                [d.pose.x - ux, d.pose.y - uy],
                [d.pose.x + ux, d.pose.y + uy],
            )
            .set("stroke", if d.open { "#2b8cbe" } else { "#e6550d" })
            .set("stroke-width", 4)
            .add(Title::new(format!(
                "{} ({})",
                d.name,
                if d.open { "open" } else { "closed" }
            ))),
        );
    }
    doors
}

/// The rooms coloured (lightened by `pale`: 0 the palette, 1 white), walls and unknown space.
fn rooms(world: &World, f: &Frame, pale: f64) -> Group {
    let g = &world.truth;
    let palette: Vec<String> = PALETTE.iter().map(|c| lighten(c, pale)).collect();
    grid_runs(g, f, |c, r| match g.get(c, r) {
        Cell::Free => {
            world.room_of_cell[g.index(c, r)].map(|k| palette[k % palette.len()].as_str())
        }
        other => cell_colour(other),
    })
    .set("class", "rooms")
}

/// The picture around a map: a title band (`title`, `subtitle`) above, the legend right of
/// it, `footer` (drawn from the map's lower left) under it.
fn compose(
    map_w: f64,
    map_h: f64,
    title: &str,
    subtitle: &str,
    map: Group,
    legend: Legend,
    footer: Group,
) -> Document {
    let legend_h = legend.height();
    let w = (map_w + legend.width())
        .max(text_width(title, 15.0) + 20.0)
        .max(text_width(subtitle, 11.5) + 20.0)
        .ceil();
    let h = (HEADER + map_h.max(legend_h) + FOOTER).ceil();
    Document::new()
        .set("viewBox", (0, 0, w, h))
        .set("width", w)
        .set("height", h)
        .add(Title::new(title))
        .add(
            Definitions::new().add(
                ClipPath::new()
                    .set("id", "map-clip")
                    .add(Rectangle::new().set("width", map_w).set("height", map_h)),
            ),
        )
        .add(
            Rectangle::new()
                .set("width", w)
                .set("height", h)
                .set("fill", "white"),
        )
        .add(
            Group::new()
                .set("id", "title")
                .add(text(title, 8.0, 21.0, 15.0).set("font-weight", "bold"))
                .add(text(subtitle, 8.0, 41.0, 11.5).set("fill", "#333")),
        )
        .add(
            map.set("id", "map")
                .set("transform", format!("translate(0 {HEADER})")),
        )
        .add(legend.draw(map_w + 8.0, HEADER))
        .add(footer.set("transform", format!("translate(0 {})", HEADER + map_h)))
}

/// The fully known world: walls, ground-truth rooms coloured and labelled (name and category),
/// doors, objects (furniture labelled with its class), the robot's start; a title, a legend and
/// a scale bar.
pub fn render_world(world: &World) -> String {
    let g = &world.truth;
    let f = Frame::new(g, SCALE);
    let (w, h) = map_size(g, &f);
    let mut placer = Placer::new(w, h);
    let s = world.env.robot.start;
    let start = [s.x, s.y, s.yaw_deg.to_radians()];
    let (sx, sy) = f.px([s.x, s.y]);
    let r = world.env.robot.radius * f.scale;
    placer.reserve([sx - r, sy - r, sx + r, sy + r]);
    let labels = label_rooms_and_objects(world, &f, &mut placer, &[]);
    let map = Group::new()
        .add(rooms(world, &f, 0.0))
        .add(doors(world, &f))
        .add(objects(world, &f))
        .add(robot_mark(world, &f, start))
        .add(labels);
    let mut legend = Legend::default();
    world_legend(world, &mut legend, 0.0);
    legend.add(robot_start_symbol(), "robot at its start");
    let width_m = g.width() as f64 * g.resolution();
    let footer = Group::new().add(scale_bar(&f, width_m, 10.0, 24.0));
    compose(
        w,
        h,
        &world.env.name,
        &format!(
            "{:.1} m × {:.1} m, {} rooms, {} doors, {} objects",
            width_m,
            g.height() as f64 * g.resolution(),
            world.env.rooms.len(),
            world.env.doors.len(),
            world.env.objects.len()
        ),
        map,
        legend,
        footer,
    )
    .to_string()
}

fn robot_start_symbol() -> Group {
    Group::new()
        .add(
            Circle::new()
                .set("cx", 12)
                .set("cy", 0)
                .set("r", 6)
                .set("fill", "#1f77b4")
                .set("fill-opacity", 0.6),
        )
        .add(
            Line::new()
                .set("x1", 12)
                .set("y1", 0)
                .set("x2", 18)
                .set("y2", 0)
                .set("stroke", "black")
                .set("stroke-width", 2),
        )
}

fn map_size(g: &OccupancyGrid, f: &Frame) -> (f64, f64) {
    (
        g.width() as f64 * g.resolution() * f.scale,
        g.height() as f64 * g.resolution() * f.scale,
    )
}

/// A partly explored state: the known grid, free cells coloured by the place-map room of their
/// nearest place, paths, places (door places square), door hypotheses (confirmed solid,
/// hypothesised dashed), placeholders (open circles), objects and the robot.
pub fn render_exploration(ex: &Explorer) -> String {
    let world = ex.robot.world();
    let known = &ex.robot.known;
    let f = Frame::new(known, SCALE);
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
            f.segment(pa, pb)
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
            f.segment(a, b)
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn office() -> World {
        World::load(
            &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/environments/office.yaml"),
        )
        .unwrap()
    }

    fn count(svg: &str, s: &str) -> usize {
        svg.matches(s).count()
    }

    /// The value of attribute `name` in the element text `el`.
    fn attr(el: &str, name: &str) -> f64 {
        let key = format!(" {name}=\"");
        let rest = &el[el.find(&key).unwrap_or_else(|| panic!("{name} in {el}")) + key.len()..];
        rest[..rest.find('"').unwrap()].parse().unwrap()
    }

    fn look(at: [f64; 2], direction: f64, detected: bool, kind: LookKind) -> Look {
        Look {
            at,
            direction,
            hfov: 45f64.to_radians(),
            detected,
            kind,
            label: "look".into(),
        }
    }

    fn picture(reported: Option<[f64; 3]>) -> SearchPicture {
        SearchPicture {
            goal: "cerealbox".into(),
            seed: Some(7),
            path_length: 12.34,
            trail: vec![[1.0, 1.2], [3.0, 1.2], [6.0, 1.2], [6.0, 4.0]],
            start: Some([1.0, 1.2, 0.0]),
            end: Some([6.0, 4.0, 1.5]),
            reported,
            looks: vec![
                look([3.0, 1.2], 0.0, false, LookKind::Cone),
                look([6.0, 4.0], 1.5, true, LookKind::Cone),
                look([6.0, 4.0], 2.0, false, LookKind::Verify),
            ],
            coverage_looks: 0,
            false_alarms: vec![[7.0, 7.4]],
            room_beliefs: vec![RoomBelief {
                room: 2,
                category: "kitchen".into(),
                probability: 0.6,
            }],
        }
    }

    #[test]
    fn a_wrong_report_is_crossed_out_and_said_in_the_title() {
        let world = office();
        // The cerealbox stands at (5.4, 5.1); a report in the corridor is wrong.
        let svg = render_search(&world, &picture(Some([2.0, 1.2, 0.8])));
        assert!(
            svg.contains("office — search for cerealbox, seed 7: wrong report, path 12.3 m"),
            "{}",
            &svg[..600]
        );
        assert_eq!(count(&svg, "class=\"report wrong\""), 1);
        assert!(
            svg.contains("wrong report: &gt; 1 m from every cerealbox")
                || svg.contains("wrong report: > 1 m from every cerealbox")
        );
        assert!(svg.contains("WRONG REPORT, the nearest true cerealbox is"));
        // Wedges: one per look, by kind and verdict.
        assert_eq!(count(&svg, "class=\"view-cone miss\""), 1);
        assert_eq!(count(&svg, "class=\"view-cone hit\""), 1);
        assert_eq!(count(&svg, "class=\"verify-look miss\""), 1);
        assert_eq!(count(&svg, "class=\"false-alarm\""), 1);
        assert_eq!(count(&svg, "class=\"start\""), 1);
        assert_eq!(count(&svg, "class=\"end\""), 1);
        assert!(svg.contains("agent: kitchen 0.60"));
        // The legend lists what is drawn, and only that: no verified detection here.
        assert!(svg.contains("view cone processed, cerealbox detected (1)"));
        assert!(!svg.contains("verifying look, detected"));
    }

    #[test]
    fn a_report_near_a_true_object_is_found_and_not_crossed_out() {
        let world = office();
        let svg = render_search(&world, &picture(Some([5.5, 5.0, 0.9])));
        assert!(svg.contains("seed 7: found, path 12.3 m"));
        assert_eq!(count(&svg, "class=\"report\""), 1);
        assert_eq!(count(&svg, "class=\"report wrong\""), 0);
        assert!(svg.contains("reported position (correct)"));
        let none = render_search(&world, &picture(None));
        assert!(none.contains("seed 7: not found, path 12.3 m"));
        assert_eq!(count(&none, "class=\"report"), 0);
    }

    #[test]
    fn room_labels_stay_inside_the_map_and_apart() {
        let world = office();
        for svg in [render_search(&world, &picture(None)), render_world(&world)] {
            let map_w = world.truth.width() as f64 * world.truth.resolution();
            let map_h = world.truth.height() as f64 * world.truth.resolution();
            let boxes: Vec<[f64; 4]> = svg
                .split("class=\"room-label\"")
                .skip(1)
                .map(|s| {
                    let el = &s[s.find("<rect").unwrap()..];
                    let el = &el[..el.find('>').unwrap()];
                    let (x, y) = (attr(el, "x"), attr(el, "y"));
                    [x, y, x + attr(el, "width"), y + attr(el, "height")]
                })
                .collect();
            assert_eq!(boxes.len(), 4, "one label per room");
            // The map is drawn at 50 px/m (world) or more (search): its pixel size bounds
            // the labels.
            let scale = if svg.contains("search for") {
                (900.0 / map_w).clamp(28.0, 70.0)
            } else {
                SCALE
            };
            for (i, a) in boxes.iter().enumerate() {
                assert!(a[0] >= 0.0 && a[1] >= 0.0, "{a:?}");
                assert!(
                    a[2] <= map_w * scale + 1e-6 && a[3] <= map_h * scale + 1e-6,
                    "{a:?}"
                );
                for b in &boxes[i + 1..] {
                    let apart = a[2] <= b[0] || b[2] <= a[0] || a[3] <= b[1] || b[3] <= a[1];
                    assert!(apart, "{a:?} overlaps {b:?}");
                }
            }
            for name in [
                "corridor (corridor)",
                "office1 (office)",
                "kitchen (kitchen)",
            ] {
                assert!(svg.contains(name), "{name}");
            }
            // Every furniture piece is labelled with its class.
            assert_eq!(count(&svg, "class=\"furniture-label\""), 6);
            assert!(svg.contains("id=\"scale-bar\"") && svg.contains("id=\"legend\""));
        }
    }

    #[test]
    fn a_wedge_opens_around_its_direction() {
        // Pointing along +x from (100, 100): the first edge is below the axis on screen (world
        // angle −hfov/2), the arc ends above it, both 50 px away.
        let d = wedge_data(100.0, 100.0, 0.0, 90f64.to_radians(), 50.0);
        let s = svg::node::Value::from(d).to_string();
        let nums: Vec<f64> = s
            .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
            .filter(|t| !t.is_empty())
            .map(|t| t.parse().unwrap())
            .collect();
        // M x y L x1 y1 A rx ry rot large sweep x2 y2 z
        let (x1, y1, x2, y2) = (nums[2], nums[3], nums[9], nums[10]);
        let h = 50.0 * 45f64.to_radians().cos();
        assert!(
            (x1 - (100.0 + h)).abs() < 1e-3 && (y1 - (100.0 + h)).abs() < 1e-3,
            "{s}"
        );
        assert!(
            (x2 - (100.0 + h)).abs() < 1e-3 && (y2 - (100.0 - h)).abs() < 1e-3,
            "{s}"
        );
    }

    #[test]
    fn trail_markers_are_at_most_about_ten() {
        assert_eq!(marker_step(15.0), 2.0);
        assert_eq!(marker_step(81.3), 10.0);
        assert_eq!(marker_step(473.9), 50.0);
        assert_eq!(marker_step(779.3), 100.0);
        assert_eq!(marker_step(1500.0), 200.0);
    }
}
