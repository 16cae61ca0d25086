//! Sum-product loopy belief propagation on factor graphs (Pearl 1988; Kschischang, Frey &
//! Loeliger 2001, eqs. 5–6), with libDAI's options and schedules.
//!
//! Messages go from factors to variables. The message from factor I to variable i is
//! `m_{I→i}(x_i) ∝ Σ_{x_I \ x_i} f_I(x_I) Π_{j ∈ N(I)\i} Π_{J ∈ N(j)\I} m_{J→j}(x_j)`
//! (the variable-to-factor messages are formed on the fly), normalised to sum 1. Beliefs are
//! `b_i(x_i) ∝ Π_{I ∈ N(i)} m_{I→i}(x_i)`. As in libDAI (Mooij 2010, `BP`):
//! * `PARALL` computes every new message from the old ones, then replaces them all;
//! * `SEQFIX` updates the messages one at a time in a fixed order (variables in order, each
//!   variable's factors in order), always using the newest messages;
//! * `SEQMAX` (residual BP, Elidan et al. 2006) repeatedly updates the message whose new value
//!   differs most from its current one (a priority queue of residuals, as libDAI's);
//! * damping `d` replaces a message by `new^(1−d) · old^d` (geometric, as libDAI);
//! * an iteration is one sweep (PARALL, SEQFIX) or as many single updates as there are edges
//!   (SEQMAX); BP stops when the largest change of a variable belief (L∞) over one iteration is
//!   below `tol` (libDAI's `maxdiff`), or after `maxiter` iterations; the largest message change
//!   of the last iteration is reported too;
//! * `logdomain` keeps messages as logarithms and sums with log-sum-exp.
//!
//! On a tree, BP is exact after at most diameter-many parallel iterations.

use crate::factor::FactorGraph;
use crate::GraphError;
use std::str::FromStr;

/// The message schedule, named as libDAI names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Updates {
    /// Sequential, fixed order.
    #[default]
    SeqFix,
    /// Sequential, largest residual first.
    SeqMax,
    /// Parallel (flooding).
    Parall,
}

impl FromStr for Updates {
    type Err = GraphError;
    fn from_str(s: &str) -> Result<Self, GraphError> {
        match s.to_ascii_uppercase().as_str() {
            "SEQFIX" => Ok(Updates::SeqFix),
            "SEQMAX" => Ok(Updates::SeqMax),
            "PARALL" => Ok(Updates::Parall),
            _ => Err(GraphError::Invalid(format!(
                "unknown BP schedule `{s}`; expected SEQFIX, SEQMAX or PARALL"
            ))),
        }
    }
}

/// Options of loopy BP (libDAI's names: updates, damping, tol, maxiter, logdomain).
#[derive(Debug, Clone, PartialEq)]
pub struct BpOptions {
    /// Message schedule.
    pub updates: Updates,
    /// Damping in [0, 1): 0 is none.
    pub damping: f64,
    /// Convergence tolerance on the L∞ change of the beliefs over one iteration.
    pub tol: f64,
    /// Iteration limit.
    pub maxiter: usize,
    /// Keep messages in the log domain.
    pub logdomain: bool,
}

impl Default for BpOptions {
    /// libDAI's test settings: SEQFIX, no damping, tol 1e-9, maxiter 10000, linear domain.
    fn default() -> Self {
        Self {
            updates: Updates::SeqFix,
            damping: 0.0,
            tol: 1e-9,
            maxiter: 10_000,
            logdomain: false,
        }
    }
}

/// What BP computed.
#[derive(Debug, Clone, PartialEq)]
pub struct BpResult {
    /// Marginal (belief) of each variable, summing to 1.
    pub marginals: Vec<Vec<f64>>,
    /// Iterations run.
    pub iterations: usize,
    /// Whether the last belief change was below `tol`.
    pub converged: bool,
    /// The last iteration's largest belief change (L∞) — libDAI's `maxdiff`, the quantity
    /// compared with `tol`.
    pub max_diff: f64,
    /// The last iteration's largest message change (L∞, probabilities).
    pub max_message_change: f64,
    /// The factor-to-variable messages (probabilities), by edge: factor 0's variables in
    /// scope order, then factor 1's, …; pass them back as a warm start.
    pub messages: Vec<Vec<f64>>,
}

