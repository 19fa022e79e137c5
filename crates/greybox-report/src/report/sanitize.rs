//! SVG figures from a study directory, rebuilt from an allow-list before they go into a
//! report page (docs/design.md: "everything that crosses a trust boundary is bounded and
//! rebuilt").
//!
//! The file is parsed with a real XML parser (`quick-xml`) and written out again: only the
//! elements and attributes a drawing needs survive, every text and attribute value is
//! escaped anew, and everything else is dropped and counted. What cannot survive: scripts
//! and event handlers (`<script>`, `on*=`), HTML islands (`<foreignObject>`), links
//! (`<a>`, any `href` but a same-figure `#id` or an embedded raster image), style sheets
//! (`<style>`; a `style` attribute keeps only plain presentation declarations, never
//! `url(…)`), animations, entity declarations and custom entities (never expanded),
//! processing instructions and comments. Ids are prefixed per figure so that two figures'
//! ids never meet and no id can shadow a global name of the page's script (`window.x`).
//! `<use>` references are bounded: a figure whose references would make the browser draw
//! more than [`MAX_USE_INSTANCES`] extra elements (nested `<use>` of `<use>`, the SVG form of
//! "billion laughs": 1 kB, 10⁹ instances) or that refer in a cycle is refused ([`fan_out`]).

use anyhow::{bail, Context, Result};
use greybox_core::escape::xml_text as escape;
use quick_xml::escape::resolve_xml_entity;
use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};
use std::collections::{BTreeSet, HashMap};

/// The most element instances `<use>` references may add to a figure (each `<use>` counts
/// the expanded size of what it refers to, recursively).
pub const MAX_USE_INSTANCES: u64 = 10_000;

/// Elements kept (what greybox's plots and chip pictures use, and the plain drawing
/// vocabulary around them). `image` keeps only embedded PNG/JPEG/GIF/WebP data; `use` only
/// same-figure references.
const ELEMENTS: &[&str] = &[
    "svg",
    "g",
    "path",
    "line",
    "polyline",
    "polygon",
    "rect",
    "circle",
    "ellipse",
    "text",
    "tspan",
    "title",
    "desc",
    "defs",
    "symbol",
    "use",
    "clipPath",
    "mask",
    "marker",
    "linearGradient",
    "radialGradient",
    "stop",
    "image",
];

/// Attributes kept with their value (geometry, presentation, text layout). A value holding
/// `url(` survives only as `url(#id)`.
const ATTRIBUTES: &[&str] = &[
    // geometry and viewports
    "x",
    "y",
    "x1",
    "y1",
    "x2",
    "y2",
    "cx",
    "cy",
    "r",
    "rx",
    "ry",
    "fx",
    "fy",
    "fr",
    "width",
    "height",
    "d",
    "points",
    "viewBox",
    "preserveAspectRatio",
    "transform",
    "pathLength",
    "version",
    // identity (ids are prefixed per figure)
    "class",
    // paint
    "fill",
    "fill-opacity",
    "fill-rule",
    "stroke",
    "stroke-width",
    "stroke-opacity",
    "stroke-dasharray",
    "stroke-dashoffset",
    "stroke-linecap",
    "stroke-linejoin",
    "stroke-miterlimit",
    "opacity",
    "color",
    "paint-order",
    "vector-effect",
    "shape-rendering",
    "image-rendering",
    "text-rendering",
    "visibility",
    "display",
    "clip-path",
    "clip-rule",
    "mask",
    "marker-start",
    "marker-mid",
    "marker-end",
    // text
    "font-family",
    "font-size",
    "font-weight",
    "font-style",
    "font-variant",
    "text-anchor",
    "dominant-baseline",
    "alignment-baseline",
    "baseline-shift",
    "letter-spacing",
    "word-spacing",
    "text-decoration",
    "dx",
    "dy",
    "rotate",
    "textLength",
    "lengthAdjust",
    "writing-mode",
    // gradients, clips, markers
    "offset",
    "stop-color",
    "stop-opacity",
    "gradientUnits",
    "gradientTransform",
    "spreadMethod",
    "clipPathUnits",
    "maskUnits",
    "maskContentUnits",
    "markerWidth",
    "markerHeight",
    "markerUnits",
    "refX",
    "refY",
    "orient",
];

