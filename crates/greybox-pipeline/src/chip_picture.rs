//! Pictures of the chip without ParaView: the workpiece's particles coloured by
//! temperature or by equivalent plastic strain, the tool drawn in, axes in mm and a colour
//! bar. Each picture is one self-contained SVG: the particles are a PNG raster embedded in
//! it (a few tens of kB, where one SVG circle per particle would be megabytes), the tool,
//! axes and labels are vector graphics.
//!
//! [`FrameRecorder`] captures the particle state at evenly spaced times of a cut (`--frames
//! N`); [`write_chip_pictures`] draws a run's frames on one common view and colour scale,
//! so that a strip of them shows the chip forming.

use anyhow::{Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::escape::xml_text as escape;
use greybox_core::plot::{fmt, nice_ticks, ColourMap};
use greybox_sim::output::tool_outline;
use greybox_sim::particles::spacing_factor;
use greybox_sim::{Control, Observer, SavedState, SimError, Solver};
use serde::{Deserialize, Serialize};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The particle state of one instant, for pictures (single precision is plenty there).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChipFrame {
    /// Simulated time, s.
    pub time_s: f64,
    /// Particle positions, m.
    pub x: Vec<f32>,
    pub y: Vec<f32>,
    /// Temperature, K.
    pub temperature_k: Vec<f32>,
    /// Equivalent plastic strain.
    pub plastic_strain: Vec<f32>,
    /// Initial particle spacing, m (of the level-0 particles).
    pub spacing_m: f64,
    /// Refinement level of each particle (spacing `spacing_m`/2ˡ); empty when none was
    /// refined.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub level: Vec<u8>,
    /// Each tool's outline, m.
    pub tools: Vec<Vec<[f64; 2]>>,
}

impl ChipFrame {
    /// The solver's state now.
    pub fn capture(sim: &Solver) -> Self {
        let p = &sim.particles;
        let f = |v: &[f64]| v.iter().map(|&a| a as f32).collect();
        ChipFrame {
            time_s: sim.time,
            x: f(&p.x),
            y: f(&p.y),
            temperature_k: f(&p.temp),
            plastic_strain: f(&p.eps_p),
            spacing_m: p.spacing,
            level: if p.is_refined() {
                p.level.clone()
            } else {
                Vec::new()
            },
            tools: sim.tools.iter().map(|t| tool_outline(t, 720)).collect(),
        }
    }
}

/// What a picture colours the particles by.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ChipField {
    /// Temperature, shown in °C (inferno).
    Temperature,
    /// Equivalent plastic strain (viridis).
    PlasticStrain,
}

impl ChipField {
    fn label(self) -> &'static str {
        match self {
            ChipField::Temperature => "temperature (°C)",
            ChipField::PlasticStrain => "equivalent plastic strain (-)",
        }
    }
    /// The file name stem.
    pub fn stem(self) -> &'static str {
        match self {
            ChipField::Temperature => "temperature",
            ChipField::PlasticStrain => "plastic_strain",
        }
    }
    fn map(self) -> ColourMap {
        match self {
            ChipField::Temperature => ColourMap::Inferno,
            ChipField::PlasticStrain => ColourMap::Viridis,
        }
    }
    /// Particle `i`'s value in display units.
    fn value(self, f: &ChipFrame, i: usize) -> f64 {
        match self {
            ChipField::Temperature => f.temperature_k[i] as f64 - 273.15,
            ChipField::PlasticStrain => f.plastic_strain[i] as f64,
        }
    }
    /// The colour scale for a set of frames: temperature from the lowest to the highest
    /// value; plastic strain from 0 to its 99.5th percentile in the last frame (a few
    /// particles at the tool's edge reach strains that would wash out the chip).
    pub fn range(self, frames: &[ChipFrame]) -> (f64, f64) {
        let (lo, hi) = match self {
            ChipField::Temperature => frames
                .iter()
                .flat_map(|f| (0..f.x.len()).map(move |i| self.value(f, i)))
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                }),
            ChipField::PlasticStrain => {
                let mut v: Vec<f64> = frames
                    .last()
                    .map(|f| (0..f.x.len()).map(|i| self.value(f, i)).collect())
                    .unwrap_or_default();
                v.retain(|a| a.is_finite());
                v.sort_by(|a, b| a.total_cmp(b));
                let hi = v
                    .get(((v.len() as f64 - 1.0) * 0.995).round().max(0.0) as usize)
                    .copied();
                (0.0, hi.unwrap_or(1.0))
            }
        };
        if lo.is_finite() && hi > lo {
            (lo, hi)
        } else if lo.is_finite() {
            (lo, lo + 1.0)
        } else {
            (0.0, 1.0)
        }
    }
}

