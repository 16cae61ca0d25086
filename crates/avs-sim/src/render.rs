//! Pictures of a world: the map, rooms coloured, doors, objects, the robot; for a partly
//! explored state the place map (places, paths, door hypotheses, placeholders); and for a search
//! ([`render_search`]) what the robot did: its trail, every camera look as a view-cone wedge,
//! false alarms, the start, the end and the reported position, with a title, a legend and a
//! scale bar.
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

/// Greedy placement of label boxes: each at the first candidate that overlaps nothing placed
/// before, else at the candidate that overlaps least; always inside `bounds`.
struct Placer {
    boxes: Vec<[f64; 4]>,
    bounds: [f64; 4],
}

impl Placer {
    fn new(w: f64, h: f64) -> Self {
        Self {
            boxes: Vec::new(),
            bounds: [0.0, 0.0, w, h],
        }
    }

    /// Reserve a box (`[x0, y0, x1, y1]`) that labels must avoid.
    fn reserve(&mut self, b: [f64; 4]) {
        self.boxes.push(b);
    }

    fn clamp(&self, x: f64, y: f64, w: f64, h: f64) -> [f64; 4] {
        let [bx0, by0, bx1, by1] = self.bounds;
        let x = x.min(bx1 - w).max(bx0);
        let y = y.min(by1 - h).max(by0);
        [x, y, x + w, y + h]
    }

    fn overlap(&self, b: [f64; 4]) -> f64 {
        self.boxes
            .iter()
            .map(|o| {
                let w = (b[2].min(o[2]) - b[0].max(o[0])).max(0.0);
                let h = (b[3].min(o[3]) - b[1].max(o[1])).max(0.0);
                w * h
            })
            .sum()
    }

    /// Place a `w`×`h` box at the first of the top-left corners `tops` that overlaps nothing
    /// and has no `misfit` (a penalty: 0 for a box where it belongs); its box.
    fn place(
        &mut self,
        tops: &[(f64, f64)],
        w: f64,
        h: f64,
        misfit: &dyn Fn([f64; 4]) -> f64,
    ) -> [f64; 4] {
        let mut best: Option<([f64; 4], f64)> = None;
        for &(x, y) in tops {
            let b = self.clamp(x, y, w, h);
            let o = self.overlap(b) + misfit(b);
            if o <= 0.0 {
                best = Some((b, 0.0));
                break;
            }
            if best.is_none_or(|(_, bo)| o < bo) {
                best = Some((b, o));
            }
        }
        let b = best.map_or_else(|| self.clamp(0.0, 0.0, w, h), |(b, _)| b);
        self.boxes.push(b);
        b
    }
}

/// A label of one or more lines on a pale box, placed by `placer` near `anchor`.
struct Label {
    lines: Vec<(String, f64, &'static str)>,
    class: &'static str,
    fill: &'static str,
}

impl Label {
    fn size(&self) -> (f64, f64) {
        let w = self
            .lines
            .iter()
            .map(|(s, size, _)| text_width(s, *size))
            .fold(0.0, f64::max);
        let h: f64 = self.lines.iter().map(|(_, size, _)| size * 1.2).sum();
        (w + 6.0, h + 4.0)
    }

    fn draw(&self, b: [f64; 4]) -> Group {
        let mut g = Group::new().set("class", self.class).add(
            Rectangle::new()
                .set("x", b[0])
                .set("y", b[1])
                .set("width", b[2] - b[0])
                .set("height", b[3] - b[1])
                .set("rx", 2)
                .set("fill", "white")
                .set("fill-opacity", 0.72),
        );
        let mut y = b[1] + 2.0;
        for (s, size, weight) in &self.lines {
            y += size * 1.2;
            g = g.add(
                text(s.clone(), b[0] + 3.0, y - size * 0.28, *size)
                    .set("font-weight", *weight)
                    .set("fill", self.fill),
            );
        }
        g
    }
}

/// Candidate top-left corners for a `w`×`h` box centred near `(x, y)`, nearest first.
fn around_centre(x: f64, y: f64, w: f64, h: f64) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for k in 0..6 {
        let dy = h * k as f64;
        for dx in [0.0, -w / 2.0, w / 2.0] {
            v.push((x - w / 2.0 + dx, y - h / 2.0 - dy));
            if k > 0 {
                v.push((x - w / 2.0 + dx, y - h / 2.0 + dy));
            }
        }
    }
    v
}

/// Candidate top-left corners for a `w`×`h` box beside a box of half extents `(ex, ey)` at
/// `(x, y)`, nearest first.
fn beside(x: f64, y: f64, (ex, ey): (f64, f64), w: f64, h: f64) -> Vec<(f64, f64)> {
    let mut v = Vec::new();
    for k in 0..4 {
        let g = 2.0 + k as f64 * h;
        v.extend([
            (x + ex + g, y - h / 2.0),
            (x - ex - g - w, y - h / 2.0),
            (x - w / 2.0, y - ey - g - h),
            (x - w / 2.0, y + ey + g),
            (x + ex + g, y - ey - g - h),
            (x - ex - g - w, y + ey + g),
            (x + ex + g, y + ey + g),
            (x - ex - g - w, y - ey - g - h),
        ]);
    }
    v
}

