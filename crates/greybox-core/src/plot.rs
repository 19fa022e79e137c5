//! Minimal self-contained SVG plots (no fonts or system libraries needed): predicted vs
//! measured scatter, a μ surface as a heat map over two features, and line plots (linear or
//! logarithmic y, with shaded x bands) for spectra.

use crate::escape::xml_text as escape;
use std::fmt::Write as _;

const W: f64 = 640.0;
const H: f64 = 480.0;
const ML: f64 = 70.0;
const MR: f64 = 30.0;
const MT: f64 = 40.0;
const MB: f64 = 60.0;

/// About five round tick values covering `lo..=hi`.
pub fn nice_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let span = (hi - lo).max(1e-12);
    let raw = span / 5.0;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 2.5, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| span / s <= 6.0)
        .unwrap_or(10.0 * mag);
    let start = (lo / step).ceil() * step;
    (0..20)
        .map(|k| start + k as f64 * step)
        .take_while(|v| *v <= hi + 1e-9 * span)
        .collect()
}

fn frame(svg: &mut String, title: &str, xl: &str, yl: &str, x: (f64, f64), y: (f64, f64)) {
    let (title, xl, yl) = (escape(title), escape(xl), escape(yl));
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12"><rect width="{W}" height="{H}" fill="white"/><text x="{ML}" y="26" font-size="15">{title}</text><text x="{}" y="{}" text-anchor="middle">{xl}</text><text transform="translate(18,{}) rotate(-90)" text-anchor="middle">{yl}</text><rect x="{ML}" y="{MT}" width="{}" height="{}" fill="none" stroke="black"/>"#,
        ML + (W - ML - MR) / 2.0,
        H - 15.0,
        MT + (H - MT - MB) / 2.0,
        W - ML - MR,
        H - MT - MB
    );
    for t in nice_ticks(x.0, x.1) {
        let px = sx(t, x);
        let _ = write!(
            svg,
            r#"<line x1="{px:.1}" y1="{}" x2="{px:.1}" y2="{}" stroke="black"/><text x="{px:.1}" y="{}" text-anchor="middle">{}</text>"#,
            H - MB,
            H - MB + 5.0,
            H - MB + 18.0,
            fmt(t)
        );
    }
    for t in nice_ticks(y.0, y.1) {
        let py = sy(t, y);
        let _ = write!(
            svg,
            r#"<line x1="{}" y1="{py:.1}" x2="{ML}" y2="{py:.1}" stroke="black"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"#,
            ML - 5.0,
            ML - 8.0,
            py + 4.0,
            fmt(t)
        );
    }
}

/// A tick label: at most four decimals, trailing zeros dropped.
pub fn fmt(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() || s == "-" {
        "0".into()
    } else {
        s.to_string()
    }
}

fn sx(v: f64, r: (f64, f64)) -> f64 {
    ML + (v - r.0) / (r.1 - r.0).max(1e-300) * (W - ML - MR)
}
fn sy(v: f64, r: (f64, f64)) -> f64 {
    H - MB - (v - r.0) / (r.1 - r.0).max(1e-300) * (H - MT - MB)
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let pad = (hi - lo).max(1e-9) * 0.05;
    (lo - pad, hi + pad)
}

/// Scatter of predictions against measurements with the identity line; `series` are
/// (label, colour, measured, predicted).
pub fn predicted_vs_measured(
    title: &str,
    unit_label: &str,
    series: &[(&str, &str, &[f64], &[f64])],
) -> String {
    let all = series
        .iter()
        .flat_map(|(_, _, m, p)| m.iter().chain(p.iter()).copied());
    let r = range(all);
    let mut svg = String::new();
    frame(
        &mut svg,
        title,
        &format!("measured {unit_label}"),
        &format!("predicted {unit_label}"),
        r,
        r,
    );
    let _ = write!(
        svg,
        r#"<line x1="{:.1}" y1="{:.1}" x2="{:.1}" y2="{:.1}" stroke="gray" stroke-dasharray="4,3"/>"#,
        sx(r.0, r),
        sy(r.0, r),
        sx(r.1, r),
        sy(r.1, r)
    );
    for (k, (label, colour, m, p)) in series.iter().enumerate() {
        for (a, b) in m.iter().zip(p.iter()) {
            let _ = write!(
                svg,
                r#"<circle cx="{:.1}" cy="{:.1}" r="2.5" fill="{colour}" fill-opacity="0.7"/>"#,
                sx(*a, r),
                sy(*b, r)
            );
        }
        let ly = MT + 16.0 + 16.0 * k as f64;
        let _ = write!(
            svg,
            r#"<circle cx="{}" cy="{ly}" r="4" fill="{colour}"/><text x="{}" y="{}">{label}</text>"#,
            ML + 14.0,
            ML + 24.0,
            ly + 4.0
        );
    }
    svg.push_str("</svg>\n");
    svg
}