/// The region a set of pictures shows, m: every particle of every frame, with a margin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub x: (f64, f64),
    pub y: (f64, f64),
}

impl View {
    pub fn covering(frames: &[ChipFrame]) -> View {
        let mut x = (f64::INFINITY, f64::NEG_INFINITY);
        let mut y = x;
        for f in frames {
            for (a, b) in f.x.iter().zip(&f.y) {
                if a.is_finite() && b.is_finite() {
                    x = (x.0.min(*a as f64), x.1.max(*a as f64));
                    y = (y.0.min(*b as f64), y.1.max(*b as f64));
                }
            }
        }
        if !x.0.is_finite() {
            return View {
                x: (0.0, 1e-3),
                y: (0.0, 1e-3),
            };
        }
        let m = 0.04 * (x.1 - x.0).max(y.1 - y.0).max(1e-9);
        View {
            x: (x.0 - m, x.1 + m),
            y: (y.0 - m, y.1 + 3.0 * m),
        }
    }
}

/// Pixel layout of a picture: plot area size from the view's aspect ratio.
struct Layout {
    w: u32,
    h: u32,
    /// Pixels per metre.
    scale: f64,
}

const LEFT: f64 = 70.0;
const RIGHT: f64 = 110.0;
const TOP: f64 = 40.0;
const BOTTOM: f64 = 50.0;

impl Layout {
    fn for_view(v: &View) -> Layout {
        let (dx, dy) = (v.x.1 - v.x.0, v.y.1 - v.y.0);
        let mut scale = 860.0 / dx;
        if dy * scale > 520.0 {
            scale = 520.0 / dy;
        }
        Layout {
            w: (dx * scale).round().max(1.0) as u32,
            h: (dy * scale).round().max(1.0) as u32,
            scale,
        }
    }
}

/// The particles as an RGBA raster, each a disc of the particle's spacing.
fn raster(f: &ChipFrame, field: ChipField, view: &View, l: &Layout, range: (f64, f64)) -> Vec<u8> {
    let (w, h) = (l.w as i64, l.h as i64);
    let mut px = vec![0u8; (w * h * 4) as usize];
    // radius 0.75 Δx: discs on the initial lattice overlap and leave no gaps (> Δx/√2); a
    // refined particle's Δx is its own
    let radius = |i: usize| {
        let dx = f.spacing_m * f.level.get(i).map_or(1.0, |&l| spacing_factor(l));
        (0.75 * dx * l.scale).max(0.75)
    };
    for i in 0..f.x.len() {
        let r = radius(i);
        let r2 = r * r;
        let (x, y) = (f.x[i] as f64, f.y[i] as f64);
        if !(x.is_finite() && y.is_finite()) {
            continue;
        }
        let cx = (x - view.x.0) * l.scale;
        let cy = (view.y.1 - y) * l.scale;
        let t = (field.value(f, i) - range.0) / (range.1 - range.0);
        let [cr, cg, cb] = field.map().rgb(t);
        let (i0, i1) = (
            ((cx - r).floor() as i64).max(0),
            ((cx + r).ceil() as i64).min(w - 1),
        );
        let (j0, j1) = (
            ((cy - r).floor() as i64).max(0),
            ((cy + r).ceil() as i64).min(h - 1),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                let (ddx, ddy) = (i as f64 + 0.5 - cx, j as f64 + 0.5 - cy);
                if ddx * ddx + ddy * ddy <= r2 {
                    let k = ((j * w + i) * 4) as usize;
                    px[k..k + 4].copy_from_slice(&[cr, cg, cb, 255]);
                }
            }
        }
    }
    px
}

