//! Readers for the inference community's model formats, and the UAI `.MAR` writer.
//!
//! * UAI (the UAI 2008–2014 inference competitions): `MARKOV` or `BAYES`, the number of
//!   variables, their cardinalities, the number of factors, each factor's scope (size then
//!   variables), then each table (entry count then entries) with the LAST scope variable varying
//!   fastest. Evidence files: the number of observed variables, then `variable value` pairs (an
//!   older layout prefixes a sample count of 1; both are read).
//! * libDAI `.fg`: the number of factors, then per factor the number of variables, their
//!   labels, their cardinalities, the number of non-zero entries and `index value` lines, with
//!   the FIRST variable varying fastest. Labels are mapped to variables `0..n` in increasing
//!   label order.

use crate::factor::{Factor, FactorGraph};
use crate::GraphError;
use std::collections::BTreeMap;

/// Largest table a model file may declare (entries), to refuse absurd inputs early.
pub const MAX_TABLE_ENTRIES: usize = 1 << 24;

struct Tokens<'a> {
    it: std::iter::Peekable<std::str::SplitWhitespace<'a>>,
    what: &'a str,
    count: usize,
}

impl<'a> Tokens<'a> {
    fn new(text: &'a str, what: &'a str) -> Self {
        Tokens {
            it: text.split_whitespace().peekable(),
            what,
            count: 0,
        }
    }
    fn next_str(&mut self, expected: &str) -> Result<&'a str, GraphError> {
        self.count += 1;
        self.it.next().ok_or_else(|| GraphError::Parse {
            what: self.what.to_string(),
            message: format!(
                "the file ends where {expected} was expected (token {})",
                self.count
            ),
        })
    }
    fn usize(&mut self, expected: &str) -> Result<usize, GraphError> {
        let s = self.next_str(expected)?;
        s.parse().map_err(|_| GraphError::Parse {
            what: self.what.to_string(),
            message: format!(
                "token {} is `{s}`; expected {expected} (a non-negative integer)",
                self.count
            ),
        })
    }
    fn f64(&mut self, expected: &str) -> Result<f64, GraphError> {
        let s = self.next_str(expected)?;
        s.parse().map_err(|_| GraphError::Parse {
            what: self.what.to_string(),
            message: format!(
                "token {} is `{s}`; expected {expected} (a number)",
                self.count
            ),
        })
    }
    fn err(&self, message: String) -> GraphError {
        GraphError::Parse {
            what: self.what.to_string(),
            message,
        }
    }
}

fn strip_comments(text: &str) -> String {
    text.lines()
        .filter(|l| !l.trim_start().starts_with('#'))
        .collect::<Vec<_>>()
        .join("\n")
}

fn table_size(cards: &[usize], t: &Tokens) -> Result<usize, GraphError> {
    cards
        .iter()
        .try_fold(1usize, |a, &c| a.checked_mul(c))
        .filter(|&s| s <= MAX_TABLE_ENTRIES)
        .ok_or_else(|| {
            t.err(format!(
                "a factor table over cardinalities {cards:?} is too large"
            ))
        })
}

