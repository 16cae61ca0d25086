//! The default environment (`domains/environments/office.yaml`) as the robot knows it when it
//! starts: it stands at the west end of the corridor, the corridor is the only room it knows
//! (category unknown), and placeholders lead off it — one at each of the three doors and one at
//! the corridor's east end. Probabilities come from a simple stand-in for the conceptual map.
#![allow(
    dead_code,
    reason = "shared by several test crates, each of which uses a part (an expect would fail in the one that uses all)"
)]

use avs_plan::domain::Domain;
use avs_plan::problem::Problem;
use std::collections::HashMap;

/// The object-search domain shipped in `domains/`.
pub fn object_search_domain() -> Domain {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../domains/object_search.yaml");
    Domain::load(&path).unwrap_or_else(|d| panic!("domain invalid: {d:?}"))
}

/// Classes of `knowledge/office.yaml`.
pub const LABELS: [&str; 8] = [
    "table",
    "counter",
    "desk",
    "shelf",
    "cerealbox",
    "stapler",
    "whiteboardmarker",
    "mug",
];
/// Landmark classes.
pub const LANDMARKS: [&str; 4] = ["table", "counter", "desk", "shelf"];

/// The world as known at the start: `corridor` places along y = 1.2 m from x = 0.5 to 11.5
/// (at least 3), the robot on the first; placeholders place1 (office1's door, x = 2),
/// place2 (kitchen door, x = 6), place3 (office2 door, x = 10) north of the corridor and
/// place4 at the east end.
pub struct World {
    /// The problem.
    pub problem: Problem,
    /// Place coordinates.
    pub xy: HashMap<String, (f64, f64)>,
}

pub fn office_start(corridor: usize, labels: &[&str], target: &str) -> World {
    assert!(corridor >= 3);
    let mut p = Problem::new()
        .object("room0", "room")
        .object("corridor", "category")
        .object("kitchen", "category")
        .object("office", "category");
    for l in labels {
        p = p.object(l, "label");
        if LANDMARKS.contains(l) {
            p = p.fact(&format!("landmark({l})"));
        }
    }
    let mut xy = HashMap::new();
    // Corridor places: place0, then place5, place6, …
    let mut corridor_names = vec!["place0".to_string()];
    for k in 1..corridor {
        corridor_names.push(format!("place{}", 4 + k));
    }
    for (k, n) in corridor_names.iter().enumerate() {
        let x = 0.5 + 11.0 * k as f64 / (corridor - 1) as f64;
        xy.insert(n.clone(), (x, 1.2));
        p = p.object(n, "place").fact(&format!("in-room({n}, room0)"));
    }
    for w in corridor_names.windows(2) {
        p = p
            .fact(&format!("connected({}, {})", w[0], w[1]))
            .fact(&format!("connected({}, {})", w[1], w[0]));
    }
    let holders = [
        ("place1", 2.0, 2.6),
        ("place2", 6.0, 2.6),
        ("place3", 10.0, 2.6),
        ("place4", 11.9, 1.2),
    ];
    for (n, x, y) in holders {
        xy.insert(n.to_string(), (x, y));
        // Attach to the nearest corridor place.
        let near = corridor_names
            .iter()
            .min_by(|a, b| {
                let da = (xy[*a].0 - x).abs();
                let db = (xy[*b].0 - x).abs();
                da.total_cmp(&db)
            })
            .unwrap()
            .clone();
        p = p
            .object(n, "place")
            .fact(&format!("placeholder({n})"))
            .fact(&format!("in-room({n}, room0)"))
            .fact(&format!("connected({near}, {n})"))
            .fact(&format!("connected({n}, {near})"))
            .init(&format!("leads-to({n}) = unknown"));
    }
    p = p
        .init("robot-at = place0")
        .init("robot-room = room0")
        .init("open-placeholders(room0) = n4")
        .goal(&format!("reported({target}) = yes"));
    World { problem: p, xy }
}

/// Stand-in probabilities: P(category | placeholder) higher for kitchen/office behind doors,
/// P(category | room) for the corridor, object priors per category.
pub fn stand_in(name: &str, args: &[&str], xy: &HashMap<String, (f64, f64)>) -> Option<f64> {
    Some(match (name, args) {
        ("distance", [a, b]) => {
            let (pa, pb) = (xy.get(*a)?, xy.get(*b)?);
            ((pa.0 - pb.0).powi(2) + (pa.1 - pb.1).powi(2)).sqrt()
        }
        ("p-leads-to-room", [ph, c]) => {
            let door = *ph != "place4";
            match (*c, door) {
                ("kitchen", true) => 0.3,
                ("office", true) => 0.5,
                ("corridor", true) => 0.1,
                ("kitchen", false) => 0.1,
                ("office", false) => 0.2,
                _ => 0.4,
            }
        }
        ("p-category", [_, c]) => match *c {
            "corridor" => 0.9,
            _ => 0.05,
        },
        ("p-object-in", [l, _, c]) => match (*l, *c) {
            ("table", "kitchen") => 0.9,
            ("counter", "kitchen") => 0.8,
            ("cerealbox", "kitchen") => 0.2,
            ("desk", "office") => 0.9,
            ("shelf", "office") => 0.6,
            ("table", "office") => 0.4,
            _ => 0.05,
        },
        ("p-object-on", [l, lc, c]) => match (*l, *lc, *c) {
            ("cerealbox", "table", "kitchen") => 0.5,
            ("cerealbox", "counter", "kitchen") => 0.4,
            ("stapler", "desk", "office") => 0.6,
            ("whiteboardmarker", "table", "office") => 0.3,
            ("mug", "table", _) => 0.4,
            _ => 0.02,
        },
        ("p-object-inside", [l, lc, c]) => match (*l, *lc, *c) {
            ("cerealbox", "shelf", "kitchen") => 0.2,
            _ => 0.0,
        },
        ("p-detect", [_]) | ("p-detect-in", [_, _]) => 0.8,
        // The flat search costs the domain had before the agent priced searches by their views.
        ("search-cost-in", [_, _]) => 20.0,
        ("search-cost-on", [_, _]) => 5.0,
        _ => return None,
    })
}
