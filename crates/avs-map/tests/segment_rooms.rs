//! Room segmentation on synthetic grids whose rooms are known by construction.

use avs_map::grid::{Cell, OccupancyGrid};
use avs_map::segment::{segment_rooms, SegmentParams};

/// `n` rooms of `room × room` cells in a row, joined by 9-cell (0.9 m) doorways.
fn rooms_in_a_row(n: usize, room: usize) -> OccupancyGrid {
    let (w, h) = (n * (room + 1) + 1, room + 2);
    let mut g = OccupancyGrid::new(w, h, 0.1, [0.0, 0.0], Cell::Occupied).unwrap();
    for k in 0..n {
        let x0 = 1 + k * (room + 1);
        for col in x0..x0 + room {
            for row in 1..=room {
                g.set(col, row, Cell::Free);
            }
        }
        if k + 1 < n {
            for row in 5..14 {
                g.set(x0 + room, row, Cell::Free);
            }
        }
    }
    g
}

#[test]
fn rooms_joined_by_doorways_are_separated_at_each_door() {
    let g = rooms_in_a_row(3, 25);
    let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
    assert_eq!(seg.rooms, 3);
    assert_eq!(seg.doors.len(), 2);
    // Each room's interior carries one label, different from its neighbours'.
    let centre = |k: usize| seg.labels[g.index(1 + k * 26 + 12, 13)];
    for k in 0..3 {
        let l = centre(k);
        for col in 1 + k * 26 + 2..1 + k * 26 + 23 {
            for row in 3..24 {
                assert_eq!(seg.labels[g.index(col, row)], l, "cell ({col}, {row})");
            }
        }
    }
    assert!(centre(0) != centre(1) && centre(1) != centre(2) && centre(0) != centre(2));
}

#[test]
fn every_free_cell_gets_a_room_and_no_wall_does() {
    let g = rooms_in_a_row(3, 25);
    let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
    for (i, &c) in g.cells().iter().enumerate() {
        if c == Cell::Free {
            assert!((1..=seg.rooms as u32).contains(&seg.labels[i]), "cell {i}");
        } else {
            assert_eq!(seg.labels[i], 0, "cell {i}");
        }
    }
}

#[test]
fn rooms_smaller_than_the_minimum_area_join_their_neighbours() {
    let g = rooms_in_a_row(2, 25);
    // Each room is 6.25 m²; with an 8 m² minimum neither is a room alone, together they are.
    let params = SegmentParams {
        min_room_area: 8.0,
        ..SegmentParams::default()
    };
    let seg = segment_rooms(&g, &params).unwrap();
    assert_eq!(seg.rooms, 1);
    assert!(seg.doors.is_empty());
    let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
    assert_eq!(seg.rooms, 2);
}

#[test]
fn unknown_cells_of_a_complete_map_are_walls() {
    let mut g = rooms_in_a_row(2, 25);
    for (i, c) in g.cells().to_vec().into_iter().enumerate() {
        if c == Cell::Occupied {
            g.set(i % g.width(), i / g.width(), Cell::Unknown);
        }
    }
    let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
    assert_eq!(seg.rooms, 2);
}

#[test]
fn invalid_parameters_are_errors_naming_the_field() {
    let g = rooms_in_a_row(2, 25);
    let params = SegmentParams {
        min_room_area: -1.0,
        ..SegmentParams::default()
    };
    let err = segment_rooms(&g, &params).unwrap_err().to_string();
    assert!(err.contains("min_room_area"), "{err}");
    let mut params = SegmentParams::default();
    params.doors.max_width = f64::INFINITY;
    let err = segment_rooms(&g, &params).unwrap_err().to_string();
    assert!(err.contains("max_width"), "{err}");
}

#[test]
fn a_free_pocket_inside_furniture_joins_the_room_around_it() {
    // One 4 m room with a closed 1 m × 0.6 m desk outline whose inside is free.
    let mut g = OccupancyGrid::new(42, 42, 0.1, [0.0, 0.0], Cell::Occupied).unwrap();
    for col in 1..41 {
        for row in 1..41 {
            g.set(col, row, Cell::Free);
        }
    }
    for col in 15..27 {
        for row in 15..23 {
            let edge = col == 15 || col == 26 || row == 15 || row == 22;
            if edge {
                g.set(col, row, Cell::Occupied);
            }
        }
    }
    let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
    assert_eq!(seg.rooms, 1);
    assert_eq!(seg.labels[g.index(20, 18)], seg.labels[g.index(5, 5)]);
    // Forbid joining: the pocket (0.6 m²) is below the minimum room area, so it is no room.
    let params = SegmentParams {
        enclosure_area: 0.0,
        ..SegmentParams::default()
    };
    let seg = segment_rooms(&g, &params).unwrap();
    assert_eq!(seg.rooms, 1);
    assert_eq!(seg.labels[g.index(20, 18)], 0);
}

#[test]
fn a_closed_room_larger_than_the_enclosure_area_is_a_room_of_its_own() {
    // Two 2.5 m rooms with no opening between them.
    let mut g = rooms_in_a_row(2, 25);
    for row in 5..14 {
        g.set(26, row, Cell::Occupied);
    }
    let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
    assert_eq!(seg.rooms, 2);
    assert!(seg.doors.is_empty());
}

proptest::proptest! {
    /// On any grid (including unknown cells and degenerate sizes) segmentation succeeds,
    /// labels exactly the free cells it can (never a non-free one) and numbers rooms 1..=rooms.
    #[test]
    fn segmentation_of_any_grid_labels_only_free_cells(
        w in 1usize..40, h in 1usize..40, cells in proptest::collection::vec(0u8..6, 1600)
    ) {
        let mut g = OccupancyGrid::new(w, h, 0.1, [0.0, 0.0], Cell::Free).unwrap();
        for row in 0..h {
            for col in 0..w {
                let c = match cells[row * 40 + col] {
                    0 => Cell::Occupied,
                    1 => Cell::Unknown,
                    _ => Cell::Free,
                };
                g.set(col, row, c);
            }
        }
        let seg = segment_rooms(&g, &SegmentParams::default()).unwrap();
        let mut seen = vec![false; seg.rooms];
        for (i, &l) in seg.labels.iter().enumerate() {
            if g.cells()[i] != Cell::Free {
                proptest::prop_assert_eq!(l, 0);
            }
            proptest::prop_assert!(l as usize <= seg.rooms);
            if l > 0 {
                seen[l as usize - 1] = true;
            }
        }
        proptest::prop_assert!(seen.iter().all(|&s| s));
    }
}
