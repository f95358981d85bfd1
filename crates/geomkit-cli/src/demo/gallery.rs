//! Gallery items: the figures of the papers that the method demos do not draw yet, as shaded
//! 3-D pictures (PNG + SVG) with their model and mesh files — Nikulin's Fig. 3 ("Mushroom",
//! degrees 8×10, and "Mask", degrees 10×10: Bézier surfaces over design nets that look like
//! them) and Dolya's closed bodies shaded and meshed watertight.

use super::{Check, Context, Item, Report};
use crate::model::load_shape as load;
use crate::model::BezierModel;
use crate::output::write_mesh;
use anyhow::Result;
use geomkit::bezier::BezierSurface;
use geomkit::compose::{bodies, RuledSurface};
use geomkit::mesh::{tessellate_surface, SurfaceOptions, TriMesh};
use geomkit_model::{Shape, Tessellation};
use geomkit_plot::figures::View;
use geomkit_plot::shaded::{Overlay, Scene, Solid, BACK, FRONT};
use geomkit_plot::svg::palette;
use geomkit_plot::svg_to_png;
use geomkit_plot::{picture_svg, PictureOptions};
use std::f64::consts::TAU;

/// The items, in order.
pub fn items() -> Vec<Item> {
    vec![
        Item {
            id: "fig3-mushroom",
            title: "Fig. 3: the \u{201c}Mushroom\u{201d} Bézier surface of degrees 8×10",
            run: mushroom,
        },
        Item {
            id: "fig3-mask",
            title: "Fig. 3: the \u{201c}Mask\u{201d} Bézier surface of degrees 10×10",
            run: mask,
        },
        Item {
            id: "gallery-shaded",
            title: "Fig. 4, Fig. 5 and the 14×14 B-spline surface, shaded",
            run: shaded_views,
        },
        Item {
            id: "gallery-bodies",
            title: "Dolya's bodies shaded and meshed: cube, pyramid, cone, capped cylinder",
            run: bodies_item,
        },
    ]
}

/// Writes a scene as SVG and PNG and shows the PNG.
fn scene_picture(
    r: &mut Report,
    ctx: &Context,
    id: &str,
    scene: &Scene,
    caption: &str,
) -> Result<()> {
    let svg = scene.render();
    r.picture(ctx, &format!("{id}.svg"), &svg, caption)?;
    // `picture` wrote the PNG beside the SVG; make sure it exists even if that changes.
    if !r.pictures.last().is_some_and(|p| p.file.ends_with(".png")) {
        ctx.write_bytes(&format!("{id}.png"), &svg_to_png(&svg, 2.0, None)?)?;
    }
    Ok(())
}

/// Writes a mesh as GLB, OBJ and binary STL and links them.
fn mesh_files(r: &mut Report, ctx: &Context, id: &str, mesh: &TriMesh, what: &str) -> Result<()> {
    let t = Tessellation::Mesh(mesh.clone());
    for (ext, label) in [
        ("glb", "glTF binary"),
        ("obj", "OBJ"),
        ("stl", "binary STL"),
    ] {
        let mut buf = Vec::new();
        write_mesh(&t, ext, false, &mut buf)?;
        r.file(
            ctx,
            &format!("{id}.{ext}"),
            &buf,
            &format!("{what}, {label}"),
        )?;
    }
    Ok(())
}

/// Largest distance between two surfaces on a k×k grid.
fn max_gap(a: &BezierSurface, b: &BezierSurface, k: usize) -> Result<f64> {
    let ts: Vec<f64> = (0..k).map(|i| i as f64 / (k - 1) as f64).collect();
    let d = a.dim();
    let (mut pa, mut pb) = (vec![0.0; k * k * d], vec![0.0; k * k * d]);
    a.eval_grid(&ts, &ts, &mut pa)?;
    b.eval_grid(&ts, &ts, &mut pb)?;
    Ok(pa
        .chunks_exact(d)
        .zip(pb.chunks_exact(d))
        .map(|(p, q)| {
            p.iter()
                .zip(q)
                .map(|(x, y)| (x - y) * (x - y))
                .sum::<f64>()
                .sqrt()
        })
        .fold(0.0, f64::max))
}

