//! Rigid tool shapes: a convex polygon rounded by a radius ρ (the Minkowski sum of a convex
//! polygon Q and a disk of radius ρ). One shape family covers every tool the solver needs:
//! * a circle (the tribometer pin): Q is a single point, ρ the pin radius;
//! * a cutting insert with an edge radius: Q is the insert shrunk by ρ, so that every corner is
//!   rounded with ρ (only the cutting edge touches the workpiece);
//! * a flat: Q a long thin rectangle.
//!
//! The surface is parametrised by arc length s, counter-clockwise: edge 0 (offset by ρ along
//! its outward normal), the arc around vertex 1, edge 1, …, the arc around vertex 0. Friction
//! windows are intervals of s.

use serde::{Deserialize, Serialize};

/// Closest-surface query result.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Signed distance to the surface, m (negative inside the tool).
    pub distance: f64,
    /// Outward unit normal of the tool surface at the closest point.
    pub normal: [f64; 2],
    /// Arc-length coordinate of the closest point, m.
    pub s: f64,
}

/// A convex polygon (counter-clockwise vertices, local frame, m) rounded by `radius` m.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RoundedPolygon {
    pub vertices: Vec<[f64; 2]>,
    pub radius: f64,
    #[serde(skip)]
    cache: Cache,
}

#[derive(Debug, Clone, PartialEq, Default)]
struct Cache {
    /// Per edge e (v_e → v_{e+1}): unit direction, outward normal, length.
    dir: Vec<[f64; 2]>,
    normal: Vec<[f64; 2]>,
    len: Vec<f64>,
    /// Arc length where edge e starts.
    s_edge: Vec<f64>,
    /// Arc length where the arc around vertex v starts, and its turning angle.
    s_arc: Vec<f64>,
    turn: Vec<f64>,
    perimeter: f64,
}

impl RoundedPolygon {
    /// A circle of radius `r` centred at the local origin.
    pub fn circle(r: f64) -> Self {
        Self::new(vec![[0.0, 0.0]], r).expect("a point is convex")
    }

    /// Builds the shape; the vertices must form a convex counter-clockwise polygon
    /// (1 vertex: a disk; 2: a capsule).
    pub fn new(vertices: Vec<[f64; 2]>, radius: f64) -> greybox_core::Result<Self> {
        let bad = |m: &str| greybox_core::Error::invalid("tool geometry", m.to_string());
        if vertices.is_empty() || radius.is_nan() || radius < 0.0 || !radius.is_finite() {
            return Err(bad("expected at least one vertex and a finite radius ≥ 0"));
        }
        if vertices.iter().flatten().any(|v| !v.is_finite()) {
            return Err(bad("vertex coordinates must be finite"));
        }
        if vertices.len() == 1 && radius == 0.0 {
            return Err(bad("a single-vertex tool needs a radius > 0"));
        }
        let k = vertices.len();
        let mut c = Cache::default();
        for e in 0..k {
            if k == 1 {
                break;
            }
            let a = vertices[e];
            let b = vertices[(e + 1) % k];
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let l = dx.hypot(dy);
            if l == 0.0 {
                return Err(bad("repeated vertex"));
            }
            c.dir.push([dx / l, dy / l]);
            c.normal.push([dy / l, -dx / l]);
            c.len.push(l);
        }
        if k >= 3 {
            for e in 0..k {
                let n = c.dir[e];
                let m = c.dir[(e + 1) % k];
                if n[0] * m[1] - n[1] * m[0] <= 0.0 {
                    return Err(bad(
                        "the polygon must be convex with counter-clockwise vertices",
                    ));
                }
            }
        }
        // Layout: edge e, then the arc around vertex e+1.
        let mut s = 0.0;
        c.s_arc = vec![0.0; k];
        c.turn = vec![0.0; k];
        for e in 0..k.max(1) {
            if k > 1 {
                c.s_edge.push(s);
                s += c.len[e];
            }
            let v = (e + 1) % k;
            let turn = if k == 1 {
                2.0 * std::f64::consts::PI
            } else {
                let n0 = c.normal[e];
                let n1 = c.normal[v % c.normal.len()];
                let cross = n0[0] * n1[1] - n0[1] * n1[0];
                let dot = n0[0] * n1[0] + n0[1] * n1[1];
                let a = cross.atan2(dot);
                if a < 0.0 {
                    a + 2.0 * std::f64::consts::PI
                } else {
                    a
                }
            };
            c.s_arc[v] = s;
            c.turn[v] = turn;
            s += radius * turn;
        }
        c.perimeter = s;
        Ok(RoundedPolygon {
            vertices,
            radius,
            cache: c,
        })
    }

