//! The triangle mesh: welded positions, triangles, per-corner normals; topology checks
//! (watertight, consistently oriented), volume and area.

use crate::{Error, Result};
use std::hash::{BuildHasherDefault, Hasher};

/// A fast hasher for the mesh's integer keys (cells, edges, normal keys): the
/// multiply-rotate of rustc's FxHash. Keys come from the mesh's own geometry, hashed in one
/// process, so the denial-of-service resistance of std's SipHash buys nothing here, while it
/// cost a quarter of meshing a million vertices.
#[derive(Default, Clone, Copy)]
pub(crate) struct FxHasher(u64);

impl Hasher for FxHasher {
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut word = [0u8; 8];
            word[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(word));
        }
    }

    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }

    fn write_u32(&mut self, x: u32) {
        self.write_u64(u64::from(x));
    }

    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }

    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}

/// A HashMap with [`FxHasher`].
pub(crate) type HashMap<K, V> = std::collections::HashMap<K, V, BuildHasherDefault<FxHasher>>;

/// A triangle mesh in R^3.
///
/// Positions are shared between triangles (welded), so the topology is explicit; normals are
/// stored once per distinct (vertex, normal) pair and indexed per triangle corner, like OBJ's
/// `f v//vn`. [`TriMesh::split_vertices`] gives the one-normal-per-vertex form of PLY and glTF.
#[derive(Debug, Clone, PartialEq)]
pub struct TriMesh {
    positions: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<[f64; 3]>,
    normal_indices: Vec<[u32; 3]>,
    /// A power of two near the largest |coordinate| (see `scale_of`).
    scale: f64,
}

fn check_tolerance(t: f64) -> Result<()> {
    if t.is_finite() && t >= 0.0 {
        Ok(())
    } else {
        Err(Error::InvalidTolerance { value: t })
    }
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The Euclidean length without overflow or underflow of the squares: scaled by the largest
/// component first (inf for a vector with an infinite component).
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    let m = a[0].abs().max(a[1].abs()).max(a[2].abs());
    if m == 0.0 || !m.is_finite() {
        return m;
    }
    let b = a.map(|x| x / m);
    m * dot(b, b).sqrt()
}

/// The unit vector along `a` (scaled first, so a tiny or huge finite vector has one); `None`
/// for the zero vector and non-finite ones.
fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let m = a[0].abs().max(a[1].abs()).max(a[2].abs());
    if !(m > 0.0 && m.is_finite()) {
        return None;
    }
    let b = a.map(|x| x / m);
    let n = dot(b, b).sqrt();
    Some(b.map(|x| x / n))
}

/// A power of two near the largest |coordinate| (1 for an empty or all-zero set): the
/// positions divided by it lie in [-2, 2], so face cross products and the volume sum neither
/// overflow nor (for any triangle the weld keeps) underflow, and the division is exact.
pub(crate) fn scale_of(points: &[[f64; 3]]) -> f64 {
    let m = points
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    if m == 0.0 {
        return 1.0;
    }
    (m.log2().ceil().clamp(-1022.0, 1023.0)).exp2()
}

impl TriMesh {
    /// A mesh from positions and triangles (indices into `positions`, counter-clockwise seen
    /// from the side the normals point to). Vertices closer than `weld_tolerance` are merged
    /// (0 merges only equal points), triangles that then repeat a vertex are dropped, and
    /// normals are computed with the crease angle `crease_degrees` (face normals further apart
    /// than it are not averaged: 0 gives flat shading, 180 smooth shading everywhere).
    ///
    /// Any finite positions and tolerance work (coordinates near ±f64::MAX, tolerances from
    /// the smallest subnormal up): the weld grid's cell keys cannot overflow.
    ///
    /// Errors: a non-finite position ([`Error::NonFinite`]), an index out of range
    /// ([`Error::IndexOutOfRange`]), a negative or non-finite tolerance or crease angle, more
    /// than `u32::MAX` vertices.
    ///
    /// ```
    /// use geomkit::mesh::TriMesh;
    /// let square = TriMesh::new(
    ///     vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
    ///     vec![[0, 1, 2], [0, 2, 3]], 0.0, 30.0).unwrap();
    /// assert_eq!(square.normals(), &[[0., 0., 1.]]);
    /// assert_eq!(square.area(), 1.0);
    /// ```
    pub fn new(
        positions: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        weld_tolerance: f64,
        crease_degrees: f64,
    ) -> Result<Self> {
        check_tolerance(weld_tolerance)?;
        Self::build(
            positions,
            triangles,
            [weld_tolerance; 3],
            Some(weld_tolerance),
            crease_degrees,
        )
    }

