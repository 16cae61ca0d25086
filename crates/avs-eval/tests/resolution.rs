//! The same building at two grid resolutions is the same building: the shipped office drawn
//! at 0.25 m cells and, cell for cell, at 0.125 m (each cell split in four) segments into the
//! same rooms, separated by the same doors; and with its furniture rasterised at each
//! resolution by the simulator, the place map keeps the same doors — no door found at one
//! resolution and missed at the other, no room split at a gap beside furniture at one of them;
//! and the robot's search for the cerealbox in it takes the same path, typically, at both.

use avs_eval::stats::median;
use avs_format::environment::{Environment, MapSource};
use avs_map::doors::{detect_doors, DoorHypothesis, DoorParams};
use avs_map::grid::Cell;
use avs_map::places::{dist, in_a_wall};
use avs_map::segment::{segment_rooms, SegmentParams, Segmentation};
use avs_sim::sim_robot::{SimAgentRobot, SimRobotConfig};
use avs_sim::World;
use std::path::{Path, PathBuf};

fn shipped(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel)
}

/// The shipped office (0.1 m cells) redrawn at `res` by sampling the cell under each new
/// cell's centre, then split `split` × `split` (so the finer drawing is the coarser one
/// exactly).
fn office_at(res: f64, split: usize) -> World {
    let path = shipped("domains/environments/office.yaml");
    let mut env: Environment = avs_format::load_yaml(&path).unwrap();
    let MapSource::Ascii(map) = &mut env.map else {
        panic!("the shipped office is an ASCII map");
    };
    let rows: Vec<Vec<char>> = map.ascii.lines().map(|l| l.chars().collect()).collect();
    let (h, w, r0) = (rows.len(), rows[0].len(), map.resolution);
    let (nw, nh) = (
        (w as f64 * r0 / res).round() as usize,
        (h as f64 * r0 / res).round() as usize,
    );
    let sample = |i: usize, j: usize| {
        let row = (((i as f64 + 0.5) * res / r0) as usize).min(h - 1);
        let col = (((j as f64 + 0.5) * res / r0) as usize).min(w - 1);
        rows[row][col]
    };
    let mut ascii = String::new();
    for i in 0..nh {
        let line: String = (0..nw)
            .flat_map(|j| std::iter::repeat_n(sample(i, j), split))
            .collect();
        for _ in 0..split {
            ascii.push_str(&line);
            ascii.push('\n');
        }
    }
    map.ascii = ascii;
    map.resolution = res / split as f64;
    World::new(env, path.parent().unwrap()).unwrap()
}

/// The door hypotheses the place map keeps on a complete map (`PlaceMap::refresh_doors`:
/// `detect_doors`, then only openings in a wall).
fn wall_doors(world: &World) -> Vec<DoorHypothesis> {
    detect_doors(&world.truth, &DoorParams::default())
        .into_iter()
        .filter(|h| in_a_wall(&world.truth, h))
        .collect()
}

/// Every door of `a` has one in `b` within a quarter metre, as wide to a quarter metre.
fn same_doors(a: &[DoorHypothesis], b: &[DoorHypothesis]) {
    assert_eq!(a.len(), b.len(), "{a:?}\nvs\n{b:?}");
    for d in a {
        let e = b
            .iter()
            .min_by(|p, q| dist(p.center, d.center).total_cmp(&dist(q.center, d.center)))
            .unwrap();
        assert!(
            dist(e.center, d.center) <= 0.25,
            "door at {:?} vs {:?}",
            d.center,
            e.center
        );
        assert!(
            (e.width - d.width).abs() <= 0.25,
            "{} vs {} m",
            d.width,
            e.width
        );
    }
}

