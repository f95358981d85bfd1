//! A small hand-written SVG figure writer: a viewBox fitted to the data (equal aspect ratio
//! for geometry, independent scales for charts), a light grid with tick labels, polylines,
//! markers, subscripted vertex labels (u₀ … uₙ) and a legend. No dependencies.

use std::fmt::Write as _;

/// How a line is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke {
    /// CSS colour.
    pub color: &'static str,
    /// Width in pixels.
    pub width: f64,
    /// `stroke-dasharray`, if dashed.
    pub dash: Option<&'static str>,
    /// Opacity in [0, 1].
    pub opacity: f64,
}

impl Stroke {
    /// A solid line.
    pub const fn solid(color: &'static str, width: f64) -> Self {
        Stroke {
            color,
            width,
            dash: None,
            opacity: 1.0,
        }
    }

    /// A dashed line.
    pub const fn dashed(color: &'static str, width: f64) -> Self {
        Stroke {
            color,
            width,
            dash: Some("5 4"),
            opacity: 1.0,
        }
    }

    /// The same line with another opacity.
    pub const fn with_opacity(mut self, opacity: f64) -> Self {
        self.opacity = opacity;
        self
    }
}

/// The palette of all figures.
pub mod palette {
    use super::Stroke;
    /// The curve or surface itself.
    pub const CURVE: Stroke = Stroke::solid("#1f4e9c", 2.6);
    /// The original control polygon / net.
    pub const OLD_POLYGON: Stroke = Stroke::dashed("#8a8a8a", 1.3);
    /// Vertices and labels of the original polygon.
    pub const OLD_VERTEX: &str = "#6e6e6e";
    /// The new control polygon / net.
    pub const NEW_POLYGON: Stroke = Stroke::solid("#e0661b", 1.5);
    /// Vertices and labels of the new polygon.
    pub const NEW_VERTEX: &str = "#c4520f";
    /// A reference shown faintly behind (the original curve or surface).
    pub const GHOST: Stroke = Stroke::solid("#9fb3d1", 1.6);
    /// Extra series of charts.
    pub const SERIES: [&str; 4] = ["#1f4e9c", "#e0661b", "#2a9d5b", "#b03a8c"];
}

/// A vertex label: a base with a subscript, e.g. u with subscript 3.
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// The base text ("u", "u′").
    pub base: String,
    /// The subscript ("3", "02").
    pub sub: String,
}

impl Label {
    /// A label `base` with subscript `sub`.
    pub fn new(base: &str, sub: impl ToString) -> Self {
        Label {
            base: base.to_string(),
            sub: sub.to_string(),
        }
    }
}

/// Where a label sits relative to its point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Placement {
    /// On the side away from a data point (e.g. the polygon's centroid).
    Away([f64; 2]),
    /// On the side toward a data point.
    Toward([f64; 2]),
}

/// The kind of axes.
#[derive(Debug, Clone, PartialEq)]
pub enum Axes {
    /// Geometry in the plane: equal scales, light grid, tick labels.
    Equal,
    /// A chart: independent scales, grid, axis titles.
    Chart {
        /// Title of the horizontal axis.
        x: String,
        /// Title of the vertical axis.
        y: String,
    },
    /// A projection of 3-D geometry: equal scales, no grid, no ticks.
    Bare,
}

#[derive(Debug, Clone)]
enum LegendKey {
    Line(Stroke, Option<&'static str>),
}

#[derive(Debug, Clone)]
enum Element {
    Line {
        points: Vec<[f64; 2]>,
        stroke: Stroke,
    },
    Dots {
        points: Vec<[f64; 2]>,
        radius: f64,
        fill: &'static str,
    },
    Labels {
        items: Vec<([f64; 2], Label)>,
        color: &'static str,
        placement: Placement,
    },
    Rects {
        cells: Vec<Cell>,
    },
    Segments {
        segments: Vec<[[f64; 2]; 2]>,
        stroke: Stroke,
    },
}

/// A filled axis-aligned rectangle in data coordinates (a cell of a height map).
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// One corner.
    pub from: [f64; 2],
    /// The opposite corner.
    pub to: [f64; 2],
    /// CSS colour ("#1f4e9c").
    pub fill: String,
}

