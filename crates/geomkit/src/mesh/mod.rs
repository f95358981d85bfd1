//! Tessellation and export: curves become polylines sampled adaptively to a tolerance,
//! surfaces become triangle meshes with normals (a uniform grid or an adaptive tensor grid),
//! and both are written to any [`std::io::Write`] as OBJ, STL (binary and ASCII), binary PLY
//! or glTF binary (`.glb`).
//!
//! Every model type of the library tessellates through the shared traits of
//! [`crate::geom`]: [`tessellate_curve`] takes any `&dyn` [`Curve`](crate::geom::Curve)
//! (Bézier, rational Bézier, B-spline and piecewise curves, point equations, composite
//! curves) and [`tessellate_surface`] any `&dyn` [`Surface`](crate::geom::Surface) (Bézier,
//! B-spline, composite (9)/(11) and piecewise-ruled (2) surfaces of
//! spec/composite-surfaces.md, point-calculus surfaces). Polylines include the curve's
//! breaks and grid lines the surface's break lines (knots, cell boundaries, the vertices of
//! ruled polygons), so corners and creases such as the cube's edges are kept exactly.
//!
//! Closed bodies come out watertight: coincident vertices (the seam u0 = u1, the poles where a
//! ruled surface starts at a point) are welded within a tolerance scaled per axis to the size
//! of the body, degenerate triangles are dropped, and a closed mesh is oriented with its
//! normals pointing outwards (positive volume); a mesh that cannot keep these promises (empty,
//! leaking, enclosing no volume in f64) is an error. Normals are per triangle corner: the
//! faces around a vertex fall into smooth sectors separated by edges sharper than a crease
//! angle, and each corner gets the area-weighted mean normal of its sector, so smooth surfaces
//! shade smoothly and edges stay sharp.
//!
//! Work is bounded: at most [`MAX_TRIANGLES`] triangles per surface mesh (2 000 000) and
//! 1 000 000 points per polyline; see [`tessellate_surface`] for what happens at the cap.
//!
//! ```
//! use geomkit::compose::bodies;
//! use geomkit::mesh::{tessellate_surface, SurfaceOptions};
//! let cube = bodies::cube().unwrap();
//! let mesh = tessellate_surface(&cube, &SurfaceOptions::uniform(9, 7)).unwrap();
//! assert!(mesh.is_watertight());
//! assert!((mesh.volume() - 8.0).abs() < 1e-12);
//! let mut obj = Vec::new();
//! geomkit::mesh::write_obj(&mesh, &mut obj).unwrap();
//! assert!(obj.starts_with(b"# geomkit"));
//! ```

mod curve;
mod surface;
mod trimesh;
mod write;

pub use curve::{tessellate_curve, tessellate_curve_with_progress, CurveOptions, Polyline};
pub use surface::{
    tessellate_surface, tessellate_surface_report, tessellate_surface_with_progress, MeshReport,
    Sampling, SurfaceOptions, MAX_TRIANGLES,
};
pub use trimesh::TriMesh;
pub use write::{
    write_glb, write_glb_polyline, write_obj, write_obj_polyline, write_obj_with, write_ply,
    write_ply_polyline, write_stl_ascii, write_stl_binary, ObjNormals,
};
