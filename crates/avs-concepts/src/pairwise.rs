//! Loopy BP specialised to the conceptual map's chain graph: a pairwise Markov random field
//! with one K-valued variable per room, a node potential per room (all its place-property,
//! object-count and search evidence multiplied together — exact, because each observation
//! variable hangs off exactly one room variable) and the connectivity potential φ_rc on every
//! door.
//!
//! Messages are the variable-to-variable messages of pairwise BP (Yedidia, Freeman & Weiss
//! 2003, eq. 13): `m_{i→j}(x_j) ∝ Σ_{x_i} u_i(x_i) φ(x_i, x_j) Π_{k ∈ N(i)\j} m_{k→i}(x_i)`,
//! beliefs `b_i ∝ u_i Π_{k ∈ N(i)} m_{k→i}` (eq. 12). This equals factor-graph BP on the same
//! graph (the generic engine in [`crate::bp`]), which the tests check.
//!
//! Schedule: sequential, room by room in order, each room sending all its outgoing messages
//! (variable by variable — not libDAI's SEQFIX of [`crate::bp`], which goes factor by factor),
//! but a room recomputes its outgoing messages only when it is *dirty* — its node potential
//! changed, or an incoming message changed by more than `tol` (L∞) since it last did. After
//! one observation only the rooms the change actually reaches are touched, so an event costs a
//! few message updates around the room rather than full sweeps (a residual-gated schedule in
//! the spirit of Elidan, McGraw & Koller 2006). BP has converged when no room is dirty.

/// Options of the map's BP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapBpOptions {
    /// A message change (L∞) above this makes its target room recompute its messages.
    pub tol: f64,
    /// Limit on sweeps.
    pub maxiter: usize,
    /// Damping in [0, 1): new ← new^(1−d) · old^d.
    pub damping: f64,
}

impl Default for MapBpOptions {
    /// tol 1e-7 (beliefs within ~5e-7 of the fixed point on the 100-room benchmark map),
    /// 1000 sweeps, no damping.
    fn default() -> Self {
        Self {
            tol: 1e-7,
            maxiter: 1000,
            damping: 0.0,
        }
    }
}

/// A pairwise MRF with a shared edge potential, and its BP state.
#[derive(Debug, Clone, Default)]
pub struct PairwiseMrf {
    k: usize,
    phi: Vec<f64>,
    unary: Vec<f64>,
    edges: Vec<(usize, usize)>,
    /// Per node: (neighbour, outgoing message index, incoming message index).
    nbrs: Vec<Vec<(usize, usize, usize)>>,
    msgs: Vec<f64>,
    dirty: Vec<bool>,
    /// The one neighbour whose message made the node dirty, or `usize::MAX` when several
    /// did or its potential changed (the message back to that neighbour does not depend on
    /// the neighbour's own message, so it need not be recomputed).
    dirty_src: Vec<usize>,
}

/// Result of one BP run on the map.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PairwiseRun {
    /// Sweeps over the dirty rooms.
    pub iterations: usize,
    /// Message updates computed.
    pub updates: usize,
    /// No room left dirty.
    pub converged: bool,
    /// Largest message change in the last sweep.
    pub max_diff: f64,
}

impl PairwiseMrf {
    /// An MRF over `unary.len() / k` nodes with node potentials `unary` (row per node, each
    /// strictly positive somewhere), edge potential `phi[a * k + b]` = φ(x_i = a, x_j = b) for
    /// every edge `(i, j)`, and starting messages from `warm(i, j)` (message i → j) when it
    /// returns one of length k, uniform otherwise. Every node starts dirty.
    pub(crate) fn new(
        k: usize,
        phi: Vec<f64>,
        unary: Vec<f64>,
        edges: Vec<(usize, usize)>,
        mut warm: impl FnMut(usize, usize) -> Option<Vec<f64>>,
    ) -> Self {
        let n = unary.len().checked_div(k).unwrap_or(0);
        let mut nbrs = vec![Vec::new(); n];
        let mut msgs = vec![1.0 / k.max(1) as f64; 2 * edges.len() * k];
        for (e, &(i, j)) in edges.iter().enumerate() {
            nbrs[i].push((j, 2 * e, 2 * e + 1));
            nbrs[j].push((i, 2 * e + 1, 2 * e));
            for (d, (a, b)) in [(2 * e, (i, j)), (2 * e + 1, (j, i))] {
                if let Some(m) = warm(a, b) {
                    if m.len() == k && m.iter().all(|x| x.is_finite() && *x > 0.0) {
                        msgs[d * k..(d + 1) * k].copy_from_slice(&m);
                    }
                }
            }
        }
        PairwiseMrf {
            k,
            phi,
            unary,
            edges,
            nbrs,
            msgs,
            dirty: vec![true; n],
            dirty_src: vec![usize::MAX; n],
        }
    }

    /// Number of nodes.
    pub fn num_nodes(&self) -> usize {
        self.dirty.len()
    }

    /// The edges `(i, j)`.
    pub fn edges(&self) -> &[(usize, usize)] {
        &self.edges
    }

    /// The message `i → j` along edge `e` (`forward`: from the edge's first node).
    pub(crate) fn message(&self, e: usize, forward: bool) -> &[f64] {
        let d = 2 * e + usize::from(!forward);
        &self.msgs[d * self.k..(d + 1) * self.k]
    }

    /// Replace node `i`'s potential and mark it dirty.
    pub(crate) fn set_unary(&mut self, i: usize, u: &[f64]) {
        self.unary[i * self.k..(i + 1) * self.k].copy_from_slice(u);
        self.dirty[i] = true;
        self.dirty_src[i] = usize::MAX;
    }