/// A room's label anchor: the centroid of its cells when that lies in the room, else its seed,
/// else its first cell.
fn room_anchor(world: &World, room: usize) -> Option<[f64; 2]> {
    let g = &world.walls;
    let (mut sx, mut sy, mut n, mut first) = (0.0, 0.0, 0usize, None);
    for row in 0..g.height() {
        for col in 0..g.width() {
            if world.room_of_cell[g.index(col, row)] == Some(room) {
                let (x, y) = g.cell_center(col as i64, row as i64);
                sx += x;
                sy += y;
                n += 1;
                first.get_or_insert([x, y]);
            }
        }
    }
    if n > 0 {
        let c = [sx / n as f64, sy / n as f64];
        if world.room_at(c[0], c[1]) == Some(room) {
            return Some(c);
        }
    }
    world.env.rooms[room].seed.map(|s| [s.x, s.y]).or(first)
}

/// How far a label box lies outside room `room`: 10⁶ for each of its left, centre and right
/// points (at mid-height) that is not in the room (pixels to world by `f`).
fn outside_room(world: &World, f: &Frame, room: Option<usize>, b: [f64; 4]) -> f64 {
    let Some(room) = room else {
        return 0.0;
    };
    let y = (b[1] + b[3]) / 2.0;
    [b[0] + 2.0, (b[0] + b[2]) / 2.0, b[2] - 2.0]
        .iter()
        .filter(|&&x| {
            let wx = x / f.scale + f.origin[0];
            let wy = f.origin[1] + f.height_m - y / f.scale;
            world.room_at(wx, wy) != Some(room)
        })
        .count() as f64
        * 1e6
}

/// Label the rooms (true name and category, and `beliefs`: the agent's likeliest category)
/// and the objects (their class), keeping off the objects and each other.
fn label_rooms_and_objects(
    world: &World,
    f: &Frame,
    placer: &mut Placer,
    beliefs: &[RoomBelief],
) -> Group {
    let mut g = Group::new().set("id", "labels");
    // Labels keep off the objects' footprints.
    let extents = |o: &avs_format::environment::Object| {
        let yaw = o.pose.yaw_deg.to_radians();
        let (c, s) = (yaw.cos().abs(), yaw.sin().abs());
        (
            ((c * o.size[0] + s * o.size[1]) / 2.0 * f.scale).max(3.0),
            ((s * o.size[0] + c * o.size[1]) / 2.0 * f.scale).max(3.0),
        )
    };
    for o in &world.env.objects {
        let (ex, ey) = extents(o);
        let (x, y) = f.px([o.pose.x, o.pose.y]);
        placer.reserve([x - ex, y - ey, x + ex, y + ey]);
    }
    for (i, room) in world.env.rooms.iter().enumerate() {
        let Some(a) = room_anchor(world, i) else {
            continue;
        };
        let mut lines = vec![(format!("{} ({})", room.name, room.category), 13.0, "bold")];
        if let Some(b) = beliefs.iter().rev().find(|b| b.room == i) {
            lines.push((
                format!("agent: {} {:.2}", b.category, b.probability),
                11.0,
                "normal",
            ));
        }
        let l = Label {
            lines,
            class: "room-label",
            fill: "#111",
        };
        let (w, h) = l.size();
        let (x, y) = f.px(a);
        let b = placer.place(&around_centre(x, y, w, h), w, h, &|b| {
            outside_room(world, f, Some(i), b)
        });
        g = g.add(l.draw(b));
    }
    for o in &world.env.objects {
        let l = Label {
            lines: vec![(o.class.clone(), 9.0, "normal")],
            class: if o.role == ObjectRole::Landmark {
                "furniture-label"
            } else {
                "object-label"
            },
            fill: match o.role {
                ObjectRole::Landmark => "#4a3510",
                ObjectRole::Target => "#0b4f0b",
                ObjectRole::Distractor => "#8b0b0b",
            },
        };
        let (w, h) = l.size();
        let (x, y) = f.px([o.pose.x, o.pose.y]);
        let room = world.env.rooms.iter().position(|rm| rm.name == o.room);
        let b = placer.place(&beside(x, y, extents(o), w, h), w, h, &|b| {
            outside_room(world, f, room, b)
        });
        g = g.add(l.draw(b));
    }
    g
}

