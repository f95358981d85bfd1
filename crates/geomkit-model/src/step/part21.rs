//! ISO 10303-21 ("Part 21") clear text: the exchange structure's tokens, its data section
//! as a map of entity instances, and the number format of the writer.
//!
//! The reader takes what section 6-11 of ISO 10303-21:2016 allows: comments `/* */`,
//! simple (`#1=NAME(...);`) and complex (`#1=(A(...)B(...));`) instances, strings with `''`
//! and the `\X\`, `\X2\` escapes kept verbatim, enumerations, typed parameters
//! (`LENGTH_MEASURE(1.E-07)`), `$` and `*`. It stops at the first error with its line.

use super::{StepError, StepResult};
use std::collections::BTreeMap;
use std::fmt::Write;

/// One parameter of an entity instance.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Param {
    /// `#12`
    Ref(u64),
    /// An integer.
    Int(i64),
    /// A real (or an integer where a real is expected: see [`Param::as_real`]).
    Real(f64),
    /// A string, its quotes removed and `''` read as `'`.
    Str(String),
    /// `.T.`, `.UNSPECIFIED.`: the name without the dots.
    Enum(String),
    /// `( ... )`
    List(Vec<Param>),
    /// `$` (unset).
    Null,
    /// `*` (derived).
    Derived,
    /// `LENGTH_MEASURE(1.0)`
    Typed(String, Box<Param>),
}

impl Param {
    /// The value as a real: a real, or an integer (exactly: |n| < 2^53).
    pub(crate) fn as_real(&self) -> Option<f64> {
        match self {
            Param::Real(x) => Some(*x),
            Param::Int(n) if n.unsigned_abs() < (1 << 53) => Some(*n as f64),
            Param::Typed(_, p) => p.as_real(),
            _ => None,
        }
    }
}

/// One entity instance: one record (`NAME(...)`), or several for a complex instance, in
/// the order of the file (which Part 21 requires to be alphabetical).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Instance {
    /// The records: (entity name in upper case, parameters).
    pub records: Vec<(String, Vec<Param>)>,
    /// The line of the instance in the file (1-based).
    pub line: usize,
}

impl Instance {
    /// The parameters of the record named `name`.
    pub(crate) fn record(&self, name: &str) -> Option<&[Param]> {
        self.records
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, p)| &p[..])
    }

    /// Whether one of its records is `name`.
    pub(crate) fn is(&self, name: &str) -> bool {
        self.records.iter().any(|(n, _)| n == name)
    }

    /// The name of a simple instance; the records joined by `+` for a complex one.
    pub(crate) fn type_name(&self) -> String {
        let names: Vec<&str> = self.records.iter().map(|(n, _)| n.as_str()).collect();
        names.join("+")
    }
}

/// The data section: instances by number, and the schema named in the header.
#[derive(Debug, Default)]
pub(crate) struct Exchange {
    /// `FILE_SCHEMA` names, upper case.
    pub schemas: Vec<String>,
    /// Instances by entity number, in increasing number order.
    pub instances: BTreeMap<u64, Instance>,
}

#[derive(Debug, Clone, PartialEq)]
enum Token {
    Ref(u64),
    Keyword(String),
    Int(i64),
    Real(f64),
    Str(String),
    Enum(String),
    Open,
    Close,
    Comma,
    Semicolon,
    Equals,
    Dollar,
    Star,
    End,
}

struct Lexer<'a> {
    text: &'a [u8],
    at: usize,
    line: usize,
}

impl<'a> Lexer<'a> {
    fn new(text: &'a str) -> Self {
        Lexer {
            text: text.as_bytes(),
            at: 0,
            line: 1,
        }
    }

    fn error(&self, message: impl Into<String>) -> StepError {
        StepError::Syntax {
            line: self.line,
            message: message.into(),
        }
    }

