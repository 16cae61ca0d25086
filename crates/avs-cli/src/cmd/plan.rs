//! `avs plan DOMAIN.pddl PROBLEM.pddl [--optimal | --fast]`: plan for a PDDL task the way
//! competition planners do — one `(action arg …)` line per step, then `; cost = N (unit cost)`
//! or `; cost = N (general cost)`. Search statistics go to stderr. Exit code 0 with a plan,
//! 1 when the task is unsolvable.

use anyhow::Context;
use avs_plan::{pddl, search, Mode, SearchOptions};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

/// Flags.
#[derive(clap::Args)]
pub struct Args {
    /// The PDDL domain file.
    pub domain: PathBuf,
    /// The PDDL problem file.
    pub problem: PathBuf,
    /// A* with LM-cut: a plan of minimum cost (the default).
    #[arg(long, conflicts_with = "fast")]
    pub optimal: bool,
    /// Greedy best-first search with h^FF and preferred operators: fast, not optimal.
    #[arg(long)]
    pub fast: bool,
    /// Give up after this many expanded states.
    #[arg(long, default_value_t = 50_000_000)]
    pub max_expansions: u64,
}

/// Run the subcommand.
pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let dname = args.domain.display().to_string();
    let pname = args.problem.display().to_string();
    let dtext =
        std::fs::read_to_string(&args.domain).with_context(|| format!("reading {dname}"))?;
    let ptext =
        std::fs::read_to_string(&args.problem).with_context(|| format!("reading {pname}"))?;
    let t0 = Instant::now();
    let d = pddl::parse_domain(&dname, &dtext)?;
    let p = pddl::parse_problem(&pname, &ptext)?;
    let task = pddl::ground(&dname, &d, &p)
        .with_context(|| format!("grounding {dname} with problem {pname}"))?;
    let t_ground = t0.elapsed().as_secs_f64();
    let mode = if args.fast { Mode::Fast } else { Mode::Optimal };
    let opts = SearchOptions {
        mode,
        max_expansions: args.max_expansions,
        ..Default::default()
    };
    let t1 = Instant::now();
    let (plan, stats) = search(&task, &opts)?;
    let t_search = t1.elapsed().as_secs_f64();
    eprintln!(
        "; {task}; mode {mode:?}; grounding {t_ground:.4} s; search {t_search:.4} s; expanded {}, generated {}, evaluated {}",
        stats.expanded, stats.generated, stats.evaluated
    );
    let Some(plan) = plan else {
        println!("; no plan: the task is unsolvable");
        return Ok(ExitCode::from(1));
    };
    for &i in &plan.steps {
        println!("{}", task.operators[i].display);
    }
    let cost = if plan.cost.fract() == 0.0 && plan.cost.abs() < 1e15 {
        format!("{}", plan.cost as i64)
    } else {
        format!("{}", plan.cost)
    };
    let kind = if task.is_unit_cost() {
        "unit cost"
    } else {
        "general cost"
    };
    println!("; cost = {cost} ({kind})");
    Ok(ExitCode::SUCCESS)
}
