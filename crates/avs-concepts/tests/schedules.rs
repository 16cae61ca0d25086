//! The BP schedules and stopping rule as documented in `avs_concepts::bp` (libDAI's), pinned
//! by traces computed by hand; and BP's zeros named for what they are.

use avs_concepts::bp::{run_bp, BpOptions, Updates};
use avs_concepts::factor::{Factor, FactorGraph};
use avs_concepts::GraphError;

fn close(got: &[f64], want: &[f64]) {
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-12, "got {got:?}, want {want:?}");
    }
}

/// Binary a (variable 0) and b (variable 1); factors in this order:
/// F0(a, b) with f(0,0) = 1, f(1,0) = 2, f(0,1) = 4, f(1,1) = 1 (first variable fastest);
/// F1(a) = (1, 3); F2(b) = (2, 1).
fn chain() -> FactorGraph {
    let mut g = FactorGraph::new(vec![2, 2]).unwrap();
    g.add_factor(Factor::new(vec![0, 1], vec![2, 2], vec![1.0, 2.0, 4.0, 1.0]).unwrap())
        .unwrap();
    g.add_factor(Factor::new(vec![0], vec![2], vec![1.0, 3.0]).unwrap())
        .unwrap();
    g.add_factor(Factor::new(vec![1], vec![2], vec![2.0, 1.0]).unwrap())
        .unwrap();
    g
}

fn seqfix(maxiter: usize) -> BpOptions {
    BpOptions {
        updates: Updates::SeqFix,
        tol: 1e-12,
        maxiter,
        ..BpOptions::default()
    }
}

#[test]
fn seqfix_goes_factor_by_factor_as_a_hand_computed_two_sweep_trace() {
    let g = chain();
    // Messages start at 1. Sweep 1, factor by factor (F0 → a, F0 → b, F1 → a, F2 → b):
    //   F0 → a: Σ_b f(a, b)·[F2 → b = (1, 1)]  = (1 + 4, 2 + 1) = (5, 3) → (5/8, 3/8)
    //   F0 → b: Σ_a f(a, b)·[F1 → a = (1, 1)]  = (1 + 2, 4 + 1) = (3, 5) → (3/8, 5/8)
    //   F1 → a: its table (1, 3);  F2 → b: its table (2, 1).
    // Beliefs: a ∝ (5/8·1, 3/8·3) = (5, 9)/8 → (5/14, 9/14);
    //          b ∝ (3/8·2, 5/8·1) = (6, 5)/8 → (6/11, 5/11).
    // (Variable by variable — a's factors F0, F1, then b's F0, F2 — F0 → b would already see
    // F1 → a = (1, 3): (1·1 + 2·3, 4·1 + 1·3) = (7, 7) → (1/2, 1/2), and b's belief would be
    // (2/3, 1/3) after one sweep.)
    let r = run_bp(&g, &seqfix(1), None).unwrap();
    assert_eq!(r.iterations, 1);
    assert!(!r.converged);
    close(&r.marginals[0], &[5.0 / 14.0, 9.0 / 14.0]);
    close(&r.marginals[1], &[6.0 / 11.0, 5.0 / 11.0]);
    // Edges: F0's variables in scope order (a, b), then F1's, then F2's; normalised.
    close(&r.messages[0], &[5.0 / 8.0, 3.0 / 8.0]);
    close(&r.messages[1], &[3.0 / 8.0, 5.0 / 8.0]);
    close(&r.messages[2], &[1.0 / 4.0, 3.0 / 4.0]);
    close(&r.messages[3], &[2.0 / 3.0, 1.0 / 3.0]);

    // Sweep 2:
    //   F0 → a: Σ_b f(a, b)·(2, 1)_b = (1·2 + 4·1, 2·2 + 1·1) = (6, 5) → (6/11, 5/11)
    //   F0 → b: Σ_a f(a, b)·(1, 3)_a = (1·1 + 2·3, 4·1 + 1·3) = (7, 7) → (1/2, 1/2)
    //   F1 → a, F2 → b: unchanged.
    // Beliefs: a ∝ (6/11·1, 5/11·3) = (6, 15)/11 → (2/7, 5/7);
    //          b ∝ (1/2·2, 1/2·1) → (2/3, 1/3).
    // These are exact (a tree): P(a, b) ∝ F1(a) F2(b) f(a, b) = 2, 12, 4, 3 at (0,0), (1,0),
    // (0,1), (1,1); Z = 21, P(a = 0) = 6/21 = 2/7, P(b = 0) = 14/21 = 2/3.
    let r = run_bp(&g, &seqfix(2), None).unwrap();
    assert_eq!(r.iterations, 2);
    close(&r.marginals[0], &[2.0 / 7.0, 5.0 / 7.0]);
    close(&r.marginals[1], &[2.0 / 3.0, 1.0 / 3.0]);
    close(&r.messages[0], &[6.0 / 11.0, 5.0 / 11.0]);
    close(&r.messages[1], &[0.5, 0.5]);

    // Sweep 3 recomputes sweep 2's messages from the same inputs, so nothing changes: BP
    // stops after iteration 3 with a belief change of exactly 0.
    let r = run_bp(&g, &seqfix(100), None).unwrap();
    assert!(r.converged);
    assert_eq!(r.iterations, 3);
    assert_eq!(r.max_diff, 0.0);
}

