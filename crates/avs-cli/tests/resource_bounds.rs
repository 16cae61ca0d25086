//! Issue 18's resource reproducers end to end: each input is generated here (no large file is
//! committed) and the command now ends with a clean error or a bounded answer.

mod common;
use common::avs_in as avs;

use std::path::Path;
use std::process::Output;

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// `avs pomdp solve --time 1` on the 9-line model with 1,000 states and 1,000 observations ran
/// past 60 s at 5.5 GB; it now stops on time with valid bounds.
#[test]
fn pomdp_solve_with_a_time_limit_stops_on_time() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("wide.pomdp"),
        "discount: 0.95\nvalues: reward\nstates: 1000\nactions: 2\nobservations: 1000\n\
         T: * uniform\nO: * uniform\nR: 0 : 0 : * : * 1\nR: 1 : 1 : * : * 1\n",
    )
    .unwrap();
    let o = avs(dir, &["pomdp", "solve", "--time", "1", "wide.pomdp"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}{err}");
    assert!(out.contains("stopped     TimeLimit"), "{out}");
}

/// Rewards of ±1e308 printed `lower -inf`, `gap NaN` and exited 0; now the file is refused at
/// the reward's line and nothing is printed as a solution.
#[test]
fn pomdp_rewards_beyond_f64_are_refused_at_their_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("big.pomdp"),
        "discount: 0.95\nvalues: reward\nstates: a b\nactions: x y\nobservations: o\n\
         T: * identity\nO: * uniform\nR: x : a : * : * 1e308\nR: y : * : * : * -1e308\n",
    )
    .unwrap();
    let o = avs(dir, &["pomdp", "solve", "big.pomdp"]);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{out}{err}");
    assert!(out.is_empty(), "{out}");
    assert!(err.contains("big.pomdp:8: reward 1e308"), "{err}");
}

/// A 5 × 5 room (PGM) with its map_server descriptor.
fn small_map(dir: &Path) {
    let (w, h) = (20usize, 20usize);
    let mut pgm = format!("P5\n{w} {h}\n255\n").into_bytes();
    for y in 0..h {
        for x in 0..w {
            let wall = x == 0 || y == 0 || x == w - 1 || y == h - 1;
            pgm.push(if wall { 0 } else { 254 });
        }
    }
    std::fs::write(dir.join("map.pgm"), pgm).unwrap();
    std::fs::write(
        dir.join("map.yaml"),
        "image: map.pgm\nresolution: 0.25\norigin: [0.0, 0.0, 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .unwrap();
}

/// `avs segment --truth` on a small image declaring 20000 × 20000 pixels allocated 6 GB and
/// aborted; it is now refused from the header.
#[test]
fn segment_truth_declaring_a_huge_size_is_a_clean_error() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    small_map(dir);
    let mut truth = b"P5\n20000 20000\n255\n".to_vec();
    truth.extend_from_slice(&[255; 64]);
    std::fs::write(dir.join("truth.pgm"), truth).unwrap();
    let o = avs(dir, &["segment", "map.yaml", "--truth", "truth.pgm"]);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{out}{err}");
    assert!(
        err.contains(
            "truth.pgm: cannot read ground-truth image: the image declares 20000 × 20000 pixels"
        ),
        "{err}"
    );
    // The same map without the truth segments (the map itself is sound).
    assert!(avs(dir, &["segment", "map.yaml"]).status.success());
}

/// A map descriptor with a value nested 100,000 deep took over a minute; it is now refused
/// with the line and column where the nesting passes the cap.
#[test]
fn a_deeply_nested_map_descriptor_is_refused_with_its_position() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let deep = format!(
        "resolution: 0.05\nimage: {}x{}\n",
        "[".repeat(100_000),
        "]".repeat(100_000)
    );
    std::fs::write(dir.join("deep.yaml"), deep).unwrap();
    let o = avs(dir, &["segment", "deep.yaml"]);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{out}{err}");
    assert!(err.contains("deep.yaml:2:"), "{err}");
    assert!(err.contains("nesting deeper than 64 levels"), "{err}");
}

/// Gripper's `move` with 8 extra unused parameters grounded for over 40 s past 1.8 GB; the
/// grounding now stops at its limit and names the action.
#[test]
fn plan_with_an_exploding_action_names_it() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let unused: String = (1..=8).map(|i| format!(" ?u{i}")).collect();
    std::fs::write(
        dir.join("domain.pddl"),
        format!(
            "(define (domain gripper-strips)
   (:predicates (room ?r) (ball ?b) (gripper ?g) (at-robby ?r) (at ?b ?r) (free ?g) (carry ?o ?g))
   (:action move :parameters (?from ?to{unused})
       :precondition (and (room ?from) (room ?to) (at-robby ?from))
       :effect (and (at-robby ?to) (not (at-robby ?from))))
   (:action pick :parameters (?obj ?room ?gripper)
       :precondition (and (ball ?obj) (room ?room) (gripper ?gripper) (at ?obj ?room) (at-robby ?room) (free ?gripper))
       :effect (and (carry ?obj ?gripper) (not (at ?obj ?room)) (not (free ?gripper))))
   (:action drop :parameters (?obj ?room ?gripper)
       :precondition (and (ball ?obj) (room ?room) (gripper ?gripper) (carry ?obj ?gripper) (at-robby ?room))
       :effect (and (at ?obj ?room) (free ?gripper) (not (carry ?obj ?gripper)))))"
        ),
    )
    .unwrap();
    std::fs::write(
        dir.join("problem.pddl"),
        "(define (problem strips-gripper-x-1) (:domain gripper-strips)
   (:objects rooma roomb ball4 ball3 ball2 ball1 left right)
   (:init (room rooma) (room roomb) (ball ball4) (ball ball3) (ball ball2) (ball ball1)
          (at-robby rooma) (free left) (free right) (at ball4 rooma) (at ball3 rooma)
          (at ball2 rooma) (at ball1 rooma) (gripper left) (gripper right))
   (:goal (and (at ball4 roomb) (at ball3 roomb) (at ball2 roomb) (at ball1 roomb))))",
    )
    .unwrap();
    let o = avs(dir, &["plan", "domain.pddl", "problem.pddl"]);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{out}{err}");
    assert!(
        err.contains("grounding domain.pddl with problem problem.pddl: grounding action `move` passed the limit of 1000000 ground operators"),
        "{err}"
    );
}
