//! Tests of view planning in the agent's memory: cones, points, ranges and prices.

use super::*;
use crate::skills::testing;
use crate::trace::Event;
use crate::AgentConfig;
use avs_format::knowledge::Knowledge;
use avs_map::grid::OccupancyGrid;

#[test]
fn cones_planned_for_a_room_stand_in_it_and_are_kept_for_the_session() {
    let (config, k) = (AgentConfig::default(), testing::knowledge());
    let mut robot = testing::robot(testing::room(5.0, 4.0), [1.0, 2.0]);
    let mut mem = testing::memory(&config, &k, &mut robot);
    let room = mem.current_room().expect("a room");
    let mut sink = testing::sink();
    let mut run = testing::run(&mut sink);
    let cx = testing::ctx(&k, &config);
    let cam = avs_robot::Robot::camera(&robot);
    create_cones(
        cx,
        &mut mem,
        &cam,
        &mut run,
        "cerealbox",
        ConeLoc::Room(room.0),
    );
    let set = &mem.cones[&("cerealbox".to_string(), ConeLoc::Room(room.0))];
    assert!(!set.views.is_empty());
    assert!(set.views.len() <= config.max_cones);
    assert!(set.covered_share > 0.5, "{}", set.covered_share);
    for v in &set.views {
        assert_eq!(mem.room_at([v.pose[0], v.pose[1]]), Some(room));
        assert_eq!(v.zoom, 1.0, "the plan's cones are unzoomed");
    }
    // The points are the room's cells at the cereal box's search height.
    assert!(set
        .points
        .iter()
        .all(|p| (p[2] - (0.825 + 0.14)).abs() < 1e-9));
    let said = run.events.iter().any(|e| {
        matches!(e, Event::Observed { what } if what.starts_with(&format!("{} view cones for cerealbox", set.views.len())))
    });
    assert!(said, "{:?}", run.events);
}

/// A robot at (1, 2) in `grid` with the default settings, its memory after the first
/// survey, and the room it stands in.
struct InRoom {
    config: AgentConfig,
    k: Knowledge,
    mem: Memory,
    cam: Camera,
    room: ConeLoc,
}

fn in_room(grid: OccupancyGrid) -> InRoom {
    let (config, k) = (AgentConfig::default(), testing::knowledge());
    let mut robot = testing::robot(grid, [1.0, 2.0]);
    let mem = testing::memory(&config, &k, &mut robot);
    let room = ConeLoc::Room(mem.current_room().expect("a room").0);
    let cam = avs_robot::Robot::camera(&robot);
    InRoom {
        config,
        k,
        mem,
        cam,
        room,
    }
}

/// The price of a search of the room the robot stands in, for `class`.
fn price_in(grid: OccupancyGrid, class: &str) -> (Price, usize) {
    let r = in_room(grid);
    let cx = testing::ctx(&r.k, &r.config);
    let price = search_cost(cx, &r.mem, &r.cam, class, r.room).expect("views see the room");
    let (set, _) = next_cones(cx, &r.mem, &r.cam, class, r.room).expect("a known class");
    (price, set.views.len())
}

#[test]
fn a_search_is_priced_by_the_views_it_will_take_and_the_walk_between_them() {
    let config = AgentConfig::default();
    let per_view = config.process_cost / config.travel_cost_per_m;
    let (small, n_small) = price_in(testing::room(4.0, 4.0), "cerealbox");
    let (large, n_large) = price_in(testing::room(12.0, 4.0), "cerealbox");
    // Each view is processed once, and the views of a 12 m room stand on more than one spot.
    assert!(
        small.metres >= n_small as f64 * per_view - 1e-9,
        "{small:?}"
    );
    assert!(
        large.metres > n_large as f64 * per_view,
        "{large:?} {n_large}"
    );
    assert!(n_large > n_small, "{n_large} views vs {n_small}");
    assert!(large.metres > small.metres, "{large:?} vs {small:?}");
    for p in [small, large] {
        assert!(p.share > 0.5 && p.share <= 1.0, "{p:?}");
    }
    // A marker is seen from less than half the cereal box's distance: more views.
    let (marker, _) = price_in(testing::room(4.0, 4.0), "whiteboardmarker");
    assert!(marker.metres > small.metres, "{marker:?} vs {small:?}");
}

