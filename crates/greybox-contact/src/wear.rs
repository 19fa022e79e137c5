//! Wear of the pins (digest §4): Archard's specific wear rate and wear volumes from height
//! maps or scar geometry.
//!
//! * Archard: k = V / (F s), s = v t, reported in mm³/(N·m) (the article's convention); the
//!   dimensionless coefficient K = k H when a hardness H is given (k in m³/(N·m), H in Pa).
//! * Height map of the worn pin (white-light interferometry export, x/y in mm, z in µm): the
//!   reference form — a sphere of the pin radius (least squares over centre x₀, y₀, z_c with
//!   the radius fixed, Gauss–Newton) or a plane — is fitted to the unworn points; the scar is
//!   where the reference lies more than 4 robust standard deviations above the surface; the fit
//!   is repeated without the scar; the wear volume is ∑ (reference − z) dx dy over the scar.
//!   Holes (NaN heights) are left out of the fit; a hole inside the scar (half or more of its
//!   valid neighbours are scar) is filled with the mean depth of those neighbours; more than
//!   20 % holes is an error.
//! * Scar geometry of a sphere worn flat: h = R − √(R² − (d/2)²), V = π h² (3R − h) / 3.

use greybox_core::csvutil::{csv_error, parse_f64, record_line, Header};
use greybox_core::linalg::solve3;
use greybox_core::{Error, Result, SourcePos};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Specific wear rate k = V / (F s) in mm³/(N·m).
pub fn archard_k(volume_mm3: f64, force_n: f64, distance_m: f64) -> Result<f64> {
    if !(volume_mm3 >= 0.0 && force_n > 0.0 && distance_m > 0.0) {
        return Err(Error::invalid("Archard", "needs V ≥ 0, F > 0 and s > 0"));
    }
    Ok(volume_mm3 / (force_n * distance_m))
}

/// Dimensionless Archard coefficient K = k H (k in mm³/(N·m), H in Pa).
pub fn archard_dimensionless(k_mm3_per_nm: f64, hardness_pa: f64) -> f64 {
    k_mm3_per_nm * 1e-9 * hardness_pa
}

/// Spherical cap worn off a sphere of radius R leaving a flat scar of diameter d (mm, mm³).
pub fn cap_volume_from_scar(radius_mm: f64, scar_diameter_mm: f64) -> Result<(f64, f64)> {
    if !(radius_mm > 0.0 && scar_diameter_mm > 0.0) || scar_diameter_mm > 2.0 * radius_mm {
        return Err(Error::invalid("scar geometry", "needs 0 < d ≤ 2R"));
    }
    let h = radius_mm - (radius_mm * radius_mm - 0.25 * scar_diameter_mm * scar_diameter_mm).sqrt();
    Ok((
        std::f64::consts::PI * h * h * (3.0 * radius_mm - h) / 3.0,
        h,
    ))
}

/// A regular height map: heights z (µm) on an nx × ny grid (x fastest) with spacings in mm.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    pub source: String,
    pub nx: usize,
    pub ny: usize,
    pub x0_mm: f64,
    pub y0_mm: f64,
    pub dx_mm: f64,
    pub dy_mm: f64,
    /// Heights, µm; NaN marks a hole.
    pub z_um: Vec<f64>,
}

impl HeightMap {
    fn xy_um(&self, i: usize) -> (f64, f64) {
        (
            (self.x0_mm + (i % self.nx) as f64 * self.dx_mm) * 1e3,
            (self.y0_mm + (i / self.nx) as f64 * self.dy_mm) * 1e3,
        )
    }
}

/// Read an XYZ CSV (`x_mm,y_mm,z_um`, any order of rows, a regular grid; `NaN` or an empty z
/// field is a hole).
pub fn read_height_map(path: &Path) -> Result<HeightMap> {
    let file = greybox_core::input::open(path, "height map", greybox_core::budget::Cap::DataBytes)?;
    read_height_map_from(file, &path.display().to_string())
}

