//! Reader for Anthony Cassandra's `.pomdp` file format (the format of pomdp-solve and SARSOP).
//!
//! Supported: `discount:`, `values: reward|cost`, `states:` / `actions:` / `observations:` as a count
//! or a list of names, `start:` as a distribution, `uniform`, a state name or index, `start include:`
//! and `start exclude:`; `T:`, `O:` and `R:` entries with `*` wildcards as single entries, rows, whole
//! matrices, `uniform` and (for T) `identity`. Entries are applied in file order, so later entries
//! override earlier ones. Comments run from `#` to the end of the line.
//!
//! Rewards `R(s, a, s', z)` are reduced to the expected immediate reward
//! `R(s, a) = Σ_{s'} T(s'|s,a) Σ_z O(z|a,s') R(s, a, s', z)`; with `values: cost` they are negated.
//!
//! ## Bounds on what a file may ask for
//! Every number must be finite. Before any table is allocated, `|S| × |A| × |Z|` and the dense
//! tables the reader builds (`|A| × |S|²` for T, `|A| × |S|² × |Z|` for rewards that depend on
//! the next state or the observation) must be at most [`crate::model::MAX_MODEL_ENTRIES`], with
//! the error at the line of the first entry that needs them. A reward must satisfy
//! `|R| / (1 − γ) ≤` [`crate::model::MAX_VALUE_MAGNITUDE`] (the largest value a policy could
//! earn), with the error at the reward's line: larger rewards parse as finite numbers but the
//! solver's sums overflow or drown in rounding (the reasons are on the constants).

use crate::error::{PomdpError, Result};
use crate::model::{Pomdp, PomdpTables};
use std::path::Path;

/// Largest dense table the reader builds (see the module docs).
const MAX_TABLE: usize = crate::model::MAX_MODEL_ENTRIES;

/// Read and parse a Cassandra `.pomdp` file.
pub fn read_pomdp_file(path: impl AsRef<Path>) -> Result<Pomdp> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| PomdpError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_pomdp(&text, &path.display().to_string())
}

/// Parse the text of a Cassandra `.pomdp` file; `file` names it in error messages.
pub fn parse_pomdp(text: &str, file: &str) -> Result<Pomdp> {
    let tokens = tokenize(text);
    let mut p = Parser {
        toks: tokens,
        pos: 0,
        file: file.to_string(),
        last_line: text.lines().count().max(1),
    };
    p.parse()
}

#[derive(Debug, Clone)]
struct Tok {
    text: String,
    line: usize,
}

fn tokenize(text: &str) -> Vec<Tok> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line_no = i + 1;
        let content = line.split('#').next().unwrap_or("");
        for word in content.split_whitespace() {
            let mut rest = word;
            while let Some(k) = rest.find(':') {
                if k > 0 {
                    out.push(Tok {
                        text: rest[..k].to_string(),
                        line: line_no,
                    });
                }
                out.push(Tok {
                    text: ":".into(),
                    line: line_no,
                });
                rest = &rest[k + 1..];
            }
            if !rest.is_empty() {
                out.push(Tok {
                    text: rest.to_string(),
                    line: line_no,
                });
            }
        }
    }
    out
}

/// Which indices an entry applies to.
#[derive(Debug, Clone, Copy)]
enum Spec {
    All,
    One(usize),
}

