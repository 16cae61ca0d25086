//! What the live view shows of a session ([`Live`], kept current from the trace events and
//! the robot's calls) and its picture ([`render_svg`]): the robot's map, the rooms coloured
//! by their likeliest category (hovering one shows its distribution), placeholders, doors, the
//! robot and its trail, the current plan, view cones as they are processed, candidates and
//! verification decisions.

use avs_agent::{Beliefs, Event};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_robot::Pose2D;
use serde::Serialize;
use svg::node::element::{Circle, Group, Line, Path, Polygon, Polyline, Rectangle, Text, Title};
use svg::Document;

/// Cones kept for the picture (the newest).
const MAX_CONES: usize = 400;
/// Trail points kept (older ones are thinned, never the newest).
const MAX_TRAIL: usize = 20_000;

/// A look the agent took.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConeMark {
    /// Where the robot stood `[x, y]`.
    pub at: [f64; 2],
    /// The camera's direction in the world, radians.
    pub direction: f64,
    /// The horizontal field of view at its zoom, radians.
    pub hfov: f64,
    /// Whether the target class was detected.
    pub detected: bool,
    /// A verification look (pointed at a candidate).
    pub verify: bool,
}

/// A candidate detection and what verification decided.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateMark {
    /// Its class.
    pub class: String,
    /// Where `[x, y]`.
    pub at: [f64; 2],
    /// `None` while undecided; then accepted or not.
    pub accepted: Option<bool>,
}

/// The live state of a session's robot and search.
#[derive(Debug, Clone)]
pub struct Live {
    /// The robot's pose as last reported.
    pub pose: Pose2D,
    /// Metres driven since the session began.
    pub odometry: f64,
    /// Where the robot has been.
    pub trail: Vec<[f64; 2]>,
    /// The robot's map as last reported.
    pub grid: Option<OccupancyGrid>,
    /// The doors the robot reported with it.
    pub doors: Vec<avs_robot::DoorSighting>,
    /// The current plan's steps.
    pub plan: Vec<String>,
    /// The step under way.
    pub step: Option<String>,
    /// Looks, newest last.
    pub cones: Vec<ConeMark>,
    /// Candidates, oldest first.
    pub candidates: Vec<CandidateMark>,
    /// Objects reported `[x, y, z]` with their names.
    pub found: Vec<([f64; 3], String)>,
    hfov: f64,
}

/// The parts of [`Live`] a snapshot keeps for tools (not needed to restore).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LiveSummary {
    /// The robot's pose.
    pub pose: Pose2D,
    /// Metres driven.
    pub odometry: f64,
    /// Where the robot has been.
    pub trail: Vec<[f64; 2]>,
    /// The robot's map.
    pub map: Option<crate::grid::RosGrid>,
    /// Objects reported.
    pub found: Vec<serde_json::Value>,
}

impl Live {
    /// A robot at `start` whose camera has horizontal field of view `hfov` (radians).
    pub fn new(start: Pose2D, hfov: f64) -> Self {
        Self {
            pose: start,
            odometry: 0.0,
            trail: vec![[start.x, start.y]],
            grid: None,
            doors: Vec::new(),
            plan: Vec::new(),
            step: None,
            cones: Vec::new(),
            candidates: Vec::new(),
            found: Vec::new(),
            hfov,
        }
    }

    /// The robot reported `pose` and `odometry`.
    pub fn robot_at(&mut self, pose: Pose2D, odometry: f64) {
        self.pose = pose;
        self.odometry = odometry;
        let p = [pose.x, pose.y];
        if self.trail.last() != Some(&p) {
            if self.trail.len() >= MAX_TRAIL {
                // Keep every other old point: the shape stays, the memory is bounded.
                let half: Vec<[f64; 2]> = self.trail.iter().step_by(2).copied().collect();
                self.trail = half;
            }
            self.trail.push(p);
        }
    }

