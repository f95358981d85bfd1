//! Mesh and polyline writers to any [`Write`]: Wavefront OBJ, STL (binary and ASCII), binary
//! little-endian PLY and glTF 2.0 binary (`.glb`).
//!
//! The formats are small enough to write directly (no allocation of the whole file, no extra
//! dependency of the library); the tests read every file back with independent readers (the
//! `gltf` and `stl_io` crates) and `bench/compat_mesh.py` with trimesh and meshio.
//! Coordinates are written as f32 where the format has no f64 (binary STL, glTF: a mesh that
//! f32 cannot hold is an error, never infinities or collapsed triangles) and in shortest
//! round-trip f64 text in OBJ and ASCII STL and as f64 in PLY. OBJ's normals: see
//! [`ObjNormals`].

use super::curve::Polyline;
use super::trimesh::TriMesh;
use std::io::{self, Write};

fn header(what: &str) -> String {
    format!("geomkit {} {what}", env!("CARGO_PKG_VERSION"))
}

/// How [`write_obj_with`] stores normals. OBJ readers disagree on normals: trimesh, Blender,
/// OCCT and MeshLab follow each face corner's `f v//vn` index, while meshio (5.x) takes the
/// k-th `vn` line as the normal of the k-th `v` line and refuses a file whose `vn` count
/// differs from its `v` count. Keeping the sharp normals of a crease on shared positions
/// (watertight) needs more normals than positions, so no single layout serves both with
/// creases; the choice is this enum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum ObjNormals {
    /// The default: `Vertex` when every position has one normal (a smooth surface: every
    /// reader takes it, watertight), else `None` (a body with sharp edges: watertight in
    /// every reader, which then computes its own shading).
    #[default]
    Auto,
    /// One `vn` per distinct normal and `f a//na b//nb c//nc`: positions shared (watertight),
    /// creases sharp; refused by meshio when the counts differ.
    Indexed,
    /// One `vn` per `v` (line k the normal of vertex k) and `f a//a b//b c//c`, vertices
    /// split where their corners' normals differ (creases): meshio reads the normals, but a
    /// closed body is watertight only after merging coincident vertices (trimesh's
    /// `merge_vertices`).
    Vertex,
    /// No normals, `f a b c`: positions shared, readable everywhere, watertight.
    None,
}

impl ObjNormals {
    /// The layout by its name: auto, indexed, per-vertex, none.
    pub fn from_name(name: &str) -> Option<Self> {
        Some(match name {
            "auto" => ObjNormals::Auto,
            "indexed" => ObjNormals::Indexed,
            "per-vertex" => ObjNormals::Vertex,
            "none" => ObjNormals::None,
            _ => return None,
        })
    }
}

/// Whether every position of the mesh has one normal at all its corners.
fn one_normal_per_position(mesh: &TriMesh) -> bool {
    let mut normal = vec![u32::MAX; mesh.positions().len()];
    for (t, n) in mesh.triangles().iter().zip(mesh.normal_indices()) {
        for k in 0..3 {
            let slot = &mut normal[t[k] as usize];
            if *slot == u32::MAX {
                *slot = n[k];
            } else if *slot != n[k] {
                return false;
            }
        }
    }
    true
}

/// Wavefront OBJ with the default normals ([`ObjNormals::Auto`]): readable by trimesh,
/// meshio, OCCT and Blender, watertight where the mesh is.
///
/// ```
/// use geomkit::mesh::{write_obj, TriMesh};
/// let m = TriMesh::new(vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.]], vec![[0, 1, 2]], 0.0, 30.0).unwrap();
/// let mut out = Vec::new();
/// write_obj(&m, &mut out).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// // One normal per position: one `vn` per `v`.
/// assert!(text.contains("vn 0 0 1\n") && text.contains("f 1//1 2//2 3//3\n"));
/// ```
pub fn write_obj(mesh: &TriMesh, w: impl Write) -> io::Result<()> {
    write_obj_with(mesh, ObjNormals::Auto, w)
}

