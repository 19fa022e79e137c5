//! The report page: sections of paragraphs, tables and figures rendered as one
//! self-contained HTML5 document (inline CSS, inline SVG, a few lines of inline script for
//! the frame slider; nothing fetched from anywhere).

use greybox_core::escape::xml_text as escape;
use std::fmt::Write as _;

/// One part of a section.
pub enum Block {
    /// A paragraph of plain text.
    Text(String),
    /// A sub-heading.
    Heading(String),
    Table(Table),
    /// An inline SVG with its caption.
    Figure {
        svg: String,
        caption: String,
    },
    /// Pictures of a run's chip over time: a slider over them (with scripts), else a strip.
    Frames {
        svgs: Vec<String>,
        caption: String,
    },
    /// Figures side by side (two per row on a wide window).
    Row(Vec<Block>),
    /// Blocks folded away under a one-line summary (long tables).
    Details {
        summary: String,
        blocks: Vec<Block>,
    },
}

/// A table with a header row; cells are plain text.
pub struct Table {
    pub caption: String,
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

impl Table {
    pub fn new(caption: &str, header: &[&str]) -> Self {
        Table {
            caption: caption.to_string(),
            header: header.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
        }
    }
    pub fn row(&mut self, cells: Vec<String>) {
        self.rows.push(cells);
    }
}

/// A titled part of the report with an anchor id.
pub struct Section {
    pub id: &'static str,
    pub title: String,
    pub blocks: Vec<Block>,
}

impl Section {
    pub fn new(id: &'static str, title: &str) -> Self {
        Section {
            id,
            title: title.to_string(),
            blocks: Vec::new(),
        }
    }
    pub fn text(&mut self, t: impl Into<String>) {
        self.blocks.push(Block::Text(t.into()));
    }
    pub fn heading(&mut self, t: impl Into<String>) {
        self.blocks.push(Block::Heading(t.into()));
    }
    pub fn push(&mut self, b: Block) {
        self.blocks.push(b);
    }
}

/// An SVG document's markup ready to inline: the XML declaration and anything before the
/// `<svg` element dropped. `None` if it holds no `<svg` element.
pub fn inline_svg(text: &str) -> Option<String> {
    let start = text.find("<svg")?;
    Some(text[start..].trim_end().to_string())
}

const STYLE: &str = r#"
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; font-size: 16px; line-height: 1.45; color: #111; margin: 0; }
header, main, nav { max-width: 1180px; margin: 0 auto; padding: 0 20px; }
header { padding-top: 18px; }
h1 { font-size: 28px; margin: 8px 0; }
h2 { font-size: 22px; border-bottom: 2px solid #333; padding-bottom: 4px; margin-top: 40px; }
h3 { font-size: 18px; margin-top: 26px; }
nav ul { list-style: none; padding: 0; display: flex; flex-wrap: wrap; gap: 6px 18px; }
nav a { color: #0645ad; }
table { border-collapse: collapse; margin: 10px 0 18px; font-size: 14px; display: block; overflow-x: auto; max-width: 100%; }
caption { text-align: left; font-weight: 600; padding: 4px 0; }
th, td { border: 1px solid #999; padding: 3px 8px; text-align: right; vertical-align: top; }
th { background: #eee; }
td:first-child, th:first-child { text-align: left; }
td.wrap { text-align: left; word-break: break-all; max-width: 520px; }
figure { margin: 12px 0 22px; }
figure svg { max-width: 100%; height: auto; display: block; }
figcaption { font-size: 14px; color: #333; margin-top: 4px; }
.row { display: flex; flex-wrap: wrap; gap: 12px; }
.row > figure { flex: 1 1 520px; min-width: 320px; }
.row > table { align-self: flex-start; }
.frames .controls { display: flex; align-items: center; gap: 12px; margin: 6px 0; }
.frames input[type=range] { width: 360px; }
code { font-size: 13px; }
details { margin: 8px 0 16px; }
summary { cursor: pointer; color: #0645ad; }
"#;

/// The page's only script: the frame slider. It finds its parts by HTML element
/// (`figure`, `div`, `input`, `output`), which no figure can contain (figures are SVG
/// rebuilt by [`super::sanitize`]), so a figure cannot take part in it.
const SCRIPT: &str = r#"
document.querySelectorAll('figure.frames').forEach(function (box) {
  var frames = box.querySelectorAll(':scope > div.frame');
  var controls = box.querySelector(':scope > div.controls');
  var slider = controls.querySelector('input');
  var label = controls.querySelector('output');
  function show(k) {
    frames.forEach(function (f, i) { f.hidden = (i !== k - 1); });
    label.textContent = 'frame ' + k + ' of ' + frames.length;
  }
  controls.hidden = false;
  slider.addEventListener('input', function () { show(Number(slider.value)); });
  show(Number(slider.value));
});
"#;

/// The page's Content-Security-Policy: nothing is fetched, images only from `data:` URLs,
/// inline styles, and no script but [`SCRIPT`] (allowed by its SHA-256, so that a script
/// that got onto the page some other way would not run).
pub fn content_security_policy() -> String {
    use base64::Engine as _;
    use sha2::Digest as _;
    let hash = base64::engine::general_purpose::STANDARD.encode(sha2::Sha256::digest(SCRIPT));
    format!(
        "default-src 'none'; script-src 'sha256-{hash}'; style-src 'unsafe-inline'; img-src data:; base-uri 'none'; form-action 'none'"
    )
}

/// The whole document.
pub fn render(title: &str, intro: &[String], sections: &[Section]) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta http-equiv=\"Content-Security-Policy\" content=\"{}\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n<style>{STYLE}</style>\n</head>\n<body>\n<header>\n<h1>{}</h1>\n",
        content_security_policy(),
        escape(title),
        escape(title)
    );
    for p in intro {
        let _ = writeln!(h, "<p>{}</p>", escape(p));
    }
    h.push_str("</header>\n<nav aria-label=\"sections\">\n<ul>\n");
    for s in sections {
        let _ = writeln!(h, "<li><a href=\"#{}\">{}</a></li>", s.id, escape(&s.title));
    }
    h.push_str("</ul>\n</nav>\n<main>\n");
    let mut frames_id = 0;
    for s in sections {
        let _ = writeln!(
            h,
            "<section id=\"{}\">\n<h2>{}</h2>",
            s.id,
            escape(&s.title)
        );
        for b in &s.blocks {
            block(&mut h, b, &mut frames_id);
        }
        h.push_str("</section>\n");
    }
    let _ = write!(h, "</main>\n<script>{SCRIPT}</script>\n</body>\n</html>\n");
    h
}

fn block(h: &mut String, b: &Block, frames_id: &mut usize) {
    match b {
        Block::Text(t) => {
            let _ = writeln!(h, "<p>{}</p>", escape(t));
        }
        Block::Heading(t) => {
            let _ = writeln!(h, "<h3>{}</h3>", escape(t));
        }
        Block::Table(t) => table(h, t),
        Block::Figure { svg, caption } => {
            let _ = writeln!(
                h,
                "<figure>\n{svg}\n<figcaption>{}</figcaption>\n</figure>",
                escape(caption)
            );
        }
        Block::Frames { svgs, caption } => {
            *frames_id += 1;
            let n = svgs.len();
            let _ = writeln!(
                h,
                "<figure class=\"frames\">\n<div class=\"controls\" hidden><input type=\"range\" min=\"1\" max=\"{n}\" value=\"{n}\" aria-label=\"chip frame\" id=\"frames-{frames_id}\"><output for=\"frames-{frames_id}\">frame {n} of {n}</output></div>"
            );
            for (k, svg) in svgs.iter().enumerate() {
                let _ = writeln!(
                    h,
                    "<div class=\"frame\" data-frame=\"{}\">\n{svg}\n</div>",
                    k + 1
                );
            }
            let _ = writeln!(h, "<figcaption>{}</figcaption>\n</figure>", escape(caption));
        }
        Block::Row(items) => {
            h.push_str("<div class=\"row\">\n");
            for b in items {
                block(h, b, frames_id);
            }
            h.push_str("</div>\n");
        }
        Block::Details { summary, blocks } => {
            let _ = writeln!(h, "<details>\n<summary>{}</summary>", escape(summary));
            for b in blocks {
                block(h, b, frames_id);
            }
            h.push_str("</details>\n");
        }
    }
}

fn table(h: &mut String, t: &Table) {
    let _ = write!(
        h,
        "<table>\n<caption>{}</caption>\n<thead><tr>",
        escape(&t.caption)
    );
    for c in &t.header {
        let _ = write!(h, "<th scope=\"col\">{}</th>", escape(c));
    }
    h.push_str("</tr></thead>\n<tbody>\n");
    for r in &t.rows {
        h.push_str("<tr>");
        for c in r {
            // long unbroken values (hashes, paths) wrap instead of widening the table
            if c.len() > 40 && !c.contains(' ') {
                let _ = write!(h, "<td class=\"wrap\"><code>{}</code></td>", escape(c));
            } else {
                let _ = write!(h, "<td>{}</td>", escape(c));
            }
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody>\n</table>\n");
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn text_is_escaped_and_sections_are_linked() {
        let mut s = Section::new("models", "Models <&>");
        s.text("a < b & c");
        let mut t = Table::new("metrics", &["family", "R²"]);
        t.row(vec!["svr".into(), "0.98".into()]);
        s.push(Block::Table(t));
        s.push(Block::Frames {
            svgs: vec!["<svg></svg>".into(), "<svg></svg>".into()],
            caption: "chip".into(),
        });
        let html = render("report", &["intro".into()], &[s]);
        assert!(html.starts_with("<!DOCTYPE html>"));
        assert!(html.contains("<a href=\"#models\">Models &lt;&amp;&gt;</a>"));
        assert!(html.contains("<p>a &lt; b &amp; c</p>"));
        assert!(html.contains("<td>0.98</td>"));
        assert!(html.contains("max=\"2\"") && html.contains("data-frame=\"2\""));
        assert_eq!(
            inline_svg("<?xml version=\"1.0\"?>\n<svg a=\"1\"></svg>\n").as_deref(),
            Some("<svg a=\"1\"></svg>")
        );
        assert_eq!(inline_svg("no picture"), None);
        // the policy allows exactly the page's script, by its hash
        let csp = content_security_policy();
        assert!(html.contains(&format!("content=\"{csp}\"")));
        assert!(
            csp.starts_with("default-src 'none'; script-src 'sha256-"),
            "{csp}"
        );
        assert_eq!(html.matches("<script").count(), 1);
        assert!(html.contains(&format!("<script>{SCRIPT}</script>")));
    }
}