    fn skip_blanks(&mut self) -> StepResult<()> {
        loop {
            match self.text.get(self.at) {
                Some(b'\n') => {
                    self.line += 1;
                    self.at += 1;
                }
                Some(c) if c.is_ascii_whitespace() => self.at += 1,
                Some(b'/') if self.text.get(self.at + 1) == Some(&b'*') => {
                    let start = self.line;
                    self.at += 2;
                    loop {
                        match self.text.get(self.at) {
                            None => {
                                return Err(StepError::Syntax {
                                    line: start,
                                    message: "a comment /* is not closed by */".into(),
                                })
                            }
                            Some(b'*') if self.text.get(self.at + 1) == Some(&b'/') => {
                                self.at += 2;
                                break;
                            }
                            Some(b'\n') => {
                                self.line += 1;
                                self.at += 1;
                            }
                            Some(_) => self.at += 1,
                        }
                    }
                }
                _ => return Ok(()),
            }
        }
    }

    fn take_while(&mut self, f: impl Fn(u8) -> bool) -> &'a str {
        let start = self.at;
        while self.text.get(self.at).is_some_and(|&c| f(c)) {
            self.at += 1;
        }
        // Only ASCII bytes are taken.
        std::str::from_utf8(&self.text[start..self.at]).unwrap_or_default()
    }

    fn next(&mut self) -> StepResult<Token> {
        self.skip_blanks()?;
        let Some(&c) = self.text.get(self.at) else {
            return Ok(Token::End);
        };
        let single = match c {
            b'(' => Some(Token::Open),
            b')' => Some(Token::Close),
            b',' => Some(Token::Comma),
            b';' => Some(Token::Semicolon),
            b'=' => Some(Token::Equals),
            b'$' => Some(Token::Dollar),
            b'*' => Some(Token::Star),
            _ => None,
        };
        if let Some(t) = single {
            self.at += 1;
            return Ok(t);
        }
        match c {
            b'#' => {
                self.at += 1;
                let digits = self.take_while(|c| c.is_ascii_digit());
                digits
                    .parse::<u64>()
                    .map(Token::Ref)
                    .map_err(|_| self.error("'#' is not followed by an entity number"))
            }
            b'\'' => {
                self.at += 1;
                let mut s = Vec::new();
                loop {
                    match self.text.get(self.at) {
                        None => return Err(self.error("a string is not closed by '")),
                        Some(b'\'') if self.text.get(self.at + 1) == Some(&b'\'') => {
                            s.push(b'\'');
                            self.at += 2;
                        }
                        Some(b'\'') => {
                            self.at += 1;
                            break;
                        }
                        Some(&c) => {
                            if c == b'\n' {
                                self.line += 1;
                            }
                            s.push(c);
                            self.at += 1;
                        }
                    }
                }
                Ok(Token::Str(String::from_utf8_lossy(&s).into_owned()))
            }
            b'.' => {
                self.at += 1;
                let name = self.take_while(|c| c.is_ascii_alphanumeric() || c == b'_');
                if name.is_empty() || self.text.get(self.at) != Some(&b'.') {
                    return Err(self.error("an enumeration .NAME. is not closed by '.'"));
                }
                self.at += 1;
                Ok(Token::Enum(name.to_ascii_uppercase()))
            }
            b'+' | b'-' | b'0'..=b'9' => {
                let text = self.take_while(|c| {
                    c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.' | b'E' | b'e')
                });
                let is_real = text.contains(['.', 'E', 'e']);
                if is_real {
                    text.parse::<f64>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .map(Token::Real)
                        .ok_or_else(|| self.error(format!("'{text}' is not a finite real number")))
                } else {
                    text.parse::<i64>()
                        .map(Token::Int)
                        .map_err(|_| self.error(format!("'{text}' is not an integer")))
                }
            }
            c if c.is_ascii_alphabetic() || c == b'!' => {
                let name = self.take_while(|c| {
                    c.is_ascii_alphanumeric() || c == b'_' || c == b'-' || c == b'!'
                });
                Ok(Token::Keyword(name.to_ascii_uppercase()))
            }
            c => Err(self.error(format!("unexpected character '{}'", c as char))),
        }
    }
}

struct Parser<'a> {
    lexer: Lexer<'a>,
    peeked: Option<Token>,
}

