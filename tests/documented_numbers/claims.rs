//! Claims: each number a document's prose states, tied to the value computed from the committed
//! CSVs, and the check that every number of the prose is claimed or named as an input.
//!
//! A claim quotes the prose around its number(s), the claimed numbers in braces:
//! `c.value("mean energy within {1.4} %", x)`. The quote (without the braces) must occur in the
//! prose; every occurrence is covered by the claim. What the claim asserts:
//! - [`Claims::value`], [`Claims::values`]: the computed value, rounded as the number is
//!   written, is the number: |stated − computed| ≤ half a unit of the stated number's last digit
//!   (`1.04` ± 0.005, `5` ± 0.5, `2e-6` ± 0.5e-6);
//! - [`Claims::upper`]: a bound, "within 1 %": computed ≤ stated (1.04 is not within 1);
//! - [`Claims::range`]: "0.01–0.4 %": the smallest and largest computed values round to the two
//!   numbers.
//!
//! - [`Claims::holds`]: a statement without a number ("the most on the 28 × 20 meshes", "not
//!   converged") whose truth the claim computes from the rows or the rule's verdicts.
//!
//! [`Claims::given`] names text whose numbers are inputs, not results (a setting of the study, a
//! parameter, a mesh's size, a tolerance the study applies, a reference to a section): every
//! number inside each occurrence is covered. A given text may hold no word of a verdict or a
//! comparison ([`VERDICT_WORDS`]): a result cannot pass as an input. [`Claims::defines`] names text
//! that defines a term or the rule ("converged when both ladders pass at 1 %"): it may use those
//! words, and its numbers are the definition's parameters. Mesh names `10 × 7` and `10×7` are
//! covered as such. Every other number of the prose is a failure naming its line, so a new number
//! cannot enter a checked document without its claim, and a rerun that moves a value fails until
//! the prose follows. A document that calls [`Claims::check_verdict_words`] also fails on every
//! verdict word of its prose that no claim's quote or definition holds.

use super::prose::{numbers_in, Prose, Token};

/// Words that state a verdict or compare results. A [`Claims::given`] text holds none; in a
/// document that checks them ([`Claims::check_verdict_words`]) each occurrence lies inside a
/// claim's quote or a definition.
pub const VERDICT_WORDS: [&str; 8] = [
    "converge",
    "settle",
    "agree",
    "the most",
    "least",
    "does not grow",
    "every mesh",
    "only the",
];

/// What a claim asserts of its computed values.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// Each stated number is its value, rounded.
    Rounded,
    /// The value is at most the stated number.
    Upper,
    /// The stated numbers are the smallest and largest values, rounded.
    Range,
    /// A statement without numbers, true by the computed value (1 for true).
    Holds,
}

struct Claim {
    /// The quote with its claimed numbers in braces.
    quote: String,
    kind: Kind,
    values: Vec<f64>,
}

/// How the numbers of a prose are covered: by a claim checked against data, as an input or a
/// definition's parameter, as a side of a mesh name; `total` counts every number.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tally {
    pub claimed: usize,
    pub inputs: usize,
    pub meshes: usize,
    pub total: usize,
}

/// The numbers of `markdown`'s prose (all of it, generated blocks and code aside): how many are
/// sides of mesh names, and how many in all.
pub fn unchecked_tally(markdown: &str) -> Tally {
    let prose = Prose::of(markdown, &[], &[], None);
    let tokens = prose.numbers();
    let meshes = (0..tokens.len())
        .filter(|&k| is_mesh(&prose.text, &tokens, k))
        .count();
    Tally {
        meshes,
        total: tokens.len(),
        ..Tally::default()
    }
}

/// The claims of one document (see the module documentation).
pub struct Claims {
    pub document: &'static str,
    /// First words of blocks (a paragraph, list item or table) left out, each with the reason.
    skipped_blocks: Vec<(&'static str, &'static str)>,
    /// The one section checked, when not the whole document, and why the rest is left out.
    only: Option<(&'static str, &'static str)>,
    claims: Vec<Claim>,
    given: Vec<String>,
    /// Texts that define a term or the rule: numbers and verdict words covered.
    definitions: Vec<String>,
    /// Whether every verdict word of the prose must lie inside a claim or a definition.
    verdict_words: bool,
}

