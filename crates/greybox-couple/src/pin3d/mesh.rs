//! The 3D half model of the pin on the disk, as a structured hexahedral mesh in mm.
//!
//! Axes: x along the sliding direction, y across the track (the model is the half y ≥ 0;
//! y = 0 is the symmetry plane), z up; the disk's free surface is z = 0 and the disk fills
//! z ∈ [−H, 0]. The pin's lowest point starts at the origin.
//!
//! * Disk: eight-node bricks (C3D8) on a tensor-product grid, uniform at size h over the
//!   band the contact sweeps (x from −c·a to slide + c·a, y up to c·a, c = [`BAND`]), graded
//!   outwards by at most [`GROWTH`] per element to margins of [`MARGIN`]·a, and graded down
//!   from h/2 at the surface to the bottom.
//! * Pin: one layer of bricks whose lower faces lie on the sphere
//!   z = r − √(r² − x² − y²), at spacing h/2 so the facets follow the sphere closely
//!   (their sag h²/32r is below 10⁻⁴ µm at article scale). Every pin node is driven by
//!   prescribed displacements, so the pin is rigid and adds no unknowns.

/// Half-width of the finely meshed band, in contact radii (the pile-up ahead of a sliding
/// pin widens the contact to about 1.3 a).
pub const BAND: f64 = 1.6;
/// Room beyond the band, in contact radii.
pub const MARGIN: f64 = 3.0;
/// Largest size ratio of neighbouring elements in the graded zones.
pub const GROWTH: f64 = 1.4;

/// The mesh geometry in mm.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshSpec {
    /// Pin radius r, mm.
    pub pin_radius: f64,
    /// Nominal contact radius a = √(2 r d − d²), mm.
    pub contact_radius: f64,
    /// Element size h in the band, mm.
    pub element: f64,
    /// Slide length, mm.
    pub slide: f64,
    /// Disk thickness H, mm.
    pub height: f64,
}

/// Nodes, bricks and the sets the deck needs (node and element numbers from 1).
#[derive(Debug, Clone, PartialEq)]
pub struct PinMesh {
    pub disk_nodes: Vec<[f64; 3]>,
    pub disk_elements: Vec<[usize; 8]>,
    pub pin_nodes: Vec<[f64; 3]>,
    pub pin_elements: Vec<[usize; 8]>,
    /// Disk nodes on the bottom face (fixed), the symmetry plane y = 0 (u_y = 0), the two
    /// end faces x = const (u_x = 0) and the far side y = max (u_y = 0).
    pub bottom: Vec<usize>,
    pub symmetry: Vec<usize>,
    pub x_ends: Vec<usize>,
    pub y_end: Vec<usize>,
    /// Disk elements whose top face (S2) is in the contact band: the slave surface.
    pub contact_faces: Vec<usize>,
}

/// Grid lines from `from` towards `to`, starting at `size` and growing by [`GROWTH`] up to
/// `max`, the last one ending exactly at `to` (without `from`).
fn graded(from: f64, to: f64, size: f64, max: f64) -> Vec<f64> {
    let sign = (to - from).signum();
    let (mut x, mut s, mut out) = (from, size, Vec::new());
    while (to - x).abs() > 1e-12 {
        s = (s * GROWTH).min(max);
        x = if (to - x).abs() < 1.5 * s {
            to
        } else {
            x + sign * s
        };
        out.push(x);
    }
    out
}

/// Grid lines from `from` to `to` (both included) at a spacing close to `size`.
fn uniform(from: f64, to: f64, size: f64) -> Vec<f64> {
    let n = ((to - from) / size).round().max(1.0) as usize;
    (0..=n)
        .map(|i| from + (to - from) * i as f64 / n as f64)
        .collect()
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    v
}

/// The eight corners of the brick (i, j, k) on an nx × ny grid of layers, bottom face first
/// (C3D8 order: S1 is the face at lower z, S2 the face at higher z).
fn brick(id: impl Fn(usize, usize, usize) -> usize, i: usize, j: usize, k: usize) -> [usize; 8] {
    [
        id(i, j, k),
        id(i + 1, j, k),
        id(i + 1, j + 1, k),
        id(i, j + 1, k),
        id(i, j, k + 1),
        id(i + 1, j, k + 1),
        id(i + 1, j + 1, k + 1),
        id(i, j + 1, k + 1),
    ]
}

/// Grid lines of the band along one axis (the band is uniform at the element size).
pub type BandLines = greybox_core::count::Count<1, 4_000>;
/// Nodes of the uniform band's top layer (the contact surface CalculiX searches).
pub type BandNodes = greybox_core::count::Count<1, 1_000_000>;

impl MeshSpec {
    /// Refuses a mesh too large to build or solve, before anything is allocated: the band's
    /// grid lines along x (slide plus both ends) and y, and their product, each a bounded
    /// count naming the setting that makes it.
    pub fn check_size(&self) -> Result<(), String> {
        let band = BAND * self.contact_radius;
        let nx: BandLines = greybox_core::count::checked(
            ((self.slide + 2.0 * band) / self.element).ceil() + 1.0,
            "pin3d mesh: grid lines along the slide (slide_per_radius × elements_per_radius)",
        )?;
        let ny: BandLines = greybox_core::count::checked(
            (band / self.element).ceil() + 1.0,
            "pin3d mesh: grid lines across the band (elements_per_radius)",
        )?;
        greybox_core::count::checked::<1, { BandNodes::MAX }>(
            nx.get() as f64 * ny.get() as f64,
            "pin3d mesh: nodes of the contact band",
        )?;
        Ok(())
    }