fn png_base64(rgba: &[u8], w: u32, h: u32) -> Result<String> {
    use base64::Engine as _;
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::High);
        let mut wr = enc.write_header().context("PNG header")?;
        wr.write_image_data(rgba).context("PNG data")?;
    }
    Ok(base64::engine::general_purpose::STANDARD.encode(bytes))
}

/// One picture as a self-contained SVG: `title` above, the particles of `f` coloured by
/// `field` on `range`, the tool outlines in grey, axes in mm, a vertical colour bar.
pub fn chip_svg(
    f: &ChipFrame,
    field: ChipField,
    view: &View,
    range: (f64, f64),
    title: &str,
) -> Result<String> {
    let l = Layout::for_view(view);
    let png = png_base64(&raster(f, field, view, &l, range), l.w, l.h)?;
    let (pw, ph) = (l.w as f64, l.h as f64);
    let (tw, th) = (LEFT + pw + RIGHT, TOP + ph + BOTTOM);
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{tw}" height="{th}" viewBox="0 0 {tw} {th}" font-family="sans-serif" font-size="12"><rect width="{tw}" height="{th}" fill="white"/><text x="{LEFT}" y="24" font-size="15">{}</text>"#,
        escape(title)
    );
    // particles and tool, clipped to the plot area by a nested viewport
    let _ = write!(
        s,
        r#"<svg x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" viewBox="0 0 {pw} {ph}"><image width="{pw}" height="{ph}" href="data:image/png;base64,{png}"/>"#
    );
    for outline in &f.tools {
        let pts: Vec<String> = outline
            .iter()
            .map(|p| {
                format!(
                    "{:.1},{:.1}",
                    (p[0] - view.x.0) * l.scale,
                    (view.y.1 - p[1]) * l.scale
                )
            })
            .collect();
        let _ = write!(
            s,
            r##"<polygon points="{}" fill="#bdbdbd" stroke="black" stroke-width="1"/>"##,
            pts.join(" ")
        );
    }
    let _ = write!(
        s,
        r#"</svg><rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="black"/>"#
    );
    axes(&mut s, view, &l);
    colour_bar(&mut s, field, range, pw, ph);
    s.push_str("</svg>\n");
    Ok(s)
}

/// Ticks and labels in mm on the bottom and left edges of the plot area.
fn axes(s: &mut String, view: &View, l: &Layout) {
    let (pw, ph) = (l.w as f64, l.h as f64);
    for t in nice_ticks(view.x.0 * 1e3, view.x.1 * 1e3) {
        let px = LEFT + (t * 1e-3 - view.x.0) * l.scale;
        let _ = write!(
            s,
            r#"<line x1="{px:.1}" y1="{}" x2="{px:.1}" y2="{}" stroke="black"/><text x="{px:.1}" y="{}" text-anchor="middle">{}</text>"#,
            TOP + ph,
            TOP + ph + 5.0,
            TOP + ph + 18.0,
            fmt(t)
        );
    }
    for t in nice_ticks(view.y.0 * 1e3, view.y.1 * 1e3) {
        let py = TOP + (view.y.1 - t * 1e-3) * l.scale;
        let _ = write!(
            s,
            r#"<line x1="{}" y1="{py:.1}" x2="{LEFT}" y2="{py:.1}" stroke="black"/><text x="{}" y="{:.1}" text-anchor="end">{}</text>"#,
            LEFT - 5.0,
            LEFT - 8.0,
            py + 4.0,
            fmt(t)
        );
    }
    let _ = write!(
        s,
        r#"<text x="{:.1}" y="{:.1}" text-anchor="middle">x (mm)</text><text transform="translate(18,{:.1}) rotate(-90)" text-anchor="middle">y (mm)</text>"#,
        LEFT + pw / 2.0,
        TOP + ph + 40.0,
        TOP + ph / 2.0
    );
}

