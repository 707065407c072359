//! The prose of a Markdown document, as the claims see it, and the numbers it states.
//!
//! Prose is the document's text without what is not stated by its author in words: fenced and
//! indented code blocks, link and image targets, HTML comments and the tables a study
//! writes between `<!-- generated: NAME ... -->` and `<!-- end generated: NAME -->` (checked by
//! their generator, not here), and the sections a document's claims leave out. Inline code stays
//! in the text that quotes match, but its numbers are names, not claims. Whitespace runs,
//! line breaks included, become one space, `**` (bold) is dropped and `\|` becomes `|`, so a
//! quote matches however the paragraph is wrapped.

/// The prose of one document: its normalized text and, per character of it, the line of the
/// document it comes from.
pub struct Prose {
    pub text: String,
    /// Line (1-based) of each byte of `text`.
    line_of: Vec<usize>,
    /// Whether each byte of `text` is inline code: quoted like prose, but its numbers are names.
    code: Vec<bool>,
}

/// A number written in prose: its byte range in [`Prose::text`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Token {
    pub start: usize,
    pub end: usize,
}

/// The opening of a generated block; the block ends at the line holding [`GENERATED_END`].
pub const GENERATED_BEGIN: &str = "<!-- generated:";
/// The closing marker of a generated block.
pub const GENERATED_END: &str = "<!-- end generated:";

/// Whether `line` opens a section whose heading is in `sections` (`## Title`, matched by the
/// title), and its level.
fn heading(line: &str) -> Option<(usize, &str)> {
    let level = line.chars().take_while(|&c| c == '#').count();
    (level > 0 && line[level..].starts_with(' ')).then(|| (level, line[level..].trim()))
}

/// Whether `line` opens an item of a numbered list: `12. text`.
fn numbered_item(line: &str) -> bool {
    let digits = line.bytes().take_while(u8::is_ascii_digit).count();
    digits > 0 && line[digits..].starts_with(". ")
}

impl Prose {
    /// The prose of `markdown`, without the sections whose headings are in `skipped` and the
    /// blocks (paragraph, list item, table: up to a blank line, the next list item or heading)
    /// whose first line starts with one of `blocks`; with `only`, the section under that heading
    /// alone.
    pub fn of(markdown: &str, skipped: &[&str], blocks: &[&str], only: Option<&str>) -> Prose {
        let mut kept: Vec<(usize, Vec<(char, bool)>)> = Vec::new();
        let (mut fenced, mut generated, mut comment) = (false, false, false);
        let mut skipping: Option<usize> = None;
        let mut in_block = false;
        // Inside the `only` section: its level, and whether the line is in it.
        let mut inside: Option<usize> = None;
        let mut previous_blank = true;
        for (n, line) in markdown.lines().enumerate() {
            let trimmed = line.trim_start();
            if let Some((level, title)) = heading(line).filter(|_| !fenced) {
                skipping = match skipping {
                    Some(at) if level > at => Some(at),
                    _ => skipped.contains(&title).then_some(level),
                };
                inside = match inside {
                    Some(at) if level > at => Some(at),
                    _ => (only == Some(title)).then_some(level),
                };
            }
            let outside = only.is_some() && inside.is_none();
            let block_ends = trimmed.is_empty()
                || trimmed.starts_with("- ")
                || numbered_item(trimmed)
                || heading(line).is_some();
            if in_block && block_ends {
                in_block = false;
            }
            if !fenced && blocks.iter().any(|b| trimmed.starts_with(b)) {
                in_block = true;
            }
            let indented_code = line.starts_with("    ") && previous_blank;
            let code_line = fenced || trimmed.starts_with("```") || indented_code;
            if trimmed.starts_with("```") {
                fenced = !fenced;
            }
            if line.contains(GENERATED_BEGIN) {
                generated = true;
            }
            let hidden = code_line || generated || skipping.is_some() || in_block || outside;
            if line.contains(GENERATED_END) {
                generated = false;
            }
            // An indented code block goes on while its lines stay indented or blank.
            previous_blank = line.trim().is_empty() || (indented_code && !fenced);
            if hidden {
                kept.push((n + 1, Vec::new()));
                continue;
            }
            let mut text = Vec::new();
            comment = strip_inline(line, comment, &mut text);
            kept.push((n + 1, text));
        }
        let mut prose = Prose {
            text: String::new(),
            line_of: Vec::new(),
            code: Vec::new(),
        };
        for (line, text) in kept {
            for (c, code) in text.into_iter().chain(std::iter::once((' ', false))) {
                let space = c.is_whitespace();
                if space && (prose.text.is_empty() || prose.text.ends_with(' ')) {
                    continue;
                }
                let c = if space { ' ' } else { c };
                prose.text.push(c);
                prose
                    .line_of
                    .extend(std::iter::repeat_n(line, c.len_utf8()));
                prose.code.extend(std::iter::repeat_n(code, c.len_utf8()));
            }
        }
        prose
    }

    /// The line of the document that byte `at` of the prose comes from.
    pub fn line(&self, at: usize) -> usize {
        self.line_of.get(at).copied().unwrap_or(0)
    }

    /// Up to 40 bytes of prose each side of `token`, for messages.
    pub fn context(&self, token: Token) -> String {
        let mut start = token.start.saturating_sub(40);
        while !self.text.is_char_boundary(start) {
            start -= 1;
        }
        let mut end = (token.end + 40).min(self.text.len());
        while !self.text.is_char_boundary(end) {
            end += 1;
        }
        format!(
            "{}[{}]{}",
            &self.text[start..token.start],
            &self.text[token.start..token.end],
            &self.text[token.end..end]
        )
    }

