//! Writing results: files atomically (a temporary file in the target's directory, then a
//! rename), so a failed or interrupted run never leaves a half-written file; and stdout
//! without panicking when the reader goes away.
//!
//! Commands compute everything first and write last: when a command fails, no output file
//! appears at all.

use crate::npy::NpyWriter;
use anyhow::{bail, Context, Result};
use geomkit::mesh;
use geomkit_model::Tessellation;
use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

/// Where a command's main output goes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Destination {
    /// Standard output.
    Stdout,
    /// A file, written atomically.
    File(PathBuf),
}

impl Destination {
    /// `-o PATH` given or not.
    pub fn from_option(path: Option<&Path>) -> Self {
        match path {
            Some(p) => Destination::File(p.to_path_buf()),
            None => Destination::Stdout,
        }
    }

    /// Writes `contents` there.
    pub fn write(&self, contents: &[u8]) -> Result<()> {
        match self {
            Destination::Stdout => write_stdout(contents),
            Destination::File(path) => write_atomic(path, contents),
        }
    }

    /// Streams output produced by `write` there (for large outputs such as CSV samples).
    /// Standard output is held back until `write` succeeds, up to [`STDOUT_HOLD_BYTES`]: a
    /// failure prints nothing there (beyond that size, output streams as it comes).
    pub fn write_with(&self, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
        match self {
            Destination::Stdout => {
                let mut out = HeldStdout {
                    held: Vec::new(),
                    passed: None,
                };
                write(&mut out)
                    .and_then(|()| out.flush())
                    .map_err(|e| write_error(e, || "cannot write to standard output".into()))
            }
            Destination::File(path) => write_atomic_with(path, write),
        }
    }
}

/// How much of a streamed output to standard output is held back until the command has
/// succeeded (a failure then prints nothing on stdout, only its error line).
pub const STDOUT_HOLD_BYTES: usize = 64 << 20;

/// Standard output that keeps the first [`STDOUT_HOLD_BYTES`] in memory and passes output
/// through only beyond them (or at the final flush).
struct HeldStdout {
    held: Vec<u8>,
    passed: Option<BufWriter<io::StdoutLock<'static>>>,
}

impl HeldStdout {
    fn release(&mut self) -> io::Result<&mut BufWriter<io::StdoutLock<'static>>> {
        if self.passed.is_none() {
            let mut out = BufWriter::new(io::stdout().lock());
            out.write_all(&self.held)?;
            self.held = Vec::new();
            self.passed = Some(out);
        }
        Ok(self.passed.as_mut().expect("just set"))
    }
}

impl Write for HeldStdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.passed.is_none() && self.held.len() + buf.len() <= STDOUT_HOLD_BYTES {
            self.held.extend_from_slice(buf);
            return Ok(buf.len());
        }
        self.release()?.write(buf)
    }

    /// The final flush (the writers flush once, at the end): prints what was held.
    fn flush(&mut self) -> io::Result<()> {
        self.release()?.flush()
    }
}

/// A failed streamed write: an error of the computation that produced the output (carried
/// through `io::Error` by the streaming writers, e.g. a point that is not finite) is reported
/// as itself; only a real I/O failure is "cannot write ...".
fn write_error(e: io::Error, target: impl FnOnce() -> String) -> anyhow::Error {
    if !e
        .get_ref()
        .is_some_and(|inner| inner.is::<geomkit::Error>())
    {
        return anyhow::Error::new(e).context(target());
    }
    match e.into_inner().map(|b| b.downcast::<geomkit::Error>()) {
        Some(Ok(inner)) => anyhow::Error::new(*inner),
        _ => anyhow::anyhow!(target()),
    }
}

/// Writes `contents` to `path` atomically: the file either keeps its old contents (or stays
/// absent) or has exactly the new ones.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<()> {
    write_atomic_with(path, |w| w.write_all(contents))
}

/// Like [`write_atomic`], with the contents produced by `write` into a buffered writer.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> Result<()> {
    let mut file = AtomicFile::create(path)?;
    write(file.writer())
        .map_err(|e| write_error(e, || format!("cannot write {}", path.display())))?;
    file.commit()
}

/// A file written in pieces and renamed into place at the end: until [`AtomicFile::commit`]
/// the data live in a temporary file next to the target, which is removed if the
/// `AtomicFile` is dropped uncommitted (a failed command leaves nothing behind).
pub struct AtomicFile {
    path: PathBuf,
    out: BufWriter<tempfile::NamedTempFile>,
}

