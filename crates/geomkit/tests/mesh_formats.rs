//! Every writer read back: glTF with the `gltf` crate, STL with `stl_io` (independent
//! readers), OBJ and PLY by small parsers here; counts, coordinates, watertightness and the
//! cube's volume survive the round trip.

use geomkit::bezier::BezierCurve;
use geomkit::compose::bodies;
use geomkit::mesh::{
    tessellate_curve, tessellate_surface, write_glb, write_glb_polyline, write_obj_polyline,
    write_obj_with, write_ply, write_ply_polyline, write_stl_ascii, write_stl_binary, CurveOptions,
    ObjNormals, SurfaceOptions, TriMesh,
};

fn cube() -> TriMesh {
    tessellate_surface(&bodies::cube().unwrap(), &SurfaceOptions::uniform(9, 7)).unwrap()
}

fn volume(tris: &[[[f64; 3]; 3]]) -> f64 {
    tris.iter()
        .map(|[a, b, c]| {
            a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0])
        })
        .sum::<f64>()
        / 6.0
}

/// An OBJ file's `v`, `vn` and faces (0-based vertex and optional normal indices).
type Obj = (
    Vec<[f64; 3]>,
    Vec<[f64; 3]>,
    Vec<[(usize, Option<usize>); 3]>,
);

fn parse_obj(text: &str) -> Obj {
    let (mut v, mut vn, mut f) = (Vec::new(), Vec::new(), Vec::new());
    for line in text.lines() {
        let mut it = line.split_whitespace();
        match it.next() {
            Some("v") => v.push([0; 3].map(|_| it.next().unwrap().parse::<f64>().unwrap())),
            Some("vn") => vn.push([0; 3].map(|_| it.next().unwrap().parse::<f64>().unwrap())),
            Some("f") => f.push([0; 3].map(|_| {
                let corner = it.next().unwrap();
                match corner.split_once("//") {
                    Some((a, b)) => (
                        a.parse::<usize>().unwrap() - 1,
                        Some(b.parse::<usize>().unwrap() - 1),
                    ),
                    None => (corner.parse::<usize>().unwrap() - 1, None),
                }
            })),
            _ => {}
        }
    }
    (v, vn, f)
}

fn obj_text(m: &TriMesh, normals: ObjNormals) -> String {
    let mut buf = Vec::new();
    write_obj_with(m, normals, &mut buf).unwrap();
    String::from_utf8(buf).unwrap()
}

#[test]
fn obj_round_trip_keeps_topology_and_exact_coordinates() {
    let m = cube();
    // Indexed: shared positions, the distinct normals, f v//vn.
    let (v, vn, f) = parse_obj(&obj_text(&m, ObjNormals::Indexed));
    assert_eq!(v, m.positions());
    assert_eq!(vn, m.normals());
    assert_eq!(f.len(), m.triangles().len());
    let tris: Vec<[[f64; 3]; 3]> = f.iter().map(|t| t.map(|(a, _)| v[a])).collect();
    assert_eq!(volume(&tris), 8.0);
    // Rebuilt from the file, the mesh is still closed.
    assert!(closed_by_index(v, &f));
}

/// Whether the file's faces, by vertex index alone (a reader that merges nothing), close.
fn closed_by_index(v: Vec<[f64; 3]>, f: &[[(usize, Option<usize>); 3]]) -> bool {
    let tris = f.iter().map(|t| t.map(|(a, _)| a as u32)).collect();
    // Weld tolerance 0 merges exactly equal positions only.
    let distinct = v.len();
    let m = TriMesh::new(v, tris, 0.0, 40.0).unwrap();
    m.positions().len() == distinct && m.is_watertight()
}

/// What meshio 5.x's OBJ reader needs (meshio/obj/_obj.py): it takes the k-th `vn` as the
/// normal of the k-th `v` and refuses a file whose counts differ; it reads only the vertex
/// index of each face corner.
fn meshio_reads(text: &str) -> bool {
    let (v, vn, f) = parse_obj(text);
    (vn.is_empty() || vn.len() == v.len())
        && f.iter().all(|t| {
            t.iter()
                .all(|&(a, n)| a < v.len() && n.is_none_or(|n| n == a))
        })
}