    /// Builds the disk and pin meshes.
    pub fn build(&self) -> PinMesh {
        let (a, h) = (self.contact_radius, self.element);
        let band = BAND * a;
        let coarse = (MARGIN * a).max(4.0 * h);
        let (x0, x1) = (-band, self.slide + band);
        let mut xs = uniform(x0, x1, h);
        xs.extend(graded(x0, x0 - coarse, h, coarse));
        xs.extend(graded(x1, x1 + coarse, h, coarse));
        let xs = sorted(xs);
        let mut ys = uniform(0.0, band, h);
        ys.extend(graded(band, band + coarse, h, coarse));
        let ys = sorted(ys);
        let mut zs = vec![0.0];
        zs.extend(graded(0.0, -self.height, 0.5 * h, self.height / 3.0));
        let zs = sorted(zs);
        let (nx, ny, nz) = (xs.len(), ys.len(), zs.len());
        let id = |i: usize, j: usize, k: usize| 1 + i + nx * (j + ny * k);
        let mut m = PinMesh {
            disk_nodes: Vec::with_capacity(nx * ny * nz),
            disk_elements: Vec::new(),
            pin_nodes: Vec::new(),
            pin_elements: Vec::new(),
            bottom: Vec::new(),
            symmetry: Vec::new(),
            x_ends: Vec::new(),
            y_end: Vec::new(),
            contact_faces: Vec::new(),
        };
        for (k, &z) in zs.iter().enumerate() {
            for (j, &y) in ys.iter().enumerate() {
                for (i, &x) in xs.iter().enumerate() {
                    m.disk_nodes.push([x, y, z]);
                    let n = id(i, j, k);
                    if k == 0 {
                        m.bottom.push(n);
                    }
                    if j == 0 {
                        m.symmetry.push(n);
                    }
                    if i == 0 || i == nx - 1 {
                        m.x_ends.push(n);
                    }
                    if j == ny - 1 {
                        m.y_end.push(n);
                    }
                }
            }
        }
        for k in 0..nz - 1 {
            for j in 0..ny - 1 {
                for i in 0..nx - 1 {
                    m.disk_elements.push(brick(id, i, j, k));
                    let in_band =
                        xs[i] >= x0 - 1e-9 && xs[i + 1] <= x1 + 1e-9 && ys[j + 1] <= band + 1e-9;
                    if k == nz - 2 && in_band {
                        m.contact_faces.push(m.disk_elements.len());
                    }
                }
            }
        }
        self.add_pin(&mut m);
        m
    }

    /// The pin's layer of bricks over the band, its nodes numbered after the disk's.
    fn add_pin(&self, m: &mut PinMesh) {
        let (r, h) = (self.pin_radius, self.element);
        let reach = BAND * self.contact_radius + 2.0 * h;
        let px = uniform(-reach, reach, 0.5 * h);
        let py = uniform(0.0, reach, 0.5 * h);
        let (nx, ny) = (px.len(), py.len());
        let base = m.disk_nodes.len();
        let id = |i: usize, j: usize, k: usize| base + 1 + i + nx * (j + ny * k);
        for k in 0..2 {
            for &y in &py {
                for &x in &px {
                    let z = r - (r * r - x * x - y * y).sqrt() + k as f64 * h;
                    m.pin_nodes.push([x, y, z]);
                }
            }
        }
        for j in 0..ny - 1 {
            for i in 0..nx - 1 {
                m.pin_elements.push(brick(id, i, j, 0));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spec() -> MeshSpec {
        MeshSpec {
            pin_radius: 17.0,
            contact_radius: 0.95,
            element: 0.12,
            slide: 1.4,
            height: 1.0,
        }
    }

    #[test]
    fn the_pin_faces_lie_on_the_sphere_and_the_band_is_uniform() {
        let m = spec().build();
        for p in &m.pin_nodes[..m.pin_nodes.len() / 2] {
            let d = (p[0].powi(2) + p[1].powi(2) + (p[2] - 17.0).powi(2)).sqrt();
            assert!((d - 17.0).abs() < 1e-12, "{p:?}");
        }
        // every slave face is h × h
        for &e in &m.contact_faces {
            let n = m.disk_elements[e - 1];
            let (p1, p3) = (m.disk_nodes[n[4] - 1], m.disk_nodes[n[6] - 1]);
            assert!(p1[2] == 0.0 && p3[2] == 0.0);
            assert!(((p3[0] - p1[0]) - 0.12).abs() < 0.01 && ((p3[1] - p1[1]) - 0.12).abs() < 0.01);
        }
        // the band covers the contact from before the slide to after it
        let xs: Vec<f64> = m
            .contact_faces
            .iter()
            .map(|&e| m.disk_nodes[m.disk_elements[e - 1][4] - 1][0])
            .collect();
        let lo = xs.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        assert!(lo <= -1.5 * 0.95 && hi >= 1.4 + 1.4 * 0.95, "{lo} {hi}");
    }

    #[test]
    fn every_brick_has_positive_volume_and_the_sets_are_on_their_faces() {
        let m = spec().build();
        let all: Vec<[f64; 3]> = m.disk_nodes.iter().chain(&m.pin_nodes).copied().collect();
        for e in m.disk_elements.iter().chain(&m.pin_elements) {
            let p = |k: usize| all[e[k] - 1];
            let (a, b, d, z) = (p(0), p(1), p(3), p(4));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
            let w = [z[0] - a[0], z[1] - a[1], z[2] - a[2]];
            let det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
                + u[2] * (v[0] * w[1] - v[1] * w[0]);
            assert!(det > 0.0, "{e:?}");
        }
        assert!(m
            .bottom
            .iter()
            .all(|&n| (m.disk_nodes[n - 1][2] + 1.0).abs() < 1e-12));
        assert!(m.symmetry.iter().all(|&n| m.disk_nodes[n - 1][1] == 0.0));
    }
}
