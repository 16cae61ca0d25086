//! Rooms, camera and objects of Sjöö et al.'s §4.3 experiments, shared by the view-planning
//! tests and benches.
#![allow(dead_code)]

use avs_robot::{Camera, ImageGeometry};
use avs_view::plan::SoughtClass;
use avs_view::ObjectModel;

/// The paper's camera.
pub fn camera() -> Camera {
    let hfov = 47.5f64.to_radians();
    Camera {
        hfov,
        // The 4:3 image's vertical field.
        vfov: 2.0 * ((hfov / 2.0).tan() * 0.75).atan(),
        pan_limits: [-100f64.to_radians(), 100f64.to_radians()],
        tilt_limits: [-30f64.to_radians(), 90f64.to_radians()],
        max_zoom: 13.0,
        height: 1.0,
    }
}

/// The paper's objects: name, front face width × height (the book, mouse pad and rice carton's
/// sizes are ours), heights of the centre.
pub fn object(letter: char) -> SoughtClass {
    let (name, w, h, heights) = match letter {
        'B' => ("book", 0.17, 0.24, [0.4, 1.2]),
        'C' => ("cup", 0.14, 0.10, [0.4, 1.2]),
        'D' => ("robot", 0.63, 0.55, [0.275, 0.275]),
        'M' => ("mousepad", 0.23, 0.19, [0.4, 1.2]),
        'R' => ("rice", 0.12, 0.20, [0.4, 1.2]),
        _ => unreachable!("the paper's objects are B, C, D, M and R"),
    };
    let model = ObjectModel {
        class: name.into(),
        width: w,
        height: h,
        vote_threshold: avs_view::zoom::DEFAULT_VOTE_THRESHOLD,
    };
    SoughtClass::from_model(&model, &camera(), &ImageGeometry::default(), heights)
}

/// A rectangular room `w × h` m with its door at `door` and tables `[x0, y0, x1, y1]`: the
/// cells objects may be in and the standpoint order.
///
/// As in the paper, the cells are the *occupied* cells of the grid (§2.1.1: "marking a cell as
/// occupied if it contains a feature"; Fig. 2 covers "a set of cells that … originate from a
/// wall"): objects rest on furniture and stand against walls, not in the middle of the floor.
/// Here: the ring of 0.5 m cells along the walls and the cells under the tables.
pub struct Room {
    /// Floor area, m².
    pub area: f64,
    /// The cells objects may be in.
    pub cells: Vec<[f64; 2]>,
    /// Standpoints in farthest-point order from the door.
    pub nodes: Vec<[f64; 2]>,
}

pub fn room(w: f64, h: f64, door: [f64; 2], tables: &[[f64; 4]]) -> Room {
    let lattice = |step: f64, margin: f64| {
        let mut out = Vec::new();
        let mut x = margin;
        while x <= w - margin + 1e-9 {
            let mut y = margin;
            while y <= h - margin + 1e-9 {
                out.push([x, y]);
                y += step;
            }
            x += step;
        }
        out
    };
    let on_table = |p: [f64; 2], pad: f64| {
        tables.iter().any(|t| {
            p[0] > t[0] - pad && p[0] < t[2] + pad && p[1] > t[1] - pad && p[1] < t[3] + pad
        })
    };
    // Whole 0.5 m cells inside the room: those along a wall, and those under a table.
    let cells: Vec<[f64; 2]> = lattice(0.5, 0.25)
        .into_iter()
        .filter(|c| {
            let wall = c[0] < 0.5 || c[1] < 0.5 || c[0] > w - 0.5 || c[1] > h - 0.5;
            wall || on_table(*c, 0.0)
        })
        .collect();
    // Standpoints: 0.5 m from the walls, 0.4 m clear of the tables.
    let spots: Vec<[f64; 2]> = lattice(0.5, 0.5)
        .into_iter()
        .filter(|p| !on_table(*p, 0.4))
        .collect();
    // Farthest-point order from the door.
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let mut near: Vec<f64> = spots.iter().map(|s| dist(*s, door)).collect();
    // The first node is the spot nearest the door.
    let mut next = (0..spots.len())
        .min_by(|&a, &b| near[a].total_cmp(&near[b]))
        .expect("a room has standpoints");
    let mut nodes: Vec<[f64; 2]> = Vec::new();
    for _ in 0..12 {
        let at = spots[next];
        nodes.push(at);
        for (n, s) in near.iter_mut().zip(&spots) {
            *n = n.min(dist(*s, at));
        }
        next = (0..spots.len())
            .max_by(|&a, &b| near[a].total_cmp(&near[b]).then(b.cmp(&a)))
            .expect("a room has standpoints");
    }
    Room {
        area: w * h,
        cells,
        nodes,
    }
}

/// §4.3's rooms: 31.6, 40.9, 17.2 and 18.9 m².
pub fn rooms() -> [Room; 4] {
    [
        room(7.9, 4.0, [0.0, 2.0], &[[3.0, 1.5, 4.5, 2.5]]),
        room(
            8.18,
            5.0,
            [4.0, 0.0],
            &[[1.5, 3.0, 3.0, 4.0], [5.5, 1.5, 6.5, 3.0]],
        ),
        room(4.3, 4.0, [0.0, 1.0], &[[2.0, 2.0, 3.0, 3.0]]),
        room(4.5, 4.2, [2.0, 0.0], &[]),
    ]
}
