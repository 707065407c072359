"""The cost model of scripts/converge's budget (plateimpact_tools.converge.cost) without an FMU:
its regimes switch where the Rust's dense eigensolver ends, and the tables of
docs/converge/README.md ("The cost model, predicted against measured") are the model's figures
beside measured ones within a factor of 1.5. A refit that moves the model fails here until the
tables follow (`python -m plateimpact_tools.converge.step_cost --check` prints them)."""

import re

import pytest

from conftest import ROOT
from plateimpact_tools.converge import cost

README = ROOT / "docs" / "converge" / "README.md"
FACTOR = 1.5  # how far a measured figure may lie from the model's


def test_the_regimes_switch_at_the_dense_limit():
    """DENSE_LIMIT is the Rust's (MODAL_AUTO_LIMIT, which DENSE_LIMIT of src/modes/mod.rs is), and
    a modal plate above it takes the large basis's laws, whose set-up at 5 257 free dofs is a
    third of what the dense laws carried past the limit would say."""
    choice = (ROOT / "src" / "backend_choice.rs").read_text()
    assert f"pub const MODAL_AUTO_LIMIT: usize = {cost.DENSE_LIMIT};" in choice
    modes = (ROOT / "src" / "modes" / "mod.rs").read_text()
    assert "pub const DENSE_LIMIT: usize = crate::backend_choice::MODAL_AUTO_LIMIT;" in modes
    limit = cost.DENSE_LIMIT
    assert cost.regime((limit, "modal")) == "modal"
    assert cost.regime((limit + 1, "modal")) == "modal-large"
    assert cost.regime((limit + 1, "sparse")) == cost.regime((100, "sparse")) == "sparse"
    for element in (1, 2):
        for name in ("modal", "modal-large", "sparse"):
            assert (element, name) in cost.RUN_COST
    (c, p), _, _ = cost.RUN_COST[(1, "modal")]
    assert cost.setup_seconds((5257, "modal"), 1) < c * 5.257**p / 3


def rows(header):
    """The cells of the Markdown table of README whose header line starts with `header`."""
    lines = README.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if line.startswith(header))
    table = []
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        table.append([cell.strip() for cell in line.strip("|").split("|")])
    assert table, header
    return table


def mesh(text):
    """(element, nx, ny) of "Argyris 16 × 9"."""
    name, nx, ny = re.fullmatch(r"(Argyris|FVS) (\d+) × (\d+)", text).groups()
    return {"Argyris": 1, "FVS": 2}[name], int(nx), int(ny)


def test_the_step_table_is_the_model_within_its_factor():
    """Per mesh: the model's set-up, internal step and communication step as the table prints
    them (3 significant digits), each measured figure within FACTOR of it (the sparse set-up,
    which the model leaves out, below a second); Argyris 28 × 20 (5 257 free dofs) and two more
    meshes above 2000 free dofs on the modal backend among them."""
    large = 0
    for cells in rows("| mesh | free dofs | regime | set-up s: model"):
        element, _, _ = mesh(cells[0])
        size = (int(cells[1]), "sparse" if cells[2] == "sparse" else "modal")
        assert cost.regime(size) == cells[2], cells
        large += cells[2] == "modal-large"
        model = [
            cost.setup_seconds(size, element),
            cost.step_us(size, element),
            cost.communication_us(size, element),
        ]
        for k, m in enumerate(model):
            shown, measured = float(cells[3 + 2 * k]), float(cells[4 + 2 * k])
            assert shown == pytest.approx(float(f"{m:.3g}")), (cells, k)
            if m == 0.0:
                assert measured < 1.0, cells
            else:
                assert 1 / FACTOR < measured / m < FACTOR, (cells, k)
    assert large >= 3
    assert ["Argyris 28 × 20", "5257", "modal-large"] in [r[:3] for r in rows("| mesh | free")]


def test_the_run_table_is_run_cost_within_its_factor():
    """Per whole run: `run_cost` at its Δt and simulated time, read every h = 1e-4 s, as the table
    prints it, and the measured CPU within FACTOR of it."""
    for cells in rows("| run (h = 1e-4 s) |"):
        match = re.fullmatch(r"(.+), Δt = ([0-9.e-]+) s, ([0-9.]+) s", cells[0])
        element, _, _ = mesh(match[1])
        size = (int(cells[1]), "sparse" if cells[2] == "sparse" else "modal")
        assert cost.regime(size) == cells[2], cells
        model = cost.run_cost(size, element, float(match[2]), float(match[3]), 1e-4)
        assert float(cells[3]) == pytest.approx(float(f"{model:.3g}")), cells
        assert 1 / FACTOR < float(cells[4]) / model < FACTOR, cells
