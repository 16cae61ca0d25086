//! The conceptual map while exploring the default environment (`domains/environments/office.yaml`,
//! after Aydemir et al. 2011 §IV): a corridor along the bottom, office1, kitchen and office2
//! above it, each joined to the corridor by a door. The topology is built by hand in the order
//! the robot discovers it; the lead's end-to-end test does the same from the real place map.

use avs_concepts::{
    ConceptualMap, Location, PlaceId, Placeholder, PlaceholderId, Relation, RoomId,
};
use avs_format::knowledge::Knowledge;

const CORRIDOR: RoomId = RoomId(1);
const OFFICE1: RoomId = RoomId(2);
const KITCHEN: RoomId = RoomId(3);

fn office_knowledge() -> Knowledge {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../knowledge/office.yaml");
    avs_format::load_yaml(std::path::Path::new(path)).expect("knowledge/office.yaml loads")
}

fn observe_place(map: &mut ConceptualMap, room: RoomId, place: u64, props: [&str; 3]) {
    for (name, value) in ["shape", "size", "appearance"].into_iter().zip(props) {
        map.observe_property(room, PlaceId(place), name, value)
            .unwrap();
    }
}

fn most_likely(map: &ConceptualMap, room: RoomId) -> String {
    let d = map.category_distribution(room).unwrap();
    let k = (0..d.len()).max_by(|a, b| d[*a].total_cmp(&d[*b])).unwrap();
    map.model().categories[k].clone()
}

