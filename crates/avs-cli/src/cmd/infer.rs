//! `avs infer MODEL [--evid FILE] [--method bp|exact] [--json]`: marginals of a UAI
//! (`MARKOV`/`BAYES`) or libDAI `.fg` factor graph, printed in the UAI `.MAR` layout.

use anyhow::Context;
use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::exact::exact_marginals;
use avs_concepts::io::{format_mar, parse_fg, parse_uai, parse_uai_evidence};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Inference method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Loopy belief propagation (sum-product).
    Bp,
    /// Exact inference (junction tree from variable elimination).
    Exact,
}

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The model: a UAI file (MARKOV or BAYES) or a libDAI `.fg` file.
    pub model: PathBuf,
    /// UAI evidence file (`N var val ...`); for `.fg` models, variables are `.fg` labels.
    #[arg(long)]
    pub evid: Option<PathBuf>,
    /// Inference method.
    #[arg(long, value_enum, default_value = "bp")]
    pub method: Method,
    /// Print JSON (marginals, labels, BP statistics, seconds) instead of the `.MAR` layout.
    #[arg(long)]
    pub json: bool,
    /// BP schedule: SEQFIX, SEQMAX or PARALL (libDAI's names).
    #[arg(long, default_value = "SEQFIX")]
    pub updates: String,
    /// BP damping in [0, 1).
    #[arg(long, default_value_t = 0.0)]
    pub damping: f64,
    /// BP tolerance on the change of the beliefs.
    #[arg(long, default_value_t = 1e-9)]
    pub tol: f64,
    /// BP iteration limit.
    #[arg(long, default_value_t = 10_000)]
    pub maxiter: usize,
    /// Run BP in the log domain.
    #[arg(long)]
    pub logdomain: bool,
    /// Exact inference: the largest junction tree allowed, in table entries.
    #[arg(long, default_value_t = 1 << 26)]
    pub max_entries: usize,
}

/// BP statistics: iterations, converged, last belief change, last message change.
type Stats = Option<(usize, bool, f64, f64)>;

/// What one inference produced.
struct Outcome {
    marginals: Vec<Vec<f64>>,
    stats: Stats,
    /// `.fg` labels of the variables (libDAI files only).
    labels: Option<Vec<usize>>,
    /// Seconds spent in inference (not parsing).
    seconds: f64,
}

/// Read the model and evidence, and compute the marginals (with BP statistics).
fn compute(args: &Args) -> anyhow::Result<Outcome> {
    let name = args.model.display().to_string();
    let text = std::fs::read_to_string(&args.model).with_context(|| format!("reading {name}"))?;
    let (mut graph, labels) = if is_fg(args) {
        let lg = parse_fg(&text, &name)?;
        (lg.graph, Some(lg.labels))
    } else {
        (parse_uai(&text, &name)?, None)
    };
    if let Some(ev) = &args.evid {
        let en = ev.display().to_string();
        let t = std::fs::read_to_string(ev).with_context(|| format!("reading {en}"))?;
        for (v, x) in parse_uai_evidence(&t, &en)? {
            let var = match &labels {
                Some(l) => l
                    .iter()
                    .position(|&lab| lab == v)
                    .with_context(|| format!("{en}: no variable labelled {v} in {name}"))?,
                None => v,
            };
            graph.clamp(var, x).with_context(|| en.clone())?;
        }
    }
    let start = Instant::now();
    let (marginals, stats) = match args.method {
        Method::Bp => {
            let opts = BpOptions {
                updates: args.updates.parse::<Updates>()?,
                damping: args.damping,
                tol: args.tol,
                maxiter: args.maxiter,
                logdomain: args.logdomain,
            };
            let r = run_bp(&graph, &opts, None)?;
            if !r.converged {
                eprintln!(
                    "warning: BP did not converge in {} iterations (last change {:.3e})",
                    r.iterations, r.max_diff
                );
            }
            (
                r.marginals,
                Some((r.iterations, r.converged, r.max_diff, r.max_message_change)),
            )
        }
        Method::Exact => (exact_marginals(&graph, args.max_entries)?, None),
    };
    Ok(Outcome {
        marginals,
        stats,
        labels,
        seconds: start.elapsed().as_secs_f64(),
    })
}