/// Heat map of `f(x, y)` on a grid with a colour bar, and points (black dots).
#[allow(clippy::too_many_arguments)]
pub fn surface(
    title: &str,
    x_label: &str,
    y_label: &str,
    z_label: &str,
    xr: (f64, f64),
    yr: (f64, f64),
    f: &dyn Fn(f64, f64) -> f64,
    points: &[(f64, f64)],
) -> String {
    heatmap(&Heatmap {
        title,
        x_label,
        y_label,
        z_label,
        x_range: xr,
        y_range: yr,
        background: Some(f),
        points,
        point_values: None,
        boxes: &[],
    })
}

/// A map over two variables: an optional background `f(x, y)` shaded with viridis, points
/// (coloured by `point_values` on the same scale, else black) and labelled rectangles
/// (e.g. a model's training domain).
pub struct Heatmap<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    /// What the colour shows, with its unit.
    pub z_label: &'a str,
    pub x_range: (f64, f64),
    pub y_range: (f64, f64),
    pub background: Option<&'a dyn Fn(f64, f64) -> f64>,
    pub points: &'a [(f64, f64)],
    pub point_values: Option<&'a [f64]>,
    /// Rectangles drawn as dashed outlines.
    pub boxes: &'a [LabelledBox<'a>],
}

/// A rectangle on a map: (x range, y range, label).
pub type LabelledBox<'a> = ((f64, f64), (f64, f64), &'a str);

/// Draws a [`Heatmap`] as SVG.
pub fn heatmap(h: &Heatmap) -> String {
    let (xr, yr) = (h.x_range, h.y_range);
    let (nx, ny) = (60, 45);
    let z: Vec<f64> = match h.background {
        Some(f) => (0..nx * ny)
            .map(|k| {
                let (i, j) = (k % nx, k / nx);
                let xv = xr.0 + (i as f64 + 0.5) / nx as f64 * (xr.1 - xr.0);
                let yv = yr.0 + (j as f64 + 0.5) / ny as f64 * (yr.1 - yr.0);
                f(xv, yv)
            })
            .collect(),
        None => Vec::new(),
    };
    let values = z
        .iter()
        .chain(h.point_values.unwrap_or(&[]).iter())
        .filter(|v| v.is_finite());
    let (zlo, zhi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(*v), b.max(*v))
    });
    let (zlo, zhi) = if zlo.is_finite() {
        (zlo, zhi)
    } else {
        (0.0, 1.0)
    };
    let t = |v: f64| (v - zlo) / (zhi - zlo).max(1e-300);
    let mut svg = String::new();
    frame(&mut svg, h.title, h.x_label, h.y_label, xr, yr);
    let (cw, ch) = ((W - ML - MR) / nx as f64, (H - MT - MB) / ny as f64);
    for (k, v) in z.iter().enumerate() {
        let (i, j) = (k % nx, k / nx);
        let _ = write!(
            svg,
            r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}"/>"#,
            ML + i as f64 * cw,
            H - MB - (j + 1) as f64 * ch,
            cw + 0.3,
            ch + 0.3,
            colour(t(*v))
        );
    }
    for (k, (px, py)) in h.points.iter().enumerate() {
        let (fill, r) = match h.point_values.and_then(|v| v.get(k)) {
            Some(v) => (colour(t(*v)), 4.5),
            None => ("black".to_string(), 2.0),
        };
        let _ = write!(
            svg,
            r#"<circle cx="{:.1}" cy="{:.1}" r="{r}" fill="{fill}" stroke="black" stroke-width="0.6"/>"#,
            sx(*px, xr),
            sy(*py, yr)
        );
    }
    for (bx, by, label) in h.boxes {
        let (x0, x1) = (sx(bx.0, xr), sx(bx.1, xr));
        let (y0, y1) = (sy(by.1, yr), sy(by.0, yr));
        let _ = write!(
            svg,
            r#"<rect x="{x0:.1}" y="{y0:.1}" width="{:.1}" height="{:.1}" fill="none" stroke="white" stroke-width="2.5"/><rect x="{x0:.1}" y="{y0:.1}" width="{:.1}" height="{:.1}" fill="none" stroke="black" stroke-width="1.2" stroke-dasharray="6,3"/><text x="{:.1}" y="{:.1}" font-size="11" stroke="white" stroke-width="3" paint-order="stroke">{}</text>"#,
            x1 - x0,
            y1 - y0,
            x1 - x0,
            y1 - y0,
            x0 + 4.0,
            y0 + 14.0,
            escape(label)
        );
    }
    colour_bar(&mut svg, ColourMap::Viridis, h.z_label, zlo, zhi);
    svg.push_str("</svg>\n");
    svg
}

/// A perceptually uniform colour map whose lightness rises monotonically, so that a
/// figure printed in greyscale still reads (Smith & van der Walt's viridis and inferno,
/// as tabulated by the `colorous` crate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ColourMap {
    Viridis,
    Inferno,
}