/// CSS properties a `style` attribute may keep (the presentation attributes above that are
/// also properties).
const STYLE_PROPERTIES: &[&str] = &[
    "fill",
    "fill-opacity",
    "fill-rule",
    "stroke",
    "stroke-width",
    "stroke-opacity",
    "stroke-dasharray",
    "stroke-dashoffset",
    "stroke-linecap",
    "stroke-linejoin",
    "stroke-miterlimit",
    "opacity",
    "color",
    "paint-order",
    "visibility",
    "display",
    "font-family",
    "font-size",
    "font-weight",
    "font-style",
    "font-variant",
    "text-anchor",
    "dominant-baseline",
    "letter-spacing",
    "word-spacing",
    "text-decoration",
    "stop-color",
    "stop-opacity",
];

/// Raster images an `<image>` may embed, as the start of its `data:` URL.
const IMAGE_DATA: &[&str] = &[
    "data:image/png;base64,",
    "data:image/jpeg;base64,",
    "data:image/gif;base64,",
    "data:image/webp;base64,",
];

/// A rebuilt SVG and what was dropped from it.
#[derive(Debug, Clone)]
pub struct Sanitized {
    /// The `<svg>` element, re-serialised (no XML declaration, no doctype).
    pub svg: String,
    /// Elements dropped (with their content), processing instructions, doctypes and
    /// custom entity references.
    pub removed_elements: usize,
    /// Attributes dropped (event handlers, links, unknown attributes, unsafe values).
    pub removed_attributes: usize,
    /// The distinct names dropped (e.g. `<script>`, `onload`), for the warning.
    pub removed_names: BTreeSet<String>,
}

impl Sanitized {
    /// A warning saying what was removed from `file`, or `None` when nothing was.
    pub fn warning(&self, file: &str) -> Option<String> {
        if self.removed_elements + self.removed_attributes == 0 {
            return None;
        }
        let names: Vec<&str> = self
            .removed_names
            .iter()
            .map(String::as_str)
            .take(8)
            .collect();
        Some(format!(
            "{} elements/attributes removed from {file} ({} elements, {} attributes: {}{}); not allowed in a report figure",
            self.removed_elements + self.removed_attributes,
            self.removed_elements,
            self.removed_attributes,
            names.join(", "),
            if self.removed_names.len() > names.len() { ", …" } else { "" }
        ))
    }
}

/// Rebuilds the SVG document `text` from the allow-lists; ids become `{id_prefix}-{id}`.
/// Errors when the text is not well-formed XML or its root element is not `<svg>`.
pub fn sanitize_svg(text: &str, id_prefix: &str) -> Result<Sanitized> {
    let mut s = Rebuild {
        out: String::with_capacity(text.len()),
        prefix: id_prefix,
        open: Vec::new(),
        skip: 0,
        root_closed: false,
        graph: UseGraph::default(),
        res: Sanitized {
            svg: String::new(),
            removed_elements: 0,
            removed_attributes: 0,
            removed_names: BTreeSet::new(),
        },
    };
    let mut r = Reader::from_str(text);
    r.config_mut().check_end_names = true;
    while !s.root_closed {
        let ev = r
            .read_event()
            .with_context(|| format!("not well-formed XML (at byte {})", r.buffer_position()))?;
        if !s.event(ev)? {
            break;
        }
    }
    if !s.root_closed {
        bail!(if s.open.is_empty() && s.skip == 0 {
            "no <svg> element in it"
        } else {
            "the SVG ends before its <svg> element is closed"
        });
    }
    fan_out(&s.graph)?;
    s.res.svg = s.out;
    Ok(s.res)
}

/// The state of one rebuild.
struct Rebuild<'p> {
    out: String,
    prefix: &'p str,
    /// Kept elements open at this point (their names, for the end tags).
    open: Vec<&'static str>,
    /// Depth inside a dropped element (its content is dropped with it).
    skip: usize,
    root_closed: bool,
    /// The kept elements and their `<use>` references, for [`fan_out`].
    graph: UseGraph,
    res: Sanitized,
}

