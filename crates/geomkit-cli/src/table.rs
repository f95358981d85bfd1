//! Reading tables of numbers: CSV text and NumPy `.npy` arrays.
//!
//! CSV (any extension but `.npy`): one record per line, cells separated by commas (or, if the
//! first record has no comma, by semicolons, tabs or blanks). Blank lines and lines starting
//! with `#` are skipped; the first record may be a header (all of its cells non-numeric).
//! Every record needs the same number of cells, each a finite number. Errors name the place:
//! `IN.csv:17:3: "abc" is not a number`, `IN.csv:9: 2 columns, but line 1 has 3`.

use crate::npy::{shape_text, NpyReader};
use crate::progress::Progress;
use anyhow::{anyhow, bail, Context, Result};
use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

/// Numbers read from a file, row-major.
#[derive(Debug, Clone)]
pub struct Table {
    /// Where they came from.
    pub path: PathBuf,
    /// The shape: `[records, cells]` for CSV, as stored for `.npy`.
    pub shape: Vec<usize>,
    /// The numbers.
    pub data: Vec<f64>,
    /// CSV: (record index, lines skipped before it) at every record after skipped lines, to
    /// name the line of a record; empty for `.npy`.
    gaps: Vec<(usize, usize)>,
    npy: bool,
}

/// True when `path` names a `.npy` file.
pub fn is_npy(path: &Path) -> bool {
    extension(path).as_deref() == Some("npy")
}

/// The lower-case extension of `path`.
pub fn extension(path: &Path) -> Option<String> {
    path.extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
}

impl Table {
    /// Reads `path`: `.npy` by its header, anything else as CSV.
    pub fn read(path: &Path, progress: &Progress) -> Result<Table> {
        if is_npy(path) {
            let mut r = NpyReader::open(path)?;
            progress.busy("reading");
            let data = r.read_all()?;
            Ok(Table {
                path: path.to_path_buf(),
                shape: r.header.shape.clone(),
                data,
                gaps: Vec::new(),
                npy: true,
            })
        } else {
            read_csv(path, progress)
        }
    }

    /// The file's name for messages.
    pub fn name(&self) -> String {
        self.path.display().to_string()
    }

    /// Whether it came from an `.npy` file.
    pub fn is_npy(&self) -> bool {
        self.npy
    }

    /// The shape as text: "(40, 3)".
    pub fn shape_text(&self) -> String {
        shape_text(&self.shape)
    }

    /// Where record `k` is: "line 17" (CSV) or "row 16" (`.npy`, numpy's 0-based index).
    pub fn place(&self, k: usize) -> String {
        if self.npy {
            return format!("row {k}");
        }
        let before = match self.gaps.partition_point(|&(row, _)| row <= k) {
            0 => 0,
            i => self.gaps[i - 1].1,
        };
        format!("line {}", k + 1 + before)
    }

    /// Where records `a` and `b` are: "lines 3 and 4", "rows 2 and 3".
    pub fn places(&self, a: usize, b: usize) -> String {
        let (pa, pb) = (self.place(a), self.place(b));
        match (pa.split_once(' '), pb.split_once(' ')) {
            (Some((word, x)), Some((_, y))) => format!("{word}s {x} and {y}"),
            _ => format!("{pa} and {pb}"),
        }
    }

    /// The table as `rows` records of `cols` numbers, for a 2-D CSV or `.npy` array (a 1-D
    /// `.npy` array is a column). Errors name the file and the shape found.
    pub fn as_records(&self) -> Result<(usize, usize)> {
        match self.shape[..] {
            [n] => Ok((n, 1)),
            [n, d] => Ok((n, d)),
            _ => bail!(
                "{}: expected an array of shape (N, d) (one point per row), found {}",
                self.name(),
                self.shape_text()
            ),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Separator {
    Char(char),
    Blank,
}

fn detect(line: &str) -> Separator {
    for c in [',', ';', '\t'] {
        if line.contains(c) {
            return Separator::Char(c);
        }
    }
    Separator::Blank
}

fn cells(line: &str, sep: Separator) -> Box<dyn Iterator<Item = &str> + '_> {
    match sep {
        Separator::Char(c) => Box::new(line.split(c).map(clean)),
        Separator::Blank => Box::new(line.split_whitespace().map(clean)),
    }
}

fn clean(cell: &str) -> &str {
    let c = cell.trim();
    c.strip_prefix('"')
        .and_then(|c| c.strip_suffix('"'))
        .map_or(c, str::trim)
}

/// One cell as a finite number, or why not.
fn number(cell: &str) -> std::result::Result<f64, String> {
    if cell.is_empty() {
        return Err("empty cell (expected a number)".into());
    }
    match cell.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("{cell:?} is not a finite number")),
        Err(_) => Err(format!("{cell:?} is not a number")),
    }
}

