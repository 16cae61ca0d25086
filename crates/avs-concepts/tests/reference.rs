//! BP and exact inference against libDAI's and the UAI 2014 competition's reference marginals.

use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::exact::exact_marginals;
use avs_concepts::io::{parse_fg, parse_mar, parse_uai, parse_uai_evidence};
use std::collections::BTreeMap;

/// Method name → marginals by variable label, from libDAI's `testfast.out`.
fn libdai_blocks(text: &str) -> BTreeMap<String, BTreeMap<usize, Vec<f64>>> {
    let mut out: BTreeMap<String, BTreeMap<usize, Vec<f64>>> = BTreeMap::new();
    let mut cur: Option<String> = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("# ({x") {
            let (label, rest) = rest.split_once('}').expect("label");
            let nums: Vec<f64> = rest
                .trim_matches(|c: char| " ,()".contains(c))
                .split(',')
                .map(|s| s.trim().parse().expect("number"))
                .collect();
            if let Some(m) = &cur {
                out.get_mut(m).unwrap().insert(label.parse().unwrap(), nums);
            }
        } else if !line.starts_with('#') && !line.trim().is_empty() {
            let name = line.split_whitespace().next().unwrap().to_string();
            out.insert(name.clone(), BTreeMap::new());
            cur = Some(name);
        }
    }
    out
}

fn opts(updates: Updates, logdomain: bool) -> BpOptions {
    BpOptions {
        updates,
        damping: 0.0,
        tol: 1e-9,
        maxiter: 10_000,
        logdomain,
    }
}

#[test]
fn bp_and_exact_match_libdai_on_testfast_to_its_printed_digits() {
    let Some(dir) = avs_testdata::reference_data("bp") else {
        return;
    };
    let fg = std::fs::read_to_string(dir.join("libdai_testfast.fg")).unwrap();
    let lg = parse_fg(&fg, "libdai_testfast.fg").unwrap();
    let blocks = libdai_blocks(&std::fs::read_to_string(dir.join("libdai_testfast.out")).unwrap());
    let check = |ours: &[Vec<f64>], block: &str| {
        let refs = &blocks[block];
        assert_eq!(refs.len(), ours.len(), "{block}");
        for (i, m) in ours.iter().enumerate() {
            let r = &refs[&lg.labels[i]];
            for (a, b) in m.iter().zip(r) {
                // 4 significant digits printed: half a unit in the last place, relative.
                assert!(
                    (a - b).abs() <= 0.5e-3 * b.abs() + 1e-12,
                    "{block} x{}: ours {m:?}, libDAI {r:?}",
                    lg.labels[i]
                );
            }
        }
    };
    let ex = exact_marginals(&lg.graph, 1 << 20).unwrap();
    check(&ex, "EXACT");
    for (u, log, block) in [
        (Updates::Parall, false, "BP_PARALL"),
        (Updates::SeqFix, false, "BP_SEQFIX"),
        (Updates::SeqMax, false, "BP_SEQMAX"),
        (Updates::Parall, true, "BP_PARALL_LOG"),
        (Updates::SeqMax, true, "BP_SEQMAX_LOG"),
    ] {
        let r = run_bp(&lg.graph, &opts(u, log), None).unwrap();
        assert!(r.converged, "{block} did not converge");
        assert!(r.max_diff < 1e-9);
        check(&r.marginals, block);
    }
}

#[test]
fn exact_inference_matches_the_uai_references_where_feasible() {
    let Some(dir) = avs_testdata::reference_data("bp") else {
        return;
    };
    let mut checked = 0;
    for name in ["Grids_11", "Grids_12", "Segmentation_11", "DBN_11"] {
        let path = dir.join(format!("{name}.uai"));
        let mut g = parse_uai(&std::fs::read_to_string(&path).unwrap(), name).unwrap();
        let ev = parse_uai_evidence(
            &std::fs::read_to_string(dir.join(format!("{name}.uai.evid"))).unwrap(),
            name,
        )
        .unwrap();
        for (v, x) in ev {
            g.clamp(v, x).unwrap();
        }
        let refs = parse_mar(
            &std::fs::read_to_string(dir.join(format!("{name}.uai.MAR"))).unwrap(),
            name,
        )
        .unwrap();
        match exact_marginals(&g, 1 << 23) {
            Ok(m) => {
                checked += 1;
                let err = m
                    .iter()
                    .flatten()
                    .zip(refs.iter().flatten())
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                // The references print 6 significant digits.
                assert!(err < 5e-6, "{name}: max error {err}");
            }
            Err(e) => eprintln!("{name}: exact inference not feasible here: {e}"),
        }
        // BP must at least produce proper distributions of the right shape.
        let mut o = opts(Updates::SeqFix, false);
        o.maxiter = 100;
        let r = run_bp(&g, &o, None).unwrap();
        assert_eq!(r.marginals.len(), refs.len());
        for m in &r.marginals {
            assert!((m.iter().sum::<f64>() - 1.0).abs() < 1e-9);
        }
    }
    assert!(
        checked >= 1,
        "exact inference should be feasible on Segmentation_11"
    );
}
