//! 2D meshes with element sets, read from Gmsh v4 ASCII or Abaqus input files.
//! Only the corner nodes of 2D elements are kept (3- and 4-node, and the corners of 6- and
//! 8-node elements); 1D and 0D elements are ignored.

use greybox_core::{Error, Result, SourcePos};
use std::collections::HashMap;
use std::path::Path;

/// A 2D element: corner node indices into [`Mesh::nodes`].
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    pub id: u64,
    pub nodes: Vec<usize>,
}

#[derive(Debug, Clone, PartialEq, Default)]
pub struct Mesh {
    pub source: String,
    /// Node coordinates (x, y) in the file's length unit.
    pub nodes: Vec<[f64; 2]>,
    pub node_ids: Vec<u64>,
    pub elements: Vec<Element>,
    /// Element sets: name → element indices.
    pub sets: HashMap<String, Vec<usize>>,
}

impl Mesh {
    /// Element indices of a set, or an error listing the sets there are.
    pub fn set(&self, name: &str) -> Result<&[usize]> {
        self.sets.get(name).map(|v| v.as_slice()).ok_or_else(|| {
            let mut names: Vec<&String> = self.sets.keys().collect();
            names.sort();
            Error::input(
                SourcePos::file(&self.source).field(name),
                format!(
                    "no element set '{name}'; the mesh has: {}",
                    names
                        .iter()
                        .map(|s| s.as_str())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
        })
    }
}

/// Read a mesh, choosing the reader by extension (`.msh` or `.inp`).
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let src = path.display().to_string();
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .as_deref()
    {
        Some("msh") => parse_gmsh(&text, &src),
        Some("inp") => parse_abaqus(&text, &src),
        _ => Err(Error::input(
            SourcePos::file(&src),
            "unknown mesh format: expected .msh (Gmsh v4 ASCII) or .inp (Abaqus)",
        )),
    }
}

fn corners(n: usize) -> Option<usize> {
    match n {
        3 | 6 => Some(3),
        4 | 8 | 9 => Some(4),
        _ => None,
    }
}

/// Gmsh MSH 4.1 ASCII: `$PhysicalNames`, `$Entities`, `$Nodes`, `$Elements`.
pub fn parse_gmsh(text: &str, source: &str) -> Result<Mesh> {
    let lines: Vec<&str> = text.lines().collect();
    let err = |i: usize, msg: String| Error::input(SourcePos::file(source).line(i as u64 + 1), msg);
    let find = |tag: &str| lines.iter().position(|l| l.trim() == tag);
    let fmt =
        find("$MeshFormat").ok_or_else(|| err(0, "not a Gmsh file: no $MeshFormat".into()))?;
    let version = lines
        .get(fmt + 1)
        .and_then(|l| l.split_whitespace().next())
        .unwrap_or("");
    if !version.starts_with('4') {
        return Err(err(
            fmt + 1,
            format!("Gmsh format {version}: only MSH 4.x ASCII is supported"),
        ));
    }
    if lines.get(fmt + 1).and_then(|l| l.split_whitespace().nth(1)) != Some("0") {
        return Err(err(
            fmt + 1,
            "binary MSH files are not supported; save as ASCII".into(),
        ));
    }
    let nums = |i: usize| -> Result<Vec<f64>> {
        let l = lines
            .get(i)
            .ok_or_else(|| err(i, "unexpected end of file".into()))?;
        l.split_whitespace()
            .map(|t| {
                t.parse::<f64>()
                    .map_err(|_| err(i, format!("expected a number, found '{t}'")))
            })
            .collect()
    };
    // physical names (dim 2)
    let mut phys_names: HashMap<i64, String> = HashMap::new();
    if let Some(p) = find("$PhysicalNames") {
        let n = nums(p + 1)?[0] as usize;
        for k in 0..n {
            let l = lines[p + 2 + k];
            let mut it = l.splitn(3, char::is_whitespace);
            let dim: i64 = it
                .next()
                .unwrap_or("")
                .parse()
                .map_err(|_| err(p + 2 + k, "bad physical name line".into()))?;
            let tag: i64 = it
                .next()
                .unwrap_or("")
                .parse()
                .map_err(|_| err(p + 2 + k, "bad physical name line".into()))?;
            if dim == 2 {
                phys_names.insert(
                    tag,
                    it.next().unwrap_or("").trim().trim_matches('"').to_string(),
                );
            }
        }
    }
    // surface entity → physical tags
    let mut surf_phys: HashMap<i64, Vec<i64>> = HashMap::new();
    if let Some(e) = find("$Entities") {
        let c = nums(e + 1)?;
        let (np, nc, ns) = (c[0] as usize, c[1] as usize, c[2] as usize);
        for k in 0..ns {
            let v = nums(e + 2 + np + nc + k)?;
            let nphys = v[7] as usize;
            surf_phys.insert(
                v[0] as i64,
                v[8..8 + nphys].iter().map(|x| *x as i64).collect(),
            );
        }
    }
    let mut mesh = Mesh {
        source: source.to_string(),
        ..Default::default()
    };
    let mut index: HashMap<u64, usize> = HashMap::new();
    let nb = find("$Nodes").ok_or_else(|| err(0, "no $Nodes section".into()))?;
    let h = nums(nb + 1)?;
    let mut i = nb + 2;
    for _ in 0..h[0] as usize {
        let b = nums(i)?;
        let n = b[3] as usize;
        let tags: Vec<u64> = (0..n)
            .map(|k| nums(i + 1 + k).map(|v| v[0] as u64))
            .collect::<Result<_>>()?;
        for (k, tag) in tags.iter().enumerate() {
            let c = nums(i + 1 + n + k)?;
            if c.len() < 2 {
                return Err(err(i + 1 + n + k, "node coordinates need x y z".into()));
            }
            index.insert(*tag, mesh.nodes.len());
            mesh.nodes.push([c[0], c[1]]);
            mesh.node_ids.push(*tag);
        }
        i += 1 + 2 * n;
    }
    let eb = find("$Elements").ok_or_else(|| err(0, "no $Elements section".into()))?;
    let h = nums(eb + 1)?;
    let mut i = eb + 2;
    for _ in 0..h[0] as usize {
        let b = nums(i)?;
        let (dim, entity, etype, n) = (b[0] as i64, b[1] as i64, b[2] as i64, b[3] as usize);
        for k in 0..n {
            let v = nums(i + 1 + k)?;
            if dim != 2 {
                continue;
            }
            let nc = match etype {
                2 | 9 => 3,
                3 | 10 | 16 => 4,
                _ => {
                    return Err(err(
                        i + 1 + k,
                        format!("unsupported 2D element type {etype}"),
                    ))
                }
            };
            let nodes = v[1..1 + nc]
                .iter()
                .map(|t| {
                    index.get(&(*t as u64)).copied().ok_or_else(|| {
                        err(i + 1 + k, format!("element refers to unknown node {t}"))
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            let ei = mesh.elements.len();
            mesh.elements.push(Element {
                id: v[0] as u64,
                nodes,
            });
            for ph in surf_phys.get(&entity).into_iter().flatten() {
                let name = phys_names
                    .get(ph)
                    .cloned()
                    .unwrap_or_else(|| ph.to_string());
                mesh.sets.entry(name).or_default().push(ei);
            }
        }
        i += 1 + n;
    }
    if mesh.elements.is_empty() {
        return Err(err(eb, "no 2D elements in the mesh".into()));
    }
    Ok(mesh)
}

/// Abaqus input: `*NODE`, `*ELEMENT[, ELSET=name]`, `*ELSET, ELSET=name[, GENERATE]`.
pub fn parse_abaqus(text: &str, source: &str) -> Result<Mesh> {
    let mut mesh = Mesh {
        source: source.to_string(),
        ..Default::default()
    };
    let mut index: HashMap<u64, usize> = HashMap::new();
    let mut elem_index: HashMap<u64, usize> = HashMap::new();
    enum Block {
        None,
        Node,
        Element(Option<String>),
        Elset(String, bool),
    }
    let mut block = Block::None;
    let mut pending_sets: Vec<(String, Vec<u64>, u64)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        let pos = || SourcePos::file(source).line(i as u64 + 1);
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if line.starts_with('*') {
            let upper = line.to_ascii_uppercase();
            let param = |key: &str| {
                line.split(',').skip(1).find_map(|p| {
                    let (k, v) = p.split_once('=')?;
                    (k.trim().eq_ignore_ascii_case(key)).then(|| v.trim().to_string())
                })
            };
            block = if upper.starts_with("*NODE")
                && !upper.starts_with("*NODE ")
                && !upper.contains("PRINT")
                && !upper.contains("OUTPUT")
            {
                Block::Node
            } else if upper.starts_with("*ELEMENT") && !upper.contains("OUTPUT") {
                Block::Element(param("ELSET"))
            } else if upper.starts_with("*ELSET") {
                let name =
                    param("ELSET").ok_or_else(|| Error::input(pos(), "*ELSET without ELSET="))?;
                Block::Elset(name, upper.contains("GENERATE"))
            } else {
                Block::None
            };
            continue;
        }
        let fields: Vec<&str> = line
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        let num = |s: &str| {
            s.parse::<f64>()
                .map_err(|_| Error::input(pos(), format!("expected a number, found '{s}'")))
        };
        match &block {
            Block::Node => {
                if fields.len() < 3 {
                    return Err(Error::input(pos(), "a *NODE line needs id, x, y"));
                }
                let id = num(fields[0])? as u64;
                index.insert(id, mesh.nodes.len());
                mesh.nodes.push([num(fields[1])?, num(fields[2])?]);
                mesh.node_ids.push(id);
            }
            Block::Element(set) => {
                let n = fields.len() - 1;
                let Some(nc) = corners(n) else {
                    return Err(Error::input(
                        pos(),
                        format!(
                            "unsupported element with {n} nodes (2D elements have 3, 4, 6 or 8)"
                        ),
                    ));
                };
                let id = num(fields[0])? as u64;
                let nodes = fields[1..1 + nc]
                    .iter()
                    .map(|t| {
                        let tag = num(t)? as u64;
                        index.get(&tag).copied().ok_or_else(|| {
                            Error::input(
                                pos(),
                                format!("element {id} refers to unknown node {tag}"),
                            )
                        })
                    })
                    .collect::<Result<Vec<_>>>()?;
                elem_index.insert(id, mesh.elements.len());
                if let Some(s) = set {
                    mesh.sets
                        .entry(s.clone())
                        .or_default()
                        .push(mesh.elements.len());
                }
                mesh.elements.push(Element { id, nodes });
            }
            Block::Elset(name, generate) => {
                let v: Vec<u64> = fields
                    .iter()
                    .map(|f| num(f).map(|x| x as u64))
                    .collect::<Result<_>>()?;
                let ids = if *generate {
                    if v.len() < 2 {
                        return Err(Error::input(
                            pos(),
                            "*ELSET, GENERATE needs start, end[, step]",
                        ));
                    }
                    let step = v.get(2).copied().unwrap_or(1).max(1);
                    (v[0]..=v[1]).step_by(step as usize).collect()
                } else {
                    v
                };
                pending_sets.push((name.clone(), ids, i as u64 + 1));
            }
            Block::None => {}
        }
    }
    for (name, ids, line) in pending_sets {
        for id in ids {
            let e = elem_index.get(&id).copied().ok_or_else(|| {
                Error::input(
                    SourcePos::file(source).line(line),
                    format!("*ELSET {name} names unknown element {id}"),
                )
            })?;
            mesh.sets.entry(name.clone()).or_default().push(e);
        }
    }
    if mesh.elements.is_empty() {
        return Err(Error::input(
            SourcePos::file(source),
            "no 2D elements (*ELEMENT) in the file",
        ));
    }
    Ok(mesh)
}
