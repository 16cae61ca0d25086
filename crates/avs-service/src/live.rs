//! What the live view shows of a session ([`Live`], kept current from the trace events and
//! the robot's calls) and its picture ([`render_svg`]): the robot's map, the rooms coloured
//! by their likeliest category (hovering one shows its distribution), placeholders, doors, the
//! robot and its trail, the current plan, view cones as they are processed, candidates and
//! verification decisions.

use avs_agent::{Beliefs, Event};
use avs_map::grid::{Cell, OccupancyGrid};
use avs_robot::Pose2D;
use serde::Serialize;
use std::fmt::Write;

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

/// Escape text for SVG.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
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
    let fold = |v: &[f64], f: fn(f64, f64) -> f64, init: f64| v.iter().copied().fold(init, f);
    let (x0, x1) = (
        fold(&xs, f64::min, f64::INFINITY) - 0.5,
        fold(&xs, f64::max, f64::NEG_INFINITY) + 0.5,
    );
    let (y0, y1) = (
        fold(&ys, f64::min, f64::INFINITY) - 0.5,
        fold(&ys, f64::max, f64::NEG_INFINITY) + 0.5,
    );
    // The plan is listed under the drawing, one line per step.
    let plan_h = if live.plan.is_empty() || !plan {
        0.0
    } else {
        10.0 + 13.0 * live.plan.len() as f64
    };
    let (w, map_h) = ((x1 - x0) * SCALE, (y1 - y0) * SCALE);
    let h = map_h + plan_h;
    let px = |x: f64| (x - x0) * SCALE;
    let py = |y: f64| (y1 - y) * SCALE;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {w:.0} {h:.0}" width="{w:.0}" height="{h:.0}" font-family="sans-serif" font-size="11">"#
    );
    let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#d9d9d9"/>"##);
    // The map: runs of free and occupied cells along each row.
    if let Some(g) = &live.grid {
        let r = g.resolution();
        let [ox, oy] = g.origin();
        for (cell, fill) in [(Cell::Free, "#ffffff"), (Cell::Occupied, "#222222")] {
            let _ = write!(s, r#"<g fill="{fill}">"#);
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
                    let _ = write!(
                        s,
                        r#"<rect x="{:.1}" y="{:.1}" width="{:.1}" height="{:.1}"/>"#,
                        px(x),
                        py(y),
                        (col - start) as f64 * r * SCALE + 0.3,
                        r * SCALE + 0.3
                    );
                }
            }
            let _ = writeln!(s, "</g>");
        }
    }
    if let Some(b) = beliefs {
        rooms(&mut s, b, &px, &py);
    }
    // The trail.
    if live.trail.len() > 1 {
        let pts: Vec<String> = live
            .trail
            .iter()
            .map(|p| format!("{:.1},{:.1}", px(p[0]), py(p[1])))
            .collect();
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#1f77b4" stroke-width="2" opacity="0.7"/>"##,
            pts.join(" ")
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
        let _ = writeln!(
            s,
            r#"<polygon points="{:.1},{:.1} {:.1},{:.1} {:.1},{:.1}" fill="{fill}" opacity="0.25"/>"#,
            px(c.at[0]),
            py(c.at[1]),
            px(c.at[0] + reach * a.cos()),
            py(c.at[1] + reach * a.sin()),
            px(c.at[0] + reach * b.cos()),
            py(c.at[1] + reach * b.sin())
        );
    }
    // Candidates: open while undecided, then a tick or a cross.
    for c in &live.candidates {
        let (x, y) = (px(c.at[0]), py(c.at[1]));
        let (stroke, word) = match c.accepted {
            None => ("#ff7f0e", "undecided"),
            Some(true) => ("#2ca02c", "accepted"),
            Some(false) => ("#d62728", "rejected"),
        };
        let _ = writeln!(
            s,
            r#"<circle cx="{x:.1}" cy="{y:.1}" r="7" fill="none" stroke="{stroke}" stroke-width="2"><title>candidate {} at ({:.2}, {:.2}): {word}</title></circle>"#,
            esc(&c.class),
            c.at[0],
            c.at[1]
        );
        if c.accepted == Some(false) {
            let _ = writeln!(
                s,
                r#"<path d="M{:.1},{:.1} L{:.1},{:.1} M{:.1},{:.1} L{:.1},{:.1}" stroke="{stroke}" stroke-width="2"/>"#,
                x - 5.0,
                y - 5.0,
                x + 5.0,
                y + 5.0,
                x - 5.0,
                y + 5.0,
                x + 5.0,
                y - 5.0
            );
        }
    }
    // Objects found by the agent (landmarks and targets) and reported.
    if let Some(b) = beliefs {
        for o in &b.objects {
            let _ = writeln!(
                s,
                r##"<rect x="{:.1}" y="{:.1}" width="6" height="6" fill="#8c564b"><title>{} {} at ({:.2}, {:.2}, {:.2})</title></rect>"##,
                px(o.at[0]) - 3.0,
                py(o.at[1]) - 3.0,
                esc(&o.name),
                esc(&o.class),
                o.at[0],
                o.at[1],
                o.at[2]
            );
        }
    }
    for (p, name) in &live.found {
        let _ = writeln!(
            s,
            r##"<circle cx="{:.1}" cy="{:.1}" r="9" fill="#2ca02c" stroke="#000"><title>reported {} at ({:.2}, {:.2}, {:.2})</title></circle>"##,
            px(p[0]),
            py(p[1]),
            esc(name),
            p[0],
            p[1],
            p[2]
        );
    }
    // The robot: a triangle pointing along its heading.
    let (x, y, yaw) = (live.pose.x, live.pose.y, live.pose.yaw);
    let tip = |d: f64, a: f64| format!("{:.1},{:.1}", px(x + d * a.cos()), py(y + d * a.sin()));
    let _ = writeln!(
        s,
        r##"<polygon points="{} {} {}" fill="#d62728" stroke="#000"><title>robot at ({x:.2}, {y:.2}), heading {:.0}°; {:.1} m driven</title></polygon>"##,
        tip(0.45, yaw),
        tip(0.3, yaw + 2.5),
        tip(0.3, yaw - 2.5),
        yaw.to_degrees(),
        live.odometry
    );
    // The current plan, under the map.
    if plan && !live.plan.is_empty() {
        let _ = writeln!(
            s,
            r##"<g class="plan"><rect x="0" y="{map_h:.0}" width="{w:.0}" height="{plan_h:.0}" fill="#f4f4f4"/>"##
        );
        for (i, step) in live.plan.iter().enumerate() {
            let current = live.step.as_deref() == Some(step.as_str());
            let _ = writeln!(
                s,
                r##"<text x="6" y="{:.0}" fill="{}" font-weight="{}">{}</text>"##,
                map_h + 16.0 + 13.0 * i as f64,
                if current { "#d62728" } else { "#333" },
                if current { "bold" } else { "normal" },
                esc(step)
            );
        }
        let _ = writeln!(s, "</g>");
    }
    s.push_str("</svg>\n");
    s
}

