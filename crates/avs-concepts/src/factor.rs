//! Discrete factors and factor graphs.
//!
//! A [`Factor`] is a non-negative table over a scope of discrete variables. Tables are stored
//! with the FIRST variable of the scope varying fastest (libDAI's convention); the UAI reader
//! converts by reversing the scope, since a UAI table (last variable fastest) over `(a, b, c)`
//! is the same array as a first-fastest table over `(c, b, a)`.

use crate::GraphError;

/// A non-negative table over discrete variables; the first variable varies fastest.
#[derive(Debug, Clone, PartialEq)]
pub struct Factor {
    vars: Vec<usize>,
    cards: Vec<usize>,
    values: Vec<f64>,
}

impl Factor {
    /// A factor over `vars` (with cardinalities `cards`) and its table, first variable fastest.
    /// Errors when sizes disagree, a variable repeats, or an entry is negative or not finite.
    pub fn new(vars: Vec<usize>, cards: Vec<usize>, values: Vec<f64>) -> Result<Self, GraphError> {
        if vars.len() != cards.len() {
            return Err(GraphError::Invalid(format!(
                "factor has {} variables but {} cardinalities",
                vars.len(),
                cards.len()
            )));
        }
        for (i, v) in vars.iter().enumerate() {
            if vars[..i].contains(v) {
                return Err(GraphError::Invalid(format!(
                    "variable {v} appears twice in one factor"
                )));
            }
        }
        if cards.contains(&0) {
            return Err(GraphError::Invalid("a variable has cardinality 0".into()));
        }
        let size = cards
            .iter()
            .try_fold(1usize, |a, &c| a.checked_mul(c))
            .ok_or_else(|| GraphError::Invalid("factor table too large".into()))?;
        if values.len() != size {
            return Err(GraphError::Invalid(format!(
                "factor over {vars:?} needs {size} entries, got {}",
                values.len()
            )));
        }
        if let Some(bad) = values.iter().find(|v| !v.is_finite() || **v < 0.0) {
            return Err(GraphError::Invalid(format!(
                "factor over {vars:?} has entry {bad}; entries must be finite and >= 0"
            )));
        }
        Ok(Self {
            vars,
            cards,
            values,
        })
    }

    /// The all-ones factor over `vars`.
    pub fn ones(vars: Vec<usize>, cards: Vec<usize>) -> Result<Self, GraphError> {
        let size = cards.iter().product();
        Self::new(vars, cards, vec![1.0; size])
    }

    /// The scope.
    pub fn vars(&self) -> &[usize] {
        &self.vars
    }
    /// Cardinalities of the scope's variables.
    pub fn cards(&self) -> &[usize] {
        &self.cards
    }
    /// The table, first variable fastest.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Scale so that the largest entry is 1 (no-op for an all-zero table); returns the scale.
    pub fn normalize_max(&mut self) -> f64 {
        let m = self.values.iter().cloned().fold(0.0, f64::max);
        if m > 0.0 {
            self.values.iter_mut().for_each(|v| *v /= m);
        }
        m
    }

    /// Product of two factors over the union of their scopes (self's variables first).
    pub fn product(&self, other: &Factor) -> Factor {
        let mut vars = self.vars.clone();
        let mut cards = self.cards.clone();
        for (v, c) in other.vars.iter().zip(&other.cards) {
            if !vars.contains(v) {
                vars.push(*v);
                cards.push(*c);
            }
        }
        let sa = strides_in(&self.vars, &self.cards, &vars);
        let sb = strides_in(&other.vars, &other.cards, &vars);
        let size: usize = cards.iter().product();
        let mut values = Vec::with_capacity(size);
        let mut state = vec![0usize; vars.len()];
        let (mut ia, mut ib) = (0usize, 0usize);
        for _ in 0..size {
            values.push(self.values[ia] * other.values[ib]);
            for d in 0..vars.len() {
                state[d] += 1;
                ia += sa[d];
                ib += sb[d];
                if state[d] < cards[d] {
                    break;
                }
                ia -= sa[d] * cards[d];
                ib -= sb[d] * cards[d];
                state[d] = 0;
            }
        }
        Factor {
            vars,
            cards,
            values,
        }
    }

