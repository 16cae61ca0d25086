//! Criterion: one plan (grounding + optimal search) for the object-search domain on the default
//! environment as known at the start (paper 002's planner took 0.2–0.5 s per plan).
#![expect(
    missing_docs,
    reason = "criterion_group! generates an undocumented public function"
)]

#[path = "../tests/common/mod.rs"]
mod common;

use avs_plan::continual::{ContinualOptions, ContinualPlanner, Decision};
use common::*;
use criterion::{criterion_group, criterion_main, Criterion};

fn bench(c: &mut Criterion) {
    let planner = ContinualPlanner::new(object_search_domain(), ContinualOptions::default());
    // 3 corridor places (the first-plan test) and a 36-place corridor (40 places in all);
    // 5 object classes; one hypothesised room besides the corridor.
    for corridor in [3usize, 36] {
        let w = office_start(corridor, &LABELS[..5], "cerealbox");
        let xy = w.xy.clone();
        let f = move |n: &str, a: &[&str]| stand_in(n, a, &xy);
        assert!(matches!(
            planner.plan(&w.problem, &f).unwrap(),
            Decision::Plan(_)
        ));
        c.bench_function(
            &format!("object_search_plan_{}_places", corridor + 4),
            |b| b.iter(|| planner.plan(&w.problem, &f).unwrap()),
        );
        let task = planner.ground(&w.problem, &f).unwrap();
        c.bench_function(
            &format!("object_search_search_only_{}_places", corridor + 4),
            |b| b.iter(|| avs_plan::search(&task, &ContinualOptions::default().search).unwrap()),
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