impl AtomicFile {
    /// Starts writing `path`: checks the name and the directory and creates the temporary
    /// file.
    pub fn create(path: &Path) -> Result<Self> {
        let what = || format!("cannot write {}", path.display());
        if path.as_os_str().is_empty() {
            anyhow::bail!("cannot write an output file with an empty name");
        }
        if path.is_dir() {
            anyhow::bail!("cannot write {}: it is a directory", path.display());
        }
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        if !dir.is_dir() {
            anyhow::bail!(
                "cannot write {}: directory {} does not exist",
                path.display(),
                dir.display()
            );
        }
        let mut builder = tempfile::Builder::new();
        builder.prefix(".geomkit-").suffix(".tmp");
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            // Like a plain `File::create`: 0o666 minus the umask (tempfile's default is 0o600).
            builder.permissions(fs::Permissions::from_mode(0o666));
        }
        let temp = builder.tempfile_in(dir).with_context(what)?;
        Ok(AtomicFile {
            path: path.to_path_buf(),
            out: BufWriter::with_capacity(1 << 16, temp),
        })
    }

    /// The final path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The buffered writer of the temporary file.
    pub fn writer(&mut self) -> &mut dyn Write {
        &mut self.out
    }

    /// Flushes, syncs and renames the temporary file to the target.
    pub fn commit(self) -> Result<()> {
        let path = self.path;
        let what = || format!("cannot write {}", path.display());
        let temp = self
            .out
            .into_inner()
            .map_err(|e| e.into_error())
            .with_context(what)?;
        temp.as_file().sync_all().with_context(what)?;
        temp.persist(&path)
            .map_err(|e| e.error)
            .with_context(what)?;
        Ok(())
    }
}

/// The format of a table of numbers written by a command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableFormat {
    /// CSV text with a header line.
    Csv,
    /// A NumPy `.npy` float64 array.
    Npy,
}

/// Rows of numbers written as they come: CSV (a header line, then one line per row) or a
/// `.npy` array whose shape is announced up front (checked at [`RowSink::finish`]).
pub struct RowSink {
    cols: usize,
    npy: Option<NpyWriter>,
    line: String,
}

impl RowSink {
    /// Starts a table of `shape` (rows × ... × columns; the last entry is the row length of
    /// the CSV) with the CSV column names `header`.
    pub fn start(
        w: &mut dyn Write,
        format: TableFormat,
        shape: &[usize],
        header: &[String],
    ) -> io::Result<Self> {
        let cols = if shape.len() >= 2 {
            shape[shape.len() - 1]
        } else {
            1
        };
        let npy = match format {
            TableFormat::Npy => Some(NpyWriter::start(w, shape)?),
            TableFormat::Csv => {
                writeln!(w, "{}", header.join(","))?;
                None
            }
        };
        Ok(RowSink {
            cols: cols.max(1),
            npy,
            line: String::new(),
        })
    }

    /// Appends whole rows (`values.len()` a multiple of the row length).
    pub fn push(&mut self, w: &mut dyn Write, values: &[f64]) -> io::Result<()> {
        use std::fmt::Write as _;
        if let Some(npy) = &mut self.npy {
            return npy.push(w, values);
        }
        for row in values.chunks(self.cols) {
            self.line.clear();
            for (k, x) in row.iter().enumerate() {
                if k > 0 {
                    self.line.push(',');
                }
                // Shortest representation that reads back to the same f64.
                let _ = write!(self.line, "{x:?}");
            }
            self.line.push('\n');
            w.write_all(self.line.as_bytes())?;
        }
        Ok(())
    }

    /// Checks that an `.npy` array got exactly its announced size.
    pub fn finish(self) -> io::Result<()> {
        match self.npy {
            Some(npy) => npy.finish(),
            None => Ok(()),
        }
    }
}

/// Writes `contents` to standard output.
pub fn write_stdout(contents: &[u8]) -> Result<()> {
    let stdout = io::stdout();
    let mut lock = stdout.lock();
    lock.write_all(contents)
        .and_then(|()| lock.flush())
        .context("cannot write to standard output")
}

/// Creates `dir` (and its parents) if missing.
pub fn ensure_dir(dir: &Path) -> Result<()> {
    fs::create_dir_all(dir).with_context(|| format!("cannot create directory {}", dir.display()))
}

/// True when the error (or one of its causes) is a broken pipe: the reader of our standard
/// output went away (`geomkit ... | head`), which is not worth an error message.
pub fn is_broken_pipe(error: &anyhow::Error) -> bool {
    error.chain().any(|e| {
        e.downcast_ref::<io::Error>()
            .is_some_and(|io| io.kind() == io::ErrorKind::BrokenPipe)
    })
}

/// Column names of points of dimension `dim`: x, y, z (x1..xd above 3).
pub fn coordinate_names(dim: usize) -> Vec<String> {
    if dim <= 3 {
        ["x", "y", "z"][..dim]
            .iter()
            .map(|s| s.to_string())
            .collect()
    } else {
        (1..=dim).map(|k| format!("x{k}")).collect()
    }
}