/// A figure under construction; [`Figure::render`] turns it into SVG text.
#[derive(Debug, Clone)]
pub struct Figure {
    title: String,
    subtitle: Option<String>,
    axes: Axes,
    width: f64,
    elements: Vec<Element>,
    legend: Vec<(LegendKey, String)>,
}

const FONT: &str = "system-ui, -apple-system, 'Segoe UI', Helvetica, Arial, sans-serif";

impl Figure {
    /// An empty figure, 640 px wide.
    pub fn new(title: impl Into<String>, axes: Axes) -> Self {
        Figure {
            title: title.into(),
            subtitle: None,
            axes,
            width: 640.0,
            elements: Vec::new(),
            legend: Vec::new(),
        }
    }

    /// Sets a smaller second title line.
    pub fn subtitle(mut self, text: impl Into<String>) -> Self {
        self.subtitle = Some(text.into());
        self
    }

    /// A polyline through `points`.
    pub fn line(&mut self, points: Vec<[f64; 2]>, stroke: Stroke) {
        self.elements.push(Element::Line { points, stroke });
    }

    /// Filled circles of `radius` px at `points`.
    pub fn dots(&mut self, points: Vec<[f64; 2]>, radius: f64, fill: &'static str) {
        self.elements.push(Element::Dots {
            points,
            radius,
            fill,
        });
    }

    /// Text labels at points.
    pub fn labels(
        &mut self,
        items: Vec<([f64; 2], Label)>,
        color: &'static str,
        placement: Placement,
    ) {
        self.elements.push(Element::Labels {
            items,
            color,
            placement,
        });
    }

    /// Filled rectangles, drawn without outlines or antialiased seams.
    pub fn rects(&mut self, cells: Vec<Cell>) {
        self.elements.push(Element::Rects { cells });
    }

    /// Separate line segments (contour lines), drawn as one path.
    pub fn segments(&mut self, segments: Vec<[[f64; 2]; 2]>, stroke: Stroke) {
        self.elements.push(Element::Segments { segments, stroke });
    }

    /// A legend entry: a line sample (with a vertex dot if `dot` is a colour) and its text.
    pub fn legend(&mut self, stroke: Stroke, dot: Option<&'static str>, text: impl Into<String>) {
        self.legend
            .push((LegendKey::Line(stroke, dot), text.into()));
    }

    fn bounds(&self) -> [f64; 4] {
        let mut b = [
            f64::INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
        ];
        let mut add = |p: &[f64; 2]| {
            if p[0].is_finite() && p[1].is_finite() {
                b[0] = b[0].min(p[0]);
                b[1] = b[1].min(p[1]);
                b[2] = b[2].max(p[0]);
                b[3] = b[3].max(p[1]);
            }
        };
        for e in &self.elements {
            match e {
                Element::Line { points, .. } | Element::Dots { points, .. } => {
                    points.iter().for_each(&mut add)
                }
                Element::Labels { items, .. } => items.iter().for_each(|(p, _)| add(p)),
                Element::Rects { cells } => cells.iter().for_each(|c| {
                    add(&c.from);
                    add(&c.to);
                }),
                Element::Segments { segments, .. } => segments.iter().flatten().for_each(&mut add),
            }
        }
        if !b[0].is_finite() {
            return [0.0, 0.0, 1.0, 1.0];
        }
        b
    }