/// The kept elements as a tree with `<use>` edges: what a browser instantiates.
#[derive(Default)]
struct UseGraph {
    /// Per element: its kept children.
    children: Vec<Vec<usize>>,
    /// Per element: the id a `<use>` refers to (same figure).
    target: Vec<Option<String>>,
    /// Element of each id (the first with it, as `getElementById` finds it).
    ids: HashMap<String, usize>,
    /// Open kept elements (parallel to [`Rebuild::open`]).
    open: Vec<usize>,
}

impl UseGraph {
    /// A kept element starts (child of the innermost open one).
    fn add(&mut self, id: Option<&str>, target: Option<&str>, empty: bool) {
        let k = self.children.len();
        if let Some(&parent) = self.open.last() {
            self.children[parent].push(k);
        }
        self.children.push(Vec::new());
        self.target.push(target.map(str::to_string));
        if let Some(id) = id {
            self.ids.entry(id.to_string()).or_insert(k);
        }
        if !empty {
            self.open.push(k);
        }
    }
}

/// Refuses a figure whose `<use>` references expand to more than [`MAX_USE_INSTANCES`]
/// extra element instances or form a cycle. Each element counts 1 plus its children plus,
/// for a `<use>`, the expanded size of the element it refers to; sizes are memoised (each
/// element is expanded once, so a 1 kB file of 10 levels × 10 references costs 100 steps,
/// not 10⁹), summed saturating, and walked without recursion.
fn fan_out(g: &UseGraph) -> Result<()> {
    let n = g.children.len();
    if n == 0 {
        return Ok(());
    }
    // 0: not seen, 1: on the current path, 2: size known
    let mut state = vec![0u8; n];
    let mut size = vec![0u64; n];
    let target = |k: usize| g.target[k].as_ref().and_then(|t| g.ids.get(t).copied());
    let mut stack = vec![(0usize, false)];
    while let Some((k, done)) = stack.pop() {
        if done {
            let refs = g.children[k].iter().copied().chain(target(k));
            size[k] = refs.fold(1u64, |s, c| s.saturating_add(size[c]));
            state[k] = 2;
            continue;
        }
        match state[k] {
            2 => continue,
            1 => bail!(
                "its <use> references form a cycle (through #{}): a report figure may not refer to itself",
                g.target.iter().flatten().find(|t| g.ids.get(*t) == Some(&k)).map_or("?", |t| t.as_str())
            ),
            _ => {}
        }
        state[k] = 1;
        stack.push((k, true));
        stack.extend(
            g.children[k]
                .iter()
                .chain(target(k).as_ref())
                .map(|&c| (c, false)),
        );
    }
    let extra = size[0].saturating_sub(n as u64);
    if extra > MAX_USE_INSTANCES {
        bail!(
            "its <use> references expand to {} element instances beyond its {n} elements (at most {MAX_USE_INSTANCES} are drawn in a report figure): nested references multiply (\"billion laughs\")",
            if size[0] == u64::MAX { "more than 10^19".to_string() } else { extra.to_string() }
        );
    }
    Ok(())
}

