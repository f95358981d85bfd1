//! The layout of written files: readable and diff-friendly, streamed (no document tree in
//! memory, so a 10⁷-point curve writes in constant extra memory).
//!
//! Objects put one field per line; an array of numbers or strings stays on one line; an
//! array of arrays puts one element per line, and an array inside an array is written on one
//! line whole — so a list of points is one point per line and a net is one row per line:
//!
//! ```text
//! {
//!   "type": "bezier_surface",
//!   "net": [
//!     [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
//!     [[1.0, 0.0, 0.0], [1.0, 1.0, 1.0]]
//!   ]
//! }
//! ```

use serde_json::ser::Formatter;
use std::io::{self, Write};

/// The error of a result that is not a finite number.
pub(crate) const NON_FINITE: &str =
    "a result is not a finite number (NaN or infinity: a computation overflowed); model files \
     hold finite numbers only";

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    /// Not yet known (no element written).
    Open,
    /// Elements on one line.
    Inline,
    /// One element per line.
    Lines,
}

struct Frame {
    mode: Mode,
    /// An object (else an array).
    object: bool,
}

/// The [`Formatter`] of the layout above.
pub(crate) struct Layout {
    stack: Vec<Frame>,
    /// An array element is about to start: its separator is written once its kind is known.
    pending: Option<bool>,
}

impl Layout {
    pub(crate) fn new() -> Layout {
        Layout {
            stack: Vec::new(),
            pending: None,
        }
    }

    /// Inside an array that is itself inline or an element of an array: everything on one
    /// line.
    fn compact(&self) -> bool {
        self.stack
            .iter()
            .any(|f| f.mode == Mode::Inline && !f.object)
    }

    fn indent<W: ?Sized + Write>(&self, w: &mut W, depth: usize) -> io::Result<()> {
        w.write_all(b"\n")?;
        for _ in 0..depth {
            w.write_all(b"  ")?;
        }
        Ok(())
    }

    /// Writes the separator of a pending array element whose kind is now known.
    fn element<W: ?Sized + Write>(&mut self, w: &mut W, nested: bool) -> io::Result<()> {
        let Some(first) = self.pending.take() else {
            return Ok(());
        };
        let compact = self.compact();
        let depth = self.stack.len();
        let frame = self
            .stack
            .last_mut()
            .expect("an element is inside an array");
        if frame.mode == Mode::Open {
            frame.mode = if nested && !compact {
                Mode::Lines
            } else {
                Mode::Inline
            };
        }
        match frame.mode {
            Mode::Lines => {
                if !first {
                    w.write_all(b",")?;
                }
                self.indent(w, depth)
            }
            _ if first => Ok(()),
            _ => w.write_all(b", "),
        }
    }
}

macro_rules! scalar {
    ($($name:ident($t:ty)),*) => {$(
        fn $name<W: ?Sized + Write>(&mut self, w: &mut W, value: $t) -> io::Result<()> {
            self.element(w, false)?;
            serde_json::ser::CompactFormatter.$name(w, value)
        }
    )*};
}

impl Formatter for Layout {
    scalar!(
        write_bool(bool),
        write_i8(i8),
        write_i16(i16),
        write_i32(i32),
        write_i64(i64),
        write_u8(u8),
        write_u16(u16),
        write_u32(u32),
        write_u64(u64)
    );

    fn write_f32<W: ?Sized + Write>(&mut self, w: &mut W, value: f32) -> io::Result<()> {
        self.write_f64(w, f64::from(value))
    }

    /// Finite numbers only: serde_json would write NaN and infinities as `null`, which
    /// reads back as no number at all.
    fn write_f64<W: ?Sized + Write>(&mut self, w: &mut W, value: f64) -> io::Result<()> {
        if !value.is_finite() {
            return Err(io::Error::new(io::ErrorKind::InvalidData, NON_FINITE));
        }
        self.element(w, false)?;
        serde_json::ser::CompactFormatter.write_f64(w, value)
    }

    /// No field of a model file is ever null (absent options are left out), and serde_json
    /// writes NaN and infinities as null: a null here is a number that overflowed.
    fn write_null<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        Err(io::Error::new(io::ErrorKind::InvalidData, NON_FINITE))
    }

    fn begin_string<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.element(w, false)?;
        w.write_all(b"\"")
    }

    fn begin_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.element(w, true)?;
        // An array element of an array is written inline whole.
        let inline = self.stack.last().is_some_and(|f| !f.object) || self.compact();
        self.stack.push(Frame {
            mode: if inline { Mode::Inline } else { Mode::Open },
            object: false,
        });
        w.write_all(b"[")
    }

    fn end_array<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        let frame = self.stack.pop().expect("balanced arrays");
        if frame.mode == Mode::Lines {
            self.indent(w, self.stack.len())?;
        }
        w.write_all(b"]")
    }

    fn begin_array_value<W: ?Sized + Write>(&mut self, _w: &mut W, first: bool) -> io::Result<()> {
        self.pending = Some(first);
        Ok(())
    }

    fn end_array_value<W: ?Sized + Write>(&mut self, _w: &mut W) -> io::Result<()> {
        Ok(())
    }

    fn begin_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        self.element(w, true)?;
        let compact = self.compact();
        self.stack.push(Frame {
            mode: if compact { Mode::Inline } else { Mode::Lines },
            object: true,
        });
        w.write_all(b"{")
    }

    fn end_object<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        let frame = self.stack.pop().expect("balanced objects");
        if frame.mode == Mode::Lines {
            self.indent(w, self.stack.len())?;
        }
        w.write_all(b"}")
    }

    fn begin_object_key<W: ?Sized + Write>(&mut self, w: &mut W, first: bool) -> io::Result<()> {
        let depth = self.stack.len();
        let lines = self.stack.last().is_some_and(|f| f.mode == Mode::Lines);
        if !first {
            w.write_all(b",")?;
        }
        if lines {
            self.indent(w, depth)
        } else if first {
            Ok(())
        } else {
            w.write_all(b" ")
        }
    }

    fn begin_object_value<W: ?Sized + Write>(&mut self, w: &mut W) -> io::Result<()> {
        w.write_all(b": ")
    }
}