pub fn read_height_map_from(reader: impl std::io::Read, source: &str) -> Result<HeightMap> {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(reader);
    let header = Header::new(source, rdr.headers().map_err(|e| csv_error(source, e))?);
    let (ix, iy, iz) = (
        header.require("x_mm")?,
        header.require("y_mm")?,
        header.require("z_um")?,
    );
    let mut pts = Vec::new();
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| csv_error(source, e))?;
        let line = record_line(rec.position(), k as u64 + 2);
        let x = parse_f64(&rec[ix], source, line, "x_mm")?;
        let y = parse_f64(&rec[iy], source, line, "y_mm")?;
        let zt = rec[iz].trim();
        let z = if zt.is_empty() || zt.eq_ignore_ascii_case("nan") {
            f64::NAN
        } else {
            parse_f64(zt, source, line, "z_um")?
        };
        pts.push((x, y, z, line));
    }
    let uniq = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() <= 1e-9 * b.abs().max(1.0));
    };
    let mut xs: Vec<f64> = pts.iter().map(|p| p.0).collect();
    let mut ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
    uniq(&mut xs);
    uniq(&mut ys);
    let (nx, ny) = (xs.len(), ys.len());
    if nx < 3 || ny < 3 || nx * ny != pts.len() {
        return Err(Error::input(
            SourcePos::file(source),
            format!("not a regular grid: {} points, {nx} distinct x and {ny} distinct y (need nx × ny points, at least 3 × 3)", pts.len()),
        ));
    }
    let (dx, dy) = (
        (xs[nx - 1] - xs[0]) / (nx - 1) as f64,
        (ys[ny - 1] - ys[0]) / (ny - 1) as f64,
    );
    let mut z = vec![f64::NAN; nx * ny];
    let mut seen = vec![false; nx * ny];
    for (x, y, zv, line) in pts {
        let i = ((x - xs[0]) / dx).round() as usize;
        let j = ((y - ys[0]) / dy).round() as usize;
        if (xs[0] + i as f64 * dx - x).abs() > 1e-6 * dx.abs().max(1e-12) * 1e3
            || (ys[0] + j as f64 * dy - y).abs() > 1e-6 * dy.abs().max(1e-12) * 1e3
        {
            return Err(Error::input(
                SourcePos::file(source).line(line),
                "point off the regular grid (spacing must be uniform)",
            ));
        }
        let k = j * nx + i;
        if seen[k] {
            return Err(Error::input(
                SourcePos::file(source).line(line),
                format!("duplicate grid point ({x}, {y})"),
            ));
        }
        seen[k] = true;
        z[k] = zv;
    }
    Ok(HeightMap {
        source: source.to_string(),
        nx,
        ny,
        x0_mm: xs[0],
        y0_mm: ys[0],
        dx_mm: dx,
        dy_mm: dy,
        z_um: z,
    })
}

/// Reference form of the unworn surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Reference {
    Plane,
    /// Sphere of the given radius, mm (the pin tip).
    Sphere {
        radius_mm: f64,
    },
}

/// What a height map says about the wear.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WearScar {
    pub volume_mm3: f64,
    pub mean_depth_um: f64,
    pub max_depth_um: f64,
    /// Extent of the scar along x and y, mm.
    pub length_mm: f64,
    pub width_mm: f64,
    pub scar_points: usize,
    pub holes: usize,
    pub holes_filled: usize,
    /// Robust standard deviation of the surface about the reference, µm.
    pub noise_um: f64,
}

fn fit_plane(pts: &[(f64, f64, f64)]) -> Option<[f64; 3]> {
    let mut a = [[0.0; 3]; 3];
    let mut b = [0.0; 3];
    for &(x, y, z) in pts {
        let r = [1.0, x, y];
        for i in 0..3 {
            for j in 0..3 {
                a[i][j] += r[i] * r[j];
            }
            b[i] += r[i] * z;
        }
    }
    solve3(a, b)
}

/// Sphere z = z_c + √(R² − (x−x₀)² − (y−y₀)²) fitted by Gauss–Newton (µm), radius fixed.
fn fit_sphere(pts: &[(f64, f64, f64)], r_um: f64, start: [f64; 3]) -> Option<[f64; 3]> {
    let mut p = start; // x0, y0, zc
    for _ in 0..30 {
        let mut a = [[0.0; 3]; 3];
        let mut b = [0.0; 3];
        for &(x, y, z) in pts {
            let q = r_um * r_um - (x - p[0]).powi(2) - (y - p[1]).powi(2);
            if q <= 0.0 {
                continue;
            }
            let s = q.sqrt();
            let res = z - p[2] - s;
            // ∂model/∂(x0, y0, zc)
            let j = [(x - p[0]) / s, (y - p[1]) / s, 1.0];
            for i in 0..3 {
                for k in 0..3 {
                    a[i][k] += j[i] * j[k];
                }
                b[i] += j[i] * res;
            }
        }
        let d = solve3(a, b)?;
        for i in 0..3 {
            p[i] += d[i];
        }
        if d.iter().map(|v| v.abs()).fold(0.0, f64::max) < 1e-9 * r_um {
            break;
        }
    }
    Some(p)
}

fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let m = v.len() / 2;
    let (_, x, _) = v.select_nth_unstable_by(m, f64::total_cmp);
    *x
}

/// Wear scar and volume from a height map.
pub fn analyze_height_map(map: &HeightMap, reference: Reference) -> Result<WearScar> {
    let n = map.z_um.len();
    let holes = map.z_um.iter().filter(|z| !z.is_finite()).count();
    if holes * 5 > n {
        return Err(Error::input(
            SourcePos::file(&map.source),
            format!("{holes} of {n} heights are missing (more than 20 %)"),
        ));
    }
    let coords: Vec<(f64, f64)> = (0..n).map(|i| map.xy_um(i)).collect();
    let (mut scar, refz, sigma) = separate_scar(map, &coords, reference)?;
    let mut depth = vec![0.0; n];
    for i in 0..n {
        if scar[i] {
            depth[i] = refz[i] - map.z_um[i];
        }
    }
    let filled = fill_holes(map, &mut scar, &mut depth);
    Ok(scar_measures(
        map, &coords, &scar, &depth, holes, filled, sigma,
    ))
}

/// Fit the reference form to the unworn points and take as scar every point more than 4 σ
/// (robust σ of the residuals, from their median absolute deviation) below it; refit
/// without the scar until it no longer changes (at most 6 rounds). Returns the scar mask,
/// the reference height at every point, µm, and σ, µm.
fn separate_scar(
    map: &HeightMap,
    coords: &[(f64, f64)],
    reference: Reference,
) -> Result<(Vec<bool>, Vec<f64>, f64)> {
    let n = map.z_um.len();
    let valid: Vec<usize> = (0..n).filter(|&i| map.z_um[i].is_finite()).collect();
    let mut scar = vec![false; n];
    let mut refz = vec![0.0; n];
    let mut sigma = f64::NAN;
    let apex = *valid
        .iter()
        .max_by(|&&a, &&b| map.z_um[a].total_cmp(&map.z_um[b]))
        .expect("some valid points");
    for _round in 0..6 {
        let pts: Vec<(f64, f64, f64)> = valid
            .iter()
            .filter(|&&i| !scar[i])
            .map(|&i| (coords[i].0, coords[i].1, map.z_um[i]))
            .collect();
        if pts.len() < 10 {
            return Err(Error::input(
                SourcePos::file(&map.source),
                "too few unworn points to fit the reference form",
            ));
        }
        let eval = reference_form(map, &pts, reference, coords[apex], map.z_um[apex])?;
        for i in 0..n {
            refz[i] = eval(coords[i].0, coords[i].1);
        }
        let resid: Vec<f64> = valid
            .iter()
            .filter(|&&i| !scar[i])
            .map(|&i| map.z_um[i] - refz[i])
            .collect();
        let med = median(resid.clone());
        sigma = 1.4826 * median(resid.iter().map(|r| (r - med).abs()).collect());
        let thr = 4.0 * sigma.max(1e-6);
        let new: Vec<bool> = (0..n)
            .map(|i| map.z_um[i].is_finite() && refz[i] - map.z_um[i] > thr)
            .collect();
        if new == scar {
            break;
        }
        scar = new;
    }
    Ok((scar, refz, sigma))
}

/// The reference form fitted to `pts` (x, y, z in µm): a plane, or a sphere of the given
/// radius started at the apex (`apex` x, y and height `apex_z`).
fn reference_form(
    map: &HeightMap,
    pts: &[(f64, f64, f64)],
    reference: Reference,
    apex: (f64, f64),
    apex_z: f64,
) -> Result<Box<dyn Fn(f64, f64) -> f64>> {
    Ok(match reference {
        Reference::Plane => {
            let c = fit_plane(pts).ok_or_else(|| {
                Error::input(
                    SourcePos::file(&map.source),
                    "plane fit failed (degenerate map)",
                )
            })?;
            Box::new(move |x, y| c[0] + c[1] * x + c[2] * y)
        }
        Reference::Sphere { radius_mm } => {
            let r = radius_mm * 1e3;
            let (ax, ay) = apex;
            let c = fit_sphere(pts, r, [ax, ay, apex_z - r])
                .ok_or_else(|| Error::input(SourcePos::file(&map.source), "sphere fit failed"))?;
            Box::new(move |x, y| {
                c[2] + (r * r - (x - c[0]).powi(2) - (y - c[1]).powi(2))
                    .max(0.0)
                    .sqrt()
            })
        }
    })
}

