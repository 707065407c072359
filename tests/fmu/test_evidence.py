"""The rule of evidence of the studies (plateimpact_tools.studies.evidence) on hand-made runs: what
it accepts, what it refuses and the bound it prints. No FMU, no simulation: well under a second.
"""

import math

from plateimpact_tools.studies import evidence
from plateimpact_tools.studies.evidence import Run

MESHES = [(4, 2), (6, 4), (10, 7)]
DTS = [1e-4, 1e-5, 1e-6]


def ladder_runs(value, element="argyris", spread=1e-4, meshes=MESHES, dts=DTS):
    """Runs on `meshes` × `dts` whose value is `value(nx, ny, dt)`."""
    return [Run(element, nx, ny, dt, value(nx, ny, dt), spread) for nx, ny in meshes for dt in dts]


def power_law(nx, ny, dt):
    """1 + a small error in the cell size (order 2) and in Δt (order 1): converged to 1 %."""
    h = 1.0 / math.sqrt(nx * ny)
    return 1.0 + 0.002 * h**2 + 0.5 * dt


def test_a_converging_study_is_accepted_with_the_sum_of_both_bounds():
    runs = ladder_runs(power_law) + ladder_runs(power_law, element="fvs")
    verdicts = evidence.judge(runs)
    both = verdicts["both"]
    assert both.accepted
    s = both.setting
    assert (s.run.nx, s.run.dt) == (10, 1e-6)
    assert s.bound == s.dt_ladder.judgement.bound + s.mesh_ladder.judgement.bound
    # The bound holds the distance to the limit, 1.
    assert abs(s.run.value - 1.0) <= s.bound


def test_meshes_are_compared_at_one_dt_only():
    """Each mesh ran its own Δt: no three meshes share one, so no mesh ladder and no verdict,
    however close the values."""
    runs = [
        Run("argyris", nx, ny, dt, 1.0, 1e-4)
        for (nx, ny), dts in zip(
            MESHES, [[1e-3, 1e-4, 1e-5], [1e-4, 1e-5, 1e-6], [1e-5, 1e-6, 1e-7]]
        )
        for dt in dts
    ]
    verdict = evidence.judge_element(runs, "argyris")
    assert not verdict.accepted
    assert "fewer than three meshes" in verdict.why


def test_a_first_pair_that_disagrees_refuses_the_ladder():
    """The periodic response at the largest Δt, 5 % off, then two agreeing runs: one agreeing
    pair is no evidence, and the studies never let an observed order stand in for the first."""

    def value(nx, ny, dt):
        return 1.05 if dt == 1e-4 else 1.0 + 1e-4 * dt / 1e-6

    verdict = evidence.judge_element(ladder_runs(value), "argyris")
    assert not verdict.accepted
    assert "Δt" in verdict.why and "a pair disagrees" in verdict.why


def test_an_unsettled_run_never_serves_as_the_value():
    """Argyris 10 × 7 moves 3 % per decade of Δt, the other meshes not at all. Its runs are
    refused as settings, and the element's value is that of an accepted setting."""

    def value(nx, ny, dt):
        return 1.0 + (0.03 * dt / 1e-4 if nx == 10 else 0.0)

    runs = ladder_runs(value, meshes=MESHES + [(14, 10)])
    unsettled = [r for r in runs if r.nx == 10]
    assert not any(evidence.judge_setting(runs, r).accepted for r in unsettled)
    verdict = evidence.judge_element(runs, "argyris")
    assert verdict.accepted and verdict.setting.run.nx != 10
    assert verdict.setting.dt_ladder.judgement.accepted
    assert verdict.setting.mesh_ladder.judgement.accepted


def test_elements_that_disagree_beyond_their_bounds_refuse_the_quantity():
    runs = ladder_runs(power_law) + ladder_runs(
        lambda nx, ny, dt: 1.05 * power_law(nx, ny, dt), element="fvs"
    )
    verdicts = evidence.judge(runs)
    assert verdicts["argyris"].accepted and verdicts["fvs"].accepted
    assert not verdicts["both"].accepted and "disagree" in verdicts["both"].why


def test_the_sum_of_the_bounds_is_held_to_the_tolerance():
    """Spreads of 0.12 %: every pair agrees within 1 % with its 2σ, and each ladder's bound alone
    (about 0.3 % in Δt, 0.85 % in the mesh, whose ratio is near 1.7) passes, but their sum
    exceeds 1 %."""
    runs = ladder_runs(power_law, spread=0.0012)
    setting = evidence.judge_setting(runs, runs[-1])
    assert setting.dt_ladder.judgement.accepted and setting.mesh_ladder.judgement.accepted
    assert not setting.accepted
    assert setting.why == "the Δt and mesh bounds together exceed the tolerance"
