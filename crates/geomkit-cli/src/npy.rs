//! A minimal reader and writer of NumPy `.npy` files: arrays of numbers in C order.
//!
//! Format (numpy.lib.format, versions 1.0, 2.0 and 3.0): the magic `\x93NUMPY`, two version
//! bytes, the header length (u16 little-endian for 1.0, u32 for 2.0/3.0), and the header, a
//! Python dict literal such as `{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }`
//! padded with spaces and a newline so that the data starts at a multiple of 64 bytes. The data
//! follow, row-major.
//!
//! Reading accepts float64 and float32, int64 and int32 in either byte order (converted to
//! f64), in C order; rows can be read anywhere in the file (seek), so that large arrays are
//! processed a block at a time. Writing produces `<f8` C-order arrays, version 1.0 (2.0 only
//! for headers of 64 KiB and more), with the shape known up front: [`NpyWriter`] then takes the
//! data in pieces.

use anyhow::{bail, Context, Result};
use std::fs::File;
use std::io::{self, BufReader, Read, Seek, SeekFrom, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};

const MAGIC: &[u8; 6] = b"\x93NUMPY";

/// Element types that can be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    F8,
    F4,
    I8,
    I4,
}

impl Kind {
    fn size(self) -> usize {
        match self {
            Kind::F8 | Kind::I8 => 8,
            Kind::F4 | Kind::I4 => 4,
        }
    }
}

/// The header of an `.npy` file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct NpyHeader {
    /// The array's shape (empty for a scalar).
    pub shape: Vec<usize>,
    kind: Kind,
    little_endian: bool,
    /// Offset of the first data byte.
    data_offset: u64,
}

impl NpyHeader {
    /// Number of elements.
    pub fn len(&self) -> usize {
        self.shape.iter().product()
    }

    /// The shape as numpy prints it: "(3, 2)", "(5,)", "()".
    pub fn shape_text(&self) -> String {
        shape_text(&self.shape)
    }
}

