//! The triangle mesh: welded positions, triangles, per-corner normals; topology checks
//! (watertight, consistently oriented), volume and area.

use crate::{Error, Result};
use std::collections::HashMap;

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

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

fn unit(a: [f64; 3]) -> Option<[f64; 3]> {
    let n = norm(a);
    (n > 0.0 && n.is_finite()).then(|| [a[0] / n, a[1] / n, a[2] / n])
}

impl TriMesh {
    /// A mesh from positions and triangles (indices into `positions`, counter-clockwise seen
    /// from the side the normals point to). Vertices closer than `weld_tolerance` are merged
    /// (0 merges only equal points), triangles that then repeat a vertex are dropped, and
    /// normals are computed with the crease angle `crease_degrees` (face normals further apart
    /// than it are not averaged: 0 gives flat shading, 180 smooth shading everywhere).
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
        if !(weld_tolerance.is_finite() && weld_tolerance >= 0.0) {
            return Err(Error::InvalidTolerance {
                value: weld_tolerance,
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
        let (positions, remap) = weld(positions, weld_tolerance);
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
        };
        mesh.drop_unused();
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

    fn face_cross(&self, t: usize) -> [f64; 3] {
        let [a, b, c] = self.triangles[t].map(|i| self.positions[i as usize]);
        cross(sub(b, a), sub(c, a))
    }

    /// Total area.
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| norm(self.face_cross(t)))
            .sum::<f64>()
            / 2.0
    }

    /// Enclosed volume by the divergence theorem, Σ a·(b×c)/6 (positive when a closed mesh
    /// is oriented outwards; meaningful only when [`TriMesh::is_watertight`]). Summed about
    /// the centre of the bounding box for accuracy.
    pub fn volume(&self) -> f64 {
        let (lo, hi) = self.bounding_box();
        let c = [0, 1, 2].map(|k| (lo[k] + hi[k]) / 2.0);
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, d] = t.map(|i| sub(self.positions[i as usize], c));
                dot(a, cross(b, d))
            })
            .sum::<f64>()
            / 6.0
    }

    /// The bounding box (min, max); zeros for an empty mesh.
    pub fn bounding_box(&self) -> ([f64; 3], [f64; 3]) {
        bounding_box(&self.positions)
    }

    /// Directed edges of the triangles with how often each occurs.
    fn edge_counts(&self) -> HashMap<(u32, u32), u32> {
        let mut edges = HashMap::with_capacity(self.triangles.len() * 3);
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
        let mut index: HashMap<(u32, u32), u32> = HashMap::new();
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

    /// Per-corner normals: at each corner the area-weighted sum of the face normals around
    /// the vertex within the crease angle of this face's normal.
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
        let mut normal_indices = vec![[0u32; 3]; self.triangles.len()];
        let mut normals: Vec<[f64; 3]> = Vec::new();
        let mut pool: HashMap<[i64; 3], usize> = HashMap::new();
        for v in 0..nv {
            let faces = &around[start[v]..start[v + 1]];
            for &t in faces {
                let ft = units[t as usize];
                let mut sum = [0.0; 3];
                for &s in faces {
                    if dot(units[s as usize], ft) >= cos_crease {
                        let c = crosses[s as usize];
                        sum = [sum[0] + c[0], sum[1] + c[1], sum[2] + c[2]];
                    }
                }
                let n = unit(sum)
                    .or_else(|| {
                        unit(faces.iter().fold([0.0; 3], |a, &s| {
                            let c = crosses[s as usize];
                            [a[0] + c[0], a[1] + c[1], a[2] + c[2]]
                        }))
                    })
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

/// Merges points closer than `tolerance` (a hash grid of cell `tolerance`, searching the 27
/// neighbouring cells). Returns the kept points and the new index of every input point.
fn weld(points: Vec<[f64; 3]>, tolerance: f64) -> (Vec<[f64; 3]>, Vec<u32>) {
    let mut kept: Vec<[f64; 3]> = Vec::with_capacity(points.len());
    let mut remap = Vec::with_capacity(points.len());
    if tolerance == 0.0 {
        let mut seen: HashMap<[u64; 3], u32> = HashMap::with_capacity(points.len());
        for p in points {
            // +0.0 and -0.0 are the same point.
            let key = p.map(|x| (x + 0.0).to_bits());
            let i = *seen.entry(key).or_insert_with(|| {
                kept.push(p);
                (kept.len() - 1) as u32
            });
            remap.push(i);
        }
        return (kept, remap);
    }
    let cell = |x: f64| (x / tolerance).floor() as i64;
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::with_capacity(points.len());
    for p in points {
        let key = p.map(cell);
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(list) = grid.get(&[key[0] + dx, key[1] + dy, key[2] + dz]) {
                        for &i in list {
                            if norm(sub(kept[i as usize], p)) <= tolerance {
                                found = Some(i);
                                break 'search;
                            }
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
