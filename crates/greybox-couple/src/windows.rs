//! Friction windows from a tool mesh (the article's algorithm, digest §8).
//!
//! 1. Edges of all 2D elements; an edge used by one element only lies on the tool's outer
//!    boundary. The boundary edges owned by a coating element form the tool surface.
//! 2. Each edge's outward normal is perpendicular to it and points away from the centroid of
//!    its element — independent of the node ordering in the file.
//! 3. The edges are chained into polylines; segments are grouped into windows of about the
//!    requested length (default: one window per segment).
//! 4. At every chain vertex the normal is the normalised mean of the adjacent segment normals,
//!    so neighbouring windows share their side and the windows tile a band without overlap.
//!    Each window is a quadrilateral from `inward` below the surface to `outward` above it,
//!    written counter-clockwise.

use crate::mesh::Mesh;
use greybox_core::atomic::write_string_atomic;
use greybox_core::{Error, Result, SourcePos};
use greybox_friction::export::frcwin_block;
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::path::Path;

/// A friction window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Window {
    /// 1-based window number.
    pub number: usize,
    /// Corner points, counter-clockwise (mesh length unit).
    pub points: [[f64; 2]; 4],
    /// The surface segment it covers: node ids along the surface.
    pub surface_nodes: Vec<u64>,
    /// Outward unit normal at the middle of the covered surface.
    pub normal: [f64; 2],
    /// Length of the covered surface.
    pub length: f64,
}

/// Window options (mesh length unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WindowOptions {
    pub outward: f64,
    pub inward: f64,
    /// Group consecutive segments until a window is at least this long (None: one per segment).
    pub segment_length: Option<f64>,
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn norm(a: [f64; 2]) -> [f64; 2] {
    let l = (a[0] * a[0] + a[1] * a[1]).sqrt();
    [a[0] / l, a[1] / l]
}

/// Signed area of a polygon (positive: counter-clockwise).
pub fn signed_area(p: &[[f64; 2]]) -> f64 {
    0.5 * (0..p.len())
        .map(|i| p[i][0] * p[(i + 1) % p.len()][1] - p[(i + 1) % p.len()][0] * p[i][1])
        .sum::<f64>()
}

/// Build the windows on the outer boundary of the elements of `coating_set`.
pub fn build_windows(mesh: &Mesh, coating_set: &str, opt: WindowOptions) -> Result<Vec<Window>> {
    if !(opt.outward >= 0.0 && opt.inward >= 0.0 && opt.outward + opt.inward > 0.0) {
        return Err(Error::invalid(
            "windows",
            "outward and inward extents must be ≥ 0 and not both 0",
        ));
    }
    let coating: HashSet<usize> = mesh.set(coating_set)?.iter().copied().collect();
    let next = coating_surface(mesh, &coating)?;
    if next.is_empty() {
        return Err(Error::input(
            SourcePos::file(&mesh.source).field(coating_set),
            format!("no element of set '{coating_set}' lies on the outer boundary of the mesh"),
        ));
    }
    let mut windows = Vec::new();
    for (chain, closed) in chains(mesh, &next) {
        chain_windows(mesh, &next, &chain, closed, &opt, &mut windows);
    }
    // A boundary that folds back on itself leaves a corner without a direction.
    if let Some(w) = windows.iter().find(|w| {
        !w.points
            .iter()
            .flatten()
            .chain(&w.normal)
            .all(|x| x.is_finite())
    }) {
        return Err(Error::input(
            SourcePos::file(&mesh.source),
            format!(
                "window {} over surface nodes {:?} has no finite corners: the coating boundary \
                 folds back on itself or has coincident nodes there",
                w.number, w.surface_nodes
            ),
        ));
    }
    Ok(windows)
}

