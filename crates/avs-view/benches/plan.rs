//! View planning speed (issue 21): a view plan for a 40 m² room and five classes (§4.3's
//! 40.9 m² room, its nine standpoints, objects B, C, D, M, R), greedy with its local search; and
//! the candidate views alone.
#![allow(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function"
)]

use avs_view::plan::{candidate_units, plan_views, PlanOptions, ViewProblem};
use criterion::{criterion_group, criterion_main, Criterion};

#[path = "../tests/common/mod.rs"]
mod common;

fn bench(c: &mut Criterion) {
    let room = &common::rooms()[1];
    let problem = ViewProblem {
        cells: room.cells.clone(),
        standpoints: room.nodes[..9].to_vec(),
        classes: "BCDMR".chars().map(common::object).collect(),
        camera: common::camera(),
        options: PlanOptions::default(),
    };
    c.bench_function("plan_views 40.9 m², 9 standpoints, 5 classes", |b| {
        b.iter(|| plan_views(&problem, |_, _| true).unwrap())
    });
    c.bench_function("candidate_units 40.9 m², 9 standpoints, 5 classes", |b| {
        b.iter(|| candidate_units(&problem, |_, _| true).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
