//! Best-first search on the objective cost(π) + R·(1 − p(π)) (paper 002, §II-A.1, the equation
//! for π*).
//!
//! # Why best-first search is exact on a non-additive objective
//! Write a path's label as (g, ℓ) with g = Σ cost(a) and ℓ = Σ ln p(a) ≤ 0. The objective of a
//! complete plan is J = g + R·(1 − e^ℓ). Appending an action adds cost ≥ 0 to g and ln p ≤ 0 to
//! ℓ, so J never decreases along a path. If h_c lower-bounds the remaining cost and h_ℓ the
//! remaining −Σ ln p (both admissible), then every completion of the label has
//! J ≥ f = g + h_c + R·(1 − e^{ℓ − h_ℓ}): a lower bound. Expanding labels in order of f and
//! stopping at the first goal label popped therefore returns a minimum-J plan (the A* argument
//! with this f). Because J depends on both g and ℓ, two labels of one state are only comparable
//! by Pareto dominance: (g₁, ℓ₁) with g₁ ≤ g₂ and ℓ₁ ≥ ℓ₂ is at least as good for *every*
//! continuation. So duplicate detection keeps, per state, the set of non-dominated labels; when
//! all p = 1 this is ordinary A* duplicate detection with reopening. A threshold θ on the success
//! probability prunes labels with e^ℓ < θ, which is exact for "the best plan with p ≥ θ"
//! because e^ℓ only falls along a path.
//!
//! Ties on f are broken by smaller heuristic (deeper first), then by generation order (FIFO), so
//! runs are deterministic.
//!
//! # Lazy evaluation, one part at a time
//! A child is queued with a bound carried from its parent (h(parent) − cost for h_c,
//! h_ℓ(parent) + ln p for h_ℓ; lower bounds because h(parent) ≤ h*(parent) ≤ cost + h*(child))
//! and evaluated when popped. The two parts are separate relaxed explorations, so they are computed
//! one at a time, h_ℓ first: when f with the first part already exceeds the key the state was
//! popped with, it goes back to the queue without the second (on the object-search domain most
//! generated states are never expanded). Any mix of computed parts and carried bounds is a lower
//! bound, so the first goal popped is still optimal.

use crate::heuristics::{Prio, Relaxed, Workspace};
use crate::task::{Plan, SearchStats, Task, Val};
use crate::PlanError;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

/// Which search to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Mode {
    /// A* with LM-cut on cost and on −ln p: the minimum objective (Fast Downward's standard
    /// optimal configuration, generalised to the objective).
    #[default]
    Optimal,
    /// Greedy best-first search with h^FF and preferred operators in a boosted dual queue
    /// (after lama-first); fast, not optimal.
    Fast,
    /// A* with h = 0 (uniform-cost search on the objective); a reference for tests.
    Blind,
}

/// The admissible heuristic of [`Mode::Optimal`] (applied to costs and to −ln p).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Heuristic {
    /// LM-cut (Helmert & Domshlak 2009): strong, a few relaxed explorations per state.
    #[default]
    LmCut,
    /// h^max (Bonet & Geffner 2001): one relaxed exploration per state; nearly as informed as
    /// LM-cut where relaxed plans are chains of dependent steps (as in the object-search domain).
    HMax,
}

/// Search settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchOptions {
    /// The search.
    pub mode: Mode,
    /// The heuristic of the optimal mode.
    pub heuristic: Heuristic,
    /// R, the reward for reaching the goal (paper 002, §II-A.1).
    pub reward: f64,
    /// Plans whose success probability falls below this are not considered.
    pub min_probability: f64,
    /// Give up after this many expansions.
    pub max_expansions: u64,
}

impl Default for SearchOptions {
    fn default() -> Self {
        SearchOptions {
            mode: Mode::Optimal,
            heuristic: Heuristic::LmCut,
            reward: 1000.0,
            min_probability: 0.0,
            max_expansions: 20_000_000,
        }
    }
}

/// Packs a state's values into 64-bit words.
#[derive(Debug, Clone)]
struct Packer {
    word: Vec<u32>,
    shift: Vec<u32>,
    mask: Vec<u64>,
    words: usize,
}

