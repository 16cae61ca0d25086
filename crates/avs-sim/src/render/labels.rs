//! Labels placed greedily without overlap: rooms first, then furniture, each at the first
//! candidate position that overlaps no label or mark already placed and stays in the picture.

use super::*;

/// Greedy placement of label boxes: each at the first candidate that overlaps nothing placed
/// before, else at the candidate that overlaps least; always inside `bounds`.
pub(super) struct Placer {
    boxes: Vec<[f64; 4]>,
    bounds: [f64; 4],
}

impl Placer {
    pub(super) fn new(w: f64, h: f64) -> Self {
        Self {
            boxes: Vec::new(),
            bounds: [0.0, 0.0, w, h],
        }
    }

    /// Reserve a box (`[x0, y0, x1, y1]`) that labels must avoid.
    pub(super) fn reserve(&mut self, b: [f64; 4]) {
        self.boxes.push(b);
    }

    pub(super) fn clamp(&self, x: f64, y: f64, w: f64, h: f64) -> [f64; 4] {
        let [bx0, by0, bx1, by1] = self.bounds;
        let x = x.min(bx1 - w).max(bx0);
        let y = y.min(by1 - h).max(by0);
        [x, y, x + w, y + h]
    }

    pub(super) fn overlap(&self, b: [f64; 4]) -> f64 {
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
    pub(super) fn place(
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
pub(super) struct Label {
    lines: Vec<(String, f64, &'static str)>,
    class: &'static str,
    fill: &'static str,
}

impl Label {
    pub(super) fn size(&self) -> (f64, f64) {
        let w = self
            .lines
            .iter()
            .map(|(s, size, _)| text_width(s, *size))
            .fold(0.0, f64::max);
        let h: f64 = self.lines.iter().map(|(_, size, _)| size * 1.2).sum();
        (w + 6.0, h + 4.0)
    }

    pub(super) fn draw(&self, b: [f64; 4]) -> Group {
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
pub(super) fn around_centre(x: f64, y: f64, w: f64, h: f64) -> Vec<(f64, f64)> {
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
pub(super) fn beside(x: f64, y: f64, (ex, ey): (f64, f64), w: f64, h: f64) -> Vec<(f64, f64)> {
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
pub(super) fn room_anchor(world: &World, room: usize) -> Option<[f64; 2]> {
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
pub(super) fn outside_room(world: &World, f: &Frame, room: Option<usize>, b: [f64; 4]) -> f64 {
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
pub(super) fn label_rooms_and_objects(
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
