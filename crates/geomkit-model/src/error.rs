//! Errors of reading and checking model files: each names the file, the JSON path of the
//! value at fault (`net[2][1][0]`) and, where the JSON reader knows it, the line and column.

use std::fmt;
use std::path::{Path, PathBuf};

/// A model file that could not be read, parsed or turned into geometry.
///
/// Its text is one line: `FILE: PATH: what is wrong (line L, column C)`, e.g.
/// `fit.json: knots[3] is the string "a"; numbers must be finite JSON numbers (line 4,
/// column 21)`. Front ends that underline the place read [`Error::path`],
/// [`Error::position`] and [`Error::kind`].
#[derive(Debug)]
pub struct Error(Box<Inner>);

#[derive(Debug)]
struct Inner {
    file: Option<PathBuf>,
    kind: ErrorKind,
}

/// What went wrong.
#[derive(Debug)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The file could not be read or written.
    Io(std::io::Error),
    /// Not JSON: the reader stopped at `line`, `column` (1-based).
    Syntax {
        /// Line of the error, 1-based.
        line: usize,
        /// Column of the error, 1-based.
        column: usize,
        /// The reader's message.
        message: String,
    },
    /// JSON, but not the schema: a wrong type, a missing or unknown field, a number that is
    /// no finite f64, a ragged array, a newer format version.
    Schema {
        /// JSON path of the value (`points[1][0]`); empty for the whole document.
        path: String,
        /// Line of the error, 1-based (0 when unknown).
        line: usize,
        /// Column of the error, 1-based (0 when unknown).
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// The schema holds but the geometry does not (a knot vector that decreases, a weight
    /// <= 0, a formula that does not parse, ...).
    Model {
        /// JSON path of the value at fault; empty for the whole model.
        path: String,
        /// What is wrong.
        message: String,
        /// The library's error, when the check is the library's (for a formula: the
        /// parser's error with its byte position).
        source: Option<geomkit::Error>,
    },
}

impl Error {
    /// An error of the model at `path` (a JSON path such as `patches[0][1]`).
    pub(crate) fn model(path: impl Into<String>, message: impl Into<String>) -> Error {
        Error::from_kind(ErrorKind::Model {
            path: path.into(),
            message: message.into(),
            source: None,
        })
    }

    /// The library's verdict on the value at `path`.
    pub(crate) fn geometry(path: impl Into<String>, source: geomkit::Error) -> Error {
        Error::from_kind(ErrorKind::Model {
            path: path.into(),
            message: source.to_string(),
            source: Some(source),
        })
    }

    pub(crate) fn from_kind(kind: ErrorKind) -> Error {
        Error(Box::new(Inner { file: None, kind }))
    }

    /// The error of reading `file`.
    pub(crate) fn io(file: &Path, err: std::io::Error) -> Error {
        Error::from_kind(ErrorKind::Io(err)).in_file(file)
    }

    /// The same error, naming `file`.
    pub fn in_file(mut self, file: &Path) -> Error {
        self.0.file = Some(file.to_path_buf());
        self
    }

    /// A syntax error with the text around its position ("near '[0, 1/0, 1]'"), so that
    /// the value at fault (`1/0`, `NaN`, `1e999`) is named, not only its line and column.
    pub(crate) fn with_snippet(mut self, text: &str) -> Error {
        if let ErrorKind::Syntax {
            line,
            column,
            message,
        } = &mut self.0.kind
        {
            if let Some(l) = text.lines().nth(line.saturating_sub(1)) {
                let chars: Vec<char> = l.chars().collect();
                let at = column.saturating_sub(1).min(chars.len());
                let from = at.saturating_sub(12);
                let to = (at + 12).min(chars.len());
                let near: String = chars[from..to].iter().collect();
                let near = near.trim();
                if !near.is_empty() {
                    message.push_str(&format!(" (near '{near}')"));
                }
            }
        }
        self
    }

    /// The same error one level down: `field` is prepended to its JSON path.
    pub(crate) fn under(mut self, field: &str) -> Error {
        if let ErrorKind::Model { path, .. } | ErrorKind::Schema { path, .. } = &mut self.0.kind {
            *path = join_path(field, path);
        }
        self
    }

    /// What went wrong.
    pub fn kind(&self) -> &ErrorKind {
        &self.0.kind
    }

    /// The file, when the error came from one.
    pub fn file(&self) -> Option<&Path> {
        self.0.file.as_deref()
    }

    /// The JSON path of the value at fault (`net[2][1]`), when known and not the whole
    /// document.
    pub fn path(&self) -> Option<&str> {
        match &self.0.kind {
            ErrorKind::Schema { path, .. } | ErrorKind::Model { path, .. } if !path.is_empty() => {
                Some(path)
            }
            _ => None,
        }
    }

