"""The numbers docs/converge/README.md and README.md state about the documented example follow
from its committed output, docs/converge/runs.csv: the rule (plateimpact_tools.rule)
replayed on the runs' values and spreads gives the verdict line, the error bounds, the ladder
table and the cost the pages print. No FMU runs: a rerun of the example that moves a number fails
here until the prose follows."""

import csv
import re
from collections import defaultdict

from conftest import ROOT
from plateimpact_tools import rule
from plateimpact_tools.converge import states
from plateimpact_tools.converge.study import refinement_ratio

DOCS = ROOT / "docs" / "converge"
TOLERANCE = 0.01  # the example's --tolerance
QUANTITIES = ["mean_energy", "rms_corner"]
# The ladders the example climbed (report.md, "The rule on each ladder"; the method of
# docs/converge/README.md): Δt on Argyris 4 × 2, the mesh at 2.5e-5 s, Δt again on 14 × 8, the
# mesh again at 1.25e-5 s, which closes.
DT1 = [(4, 2, 1e-4), (4, 2, 5e-5), (4, 2, 2.5e-5)]
MESH1 = [(6, 3, 2.5e-5), (9, 5, 2.5e-5), (14, 8, 2.5e-5)]
DT2_FIRST = [(14, 8, 1e-4), (14, 8, 5e-5), (14, 8, 2.5e-5)]
DT2 = [(14, 8, 5e-5), (14, 8, 2.5e-5), (14, 8, 1.25e-5)]
MESH2 = [(6, 3, 1.25e-5), (9, 5, 1.25e-5), (14, 8, 1.25e-5)]
RECOMMENDED = (14, 8, 1.25e-5)


def example_runs():
    """{(nx, ny, dt): {start: {quantity: (value, spread)}}}, {(nx, ny, dt, start): cpu_s} and the
    simulated seconds of a run, from runs.csv."""
    stats, cpu, simulated = defaultdict(lambda: defaultdict(dict)), {}, set()
    with open(DOCS / "runs.csv") as f:
        for row in csv.DictReader(f):
            setting = (int(row["nx"]), int(row["ny"]), float(row["dt"]))
            stats[setting][row["start"]][row["quantity"]] = (
                float(row["value"]),
                float(row["spread"]),
            )
            cpu[setting + (row["start"],)] = float(row["cpu_s"])
            simulated.add(float(row["simulated_s"]))
    assert len(simulated) == 1
    return stats, cpu, simulated.pop()


def one_state(stats, setting):
    """The starts of the example's one state at a setting (every start, as the pages say)."""
    per_start = [dict(stats[setting][s], impact_rate=(0.0, 0.0)) for s in stats[setting]]
    found = states.group(per_start, QUANTITIES, TOLERANCE)
    assert len(found) == 1, setting
    return per_start, found[0].starts


def judge(stats, triple, quantity, taken=0.0):
    values, spreads = zip(*(states.state_value(*one_state(stats, s), quantity) for s in triple))
    ratios = (refinement_ratio(*triple[:2]), refinement_ratio(*triple[1:]))
    # No run of the example warned (report.md's runs table): an observed order is trusted.
    return values, rule.judge(values, spreads, ratios, TOLERANCE, extrapolate=True, taken=taken)


def text(path):
    """A page with its lines joined, so a wrapped sentence reads as one."""
    return re.sub(r"\s*\n\s*", " ", path.read_text())


