//! Delete-relaxation heuristics over SAS+ facts `(var, val)`.
//!
//! * **LM-cut** (Helmert & Domshlak, *Landmarks, critical paths and abstractions: what's the
//!   difference anyway?*, ICAPS 2009, §4): repeatedly compute h^max, build the justification graph
//!   from each operator's h^max-maximal precondition (its *pre-supporter*), take the cut between
//!   the facts reachable from the state without passing the zero-cost goal zone and that zone,
//!   add the cut's minimum cost to h and subtract it from the cut's operators. Admissible.
//! * **h^add / h^FF** (Bonet & Geffner 2001; Hoffmann & Nebel 2001): best supporters by h^add,
//!   relaxed plan extracted backwards from the goal; the relaxed plan's operators applicable in
//!   the state are the *preferred operators* (as in lama-first).
//!
//! A fact `⊤` (true in every state) is the precondition of operators with none, and an
//! artificial goal operator of cost 0 achieves the fact `G` from the goal facts, as in the paper.
//!
//! Conditions on control variables ([`crate::task::Variable::control`]) are dropped, and the
//! operators that then have the same conditions and effects become one relaxed operator with
//! the cheapest of their costs (the grounding's assumption chain copies each assumption once
//! per value of its variable: one 30-room object-search task had 3 640 operators, copies of
//! 1 321 distinct ones). Dropping conditions relaxes further, so h^max and LM-cut stay
//! admissible (and h^max consistent); they may be lower in a state where the control variable would
//! have forced a costlier order.

use crate::task::{Task, Val};
use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

const EPS: f64 = 1e-9;

/// Total-order wrapper for f64 priorities (`total_cmp`), shared by the heuristics and the search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Prio(pub(crate) f64);
impl Eq for Prio {}
impl PartialOrd for Prio {
    fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Prio {
    fn cmp(&self, o: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&o.0)
    }
}

/// A non-negative f64 as a key whose integer order is the numbers' order (the IEEE-754 bit
/// patterns of non-negative floats sort as unsigned integers; `+ 0.0` turns −0 into +0): the
/// relaxed explorations' heap compares integers.
#[inline]
fn key(d: f64) -> u64 {
    debug_assert!(
        d >= 0.0 || d.is_nan(),
        "relaxed values are non-negative: {d}"
    );
    (d + 0.0).to_bits()
}

/// Rows of indices stored back to back (compressed sparse rows): one allocation, and a row's
/// items adjacent in memory, which is what the explorations' inner loops walk.
#[derive(Debug, Clone, Default)]
struct Rows {
    /// Row `i` is `items[start[i]..start[i + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Rows {
    fn from_rows<I: IntoIterator<Item = u32>>(rows: impl IntoIterator<Item = I>) -> Self {
        let mut r = Rows {
            start: vec![0],
            items: Vec::new(),
        };
        for row in rows {
            r.items.extend(row);
            r.start.push(r.items.len() as u32);
        }
        r
    }

    /// Rows `0..n` listing, for each `i`, the rows of `self` that contain `i` (the transpose).
    fn transpose(&self, n: usize) -> Self {
        let mut count = vec![0u32; n + 1];
        for &x in &self.items {
            count[x as usize + 1] += 1;
        }
        for i in 0..n {
            count[i + 1] += count[i];
        }
        let mut items = vec![0u32; self.items.len()];
        let mut next = count.clone();
        for row in 0..self.len() {
            for &x in self.row(row) {
                items[next[x as usize] as usize] = row as u32;
                next[x as usize] += 1;
            }
        }
        Rows {
            start: count,
            items,
        }
    }

    fn len(&self) -> usize {
        self.start.len() - 1
    }

    #[inline]
    fn row(&self, i: usize) -> &[u32] {
        &self.items[self.start[i] as usize..self.start[i + 1] as usize]
    }
}