/// "(3, 2)", "(5,)", "()".
pub fn shape_text(shape: &[usize]) -> String {
    match shape {
        [] => "()".into(),
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// An open `.npy` file whose header has been read and checked against the file's size.
#[derive(Debug)]
pub struct NpyReader {
    path: PathBuf,
    file: BufReader<File>,
    /// The header.
    pub header: NpyHeader,
}

impl NpyReader {
    /// Opens `path` and reads its header. Errors name the file and what is wrong.
    pub fn open(path: &Path) -> Result<Self> {
        let name = path.display().to_string();
        let file = File::open(path).with_context(|| format!("cannot read {name}"))?;
        let size = file
            .metadata()
            .with_context(|| format!("cannot read {name}"))?
            .len();
        let mut file = BufReader::new(file);
        let header = read_header(&mut file).with_context(|| name.clone())?;
        let bytes = header
            .shape
            .iter()
            .try_fold(header.kind.size() as u64, |acc, &n| {
                acc.checked_mul(n as u64)
            });
        let want = bytes.and_then(|b| b.checked_add(header.data_offset));
        if want != Some(size) {
            bail!(
                "{name}: the header says shape {} of {}-byte numbers, but the file has {} bytes \
                 of data (truncated or not an .npy file)",
                header.shape_text(),
                header.kind.size(),
                size.saturating_sub(header.data_offset)
            );
        }
        Ok(NpyReader {
            path: path.to_path_buf(),
            file,
            header,
        })
    }

    /// Reads elements `range` (flat, row-major indices) as f64, checking that every value is
    /// finite; a non-finite one is reported with its numpy index (`[17, 2]`).
    pub fn read_range(&mut self, range: Range<usize>) -> Result<Vec<f64>> {
        let size = self.header.kind.size();
        let name = || self.path.display().to_string();
        self.file
            .seek(SeekFrom::Start(
                self.header.data_offset + (range.start * size) as u64,
            ))
            .with_context(name)?;
        let mut out = Vec::with_capacity(range.len());
        let mut buf = vec![0u8; 8192 * size];
        let mut left = range.len();
        while left > 0 {
            let take = left.min(8192);
            let chunk = &mut buf[..take * size];
            self.file
                .read_exact(chunk)
                .with_context(|| format!("cannot read {}", name()))?;
            decode(chunk, self.header.kind, self.header.little_endian, &mut out);
            left -= take;
        }
        if let Some(k) = out.iter().position(|x| !x.is_finite()) {
            bail!(
                "{}: element {} is {}, not a finite number",
                name(),
                index_text(&self.header.shape, range.start + k),
                out[k]
            );
        }
        Ok(out)
    }

    /// Reads the whole array (finite values only).
    pub fn read_all(&mut self) -> Result<Vec<f64>> {
        self.read_range(0..self.header.len())
    }
}

/// The numpy index "[i, j]" of flat element `k` of an array of `shape`.
pub fn index_text(shape: &[usize], mut k: usize) -> String {
    let mut idx = vec![0; shape.len()];
    for (i, &n) in shape.iter().enumerate().rev() {
        if n > 0 {
            idx[i] = k % n;
            k /= n;
        }
    }
    format!(
        "[{}]",
        idx.iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join(", ")
    )
}

fn decode(bytes: &[u8], kind: Kind, little: bool, out: &mut Vec<f64>) {
    macro_rules! conv {
        ($t:ty, $n:expr) => {
            out.extend(bytes.chunks_exact($n).map(|c| {
                let a: [u8; $n] = c.try_into().unwrap_or([0; $n]);
                (if little {
                    <$t>::from_le_bytes(a)
                } else {
                    <$t>::from_be_bytes(a)
                }) as f64
            }))
        };
    }
    match kind {
        Kind::F8 => conv!(f64, 8),
        Kind::F4 => conv!(f32, 4),
        Kind::I8 => conv!(i64, 8),
        Kind::I4 => conv!(i32, 4),
    }
}

fn read_header(r: &mut impl Read) -> Result<NpyHeader> {
    let mut start = [0u8; 8];
    r.read_exact(&mut start)
        .map_err(|_| anyhow::anyhow!("not a NumPy .npy file (too short)"))?;
    if &start[..6] != MAGIC {
        bail!("not a NumPy .npy file (it does not start with \\x93NUMPY)");
    }
    let major = start[6];
    let (len, prefix) = match major {
        1 => {
            let mut b = [0u8; 2];
            r.read_exact(&mut b)?;
            (u16::from_le_bytes(b) as usize, 10)
        }
        2 | 3 => {
            let mut b = [0u8; 4];
            r.read_exact(&mut b)?;
            (u32::from_le_bytes(b) as usize, 12)
        }
        v => bail!("unsupported .npy format version {v}.{}", start[7]),
    };
    if len > 1 << 20 {
        bail!("the .npy header is implausibly long ({len} bytes)");
    }
    let mut text = vec![0u8; len];
    r.read_exact(&mut text)
        .map_err(|_| anyhow::anyhow!("truncated .npy header"))?;
    let text = String::from_utf8_lossy(&text);
    let (kind, little_endian, shape) = parse_dict(&text)?;
    Ok(NpyHeader {
        shape,
        kind,
        little_endian,
        data_offset: (prefix + len) as u64,
    })
}

/// The text after `'key':` in a header dict, up to the end of the dict.
fn value_of<'a>(dict: &'a str, key: &str) -> Option<&'a str> {
    for quote in ['\'', '"'] {
        let k = format!("{quote}{key}{quote}");
        if let Some(at) = dict.find(&k) {
            let rest = dict[at + k.len()..].trim_start();
            return rest.strip_prefix(':').map(str::trim_start);
        }
    }
    None
}

