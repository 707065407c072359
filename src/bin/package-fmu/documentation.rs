//! `documentation/index.html` of both FMUs, rendered from `docs/fmu-documentation.md`, and the
//! variable table that page and `docs/usage.md` carry, generated from the model descriptions:
//! one source for the repository's docs and the FMU's page, so the two cannot drift. The table
//! sits between [`TABLE_START`] and [`TABLE_END`] in each Markdown file; `package-fmu
//! --write-docs` rewrites it there, and packaging refuses a file whose table is stale.
//!
//! The renderer knows the Markdown those pages use, and no more: headings, paragraphs, bullet
//! lists, tables, fenced code, `code`, **bold** and links (relative links become the repository
//! path they name, since the FMU does not carry the repository).

use plate_impact::fmi::variables::{Description, Kind, Start, Variable};
use std::fmt::Write;

/// The line before the generated table.
pub const TABLE_START: &str =
    "<!-- variables: generated from the model description by package-fmu; do not edit -->";
/// The line after it.
pub const TABLE_END: &str = "<!-- end variables -->";

/// The Markdown files that carry the table, relative to the repository root.
pub const TABLE_FILES: [&str; 2] = ["docs/fmu-documentation.md", "docs/usage.md"];

/// The page the FMUs ship, relative to the repository root.
pub const PAGE_SOURCE: &str = "docs/fmu-documentation.md";

/// A number as a reader writes it: plain between 1e-3 and 1e6, else in exponent form.
fn number(x: f64) -> String {
    if x == 0.0 || (1e-3..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn kind_name(kind: Kind) -> &'static str {
    match kind {
        Kind::Real => "Real",
        Kind::Integer | Kind::Enumeration => "Integer",
        Kind::UInt64 => "UInt64",
        Kind::Boolean => "Boolean",
        Kind::String => "String",
    }
}

fn start_text(v: &Variable) -> String {
    match &v.start {
        None => String::new(),
        Some(Start::Real(x)) => number(*x),
        Some(Start::Integer(i)) => i.to_string(),
        Some(Start::Boolean(b)) => b.to_string(),
        Some(Start::String(s)) => (*s).to_string(),
    }
}

fn range_text(v: &Variable) -> String {
    match (v.min, v.max) {
        (Some(lo), Some(hi)) => format!("[{}, {}]", number(lo), number(hi)),
        (Some(lo), None) => format!("≥ {}", number(lo)),
        (None, Some(hi)) => format!("≤ {}", number(hi)),
        (None, None) => String::new(),
    }
}

/// The variable table in Markdown: every FMI 2.0 variable in its order, then those only the FMI
/// 3.0 description declares.
pub fn variable_table(fmi2: &Description, fmi3: &Description) -> String {
    let mut out = String::from(
        "| name | causality / variability | type | unit | start | range | meaning |\n\
         |---|---|---|---|---|---|---|\n",
    );
    let only3 = fmi3
        .variables
        .iter()
        .filter(|v| fmi2.by_name(v.name).is_none());
    for (v, fmi3_only) in fmi2
        .variables
        .iter()
        .map(|v| (v, false))
        .chain(only3.map(|v| (v, true)))
    {
        let causality = format!("{:?} / {:?}", v.causality, v.variability).to_lowercase();
        let meaning = v.description.unwrap_or("").replace('|', "\\|");
        let _ = writeln!(
            out,
            "| `{}` | {causality} | {} | {} | {} | {} | {}{meaning} |",
            v.name,
            kind_name(v.kind),
            v.unit.unwrap_or(""),
            start_text(v),
            range_text(v),
            if fmi3_only { "(FMI 3.0 only) " } else { "" },
        );
    }
    out
}

/// `text` with the part between the table markers replaced by `table`; an error names a file
/// without both markers.
pub fn with_table(file: &str, text: &str, table: &str) -> Result<String, String> {
    let start = text.find(TABLE_START);
    let end = text.find(TABLE_END);
    match (start, end) {
        (Some(s), Some(e)) if s < e => Ok(format!(
            "{}{TABLE_START}\n{table}{}",
            &text[..s],
            &text[e..]
        )),
        _ => Err(format!(
            "{file} lacks the lines {TABLE_START:?} and {TABLE_END:?} around its variable table"
        )),
    }
}

/// Escapes text for HTML.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Inline Markdown of one line or cell (already split from its block) as HTML: `code`, **bold**
/// and `[links](target)`; a relative link becomes its text and the repository path it names.
fn inline(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix('`') {
            if let Some(end) = after.find('`') {
                let _ = write!(out, "<code>{}</code>", escape(&after[..end]));
                rest = &after[end + 1..];
                continue;
            }
        }
        if let Some(after) = rest.strip_prefix("**") {
            if let Some(end) = after.find("**") {
                let _ = write!(out, "<strong>{}</strong>", inline(&after[..end]));
                rest = &after[end + 2..];
                continue;
            }
        }
        if let Some(after) = rest.strip_prefix('[') {
            let link = after.find("](").and_then(|mid| {
                after[mid + 2..]
                    .find(')')
                    .map(|end| (&after[..mid], &after[mid + 2..mid + 2 + end]))
            });
            if let Some((label, target)) = link {
                if target.contains("://") {
                    let _ = write!(out, "<a href=\"{}\">{}</a>", escape(target), inline(label));
                } else {
                    let _ = write!(
                        out,
                        "{} (<code>docs/{}</code>)",
                        inline(label),
                        escape(target)
                    );
                }
                rest = &after[label.len() + target.len() + 3..];
                continue;
            }
        }
        let first = rest.chars().next().map_or(1, char::len_utf8);
        let next = rest[first..]
            .find(['`', '*', '['])
            .map_or(rest.len(), |i| i + first);
        out.push_str(&escape(&rest[..next]));
        rest = &rest[next..];
    }
    out
}