/// A number for a message: plain, or in exponent form when that is shorter (1e-300, not
/// 0.000…1 with 300 digits).
pub fn short(x: f64) -> String {
    let (plain, exp) = (format!("{x}"), format!("{x:e}"));
    if exp.len() < plain.len() {
        exp
    } else {
        plain
    }
}

/// "OUT: V vertices, T triangles, closed, volume X" (or the polyline's size).
pub fn mesh_summary(path: &Path, t: &Tessellation) -> String {
    match t {
        Tessellation::Mesh(m) => format!(
            "{}: {} vertices, {} triangles{}",
            path.display(),
            m.positions().len(),
            m.triangles().len(),
            if m.is_watertight() {
                match m.volume() {
                    v if v.is_finite() => format!(", closed, volume {}", short(v)),
                    _ => ", closed, volume beyond f64's range".to_string(),
                }
            } else {
                String::new()
            }
        ),
        Tessellation::Polyline(p) => format!("{}: polyline of {} points", path.display(), p.len()),
    }
}

/// The mesh formats by extension: "obj", "stl", "ply", "glb".
pub const MESH_FORMATS: [&str; 4] = ["obj", "stl", "ply", "glb"];

/// Writes a tessellation in the format named by `ext` (OBJ with the default normals).
pub fn write_mesh(t: &Tessellation, ext: &str, ascii: bool, w: &mut dyn Write) -> Result<()> {
    write_mesh_with(t, ext, ascii, mesh::ObjNormals::Auto, w)
}

/// Writes a tessellation in the format named by `ext`, OBJ normals as `obj` says.
pub fn write_mesh_with(
    t: &Tessellation,
    ext: &str,
    ascii: bool,
    obj: mesh::ObjNormals,
    w: &mut dyn Write,
) -> Result<()> {
    match (t, ext) {
        (Tessellation::Mesh(m), "obj") => mesh::write_obj_with(m, obj, w)?,
        (Tessellation::Mesh(m), "stl") if ascii => mesh::write_stl_ascii(m, w)?,
        (Tessellation::Mesh(m), "stl") => mesh::write_stl_binary(m, w)?,
        (Tessellation::Mesh(m), "ply") => mesh::write_ply(m, w)?,
        (Tessellation::Mesh(m), "glb") => mesh::write_glb(m, w)?,
        (Tessellation::Polyline(p), "obj") => mesh::write_obj_polyline(p, w)?,
        (Tessellation::Polyline(p), "ply") => mesh::write_ply_polyline(p, w)?,
        (Tessellation::Polyline(p), "glb") => mesh::write_glb_polyline(p, w)?,
        (Tessellation::Polyline(_), "stl") => {
            bail!("STL holds triangles only: write a curve as .obj, .ply or .glb")
        }
        (_, other) => bail!("unknown mesh format .{other}"),
    }
    Ok(())
}

/// Writes a tessellation to `dest` (streamed: no copy of the file in memory), OBJ normals as
/// `obj` says; a failure leaves no file.
pub fn write_mesh_to(
    dest: &Destination,
    t: &Tessellation,
    ext: &str,
    ascii: bool,
    obj: mesh::ObjNormals,
) -> Result<()> {
    if matches!(t, Tessellation::Polyline(_)) && ext == "stl" {
        bail!("STL holds triangles only: write a curve as .obj, .ply or .glb");
    }
    if !MESH_FORMATS.contains(&ext) {
        bail!("unknown mesh format .{ext}");
    }
    dest.write_with(|w| {
        write_mesh_with(t, ext, ascii, obj, w).map_err(|e| match e.downcast::<io::Error>() {
            Ok(io) => io,
            Err(e) => io::Error::other(format!("{e:#}")),
        })
    })
}

/// Commits a control points file and its knots sibling: the knots first; if the control
/// points then fail, the knots file is removed again (no half pair is left behind).
pub fn commit_pair(control: AtomicFile, knots: AtomicFile) -> Result<()> {
    let knots_path = knots.path().to_path_buf();
    knots.commit()?;
    control.commit().inspect_err(|_| {
        let _ = std::fs::remove_file(&knots_path);
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_and_replaces() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        write_atomic(&path, b"one").unwrap();
        write_atomic(&path, b"two").unwrap();
        assert_eq!(fs::read_to_string(&path).unwrap(), "two");
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("b.txt");
        let err = write_atomic_with(&path, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("boom"));
        assert!(!path.exists());
        assert_eq!(fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn failed_write_keeps_old_contents() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.txt");
        write_atomic(&path, b"old").unwrap();
        let _ = write_atomic_with(&path, |_| Err(io::Error::other("boom")));
        assert_eq!(fs::read_to_string(&path).unwrap(), "old");
    }

    #[test]
    fn missing_directory_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("no/such/dir/d.txt");
        let err = write_atomic(&path, b"x").unwrap_err();
        assert!(format!("{err:#}").contains("does not exist"), "{err:#}");
    }
}