#[test]
fn a_room_searched_in_part_is_priced_for_the_points_not_looked_at_yet() {
    let InRoom {
        config,
        k,
        mut mem,
        cam,
        room,
    } = in_room(testing::room(12.0, 4.0));
    let cx = testing::ctx(&k, &config);
    let before = search_cost(cx, &mem, &cam, "cerealbox", room).expect("priced");
    // The western two thirds looked at once.
    let class = k.class("cerealbox").unwrap();
    let looked: BTreeMap<_, _> = location_points(cx, &mem, class, room)
        .into_iter()
        .filter(|p| p[0] < 8.0)
        .map(|p| (mem.point_key(p), 1))
        .collect();
    mem.looks.insert("cerealbox".into(), looked);
    let after = search_cost(cx, &mem, &cam, "cerealbox", room).expect("priced");
    assert!(after.metres < before.metres, "{after:?} vs {before:?}");
}

/// The zoom pipeline's measured marker: zoom 4 finds it from 1.0 to 1.73 m. Its whole
/// range counts (it already ends where half the looks find it), and the coverage's views
/// reach the floor of the room, 1.19 m below the camera, only with it.
#[test]
fn a_measured_range_counts_whole_and_reaches_a_marker_on_the_floor() {
    let InRoom {
        mut config,
        k,
        mem,
        cam,
        room,
    } = in_room(testing::room(5.0, 4.0));
    let ConeLoc::Room(r) = room else {
        unreachable!("a room")
    };
    let marker = crate::MeasuredSensing {
        class: "whiteboardmarker".into(),
        detection_range: [0.25, 0.71],
        ranges_by_zoom: vec![(1.0, [0.25, 0.71]), (2.0, [0.5, 0.86]), (4.0, [1.0, 1.73])],
        false_negative: 0.13,
        false_positive: 0.001,
        found_by_zoom: Vec::new(),
        repeat_correlation: 0.0,
    };
    config.measured_sensing = vec![marker];
    let floor_views = |config: &AgentConfig| {
        let cx = testing::ctx(&k, config);
        let class = k.class("whiteboardmarker").unwrap();
        let levels = range_levels(cx, class, &[1.0], cam.max_zoom);
        let points = room_points(cx, &mem, r, class, true);
        let floor: Vec<usize> = (0..points.len()).filter(|&i| points[i][2] < 0.05).collect();
        assert!(!floor.is_empty());
        let set = plan_cones(
            cx,
            &mem,
            &cam,
            "whiteboardmarker",
            room,
            Some(points),
            &[1.0],
        )
        .expect("a known class");
        let on_floor = set
            .cells
            .iter()
            .flatten()
            .filter(|i| floor.contains(i))
            .count();
        (levels, on_floor)
    };
    let (levels, on_floor) = floor_views(&config);
    assert_eq!(
        levels.last(),
        Some(&(
            4.0,
            DetectionRange {
                min: 1.0,
                max: 1.73
            }
        ))
    );
    assert!(on_floor > 0, "no view covers a point of the floor");
    // Cut to the nearer 80 % as a range from the knowledge is, no view reached the floor.
    let share = config.tuning.cover_range_share;
    config.measured_sensing[0].ranges_by_zoom[2].1[1] = 1.0 + share * 0.73;
    let (_, cut) = floor_views(&config);
    assert_eq!(cut, 0);
}