/// The cells of a table row `| a | b |`, split at unescaped bars.
fn cells(row: &str) -> Vec<String> {
    let inner = row.trim().trim_start_matches('|').trim_end_matches('|');
    let mut cells = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cells.last_mut().expect("one cell").push('|');
                chars.next();
            }
            '|' => cells.push(String::new()),
            _ => cells.last_mut().expect("one cell").push(c),
        }
    }
    cells.into_iter().map(|c| c.trim().to_string()).collect()
}

/// One block of Markdown lines (no blank line inside) as HTML.
fn block(lines: &[&str], out: &mut String) {
    let first = lines[0];
    if let Some(level) = (1..=4).find(|&n| first.starts_with(&format!("{} ", "#".repeat(n)))) {
        let _ = writeln!(out, "<h{level}>{}</h{level}>", inline(&first[level + 1..]));
    } else if first.starts_with("<!--") {
        // A comment (the table markers) is not shown.
    } else if first.starts_with('|') {
        out.push_str("<table>\n");
        for (i, row) in lines.iter().enumerate().filter(|(i, _)| *i != 1) {
            let tag = if i == 0 { "th" } else { "td" };
            out.push_str("<tr>");
            for cell in cells(row) {
                let _ = write!(out, "<{tag}>{}</{tag}>", inline(&cell));
            }
            out.push_str("</tr>\n");
        }
        out.push_str("</table>\n");
    } else if first.starts_with("* ") || first.starts_with("- ") {
        out.push_str("<ul>\n");
        let mut item = String::new();
        for line in lines {
            if line.starts_with("* ") || line.starts_with("- ") {
                if !item.is_empty() {
                    let _ = writeln!(out, "<li>{}</li>", inline(&item));
                }
                item = line[2..].to_string();
            } else {
                item.push(' ');
                item.push_str(line.trim());
            }
        }
        let _ = writeln!(out, "<li>{}</li>", inline(&item));
        out.push_str("</ul>\n");
    } else {
        let _ = writeln!(out, "<p>{}</p>", inline(&lines.join(" ")));
    }
}