impl Rebuild<'_> {
    /// Handles one parser event; `false` at the end of the input.
    fn event(&mut self, ev: Event<'_>) -> Result<bool> {
        let inside = self.skip == 0 && !self.open.is_empty();
        match ev {
            Event::Start(e) => self.start(&e, false)?,
            Event::Empty(e) => self.start(&e, true)?,
            Event::End(_) if self.skip > 0 => self.skip -= 1,
            Event::End(_) => {
                if let Some(name) = self.open.pop() {
                    self.graph.open.pop();
                    self.out.push_str("</");
                    self.out.push_str(name);
                    self.out.push('>');
                    self.root_closed = self.open.is_empty();
                }
            }
            Event::Text(t) if inside => self.out.push_str(&escape(&t.xml10_content())),
            Event::CData(t) if inside => self.out.push_str(&escape(&t.xml10_content())),
            Event::GeneralRef(g) if inside => {
                if let Some(c) = g.resolve_char_ref().ok().flatten() {
                    self.out.push_str(&escape(&c.to_string()));
                } else if let Some(v) = resolve_xml_entity(&g.xml10_content()) {
                    self.out.push_str(&escape(v));
                } else {
                    self.drop_element(format!("&{};", g.xml10_content()));
                }
            }
            Event::PI(_) => self.drop_element("<?…?>".into()),
            Event::DocType(_) => self.drop_element("<!DOCTYPE>".into()),
            Event::Eof => return Ok(false),
            // declarations, comments, and text outside the root or inside dropped elements
            _ => {}
        }
        Ok(true)
    }

    fn drop_element(&mut self, name: String) {
        self.res.removed_elements += 1;
        self.res.removed_names.insert(name);
    }

    fn drop_attribute(&mut self, name: &str) {
        self.res.removed_attributes += 1;
        self.res.removed_names.insert(name.to_string());
    }

    /// A start (or empty) tag: written with its allowed attributes, or dropped with its
    /// content.
    fn start(&mut self, e: &BytesStart<'_>, empty: bool) -> Result<()> {
        let raw = e.name().as_ref().to_string();
        if self.skip > 0 {
            self.drop_element(format!("<{raw}>"));
            self.skip += usize::from(!empty);
            return Ok(());
        }
        let allowed = ELEMENTS.iter().copied().find(|n| *n == raw);
        let name = match allowed {
            Some(n) if !self.open.is_empty() || n == "svg" => n,
            _ if self.open.is_empty() => bail!("the root element is <{raw}>, not <svg>"),
            _ => {
                self.drop_element(format!("<{raw}>"));
                self.skip = usize::from(!empty);
                return Ok(());
            }
        };
        self.out.push('<');
        self.out.push_str(name);
        if self.open.is_empty() {
            self.out.push_str(" xmlns=\"http://www.w3.org/2000/svg\"");
        }
        let (mut id, mut target) = (None, None);
        for a in e.attributes() {
            let Ok(a) = a else {
                self.drop_attribute("(malformed attribute)");
                continue;
            };
            let key = a.key.as_ref().to_string();
            let value = a.normalized_value_with(XmlVersion::Implicit1_0, 1, resolve_xml_entity);
            let value = value.ok();
            match value.as_deref().and_then(|v| self.attribute(name, &key, v)) {
                Some((k, v)) => {
                    let raw = value.as_deref().unwrap_or_default().trim();
                    match k {
                        "id" => id = Some(raw.to_string()),
                        "href" if name == "use" => target = raw.strip_prefix('#').map(String::from),
                        _ => {}
                    }
                    self.out.push(' ');
                    self.out.push_str(k);
                    self.out.push_str("=\"");
                    self.out.push_str(&escape(&v));
                    self.out.push('"');
                }
                None if key == "xmlns" || key.starts_with("xmlns:") => {}
                None => self.drop_attribute(&key),
            }
        }
        self.graph.add(id.as_deref(), target.as_deref(), empty);
        if empty {
            self.out.push_str("/>");
            self.root_closed = self.open.is_empty();
        } else {
            self.out.push('>');
            self.open.push(name);
        }
        Ok(())
    }

    /// The attribute as written (canonical name, cleaned value), or `None` to drop it.
    fn attribute(&self, element: &str, key: &str, value: &str) -> Option<(&'static str, String)> {
        match key {
            "id" => return plain_id(value).then(|| ("id", format!("{}-{value}", self.prefix))),
            "href" | "xlink:href" => return self.href(element, value).map(|v| ("href", v)),
            "style" => return style(value).map(|v| ("style", v)),
            _ => {}
        }
        let name = ATTRIBUTES.iter().copied().find(|n| *n == key)?;
        let squeezed: String = value
            .chars()
            .filter(|c| !c.is_whitespace())
            .collect::<String>()
            .to_ascii_lowercase();
        if squeezed.contains("javascript:") || squeezed.contains("data:") {
            return None;
        }
        if !squeezed.contains("url(") {
            return Some((name, value.to_string()));
        }
        // only a whole-value reference to an element of the same figure
        let id = value.trim().strip_prefix("url(#")?.strip_suffix(')')?;
        plain_id(id).then(|| (name, format!("url(#{}-{id})", self.prefix)))
    }

    /// An `href`: an embedded raster for `<image>`, else a same-figure `#id`.
    fn href(&self, element: &str, value: &str) -> Option<String> {
        let v = value.trim();
        if element == "image" {
            let data = IMAGE_DATA.iter().find_map(|p| v.strip_prefix(p))?;
            let base64 = data
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'+' | b'/' | b'='));
            return base64.then(|| v.to_string());
        }
        let id = v.strip_prefix('#')?;
        plain_id(id).then(|| format!("#{}-{id}", self.prefix))
    }
}

