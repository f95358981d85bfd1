//! A shaded 3-D view of triangle meshes as SVG: orthographic camera at an azimuth and
//! elevation, triangles painted back to front with flat Lambert + Blinn–Phong shading (front
//! faces blue, back faces warm, so the inside of an open surface reads at once; closed meshes
//! cull their back faces), and on top
//! the overlays: control nets, reference points, curves, with a legend.

use crate::figures::View;
use crate::svg::escape;
use geomkit::mesh::TriMesh;
use std::fmt::Write as _;

/// An RGB colour.
pub type Rgb = [u8; 3];

/// Default front-face colour (steel blue).
pub const FRONT: Rgb = [74, 128, 201];
/// Default back-face colour (warm ochre).
pub const BACK: Rgb = [222, 160, 86];

/// A mesh and its colours.
pub struct Solid<'a> {
    /// The mesh.
    pub mesh: &'a TriMesh,
    /// Colour of the side the normals point to.
    pub front: Rgb,
    /// Colour of the other side.
    pub back: Rgb,
}

/// What is drawn on top of the shaded meshes.
pub enum Overlay {
    /// A control net: `rows` × `cols` points joined along rows and columns, with dots.
    Net {
        /// Row-major points.
        points: Vec<[f64; 3]>,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
        /// CSS colour.
        color: &'static str,
        /// Legend text.
        legend: String,
    },
    /// Points (reference points), optionally labelled.
    Points {
        /// The points.
        points: Vec<[f64; 3]>,
        /// CSS colour.
        color: &'static str,
        /// Dot radius (px).
        radius: f64,
        /// Labels, one per point (empty: none).
        labels: Vec<String>,
        /// Legend text.
        legend: String,
    },
}

/// A picture of meshes and overlays.
pub struct Scene<'a> {
    /// Title (first line).
    pub title: String,
    /// Subtitle (second line, grey).
    pub subtitle: String,
    /// The camera.
    pub view: View,
    /// Picture size in px.
    pub size: (f64, f64),
    /// Shaded meshes.
    pub solids: Vec<Solid<'a>>,
    /// Overlays.
    pub overlays: Vec<Overlay>,
}

impl<'a> Scene<'a> {
    /// An empty scene of the default size 720 × 540 in the default view.
    pub fn new(title: impl Into<String>, subtitle: impl Into<String>) -> Self {
        Scene {
            title: title.into(),
            subtitle: subtitle.into(),
            view: View::default(),
            size: (720.0, 540.0),
            solids: Vec::new(),
            overlays: Vec::new(),
        }
    }

    /// Adds a mesh in the default colours.
    pub fn solid(mut self, mesh: &'a TriMesh) -> Self {
        self.solids.push(Solid {
            mesh,
            front: FRONT,
            back: BACK,
        });
        self
    }

    /// Adds an overlay.
    pub fn overlay(mut self, overlay: Overlay) -> Self {
        self.overlays.push(overlay);
        self
    }

    /// Sets the camera.
    pub fn view(mut self, view: View) -> Self {
        self.view = view;
        self
    }

    /// Sets the size in px.
    pub fn size(mut self, size: (f64, f64)) -> Self {
        self.size = size;
        self
    }
}

