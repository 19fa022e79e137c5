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
    let text = greybox_core::input::read_regular_text(path, "mesh")?;
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

/// `x` as a node, element or tag number: a whole number ≥ 0 that fits a u64.
fn whole_number(x: f64) -> Option<u64> {
    (x >= 0.0 && x.fract() == 0.0 && x < u64::MAX as f64).then_some(x as u64)
}

/// The lines of a Gmsh file with checked access: every number finite, every count a whole
/// number no larger than the file could hold, every record as long as its format says.
struct GmshLines<'a> {
    lines: Vec<&'a str>,
    source: &'a str,
}

impl GmshLines<'_> {
    fn err(&self, i: usize, msg: String) -> Error {
        Error::input(SourcePos::file(self.source).line(i as u64 + 1), msg)
    }

    fn find(&self, tag: &str) -> Option<usize> {
        self.lines.iter().position(|l| l.trim() == tag)
    }

    fn line(&self, i: usize) -> Result<&str> {
        self.lines
            .get(i)
            .copied()
            .ok_or_else(|| self.err(i, "unexpected end of file".into()))
    }

    /// The numbers on line `i`, at least `min` of them (`what` names the record).
    fn numbers(&self, i: usize, min: usize, what: &str) -> Result<Vec<f64>> {
        let v = self
            .line(i)?
            .split_whitespace()
            .map(|t| match t.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => Err(self.err(i, format!("expected a finite number, found '{t}'"))),
            })
            .collect::<Result<Vec<f64>>>()?;
        if v.len() < min {
            return Err(self.err(i, format!("{what} needs {min} numbers, found {}", v.len())));
        }
        Ok(v)
    }

    /// A whole number ≥ 0 read on line `i`.
    fn whole(&self, i: usize, x: f64, what: &str) -> Result<u64> {
        whole_number(x)
            .ok_or_else(|| self.err(i, format!("{what} must be a whole number ≥ 0, found {x}")))
    }

    /// A count of records that take at least `lines_each` lines each: no more than the lines
    /// after line `i` can hold (a huge count in a damaged file is refused before any loop or
    /// allocation).
    fn count(&self, i: usize, x: f64, lines_each: usize, what: &str) -> Result<usize> {
        let n = self.whole(i, x, what)?;
        let room = self.lines.len().saturating_sub(i + 1) / lines_each.max(1);
        if n > room as u64 {
            return Err(self.err(
                i,
                format!("{what} is {n}, but only {room} fit in the rest of the file"),
            ));
        }
        Ok(n as usize)
    }
}