/// The delete relaxation of a task, built once and evaluated per state.
#[derive(Debug, Clone)]
pub struct Relaxed {
    offsets: Vec<usize>,
    n_facts: usize,
    top: usize,
    goal_fact: usize,
    /// Per relaxed operator: preconditions (fact ids, never empty).
    pre: Rows,
    /// Per relaxed operator: the number of preconditions (the explorations' initial counters).
    n_pre: Vec<u32>,
    /// Per relaxed operator: effects (fact ids).
    eff: Rows,
    /// Per relaxed operator: the task's operators it stands for (several when they differ
    /// only in conditions on control variables; none for the goal operator).
    members: Rows,
    /// For each fact, the relaxed operators having it as a precondition.
    pre_of: Rows,
    /// For each fact, the relaxed operators adding it.
    achievers: Rows,
    /// The goal operator's index (last).
    goal_op: usize,
}

impl Relaxed {
    /// Build the relaxation of `task`.
    pub fn new(task: &Task) -> Self {
        let (offsets, n) = task.fact_offsets();
        let top = n;
        let goal_fact = n + 1;
        let n_facts = n + 2;
        // Conditions on control variables are dropped (`Variable::control`): dropping
        // preconditions relaxes further, so every estimate stays admissible.
        let facts = |cs: &[(crate::task::Var, Val)]| -> Vec<u32> {
            cs.iter()
                .filter(|&&(v, _)| !task.variables[v as usize].control)
                .map(|&(v, x)| (offsets[v as usize] + x as usize) as u32)
                .collect()
        };
        // A fact `⊤` stands in for an empty precondition (also the goal's).
        let or_top = |mut p: Vec<u32>| {
            if p.is_empty() {
                p.push(top as u32);
            }
            p
        };
        // Operators identical once projected (a control variable's copies) become one.
        let mut index: HashMap<(Vec<u32>, Vec<u32>), usize> = HashMap::new();
        let mut pre_rows = Vec::new();
        let mut eff_rows = Vec::new();
        let mut member_rows: Vec<Vec<u32>> = Vec::new();
        for (i, o) in task.operators.iter().enumerate() {
            let k = (or_top(facts(&o.pre)), facts(&o.eff));
            let r = *index.entry(k).or_insert_with_key(|k| {
                pre_rows.push(k.0.clone());
                eff_rows.push(k.1.clone());
                member_rows.push(Vec::new());
                pre_rows.len() - 1
            });
            member_rows[r].push(i as u32);
        }
        pre_rows.push(or_top(facts(&task.goal)));
        eff_rows.push(vec![goal_fact as u32]);
        member_rows.push(Vec::new());
        let pre = Rows::from_rows(pre_rows);
        let eff = Rows::from_rows(eff_rows);
        let members = Rows::from_rows(member_rows);
        let goal_op = pre.len() - 1;
        let n_pre = (0..pre.len()).map(|o| pre.row(o).len() as u32).collect();
        let pre_of = pre.transpose(n_facts);
        let achievers = eff.transpose(n_facts);
        Relaxed {
            offsets,
            n_facts,
            top,
            goal_fact,
            pre,
            n_pre,
            eff,
            members,
            pre_of,
            achievers,
            goal_op,
        }
    }

    fn state_facts<'a>(&'a self, state: &'a [Val]) -> impl Iterator<Item = usize> + 'a {
        state
            .iter()
            .enumerate()
            .map(|(v, &x)| self.offsets[v] + x as usize)
            .chain(std::iter::once(self.top))
    }

    /// The per-relaxed-operator cost vector for `task`'s costs `f`: the cheapest of the
    /// operators each stands for (the goal operator costs 0).
    pub fn costs_of(&self, task: &Task, f: impl Fn(&crate::task::Operator) -> f64) -> Vec<f64> {
        (0..self.goal_op)
            .map(|r| {
                self.members
                    .row(r)
                    .iter()
                    .map(|&i| f(&task.operators[i as usize]))
                    .fold(f64::INFINITY, f64::min)
            })
            .chain(std::iter::once(0.0))
            .collect()
    }