    /// The byte offsets at which `quote` occurs in the prose.
    pub fn occurrences(&self, quote: &str) -> Vec<usize> {
        self.text.match_indices(quote).map(|(at, _)| at).collect()
    }

    /// Every number the prose writes: a run of ASCII digits not glued to a word before it (so
    /// not `fmi2`, `x86_64`, `f1`), with its decimals and an exponent (`1e-4`, `2.5e−6`).
    pub fn numbers(&self) -> Vec<Token> {
        numbers_in(&self.text)
            .into_iter()
            .filter(|t| !self.code[t.start])
            .collect()
    }
}

/// The numbers of `text` (see [`Prose::numbers`]).
pub fn numbers_in(text: &str) -> Vec<Token> {
    let bytes = text.as_bytes();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let glued = text[..i]
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.');
        if !bytes[i].is_ascii_digit() || glued {
            i += text[i..].chars().next().map_or(1, char::len_utf8);
            continue;
        }
        let start = i;
        let digits = |mut j: usize| {
            while j < bytes.len() && bytes[j].is_ascii_digit() {
                j += 1;
            }
            j
        };
        i = digits(i);
        if bytes.get(i) == Some(&b'.') && bytes.get(i + 1).is_some_and(u8::is_ascii_digit) {
            i = digits(i + 1);
        }
        if bytes.get(i) == Some(&b'e') {
            let rest = &text[i + 1..];
            let sign = ["-", "+", "−"].iter().find(|s| rest.starts_with(**s));
            let after = i + 1 + sign.map_or(0, |s| s.len());
            if bytes.get(after).is_some_and(u8::is_ascii_digit) {
                i = digits(after);
            }
        }
        tokens.push(Token { start, end: i });
    }
    tokens
}

/// Appends to `out` the prose of `line`, each character with whether it is inline code: without
/// link targets and HTML comments (`comment`: one is open at the start of the line; returned: one
/// is open at its end), `**` dropped and `\|` as `|`.
fn strip_inline(line: &str, mut comment: bool, out: &mut Vec<(char, bool)>) -> bool {
    let mut rest = line;
    let push = |out: &mut Vec<(char, bool)>, text: &str, code: bool| {
        out.extend(text.chars().map(|c| (c, code)));
    };
    while !rest.is_empty() {
        if comment {
            match rest.find("-->") {
                Some(end) => {
                    rest = &rest[end + 3..];
                    comment = false;
                    push(out, " ", false);
                }
                None => return true,
            }
            continue;
        }
        if let Some(after) = rest.strip_prefix("<!--") {
            comment = true;
            rest = after;
        } else if rest.starts_with('`') {
            let ticks = rest.chars().take_while(|&c| c == '`').count();
            let fence = &rest[..ticks];
            match rest[ticks..].find(fence) {
                Some(end) => {
                    push(out, &rest[..ticks + end + ticks], true);
                    rest = &rest[ticks + end + ticks..];
                }
                None => {
                    push(out, fence, false);
                    rest = &rest[ticks..];
                }
            }
        } else if let Some(after) = rest.strip_prefix("](") {
            push(out, "]", false);
            rest = after.find(')').map_or("", |end| &after[end + 1..]);
        } else if let Some(after) = rest.strip_prefix("**") {
            rest = after;
        } else if let Some(after) = rest.strip_prefix("\\|") {
            push(out, "|", false);
            rest = after;
        } else {
            let c = rest.chars().next().expect("not empty");
            out.push((c, false));
            rest = &rest[c.len_utf8()..];
        }
    }
    comment
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<&str> {
        numbers_in(text)
            .iter()
            .map(|t| &text[t.start..t.end])
            .collect()
    }

    #[test]
    fn numbers_are_found_with_decimals_and_exponents_but_not_inside_words() {
        assert_eq!(
            words("Δt = 1e-4 s, 2.5e−6 m, 13 s, fmi2 x86_64 f1 10 × 7, 4e and 3.x"),
            ["1e-4", "2.5e−6", "13", "10", "7", "4", "3"]
        );
    }

    #[test]
    fn code_links_comments_and_generated_tables_are_not_prose() {
        let markdown = "A **bold** 1 `code 2` [link 3](target-4.md) <!-- 5 -->\n\n    \
                        indented 6\n\n```\n7\n```\n<!-- generated: t -->\n| 8 |\n\
                        <!-- end generated: t -->\nwrapped\nline 9 a \\| b\n## Skipped\n10\n\
                        ### Sub\n11\n## Kept\n12\n- Left 13\n  out 14\n- kept 15\n";
        let prose = Prose::of(markdown, &["Skipped"], &["- Left"], None);
        let kept = Prose::of(markdown, &[], &[], Some("Kept"));
        assert_eq!(kept.numbers().len(), 4, "12 to 15 only: {}", kept.text);
        let numbers: Vec<&str> = prose
            .numbers()
            .iter()
            .map(|t| &prose.text[t.start..t.end])
            .collect();
        assert_eq!(numbers, ["1", "3", "9", "12", "15"]);
        assert!(
            prose.text.contains("`code 2`"),
            "inline code is quoted like prose"
        );
        assert!(prose.text.contains("A bold 1"));
        assert!(prose.text.contains("wrapped line 9 a | b"));
        let nine = prose.text.find('9').unwrap();
        assert_eq!(prose.line(nine), 12);
    }
}