/// The edges of a factor graph: edge `start[f] + p` joins factor `f` and its `p`-th variable;
/// its message lives at `msgs[off[e] .. off[e] + card]`.
#[derive(Debug, Clone)]
struct Topo {
    start: Vec<usize>,
    edge_var: Vec<usize>,
    edge_factor: Vec<usize>,
    edge_pos: Vec<usize>,
    off: Vec<usize>,
    var_edges: Vec<Vec<usize>>,
    total: usize,
}

impl Topo {
    fn new(g: &FactorGraph) -> Self {
        let mut t = Topo {
            start: Vec::with_capacity(g.factors().len()),
            edge_var: Vec::new(),
            edge_factor: Vec::new(),
            edge_pos: Vec::new(),
            off: Vec::new(),
            var_edges: vec![Vec::new(); g.num_vars()],
            total: 0,
        };
        for (f, fac) in g.factors().iter().enumerate() {
            t.start.push(t.edge_var.len());
            for (p, &v) in fac.vars().iter().enumerate() {
                t.var_edges[v].push(t.edge_var.len());
                t.edge_var.push(v);
                t.edge_factor.push(f);
                t.edge_pos.push(p);
                t.off.push(t.total);
                t.total += g.cards()[v];
            }
        }
        t
    }
}

struct Engine<'g> {
    g: &'g FactorGraph,
    t: Topo,
    log: bool,
    logf: Vec<Vec<f64>>,
    /// Scratch: the variable-to-factor message of each scope position, flat.
    inputs: Vec<f64>,
    in_off: Vec<usize>,
    state: Vec<usize>,
    acc: Vec<f64>,
}

/// Number of edges (messages) of a factor graph; the length of [`BpResult::messages`].
pub fn num_edges(g: &FactorGraph) -> usize {
    g.factors().iter().map(|f| f.vars().len()).sum()
}

impl<'g> Engine<'g> {
    fn new(g: &'g FactorGraph, log: bool) -> Self {
        let logf = if log {
            g.factors()
                .iter()
                .map(|f| f.values().iter().map(|v| v.ln()).collect())
                .collect()
        } else {
            Vec::new()
        };
        Engine {
            g,
            t: Topo::new(g),
            log,
            logf,
            inputs: Vec::new(),
            in_off: Vec::new(),
            state: Vec::new(),
            acc: Vec::new(),
        }
    }

    fn card(&self, e: usize) -> usize {
        self.g.cards()[self.t.edge_var[e]]
    }

    /// The variable-to-factor message along edge `eq` (product / sum of the other factors'
    /// messages to its variable), written to `self.inputs[at..]`.
    fn var_to_factor(&mut self, eq: usize, msgs: &[f64], at: usize) {
        let v = self.t.edge_var[eq];
        let c = self.g.cards()[v];
        let buf = &mut self.inputs[at..at + c];
        buf.fill(if self.log { 0.0 } else { 1.0 });
        for &e2 in &self.t.var_edges[v] {
            if e2 == eq {
                continue;
            }
            let m = &msgs[self.t.off[e2]..self.t.off[e2] + c];
            if self.log {
                buf.iter_mut().zip(m).for_each(|(a, b)| *a += b);
            } else {
                buf.iter_mut().zip(m).for_each(|(a, b)| *a *= b);
            }
        }
    }