/// Missing heights inside the scar: a hole whose valid neighbours (8-neighbourhood) are at
/// least half scar joins the scar with their mean depth. Returns how many were filled.
fn fill_holes(map: &HeightMap, scar: &mut [bool], depth: &mut [f64]) -> usize {
    let mut filled = 0;
    for i in 0..map.z_um.len() {
        if map.z_um[i].is_finite() {
            continue;
        }
        let (ix, iy) = ((i % map.nx) as i64, (i / map.nx) as i64);
        let (mut nvalid, mut nscar, mut sum) = (0, 0, 0.0);
        for dy in -1..=1 {
            for dx in -1..=1 {
                let (jx, jy) = (ix + dx, iy + dy);
                if (dx, dy) == (0, 0)
                    || jx < 0
                    || jy < 0
                    || jx >= map.nx as i64
                    || jy >= map.ny as i64
                {
                    continue;
                }
                let j = jy as usize * map.nx + jx as usize;
                if map.z_um[j].is_finite() {
                    nvalid += 1;
                    if scar[j] {
                        nscar += 1;
                        sum += depth[j];
                    }
                }
            }
        }
        if nscar > 0 && 2 * nscar >= nvalid {
            scar[i] = true;
            depth[i] = sum / nscar as f64;
            filled += 1;
        }
    }
    filled
}

/// Volume, depths and extent of the scar.
fn scar_measures(
    map: &HeightMap,
    coords: &[(f64, f64)],
    scar: &[bool],
    depth: &[f64],
    holes: usize,
    filled: usize,
    sigma: f64,
) -> WearScar {
    let idx: Vec<usize> = (0..scar.len()).filter(|&i| scar[i]).collect();
    if idx.is_empty() {
        return WearScar {
            volume_mm3: 0.0,
            mean_depth_um: 0.0,
            max_depth_um: 0.0,
            length_mm: 0.0,
            width_mm: 0.0,
            scar_points: 0,
            holes,
            holes_filled: 0,
            noise_um: sigma,
        };
    }
    let cell_mm2 = map.dx_mm * map.dy_mm;
    let vol_um_mm2: f64 = idx.iter().map(|&i| depth[i]).sum::<f64>() * cell_mm2;
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &i in &idx {
        let (x, y) = (coords[i].0 / 1e3, coords[i].1 / 1e3);
        xmin = xmin.min(x);
        xmax = xmax.max(x);
        ymin = ymin.min(y);
        ymax = ymax.max(y);
    }
    WearScar {
        volume_mm3: vol_um_mm2 * 1e-3,
        mean_depth_um: idx.iter().map(|&i| depth[i]).sum::<f64>() / idx.len() as f64,
        max_depth_um: idx.iter().map(|&i| depth[i]).fold(0.0, f64::max),
        length_mm: xmax - xmin + map.dx_mm,
        width_mm: ymax - ymin + map.dy_mm,
        scar_points: idx.len(),
        holes,
        holes_filled: filled,
        noise_um: sigma,
    }
}

/// One wear test: load, speed, duration and a volume (measured or implied).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct WearTest {
    pub pin: String,
    #[serde(rename = "normal_force_N")]
    pub normal_force_n: f64,
    pub velocity_m_per_min: f64,
    pub duration_s: f64,
    /// Specific wear rate, 10⁻⁷ mm³/(N·m) (the article's Table 2 unit).
    #[serde(rename = "k_1e-7_mm3_per_Nm")]
    pub k_1e7: f64,
    #[serde(rename = "mean_depth_um")]
    pub mean_depth_um: f64,
}

impl WearTest {
    /// Sliding distance s = v t, m.
    pub fn distance_m(&self) -> f64 {
        self.velocity_m_per_min / 60.0 * self.duration_s
    }
    /// V = k F s, mm³.
    pub fn implied_volume_mm3(&self) -> f64 {
        self.k_1e7 * 1e-7 * self.normal_force_n * self.distance_m()
    }
}