#[test]
fn a_room_not_known_yet_is_priced_as_an_empty_room_of_the_knowledges_size() {
    let config = AgentConfig::default();
    let mut k = testing::knowledge();
    let robot = testing::robot(testing::room(4.0, 4.0), [1.0, 2.0]);
    let cam = avs_robot::Robot::camera(&robot);
    let typical = |k: &Knowledge, class: &str| {
        typical_room_cost(testing::ctx(k, &config), &cam, class)
            .expect("priced")
            .metres
    };
    let small = typical(&k, "cerealbox");
    assert!(small > 0.0);
    assert!(typical(&k, "whiteboardmarker") > small);
    k.placeholder.room_area_m2 *= 4.0;
    assert!(typical(&k, "cerealbox") > small);
    // Any area a knowledge file may give is priced in bounded work: a hall's capped views
    // see a small share of it.
    k.placeholder.room_area_m2 = 1e9;
    let c = testing::ctx(&k, &config);
    let hall = typical_room_cost(c, &cam, "cerealbox").expect("priced");
    assert!(hall.metres.is_finite() && hall.share < 1e-6, "{hall:?}");
    // About what the same room costs when known: an empty 4 m × 3 m room (12 m²).
    let (known, _) = price_in(testing::room(4.0, 3.0), "cerealbox");
    assert!(
        (known.metres - small).abs() <= 0.5 * known.metres,
        "{known:?} vs {small}"
    );
}

#[test]
fn a_price_is_computed_again_only_when_what_it_depends_on_changes() {
    let InRoom {
        config,
        k,
        mut mem,
        cam,
        room,
    } = in_room(testing::room(8.0, 4.0));
    let cx = testing::ctx(&k, &config);
    price_searches(cx, &mut mem, &cam, "cerealbox");
    let entry = ("cerealbox".to_string(), room);
    let priced = mem.search_costs[&entry].1.expect("the room is seen");
    assert!(mem.typical_costs["cerealbox"].is_some());
    // The landmark classes a cereal box lies on or in are priced too.
    assert!(mem.search_costs.contains_key(&("table".to_string(), room)));
    // A stand-in price survives a pricing with nothing changed...
    let stand_in = Price {
        metres: -1.0,
        share: 0.0,
    };
    mem.search_costs.get_mut(&entry).unwrap().1 = Some(stand_in);
    price_searches(cx, &mut mem, &cam, "cerealbox");
    assert_eq!(mem.search_costs[&entry].1, Some(stand_in));
    // ...and not one after a look at the room's points.
    let class = k.class("cerealbox").unwrap();
    let p = location_points(cx, &mem, class, room)[0];
    let key = mem.point_key(p);
    mem.looks
        .entry("cerealbox".into())
        .or_default()
        .insert(key, 1);
    price_searches(cx, &mut mem, &cam, "cerealbox");
    let again = mem.search_costs[&entry].1.expect("priced again");
    assert!(
        again.metres > 0.0 && again.metres <= priced.metres + 1e-9,
        "{again:?}"
    );
}