/// A stated number as written in a quote: `−1.04`, `4 889`, `2.5e-6` (a thin or normal space
/// groups thousands).
fn parse(literal: &str) -> f64 {
    let plain: String = literal
        .chars()
        .filter(|c| !c.is_whitespace() && *c != '+')
        .map(|c| if c == '−' { '-' } else { c })
        .collect();
    plain
        .parse()
        .unwrap_or_else(|_| panic!("claimed number {literal:?} is not a number"))
}

/// Half a unit of the last digit of `literal`: 0.005 for `1.04`, 0.5 for `5`, 0.5e-6 for `2e-6`.
fn half_unit(literal: &str) -> f64 {
    let plain = literal.replace('−', "-");
    let (mantissa, exponent) = match plain.split_once(['e', 'E']) {
        Some((m, e)) => (m.to_string(), e.parse::<i32>().expect("exponent")),
        None => (plain.clone(), 0),
    };
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    0.5 * 10f64.powi(exponent - decimals)
}

/// The quote without braces, and the byte ranges (in it) of the braced numbers with their text.
fn unbrace(quote: &str) -> (String, Vec<(usize, usize, String)>) {
    let mut plain = String::new();
    let mut marked = Vec::new();
    let mut open = None;
    for c in quote.chars() {
        match c {
            '{' => open = Some(plain.len()),
            '}' => {
                let start = open
                    .take()
                    .unwrap_or_else(|| panic!("unbalanced }} in {quote:?}"));
                marked.push((start, plain.len(), plain[start..].to_string()));
            }
            _ => plain.push(c),
        }
    }
    assert!(open.is_none(), "unbalanced {{ in {quote:?}");
    (plain, marked)
}

impl Claims {
    pub fn new(document: &'static str) -> Claims {
        Claims {
            document,
            skipped_blocks: Vec::new(),
            only: None,
            claims: Vec::new(),
            given: Vec::new(),
            definitions: Vec::new(),
            verdict_words: false,
        }
    }

    /// Checks the section under `heading` alone, the rest of the document left out for `reason`.
    pub fn only_section(&mut self, heading: &'static str, reason: &'static str) {
        assert!(
            !reason.is_empty(),
            "the rest of the document needs the reason it is left out"
        );
        self.only = Some((heading, reason));
    }

    /// Leaves out the block (a paragraph, list item or table) whose first line starts with
    /// `start`, for `reason`.
    pub fn skip_block(&mut self, start: &'static str, reason: &'static str) {
        assert!(!reason.is_empty(), "a skipped block needs its reason");
        self.skipped_blocks.push((start, reason));
    }

    /// Texts whose numbers are inputs, not results (see the module documentation); a text with
    /// a word of [`VERDICT_WORDS`] is refused: a verdict is claimed, never given.
    pub fn given(&mut self, texts: &[&str]) {
        for text in texts {
            let lower = text.to_lowercase();
            if let Some(word) = VERDICT_WORDS.iter().find(|w| lower.contains(*w)) {
                panic!("given text {text:?} states a verdict ({word:?}): claim it instead");
            }
        }
        self.given.extend(texts.iter().map(|t| t.to_string()));
    }

    /// Texts that define a term or the rule (see the module documentation).
    pub fn defines(&mut self, texts: &[&str]) {
        self.definitions.extend(texts.iter().map(|t| t.to_string()));
    }

    /// Makes every verdict word of the prose ([`VERDICT_WORDS`]) need a claim or a definition.
    pub fn check_verdict_words(&mut self) {
        self.verdict_words = true;
    }

    /// The statement `quote` (no braced numbers) is true: `truth`, computed from the data.
    pub fn holds(&mut self, quote: &str, truth: bool) {
        self.push(quote, Kind::Holds, vec![f64::from(u8::from(truth))]);
    }

    fn push(&mut self, quote: &str, kind: Kind, values: Vec<f64>) {
        self.claims.push(Claim {
            quote: quote.to_string(),
            kind,
            values,
        });
    }

    /// The braced number of `quote` is `value`, rounded as written.
    pub fn value(&mut self, quote: &str, value: f64) {
        self.push(quote, Kind::Rounded, vec![value]);
    }

    /// The braced numbers of `quote` are `values`, in order, each rounded as written.
    pub fn values(&mut self, quote: &str, values: &[f64]) {
        self.push(quote, Kind::Rounded, values.to_vec());
    }

    /// The braced number of `quote` bounds `value` from above.
    pub fn upper(&mut self, quote: &str, value: f64) {
        self.push(quote, Kind::Upper, vec![value]);
    }