fn doors(world: &World, f: &Frame) -> Group {
    let mut doors = Group::new().set("class", "doors");
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

/// The legend: a column of entries, each a symbol (drawn around `(12, 0)`) and its text.
#[derive(Default)]
struct Legend {
    entries: Vec<(Group, String)>,
}

impl Legend {
    fn add(&mut self, symbol: Group, s: impl Into<String>) {
        self.entries.push((symbol, s.into()));
    }

    const ROW: f64 = 19.0;

    fn height(&self) -> f64 {
        28.0 + self.entries.len() as f64 * Self::ROW
    }

    /// Width of the column: the widest entry's, at least [`LEGEND_W`].
    fn width(&self) -> f64 {
        self.entries
            .iter()
            .map(|(_, s)| 46.0 + text_width(s, Self::FONT))
            .fold(LEGEND_W, f64::max)
    }

    const FONT: f64 = 10.5;

    fn draw(self, x: f64, y: f64) -> Group {
        let w = self.width();
        let mut g = Group::new()
            .set("id", "legend")
            .set("transform", format!("translate({x} {y})"))
            .add(
                Rectangle::new()
                    .set("x", 0)
                    .set("y", 0)
                    .set("width", w - 16.0)
                    .set("height", self.height())
                    .set("fill", "#fafafa")
                    .set("stroke", "#999"),
            )
            .add(text("Legend", 8.0, 17.0, 12.0).set("font-weight", "bold"));
        for (i, (sym, s)) in self.entries.into_iter().enumerate() {
            let cy = 28.0 + (i as f64 + 0.5) * Self::ROW;
            g = g.add(
                Group::new()
                    .set("class", "legend-entry")
                    .add(sym.set("transform", format!("translate(8 {cy})")))
                    .add(text(s, 38.0, cy + 4.0, Self::FONT)),
            );
        }
        g
    }
}

fn legend_rect(fill: &str, stroke: &str) -> Group {
    Group::new().add(
        Rectangle::new()
            .set("x", 4)
            .set("y", -6)
            .set("width", 16)
            .set("height", 12)
            .set("fill", fill)
            .set("stroke", stroke),
    )
}

fn legend_line(stroke: &str, width: f64) -> Group {
    Group::new().add(
        Line::new()
            .set("x1", 2)
            .set("y1", 0)
            .set("x2", 22)
            .set("y2", 0)
            .set("stroke", stroke)
            .set("stroke-width", width),
    )
}

/// The world legend entries (rooms, walls, doors, objects) of the marks `world` uses.
fn world_legend(world: &World, legend: &mut Legend, pale: f64) {
    legend.add(
        legend_rect(&lighten(PALETTE[0], pale), "none"),
        "room (one colour each)",
    );
    legend.add(legend_rect("#222", "none"), "wall");
    if world.env.doors.iter().any(|d| d.open) {
        legend.add(legend_line("#2b8cbe", 4.0), "open door");
    }
    if world.env.doors.iter().any(|d| !d.open) {
        legend.add(legend_line("#e6550d", 4.0), "closed door");
    }
    for (role, s) in [
        (ObjectRole::Landmark, "furniture (labelled with its class)"),
        (ObjectRole::Target, "object a search may target"),
        (ObjectRole::Distractor, "distractor object"),
    ] {
        if world.env.objects.iter().any(|o| o.role == role) {
            let (fill, stroke) = object_colours(role);
            legend.add(legend_rect(fill, stroke), s);
        }
    }
}

/// The scale bar's length, metres: 2 m on maps at least 12 m wide, 1 m on smaller ones.
fn scale_bar_m(width_m: f64) -> f64 {
    if width_m >= 12.0 {
        2.0
    } else {
        1.0
    }
}

/// The scale bar ([`scale_bar_m`]) from `(x, y)`.
fn scale_bar(f: &Frame, width_m: f64, x: f64, y: f64) -> Group {
    let m = scale_bar_m(width_m);
    let len = m * f.scale;
    let tick = |x: f64| {
        Line::new()
            .set("x1", x)
            .set("y1", -5)
            .set("x2", x)
            .set("y2", 5)
            .set("stroke", "black")
            .set("stroke-width", 2)
    };
    Group::new()
        .set("id", "scale-bar")
        .set("transform", format!("translate({x} {y})"))
        .add(
            Line::new()
                .set("x1", 0)
                .set("y1", 0)
                .set("x2", len)
                .set("y2", 0)
                .set("stroke", "black")
                .set("stroke-width", 3),
        )
        .add(tick(0.0))
        .add(tick(len))
        .add(text(format!("{m} m"), len + 6.0, 4.0, 12.0))
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

/// How a search ended, scored against the truth.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchOutcome {
    /// Reported within [`crate::score::SUCCESS_RADIUS`] of a true object of the class.
    Found,
    /// Nothing reported.
    NotFound,
    /// Reported, but farther than [`crate::score::SUCCESS_RADIUS`] from every true object of
    /// the class.
    WrongReport,
}

impl SearchOutcome {
    /// The outcome of reporting `reported` (or nothing) when searching `world` for `goal`.
    pub fn of(world: &World, goal: &str, reported: Option<[f64; 3]>) -> Self {
        match reported {
            None => Self::NotFound,
            Some(r) => {
                if world.objects_of_class(goal).any(|o| {
                    (o.pose.x - r[0]).hypot(o.pose.y - r[1]) <= crate::score::SUCCESS_RADIUS
                }) {
                    Self::Found
                } else {
                    Self::WrongReport
                }
            }
        }
    }
}

impl fmt::Display for SearchOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Found => "found",
            Self::NotFound => "not found",
            Self::WrongReport => "wrong report",
        })
    }
}