/// A 5 m × 4 m room with a table whose edge the laser saw and whose top it could not
/// (the cells under it unknown, as a real scan leaves them): a search of the room looks
/// at the table's top too, not only at the floor around it, whether or not the look
/// around reported the table (a table it missed still has a top: a pocket of the room).
#[test]
fn a_room_search_covers_the_tops_of_its_furniture_known_or_not() {
    let (config, k) = (AgentConfig::default(), testing::knowledge());
    let mut grid = testing::room(5.0, 4.0);
    // The table: 1.2 m × 0.8 m centred at (3.0, 2.0) on 0.1 m cells, its rim occupied.
    let (c0, c1, r0, r1) = (24, 35, 16, 23);
    for row in r0..=r1 {
        for col in c0..=c1 {
            let rim = row == r0 || row == r1 || col == c0 || col == c1;
            grid.set(col, row, if rim { Cell::Occupied } else { Cell::Unknown });
        }
    }
    let mut robot = testing::robot(grid, [1.0, 2.0]);
    let mut mem = testing::memory(&config, &k, &mut robot);
    let room = mem.current_room().expect("a room");
    assert_eq!(
        mem.pockets.len(),
        1,
        "the table's inside is the room's one pocket"
    );
    let cx = testing::ctx(&k, &config);
    let class = k.class("cerealbox").unwrap().clone();
    let on_table = |pts: &[[f64; 3]]| -> Vec<[f64; 3]> {
        pts.iter()
            .filter(|p| (p[0] - 3.0).abs() < 0.45 && (p[1] - 2.0).abs() < 0.25)
            .copied()
            .collect()
    };
    // No landmark known: the pocket's cells are the room's, at the surfaces' heights.
    let top = on_table(&room_points(cx, &mem, room.0, &class, false));
    assert!(!top.is_empty(), "no point on the unseen table's top");
    assert!(top.iter().all(|p| p[2] > 0.75));
    // The coverage's heights include the floor: not inside the table.
    let cover = on_table(&room_points(cx, &mem, room.0, &class, true));
    assert!(
        !cover.is_empty() && cover.iter().all(|p| p[2] > 0.75),
        "{cover:?}"
    );
    // And a view sees them over the table's edge.
    let cam = avs_robot::Camera::default();
    let set = plan_cones(
        cx,
        &mem,
        &cam,
        "cerealbox",
        ConeLoc::Room(room.0),
        Some(top.clone()),
        &[1.0],
    )
    .expect("a known class");
    assert!(set.covered_share > 0.99, "{}", set.covered_share);
    // Once the table is known, its top is looked at as before, each point once.
    let place = mem.current_place().expect("a place");
    let lm = mem.wm.found_landmark(place, "table").unwrap();
    mem.objects.push(crate::memory::Known {
        class: "table".into(),
        pos: avs_robot::Point3 {
            x: 3.0,
            y: 2.0,
            z: 0.0,
        },
        place,
        landmark: Some(lm),
        on: None,
        counted: true,
        confidence: 1.0,
    });
    let pts = room_points(cx, &mem, room.0, &class, false);
    assert_eq!(on_table(&pts), top);
}

/// Two 4 m × 4 m rooms side by side, a 0.2 m wall between them with a 1 m door in its
/// middle, and a counter (its top a surface) against the wall on the east side. The
/// disc its top may occupy reaches through the wall into the west room; a search on the
/// counter still looks from the east room only, the one whose floor surrounds it.
#[test]
fn a_search_on_a_counter_against_a_wall_looks_from_the_counters_own_room() {
    let (config, k) = (AgentConfig::default(), testing::knowledge());
    let mut grid = testing::room(8.2, 4.0);
    for row in (1..15).chain(25..39) {
        for col in 40..42 {
            grid.set(col, row, Cell::Occupied);
        }
    }
    // The counter's footprint, 0.6 m deep along the wall's east face, 1.2 m long.
    for row in 27..39 {
        for col in 42..48 {
            grid.set(col, row, Cell::Occupied);
        }
    }
    let mut robot = testing::robot(grid, [1.0, 2.0]);
    let mut mem = testing::memory(&config, &k, &mut robot);
    let cx = testing::ctx(&k, &config);
    let mut body = crate::body::Body::new(&mut robot);
    // Walk through the door into the east room and look at the counter from there.
    body.go_to(&mut mem, [6.0, 2.0]).unwrap().unwrap();
    body.go_to(&mut mem, [6.5, 1.0]).unwrap().unwrap();
    mem.sync().unwrap();
    let east = mem.current_room().expect("the east room");
    let west = mem.room_at([1.0, 2.0]).expect("the west room");
    assert_ne!(east, west, "the door splits the floor into two rooms");
    let place = mem.current_place().expect("a place");
    mem.objects.push(crate::memory::Known {
        class: "counter".into(),
        pos: avs_robot::Point3 {
            x: 4.5,
            y: 3.3,
            z: 0.0,
        },
        place,
        landmark: None,
        on: None,
        counted: true,
        confidence: 1.0,
    });
    let k_counter = mem.objects.len() - 1;
    let cam = avs_robot::Robot::camera(&robot);
    let set = plan_cones(
        cx,
        &mem,
        &cam,
        "cerealbox",
        ConeLoc::On(k_counter),
        None,
        &[1.0],
    )
    .expect("cones on the counter");
    assert!(!set.views.is_empty());
    for v in &set.views {
        assert_eq!(
            mem.room_at([v.pose[0], v.pose[1]]),
            Some(east),
            "a view from {:?}",
            v.pose
        );
    }
}