def test_the_verdict_and_its_bounds_follow_from_the_runs():
    stats, cpu, simulated = example_runs()
    bounds = {}
    for q in QUANTITIES:
        for ladder in (DT1, MESH1):
            assert judge(stats, ladder, q)[1].accepted, (ladder, q)
        mesh1 = judge(stats, MESH1, q)[1].bound
        dt2 = judge(stats, DT2, q)[1]
        mesh2 = judge(stats, MESH2, q, taken=dt2.bound)[1]
        assert dt2.accepted and mesh2.accepted, q
        bounds[q] = dt2.bound + mesh2.bound
        if q == "rms_corner":  # the first Δt triple on 14 × 8 fails on the sum of the bounds
            values, first = judge(stats, DT2_FIRST, q, taken=mesh1)
            assert not first.accepted and first.why == "the error bound exceeds the tolerance"
            own, other = 100 * first.bound / values[-1], 100 * mesh1 / values[-1]
            claim = (
                f"the RMS corner's bounds in Δt ({own:.3f} %) and in the mesh "
                f"({other:.3f} %) summed to {own + other:.3f} %"
            )
            assert claim in text(DOCS / "README.md"), claim
    per_start, members = one_state(stats, RECOMMENDED)
    values = {q: states.state_value(per_start, members, q)[0] for q in QUANTITIES}
    cost = sum(c for run, c in cpu.items() if run[:3] == RECOMMENDED) / len(members) / simulated
    line = (
        "converged: "
        + ", ".join(
            f"{q} = {values[q]:.6g} {unit} ± {100 * bounds[q] / values[q]:.2g} %"
            for q, unit in zip(QUANTITIES, ("J", "m"))
        )
        + f"; one steady state (5 of 5 starts); settings mesh.element=1 mesh.nx=14 mesh.ny=8 "
        f"solver.time_step=1.25e-05; cost {cost:.3g} CPU s per simulated s; the FMU does not "
        "warn at these settings"
    )
    for page in (DOCS / "report.md", DOCS / "README.md", ROOT / "README.md"):
        assert line in text(page), (page, line)
    spent = f"spent {sum(cpu.values()):.1f} CPU s in {len(cpu)} runs"
    assert spent in text(DOCS / "report.md"), spent
    settings = len({run[:3] for run in cpu})
    row = f"| the rule, five starts (default) | {settings} | {len(cpu)} | {sum(cpu.values()):.1f} |"
    assert row in text(DOCS / "README.md"), row
    assert f"55 runs, {sum(cpu.values()):.0f} CPU s" in text(ROOT / "README.md")


def test_the_ladder_table_follows_from_the_runs():
    """The example's table of ladders: each ladder's last three values, mean energy in J and RMS
    corner in mm, to four decimals."""
    stats, _, _ = example_runs()
    page = (DOCS / "README.md").read_text()
    for name, triple in (("dt-1", DT1), ("mesh-1", MESH1), ("dt-2", DT2), ("mesh-2", MESH2)):
        [row] = [r for r in page.splitlines() if r.startswith(f"| {name} |")]
        cells = [c.strip() for c in row.split("|")[1:-1]]
        for cell, q, scale in ((cells[2], "mean_energy", 1.0), (cells[3], "rms_corner", 1e3)):
            values = [scale * states.state_value(*one_state(stats, s), q)[0] for s in triple]
            assert cell == ", ".join(f"{v:.4f}" for v in values), (name, q, cell, values)
        assert cells[4].startswith("accepted"), row


def test_the_resolved_reference_is_that_of_the_damping_study():
    """The page compares the recommended values with the damping study's resolved values for
    the preset (β, Argyris 10 × 7, Δt = 1e-6 s, docs/accuracy/damping.csv): those values and the
    differences as the page prints them."""
    stats, _, _ = example_runs()
    resolved = {}
    with open(ROOT / "docs" / "accuracy" / "damping.csv") as f:
        for row in csv.DictReader(f):
            if (
                row["scene"],
                row["damping"],
                row["element"],
                row["nx"],
                row["ny"],
                row["dt"],
                row["part"],
            ) == ("forced-35hz", "beta", "argyris", "10", "7", "1e-6", "grid"):
                resolved[row["quantity"]] = float(row["value"])
    energy, corner = resolved["mean_energy_J"], 1e3 * resolved["rms_corner_m"]
    per_start, members = one_state(stats, RECOMMENDED)
    ours = {q: states.state_value(per_start, members, q)[0] for q in QUANTITIES}
    off_energy = 100 * abs(ours["mean_energy"] / resolved["mean_energy_J"] - 1)
    off_corner = 100 * abs(ours["rms_corner"] / resolved["rms_corner_m"] - 1)
    claim = (
        f"{energy:.4f} J, {corner:.3f} mm, [../accuracy/damping.md](../accuracy/damping.md)) "
        f"the recommended values are {off_energy:.3f} % and {off_corner:.3f} % off"
    )
    assert claim in text(DOCS / "README.md"), claim