impl Packer {
    fn new(task: &Task) -> Self {
        let (mut word, mut shift, mut mask) = (Vec::new(), Vec::new(), Vec::new());
        let (mut w, mut used) = (0u32, 0u32);
        for v in &task.variables {
            let n = v.values.len().max(2) as u64;
            let bits = 64 - (n - 1).leading_zeros();
            if used + bits > 64 {
                w += 1;
                used = 0;
            }
            word.push(w);
            shift.push(used);
            mask.push(if bits == 64 {
                u64::MAX
            } else {
                (1u64 << bits) - 1
            });
            used += bits;
        }
        Packer {
            word,
            shift,
            mask,
            words: w as usize + 1,
        }
    }
    fn pack(&self, s: &[Val], out: &mut [u64]) {
        out.iter_mut().for_each(|x| *x = 0);
        for (i, &x) in s.iter().enumerate() {
            out[self.word[i] as usize] |= (x as u64) << self.shift[i];
        }
    }
    fn unpack(&self, p: &[u64], out: &mut Vec<Val>) {
        out.clear();
        for i in 0..self.word.len() {
            out.push(((p[self.word[i] as usize] >> self.shift[i]) & self.mask[i]) as Val);
        }
    }
}

/// Interned states.
struct Registry {
    packer: Packer,
    data: Vec<u64>,
    index: HashMap<Box<[u64]>, u32>,
    buf: Vec<u64>,
}

impl Registry {
    fn new(task: &Task) -> Self {
        let packer = Packer::new(task);
        let buf = vec![0; packer.words];
        Registry {
            packer,
            data: Vec::new(),
            index: HashMap::new(),
            buf,
        }
    }
    /// (id, newly inserted)
    fn insert(&mut self, s: &[Val]) -> (u32, bool) {
        let mut buf = std::mem::take(&mut self.buf);
        self.packer.pack(s, &mut buf);
        let r = if let Some(&id) = self.index.get(&buf[..]) {
            (id, false)
        } else {
            let id = (self.data.len() / self.packer.words) as u32;
            self.data.extend_from_slice(&buf);
            self.index.insert(buf.clone().into_boxed_slice(), id);
            (id, true)
        };
        self.buf = buf;
        r
    }
    fn get(&self, id: u32, out: &mut Vec<Val>) {
        let w = self.packer.words;
        let i = id as usize * w;
        self.packer.unpack(&self.data[i..i + w], out);
    }
}

struct Node {
    state: u32,
    parent: u32,
    op: u32,
    g: f64,
    lp: f64,
    stale: bool,
}

const NONE: u32 = u32::MAX;

impl Node {
    /// The search's root: the initial state, reached at no cost with certainty.
    fn root(state: u32) -> Self {
        Node {
            state,
            parent: NONE,
            op: NONE,
            g: 0.0,
            lp: 0.0,
            stale: false,
        }
    }
}

/// Before node `n` (in state `s`) is expanded: its plan when `s` is a goal, the search-limit
/// error once the expansions (this one counted) pass the budget, else `None`.
fn goal_or_limit(
    task: &Task,
    nodes: &[Node],
    n: u32,
    s: &[Val],
    opts: &SearchOptions,
    stats: &mut SearchStats,
) -> Option<Result<(Option<Plan>, SearchStats), PlanError>> {
    if task.is_goal(s) {
        let steps = extract(nodes, n);
        return Some(Ok((Some(make_plan(task, steps, opts.reward)), *stats)));
    }
    stats.expanded += 1;
    (stats.expanded > opts.max_expansions)
        .then_some(Err(PlanError::SearchLimit(opts.max_expansions)))
}

fn applicable<'a>(task: &'a Task, s: &[Val]) -> impl Iterator<Item = usize> + 'a {
    let s = s.to_vec();
    task.operators
        .iter()
        .enumerate()
        .filter(move |(_, o)| o.pre.iter().all(|&(v, x)| s[v as usize] == x))
        .map(|(i, _)| i)
}

fn apply(task: &Task, op: usize, s: &[Val], out: &mut Vec<Val>) {
    out.clear();
    out.extend_from_slice(s);
    for &(v, x) in &task.operators[op].eff {
        out[v as usize] = x;
    }
}