    /// The two braced numbers of `quote` are the smallest and largest of `values`, rounded.
    pub fn range(&mut self, quote: &str, values: &[f64]) {
        self.push(quote, Kind::Range, values.to_vec());
    }

    /// Every failure of the document: claims that do not hold or are not in the prose, given
    /// texts that are not, and numbers of the prose that nothing covers.
    pub fn failures(&self) -> Vec<String> {
        self.analyse().0
    }

    /// How the numbers of the document's checked prose are covered.
    pub fn tally(&self) -> Tally {
        self.analyse().1
    }

    /// The failures and the tally (see [`Claims::failures`], [`Tally`]).
    fn analyse(&self) -> (Vec<String>, Tally) {
        let path = super::root().join(self.document);
        let markdown =
            std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let blocks: Vec<&str> = self.skipped_blocks.iter().map(|(b, _)| *b).collect();
        let prose = Prose::of(&markdown, &[], &blocks, self.only.map(|o| o.0));
        let mut failures = Vec::new();
        let mut covered: Vec<Token> = Vec::new();
        // The numbers of claims, apart from those of inputs and definitions.
        let mut claimed: Vec<Token> = Vec::new();
        // Whole quotes of claims and definitions: where verdict words may stand.
        let mut stated: Vec<Token> = Vec::new();
        for claim in &self.claims {
            let (plain, marked) = unbrace(&claim.quote);
            let found = prose.occurrences(&plain);
            if found.is_empty() {
                failures.push(format!("claim not in the prose: {:?}", claim.quote));
                continue;
            }
            stated.extend(found.iter().map(|&at| Token {
                start: at,
                end: at + plain.len(),
            }));
            for at in &found {
                for (start, end, _) in &marked {
                    claimed.push(Token {
                        start: at + start,
                        end: at + end,
                    });
                }
            }
            let line = prose.line(found[0]);
            if let Some(wrong) = check(claim, &marked) {
                failures.push(format!("line {line}: {:?}: {wrong}", claim.quote));
            }
        }
        for text in &self.given {
            let found = prose.occurrences(text);
            if found.is_empty() {
                failures.push(format!("given text not in the prose: {text:?}"));
            }
            for at in found {
                covered.extend(numbers_in(text).into_iter().map(|t| Token {
                    start: at + t.start,
                    end: at + t.end,
                }));
            }
        }
        for text in &self.definitions {
            let found = prose.occurrences(text);
            if found.is_empty() {
                failures.push(format!("definition not in the prose: {text:?}"));
            }
            for at in found {
                stated.push(Token {
                    start: at,
                    end: at + text.len(),
                });
                covered.extend(numbers_in(text).into_iter().map(|t| Token {
                    start: at + t.start,
                    end: at + t.end,
                }));
            }
        }
        if self.verdict_words {
            let lower = prose.text.to_lowercase();
            for word in VERDICT_WORDS {
                for (at, _) in lower.match_indices(word) {
                    let inside = |c: &Token| c.start <= at && at + word.len() <= c.end;
                    if !stated.iter().any(inside) {
                        failures.push(format!(
                            "line {}: verdict word {word:?} without a claim: {}",
                            prose.line(at),
                            prose.context(Token {
                                start: at,
                                end: at + word.len()
                            })
                        ));
                    }
                }
            }
        }
        let tokens = prose.numbers();
        let mut tally = Tally {
            total: tokens.len(),
            ..Tally::default()
        };
        for (k, token) in tokens.iter().enumerate() {
            let inside = |c: &Token| c.start <= token.start && token.end <= c.end;
            if claimed.iter().any(inside) {
                tally.claimed += 1;
            } else if covered.iter().any(inside) {
                tally.inputs += 1;
            } else if is_mesh(&prose.text, &tokens, k) {
                tally.meshes += 1;
            } else {
                failures.push(format!(
                    "line {}: number without a claim: {}",
                    prose.line(token.start),
                    prose.context(*token)
                ));
            }
        }
        (failures, tally)
    }

    /// Fails with every failure of the document, one per line.
    pub fn check(&self) {
        let failures = self.failures();
        assert!(
            failures.is_empty(),
            "{}: {} failure(s):\n{}",
            self.document,
            failures.len(),
            failures.join("\n")
        );
    }
}

