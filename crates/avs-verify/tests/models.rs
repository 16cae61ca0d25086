//! The sensor models, fields and planners on a small hand-written model: an object scores
//! about 2 near 2 m and less far away, a look-alike about 0.8; each feature's residual field
//! has variance 0.5 and length scales 1.5 m × 0.4 rad, and the white noise of one look is
//! 0.06 — a detector whose errors come mostly from the view, not from the image (as the
//! simulated detectors' profiles), so that a repeated look can carry little news.

use avs_format::verifier::{CorrSpec, KernelSpec};
use avs_verify::field::{perception_field, value, FieldMethod, PreparedGrid, VantageGrid};
use avs_verify::planner::greedy::{self, GreedyConfig};
use avs_verify::planner::planned::{self, PlannedConfig};
use avs_verify::planner::{Candidate, OpenPlane, Step, Terrain};
use avs_verify::sensor::{Conditioned, Look, ModelKind, SensorModel};
use avs_verify::train::{HypothesisSpec, SensorModelSpec};
use avs_verify::vantage::Vantage;
use rand::SeedableRng;

fn hypothesis(peak: f64) -> HypothesisSpec {
    let points = [1.0, 2.0, 3.0, 4.5, 6.0]
        .iter()
        .flat_map(|&r| {
            [-0.8, 0.0, 0.8].map(|a: f64| {
                let m = 0.4 + (peak - 0.4) * (-0.5 * ((r - 2.0) / 2.0f64).powi(2)).exp() * a.cos();
                [r, a, m]
            })
        })
        .collect();
    HypothesisSpec {
        mean: 0.4 + 0.6 * (peak - 0.4),
        kernel: KernelSpec {
            signal_variance: 0.5,
            length_scales: vec![2.0, 0.8],
        },
        noise_variance: 0.01,
        spread: 0.5 + 0.06,
        points,
        corr: CorrSpec {
            kernel: KernelSpec {
                signal_variance: 0.5,
                length_scales: vec![1.5, 0.4],
            },
            noise_variance: 0.06,
        },
    }
}

fn model(kind: ModelKind) -> SensorModel {
    SensorModel::from_spec(&SensorModelSpec {
        kind,
        max_range: 6.0,
        aspect_limit: Some(1.4),
        object: hypothesis(2.0),
        no_object: hypothesis(0.8),
    })
    .unwrap()
}

const DYNAMIC: ModelKind = ModelKind::Dynamic { alpha_scale: 5.0 };
const DISC: ModelKind = ModelKind::Disc { d_max: 3.0 };

#[test]
fn a_second_identical_look_moves_the_dynamic_belief_far_less_than_the_first() {
    let v = Vantage::new(2.0, 0.1);
    for (kind, repeat_ratio_max) in [(DYNAMIC, 0.35), (DISC, 1e-9)] {
        let m = model(kind);
        let c0 = m.condition(&[]).unwrap();
        let p1 = c0.update(0.5, &v, 1.9);
        let first = p1 - 0.5;
        assert!(
            first > 0.1,
            "{kind:?}: an object-like score raises the belief: {p1}"
        );
        let c1 = m
            .condition(&[Look {
                vantage: v,
                score: 1.9,
            }])
            .unwrap();
        let p2 = c1.update(p1, &v, 1.9);
        let second = p2 - p1;
        assert!(
            second.abs() <= repeat_ratio_max * first,
            "{kind:?}: the repeat moved {second}, the first look {first}"
        );
        // The independent model believes the repeat as much as the first look.
        let ind = model(ModelKind::Independent);
        let ci = ind
            .condition(&[Look {
                vantage: v,
                score: 1.9,
            }])
            .unwrap();
        assert!(ci.update(p1, &v, 1.9) - p1 > 0.5 * first);
    }
}