    /// Generalised Dijkstra for h^max (`sum = false`) or h^add (`sum = true`); fills `value`
    /// per fact and `op_val` (the operator's precondition value) per operator, `supporter`
    /// (the precondition reached last: for h^max the one with maximal value) and, for h^add,
    /// `achiever` (the cheapest achiever of each fact).
    fn explore(
        &self,
        state: &[Val],
        costs: &[f64],
        sum: bool,
        ws: &mut Workspace,
        stop_at_goal: bool,
    ) {
        let nops = self.n_pre.len();
        ws.value.clear();
        ws.value.resize(self.n_facts, f64::INFINITY);
        ws.op_val.clear();
        ws.op_val.resize(nops, f64::INFINITY);
        ws.unsat.clear();
        ws.unsat.extend_from_slice(&self.n_pre);
        ws.supporter.clear();
        ws.supporter.resize(nops, usize::MAX);
        if sum {
            ws.achiever.clear();
            ws.achiever.resize(self.n_facts, usize::MAX);
            ws.acc.clear();
            ws.acc.resize(nops, 0.0);
        }
        ws.heap.clear();
        for f in self.state_facts(state) {
            ws.value[f] = 0.0;
            ws.heap.push(Reverse((key(0.0), f as u32)));
        }
        while let Some(Reverse((d, f))) = ws.heap.pop() {
            let (d, f) = (f64::from_bits(d), f as usize);
            if d > ws.value[f] {
                continue;
            }
            if stop_at_goal && f == self.goal_fact {
                break;
            }
            for &o in self.pre_of.row(f) {
                let o = o as usize;
                if sum {
                    ws.acc[o] += d;
                }
                ws.unsat[o] -= 1;
                if ws.unsat[o] == 0 {
                    ws.supporter[o] = f;
                    let base = if sum { ws.acc[o] } else { d };
                    ws.op_val[o] = base;
                    let nd = base + costs[o];
                    for &e in self.eff.row(o) {
                        let e = e as usize;
                        if nd < ws.value[e] {
                            ws.value[e] = nd;
                            if sum {
                                ws.achiever[e] = o;
                            }
                            ws.heap.push(Reverse((key(nd), e as u32)));
                        }
                    }
                }
            }
        }
    }

    /// h^max value of `state` under `costs` (admissible, weaker than LM-cut, one exploration).
    pub fn hmax(&self, state: &[Val], costs: &[f64], ws: &mut Workspace) -> Option<f64> {
        self.explore(state, costs, false, ws, true);
        let v = ws.value[self.goal_fact];
        v.is_finite().then_some(v)
    }