#[test]
fn obj_layouts_serve_meshio_and_keep_bodies_watertight() {
    let m = cube();
    // The cube has creases: the indexed layout has 6 normals for 74 vertices (meshio refuses).
    assert!(!meshio_reads(&obj_text(&m, ObjNormals::Indexed)));
    // The default writes no normals for a creased body: meshio reads it, positions shared.
    let auto = obj_text(&m, ObjNormals::Auto);
    assert_eq!(auto, obj_text(&m, ObjNormals::None));
    assert!(meshio_reads(&auto));
    let (v, vn, f) = parse_obj(&auto);
    assert!(vn.is_empty());
    assert!(closed_by_index(v, &f));
    // Per-vertex: one vn per v, meshio reads the normals; watertight after merging equal
    // positions (the crease vertices are split).
    let per = obj_text(&m, ObjNormals::Vertex);
    assert!(meshio_reads(&per));
    let (v, vn, f) = parse_obj(&per);
    assert_eq!(v.len(), vn.len());
    assert!(v.len() > m.positions().len());
    // Not closed by index (the split crease vertices); closed once equal positions merge.
    assert!(!closed_by_index(v.clone(), &f));
    let merged = TriMesh::new(
        v.clone(),
        f.iter().map(|t| t.map(|(a, _)| a as u32)).collect(),
        0.0,
        40.0,
    )
    .unwrap();
    assert!(merged.is_watertight());
    for t in &f {
        for &(a, n) in t {
            // The normal of a corner is its vertex's: one of the cube's six face normals.
            let n = vn[n.unwrap()];
            assert_eq!(
                n.iter().map(|x| x.abs()).sum::<f64>(),
                1.0,
                "{n:?} at {:?}",
                v[a]
            );
        }
    }
    // A smooth surface: one normal per position, so the default writes one vn per v.
    let s = geomkit::bezier::BezierSurface::new(vec![
        vec![vec![0., 0., 0.], vec![0., 1., 0.5]],
        vec![vec![1., 0., 0.5], vec![1., 1., 0.]],
    ])
    .unwrap();
    let smooth = tessellate_surface(&s, &SurfaceOptions::uniform(6, 5)).unwrap();
    let text = obj_text(&smooth, ObjNormals::Auto);
    assert!(meshio_reads(&text));
    let (v, vn, _) = parse_obj(&text);
    assert_eq!((v.len(), vn.len()), (30, 30));
    assert_eq!(v, smooth.positions());
}

#[test]
fn stl_binary_and_ascii_read_back_with_stl_io() {
    let m = cube();
    for ascii in [false, true] {
        let mut buf = Vec::new();
        if ascii {
            write_stl_ascii(&m, &mut buf).unwrap();
        } else {
            write_stl_binary(&m, &mut buf).unwrap();
        }
        let stl = stl_io::read_stl(&mut std::io::Cursor::new(buf)).unwrap();
        assert_eq!(stl.faces.len(), m.triangles().len(), "ascii {ascii}");
        // stl_io welds equal vertices: the cube's vertices come back.
        assert_eq!(stl.vertices.len(), m.positions().len());
        stl.validate().unwrap();
        let tris: Vec<[[f64; 3]; 3]> = stl
            .faces
            .iter()
            .map(|f| f.vertices.map(|i| stl.vertices[i].0.map(|x| x as f64)))
            .collect();
        assert!((volume(&tris) - 8.0).abs() < 1e-5, "ascii {ascii}");
        for (k, f) in stl.faces.iter().enumerate() {
            assert_eq!(
                f.normal.0.map(|x| x as f64),
                m.face_normal(k).map(|x| x as f32 as f64)
            );
        }
    }
}

/// A minimal binary little-endian PLY reader for the writer's layout.
fn read_ply(buf: &[u8]) -> (Vec<String>, &[u8]) {
    let end = b"end_header\n";
    let at = buf.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = std::str::from_utf8(&buf[..at]).unwrap();
    (header.lines().map(String::from).collect(), &buf[at..])
}

fn f64_at(b: &[u8], k: usize) -> f64 {
    f64::from_le_bytes(b[k * 8..k * 8 + 8].try_into().unwrap())
}

