"""The generated tables of the study pages follow from the committed CSVs.

Each study's write step (`python -m plateimpact_tools.studies.<module> DIR --tables-only`) runs on
a copy of docs/accuracy/; the page it rewrites and every file it writes beside it (the verdicts of
the rule, `*_verdicts.csv`) must equal the committed ones, so a CSV changed without its tables or
verdicts, or a table edited by hand, fails here. The prose around the tables is checked
against the same CSVs by `cargo test --test documented_numbers` (docs/studies.md). No simulation
runs: a few seconds.
"""

import shutil
import subprocess
import sys

import pytest

from conftest import ROOT

PAGES = [
    ("accuracy_plots", "README.md"),
    ("statistics_plots", "statistics.md"),
    ("damping_plots", "damping.md"),
    ("modal_damping_plots", "modal_damping.md"),
]


def write_step(module, directory, **options):
    """Runs the write step `module` of plateimpact_tools.studies with --tables-only on
    `directory`."""
    return subprocess.run(
        [
            sys.executable,
            "-m",
            f"plateimpact_tools.studies.{module}",
            str(directory),
            "--tables-only",
        ],
        cwd=ROOT,
        **options,
    )


@pytest.mark.parametrize("module,page", PAGES)
def test_generated_tables_match_the_committed_csvs(tmp_path, module, page):
    copy = tmp_path / "accuracy"
    shutil.copytree(ROOT / "docs" / "accuracy", copy)
    write_step(module, copy, check=True)
    committed = ROOT / "docs" / "accuracy"
    written = sorted(p.name for p in copy.iterdir())
    assert written == sorted(p.name for p in committed.iterdir()), (
        f"plateimpact_tools.studies.{module} writes files docs/accuracy/ does not commit"
    )
    changed = [
        name for name in written if (copy / name).read_bytes() != (committed / name).read_bytes()
    ]
    assert not changed, (
        f"docs/accuracy/{changed}: differ from what plateimpact_tools.studies.{module} writes "
        f"from the committed CSVs (the page {page} and its verdicts); run it with --tables-only "
        "on docs/accuracy and commit the result"
    )


def test_a_page_and_its_tables_must_agree(tmp_path):
    """A generated block without its table is refused, not left stale."""
    copy = tmp_path / "accuracy"
    shutil.copytree(ROOT / "docs" / "accuracy", copy)
    page = copy / "statistics.md"
    page.write_text(
        page.read_text() + "\n<!-- generated: unknown (x) -->\n<!-- end generated: unknown -->\n"
    )
    run = write_step("statistics_plots", copy, capture_output=True, text=True)
    assert run.returncode != 0 and "blocks without a table ['unknown']" in run.stderr