    /// New message along edge `e` from the current messages, written to `out`.
    fn calc(&mut self, e: usize, msgs: &[f64], out: &mut [f64]) -> Result<(), GraphError> {
        let f = self.t.edge_factor[e];
        let p = self.t.edge_pos[e];
        let g = self.g;
        let fac = &g.factors()[f];
        let n = fac.vars().len();
        let cards = fac.cards();
        if !self.log && n <= 2 {
            // Fast paths for unary and pairwise factors (linear domain).
            let vals = fac.values();
            if n == 1 {
                out.copy_from_slice(vals);
            } else {
                let q = 1 - p;
                let cq = cards[q];
                if self.inputs.len() < cq {
                    self.inputs.resize(cq, 0.0);
                }
                self.var_to_factor(self.t.start[f] + q, msgs, 0);
                let inp = &self.inputs[..cq];
                let c0 = cards[0];
                if p == 0 {
                    out.fill(0.0);
                    for (s1, w) in inp.iter().enumerate() {
                        let row = &vals[s1 * c0..(s1 + 1) * c0];
                        out.iter_mut().zip(row).for_each(|(o, f)| *o += f * w);
                    }
                } else {
                    for (s1, o) in out.iter_mut().enumerate() {
                        let row = &vals[s1 * c0..(s1 + 1) * c0];
                        *o = row.iter().zip(inp).map(|(f, w)| f * w).sum();
                    }
                }
            }
            let z: f64 = out.iter().sum();
            if !(z > 0.0 && z.is_finite()) {
                return Err(self.zero(e));
            }
            let inv = 1.0 / z;
            out.iter_mut().for_each(|x| *x *= inv);
            return Ok(());
        }
        self.in_off.clear();
        let mut tot = 0;
        for &c in cards {
            self.in_off.push(tot);
            tot += c;
        }
        if self.inputs.len() < tot {
            self.inputs.resize(tot, 0.0);
        }
        for q in 0..n {
            if q != p {
                let at = self.in_off[q];
                self.var_to_factor(self.t.start[f] + q, msgs, at);
            }
        }
        let cp = cards[p];
        if self.log {
            let table = &self.logf[f];
            self.state.clear();
            self.state.resize(n, 0);
            self.acc.clear();
            self.acc.resize(cp, 0.0);
            let (m, s) = (&mut *out, &mut self.acc);
            m.fill(f64::NEG_INFINITY);
            for &lt in table.iter() {
                if lt != f64::NEG_INFINITY {
                    let mut x = lt;
                    for q in 0..n {
                        if q != p {
                            x += self.inputs[self.in_off[q] + self.state[q]];
                        }
                    }
                    let o = self.state[p];
                    if x > m[o] {
                        s[o] = s[o] * (m[o] - x).exp() + 1.0;
                        m[o] = x;
                    } else if x != f64::NEG_INFINITY {
                        s[o] += (x - m[o]).exp();
                    }
                }
                odometer(&mut self.state, cards);
            }
            for (mo, so) in m.iter_mut().zip(s.iter()) {
                if *mo != f64::NEG_INFINITY {
                    *mo += so.ln();
                }
            }
            let z = logsumexp(m);
            if !z.is_finite() {
                return Err(self.zero(e));
            }
            m.iter_mut().for_each(|x| *x -= z);
            return Ok(());
        }
        let vals = fac.values();
        out.fill(0.0);
        self.state.clear();
        self.state.resize(n, 0);
        for &x0 in vals {
            if x0 != 0.0 {
                let mut x = x0;
                for q in 0..n {
                    if q != p {
                        x *= self.inputs[self.in_off[q] + self.state[q]];
                    }
                }
                out[self.state[p]] += x;
            }
            odometer(&mut self.state, cards);
        }
        let z: f64 = out.iter().sum();
        if !(z > 0.0 && z.is_finite()) {
            return Err(self.zero(e));
        }
        out.iter_mut().for_each(|x| *x /= z);
        Ok(())
    }

    fn zero(&self, e: usize) -> GraphError {
        GraphError::Inconsistent(format!(
            "the message from factor {} to variable {} is zero everywhere (contradictory evidence or factors)",
            self.t.edge_factor[e], self.t.edge_var[e]
        ))
    }

    fn damp(&self, new: &mut [f64], old: &[f64], d: f64) {
        if d == 0.0 {
            return;
        }
        if self.log {
            new.iter_mut().zip(old).for_each(|(n, o)| {
                *n = if *o == f64::NEG_INFINITY || *n == f64::NEG_INFINITY {
                    f64::NEG_INFINITY
                } else {
                    (1.0 - d) * *n + d * o
                }
            });
            let z = logsumexp(new);
            new.iter_mut().for_each(|x| *x -= z);
        } else {
            new.iter_mut()
                .zip(old)
                .for_each(|(n, o)| *n = n.powf(1.0 - d) * o.powf(d));
            let z: f64 = new.iter().sum();
            if z > 0.0 {
                new.iter_mut().for_each(|x| *x /= z);
            }
        }
    }

    fn dist(&self, a: &[f64], b: &[f64]) -> f64 {
        if self.log {
            a.iter()
                .zip(b)
                .map(|(x, y)| (x.exp() - y.exp()).abs())
                .fold(0.0, f64::max)
        } else {
            linf(a, b)
        }
    }