    /// LM-cut value of `state` under `costs` (one per operator, goal operator last), or `None`
    /// when the goal is unreachable even in the relaxation (a dead end).
    pub fn lmcut(&self, state: &[Val], costs: &[f64], ws: &mut Workspace) -> Option<f64> {
        ws.cost.clear();
        ws.cost.extend_from_slice(costs);
        let mut h = 0.0;
        let cost = std::mem::take(&mut ws.cost);
        self.explore(state, &cost, false, ws, false);
        ws.cost = cost;
        loop {
            let hg = ws.value[self.goal_fact];
            if hg.is_infinite() {
                return None;
            }
            if hg <= EPS {
                return Some(h);
            }
            // Goal zone: facts from which G is reached by zero-cost justification edges.
            ws.zone.clear();
            ws.zone.resize(self.n_facts, 0); // 0 none, 1 goal zone, 2 before-zone
            ws.stack.clear();
            ws.zone[self.goal_fact] = 1;
            ws.stack.push(self.goal_fact);
            while let Some(g) = ws.stack.pop() {
                for &o in self.achievers.row(g) {
                    let o = o as usize;
                    if ws.unsat[o] == 0 && ws.cost[o] <= EPS {
                        let s = ws.supporter[o];
                        if ws.zone[s] == 0 {
                            ws.zone[s] = 1;
                            ws.stack.push(s);
                        }
                    }
                }
            }
            // Operators by pre-supporter (the justification graph's edges).
            if ws.by_sup.len() < self.n_facts {
                ws.by_sup.resize(self.n_facts, Vec::new());
            }
            for l in ws.by_sup.iter_mut() {
                l.clear();
            }
            for o in 0..self.n_pre.len() {
                if ws.unsat[o] == 0 {
                    let sp = ws.supporter[o];
                    ws.by_sup[sp].push(o);
                }
            }
            // Before-zone: reachable from the state without entering the goal zone.
            ws.cut.clear();
            for f in self.state_facts(state) {
                if ws.zone[f] == 0 {
                    ws.zone[f] = 2;
                    ws.stack.push(f);
                }
            }
            while let Some(f) = ws.stack.pop() {
                for k in 0..ws.by_sup[f].len() {
                    let o = ws.by_sup[f][k];
                    let mut in_cut = false;
                    for &e in self.eff.row(o) {
                        let e = e as usize;
                        match ws.zone[e] {
                            1 => in_cut = true,
                            0 => {
                                ws.zone[e] = 2;
                                ws.stack.push(e);
                            }
                            _ => {}
                        }
                    }
                    if in_cut {
                        ws.cut.push(o);
                    }
                }
            }
            let m = ws
                .cut
                .iter()
                .map(|&o| ws.cost[o])
                .fold(f64::INFINITY, f64::min);
            if !m.is_finite() || m <= EPS {
                // Cannot happen for a correct cut; stay admissible and stop.
                return Some(h);
            }
            h += m;
            for i in 0..ws.cut.len() {
                let o = ws.cut[i];
                ws.cost[o] -= m;
            }
            self.hmax_incremental(ws);
        }
    }

    /// After the costs of the cut's operators fell, lower the h^max values that depend on them
    /// (values only decrease), as in Fast Downward's incremental LM-cut.
    fn hmax_incremental(&self, ws: &mut Workspace) {
        ws.heap.clear();
        for i in 0..ws.cut.len() {
            let o = ws.cut[i];
            let target = ws.op_val[o] + ws.cost[o];
            for &e in self.eff.row(o) {
                if ws.value[e as usize] > target {
                    ws.value[e as usize] = target;
                    ws.heap.push(Reverse((key(target), e)));
                }
            }
        }
        while let Some(Reverse((d, f))) = ws.heap.pop() {
            let (d, f) = (f64::from_bits(d), f as usize);
            if d > ws.value[f] {
                continue;
            }
            for &o in self.pre_of.row(f) {
                let o = o as usize;
                if ws.unsat[o] != 0 || ws.supporter[o] != f || ws.op_val[o] <= d {
                    continue;
                }
                // Re-select the supporter: the precondition with the largest value.
                let mut best = f;
                let mut bv = f64::NEG_INFINITY;
                for &p in self.pre.row(o) {
                    let p = p as usize;
                    if ws.value[p] > bv {
                        bv = ws.value[p];
                        best = p;
                    }
                }
                ws.supporter[o] = best;
                if bv < ws.op_val[o] {
                    ws.op_val[o] = bv;
                    let target = bv + ws.cost[o];
                    for &e in self.eff.row(o) {
                        if ws.value[e as usize] > target {
                            ws.value[e as usize] = target;
                            ws.heap.push(Reverse((key(target), e)));
                        }
                    }
                }
            }
        }
    }

