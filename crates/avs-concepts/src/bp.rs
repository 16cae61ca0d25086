//! Sum-product loopy belief propagation on factor graphs (Pearl 1988; Kschischang, Frey &
//! Loeliger 2001, eqs. 5–6), with the options, schedules and stopping rule of libDAI's `BP`
//! (Mooij 2010, *libDAI: a free and open source C++ library for discrete approximate
//! inference in graphical models*, JMLR 11; `src/bp.cpp` of libDAI 0.3).
//!
//! Messages go from factors to variables. The message from factor I to variable i is
//! `m_{I→i}(x_i) ∝ Σ_{x_I \ x_i} f_I(x_I) Π_{j ∈ N(I)\i} Π_{J ∈ N(j)\I} m_{J→j}(x_j)`
//! (the variable-to-factor messages are formed on the fly), normalised to sum 1; a factor
//! over one variable sends its table as it is. Messages start at 1 (unnormalised, as
//! libDAI's). Beliefs are `b_i(x_i) ∝ Π_{I ∈ N(i)} m_{I→i}(x_i)` and
//! `b_I(x_I) ∝ f_I(x_I) Π_{i ∈ N(I)} Π_{J ∈ N(i)\I} m_{J→i}(x_i)`.
//!
//! Each message has a *computed* value (libDAI's `newMessage`) and a *sent* value (its
//! `message`); updating a message sends its computed value, damped. New messages are always
//! computed from sent ones. The schedules, as libDAI's:
//! * `PARALL` computes every message, then sends them all;
//! * `SEQFIX` goes factor by factor — factors in order, each factor's variables in increasing
//!   index (libDAI keeps a factor's variables sorted) — computing and sending each message
//!   in turn, so later messages of a sweep see the earlier ones;
//! * `SEQMAX` (residual BP, Elidan, McGraw & Koller 2006) first computes every message
//!   (variables in order, each variable's factors in order), then repeatedly sends the
//!   message with the largest residual — the L∞ distance between its computed and sent
//!   values, in the domain messages are kept in (probabilities, or their logarithms with
//!   `logdomain`), unnormalised as they are — and recomputes the messages that depend on it:
//!   for each other factor J of the receiving variable i, J's messages to its variables other
//!   than i (J's variables in increasing index). A sent message's residual becomes 0 (without
//!   damping) or the distance between its computed and damped values. Ties go to the message
//!   whose residual was set last (libDAI keeps residuals in a `std::multimap`, where an
//!   equal key is inserted after the existing ones, and takes the last element).
//! * damping `d` sends `new^(1−d) · old^d` (linear) or `(1−d)·new + d·old` (log domain),
//!   unnormalised, as libDAI;
//! * an iteration is one sweep (PARALL, SEQFIX) or as many single updates as there are edges
//!   (SEQMAX). After each, BP forms the variable beliefs from the *computed* messages and the
//!   factor beliefs from the *sent* ones (as libDAI does; the two agree without damping,
//!   except for SEQMAX's pending messages) and stops when the largest change of any variable
//!   or factor belief (L∞, libDAI's `maxdiff`) is not above `tol`, or after `maxiter`
//!   iterations. Before the first iteration the old beliefs are uniform (or, for a warm start,
//!   those of the given messages);
//! * `logdomain` keeps messages as logarithms and sums with log-sum-exp.
//!
//! On a tree, BP is exact after at most diameter-many parallel iterations.
//!
//! **Zeros.** In exact arithmetic a message or belief of BP is never zero for every value
//! unless the model is contradictory: every value that survives generalised arc consistency
//! on the factors' supports (Mackworth 1977; Dechter 2003, *Constraint Processing*, ch. 3)
//! keeps a positive message — by induction over the updates, the configuration that supports
//! it contributes a positive term to every sum. So when BP meets a zero it runs arc
//! consistency: if it empties a variable's domain, the evidence and factors are contradictory
//! ([`GraphError::Inconsistent`]); if not, the zero is BP's own, from the range of floating
//! point ([`GraphError::BpNumericalZero`]) — the evidence may well be consistent, and the log
//! domain or exact inference will answer.