/// Wavefront OBJ: `v` lines (shortest round-trip f64), normals as `normals` says, and one
/// `f` per triangle (1-based indices).
///
/// ```
/// use geomkit::compose::bodies;
/// use geomkit::mesh::{tessellate_surface, write_obj_with, ObjNormals, SurfaceOptions};
/// let cube = tessellate_surface(&bodies::cube().unwrap(), &SurfaceOptions::uniform(5, 4)).unwrap();
/// let mut out = Vec::new();
/// write_obj_with(&cube, ObjNormals::Indexed, &mut out).unwrap();
/// let text = String::from_utf8(out).unwrap();
/// // Six face normals, shared positions.
/// assert_eq!(text.lines().filter(|l| l.starts_with("vn ")).count(), 6);
/// assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), cube.positions().len());
/// ```
pub fn write_obj_with(mesh: &TriMesh, normals: ObjNormals, mut w: impl Write) -> io::Result<()> {
    let layout = match normals {
        ObjNormals::Auto if one_normal_per_position(mesh) => ObjNormals::Vertex,
        ObjNormals::Auto => ObjNormals::None,
        other => other,
    };
    let split;
    type Points<'a> = &'a [[f64; 3]];
    let (positions, vn, faces): (Points, Points, &[[u32; 3]]) = match layout {
        ObjNormals::Vertex => {
            split = mesh.split_vertices();
            (&split.0, &split.1, &split.2)
        }
        ObjNormals::Indexed => (mesh.positions(), mesh.normals(), mesh.triangles()),
        _ => (mesh.positions(), &[], mesh.triangles()),
    };
    writeln!(w, "# {}", header("mesh"))?;
    writeln!(
        w,
        "# {} vertices, {} triangles",
        positions.len(),
        faces.len()
    )?;
    for p in positions {
        writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
    }
    for n in vn {
        writeln!(w, "vn {} {} {}", n[0], n[1], n[2])?;
    }
    match layout {
        ObjNormals::Indexed => {
            for (t, n) in faces.iter().zip(mesh.normal_indices()) {
                writeln!(
                    w,
                    "f {}//{} {}//{} {}//{}",
                    t[0] + 1,
                    n[0] + 1,
                    t[1] + 1,
                    n[1] + 1,
                    t[2] + 1,
                    n[2] + 1
                )?;
            }
        }
        ObjNormals::Vertex => {
            for t in faces {
                let [a, b, c] = t.map(|i| i + 1);
                writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
            }
        }
        _ => {
            for t in faces {
                writeln!(w, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
            }
        }
    }
    w.flush()
}

/// A polyline as OBJ: `v` lines and one `l` element (points in R^3, see
/// [`Polyline::points3`]).
pub fn write_obj_polyline(line: &Polyline, mut w: impl Write) -> io::Result<()> {
    writeln!(w, "# {}", header("polyline"))?;
    for p in line.points3() {
        writeln!(w, "v {} {} {}", p[0], p[1], p[2])?;
    }
    write!(w, "l")?;
    for k in 1..=line.len() {
        write!(w, " {k}")?;
    }
    writeln!(w)?;
    w.flush()
}

/// Checks that a mesh survives a format's f32 coordinates: every coordinate within f32's
/// range (beyond it f32 holds only infinity) and no triangle whose rounded corners coincide
/// (a detail below f32's resolution at the model's size would collapse). Errors name the
/// format, the vertex or triangle, and suggest the f64 formats.
fn check_f32(format: &str, positions: &[[f64; 3]], triangles: &[[u32; 3]]) -> io::Result<()> {
    let bad = |msg: String| Err(io::Error::new(io::ErrorKind::InvalidData, msg));
    for (k, p) in positions.iter().enumerate() {
        if let Some(x) = p.iter().find(|x| x.abs() > f32::MAX as f64) {
            return bad(format!(
                "{format} stores coordinates as f32: vertex {k} has {x:e}, beyond f32's range \
                 (±3.4e38); write .obj or .ply (f64) instead"
            ));
        }
    }
    let r = |i: u32| positions[i as usize].map(|x| x as f32);
    for (k, t) in triangles.iter().enumerate() {
        let [a, b, c] = t.map(r);
        if a == b || b == c || a == c {
            return bad(format!(
                "{format} stores coordinates as f32: triangle {k} collapses when rounded to \
                 f32 (the model has details below f32's resolution at its size); write .obj \
                 or .ply (f64) instead"
            ));
        }
    }
    Ok(())
}

fn f32s(w: &mut impl Write, xs: &[f64]) -> io::Result<()> {
    for &x in xs {
        w.write_all(&(x as f32).to_le_bytes())?;
    }
    Ok(())
}

/// Binary STL: an 80-byte header, the triangle count, and per triangle its face normal and
/// three vertices as f32.
///
/// Errors ([`io::ErrorKind::InvalidData`], before writing anything): a coordinate beyond
/// f32's range, or a triangle that collapses when rounded to f32.
pub fn write_stl_binary(mesh: &TriMesh, mut w: impl Write) -> io::Result<()> {
    check_f32("binary STL", mesh.positions(), mesh.triangles())?;
    let mut head = [b' '; 80];
    let text = header("binary STL");
    head[..text.len().min(80)].copy_from_slice(&text.as_bytes()[..text.len().min(80)]);
    w.write_all(&head)?;
    let count = u32::try_from(mesh.triangles().len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many triangles for STL"))?;
    w.write_all(&count.to_le_bytes())?;
    for (k, t) in mesh.triangles().iter().enumerate() {
        f32s(&mut w, &mesh.face_normal(k))?;
        for &i in t {
            f32s(&mut w, &mesh.positions()[i as usize])?;
        }
        w.write_all(&[0, 0])?;
    }
    w.flush()
}

/// ASCII STL (`solid geomkit` … `endsolid geomkit`), f64 coordinates in shortest round-trip
/// form.
pub fn write_stl_ascii(mesh: &TriMesh, mut w: impl Write) -> io::Result<()> {
    writeln!(w, "solid geomkit")?;
    for (k, t) in mesh.triangles().iter().enumerate() {
        let n = mesh.face_normal(k);
        writeln!(
            w,
            "  facet normal {} {} {}\n    outer loop",
            n[0], n[1], n[2]
        )?;
        for &i in t {
            let p = mesh.positions()[i as usize];
            writeln!(w, "      vertex {} {} {}", p[0], p[1], p[2])?;
        }
        writeln!(w, "    endloop\n  endfacet")?;
    }
    writeln!(w, "endsolid geomkit")?;
    w.flush()
}

/// Binary little-endian PLY: vertices with `double x, y, z, nx, ny, nz` (one normal per
/// vertex: crease vertices are duplicated, see [`TriMesh::split_vertices`]) and faces as
/// `list uchar uint vertex_indices`.
pub fn write_ply(mesh: &TriMesh, mut w: impl Write) -> io::Result<()> {
    let (pos, nrm, tris) = mesh.split_vertices();
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment {}\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\n\
         property double nx\nproperty double ny\nproperty double nz\n\
         element face {}\nproperty list uchar uint vertex_indices\nend_header\n",
        header("mesh"),
        pos.len(),
        tris.len()
    )?;
    for (p, n) in pos.iter().zip(&nrm) {
        for x in p.iter().chain(n) {
            w.write_all(&x.to_le_bytes())?;
        }
    }
    for t in &tris {
        w.write_all(&[3])?;
        for i in t {
            w.write_all(&i.to_le_bytes())?;
        }
    }
    w.flush()
}

/// A polyline as binary PLY: its vertices (`double x, y, z`) and its segments as `edge`
/// elements (`int vertex1, vertex2`).
pub fn write_ply_polyline(line: &Polyline, mut w: impl Write) -> io::Result<()> {
    let pts = line.points3();
    let edges = pts.len().saturating_sub(1);
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment {}\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\n\
         element edge {edges}\nproperty int vertex1\nproperty int vertex2\nend_header\n",
        header("polyline"),
        pts.len()
    )?;
    for p in &pts {
        for x in p {
            w.write_all(&x.to_le_bytes())?;
        }
    }
    for k in 0..edges as u32 {
        w.write_all(&(k as i32).to_le_bytes())?;
        w.write_all(&(k as i32 + 1).to_le_bytes())?;
    }
    w.flush()
}

