//! Minimal self-contained SVG plots (no fonts or system libraries needed): predicted vs
//! measured scatter, a μ surface as a heat map over two features, and line plots (linear or
//! logarithmic y, with shaded x bands) for spectra.

use std::fmt::Write as _;

const W: f64 = 640.0;
const H: f64 = 480.0;
const ML: f64 = 70.0;
const MR: f64 = 30.0;
const MT: f64 = 40.0;
const MB: f64 = 60.0;

fn nice_ticks(lo: f64, hi: f64) -> Vec<f64> {
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
    let _ = write!(
        svg,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" viewBox="0 0 {W} {H}" font-family="sans-serif" font-size="12"><rect width="{W}" height="{H}" fill="white"/><text x="{}" y="24" text-anchor="middle" font-size="15">{title}</text><text x="{}" y="{}" text-anchor="middle">{xl}</text><text transform="translate(18,{}) rotate(-90)" text-anchor="middle">{yl}</text><rect x="{ML}" y="{MT}" width="{}" height="{}" fill="none" stroke="black"/>"#,
        W / 2.0,
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

fn fmt(v: f64) -> String {
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

/// Heat map of `f(x, y)` on a grid with a colour bar.
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
    let (nx, ny) = (60, 45);
    let mut z = vec![0.0; nx * ny];
    for j in 0..ny {
        for i in 0..nx {
            let xv = xr.0 + (i as f64 + 0.5) / nx as f64 * (xr.1 - xr.0);
            let yv = yr.0 + (j as f64 + 0.5) / ny as f64 * (yr.1 - yr.0);
            z[j * nx + i] = f(xv, yv);
        }
    }
    let (zlo, zhi) = z
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let mut svg = String::new();
    frame(&mut svg, title, x_label, y_label, xr, yr);
    let (cw, ch) = ((W - ML - MR) / nx as f64, (H - MT - MB) / ny as f64);
    for j in 0..ny {
        for i in 0..nx {
            let t = (z[j * nx + i] - zlo) / (zhi - zlo).max(1e-300);
            let _ = write!(
                svg,
                r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}"/>"#,
                ML + i as f64 * cw,
                H - MB - (j + 1) as f64 * ch,
                cw + 0.3,
                ch + 0.3,
                colour(t)
            );
        }
    }
    for (px, py) in points {
        let _ = write!(
            svg,
            r#"<circle cx="{:.1}" cy="{:.1}" r="1.8" fill="black"/>"#,
            sx(*px, xr),
            sy(*py, yr)
        );
    }
    let _ = write!(
        svg,
        r#"<text x="{}" y="{}" text-anchor="end">{z_label}: {} (blue) … {} (red)</text>"#,
        W - MR,
        MT - 6.0,
        fmt(zlo),
        fmt(zhi)
    );
    svg.push_str("</svg>\n");
    svg
}

/// Blue → red colour map.
fn colour(t: f64) -> String {
    let t = t.clamp(0.0, 1.0);
    let r = (255.0 * t) as u8;
    let b = (255.0 * (1.0 - t)) as u8;
    let g = (255.0 * (1.0 - (2.0 * t - 1.0).abs()) * 0.8) as u8;
    format!("#{r:02x}{g:02x}{b:02x}")
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
                MT + 12.0
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
            r#"<polyline fill="none" stroke="{}" stroke-width="1.2" points="{}"/>"#,
            l.colour,
            pts.join(" ")
        );
        let ly = MT + 16.0 + 16.0 * k as f64;
        let _ = write!(
            svg,
            r#"<line x1="{}" y1="{ly}" x2="{}" y2="{ly}" stroke="{}" stroke-width="2"/><text x="{}" y="{}">{}</text>"#,
            W - MR - 150.0,
            W - MR - 130.0,
            l.colour,
            W - MR - 125.0,
            ly + 4.0,
            l.label
        );
    }
    svg.push_str("</svg>\n");
    svg
}