fn read_csv(path: &Path, progress: &Progress) -> Result<Table> {
    let name = path.display().to_string();
    let file = File::open(path).with_context(|| format!("cannot read {name}"))?;
    let size = file.metadata().map(|m| m.len()).unwrap_or(0);
    progress.phase("reading", size);
    let mut reader = BufReader::with_capacity(1 << 16, file);
    let mut buf = Vec::new();
    let (mut line_no, mut read, mut shown) = (0usize, 0u64, 0u64);
    let mut sep = None;
    // (cells per record, the line that set it, whether that line is the header)
    let mut width: Option<(usize, usize, bool)> = None;
    let mut data = Vec::new();
    let (mut rows, mut skipped, mut gaps) = (0usize, 0usize, Vec::new());
    loop {
        buf.clear();
        let n = reader
            .read_until(b'\n', &mut buf)
            .with_context(|| format!("cannot read {name}"))?;
        if n == 0 {
            break;
        }
        line_no += 1;
        read += n as u64;
        if read - shown > 1 << 20 {
            progress.set(read);
            shown = read;
        }
        let line = std::str::from_utf8(&buf)
            .map_err(|_| anyhow!("{name}:{line_no}: not UTF-8 text (is this a CSV file?)"))?
            .trim();
        if line.is_empty() || line.starts_with('#') {
            skipped += 1;
            continue;
        }
        let sep = *sep.get_or_insert_with(|| detect(line));
        if width.is_none() && cells(line, sep).all(|c| number(c).is_err() && !c.is_empty()) {
            width = Some((cells(line, sep).count(), line_no, true));
            skipped += 1;
            continue;
        }
        let mut count = 0;
        for (c, cell) in cells(line, sep).enumerate() {
            count += 1;
            let x = number(cell).map_err(|why| anyhow!("{name}:{line_no}:{}: {why}", c + 1))?;
            data.push(x);
        }
        match width {
            None => width = Some((count, line_no, false)),
            Some((w, at, is_header)) if w != count => {
                bail!(
                "{name}:{line_no}: {} but {} {at} has {w} (every line needs the same number of \
                 columns)",
                plural(count, "column"),
                if is_header { "the header on line" } else { "line" }
            )
            }
            Some(_) => {}
        }
        if gaps.last().map_or(0, |&(_, s)| s) != skipped {
            gaps.push((rows, skipped));
        }
        rows += 1;
    }
    let cols = width.map_or(0, |w| w.0);
    if rows == 0 {
        bail!("{name}: no numbers found (the file is empty or has only a header)");
    }
    Ok(Table {
        path: path.to_path_buf(),
        shape: vec![rows, cols],
        data,
        gaps,
        npy: false,
    })
}

/// "1 column", "3 columns".
pub fn plural(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(text: &str) -> Result<Table> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("in.csv");
        std::fs::write(&path, text).unwrap();
        Table::read(&path, &Progress::hidden())
    }

    fn err(text: &str) -> String {
        let e = format!("{:#}", csv(text).unwrap_err());
        e.split("in.csv").nth(1).unwrap_or(&e).to_string()
    }

    #[test]
    fn reads_csv_with_header_comments_and_separators() {
        let t = csv("x,y\n# a comment\n1,2\n\n 3 , 4.5e1 \r\n\"5\",6\n").unwrap();
        assert_eq!(t.shape, vec![3, 2]);
        assert_eq!(t.data, [1.0, 2.0, 3.0, 45.0, 5.0, 6.0]);
        assert_eq!(t.place(0), "line 3");
        assert_eq!(t.place(1), "line 5");
        assert_eq!(t.place(2), "line 6");
        assert_eq!(t.places(1, 2), "lines 5 and 6");
        let t = csv("1 2 3\n4\t5   6\n").unwrap();
        assert_eq!(t.shape, vec![2, 3]);
        let t = csv("1;2\n3;4\n").unwrap();
        assert_eq!(t.data, [1.0, 2.0, 3.0, 4.0]);
        let t = csv("7\n8\n").unwrap();
        assert_eq!(t.shape, vec![2, 1]);
    }

    #[test]
    fn names_line_and_column() {
        assert_eq!(err("1,2,3\n4,5,abc\n"), ":2:3: \"abc\" is not a number");
        assert_eq!(err("1,2\n3,nan\n"), ":2:2: \"nan\" is not a finite number");
        assert_eq!(
            err("1,2\n3,1e999\n"),
            ":2:2: \"1e999\" is not a finite number"
        );
        assert_eq!(err("1,2\n3,\n"), ":2:2: empty cell (expected a number)");
        assert!(err("1,2\n3,4,5\n").starts_with(":2: 3 columns but line 1 has 2"));
        assert!(err("x,y,z\n3,4\n").starts_with(":2: 2 columns but the header on line 1 has 3"));
        assert!(err("x,y\n").contains("no numbers"));
        assert!(err("").contains("no numbers"));
    }
}