fn extract(nodes: &[Node], mut n: u32) -> Vec<usize> {
    let mut steps = Vec::new();
    while nodes[n as usize].parent != NONE {
        steps.push(nodes[n as usize].op as usize);
        n = nodes[n as usize].parent;
    }
    steps.reverse();
    steps
}

fn make_plan(task: &Task, steps: Vec<usize>, reward: f64) -> Plan {
    let cost: f64 = steps.iter().map(|&i| task.operators[i].cost).sum();
    let probability: f64 = steps.iter().map(|&i| task.operators[i].prob).product();
    Plan {
        steps,
        cost,
        probability,
        objective: cost + reward * (1.0 - probability),
    }
}

/// Search `task` for a plan; `Ok(None)` when no plan (with p ≥ `min_probability`) exists.
pub fn search(task: &Task, opts: &SearchOptions) -> Result<(Option<Plan>, SearchStats), PlanError> {
    with_relevant(task, opts, |t| match opts.mode {
        Mode::Fast => gbfs(t, opts),
        _ => astar(t, opts),
    })
}

/// The plan with the largest p(π)/cost(π) (among plans with p ≥ `opts.min_probability`), by
/// Dinkelbach's iteration for fractional programs: search with `opts.reward`, then with
/// R = cost/p of the plan found, while that raises p/cost, at most `rounds` times more. The
/// plan optimal for R = its own cost/p maximises p/cost over all plans, and p/cost never
/// decreases from one round to the next. In [`Mode::Optimal`] the rounds share the interned
/// states and their heuristic values (neither depends on R), so a round after the first
/// evaluates only states the earlier ones did not reach.
pub fn search_best_ratio(
    task: &Task,
    opts: &SearchOptions,
    rounds: usize,
) -> Result<(Option<Plan>, SearchStats), PlanError> {
    with_relevant(task, opts, |t| {
        let mut astar_state = (opts.mode == Mode::Optimal).then(|| AStar::new(t));
        let mut run = |o: &SearchOptions| match astar_state.as_mut() {
            Some(a) => a.run(o),
            None => gbfs(t, o),
        };
        let (first, mut stats) = run(opts)?;
        let Some(mut best) = first else {
            return Ok((None, stats));
        };
        let ratio = |p: &Plan| p.probability / p.cost;
        for _ in 0..rounds {
            let r = best.cost / best.probability;
            if !(r.is_finite() && r > 0.0) {
                break; // a free plan: nothing beats it per unit of cost
            }
            let o = SearchOptions { reward: r, ..*opts };
            let (next, st) = run(&o)?;
            tracing::trace!(reward = r, expanded = st.expanded, "ratio round");
            stats.add(st);
            match next {
                Some(n) if ratio(&n) > ratio(&best) * (1.0 + 1e-9) => best = n,
                _ => break,
            }
        }
        Ok((Some(best), stats))
    })
}

/// Check `opts`, search (`run`) the operators that can contribute to a plan likely enough
/// (exact: see `Task::relevant_operators`) and map the plan back to `task`'s indices.
fn with_relevant(
    task: &Task,
    opts: &SearchOptions,
    run: impl FnOnce(&Task) -> Result<(Option<Plan>, SearchStats), PlanError>,
) -> Result<(Option<Plan>, SearchStats), PlanError> {
    task.check()?;
    if !(opts.reward.is_finite() && opts.reward >= 0.0) {
        return Err(PlanError::InvalidOption(format!(
            "reward R = {}; expected a finite number ≥ 0",
            opts.reward
        )));
    }
    if !(0.0..=1.0).contains(&opts.min_probability) {
        return Err(PlanError::InvalidOption(format!(
            "minimum probability {}; expected a number in [0, 1]",
            opts.min_probability
        )));
    }
    let keep = task.relevant_operators(opts.min_probability);
    tracing::trace!(
        relevant = keep.len(),
        operators = task.operators.len(),
        "relevance analysis"
    );
    let pruned;
    let t = if keep.len() < task.operators.len() {
        pruned = Task {
            variables: task.variables.clone(),
            init: task.init.clone(),
            goal: task.goal.clone(),
            operators: keep.iter().map(|&i| task.operators[i].clone()).collect(),
        };
        &pruned
    } else {
        task
    };
    let (plan, stats) = run(t)?;
    let plan = plan.map(|mut p| {
        for s in &mut p.steps {
            *s = keep[*s];
        }
        p
    });
    Ok((plan, stats))
}