/// A vertical colour bar right of the plot area.
fn colour_bar(s: &mut String, field: ChipField, range: (f64, f64), pw: f64, ph: f64) {
    let (x0, bw) = (LEFT + pw + 22.0, 14.0);
    let n = 48;
    for k in 0..n {
        let t = (k as f64 + 0.5) / n as f64;
        let _ = write!(
            s,
            r#"<rect x="{x0}" y="{:.2}" width="{bw}" height="{:.2}" fill="{}"/>"#,
            TOP + ph * (1.0 - (k + 1) as f64 / n as f64),
            ph / n as f64 + 0.3,
            field.map().hex(t)
        );
    }
    let _ = write!(
        s,
        r#"<rect x="{x0}" y="{TOP}" width="{bw}" height="{ph}" fill="none" stroke="black" stroke-width="0.6"/><text transform="translate({:.1},{:.1}) rotate(-90)" text-anchor="middle" font-size="11">{}</text>"#,
        x0 + bw + 58.0,
        TOP + ph / 2.0,
        escape(field.label())
    );
    for t in nice_ticks(range.0, range.1) {
        let py = TOP + ph * (1.0 - (t - range.0) / (range.1 - range.0));
        let _ = write!(
            s,
            r#"<line x1="{}" y1="{py:.1}" x2="{}" y2="{py:.1}" stroke="black" stroke-width="0.6"/><text x="{}" y="{:.1}" font-size="11">{}</text>"#,
            x0 + bw,
            x0 + bw + 4.0,
            x0 + bw + 6.0,
            py + 4.0,
            fmt(t)
        );
    }
}

/// Captures [`ChipFrame`]s at `count` evenly spaced times up to `end_s` (the last one at
/// the end of the run, also when the run stops early).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FrameRecorder {
    pub end_s: f64,
    pub count: usize,
    pub frames: Vec<ChipFrame>,
}

impl FrameRecorder {
    pub fn new(end_s: f64, count: usize) -> Self {
        FrameRecorder {
            end_s,
            count,
            frames: Vec::new(),
        }
    }
    fn next_time(&self) -> Option<f64> {
        (self.frames.len() < self.count)
            .then(|| self.end_s * (self.frames.len() + 1) as f64 / self.count as f64)
    }
}

impl Observer for FrameRecorder {
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        if let Some(t) = self.next_time() {
            if sim.time >= t - 0.5 * sim.dt {
                self.frames.push(ChipFrame::capture(sim));
            }
        }
        Ok(Control::Continue)
    }
    fn finish(&mut self, sim: &Solver) -> Result<(), SimError> {
        let last = self.frames.last().map(|f| f.time_s);
        if self.count > 0 && last != Some(sim.time) {
            self.frames.push(ChipFrame::capture(sim));
        }
        Ok(())
    }
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        self.saved()
    }
}

impl SavedState for FrameRecorder {
    const KEY: &'static str = "chip_frames";
}