/// What kind of camera look a [`Look`] was.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LookKind {
    /// A view cone processed in a view-cone POMDP session (`PROCESSVIEWCONE`).
    Cone,
    /// A closer look verifying a sighting (`VERIFY`).
    Verify,
}

/// One look of the camera, as a search picture draws it: a wedge from the standpoint.
#[derive(Debug, Clone, PartialEq)]
pub struct Look {
    /// Where the robot stood, metres.
    pub at: [f64; 2],
    /// World direction of the camera's optical axis, radians (0 along +x, counter-clockwise).
    pub direction: f64,
    /// Horizontal field of view of the look (the camera's divided by the zoom), radians.
    pub hfov: f64,
    /// Whether the look detected what it looked for.
    pub detected: bool,
    /// A view cone or a verifying look.
    pub kind: LookKind,
    /// What the trace said (the wedge's tooltip).
    pub label: String,
}

/// The agent's most likely category of one true room.
#[derive(Debug, Clone, PartialEq)]
pub struct RoomBelief {
    /// The true room (index into `env.rooms`).
    pub room: usize,
    /// The agent's most likely category.
    pub category: String,
    /// Its probability.
    pub probability: f64,
}

/// What a search picture shows over the world (the CLI builds it from the plan trace).
#[derive(Debug, Clone, Default)]
pub struct SearchPicture {
    /// The object class searched for.
    pub goal: String,
    /// The simulated robot's seed, for the title.
    pub seed: Option<u64>,
    /// Distance driven, metres.
    pub path_length: f64,
    /// Every position the robot passed, in order.
    pub trail: Vec<[f64; 2]>,
    /// Where the robot started, `[x, y, yaw]`.
    pub start: Option<[f64; 3]>,
    /// Where the robot ended, `[x, y, yaw]`.
    pub end: Option<[f64; 3]>,
    /// The position the agent reported, `[x, y, z]`.
    pub reported: Option<[f64; 3]>,
    /// Every camera look, in order.
    pub looks: Vec<Look>,
    /// Looks of the coverage after the planner gave up (not drawn: the trail shows where the
    /// robot went; the subtitle counts them).
    pub coverage_looks: usize,
    /// Sightings a closer look did not confirm, `[x, y]`.
    pub false_alarms: Vec<[f64; 2]>,
    /// The agent's most likely category of the true rooms it looked around in (the last
    /// belief of a room counts).
    pub room_beliefs: Vec<RoomBelief>,
}

/// The SVG path of a wedge from `(x, y)` (pixels) towards world direction `dir` (radians),
/// `hfov` wide and `len` pixels long.
fn wedge_data(x: f64, y: f64, dir: f64, hfov: f64, len: f64) -> Data {
    let half = (hfov / 2.0).clamp(0.01, 3.1);
    let (a, b) = (dir - half, dir + half);
    // Screen y points down: world angle θ is the screen vector (cos θ, −sin θ); going from
    // `a` to `b` counter-clockwise in the world is counter-clockwise on the screen (sweep 0).
    Data::new()
        .move_to((x, y))
        .line_to((x + len * a.cos(), y - len * a.sin()))
        .elliptical_arc_to((
            len,
            len,
            0,
            i32::from(hfov > std::f64::consts::PI),
            0,
            x + len * b.cos(),
            y - len * b.sin(),
        ))
        .close()
}

/// (colour, fill opacity, stroke opacity, stroke width, dash) of a look's wedge; `thin` (≤ 1)
/// thins the misses out where hundreds of them overlap.
fn look_style(
    kind: LookKind,
    detected: bool,
    thin: f64,
) -> (&'static str, f64, f64, f64, &'static str) {
    let colour = if detected { CONE_HIT } else { CONE_MISS };
    match (kind, detected) {
        (LookKind::Cone, false) => (colour, 0.07 * thin, 0.5 * thin.sqrt(), 0.7, "none"),
        (LookKind::Cone, true) => (colour, 0.28, 0.9, 1.6, "none"),
        (LookKind::Verify, false) => (colour, 0.06 * thin, 0.6 * thin.sqrt(), 1.2, "4,2"),
        (LookKind::Verify, true) => (colour, 0.18, 0.9, 1.6, "4,2"),
    }
}

fn wedge(d: Data, kind: LookKind, detected: bool, thin: f64) -> Path {
    let (colour, fill_opacity, stroke_opacity, width, dash) = look_style(kind, detected, thin);
    Path::new()
        .set("d", d)
        .set("fill", colour)
        .set("fill-opacity", fill_opacity)
        .set("stroke", colour)
        .set("stroke-opacity", stroke_opacity)
        .set("stroke-width", width)
        .set("stroke-dasharray", dash)
}