impl<'a> Parser<'a> {
    fn peek(&mut self) -> StepResult<&Token> {
        if self.peeked.is_none() {
            self.peeked = Some(self.lexer.next()?);
        }
        Ok(self.peeked.as_ref().expect("just set"))
    }

    fn next(&mut self) -> StepResult<Token> {
        match self.peeked.take() {
            Some(t) => Ok(t),
            None => self.lexer.next(),
        }
    }

    fn expect(&mut self, want: Token, what: &str) -> StepResult<()> {
        let t = self.next()?;
        if t == want {
            Ok(())
        } else {
            Err(self.unexpected(&t, what))
        }
    }

    fn unexpected(&self, t: &Token, what: &str) -> StepError {
        let found = match t {
            Token::End => "the end of the file".to_string(),
            Token::Keyword(k) => format!("'{k}'"),
            Token::Ref(r) => format!("'#{r}'"),
            Token::Str(_) => "a string".to_string(),
            Token::Int(n) => format!("'{n}'"),
            Token::Real(x) => format!("'{x}'"),
            Token::Enum(e) => format!("'.{e}.'"),
            Token::Open => "'('".into(),
            Token::Close => "')'".into(),
            Token::Comma => "','".into(),
            Token::Semicolon => "';'".into(),
            Token::Equals => "'='".into(),
            Token::Dollar => "'$'".into(),
            Token::Star => "'*'".into(),
        };
        self.lexer.error(format!("expected {what}, found {found}"))
    }

    /// `( p, p, ... )` after the opening parenthesis was read.
    fn list_rest(&mut self, depth: usize) -> StepResult<Vec<Param>> {
        if depth > 64 {
            return Err(self.lexer.error("lists nested more than 64 deep"));
        }
        let mut out = Vec::new();
        if *self.peek()? == Token::Close {
            self.next()?;
            return Ok(out);
        }
        loop {
            out.push(self.param(depth)?);
            match self.next()? {
                Token::Comma => continue,
                Token::Close => return Ok(out),
                t => return Err(self.unexpected(&t, "',' or ')'")),
            }
        }
    }

    fn param(&mut self, depth: usize) -> StepResult<Param> {
        Ok(match self.next()? {
            Token::Ref(r) => Param::Ref(r),
            Token::Int(n) => Param::Int(n),
            Token::Real(x) => Param::Real(x),
            Token::Str(s) => Param::Str(s),
            Token::Enum(e) => Param::Enum(e),
            Token::Dollar => Param::Null,
            Token::Star => Param::Derived,
            Token::Open => Param::List(self.list_rest(depth + 1)?),
            Token::Keyword(k) => {
                self.expect(Token::Open, "'(' after a type name")?;
                let mut inner = self.list_rest(depth + 1)?;
                if inner.len() != 1 {
                    return Err(self.lexer.error(format!(
                        "the typed value {k}(...) holds {} values, not one",
                        inner.len()
                    )));
                }
                Param::Typed(k, Box::new(inner.remove(0)))
            }
            t => return Err(self.unexpected(&t, "a parameter")),
        })
    }

    /// `NAME(params)`
    fn record(&mut self) -> StepResult<(String, Vec<Param>)> {
        match self.next()? {
            Token::Keyword(k) => {
                self.expect(Token::Open, "'(' after an entity name")?;
                Ok((k, self.list_rest(0)?))
            }
            t => Err(self.unexpected(&t, "an entity name")),
        }
    }
}