    /// Take in a trace event.
    pub fn event(&mut self, e: &Event) {
        match e {
            Event::Started { .. } => {
                self.plan.clear();
                self.step = None;
            }
            Event::PlanMade { steps, .. } => {
                self.plan = steps.clone();
                self.step = None;
            }
            Event::ActionStarted { action } => self.step = Some(action.clone()),
            Event::DtAction {
                detected,
                view: Some(v),
                target,
                ..
            } => {
                let direction = match target {
                    Some([tx, ty]) => (ty - v.y).atan2(tx - v.x),
                    None => v.pan_deg.to_radians(),
                };
                self.cones.push(ConeMark {
                    at: [v.x, v.y],
                    direction,
                    hfov: self.hfov / v.zoom.max(1.0),
                    detected: detected.unwrap_or(false),
                    verify: target.is_some(),
                });
                if self.cones.len() > MAX_CONES {
                    self.cones.remove(0);
                }
            }
            Event::CandidateCreated { class, at, .. } => self.candidates.push(CandidateMark {
                class: class.clone(),
                at: *at,
                accepted: None,
            }),
            Event::VerificationDecision {
                class,
                at,
                accepted,
                ..
            } => {
                match self
                    .candidates
                    .iter_mut()
                    .rev()
                    .find(|c| c.accepted.is_none() && &c.class == class && c.at == *at)
                {
                    Some(c) => c.accepted = Some(*accepted),
                    None => self.candidates.push(CandidateMark {
                        class: class.clone(),
                        at: *at,
                        accepted: Some(*accepted),
                    }),
                }
            }
            Event::GoalReached { object, pose } => {
                self.found.push((*pose, object.clone()));
                self.step = None;
            }
            Event::GaveUp { .. } => self.step = None,
            _ => {}
        }
    }

    /// What a snapshot keeps of it.
    pub fn summary(&self) -> LiveSummary {
        LiveSummary {
            pose: self.pose,
            odometry: self.odometry,
            trail: self.trail.clone(),
            map: self.grid.as_ref().map(crate::grid::RosGrid::from_grid),
            found: self
                .found
                .iter()
                .map(|(p, n)| serde_json::json!({ "name": n, "pose": p }))
                .collect(),
        }
    }
}

/// Fill colours of room categories, by the category's index in the knowledge file.
const PALETTE: [&str; 8] = [
    "#4e79a7", "#f28e2b", "#59a14f", "#e15759", "#b07aa1", "#edc948", "#76b7b2", "#ff9da7",
];

/// Pixels per metre.
const SCALE: f64 = 40.0;