    fn belief(&self, v: usize, msgs: &[f64], b: &mut [f64]) -> Result<(), GraphError> {
        let card = self.g.cards()[v];
        if self.log {
            b.fill(0.0);
            for &e in &self.t.var_edges[v] {
                b.iter_mut()
                    .zip(&msgs[self.t.off[e]..self.t.off[e] + card])
                    .for_each(|(a, x)| *a += x);
            }
            let z = logsumexp(b);
            if !z.is_finite() {
                return Err(GraphError::Inconsistent(format!(
                    "the belief of variable {v} is zero everywhere (contradictory evidence)"
                )));
            }
            b.iter_mut().for_each(|x| *x = (*x - z).exp());
        } else {
            b.fill(1.0);
            for &e in &self.t.var_edges[v] {
                b.iter_mut()
                    .zip(&msgs[self.t.off[e]..self.t.off[e] + card])
                    .for_each(|(a, x)| *a *= x);
            }
            let z: f64 = b.iter().sum();
            if !(z > 0.0 && z.is_finite()) {
                return Err(GraphError::Inconsistent(format!(
                    "the belief of variable {v} is zero everywhere (contradictory evidence)"
                )));
            }
            b.iter_mut().for_each(|x| *x /= z);
        }
        Ok(())
    }
}

/// A residual in the SEQMAX priority queue: (residual, edge, version); larger residual
/// first, then smaller edge index (deterministic ties).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Resid(f64, usize, u64);

impl Eq for Resid {}

impl PartialOrd for Resid {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Resid {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0
            .total_cmp(&other.0)
            .then_with(|| other.1.cmp(&self.1))
    }
}

fn odometer(state: &mut [usize], cards: &[usize]) {
    for d in 0..state.len() {
        state[d] += 1;
        if state[d] < cards[d] {
            return;
        }
        state[d] = 0;
    }
}

fn logsumexp(x: &[f64]) -> f64 {
    let m = x.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if m == f64::NEG_INFINITY {
        return m;
    }
    m + x.iter().map(|v| (v - m).exp()).sum::<f64>().ln()
}