/// min and max of f32-rounded coordinates, as glTF wants them for POSITION accessors.
fn min_max(points: &[[f64; 3]]) -> ([f32; 3], [f32; 3]) {
    let mut lo = [f32::INFINITY; 3];
    let mut hi = [f32::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k] as f32);
            hi[k] = hi[k].max(p[k] as f32);
        }
    }
    if points.is_empty() {
        return ([0.0; 3], [0.0; 3]);
    }
    (lo, hi)
}

fn json_vec(v: [f32; 3]) -> String {
    format!("[{:?},{:?},{:?}]", v[0], v[1], v[2])
}

/// Writes a GLB container: 12-byte header, JSON chunk padded with spaces, BIN chunk padded
/// with zeros, every length a multiple of 4.
fn glb(mut w: impl Write, json: &str, bin: &[u8]) -> io::Result<()> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let total = u32::try_from(total)
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "mesh too large for GLB"))?;
    w.write_all(b"glTF")?;
    w.write_all(&2u32.to_le_bytes())?;
    w.write_all(&total.to_le_bytes())?;
    w.write_all(&(j.len() as u32).to_le_bytes())?;
    w.write_all(b"JSON")?;
    w.write_all(&j)?;
    w.write_all(&(b.len() as u32).to_le_bytes())?;
    w.write_all(b"BIN\0")?;
    w.write_all(&b)?;
    w.flush()
}

