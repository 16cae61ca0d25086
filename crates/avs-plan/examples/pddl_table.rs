//! Solve every instance of the reference PDDL benchmarks and print a markdown table.
//! `cargo run --release -p avs-plan --example pddl_table [-- --with-fast]`
use avs_plan::{pddl, search, Mode, SearchOptions};
use std::time::Instant;

fn main() {
    let Some(dir) = avs_testdata::reference_data("pddl") else {
        return;
    };
    let csv = std::fs::read_to_string(dir.join("optimal_costs.csv")).expect("optimal_costs.csv");
    println!("| domain | problem | opt | ours --optimal | expanded (FD) | s (FD) | --fast cost (lama) | --fast expanded | --fast s (lama) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (dom, prob) = (f[0], f[1]);
        let dpath = dir.join(dom).join("domain.pddl");
        let ppath = dir.join(dom).join(format!("{prob}.pddl"));
        let d = pddl::parse_domain("d", &std::fs::read_to_string(&dpath).unwrap()).unwrap();
        let p = pddl::parse_problem("p", &std::fs::read_to_string(&ppath).unwrap()).unwrap();
        let t0 = Instant::now();
        let task = pddl::ground("d", &d, &p).unwrap();
        let tg = t0.elapsed().as_secs_f64();
        let mut row = Vec::new();
        for mode in [Mode::Optimal, Mode::Fast] {
            let t1 = Instant::now();
            let (plan, st) = search(
                &task,
                &SearchOptions {
                    mode,
                    ..Default::default()
                },
            )
            .unwrap();
            let dt = t1.elapsed().as_secs_f64() + tg;
            let plan = plan.expect("solvable");
            let steps: Vec<(String, Vec<String>)> = plan
                .steps
                .iter()
                .map(|&i| {
                    (
                        task.operators[i].schema.clone(),
                        task.operators[i].args.clone(),
                    )
                })
                .collect();
            let c = pddl::validate_plan(&d, &p, &steps).expect("valid");
            row.push((c, st.expanded, dt));
        }
        println!(
            "| {dom} | {prob} | {} | {} | {} ({}) | {:.4} ({}) | {} ({}) | {} | {:.4} ({}) |",
            f[2],
            row[0].0,
            row[0].1,
            f[3],
            row[0].2,
            f[4],
            row[1].0,
            f[5],
            row[1].1,
            row[1].2,
            f[6]
        );
    }
}