#[test]
fn exploring_the_default_environment_recognises_the_kitchen_and_predicts_rooms_behind_doors() {
    let mut map = ConceptualMap::new("office.yaml", &office_knowledge()).unwrap();

    // The corridor, seen from its west end and two more places.
    map.add_room(CORRIDOR).unwrap();
    observe_place(
        &mut map,
        CORRIDOR,
        1,
        ["elongated", "large", "corridor_like"],
    );
    observe_place(
        &mut map,
        CORRIDOR,
        2,
        ["elongated", "large", "corridor_like"],
    );
    assert_eq!(most_likely(&map, CORRIDOR), "corridor");

    // Two placeholders: one behind the door to office1, one at the corridor's dead end.
    let behind_door = PlaceholderId(10);
    let dead_end = PlaceholderId(11);
    map.set_placeholder(
        behind_door,
        Placeholder {
            room: CORRIDOR,
            open_area_m2: 9.0,
            door_distance_m: Some(0.3),
        },
    )
    .unwrap();
    map.set_placeholder(
        dead_end,
        Placeholder {
            room: CORRIDOR,
            open_area_m2: 0.6,
            door_distance_m: None,
        },
    )
    .unwrap();
    let (pd, pe) = (
        map.p_new_room(behind_door).unwrap(),
        map.p_new_room(dead_end).unwrap(),
    );
    assert!(pd > pe, "door placeholder {pd} should beat dead end {pe}");
    assert!(pd > 0.5 && pe < 0.2, "door {pd}, dead end {pe}");
    for cat in ["kitchen", "office"] {
        assert!(
            map.p_category_placeholder(behind_door, cat).unwrap()
                > map.p_category_placeholder(dead_end, cat).unwrap()
        );
    }
    let h = map.placeholder_hypotheses(behind_door).unwrap();
    assert!((h.probabilities.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    // The placeholder behind the door predicts a kitchen with some probability, which is what
    // makes the planner assume it (the paper's run enters office1 first for this reason).
    let p_kitchen_behind = map.p_category_placeholder(behind_door, "kitchen").unwrap();
    assert!(p_kitchen_behind > 0.05, "{p_kitchen_behind}");

    // office1: desk and shelf seen.
    map.remove_placeholder(behind_door).unwrap();
    map.add_room(OFFICE1).unwrap();
    map.add_adjacency(CORRIDOR, OFFICE1).unwrap();
    observe_place(&mut map, OFFICE1, 3, ["square", "small", "office_like"]);
    map.observe_objects(OFFICE1, PlaceId(3), "desk", 1, 1.0)
        .unwrap();
    map.observe_objects(OFFICE1, PlaceId(3), "shelf", 1, 1.0)
        .unwrap();
    assert_eq!(most_likely(&map, OFFICE1), "office");

    // The kitchen: first its places, then its counter and table.
    map.add_room(KITCHEN).unwrap();
    map.add_adjacency(CORRIDOR, KITCHEN).unwrap();
    observe_place(&mut map, KITCHEN, 4, ["square", "medium", "kitchen_like"]);
    let before = map.p_category(KITCHEN, "kitchen").unwrap();
    assert!(
        before < 0.8,
        "before the counter and table P(kitchen) = {before}"
    );
    map.observe_objects(KITCHEN, PlaceId(4), "counter", 1, 1.0)
        .unwrap();
    let mid = map.p_category(KITCHEN, "kitchen").unwrap();
    map.observe_objects(KITCHEN, PlaceId(4), "table", 1, 1.0)
        .unwrap();
    let after = map.p_category(KITCHEN, "kitchen").unwrap();
    assert!(before < mid && mid < after, "{before} {mid} {after}");
    assert!(after > 0.8, "after counter and table P(kitchen) = {after}");
    eprintln!(
        "P(kitchen): {before:.3} -> {mid:.3} (counter) -> {after:.3} (table); \
         P(new room): behind door {pd:.3}, dead end {pe:.3}"
    );
    assert!(map.stats().converged);

    // Where is the cereal? On the kitchen table rather than on the office desk.
    let table = map.add_landmark(KITCHEN, "table").unwrap();
    let desk = map.add_landmark(OFFICE1, "desk").unwrap();
    let on_table = map
        .p_object_at(Location::Landmark(table, Relation::On), "cerealbox")
        .unwrap();
    let on_desk = map
        .p_object_at(Location::Landmark(desk, Relation::On), "cerealbox")
        .unwrap();
    assert!(on_table > 5.0 * on_desk, "table {on_table}, desk {on_desk}");
    // The room holds the table, so the room is at least as likely (rates add over sub-locations).
    let in_kitchen = map
        .p_object_at(Location::Room(KITCHEN), "cerealbox")
        .unwrap();
    assert!(in_kitchen > on_table);

    // Searching the table without success lowers both P(cereal on it) and, a little, P(kitchen).
    map.mark_searched(Location::Landmark(table, Relation::On), "cerealbox", 0.8)
        .unwrap();
    let on_table_after = map
        .p_object_at(Location::Landmark(table, Relation::On), "cerealbox")
        .unwrap();
    assert!(
        on_table_after < 0.5 * on_table,
        "{on_table} -> {on_table_after}"
    );
    assert!(map.p_category(KITCHEN, "kitchen").unwrap() < after);
}

/// A single-category knowledge makes the category certain, so eq. 1–2 and thinning can be
/// checked against their closed forms.
fn one_category() -> Knowledge {
    avs_format::load_yaml_str(
        "one.yaml",
        r#"
kind: knowledge
name: one
room_categories: [kitchen]
object_classes:
  - { name: table, size: [1, 1, 1], detection_range: [0.5, 4], recognition_range: [0.5, 3], landmark: true }
  - { name: cup, size: [0.1, 0.1, 0.1], detection_range: [0.5, 2], recognition_range: [0.5, 1] }
object_rates: { cup: [0.7] }
landmark_rates:
  - { object: cup, relation: on, landmark: table, rates: [0.5] }
"#,
    )
    .unwrap()
}

#[test]
fn object_probability_follows_the_poisson_model_and_rates_add_over_sub_locations() {
    let mut map = ConceptualMap::new("one.yaml", &one_category()).unwrap();
    map.add_room(RoomId(0)).unwrap();
    let t = map.add_landmark(RoomId(0), "table").unwrap();
    let on = Location::Landmark(t, Relation::On);
    let p_on = map.p_object_at(on, "cup").unwrap();
    assert!((p_on - (1.0 - (-0.5f64).exp())).abs() < 1e-12);
    let p_room = map.p_object_at(Location::Room(RoomId(0)), "cup").unwrap();
    assert!((p_room - (1.0 - (-1.2f64).exp())).abs() < 1e-12);
    // A failed search with q = 0.6 thins the rate to 0.4 λ.
    map.mark_searched(on, "cup", 0.6).unwrap();
    let p_on = map.p_object_at(on, "cup").unwrap();
    assert!((p_on - (1.0 - (-0.5f64 * 0.4).exp())).abs() < 1e-12);
    // A certain search (q = 1) empties the location.
    map.mark_searched(on, "cup", 1.0).unwrap();
    assert!(map.p_object_at(on, "cup").unwrap().abs() < 1e-15);
    assert!(map.mark_searched(on, "cup", 1.5).is_err());
}

#[test]
fn warm_started_updates_agree_with_a_map_built_in_one_go() {
    let k = office_knowledge();
    let mut a = ConceptualMap::new("office.yaml", &k).unwrap();
    // a ring of rooms (a loopy graph), built event by event
    for r in 0..6 {
        a.add_room(RoomId(r)).unwrap();
    }
    for r in 0..6 {
        a.add_adjacency(RoomId(r), RoomId((r + 1) % 6)).unwrap();
    }
    a.observe_property(RoomId(0), PlaceId(0), "shape", "elongated")
        .unwrap();
    a.observe_objects(RoomId(2), PlaceId(1), "counter", 1, 0.5)
        .unwrap();
    a.observe_objects(RoomId(4), PlaceId(2), "desk", 2, 1.0)
        .unwrap();
    // the same final state with the observations first and the doors last
    let mut b = ConceptualMap::new("office.yaml", &k).unwrap();
    for r in 0..6 {
        b.add_room(RoomId(r)).unwrap();
    }
    b.observe_objects(RoomId(4), PlaceId(2), "desk", 2, 1.0)
        .unwrap();
    b.observe_objects(RoomId(2), PlaceId(1), "counter", 1, 0.5)
        .unwrap();
    b.observe_property(RoomId(0), PlaceId(0), "shape", "elongated")
        .unwrap();
    for r in (0..6).rev() {
        b.add_adjacency(RoomId(r), RoomId((r + 1) % 6)).unwrap();
    }
    for r in 0..6 {
        let (x, y) = (
            a.category_distribution(RoomId(r)).unwrap(),
            b.category_distribution(RoomId(r)).unwrap(),
        );
        for (p, q) in x.iter().zip(&y) {
            // the map converges to within ~5e-7 at its default message tolerance 1e-7
            assert!((p - q).abs() < 1e-5, "room {r}: {x:?} vs {y:?}");
        }
    }
}

#[test]
fn merging_and_splitting_rooms_moves_their_evidence() {
    let mut map = ConceptualMap::new("office.yaml", &office_knowledge()).unwrap();
    map.add_room(RoomId(1)).unwrap();
    map.add_room(RoomId(2)).unwrap();
    map.observe_objects(RoomId(2), PlaceId(20), "counter", 1, 1.0)
        .unwrap();
    map.observe_objects(RoomId(2), PlaceId(21), "table", 1, 1.0)
        .unwrap();
    let kitchen2 = map.p_category(RoomId(2), "kitchen").unwrap();
    let kitchen1 = map.p_category(RoomId(1), "kitchen").unwrap();
    assert!(kitchen2 > kitchen1);
    // The door between them was wrong: one room.
    map.merge_rooms(RoomId(1), RoomId(2)).unwrap();
    assert!(map.category_distribution(RoomId(2)).is_err());
    assert!((map.p_category(RoomId(1), "kitchen").unwrap() - kitchen2).abs() < 1e-9);
    // A door found after all: the counter's place moves to a new room.
    map.split_room(RoomId(1), RoomId(3), &[PlaceId(20)], &[])
        .unwrap();
    assert!(
        map.p_category(RoomId(3), "kitchen").unwrap()
            > map.p_category(RoomId(1), "kitchen").unwrap()
    );
}

#[test]
fn bad_input_is_a_clear_error() {
    let mut map = ConceptualMap::new("office.yaml", &office_knowledge()).unwrap();
    map.add_room(RoomId(1)).unwrap();
    let e = map
        .observe_objects(RoomId(1), PlaceId(0), "unicorn", 1, 1.0)
        .unwrap_err();
    assert!(
        e.to_string().contains("unicorn") && e.to_string().contains("cerealbox"),
        "{e}"
    );
    assert!(map
        .observe_property(RoomId(1), PlaceId(0), "shape", "round")
        .is_err());
    assert!(map
        .observe_objects(RoomId(9), PlaceId(0), "mug", 1, 1.0)
        .is_err());
    assert!(map
        .observe_objects(RoomId(1), PlaceId(0), "mug", 1, f64::NAN)
        .is_err());
    assert!(map.add_landmark(RoomId(1), "mug").is_err());
    let bad = Placeholder {
        room: RoomId(1),
        open_area_m2: f64::NAN,
        door_distance_m: None,
    };
    assert!(map.set_placeholder(PlaceholderId(0), bad).is_err());
    let mut k = office_knowledge();
    k.category_prior = Some(vec![0.5, 0.5, 0.5]);
    assert!(ConceptualMap::new("office.yaml", &k).is_err());
}

#[test]
fn the_map_engine_agrees_with_factor_graph_bp_and_with_exact_inference_on_a_tree() {
    use avs_concepts::bp::{run_bp, BpOptions, Updates};
    let mut map = ConceptualMap::new("office.yaml", &office_knowledge()).unwrap();
    map.set_bp_options(avs_concepts::MapBpOptions {
        tol: 1e-12,
        ..Default::default()
    })
    .unwrap();
    // a loopy 3 × 3 grid of rooms with mixed evidence
    for r in 0..9 {
        map.add_room(RoomId(r)).unwrap();
    }
    map.observe_objects(RoomId(0), PlaceId(0), "counter", 1, 1.0)
        .unwrap();
    map.observe_objects(RoomId(4), PlaceId(1), "desk", 2, 1.0)
        .unwrap();
    map.observe_property(RoomId(8), PlaceId(2), "shape", "elongated")
        .unwrap();
    for r in 0..9 {
        if r % 3 != 2 {
            map.add_adjacency(RoomId(r), RoomId(r + 1)).unwrap();
        }
        if r < 6 {
            map.add_adjacency(RoomId(r), RoomId(r + 3)).unwrap();
        }
    }
    let (ids, g) = map.factor_graph().unwrap();
    let opts = BpOptions {
        updates: Updates::Parall,
        tol: 1e-12,
        ..BpOptions::default()
    };
    let bp = run_bp(&g, &opts, None).unwrap();
    assert!(bp.converged);
    for (i, r) in ids.iter().enumerate() {
        let ours = map.category_distribution(*r).unwrap();
        for (a, b) in ours.iter().zip(&bp.marginals[i]) {
            assert!(
                (a - b).abs() < 1e-7,
                "room {}: {ours:?} vs {:?}",
                r.0,
                bp.marginals[i]
            );
        }
    }
    // Remove the loops (keep a spanning tree): now BP must be exact.
    for r in [1u64, 4, 2, 5] {
        map.remove_adjacency(RoomId(r), RoomId(r + 3)).unwrap();
    }
    let (ids, g) = map.factor_graph().unwrap();
    let ex = avs_concepts::exact_marginals(&g, 1 << 20).unwrap();
    for (i, r) in ids.iter().enumerate() {
        let ours = map.category_distribution(*r).unwrap();
        for (a, b) in ours.iter().zip(&ex[i]) {
            assert!(
                (a - b).abs() < 1e-7,
                "room {}: {ours:?} vs exact {:?}",
                r.0,
                ex[i]
            );
        }
    }
}

#[test]
fn when_bp_does_not_converge_small_maps_fall_back_to_exact_inference() {
    let mut map = ConceptualMap::new("office.yaml", &office_knowledge()).unwrap();
    for r in 0..4 {
        map.add_room(RoomId(r)).unwrap();
    }
    for r in 0..4 {
        map.add_adjacency(RoomId(r), RoomId((r + 1) % 4)).unwrap();
    }
    map.observe_objects(RoomId(0), PlaceId(0), "counter", 1, 1.0)
        .unwrap();
    assert!(!map.uses_exact_fallback());
    // one sweep and a zero tolerance: BP cannot report convergence
    map.set_bp_options(avs_concepts::MapBpOptions {
        tol: 0.0,
        maxiter: 1,
        damping: 0.0,
    })
    .unwrap();
    assert!(!map.stats().converged);
    assert!(map.uses_exact_fallback());
    let (ids, g) = map.factor_graph().unwrap();
    let ex = avs_concepts::exact_marginals(&g, 1 << 20).unwrap();
    for (i, r) in ids.iter().enumerate() {
        assert_eq!(map.category_distribution(*r).unwrap(), ex[i]);
    }
}

/// A second look around a room counts only the instances every earlier look missed: the
/// instances first found by look i are Poisson with rate s_i · p_d · λ_k · Π_{j<i}(1 − s_j p_d)
/// (crate docs, *Object counts*). Computed here by hand for one room: a counter seen by the
/// first look, none new in the second. As two fresh Poisson draws the empty second look would
/// weigh as much as the first.
#[test]
fn a_second_look_counts_only_what_the_first_missed() {
    let k = office_knowledge();
    let mut map = ConceptualMap::new("office.yaml", &k).unwrap();
    map.add_room(KITCHEN).unwrap();
    let (s1, s2) = (0.8, 0.6);
    map.observe_objects(KITCHEN, PlaceId(1), "counter", 1, s1)
        .unwrap();
    let after_first = map.category_distribution(KITCHEN).unwrap();
    map.observe_objects(KITCHEN, PlaceId(2), "counter", 0, s2)
        .unwrap();
    let after_second = map.category_distribution(KITCHEN).unwrap();

    let m = map.model();
    let (pd, fp, prior) = (m.count_detection, m.count_false_positive, m.prior.clone());
    let c = m.classes.iter().position(|c| c == "counter").unwrap();
    let counter = m.room_rates[c].clone();
    let kitchen = m.categories.iter().position(|c| c == "kitchen").unwrap();
    // `thin`: whether a look's rate is thinned by the looks before it.
    let expect = |looks: &[(u32, f64)], thin: bool| -> Vec<f64> {
        let mut post: Vec<f64> = (0..prior.len())
            .map(|c| {
                let mut unseen = 1.0;
                let mut lik = prior[c];
                for &(n, s) in looks {
                    let rate = s * (pd * counter[c] * unseen + fp);
                    lik *= rate.powi(n as i32) * (-rate).exp(); // n ≤ 1: n! = 1
                    if thin {
                        unseen *= 1.0 - s * pd;
                    }
                }
                lik
            })
            .collect();
        let z: f64 = post.iter().sum();
        post.iter_mut().for_each(|p| *p /= z);
        post
    };
    for (got, want) in [
        (&after_first, expect(&[(1, s1)], true)),
        (&after_second, expect(&[(1, s1), (0, s2)], true)),
    ] {
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-9, "{got:?} vs {want:?}");
        }
    }
    // The empty second look still speaks against the kitchen, but less than a fresh draw.
    let fresh = expect(&[(1, s1), (0, s2)], false);
    assert!(after_second[kitchen] < after_first[kitchen]);
    assert!(
        after_second[kitchen] > fresh[kitchen] + 0.01,
        "{after_second:?} vs {fresh:?}"
    );
}