/// The node's rotation turning geomkit's z-up into glTF's y-up (-90° about x).
const Z_UP_TO_Y_UP: &str = "[-0.70710677,0.0,0.0,0.70710677]";

/// glTF 2.0 binary (`.glb`): one mesh with POSITION and NORMAL (f32, one normal per vertex as
/// in [`write_ply`]) and u32 indices, a double-sided material, and a node rotating z-up to
/// glTF's y-up.
///
/// Errors: as [`write_stl_binary`] (f32 coordinates).
pub fn write_glb(mesh: &TriMesh, w: impl Write) -> io::Result<()> {
    check_f32("glTF", mesh.positions(), mesh.triangles())?;
    let (pos, nrm, tris) = mesh.split_vertices();
    let mut bin = Vec::with_capacity(pos.len() * 24 + tris.len() * 12);
    for p in &pos {
        f32s(&mut bin, p)?;
    }
    for n in &nrm {
        f32s(&mut bin, n)?;
    }
    for t in &tris {
        for i in t {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let (lo, hi) = min_max(&pos);
    let vbytes = pos.len() * 12;
    let ibytes = tris.len() * 12;
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"{gen}\"}},\"scene\":0,\
         \"scenes\":[{{\"nodes\":[0]}}],\
         \"nodes\":[{{\"mesh\":0,\"rotation\":{Z_UP_TO_Y_UP}}}],\
         \"materials\":[{{\"pbrMetallicRoughness\":{{\"baseColorFactor\":[0.45,0.6,0.85,1.0],\
         \"metallicFactor\":0.1,\"roughnessFactor\":0.6}},\"doubleSided\":true}}],\
         \"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0,\"NORMAL\":1}},\
         \"indices\":2,\"material\":0,\"mode\":4}}]}}],\
         \"buffers\":[{{\"byteLength\":{blen}}}],\
         \"bufferViews\":[{{\"buffer\":0,\"byteOffset\":0,\"byteLength\":{vb2},\"byteStride\":12,\"target\":34962}},\
         {{\"buffer\":0,\"byteOffset\":{vb2},\"byteLength\":{ibytes},\"target\":34963}}],\
         \"accessors\":[\
         {{\"bufferView\":0,\"byteOffset\":0,\"componentType\":5126,\"count\":{nv},\"type\":\"VEC3\",\"min\":{lo},\"max\":{hi}}},\
         {{\"bufferView\":0,\"byteOffset\":{vbytes},\"componentType\":5126,\"count\":{nv},\"type\":\"VEC3\"}},\
         {{\"bufferView\":1,\"byteOffset\":0,\"componentType\":5125,\"count\":{ni},\"type\":\"SCALAR\"}}]}}",
        gen = header("mesh"),
        blen = bin.len(),
        vb2 = 2 * vbytes,
        nv = pos.len(),
        ni = tris.len() * 3,
        lo = json_vec(lo),
        hi = json_vec(hi),
    );
    glb(w, &json, &bin)
}

/// A polyline as glTF binary: one LINE_STRIP primitive (points in R^3, see
/// [`Polyline::points3`]).
///
/// Errors: a coordinate beyond f32's range.
pub fn write_glb_polyline(line: &Polyline, w: impl Write) -> io::Result<()> {
    let pts = line.points3();
    check_f32("glTF", &pts, &[])?;
    let mut bin = Vec::with_capacity(pts.len() * 12);
    for p in &pts {
        f32s(&mut bin, p)?;
    }
    let (lo, hi) = min_max(&pts);
    let json = format!(
        "{{\"asset\":{{\"version\":\"2.0\",\"generator\":\"{gen}\"}},\"scene\":0,\
         \"scenes\":[{{\"nodes\":[0]}}],\
         \"nodes\":[{{\"mesh\":0,\"rotation\":{Z_UP_TO_Y_UP}}}],\
         \"meshes\":[{{\"primitives\":[{{\"attributes\":{{\"POSITION\":0}},\"mode\":3}}]}}],\
         \"buffers\":[{{\"byteLength\":{blen}}}],\
         \"bufferViews\":[{{\"buffer\":0,\"byteOffset\":0,\"byteLength\":{blen},\"target\":34962}}],\
         \"accessors\":[{{\"bufferView\":0,\"byteOffset\":0,\"componentType\":5126,\"count\":{n},\
         \"type\":\"VEC3\",\"min\":{lo},\"max\":{hi}}}]}}",
        gen = header("polyline"),
        blen = bin.len(),
        n = pts.len(),
        lo = json_vec(lo),
        hi = json_vec(hi),
    );
    glb(w, &json, &bin)
}