/// Gmsh MSH 4.1 ASCII: `$PhysicalNames`, `$Entities`, `$Nodes`, `$Elements`.
pub fn parse_gmsh(text: &str, source: &str) -> Result<Mesh> {
    let g = GmshLines {
        lines: text.lines().collect(),
        source,
    };
    let fmt = g
        .find("$MeshFormat")
        .ok_or_else(|| g.err(0, "not a Gmsh file: no $MeshFormat".into()))?;
    let format_line = g.lines.get(fmt + 1).copied().unwrap_or("");
    let version = format_line.split_whitespace().next().unwrap_or("");
    if !version.starts_with('4') {
        return Err(g.err(
            fmt + 1,
            format!("Gmsh format {version}: only MSH 4.x ASCII is supported"),
        ));
    }
    if format_line.split_whitespace().nth(1) != Some("0") {
        return Err(g.err(
            fmt + 1,
            "binary MSH files are not supported; save as ASCII".into(),
        ));
    }
    let phys_names = gmsh_physical_names(&g)?;
    let surf_phys = gmsh_surface_physicals(&g)?;
    let mut mesh = Mesh {
        source: source.to_string(),
        ..Default::default()
    };
    let index = gmsh_nodes(&g, &mut mesh)?;
    let eb = g
        .find("$Elements")
        .ok_or_else(|| g.err(0, "no $Elements section".into()))?;
    let h = g.numbers(eb + 1, 1, "the $Elements header")?;
    let mut i = eb + 2;
    for _ in 0..g.count(eb + 1, h[0], 1, "the number of element blocks")? {
        let b = g.numbers(i, 4, "an element block header (dim, entity, type, count)")?;
        let (dim, entity, etype) = (b[0], b[1] as i64, b[2]);
        let n = g.count(i, b[3], 1, "the number of elements in the block")?;
        let nc = match etype as i64 {
            _ if dim != 2.0 => 0,
            2 | 9 => 3,
            3 | 10 | 16 => 4,
            _ => return Err(g.err(i, format!("unsupported 2D element type {etype}"))),
        };
        for k in 0..n {
            let line = i + 1 + k;
            if dim != 2.0 {
                continue;
            }
            let v = g.numbers(line, 1 + nc, "an element (tag and corner nodes)")?;
            let nodes = v[1..1 + nc]
                .iter()
                .map(|t| {
                    let tag = g.whole(line, *t, "a node tag")?;
                    index
                        .get(&tag)
                        .copied()
                        .ok_or_else(|| g.err(line, format!("element refers to unknown node {tag}")))
                })
                .collect::<Result<Vec<_>>>()?;
            let ei = mesh.elements.len();
            mesh.elements.push(Element {
                id: g.whole(line, v[0], "an element tag")?,
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
        return Err(g.err(eb, "no 2D elements in the mesh".into()));
    }
    Ok(mesh)
}

/// `$PhysicalNames`: physical tag → name, for surfaces (dimension 2).
fn gmsh_physical_names(g: &GmshLines) -> Result<HashMap<i64, String>> {
    let mut names = HashMap::new();
    let Some(p) = g.find("$PhysicalNames") else {
        return Ok(names);
    };
    let n = g.numbers(p + 1, 1, "the $PhysicalNames count")?[0];
    for k in 0..g.count(p + 1, n, 1, "the number of physical names")? {
        let line = p + 2 + k;
        let mut it = g.line(line)?.trim().splitn(3, char::is_whitespace);
        let mut int = || -> Result<i64> {
            it.next()
                .unwrap_or("")
                .parse()
                .map_err(|_| g.err(line, "a physical name line is: dim tag \"name\"".into()))
        };
        let (dim, tag) = (int()?, int()?);
        if dim == 2 {
            names.insert(
                tag,
                it.next().unwrap_or("").trim().trim_matches('"').to_string(),
            );
        }
    }
    Ok(names)
}

/// `$Entities`: surface entity → its physical tags.
fn gmsh_surface_physicals(g: &GmshLines) -> Result<HashMap<i64, Vec<i64>>> {
    let mut surf_phys = HashMap::new();
    let Some(e) = g.find("$Entities") else {
        return Ok(surf_phys);
    };
    let c = g.numbers(e + 1, 3, "the $Entities header (points, curves, surfaces)")?;
    let points = g.count(e + 1, c[0], 1, "the number of point entities")?;
    let curves = g.count(e + 1, c[1], 1, "the number of curve entities")?;
    let surfaces = g.count(e + 1, c[2], 1, "the number of surface entities")?;
    for k in 0..surfaces {
        let line = e + 2 + points + curves + k;
        let v = g.numbers(line, 8, "a surface entity (tag, box, physical count)")?;
        let nphys = g.whole(line, v[7], "the number of physical tags")? as usize;
        let tags = v.get(8..8usize.saturating_add(nphys)).ok_or_else(|| {
            g.err(
                line,
                format!("the surface entity names {nphys} physical tags but has fewer"),
            )
        })?;
        surf_phys.insert(v[0] as i64, tags.iter().map(|x| *x as i64).collect());
    }
    Ok(surf_phys)
}

/// `$Nodes`: fills the mesh's nodes and returns node tag → index.
fn gmsh_nodes(g: &GmshLines, mesh: &mut Mesh) -> Result<HashMap<u64, usize>> {
    let mut index = HashMap::new();
    let nb = g
        .find("$Nodes")
        .ok_or_else(|| g.err(0, "no $Nodes section".into()))?;
    let h = g.numbers(nb + 1, 1, "the $Nodes header")?;
    let mut i = nb + 2;
    for _ in 0..g.count(nb + 1, h[0], 1, "the number of node blocks")? {
        let b = g.numbers(i, 4, "a node block header (dim, entity, parametric, count)")?;
        // each node takes two lines: its tag, then its coordinates
        let n = g.count(i, b[3], 2, "the number of nodes in the block")?;
        for k in 0..n {
            let tag_line = i + 1 + k;
            let tag = g.numbers(tag_line, 1, "a node tag")?[0];
            let id = g.whole(tag_line, tag, "a node tag")?;
            let c = g.numbers(i + 1 + n + k, 2, "node coordinates (x y z)")?;
            index.insert(id, mesh.nodes.len());
            mesh.nodes.push([c[0], c[1]]);
            mesh.node_ids.push(id);
        }
        i += 1 + 2 * n;
    }
    Ok(index)
}

/// Abaqus input: `*NODE`, `*ELEMENT[, ELSET=name]`, `*ELSET, ELSET=name[, GENERATE]`.
pub fn parse_abaqus(text: &str, source: &str) -> Result<Mesh> {
    let mut mesh = Mesh {
        source: source.to_string(),
        ..Default::default()
    };
    let mut index: HashMap<u64, usize> = HashMap::new();
    let mut elem_index: HashMap<u64, usize> = HashMap::new();
    let mut block = Block::None;
    let mut pending_sets: Vec<(String, Vec<u64>, u64)> = Vec::new();
    let line_count = text.lines().count();
    for (i, raw) in text.lines().enumerate() {
        let line = raw.trim();
        let pos = || SourcePos::file(source).line(i as u64 + 1);
        if line.is_empty() || line.starts_with("**") {
            continue;
        }
        if line.starts_with('*') {
            block = Block::of_keyword(line, &pos)?;
            continue;
        }
        let fields: Vec<&str> = line
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        match &block {
            Block::Node => {
                if fields.len() < 3 {
                    return Err(Error::input(pos(), "a *NODE line needs id, x, y"));
                }
                let id = whole(fields[0], &pos)?;
                index.insert(id, mesh.nodes.len());
                mesh.nodes
                    .push([finite(fields[1], &pos)?, finite(fields[2], &pos)?]);
                mesh.node_ids.push(id);
            }
            Block::Element(set) => {
                let element = element_line(&fields, &index, &pos)?;
                elem_index.insert(element.id, mesh.elements.len());
                if let Some(s) = set {
                    mesh.sets
                        .entry(s.clone())
                        .or_default()
                        .push(mesh.elements.len());
                }
                mesh.elements.push(element);
            }
            Block::Elset(name, generate) => {
                let v: Vec<u64> = fields
                    .iter()
                    .map(|f| whole(f, &pos))
                    .collect::<Result<_>>()?;
                let ids = if *generate {
                    generated_ids(&v, line_count).map_err(|m| Error::input(pos(), m))?
                } else {
                    v
                };
                pending_sets.push((name.clone(), ids, i as u64 + 1));
            }
            Block::None => {}
        }
    }
    add_element_sets(&mut mesh, pending_sets, &elem_index, source)?;
    if mesh.elements.is_empty() {
        return Err(Error::input(
            SourcePos::file(source),
            "no 2D elements (*ELEMENT) in the file",
        ));
    }
    Ok(mesh)
}

/// The keyword block a data line of an Abaqus input belongs to.
enum Block {
    None,
    Node,
    /// `*ELEMENT`, with its `ELSET=` if any.
    Element(Option<String>),
    /// `*ELSET`: its name and whether it is `GENERATE`d.
    Elset(String, bool),
}

impl Block {
    /// The block a keyword line (`*…`) opens; `pos` gives the line for errors.
    fn of_keyword(line: &str, pos: &dyn Fn() -> SourcePos) -> Result<Block> {
        let upper = line.to_ascii_uppercase();
        let param = |key: &str| {
            line.split(',').skip(1).find_map(|p| {
                let (k, v) = p.split_once('=')?;
                (k.trim().eq_ignore_ascii_case(key)).then(|| v.trim().to_string())
            })
        };
        Ok(
            if upper.starts_with("*NODE")
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
            },
        )
    }
}

/// A finite number of a data line.
fn finite(s: &str, pos: &dyn Fn() -> SourcePos) -> Result<f64> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(Error::input(
            pos(),
            format!("expected a finite number, found '{s}'"),
        )),
    }
}