impl ColourMap {
    /// The colour at `t` ∈ [0, 1] (clamped) as red, green, blue.
    pub fn rgb(self, t: f64) -> [u8; 3] {
        let g = match self {
            ColourMap::Viridis => colorous::VIRIDIS,
            ColourMap::Inferno => colorous::INFERNO,
        };
        let c = g.eval_continuous(if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            0.0
        });
        [c.r, c.g, c.b]
    }
    /// The colour at `t` as `#rrggbb`.
    pub fn hex(self, t: f64) -> String {
        let [r, g, b] = self.rgb(t);
        format!("#{r:02x}{g:02x}{b:02x}")
    }
}

fn colour(t: f64) -> String {
    ColourMap::Viridis.hex(t)
}

/// A horizontal colour bar in the top margin, right-aligned: `label` with ticks over
/// `lo..=hi`.
fn colour_bar(svg: &mut String, map: ColourMap, label: &str, lo: f64, hi: f64) {
    let (x0, w, y, h) = (W - MR - 220.0, 220.0, 8.0, 9.0);
    let n = 44;
    for k in 0..n {
        let _ = write!(
            svg,
            r#"<rect x="{:.2}" y="{y}" width="{:.2}" height="{h}" fill="{}"/>"#,
            x0 + w * k as f64 / n as f64,
            w / n as f64 + 0.3,
            map.hex((k as f64 + 0.5) / n as f64)
        );
    }
    let _ = write!(
        svg,
        r#"<rect x="{x0}" y="{y}" width="{w}" height="{h}" fill="none" stroke="black" stroke-width="0.5"/><text x="{}" y="{}" text-anchor="end" font-size="11">{}</text>"#,
        x0 - 6.0,
        y + h,
        escape(label)
    );
    for t in nice_ticks(lo, hi) {
        let px = x0 + (t - lo) / (hi - lo).max(1e-300) * w;
        let _ = write!(
            svg,
            r#"<line x1="{px:.1}" y1="{}" x2="{px:.1}" y2="{}" stroke="black" stroke-width="0.5"/><text x="{px:.1}" y="{}" text-anchor="middle" font-size="10">{}</text>"#,
            y + h,
            y + h + 3.0,
            y + h + 13.0,
            fmt(t)
        );
    }
}

/// Dash pattern of the `k`-th line of a plot, so lines stay apart in greyscale.
fn dashes(k: usize) -> &'static str {
    ["none", "7,3", "2,2", "9,3,2,3", "4,4", "12,4"][k % 6]
}

/// One line of a line plot: label, colour, x and y values.
pub struct Line<'a> {
    pub label: &'a str,
    pub colour: &'a str,
    pub x: &'a [f64],
    pub y: &'a [f64],
}

/// Line plot; `log_y` plots log10(y) (non-positive values are skipped); `bands` are shaded
/// x ranges with a label (e.g. an excitation band).
pub fn lines(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Line],
    log_y: bool,
    bands: &[(f64, f64, &str)],
) -> String {
    let ty = |v: f64| {
        if log_y {
            if v > 0.0 {
                Some(v.log10())
            } else {
                None
            }
        } else {
            Some(v)
        }
    };
    let xr = range(series.iter().flat_map(|l| l.x.iter().copied()));
    let yr = range(
        series
            .iter()
            .flat_map(|l| l.y.iter().filter_map(|v| ty(*v))),
    );
    let mut svg = String::new();
    let yl = if log_y {
        format!("log10 {y_label}")
    } else {
        y_label.to_string()
    };
    frame(&mut svg, title, x_label, &yl, xr, yr);
    for (a, b, label) in bands {
        let (x0, x1) = (sx(a.max(xr.0), xr), sx(b.min(xr.1), xr));
        if x1 > x0 {
            let _ = write!(
                svg,
                r#"<rect x="{x0:.1}" y="{MT}" width="{:.1}" height="{}" fill="orange" fill-opacity="0.25"/><text x="{:.1}" y="{}" font-size="10">{label}</text>"#,
                x1 - x0,
                H - MT - MB,
                x0 + 2.0,
                MT + 12.0,
                label = escape(label)
            );
        }
    }
    for (k, l) in series.iter().enumerate() {
        let pts: Vec<String> =
            l.x.iter()
                .zip(l.y.iter())
                .filter_map(|(x, y)| ty(*y).map(|v| format!("{:.1},{:.1}", sx(*x, xr), sy(v, yr))))
                .collect();
        let _ = write!(
            svg,
            r#"<polyline fill="none" stroke="{}" stroke-width="1.4" stroke-dasharray="{}" points="{}"/>"#,
            l.colour,
            dashes(k),
            pts.join(" ")
        );
        let ly = MT + 16.0 + 16.0 * k as f64;
        let _ = write!(
            svg,
            r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{}" stroke-width="2" stroke-dasharray="{}"/><text x="{}" y="{}">{}</text>"#,
            W - MR - 165.0,
            W - MR - 135.0,
            l.colour,
            dashes(k),
            W - MR - 130.0,
            ly + 4.0,
            escape(l.label)
        );
    }
    svg.push_str("</svg>\n");
    svg
}