use crate::factor::FactorGraph;
use crate::GraphError;
use std::collections::BinaryHeap;
use std::str::FromStr;

/// The message schedule, named as libDAI names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Updates {
    /// Sequential, fixed order: factor by factor, each factor's variables in increasing index.
    #[default]
    SeqFix,
    /// Sequential, largest residual first (residual BP).
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
    /// Convergence tolerance on the L∞ change of the variable and factor beliefs over one
    /// iteration.
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
    /// Whether the last belief change was not above `tol`.
    pub converged: bool,
    /// The last iteration's largest change of a variable or factor belief (L∞) — libDAI's
    /// `maxdiff`, the quantity compared with `tol`.
    pub max_diff: f64,
    /// The last iteration's largest change of a sent message (L∞, both normalised to
    /// probabilities).
    pub max_message_change: f64,
    /// The sent factor-to-variable messages, normalised to probabilities, by edge: factor
    /// 0's variables in scope order, then factor 1's, …; pass them back as a warm start.
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
    /// Each variable's edges, its factors in order (libDAI's `nbV`).
    var_edges: Vec<Vec<usize>>,
    /// Factor f's edges at `sorted[start[f]..start[f + 1]]`, its variables in increasing
    /// index (libDAI's `nbF`); read whole, the SEQFIX sequence.
    sorted: Vec<usize>,
    total: usize,
}

impl Topo {
    fn new(g: &FactorGraph) -> Self {
        let mut t = Topo {
            start: Vec::with_capacity(g.factors().len() + 1),
            edge_var: Vec::new(),
            edge_factor: Vec::new(),
            edge_pos: Vec::new(),
            off: Vec::new(),
            var_edges: vec![Vec::new(); g.num_vars()],
            sorted: Vec::new(),
            total: 0,
        };
        for (f, fac) in g.factors().iter().enumerate() {
            let s = t.edge_var.len();
            t.start.push(s);
            for (p, &v) in fac.vars().iter().enumerate() {
                t.var_edges[v].push(t.edge_var.len());
                t.edge_var.push(v);
                t.edge_factor.push(f);
                t.edge_pos.push(p);
                t.off.push(t.total);
                t.total += g.cards()[v];
            }
            let mut es: Vec<usize> = (s..t.edge_var.len()).collect();
            es.sort_by_key(|&e| t.edge_var[e]);
            t.sorted.extend(es);
        }
        t.start.push(t.edge_var.len());
        t
    }
}

/// Where BP met a zero (for every value), before it is explained.
#[derive(Debug, Clone, Copy)]
enum Zero {
    /// The computed message along an edge.
    Message(usize),
    /// A variable's belief.
    VarBelief(usize),
    /// A factor's belief.
    FactorBelief(usize),
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

    fn range(&self, e: usize) -> std::ops::Range<usize> {
        self.t.off[e]..self.t.off[e] + self.card(e)
    }

    /// The variable-to-factor message along edge `eq` (product / sum of the other factors'
    /// sent messages to its variable), written to `self.inputs[at..]`.
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

    /// Fill `self.inputs` with the variable-to-factor messages into factor `f`, all scope
    /// positions but `skip`.
    fn gather(&mut self, f: usize, skip: Option<usize>, msgs: &[f64]) {
        let cards = self.g.factors()[f].cards();
        self.in_off.clear();
        let mut tot = 0;
        for &c in cards {
            self.in_off.push(tot);
            tot += c;
        }
        if self.inputs.len() < tot {
            self.inputs.resize(tot, 0.0);
        }
        for q in 0..cards.len() {
            if Some(q) != skip {
                let at = self.in_off[q];
                self.var_to_factor(self.t.start[f] + q, msgs, at);
            }
        }
    }