/// A node or element number of a data line.
fn whole(s: &str, pos: &dyn Fn() -> SourcePos) -> Result<u64> {
    match s.parse::<f64>().ok().and_then(whole_number) {
        Some(id) => Ok(id),
        None => Err(Error::input(
            pos(),
            format!("expected a node or element number (a whole number ≥ 0), found '{s}'"),
        )),
    }
}

/// An `*ELEMENT` data line: its number and its corner nodes (indices into the mesh's nodes,
/// through `index`).
fn element_line(
    fields: &[&str],
    index: &HashMap<u64, usize>,
    pos: &dyn Fn() -> SourcePos,
) -> Result<Element> {
    let n = fields.len().saturating_sub(1);
    let Some(nc) = corners(n) else {
        return Err(Error::input(
            pos(),
            format!("unsupported element with {n} nodes (2D elements have 3, 4, 6 or 8)"),
        ));
    };
    let id = whole(fields[0], pos)?;
    let nodes = fields[1..1 + nc]
        .iter()
        .map(|t| {
            let tag = whole(t, pos)?;
            index.get(&tag).copied().ok_or_else(|| {
                Error::input(pos(), format!("element {id} refers to unknown node {tag}"))
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Element { id, nodes })
}

/// The `*ELSET` blocks' elements added to their sets (after every element is known);
/// `pending` holds each set's name, element numbers and line.
fn add_element_sets(
    mesh: &mut Mesh,
    pending: Vec<(String, Vec<u64>, u64)>,
    elem_index: &HashMap<u64, usize>,
    source: &str,
) -> Result<()> {
    for (name, ids, line) in pending {
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
    Ok(())
}

/// The element numbers of `*ELSET, GENERATE`'s `start, end[, step]`, refused when the range
/// names more elements than a file of `line_count` lines can hold (each takes a line).
fn generated_ids(v: &[u64], line_count: usize) -> std::result::Result<Vec<u64>, String> {
    let [start, end, ..] = v[..] else {
        return Err("*ELSET, GENERATE needs start, end[, step]".into());
    };
    let step = v.get(2).copied().unwrap_or(1).max(1);
    let count = end.saturating_sub(start) / step + u64::from(end >= start);
    if count > line_count as u64 {
        return Err(format!(
            "*ELSET, GENERATE {start}..{end} names {count} elements, more than the file's \
             {line_count} lines can hold"
        ));
    }
    Ok((start..=end).step_by(step as usize).collect())
}
