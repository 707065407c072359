"""One rule of evidence for the studies: every "converged" a study page prints comes from
`plateimpact_tools.rule`, the rule scripts/converge judges a user's scene by, applied to the
study's runs (docs/studies.md, "One rule of evidence").

A study has, for one (scene, damping, quantity), runs on meshes of two elements at several Δt,
each a value with its spread σ (1σ). A *setting* is (mesh, Δt). The rule judges a setting S when
S closes two ladders of three settings each:

- the **Δt ladder**: S's mesh at S's Δt and the next two larger Δt it ran (refinement ratios
  the ratios of the Δt);
- the **mesh ladder**: S's Δt on S's mesh and the next two coarser meshes of its element that ran
  that same Δt (ratios the ratios of the cell sizes, √ of the cell counts), so meshes are only
  ever compared at one Δt.

S is *converged* when the rule accepts both ladders and the sum of their error bounds (each the
grid convergence index of its three settings plus 2σ of S, `rule.judge`) is within the
tolerance; that sum is the ± the pages print. The studies never let an observed order stand in
for the first pair's agreement (`rule.judge(extrapolate=False)`, which scripts/converge allows
where the FMU does not warn): their Δt ladders step by 10, so a triple spans two decades, across
which the project's runs change regime (the periodic response at 1e-4 s that turns chaotic at
1e-5 s), and two agreeing pairs are the least evidence.

An element is converged when one of its settings is; its value is that of the accepted setting
with the smallest relative bound. A quantity is converged when an element is and, where both are,
their values lie within the sum of their bounds (the second element is an independent check; a
disagreement refuses both). A setting that is not converged never serves as a reference: the
value printed is always that of an accepted setting. One tolerance, TOLERANCE, for every verdict
and mark.
"""

import csv
import dataclasses
import math
from collections.abc import Callable
from pathlib import Path

from plateimpact_tools import rule

# The one tolerance of every study verdict (relative).
TOLERANCE = 0.01
ELEMENTS = ("argyris", "fvs")


@dataclasses.dataclass(frozen=True)
class Run:
    """One run's statistic: the mesh (element, nx, ny), Δt (s), value and spread (1σ)."""

    element: str
    nx: int
    ny: int
    dt: float
    value: float
    spread: float

    @property
    def mesh(self) -> tuple[str, int, int]:
        return (self.element, self.nx, self.ny)

    @property
    def cells(self) -> int:
        return self.nx * self.ny


@dataclasses.dataclass(frozen=True)
class Ladder:
    """Three settings the rule judged (coarse to fine) and what it said."""

    runs: tuple[Run, ...]
    judgement: rule.Judgement


@dataclasses.dataclass(frozen=True)
class Setting:
    """The rule at one setting: its run, its Δt and mesh ladders (None where the study did not
    run three), whether it is converged, the summed bound (absolute) and why not."""

    run: Run
    dt_ladder: Ladder | None
    mesh_ladder: Ladder | None
    accepted: bool
    bound: float
    why: str

    def evidence(self) -> tuple[int, int, float]:
        """How much the setting rests on: its ladders, its cells, its Δt (smaller is more)."""
        ladders = (self.dt_ladder is not None) + (self.mesh_ladder is not None)
        return (ladders, self.run.cells, -self.run.dt)


@dataclasses.dataclass(frozen=True)
class Verdict:
    """The verdict on one element ("argyris", "fvs") or on the quantity ("both"): `setting` is
    the accepted setting when `accepted`, else the one with the most evidence, whose `why` says
    what failed; `why` adds what failed between the elements."""

    element: str
    accepted: bool
    setting: Setting | None
    why: str

    @property
    def value(self) -> float:
        return self.setting.run.value if self.setting else math.nan

    @property
    def bound(self) -> float:
        return self.setting.bound if self.setting else math.inf


def cell_ratio(coarse: Run, fine: Run) -> float:
    """The refinement ratio of two meshes of one element: the ratio of their cell sizes."""
    return math.sqrt(fine.cells / coarse.cells)