/// Read wear tests from a CSV with the [`WearTest`] columns.
pub fn read_wear_tests(path: &Path) -> Result<Vec<WearTest>> {
    let src = path.display().to_string();
    let mut rdr = greybox_core::input::data_csv(path, "wear tests", &csv::ReaderBuilder::new())?;
    let mut out = Vec::new();
    for (k, r) in rdr.deserialize::<WearTest>().enumerate() {
        let t = r.map_err(|e| Error::input(SourcePos::file(&src).line(k as u64 + 2), format!("expected pin,normal_force_N,velocity_m_per_min,duration_s,k_1e-7_mm3_per_Nm,mean_depth_um: {e}")))?;
        if !(t.normal_force_n > 0.0
            && t.velocity_m_per_min > 0.0
            && t.duration_s > 0.0
            && t.k_1e7 >= 0.0)
        {
            return Err(Error::input(
                SourcePos::file(&src).line(k as u64 + 2),
                "force, velocity and duration must be positive, k ≥ 0",
            ));
        }
        out.push(t);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::Distribution;

    /// A pin tip (sphere R) worn flat at depth h, tilted and noisy, on a regular grid.
    fn synthetic(
        r_mm: f64,
        h_um: f64,
        tilt: (f64, f64),
        noise_um: f64,
        holes: usize,
    ) -> (HeightMap, f64) {
        let (nx, ny, d) = (241usize, 201usize, 0.005);
        let r = r_mm * 1e3;
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let normal = rand_distr::Normal::new(0.0, noise_um).unwrap();
        let (xc, yc) = (0.03e3, -0.02e3);
        let mut z = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                let (x, y) = ((-0.6 + i as f64 * d) * 1e3, (-0.5 + j as f64 * d) * 1e3);
                let sphere = (r * r - (x - xc).powi(2) - (y - yc).powi(2)).sqrt() - r;
                let worn = sphere.min(-h_um);
                z.push(worn + tilt.0 * x + tilt.1 * y + normal.sample(&mut rng));
            }
        }
        for k in 0..holes {
            z[(k * 7919) % (nx * ny)] = f64::NAN;
        }
        let exact_mm3 = std::f64::consts::PI * h_um * h_um * (3.0 * r - h_um) / 3.0 * 1e-9;
        (
            HeightMap {
                source: "synthetic".into(),
                nx,
                ny,
                x0_mm: -0.6,
                y0_mm: -0.5,
                dx_mm: d,
                dy_mm: d,
                z_um: z,
            },
            exact_mm3,
        )
    }

    #[test]
    fn height_map_volume_within_2_percent() {
        let (map, exact) = synthetic(17.0, 4.0, (1e-3, -5e-4), 0.02, 0);
        let s = analyze_height_map(&map, Reference::Sphere { radius_mm: 17.0 }).unwrap();
        assert!(
            (s.volume_mm3 / exact - 1.0).abs() < 0.02,
            "{} vs {exact}",
            s.volume_mm3
        );
        assert!((s.max_depth_um - 4.0).abs() < 0.2, "{}", s.max_depth_um);
        // scar diameter 2√(2Rh) = 0.737 mm
        let d = 2.0 * (2.0 * 17.0 * 4e-3f64).sqrt();
        assert!(
            (s.length_mm - d).abs() < 0.03 && (s.width_mm - d).abs() < 0.03,
            "{} {} vs {d}",
            s.length_mm,
            s.width_mm
        );
        // and with 3 % holes
        let (map, exact) = synthetic(17.0, 4.0, (1e-3, -5e-4), 0.02, 1500);
        let s = analyze_height_map(&map, Reference::Sphere { radius_mm: 17.0 }).unwrap();
        assert!(s.holes == 1500 && s.holes_filled > 0);
        assert!(
            (s.volume_mm3 / exact - 1.0).abs() < 0.02,
            "{} vs {exact}",
            s.volume_mm3
        );
    }

    #[test]
    fn mostly_holes_is_an_error() {
        let (mut map, _) = synthetic(17.0, 4.0, (0.0, 0.0), 0.02, 0);
        let n = map.z_um.len();
        for z in map.z_um.iter_mut().take(n / 4) {
            *z = f64::NAN;
        }
        let e = analyze_height_map(&map, Reference::Plane)
            .unwrap_err()
            .to_string();
        assert!(e.contains("more than 20 %"), "{e}");
    }

    #[test]
    fn cap_and_archard() {
        // h = R − √(R² − (d/2)²); V = π h²(3R − h)/3
        let (v, h) = cap_volume_from_scar(17.0, 0.737).unwrap();
        assert!((h - 0.003994).abs() < 1e-5, "{h}");
        assert!((v - std::f64::consts::PI * h * h * (3.0 * 17.0 - h) / 3.0).abs() < 1e-15);
        assert_eq!(archard_k(5.0, 100.0, 50.0).unwrap(), 1e-3);
        // K = k H: 1e-7 mm³/(N·m) with H = 2 GPa → 2e-7
        assert!((archard_dimensionless(1e-7, 2e9) - 2e-7).abs() < 1e-22);
    }
}