fn astar(task: &Task, opts: &SearchOptions) -> Result<(Option<Plan>, SearchStats), PlanError> {
    AStar::new(task).run(opts)
}

/// A* over one task, keeping between runs what does not depend on the reward R: the relaxed
/// task, the interned states and each state's heuristic values (h_cost, h_lp).
struct AStar<'t> {
    task: &'t Task,
    relaxed: Relaxed,
    c_cost: Vec<f64>,
    c_lp: Vec<f64>,
    ws: Workspace,
    reg: Registry,
    /// Per state: what is known of (h_cost, h_lp).
    heur: Vec<Est>,
}

/// What is known of a state's heuristic values (h_cost, h_lp): each part is either computed
/// (`exact`) or an admissible lower bound carried from a parent (initially 0).
#[derive(Debug, Clone, Copy, Default)]
struct Est {
    h: (f64, f64),
    exact: [bool; 2],
}

impl Est {
    fn set(&mut self, part: usize, v: f64) {
        if part == 0 {
            self.h.0 = v;
        } else {
            self.h.1 = v;
        }
        self.exact[part] = true;
    }

    /// Raise the parts not computed yet to the bound `b` (the larger of two lower bounds is one).
    fn raise(&mut self, b: (f64, f64)) {
        if !self.exact[0] {
            self.h.0 = self.h.0.max(b.0);
        }
        if !self.exact[1] {
            self.h.1 = self.h.1.max(b.1);
        }
    }

    /// The goal is unreachable from the state even in the relaxation.
    fn dead(&self) -> bool {
        self.h.0.is_infinite() || self.h.1.is_infinite()
    }
}

impl<'t> AStar<'t> {
    fn new(task: &'t Task) -> Self {
        let relaxed = Relaxed::new(task);
        let c_cost = relaxed.costs_of(task, |o| o.cost);
        let c_lp = relaxed.costs_of(task, |o| -o.prob.ln());
        AStar {
            task,
            relaxed,
            c_cost,
            c_lp,
            ws: Workspace::default(),
            reg: Registry::new(task),
            heur: Vec::new(),
        }
    }