fn parse_dict(dict: &str) -> Result<(Kind, bool, Vec<usize>)> {
    let bad = || anyhow::anyhow!("cannot read the .npy header {:?}", dict.trim_end());
    let descr = value_of(dict, "descr").ok_or_else(bad)?;
    let q = descr.chars().next().ok_or_else(bad)?;
    if q != '\'' && q != '"' {
        bail!(
            "the .npy file holds a structured array ({}); geomkit reads plain number arrays",
            descr.split('}').next().unwrap_or(descr)
        );
    }
    let descr = descr[1..].split(q).next().ok_or_else(bad)?;
    let (order, code) = match descr.chars().next() {
        Some(c @ ('<' | '>' | '|' | '=')) => (c, &descr[1..]),
        _ => ('=', descr),
    };
    let little = match order {
        '>' => false,
        '<' => true,
        _ => cfg!(target_endian = "little"),
    };
    let kind = match code {
        "f8" => Kind::F8,
        "f4" => Kind::F4,
        "i8" => Kind::I8,
        "i4" => Kind::I4,
        other => bail!(
            "the .npy file holds {other:?} data (descr {descr:?}); geomkit reads float64, \
             float32, int64 and int32 arrays (convert with a.astype('float64'))"
        ),
    };
    let fortran = value_of(dict, "fortran_order").ok_or_else(bad)?;
    if fortran.starts_with("True") {
        bail!(
            "the .npy array is in Fortran order; save it in C order \
             (np.save(path, np.ascontiguousarray(a)))"
        );
    }
    if !fortran.starts_with("False") {
        return Err(bad());
    }
    let shape = value_of(dict, "shape").ok_or_else(bad)?;
    let inner = shape
        .strip_prefix('(')
        .and_then(|s| s.split(')').next())
        .ok_or_else(bad)?;
    let shape = inner
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.trim_end_matches('L').parse::<usize>().map_err(|_| bad()))
        .collect::<Result<Vec<_>>>()?;
    Ok((kind, little, shape))
}

/// The header bytes of a `<f8` C-order array of `shape`.
pub fn header_bytes(shape: &[usize]) -> Vec<u8> {
    let dict = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': {}, }}",
        shape_text(shape)
    );
    // Total length (prefix + dict + padding + '\n') a multiple of 64.
    let (prefix, version) = if dict.len() + 1 + 10 < 65536 {
        (10, 1u8)
    } else {
        (12, 2u8)
    };
    let total = (prefix + dict.len() + 1).div_ceil(64) * 64;
    let header_len = total - prefix;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&[version, 0]);
    if version == 1 {
        out.extend_from_slice(&(header_len as u16).to_le_bytes());
    } else {
        out.extend_from_slice(&(header_len as u32).to_le_bytes());
    }
    out.extend_from_slice(dict.as_bytes());
    out.resize(total - 1, b' ');
    out.push(b'\n');
    out
}