impl Spec {
    fn range(self, n: usize) -> std::ops::Range<usize> {
        match self {
            Spec::All => 0..n,
            Spec::One(i) => i..i + 1,
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct RewardEntry {
    a: Spec,
    s: Spec,
    s2: Spec,
    z: Spec,
    value: f64,
    /// 1-based line of the value.
    line: usize,
}

const KEYWORDS: [&str; 9] = [
    "discount",
    "values",
    "states",
    "actions",
    "observations",
    "start",
    "T",
    "O",
    "R",
];

struct Parser {
    toks: Vec<Tok>,
    pos: usize,
    file: String,
    last_line: usize,
}

#[derive(Clone, Copy, PartialEq)]
enum Kind {
    State,
    Action,
    Observation,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::State => "state",
            Kind::Action => "action",
            Kind::Observation => "observation",
        }
    }
}

impl Parser {
    fn err<T>(&self, line: usize, message: impl Into<String>) -> Result<T> {
        Err(PomdpError::Parse {
            file: self.file.clone(),
            line,
            message: message.into(),
        })
    }
    fn line(&self) -> usize {
        self.toks
            .get(self.pos)
            .map(|t| t.line)
            .unwrap_or(self.last_line)
    }
    fn peek(&self) -> Option<&str> {
        self.toks.get(self.pos).map(|t| t.text.as_str())
    }
    fn peek_at(&self, k: usize) -> Option<&str> {
        self.toks.get(self.pos + k).map(|t| t.text.as_str())
    }
    fn next(&mut self, what: &str) -> Result<Tok> {
        match self.toks.get(self.pos) {
            Some(t) => {
                self.pos += 1;
                Ok(t.clone())
            }
            None => self.err(
                self.last_line,
                format!("unexpected end of file, expected {what}"),
            ),
        }
    }
    fn expect_colon(&mut self) -> Result<()> {
        let t = self.next("`:`")?;
        if t.text != ":" {
            return self.err(t.line, format!("expected `:`, found `{}`", t.text));
        }
        Ok(())
    }
    fn at_statement_start(&self) -> bool {
        match self.peek() {
            None => true,
            Some(w) if KEYWORDS.contains(&w) => {
                matches!(self.peek_at(1), Some(":"))
                    || (w == "start" && matches!(self.peek_at(1), Some("include" | "exclude")))
            }
            _ => false,
        }
    }
    fn number(&mut self, what: &str) -> Result<f64> {
        let t = self.next(what)?;
        match t.text.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => self.err(
                t.line,
                format!("expected {what} (a finite number), found `{}`", t.text),
            ),
        }
    }
    fn numbers(&mut self, n: usize, what: &str) -> Result<Vec<f64>> {
        (0..n).map(|_| self.number(what)).collect()
    }

    fn parse(&mut self) -> Result<Pomdp> {
        let mut discount: Option<f64> = None;
        let mut cost = false;
        let mut states: Option<Vec<String>> = None;
        let mut actions: Option<Vec<String>> = None;
        let mut observations: Option<Vec<String>> = None;
        let mut start: Option<Vec<f64>> = None;
        let mut trans: Vec<f64> = Vec::new();
        let mut obs: Vec<f64> = Vec::new();
        let mut rewards: Vec<RewardEntry> = Vec::new();
        let mut tables_ready = false;

        while let Some(word) = self.peek().map(str::to_string) {
            let line = self.line();
            if !self.at_statement_start() {
                return self.err(
                    line,
                    format!(
                        "expected a statement (discount:, values:, states:, actions:, observations:, start:, T:, O:, R:), found `{word}`"
                    ),
                );
            }
            self.pos += 1;
            match word.as_str() {
                "discount" => {
                    self.expect_colon()?;
                    let d = self.number("the discount")?;
                    if !(0.0..=1.0).contains(&d) {
                        return self.err(line, format!("discount {d} is outside [0, 1]"));
                    }
                    discount = Some(d);
                }
                "values" => {
                    self.expect_colon()?;
                    let t = self.next("`reward` or `cost`")?;
                    cost = match t.text.as_str() {
                        "reward" => false,
                        "cost" => true,
                        other => {
                            return self.err(
                                t.line,
                                format!("values must be `reward` or `cost`, found `{other}`"),
                            )
                        }
                    };
                }
                "states" | "actions" | "observations" => {
                    if tables_ready {
                        return self.err(
                            line,
                            format!("`{word}:` must come before start:, T:, O: and R: entries"),
                        );
                    }
                    self.expect_colon()?;
                    let names = self.name_list(&word)?;
                    match word.as_str() {
                        "states" => states = Some(names),
                        "actions" => actions = Some(names),
                        _ => observations = Some(names),
                    }
                }
                "start" | "T" | "O" | "R" => {
                    let (Some(st), Some(ac), Some(ob)) = (&states, &actions, &observations) else {
                        return self.err(
                            line,
                            format!("`{word}` appears before states:, actions: and observations: are all declared"),
                        );
                    };
                    let (ns, na, no) = (st.len(), ac.len(), ob.len());
                    if !tables_ready {
                        let (t, o) = self.table_sizes(line, ns, na, no)?;
                        trans = vec![0.0; t];
                        obs = vec![0.0; o];
                        tables_ready = true;
                    }
                    let names = Names {
                        states: st.clone(),
                        actions: ac.clone(),
                        observations: ob.clone(),
                    };
                    match word.as_str() {
                        "start" => start = Some(self.start(&names)?),
                        "T" => self.t_entry(&names, &mut trans)?,
                        "O" => self.o_entry(&names, &mut obs)?,
                        _ => self.r_entry(&names, &mut rewards)?,
                    }
                }
                _ => unreachable!("at_statement_start only accepts keywords"),
            }
        }

        let Some(discount) = discount else {
            return self.err(1, "missing `discount:`");
        };
        let (Some(states), Some(actions), Some(observations)) = (states, actions, observations)
        else {
            return self.err(1, "missing one of `states:`, `actions:`, `observations:`");
        };
        let (ns, na, no) = (states.len(), actions.len(), observations.len());
        if !tables_ready {
            let (t, o) = self.table_sizes(self.last_line, ns, na, no)?;
            trans = vec![0.0; t];
            obs = vec![0.0; o];
        }
        // Rewards too large for the solver's arithmetic, named at their line (a discount of 1
        // is refused by the model with its own message).
        if discount < 1.0 {
            if let Some(e) = rewards
                .iter()
                .find(|e| !crate::model::reward_in_range(e.value, discount))
            {
                return self.err(
                    e.line,
                    format!(
                        "reward {:e} at discount {discount} allows values up to {:.2e}; expected |reward| / (1 − discount) ≤ {:e} (rescale the rewards)",
                        e.value,
                        e.value.abs() / (1.0 - discount),
                        crate::model::MAX_VALUE_MAGNITUDE
                    ),
                );
            }
        }
        let reward_table = expected_rewards(&rewards, &trans, &obs, ns, na, no).map_err(|m| {
            PomdpError::Parse {
                file: self.file.clone(),
                line: 1,
                message: m,
            }
        })?;
        let rewards = if cost {
            reward_table.into_iter().map(|r| -r).collect()
        } else {
            reward_table
        };
        let initial = start.unwrap_or_else(|| vec![1.0 / ns as f64; ns]);
        Pomdp::new(PomdpTables {
            states,
            actions,
            observations,
            discount,
            transitions: trans,
            observation_probs: obs,
            rewards,
            initial,
        })
        .map_err(|e| match e {
            PomdpError::InvalidModel(m) => PomdpError::InvalidModel(format!("{}: {m}", self.file)),
            other => other,
        })
    }