/// The coating's outer surface: for each surface node, the next node along the surface and
/// the outward unit normal of the edge between them. Edges are oriented so that the outward
/// normal is the edge direction turned clockwise (the solid lies to the left when walking
/// a → b).
fn coating_surface(
    mesh: &Mesh,
    coating: &HashSet<usize>,
) -> Result<HashMap<usize, (usize, [f64; 2])>> {
    // edge (sorted node pair) → owning elements
    let mut owners: HashMap<(usize, usize), Vec<usize>> = HashMap::new();
    for (ei, e) in mesh.elements.iter().enumerate() {
        for k in 0..e.nodes.len() {
            let (a, b) = (e.nodes[k], e.nodes[(k + 1) % e.nodes.len()]);
            owners.entry((a.min(b), a.max(b))).or_default().push(ei);
        }
    }
    let centroid = |ei: usize| {
        let e = &mesh.elements[ei];
        let n = e.nodes.len() as f64;
        let s = e.nodes.iter().fold([0.0, 0.0], |acc, &i| {
            [acc[0] + mesh.nodes[i][0], acc[1] + mesh.nodes[i][1]]
        });
        [s[0] / n, s[1] / n]
    };
    let mut next: HashMap<usize, (usize, [f64; 2])> = HashMap::new();
    for (&(a, b), own) in &owners {
        if own.len() != 1 || !coating.contains(&own[0]) {
            continue;
        }
        let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
        let d = sub(pb, pa);
        if !(d[0] != 0.0 || d[1] != 0.0) {
            return Err(Error::input(
                SourcePos::file(&mesh.source),
                format!(
                    "the coating boundary has an edge of zero length: nodes {} and {} both lie at ({}, {})",
                    mesh.node_ids[a], mesh.node_ids[b], pa[0], pa[1]
                ),
            ));
        }
        let n_cw = norm([d[1], -d[0]]);
        let mid = [(pa[0] + pb[0]) / 2.0, (pa[1] + pb[1]) / 2.0];
        let c = centroid(own[0]);
        let outward_is_cw = (mid[0] - c[0]) * n_cw[0] + (mid[1] - c[1]) * n_cw[1] > 0.0;
        let (from, to, n) = if outward_is_cw {
            (a, b, n_cw)
        } else {
            (b, a, [-n_cw[0], -n_cw[1]])
        };
        if next.insert(from, (to, n)).is_some() {
            return Err(Error::input(
                SourcePos::file(&mesh.source),
                format!(
                    "the coating boundary branches at node {}",
                    mesh.node_ids[from]
                ),
            ));
        }
    }
    Ok(next)
}

/// The surface as chains of nodes (and whether each closes on itself): open chains from the
/// nodes without a predecessor first, then the closed loops, each started at its lowest node
/// id so that the numbering does not depend on hashing.
fn chains(mesh: &Mesh, next: &HashMap<usize, (usize, [f64; 2])>) -> Vec<(Vec<usize>, bool)> {
    let has_prev: HashSet<usize> = next.values().map(|&(to, _)| to).collect();
    let mut starts: Vec<usize> = next
        .keys()
        .filter(|k| !has_prev.contains(k))
        .copied()
        .collect();
    starts.sort_by_key(|&k| mesh.node_ids[k]);
    let mut visited: HashSet<usize> = HashSet::new();
    let mut chains: Vec<(Vec<usize>, bool)> = Vec::new();
    let walk = |start: usize, visited: &mut HashSet<usize>| {
        let mut chain = vec![start];
        let mut cur = start;
        let mut closed = false;
        while let Some(&(to, _)) = next.get(&cur) {
            visited.insert(cur);
            if to == start {
                closed = true;
                break;
            }
            chain.push(to);
            if visited.contains(&to) {
                break;
            }
            cur = to;
        }
        (chain, closed)
    };
    for s in starts {
        chains.push(walk(s, &mut visited));
    }
    let mut rest: Vec<usize> = next
        .keys()
        .filter(|k| !visited.contains(k))
        .copied()
        .collect();
    rest.sort_by_key(|&k| mesh.node_ids[k]);
    for s in rest {
        if !visited.contains(&s) {
            chains.push(walk(s, &mut visited));
        }
    }
    chains
}

