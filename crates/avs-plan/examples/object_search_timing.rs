//! Time the object-search planner on the default environment and print its plans:
//! `cargo run --release -p avs-plan --example object_search_timing -- [CORRIDOR_PLACES] [REPEATS]`.
#[path = "../tests/common/mod.rs"]
mod common;
use avs_plan::search::{search, Mode, SearchOptions};
use common::*;
use std::time::Instant;

fn main() {
    let d = object_search_domain();
    let corridor: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3);
    let w = office_start(corridor, &LABELS[..5], "cerealbox");
    let xy = w.xy.clone();
    let f = move |n: &str, a: &[&str]| stand_in(n, a, &xy);
    let planner = avs_plan::continual::ContinualPlanner::new(d, Default::default());
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(1);
    let t = Instant::now();
    for _ in 1..reps {
        let _ = planner.plan(&w.problem, &f).unwrap();
    }
    eprintln!("{reps} plans {:?}", t.elapsed());
    let t = Instant::now();
    let task = planner.ground(&w.problem, &f).unwrap();
    let mut by: std::collections::BTreeMap<&str, usize> = Default::default();
    for o in &task.operators {
        *by.entry(o.schema.as_str()).or_default() += 1;
    }
    eprintln!("{by:?}");
    eprintln!("ground {:?}: {task}", t.elapsed());
    let rel = avs_plan::heuristics::Relaxed::new(&task);
    let mut ws = Default::default();
    let hc = rel.lmcut(&task.init, &rel.costs_of(&task, |o| o.cost), &mut ws);
    let hl = rel.lmcut(&task.init, &rel.costs_of(&task, |o| -o.prob.ln()), &mut ws);
    eprintln!(
        "h_c {hc:?} h_l {hl:?} f0 {}",
        hc.unwrap() + 1000.0 * (1.0 - (-hl.unwrap()).exp())
    );
    for mode in [Mode::Optimal, Mode::Fast] {
        let t = Instant::now();
        let (p, st) = search(
            &task,
            &SearchOptions {
                mode,
                max_expansions: 2_000_000,
                ..Default::default()
            },
        )
        .unwrap();
        eprintln!("{mode:?} {:?} {st:?}", t.elapsed());
        if let Some(p) = p {
            for &s in &p.steps {
                eprintln!("  {}", task.operators[s].display);
            }
            eprintln!("  cost {} p {} obj {}", p.cost, p.probability, p.objective);
        }
    }
}