    /// h^FF of `state` (relaxed plan cost under `costs`), with the relaxed plan's operators
    /// that are applicable in `state` pushed into `preferred`; `None` at a dead end.
    pub fn ff(
        &self,
        state: &[Val],
        costs: &[f64],
        ws: &mut Workspace,
        preferred: &mut Vec<usize>,
    ) -> Option<f64> {
        preferred.clear();
        self.explore(state, costs, true, ws, true);
        if ws.value[self.goal_fact].is_infinite() {
            return None;
        }
        ws.mark.clear();
        ws.mark.resize(self.n_pre.len(), false);
        ws.seen.clear();
        ws.seen.resize(self.n_facts, false);
        ws.stack.clear();
        ws.stack.push(self.goal_fact);
        ws.seen[self.goal_fact] = true;
        let mut h = 0.0;
        while let Some(f) = ws.stack.pop() {
            let o = ws.achiever[f];
            if o == usize::MAX || ws.mark[o] {
                continue;
            }
            ws.mark[o] = true;
            if o != self.goal_op {
                h += costs[o];
                if ws.op_val[o] == 0.0 {
                    preferred.extend(self.members.row(o).iter().map(|&i| i as usize));
                }
            }
            for &p in self.pre.row(o) {
                let p = p as usize;
                if !ws.seen[p] {
                    ws.seen[p] = true;
                    ws.stack.push(p);
                }
            }
        }
        preferred.sort_unstable();
        Some(h)
    }
}

/// Reusable buffers for heuristic evaluation.
#[derive(Debug, Default, Clone)]
pub struct Workspace {
    value: Vec<f64>,
    op_val: Vec<f64>,
    acc: Vec<f64>,
    unsat: Vec<u32>,
    supporter: Vec<usize>,
    achiever: Vec<usize>,
    cost: Vec<f64>,
    zone: Vec<u8>,
    stack: Vec<usize>,
    cut: Vec<usize>,
    mark: Vec<bool>,
    seen: Vec<bool>,
    heap: BinaryHeap<Reverse<(u64, u32)>>,
    by_sup: Vec<Vec<usize>>,
}

#[cfg(test)]
mod tests {
    use super::{key, Relaxed, Workspace};
    use crate::task::{Operator, Task, Variable};

    #[test]
    fn copies_that_differ_only_in_a_control_variable_are_one_relaxed_operator() {
        // g: no → yes by `o`, copied once per value of the control variable c.
        let op = |c: u32, cost: f64| Operator {
            schema: "o".into(),
            args: vec![],
            display: "O".into(),
            pre: vec![(0, 0), (1, c)],
            eff: vec![(0, 1), (1, 0)],
            cost,
            prob: 1.0,
            assumption: false,
        };
        let mut task = Task {
            variables: vec![
                Variable::new("g", vec!["no".into(), "yes".into()]),
                Variable {
                    control: true,
                    ..Variable::new("c", vec!["0".into(), "1".into(), "2".into()])
                },
            ],
            init: vec![0, 2],
            goal: vec![(0, 1)],
            operators: vec![op(0, 3.0), op(1, 2.0), op(2, 5.0)],
        };
        let r = Relaxed::new(&task);
        assert_eq!(r.n_pre.len(), 2, "one relaxed operator and the goal's");
        assert_eq!(r.members.row(0), [0, 1, 2]);
        // The merged operator costs the cheapest copy's cost: below the copy that applies.
        let costs = r.costs_of(&task, |o| o.cost);
        let mut ws = Workspace::default();
        assert_eq!(r.hmax(&task.init, &costs, &mut ws), Some(2.0));
        // An ordinary variable in the same place keeps its copies apart.
        task.variables[1].control = false;
        let r = Relaxed::new(&task);
        assert_eq!(r.n_pre.len(), 4);
        let costs = r.costs_of(&task, |o| o.cost);
        assert_eq!(r.hmax(&task.init, &costs, &mut ws), Some(5.0));
    }

    #[test]
    fn heap_keys_order_as_the_non_negative_values_they_encode() {
        let xs = [0.0, -0.0, 1e-300, 0.5, 1.0, 2.0, 1e300, f64::INFINITY];
        for a in xs {
            for b in xs {
                // −0 and +0 are one key, as they are one number.
                assert_eq!(
                    key(a).cmp(&key(b)),
                    a.partial_cmp(&b).unwrap(),
                    "{a} vs {b}"
                );
            }
        }
    }
}
