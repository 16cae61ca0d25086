//! Error, iterations and time of BP on the UAI reference models, optionally side by side with
//! libDAI's BP on the same factor graphs.
//!
//! `cargo run --release -p avs-concepts --example bp_report [-- --libdai DIR] [--reps N]
//! [--maxiter N] [--exact]`
//!
//! For every model and schedule (tol 1e-9, maxiter 10000 unless given, no damping, linear
//! domain) it
//! prints one markdown row: avs's iterations, whether it converged, its largest error against
//! the `.MAR` reference (max over variables and states of |ours − reference|; the references
//! are exact marginals) and its median time over `--reps` runs (BP alone, parsing excluded).
//! With `--libdai DIR`, it reads libDAI's results from `DIR/NAME.SCHEDULE.out` — a first line
//! `iterations maxdiff seconds`, then the marginals in the `.MAR` layout, as written by the
//! driver described in `docs/benchmarks/concepts.md` — and adds libDAI's columns and the
//! largest difference between the two. With `--exact`, a second table gives exact
//! inference's error against the references and its time (junction trees up to 2^26 entries).

use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::exact::exact_marginals;
use avs_concepts::io::{parse_mar, parse_uai, parse_uai_evidence};
use std::path::PathBuf;
use std::time::Instant;

const TOL: f64 = 1e-9;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Largest |a − b| over all variables and states.
fn max_err(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// libDAI's result: (iterations, maxdiff, seconds, marginals).
fn read_libdai(path: &PathBuf) -> Option<(usize, f64, f64, Vec<Vec<f64>>)> {
    let text = std::fs::read_to_string(path).ok()?;
    let (first, rest) = text.split_once('\n')?;
    let mut it = first.split_whitespace();
    let iters = it.next()?.parse().ok()?;
    let md = it.next()?.parse().ok()?;
    let secs = it.next()?.parse().ok()?;
    let mar = parse_mar(rest, &path.display().to_string()).ok()?;
    Some((iters, md, secs, mar))
}

fn main() {
    let Some(dir) = avs_testdata::reference_data("bp") else {
        eprintln!("no reference data (set AVS_REFERENCE_DATA)");
        return;
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let flag = |name: &str| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let libdai = flag("--libdai").map(PathBuf::from);
    let reps: usize = flag("--reps").and_then(|s| s.parse().ok()).unwrap_or(5);
    let maxiter: usize = flag("--maxiter")
        .and_then(|s| s.parse().ok())
        .unwrap_or(10_000);
    print!("| model | schedule | avs iterations | avs converged | avs max err | avs time |");
    if libdai.is_some() {
        print!(" libDAI iterations | libDAI converged | libDAI max err | libDAI time | max \\|avs − libDAI\\| |");
    }
    println!();
    println!(
        "|---|---|---|---|---|---|{}",
        if libdai.is_some() {
            "---|---|---|---|---|"
        } else {
            ""
        }
    );
    let mut exact_rows = Vec::new();
    for name in ["Grids_11", "Grids_12", "Segmentation_11", "DBN_11"] {
        let text = std::fs::read_to_string(dir.join(format!("{name}.uai"))).unwrap();
        let mut g = parse_uai(&text, name).unwrap();
        let ev = std::fs::read_to_string(dir.join(format!("{name}.uai.evid"))).unwrap();
        for (v, x) in parse_uai_evidence(&ev, name).unwrap() {
            g.clamp(v, x).unwrap();
        }
        let mar = std::fs::read_to_string(dir.join(format!("{name}.uai.MAR"))).unwrap();
        let refs = parse_mar(&mar, name).unwrap();
        if args.iter().any(|a| a == "--exact") {
            let t = Instant::now();
            exact_rows.push(match exact_marginals(&g, 1 << 26) {
                Ok(m) => format!(
                    "| {name} | {} | {} | {:.1e} | {:.2} s |",
                    g.num_vars(),
                    g.factors().len(),
                    max_err(&m, &refs),
                    t.elapsed().as_secs_f64()
                ),
                Err(e) => format!(
                    "| {name} | {} | {} | not run: {e} | |",
                    g.num_vars(),
                    g.factors().len()
                ),
            });
        }
        for sched in ["PARALL", "SEQFIX", "SEQMAX"] {
            let opts = BpOptions {
                updates: sched.parse::<Updates>().unwrap(),
                damping: 0.0,
                tol: TOL,
                maxiter,
                logdomain: false,
            };
            let mut times = Vec::new();
            let mut last = None;
            for _ in 0..reps.max(1) {
                let t = Instant::now();
                let r = run_bp(&g, &opts, None);
                times.push(t.elapsed().as_secs_f64());
                last = Some(r);
            }
            let row = match last.unwrap() {
                Ok(r) => format!(
                    "{} | {} | {:.3e} | {:.2} ms",
                    r.iterations,
                    if r.converged { "yes" } else { "no" },
                    max_err(&r.marginals, &refs),
                    median(times) * 1e3
                ),
                Err(e) => format!("error: {e} | | | "),
            };
            print!("| {name} | {sched} | {row} |");
            if let Some(ld) = &libdai {
                match read_libdai(&ld.join(format!("{name}.{sched}.out"))) {
                    Some((it, md, secs, m)) => {
                        let ours = run_bp(&g, &opts, None).ok();
                        let diff = ours
                            .map(|r| format!("{:.1e}", max_err(&r.marginals, &m)))
                            .unwrap_or_else(|| "–".into());
                        print!(
                            " {it} | {} | {:.3e} | {:.2} ms | {diff} |",
                            if md <= TOL { "yes" } else { "no" },
                            max_err(&m, &refs),
                            secs * 1e3
                        );
                    }
                    None => print!(" – | – | – | – | – |"),
                }
            }
            println!();
        }
    }
    if !exact_rows.is_empty() {
        println!("\n| model | vars | factors | exact max err | exact time |");
        println!("|---|---|---|---|---|");
        for r in exact_rows {
            println!("{r}");
        }
    }
}
