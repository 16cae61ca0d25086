//! Look-alikes on generated floors (`GenerateParams::lookalikes_per_room`): at rate 0 a floor
//! is byte for byte the floor generated before look-alikes existed (but for the targets' yaws,
//! drawn since from a stream of their own); at the default rate they only append distractors,
//! which appear on many floors, and leave the rest unchanged.

use avs_format::environment::{Environment, ObjectRole};
use avs_format::knowledge::Knowledge;
use avs_sim::generate::{
    generate, GenerateParams, Placement, DEFAULT_LOOKALIKES_PER_ROOM, MAX_LOOKALIKES_PER_ROOM,
};
use avs_sim::World;
use std::path::Path;

fn knowledge(name: &str) -> Knowledge {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../knowledge/{name}.yaml"));
    avs_format::load_yaml(&p).expect("shipped knowledge loads")
}

/// 64-bit FNV-1a of a text.
fn fnv(s: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in s.bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

fn params(seed: u64, rooms: usize, ensure: Option<&str>, placement: Placement) -> GenerateParams {
    GenerateParams {
        seed,
        rooms,
        ensure_class: ensure.map(String::from),
        placement,
        lookalikes_per_room: 0.0,
    }
}

/// A floor generated before the look-alike knob existed: its parameters and the FNV-1a hash
/// and length of its YAML.
struct Golden {
    knowledge: &'static str,
    seed: u64,
    rooms: usize,
    ensure: Option<&'static str>,
    placement: Placement,
    hash: u64,
    len: usize,
}

const fn golden(
    knowledge: &'static str,
    seed: u64,
    rooms: usize,
    ensure: Option<&'static str>,
    placement: Placement,
    hash: u64,
    len: usize,
) -> Golden {
    Golden {
        knowledge,
        seed,
        rooms,
        ensure,
        placement,
        hash,
        len,
    }
}

#[test]
fn lookalikes_at_zero_leave_the_floor_byte_identical_to_before_lookalikes_but_for_target_yaws() {
    use Placement::{AsKnowledge, Unlikely};
    // Measured with the generator of commit 6fc4378, before look-alikes (and before targets
    // were turned: their yaw is set back to that generator's 0 below).
    let floors = [
        golden("office", 0, 4, None, AsKnowledge, 0xdb7dfd8e7c3e57ce, 14826),
        golden("office", 7, 5, None, AsKnowledge, 0xbebb94d5bbfa0496, 17307),
        golden(
            "office",
            3,
            6,
            Some("cerealbox"),
            AsKnowledge,
            0x7774536cdd7c450e,
            23227,
        ),
        golden(
            "office",
            11,
            3,
            Some("mug"),
            Unlikely,
            0x0104e4b3c3a04ba6,
            11518,
        ),
        golden(
            "office",
            42,
            8,
            Some("stapler"),
            AsKnowledge,
            0x2b851a0f37de1e9f,
            29650,
        ),
        golden("home", 0, 4, None, AsKnowledge, 0xa16e423469ff8ae7, 14271),
        golden("home", 7, 5, None, AsKnowledge, 0x0dcd4e7df766fe7f, 16353),
        golden(
            "home",
            3,
            6,
            Some("cerealbox"),
            AsKnowledge,
            0x26edfa6bedde6e46,
            22687,
        ),
        golden(
            "home",
            11,
            3,
            Some("mug"),
            Unlikely,
            0x2cf039a4465343a4,
            10727,
        ),
    ];
    for g in floors {
        let p = params(g.seed, g.rooms, g.ensure, g.placement);
        let mut env = generate(&knowledge(g.knowledge), &p).unwrap();
        for o in env
            .objects
            .iter_mut()
            .filter(|o| o.role == ObjectRole::Target)
        {
            o.pose.yaw_deg = 0.0;
        }
        let yaml = serde_yaml::to_string(&env).unwrap();
        assert_eq!(
            (fnv(&yaml), yaml.len()),
            (g.hash, g.len),
            "{} seed {}, {} rooms, {:?} {:?}",
            g.knowledge,
            g.seed,
            g.rooms,
            g.ensure,
            g.placement
        );
    }
}

/// `env` without its look-alikes, serialised.
fn without_lookalikes(env: &Environment, before: usize) -> String {
    let mut env = env.clone();
    env.objects.truncate(before);
    serde_yaml::to_string(&env).unwrap()
}

#[test]
fn default_rate_appends_distractors_on_many_floors_and_leaves_the_rest_unchanged() {
    assert_eq!(
        GenerateParams::default().lookalikes_per_room,
        DEFAULT_LOOKALIKES_PER_ROOM
    );
    let k = knowledge("office");
    let (mut floors_with, mut total, mut yaws) = (0, 0, Vec::new());
    let mut on_landmark = 0;
    for seed in 0..50u64 {
        let plain = params(seed, 4, Some("cerealbox"), Placement::AsKnowledge);
        let with = GenerateParams {
            lookalikes_per_room: DEFAULT_LOOKALIKES_PER_ROOM,
            ..plain.clone()
        };
        let a = generate(&k, &plain).unwrap();
        let b = generate(&k, &with).unwrap();
        let n = a.objects.len();
        assert_eq!(
            without_lookalikes(&b, n),
            serde_yaml::to_string(&a).unwrap(),
            "seed {seed}: the floor besides its look-alikes changed"
        );
        let added = &b.objects[n..];
        for o in added {
            assert_eq!(o.role, ObjectRole::Distractor, "seed {seed}: {}", o.id);
            let class = k.class(&o.class).unwrap();
            assert!(!class.landmark && o.class != "cerealbox", "{}", o.class);
            assert_ne!(o.room, "corridor1", "look-alikes go in rooms");
            on_landmark += usize::from(o.on.is_some());
            yaws.push(o.pose.yaw_deg);
        }
        floors_with += usize::from(!added.is_empty());
        total += added.len();
        if seed < 10 {
            World::new(b, Path::new(".")).expect("a floor with look-alikes builds");
        }
    }
    eprintln!(
        "{floors_with} of 50 floors have look-alikes, {total} in all, {on_landmark} on furniture"
    );
    // Poisson(0.5) per room over 4 rooms: no look-alike on e^-2 = 14 % of floors; about 100 in
    // all, fewer when one does not fit.
    assert!((30..50).contains(&floors_with), "{floors_with}");
    assert!((60..=130).contains(&total), "{total}");
    assert!(
        on_landmark > 0 && on_landmark < total,
        "{on_landmark} of {total}"
    );
    // Random yaws, not all alike.
    let spread = yaws.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - yaws.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(spread > 180.0, "{spread}");
    assert!(yaws.iter().all(|y| (0.0..360.0).contains(y)));
}

#[test]
fn lookalikes_are_deterministic_and_never_of_the_ensured_class() {
    let k = knowledge("office");
    for target in ["mug", "stapler"] {
        let p = GenerateParams {
            seed: 5,
            rooms: 8,
            ensure_class: Some(target.into()),
            placement: Placement::AsKnowledge,
            lookalikes_per_room: 2.0,
        };
        let a = generate(&k, &p).unwrap();
        assert_eq!(a, generate(&k, &p).unwrap());
        let fakes: Vec<_> = a
            .objects
            .iter()
            .filter(|o| o.role == ObjectRole::Distractor)
            .collect();
        assert!(fakes.len() > 4, "{}", fakes.len());
        assert!(fakes.iter().all(|o| o.class != target), "{target}");
    }
}

#[test]
fn lookalike_rate_out_of_range_is_rejected_with_the_field_named() {
    let k = knowledge("office");
    for bad in [-0.1, f64::NAN, MAX_LOOKALIKES_PER_ROOM + 1.0] {
        let p = GenerateParams {
            lookalikes_per_room: bad,
            ..GenerateParams::default()
        };
        let e = generate(&k, &p).unwrap_err().to_string();
        assert!(e.contains("lookalikes_per_room"), "{e}");
    }
}

#[test]
fn targets_are_turned_any_way_from_a_stream_of_their_own() {
    let k = knowledge("office");
    let mut yaws = Vec::new();
    for seed in 0..20u64 {
        let plain = params(seed, 4, Some("whiteboardmarker"), Placement::AsKnowledge);
        let with = GenerateParams {
            lookalikes_per_room: 2.0,
            ..plain.clone()
        };
        let a = generate(&k, &plain).unwrap();
        let b = generate(&k, &with).unwrap();
        let targets = |e: &Environment| -> Vec<(String, f64)> {
            e.objects
                .iter()
                .filter(|o| o.role == ObjectRole::Target)
                .map(|o| (o.id.clone(), o.pose.yaw_deg))
                .collect()
        };
        // Look-alikes draw from their own stream: the targets' yaws do not follow the rate.
        assert_eq!(targets(&a), targets(&b), "seed {seed}");
        yaws.extend(targets(&a).into_iter().map(|(_, y)| y));
        // Landmarks keep their axis-aligned footprints.
        assert!(a
            .objects
            .iter()
            .filter(|o| o.role == ObjectRole::Landmark)
            .all(|o| o.pose.yaw_deg == 0.0));
    }
    assert!(yaws.len() > 40, "{}", yaws.len());
    assert!(yaws.iter().all(|y| (0.0..360.0).contains(y)));
    // Uniform: each quarter of the circle holds some of them.
    for q in 0..4 {
        let lo = 90.0 * f64::from(q);
        let n = yaws
            .iter()
            .filter(|&&y| (lo..lo + 90.0).contains(&y))
            .count();
        assert!(n * 8 > yaws.len(), "quarter {q}: {n} of {}", yaws.len());
    }
}
