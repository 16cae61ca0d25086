//! Door hypotheses on synthetic grids whose doors are known by construction.

use avs_map::doors::{detect_doors, ClearanceMap, DoorHypothesis, DoorParams};
use avs_map::grid::{Cell, OccupancyGrid};
use proptest::prelude::*;

/// Two rooms side by side (each `room` cells wide, `rows` high inside) separated by a one-cell
/// wall at column `room + 1` with a gap of `gap` cells starting at row `gap_from`.
fn two_rooms(room: usize, rows: usize, gap_from: usize, gap: usize) -> String {
    let (w, h) = (2 * room + 3, rows + 2);
    let mut text = String::new();
    for r in 0..h {
        let row = h - 1 - r; // text lists the top row first
        for col in 0..w {
            let wall = row == 0
                || row == h - 1
                || col == 0
                || col == w - 1
                || (col == room + 1 && !(gap_from..gap_from + gap).contains(&row));
            text.push(if wall { '#' } else { '.' });
        }
        text.push('\n');
    }
    text
}

#[test]
fn a_gap_in_the_door_range_is_one_door_with_its_width_and_position() {
    // 0.1 m cells: a 9-cell gap is 0.9 m wide, rows 8..17 → y from 0.8 to 1.7 m.
    let grid = OccupancyGrid::from_ascii(&two_rooms(25, 25, 8, 9), 0.1, [0.0, 0.0]).unwrap();
    let doors = detect_doors(&grid, &DoorParams::default());
    assert_eq!(doors.len(), 1, "{doors:?}");
    let d = doors[0];
    assert!((d.width - 0.9).abs() < 0.1 + 1e-9, "width {}", d.width);
    // The wall is column 26 → x from 2.6 to 2.7 m.
    assert!((d.center[0] - 2.65).abs() <= 0.1, "center {:?}", d.center);
    assert!((d.center[1] - 1.25).abs() <= 0.1, "center {:?}", d.center);
    for j in d.jambs {
        let (c, r) = grid.world_to_cell(j[0], j[1]);
        assert_eq!(
            grid.get_i(c, r),
            Cell::Occupied,
            "jamb {j:?} is an obstacle"
        );
    }
}

#[test]
fn gaps_outside_the_width_range_are_not_doors() {
    for gap in [4, 20] {
        let grid = OccupancyGrid::from_ascii(&two_rooms(25, 30, 6, gap), 0.1, [0.0, 0.0]).unwrap();
        let doors = detect_doors(&grid, &DoorParams::default());
        assert!(doors.is_empty(), "gap of {gap} cells gave {doors:?}");
    }
}

#[test]
fn the_width_range_is_taken_from_the_parameters() {
    let grid = OccupancyGrid::from_ascii(&two_rooms(25, 30, 6, 16), 0.1, [0.0, 0.0]).unwrap();
    let wide = DoorParams {
        min_width: 1.4,
        max_width: 1.8,
        ..DoorParams::default()
    };
    let doors = detect_doors(&grid, &wide);
    assert_eq!(doors.len(), 1, "{doors:?}");
    assert!((doors[0].width - 1.6).abs() < 0.1 + 1e-9);
}

#[test]
fn a_uniform_corridor_has_no_door_along_it() {
    // A 1 m wide, 6 m long corridor between two 3 m rooms: its clearance does not rise on
    // both sides anywhere inside it.
    let (w, h) = (121, 32);
    let mut text = String::new();
    for r in 0..h {
        let row = h - 1 - r;
        for col in 0..w {
            let in_room = (1..31).contains(&col) || (90..120).contains(&col);
            let in_corridor = (31..90).contains(&col) && (11..21).contains(&row);
            let free = (1..h - 1).contains(&row) && (in_room || in_corridor);
            text.push(if free { '.' } else { '#' });
        }
        text.push('\n');
    }
    let grid = OccupancyGrid::from_ascii(&text, 0.1, [0.0, 0.0]).unwrap();
    let doors = detect_doors(&grid, &DoorParams::default());
    assert!(
        doors.iter().all(|d| d.center[0] < 3.3 || d.center[0] > 8.8),
        "door inside the corridor: {doors:?}"
    );
}

#[test]
fn a_gap_bounded_by_unknown_space_is_a_frontier_not_a_door() {
    let text = two_rooms(25, 25, 8, 9);
    let mut grid = OccupancyGrid::from_ascii(&text, 0.1, [0.0, 0.0]).unwrap();
    // Forget the wall below the gap: that jamb is now unknown.
    for row in 0..8 {
        grid.set(26, row, Cell::Unknown);
    }
    assert!(detect_doors(&grid, &DoorParams::default()).is_empty());
}