    /// (line, column), 1-based, when the JSON reader knows them.
    pub fn position(&self) -> Option<(usize, usize)> {
        match self.0.kind {
            ErrorKind::Syntax { line, column, .. } | ErrorKind::Schema { line, column, .. }
                if line > 0 =>
            {
                Some((line, column))
            }
            _ => None,
        }
    }

    /// Turns a serde_json error (through serde_path_to_error) into a schema or syntax error.
    pub(crate) fn from_json(err: serde_path_to_error::Error<serde_json::Error>) -> Error {
        let path = err.path().to_string();
        Error::from_json_at(path, err.into_inner())
    }

    /// Turns a serde_json error at JSON path `path` ("." for the document) into a schema or
    /// syntax error.
    pub(crate) fn from_json_at(path: String, inner: serde_json::Error) -> Error {
        let (line, column) = (inner.line(), inner.column());
        let mut message = inner.to_string();
        let suffix = format!(" at line {line} column {column}");
        if let Some(stripped) = message.strip_suffix(&suffix) {
            message = stripped.to_string();
        }
        // serde quotes field names in backticks; JSON users read double quotes.
        if ["unknown field", "missing field", "duplicate field"]
            .iter()
            .any(|w| message.starts_with(w))
        {
            message = message.replace('`', "\"");
        }
        if message.starts_with("number out of range") {
            message.push_str(" (every number must be a finite f64)");
        }
        let kind = if inner.is_syntax() || inner.is_eof() {
            ErrorKind::Syntax {
                line,
                column,
                message,
            }
        } else {
            let path = if path == "." { String::new() } else { path };
            // A file whose "type" is not its first field is read from a buffer, whose
            // reader names the place inside the message ("points[1][1]: is the string
            // ..."): the place goes to the path, below the path of the buffer itself.
            let (path, message) = match message.split_once(": ") {
                Some((place, rest)) if is_json_path(place) => {
                    (join_path(&path, place), rest.to_string())
                }
                _ => (path, message),
            };
            ErrorKind::Schema {
                path,
                line,
                column,
                message,
            }
        };
        Error::from_kind(kind)
    }
}

/// Whether `s` is a JSON path of a model file (`points[1][1]`, `factors[0].nodes`): a
/// field name first, then names, dots and indices only.
fn is_json_path(s: &str) -> bool {
    s.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '[' | ']'))
}

/// `a` then `b` as one JSON path: `patches[0]` + `bezier[1]` = `patches[0].bezier[1]`.
pub(crate) fn join_path(a: &str, b: &str) -> String {
    match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_string(),
        (_, true) => a.to_string(),
        _ if b.starts_with('[') => format!("{a}{b}"),
        _ => format!("{a}.{b}"),
    }
}

/// `path` and `message` as one phrase: `points[1] has 3 coordinates`, `"knots" must
/// increase` (a lone field name is quoted as in the file).
fn place(f: &mut fmt::Formatter<'_>, path: &str, message: &str) -> fmt::Result {
    let quoted;
    let path = if !path.is_empty() && path.chars().all(|c| c.is_alphanumeric() || c == '_') {
        quoted = format!("\"{path}\"");
        &quoted
    } else {
        path
    };
    if path.is_empty() {
        f.write_str(message)
    } else if ["is ", "has ", "must "]
        .iter()
        .any(|w| message.starts_with(w))
    {
        write!(f, "{path} {message}")
    } else {
        write!(f, "{path}: {message}")
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.0.file, &self.0.kind) {
            (Some(file), ErrorKind::Io(_)) => write!(f, "cannot read {}: ", file.display())?,
            (Some(file), _) => write!(f, "{}: ", file.display())?,
            (None, ErrorKind::Io(_)) => f.write_str("I/O error: ")?,
            _ => {}
        }
        match &self.0.kind {
            ErrorKind::Io(e) => write!(f, "{e}"),
            ErrorKind::Syntax {
                line,
                column,
                message,
            } => write!(f, "invalid JSON: {message} at line {line} column {column}"),
            ErrorKind::Schema {
                path,
                line,
                column,
                message,
            } => {
                place(f, path, message)?;
                if *line > 0 {
                    write!(f, " (line {line}, column {column})")?;
                }
                Ok(())
            }
            ErrorKind::Model { path, message, .. } => place(f, path, message),
        }
    }
}

/// The text above is complete (the library's message included), so no `source()`: a chain
/// printer would repeat it. The library's error is in [`ErrorKind::Model`].
impl std::error::Error for Error {}

/// A result of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
