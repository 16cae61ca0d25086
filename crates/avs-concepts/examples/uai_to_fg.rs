//! Write a UAI model, with its evidence clamped exactly as `avs infer` and `bp_report` clamp
//! it (one indicator factor per observed variable, appended in the evidence file's order), as
//! a libDAI `.fg` file, so that libDAI's BP runs on the very factor graph avs runs on.
//! `cargo run --release -p avs-concepts --example uai_to_fg -- MODEL.uai [EVID] > MODEL.fg`
//!
//! Variables are labelled `0..n` (avs's indices); tables are written first variable fastest
//! (the `.fg` convention, and avs's), with every entry in Rust's shortest round-trip form, so
//! the file denotes the same numbers.

use avs_concepts::io::{parse_uai, parse_uai_evidence};
use std::fmt::Write;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(model) = args.first() else {
        return Err("usage: uai_to_fg MODEL.uai [EVIDENCE]".into());
    };
    let mut g = parse_uai(&std::fs::read_to_string(model)?, model)?;
    if let Some(ev) = args.get(1) {
        for (v, x) in parse_uai_evidence(&std::fs::read_to_string(ev)?, ev)? {
            g.clamp(v, x)?;
        }
    }
    let mut s = format!("{}\n", g.factors().len());
    for f in g.factors() {
        let join = |xs: &[usize]| {
            xs.iter()
                .map(|x| x.to_string())
                .collect::<Vec<_>>()
                .join(" ")
        };
        let nz: Vec<(usize, f64)> = f
            .values()
            .iter()
            .copied()
            .enumerate()
            .filter(|(_, v)| *v != 0.0)
            .collect();
        write!(
            s,
            "\n{}\n{}\n{}\n{}\n",
            f.vars().len(),
            join(f.vars()),
            join(f.cards()),
            nz.len()
        )?;
        for (i, v) in nz {
            writeln!(s, "{i} {v:e}")?;
        }
    }
    print!("{s}");
    Ok(())
}