#[test]
fn a_rooms_rate_counts_the_landmarks_not_found_yet() {
    // Tables are a Poisson population too (μ = 2 per kitchen), each holding Poisson(0.5) cups:
    // the cups on tables nobody has seen add μ (1 − e^{−0.5}) (compound Poisson).
    let mut k = one_category();
    k.object_rates.insert("table".into(), vec![2.0]);
    let mut map = ConceptualMap::new("one.yaml", &k).unwrap();
    let room = Location::Room(RoomId(0));
    map.add_room(RoomId(0)).unwrap();
    let rate = |map: &ConceptualMap| map.rates(room, "cup").unwrap()[0];
    // Off by default: the room's own rate only.
    assert!(!map.unfound_landmarks());
    assert!((rate(&map) - 0.7).abs() < 1e-12, "{}", rate(&map));
    map.set_unfound_landmarks(true);
    let unseen = 2.0 * (1.0 - (-0.5f64).exp());
    assert!(
        (rate(&map) - (0.7 + unseen)).abs() < 1e-12,
        "{}",
        rate(&map)
    );
    let cup = map.model().class("cup").unwrap();
    assert!((map.model().unseen_room_rates(cup)[0] - rate(&map)).abs() < 1e-12);
    // A look over the whole room counts one table: the tables it missed are a share
    // (1 − p_d) of the population; the one it saw is a landmark location of its own.
    let p_d = map.model().count_detection;
    map.observe_objects(RoomId(0), PlaceId(1), "table", 1, 1.0)
        .unwrap();
    map.add_landmark(RoomId(0), "table").unwrap();
    let want = 0.7 + 0.5 + (1.0 - p_d) * unseen;
    assert!(
        (rate(&map) - want).abs() < 1e-12,
        "{} vs {want}",
        rate(&map)
    );
    // A failed search of the room thins every part alike.
    map.mark_searched(room, "cup", 0.6).unwrap();
    assert!(
        (rate(&map) - 0.4 * want).abs() < 1e-12,
        "{} vs {}",
        rate(&map),
        0.4 * want
    );
}