/// Read a UAI `MARKOV` / `BAYES` model; `what` names the source in errors.
pub fn parse_uai(text: &str, what: &str) -> Result<FactorGraph, GraphError> {
    let text = strip_comments(text);
    let mut t = Tokens::new(&text, what);
    let kind = t.next_str("MARKOV or BAYES")?;
    if !kind.eq_ignore_ascii_case("MARKOV") && !kind.eq_ignore_ascii_case("BAYES") {
        return Err(t.err(format!("the header is `{kind}`; expected MARKOV or BAYES")));
    }
    let n = t.usize("the number of variables")?;
    let mut cards = Vec::with_capacity(n.min(1 << 20));
    // Inference keeps a belief of every variable's cardinality, used by a factor or not: the
    // beliefs together are bounded like one table (fuzzing found a variable of cardinality
    // 10^11 in no factor, whose uniform belief aborted the allocation).
    let mut beliefs = 0usize;
    for i in 0..n {
        let c = t.usize(&format!("the cardinality of variable {i}"))?;
        if c == 0 {
            return Err(t.err(format!("variable {i} has cardinality 0")));
        }
        beliefs = beliefs.saturating_add(c);
        if beliefs > MAX_TABLE_ENTRIES {
            return Err(t.err(format!(
                "the cardinalities of variables 0..={i} sum to more than {MAX_TABLE_ENTRIES}; \
                 expected at most {MAX_TABLE_ENTRIES} values over all variables"
            )));
        }
        cards.push(c);
    }
    let m = t.usize("the number of factors")?;
    let mut scopes = Vec::with_capacity(m.min(1 << 20));
    for f in 0..m {
        let k = t.usize(&format!("the scope size of factor {f}"))?;
        let mut s = Vec::with_capacity(k.min(64));
        for _ in 0..k {
            let v = t.usize(&format!("a variable of factor {f}"))?;
            if v >= n {
                return Err(t.err(format!(
                    "factor {f} uses variable {v}, but there are {n} variables"
                )));
            }
            s.push(v);
        }
        scopes.push(s);
    }
    let mut g = FactorGraph::new(cards.clone())?;
    for (f, scope) in scopes.into_iter().enumerate() {
        let fc: Vec<usize> = scope.iter().map(|&v| cards[v]).collect();
        let size = table_size(&fc, &t)?;
        let k = t.usize(&format!("the table size of factor {f}"))?;
        if k != size {
            return Err(t.err(format!(
                "factor {f} declares {k} entries; its scope needs {size}"
            )));
        }
        let mut vals = Vec::with_capacity(size.min(1 << 16));
        for _ in 0..size {
            vals.push(t.f64(&format!("an entry of factor {f}"))?);
        }
        // UAI: last variable fastest == first-fastest over the reversed scope.
        let mut rs = scope;
        rs.reverse();
        let mut rc = fc;
        rc.reverse();
        let fac = Factor::new(rs, rc, vals).map_err(|e| t.err(format!("factor {f}: {e}")))?;
        g.add_factor(fac)?;
    }
    Ok(g)
}

/// Read UAI evidence: `(variable, value)` pairs.
pub fn parse_uai_evidence(text: &str, what: &str) -> Result<Vec<(usize, usize)>, GraphError> {
    let toks: Vec<&str> = text.split_whitespace().collect();
    let nums: Vec<usize> = toks
        .iter()
        .map(|s| {
            s.parse().map_err(|_| GraphError::Parse {
                what: what.to_string(),
                message: format!("`{s}` is not a non-negative integer"),
            })
        })
        .collect::<Result<_, _>>()?;
    if nums.is_empty() {
        return Ok(Vec::new());
    }
    let pairs = if nums.len() == 1 + 2 * nums[0] {
        &nums[1..]
    } else if nums[0] == 1 && nums.len() >= 2 && nums.len() == 2 + 2 * nums[1] {
        &nums[2..]
    } else {
        return Err(GraphError::Parse {
            what: what.to_string(),
            message: format!(
                "{} numbers do not form `N var val ...` with N pairs",
                nums.len()
            ),
        });
    };
    Ok(pairs.chunks(2).map(|c| (c[0], c[1])).collect())
}

/// A libDAI `.fg` model and the original labels of its variables (variable `i` has label
/// `labels[i]`).
#[derive(Debug, Clone)]
pub struct LabeledGraph {
    /// The factor graph over variables `0..n`.
    pub graph: FactorGraph,
    /// The `.fg` label of each variable.
    pub labels: Vec<usize>,
}

