//! Infix parser: `+ - * /`, `^` or `**` for powers (right-associative, binding tighter than
//! unary minus: `-x^2 = -(x^2)`), parentheses, function calls `abs(..)`, `sqrt(..)`, ...,
//! the constant `pi`. Number literals are exact: `0.1` is the rational 1/10, `1e-3` is
//! 1/1000. A mistake is a [`ParseError`] with the byte span to underline.

use std::ops::Range;

use num_bigint::BigInt;
use num_rational::BigRational;
use num_traits::{ToPrimitive, Zero};

use crate::error::{ExprError, Result};
use crate::graph::{Const, Func, Graph, Id, Node, MAX_EXACT_BITS};
use crate::parse_error::{Expected, ParseError, ParseErrorKind, MAX_DECIMAL_EXPONENT};

/// Deepest nesting of parentheses, function calls, unary signs and powers accepted.
pub const MAX_DEPTH: usize = 200;

/// What may start an operand.
const OPERAND: [Expected; 3] = [Expected::Number, Expected::Name, Expected::OpenParen];

/// Parses infix `text` into `g`.
///
/// Grammar: `expr = term (("+"|"-") term)*`, `term = unary (("*"|"/") unary)*`,
/// `unary = ("-"|"+") unary | power`, `power = atom (("^"|"**") unary)?`,
/// `atom = number | name | name "(" expr ")" | "(" expr ")"`. Exponents must be integer
/// constants (or exactly 1/2, read as `sqrt`). Function names: `abs sign sqrt sin cos tan
/// exp ln log(=ln) atan arctan asin arcsin acos arccos sinh cosh tanh` (and `Abs`, `signum`,
/// `Log`, `Pi` as Maple and SymPy print them). Whitespace, newlines included, separates
/// tokens.
///
/// Constants are exact while their numerator and denominator have at most
/// [`MAX_EXACT_BITS`] bits (`2^4000` is exact); a longer one becomes its nearest `f64`
/// (`(1234567/1234568)^300` is 0.99975702944315); one whose `f64` would be infinite or zero
/// is refused, naming the sub-expression (`1.5^100000`, `(7e-4000)^100`). Exponents are at
/// most 2^20 in magnitude, decimal exponents of literals at most 4000. Parsing takes time
/// about linear in the text and never panics, whatever the text.
///
/// # Errors
/// [`ExprError::Parse`] with a [`ParseError`]: the byte span of the mistake in `text`, its
/// [`ParseErrorKind`] (an unexpected char or end, an unclosed or unmatched parenthesis, an
/// unknown function, a malformed number, a non-integer exponent, nesting deeper than
/// [`MAX_DEPTH`], a constant out of range) and what was [`Expected`] there.
///
/// ```
/// use geomkit_expr::{parse, ExprError, Format, Graph, ParseErrorKind};
/// let mut g = Graph::new();
/// let e = parse(&mut g, "2*(u - 1)^2 - -v").unwrap();
/// assert_eq!(g.print(e, Format::Sympy).unwrap(), "2*(u - 1)**2 + v");
/// let err = parse(&mut g, "u + * v").unwrap_err();
/// assert_eq!(err.to_string(), "parse error at byte 4: expected a number, a name or `(`, found `*`");
/// // What an editor underlines:
/// let ExprError::Parse(e) = err else { panic!() };
/// assert_eq!((e.span.clone(), &e.kind), (4..5, &ParseErrorKind::UnexpectedChar('*')));
/// ```
pub fn parse(g: &mut Graph, text: &str) -> Result<Id> {
    parse_in(g, text, None)
}

/// Parses infix `text` into `g` like [`parse`], refusing any variable name other than
/// `variables` (`pi` stays the constant): for formulas in known variables, so that a
/// misspelt name is reported where it stands, even where simplification would cancel it
/// (`u + w - w`).
///
/// # Errors
/// Those of [`parse`], and [`ParseErrorKind::UnknownVariable`] with the span of the first
/// unknown name.
///
/// ```
/// use geomkit_expr::{parse_with_variables, ExprError, Graph, ParseErrorKind};
/// let text = "sin(u) * wv";
/// let err = parse_with_variables(&mut Graph::new(), text, &["u", "v"]).unwrap_err();
/// assert_eq!(
///     err.to_string(),
///     "unknown variable `wv` (the variables are u, v) at byte 9"
/// );
/// let ExprError::Parse(e) = err else { panic!() };
/// assert_eq!(&text[e.span.clone()], "wv");
/// assert!(matches!(e.kind, ParseErrorKind::UnknownVariable { .. }));
/// ```
pub fn parse_with_variables(g: &mut Graph, text: &str, variables: &[&str]) -> Result<Id> {
    parse_in(g, text, Some(variables))
}