    /// The new message along edge `e` from the sent messages `msgs`, written to `out`.
    fn calc(&mut self, e: usize, msgs: &[f64], out: &mut [f64]) -> Result<(), Zero> {
        let f = self.t.edge_factor[e];
        let p = self.t.edge_pos[e];
        let g = self.g;
        let fac = &g.factors()[f];
        let n = fac.vars().len();
        let cards = fac.cards();
        if n == 1 {
            // A factor over one variable sends its table, unnormalised (as libDAI).
            if self.log {
                out.copy_from_slice(&self.logf[f]);
                if out.iter().all(|x| *x == f64::NEG_INFINITY) {
                    return Err(Zero::Message(e));
                }
            } else {
                out.copy_from_slice(fac.values());
                if out.iter().all(|x| *x == 0.0) {
                    return Err(Zero::Message(e));
                }
            }
            return Ok(());
        }
        if !self.log && n == 2 {
            // Fast path for pairwise factors (linear domain).
            let vals = fac.values();
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
            return normalise(out).map_err(|()| Zero::Message(e));
        }
        self.gather(f, Some(p), msgs);
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
            return log_normalise(m).map_err(|()| Zero::Message(e));
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
        normalise(out).map_err(|()| Zero::Message(e))
    }

    /// Send the computed message of edge `e` (damped by `d`); returns the change of the sent
    /// message (L∞, both normalised to probabilities). `scratch` holds at least its card.
    fn send(&self, e: usize, msgs: &mut [f64], newm: &[f64], d: f64, scratch: &mut [f64]) -> f64 {
        let r = self.range(e);
        let old = &mut scratch[..r.len()];
        old.copy_from_slice(&msgs[r.clone()]);
        let (m, n) = (&mut msgs[r.clone()], &newm[r]);
        if d == 0.0 {
            m.copy_from_slice(n);
        } else if self.log {
            m.iter_mut()
                .zip(n)
                .for_each(|(o, x)| *o = (1.0 - d) * x + d * *o);
        } else {
            m.iter_mut()
                .zip(n)
                .for_each(|(o, x)| *o = x.powf(1.0 - d) * o.powf(d));
        }
        self.prob_dist(old, m)
    }

    /// L∞ distance of two messages after normalising each to probabilities.
    fn prob_dist(&self, a: &[f64], b: &[f64]) -> f64 {
        if self.log {
            let (za, zb) = (logsumexp(a), logsumexp(b));
            a.iter()
                .zip(b)
                .map(|(x, y)| ((x - za).exp() - (y - zb).exp()).abs())
                .fold(0.0, f64::max)
        } else {
            let (za, zb) = (a.iter().sum::<f64>(), b.iter().sum::<f64>());
            a.iter()
                .zip(b)
                .map(|(x, y)| (x / za - y / zb).abs())
                .fold(0.0, f64::max)
        }
    }

    /// SEQMAX's residual: the L∞ distance of two messages as they are kept (probabilities or
    /// logarithms, unnormalised), as libDAI's `dist(…, DISTLINF)`; equal infinities count 0.
    fn resid_dist(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .map(|(x, y)| if x == y { 0.0 } else { (x - y).abs() })
            .fold(0.0, f64::max)
    }

    /// Variable `v`'s belief from the messages `m` (libDAI forms it from the computed ones).
    fn belief_var(&self, v: usize, m: &[f64], b: &mut [f64]) -> Result<(), Zero> {
        let card = self.g.cards()[v];
        b.fill(if self.log { 0.0 } else { 1.0 });
        for &e in &self.t.var_edges[v] {
            let x = &m[self.t.off[e]..self.t.off[e] + card];
            if self.log {
                b.iter_mut().zip(x).for_each(|(a, x)| *a += x);
            } else {
                b.iter_mut().zip(x).for_each(|(a, x)| *a *= x);
            }
        }
        if self.log {
            log_normalise(b).map_err(|()| Zero::VarBelief(v))?;
            b.iter_mut().for_each(|x| *x = x.exp());
            Ok(())
        } else {
            normalise(b).map_err(|()| Zero::VarBelief(v))
        }
    }

