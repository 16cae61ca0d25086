//! The picture of a search ([`render_search`]): the trail, every camera look as a view-cone
//! wedge, false alarms, the start, the end and the report, with a title, a legend and a scale bar.

use super::*;

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
pub(super) fn wedge_data(x: f64, y: f64, dir: f64, hfov: f64, len: f64) -> Data {
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
pub(super) fn marker_step(path: f64) -> f64 {
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