def judge_ladder(ladder: list[Run], ratio: Callable[[Run, Run], float], tolerance: float) -> Ladder:
    """The rule on three settings (coarse to fine), `ratio` the refinement ratio of a pair."""
    values = [r.value for r in ladder]
    spreads = [r.spread for r in ladder]
    ratios = (ratio(ladder[0], ladder[1]), ratio(ladder[1], ladder[2]))
    return Ladder(tuple(ladder), rule.judge(values, spreads, ratios, tolerance, extrapolate=False))


def judge_setting(runs: list[Run], run: Run, tolerance: float = TOLERANCE) -> Setting:
    """The rule at the setting of `run` (module docs), from the element's `runs`."""
    same_mesh = sorted(
        (r for r in runs if r.mesh == run.mesh and r.dt >= run.dt), key=lambda r: -r.dt
    )
    same_dt = sorted(
        (r for r in runs if r.dt == run.dt and r.cells <= run.cells), key=lambda r: r.cells
    )
    dt_ladder = (
        judge_ladder(same_mesh[-3:], lambda a, b: a.dt / b.dt, tolerance)
        if len(same_mesh) >= 3
        else None
    )
    mesh_ladder = judge_ladder(same_dt[-3:], cell_ratio, tolerance) if len(same_dt) >= 3 else None
    scale = tolerance * abs(run.value)
    whys = []
    if dt_ladder is None:
        whys.append(f"fewer than three Δt on {mesh_name(run.mesh)}")
    elif not dt_ladder.judgement.accepted:
        whys.append(f"Δt {ladder_text(dt_ladder, 'dt')}: {dt_ladder.judgement.why}")
    if mesh_ladder is None:
        whys.append(f"fewer than three meshes at {run.dt:g} s")
    elif not mesh_ladder.judgement.accepted:
        whys.append(f"mesh {ladder_text(mesh_ladder, 'mesh')}: {mesh_ladder.judgement.why}")
    bound = (
        dt_ladder.judgement.bound + mesh_ladder.judgement.bound
        if dt_ladder and mesh_ladder
        else math.inf
    )
    if not whys and bound > scale:
        whys.append("the Δt and mesh bounds together exceed the tolerance")
    return Setting(run, dt_ladder, mesh_ladder, not whys, bound, "; ".join(whys))


def judge_settings(runs: list[Run], element: str, tolerance: float = TOLERANCE) -> list[Setting]:
    """The rule at every setting of the element."""
    own = [r for r in runs if r.element == element]
    return [judge_setting(own, r, tolerance) for r in own]


def judge_element(runs: list[Run], element: str, tolerance: float = TOLERANCE) -> Verdict:
    """The element's verdict: converged at its accepted setting of smallest relative bound, or
    not, with the reason at its setting of most evidence."""
    settings = judge_settings(runs, element, tolerance)
    if not settings:
        return Verdict(element, False, None, f"no runs on {element}")
    accepted = [s for s in settings if s.accepted]
    if accepted:
        best = min(accepted, key=lambda s: (s.bound / abs(s.run.value), -s.run.cells, s.run.dt))
        return Verdict(element, True, best, "")
    best = max(settings, key=Setting.evidence)
    return Verdict(element, False, best, best.why)


def judge(runs: list[Run], tolerance: float = TOLERANCE) -> dict[str, Verdict]:
    """The verdict on each element and on the quantity ("both"; module docs)."""
    verdicts = {e: judge_element(runs, e, tolerance) for e in ELEMENTS}
    converged = [verdicts[e] for e in ELEMENTS if verdicts[e].accepted]
    if len(converged) == 2:
        a, f = converged
        if abs(a.value - f.value) > a.bound + f.bound:
            why = (
                f"the elements disagree: {a.value:.6g} ± {a.bound:.2g} against "
                f"{f.value:.6g} ± {f.bound:.2g}"
            )
            verdicts["both"] = Verdict("both", False, None, why)
            return verdicts
    if converged:
        best = min(converged, key=lambda v: v.bound / abs(v.value))
        verdicts["both"] = Verdict("both", True, best.setting, "")
    else:
        verdicts["both"] = Verdict("both", False, None, "neither element converges")
    return verdicts


def mesh_name(mesh: tuple[str, int, int]) -> str:
    element, nx, ny = mesh
    return f"{'Argyris' if element == 'argyris' else 'FVS'} {nx}×{ny}"