/// A coordinate or length rounded to a tenth of a pixel (the picture's precision).
fn r1(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

/// `points` as an SVG `points` attribute.
fn points(ps: &[(f64, f64)]) -> String {
    ps.iter()
        .map(|(x, y)| format!("{},{}", r1(*x), r1(*y)))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The picture's frame: world metres to pixels, y up in the world and down in the picture.
struct Frame {
    x0: f64,
    y1: f64,
}

impl Frame {
    fn px(&self, x: f64) -> f64 {
        r1((x - self.x0) * SCALE)
    }

    fn py(&self, y: f64) -> f64 {
        r1((self.y1 - y) * SCALE)
    }

    fn at(&self, p: [f64; 2]) -> (f64, f64) {
        (self.px(p[0]), self.py(p[1]))
    }
}

/// The picture of `live` with `beliefs` (rooms, placeholders, doors) as an SVG document, with
/// the current plan listed under the map when `plan`.
pub fn render_svg(live: &Live, beliefs: Option<&Beliefs>, plan: bool) -> String {
    // The frame: the map, else everything drawn, with a margin.
    let mut xs: Vec<f64> = live.trail.iter().map(|p| p[0]).collect();
    let mut ys: Vec<f64> = live.trail.iter().map(|p| p[1]).collect();
    if let Some(g) = &live.grid {
        let [ox, oy] = g.origin();
        let r = g.resolution();
        xs.extend([ox, ox + g.width() as f64 * r]);
        ys.extend([oy, oy + g.height() as f64 * r]);
    }
    if let Some(b) = beliefs {
        for p in b.rooms.iter().flat_map(|r| &r.places) {
            xs.push(p[0]);
            ys.push(p[1]);
        }
    }
    let lo = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min) - 0.5;
    let hi = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max) + 0.5;
    let (x0, x1, y0, y1) = (lo(&xs), hi(&xs), lo(&ys), hi(&ys));
    let f = Frame { x0, y1 };
    // The plan is listed under the drawing, one line per step.
    let plan_h = if live.plan.is_empty() || !plan {
        0.0
    } else {
        10.0 + 13.0 * live.plan.len() as f64
    };
    let (w, map_h) = (r1((x1 - x0) * SCALE), r1((y1 - y0) * SCALE));
    let h = map_h + plan_h;
    let mut doc = Document::new()
        .set("viewBox", (0, 0, w, h))
        .set("width", w)
        .set("height", h)
        .set("font-family", "sans-serif")
        .set("font-size", 11)
        .add(
            Rectangle::new()
                .set("width", "100%")
                .set("height", "100%")
                .set("fill", "#d9d9d9"),
        );
    // The map: runs of free and occupied cells along each row.
    if let Some(g) = &live.grid {
        let r = g.resolution();
        let [ox, oy] = g.origin();
        for (cell, fill) in [(Cell::Free, "#ffffff"), (Cell::Occupied, "#222222")] {
            let mut layer = Group::new().set("fill", fill);
            for row in 0..g.height() {
                let mut col = 0;
                while col < g.width() {
                    if g.get(col, row) != cell {
                        col += 1;
                        continue;
                    }
                    let start = col;
                    while col < g.width() && g.get(col, row) == cell {
                        col += 1;
                    }
                    let (x, y) = (ox + start as f64 * r, oy + (row + 1) as f64 * r);
                    layer = layer.add(
                        Rectangle::new()
                            .set("x", f.px(x))
                            .set("y", f.py(y))
                            .set("width", r1((col - start) as f64 * r * SCALE + 0.3))
                            .set("height", r1(r * SCALE + 0.3)),
                    );
                }
            }
            doc = doc.add(layer);
        }
    }
    if let Some(b) = beliefs {
        doc = rooms(doc, b, &f);
    }
    // The trail.
    if live.trail.len() > 1 {
        let ps: Vec<(f64, f64)> = live.trail.iter().map(|p| f.at(*p)).collect();
        doc = doc.add(
            Polyline::new()
                .set("points", points(&ps))
                .set("fill", "none")
                .set("stroke", "#1f77b4")
                .set("stroke-width", 2)
                .set("opacity", 0.7),
        );
    }
    // Looks: a wedge each, green when the class was seen.
    for c in &live.cones {
        let reach = 1.5;
        let (a, b) = (c.direction - c.hfov / 2.0, c.direction + c.hfov / 2.0);
        let fill = match (c.detected, c.verify) {
            (true, _) => "#2ca02c",
            (false, true) => "#9467bd",
            (false, false) => "#ffbf00",
        };
        let ps = [
            f.at(c.at),
            f.at([c.at[0] + reach * a.cos(), c.at[1] + reach * a.sin()]),
            f.at([c.at[0] + reach * b.cos(), c.at[1] + reach * b.sin()]),
        ];
        doc = doc.add(
            Polygon::new()
                .set("points", points(&ps))
                .set("fill", fill)
                .set("opacity", 0.25),
        );
    }
    // Candidates: open while undecided, then a tick or a cross.
    for c in &live.candidates {
        let (x, y) = f.at(c.at);
        let (stroke, word) = match c.accepted {
            None => ("#ff7f0e", "undecided"),
            Some(true) => ("#2ca02c", "accepted"),
            Some(false) => ("#d62728", "rejected"),
        };
        doc = doc.add(
            Circle::new()
                .set("cx", x)
                .set("cy", y)
                .set("r", 7)
                .set("fill", "none")
                .set("stroke", stroke)
                .set("stroke-width", 2)
                .add(Title::new(format!(
                    "candidate {} at ({:.2}, {:.2}): {word}",
                    c.class, c.at[0], c.at[1]
                ))),
        );
        if c.accepted == Some(false) {
            let d = format!(
                "M{},{} L{},{} M{},{} L{},{}",
                x - 5.0,
                y - 5.0,
                x + 5.0,
                y + 5.0,
                x - 5.0,
                y + 5.0,
                x + 5.0,
                y - 5.0
            );
            doc = doc.add(
                Path::new()
                    .set("d", d)
                    .set("stroke", stroke)
                    .set("stroke-width", 2),
            );
        }
    }
    // Objects found by the agent (landmarks and targets) and reported.
    for o in beliefs.iter().flat_map(|b| &b.objects) {
        let (x, y) = f.at([o.at[0], o.at[1]]);
        doc = doc.add(
            Rectangle::new()
                .set("x", x - 3.0)
                .set("y", y - 3.0)
                .set("width", 6)
                .set("height", 6)
                .set("fill", "#8c564b")
                .add(Title::new(format!(
                    "{} {} at ({:.2}, {:.2}, {:.2})",
                    o.name, o.class, o.at[0], o.at[1], o.at[2]
                ))),
        );
    }
    for (p, name) in &live.found {
        let (x, y) = f.at([p[0], p[1]]);
        doc = doc.add(
            Circle::new()
                .set("cx", x)
                .set("cy", y)
                .set("r", 9)
                .set("fill", "#2ca02c")
                .set("stroke", "#000")
                .add(Title::new(format!(
                    "reported {name} at ({:.2}, {:.2}, {:.2})",
                    p[0], p[1], p[2]
                ))),
        );
    }
    // The robot: a triangle pointing along its heading.
    let (x, y, yaw) = (live.pose.x, live.pose.y, live.pose.yaw);
    let tip = |d: f64, a: f64| f.at([x + d * a.cos(), y + d * a.sin()]);
    doc = doc.add(
        Polygon::new()
            .set(
                "points",
                points(&[tip(0.45, yaw), tip(0.3, yaw + 2.5), tip(0.3, yaw - 2.5)]),
            )
            .set("fill", "#d62728")
            .set("stroke", "#000")
            .add(Title::new(format!(
                "robot at ({x:.2}, {y:.2}), heading {:.0}°; {:.1} m driven",
                yaw.to_degrees(),
                live.odometry
            ))),
    );
    // The current plan, under the map.
    if plan && !live.plan.is_empty() {
        let mut list = Group::new().set("class", "plan").add(
            Rectangle::new()
                .set("x", 0)
                .set("y", map_h)
                .set("width", w)
                .set("height", plan_h)
                .set("fill", "#f4f4f4"),
        );
        for (i, step) in live.plan.iter().enumerate() {
            let current = live.step.as_deref() == Some(step.as_str());
            list = list.add(
                Text::new(step.as_str())
                    .set("x", 6)
                    .set("y", r1(map_h + 16.0 + 13.0 * i as f64))
                    .set("fill", if current { "#d62728" } else { "#333" })
                    .set("font-weight", if current { "bold" } else { "normal" }),
            );
        }
        doc = doc.add(list);
    }
    format!("{doc}\n")
}