    /// Sizes of the dense T and O tables, or the error (at `line`) when the model is larger
    /// than [`MAX_TABLE`] allows.
    fn table_sizes(&self, line: usize, ns: usize, na: usize, no: usize) -> Result<(usize, usize)> {
        if let Err(e) = crate::model::check_size(ns, na, no) {
            return self.err(line, e.to_string());
        }
        match na.checked_mul(ns).and_then(|x| x.checked_mul(ns)) {
            Some(t) if t <= MAX_TABLE => Ok((t, na * ns * no)),
            _ => self.err(
                line,
                format!("model too large: the transition table of {na} actions × {ns} states × {ns} states is above {MAX_TABLE} entries; expected fewer states or actions"),
            ),
        }
    }

    fn name_list(&mut self, what: &str) -> Result<Vec<String>> {
        let line = self.line();
        let mut names = Vec::new();
        while !self.at_statement_start() {
            let t = self.next("a name")?;
            if t.text == ":" {
                return self.err(t.line, format!("unexpected `:` in the {what} list"));
            }
            names.push(t.text);
        }
        if names.len() == 1 {
            if let Ok(n) = names[0].parse::<usize>() {
                if n == 0 || n > 1 << 20 {
                    return self.err(
                        line,
                        format!("`{what}:` count must be between 1 and 2^20, got {n}"),
                    );
                }
                return Ok((0..n).map(|i| i.to_string()).collect());
            }
        }
        if names.is_empty() {
            return self.err(line, format!("`{what}:` needs a count or a list of names"));
        }
        for (i, n) in names.iter().enumerate() {
            if names[..i].contains(n) {
                return self.err(line, format!("{what} name `{n}` is declared twice"));
            }
        }
        Ok(names)
    }

    fn spec(&mut self, names: &Names, kind: Kind) -> Result<Spec> {
        let t = self.next(kind.name())?;
        if t.text == "*" {
            return Ok(Spec::All);
        }
        let list = names.of(kind);
        if let Some(i) = list.iter().position(|n| *n == t.text) {
            return Ok(Spec::One(i));
        }
        if let Ok(i) = t.text.parse::<usize>() {
            if i < list.len() {
                return Ok(Spec::One(i));
            }
        }
        self.err(
            t.line,
            format!(
                "unknown {} `{}` (expected a declared name, an index below {}, or `*`)",
                kind.name(),
                t.text,
                list.len()
            ),
        )
    }