    /// Rebuilds the derived data after deserialisation.
    pub fn rebuilt(self) -> greybox_core::Result<Self> {
        Self::new(self.vertices, self.radius)
    }

    /// Surface length, m.
    pub fn perimeter(&self) -> f64 {
        self.cache.perimeter
    }

    /// Arc-length range [start, end) of the straight edge from vertex `e` to vertex e+1, m.
    pub fn edge_span(&self, e: usize) -> (f64, f64) {
        let c = &self.cache;
        (c.s_edge[e], c.s_edge[e] + c.len[e])
    }

    /// Arc-length range [start, end) of the rounded corner around vertex `v`, m.
    pub fn arc_span(&self, v: usize) -> (f64, f64) {
        let c = &self.cache;
        (c.s_arc[v], c.s_arc[v] + self.radius * c.turn[v])
    }

    /// Axis-aligned bounding box (min, max) in the local frame, m.
    pub fn bounding_box(&self) -> ([f64; 2], [f64; 2]) {
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for v in &self.vertices {
            for d in 0..2 {
                lo[d] = lo[d].min(v[d] - self.radius);
                hi[d] = hi[d].max(v[d] + self.radius);
            }
        }
        (lo, hi)
    }

    /// Arc-length coordinate of the point on the arc around vertex `v` with normal `n`.
    fn arc_s(&self, v: usize, n: [f64; 2]) -> f64 {
        let c = &self.cache;
        let k = self.vertices.len();
        let angle = if k == 1 {
            let a = n[1].atan2(n[0]);
            if a < 0.0 {
                a + 2.0 * std::f64::consts::PI
            } else {
                a
            }
        } else {
            let n0 = c.normal[(v + k - 1) % k];
            let a = (n0[0] * n[1] - n0[1] * n[0]).atan2(n0[0] * n[0] + n0[1] * n[1]);
            a.clamp(0.0, c.turn[v])
        };
        c.s_arc[v] + self.radius * angle
    }

    /// Whether `p` (local frame) lies surely farther than `gap` m outside the surface,
    /// from the edges' half-planes alone: the core polygon is the intersection of its edges'
    /// inner half-planes, so the distance to it is at least the largest signed distance to
    /// an edge's line, and the rounded surface is `radius` nearer. A cheap first test before
    /// [`Self::closest`] (no square root, no arc length) for the many particles in a tool's
    /// bounding box that are nowhere near it; `false` (no verdict) for a point or a segment,
    /// and within 10⁻¹² of an edge's length of the threshold, so that round-off cannot
    /// decide a case [`Self::closest`] would decide the other way.
    #[inline]
    pub fn surely_clear(&self, p: [f64; 2], gap: f64) -> bool {
        if self.vertices.len() < 3 {
            return false;
        }
        let (d, e) = self.farthest_edge_line(p);
        d - self.radius > gap + 1e-12 * self.cache.len[e]
    }

    /// The largest signed distance from `p` to the core polygon's edge lines (positive
    /// outside an edge), m, and that edge: ≤ 0 exactly when `p` is inside the convex core.
    #[inline]
    fn farthest_edge_line(&self, p: [f64; 2]) -> (f64, usize) {
        let c = &self.cache;
        let mut best = (f64::NEG_INFINITY, 0usize);
        for (e, v) in self.vertices.iter().enumerate() {
            let d = c.normal[e][0] * (p[0] - v[0]) + c.normal[e][1] * (p[1] - v[1]);
            if d > best.0 {
                best = (d, e);
            }
        }
        best
    }