/// The model conditioned on one look of `score` from `v`, and the belief after it from ½.
fn one_look(m: &SensorModel, v: Vantage, score: f64) -> (Conditioned<'_>, f64) {
    let c = m.condition(&[Look { vantage: v, score }]).unwrap();
    let p = m.condition(&[]).unwrap().update(0.5, &v, score);
    (c, p)
}

#[test]
fn a_look_from_a_new_vantage_point_counts_again() {
    let m = model(DYNAMIC);
    let (c1, p1) = one_look(&m, Vantage::new(2.0, 0.0), 1.9);
    let far = Vantage::new(4.5, -1.0);
    let near = Vantage::new(2.1, 0.02);
    let gain_far = c1.update(p1, &far, 1.6) - p1;
    let gain_near = c1.update(p1, &near, 1.9) - p1;
    assert!(
        gain_far > 3.0 * gain_near.abs(),
        "far {gain_far} near {gain_near}"
    );
}

#[test]
fn a_look_from_just_across_the_bearing_pi_is_as_near_as_it_is() {
    // An all-round class whose facing is unknown: the aspect is the bearing from +x, and a
    // robot west of the candidate sees it at an aspect near ±π. Two looks 0.04 rad apart are
    // two looks 0.04 rad apart, whichever side of the seam they fall on.
    let m = SensorModel::from_spec(&SensorModelSpec {
        kind: DYNAMIC,
        max_range: 6.0,
        aspect_limit: None,
        object: hypothesis(2.0),
        no_object: hypothesis(0.8),
    })
    .unwrap();
    let (c1, p1) = one_look(&m, Vantage::new(2.0, 3.12), 1.9);
    let across = c1.update(p1, &Vantage::new(2.0, 3.12 + 0.04), 1.9) - p1;
    let this_side = c1.update(p1, &Vantage::new(2.0, 3.12 - 0.04), 1.9) - p1;
    assert!(
        (across - this_side).abs() < 0.01 * this_side.abs(),
        "across {across}, this side {this_side}"
    );
    // And both are a repeat, far less news than a fresh vantage point.
    let fresh = c1.update(p1, &Vantage::new(4.5, 0.0), 1.9) - p1;
    assert!(
        across.abs() < 0.35 * fresh,
        "across {across}, fresh {fresh}"
    );
}

#[test]
fn the_field_vanishes_where_the_robot_already_looked_and_not_elsewhere() {
    // Velez et al. §5.4: as looks from one vantage point accumulate, its information goes to 0.
    let grid = VantageGrid::regular([1.0, 6.0], 6, 1.2, 7);
    for kind in [DYNAMIC, DISC] {
        let m = model(kind);
        let pg = PreparedGrid::new(&m, grid.clone());
        let looked = grid.vantages[8];
        let before = perception_field(&m.condition(&[]).unwrap(), 0.6, &pg, FieldMethod::Pbd);
        let mut history = Vec::new();
        let mut last = before[8];
        for _ in 0..4 {
            history.push(Look {
                vantage: looked,
                score: 1.5,
            });
            let f = perception_field(&m.condition(&history).unwrap(), 0.6, &pg, FieldMethod::Pbd);
            assert!(
                f[8] < last || f[8] == 0.0,
                "{kind:?}: a repeat must lower the field"
            );
            last = f[8];
        }
        assert!(last < 0.12 * before[8], "{kind:?}: {last} vs {}", before[8]);
        let after = perception_field(&m.condition(&history).unwrap(), 0.6, &pg, FieldMethod::Pbd);
        let far = grid
            .vantages
            .iter()
            .enumerate()
            .filter(|(k, _)| before[*k] > 0.0)
            .max_by(|a, b| {
                let d = |v: &Vantage| avs_verify::sensor::waypoint_distance(v, &looked);
                d(a.1).total_cmp(&d(b.1))
            })
            .unwrap()
            .0;
        assert!(
            after[far] > 0.8 * before[far],
            "{kind:?}: far {} vs {}",
            after[far],
            before[far]
        );
    }
}

