//! Criterion benches: HSVI on tiger.95 to a gap of 1e-3, and one online decision of a 20-cone
//! view-cone session (RTBSS, depth 2, on offline bounds computed when the session starts).
#![expect(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function"
)]
use avs_pomdp::{
    euclidean_travel, DecisionRewards, OfflineOptions, OnlineOptions, SessionOptions,
    ViewConeProblem, ViewConeSession,
};
use criterion::{criterion_group, criterion_main, BatchSize, Criterion};

fn tiger(c: &mut Criterion) {
    let Some(dir) = avs_testdata::reference_data("pomdp") else {
        return;
    };
    for file in ["tiger.95.POMDP", "cheese.95.POMDP", "parr95.95.POMDP"] {
        let m = avs_pomdp::read_pomdp_file(dir.join(file)).expect("reference file parses");
        c.bench_function(&format!("hsvi_{file}_gap_1e-3"), |b| {
            b.iter(|| {
                let s = avs_pomdp::solve(&m, &OfflineOptions::default()).expect("solves");
                assert!(s.gap() <= 1e-3);
                s.lower
            })
        });
    }
}

/// 20 cones on a 5 × 4 grid of poses 1.5 m apart; prior 0.8 spread unevenly; travel 0.5 per metre.
fn twenty_cones() -> ViewConeProblem {
    let n = 20;
    let pos: Vec<[f64; 2]> = (0..n)
        .map(|i| [1.5 * (i % 5) as f64, 1.5 * (i / 5) as f64])
        .collect();
    let w: Vec<f64> = (0..n).map(|i| 1.0 + (i % 3) as f64).collect();
    let total: f64 = w.iter().sum();
    let (from_start, travel) = euclidean_travel([-1.0, -1.0], &pos, 0.5);
    ViewConeProblem {
        cone_prior: w.iter().map(|x| 0.8 * x / total).collect(),
        travel_from_start: from_start,
        travel,
        process_cost: 0.5,
        false_negative: 0.2,
        false_positive: 0.05,
        rewards: DecisionRewards::default(),
        discount: 0.95,
    }
}

fn viewcone(c: &mut Criterion) {
    let opts = SessionOptions {
        // A fixed trial budget (not a time budget) so the bounds, and so the work per decision, do
        // not depend on the machine's load.
        offline: OfflineOptions {
            target_gap: 1e-3,
            time_limit: None,
            max_trials: 20,
            init_iterations: 500,
        },
        online: OnlineOptions {
            depth: 2,
            time_limit: None,
            node_limit: None,
        },
        max_steps: 100,
        sweep_bounds: false,
        policy: Default::default(),
    };
    let session = ViewConeSession::new(&twenty_cones(), opts).expect("session starts");
    c.bench_function("viewcone20_next_action_first", |b| {
        b.iter_batched(
            || session.clone(),
            |mut s| {
                let a = s.next_action().expect("decides");
                (s, a)
            },
            BatchSize::LargeInput,
        )
    });
    // After two misses, mid-session.
    let mut mid = session.clone();
    for _ in 0..2 {
        if let avs_pomdp::ViewConeAction::Process { .. } = mid.next_action().unwrap() {
            mid.observe(false).unwrap();
        }
    }
    c.bench_function("viewcone20_next_action_after_two_misses", |b| {
        b.iter_batched(
            || mid.clone(),
            |mut s| {
                let a = s.next_action().expect("decides");
                (s, a)
            },
            BatchSize::LargeInput,
        )
    });
}

criterion_group!(benches, tiger, viewcone);
criterion_main!(benches);