    /// Like [`TriMesh::new`], welding per axis: vertices that differ by at most
    /// `weld_tolerance[k]` in every coordinate k are merged. This is how a mesh of a thin or
    /// long model closes its seams without merging what is close along its thin axis only: a
    /// 1e-9 × 1 × 1 box welds within ~1e-18 across its thickness and ~1e-9 along its faces.
    ///
    /// Errors: as [`TriMesh::new`].
    ///
    /// ```
    /// use geomkit::mesh::TriMesh;
    /// // Two points 1e-12 apart in x, one tolerance per axis.
    /// let m = TriMesh::new_per_axis(
    ///     vec![[0., 0., 0.], [1e-12, 0., 0.], [0., 1., 0.], [0., 0., 1.]],
    ///     vec![[0, 2, 3], [1, 2, 3]], [1e-15, 1e-9, 1e-9], 30.0).unwrap();
    /// assert_eq!(m.positions().len(), 4);
    /// ```
    pub fn new_per_axis(
        positions: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        weld_tolerance: [f64; 3],
        crease_degrees: f64,
    ) -> Result<Self> {
        for t in weld_tolerance {
            check_tolerance(t)?;
        }
        Self::build(positions, triangles, weld_tolerance, None, crease_degrees)
    }

    fn build(
        positions: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        weld_tolerance: [f64; 3],
        radius: Option<f64>,
        crease_degrees: f64,
    ) -> Result<Self> {
        if let Some(index) = positions
            .iter()
            .position(|p| p.iter().any(|x| !x.is_finite()))
        {
            return Err(Error::NonFinite {
                what: "mesh vertex",
                index,
            });
        }
        if positions.len() > u32::MAX as usize {
            return Err(Error::InvalidShape {
                what: "mesh",
                reason: format!("{} vertices exceed the u32 index range", positions.len()),
            });
        }
        if !(crease_degrees.is_finite() && (0.0..=180.0).contains(&crease_degrees)) {
            return Err(Error::InvalidOption {
                option: "crease angle",
                reason: "must be between 0 and 180 degrees",
            });
        }
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&bad) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(Error::InvalidShape {
                    what: "mesh",
                    reason: format!(
                        "triangle {t} refers to vertex {bad}, there are {}",
                        positions.len()
                    ),
                });
            }
        }
        let (positions, remap) = weld(positions, weld_tolerance, radius);
        let triangles: Vec<[u32; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| remap[i as usize]))
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .collect();
        let mut mesh = TriMesh {
            positions,
            triangles,
            normals: Vec::new(),
            normal_indices: Vec::new(),
            scale: 1.0,
        };
        mesh.drop_unused();
        mesh.scale = scale_of(&mesh.positions);
        mesh.compute_normals(crease_degrees);
        Ok(mesh)
    }

    /// The vertex positions.
    pub fn positions(&self) -> &[[f64; 3]] {
        &self.positions
    }

    /// The triangles (indices into [`TriMesh::positions`]).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The distinct unit normals.
    pub fn normals(&self) -> &[[f64; 3]] {
        &self.normals
    }

    /// The normal of every triangle corner (indices into [`TriMesh::normals`]).
    pub fn normal_indices(&self) -> &[[u32; 3]] {
        &self.normal_indices
    }

    /// The unit normal of triangle `t` from its vertices ([0, 0, 0] for a zero-area one).
    pub fn face_normal(&self, t: usize) -> [f64; 3] {
        unit(self.face_cross(t)).unwrap_or([0.0; 3])
    }

    /// The cross product of triangle t's edges in positions divided by the mesh's scale
    /// (a power of two): never overflows, and points along the true one.
    fn face_cross(&self, t: usize) -> [f64; 3] {
        let s = self.scale;
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize].map(|x| x / s));
        cross(sub(b, a), sub(c, a))
    }

    /// Total area (summed at the mesh's scale, so only an area beyond f64's range is inf).
    pub fn area(&self) -> f64 {
        let sum = (0..self.triangles.len())
            .map(|t| norm(self.face_cross(t)))
            .sum::<f64>()
            / 2.0;
        sum * self.scale * self.scale
    }

    /// Enclosed volume by the divergence theorem, Σ a·(b×c)/6 (positive when a closed mesh
    /// is oriented outwards; meaningful only when [`TriMesh::is_watertight`]). Summed about
    /// the centre of the bounding box and at the mesh's scale for accuracy; infinite (with
    /// the right sign) only when the volume itself is beyond f64's range.
    pub fn volume(&self) -> f64 {
        let s = self.scale;
        let (lo, hi) = self.bounding_box();
        let c = [0, 1, 2].map(|k| lo[k] / s / 2.0 + hi[k] / s / 2.0);
        let sum = self
            .triangles
            .iter()
            .map(|t| {
                let [a, b, d] = t.map(|i| sub(self.positions[i as usize].map(|x| x / s), c));
                dot(a, cross(b, d))
            })
            .sum::<f64>()
            / 6.0;
        sum * s * s * s
    }

    /// The bounding box (min, max); zeros for an empty mesh.
    pub fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        bounding_box(&self.positions)
    }

    /// Directed edges of the triangles with how often each occurs.
    fn edge_counts(&self) -> HashMap<(u32, u32), u32> {
        let mut edges =
            HashMap::with_capacity_and_hasher(self.triangles.len() * 3, Default::default());
        for t in &self.triangles {
            for k in 0..3 {
                *edges.entry((t[k], t[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        edges
    }

    /// Edges used by only one triangle (the border of an open surface); 0 for a closed mesh.
    pub fn boundary_edge_count(&self) -> usize {
        let edges = self.edge_counts();
        edges
            .keys()
            .filter(|&&(a, b)| !edges.contains_key(&(b, a)))
            .count()
    }

    /// Directed edges that break watertightness: those used more than once, or whose
    /// reverse is not used exactly once (0 for a watertight mesh; an open border counts its
    /// edges, a fold or a collapse the edges it doubles).
    pub fn unpaired_edge_count(&self) -> usize {
        let edges = self.edge_counts();
        edges
            .iter()
            .filter(|&(&(a, b), &n)| n != 1 || edges.get(&(b, a)) != Some(&1))
            .count()
    }

    /// Whether the mesh is closed and consistently oriented: every directed edge occurs
    /// exactly once and its reverse exactly once (each edge shared by exactly two triangles
    /// that traverse it in opposite directions). An empty mesh is not watertight.
    pub fn is_watertight(&self) -> bool {
        let edges = self.edge_counts();
        !edges.is_empty()
            && edges
                .iter()
                .all(|(&(a, b), &n)| n == 1 && edges.get(&(b, a)) == Some(&1))
    }

    /// Reverses every triangle (and normal).
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
        for t in &mut self.normal_indices {
            t.swap(1, 2);
        }
        for n in &mut self.normals {
            *n = n.map(|x| -x);
        }
    }

    /// One normal per vertex, as PLY and glTF store them: a vertex whose corners have
    /// different normals (a crease) is duplicated. Returns (positions, normals, triangles).
    #[allow(clippy::type_complexity)]
    pub fn split_vertices(&self) -> (Vec<[f64; 3]>, Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut index: HashMap<(u32, u32), u32> = HashMap::default();
        let (mut pos, mut nrm) = (Vec::new(), Vec::new());
        let tris = self
            .triangles
            .iter()
            .zip(&self.normal_indices)
            .map(|(t, n)| {
                [0, 1, 2].map(|k| {
                    *index.entry((t[k], n[k])).or_insert_with(|| {
                        pos.push(self.positions[t[k] as usize]);
                        nrm.push(self.normals[n[k] as usize]);
                        (pos.len() - 1) as u32
                    })
                })
            })
            .collect();
        (pos, nrm, tris)
    }

    fn drop_unused(&mut self) {
        let mut used = vec![u32::MAX; self.positions.len()];
        let mut kept = Vec::with_capacity(self.positions.len());
        for t in &mut self.triangles {
            for i in t.iter_mut() {
                if used[*i as usize] == u32::MAX {
                    used[*i as usize] = kept.len() as u32;
                    kept.push(self.positions[*i as usize]);
                }
                *i = used[*i as usize];
            }
        }
        self.positions = kept;
    }

    /// Per-corner normals: the faces around each vertex fall into smooth sectors, joined
    /// across the edges where neighbouring faces' normals lie within the crease angle (a
    /// sharper edge separates them), and each corner gets the area-weighted mean of its
    /// sector's face normals. O(d log d) at a vertex of d faces (a pole of 10000 faces: the
    /// old pairwise test of every face against every other was quadratic there).
    fn compute_normals(&mut self, crease_degrees: f64) {
        let cos_crease = crease_degrees.to_radians().cos() - 1e-12;
        let crosses: Vec<[f64; 3]> = (0..self.triangles.len())
            .map(|t| self.face_cross(t))
            .collect();
        let units: Vec<[f64; 3]> = crosses
            .iter()
            .map(|c| unit(*c).unwrap_or([0.0; 3]))
            .collect();
        // Triangles around each vertex (CSR).
        let nv = self.positions.len();
        let mut start = vec![0usize; nv + 1];
        for t in &self.triangles {
            for &i in t {
                start[i as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut around = vec![0u32; start[nv]];
        for (k, t) in self.triangles.iter().enumerate() {
            for &i in t {
                around[fill[i as usize]] = k as u32;
                fill[i as usize] += 1;
            }
        }
        let add = |a: [f64; 3], b: [f64; 3]| [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        let mut normal_indices = vec![[0u32; 3]; self.triangles.len()];
        let mut normals: Vec<[f64; 3]> = Vec::new();
        let mut pool: HashMap<[i64; 3], usize> = HashMap::default();
        // Scratch per vertex: (other vertex, local face) of every edge at v; union-find.
        let mut edges: Vec<(u32, usize)> = Vec::new();
        let mut parent: Vec<usize> = Vec::new();
        let mut sums: Vec<[f64; 3]> = Vec::new();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        for v in 0..nv {
            let faces = &around[start[v]..start[v + 1]];
            edges.clear();
            for (local, &t) in faces.iter().enumerate() {
                for &w in &self.triangles[t as usize] {
                    if w as usize != v {
                        edges.push((w, local));
                    }
                }
            }
            edges.sort_unstable();
            parent.clear();
            parent.extend(0..faces.len());
            for group in edges.chunk_by(|a, b| a.0 == b.0) {
                // Two faces share an edge in a manifold mesh; past a few (a non-manifold
                // edge), only neighbours in the list are compared: linear work.
                let reach = if group.len() <= 8 { group.len() } else { 2 };
                for (x, &(_, i)) in group.iter().enumerate() {
                    for &(_, j) in &group[x + 1..(x + reach).min(group.len())] {
                        let (ti, tj) = (faces[i] as usize, faces[j] as usize);
                        if dot(units[ti], units[tj]) >= cos_crease {
                            let (ri, rj) = (root(&mut parent, i), root(&mut parent, j));
                            parent[ri] = rj;
                        }
                    }
                }
            }
            sums.clear();
            sums.resize(faces.len(), [0.0; 3]);
            let mut total = [0.0; 3];
            for (local, &t) in faces.iter().enumerate() {
                let r = root(&mut parent, local);
                sums[r] = add(sums[r], crosses[t as usize]);
                total = add(total, crosses[t as usize]);
            }
            for (local, &t) in faces.iter().enumerate() {
                let r = root(&mut parent, local);
                let n = unit(sums[r])
                    .or_else(|| unit(total))
                    .unwrap_or([0.0, 0.0, 1.0]);
                // Normals equal to 1e-12 are shared (flat faces: one normal).
                let key = n.map(|x| (x * 1e12).round() as i64);
                let idx = *pool.entry(key).or_insert_with(|| {
                    normals.push(n);
                    normals.len() - 1
                });
                let tri = &self.triangles[t as usize];
                let corner = tri.iter().position(|&i| i as usize == v).unwrap_or(0);
                normal_indices[t as usize][corner] = idx as u32;
            }
        }
        self.normals = normals;
        self.normal_indices = normal_indices;
    }
}

pub(crate) fn bounding_box(points: &[[f64; 3]]) -> ([f64; 3], [f64; 3]) {
    if points.is_empty() {
        return ([0.0; 3], [0.0; 3]);
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// A weld-grid cell along one axis: the index of the cell of width `tolerance` holding the
/// coordinate while that index is small enough to step to its neighbours exactly (|index| <=
/// 2^60), else the coordinate's own bits. Beyond 2^60 cells from 0 the floats are spaced more
/// than 2^7 tolerances apart, so a coordinate there is within the tolerance of itself only:
/// its cell needs no neighbours. A tolerance of 0 keys every coordinate by its bits (+0.0 and
/// -0.0 alike). The key is thus exact for any finite coordinate and tolerance: no overflow
/// (the old `floor(x / tolerance) as i64 + 1` overflowed past 9.2e18 cells) and no false
/// neighbours.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Cell {
    Near(i64),
    Far(u64),
}

const NEAR_CELLS: f64 = (1u64 << 60) as f64;

fn cell(x: f64, tolerance: f64) -> Cell {
    if tolerance > 0.0 {
        let q = (x / tolerance).floor();
        if q.abs() <= NEAR_CELLS {
            return Cell::Near(q as i64);
        }
    }
    Cell::Far((x + 0.0).to_bits())
}

/// The cells to search around `c`: itself and, for a small index, the two beside it.
fn around(c: Cell) -> impl Iterator<Item = Cell> {
    let (lo, hi) = match c {
        Cell::Near(_) => (-1i64, 1i64),
        Cell::Far(_) => (0, 0),
    };
    (lo..=hi).map(move |d| match c {
        Cell::Near(k) => Cell::Near(k + d),
        far => far,
    })
}

/// Merges points within `tolerance[k]` of each other in every coordinate k (and, when
/// `radius` is given, within that Euclidean distance): a hash grid of cells `tolerance`
/// wide, searching the neighbouring cells (see [`Cell`]). A point joins the first kept point
/// it is close to. Returns the kept points and the new index of every input point.
fn weld(
    points: Vec<[f64; 3]>,
    tolerance: [f64; 3],
    radius: Option<f64>,
) -> (Vec<[f64; 3]>, Vec<u32>) {
    let mut kept: Vec<[f64; 3]> = Vec::with_capacity(points.len());
    let mut remap = Vec::with_capacity(points.len());
    let mut grid: HashMap<[Cell; 3], Vec<u32>> =
        HashMap::with_capacity_and_hasher(points.len(), Default::default());
    let close = |a: [f64; 3], b: [f64; 3]| {
        (0..3).all(|k| (a[k] - b[k]).abs() <= tolerance[k])
            && radius.is_none_or(|r| norm(sub(a, b)) <= r)
    };
    for p in points {
        let key = [0, 1, 2].map(|k| cell(p[k], tolerance[k]));
        let mut found = None;
        'search: for cx in around(key[0]) {
            for cy in around(key[1]) {
                for cz in around(key[2]) {
                    if let Some(list) = grid.get(&[cx, cy, cz]) {
                        if let Some(&i) = list.iter().find(|&&i| close(kept[i as usize], p)) {
                            found = Some(i);
                            break 'search;
                        }
                    }
                }
            }
        }
        let i = found.unwrap_or_else(|| {
            kept.push(p);
            let i = (kept.len() - 1) as u32;
            grid.entry(key).or_default().push(i);
            i
        });
        remap.push(i);
    }
    (kept, remap)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tetra() -> TriMesh {
        TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
            0.0,
            30.0,
        )
        .unwrap()
    }

    #[test]
    fn tetrahedron_is_closed_with_volume_one_sixth() {
        let t = tetra();
        assert!(t.is_watertight());
        assert_eq!(t.boundary_edge_count(), 0);
        assert!((t.volume() - 1.0 / 6.0).abs() < 1e-15);
        // Four faces meeting at creases sharper than 30°: four normals, 12 split vertices.
        assert_eq!(t.normals().len(), 4);
        let (p, n, tris) = t.split_vertices();
        assert_eq!((p.len(), n.len(), tris.len()), (12, 12, 4));
    }

    #[test]
    fn flipped_mesh_has_negative_volume() {
        let mut t = tetra();
        t.flip();
        assert!(t.is_watertight());
        assert!((t.volume() + 1.0 / 6.0).abs() < 1e-15);
    }

    #[test]
    fn welding_merges_near_points_and_drops_degenerate_triangles() {
        let m = TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [1e-13, 0., 0.], [0., 1., 0.]],
            vec![[0, 1, 3], [0, 2, 3]],
            1e-12,
            30.0,
        )
        .unwrap();
        assert_eq!(m.positions().len(), 3);
        assert_eq!(m.triangles().len(), 1);
        assert_eq!(m.boundary_edge_count(), 3);
        assert!(!m.is_watertight());
    }

    #[test]
    fn bad_input_is_an_error() {
        let e = TriMesh::new(vec![[0., f64::NAN, 0.]], vec![], 0.0, 30.0).unwrap_err();
        assert_eq!(
            e,
            Error::NonFinite {
                what: "mesh vertex",
                index: 0
            }
        );
        let e = TriMesh::new(vec![[0.; 3]; 3], vec![[0, 1, 3]], 0.0, 30.0).unwrap_err();
        assert!(
            e.to_string().contains("triangle 0 refers to vertex 3"),
            "{e}"
        );
        assert!(TriMesh::new(vec![], vec![], -1.0, 30.0).is_err());
        assert!(TriMesh::new(vec![], vec![], 0.0, 200.0).is_err());
    }
}