    /// Factor `f`'s belief (first variable fastest) from the sent messages `msgs`.
    fn belief_factor(&mut self, f: usize, msgs: &[f64], b: &mut [f64]) -> Result<(), Zero> {
        self.gather(f, None, msgs);
        let g = self.g;
        let fac = &g.factors()[f];
        let (n, cards) = (fac.vars().len(), fac.cards());
        self.state.clear();
        self.state.resize(n, 0);
        for (k, out) in b.iter_mut().enumerate() {
            let mut x = if self.log {
                self.logf[f][k]
            } else {
                fac.values()[k]
            };
            for q in 0..n {
                let m = self.inputs[self.in_off[q] + self.state[q]];
                if self.log {
                    x += m;
                } else {
                    x *= m;
                }
            }
            *out = x;
            odometer(&mut self.state, cards);
        }
        if self.log {
            log_normalise(b).map_err(|()| Zero::FactorBelief(f))?;
            b.iter_mut().for_each(|x| *x = x.exp());
            Ok(())
        } else {
            normalise(b).map_err(|()| Zero::FactorBelief(f))
        }
    }

    /// The error for a zero BP met in `iteration` (1-based): contradictory evidence if arc
    /// consistency finds it, BP's own numerical zero otherwise.
    fn explain(&self, z: Zero, iteration: usize) -> GraphError {
        let what = match z {
            Zero::Message(e) => format!(
                "the message from factor {} to variable {}",
                self.t.edge_factor[e], self.t.edge_var[e]
            ),
            Zero::VarBelief(v) => format!("the belief of variable {v}"),
            Zero::FactorBelief(f) => format!("the belief of factor {f}"),
        };
        match arc_consistency_wipeout(self.g) {
            Some(v) => GraphError::Inconsistent(format!(
                "the factors and evidence leave variable {v} no value of positive probability \
                 (found by arc consistency after loopy BP's {what} became zero at iteration \
                 {iteration})"
            )),
            None => GraphError::BpNumericalZero {
                what,
                iteration,
                hint: if self.log {
                    ""
                } else {
                    "; run BP in the log domain (`logdomain`)"
                },
            },
        }
    }
}

/// Normalise to sum 1; `Err` when the sum is 0 or not finite.
fn normalise(x: &mut [f64]) -> Result<(), ()> {
    let z: f64 = x.iter().sum();
    if !(z > 0.0 && z.is_finite()) {
        return Err(());
    }
    let inv = 1.0 / z;
    x.iter_mut().for_each(|v| *v *= inv);
    Ok(())
}

/// Normalise logarithms to log-sum-exp 0; `Err` when every entry is −∞ or the sum is not
/// finite.
fn log_normalise(x: &mut [f64]) -> Result<(), ()> {
    let z = logsumexp(x);
    if !z.is_finite() {
        return Err(());
    }
    x.iter_mut().for_each(|v| *v -= z);
    Ok(())
}

/// Generalised arc consistency on the factors' supports (which values can still have
/// positive probability): repeatedly remove a variable's value when no positive entry of
/// some factor over it has all its variables at values not yet removed (Mackworth 1977).
/// Returns the first variable left with no value, if any. Sound: a value of any
/// configuration of positive probability is never removed.
pub(crate) fn arc_consistency_wipeout(g: &FactorGraph) -> Option<usize> {
    let mut dom: Vec<Vec<bool>> = g.cards().iter().map(|&c| vec![true; c]).collect();
    let mut state = Vec::new();
    let mut supp: Vec<Vec<bool>> = Vec::new();
    let mut changed = true;
    while changed {
        changed = false;
        for fac in g.factors() {
            let (vars, cards) = (fac.vars(), fac.cards());
            supp.clear();
            supp.extend(cards.iter().map(|&c| vec![false; c]));
            state.clear();
            state.resize(vars.len(), 0);
            for &x in fac.values() {
                if x > 0.0 && vars.iter().zip(&state).all(|(&v, &s)| dom[v][s]) {
                    for (q, &s) in state.iter().enumerate() {
                        supp[q][s] = true;
                    }
                }
                odometer(&mut state, cards);
            }
            for (q, &v) in vars.iter().enumerate() {
                for (d, s) in dom[v].iter_mut().zip(&supp[q]) {
                    if *d && !s {
                        *d = false;
                        changed = true;
                    }
                }
                if !dom[v].iter().any(|d| *d) {
                    return Some(v);
                }
            }
        }
    }
    None
}