    /// The SVG document. Data near the ends of f64 (beyond 1e300 or below 1e-300 in
    /// magnitude) is drawn scaled by a power of ten, its tick labels carrying the exponent
    /// ("1.5e308"), so that no layout quantity overflows or loses its digits.
    pub fn render(&self) -> String {
        let bounds = self.bounds();
        let scale = Scale::of(&bounds);
        let [mut x0, mut y0, mut x1, mut y1] = bounds.map(|v| scale.apply(v));
        let ticks = !matches!(self.axes, Axes::Bare);
        let chart = matches!(self.axes, Axes::Chart { .. });
        let ml = if chart {
            70.0
        } else if ticks {
            48.0
        } else {
            18.0
        } + if ticks && scale.exponent != 0 {
            30.0
        } else {
            0.0
        };
        let mr = 18.0;
        let mt = if self.subtitle.is_some() { 52.0 } else { 34.0 };
        let plot_w = self.width - ml - mr;

        // Data range with padding; degenerate ranges get a unit size.
        let (dx, dy) = ((x1 - x0).max(0.0), (y1 - y0).max(0.0));
        let size = dx.max(dy).max(f64::MIN_POSITIVE);
        let plot_h;
        if chart {
            let pad_y = if dy > 0.0 { 0.06 * dy } else { 0.5 };
            y0 -= pad_y;
            y1 += pad_y;
            let pad_x = if dx > 0.0 { 0.025 * dx } else { 0.5 };
            x0 -= pad_x;
            x1 += pad_x;
            plot_h = (0.55 * plot_w).round();
        } else {
            let pad = 0.07 * size + if size == f64::MIN_POSITIVE { 1.0 } else { 0.0 };
            x0 -= pad;
            x1 += pad;
            y0 -= pad;
            y1 += pad;
            let (dx, dy) = (x1 - x0, y1 - y0);
            let h = plot_w * dy / dx;
            let (lo, hi) = (0.42 * plot_w, 1.0 * plot_w);
            if h < lo {
                // Too flat: widen the y range around its centre.
                let c = 0.5 * (y0 + y1);
                let half = 0.5 * dx * lo / plot_w;
                (y0, y1) = (c - half, c + half);
                plot_h = lo;
            } else if h > hi {
                // Too tall: widen the x range.
                let c = 0.5 * (x0 + x1);
                let half = 0.5 * dy * plot_w / hi;
                (x0, x1) = (c - half, c + half);
                plot_h = hi;
            } else {
                plot_h = h;
            }
        }
        let sx = plot_w / (x1 - x0);
        let sy = plot_h / (y1 - y0);
        let map = |p: &[f64; 2]| {
            let (x, y) = (scale.apply(p[0]), scale.apply(p[1]));
            [ml + (x - x0) * sx, mt + plot_h - (y - y0) * sy]
        };

        // Legend layout below the plot, flowing in rows.
        let legend_top =
            mt + plot_h + if ticks { 34.0 } else { 14.0 } + if chart { 14.0 } else { 0.0 };
        let mut legend_items = Vec::new();
        let (mut lx, mut ly) = (ml, legend_top);
        for (key, text) in &self.legend {
            let w = 34.0 + 6.6 * text.chars().count() as f64 + 22.0;
            if lx + w > self.width - mr && lx > ml {
                lx = ml;
                ly += 20.0;
            }
            legend_items.push((lx, ly, key, text));
            lx += w;
        }
        let height = if self.legend.is_empty() {
            legend_top
        } else {
            ly + 18.0
        };

        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w:.0}" height="{h:.0}" viewBox="0 0 {w:.0} {h:.0}" font-family="{FONT}">"#,
            w = self.width,
            h = height.ceil()
        );
        let _ = writeln!(s, r##"<rect width="100%" height="100%" fill="#ffffff"/>"##);
        let _ = writeln!(
            s,
            r##"<text x="{ml:.1}" y="22" font-size="15" font-weight="600" fill="#222">{}</text>"##,
            escape(&self.title)
        );
        if let Some(sub) = &self.subtitle {
            let _ = writeln!(
                s,
                r##"<text x="{ml:.1}" y="40" font-size="12" fill="#666">{}</text>"##,
                escape(sub)
            );
        }

        if ticks {
            let (stx, sty) = if chart {
                (nice_step(x1 - x0, 6.0), nice_step(y1 - y0, 5.0))
            } else {
                let st = nice_step((x1 - x0).max(y1 - y0), 7.0);
                (st, st)
            };
            let _ = writeln!(s, r##"<g stroke="#ececec" stroke-width="1">"##);
            for x in tick_values(x0, x1, stx) {
                let px = ml + (x - x0) * sx;
                let _ = writeln!(
                    s,
                    r#"<line x1="{px:.2}" y1="{mt:.2}" x2="{px:.2}" y2="{:.2}"/>"#,
                    mt + plot_h
                );
            }
            for y in tick_values(y0, y1, sty) {
                let py = mt + plot_h - (y - y0) * sy;
                let _ = writeln!(
                    s,
                    r#"<line x1="{ml:.2}" y1="{py:.2}" x2="{:.2}" y2="{py:.2}"/>"#,
                    ml + plot_w
                );
            }
            let _ = writeln!(s, "</g>");
            let _ = writeln!(
                s,
                r##"<rect x="{ml:.2}" y="{mt:.2}" width="{plot_w:.2}" height="{plot_h:.2}" fill="none" stroke="#d4d4d4"/>"##
            );
            let _ = writeln!(s, r##"<g font-size="10" fill="#8a8a8a">"##);
            for x in tick_values(x0, x1, stx) {
                let px = ml + (x - x0) * sx;
                let _ = writeln!(
                    s,
                    r#"<text x="{px:.2}" y="{:.2}" text-anchor="middle">{}</text>"#,
                    mt + plot_h + 14.0,
                    scale.label(tick_label(x, stx))
                );
            }
            for y in tick_values(y0, y1, sty) {
                let py = mt + plot_h - (y - y0) * sy;
                let _ = writeln!(
                    s,
                    r#"<text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"#,
                    ml - 6.0,
                    py + 3.5,
                    scale.label(tick_label(y, sty))
                );
            }
            let _ = writeln!(s, "</g>");
            if let Axes::Chart { x, y } = &self.axes {
                let _ = writeln!(
                    s,
                    r##"<text x="{:.2}" y="{:.2}" font-size="12" fill="#555" text-anchor="middle">{}</text>"##,
                    ml + 0.5 * plot_w,
                    mt + plot_h + 32.0,
                    escape(x)
                );
                let (tx, ty) = (16.0, mt + 0.5 * plot_h);
                let _ = writeln!(
                    s,
                    r##"<text x="{tx:.2}" y="{ty:.2}" font-size="12" fill="#555" text-anchor="middle" transform="rotate(-90 {tx:.2} {ty:.2})">{}</text>"##,
                    escape(y)
                );
            }
        }

        for e in &self.elements {
            match e {
                Element::Line { points, stroke } => {
                    let pts: Vec<String> = points
                        .iter()
                        .filter(|p| p[0].is_finite() && p[1].is_finite())
                        .map(|p| {
                            let q = map(p);
                            format!("{:.2},{:.2}", q[0], q[1])
                        })
                        .collect();
                    let _ = writeln!(
                        s,
                        r#"<polyline points="{}" {}/>"#,
                        pts.join(" "),
                        stroke_attrs(stroke)
                    );
                }
                Element::Dots {
                    points,
                    radius,
                    fill,
                } => {
                    let _ = writeln!(
                        s,
                        r##"<g fill="{fill}" stroke="#ffffff" stroke-width="1">"##
                    );
                    for p in points {
                        let q = map(p);
                        if !(q[0].is_finite() && q[1].is_finite()) {
                            continue;
                        }
                        let _ = writeln!(
                            s,
                            r#"<circle cx="{:.2}" cy="{:.2}" r="{radius}"/>"#,
                            q[0], q[1]
                        );
                    }
                    let _ = writeln!(s, "</g>");
                }
                Element::Rects { cells } => {
                    let _ = writeln!(s, r#"<g shape-rendering="crispEdges">"#);
                    for c in cells {
                        let (a, b) = (map(&c.from), map(&c.to));
                        let _ = writeln!(
                            s,
                            r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}"/>"#,
                            a[0].min(b[0]),
                            a[1].min(b[1]),
                            // Overlap the neighbours by 0.6 px: crisp edges round x and
                            // width separately and would otherwise leave hairline gaps.
                            (b[0] - a[0]).abs() + 0.6,
                            (b[1] - a[1]).abs() + 0.6,
                            escape(&c.fill)
                        );
                    }
                    let _ = writeln!(s, "</g>");
                }
                Element::Segments { segments, stroke } => {
                    let mut d = String::new();
                    for [p, q] in segments {
                        let (a, b) = (map(p), map(q));
                        if a.iter().chain(&b).all(|v| v.is_finite()) {
                            let _ = write!(d, "M{:.1} {:.1}L{:.1} {:.1}", a[0], a[1], b[0], b[1]);
                        }
                    }
                    let _ = writeln!(s, r#"<path d="{d}" {}/>"#, stroke_attrs(stroke));
                }
                Element::Labels {
                    items,
                    color,
                    placement,
                } => {
                    let _ = writeln!(
                        s,
                        r##"<g font-size="13" fill="{color}" font-style="italic" text-anchor="middle" stroke="#ffffff" stroke-width="3" stroke-linejoin="round" paint-order="stroke">"##
                    );
                    for (p, label) in items {
                        let q = map(p);
                        if !(q[0].is_finite() && q[1].is_finite()) {
                            continue;
                        }
                        let (c, sign) = match placement {
                            Placement::Away(c) => (map(c), 1.0),
                            Placement::Toward(c) => (map(c), -1.0),
                        };
                        let (vx, vy) = (q[0] - c[0], q[1] - c[1]);
                        let len = vx.hypot(vy);
                        // Coincident with the centre, or a centre that overflowed (the mean
                        // of points near f64::MAX): above the point.
                        let (vx, vy) = if !(len >= 1e-9 && len.is_finite()) {
                            (0.0, -1.0)
                        } else {
                            (vx / len, vy / len)
                        };
                        let (ox, oy) = (13.0 * sign * vx, 13.0 * sign * vy);
                        let _ = writeln!(
                            s,
                            r#"<text x="{:.2}" y="{:.2}">{}<tspan dy="4" font-size="9.5">{}</tspan></text>"#,
                            q[0] + ox,
                            q[1] + oy + 4.0,
                            escape(&label.base),
                            escape(&label.sub)
                        );
                    }
                    let _ = writeln!(s, "</g>");
                }
            }
        }

        if !legend_items.is_empty() {
            let _ = writeln!(s, r##"<g font-size="12" fill="#333">"##);
            for (x, y, key, text) in legend_items {
                let LegendKey::Line(stroke, dot) = key;
                let _ = writeln!(
                    s,
                    r#"<line x1="{x:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" {}/>"#,
                    x + 26.0,
                    stroke_attrs(stroke)
                );
                if let Some(fill) = dot {
                    let _ = writeln!(
                        s,
                        r#"<circle cx="{:.1}" cy="{y:.1}" r="3" fill="{fill}"/>"#,
                        x + 13.0
                    );
                }
                let _ = writeln!(
                    s,
                    r#"<text x="{:.1}" y="{:.1}">{}</text>"#,
                    x + 32.0,
                    y + 4.0,
                    escape(text)
                );
            }
            let _ = writeln!(s, "</g>");
        }
        s.push_str("</svg>\n");
        s
    }
}

fn stroke_attrs(stroke: &Stroke) -> String {
    let mut a = format!(
        r#"fill="none" stroke="{}" stroke-width="{}" stroke-linejoin="round" stroke-linecap="round""#,
        stroke.color, stroke.width
    );
    if let Some(d) = stroke.dash {
        let _ = write!(a, r#" stroke-dasharray="{d}""#);
    }
    if stroke.opacity < 1.0 {
        let _ = write!(a, r#" stroke-opacity="{}""#, stroke.opacity);
    }
    a
}

/// Escapes text for XML.
pub fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `target` ticks.
/// The power of ten that brings a figure's data into a safe range: 10^-exponent applied as
/// two factors (each a normal f64 even where 10^-exponent alone would not be).
#[derive(Debug, Clone, Copy)]
struct Scale {
    exponent: i32,
    factors: [f64; 2],
}

impl Scale {
    /// The scale of data within `bounds` ([x0, y0, x1, y1]): 1 unless the largest magnitude
    /// is beyond 1e300 or (nonzero) below 1e-300.
    fn of(bounds: &[f64; 4]) -> Scale {
        let m = bounds.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let exponent = if m > 1e300 || (m > 0.0 && m < 1e-300) {
            m.log10().floor() as i32
        } else {
            0
        };
        let half = -exponent / 2;
        Scale {
            exponent,
            factors: [10f64.powi(half), 10f64.powi(-exponent - half)],
        }
    }

    fn apply(&self, v: f64) -> f64 {
        if self.exponent == 0 {
            v
        } else {
            v * self.factors[0] * self.factors[1]
        }
    }

    /// A tick label of a scaled value, with the exponent.
    fn label(&self, text: String) -> String {
        if self.exponent == 0 || text == "0" {
            text
        } else {
            format!("{text}e{}", self.exponent)
        }
    }
}

fn nice_step(range: f64, target: f64) -> f64 {
    if !range.is_finite() || range <= 0.0 {
        return 1.0;
    }
    let raw = range / target;
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let nice = if f < 1.5 {
        1.0
    } else if f < 3.5 {
        2.0
    } else if f < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

fn tick_values(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    if last < first || last.saturating_sub(first) > 1000 {
        return Vec::new();
    }
    (first..=last).map(|k| k as f64 * step).collect()
}

fn tick_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10().floor()).max(0.0) as usize;
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(10.0, 5.0), 2.0);
        assert_eq!(nice_step(1.0, 7.0), 0.1);
        assert_eq!(nice_step(30.0, 7.0), 5.0);
        assert_eq!(tick_label(-0.0000001, 0.1), "0");
        assert_eq!(tick_label(2.5, 0.5), "2.5");
    }

    #[test]
    fn data_at_the_ends_of_f64_is_drawn_scaled() {
        for (big, exponent) in [(1.7e308, "e308"), (3e-310, "e-310"), (f64::MAX, "e308")] {
            let mut f = Figure::new("extreme", Axes::Equal);
            f.line(vec![[-big, 0.0], [big, big], [0.0, -big]], palette::CURVE);
            f.dots(vec![[big, big]], 3.0, palette::OLD_VERTEX);
            let svg = f.render();
            assert!(!svg.contains("NaN") && !svg.contains("inf"), "{big}: {svg}");
            assert!(svg.contains(exponent), "{big}: no {exponent} tick label");
            // The polyline spans the plot: its x coordinates differ by hundreds of pixels.
            let line = svg.lines().find(|l| l.starts_with("<polyline")).unwrap();
            let xs: Vec<f64> = line
                .split('"')
                .nth(1)
                .unwrap()
                .split(' ')
                .map(|p| p.split(',').next().unwrap().parse().unwrap())
                .collect();
            assert!(xs[1] - xs[0] > 300.0, "{big}: {xs:?}");
        }
    }

    #[test]
    fn renders_a_figure() {
        let mut f = Figure::new("A <test>", Axes::Equal).subtitle("sub");
        f.line(vec![[0.0, 0.0], [1.0, 2.0]], palette::CURVE);
        f.dots(vec![[0.0, 0.0]], 3.0, palette::OLD_VERTEX);
        f.labels(
            vec![([0.0, 0.0], Label::new("u", 0))],
            palette::OLD_VERTEX,
            Placement::Away([0.5, 1.0]),
        );
        f.legend(palette::CURVE, None, "curve");
        let svg = f.render();
        assert!(svg.starts_with("<svg"));
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("A &lt;test&gt;"));
        assert!(svg.contains("<polyline"));
        assert!(!svg.contains("NaN"));
    }

    #[test]
    fn degenerate_data_does_not_break() {
        let mut f = Figure::new("point", Axes::Equal);
        f.dots(vec![[1.0, 1.0]], 3.0, "#000");
        let svg = f.render();
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        let mut f = Figure::new(
            "flat chart",
            Axes::Chart {
                x: "t".into(),
                y: "v".into(),
            },
        );
        f.line(vec![[0.0, 0.0], [1.0, 0.0]], palette::CURVE);
        let svg = f.render();
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }
}