/// A five-pointed star of outer radius `r` at `(x, y)`.
fn star_data(x: f64, y: f64, r: f64) -> Data {
    let mut d = Data::new();
    for k in 0..10 {
        let a = std::f64::consts::FRAC_PI_2 + k as f64 * std::f64::consts::PI / 5.0;
        let rr = if k % 2 == 0 { r } else { 0.45 * r };
        let p = (x + rr * a.cos(), y - rr * a.sin());
        d = if k == 0 { d.move_to(p) } else { d.line_to(p) };
    }
    d.close()
}

/// An × of half-size `r` at `(x, y)`.
fn cross_data(x: f64, y: f64, r: f64) -> Data {
    Data::new()
        .move_to((x - r, y - r))
        .line_to((x + r, y + r))
        .move_to((x - r, y + r))
        .line_to((x + r, y - r))
}

/// A group holding, when the heading `yaw` is known, a short line from `(x, y)` along it.
fn heading_mark(x: f64, y: f64, yaw: Option<f64>, colour: &str) -> Group {
    let g = Group::new();
    match yaw {
        Some(yaw) => g.add(
            Line::new()
                .set("x1", x)
                .set("y1", y)
                .set("x2", x + 14.0 * yaw.cos())
                .set("y2", y - 14.0 * yaw.sin())
                .set("stroke", colour)
                .set("stroke-width", 3),
        ),
        None => g,
    }
}

fn start_symbol(x: f64, y: f64, yaw: Option<f64>) -> Group {
    let g = heading_mark(x, y, yaw, START);
    g.add(
        Circle::new()
            .set("cx", x)
            .set("cy", y)
            .set("r", 8)
            .set("fill", START)
            .set("stroke", "white")
            .set("stroke-width", 1.5),
    )
    .add(
        text("S", x - 3.6, y + 4.0, 10.5)
            .set("fill", "white")
            .set("font-weight", "bold"),
    )
}

fn end_symbol(x: f64, y: f64, yaw: Option<f64>) -> Group {
    let g = heading_mark(x, y, yaw, END);
    g.add(
        Rectangle::new()
            .set("x", x - 7.5)
            .set("y", y - 7.5)
            .set("width", 15)
            .set("height", 15)
            .set("fill", END)
            .set("stroke", "white")
            .set("stroke-width", 1.5),
    )
    .add(
        text("E", x - 3.6, y + 4.0, 10.5)
            .set("fill", "white")
            .set("font-weight", "bold"),
    )
}

fn report_symbol(x: f64, y: f64, ok: bool) -> Group {
    let mut g = Group::new().add(
        Path::new()
            .set("d", star_data(x, y, 11.0))
            .set("fill", if ok { REPORT_OK } else { REPORT_WRONG })
            .set("stroke", "black")
            .set("stroke-width", 1.2),
    );
    if !ok {
        g = g.add(
            Path::new()
                .set("d", cross_data(x, y, 9.0))
                .set("stroke", "black")
                .set("stroke-width", 2.5),
        );
    }
    g
}

fn false_alarm_symbol(x: f64, y: f64) -> Group {
    Group::new()
        .add(
            Circle::new()
                .set("cx", x)
                .set("cy", y)
                .set("r", 8)
                .set("fill", "white")
                .set("fill-opacity", 0.8)
                .set("stroke", FALSE_ALARM)
                .set("stroke-width", 1.2),
        )
        .add(
            Path::new()
                .set("d", cross_data(x, y, 5.0))
                .set("stroke", FALSE_ALARM)
                .set("stroke-width", 2.5),
        )
}

fn goal_ring(x: f64, y: f64) -> Circle {
    Circle::new()
        .set("cx", x)
        .set("cy", y)
        .set("r", 9)
        .set("fill", "none")
        .set("stroke", "#0b6e0b")
        .set("stroke-width", 2.5)
}

fn ramp(t: f64) -> String {
    let c = |i: usize| (TRAIL_OLD[i] + (TRAIL_NEW[i] - TRAIL_OLD[i]) * t).round() as u8;
    format!("#{:02x}{:02x}{:02x}", c(0), c(1), c(2))
}

/// The distance between numbered trail markers: the smallest of 2, 5, 10, 20, 50, 100 … m
/// that gives at most 10 markers.
fn marker_step(path: f64) -> f64 {
    let mut step = 2.0;
    let mut k = 0;
    while path / step > 10.0 {
        k += 1;
        step = [2.0, 5.0, 10.0][k % 3] * 10f64.powi((k / 3) as i32);
    }
    step
}