/// A residual in the SEQMAX priority queue: (residual, stamp, edge). Larger residual first;
/// among equal residuals the larger stamp — the residual set last — as libDAI's multimap.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Resid(f64, u64, usize);

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
            .then_with(|| self.1.cmp(&other.1))
    }
}

/// SEQMAX's residuals: one live entry per edge (the one whose stamp is the edge's), stale
/// entries skipped on pop and dropped when the heap grows.
struct ResidQueue {
    heap: BinaryHeap<Resid>,
    resid: Vec<f64>,
    stamp_of: Vec<u64>,
    stamp: u64,
}

impl ResidQueue {
    fn new(ne: usize) -> Self {
        ResidQueue {
            heap: BinaryHeap::with_capacity(2 * ne),
            resid: vec![0.0; ne],
            stamp_of: vec![0; ne],
            stamp: 0,
        }
    }

    /// Set edge `e`'s residual (libDAI's `updateResidual`: erase, then insert last).
    fn set(&mut self, e: usize, r: f64) {
        self.stamp += 1;
        self.stamp_of[e] = self.stamp;
        self.resid[e] = r;
        self.heap.push(Resid(r, self.stamp, e));
        if self.heap.len() > 4 * self.resid.len() + 64 {
            self.heap = (0..self.resid.len())
                .map(|e| Resid(self.resid[e], self.stamp_of[e], e))
                .collect();
        }
    }

