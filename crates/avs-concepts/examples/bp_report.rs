//! Error and time of BP (and feasibility of exact inference) on the reference models.
//! `cargo run --release -p avs-concepts --example bp_report [-- MAX_EXACT_ENTRIES]`
//! Prints one markdown table row per model.

use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::exact::exact_marginals;
use avs_concepts::io::{parse_mar, parse_uai, parse_uai_evidence};
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let Some(dir) = avs_testdata::reference_data("bp") else {
        return;
    };
    let limit: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1 << 26);
    println!("| model | vars | factors | schedule | iterations | converged | BP max err | BP mean err | BP time (median of 5) | exact max err | exact time |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for name in ["Grids_11", "Grids_12", "Segmentation_11", "DBN_11"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.uai"))).unwrap();
        let mut g = parse_uai(&text, name).unwrap();
        let ev = std::fs::read_to_string(dir.join(format!("{name}.uai.evid"))).unwrap();
        for (v, x) in parse_uai_evidence(&ev, name).unwrap() {
            g.clamp(v, x).unwrap();
        }
        let mar = std::fs::read_to_string(dir.join(format!("{name}.uai.MAR"))).unwrap();
        let refs = parse_mar(&mar, name).unwrap();
        let err = |m: &[Vec<f64>]| {
            let e: Vec<f64> = m
                .iter()
                .zip(&refs)
                .map(|(a, b)| {
                    a.iter()
                        .zip(b)
                        .map(|(x, y)| (x - y).abs())
                        .fold(0.0, f64::max)
                })
                .collect();
            (
                e.iter().cloned().fold(0.0, f64::max),
                e.iter().sum::<f64>() / e.len() as f64,
            )
        };
        for (sched, updates, damping) in [
            ("SEQFIX", Updates::SeqFix, 0.0),
            ("PARALL", Updates::Parall, 0.0),
            ("SEQMAX", Updates::SeqMax, 0.0),
            ("PARALL d=0.5", Updates::Parall, 0.5),
        ] {
            let opts = BpOptions {
                updates,
                damping,
                tol: 1e-9,
                maxiter: 10_000,
                logdomain: false,
            };
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..5 {
                let t = Instant::now();
                let r = run_bp(&g, &opts, None).unwrap();
                times.push(t.elapsed().as_secs_f64());
                last = Some(r);
            }
            let r = last.unwrap();
            let (mx, mean) = err(&r.marginals);
            let exact = if sched == "SEQFIX" {
                let t = Instant::now();
                match exact_marginals(&g, limit) {
                    Ok(m) => format!("{:.1e} | {:.3} s", err(&m).0, t.elapsed().as_secs_f64()),
                    Err(e) => format!("not run: {e} | –"),
                }
            } else {
                "| ".to_string()
            };
            println!(
                "| {name} | {} | {} | {sched} | {} | {} | {mx:.2e} | {mean:.2e} | {:.2} ms | {exact} |",
                g.num_vars(),
                g.factors().len(),
                r.iterations,
                r.converged,
                median(times) * 1e3
            );
        }
    }
}