    fn start(&mut self, names: &Names) -> Result<Vec<f64>> {
        let ns = names.states.len();
        let line = self.line();
        match self.peek() {
            Some("include") | Some("exclude") => {
                let include = self.next("include")?.text == "include";
                self.expect_colon()?;
                let mut listed = vec![false; ns];
                let mut any = false;
                while !self.at_statement_start() {
                    match self.spec(names, Kind::State)? {
                        Spec::All => listed.iter_mut().for_each(|x| *x = true),
                        Spec::One(i) => listed[i] = true,
                    }
                    any = true;
                }
                if !any {
                    return self.err(line, "`start include:`/`start exclude:` needs states");
                }
                let chosen: Vec<bool> = listed.iter().map(|l| *l == include).collect();
                let k = chosen.iter().filter(|c| **c).count();
                if k == 0 {
                    return self.err(line, "start exclude: leaves no state");
                }
                Ok(chosen
                    .iter()
                    .map(|c| if *c { 1.0 / k as f64 } else { 0.0 })
                    .collect())
            }
            _ => {
                self.expect_colon()?;
                let first = self.next("a start distribution, `uniform` or a state")?;
                self.pos -= 1;
                if first.text == "uniform" {
                    self.pos += 1;
                    return Ok(vec![1.0 / ns as f64; ns]);
                }
                let is_named = names.states.contains(&first.text);
                let single_index = !is_named && first.text.parse::<usize>().is_ok() && ns > 1 && {
                    self.pos += 1;
                    let end = self.at_statement_start();
                    self.pos -= 1;
                    end
                };
                if is_named || single_index || first.text.parse::<f64>().is_err() {
                    let Spec::One(i) = self.spec(names, Kind::State)? else {
                        return self.err(
                            first.line,
                            "`start: *` is not allowed; use `start: uniform`",
                        );
                    };
                    let mut b = vec![0.0; ns];
                    b[i] = 1.0;
                    return Ok(b);
                }
                let b = self.numbers(ns, "a start probability")?;
                let sum: f64 = b.iter().sum();
                if b.iter().any(|p| *p < 0.0) || (sum - 1.0).abs() > crate::model::ROW_TOLERANCE {
                    return self.err(
                        line,
                        format!(
                            "start distribution must be non-negative and sum to 1 (sums to {sum})"
                        ),
                    );
                }
                Ok(b)
            }
        }
    }

    fn t_entry(&mut self, names: &Names, trans: &mut [f64]) -> Result<()> {
        let ns = names.states.len();
        self.table_entry(
            names,
            trans,
            Kind::State,
            ns,
            "a transition probability",
            true,
        )
    }

    fn o_entry(&mut self, names: &Names, obs: &mut [f64]) -> Result<()> {
        let no = names.observations.len();
        self.table_entry(
            names,
            obs,
            Kind::Observation,
            no,
            "an observation probability",
            false,
        )
    }

    /// One `T:` or `O:` entry: a table indexed `[action][state][col]` with `ncols` columns of
    /// kind `col` (end states for T, observations for O). Forms: `a : s : col p`, `a : s` and a
    /// row (or `uniform`), `a` and a matrix (or `uniform`, or `identity` where `identity_ok`).
    fn table_entry(
        &mut self,
        names: &Names,
        table: &mut [f64],
        col: Kind,
        ncols: usize,
        what: &str,
        identity_ok: bool,
    ) -> Result<()> {
        let ns = names.states.len();
        let na = names.actions.len();
        self.expect_colon()?;
        let a = self.spec(names, Kind::Action)?;
        if self.peek() == Some(":") {
            self.pos += 1;
            let s = self.spec(names, Kind::State)?;
            if self.peek() == Some(":") {
                self.pos += 1;
                let c = self.spec(names, col)?;
                let p = self.number(what)?;
                for a in a.range(na) {
                    for s in s.range(ns) {
                        for c in c.range(ncols) {
                            table[(a * ns + s) * ncols + c] = p;
                        }
                    }
                }
            } else {
                let row = if self.peek() == Some("uniform") {
                    self.pos += 1;
                    vec![1.0 / ncols as f64; ncols]
                } else {
                    self.numbers(ncols, what)?
                };
                for a in a.range(na) {
                    for s in s.range(ns) {
                        table[(a * ns + s) * ncols..(a * ns + s + 1) * ncols].copy_from_slice(&row);
                    }
                }
            }
        } else {
            let m: Vec<f64> = match self.peek() {
                Some("uniform") => {
                    self.pos += 1;
                    vec![1.0 / ncols as f64; ns * ncols]
                }
                Some("identity") if identity_ok => {
                    self.pos += 1;
                    (0..ns * ncols)
                        .map(|i| if i / ncols == i % ncols { 1.0 } else { 0.0 })
                        .collect()
                }
                _ => self.numbers(ns * ncols, what)?,
            };
            for a in a.range(na) {
                table[a * ns * ncols..(a + 1) * ns * ncols].copy_from_slice(&m);
            }
        }
        Ok(())
    }