/// The Markdown page as a standalone HTML document titled `title`.
pub fn html(markdown: &str, title: &str) -> String {
    let mut body = String::new();
    let mut group: Vec<&str> = Vec::new();
    let mut lines = markdown.lines();
    while let Some(line) = lines.next() {
        // Headings and comments (the table markers) are blocks of one line.
        let single = line.starts_with('#') || line.starts_with("<!--");
        let fence = line.starts_with("```");
        if (line.trim().is_empty() || single || fence) && !group.is_empty() {
            block(&group, &mut body);
            group.clear();
        }
        if fence {
            body.push_str("<pre><code>");
            for code in lines.by_ref().take_while(|l| !l.starts_with("```")) {
                body.push_str(&escape(code));
                body.push('\n');
            }
            body.push_str("</code></pre>\n");
        } else if single {
            block(&[line], &mut body);
        } else if !line.trim().is_empty() {
            group.push(line);
        }
    }
    if !group.is_empty() {
        block(&group, &mut body);
    }
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n\
         <style>body {{ font-family: sans-serif; max-width: 60em; margin: 2em auto; line-height: 1.4 }} \
         table {{ border-collapse: collapse }} td, th {{ border: 1px solid #bbb; padding: 0.2em 0.4em; \
         vertical-align: top }} code {{ background: #f3f3f3 }}</style>\n</head>\n<body>\n{body}</body>\n</html>\n",
        escape(title)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use plate_impact::fmi::variables::{FMI2, FMI3};

    #[test]
    fn every_variable_has_one_row_with_its_unit_start_and_range() {
        let table = variable_table(&FMI2, &FMI3);
        for v in FMI3.variables {
            let rows: Vec<&str> = table
                .lines()
                .filter(|l| l.starts_with(&format!("| `{}` |", v.name)))
                .collect();
            assert_eq!(rows.len(), 1, "{}", v.name);
            assert_eq!(cells(rows[0]).len(), 7, "{}", rows[0]);
        }
        assert_eq!(table.lines().count(), FMI3.variables.len() + 2);
        assert!(table.contains(
            "| `plate.length` | parameter / fixed | Real | m | 0.4 | ≥ 0 | span Lx from the clamped edge x = 0 to the free edge |"
        ));
        assert!(
            table.contains("| `material.young_modulus` | parameter / fixed | Real | Pa | 2.1e11 |")
        );
        assert!(table.contains("| `mesh.element` | parameter / fixed | Integer |  | 1 | [1, 2] |"));
    }

    /// The committed docs carry the table of the current model descriptions: after a change of
    /// a variable, `cargo run --release --bin package-fmu -- --write-docs` rewrites them.
    #[test]
    fn the_docs_carry_the_current_table() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let table = variable_table(&FMI2, &FMI3);
        for file in TABLE_FILES {
            let text = std::fs::read_to_string(root.join(file)).unwrap();
            assert_eq!(
                with_table(file, &text, &table).unwrap(),
                text,
                "{file} is stale"
            );
        }
    }

    #[test]
    fn markdown_becomes_html() {
        let page = html(
            "# Title\n\nSome `code` and **bold**, a [file](fmu.md) and a [site](https://x.org/a).\n\n\
             * one\n  more\n* two\n\n| a | b |\n|---|---|\n| 1 \\| 2 | <3 |\n\n```\nx < y\n```\n",
            "T & U",
        );
        for part in [
            "<title>T &amp; U</title>",
            "<h1>Title</h1>",
            "<p>Some <code>code</code> and <strong>bold</strong>, a file (<code>docs/fmu.md</code>) and a <a href=\"https://x.org/a\">site</a>.</p>",
            "<ul>\n<li>one more</li>\n<li>two</li>\n</ul>",
            "<tr><th>a</th><th>b</th></tr>\n<tr><td>1 | 2</td><td>&lt;3</td></tr>",
            "<pre><code>x &lt; y\n</code></pre>",
        ] {
            assert!(page.contains(part), "{part:?} not in\n{page}");
        }
    }
}