    /// Sum out every variable not in `keep`; the result's scope is `keep` in the given order
    /// (variables of `keep` absent from the scope are ignored).
    pub fn marginal(&self, keep: &[usize]) -> Factor {
        let mut vars = Vec::new();
        let mut cards = Vec::new();
        for k in keep {
            if let Some(p) = self.vars.iter().position(|v| v == k) {
                vars.push(*k);
                cards.push(self.cards[p]);
            }
        }
        let st = strides_in(&vars, &cards, &self.vars);
        let size: usize = cards.iter().product();
        let mut values = vec![0.0; size];
        let mut state = vec![0usize; self.vars.len()];
        let mut it = 0usize;
        for &x in &self.values {
            values[it] += x;
            for d in 0..self.vars.len() {
                state[d] += 1;
                it += st[d];
                if state[d] < self.cards[d] {
                    break;
                }
                it -= st[d] * self.cards[d];
                state[d] = 0;
            }
        }
        Factor {
            vars,
            cards,
            values,
        }
    }
}

/// For each variable of `target`, its stride in a table over `vars` (0 when absent).
pub(crate) fn strides_in(vars: &[usize], cards: &[usize], target: &[usize]) -> Vec<usize> {
    let mut own = Vec::with_capacity(vars.len());
    let mut s = 1;
    for c in cards {
        own.push(s);
        s *= c;
    }
    target
        .iter()
        .map(|t| vars.iter().position(|v| v == t).map_or(0, |p| own[p]))
        .collect()
}

/// A factor graph: discrete variables `0..n` with cardinalities, and factors over them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FactorGraph {
    cards: Vec<usize>,
    factors: Vec<Factor>,
}

impl FactorGraph {
    /// A graph with the given variable cardinalities and no factors.
    pub fn new(cards: Vec<usize>) -> Result<Self, GraphError> {
        if cards.contains(&0) {
            return Err(GraphError::Invalid("a variable has cardinality 0".into()));
        }
        Ok(Self {
            cards,
            factors: Vec::new(),
        })
    }

    /// Add a factor; its variables must exist with the same cardinalities. Returns its index.
    pub fn add_factor(&mut self, f: Factor) -> Result<usize, GraphError> {
        for (v, c) in f.vars().iter().zip(f.cards()) {
            match self.cards.get(*v) {
                None => {
                    return Err(GraphError::Invalid(format!(
                        "factor uses variable {v}, but the graph has {} variables",
                        self.cards.len()
                    )))
                }
                Some(k) if k != c => {
                    return Err(GraphError::Invalid(format!(
                        "variable {v} has cardinality {k} in the graph but {c} in a factor"
                    )))
                }
                _ => {}
            }
        }
        self.factors.push(f);
        Ok(self.factors.len() - 1)
    }

    /// Replace the table of factor `i` by one over the same scope.
    pub fn set_factor(&mut self, i: usize, f: Factor) -> Result<(), GraphError> {
        let old = self
            .factors
            .get(i)
            .ok_or_else(|| GraphError::Invalid(format!("no factor {i}")))?;
        if old.vars() != f.vars() {
            return Err(GraphError::Invalid(format!(
                "factor {i} is over {:?}, not {:?}",
                old.vars(),
                f.vars()
            )));
        }
        self.factors[i] = f;
        Ok(())
    }

    /// Clamp variable `var` to `value` (evidence) by adding an indicator factor.
    pub fn clamp(&mut self, var: usize, value: usize) -> Result<(), GraphError> {
        let card = *self.cards.get(var).ok_or_else(|| {
            GraphError::Invalid(format!("evidence on variable {var}, which does not exist"))
        })?;
        if value >= card {
            return Err(GraphError::Invalid(format!(
                "evidence sets variable {var} to {value}, but it has only {card} values"
            )));
        }
        let mut t = vec![0.0; card];
        t[value] = 1.0;
        self.add_factor(Factor::new(vec![var], vec![card], t)?)?;
        Ok(())
    }

    /// Number of variables.
    pub fn num_vars(&self) -> usize {
        self.cards.len()
    }
    /// Cardinalities of all variables.
    pub fn cards(&self) -> &[usize] {
        &self.cards
    }
    /// All factors.
    pub fn factors(&self) -> &[Factor] {
        &self.factors
    }
}