fn ranks(v: &[f64]) -> Vec<f64> {
    let mut idx: Vec<usize> = (0..v.len()).collect();
    idx.sort_by(|&a, &b| v[a].total_cmp(&v[b]));
    let mut r = vec![0.0; v.len()];
    for (k, &i) in idx.iter().enumerate() {
        r[i] = k as f64;
    }
    r
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
    let va: f64 = a.iter().map(|x| (x - ma).powi(2)).sum();
    let vb: f64 = b.iter().map(|y| (y - mb).powi(2)).sum();
    cov / (va * vb).sqrt()
}

#[test]
fn pbd_and_enumeration_rank_vantage_points_alike_and_bins_converge() {
    let grid = VantageGrid::regular([0.75, 6.0], 10, 1.3, 9);
    let m = model(DYNAMIC);
    let pg = PreparedGrid::new(&m, grid.clone());
    let c = m
        .condition(&[Look {
            vantage: Vantage::new(2.0, 0.3),
            score: 1.4,
        }])
        .unwrap();
    for p in [0.3, 0.5, 0.8] {
        let pbd = perception_field(&c, p, &pg, FieldMethod::Pbd);
        let b10 = perception_field(&c, p, &pg, FieldMethod::Bins(10));
        let b100 = perception_field(&c, p, &pg, FieldMethod::Bins(100));
        let rho = correlation(&ranks(&pbd), &ranks(&b100));
        assert!(rho > 0.9, "p {p}: Spearman {rho}");
        let worst = b10
            .iter()
            .zip(&b100)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        let top = b100.iter().cloned().fold(0.0, f64::max);
        assert!(
            worst < 0.15 * top,
            "p {p}: 10 vs 100 bins differ by {worst} (top {top})"
        );
    }
}

#[test]
fn a_planar_class_gives_no_field_and_no_evidence_beyond_its_aspect_limit() {
    let m = model(DYNAMIC);
    let c = m.condition(&[]).unwrap();
    let behind = Vantage::new(2.0, 2.0);
    assert!(c.at(&behind).is_none());
    assert_eq!(c.update(0.4, &behind, 5.0), 0.4);
    let front = Vantage::new(2.0, 0.0);
    assert!(value(&c.at(&front).unwrap(), 0.4, FieldMethod::Pbd) > 0.0);
}

fn rng(seed: u64) -> rand_chacha::ChaCha8Rng {
    rand_chacha::ChaCha8Rng::seed_from_u64(seed)
}

#[test]
fn a_near_certain_candidate_is_decided_without_a_detour() {
    let m = model(DYNAMIC);
    let c = Candidate::new([3.0, 2.0], Some(-std::f64::consts::FRAC_PI_2), &m, 0.995);
    let plan = planned::plan(
        &[c],
        [0.0, 0.0],
        [10.0, 0.0],
        &OpenPlane,
        &PlannedConfig::default(),
        &mut rng(1),
    )
    .unwrap();
    assert_eq!(plan.step, Step::Decide);
}

#[test]
fn an_uncertain_candidate_beside_the_route_is_looked_at_and_the_plan_is_deterministic() {
    let m = model(DYNAMIC);
    let c = Candidate::new([3.0, 2.0], Some(-std::f64::consts::FRAC_PI_2), &m, 0.5);
    let cfg = PlannedConfig::default();
    let a = planned::plan(
        std::slice::from_ref(&c),
        [0.0, 0.0],
        [10.0, 0.0],
        &OpenPlane,
        &cfg,
        &mut rng(3),
    )
    .unwrap();
    let Step::Look {
        candidate,
        waypoint,
        vantage,
    } = a.step.clone()
    else {
        panic!("expected a look, got {:?}", a.step)
    };
    assert_eq!(candidate, 0);
    assert!(m.sees(&vantage));
    assert!(
        a.cost() < cfg.costs.now(0.5),
        "the plan must beat deciding now"
    );
    // The detour is modest: the planner weighs motion.
    assert!(a.motion < 12.0, "motion {}", a.motion);
    assert!(
        waypoint[1] < 2.0,
        "the look is from the candidate's front: {waypoint:?}"
    );
    let b = planned::plan(&[c], [0.0, 0.0], [10.0, 0.0], &OpenPlane, &cfg, &mut rng(3)).unwrap();
    assert_eq!(a, b);
}

