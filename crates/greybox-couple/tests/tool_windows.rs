//! Windows on a synthetic coated tool: a convex wedge (rake face, 50 µm edge radius, flank,
//! back) meshed as a closed band of quads whose outer layer is the coating; written as Abaqus
//! and Gmsh files by the test, with element node orders scrambled.

use greybox_couple::mesh::{parse_abaqus, parse_gmsh, read_mesh};
use greybox_couple::windows::{build_windows, frcwin_text, signed_area, Window, WindowOptions};
use greybox_friction::export::parse_frcwin;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt::Write as _;

fn norm(a: [f64; 2]) -> [f64; 2] {
    let l = (a[0] * a[0] + a[1] * a[1]).sqrt();
    [a[0] / l, a[1] / l]
}

/// Closed counter-clockwise tool profile (mm) with a rounded cutting edge.
fn profile() -> Vec<[f64; 2]> {
    let (a, d, c, b) = ([0.0, 0.0], [0.3, -2.0], [2.0, -2.0], [2.0, 0.0]);
    let r = 0.05;
    let u1 = norm([b[0] - a[0], b[1] - a[1]]);
    let u2 = norm([d[0] - a[0], d[1] - a[1]]);
    let theta = (u1[0] * u2[0] + u1[1] * u2[1]).acos();
    let bis = norm([u1[0] + u2[0], u1[1] + u2[1]]);
    let centre = [
        a[0] + bis[0] * r / (theta / 2.0).sin(),
        a[1] + bis[1] * r / (theta / 2.0).sin(),
    ];
    let t1 = [
        a[0] + u1[0] * r / (theta / 2.0).tan(),
        a[1] + u1[1] * r / (theta / 2.0).tan(),
    ];
    let t2 = [
        a[0] + u2[0] * r / (theta / 2.0).tan(),
        a[1] + u2[1] * r / (theta / 2.0).tan(),
    ];
    let line = |p: [f64; 2], q: [f64; 2], pts: &mut Vec<[f64; 2]>| {
        let l = ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2)).sqrt();
        let n = (l / 0.1).ceil() as usize;
        for k in 0..n {
            let s = k as f64 / n as f64;
            pts.push([p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])]);
        }
    };
    let mut pts = Vec::new();
    // arc from t1 (rake side) to t2 (flank side), bulging towards the corner a
    let (p1, p2) = (
        (t1[1] - centre[1]).atan2(t1[0] - centre[0]),
        (t2[1] - centre[1]).atan2(t2[0] - centre[0]),
    );
    let mut sweep = p2 - p1;
    let mid = |s: f64| {
        [
            centre[0] + r * (p1 + s).cos(),
            centre[1] + r * (p1 + s).sin(),
        ]
    };
    let dist_a = |p: [f64; 2]| (p[0] - a[0]).powi(2) + (p[1] - a[1]).powi(2);
    let alt = if sweep > 0.0 {
        sweep - 2.0 * std::f64::consts::PI
    } else {
        sweep + 2.0 * std::f64::consts::PI
    };
    if dist_a(mid(alt / 2.0)) < dist_a(mid(sweep / 2.0)) {
        sweep = alt;
    }
    for k in 0..8 {
        pts.push(mid(sweep * k as f64 / 8.0));
    }
    line(t2, d, &mut pts);
    line(d, c, &mut pts);
    line(c, b, &mut pts);
    line(b, t1, &mut pts);
    assert!(signed_area(&pts) > 0.0);
    pts
}

struct ToolMesh {
    nodes: Vec<[f64; 2]>,
    /// (element nodes, layer: 0 = coating)
    elements: Vec<(Vec<usize>, usize)>,
}