/// The trail: a white casing and the full line (`robot trail`), then [`TRAIL_PIECES`] pieces
/// coloured from pale (old) to dark (new), then numbered markers every [`marker_step`] metres.
fn trail(f: &Frame, pts: &[[f64; 2]], placer: &mut Placer) -> Group {
    let mut g = Group::new().set("id", "trail");
    if pts.len() < 2 {
        return g;
    }
    let points: Vec<String> = pts
        .iter()
        .map(|p| format!("{:.1},{:.1}", f.x(p[0]), f.y(p[1])))
        .collect();
    g = g.add(
        Polyline::new()
            .set("points", points.join(" "))
            .set("fill", "none")
            .set("stroke", "white")
            .set("stroke-width", 5.5)
            .set("stroke-opacity", 0.85)
            .set("stroke-linejoin", "round")
            .add(Title::new("robot trail")),
    );
    // Cumulative length along the trail.
    let mut cum = vec![0.0];
    for w in pts.windows(2) {
        let l = cum[cum.len() - 1] + (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        cum.push(l);
    }
    let total = cum[cum.len() - 1].max(1e-9);
    let pieces = TRAIL_PIECES.min(pts.len() - 1);
    let mut pieces_g = Group::new().set("class", "trail-pieces");
    let mut i = 0;
    for k in 0..pieces {
        let until = total * (k + 1) as f64 / pieces as f64;
        let from = i;
        while i + 1 < pts.len() && (cum[i + 1] <= until || k + 1 == pieces) {
            i += 1;
        }
        if i == from {
            continue;
        }
        let mut d = Data::new().move_to(f.px(pts[from]));
        for p in &pts[from + 1..=i] {
            d = d.line_to(f.px(*p));
        }
        let t = (k as f64 + 0.5) / pieces as f64;
        pieces_g = pieces_g.add(
            Path::new()
                .set("d", d)
                .set("fill", "none")
                .set("stroke", ramp(t))
                .set("stroke-width", 2.0 + 1.5 * t)
                .set("stroke-linejoin", "round")
                .set("stroke-linecap", "round"),
        );
    }
    g = g.add(pieces_g);
    let step = marker_step(total);
    let mut markers = Group::new().set("class", "trail-markers");
    let mut next = step;
    for (k, p) in pts.iter().enumerate() {
        if cum[k] + 1e-9 < next {
            continue;
        }
        let s = format!("{}", next as i64);
        next += step;
        let (x, y) = f.px(*p);
        let r = (text_width(&s, 8.0) / 2.0 + 2.5).max(6.5);
        let b = [x - r, y - r, x + r, y + r];
        if placer.overlap(b) > 0.0 {
            continue;
        }
        placer.reserve(b);
        markers = markers.add(
            Group::new()
                .add(
                    Circle::new()
                        .set("cx", x)
                        .set("cy", y)
                        .set("r", r)
                        .set("fill", "white")
                        .set("stroke", ramp(cum[k] / total))
                        .set("stroke-width", 1.5),
                )
                .add(
                    text(s.clone(), x - text_width(&s, 8.0) / 2.0 + 0.8, y + 3.0, 8.0)
                        .set("fill", "#08306b"),
                )
                .add(Title::new(format!("{s} m driven"))),
        );
    }
    g.add(markers)
}

/// A search run over the fully known world, readable on its own: a title (environment, goal,
/// seed, outcome, path length), the rooms (pale, labelled with their true name and category and,
/// when known, the agent's most likely category), furniture labelled with its class, every
/// camera look as a wedge ([`CONE_LENGTH_M`] long, the look's field of view wide; lightly
/// filled, orange where the look detected its class, verifying looks dashed), the trail by time
/// (see the module docs), the start (`S`), the end (`E`), the reported position (a star; red
/// and crossed out when wrong, with its 1 m success ring), the true objects of the goal class
/// (green rings), false alarms (×), a legend of every mark used and a scale bar.
pub fn render_search(world: &World, pic: &SearchPicture) -> String {
    let g = &world.truth;
    let width_m = g.width() as f64 * g.resolution();
    // Small floors are drawn larger, so that labels fit; large ones smaller.
    let scale = (900.0 / width_m).clamp(28.0, 70.0);
    let f = Frame::new(g, scale);
    let (w, h) = map_size(g, &f);
    let goal = pic.goal.as_str();
    let outcome = SearchOutcome::of(world, goal, pic.reported);
    let pale = 0.6;
    let mut placer = Placer::new(w, h);
    let mut legend = Legend::default();
    world_legend(world, &mut legend, pale);

    // Marks first in the placer, so that labels avoid them.
    let reserve = |placer: &mut Placer, p: [f64; 2], r: f64| {
        let (x, y) = f.px(p);
        placer.reserve([x - r, y - r, x + r, y + r]);
    };
    let goal_objects: Vec<[f64; 2]> = world
        .objects_of_class(goal)
        .map(|o| [o.pose.x, o.pose.y])
        .collect();
    for p in pic.start.iter().chain(&pic.end) {
        reserve(&mut placer, [p[0], p[1]], 9.0);
    }
    if let Some(r) = pic.reported {
        reserve(&mut placer, [r[0], r[1]], 11.0);
    }
    for p in &pic.false_alarms {
        reserve(&mut placer, *p, 8.0);
    }

    // View cones, in the order taken (later ones on top).
    let len = CONE_LENGTH_M * f.scale;
    // Misses fade where there are many, so that hundreds of them do not hide the map.
    let misses = pic.looks.iter().filter(|l| !l.detected).count();
    let thin = (60.0 / misses.max(1) as f64).min(1.0);
    let mut cones = Group::new()
        .set("id", "view-cones")
        .set("clip-path", "url(#map-clip)");
    for l in &pic.looks {
        let (x, y) = f.px(l.at);
        let class = match (l.kind, l.detected) {
            (LookKind::Cone, false) => "view-cone miss",
            (LookKind::Cone, true) => "view-cone hit",
            (LookKind::Verify, false) => "verify-look miss",
            (LookKind::Verify, true) => "verify-look hit",
        };
        cones = cones.add(
            wedge(
                wedge_data(x, y, l.direction, l.hfov, len),
                l.kind,
                l.detected,
                thin,
            )
            .set("class", class)
            .add(Title::new(l.label.clone())),
        );
    }
    let legend_wedge = |kind, detected| {
        Group::new().add(wedge(
            wedge_data(2.0, 0.0, 0.0, 0.75, 22.0),
            kind,
            detected,
            1.0,
        ))
    };
    let count = |kind: LookKind, detected: bool| {
        pic.looks
            .iter()
            .filter(|l| l.kind == kind && l.detected == detected)
            .count()
    };
    for (kind, detected, s) in [
        (LookKind::Cone, false, "view cone processed, nothing seen"),
        (
            LookKind::Cone,
            true,
            format!("view cone processed, {goal} detected").as_str(),
        ),
        (LookKind::Verify, false, "verifying look, not confirmed"),
        (LookKind::Verify, true, "verifying look, detected"),
    ] {
        let n = count(kind, detected);
        if n > 0 {
            legend.add(legend_wedge(kind, detected), format!("{s} ({n})"));
        }
    }

    let trail_g = trail(&f, &pic.trail, &mut placer);
    if pic.trail.len() >= 2 {
        legend.add(
            Group::new()
                .add(
                    Line::new()
                        .set("x1", 2)
                        .set("y1", 0)
                        .set("x2", 12)
                        .set("y2", 0)
                        .set("stroke", ramp(0.1))
                        .set("stroke-width", 2.5),
                )
                .add(
                    Line::new()
                        .set("x1", 12)
                        .set("y1", 0)
                        .set("x2", 22)
                        .set("y2", 0)
                        .set("stroke", ramp(0.9))
                        .set("stroke-width", 3.5),
                ),
            "trail, pale (early) to dark (late)",
        );
        let s = format!("{}", marker_step(pic.path_length.max(1e-9)) as i64);
        legend.add(
            Group::new()
                .add(
                    Circle::new()
                        .set("cx", 12)
                        .set("cy", 0)
                        .set("r", 6.5)
                        .set("fill", "white")
                        .set("stroke", ramp(0.5))
                        .set("stroke-width", 1.5),
                )
                .add(text("n", 9.5, 3.0, 8.0).set("fill", "#08306b")),
            format!("metres driven (every {s} m)"),
        );
    }

    let labels = label_rooms_and_objects(world, &f, &mut placer, &pic.room_beliefs);

    let mut marks = Group::new().set("id", "marks");
    for p in &goal_objects {
        let (x, y) = f.px(*p);
        marks = marks.add(
            goal_ring(x, y)
                .set("class", "goal-object")
                .add(Title::new(format!("a true {goal}"))),
        );
    }
    if !goal_objects.is_empty() {
        legend.add(
            Group::new().add(goal_ring(12.0, 0.0).set("r", 6)),
            format!("true {goal} (every one)"),
        );
    }
    for p in &pic.false_alarms {
        let (x, y) = f.px(*p);
        marks = marks.add(
            false_alarm_symbol(x, y)
                .set("class", "false-alarm")
                .add(Title::new(format!(
                    "false alarm: {goal} sighted at ({:.2}, {:.2}), not confirmed",
                    p[0], p[1]
                ))),
        );
    }
    if !pic.false_alarms.is_empty() {
        legend.add(
            false_alarm_symbol(12.0, 0.0),
            format!(
                "false alarm: sighting not confirmed ({})",
                pic.false_alarms.len()
            ),
        );
    }
    if let Some(s) = pic.start {
        let (x, y) = f.px([s[0], s[1]]);
        marks = marks.add(
            start_symbol(x, y, Some(s[2]))
                .set("class", "start")
                .add(Title::new(format!("start ({:.2}, {:.2})", s[0], s[1]))),
        );
        legend.add(start_symbol(12.0, 0.0, None), "start (line: heading)");
    }
    if let Some(e) = pic.end {
        let (x, y) = f.px([e[0], e[1]]);
        marks = marks.add(
            end_symbol(x, y, Some(e[2]))
                .set("class", "end")
                .add(Title::new(format!("end ({:.2}, {:.2})", e[0], e[1]))),
        );
        legend.add(end_symbol(12.0, 0.0, None), "end pose (line: heading)");
    }
    if let Some(r) = pic.reported {
        let ok = outcome == SearchOutcome::Found;
        let (x, y) = f.px([r[0], r[1]]);
        let nearest = goal_objects
            .iter()
            .map(|o| (o[0] - r[0]).hypot(o[1] - r[1]))
            .min_by(f64::total_cmp);
        let ring = crate::score::SUCCESS_RADIUS * f.scale;
        marks = marks
            .add(
                Circle::new()
                    .set("class", "success-ring")
                    .set("cx", x)
                    .set("cy", y)
                    .set("r", ring)
                    .set("fill", "none")
                    .set("stroke", if ok { "#2ca02c" } else { REPORT_WRONG })
                    .set("stroke-width", 1.5)
                    .set("stroke-dasharray", "5,3"),
            )
            .add(
                report_symbol(x, y, ok)
                    .set("class", if ok { "report" } else { "report wrong" })
                    .add(Title::new(format!(
                        "reported {goal} at ({:.2}, {:.2}, {:.2}){}",
                        r[0],
                        r[1],
                        r[2],
                        match (ok, nearest) {
                            (true, _) => String::new(),
                            (false, Some(d)) => {
                                format!(": WRONG REPORT, the nearest true {goal} is {d:.1} m away")
                            }
                            (false, None) => format!(": WRONG REPORT, there is no {goal}"),
                        }
                    ))),
            );
        if ok {
            legend.add(
                report_symbol(12.0, 0.0, true),
                "reported position (correct)",
            );
        } else {
            legend.add(
                report_symbol(12.0, 0.0, false),
                format!("wrong report: > 1 m from every {goal}"),
            );
        }
        legend.add(
            Group::new().add(
                Circle::new()
                    .set("cx", 12)
                    .set("cy", 0)
                    .set("r", 7)
                    .set("fill", "none")
                    .set("stroke", if ok { "#2ca02c" } else { REPORT_WRONG })
                    .set("stroke-width", 1.5)
                    .set("stroke-dasharray", "3,2"),
            ),
            "1 m around the report",
        );
    }
    if !pic.room_beliefs.is_empty() {
        legend.add(
            Group::new().add(text("Aa", 3.0, 4.0, 11.0).set("font-weight", "bold")),
            "room: true name (category)",
        );
        legend.add(
            Group::new().add(text("Aa", 3.0, 4.0, 10.0)),
            "agent: its likeliest category, p",
        );
    } else {
        legend.add(
            Group::new().add(text("Aa", 3.0, 4.0, 11.0).set("font-weight", "bold")),
            "room: true name (category)",
        );
    }

    let map = Group::new()
        .add(rooms(world, &f, pale))
        .add(doors(world, &f))
        .add(objects(world, &f))
        .add(cones)
        .add(trail_g)
        .add(labels)
        .add(marks);

    // Under the map: the scale bar and the trail's time ramp.
    let mut footer = Group::new().add(scale_bar(&f, width_m, 10.0, 24.0));
    if pic.trail.len() >= 2 {
        let x0 = 10.0 + scale_bar_m(width_m) * f.scale + 50.0;
        let mut ramp_g =
            Group::new()
                .set("id", "trail-ramp")
                .add(text("trail: start", x0, 28.0, 11.0));
        let rx = x0 + text_width("trail: start", 11.0) + 4.0;
        for k in 0..10 {
            ramp_g = ramp_g.add(
                Rectangle::new()
                    .set("x", rx + k as f64 * 12.0)
                    .set("y", 17)
                    .set("width", 12)
                    .set("height", 14)
                    .set("fill", ramp((k as f64 + 0.5) / 10.0)),
            );
        }
        ramp_g = ramp_g.add(text(
            format!("end ({:.1} m)", pic.path_length),
            rx + 124.0,
            28.0,
            11.0,
        ));
        footer = footer.add(ramp_g);
    }

    let seed = pic.seed.map_or(String::new(), |s| format!(", seed {s}"));
    let title = format!(
        "{} — search for {goal}{seed}: {outcome}, path {:.1} m",
        world.env.name, pic.path_length
    );
    let cones_n = pic
        .looks
        .iter()
        .filter(|l| l.kind == LookKind::Cone)
        .count();
    let hits = pic
        .looks
        .iter()
        .filter(|l| l.kind == LookKind::Cone && l.detected)
        .count();
    let verify_n = pic.looks.len() - cones_n;
    let mut subtitle = format!(
        "{cones_n} view cones processed ({hits} with a detection), {verify_n} verifying looks, {} false alarms",
        pic.false_alarms.len()
    );
    if pic.coverage_looks > 0 {
        subtitle.push_str(&format!(
            ", {} coverage looks (not drawn)",
            pic.coverage_looks
        ));
    }
    if let Some(r) = pic.reported {
        if let Some(d) = goal_objects
            .iter()
            .map(|o| (o[0] - r[0]).hypot(o[1] - r[1]))
            .min_by(f64::total_cmp)
        {
            subtitle.push_str(&format!("; report {d:.2} m from the nearest true {goal}"));
        }
    }
    compose(w, h, &title, &subtitle, map, legend, footer).to_string()
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