/// The windows along one chain: consecutive segments grouped until `segment_length` is
/// reached (one per segment without it), each window the band from `inward` inside to
/// `outward` outside the surface, offset along the vertex normals.
fn chain_windows(
    mesh: &Mesh,
    next: &HashMap<usize, (usize, [f64; 2])>,
    chain: &[usize],
    closed: bool,
    opt: &WindowOptions,
    windows: &mut Vec<Window>,
) {
    let nseg = if closed { chain.len() } else { chain.len() - 1 };
    let seg_normal = |k: usize| next[&chain[k % chain.len()]].1;
    let seg_len = |k: usize| {
        let d = sub(
            mesh.nodes[chain[(k + 1) % chain.len()]],
            mesh.nodes[chain[k % chain.len()]],
        );
        (d[0] * d[0] + d[1] * d[1]).sqrt()
    };
    // vertex normals (miter direction, scaled so the offset band keeps its thickness)
    let vnormal = |k: usize| -> [f64; 2] {
        let prev = if k > 0 {
            Some(seg_normal(k - 1))
        } else if closed {
            Some(seg_normal(nseg - 1))
        } else {
            None
        };
        let cur = if k < nseg {
            Some(seg_normal(k))
        } else if closed {
            Some(seg_normal(0))
        } else {
            None
        };
        match (prev, cur) {
            (Some(a), Some(b)) => {
                let m = norm([a[0] + b[0], a[1] + b[1]]);
                let c = (m[0] * a[0] + m[1] * a[1]).max(0.3);
                [m[0] / c, m[1] / c]
            }
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => [0.0, 0.0],
        }
    };
    let mut k = 0;
    while k < nseg {
        let first = k;
        let mut len = 0.0;
        loop {
            len += seg_len(k);
            k += 1;
            if k >= nseg || opt.segment_length.is_none_or(|l| len >= l) {
                break;
            }
        }
        let (a, b) = (chain[first % chain.len()], chain[k % chain.len()]);
        let (na, nb) = (vnormal(first), vnormal(k));
        let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
        let off = |p: [f64; 2], n: [f64; 2], d: f64| [p[0] + d * n[0], p[1] + d * n[1]];
        let mut pts = [
            off(pa, na, -opt.inward),
            off(pb, nb, -opt.inward),
            off(pb, nb, opt.outward),
            off(pa, na, opt.outward),
        ];
        if signed_area(&pts) < 0.0 {
            pts.reverse();
        }
        let mid = (first + k) / 2;
        windows.push(Window {
            number: windows.len() + 1,
            points: pts,
            surface_nodes: (first..=k)
                .map(|j| mesh.node_ids[chain[j % chain.len()]])
                .collect(),
            normal: seg_normal(mid.min(nseg - 1)),
            length: len,
        });
    }
}

/// Windows as JSON.
pub fn write_json(path: &Path, windows: &[Window]) -> Result<()> {
    write_string_atomic(
        path,
        &serde_json::to_string_pretty(windows)
            .map_err(|e| Error::invalid("windows", e.to_string()))?,
    )
}

/// Windows as CSV: `window,point,x,y`.
pub fn write_csv(path: &Path, windows: &[Window]) -> Result<()> {
    let mut s = String::from("window,point,x,y\n");
    for w in windows {
        for (k, p) in w.points.iter().enumerate() {
            let _ = writeln!(s, "{},{},{},{}", w.number, k + 1, p[0], p[1]);
        }
    }
    write_string_atomic(path, &s)
}

/// Windows as VTK legacy polydata (one polygon per window, cell data `window`).
pub fn write_vtk(path: &Path, windows: &[Window]) -> Result<()> {
    let mut s = String::from(
        "# vtk DataFile Version 3.0\ngreybox friction windows\nASCII\nDATASET POLYDATA\n",
    );
    let _ = writeln!(s, "POINTS {} double", 4 * windows.len());
    for w in windows {
        for p in &w.points {
            let _ = writeln!(s, "{} {} 0", p[0], p[1]);
        }
    }
    let _ = writeln!(s, "POLYGONS {} {}", windows.len(), 5 * windows.len());
    for (i, _) in windows.iter().enumerate() {
        let _ = writeln!(s, "4 {} {} {} {}", 4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3);
    }
    let _ = writeln!(
        s,
        "CELL_DATA {}\nSCALARS window int 1\nLOOKUP_TABLE default",
        windows.len()
    );
    for w in windows {
        let _ = writeln!(s, "{}", w.number);
    }
    write_string_atomic(path, &s)
}

/// DEFORM `FRCWIN` blocks (2D form): Coulomb friction (FricType 2) with a constant initial μ
/// (FricDefType 0); each window follows object `objects.0` (SpdType −n).
pub fn frcwin_text(windows: &[Window], mu: f64, objects: (u32, u32)) -> String {
    let mut s =
        String::from("* greybox friction windows (DEFORM FRCWIN, counter-clockwise points)\n");
    for w in windows {
        s.push_str(&frcwin_block(w.number, &w.points, mu, objects));
    }
    s
}