/// An id made of letters, digits, `-`, `_` and `.` only.
fn plain_id(id: &str) -> bool {
    !id.is_empty()
        && id.len() <= 128
        && id
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.'))
}

/// A `style` attribute reduced to allowed presentation declarations with plain values (no
/// `url(`, no escapes, quotes, comments or at-rules); `None` if nothing is left.
fn style(value: &str) -> Option<String> {
    let kept: Vec<String> = value
        .split(';')
        .filter_map(|decl| {
            let (prop, v) = decl.split_once(':')?;
            let prop = prop.trim().to_ascii_lowercase();
            let v = v.trim();
            let plain = v
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b" #.,%()+-".contains(&b));
            let lower = v.to_ascii_lowercase();
            (STYLE_PROPERTIES.contains(&prop.as_str())
                && plain
                && !v.is_empty()
                && !lower.contains("url(")
                && !lower.contains("expression"))
            .then(|| format!("{prop}: {v}"))
        })
        .collect();
    (!kept.is_empty()).then(|| kept.join("; "))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Nothing executable or fetching is left in `svg`: no forbidden tag, and within tags
    /// (text is escaped, so every `<` starts one) no event handler or outside URL.
    fn inert(svg: &str) {
        let lower = svg
            .to_ascii_lowercase()
            .replace(" xmlns=\"http://www.w3.org/2000/svg\"", "");
        for tag in lower.split('<').skip(1) {
            let tag = tag.split('>').next().unwrap();
            let name = tag
                .trim_start_matches('/')
                .split([' ', '/'])
                .next()
                .unwrap();
            assert!(
                ELEMENTS.iter().any(|e| e.to_ascii_lowercase() == name),
                "<{name}> in {svg}"
            );
            for bad in ["javascript:", "http:", "https:", "url(javascript"] {
                assert!(!tag.contains(bad), "{bad} in <{tag}> of {svg}");
            }
            // values are quoted with every `"` in them escaped: outside the quotes, names
            for names in tag.split('"').step_by(2) {
                assert!(!names.contains(" on"), "event handler in <{tag}> of {svg}");
            }
        }
    }

    fn clean(text: &str) -> Sanitized {
        let s = sanitize_svg(text, "f1").unwrap();
        inert(&s.svg);
        s
    }

    #[test]
    fn hostile_vectors_are_removed_and_counted() {
        let corpus: &[(&str, &str)] = &[
            (
                r#"<svg onload="window.pwned=1"><rect width="1"/></svg>"#,
                "onload",
            ),
            (r#"<svg><script>window.pwned=1</script></svg>"#, "<script>"),
            (
                r#"<svg><script><![CDATA[window.pwned=1]]></script></svg>"#,
                "<script>",
            ),
            (
                r#"<svg><foreignObject><body xmlns="http://www.w3.org/1999/xhtml"><img src="x" onerror="window.pwned=1"/></body></foreignObject></svg>"#,
                "<foreignObject>",
            ),
            (
                r#"<svg><img src="x" onerror="window.pwned=1"/></svg>"#,
                "<img>",
            ),
            (
                r#"<svg xmlns:xlink="http://www.w3.org/1999/xlink"><a xlink:href="javascript:window.pwned=1"><text>x</text></a></svg>"#,
                "<a>",
            ),
            (
                r#"<svg><use href="javascript:window.pwned=1"/></svg>"#,
                "href",
            ),
            (
                r#"<svg><use href="http://evil.example/x.svg#a"/></svg>"#,
                "href",
            ),
            (
                r#"<svg><image href="http://evil.example/x.png"/></svg>"#,
                "href",
            ),
            (
                r#"<svg><image href="data:image/svg+xml;base64,PHN2Zz4="/></svg>"#,
                "href",
            ),
            (
                r#"<svg><style>rect { fill: url(javascript:alert(1)) } @import "http://x";</style><rect/></svg>"#,
                "<style>",
            ),
            (
                r#"<svg><rect style="fill: url(javascript:alert(1))"/></svg>"#,
                "style",
            ),
            (
                r#"<svg><rect fill="url(http://evil.example/#p)"/></svg>"#,
                "fill",
            ),
            (r#"<svg><rect fill="javascript:alert(1)"/></svg>"#, "fill"),
            (
                r#"<?xml version="1.0"?><!DOCTYPE svg [<!ENTITY x "<script>window.pwned=1</script>">]><svg><text>&x;</text></svg>"#,
                "&x;",
            ),
            (
                r#"<svg><?xml-stylesheet href="http://x"?><rect/></svg>"#,
                "<?…?>",
            ),
            (
                r#"<svg><animate attributeName="href" to="javascript:alert(1)"/></svg>"#,
                "<animate>",
            ),
            (
                r#"<svg><set attributeName="onmouseover" to="alert(1)"/></svg>"#,
                "<set>",
            ),
            (
                r#"<svg><iframe src="javascript:alert(1)"></iframe></svg>"#,
                "<iframe>",
            ),
            (
                r#"<svg><svg:script xmlns:svg="http://www.w3.org/2000/svg">x</svg:script></svg>"#,
                "<svg:script>",
            ),
            (
                r#"<svg><rect ONLOAD="x" onmouseover="y"/></svg>"#,
                "onmouseover",
            ),
            (
                r#"<svg><g><g><script>deep()</script></g></g></svg>"#,
                "<script>",
            ),
        ];
        for (text, removed) in corpus {
            let s = clean(text);
            assert!(
                s.removed_names.contains(*removed),
                "{removed} not counted for {text}: {:?} → {}",
                s.removed_names,
                s.svg
            );
            assert!(s.warning("x.svg").unwrap().contains("removed from x.svg"));
        }
    }

    #[test]
    fn text_and_values_are_escaped_anew() {
        // an escaped tag in text stays text; a quote cannot close an attribute
        let s = clean(
            r#"<svg><text x="1&quot; onload=&quot;a()">&lt;script&gt;a()&lt;/script&gt; &#60;b&#62; <![CDATA[<img src=x onerror=a()>]]></text></svg>"#,
        );
        assert!(
            s.svg.contains(
                "&lt;script&gt;a()&lt;/script&gt; &lt;b&gt; &lt;img src=x onerror=a()&gt;"
            ),
            "{}",
            s.svg
        );
        assert!(
            s.svg.contains(r#"x="1&quot; onload=&quot;a()""#),
            "{}",
            s.svg
        );
        assert_eq!(s.removed_elements + s.removed_attributes, 0);
    }

    #[test]
    fn ids_and_same_figure_references_are_prefixed() {
        let s = clean(
            r##"<svg><defs><clipPath id="c"><rect/></clipPath></defs><g clip-path="url(#c)"><use href="#c"/></g><rect id="pwned" style="fill: #fff; stroke: red; behavior: url(x)"/></svg>"##,
        );
        assert!(s.svg.contains(r#"<clipPath id="f1-c">"#), "{}", s.svg);
        assert!(s.svg.contains(r##"clip-path="url(#f1-c)""##), "{}", s.svg);
        assert!(s.svg.contains(r##"<use href="#f1-c"/>"##), "{}", s.svg);
        assert!(s.svg.contains(r#"id="f1-pwned""#), "{}", s.svg);
        assert!(
            s.svg.contains(r##"style="fill: #fff; stroke: red""##),
            "{}",
            s.svg
        );
    }

    #[test]
    fn broken_or_foreign_documents_are_refused() {
        for text in [
            "no picture",
            "<svg><rect></svg>",
            "<svg><g>",
            "<html><svg/></html>",
            "<script>x</script>",
        ] {
            assert!(sanitize_svg(text, "f").is_err(), "{text}");
        }
    }

    #[test]
    fn greybox_plots_and_chip_pictures_survive_whole() {
        let x = [0.0, 1.0, 2.0];
        let y = [0.1, 0.4, 0.2];
        let plot = greybox_core::plot::lines(
            "mu <&> history",
            "time (µs)",
            "mu (-)",
            &[greybox_core::plot::Line {
                label: "a",
                colour: "#1f77b4",
                x: &x,
                y: &y,
            }],
            false,
            &[(0.5, 1.5, "steady")],
        );
        let s = clean(&plot);
        assert_eq!(
            (s.removed_elements, s.removed_attributes),
            (0, 0),
            "{:?}",
            s.removed_names
        );
        // the same geometry, element for element and attribute for attribute
        let strip = |t: &str| t.replace(" xmlns=\"http://www.w3.org/2000/svg\"", "");
        let expected = plot[plot.find("<svg").unwrap()..].trim_end().to_string();
        assert_eq!(strip(&s.svg), strip(&expected));
        let chip = r##"<svg xmlns="http://www.w3.org/2000/svg" width="300" height="200" viewBox="0 0 300 200" font-family="sans-serif" font-size="12"><rect width="300" height="200" fill="white"/><svg x="60" y="40" width="200" height="120" viewBox="0 0 200 120"><image width="200" height="120" href="data:image/png;base64,iVBORw0KGgo="/><polygon points="1.0,2.0 3.0,4.0" fill="#bdbdbd" stroke="black" stroke-width="1"/></svg><text x="1" y="2" paint-order="stroke" fill-opacity="0.5">0.5</text></svg>"##;
        let s = clean(chip);
        assert_eq!(s.svg, chip);
    }

    /// 1 kB of nested `<use>`: level k holds 10 references to level k−1, 10⁹ rects at level 9.
    fn billion_laughs(xlink: bool) -> String {
        let attr = if xlink { "xlink:href" } else { "href" };
        let mut s = String::from(
            r#"<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"><defs><rect id="a0" width="1" height="1"/>"#,
        );
        for k in 1..10 {
            s.push_str(&format!("<g id=\"a{k}\">"));
            for _ in 0..10 {
                s.push_str(&format!("<use {attr}=\"#a{}\"/>", k - 1));
            }
            s.push_str("</g>");
        }
        s.push_str(r##"</defs><use href="#a9"/></svg>"##);
        s
    }

    #[test]
    fn nested_use_fan_out_is_refused() {
        for xlink in [false, true] {
            let svg = billion_laughs(xlink);
            assert!(svg.len() < 2_500, "{} bytes", svg.len());
            let t = std::time::Instant::now();
            let e = sanitize_svg(&svg, "f1").unwrap_err().to_string();
            assert!(t.elapsed().as_secs_f64() < 1.0, "{:?}", t.elapsed());
            assert!(
                e.contains("<use> references expand to") && e.contains("10000"),
                "{e}"
            );
        }
        // deeper, with forward references: counts saturate, no overflow
        let mut deep =
            String::from(r##"<svg xmlns="http://www.w3.org/2000/svg"><use href="#b0"/>"##);
        for k in 0..80 {
            deep.push_str(&format!(
                "<g id=\"b{k}\"><use href=\"#b{0}\"/><use href=\"#b{0}\"/></g>",
                k + 1
            ));
        }
        deep.push_str(r#"<rect id="b80"/></svg>"#);
        let e = sanitize_svg(&deep, "f1").unwrap_err().to_string();
        assert!(e.contains("more than 10^19 element instances"), "{e}");
    }

    #[test]
    fn use_cycles_are_refused() {
        for svg in [
            r##"<svg xmlns="http://www.w3.org/2000/svg"><g id="a"><use href="#a"/></g></svg>"##,
            r##"<svg xmlns="http://www.w3.org/2000/svg"><g id="a"><use href="#b"/></g><g id="b"><use href="#a"/></g></svg>"##,
        ] {
            let e = sanitize_svg(svg, "f1").unwrap_err().to_string();
            assert!(e.contains("cycle"), "{e}");
        }
    }

    #[test]
    fn modest_use_is_kept() {
        // a marker symbol drawn 500 times, and references to missing ids
        let mut svg = String::from(
            r##"<svg xmlns="http://www.w3.org/2000/svg"><defs><g id="m"><circle r="2"/><line x2="1"/></g></defs>"##,
        );
        for i in 0..500 {
            svg.push_str(&format!("<use href=\"#m\" x=\"{i}\"/>"));
        }
        svg.push_str(r##"<use href="#missing"/></svg>"##);
        let s = clean(&svg);
        assert_eq!(s.svg.matches("<use").count(), 501);
    }
}