/// Read a libDAI `.fg` file; `what` names the source in errors.
pub fn parse_fg(text: &str, what: &str) -> Result<LabeledGraph, GraphError> {
    let text = strip_comments(text);
    let mut t = Tokens::new(&text, what);
    let m = t.usize("the number of factors")?;
    let mut raw = Vec::with_capacity(m.min(1 << 20));
    let mut label_card: BTreeMap<usize, usize> = BTreeMap::new();
    for f in 0..m {
        let k = t.usize(&format!("the number of variables of factor {f}"))?;
        let mut labels = Vec::with_capacity(k.min(64));
        for _ in 0..k {
            labels.push(t.usize(&format!("a variable label of factor {f}"))?);
        }
        let mut cards = Vec::with_capacity(k.min(64));
        for (i, &l) in labels.iter().enumerate() {
            let c = t.usize(&format!("the cardinality of variable {l} in factor {f}"))?;
            if c == 0 {
                return Err(t.err(format!("variable {l} has cardinality 0")));
            }
            if let Some(&old) = label_card.get(&l) {
                if old != c {
                    return Err(t.err(format!(
                        "variable {l} has cardinality {old} elsewhere but {c} in factor {f}"
                    )));
                }
            }
            label_card.insert(l, c);
            let _ = i;
            cards.push(c);
        }
        let size = table_size(&cards, &t)?;
        let nz = t.usize(&format!("the number of non-zero entries of factor {f}"))?;
        let mut vals = vec![0.0; size];
        for _ in 0..nz {
            let i = t.usize(&format!("an entry index of factor {f}"))?;
            let v = t.f64(&format!("an entry value of factor {f}"))?;
            if i >= size {
                return Err(t.err(format!(
                    "factor {f} has entry index {i}; its table has {size} entries"
                )));
            }
            vals[i] = v;
        }
        raw.push((labels, cards, vals));
    }
    let labels: Vec<usize> = label_card.keys().copied().collect();
    let index: BTreeMap<usize, usize> = labels.iter().enumerate().map(|(i, &l)| (l, i)).collect();
    let mut g = FactorGraph::new(label_card.values().copied().collect())?;
    for (f, (ls, cards, vals)) in raw.into_iter().enumerate() {
        let vars = ls.iter().map(|l| index[l]).collect();
        let fac = Factor::new(vars, cards, vals).map_err(|e| t.err(format!("factor {f}: {e}")))?;
        g.add_factor(fac)?;
    }
    Ok(LabeledGraph { graph: g, labels })
}

/// Marginals in the UAI `.MAR` layout: `MAR`, then on one line the number of variables and per
/// variable its cardinality and probabilities.
pub fn format_mar(marginals: &[Vec<f64>]) -> String {
    let mut s = format!("MAR\n{}", marginals.len());
    for m in marginals {
        s.push_str(&format!(" {}", m.len()));
        for p in m {
            s.push_str(&format!(" {p}"));
        }
    }
    s.push('\n');
    s
}

/// Read a UAI `.MAR` file (the last `MAR` block if there are several).
pub fn parse_mar(text: &str, what: &str) -> Result<Vec<Vec<f64>>, GraphError> {
    let start = text.rfind("MAR").ok_or_else(|| GraphError::Parse {
        what: what.to_string(),
        message: "no `MAR` header".into(),
    })?;
    let mut t = Tokens::new(&text[start + 3..], what);
    let n = t.usize("the number of variables")?;
    let mut out = Vec::with_capacity(n.min(1 << 20));
    for i in 0..n {
        let c = t.usize(&format!("the cardinality of variable {i}"))?;
        let mut m = Vec::with_capacity(c.min(1 << 16));
        for _ in 0..c {
            m.push(t.f64(&format!("a probability of variable {i}"))?);
        }
        out.push(m);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Found by fuzzing (issue 18, `fuzz/README.md`): one variable of cardinality 10^11 in no
    /// factor parsed, and inference then aborted allocating its uniform belief.
    #[test]
    fn cardinalities_beyond_the_table_bound_are_refused_even_in_no_factor() {
        let e = parse_uai("MARKOV\n1\n100000000000\n0\n", "huge.uai")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("huge.uai") && e.contains("sum to more than"),
            "{e}"
        );
        // Many variables whose cardinalities add up past the bound, too.
        let many = format!("MARKOV\n3\n{0} {0} {0}\n0\n", MAX_TABLE_ENTRIES / 2);
        assert!(parse_uai(&many, "many.uai").is_err());
        // At the bound, a model still reads.
        let fits = format!("MARKOV\n2\n{} 1\n0\n", MAX_TABLE_ENTRIES - 1);
        assert!(parse_uai(&fits, "fits.uai").is_ok());
    }
}