fn normalize(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if n > 0.0 {
        v.map(|x| x / n)
    } else {
        v
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Camera frame: (right, up, toward the viewer).
fn frame(view: &View) -> ([f64; 3], [f64; 3], [f64; 3]) {
    let (a, e) = (view.azimuth.to_radians(), view.elevation.to_radians());
    (
        [-a.sin(), a.cos(), 0.0],
        [-e.sin() * a.cos(), -e.sin() * a.sin(), e.cos()],
        [e.cos() * a.cos(), e.cos() * a.sin(), e.sin()],
    )
}

fn hex(c: [f64; 3]) -> String {
    let b = c.map(|x| (x.clamp(0.0, 255.0)).round() as u8);
    format!("#{:02x}{:02x}{:02x}", b[0], b[1], b[2])
}

/// The colour of a face with unit normal `n` facing the viewer.
fn shade(base: Rgb, n: [f64; 3], light: [f64; 3], fill: [f64; 3], half: [f64; 3]) -> [f64; 3] {
    let diffuse = dot(n, light).max(0.0);
    let soft = dot(n, fill).max(0.0);
    let spec = dot(n, half).max(0.0).powi(40);
    let k = 0.30 + 0.62 * diffuse + 0.14 * soft;
    base.map(|c| c as f64 * k + 255.0 * 0.28 * spec)
}

impl Scene<'_> {
    /// The SVG document.
    pub fn render(&self) -> String {
        let (w, h) = self.size;
        let (right, up, toward) = frame(&self.view);
        let page = |p: [f64; 3]| [dot(p, right), dot(p, up)];
        // Key light from the upper left, a weak fill light from the right.
        let light = normalize([
            toward[0] + 0.9 * up[0] - 0.6 * right[0],
            toward[1] + 0.9 * up[1] - 0.6 * right[1],
            toward[2] + 0.9 * up[2] - 0.6 * right[2],
        ]);
        let fill = normalize([
            toward[0] + 0.8 * right[0] - 0.2 * up[0],
            toward[1] + 0.8 * right[1] - 0.2 * up[1],
            toward[2] + 0.8 * right[2] - 0.2 * up[2],
        ]);
        let half = normalize([
            light[0] + toward[0],
            light[1] + toward[1],
            light[2] + toward[2],
        ]);

        // Bounds of everything on the page.
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        let mut grow = |q: [f64; 2]| {
            for k in 0..2 {
                lo[k] = lo[k].min(q[k]);
                hi[k] = hi[k].max(q[k]);
            }
        };
        for s in &self.solids {
            s.mesh.positions().iter().for_each(|&p| grow(page(p)));
        }
        for o in &self.overlays {
            let pts = match o {
                Overlay::Net { points, .. } | Overlay::Points { points, .. } => points,
            };
            pts.iter().for_each(|&p| grow(page(p)));
        }
        if !lo[0].is_finite() {
            lo = [0.0, 0.0];
            hi = [1.0, 1.0];
        }
        let legend_rows = self
            .overlays
            .iter()
            .filter(|o| match o {
                Overlay::Net { legend, .. } | Overlay::Points { legend, .. } => !legend.is_empty(),
            })
            .count();
        let top = if self.subtitle.is_empty() { 38.0 } else { 56.0 };
        let bottom = 14.0 + 18.0 * legend_rows as f64;
        let (pw, ph) = (w - 36.0, (h - top - bottom).max(10.0));
        let (dx, dy) = ((hi[0] - lo[0]).max(1e-300), (hi[1] - lo[1]).max(1e-300));
        let scale = (pw / dx).min(ph / dy) * 0.94;
        let (cx, cy) = ((lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0);
        let (ox, oy) = (w / 2.0, top + ph / 2.0);
        let to_px = |q: [f64; 2]| [ox + (q[0] - cx) * scale, oy - (q[1] - cy) * scale];
        let px = |p: [f64; 3]| to_px(page(p));

        let mut s = String::with_capacity(1 << 16);
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="DejaVu Sans, system-ui, Helvetica, Arial, sans-serif">"#
        );
        let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
        let _ = writeln!(
            s,
            r##"<text x="18" y="24" font-size="15" font-weight="600" fill="#222">{}</text>"##,
            escape(&self.title)
        );
        if !self.subtitle.is_empty() {
            let _ = writeln!(
                s,
                r##"<text x="18" y="43" font-size="12" fill="#666">{}</text>"##,
                escape(&self.subtitle)
            );
        }

        // Triangles, far to near.
        let mut faces: Vec<(f64, String, [[f64; 2]; 3])> = Vec::new();
        for solid in &self.solids {
            let m = solid.mesh;
            // A closed mesh hides its back faces: culling them keeps them from bleeding
            // through the edges of the painter's order (the sign of the volume tells which
            // side the normals point to).
            let outward = if m.is_watertight() {
                m.volume().signum()
            } else {
                0.0
            };
            for (t, tri) in m.triangles().iter().enumerate() {
                let p = tri.map(|i| m.positions()[i as usize]);
                let depth = (dot(p[0], toward) + dot(p[1], toward) + dot(p[2], toward)) / 3.0;
                let n = m.face_normal(t);
                let facing = dot(n, toward);
                if facing * outward < 0.0 {
                    continue;
                }
                let (base, n) = if facing >= 0.0 {
                    (solid.front, n)
                } else {
                    (solid.back, n.map(|x| -x))
                };
                let color = hex(shade(base, n, light, fill, half));
                faces.push((depth, color, p.map(px)));
            }
        }
        faces.sort_by(|a, b| a.0.total_cmp(&b.0));
        let _ = writeln!(s, r#"<g stroke-width="0.7" stroke-linejoin="round">"#);
        for (_, color, q) in &faces {
            let _ = writeln!(
                s,
                r#"<path d="M{:.1} {:.1}L{:.1} {:.1}L{:.1} {:.1}Z" fill="{color}" stroke="{color}"/>"#,
                q[0][0], q[0][1], q[1][0], q[1][1], q[2][0], q[2][1]
            );
        }
        let _ = writeln!(s, "</g>");

        let polyline = |s: &mut String, pts: &[[f64; 2]], color: &str, width: f64, dash: bool| {
            let d: Vec<String> = pts
                .iter()
                .map(|q| format!("{:.1},{:.1}", q[0], q[1]))
                .collect();
            let _ = writeln!(
                s,
                r#"<polyline points="{}" fill="none" stroke="{color}" stroke-width="{width}" stroke-opacity="0.8" stroke-linejoin="round" stroke-linecap="round"{}/>"#,
                d.join(" "),
                if dash {
                    r#" stroke-dasharray="5 3""#
                } else {
                    ""
                }
            );
        };
        let dots = |s: &mut String, pts: &[[f64; 2]], color: &str, r: f64| {
            for q in pts {
                let _ = writeln!(
                    s,
                    r##"<circle cx="{:.1}" cy="{:.1}" r="{r}" fill="{color}" stroke="#ffffff" stroke-width="1"/>"##,
                    q[0], q[1]
                );
            }
        };
        let mut legend: Vec<(&'static str, bool, bool, &str)> = Vec::new();
        for o in &self.overlays {
            match o {
                Overlay::Net {
                    points,
                    rows,
                    cols,
                    color,
                    legend: text,
                } => {
                    let q: Vec<[f64; 2]> = points.iter().map(|&p| px(p)).collect();
                    if q.len() == rows * cols {
                        for r in q.chunks_exact(*cols) {
                            polyline(&mut s, r, color, 1.0, false);
                        }
                        for j in 0..*cols {
                            let col: Vec<[f64; 2]> = (0..*rows).map(|i| q[i * cols + j]).collect();
                            polyline(&mut s, &col, color, 1.0, false);
                        }
                    }
                    dots(&mut s, &q, color, 2.8);
                    legend.push((color, true, true, text));
                }
                Overlay::Points {
                    points,
                    color,
                    radius,
                    labels,
                    legend: text,
                } => {
                    let q: Vec<[f64; 2]> = points.iter().map(|&p| px(p)).collect();
                    dots(&mut s, &q, color, *radius);
                    let _ = writeln!(
                        s,
                        r##"<g font-size="12" fill="{color}" stroke="#ffffff" stroke-width="3" paint-order="stroke">"##
                    );
                    for (p, l) in q.iter().zip(labels) {
                        let _ = writeln!(
                            s,
                            r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
                            p[0] + radius + 3.0,
                            p[1] - radius - 2.0,
                            escape(l)
                        );
                    }
                    let _ = writeln!(s, "</g>");
                    legend.push((color, false, true, text));
                }
            }
        }
        let mut y = h - 12.0 - 18.0 * (legend_rows.saturating_sub(1)) as f64;
        for (color, line, dot, text) in legend.iter().filter(|l| !l.3.is_empty()) {
            if *line {
                let _ = writeln!(
                    s,
                    r#"<line x1="18" y1="{:.1}" x2="42" y2="{:.1}" stroke="{color}" stroke-width="2"/>"#,
                    y - 4.0,
                    y - 4.0
                );
            }
            if *dot {
                let _ = writeln!(
                    s,
                    r#"<circle cx="30" cy="{:.1}" r="3" fill="{color}"/>"#,
                    y - 4.0
                );
            }
            let _ = writeln!(
                s,
                r##"<text x="50" y="{y:.1}" font-size="12" fill="#333">{}</text>"##,
                escape(text)
            );
            y += 18.0;
        }
        s.push_str("</svg>\n");
        s
    }
}
