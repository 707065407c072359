"""The generated tables of the study pages follow from the committed CSVs.

Each study's write step (`python -m plateimpact_tools.studies.<module> DIR --tables-only`) runs on
a copy of docs/accuracy/; the page it rewrites must equal the committed one, so a CSV changed
without its tables, or a table edited by hand, fails here. The prose around the tables is checked
against the same CSVs by `cargo test --test documented_numbers` (docs/studies.md). No simulation
runs: a few seconds.
"""

import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

PAGES = [("accuracy_plots", "README.md"), ("statistics_plots", "statistics.md"),
         ("damping_plots", "damping.md")]


def write_step(module, directory, **options):
    """Runs the write step `module` of plateimpact_tools.studies with --tables-only on
    `directory`."""
    return subprocess.run([sys.executable, "-m", f"plateimpact_tools.studies.{module}",
                           str(directory), "--tables-only"], cwd=ROOT, **options)


@pytest.mark.parametrize("module,page", PAGES)
def test_generated_tables_match_the_committed_csvs(tmp_path, module, page):
    copy = tmp_path / "accuracy"
    shutil.copytree(ROOT / "docs" / "accuracy", copy)
    write_step(module, copy, check=True)
    committed = (ROOT / "docs" / "accuracy" / page).read_text()
    assert (copy / page).read_text() == committed, (
        f"docs/accuracy/{page}: its generated tables differ from what "
        f"plateimpact_tools.studies.{module} writes from the committed CSVs; run it with "
        "--tables-only on docs/accuracy and commit the page")


def test_a_page_and_its_tables_must_agree(tmp_path):
    """A generated block without its table is refused, not left stale."""
    copy = tmp_path / "accuracy"
    shutil.copytree(ROOT / "docs" / "accuracy", copy)
    page = copy / "statistics.md"
    page.write_text(page.read_text() + "\n<!-- generated: unknown (x) -->\n<!-- end generated: unknown -->\n")
    run = write_step("statistics_plots", copy, capture_output=True, text=True)
    assert run.returncode != 0 and "blocks without a table ['unknown']" in run.stderr
