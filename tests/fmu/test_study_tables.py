"""The generated tables of the study pages follow from the committed CSVs.

Each study's write step (`examples/studies/<script> DIR --tables-only`) runs on a copy of
docs/accuracy/; the page it rewrites must equal the committed one, so a CSV changed without its
tables, or a table edited by hand, fails here. The prose around the tables is checked against the
same CSVs by `cargo test --test documented_numbers` (docs/studies.md). No simulation runs: a few
seconds.
"""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGES = [("accuracy_plots.py", "README.md"), ("statistics_plots.py", "statistics.md"),
         ("damping_plots.py", "damping.md")]


@pytest.mark.parametrize("script,page", PAGES)
def test_generated_tables_match_the_committed_csvs(tmp_path, script, page):
    copy = tmp_path / "accuracy"
    shutil.copytree(ROOT / "docs" / "accuracy", copy)
    subprocess.run([sys.executable, str(ROOT / "examples" / "studies" / script), str(copy),
                    "--tables-only"], check=True)
    committed = (ROOT / "docs" / "accuracy" / page).read_text()
    assert (copy / page).read_text() == committed, (
        f"docs/accuracy/{page}: its generated tables differ from what examples/studies/{script} "
        "writes from the committed CSVs; run it with --tables-only on docs/accuracy and commit "
        "the page")


def test_a_page_and_its_tables_must_agree(tmp_path):
    """A generated block without its table is refused, not left stale."""
    copy = tmp_path / "accuracy"
    shutil.copytree(ROOT / "docs" / "accuracy", copy)
    page = copy / "statistics.md"
    page.write_text(page.read_text() + "\n<!-- generated: unknown (x) -->\n<!-- end generated: unknown -->\n")
    run = subprocess.run([sys.executable, str(ROOT / "examples" / "studies" / "statistics_plots.py"),
                          str(copy), "--tables-only"], capture_output=True, text=True)
    assert run.returncode != 0 and "blocks without a table ['unknown']" in run.stderr