fn tool_mesh(seed: u64) -> (ToolMesh, Vec<[f64; 2]>) {
    let p = profile();
    let m = p.len();
    // coating 10 µm, then two substrate layers; all thinner than the 50 µm edge radius
    let layers = [0.0, 0.01, 0.025, 0.045];
    let seg_in = |i: usize| {
        let (a, b) = (p[i], p[(i + 1) % m]);
        norm([-(b[1] - a[1]), b[0] - a[0]]) // left of a→b = inside for a CCW polygon
    };
    let mut nodes = Vec::new();
    #[allow(clippy::needless_range_loop)]
    for d in layers {
        for i in 0..m {
            let (na, nb) = (seg_in((i + m - 1) % m), seg_in(i));
            let mm = norm([na[0] + nb[0], na[1] + nb[1]]);
            let c = mm[0] * nb[0] + mm[1] * nb[1];
            nodes.push([p[i][0] + d * mm[0] / c, p[i][1] + d * mm[1] / c]);
        }
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut elements = Vec::new();
    for l in 0..layers.len() - 1 {
        for i in 0..m {
            let j = (i + 1) % m;
            let mut q = vec![l * m + i, l * m + j, (l + 1) * m + j, (l + 1) * m + i];
            // scramble: rotate and maybe reverse the node order
            q.rotate_left(rng.gen_range(0..4));
            if rng.gen_bool(0.5) {
                q.reverse();
            }
            elements.push((q, l));
        }
    }
    (ToolMesh { nodes, elements }, p)
}

fn abaqus_text(t: &ToolMesh) -> String {
    let mut s = String::from("** synthetic coated tool\n*NODE\n");
    for (i, n) in t.nodes.iter().enumerate() {
        let _ = writeln!(s, "{}, {}, {}", i + 1, n[0], n[1]);
    }
    for (name, layer) in [("COATING", 0), ("MIDDLE", 1), ("SUBSTRATE", 2)] {
        let _ = writeln!(s, "*ELEMENT, TYPE=CPE4, ELSET={name}");
        for (k, (q, l)) in t.elements.iter().enumerate() {
            if *l == layer {
                let _ = writeln!(
                    s,
                    "{}, {}, {}, {}, {}",
                    k + 1,
                    q[0] + 1,
                    q[1] + 1,
                    q[2] + 1,
                    q[3] + 1
                );
            }
        }
    }
    s
}

fn gmsh_text(t: &ToolMesh) -> String {
    let mut s = String::from("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 1 \"COATING\"\n2 2 \"SUBSTRATE\"\n$EndPhysicalNames\n");
    s.push_str("$Entities\n0 0 2 0\n1 -3 -3 0 3 3 0 1 1 0\n2 -3 -3 0 3 3 0 1 2 0\n$EndEntities\n");
    let n = t.nodes.len();
    let _ = writeln!(s, "$Nodes\n1 {n} 1 {n}\n2 1 0 {n}");
    for i in 0..n {
        let _ = writeln!(s, "{}", i + 1);
    }
    for p in &t.nodes {
        let _ = writeln!(s, "{} {} 0", p[0], p[1]);
    }
    s.push_str("$EndNodes\n");
    let coat: Vec<_> = t
        .elements
        .iter()
        .enumerate()
        .filter(|e| e.1 .1 == 0)
        .collect();
    let sub: Vec<_> = t
        .elements
        .iter()
        .enumerate()
        .filter(|e| e.1 .1 != 0)
        .collect();
    let _ = writeln!(
        s,
        "$Elements\n2 {} 1 {}",
        t.elements.len(),
        t.elements.len()
    );
    for (entity, list) in [(1, &coat), (2, &sub)] {
        let _ = writeln!(s, "2 {entity} 3 {}", list.len());
        for (k, (q, _)) in list.iter() {
            let _ = writeln!(
                s,
                "{} {} {} {} {}",
                k + 1,
                q[0] + 1,
                q[1] + 1,
                q[2] + 1,
                q[3] + 1
            );
        }
    }
    s.push_str("$EndElements\n");
    s
}

fn inside(poly: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut c = false;
    let n = poly.len();
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]
        {
            c = !c;
        }
    }
    c
}

fn check(windows: &[Window], profile: &[[f64; 2]], mesh_nodes: &[[f64; 2]]) {
    for w in windows {
        assert!(
            signed_area(&w.points) > 0.0,
            "window {} not counter-clockwise",
            w.number
        );
        // outward: a point just outside the surface along the normal is outside the tool
        // the middle segment of the covered surface carries the window normal
        let rel = (w.surface_nodes.len() - 1) / 2;
        let a = mesh_nodes[(w.surface_nodes[rel] - 1) as usize];
        let b = mesh_nodes[(w.surface_nodes[rel + 1] - 1) as usize];
        let mid = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        let eps = 1e-4;
        assert!(
            !inside(
                profile,
                [mid[0] + eps * w.normal[0], mid[1] + eps * w.normal[1]]
            ),
            "window {} normal points inward",
            w.number
        );
        assert!(inside(
            profile,
            [mid[0] - eps * w.normal[0], mid[1] - eps * w.normal[1]]
        ));
    }
    // no overlap: interior sample points of every window lie in exactly one window
    for w in windows {
        let c = [
            w.points.iter().map(|p| p[0]).sum::<f64>() / 4.0,
            w.points.iter().map(|p| p[1]).sum::<f64>() / 4.0,
        ];
        for p in std::iter::once(c).chain(
            w.points
                .iter()
                .map(|q| [c[0] + 0.8 * (q[0] - c[0]), c[1] + 0.8 * (q[1] - c[1])]),
        ) {
            let n = windows.iter().filter(|v| inside(&v.points, p)).count();
            assert_eq!(
                n, 1,
                "point {p:?} of window {} lies in {n} windows",
                w.number
            );
        }
    }
}

