//! The small expression language of domain files:
//!
//! * conditions `var(?a, b) = ?x`, `var = value`, `var(?a) != unknown`, `relation(?a, ?b)`,
//!   `not relation(?a, ?b)`, `?a != ?b`;
//! * effects `var(?a) := value`;
//! * quantities: a number, or a caller-supplied function `name(?a, ?b)`.

/// A term as written: `?x` (a parameter) or a name (an object, constant or value).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RawTerm {
    /// `?name`.
    Param(String),
    /// A name.
    Name(String),
}

/// A parsed but unresolved expression.
#[derive(Debug, Clone, PartialEq)]
pub enum RawExpr {
    /// `name(args)` or `name(args) = t` / `!= t` / `:= t`.
    Call {
        /// The variable or relation name.
        name: String,
        /// Arguments.
        args: Vec<RawTerm>,
        /// The operator and right-hand side, if any: `=`, `!=` or `:=`.
        rhs: Option<(String, RawTerm)>,
        /// A leading `not`.
        negated: bool,
    },
    /// `?a = ?b` or `?a != ?b`.
    Compare {
        /// Left.
        a: RawTerm,
        /// Right.
        b: RawTerm,
        /// `!=`.
        negated: bool,
    },
    /// A number.
    Number(f64),
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Ident(String),
    Param(String),
    Num(f64),
    Sym(&'static str),
}

fn tokens(s: &str) -> Result<Vec<Tok>, String> {
    let mut out = Vec::new();
    let b: Vec<char> = s.chars().collect();
    let mut i = 0;
    let ident_char = |c: char| c.is_alphanumeric() || c == '-' || c == '_' || c == '.';
    while i < b.len() {
        let c = b[i];
        if c.is_whitespace() {
            i += 1;
        } else if c == '(' || c == ')' || c == ',' {
            out.push(Tok::Sym(match c {
                '(' => "(",
                ')' => ")",
                _ => ",",
            }));
            i += 1;
        } else if c == '=' {
            out.push(Tok::Sym("="));
            i += 1;
        } else if c == '!' && b.get(i + 1) == Some(&'=') {
            out.push(Tok::Sym("!="));
            i += 2;
        } else if c == ':' && b.get(i + 1) == Some(&'=') {
            out.push(Tok::Sym(":="));
            i += 2;
        } else if c == '?' {
            let start = i + 1;
            i += 1;
            while i < b.len() && ident_char(b[i]) {
                i += 1;
            }
            if i == start {
                return Err("`?` must be followed by a parameter name".into());
            }
            out.push(Tok::Param(b[start..i].iter().collect()));
        } else if ident_char(c) {
            let start = i;
            while i < b.len() && ident_char(b[i]) {
                i += 1;
            }
            let w: String = b[start..i].iter().collect();
            let numeric = w.starts_with(|c: char| c.is_ascii_digit() || c == '.');
            if numeric {
                let v: f64 = w.parse().map_err(|_| format!("`{w}` is not a number"))?;
                out.push(Tok::Num(v));
            } else {
                out.push(Tok::Ident(w));
            }
        } else {
            return Err(format!("unexpected character `{c}`"));
        }
    }
    Ok(out)
}

fn term(t: Option<&Tok>) -> Result<RawTerm, String> {
    match t {
        Some(Tok::Param(p)) => Ok(RawTerm::Param(p.clone())),
        Some(Tok::Ident(n)) => Ok(RawTerm::Name(n.clone())),
        Some(other) => Err(format!("found {other:?}; expected `?param` or a name")),
        None => Err("the expression ends early; expected `?param` or a name".into()),
    }
}

/// Parse one expression.
pub fn parse(s: &str) -> Result<RawExpr, String> {
    let t = tokens(s)?;
    if t.is_empty() {
        return Err("empty expression".into());
    }
    if let [Tok::Num(v)] = t.as_slice() {
        return Ok(RawExpr::Number(*v));
    }
    let mut i = 0;
    let mut negated = false;
    if matches!(&t[0], Tok::Ident(w) if w == "not") && t.len() > 1 {
        negated = true;
        i = 1;
    }
    let lhs = term(t.get(i))?;
    i += 1;
    match lhs {
        RawTerm::Param(_) => {
            let op = match t.get(i) {
                Some(Tok::Sym("=")) => false,
                Some(Tok::Sym("!=")) => true,
                _ => return Err("after a parameter expected `=` or `!=`".into()),
            };
            let b = term(t.get(i + 1))?;
            if t.len() != i + 2 {
                return Err("unexpected text after the comparison".into());
            }
            Ok(RawExpr::Compare {
                a: lhs,
                b,
                negated: op != negated,
            })
        }
        RawTerm::Name(name) => {
            let mut args = Vec::new();
            if t.get(i) == Some(&Tok::Sym("(")) {
                i += 1;
                if t.get(i) == Some(&Tok::Sym(")")) {
                    i += 1;
                } else {
                    loop {
                        args.push(term(t.get(i))?);
                        i += 1;
                        match t.get(i) {
                            Some(Tok::Sym(",")) => i += 1,
                            Some(Tok::Sym(")")) => {
                                i += 1;
                                break;
                            }
                            _ => return Err("expected `,` or `)` in the argument list".into()),
                        }
                    }
                }
            }
            let rhs = match t.get(i) {
                None => None,
                Some(Tok::Sym(op @ ("=" | "!=" | ":="))) => {
                    let r = term(t.get(i + 1))?;
                    i += 2;
                    Some((op.to_string(), r))
                }
                Some(other) => return Err(format!("unexpected {other:?}")),
            };
            if i != t.len() {
                return Err("unexpected text at the end".into());
            }
            Ok(RawExpr::Call {
                name,
                args,
                rhs,
                negated,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_conditions_effects_and_numbers() {
        assert_eq!(
            parse("category(?r) = kitchen").unwrap(),
            RawExpr::Call {
                name: "category".into(),
                args: vec![RawTerm::Param("r".into())],
                rhs: Some(("=".into(), RawTerm::Name("kitchen".into()))),
                negated: false
            }
        );
        assert!(
            matches!(parse("robot-at := ?to").unwrap(), RawExpr::Call { ref args, rhs: Some((ref op, _)), .. } if args.is_empty() && op == ":=")
        );
        assert!(matches!(
            parse("not connected(?a, ?b)").unwrap(),
            RawExpr::Call { negated: true, .. }
        ));
        assert!(matches!(
            parse("?a != ?b").unwrap(),
            RawExpr::Compare { negated: true, .. }
        ));
        assert_eq!(parse("0.25").unwrap(), RawExpr::Number(0.25));
        assert!(parse("f(?a").is_err());
        assert!(parse("a = ").is_err());
        assert!(parse("a # b").is_err());
    }
}