#[test]
fn a_mask_of_the_wrong_size_is_an_error_not_a_panic() {
    let err = ClearanceMap::new(3, 3, &[true; 8]).unwrap_err().to_string();
    assert!(err.contains("8 cells") && err.contains("3 × 3"), "{err}");
}

#[test]
fn crossed_by_tells_a_move_through_the_opening_from_one_beside_it() {
    let d = DoorHypothesis {
        center: [1.0, 0.0],
        jambs: [[1.0, -0.45], [1.0, 0.45]],
        width: 0.9,
    };
    assert!(d.crossed_by([0.5, 0.1], [1.5, -0.1]));
    assert!(!d.crossed_by([0.5, 1.0], [1.5, 1.0]));
    assert!(!d.crossed_by([0.2, 0.0], [0.8, 0.0]));
}

#[test]
fn invalid_parameters_name_the_field_and_yield_no_doors() {
    let bad = DoorParams {
        min_width: 1.5,
        max_width: 1.0,
        ..DoorParams::default()
    };
    let err = bad.validate().unwrap_err().to_string();
    assert!(err.contains("max_width"), "{err}");
    let nan = DoorParams {
        neck_ratio: f64::NAN,
        ..DoorParams::default()
    };
    assert!(nan
        .validate()
        .unwrap_err()
        .to_string()
        .contains("neck_ratio"));
    let grid = OccupancyGrid::from_ascii(&two_rooms(25, 25, 8, 9), 0.1, [0.0, 0.0]).unwrap();
    assert!(detect_doors(&grid, &bad).is_empty());
}

proptest! {
    /// The separable transform equals brute force: the distance to the nearest non-free cell,
    /// with the ring just outside the grid counting as non-free.
    #[test]
    fn clearance_equals_brute_force_distance(
        w in 1usize..12, h in 1usize..12, bits in proptest::collection::vec(0u8..4, 144)
    ) {
        let free: Vec<bool> = (0..w * h).map(|i| bits[i] != 0).collect();
        let map = ClearanceMap::new(w, h, &free).unwrap();
        for row in 0..h {
            for col in 0..w {
                let i = row * w + col;
                let mut best = i64::MAX;
                for y in -1..=h as i64 {
                    for x in -1..=w as i64 {
                        let outside = x < 0 || y < 0 || x >= w as i64 || y >= h as i64;
                        if outside || !free[y as usize * w + x as usize] {
                            let d = (x - col as i64).pow(2) + (y - row as i64).pow(2);
                            best = best.min(d);
                        }
                    }
                }
                prop_assert!((map.distance(i) - (best as f64).sqrt()).abs() < 1e-9);
                let (fx, fy) = map.feature(i);
                let fd = (i64::from(fx) - col as i64).pow(2) + (i64::from(fy) - row as i64).pow(2);
                prop_assert_eq!(fd, best);
            }
        }
    }
}

proptest! {
    /// On any partially known grid every hypothesis has a width in range and two obstacle jambs.
    #[test]
    fn every_hypothesis_is_in_range_between_two_obstacles(
        w in 1usize..40, h in 1usize..40, cells in proptest::collection::vec(0u8..8, 1600)
    ) {
        let mut g = OccupancyGrid::new(w, h, 0.1, [0.0, 0.0], Cell::Free).unwrap();
        for row in 0..h {
            for col in 0..w {
                match cells[row * 40 + col] {
                    0 => g.set(col, row, Cell::Occupied),
                    1 => g.set(col, row, Cell::Unknown),
                    _ => {}
                }
            }
        }
        let p = DoorParams::default();
        for d in detect_doors(&g, &p) {
            prop_assert!(d.width >= p.min_width - 1e-9 && d.width <= p.max_width + 1e-9);
            for j in d.jambs {
                let (c, r) = g.world_to_cell(j[0], j[1]);
                prop_assert_eq!(g.get_i(c, r), Cell::Occupied);
            }
        }
    }
}

#[test]
fn a_doorway_onto_unexplored_space_is_a_hypothesis() {
    // The wall and its 0.9 m gap (rows 8..17) are seen, and of the room behind it only a
    // 0.3 m deep strip just beyond the gap; the rest of that room is unknown.
    let mut grid = OccupancyGrid::from_ascii(&two_rooms(25, 25, 8, 9), 0.1, [0.0, 0.0]).unwrap();
    for col in 27..52usize {
        for row in 1..26usize {
            let seen = col < 30 && (8..17).contains(&row);
            if !seen {
                grid.set(col, row, Cell::Unknown);
            }
        }
    }
    let doors = detect_doors(&grid, &DoorParams::default());
    assert_eq!(doors.len(), 1, "{doors:?}");
    assert!((doors[0].center[0] - 2.65).abs() <= 0.1);
}
