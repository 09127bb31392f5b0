//! Initial fields and obstacle bounds: a number, an expression in `x`
//! (evalexpr, read as reals) or a piecewise-linear table.

use crate::{field, finite, FieldToml, SceneError, NODE_TOLERANCE};
use signorini_run::text::num;

/// The expression with every integer literal written as a real (`1` →
/// `1.0`), so that it evaluates in floating point: `1/2` is 0.5, not the
/// integer division's 0 (evalexpr types a literal without a dot or an
/// exponent as an integer). Digits inside identifiers (`x2`) are left alone.
pub fn real_literals(expr: &str) -> String {
    let b = expr.as_bytes();
    let mut out = String::with_capacity(expr.len() + 8);
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        let in_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_' || b[i - 1] == b'.');
        if c.is_ascii_digit() && !in_word {
            let start = i;
            let mut real = false;
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            if i < b.len() && b[i] == b'.' {
                real = true;
                i += 1;
                while i < b.len() && b[i].is_ascii_digit() {
                    i += 1;
                }
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                let mut j = i + 1;
                if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
                    j += 1;
                }
                if j < b.len() && b[j].is_ascii_digit() {
                    real = true;
                    i = j;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            out.push_str(&expr[start..i]);
            if !real {
                out.push_str(".0");
            }
        } else {
            // Copy one whole UTF-8 character.
            let len = expr[i..].chars().next().map_or(1, char::len_utf8);
            out.push_str(&expr[i..i + len]);
            i += len;
        }
    }
    out
}

/// The longest expression accepted (characters).
pub const MAX_EXPRESSION_CHARS: usize = 1000;

/// An initial field as a function of x.
pub enum InitialField {
    /// Constant.
    Number(f64),
    /// Compiled expression.
    Expr(evalexpr::Node<evalexpr::DefaultNumericTypes>),
    /// Table.
    Table(Vec<[f64; 2]>),
}

impl InitialField {
    pub(crate) fn compile(name: &str, f: &FieldToml) -> Result<Self, SceneError> {
        Ok(match f {
            FieldToml::Number(v) => InitialField::Number(finite(name, *v)?),
            FieldToml::Expr(s) => {
                // evalexpr parses and evaluates recursively: a cap on the
                // length keeps the nesting far from the stack's limit.
                if s.chars().count() > MAX_EXPRESSION_CHARS {
                    return Err(field(name, format!("an expression of {} characters is not allowed: at most {MAX_EXPRESSION_CHARS} (use a table [[x, u], …] for long data)", s.chars().count())));
                }
                let s = &real_literals(s);
                let tree = evalexpr::build_operator_tree(s).map_err(|e| field(name, format!("expression {s:?}: {e} (allowed: a number in x, e.g. \"0.5 * (1 - x)\" or \"math::sin(pi * x)\")")))?;
                // Evaluate once so that errors surface here with the field's name.
                let mut ctx = evalexpr::HashMapContext::<evalexpr::DefaultNumericTypes>::new();
                use evalexpr::ContextWithMutableVariables;
                for (k, v) in [("x", 0.0), ("pi", std::f64::consts::PI)] {
                    ctx.set_value(k.into(), evalexpr::Value::Float(v)).map_err(|e| field(name, e))?;
                }
                tree.eval_number_with_context(&ctx).map_err(|e| field(name, format!("expression {s:?} (a number in x, e.g. \"0.5 * (1 - x)\" or \"math::sin(pi * x)\"): {e}")))?;
                InitialField::Expr(tree)
            }
            FieldToml::Table(t) => {
                if t.is_empty() || t.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) || t.windows(2).any(|w| w[1][0] <= w[0][0]) {
                    return Err(field(name, "a table needs at least one [x, value] pair, finite values and strictly increasing x"));
                }
                InitialField::Table(t.clone())
            }
        })
    }

    /// Refuses a table whose x range does not cover `[a, b]` (to within
    /// [`NODE_TOLERANCE`] of the span's end): outside its range a table would
    /// otherwise be extended by its end values without a word.
    pub(crate) fn check_covers(&self, name: &str, a: f64, b: f64) -> Result<(), SceneError> {
        let InitialField::Table(t) = self else { return Ok(()) };
        let tol = NODE_TOLERANCE * b.abs().max(a.abs());
        let (first, last) = (t[0][0], t[t.len() - 1][0]);
        if first > a + tol || last < b - tol {
            return Err(field(
                name,
                format!("a table on [{}, {}] is not allowed: its x must cover the whole [{}, {}] (first x <= {}, last x >= {})", num(first), num(last), num(a), num(b), num(a), num(b)),
            ));
        }
        Ok(())
    }

    /// The value at x (NaN if an expression fails to evaluate, caught by the problem's finiteness check).
    pub fn eval(&self, x: f64) -> f64 {
        match self {
            InitialField::Number(v) => *v,
            InitialField::Expr(tree) => {
                let mut ctx = evalexpr::HashMapContext::<evalexpr::DefaultNumericTypes>::new();
                use evalexpr::ContextWithMutableVariables;
                if ctx.set_value("x".into(), evalexpr::Value::Float(x)).is_err() || ctx.set_value("pi".into(), evalexpr::Value::Float(std::f64::consts::PI)).is_err() {
                    return f64::NAN;
                }
                tree.eval_number_with_context(&ctx).unwrap_or(f64::NAN)
            }
            InitialField::Table(t) => {
                if x <= t[0][0] {
                    return t[0][1];
                }
                for w in t.windows(2) {
                    if x <= w[1][0] {
                        let s = (x - w[0][0]) / (w[1][0] - w[0][0]);
                        return w[0][1] + s * (w[1][1] - w[0][1]);
                    }
                }
                t[t.len() - 1][1]
            }
        }
    }
}