/// Checks shared by the two Fig. 3 surfaces: the real degrees equal the formal ones (the
/// net has no defect), one-step elevation by (1, 1) keeps the surface, the corners are
/// interpolated.
fn fig3_checks(r: &mut Report, s: &BezierSurface) -> Result<()> {
    let (n, m) = s.degrees();
    let report = s.degree_report(None)?;
    r.check(Check::equal(
        "real degrees (no defect in the design net)",
        format!("{:?}", report.real_degrees()),
        format!("{:?}", (n, m)),
    ));
    let up = s.change_degree(n + 1, m + 1, None)?;
    let scale = s.scale();
    r.check(Check::at_most(
        "elevation by (1, 1) keeps the surface (max gap / size, 65×65 grid)",
        max_gap(s, &up, 65)? / scale,
        8.0 * f64::EPSILON,
    ));
    let corner_err = [
        (0.0, 0.0, 0, 0),
        (1.0, 0.0, n, 0),
        (0.0, 1.0, 0, m),
        (1.0, 1.0, n, m),
    ]
    .iter()
    .map(|&(u, v, i, j)| {
        s.eval(u, v)
            .iter()
            .zip(s.point(i, j))
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    })
    .fold(0.0, f64::max);
    r.check(Check::at_most(
        "the surface passes through the 4 corner vertices",
        corner_err,
        4.0 * f64::EPSILON * scale,
    ));
    Ok(())
}

/// Overlay of a Bézier net.
fn net_overlay(s: &BezierSurface) -> Overlay {
    let (n, m) = s.degrees();
    let points = (0..=n)
        .flat_map(|i| (0..=m).map(move |j| (i, j)))
        .map(|(i, j)| {
            let p = s.point(i, j);
            [p[0], p[1], p[2]]
        })
        .collect();
    Overlay::Net {
        points,
        rows: n + 1,
        cols: m + 1,
        color: palette::NEW_VERTEX,
        legend: format!("design net, {}×{} vertices", n + 1, m + 1),
    }
}

/// Radii r_j of a closed control polygon at angles 2πj/m (r_0 = r_m = 1) whose Bézier curve
/// of degree m is as round as possible: least squares of |C(t)| against 1 on 4m samples with
/// a small pull towards 1 (keeps the polygon tidy), solved by Gauss–Jordan.
fn round_radii(m: usize) -> Vec<f64> {
    let k = 8 * m;
    let binom = |n: usize, i: usize| -> f64 {
        (0..i).fold(1.0, |b, q| b * (n - q) as f64 / (q + 1) as f64)
    };
    let bern = |t: f64, j: usize| binom(m, j) * t.powi(j as i32) * (1.0 - t).powi((m - j) as i32);
    // Unknowns r_1..r_(m-1); C(t) = Σ b_j(t) r_j e^{iθ_j} ≈ e^{2πit} (the polygon's own
    // angles make the curve follow the angle).
    let free = m - 1;
    let mut a = vec![vec![0.0; free + 1]; free];
    let lambda = 0.02;
    for s in 0..=k {
        let t = s as f64 / k as f64;
        let target = [(TAU * t).cos(), (TAU * t).sin()];
        let mut rows = [vec![0.0; free], vec![0.0; free]];
        let mut rhs = target;
        for j in 0..=m {
            let th = TAU * j as f64 / m as f64;
            let b = bern(t, j);
            let e = [th.cos() * b, th.sin() * b];
            if j == 0 || j == m {
                rhs[0] -= e[0];
                rhs[1] -= e[1];
            } else {
                rows[0][j - 1] = e[0];
                rows[1][j - 1] = e[1];
            }
        }
        for c in 0..2 {
            for p in 0..free {
                for q in 0..free {
                    a[p][q] += rows[c][p] * rows[c][q];
                }
                a[p][free] += rows[c][p] * rhs[c];
            }
        }
    }
    for p in 0..free {
        a[p][p] += lambda;
        a[p][free] += lambda;
    }
    for col in 0..free {
        let piv = (col..free)
            .max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))
            .unwrap_or(col);
        a.swap(col, piv);
        let d = a[col][col];
        for q in col..=free {
            a[col][q] /= d;
        }
        for p in 0..free {
            if p != col {
                let f = a[p][col];
                for q in col..=free {
                    a[p][q] -= f * a[col][q];
                }
            }
        }
    }
    let mut r = vec![1.0];
    r.extend((0..free).map(|p| a[p][free]));
    r.push(1.0);
    r
}