/// Reads a whole exchange structure.
pub(crate) fn parse(text: &str) -> StepResult<Exchange> {
    let mut p = Parser {
        lexer: Lexer::new(text),
        peeked: None,
    };
    match p.next()? {
        Token::Keyword(k) if k == "ISO-10303-21" => {}
        t => return Err(p.unexpected(&t, "'ISO-10303-21;' (this is not a STEP file)")),
    }
    p.expect(Token::Semicolon, "';'")?;
    match p.next()? {
        Token::Keyword(k) if k == "HEADER" => {}
        t => return Err(p.unexpected(&t, "'HEADER;'")),
    }
    p.expect(Token::Semicolon, "';'")?;
    let mut exchange = Exchange::default();
    // Header records up to ENDSEC.
    loop {
        match p.peek()? {
            Token::Keyword(k) if k == "ENDSEC" => {
                p.next()?;
                p.expect(Token::Semicolon, "';'")?;
                break;
            }
            _ => {
                let (name, params) = p.record()?;
                p.expect(Token::Semicolon, "';' after a header record")?;
                if name == "FILE_SCHEMA" {
                    if let Some(Param::List(l)) = params.first() {
                        exchange.schemas = l
                            .iter()
                            .filter_map(|s| match s {
                                Param::Str(s) => Some(s.to_ascii_uppercase()),
                                _ => None,
                            })
                            .collect();
                    }
                }
            }
        }
    }
    // Data sections (Part 21 allows several) up to END-ISO-10303-21.
    loop {
        match p.next()? {
            Token::Keyword(k) if k == "END-ISO-10303-21" => {
                p.expect(Token::Semicolon, "';'")?;
                return Ok(exchange);
            }
            Token::Keyword(k) if k == "DATA" => {
                // DATA or DATA('name', (schemas)) in the 2002 edition.
                if *p.peek()? == Token::Open {
                    p.next()?;
                    p.list_rest(0)?;
                }
                p.expect(Token::Semicolon, "';' after DATA")?;
                data_section(&mut p, &mut exchange)?;
            }
            Token::End => {
                return Err(p
                    .lexer
                    .error("the file ends before 'END-ISO-10303-21;' (truncated?)"))
            }
            t => return Err(p.unexpected(&t, "'DATA;' or 'END-ISO-10303-21;'")),
        }
    }
}

fn data_section(p: &mut Parser<'_>, exchange: &mut Exchange) -> StepResult<()> {
    loop {
        let token = p.next()?;
        // The line of the token just read (it holds no line break).
        let line = p.lexer.line;
        match token {
            Token::Keyword(k) if k == "ENDSEC" => {
                p.expect(Token::Semicolon, "';'")?;
                return Ok(());
            }
            Token::Ref(id) => {
                p.expect(Token::Equals, &format!("'=' after #{id}"))?;
                let records = if *p.peek()? == Token::Open {
                    p.next()?;
                    let mut records = Vec::new();
                    while *p.peek()? != Token::Close {
                        records.push(p.record().map_err(|e| e.at(id))?);
                    }
                    p.next()?;
                    if records.is_empty() {
                        return Err(StepError::Entity {
                            id,
                            message: "a complex instance without records".into(),
                        });
                    }
                    records
                } else {
                    vec![p.record().map_err(|e| e.at(id))?]
                };
                p.expect(Token::Semicolon, &format!("';' after #{id}"))
                    .map_err(|e| e.at(id))?;
                let instance = Instance { records, line };
                if exchange.instances.insert(id, instance).is_some() {
                    return Err(StepError::Entity {
                        id,
                        message: "is defined twice".into(),
                    });
                }
            }
            Token::End => {
                return Err(p
                    .lexer
                    .error("the file ends inside the DATA section (truncated?)"))
            }
            t => return Err(p.unexpected(&t, "an entity instance '#N=' or 'ENDSEC;'")),
        }
    }
}

/// A real in Part 21 form, reading back to the same bits: Rust's shortest round-trip
/// digits with the decimal point STEP requires (`1.`, `0.1`, `1.5E-07`, `-2.E+300`).
pub(crate) fn real(x: f64) -> String {
    let s = format!("{x:?}");
    match s.split_once('e') {
        Some((mantissa, exp)) => {
            let mantissa = if mantissa.contains('.') {
                mantissa.to_string()
            } else {
                format!("{mantissa}.")
            };
            format!("{mantissa}E{exp}")
        }
        None => s,
    }
}

/// A string in Part 21 form: quotes doubled, characters outside printable ASCII replaced
/// by `?` (the writer writes names only).
pub(crate) fn string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('\'');
    for c in s.chars() {
        match c {
            '\'' => out.push_str("''"),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            _ => out.push('?'),
        }
    }
    out.push('\'');
    out
}