fn is_fg(args: &Args) -> bool {
    args.model
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("fg"))
}

/// Run the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let name = args.model.display().to_string();
    let Outcome {
        marginals,
        stats,
        labels,
        seconds: secs,
    } = compute(&args)?;
    if args.json {
        let mut j = serde_json::json!({
            "model": name,
            "method": match args.method { Method::Bp => "bp", Method::Exact => "exact" },
            "marginals": marginals,
            "seconds": secs,
        });
        if let Some(l) = labels {
            j["labels"] = serde_json::json!(l);
        }
        if let Some((it, conv, md, mm)) = stats {
            j["iterations"] = it.into();
            j["converged"] = conv.into();
            j["max_diff"] = md.into();
            j["max_message_change"] = mm.into();
        }
        println!("{}", serde_json::to_string_pretty(&j)?);
    } else {
        print!("{}", format_mar(&marginals));
        if let Some((it, conv, md, mm)) = stats {
            eprintln!(
                "bp: {it} iterations, converged {conv}, last belief change {md:.3e}, \
                 last message change {mm:.3e}, {secs:.6} s"
            );
        } else {
            eprintln!("exact: {secs:.6} s");
        }
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(model: PathBuf, method: Method) -> Args {
        Args {
            model,
            evid: None,
            method,
            json: false,
            updates: "PARALL".into(),
            damping: 0.0,
            tol: 1e-12,
            maxiter: 1000,
            logdomain: false,
            max_entries: 1 << 20,
        }
    }

    #[test]
    fn a_uai_chain_gives_the_same_marginals_by_bp_and_exact_with_evidence_clamped() {
        let dir = std::env::temp_dir().join(format!("avs-infer-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let model = dir.join("chain.uai");
        // x0 - x1 - x2, binary; last variable of a scope varies fastest
        std::fs::write(
            &model,
            "MARKOV\n3\n2 2 2\n3\n1 0\n2 0 1\n2 1 2\n2\n0.3 0.7\n4\n1 2 3 4\n4\n5 1 1 5\n",
        )
        .unwrap();
        let evid = dir.join("chain.uai.evid");
        std::fs::write(&evid, "1 2 0\n").unwrap();
        let mut a = args(model.clone(), Method::Bp);
        a.evid = Some(evid.clone());
        let bp = compute(&a).unwrap().marginals;
        let mut e = args(model, Method::Exact);
        e.evid = Some(evid);
        let ex = compute(&e).unwrap().marginals;
        for (x, y) in bp.iter().flatten().zip(ex.iter().flatten()) {
            assert!((x - y).abs() < 1e-9);
        }
        assert_eq!(ex[2], vec![1.0, 0.0]);
        // brute force: P(x0, x1 | x2 = 0) ∝ p0(x0) f01(x0, x1) f12(x1, 0)
        let p0 = [0.3, 0.7];
        let f01 = [[1.0, 2.0], [3.0, 4.0]];
        let f12 = [5.0, 1.0];
        let w: Vec<f64> = (0..4)
            .map(|i| p0[i / 2] * f01[i / 2][i % 2] * f12[i % 2])
            .collect();
        let z: f64 = w.iter().sum();
        assert!((ex[0][0] - (w[0] + w[1]) / z).abs() < 1e-12);
        assert!((ex[1][0] - (w[0] + w[2]) / z).abs() < 1e-12);
        let text = format_mar(&ex);
        assert!(text.starts_with("MAR\n3 2 "));
        std::fs::remove_dir_all(&dir).ok();
    }
}
