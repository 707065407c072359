//! The committed CSVs, read as tables of text cells, and the rows a claim selects from them.
//!
//! A selection is written as space-separated terms `column=value` (also `!=`, `<`, `<=`, `>`,
//! `>=`), plus the shorthand `mesh=argyris:10x7` for `element=argyris nx=10 ny=7` (in a table
//! without a `mesh` column: the verdicts of the rule name the mesh so). Cells and
//! values compare as numbers when both parse as numbers (`dt=1e-4` matches `0.0001`), else as
//! text.

use std::path::Path;

/// One CSV file: its header and rows.
pub struct Table {
    pub path: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

/// The fields of one CSV line; a field in double quotes may hold commas and doubled quotes.
fn fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut field)),
            _ => field.push(c),
        }
    }
    out.push(field);
    out
}

/// A term of a selection.
struct Term {
    column: String,
    op: &'static str,
    value: String,
}

/// The terms of `selection`; `mesh=` is expanded unless the table has a `mesh` column.
fn terms(selection: &str, mesh_column: bool) -> Vec<Term> {
    let mut out = Vec::new();
    for word in selection.split_whitespace() {
        let op = ["!=", "<=", ">=", "=", "<", ">"]
            .into_iter()
            .find(|op| word.contains(op))
            .unwrap_or_else(|| panic!("selection term {word:?}: use column=value"));
        let (column, value) = word.split_once(op).expect("operator");
        if column == "mesh" && !mesh_column {
            let (element, cells) = value
                .split_once(':')
                .unwrap_or_else(|| panic!("{word}: use mesh=ELEMENT:NXxNY"));
            let (nx, ny) = cells
                .split_once('x')
                .unwrap_or_else(|| panic!("{word}: use mesh=ELEMENT:NXxNY"));
            for (c, v) in [("element", element), ("nx", nx), ("ny", ny)] {
                out.push(Term {
                    column: c.into(),
                    op: "=",
                    value: v.into(),
                });
            }
        } else {
            out.push(Term {
                column: column.into(),
                op,
                value: value.into(),
            });
        }
    }
    out
}

/// Whether `cell` stands in relation `op` to `value`, as numbers when both are.
fn holds(cell: &str, op: &str, value: &str) -> bool {
    use std::cmp::Ordering::{Equal, Greater, Less};
    let order = match (cell.parse::<f64>(), value.parse::<f64>()) {
        (Ok(a), Ok(b)) => a.partial_cmp(&b),
        _ => Some(cell.cmp(value)),
    };
    matches!(
        (op, order),
        ("=", Some(Equal))
            | ("!=", Some(Less | Greater))
            | ("<", Some(Less))
            | ("<=", Some(Less | Equal))
            | (">", Some(Greater))
            | (">=", Some(Greater | Equal))
    )
}

impl Table {
    /// Reads the CSV at `path` (relative to the repository root).
    pub fn load(root: &Path, path: &str) -> Table {
        let text =
            std::fs::read_to_string(root.join(path)).unwrap_or_else(|e| panic!("{path}: {e}"));
        let mut lines = text.lines().filter(|l| !l.trim().is_empty());
        let header = fields(lines.next().unwrap_or_else(|| panic!("{path} is empty")));
        let rows = lines.map(fields).collect();
        Table {
            path: path.to_string(),
            header,
            rows,
        }
    }

    /// Whether the table has the column `name`.
    pub fn has_column(&self, name: &str) -> bool {
        self.header.iter().any(|h| h == name)
    }

    fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{} has no column {name:?}", self.path))
    }

    /// The rows that satisfy every term of `selection`.
    pub fn select(&self, selection: &str) -> Vec<Row<'_>> {
        let terms = terms(selection, self.has_column("mesh"));
        let columns: Vec<usize> = terms.iter().map(|t| self.column(&t.column)).collect();
        self.rows
            .iter()
            .filter(|row| {
                terms
                    .iter()
                    .zip(&columns)
                    .all(|(t, &c)| row.get(c).is_some_and(|cell| holds(cell, t.op, &t.value)))
            })
            .map(|cells| Row { table: self, cells })
            .collect()
    }

    /// The one row `selection` picks (a failure names the selection when it picks none or
    /// several).
    pub fn one(&self, selection: &str) -> Row<'_> {
        let rows = self.select(selection);
        assert!(
            rows.len() == 1,
            "{}: [{selection}] selects {} rows, not one",
            self.path,
            rows.len()
        );
        rows[0]
    }
}

/// One row of a [`Table`].
#[derive(Clone, Copy)]
pub struct Row<'a> {
    table: &'a Table,
    cells: &'a [String],
}

impl Row<'_> {
    /// The cell of `column` as text.
    pub fn text(&self, column: &str) -> &str {
        &self.cells[self.table.column(column)]
    }

    /// The cell of `column` as a number.
    pub fn number(&self, column: &str) -> f64 {
        let cell = self.text(column);
        cell.parse()
            .unwrap_or_else(|_| panic!("{}: {column} = {cell:?} is not a number", self.table.path))
    }
}

/// The committed CSV at `path` (relative to the repository root).
pub fn table(path: &str) -> Table {
    Table::load(super::root(), path)
}

/// 100·(a/b − 1): `a` relative to `b`, in percent.
pub fn pct(a: f64, b: f64) -> f64 {
    100.0 * (a / b - 1.0)
}

/// The smallest and largest of `values`.
pub fn span(values: &[f64]) -> (f64, f64) {
    values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &v| {
            (lo.min(v), hi.max(v))
        })
}

/// The number under `key` in a meta file (`key,value` rows).
pub fn meta(path: &str, key: &str) -> f64 {
    table(path).one(&format!("key={key}")).number("value")
}
