//! Exact marginals by variable elimination organised as a junction tree (Shafer–Shenoy
//! message passing; Koller & Friedman 2009, §9.3 and §10.2).
//!
//! The elimination order is greedy min-fill with min-weight tie-breaking (Koller & Friedman
//! §9.4.3.2). Eliminating variable v creates the clique `{v} ∪ N(v)`; the clique's parent is the
//! clique of the first-eliminated variable of its separator `N(v)`, which gives a junction tree.
//! Every factor goes to the clique of its first-eliminated variable. One upward and one
//! downward pass give every clique's exact belief; each variable's marginal is read from the
//! clique that eliminated it. Messages are rescaled (max 1) so products of many factors do not
//! underflow. Used by the tests as an oracle and as a fallback for small graphs.

use crate::factor::{Factor, FactorGraph};
use crate::GraphError;
use std::collections::BTreeSet;

/// A plan for exact inference: the elimination order and its cliques.
#[derive(Debug, Clone)]
pub struct EliminationPlan {
    /// Variables in elimination order.
    pub order: Vec<usize>,
    /// Clique created by each elimination step (eliminated variable first).
    pub cliques: Vec<Vec<usize>>,
    /// Sum of the clique table sizes.
    pub total_entries: f64,
    /// Size of the largest clique table.
    pub max_clique_entries: f64,
}

/// Greedy min-fill elimination order for the graph's interaction graph.
pub fn plan(g: &FactorGraph) -> EliminationPlan {
    let n = g.num_vars();
    let mut adj: Vec<BTreeSet<usize>> = vec![BTreeSet::new(); n];
    for f in g.factors() {
        for &a in f.vars() {
            for &b in f.vars() {
                if a != b {
                    adj[a].insert(b);
                }
            }
        }
    }
    let cards = g.cards();
    let mut alive = vec![true; n];
    let mut order = Vec::with_capacity(n);
    let mut cliques = Vec::with_capacity(n);
    let (mut total, mut maxc) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let mut best = usize::MAX;
        let mut best_key = (usize::MAX, f64::INFINITY);
        for v in 0..n {
            if !alive[v] {
                continue;
            }
            let nb: Vec<usize> = adj[v].iter().copied().collect();
            let mut fill = 0;
            for i in 0..nb.len() {
                for j in i + 1..nb.len() {
                    if !adj[nb[i]].contains(&nb[j]) {
                        fill += 1;
                    }
                }
            }
            let w: f64 =
                (cards[v] as f64).ln() + nb.iter().map(|&u| (cards[u] as f64).ln()).sum::<f64>();
            if fill < best_key.0 || (fill == best_key.0 && w < best_key.1) {
                best = v;
                best_key = (fill, w);
            }
        }
        let v = best;
        let nb: Vec<usize> = adj[v].iter().copied().collect();
        for &a in &nb {
            adj[a].remove(&v);
            for &b in &nb {
                if a != b {
                    adj[a].insert(b);
                }
            }
        }
        adj[v].clear();
        alive[v] = false;
        let mut c = vec![v];
        c.extend(nb);
        let size = best_key.1.exp();
        total += size;
        maxc = maxc.max(size);
        order.push(v);
        cliques.push(c);
    }
    EliminationPlan {
        order,
        cliques,
        total_entries: total,
        max_clique_entries: maxc,
    }
}

/// Exact marginals of every variable. Fails with [`GraphError::TooLarge`] when the junction
/// tree would hold more than `max_entries` table entries, and with
/// [`GraphError::Inconsistent`] when the factors give every configuration probability zero.
pub fn exact_marginals(g: &FactorGraph, max_entries: usize) -> Result<Vec<Vec<f64>>, GraphError> {
    let pl = plan(g);
    if pl.total_entries > max_entries as f64 {
        return Err(GraphError::TooLarge {
            needed: pl.total_entries,
            limit: max_entries,
        });
    }
    let n = g.num_vars();
    let cards = g.cards();
    let mut step_of = vec![0usize; n];
    for (k, &v) in pl.order.iter().enumerate() {
        step_of[v] = k;
    }
    let mut parent: Vec<Option<usize>> = vec![None; n];
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); n];
    let seps: Vec<Vec<usize>> = pl.cliques.iter().map(|c| c[1..].to_vec()).collect();
    for k in 0..n {
        if let Some(p) = seps[k].iter().map(|&u| step_of[u]).min() {
            parent[k] = Some(p);
            children[p].push(k);
        }
    }
    let mut pot: Vec<Factor> = pl
        .cliques
        .iter()
        .map(|c| Factor::ones(c.clone(), c.iter().map(|&v| cards[v]).collect()))
        .collect::<Result<_, _>>()?;
    for f in g.factors() {
        if let Some(k) = f.vars().iter().map(|&v| step_of[v]).min() {
            let mut p = pot[k].product(f);
            p.normalize_max();
            // keep the clique's variable order
            pot[k] = p.marginal(&pl.cliques[k]);
        }
    }
    let mut up: Vec<Option<Factor>> = vec![None; n];
    for k in 0..n {
        if parent[k].is_none() {
            continue;
        }
        let mut b = pot[k].clone();
        for &c in &children[k] {
            b = b.product(up[c].as_ref().expect("children come first"));
            b.normalize_max();
        }
        let mut m = b.marginal(&seps[k]);
        m.normalize_max();
        up[k] = Some(m);
    }
    let mut down: Vec<Option<Factor>> = vec![None; n];
    let mut marginals = vec![Vec::new(); n];
    for k in (0..n).rev() {
        let mut base = pot[k].clone();
        if let Some(d) = &down[k] {
            base = base.product(d);
            base.normalize_max();
        }
        for &c in &children[k] {
            let mut b = base.clone();
            for &c2 in &children[k] {
                if c2 != c {
                    b = b.product(up[c2].as_ref().expect("set above"));
                    b.normalize_max();
                }
            }
            let mut m = b.marginal(&seps[c]);
            m.normalize_max();
            down[c] = Some(m);
        }
        let mut full = base;
        for &c in &children[k] {
            full = full.product(up[c].as_ref().expect("set above"));
            full.normalize_max();
        }
        let v = pl.order[k];
        let m = full.marginal(&[v]);
        let z: f64 = m.values().iter().sum();
        if !(z > 0.0 && z.is_finite()) {
            return Err(GraphError::Inconsistent(format!(
                "every configuration has probability zero (seen at variable {v})"
            )));
        }
        marginals[v] = m.values().iter().map(|x| x / z).collect();
    }
    Ok(marginals)
}