fn linf(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Run sum-product loopy BP. `warm`, if given, holds the starting messages by edge (as
/// returned in [`BpResult::messages`] for the same graph structure); otherwise they start
/// uniform.
pub fn run_bp(
    g: &FactorGraph,
    opts: &BpOptions,
    warm: Option<&[Vec<f64>]>,
) -> Result<BpResult, GraphError> {
    if !(0.0..1.0).contains(&opts.damping) {
        return Err(GraphError::Invalid(format!(
            "damping {} is outside [0, 1)",
            opts.damping
        )));
    }
    if opts.tol.is_nan() || opts.tol < 0.0 {
        return Err(GraphError::Invalid(format!("tol {} is not >= 0", opts.tol)));
    }
    let mut en = Engine::new(g, opts.logdomain);
    let ne = en.t.edge_var.len();
    let mut msgs = vec![0.0; en.t.total];
    match warm {
        Some(w) => {
            if w.len() != ne || (0..ne).any(|e| w[e].len() != en.card(e)) {
                return Err(GraphError::Invalid(
                    "warm-start messages do not fit the graph's edges".into(),
                ));
            }
            for (e, m) in w.iter().enumerate() {
                let z: f64 = m.iter().sum();
                let ok = z > 0.0 && z.is_finite() && m.iter().all(|x| *x >= 0.0);
                let dst = &mut msgs[en.t.off[e]..en.t.off[e] + m.len()];
                for (d, x) in dst.iter_mut().zip(m) {
                    let p = if ok { x / z } else { 1.0 / m.len() as f64 };
                    *d = if opts.logdomain { p.ln() } else { p };
                }
            }
        }
        None => {
            for e in 0..ne {
                let c = en.card(e);
                let u = if opts.logdomain {
                    -(c as f64).ln()
                } else {
                    1.0 / c as f64
                };
                msgs[en.t.off[e]..en.t.off[e] + c].fill(u);
            }
        }
    }
    let nv = g.num_vars();
    let mut old: Vec<Vec<f64>> = g.cards().iter().map(|&c| vec![0.0; c]).collect();
    for (v, b) in old.iter_mut().enumerate() {
        en.belief(v, &msgs, b)?;
    }
    let maxc = g.cards().iter().copied().max().unwrap_or(1);
    let mut tmp = vec![0.0; maxc];
    let mut bel = vec![0.0; maxc];
    // SEQFIX order: variables in order, each variable's factors in order (as libDAI).
    let seq: Vec<usize> = en.t.var_edges.iter().flatten().copied().collect();
    let mut newm = vec![
        0.0;
        if opts.updates == Updates::SeqFix {
            0
        } else {
            en.t.total
        }
    ];
    let mut resid = vec![0.0; ne];
    let mut version = vec![0u64; ne];
    let mut heap: std::collections::BinaryHeap<Resid> = std::collections::BinaryHeap::new();
    let mut iterations = 0;
    let mut max_diff = f64::INFINITY;
    let mut converged = false;
    let mut msg_change = 0.0f64;
    while iterations < opts.maxiter {
        msg_change = 0.0;
        match opts.updates {
            Updates::Parall => {
                for e in 0..ne {
                    let (o, c) = (en.t.off[e], en.card(e));
                    en.calc(e, &msgs, &mut newm[o..o + c])?;
                    en.damp(&mut newm[o..o + c], &msgs[o..o + c], opts.damping);
                    msg_change = msg_change.max(en.dist(&newm[o..o + c], &msgs[o..o + c]));
                }
                std::mem::swap(&mut msgs, &mut newm);
            }
            Updates::SeqFix => {
                for &e in &seq {
                    let (o, c) = (en.t.off[e], en.card(e));
                    en.calc(e, &msgs, &mut tmp[..c])?;
                    en.damp(&mut tmp[..c], &msgs[o..o + c], opts.damping);
                    msg_change = msg_change.max(en.dist(&tmp[..c], &msgs[o..o + c]));
                    msgs[o..o + c].copy_from_slice(&tmp[..c]);
                }
            }
            Updates::SeqMax => {
                if iterations == 0 {
                    for (e, r) in resid.iter_mut().enumerate() {
                        let (o, c) = (en.t.off[e], en.card(e));
                        en.calc(e, &msgs, &mut newm[o..o + c])?;
                        *r = en.dist(&newm[o..o + c], &msgs[o..o + c]);
                        heap.push(Resid(*r, e, 0));
                    }
                }
                for _ in 0..ne {
                    if heap.len() > 4 * ne + 64 {
                        // drop the stale entries
                        heap = resid
                            .iter()
                            .enumerate()
                            .map(|(e, r)| Resid(*r, e, version[e]))
                            .collect();
                    }
                    // the largest current residual (stale heap entries are skipped)
                    let best = loop {
                        match heap.pop() {
                            Some(Resid(_, e, v)) if v == version[e] => break Some(e),
                            Some(_) => continue,
                            None => break None,
                        }
                    };
                    let Some(best) = best else { break };
                    let (o, c) = (en.t.off[best], en.card(best));
                    tmp[..c].copy_from_slice(&newm[o..o + c]);
                    en.damp(&mut tmp[..c], &msgs[o..o + c], opts.damping);
                    msg_change = msg_change.max(en.dist(&tmp[..c], &msgs[o..o + c]));
                    msgs[o..o + c].copy_from_slice(&tmp[..c]);
                    resid[best] = 0.0;
                    version[best] += 1;
                    heap.push(Resid(0.0, best, version[best]));
                    let i = en.t.edge_var[best];
                    let fi = en.t.edge_factor[best];
                    for k in 0..en.t.var_edges[i].len() {
                        let fj = en.t.edge_factor[en.t.var_edges[i][k]];
                        if fj == fi {
                            continue;
                        }
                        for q in 0..g.factors()[fj].vars().len() {
                            let e2 = en.t.start[fj] + q;
                            if en.t.edge_var[e2] == i {
                                continue;
                            }
                            let (o2, c2) = (en.t.off[e2], en.card(e2));
                            en.calc(e2, &msgs, &mut tmp[..c2])?;
                            resid[e2] = en.dist(&tmp[..c2], &msgs[o2..o2 + c2]);
                            newm[o2..o2 + c2].copy_from_slice(&tmp[..c2]);
                            version[e2] += 1;
                            heap.push(Resid(resid[e2], e2, version[e2]));
                        }
                    }
                }
            }
        }
        iterations += 1;
        max_diff = 0.0;
        for (v, o) in old.iter_mut().enumerate() {
            let c = o.len();
            en.belief(v, &msgs, &mut bel[..c])?;
            max_diff = max_diff.max(linf(&bel[..c], o));
            o.copy_from_slice(&bel[..c]);
        }
        if max_diff < opts.tol {
            converged = true;
            break;
        }
    }
    let _ = nv;
    tracing::debug!(iterations, converged, max_diff, "loopy BP finished");
    let messages = (0..ne)
        .map(|e| {
            let m = &msgs[en.t.off[e]..en.t.off[e] + en.card(e)];
            if opts.logdomain {
                m.iter().map(|x| x.exp()).collect()
            } else {
                m.to_vec()
            }
        })
        .collect();
    Ok(BpResult {
        marginals: old,
        iterations,
        converged,
        max_diff,
        max_message_change: msg_change,
        messages,
    })
}