    fn run(&mut self, opts: &SearchOptions) -> Result<(Option<Plan>, SearchStats), PlanError> {
        let task = self.task;
        let use_h = opts.mode == Mode::Optimal;
        // With R = 0 (or certain operators) the −ln p part has no weight in f: it is not computed.
        let probabilistic = !task.is_deterministic() && opts.reward > 0.0;
        let (relaxed, c_cost, c_lp) = (&self.relaxed, &self.c_cost, &self.c_lp);
        let ws = &mut self.ws;
        let reg = &mut self.reg;
        let heur = &mut self.heur;
        // Labels of this run, per state.
        let mut labels: Vec<Vec<u32>> = vec![Vec::new(); heur.len()];
        let mut nodes: Vec<Node> = Vec::new();
        let mut open = BinaryHeap::new();
        let mut stats = SearchStats::default();
        let mut seq: u64 = 0;
        let log_min = if opts.min_probability > 0.0 {
            opts.min_probability.ln() - 1e-12
        } else {
            f64::NEG_INFINITY
        };
        // Compute one part of a state's heuristic (0 on cost, 1 on −ln p; ∞ at a relaxed dead
        // end) unless it is known; whether it was computed now. A state counts as evaluated
        // when its first part is computed.
        let mut evaluate = |e: &mut Est, s: &[Val], part: usize, stats: &mut SearchStats| {
            if e.exact[part] {
                return false;
            }
            if !e.exact.iter().any(|&x| x) {
                stats.evaluated += 1;
            }
            let c = if part == 0 { c_cost } else { c_lp };
            let h = match opts.heuristic {
                Heuristic::HMax => relaxed.hmax(s, c, ws),
                Heuristic::LmCut => relaxed.lmcut(s, c, ws),
            };
            e.set(part, h.unwrap_or(f64::INFINITY));
            true
        };
        // The parts a state still needs, in the order they are computed: the −ln p part first,
        // which moves f the most where R is large (every assumption lowers p).
        let parts: &[usize] = match (use_h, probabilistic) {
            (false, _) => &[],
            (true, true) => &[1, 0],
            (true, false) => &[0],
        };
        let f_of = |g: f64, lp: f64, h: (f64, f64)| -> f64 {
            g + h.0 + opts.reward * (1.0 - (lp - h.1).exp())
        };
        let (sid, new) = reg.insert(&task.init);
        if new {
            heur.push(Est::default());
            labels.push(Vec::new());
        }
        for &part in parts {
            evaluate(&mut heur[sid as usize], &task.init, part, &mut stats);
        }
        if heur[sid as usize].dead() {
            return Ok((None, stats));
        }
        let h0 = heur[sid as usize].h;
        labels[sid as usize].push(0);
        nodes.push(Node::root(sid));
        open.push(Reverse((Prio(f_of(0.0, 0.0, h0)), Prio(h0.0), seq, 0u32)));
        let mut s = Vec::new();
        let mut t = Vec::new();
        'pop: while let Some(Reverse((Prio(key_f), _, _, n))) = open.pop() {
            let node = &nodes[n as usize];
            if node.stale {
                continue;
            }
            let (g, lp, st) = (node.g, node.lp, node.state);
            reg.get(st, &mut s);
            // Lazy evaluation, one part at a time: a state whose f rises above its key after
            // one part goes back to the queue without the other (most never come back).
            for &part in parts {
                let e = &mut heur[st as usize];
                if e.dead() {
                    continue 'pop;
                }
                if !evaluate(e, &s, part, &mut stats) {
                    continue;
                }
                if e.dead() {
                    continue 'pop;
                }
                let h = e.h;
                let f = f_of(g, lp, h);
                if f > key_f + 1e-9 {
                    seq += 1;
                    open.push(Reverse((Prio(f), Prio(h.0), seq, n)));
                    continue 'pop;
                }
            }
            if heur[st as usize].dead() {
                continue;
            }
            if let Some(end) = goal_or_limit(task, &nodes, n, &s, opts, &mut stats) {
                return end;
            }
            let ops: Vec<usize> = applicable(task, &s).collect();
            for op in ops {
                let o = &task.operators[op];
                let g2 = g + o.cost;
                let lp2 = lp + o.prob.ln();
                if lp2 < log_min {
                    continue;
                }
                apply(task, op, &s, &mut t);
                stats.generated += 1;
                let (sid2, new) = reg.insert(&t);
                if new {
                    heur.push(Est::default());
                    labels.push(Vec::new());
                }
                let si = sid2 as usize;
                // Pareto dominance among the labels of this state.
                let mut dominated = false;
                for &l in &labels[si] {
                    let ln = &nodes[l as usize];
                    if ln.g <= g2 + 1e-9 && ln.lp >= lp2 - 1e-12 {
                        dominated = true;
                        break;
                    }
                }
                if dominated {
                    continue;
                }
                // Deferred evaluation: a child is queued with the admissible estimate
                // max(0, h(parent) − cost) (h(parent) ≤ cost + h*(child)) and evaluated when popped.
                let ph = heur[st as usize].h;
                heur[si].raise(((ph.0 - o.cost).max(0.0), (ph.1 + o.prob.ln()).max(0.0)));
                let h = heur[si].h;
                if heur[si].dead() {
                    continue;
                }
                let mut keep = Vec::with_capacity(labels[si].len() + 1);
                for &l in &labels[si] {
                    let ln = &mut nodes[l as usize];
                    if g2 <= ln.g && lp2 >= ln.lp {
                        ln.stale = true;
                    } else {
                        keep.push(l);
                    }
                }
                let id = nodes.len() as u32;
                nodes.push(Node {
                    state: sid2,
                    parent: n,
                    op: op as u32,
                    g: g2,
                    lp: lp2,
                    stale: false,
                });
                keep.push(id);
                labels[si] = keep;
                seq += 1;
                open.push(Reverse((Prio(f_of(g2, lp2, h)), Prio(h.0), seq, id)));
            }
        }
        Ok((None, stats))
    }
}