#[test]
fn the_office_at_a_quarter_and_an_eighth_of_a_metre_has_the_same_rooms_and_doors() {
    let coarse = office_at(0.25, 1);
    let fine = office_at(0.25, 2);
    assert_eq!(coarse.truth.resolution(), 0.25);
    assert_eq!(fine.truth.resolution(), 0.125);
    // The walls are one drawing, cell for cell.
    for r in 0..coarse.walls.height() {
        for c in 0..coarse.walls.width() {
            let (c, r) = (c as i64, r as i64);
            assert_eq!(coarse.walls.get_i(c, r), fine.walls.get_i(2 * c, 2 * r));
        }
    }

    // The building (`avs segment`: walls, closed doors shut, no furniture): the environment's
    // four rooms at both resolutions, every coarse cell in the room of its four fine cells, and
    // the same three doors.
    let params = SegmentParams::default();
    let a = segment_rooms(&coarse.walls, &params).unwrap();
    let b = segment_rooms(&fine.walls, &params).unwrap();
    assert_eq!(a.rooms, coarse.env.rooms.len());
    assert_eq!(b.rooms, a.rooms);
    // (The cells of a doorway, in the wall's thickness, go to one side or the other: one
    // coarse cell is two fine ones there, split between the rooms.)
    let label = |s: &Segmentation, c: usize, r: usize| s.labels[r * s.width + c];
    let in_doorway = |c: usize, r: usize| {
        let (x, y) = coarse.walls.cell_center(c as i64, r as i64);
        let p = [x, y];
        a.doors
            .iter()
            .any(|d| dist(p, d.center) <= 0.5 * d.width + 0.25)
    };
    let mut same = std::collections::BTreeMap::new();
    for r in 0..a.height {
        for c in 0..a.width {
            if in_doorway(c, r) {
                continue;
            }
            let l = label(&a, c, r);
            for (dc, dr) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let m = label(&b, 2 * c + dc, 2 * r + dr);
                assert_eq!(l == 0, m == 0, "cell ({c}, {r})");
                if l != 0 {
                    assert_eq!(*same.entry(l).or_insert(m), m, "cell ({c}, {r})");
                }
            }
        }
    }
    same_doors(&a.doors, &b.doors);
    assert_eq!(a.doors.len(), coarse.env.doors.len());

    // The furnished map, as the robot's laser and the simulator's footprints make it: the
    // place map keeps the same three doors at both resolutions. The gaps between office2's
    // table and the walls (1.15 m: 1.25 m at 0.25 m cells, 1.125 m at 0.125 m, a door's width
    // at one resolution and not at the other) are no doors at either: they are not in a wall.
    let furniture = |w: &World| {
        let n = |g: &avs_map::grid::OccupancyGrid| {
            g.cells().iter().filter(|&&c| c == Cell::Occupied).count()
        };
        n(&w.truth) > n(&w.walls)
    };
    assert!(furniture(&coarse) && furniture(&fine));
    let (da, db) = (wall_doors(&coarse), wall_doors(&fine));
    same_doors(&da, &db);
    same_doors(&da, &a.doors);
    // Without the wall test the fine map has the table's two gaps as doors: the test above is
    // what keeps office2 one room.
    let raw = detect_doors(&fine.truth, &DoorParams::default());
    assert!(raw.len() > db.len(), "{raw:?}");
}

/// The path of the planner's cerealbox search in `world` from the environment's start, seed
/// `seed`, metres (the search must find it). Its look around looks for landmarks only
/// (`goal_in_look_around: false`): with the goal in it the cereal box is seen from the kitchen
/// door, the searches shrink to 12–17 m, and over seeds 1–20 the medians were 16.9 m at 0.25 m
/// cells and 13.3 m at 0.125 m — 0.8 m of that is the coarse grid's longer walk to the same
/// places (6 % of such a search), the rest closer looks at a look-alike: the robot looks
/// around office1 where it stops at the placeholder, 0.2 m apart at the two cell sizes, and
/// from the coarse spot the mug on office1's desk is confirmed as a cereal-box sighting in 8
/// of 20 runs (3 of 20 from the fine one), each a walk to verify it. What this test pins is
/// that the map makes the planner decide alike.
fn search_path(world: &World, seed: u64) -> f64 {
    let knowledge: avs_format::knowledge::Knowledge =
        avs_format::load_yaml(&shipped("knowledge/office.yaml")).unwrap();
    let domain = avs_plan::domain::Domain::load(&shipped("domains/object_search.yaml")).unwrap();
    let mut robot =
        SimAgentRobot::new(world, knowledge.clone(), SimRobotConfig::default(), seed).unwrap();
    let config = avs_agent::AgentConfig {
        goal_in_look_around: false,
        ..avs_agent::AgentConfig::default()
    };
    let mut agent = avs_agent::Agent::new(domain, knowledge, config).unwrap();
    let report = agent
        .search(&mut robot, avs_agent::Goal::find("cerealbox"))
        .unwrap();
    assert!(
        report.found.is_some(),
        "seed {seed} at {} m cells: {}",
        world.truth.resolution(),
        report.reason
    );
    report.metrics.path_length
}

#[test]
fn the_search_path_is_the_same_at_a_quarter_and_an_eighth_of_a_metre() {
    // Over seeds 1–10, the median path at 0.25 m cells within 10 % of the one at 0.125 m. A
    // single seed may part by chance at either resolution (a landmark missed in a look-around,
    // a false alarm: seed 6 wanders at both); a map that makes the robot decide otherwise
    // shifts them all. That happened when the unknown space ENTER weighs beyond a door was
    // counted in cells a ray touched: at 0.25 m a shadow behind office1's desk counted 1.19 m²
    // (0.67 m² at 0.125 m), over the 1 m² that sends the robot on, and every coarse search
    // went 3.5 m further (medians 16.1 and 12.7 m).
    let (coarse, fine) = (office_at(0.25, 1), office_at(0.25, 2));
    let seeds = 1..=10;
    let a: Vec<f64> = seeds.clone().map(|s| search_path(&coarse, s)).collect();
    let b: Vec<f64> = seeds.map(|s| search_path(&fine, s)).collect();
    let (ma, mb) = (median(&a), median(&b));
    assert!(
        (ma - mb).abs() <= 0.1 * mb,
        "median {ma:.1} m at 0.25 m cells, {mb:.1} m at 0.125 m\n{a:.1?}\n{b:.1?}"
    );
}