def ladder_text(ladder: Ladder, kind: str) -> str:
    if kind == "dt":
        return (
            f"{mesh_name(ladder.runs[0].mesh)} "
            + ", ".join(f"{r.dt:g}" for r in ladder.runs)
            + " s"
        )
    return ", ".join(f"{r.nx}×{r.ny}" for r in ladder.runs) + f" at {ladder.runs[0].dt:g} s"


HEADER = [
    "scene",
    "damping",
    "quantity",
    "element",
    "verdict",
    "value",
    "bound",
    "bound_pct",
    "mesh",
    "dt",
    "dt_ladder",
    "dt_bound",
    "mesh_ladder",
    "mesh_bound",
    "why",
]


def rows(key: tuple[str, str, str], verdicts: dict[str, Verdict]) -> list[list[str]]:
    """The verdicts of one (scene, damping, quantity) as rows of HEADER."""
    out = []
    for element in (*ELEMENTS, "both"):
        v = verdicts[element]
        s = v.setting
        why = v.why
        cells = [*key, element, "converged" if v.accepted else "not converged"]
        if s is None:
            cells += ["", "", "", "", "", "", "", "", ""]
        else:
            value = s.run.value
            pct = 100 * s.bound / abs(value) if math.isfinite(s.bound) and value else math.inf
            cells += [
                f"{value:.10g}",
                f"{s.bound:.4g}",
                f"{pct:.4g}",
                f"{s.run.element}:{s.run.nx}x{s.run.ny}",
                f"{s.run.dt:g}",
                " ".join(f"{r.dt:g}" for r in s.dt_ladder.runs) if s.dt_ladder else "",
                f"{s.dt_ladder.judgement.bound:.4g}" if s.dt_ladder else "",
                " ".join(f"{r.nx}x{r.ny}" for r in s.mesh_ladder.runs) if s.mesh_ladder else "",
                f"{s.mesh_ladder.judgement.bound:.4g}" if s.mesh_ladder else "",
            ]
        out.append(cells + [why])
    return out


def write(path: str | Path, judged: dict[tuple[str, str, str], dict[str, Verdict]]) -> None:
    """Writes every verdict of a study to the CSV `path` (HEADER), in the order of `judged`."""
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(HEADER)
        for key, verdicts in judged.items():
            writer.writerows(rows(key, verdicts))


LADDER_HEADER = [
    "scene",
    "damping",
    "quantity",
    "mesh",
    "dt",
    "verdict",
    "bound",
    "dt_ladder",
    "dt_verdict",
    "dt_bound",
    "dt_order",
    "dt_why",
    "mesh_ladder",
    "mesh_verdict",
    "mesh_bound",
    "mesh_order",
    "mesh_why",
]


def ladder_cells(ladder: Ladder | None, kind: str) -> list[str]:
    if ladder is None:
        return ["", "none", "", "", "fewer than three"]
    j = ladder.judgement
    settings = (
        " ".join(f"{r.dt:g}" for r in ladder.runs)
        if kind == "dt"
        else " ".join(f"{r.nx}x{r.ny}" for r in ladder.runs)
    )
    return [
        settings,
        "accepted" if j.accepted else "refused",
        f"{j.bound:.4g}",
        f"{j.order:.3g}" if j.order is not None else "",
        j.why,
    ]


def write_ladders(path: str | Path, study: dict[tuple[str, str, str], list[Run]]) -> None:
    """Writes the rule at every setting of a study (LADDER_HEADER): both ladders, their
    judgements, bounds, observed orders and reasons; `study` maps (scene, damping, quantity) to
    its runs."""
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(LADDER_HEADER)
        for key, runs in study.items():
            for element in ELEMENTS:
                for s in sorted(
                    judge_settings(runs, element), key=lambda s: (s.run.cells, -s.run.dt)
                ):
                    writer.writerow(
                        [
                            *key,
                            f"{s.run.element}:{s.run.nx}x{s.run.ny}",
                            f"{s.run.dt:g}",
                            "converged" if s.accepted else "not converged",
                            f"{s.bound:.4g}",
                            *ladder_cells(s.dt_ladder, "dt"),
                            *ladder_cells(s.mesh_ladder, "mesh"),
                        ]
                    )