/// The data section being written: instances numbered from 1 in the order they are added.
#[derive(Debug, Default)]
pub(crate) struct Writer {
    lines: String,
    next: u64,
}

impl Writer {
    /// Adds `#N=text;` and returns N.
    pub(crate) fn add(&mut self, text: impl AsRef<str>) -> u64 {
        self.next += 1;
        let _ = writeln!(self.lines, "#{}={};", self.next, text.as_ref());
        self.next
    }

    /// The instances, one per line.
    pub(crate) fn finish(self) -> String {
        self.lines
    }
}

/// `(#1,#2,#3)`
pub(crate) fn refs(ids: &[u64]) -> String {
    let items: Vec<String> = ids.iter().map(|i| format!("#{i}")).collect();
    format!("({})", items.join(","))
}

/// `(1.,2.5,3.)`
pub(crate) fn reals(xs: &[f64]) -> String {
    let items: Vec<String> = xs.iter().map(|&x| real(x)).collect();
    format!("({})", items.join(","))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reals_read_back_to_the_same_bits() {
        for x in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1e-7,
            -2.5e300,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            1.0 / 3.0,
            123456789.125,
        ] {
            let s = real(x);
            assert!(s.contains('.'), "{s}");
            let mut lexer = Lexer::new(&s);
            match lexer.next().unwrap() {
                Token::Real(y) => assert_eq!(y.to_bits(), x.to_bits(), "{s}"),
                t => panic!("{s} read as {t:?}"),
            }
        }
        assert_eq!(real(1e-7), "1.E-7");
        assert_eq!(real(1.5e300), "1.5E300");
        assert_eq!(real(2.0), "2.0");
    }

    #[test]
    fn parses_simple_complex_and_typed_instances() {
        let text = "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION(('a'),'2;1');\n\
            FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n\
            /* a comment */ #1=CARTESIAN_POINT('it''s',(1.,-2.5E-1,3));\n\
            #2=(LENGTH_UNIT()NAMED_UNIT(*)SI_UNIT(.MILLI.,.METRE.));\n\
            #3=UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE(1.E-07),#2,'d',$);\n\
            ENDSEC;\nEND-ISO-10303-21;\n";
        let x = parse(text).unwrap();
        assert_eq!(
            x.schemas,
            vec!["AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }"]
        );
        let p = &x.instances[&1];
        assert_eq!(p.line, 7);
        assert_eq!(
            p.records[0].1,
            vec![
                Param::Str("it's".into()),
                Param::List(vec![Param::Real(1.0), Param::Real(-0.25), Param::Int(3)])
            ]
        );
        assert_eq!(
            x.instances[&2].type_name(),
            "LENGTH_UNIT+NAMED_UNIT+SI_UNIT"
        );
        assert_eq!(
            x.instances[&3].records[0].1[0],
            Param::Typed("LENGTH_MEASURE".into(), Box::new(Param::Real(1e-7)))
        );
    }

    #[test]
    fn syntax_errors_name_the_line_or_the_entity() {
        let head = "ISO-10303-21;\nHEADER;\nENDSEC;\nDATA;\n";
        let cases = [
            ("#1=CARTESIAN_POINT('',(1.,2.)", "#1"),
            ("#1=CARTESIAN_POINT('',(1.,2.));\n", "truncated"),
            ("#1=CARTESIAN_POINT('',(1.,2.));\n#1=CARTESIAN_POINT('',(1.));\nENDSEC;\nEND-ISO-10303-21;", "#1: is defined twice"),
            ("#1=CARTESIAN_POINT('',(1.,2.E999));\n", "line 5"),
            ("#1=CARTESIAN_POINT('abc", "not closed"),
        ];
        for (body, want) in cases {
            let err = parse(&format!("{head}{body}")).unwrap_err().to_string();
            assert!(err.contains(want), "{body:?}: {err}");
        }
        let err = parse("solid cube\nfacet normal 0 0 1\n")
            .unwrap_err()
            .to_string();
        assert!(err.contains("not a STEP file"), "{err}");
    }
}