#[test]
fn the_stopping_rule_counts_factor_beliefs_as_libdai_maxdiff() {
    // One symmetric factor f(a, b) = 2 if a = b else 1, nothing else: both variable beliefs
    // are (1/2, 1/2) from the start, so only the factor belief can change. Before the first
    // iteration it is uniform (1/4 each, libDAI's start); after it, f normalised:
    // (2, 1, 1, 2)/6, a change of 1/3 − 1/4 = 1/12. Iteration 2 changes nothing.
    let mut g = FactorGraph::new(vec![2, 2]).unwrap();
    g.add_factor(Factor::new(vec![0, 1], vec![2, 2], vec![2.0, 1.0, 1.0, 2.0]).unwrap())
        .unwrap();
    for updates in [Updates::Parall, Updates::SeqFix, Updates::SeqMax] {
        let o = BpOptions {
            updates,
            tol: 1e-12,
            ..BpOptions::default()
        };
        let one = run_bp(
            &g,
            &BpOptions {
                maxiter: 1,
                ..o.clone()
            },
            None,
        )
        .unwrap();
        assert!(!one.converged, "{updates:?}");
        assert!((one.max_diff - 1.0 / 12.0).abs() < 1e-15, "{updates:?}");
        let r = run_bp(&g, &o, None).unwrap();
        assert!(r.converged, "{updates:?}");
        assert_eq!(r.iterations, 2, "{updates:?}");
    }
}

#[test]
fn a_linear_domain_underflow_is_named_as_bps_not_as_contradictory_evidence() {
    // x is observed at 1 (an indicator factor (0, 1)) after 400 factors (1, 0.01) that each
    // favour 0. P(x = 1) = 1 exactly: the evidence is consistent. In the linear domain BP's
    // belief of x multiplies 0.01 four hundred times (1e-800 underflows to 0) at x = 1 and
    // the indicator's 0 at x = 0: zero for both values.
    let mut g = FactorGraph::new(vec![2]).unwrap();
    for _ in 0..400 {
        g.add_factor(Factor::new(vec![0], vec![2], vec![1.0, 0.01]).unwrap())
            .unwrap();
    }
    g.clamp(0, 1).unwrap();
    match run_bp(&g, &BpOptions::default(), None) {
        Err(GraphError::BpNumericalZero {
            what, iteration, ..
        }) => {
            assert_eq!(what, "the belief of variable 0");
            assert_eq!(iteration, 1);
        }
        other => panic!("expected BP's numerical zero, got {other:?}"),
    }
    let msg = run_bp(&g, &BpOptions::default(), None)
        .unwrap_err()
        .to_string();
    assert!(msg.contains("not contradictory evidence"), "{msg}");
    assert!(msg.contains("log domain"), "{msg}");
    // The log domain has the range: ln 0.01 · 400 ≈ −1842 is finite.
    let log = BpOptions {
        logdomain: true,
        ..BpOptions::default()
    };
    let r = run_bp(&g, &log, None).unwrap();
    assert_eq!(r.marginals[0], vec![0.0, 1.0]);
}

#[test]
fn contradictory_evidence_is_found_by_arc_consistency_and_said_so() {
    // a = 0 observed, b = 1 observed, and a factor allowing only a = b: no configuration has
    // positive probability. After the first sweep the belief of F0, f(a, b)·(1, 0)_a·(0, 1)_b,
    // is zero everywhere (and the next sweep's messages would be too). Arc consistency
    // removes a = 1 and b = 0 (the evidence), then a = 0 (its only partner, b = 0, is gone):
    // a is left empty.
    let mut g = FactorGraph::new(vec![2, 2]).unwrap();
    g.add_factor(Factor::new(vec![0, 1], vec![2, 2], vec![1.0, 0.0, 0.0, 1.0]).unwrap())
        .unwrap();
    g.clamp(0, 0).unwrap();
    g.clamp(1, 1).unwrap();
    for updates in [Updates::Parall, Updates::SeqFix, Updates::SeqMax] {
        for logdomain in [false, true] {
            let o = BpOptions {
                updates,
                logdomain,
                ..BpOptions::default()
            };
            match run_bp(&g, &o, None) {
                Err(GraphError::Inconsistent(m)) => {
                    assert!(m.contains("arc consistency"), "{m}");
                    assert!(m.contains("no value of positive probability"), "{m}");
                }
                other => {
                    panic!("{updates:?} log {logdomain}: expected Inconsistent, got {other:?}")
                }
            }
        }
    }
}
