//! Pictures of any model (a [`Loaded`] shape of the model crate): curves with their control
//! polygon and reference points, surfaces shaded with their control net.

use crate::figures::{add_polygon, View};
use crate::shaded::{Overlay, Scene};
use crate::svg::{palette, Axes, Figure, Stroke};
use crate::Result;
use geomkit::geom::Curve;
use geomkit::mesh::{tessellate_curve, tessellate_surface, CurveOptions, SurfaceOptions};
use geomkit_model::shape::{Loaded, Shape};

/// Picture options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PictureOptions {
    /// Camera for 3-D.
    pub view: View,
    /// Size in px of a shaded surface picture (curve pictures size themselves).
    pub size: (f64, f64),
    /// Draw the control net or polygon.
    pub net: bool,
}

impl Default for PictureOptions {
    fn default() -> Self {
        PictureOptions {
            view: View::default(),
            size: (720.0, 540.0),
            net: true,
        }
    }
}

/// Samples per direction of the mesh of a shaded picture.
const PICTURE_SAMPLES: usize = 60;

/// The picture of a loaded model as SVG: a curve with its control polygon and reference
/// points, or a shaded surface with its net and reference points.
pub fn picture_svg(
    loaded: &Loaded,
    title: &str,
    subtitle: &str,
    opts: &PictureOptions,
) -> Result<String> {
    match &loaded.shape {
        Shape::Curve {
            curve,
            control,
            references,
        } => curve_svg(
            curve.as_ref(),
            control.as_ref().filter(|_| opts.net),
            references,
            title,
            subtitle,
            opts.view,
        ),
        Shape::Surface {
            surface,
            net,
            references,
        } => {
            let mesh = tessellate_surface(
                surface.as_ref(),
                &SurfaceOptions::uniform(PICTURE_SAMPLES, PICTURE_SAMPLES),
            )?;
            let mut scene = Scene::new(title, subtitle)
                .view(opts.view)
                .size(opts.size)
                .solid(&mesh);
            if let (Some((rows, cols, points)), true) = (net, opts.net) {
                scene = scene.overlay(Overlay::Net {
                    points: points.clone(),
                    rows: *rows,
                    cols: *cols,
                    color: palette::NEW_VERTEX,
                    legend: format!("control net, {rows}×{cols}"),
                });
            }
            if !references.is_empty() {
                scene = scene.overlay(Overlay::Points {
                    points: references.clone(),
                    color: "#222222",
                    radius: 2.4,
                    labels: Vec::new(),
                    legend: format!("{} points it passes through", references.len()),
                });
            }
            Ok(scene.render())
        }
    }
}

/// A curve picture: the adaptive polyline, the control polygon with labels, the reference
/// points. 1-D curves are graphs over the parameter, 3-D ones in the axonometric `view`.
pub fn curve_svg(
    curve: &dyn Curve,
    control: Option<&(Vec<Vec<f64>>, Vec<f64>)>,
    references: &[(f64, Vec<f64>)],
    title: &str,
    subtitle: &str,
    view: View,
) -> Result<String> {
    let dim = curve.dim();
    let page = |t: f64, p: &[f64]| -> [f64; 2] {
        match dim {
            1 => [t, p[0]],
            2 => [p[0], p[1]],
            _ => view.project(p),
        }
    };
    let axes = match dim {
        1 => Axes::Chart {
            x: "t".into(),
            y: "x".into(),
        },
        2 => Axes::Equal,
        3 => Axes::Bare,
        d => {
            return Err(crate::Error::Unsupported(format!(
                "cannot draw a curve in R^{d} (pictures need 1-, 2- or 3-D points)"
            )))
        }
    };
    let line = tessellate_curve(curve, &CurveOptions::default())?;
    let mut fig = Figure::new(title, axes).subtitle(subtitle);
    let pts: Vec<[f64; 2]> = (0..line.len())
        .map(|k| page(line.params()[k], line.point(k)))
        .collect();
    if let Some((points, ts)) = control {
        let poly: Vec<[f64; 2]> = points.iter().zip(ts).map(|(p, &t)| page(t, p)).collect();
        let n = poly.len().max(1) as f64;
        let c = poly
            .iter()
            .fold([0.0, 0.0], |a, p| [a[0] + p[0] / n, a[1] + p[1] / n]);
        add_polygon(
            &mut fig,
            &poly,
            palette::NEW_POLYGON,
            palette::NEW_VERTEX,
            "p",
            true,
            c,
        );
        fig.legend(
            palette::NEW_POLYGON,
            Some(palette::NEW_VERTEX),
            format!("control polygon, {} points", poly.len()),
        );
    }
    fig.line(pts, palette::CURVE);
    fig.legend(palette::CURVE, None, "curve");
    if !references.is_empty() {
        let dots: Vec<[f64; 2]> = references.iter().map(|(t, p)| page(*t, p)).collect();
        fig.dots(dots, 3.6, "#222222");
        fig.legend(
            Stroke::solid("#222222", 0.0),
            Some("#222222"),
            format!("{} points it passes through", references.len()),
        );
    }
    Ok(fig.render())
}