/// Rooms (their places as discs in the likeliest category's colour, the distribution on
/// hover), placeholders and doors.
fn rooms(mut doc: Document, b: &Beliefs, f: &Frame) -> Document {
    let categories: Vec<&str> = b
        .rooms
        .first()
        .map(|r| r.categories.iter().map(|c| c.category.as_str()).collect())
        .unwrap_or_default();
    let colour = |name: &str| {
        categories
            .iter()
            .position(|c| *c == name)
            .map(|i| PALETTE[i % PALETTE.len()])
            .unwrap_or("#999999")
    };
    let dist = |cs: &[avs_agent::trace::CategoryBelief]| {
        let mut v: Vec<&avs_agent::trace::CategoryBelief> = cs.iter().collect();
        v.sort_by(|a, b| b.p.total_cmp(&a.p));
        v.iter()
            .map(|c| format!("{} {:.2}", c.category, c.p))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for r in &b.rooms {
        let Some(top) = r.categories.iter().max_by(|a, b| a.p.total_cmp(&b.p)) else {
            continue;
        };
        let mut g = Group::new()
            .set("class", "room")
            .set("fill", colour(&top.category))
            .set("opacity", r1(100.0 * (0.2 + 0.35 * top.p)) / 100.0)
            .add(Title::new(format!("{}: {}", r.name, dist(&r.categories))));
        for p in &r.places {
            let (x, y) = f.at(*p);
            g = g.add(
                Circle::new()
                    .set("cx", x)
                    .set("cy", y)
                    .set("r", 0.75 * SCALE),
            );
        }
        doc = doc.add(g);
    }
    for d in &b.doors {
        let [a, c] = d.jambs;
        let ((xa, ya), (xc, yc)) = (f.at(a), f.at(c));
        doc = doc.add(
            Line::new()
                .set("x1", xa)
                .set("y1", ya)
                .set("x2", xc)
                .set("y2", yc)
                .set("stroke", if d.confirmed { "#2ca02c" } else { "#ff7f0e" })
                .set("stroke-width", 4)
                .add(Title::new(format!(
                    "door hypothesis at ({:.2}, {:.2}), {:.2} m wide{}",
                    d.at[0],
                    d.at[1],
                    d.width,
                    if d.confirmed { ", passed through" } else { "" }
                ))),
        );
    }
    for p in &b.placeholders {
        let (x, y) = f.at(p.at);
        doc = doc.add(
            Polygon::new()
                .set(
                    "points",
                    points(&[(x, y - 7.0), (x + 7.0, y), (x, y + 7.0), (x - 7.0, y)]),
                )
                .set("fill", "#ffffff")
                .set("stroke", "#e377c2")
                .set("stroke-width", 2)
                .add(Title::new(format!(
                    "{}: P(new room) {:.2}; {}",
                    p.name,
                    p.p_new_room,
                    dist(&p.categories)
                ))),
        );
    }
    doc
}

#[cfg(test)]
mod tests {
    use super::*;
    use avs_agent::beliefs::{PlaceholderBelief, RoomBelief};
    use avs_agent::trace::CategoryBelief;

    fn cat(c: &str, p: f64) -> CategoryBelief {
        CategoryBelief {
            category: c.into(),
            p,
        }
    }

    #[test]
    fn the_picture_colours_rooms_by_their_likeliest_category_and_names_the_distribution() {
        let mut live = Live::new(Pose2D::new(1.0, 1.0, 0.0), 0.8);
        live.grid = Some(OccupancyGrid::from_ascii("####\n#..#\n####", 0.5, [0.0, 0.0]).unwrap());
        live.robot_at(Pose2D::new(1.2, 1.0, 0.5), 0.2);
        let b = Beliefs {
            rooms: vec![RoomBelief {
                name: "room0".into(),
                id: 0,
                places: vec![[1.0, 1.0]],
                categories: vec![cat("office", 0.2), cat("kitchen", 0.8)],
            }],
            placeholders: vec![PlaceholderBelief {
                name: "placeholder3".into(),
                at: [1.5, 1.0],
                p_new_room: 0.6,
                hypotheses: [0.1, 0.3, 0.4, 0.2, 0.0, 0.0],
                p_object: None,
                categories: vec![cat("office", 0.5), cat("kitchen", 0.1)],
            }],
            ..Beliefs::default()
        };
        let svg = render_svg(&live, Some(&b), true);
        // Kitchen is the second category: the second colour, and the hover text ranks it first.
        assert!(svg.contains(&format!(r#"fill="{}""#, PALETTE[1])), "{svg}");
        assert!(svg.contains("<title>room0: kitchen 0.80, office 0.20</title>"));
        assert!(svg.contains("placeholder3: P(new room) 0.60"));
        // Two free cells in one run, the walls in runs; the trail and the robot.
        assert!(svg.contains("<polyline"));
        assert!(svg.contains("robot at (1.20, 1.00)"));
        assert!(svg.starts_with("<svg") && svg.trim_end().ends_with("</svg>"));
    }

    #[test]
    fn a_decision_closes_its_candidate() {
        let mut live = Live::new(Pose2D::new(0.0, 0.0, 0.0), 0.8);
        live.event(&Event::CandidateCreated {
            class: "mug".into(),
            at: [1.0, 2.0],
            prior: 0.3,
            verifier: "count".into(),
        });
        assert_eq!(live.candidates[0].accepted, None);
        live.event(&Event::VerificationDecision {
            class: "mug".into(),
            at: [1.0, 2.0],
            accepted: false,
            belief: None,
            looks: 3,
            detour_m: 1.0,
            reason: "no".into(),
        });
        assert_eq!(live.candidates.len(), 1);
        assert_eq!(live.candidates[0].accepted, Some(false));
    }
}