/// Writes the last state as `chip_temperature.svg` and `chip_plastic_strain.svg` in `out`
/// and, when there are several frames, every frame as `frames/chip_NNN.svg` (temperature,
/// one view and colour scale for all). `cut_length_of` turns a frame's time into mm of cut
/// for the titles. Returns the files written.
pub fn write_chip_pictures(
    out: &Path,
    frames: &[ChipFrame],
    animate: bool,
    cut_length_of: &dyn Fn(f64) -> f64,
) -> Result<Vec<PathBuf>> {
    let Some(last) = frames.last() else {
        return Ok(Vec::new());
    };
    let view = View::covering(frames);
    let mut written = Vec::new();
    for field in [ChipField::Temperature, ChipField::PlasticStrain] {
        let title = format!(
            "Chip at {:.3} mm of cut: {}",
            cut_length_of(last.time_s),
            field.label()
        );
        let p = out.join(format!("chip_{}.svg", field.stem()));
        let range = field.range(std::slice::from_ref(last));
        write_string_atomic(&p, &chip_svg(last, field, &view, range, &title)?)?;
        written.push(p);
    }
    if animate {
        let dir = out.join("frames");
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        let field = ChipField::Temperature;
        let range = field.range(frames);
        for (k, f) in frames.iter().enumerate() {
            let title = format!(
                "Frame {}/{}: {:.3} mm of cut, {}",
                k + 1,
                frames.len(),
                cut_length_of(f.time_s),
                field.label()
            );
            let p = dir.join(format!("chip_{:03}.svg", k + 1));
            write_string_atomic(&p, &chip_svg(f, field, &view, range, &title)?)?;
            written.push(p);
        }
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> ChipFrame {
        // a 10 × 5 block of particles, 10 µm apart, hot on the right
        let (mut x, mut y, mut t, mut e) = (vec![], vec![], vec![], vec![]);
        for j in 0..5 {
            for i in 0..10 {
                x.push(i as f32 * 1e-5);
                y.push(j as f32 * 1e-5);
                t.push(293.15 + 50.0 * i as f32);
                e.push(0.1 * j as f32);
            }
        }
        ChipFrame {
            time_s: 1e-5,
            x,
            y,
            temperature_k: t,
            plastic_strain: e,
            spacing_m: 1e-5,
            level: Vec::new(),
            tools: vec![vec![[1.2e-4, 0.0], [1.5e-4, 0.0], [1.5e-4, 1e-4]]],
        }
    }

    #[test]
    fn pictures_colour_by_value_on_a_greyscale_safe_map() {
        let f = frame();
        let view = View::covering(std::slice::from_ref(&f));
        let l = Layout::for_view(&view);
        let range = ChipField::Temperature.range(std::slice::from_ref(&f));
        assert!(
            (range.0 - 20.0).abs() < 1e-4 && (range.1 - 470.0).abs() < 1e-4,
            "{range:?}"
        );
        let px = raster(&f, ChipField::Temperature, &view, &l, range);
        // the pixel at the coldest and at the hottest particle's centre
        let at = |x: f64, y: f64| {
            let i = ((x - view.x.0) * l.scale) as usize;
            let j = ((view.y.1 - y) * l.scale) as usize;
            let k = (j * l.w as usize + i) * 4;
            [px[k], px[k + 1], px[k + 2], px[k + 3]]
        };
        let cold = at(0.0, 2e-5);
        let hot = at(9e-5, 2e-5);
        assert_eq!(&cold[..3], &ColourMap::Inferno.rgb(0.0)[..]);
        assert_eq!(&hot[..3], &ColourMap::Inferno.rgb(1.0)[..]);
        // luminance rises with the value: readable in greyscale
        let lum = |c: [u8; 4]| 0.299 * c[0] as f64 + 0.587 * c[1] as f64 + 0.114 * c[2] as f64;
        assert!(lum(hot) > lum(cold) + 100.0);
        // empty space stays transparent
        assert_eq!(at(5e-5, 4.7e-5 + 2e-5)[3], 0);
        let svg = chip_svg(&f, ChipField::Temperature, &view, range, "T <test>").unwrap();
        assert!(svg.contains("data:image/png;base64,") && svg.contains("T &lt;test&gt;"));
        assert!(svg.contains("<polygon") && svg.contains("x (mm)"));
    }

    #[test]
    fn recorder_captures_evenly_spaced_frames_and_the_last_state() {
        let r = FrameRecorder::new(1.0, 4);
        assert_eq!(r.next_time(), Some(0.25));
        let dir = tempfile::tempdir().unwrap();
        let frames = vec![frame(), frame()];
        let files = write_chip_pictures(dir.path(), &frames, true, &|t| t * 1e3).unwrap();
        let names: Vec<String> = files
            .iter()
            .map(|p| p.strip_prefix(dir.path()).unwrap().display().to_string())
            .collect();
        assert_eq!(
            names,
            [
                "chip_temperature.svg",
                "chip_plastic_strain.svg",
                "frames/chip_001.svg",
                "frames/chip_002.svg"
            ]
        );
    }
}