/// The mushroom: 9 profile vertices (top centre, cap, rim, gills, stem, base centre) turned
/// around the axis on 11 closed-polygon angles: a closed body of degrees (8, 10).
fn mushroom_surface() -> Result<BezierSurface> {
    // (radius, height) of the profile, top to bottom.
    let profile = [
        (0.0, 3.2),
        (3.0, 3.7),
        (5.0, 2.6),
        (4.2, 1.0),
        (0.0, 2.3),
        (1.1, 0.9),
        (0.3, 0.7),
        (1.3, -0.3),
        (0.0, 0.0),
    ];

    let m = 10;
    let radii = round_radii(m);
    let net = profile
        .iter()
        .map(|&(rad, z)| {
            (0..=m)
                .map(|j| {
                    let th = TAU * j as f64 / m as f64;
                    let rr = rad * radii[j];
                    vec![rr * th.cos(), rr * th.sin(), z]
                })
                .collect()
        })
        .collect();
    Ok(BezierSurface::new(net)?)
}

fn mushroom(ctx: &Context) -> Result<Report> {
    let s = mushroom_surface()?;
    let mut r = Report::new(
        "Nikulin, Fig. 3 \u{201c}Гриб 8n×10m\u{201d}: a Bézier surface (11) of degrees 8 and 10 \
         over a 9×11 design net — nine profile vertices (cap, rim, gills, stem) turned about \
         the axis on a closed polygon of 11 vertices whose radii are fitted so that the degree-10 \
         curves come out round. The first and last columns coincide and the first and last \
         rows are single points, so the surface is a closed body: its mesh welds the seam and \
         the poles and is watertight.",
    );
    fig3_checks(&mut r, &s)?;
    let mesh = tessellate_surface(&s, &SurfaceOptions::uniform(97, 121))?;
    r.check(Check::equal(
        "mesh is watertight (seam and poles welded, consistent orientation)",
        mesh.is_watertight(),
        true,
    ));
    let coarse = tessellate_surface(&s, &SurfaceOptions::uniform(49, 61))?;
    let (v, vc) = (mesh.volume(), coarse.volume());
    r.check(Check::at_most(
        "enclosed volume converges (|V(96×120) - V(48×60)| / V)",
        (v - vc).abs() / v,
        1e-2,
    ));
    r.text = format!(
        "mushroom volume {v:.4} (mesh of {} triangles)",
        mesh.triangles().len()
    );
    let scene = Scene::new(
        "Fig. 3 \u{201c}Mushroom\u{201d}: Bézier surface of degrees 8×10",
        format!(
            "9×11 design net; closed body, volume {v:.3}; mesh {} triangles, watertight",
            mesh.triangles().len()
        ),
    )
    .view(View {
        azimuth: 30.0,
        elevation: 22.0,
    })
    .size((720.0, 600.0))
    .solid(&mesh)
    .overlay(net_overlay(&s));
    scene_picture(
        &mut r,
        ctx,
        "fig3-mushroom",
        &scene,
        "the mushroom and its design net",
    )?;
    let bare = Scene::new(
        "Fig. 3 \u{201c}Mushroom\u{201d}",
        "seen from below: the gills",
    )
    .view(View {
        azimuth: -50.0,
        elevation: -35.0,
    })
    .size((720.0, 600.0))
    .solid(&mesh);
    scene_picture(
        &mut r,
        ctx,
        "fig3-mushroom-below",
        &bare,
        "from below, without the net",
    )?;
    r.model(
        ctx,
        "fig3-mushroom.json",
        &BezierModel::Surface(s),
        None,
        "the surface, bezier_surface",
    )?;
    mesh_files(&mut r, ctx, "fig3-mushroom", &mesh, "the closed mesh")?;
    Ok(r)
}

/// The mask: an 11×11 net over x (across the face) and height, pushed out for the forehead,
/// nose, cheeks and chin and pulled in for the eyes and mouth.
fn mask_surface() -> Result<BezierSurface> {
    let n = 10;
    let bump = |x: f64, y: f64, cx: f64, cy: f64, w: f64, h: f64| {
        (-((x - cx) / w).powi(2) - ((y - cy) / h).powi(2)).exp()
    };
    let net = (0..=n)
        .map(|i| {
            let u = -1.0 + 2.0 * i as f64 / n as f64;
            (0..=n)
                .map(|j| {
                    let y = -1.3 + 2.6 * j as f64 / n as f64;
                    let q = (y / 1.3).powi(2);
                    // An oval outline, narrower at the chin.
                    let x = u * (1.0 - 0.22 * q - if y < 0.0 { 0.3 * q } else { 0.0 });
                    let dome = 1.3 * (1.0 - 0.7 * u * u).max(0.0).sqrt() * (1.0 - 0.15 * q);
                    let depth = dome + 3.2 * bump(u, y, 0.0, 0.0, 0.22, 0.45)
                        - 3.0 * bump(u, y, -0.45, 0.4, 0.25, 0.2)
                        - 3.0 * bump(u, y, 0.45, 0.4, 0.25, 0.2)
                        + 1.0 * bump(u, y, 0.0, 0.8, 0.9, 0.2)
                        - 1.6 * bump(u, y, 0.0, -0.6, 0.35, 0.12)
                        + 0.9 * bump(u, y, 0.0, -1.05, 0.4, 0.2);
                    // The face looks towards -y: (x, -depth, height).
                    vec![x, -depth, y]
                })
                .collect()
        })
        .collect();
    Ok(BezierSurface::new(net)?)
}