    /// Run BP until no node is dirty or `maxiter` sweeps.
    pub fn run(&mut self, opts: &MapBpOptions) -> PairwiseRun {
        // Monomorphise the common category counts (constant k lets the compiler unroll).
        match self.k {
            2 => self.run_k(2, opts),
            3 => self.run_k(3, opts),
            4 => self.run_k(4, opts),
            5 => self.run_k(5, opts),
            6 => self.run_k(6, opts),
            k => self.run_k(k, opts),
        }
    }

    #[inline(always)]
    fn run_k(&mut self, k: usize, opts: &MapBpOptions) -> PairwiseRun {
        let mut run = PairwiseRun::default();
        let (mut p, mut h) = (vec![0.0; k], vec![0.0; k]);
        let mut new = vec![0.0; k];
        let n = self.dirty.len();
        let mut queue: std::collections::VecDeque<(usize, usize)> =
            (0..n).filter(|&i| self.dirty[i]).map(|i| (i, 0)).collect();
        let limit = opts.maxiter.saturating_mul(n.max(1));
        let mut visits = 0usize;
        while let Some((i, gen)) = queue.pop_front() {
            if visits >= limit {
                queue.push_front((i, gen));
                break;
            }
            visits += 1;
            if gen + 1 > run.iterations {
                run.iterations = gen + 1;
                run.max_diff = 0.0;
            }
            {
                self.dirty[i] = false;
                let src = std::mem::replace(&mut self.dirty_src[i], usize::MAX);
                p.copy_from_slice(&self.unary[i * k..(i + 1) * k]);
                for &(_, _, inn) in &self.nbrs[i] {
                    p.iter_mut()
                        .zip(&self.msgs[inn * k..(inn + 1) * k])
                        .for_each(|(a, m)| *a *= m);
                }
                let mx = p.iter().cloned().fold(0.0, f64::max);
                if mx > 0.0 {
                    p.iter_mut().for_each(|a| *a /= mx);
                }
                for idx in 0..self.nbrs[i].len() {
                    let (j, out, inn) = self.nbrs[i][idx];
                    if j == src {
                        continue;
                    }
                    let m_in = &self.msgs[inn * k..(inn + 1) * k];
                    if m_in.iter().all(|x| *x > 0.0) {
                        h.iter_mut()
                            .zip(p.iter().zip(m_in))
                            .for_each(|(h, (p, m))| *h = p / m);
                    } else {
                        // a zero in the incoming message: form the cavity product directly
                        h.copy_from_slice(&self.unary[i * k..(i + 1) * k]);
                        for &(_, _, inn2) in &self.nbrs[i] {
                            if inn2 != inn {
                                h.iter_mut()
                                    .zip(&self.msgs[inn2 * k..(inn2 + 1) * k])
                                    .for_each(|(a, m)| *a *= m);
                            }
                        }
                    }
                    new.fill(0.0);
                    if out % 2 == 0 {
                        // i is the edge's first node: new(b) = Σ_a h(a) φ(a, b)
                        for (a, ha) in h.iter().enumerate() {
                            let row = &self.phi[a * k..(a + 1) * k];
                            new.iter_mut().zip(row).for_each(|(n, f)| *n += ha * f);
                        }
                    } else {
                        // i is the edge's second node: new(a) = Σ_b φ(a, b) h(b)
                        for (a, na) in new.iter_mut().enumerate() {
                            let row = &self.phi[a * k..(a + 1) * k];
                            *na = row.iter().zip(&h).map(|(f, hb)| f * hb).sum();
                        }
                    }
                    let z: f64 = new.iter().sum();
                    if !(z > 0.0 && z.is_finite()) {
                        // an impossible configuration upstream; keep the old message
                        continue;
                    }
                    let inv = 1.0 / z;
                    new.iter_mut().for_each(|x| *x *= inv);
                    let old = &mut self.msgs[out * k..(out + 1) * k];
                    if opts.damping > 0.0 {
                        new.iter_mut().zip(old.iter()).for_each(|(n, o)| {
                            *n = n.powf(1.0 - opts.damping) * o.powf(opts.damping)
                        });
                        let z: f64 = new.iter().sum();
                        new.iter_mut().for_each(|x| *x /= z);
                    }
                    let change = new
                        .iter()
                        .zip(old.iter())
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max);
                    old.copy_from_slice(&new);
                    run.updates += 1;
                    run.max_diff = run.max_diff.max(change);
                    if change > opts.tol {
                        if !self.dirty[j] {
                            self.dirty[j] = true;
                            self.dirty_src[j] = i;
                            queue.push_back((j, gen + 1));
                        } else if self.dirty_src[j] != i {
                            self.dirty_src[j] = usize::MAX;
                        }
                    }
                }
            }
        }
        run.converged = queue.is_empty();
        run
    }

    /// Belief of node `i`.
    pub(crate) fn belief(&self, i: usize) -> Vec<f64> {
        let k = self.k;
        let mut b = self.unary[i * k..(i + 1) * k].to_vec();
        for &(_, _, inn) in &self.nbrs[i] {
            b.iter_mut()
                .zip(&self.msgs[inn * k..(inn + 1) * k])
                .for_each(|(a, m)| *a *= m);
        }
        let z: f64 = b.iter().sum();
        if z > 0.0 && z.is_finite() {
            b.iter_mut().for_each(|x| *x /= z);
        } else {
            b.iter_mut().for_each(|x| *x = 1.0 / k as f64);
        }
        b
    }
}