fn opts(len: Option<f64>) -> WindowOptions {
    WindowOptions {
        outward: 0.02,
        inward: 0.005,
        segment_length: len,
    }
}

#[test]
fn one_window_per_boundary_segment_outward_no_overlap() {
    let (t, prof) = tool_mesh(1);
    let mesh = parse_abaqus(&abaqus_text(&t), "tool.inp").unwrap();
    let w = build_windows(&mesh, "COATING", opts(None)).unwrap();
    assert_eq!(w.len(), prof.len(), "one window per boundary segment");
    check(&w, &prof, &t.nodes);
    // the same mesh from Gmsh gives the same windows
    let g = parse_gmsh(&gmsh_text(&t), "tool.msh").unwrap();
    let wg = build_windows(&g, "COATING", opts(None)).unwrap();
    assert_eq!(w, wg);
    // another scrambling of node orders gives the same windows
    let (t2, _) = tool_mesh(99);
    let w2 = build_windows(
        &parse_abaqus(&abaqus_text(&t2), "tool2.inp").unwrap(),
        "COATING",
        opts(None),
    )
    .unwrap();
    assert_eq!(w, w2);
}

#[test]
fn grouped_windows_and_frcwin_round_trip() {
    let (t, prof) = tool_mesh(2);
    let mesh = parse_abaqus(&abaqus_text(&t), "tool.inp").unwrap();
    let w = build_windows(&mesh, "COATING", opts(Some(0.3))).unwrap();
    assert!(w.len() < prof.len() / 2);
    assert!(w
        .iter()
        .all(|x| x.length >= 0.3 - 1e-12 || x.number == w.len()));
    check(&w, &prof, &t.nodes);
    let total: f64 = w.iter().map(|x| x.length).sum();
    let perimeter: f64 = (0..prof.len())
        .map(|i| {
            let (a, b) = (prof[i], prof[(i + 1) % prof.len()]);
            ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
        })
        .sum();
    assert!((total - perimeter).abs() < 1e-9);
    let text = frcwin_text(&w, 0.3, (2, 1));
    let back = parse_frcwin(&text, "w.key").unwrap();
    assert_eq!(back.len(), w.len());
    for (a, b) in w.iter().zip(&back) {
        assert_eq!(a.number, b.number);
        assert_eq!(a.points.to_vec(), b.points);
        assert_eq!(b.mu, 0.3);
    }
}

#[test]
fn bad_meshes_are_named() {
    let (t, _) = tool_mesh(3);
    let mesh = parse_abaqus(&abaqus_text(&t), "tool.inp").unwrap();
    let e = build_windows(&mesh, "COAT", opts(None))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("no element set 'COAT'") && e.contains("COATING, MIDDLE, SUBSTRATE"),
        "{e}"
    );
    let e = build_windows(&mesh, "MIDDLE", opts(None))
        .unwrap_err()
        .to_string();
    assert!(e.contains("lies on the outer boundary"), "{e}");
    let e = parse_abaqus(
        "*NODE\n1, 0, 0\n*ELEMENT, TYPE=CPE4\n1, 1, 2, 3, 4\n",
        "bad.inp",
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("bad.inp, line 4") && e.contains("unknown node 2"),
        "{e}"
    );
    let e = parse_gmsh("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n", "old.msh")
        .unwrap_err()
        .to_string();
    assert!(e.contains("only MSH 4.x"), "{e}");
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("tool.stl"), "solid").unwrap();
    assert!(read_mesh(&dir.path().join("tool.stl")).is_err());
}