    /// Closest point on the surface to `p` (local frame).
    pub fn closest(&self, p: [f64; 2]) -> SurfacePoint {
        let c = &self.cache;
        let k = self.vertices.len();
        if k == 1 {
            let (dx, dy) = (p[0] - self.vertices[0][0], p[1] - self.vertices[0][1]);
            let d = dx.hypot(dy);
            let n = if d > 0.0 {
                [dx / d, dy / d]
            } else {
                [0.0, 1.0]
            };
            return SurfacePoint {
                distance: d - self.radius,
                normal: n,
                s: self.arc_s(0, n),
            };
        }
        // Inside the core polygon (only possible with an interior, k ≥ 3).
        if k >= 3 {
            let best = self.farthest_edge_line(p);
            if best.0 <= 0.0 {
                let e = best.1;
                let v = self.vertices[e];
                let t = (c.dir[e][0] * (p[0] - v[0]) + c.dir[e][1] * (p[1] - v[1]))
                    .clamp(0.0, c.len[e]);
                return SurfacePoint {
                    distance: best.0 - self.radius,
                    normal: c.normal[e],
                    s: c.s_edge[e] + t,
                };
            }
        }
        // Outside: nearest feature over the edges.
        let mut best = (f64::INFINITY, 0usize, 0.0);
        for e in 0..k {
            let v = self.vertices[e];
            let t =
                (c.dir[e][0] * (p[0] - v[0]) + c.dir[e][1] * (p[1] - v[1])).clamp(0.0, c.len[e]);
            let q = [v[0] + t * c.dir[e][0], v[1] + t * c.dir[e][1]];
            let d2 = (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
            if d2 < best.0 {
                best = (d2, e, t);
            }
        }
        let (d2, e, t) = best;
        let d = d2.sqrt();
        let v = self.vertices[e];
        let q = [v[0] + t * c.dir[e][0], v[1] + t * c.dir[e][1]];
        let normal = if d > 0.0 {
            [(p[0] - q[0]) / d, (p[1] - q[1]) / d]
        } else {
            c.normal[e]
        };
        let s = if t <= 0.0 {
            self.arc_s(e, normal)
        } else if t >= c.len[e] {
            self.arc_s((e + 1) % k, normal)
        } else {
            c.s_edge[e] + t
        };
        SurfacePoint {
            distance: d - self.radius,
            normal,
            s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn circle_distance_normal_and_arc_length() {
        let c = RoundedPolygon::circle(2.0);
        let q = c.closest([0.0, 3.0]);
        assert!((q.distance - 1.0).abs() < 1e-15);
        assert_eq!(q.normal, [0.0, 1.0]);
        assert!((q.s - std::f64::consts::PI).abs() < 1e-12);
        assert!((c.perimeter() - 4.0 * std::f64::consts::PI).abs() < 1e-12);
        assert!((c.closest([0.5, 0.0]).distance + 1.5).abs() < 1e-15);
    }

    #[test]
    fn rounded_square_layout() {
        let sq =
            RoundedPolygon::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], 0.5).unwrap();
        let pi = std::f64::consts::PI;
        assert!((sq.perimeter() - (4.0 + pi)).abs() < 1e-12);
        // Below edge 0: s in [0, 1].
        let q = sq.closest([0.25, -1.0]);
        assert!((q.distance - 0.5).abs() < 1e-15 && q.normal == [0.0, -1.0]);
        assert!((q.s - 0.25).abs() < 1e-15);
        // Diagonal of the arc around vertex 1: halfway round the quarter arc.
        let q = sq.closest([2.0, -1.0]);
        assert!((q.distance - (2f64.sqrt() - 0.5)).abs() < 1e-12);
        assert!((q.s - (1.0 + 0.5 * pi / 4.0)).abs() < 1e-12, "{}", q.s);
        // Inside the core: nearest edge 1 (x = 1).
        let q = sq.closest([0.9, 0.5]);
        assert!((q.distance + 0.6).abs() < 1e-12 && q.normal == [1.0, 0.0]);
        assert!(RoundedPolygon::new(vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]], 0.1).is_err());
    }

    /// The half-plane test never calls a point clear that [`RoundedPolygon::closest`] puts
    /// within the gap, on an insert-sized convex quadrilateral (faces tilted 7° and 15°,
    /// 20 µm corner radius) at points all round it, also exactly on its surface; and it does clear most
    /// points far from it, which is what it is for.
    #[test]
    fn clear_points_are_those_closest_puts_beyond_the_gap() {
        let r = 20e-6;
        let (rake, clearance) = (15f64.to_radians(), 7f64.to_radians());
        let insert = RoundedPolygon::new(
            vec![
                [0.0, 0.0],
                [2e-4 * clearance.sin(), 2e-4 * clearance.cos()],
                [-4e-4 * rake.cos() + 2e-4 * clearance.sin(), 4e-4],
                [-4e-4 * rake.cos(), 4e-4 * rake.sin()],
            ],
            r,
        )
        .unwrap();
        let (mut cleared, mut tried) = (0, 0);
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..20_000 {
            let p = [-7e-4 + 1.2e-3 * next(), -3e-4 + 1.0e-3 * next()];
            // Also the point on the surface nearest to it, where round-off decides.
            let sp = insert.closest(p);
            let on = [
                p[0] - sp.distance * sp.normal[0],
                p[1] - sp.distance * sp.normal[1],
            ];
            for q in [p, on] {
                for gap in [0.0, 5e-6, 3e-5] {
                    tried += 1;
                    if insert.surely_clear(q, gap) {
                        cleared += 1;
                        let d = insert.closest(q).distance;
                        assert!(
                            d > gap,
                            "{q:?} cleared at gap {gap} but {d} from the surface"
                        );
                    }
                }
            }
        }
        assert!(2 * cleared > tried / 3, "{cleared} of {tried} cleared");
    }
}