fn mask(ctx: &Context) -> Result<Report> {
    let s = mask_surface()?;
    let mut r = Report::new(
        "Nikulin, Fig. 3 \u{201c}Маска 10n×10m\u{201d}: a Bézier surface (11) of degrees 10 and 10 \
         over an 11×11 design net shaped like a face — the net's vertices are pushed out for the \
         forehead, nose and chin and pulled in for the eyes and mouth; the surface smooths them \
         into a mask, inside the convex hull of the net.",
    );
    fig3_checks(&mut r, &s)?;
    let mesh = tessellate_surface(&s, &SurfaceOptions::adaptive(2e-3))?;
    r.check(Check::equal(
        "an open surface: the mesh has a boundary",
        mesh.boundary_edge_count() > 0,
        true,
    ));
    // Pictures from a fine uniform grid (flat-shaded facets stay small).
    let fine = tessellate_surface(&s, &SurfaceOptions::uniform(81, 81))?;
    let front = View {
        azimuth: -100.0,
        elevation: 8.0,
    };
    let scene = Scene::new(
        "Fig. 3 \u{201c}Mask\u{201d}: Bézier surface of degrees 10×10",
        format!(
            "11×11 design net; adaptive mesh to 0.002: {} triangles",
            mesh.triangles().len()
        ),
    )
    .view(front)
    .size((640.0, 640.0))
    .solid(&fine)
    .overlay(net_overlay(&s));
    scene_picture(
        &mut r,
        ctx,
        "fig3-mask",
        &scene,
        "the mask and its design net",
    )?;
    let mut plain = Scene::new(
        "Fig. 3 \u{201c}Mask\u{201d}",
        "the surface alone, from the side",
    )
    .view(View {
        azimuth: -105.0,
        elevation: 8.0,
    })
    .size((640.0, 640.0));
    plain.solids.push(Solid {
        mesh: &fine,
        front: [214, 206, 196],
        back: BACK,
    });
    scene_picture(&mut r, ctx, "fig3-mask-plain", &plain, "the mask alone")?;
    r.model(
        ctx,
        "fig3-mask.json",
        &BezierModel::Surface(s.clone()),
        None,
        "the surface, bezier_surface",
    )?;
    mesh_files(&mut r, ctx, "fig3-mask", &mesh, "the adaptive mesh")?;
    Ok(r)
}

/// A copy of a mesh moved by `d`.
fn moved(m: &TriMesh, d: [f64; 3]) -> Result<TriMesh> {
    let pos = m
        .positions()
        .iter()
        .map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]])
        .collect();
    Ok(TriMesh::new(pos, m.triangles().to_vec(), 0.0, 40.0)?)
}