    fn r_entry(&mut self, names: &Names, out: &mut Vec<RewardEntry>) -> Result<()> {
        let ns = names.states.len();
        let no = names.observations.len();
        self.expect_colon()?;
        let a = self.spec(names, Kind::Action)?;
        self.expect_colon()?;
        let s = self.spec(names, Kind::State)?;
        if self.peek() == Some(":") {
            self.pos += 1;
            let s2 = self.spec(names, Kind::State)?;
            if self.peek() == Some(":") {
                self.pos += 1;
                let z = self.spec(names, Kind::Observation)?;
                let line = self.line();
                let value = self.number("a reward")?;
                out.push(RewardEntry {
                    a,
                    s,
                    s2,
                    z,
                    value,
                    line,
                });
            } else {
                for z in 0..no {
                    let line = self.line();
                    let value = self.number("a reward")?;
                    out.push(RewardEntry {
                        a,
                        s,
                        s2,
                        z: Spec::One(z),
                        value,
                        line,
                    });
                }
            }
        } else {
            for i in 0..ns * no {
                let line = self.line();
                let value = self.number("a reward")?;
                out.push(RewardEntry {
                    a,
                    s,
                    s2: Spec::One(i / no),
                    z: Spec::One(i % no),
                    value,
                    line,
                });
            }
        }
        Ok(())
    }
}

struct Names {
    states: Vec<String>,
    actions: Vec<String>,
    observations: Vec<String>,
}

impl Names {
    fn of(&self, k: Kind) -> &[String] {
        match k {
            Kind::State => &self.states,
            Kind::Action => &self.actions,
            Kind::Observation => &self.observations,
        }
    }
}

/// Reduce reward entries (in file order; later ones override) to `R(s, a)` at `a * ns + s`.
fn expected_rewards(
    entries: &[RewardEntry],
    trans: &[f64],
    obs: &[f64],
    ns: usize,
    na: usize,
    no: usize,
) -> std::result::Result<Vec<f64>, String> {
    let simple = entries
        .iter()
        .all(|e| matches!((e.s2, e.z), (Spec::All, Spec::All)));
    let mut r = vec![0.0; na * ns];
    if simple {
        for e in entries {
            for a in e.a.range(na) {
                for s in e.s.range(ns) {
                    r[a * ns + s] = e.value;
                }
            }
        }
        return Ok(r);
    }
    let size = na
        .checked_mul(ns)
        .and_then(|x| x.checked_mul(ns))
        .and_then(|x| x.checked_mul(no))
        .filter(|x| *x <= MAX_TABLE)
        .ok_or_else(|| {
            format!("rewards depend on next state or observation and the table of {na}×{ns}×{ns}×{no} entries is too large")
        })?;
    let mut full = vec![0.0; size];
    for e in entries {
        for a in e.a.range(na) {
            for s in e.s.range(ns) {
                for s2 in e.s2.range(ns) {
                    for z in e.z.range(no) {
                        full[((a * ns + s) * ns + s2) * no + z] = e.value;
                    }
                }
            }
        }
    }
    for a in 0..na {
        for s in 0..ns {
            let mut acc = 0.0;
            for s2 in 0..ns {
                let t = trans[(a * ns + s) * ns + s2];
                if t == 0.0 {
                    continue;
                }
                let mut inner = 0.0;
                for z in 0..no {
                    inner += obs[(a * ns + s2) * no + z] * full[((a * ns + s) * ns + s2) * no + z];
                }
                acc += t * inner;
            }
            r[a * ns + s] = acc;
        }
    }
    Ok(r)
}