/// Rooms (their places as discs in the likeliest category's colour, the distribution on
/// hover), placeholders and doors.
fn rooms(s: &mut String, b: &Beliefs, px: &dyn Fn(f64) -> f64, py: &dyn Fn(f64) -> f64) {
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
        let _ = write!(
            s,
            r#"<g class="room" fill="{}" opacity="{:.2}"><title>{}: {}</title>"#,
            colour(&top.category),
            0.2 + 0.35 * top.p,
            esc(&r.name),
            esc(&dist(&r.categories))
        );
        for p in &r.places {
            let _ = write!(
                s,
                r#"<circle cx="{:.1}" cy="{:.1}" r="{:.1}"/>"#,
                px(p[0]),
                py(p[1]),
                0.75 * SCALE
            );
        }
        let _ = writeln!(s, "</g>");
    }
    for d in &b.doors {
        let [a, c] = d.jambs;
        let _ = writeln!(
            s,
            r##"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="{}" stroke-width="4"><title>door hypothesis at ({:.2}, {:.2}), {:.2} m wide{}</title></line>"##,
            px(a[0]),
            py(a[1]),
            px(c[0]),
            py(c[1]),
            if d.confirmed { "#2ca02c" } else { "#ff7f0e" },
            d.at[0],
            d.at[1],
            d.width,
            if d.confirmed { ", passed through" } else { "" }
        );
    }
    for p in &b.placeholders {
        let (x, y) = (px(p.at[0]), py(p.at[1]));
        let _ = writeln!(
            s,
            r##"<polygon points="{:.1},{:.1} {:.1},{:.1} {:.1},{:.1} {:.1},{:.1}" fill="#ffffff" stroke="#e377c2" stroke-width="2"><title>{}: P(new room) {:.2}; {}</title></polygon>"##,
            x,
            y - 7.0,
            x + 7.0,
            y,
            x,
            y + 7.0,
            x - 7.0,
            y,
            esc(&p.name),
            p.p_new_room,
            esc(&dist(&p.categories))
        );
    }
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
