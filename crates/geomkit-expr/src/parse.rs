//! Infix parser: `+ - * /`, `^` or `**` for powers (right-associative, binding tighter than
//! unary minus: `-x^2 = -(x^2)`), parentheses, function calls `abs(..)`, `sqrt(..)`, ...,
//! the constant `pi`. Number literals are exact: `0.1` is the rational 1/10, `1e-3` is
//! 1/1000.

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};

use crate::error::{ExprError, Result};
use crate::graph::{Const, Func, Graph, Id, Node};

/// Deepest nesting of parentheses, function calls, unary signs and powers accepted.
pub const MAX_DEPTH: usize = 200;

/// Parses infix `text` into `g`.
///
/// Grammar: `expr = term (("+"|"-") term)*`, `term = unary (("*"|"/") unary)*`,
/// `unary = ("-"|"+") unary | power`, `power = atom (("^"|"**") unary)?`,
/// `atom = number | name | name "(" expr ")" | "(" expr ")"`. Exponents must be integer
/// constants (or exactly 1/2, read as `sqrt`). Function names: `abs sign sqrt sin cos tan
/// exp ln log(=ln) atan arctan asin arcsin acos arccos sinh cosh tanh` (and `Abs`, `signum`,
/// `Log`, `Pi` as Maple and SymPy print them).
///
/// # Errors
/// [`ExprError::Parse`] with the byte position and what was expected,
/// [`ExprError::Exponent`] for a non-integer exponent, [`ExprError::TooDeep`].
///
/// ```
/// use geomkit_expr::{parse, Format, Graph};
/// let mut g = Graph::new();
/// let e = parse(&mut g, "2*(u - 1)^2 - -v").unwrap();
/// assert_eq!(g.print(e, Format::Sympy), "2*(u - 1)**2 + v");
/// let err = parse(&mut g, "u + * v").unwrap_err();
/// assert_eq!(err.to_string(), "parse error at byte 4: expected a number, a name or `(`, found `*`");
/// ```
pub fn parse(g: &mut Graph, text: &str) -> Result<Id> {
    let mut p = Parser {
        g,
        s: text.as_bytes(),
        text,
        pos: 0,
        depth: 0,
    };
    let e = p.expr()?;
    p.skip_ws();
    if p.pos < p.s.len() {
        return Err(p.error("an operator or the end of the formula"));
    }
    Ok(e)
}

struct Parser<'a, 'g> {
    g: &'g mut Graph,
    s: &'a [u8],
    text: &'a str,
    pos: usize,
    depth: usize,
}

impl Parser<'_, '_> {
    fn skip_ws(&mut self) {
        while self.pos < self.s.len() && self.s[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    fn peek(&mut self) -> Option<u8> {
        self.skip_ws();
        self.s.get(self.pos).copied()
    }

    fn found(&self) -> String {
        match self.text[self.pos..].chars().next() {
            None => "end of input".to_string(),
            Some(c) => format!("`{c}`"),
        }
    }

    fn error(&self, expected: &str) -> ExprError {
        ExprError::Parse {
            position: self.pos,
            expected: expected.to_string(),
            found: self.found(),
        }
    }

    fn enter(&mut self) -> Result<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(ExprError::TooDeep {
                position: self.pos,
                max: MAX_DEPTH,
            });
        }
        Ok(())
    }

    fn expr(&mut self) -> Result<Id> {
        self.enter()?;
        let mut terms = vec![self.term()?];
        loop {
            match self.peek() {
                Some(b'+') => {
                    self.pos += 1;
                    terms.push(self.term()?);
                }
                Some(b'-') => {
                    self.pos += 1;
                    let t = self.term()?;
                    terms.push(self.g.neg(t));
                }
                _ => break,
            }
        }
        self.depth -= 1;
        Ok(self.g.sum(&terms))
    }

    fn term(&mut self) -> Result<Id> {
        let mut fs = vec![(self.unary()?, 1)];
        loop {
            match self.peek() {
                Some(b'*') if self.s.get(self.pos + 1) != Some(&b'*') => {
                    self.pos += 1;
                    fs.push((self.unary()?, 1));
                }
                Some(b'/') => {
                    self.pos += 1;
                    fs.push((self.unary()?, -1));
                }
                _ => break,
            }
        }
        Ok(if fs.len() == 1 {
            fs[0].0
        } else {
            self.g.prod(&fs)
        })
    }