    /// The edge with the largest residual (its entry stays live until `set` again).
    fn top(&mut self) -> Option<usize> {
        while let Some(&Resid(_, s, e)) = self.heap.peek() {
            if s == self.stamp_of[e] {
                return Some(e);
            }
            self.heap.pop();
        }
        None
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
    if m == f64::NEG_INFINITY || !m.is_finite() {
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
/// at 1, as libDAI's.
///
/// Errors: [`GraphError::Invalid`] for options out of range or warm messages that do not fit;
/// [`GraphError::Inconsistent`] when a message or belief becomes zero for every value and
/// arc consistency shows the factors and evidence contradictory;
/// [`GraphError::BpNumericalZero`] when it becomes zero although arc consistency does not.
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
    let mut iterations = 0;
    run(&mut en, opts, warm, &mut iterations).map_err(|z| match z {
        Ok(e) => e,
        Err(z) => en.explain(z, iterations),
    })
}

/// The body of [`run_bp`]; a zero comes back unexplained (`Err(Err(zero))`), with
/// `iterations` the iteration it happened in (1-based; 0 before the first).
fn run(
    en: &mut Engine,
    opts: &BpOptions,
    warm: Option<&[Vec<f64>]>,
    iterations: &mut usize,
) -> Result<BpResult, Result<GraphError, Zero>> {
    let g = en.g;
    let ne = en.t.edge_var.len();
    let log = opts.logdomain;
    let mut msgs = vec![if log { 0.0 } else { 1.0 }; en.t.total];
    if let Some(w) = warm {
        if w.len() != ne || (0..ne).any(|e| w[e].len() != en.card(e)) {
            return Err(Ok(GraphError::Invalid(
                "warm-start messages do not fit the graph's edges".into(),
            )));
        }
        for (e, m) in w.iter().enumerate() {
            let z: f64 = m.iter().sum();
            let ok = z > 0.0 && z.is_finite() && m.iter().all(|x| *x >= 0.0);
            let r = en.range(e);
            for (d, x) in msgs[r].iter_mut().zip(m) {
                let p = if ok { x / z } else { 1.0 / m.len() as f64 };
                *d = if log { p.ln() } else { p };
            }
        }
    }
    let mut newm = msgs.clone();
    // Old beliefs: uniform (libDAI), or those of the warm messages.
    let mut old_v: Vec<Vec<f64>> = g.cards().iter().map(|&c| vec![1.0 / c as f64; c]).collect();
    if warm.is_some() {
        for (v, b) in old_v.iter_mut().enumerate() {
            en.belief_var(v, &newm, b).map_err(Err)?;
        }
    }
    // The sent messages before the current iteration: the old factor beliefs are formed
    // from them only when they are needed (see below).
    let mut prev = msgs.clone();
    let maxc = g.cards().iter().copied().max().unwrap_or(1);
    let maxf = g
        .factors()
        .iter()
        .map(|f| f.values().len())
        .max()
        .unwrap_or(1);
    let mut scratch = vec![0.0; maxc];
    let mut bel = vec![0.0; maxc.max(maxf)];
    let mut bel_old = vec![0.0; maxf];
    let d = opts.damping;
    let mut queue = ResidQueue::new(if opts.updates == Updates::SeqMax {
        ne
    } else {
        0
    });
    let mut max_diff = f64::INFINITY;
    let mut converged = false;
    let mut msg_change = 0.0f64;
    while *iterations < opts.maxiter {
        *iterations += 1;
        msg_change = 0.0;
        prev.copy_from_slice(&msgs);
        match opts.updates {
            Updates::Parall => {
                for e in 0..ne {
                    let r = en.range(e);
                    en.calc(e, &msgs, &mut newm[r]).map_err(Err)?;
                }
                for e in 0..ne {
                    msg_change = msg_change.max(en.send(e, &mut msgs, &newm, d, &mut scratch));
                }
            }
            Updates::SeqFix => {
                for k in 0..ne {
                    let e = en.t.sorted[k];
                    let r = en.range(e);
                    en.calc(e, &msgs, &mut newm[r]).map_err(Err)?;
                    msg_change = msg_change.max(en.send(e, &mut msgs, &newm, d, &mut scratch));
                }
            }
            Updates::SeqMax => {
                if *iterations == 1 {
                    for v in 0..g.num_vars() {
                        for k in 0..en.t.var_edges[v].len() {
                            let e = en.t.var_edges[v][k];
                            let r = en.range(e);
                            en.calc(e, &msgs, &mut newm[r.clone()]).map_err(Err)?;
                            queue.set(e, en.resid_dist(&newm[r.clone()], &msgs[r]));
                        }
                    }
                }
                for _ in 0..ne {
                    let Some(best) = queue.top() else { break };
                    msg_change = msg_change.max(en.send(best, &mut msgs, &newm, d, &mut scratch));
                    let r = en.range(best);
                    let rb = if d == 0.0 {
                        0.0
                    } else {
                        en.resid_dist(&newm[r.clone()], &msgs[r])
                    };
                    queue.set(best, rb);
                    let i = en.t.edge_var[best];
                    let fi = en.t.edge_factor[best];
                    for k in 0..en.t.var_edges[i].len() {
                        let fj = en.t.edge_factor[en.t.var_edges[i][k]];
                        if fj == fi {
                            continue;
                        }
                        for q in en.t.start[fj]..en.t.start[fj + 1] {
                            let e2 = en.t.sorted[q];
                            if en.t.edge_var[e2] == i {
                                continue;
                            }
                            let r2 = en.range(e2);
                            en.calc(e2, &msgs, &mut newm[r2.clone()]).map_err(Err)?;
                            queue.set(e2, en.resid_dist(&newm[r2.clone()], &msgs[r2]));
                        }
                    }
                }
            }
        }
        max_diff = 0.0;
        for (v, o) in old_v.iter_mut().enumerate() {
            let c = o.len();
            en.belief_var(v, &newm, &mut bel[..c]).map_err(Err)?;
            max_diff = max_diff.max(linf(&bel[..c], o));
            o.copy_from_slice(&bel[..c]);
        }
        // The factor beliefs' change can only matter when the variable beliefs' change is
        // not above tol (or to report libDAI's maxdiff after the last iteration), so they
        // are formed then only, old and new, from the sent messages before and after this
        // iteration: the same numbers libDAI forms every iteration.
        if max_diff <= opts.tol || *iterations == opts.maxiter {
            for f in 0..g.factors().len() {
                let c = g.factors()[f].values().len();
                if warm.is_none() && *iterations == 1 {
                    bel_old[..c].fill(1.0 / c as f64);
                } else {
                    en.belief_factor(f, &prev, &mut bel_old[..c]).map_err(Err)?;
                }
                en.belief_factor(f, &msgs, &mut bel[..c]).map_err(Err)?;
                max_diff = max_diff.max(linf(&bel[..c], &bel_old[..c]));
            }
        }
        if max_diff <= opts.tol {
            converged = true;
            break;
        }
    }
    let iterations = *iterations;
    tracing::debug!(iterations, converged, max_diff, "loopy BP finished");
    let messages = (0..ne)
        .map(|e| {
            let m = &msgs[en.range(e)];
            let mut p: Vec<f64> = if log {
                let z = logsumexp(m);
                m.iter().map(|x| (x - z).exp()).collect()
            } else {
                m.to_vec()
            };
            let z: f64 = p.iter().sum();
            p.iter_mut().for_each(|x| *x /= z);
            p
        })
        .collect();
    Ok(BpResult {
        marginals: old_v,
        iterations,
        converged,
        max_diff,
        max_message_change: msg_change,
        messages,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factor::Factor;

    #[test]
    fn equal_residuals_go_to_the_one_set_last_as_libdais_multimap() {
        let mut q = ResidQueue::new(3);
        q.set(0, 0.5);
        q.set(1, 0.5);
        q.set(2, 0.25);
        assert_eq!(q.top(), Some(1));
        // Setting 0 again, to the same value, moves it after 1.
        q.set(0, 0.5);
        assert_eq!(q.top(), Some(0));
        // A larger residual wins whatever its age.
        q.set(2, 0.75);
        q.set(1, 0.5);
        assert_eq!(q.top(), Some(2));
        q.set(2, 0.0);
        assert_eq!(q.top(), Some(1));
    }

    #[test]
    fn the_queue_keeps_its_order_when_it_drops_stale_entries() {
        let mut q = ResidQueue::new(2);
        // Far more sets than 4 × edges + 64, so the heap is rebuilt several times.
        for k in 0..1000 {
            q.set(k % 2, 1.0);
        }
        // The last set was edge 1 (k = 999).
        assert_eq!(q.top(), Some(1));
        assert!(q.heap.len() <= 4 * 2 + 64 + 1);
    }

    #[test]
    fn arc_consistency_empties_a_domain_only_when_the_supports_are_contradictory() {
        // a = b required; a ∈ {0}, b ∈ {1} by evidence: contradictory.
        let mut g = FactorGraph::new(vec![2, 2]).unwrap();
        g.add_factor(Factor::new(vec![0, 1], vec![2, 2], vec![1.0, 0.0, 0.0, 1.0]).unwrap())
            .unwrap();
        g.clamp(0, 0).unwrap();
        assert_eq!(arc_consistency_wipeout(&g), None);
        g.clamp(1, 1).unwrap();
        assert!(arc_consistency_wipeout(&g).is_some());
        // a ≠ b, b ≠ c, a ≠ c on binary variables (an odd cycle) has no solution, but every
        // value has a support in every factor: arc consistency, being local, keeps them all.
        let mut g = FactorGraph::new(vec![2, 2, 2]).unwrap();
        for (x, y) in [(0, 1), (1, 2), (0, 2)] {
            g.add_factor(Factor::new(vec![x, y], vec![2, 2], vec![0.0, 1.0, 1.0, 0.0]).unwrap())
                .unwrap();
        }
        assert_eq!(arc_consistency_wipeout(&g), None);
    }
}