/// Whether token `k` is a side of a mesh name, `10 × 7` or `10×7` (whole numbers).
fn is_mesh(text: &str, tokens: &[Token], k: usize) -> bool {
    let whole = |t: &Token| text[t.start..t.end].bytes().all(|b| b.is_ascii_digit());
    let joined = |a: &Token, b: &Token| {
        let between = text[a.end..b.start].trim();
        between == "×" && whole(a) && whole(b)
    };
    let t = &tokens[k];
    (k > 0 && joined(&tokens[k - 1], t)) || tokens.get(k + 1).is_some_and(|n| joined(t, n))
}

/// Why `claim` does not hold, if it does not; `marked` are its braced numbers.
fn check(claim: &Claim, marked: &[(usize, usize, String)]) -> Option<String> {
    let stated: Vec<(f64, f64)> = marked
        .iter()
        .map(|(_, _, text)| (parse(text), half_unit(text)))
        .collect();
    let values = &claim.values;
    let expect = |n: usize| {
        (stated.len() != n).then(|| format!("{} braced numbers, {n} expected", stated.len()))
    };
    match claim.kind {
        Kind::Rounded => {
            if stated.len() != values.len() {
                return Some(format!(
                    "{} braced numbers for {} values",
                    stated.len(),
                    values.len()
                ));
            }
            let wrong: Vec<String> = stated
                .iter()
                .zip(values)
                .filter(|((s, half), v)| (s - *v).abs() > half * (1.0 + 1e-9))
                .map(|((s, _), v)| format!("states {s}, the data give {v:.6}"))
                .collect();
            (!wrong.is_empty()).then(|| wrong.join("; "))
        }
        Kind::Upper => expect(1).or_else(|| {
            let s = stated[0].0;
            (values[0] > s).then(|| format!("states at most {s}, the data give {:.6}", values[0]))
        }),
        Kind::Holds => {
            expect(0).or_else(|| (values[0] != 1.0).then(|| "the data say it is false".to_string()))
        }
        Kind::Range => expect(2).or_else(|| {
            let (lo, hi) = super::data::span(values);
            let ((a, ha), (b, hb)) = (stated[0], stated[1]);
            ((a - lo).abs() > ha * (1.0 + 1e-9) || (b - hi).abs() > hb * (1.0 + 1e-9))
                .then(|| format!("states {a}–{b}, the data span {lo:.6}–{hi:.6}"))
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_number_is_read_with_the_precision_it_is_written_with() {
        assert_eq!(parse("−1.04"), -1.04);
        assert_eq!(parse("4 889"), 4889.0);
        assert!((half_unit("1.04") - 0.005).abs() < 1e-15);
        assert_eq!(half_unit("5"), 0.5);
        assert!((half_unit("2e-6") - 0.5e-6).abs() < 1e-20);
        assert!((half_unit("2.5e−6") - 0.05e-6).abs() < 1e-20);
    }

    #[test]
    fn braces_mark_the_claimed_numbers() {
        let (plain, marked) = unbrace("from {1.4} to {2} %");
        assert_eq!(plain, "from 1.4 to 2 %");
        assert_eq!(marked[0], (5, 8, "1.4".to_string()));
        assert_eq!(&plain[marked[1].0..marked[1].1], "2");
    }

    fn claim(kind: Kind, quote: &str, values: &[f64]) -> Option<String> {
        let (_, marked) = unbrace(quote);
        let c = Claim {
            quote: quote.into(),
            kind,
            values: values.to_vec(),
        };
        check(&c, &marked)
    }

    #[test]
    fn each_kind_holds_or_fails_where_it_should() {
        assert!(claim(Kind::Rounded, "{1.04} %", &[1.044]).is_none());
        assert!(claim(Kind::Rounded, "{1.04} %", &[1.046]).is_some());
        assert!(claim(Kind::Upper, "within {1} %", &[0.3]).is_none());
        assert!(claim(Kind::Upper, "within {1} %", &[1.04]).is_some());
        assert!(claim(Kind::Range, "{0.01}–{0.4} %", &[0.4, 0.012, 0.2]).is_none());
        assert!(claim(Kind::Range, "{0.01}–{0.4} %", &[0.5, 0.012]).is_some());
        assert!(claim(Kind::Holds, "the most", &[1.0]).is_none());
        assert!(claim(Kind::Holds, "the most", &[0.0]).is_some());
        assert!(claim(Kind::Holds, "{1} most", &[1.0]).is_some());
    }
}

#[cfg(test)]
mod given_tests {
    use super::*;

    #[test]
    #[should_panic(expected = "states a verdict")]
    fn a_verdict_cannot_be_given() {
        Claims::new("README.md").given(&["converged to 5 %"]);
    }
}