struct Walled;
impl Terrain for Walled {
    fn can_view(&self, _: [f64; 2], _: [f64; 2]) -> bool {
        false
    }
    fn distance(&self, a: [f64; 2], b: [f64; 2]) -> f64 {
        OpenPlane.distance(a, b)
    }
}

#[test]
fn a_candidate_that_cannot_be_seen_from_anywhere_is_decided_not_looked_at_forever() {
    let m = model(DYNAMIC);
    let c = Candidate::new([3.0, 2.0], None, &m, 0.5);
    let plan = planned::plan(
        std::slice::from_ref(&c),
        [0.0, 0.0],
        [10.0, 0.0],
        &Walled,
        &PlannedConfig::default(),
        &mut rng(1),
    )
    .unwrap();
    assert_eq!(plan.step, Step::Decide);
    assert_eq!(
        greedy::plan(&[c], [0.0, 0.0], &Walled, &GreedyConfig::default()).unwrap(),
        Step::Decide
    );
}

#[test]
fn greedy_looks_until_the_belief_passes_its_threshold() {
    let m = model(DYNAMIC);
    let mut c = Candidate::new([3.0, 2.0], Some(-std::f64::consts::FRAC_PI_2), &m, 0.5);
    let cfg = GreedyConfig {
        threshold: 0.8,
        ..GreedyConfig::default()
    };
    let mut looks = 0;
    while let Step::Look { waypoint, .. } =
        greedy::plan(std::slice::from_ref(&c), [0.0, 0.0], &OpenPlane, &cfg).unwrap()
    {
        // A truthful object-like score each time.
        c.observe(waypoint, 2.0).unwrap();
        looks += 1;
        assert!(looks <= cfg.max_looks, "greedy must stop");
    }
    assert!(
        c.belief > 0.8 || c.looks.len() == cfg.max_looks,
        "belief {}",
        c.belief
    );
    assert!(looks >= 1);
}

#[test]
fn rtbss_settles_a_near_certain_candidate_and_looks_at_an_uncertain_one() {
    use avs_verify::planner::rtbss::{self, RtbssConfig};
    let m = model(DYNAMIC);
    let cfg = RtbssConfig::default();
    let sure = Candidate::new([3.0, 2.0], Some(-std::f64::consts::FRAC_PI_2), &m, 0.998);
    assert_eq!(
        rtbss::plan(&[sure], [0.0, 0.0], &OpenPlane, &cfg).unwrap(),
        Step::Settle { candidate: 0 }
    );
    let unsure = Candidate::new([3.0, 2.0], Some(-std::f64::consts::FRAC_PI_2), &m, 0.5);
    let Step::Look {
        candidate, vantage, ..
    } = rtbss::plan(std::slice::from_ref(&unsure), [0.0, 0.0], &OpenPlane, &cfg).unwrap()
    else {
        panic!("expected a look at an even-odds candidate")
    };
    assert_eq!(candidate, 0);
    assert!(m.sees(&vantage));
    // Deterministic, and nothing to do without an open candidate.
    assert_eq!(
        rtbss::plan(std::slice::from_ref(&unsure), [0.0, 0.0], &OpenPlane, &cfg).unwrap(),
        rtbss::plan(std::slice::from_ref(&unsure), [0.0, 0.0], &OpenPlane, &cfg).unwrap()
    );
    assert_eq!(
        rtbss::plan(&[], [0.0, 0.0], &OpenPlane, &cfg).unwrap(),
        Step::Decide
    );
}