/// Writes f64 values little-endian, a block at a time.
pub fn write_values(w: &mut dyn Write, values: &[f64]) -> io::Result<()> {
    let mut buf = Vec::with_capacity(8 * 4096);
    for block in values.chunks(4096) {
        buf.clear();
        for x in block {
            buf.extend_from_slice(&x.to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    Ok(())
}

/// Writes a whole `<f8` array.
pub fn write_npy(w: &mut dyn Write, shape: &[usize], data: &[f64]) -> io::Result<()> {
    debug_assert_eq!(shape.iter().product::<usize>(), data.len());
    w.write_all(&header_bytes(shape))?;
    write_values(w, data)
}

/// Writes an array of known shape in pieces, checking that exactly the announced number of
/// values arrives.
pub struct NpyWriter {
    expected: usize,
    written: usize,
}

impl NpyWriter {
    /// Writes the header of an array of `shape` to `w`.
    pub fn start(w: &mut dyn Write, shape: &[usize]) -> io::Result<Self> {
        w.write_all(&header_bytes(shape))?;
        Ok(NpyWriter {
            expected: shape.iter().product(),
            written: 0,
        })
    }

    /// Appends values.
    pub fn push(&mut self, w: &mut dyn Write, values: &[f64]) -> io::Result<()> {
        self.written += values.len();
        if self.written > self.expected {
            return Err(io::Error::other(format!(
                "internal error: more than the {} values announced in the .npy header",
                self.expected
            )));
        }
        write_values(w, values)
    }

    /// Checks that the array is complete.
    pub fn finish(self) -> io::Result<()> {
        if self.written != self.expected {
            return Err(io::Error::other(format!(
                "internal error: {} values written, the .npy header announced {}",
                self.written, self.expected
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn round_trip(shape: &[usize], data: &[f64]) -> (NpyHeader, Vec<f64>) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.npy");
        let mut bytes = Vec::new();
        write_npy(&mut bytes, shape, data).unwrap();
        std::fs::write(&path, &bytes).unwrap();
        let mut r = NpyReader::open(&path).unwrap();
        let all = r.read_all().unwrap();
        (r.header.clone(), all)
    }

    #[test]
    fn writes_and_reads_back() {
        let data: Vec<f64> = (0..12).map(|i| i as f64 * 0.5 - 1.0).collect();
        let (h, back) = round_trip(&[4, 3], &data);
        assert_eq!(h.shape, vec![4, 3]);
        assert_eq!(h.data_offset % 64, 0);
        assert_eq!(back, data);
        let (h, back) = round_trip(&[12], &data);
        assert_eq!(h.shape_text(), "(12,)");
        assert_eq!(back, data);
        let (h, back) = round_trip(&[2, 0, 3], &[]);
        assert_eq!(h.shape, vec![2, 0, 3]);
        assert!(back.is_empty());
    }

    #[test]
    fn header_is_what_numpy_writes() {
        let h = header_bytes(&[3, 2]);
        assert_eq!(h.len(), 128);
        let text = String::from_utf8_lossy(&h[10..]).to_string();
        assert!(text.starts_with("{'descr': '<f8', 'fortran_order': False, 'shape': (3, 2), }"));
        assert!(text.ends_with(" \n"));
    }

    #[test]
    fn reads_other_types_and_byte_orders() {
        let (k, l, s) =
            parse_dict("{'descr': '>i4', 'fortran_order': False, 'shape': (2,), }").unwrap();
        assert_eq!((k, l, s), (Kind::I4, false, vec![2]));
        let mut out = Vec::new();
        decode(&[0, 0, 0, 7, 255, 255, 255, 254], Kind::I4, false, &mut out);
        assert_eq!(out, [7.0, -2.0]);
        let (_, _, s) =
            parse_dict("{'descr': '<f8', 'fortran_order': False, 'shape': (), }").unwrap();
        assert!(s.is_empty());
    }

    #[test]
    fn clear_errors() {
        let e = |d: &str| format!("{:#}", parse_dict(d).unwrap_err());
        assert!(
            e("{'descr': '<c16', 'fortran_order': False, 'shape': (2,), }")
                .contains("astype('float64')")
        );
        assert!(
            e("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 2), }")
                .contains("Fortran order")
        );
        assert!(
            e("{'descr': [('x', '<f8')], 'fortran_order': False, 'shape': (2,), }")
                .contains("structured")
        );
        assert_eq!(index_text(&[4, 3], 7), "[2, 1]");
    }

    #[test]
    fn truncated_file_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("t.npy");
        let mut bytes = Vec::new();
        write_npy(&mut bytes, &[4, 2], &[0.0; 8]).unwrap();
        bytes.truncate(bytes.len() - 8);
        std::fs::write(&path, &bytes).unwrap();
        let err = format!("{:#}", NpyReader::open(&path).unwrap_err());
        assert!(err.contains("t.npy") && err.contains("(4, 2)"), "{err}");
        std::fs::write(&path, b"hello").unwrap();
        let err = format!("{:#}", NpyReader::open(&path).unwrap_err());
        assert!(err.contains("not a NumPy .npy file"), "{err}");
    }
}