    fn unary(&mut self) -> Result<Id> {
        match self.peek() {
            Some(b'-') => {
                self.pos += 1;
                self.enter()?;
                let a = self.unary()?;
                self.depth -= 1;
                Ok(self.g.neg(a))
            }
            Some(b'+') => {
                self.pos += 1;
                self.enter()?;
                let a = self.unary()?;
                self.depth -= 1;
                Ok(a)
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Id> {
        let base = self.atom()?;
        let op = self.peek();
        let at = self.pos;
        let is_pow = match op {
            Some(b'^') => {
                self.pos += 1;
                true
            }
            Some(b'*') if self.s.get(self.pos + 1) == Some(&b'*') => {
                self.pos += 2;
                true
            }
            _ => false,
        };
        if !is_pow {
            return Ok(base);
        }
        self.enter()?;
        let ex = self.unary()?;
        self.depth -= 1;
        let bad = |reason: &str| ExprError::Exponent {
            position: at,
            reason: reason.to_string(),
        };
        let r = match self.g.node(ex) {
            Node::Const(Const::Rat(r)) => r.clone(),
            Node::Const(Const::Float(_)) => return Err(bad("a floating-point exponent")),
            _ => return Err(bad("exponents must be integer constants (or 1/2 for sqrt)")),
        };
        if r == BigRational::new(1.into(), 2.into()) {
            return Ok(self.g.sqrt(base));
        }
        if !r.is_integer() {
            return Err(bad("only integer exponents and 1/2 are supported"));
        }
        let n = r
            .to_integer()
            .to_i32()
            .filter(|n| n.unsigned_abs() <= 1 << 20);
        match n {
            Some(n) => Ok(self.g.powi(base, n)),
            None => Err(bad("the exponent is too large")),
        }
    }

    fn atom(&mut self) -> Result<Id> {
        match self.peek() {
            Some(b'(') => {
                self.pos += 1;
                let e = self.expr()?;
                if self.peek() != Some(b')') {
                    return Err(self.error("`)`"));
                }
                self.pos += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => self.name(),
            _ => Err(self.error("a number, a name or `(`")),
        }
    }

    fn name(&mut self) -> Result<Id> {
        let start = self.pos;
        while self.pos < self.s.len()
            && (self.s[self.pos].is_ascii_alphanumeric() || self.s[self.pos] == b'_')
        {
            self.pos += 1;
        }
        let name = &self.text[start..self.pos];
        let func = match name {
            "log" | "Log" => Some(Func::Ln),
            "Abs" => Some(Func::Abs),
            "signum" | "Sign" => Some(Func::Sign),
            "arctan" => Some(Func::Atan),
            "arcsin" => Some(Func::Asin),
            "arccos" => Some(Func::Acos),
            _ => Func::ALL.iter().copied().find(|f| f.name() == name),
        };
        if let Some(f) = func {
            if self.peek() != Some(b'(') {
                return Err(self.error(&format!("`(` after the function name `{name}`")));
            }
            self.pos += 1;
            let a = self.expr()?;
            if self.peek() != Some(b')') {
                return Err(self.error(&format!("`)` closing `{name}(`")));
            }
            self.pos += 1;
            return Ok(self.g.fun(f, a));
        }
        if self.peek() == Some(b'(') {
            self.pos = start;
            return Err(self.error(&format!(
                "a known function (abs, sign, sqrt, sin, cos, tan, exp, ln, atan, asin, acos, sinh, cosh, tanh), not `{name}`"
            )));
        }
        if name == "pi" || name == "Pi" {
            return Ok(self.g.pi());
        }
        Ok(self.g.var(name))
    }

    fn number(&mut self) -> Result<Id> {
        let start = self.pos;
        let digits = |p: &mut Self| {
            let s = p.pos;
            while p.pos < p.s.len() && p.s[p.pos].is_ascii_digit() {
                p.pos += 1;
            }
            &p.text[s..p.pos]
        };
        let int_part = digits(self).to_string();
        let mut frac = String::new();
        if self.s.get(self.pos) == Some(&b'.') {
            self.pos += 1;
            frac = digits(self).to_string();
        }
        if int_part.is_empty() && frac.is_empty() {
            self.pos = start;
            return Err(self.error("a digit"));
        }
        let mut exp: i64 = 0;
        if matches!(self.s.get(self.pos), Some(b'e' | b'E')) {
            let save = self.pos;
            self.pos += 1;
            let neg = match self.s.get(self.pos) {
                Some(b'-') => {
                    self.pos += 1;
                    true
                }
                Some(b'+') => {
                    self.pos += 1;
                    false
                }
                _ => false,
            };
            let d = digits(self);
            if d.is_empty() {
                self.pos = save + 1;
                return Err(self.error("digits of the exponent"));
            }
            exp = match d.parse::<i64>() {
                Ok(e) if e <= 4000 => e,
                _ => {
                    self.pos = save;
                    return Err(self.error("an exponent of at most 4000"));
                }
            };
            if neg {
                exp = -exp;
            }
        }
        let mantissa: BigInt = format!("{int_part}{frac}")
            .parse()
            .unwrap_or_else(|_| BigInt::zero());
        let scale = exp - frac.len() as i64;
        let ten = BigInt::from(10);
        let r = if scale >= 0 {
            BigRational::from_integer(mantissa * num_traits::Pow::pow(&ten, scale as u64))
        } else {
            BigRational::new(mantissa, num_traits::Pow::pow(&ten, (-scale) as u64))
        };
        Ok(self.g.rat(r))
    }
}