fn parse_in(g: &mut Graph, text: &str, variables: Option<&[&str]>) -> Result<Id> {
    let mut p = Parser {
        g,
        s: text.as_bytes(),
        text,
        pos: 0,
        depth: 0,
        number_end: None,
        variables,
    };
    let e = p.expr()?;
    p.skip_ws();
    if p.pos < p.s.len() {
        let expected = vec![Expected::Operator, Expected::End];
        if p.s[p.pos] == b')' {
            return Err(p.fail(p.here(), ParseErrorKind::UnmatchedCloseParen, expected));
        }
        return Err(p.unexpected(expected));
    }
    Ok(e)
}

struct Parser<'a, 'g> {
    g: &'g mut Graph,
    s: &'a [u8],
    text: &'a str,
    pos: usize,
    depth: usize,
    /// Where the last number literal ended (a `.` there makes it malformed: `2..3`).
    number_end: Option<usize>,
    variables: Option<&'a [&'a str]>,
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

    /// The span of the char at the position (empty at the end).
    fn here(&self) -> Range<usize> {
        let len = self.text[self.pos..]
            .chars()
            .next()
            .map_or(0, char::len_utf8);
        self.pos..self.pos + len
    }

    fn fail(&self, span: Range<usize>, kind: ParseErrorKind, expected: Vec<Expected>) -> ExprError {
        ParseError::new(self.text, span, kind, expected).into()
    }

    /// The char at the position (or the end) where one of `expected` should be.
    fn unexpected(&self, expected: Vec<Expected>) -> ExprError {
        let kind = match self.text[self.pos..].chars().next() {
            None => ParseErrorKind::UnexpectedEnd,
            Some('.') if self.number_end == Some(self.pos) => ParseErrorKind::BadNumber,
            Some(c) => ParseErrorKind::UnexpectedChar(c),
        };
        self.fail(self.here(), kind, expected)
    }

    /// A `)` missing where the position is, for the `(` at `open`.
    fn unclosed(&self, open: usize, function: Option<&str>) -> ExprError {
        let kind = ParseErrorKind::UnclosedParen {
            open,
            function: function.map(str::to_string),
        };
        self.fail(self.here(), kind, vec![Expected::CloseParen])
    }

    fn enter(&mut self) -> Result<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            let kind = ParseErrorKind::TooDeep { max: MAX_DEPTH };
            return Err(self.fail(self.here(), kind, Vec::new()));
        }
        Ok(())
    }

    /// `id`, or [`ParseErrorKind::ConstantOutOfRange`] at `span` if the node just built holds
    /// a constant that left the range of `f64`. The parser's constants are exact; an `f64`
    /// constant appears only where an exact one grew beyond [`MAX_EXACT_BITS`], so an
    /// infinite, NaN or zero `f64` is a value out of range.
    fn in_range(&self, id: Id, span: Range<usize>) -> Result<Id> {
        for c in self.g.node_constants(id) {
            if let Const::Float(x) = c {
                if !x.is_finite() || *x == 0.0 {
                    return Err(self.out_of_range(span, *x != 0.0));
                }
            }
        }
        Ok(id)
    }

    /// [`ParseErrorKind::ConstantOutOfRange`] for the sub-expression at `span`.
    fn out_of_range(&self, span: Range<usize>, overflow: bool) -> ExprError {
        let whole = &self.text[span.clone()];
        let text = match whole.char_indices().nth(40) {
            Some((cut, _)) => format!("{}...", &whole[..cut]),
            None => whole.to_string(),
        };
        let kind = ParseErrorKind::ConstantOutOfRange { text, overflow };
        self.fail(span, kind, Vec::new())
    }

    /// Where the next token starts.
    fn start(&mut self) -> usize {
        self.skip_ws();
        self.pos
    }

    fn expr(&mut self) -> Result<Id> {
        self.enter()?;
        let start = self.start();
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
        if terms.len() == 1 {
            return Ok(terms[0]);
        }
        let e = self.g.sum(&terms);
        self.in_range(e, start..self.pos)
    }

    fn term(&mut self) -> Result<Id> {
        let start = self.start();
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
        if fs.len() == 1 {
            return Ok(fs[0].0);
        }
        let e = self.g.prod(&fs);
        self.in_range(e, start..self.pos)
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
        let start = self.start();
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
        let text = self.text;
        let end = at + text[at..self.pos].trim_end().len();
        let bad = |reason: &str| -> ExprError {
            let kind = ParseErrorKind::BadExponent {
                reason: reason.to_string(),
            };
            ParseError::new(text, at..end, kind, Vec::new()).into()
        };
        let r = match self.g.node(ex) {
            Node::Const(Const::Rat(r)) => r.clone(),
            Node::Const(Const::Float(_)) => return Err(bad("a floating-point exponent")),
            _ => return Err(bad("exponents must be integer constants (or 1/2 for sqrt)")),
        };
        if r == BigRational::new(1.into(), 2.into()) {
            let e = self.g.sqrt(base);
            return self.in_range(e, start..end);
        }
        if !r.is_integer() {
            return Err(bad("only integer exponents and 1/2 are supported"));
        }
        let n = r
            .to_integer()
            .to_i32()
            .filter(|n| n.unsigned_abs() <= 1 << 20);
        match n {
            Some(n) => {
                let e = self.g.powi(base, n);
                self.in_range(e, start..end)
            }
            None => Err(bad("the exponent is too large")),
        }
    }

    fn atom(&mut self) -> Result<Id> {
        match self.peek() {
            Some(b'(') => {
                let open = self.pos;
                self.pos += 1;
                let e = self.expr()?;
                if self.peek() != Some(b')') {
                    return Err(self.unclosed(open, None));
                }
                self.pos += 1;
                Ok(e)
            }
            Some(c) if c.is_ascii_digit() || c == b'.' => self.number(),
            Some(c) if c.is_ascii_alphabetic() || c == b'_' => self.name(),
            _ => Err(self.unexpected(OPERAND.to_vec())),
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
        let name_span = start..self.pos;
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
                let kind = ParseErrorKind::CallWithoutParen {
                    function: name.to_string(),
                };
                return Err(self.fail(self.here(), kind, vec![Expected::OpenParen]));
            }
            let open = self.pos;
            self.pos += 1;
            let a = self.expr()?;
            if self.peek() != Some(b')') {
                return Err(self.unclosed(open, Some(name)));
            }
            self.pos += 1;
            let e = self.g.fun(f, a);
            return self.in_range(e, start..self.pos);
        }
        if self.peek() == Some(b'(') {
            let kind = ParseErrorKind::UnknownFunction {
                name: name.to_string(),
            };
            return Err(self.fail(name_span, kind, vec![Expected::Function]));
        }
        if name == "pi" || name == "Pi" {
            return Ok(self.g.pi());
        }
        if let Some(known) = self.variables.filter(|v| !v.contains(&name)) {
            let kind = ParseErrorKind::UnknownVariable {
                name: name.to_string(),
                known: known.iter().map(|v| v.to_string()).collect(),
            };
            return Err(self.fail(name_span, kind, Vec::new()));
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
            return Err(self.fail(
                self.here(),
                ParseErrorKind::BadNumber,
                vec![Expected::Digit],
            ));
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
                let expected = vec![Expected::ExponentDigits];
                return Err(self.fail(self.here(), ParseErrorKind::BadNumber, expected));
            }
            exp = match d.parse::<i64>() {
                Ok(e) if e <= MAX_DECIMAL_EXPONENT => e,
                _ => {
                    let span = save..self.pos;
                    self.pos = save;
                    let expected = vec![Expected::SmallExponent];
                    return Err(self.fail(span, ParseErrorKind::BadNumber, expected));
                }
            };
            if neg {
                exp = -exp;
            }
        }
        self.number_end = Some(self.pos);
        let span = start..self.pos;
        // The value is digits · 10^scale, without leading and trailing zeros in the digits.
        let all = format!("{int_part}{frac}");
        let digits = all.trim_start_matches('0').trim_end_matches('0');
        if digits.is_empty() {
            return Ok(self.g.int(0));
        }
        let trailing = all.trim_start_matches('0').len() - digits.len();
        let scale = exp - frac.len() as i64 + trailing as i64;
        // Bits of the numerator and of the denominator, over-estimated (log2(10) < 3.33).
        let bits = |decimal_digits: i64| (decimal_digits.max(0) as f64 * 3.33) as u64;
        let longest = bits(digits.len() as i64 + scale).max(bits(-scale));
        if longest > 2 * MAX_EXACT_BITS {
            // Far too long to keep exact: the f64 it reads as, if there is one.
            let x: f64 = format!("{digits}e{scale}").parse().unwrap_or(f64::NAN);
            if x == 0.0 || !x.is_finite() {
                return Err(self.out_of_range(span, x != 0.0));
            }
            return Ok(self.g.num(x));
        }
        let mantissa: BigInt = digits.parse().unwrap_or_else(|_| BigInt::zero());
        let ten = BigInt::from(10);
        let r = if scale >= 0 {
            BigRational::from_integer(mantissa * num_traits::Pow::pow(&ten, scale as u64))
        } else {
            BigRational::new(mantissa, num_traits::Pow::pow(&ten, (-scale) as u64))
        };
        let e = self.g.rat(r);
        self.in_range(e, span)
    }
}