fn gbfs(task: &Task, opts: &SearchOptions) -> Result<(Option<Plan>, SearchStats), PlanError> {
    let relaxed = Relaxed::new(task);
    // Relaxed costs 1 + cost + R·(−ln p): the 1 keeps plans short (as lama-first's unit
    // costs), R·(−ln p) ≥ R·(1 − p) makes the relaxed plan an over-estimate of the objective.
    let costs = relaxed.costs_of(task, |o| 1.0 + o.cost + opts.reward * (-o.prob.ln()));
    // h^max over −ln p is an admissible bound on the rest of a plan's −ln p: a state whose
    // best reachable success probability is below `min_probability` is pruned (without it, a
    // task with no plan above the bound is exhausted state by state).
    let bound_lp = opts.min_probability > 0.0 && !task.is_deterministic();
    let c_lp = relaxed.costs_of(task, |o| -o.prob.ln());
    let mut ws = Workspace::default();
    let mut reg = Registry::new(task);
    let mut nodes: Vec<Node> = Vec::new();
    let mut stats = SearchStats::default();
    let log_min = if opts.min_probability > 0.0 {
        opts.min_probability.ln() - 1e-12
    } else {
        f64::NEG_INFINITY
    };
    let mut pref = Vec::new();
    stats.evaluated += 1;
    let Some(h0) = relaxed.ff(&task.init, &costs, &mut ws, &mut pref) else {
        return Ok((None, stats));
    };
    let (sid, _) = reg.insert(&task.init);
    nodes.push(Node::root(sid));
    let mut preferred_of: Vec<Vec<usize>> = vec![pref.clone()];
    // Two queues: all successors, successors by preferred operators; the queue with the lower
    // priority counter is used next; progress boosts the preferred queue by 1000.
    let mut queues = [BinaryHeap::new(), BinaryHeap::new()];
    let mut prio = [0i64, 0i64];
    let mut seq = 0u64;
    queues[0].push(Reverse((Prio(h0), seq, 0u32)));
    let mut best_h = h0;
    let mut s = Vec::new();
    let mut t = Vec::new();
    loop {
        let q = if queues[0].is_empty() && queues[1].is_empty() {
            break;
        } else if queues[1].is_empty() {
            0
        } else if queues[0].is_empty() || prio[1] < prio[0] {
            1
        } else {
            0
        };
        prio[q] += 1;
        let Some(Reverse((_, _, n))) = queues[q].pop() else {
            continue;
        };
        let node = &nodes[n as usize];
        if node.stale {
            continue;
        }
        nodes[n as usize].stale = true; // expanded once
        let (g, lp, st) = (
            nodes[n as usize].g,
            nodes[n as usize].lp,
            nodes[n as usize].state,
        );
        reg.get(st, &mut s);
        if let Some(end) = goal_or_limit(task, &nodes, n, &s, opts, &mut stats) {
            return end;
        }
        let parent_pref = std::mem::take(&mut preferred_of[n as usize]);
        let ops: Vec<usize> = applicable(task, &s).collect();
        for op in ops {
            let o = &task.operators[op];
            let lp2 = lp + o.prob.ln();
            if lp2 < log_min {
                continue;
            }
            apply(task, op, &s, &mut t);
            stats.generated += 1;
            let (sid2, new) = reg.insert(&t);
            if !new {
                continue;
            }
            stats.evaluated += 1;
            if bound_lp {
                match relaxed.hmax(&t, &c_lp, &mut ws) {
                    Some(hl) if lp2 - hl >= log_min => {}
                    _ => continue,
                }
            }
            let Some(h) = relaxed.ff(&t, &costs, &mut ws, &mut pref) else {
                continue;
            };
            let id = nodes.len() as u32;
            nodes.push(Node {
                state: sid2,
                parent: n,
                op: op as u32,
                g: g + o.cost,
                lp: lp2,
                stale: false,
            });
            preferred_of.push(pref.clone());
            seq += 1;
            if h < best_h {
                best_h = h;
                prio[1] -= 1000;
            }
            queues[0].push(Reverse((Prio(h), seq, id)));
            if parent_pref.binary_search(&op).is_ok() {
                queues[1].push(Reverse((Prio(h), seq, id)));
            }
        }
    }
    Ok((None, stats))
}
