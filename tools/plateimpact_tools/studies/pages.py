"""The hand-written pages of the studies and the tables and figure data the studies write into
and beside them.

A study page (docs/accuracy/README.md, statistics.md, damping.md) is Markdown written by hand.
Each table a study generates sits in a block of the page,

    <!-- generated: NAME (MODULE; do not edit) -->
    | the table |
    <!-- end generated: NAME -->

and `fill` replaces the content of every block with the table of that name: the prose around the
blocks is never touched, and every number it states is checked against the CSVs by
`cargo test --test documented_numbers` (docs/studies.md, "Numbers in the prose"). A block
without its table, or a table without its block, is an error: the page and the study disagree.

Beside each figure `figure_data` writes the data it shows, as the CSV of the figure's name
(`work_precision.png`: `work_precision.csv`), one row per plotted point.
"""

import csv
import re
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

BLOCK = re.compile(
    r"<!-- generated: (?P<name>[\w-]+) \([^)]*\) -->\n.*?<!-- end generated: (?P=name) -->", re.S
)


class PageError(Exception):
    """The generated blocks of a page and the tables of its study disagree."""


def fill(page: Path, tables: dict[str, list[str]], module: str) -> None:
    """Replaces the content of each generated block of `page` (a Path) by `tables[name]` (lines
    of Markdown), naming `module` as its source."""
    text = page.read_text()
    names = [m.group("name") for m in BLOCK.finditer(text)]
    without_table = [n for n in names if n not in tables]
    without_block = [n for n in tables if n not in names]
    if without_table or without_block or len(set(names)) != len(names):
        raise PageError(
            f"{page}: blocks without a table {without_table}, tables without a "
            f"block {without_block}, blocks {names}"
        )

    def block(match: re.Match[str]) -> str:
        name = match.group("name")
        body = "\n".join(tables[name])
        return (
            f"<!-- generated: {name} ({module}; do not edit) -->\n{body}\n"
            f"<!-- end generated: {name} -->"
        )

    page.write_text(BLOCK.sub(block, text))


def figure_data(figure: str | Path, header: list[str], rows: Iterable[Sequence[Any]]) -> None:
    """Writes `rows` (under `header`) to the CSV beside `figure` (a Path to the .png)."""
    with open(Path(figure).with_suffix(".csv"), "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows(rows)
