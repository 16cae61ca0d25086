//! Property tests: BP is exact on trees; evidence never produces NaN.

use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::exact::exact_marginals;
use avs_concepts::factor::{Factor, FactorGraph};
use proptest::prelude::*;

/// A random tree: variable i > 0 hangs off a parent < i by a pairwise factor; every variable
/// has a unary factor. Values are in [0.05, 5).
fn tree() -> impl Strategy<Value = FactorGraph> {
    (1usize..10)
        .prop_flat_map(|n| {
            (
                prop::collection::vec(2usize..4, n),
                prop::collection::vec(any::<prop::sample::Index>(), n),
                prop::collection::vec(0.05f64..5.0, 16 * n + 16),
            )
        })
        .prop_map(|(cards, parents, vals)| {
            let n = cards.len();
            let mut g = FactorGraph::new(cards.clone()).unwrap();
            let mut vi = vals.into_iter().cycle();
            for v in 0..n {
                let t: Vec<f64> = (0..cards[v]).map(|_| vi.next().unwrap()).collect();
                g.add_factor(Factor::new(vec![v], vec![cards[v]], t).unwrap())
                    .unwrap();
                if v > 0 {
                    let p = parents[v].index(v);
                    let t: Vec<f64> = (0..cards[v] * cards[p])
                        .map(|_| vi.next().unwrap())
                        .collect();
                    g.add_factor(Factor::new(vec![v, p], vec![cards[v], cards[p]], t).unwrap())
                        .unwrap();
                }
            }
            g
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn bp_equals_exact_inference_on_trees(g in tree(), sched in 0usize..3, log in any::<bool>()) {
        let updates = [Updates::Parall, Updates::SeqFix, Updates::SeqMax][sched];
        let opts = BpOptions { updates, logdomain: log, tol: 1e-12, ..BpOptions::default() };
        let bp = run_bp(&g, &opts, None).unwrap();
        prop_assert!(bp.converged);
        let ex = exact_marginals(&g, 1 << 20).unwrap();
        for (a, b) in bp.marginals.iter().zip(&ex) {
            for (x, y) in a.iter().zip(b) {
                prop_assert!((x - y).abs() < 1e-9, "bp {:?} exact {:?}", a, b);
            }
        }
    }

    #[test]
    fn clamping_evidence_gives_finite_marginals(g in tree(), which in any::<prop::sample::Index>()) {
        let mut g = g;
        let v = which.index(g.num_vars());
        g.clamp(v, 1).unwrap();
        let bp = run_bp(&g, &BpOptions::default(), None).unwrap();
        let ex = exact_marginals(&g, 1 << 20).unwrap();
        for m in bp.marginals.iter().chain(&ex) {
            prop_assert!(m.iter().all(|p| p.is_finite()));
        }
        prop_assert!((bp.marginals[v][1] - 1.0).abs() < 1e-12);
        prop_assert!((ex[v][1] - 1.0).abs() < 1e-12);
    }
}

#[test]
fn contradictory_evidence_is_an_error_not_nan() {
    let mut g = FactorGraph::new(vec![2]).unwrap();
    g.clamp(0, 0).unwrap();
    g.clamp(0, 1).unwrap();
    assert!(run_bp(&g, &BpOptions::default(), None).is_err());
    assert!(exact_marginals(&g, 1 << 10).is_err());
}

#[test]
fn warm_start_from_converged_messages_needs_one_iteration() {
    let mut g = FactorGraph::new(vec![2, 3, 2]).unwrap();
    g.add_factor(Factor::new(vec![0, 1], vec![2, 3], vec![1.0, 2.0, 3.0, 1.0, 0.5, 2.0]).unwrap())
        .unwrap();
    g.add_factor(Factor::new(vec![1, 2], vec![3, 2], vec![2.0, 1.0, 1.0, 3.0, 1.0, 1.0]).unwrap())
        .unwrap();
    g.add_factor(Factor::new(vec![2, 0], vec![2, 2], vec![3.0, 1.0, 1.0, 2.0]).unwrap())
        .unwrap();
    let opts = BpOptions {
        updates: Updates::Parall,
        ..BpOptions::default()
    };
    let cold = run_bp(&g, &opts, None).unwrap();
    assert!(cold.iterations > 1);
    let warm = run_bp(&g, &opts, Some(&cold.messages)).unwrap();
    assert_eq!(warm.iterations, 1);
    for (a, b) in warm.marginals.iter().zip(&cold.marginals) {
        for (x, y) in a.iter().zip(b) {
            assert!((x - y).abs() < 1e-9);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn model_readers_never_panic_on_arbitrary_text(text in "[ -~\n]{0,200}") {
        let _ = avs_concepts::io::parse_uai(&text, "fuzz.uai");
        let _ = avs_concepts::io::parse_fg(&text, "fuzz.fg");
        let _ = avs_concepts::io::parse_uai_evidence(&text, "fuzz.evid");
        let _ = avs_concepts::io::parse_mar(&text, "fuzz.MAR");
    }

    #[test]
    fn model_readers_never_panic_on_number_soup(nums in prop::collection::vec(0u32..6, 0..40)) {
        let body = nums.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(" ");
        let _ = avs_concepts::io::parse_uai(&format!("MARKOV {body}"), "fuzz.uai");
        let _ = avs_concepts::io::parse_fg(&body, "fuzz.fg");
        if let Ok(lg) = avs_concepts::io::parse_fg(&body, "fuzz.fg") {
            let _ = run_bp(&lg.graph, &BpOptions { maxiter: 20, ..BpOptions::default() }, None);
            let _ = exact_marginals(&lg.graph, 1 << 12);
        }
    }
}

#[test]
fn model_readers_report_the_file_and_what_was_expected() {
    let e = avs_concepts::io::parse_uai("MARKOV\n2\n2 2\n1\n2 0 5\n", "m.uai").unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.starts_with("m.uai:") && msg.contains("variable 5"),
        "{msg}"
    );
    let e = avs_concepts::io::parse_uai("MARKOV\n1\n2\n1\n1 0\n2\n0.5\n", "m.uai").unwrap_err();
    assert!(e.to_string().contains("file ends"), "{e}");
    let e = avs_concepts::io::parse_fg("1\n1\n0\n2\n1\n7 1.0\n", "m.fg").unwrap_err();
    assert!(e.to_string().contains("index 7"), "{e}");
    let e = avs_concepts::io::parse_uai("MARKOV\n1\n2\n1\n1 0\n2\n0.5 -1\n", "m.uai").unwrap_err();
    assert!(e.to_string().contains(">= 0"), "{e}");
}