fn bodies_item(ctx: &Context) -> Result<Report> {
    let k = 129;
    let ngon = |n: usize, r: f64| n as f64 / 2.0 * r * r * (TAU / n as f64).sin();
    let list: [(&str, RuledSurface, f64, &str); 4] = [
        (
            "cube",
            bodies::cube()?,
            8.0,
            "the paper's cube, V = 8 exactly",
        ),
        (
            "pyramid",
            bodies::square_pyramid(2.0, 2.0)?,
            8.0 / 3.0,
            "square pyramid 2×2×2, V = 8/3 exactly",
        ),
        (
            "cone",
            bodies::cone(1.0, 2.0)?,
            ngon(k - 1, 1.0) * 2.0 / 3.0,
            "cone r = 1, h = 2: V of the inscribed 128-gon cone",
        ),
        (
            "cylinder",
            bodies::cylinder(1.0, 2.0)?,
            ngon(k - 1, 1.0) * 2.0,
            "capped cylinder r = 1, h = 2: V of the inscribed 128-gon prism",
        ),
    ];
    let mut r = Report::new(
        "Dolya, §2: the closed bodies of the composite-formula paper, each one piecewise-ruled \
         formula (2), tessellated on a 129×… grid that includes every break line (the cube's \
         and pyramid's edges), welded at the seam and the poles, oriented outwards and checked \
         watertight; the volume by the divergence theorem equals the exact volume of the \
         polyhedron the mesh is (the cube's is 8). Each body is written as GLB, OBJ and STL.",
    );
    let mut meshes = Vec::new();
    let mut notes = Vec::new();
    for (i, (name, body, volume, what)) in list.into_iter().enumerate() {
        let mesh = tessellate_surface(&body, &SurfaceOptions::uniform(k, 33))?;
        r.check(Check::equal(
            format!("{name}: watertight, consistently oriented"),
            mesh.is_watertight(),
            true,
        ));
        r.check(Check::at_most(
            format!("{name}: |V - V_exact| / V_exact ({what})"),
            (mesh.volume() - volume).abs() / volume,
            1e-13,
        ));
        notes.push(format!("{name} {} triangles", mesh.triangles().len()));
        mesh_files(&mut r, ctx, &format!("gallery-{name}"), &mesh, name)?;
        let shift = [
            0.0,
            3.0 * i as f64,
            if name == "pyramid" || name == "cone" {
                -1.0
            } else {
                0.0
            },
        ];
        meshes.push(moved(&mesh, shift)?);
    }
    let colors: [[u8; 3]; 4] = [FRONT, [92, 160, 110], [205, 120, 80], [150, 120, 190]];
    let mut scene = Scene::new(
        "Dolya's bodies, one formula each — shaded from their meshes",
        notes.join(" · "),
    )
    .view(View {
        azimuth: 20.0,
        elevation: 24.0,
    })
    .size((900.0, 420.0));
    for (m, c) in meshes.iter().zip(colors) {
        scene.solids.push(Solid {
            mesh: m,
            front: c,
            back: BACK,
        });
    }
    scene_picture(
        &mut r,
        ctx,
        "gallery-bodies",
        &scene,
        "cube, pyramid, cone and capped cylinder",
    )?;
    Ok(r)
}

/// Shaded 3-D views of surfaces that earlier demo items wrote as model files (read back as
/// `geomkit render` reads them).
fn shaded_views(ctx: &Context) -> Result<Report> {
    let mut r = Report::new(
        "The wireframe figures above, read back from their model files and drawn as \
         `geomkit render MODEL.json -o OUT.png` draws them: Nikulin's Fig. 4 (the 7×3 net) and \
         Fig. 5 (the (4, 3) surface), and Ho's surface through 14×14 points with its control \
         net and the reference points it passes through.",
    );
    let cases = [
        (
            "fig4_original.json",
            "Fig. 4: the surface over the 7×3 net",
            View::default(),
        ),
        (
            "fig5_43.json",
            "Fig. 5: the surface of degrees (4, 3)",
            View::default(),
        ),
        (
            "surf14.json",
            "Ho: the bicubic surface through 14×14 points",
            View {
                azimuth: 35.0,
                elevation: 35.0,
            },
        ),
    ];
    for (file, title, view) in cases {
        let path = ctx.dir.join(file);
        let loaded = load(&path)?;
        if let Shape::Surface { surface, net, .. } = &loaded.shape {
            // The mesh reaches the corner vertices of a Bézier net (end-point interpolation).
            if let (Some((rows, cols, pts)), true) = (net, file.starts_with("fig")) {
                let mesh = tessellate_surface(surface.as_ref(), &SurfaceOptions::uniform(33, 33))?;
                let worst = [0, cols - 1, (rows - 1) * cols, rows * cols - 1]
                    .iter()
                    .map(|&k| {
                        mesh.positions()
                            .iter()
                            .map(|q| (0..3).map(|c| (q[c] - pts[k][c]).abs()).fold(0.0, f64::max))
                            .fold(f64::INFINITY, f64::min)
                    })
                    .fold(0.0, f64::max);
                r.check(Check::at_most(
                    format!("{file}: the mesh reaches the 4 corner vertices of the net"),
                    worst,
                    1e-12,
                ));
            }
        }
        let opts = PictureOptions {
            view,
            ..PictureOptions::default()
        };
        let svg = picture_svg(&loaded, title, &loaded.what, &opts)?;
        let stem = format!("shaded-{}", file.trim_end_matches(".json"));
        r.picture(ctx, &format!("{stem}.svg"), &svg, title)?;
    }
    Ok(r)
}