#[test]
fn ply_holds_split_vertices_and_faces() {
    let m = cube();
    let mut buf = Vec::new();
    write_ply(&m, &mut buf).unwrap();
    let (header, body) = read_ply(&buf);
    let (pos, nrm, tris) = m.split_vertices();
    assert!(header.contains(&format!("element vertex {}", pos.len())));
    assert!(header.contains(&format!("element face {}", tris.len())));
    assert_eq!(body.len(), pos.len() * 48 + tris.len() * 13);
    for (k, (p, n)) in pos.iter().zip(&nrm).enumerate() {
        for c in 0..3 {
            assert_eq!(f64_at(body, k * 6 + c), p[c]);
            assert_eq!(f64_at(body, k * 6 + 3 + c), n[c]);
        }
    }
    let faces = &body[pos.len() * 48..];
    for (k, t) in tris.iter().enumerate() {
        let rec = &faces[k * 13..k * 13 + 13];
        assert_eq!(rec[0], 3);
        for c in 0..3 {
            let i = u32::from_le_bytes(rec[1 + 4 * c..5 + 4 * c].try_into().unwrap());
            assert_eq!(i, t[c]);
        }
    }
}

#[test]
fn glb_reads_back_with_the_gltf_crate() {
    let m = cube();
    let mut buf = Vec::new();
    write_glb(&m, &mut buf).unwrap();
    assert_eq!(buf.len() % 4, 0);
    let g = gltf::Gltf::from_slice(&buf).unwrap();
    let blob = g.blob.clone().unwrap();
    let mesh = g.document.meshes().next().unwrap();
    let prim = mesh.primitives().next().unwrap();
    assert_eq!(prim.mode(), gltf::mesh::Mode::Triangles);
    let reader = prim.reader(|_| Some(&blob));
    let pos: Vec<[f32; 3]> = reader.read_positions().unwrap().collect();
    let nrm: Vec<[f32; 3]> = reader.read_normals().unwrap().collect();
    let idx: Vec<u32> = reader.read_indices().unwrap().into_u32().collect();
    let (p, n, t) = m.split_vertices();
    assert_eq!(
        (pos.len(), nrm.len(), idx.len()),
        (p.len(), n.len(), 3 * t.len())
    );
    let tris: Vec<[[f64; 3]; 3]> = idx
        .chunks_exact(3)
        .map(|c| [0, 1, 2].map(|k| pos[c[k] as usize].map(|x| x as f64)))
        .collect();
    assert!((volume(&tris) - 8.0).abs() < 1e-5);
    let bounds = prim.bounding_box();
    assert_eq!((bounds.min, bounds.max), ([-1.0; 3], [1.0; 3]));
    // Validation of the document (accessor ranges, buffer lengths) by the crate.
    assert_eq!(g.document.buffers().next().unwrap().length(), blob.len());
}

#[test]
fn polylines_in_every_line_format() {
    let c = BezierCurve::new(vec![vec![0., 0.], vec![1., 2.], vec![2., 0.]]).unwrap();
    let line = tessellate_curve(&c, &CurveOptions::default().with_tolerance(1e-3)).unwrap();
    let n = line.len();
    let mut obj = Vec::new();
    write_obj_polyline(&line, &mut obj).unwrap();
    let text = String::from_utf8(obj).unwrap();
    assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), n);
    let l = text.lines().find(|l| l.starts_with("l ")).unwrap();
    assert_eq!(l.split_whitespace().count(), n + 1);

    let mut ply = Vec::new();
    write_ply_polyline(&line, &mut ply).unwrap();
    let (header, body) = read_ply(&ply);
    assert!(header.contains(&format!("element edge {}", n - 1)));
    assert_eq!(body.len(), n * 24 + (n - 1) * 8);
    assert_eq!(f64_at(body, 3 * (n - 1)), 2.0);

    let mut glb = Vec::new();
    write_glb_polyline(&line, &mut glb).unwrap();
    let g = gltf::Gltf::from_slice(&glb).unwrap();
    let blob = g.blob.clone().unwrap();
    let prim = g
        .document
        .meshes()
        .next()
        .unwrap()
        .primitives()
        .next()
        .unwrap();
    assert_eq!(prim.mode(), gltf::mesh::Mode::LineStrip);
    let pos: Vec<[f32; 3]> = prim
        .reader(|_| Some(&blob))
        .read_positions()
        .unwrap()
        .collect();
    assert_eq!(pos.len(), n);
    assert_eq!(pos[n - 1], [2.0, 0.0, 0.0]);
}
