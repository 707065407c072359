"""The packaged FMU against its golden results (tests/fmu/reference/<scene>.csv, written by
tests/fmu/reference/regenerate.py, regenerated only on purpose): every shipped scene over its
1 s horizon at 1 ms communication points.

How sensitive the scenes are, measured before choosing the tolerances (1 s, every 1 ms point):
* shifting the base by 1e-15 m (`regenerate.py --sensitivity`) moves corner1 by at most 3e-11 m
  (forced-35hz; 8e-13 to 3e-12 m in the others) and energy.total by at most 1.2e-8 of its scale;
* solving every contact step with clarabel instead of the exact active-set method (a different
  solver with its own round-off and a 1e-12 tolerance; `examples/scene.rs ... solver.qp=clarabel`)
  moves the displacements by at most 8.8e-10 m, energy.total by 2.2e-7 of its scale, the total
  contact force by 4.2e-7 of its largest value, and not one row's count of vertices in contact.
* the same shift moves the coupling outputs by at most 4e-8 of their scales (base.force 2.6e-8,
  contact.peak_force 3.8e-8, contact.impulse 9.3e-9, base.mean_force 9.3e-9, the works and losses
  2.8e-10; forced-35hz) and not one row's impact count.
So within 1 s no scene diverges chaotically: every row is compared, with tolerances about 100
times the solver-to-solver differences (what a legitimate change of the contact solver's round-off
can do) and far below what a real regression does (a wrong scheme, element, load or input rule
moves the corners by millimetres and the energy by percents).
"""

import numpy as np
import pytest
from fmpy import simulate_fmu

import reference.regenerate as regenerate
from conftest import SCENES, scene_start_values

# 1e-7 m, 1e-5 of the 0.01 m gap: 100 x the largest solver-to-solver difference (8.8e-10 m).
DISPLACEMENT_ATOL = 1e-7
# Of the scene's largest |energy.total| (or of the largest work or loss, if larger): 45 x the
# solver-to-solver difference (2.2e-7), 250 x the round-off sensitivity of the works and losses.
ENERGY_RTOL = 1e-5
# Of each force's largest value (contact.force, base.force, contact.peak_force, base.mean_force;
# contact.impulse likewise): 24 x the solver-to-solver difference of contact.force (4.2e-7), 250 x the round-off
# sensitivity of the others.
FORCE_RTOL = 1e-5
# Rows whose count of vertices in contact (or of impacts) may differ by one: a vertex grazing an
# obstacle may flip with round-off (none did between the two solvers); a regression changes many
# rows.
ACTIVE_FLIPS = 3

SCENE_NAMES = sorted(p.stem for p in SCENES.glob("*.json"))


@pytest.mark.parametrize("scene", SCENE_NAMES)
def test_fmu_matches_its_golden_result(fmu_path, scene):
    reference = regenerate.read(regenerate.HERE / f"{scene}.csv")
    start, stop = scene_start_values(scene)
    result = simulate_fmu(
        fmu_path,
        start_time=0.0,
        stop_time=stop,
        output_interval=regenerate.STEP,
        start_values=start,
        output=regenerate.OUTPUTS,
    )
    assert_matches(result, reference, scene)


def assert_matches(result, reference, scene):
    """Every row of `result` within the tolerances above of `reference` (both structured arrays
    with time and every output): the rule the FMU's packaged reference results state too."""
    assert len(result) == len(reference)
    np.testing.assert_allclose(result["time"], reference["time"], rtol=0, atol=1e-12)
    for name in regenerate.DISPLACEMENTS:
        np.testing.assert_allclose(
            result[name],
            reference[name],
            rtol=0,
            atol=DISPLACEMENT_ATOL,
            err_msg=f"{scene}: {name}",
        )
    for name in regenerate.VELOCITIES:
        # A velocity is a displacement's slope over one internal step: held, as the forces, to
        # 1e-5 of its largest value (at least 1e-6 m/s).
        scale = max(np.max(np.abs(reference[name])), 1e-6)
        np.testing.assert_allclose(
            result[name],
            reference[name],
            rtol=0,
            atol=FORCE_RTOL * scale,
            err_msg=f"{scene}: {name}",
        )
    energy_scale = np.max(np.abs(reference["energy.total"]))
    for name in regenerate.ENERGIES:
        # The works and losses summed since the start may exceed the energy itself (forced scenes).
        scale = max(energy_scale, np.max(np.abs(reference[name])))
        np.testing.assert_allclose(
            result[name],
            reference[name],
            rtol=0,
            atol=ENERGY_RTOL * scale,
            err_msg=f"{scene}: {name}",
        )
    for name in regenerate.FORCES:
        scale = max(np.max(np.abs(reference[name])), 1.0)
        np.testing.assert_allclose(
            result[name],
            reference[name],
            rtol=0,
            atol=FORCE_RTOL * scale,
            err_msg=f"{scene}: {name}",
        )
    for name in regenerate.INTEGERS:
        flips = np.abs(result[name].astype(int) - reference[name].astype(int))
        assert flips.max() <= 1 and np.count_nonzero(flips) <= ACTIVE_FLIPS, (
            f"{scene}: {name} differ"
        )


def test_the_golden_results_are_not_trivial():
    """Each scene moves and hits (the stop scenes their stop): a reference of zeros would test
    nothing. The smallest scene is the 2 mm panel, shaken by 0.1 mm and held 0.2 mm above its
    stud: a deflection of a tenth of a millimetre and a base force of a hundred newtons."""
    for scene in SCENE_NAMES:
        reference = regenerate.read(regenerate.HERE / f"{scene}.csv")
        moved = max(np.max(np.abs(reference[name])) for name in regenerate.DISPLACEMENTS)
        assert moved > 1e-4, scene
        assert np.count_nonzero(reference["contact.active_nodes"]) >= 10, scene
        assert np.sum(reference["contact.impacts"]) >= 5, scene
        assert np.max(np.abs(reference["base.force"])) > 100, scene
        if start_values_have_stops(scene):
            assert np.sum(reference["stop1.impacts"]) >= 5, scene


def start_values_have_stops(scene):
    """Whether the scene's lower obstacle is made of local stops."""
    start, _ = scene_start_values(scene)
    profile = start.get("obstacle.lower_profile", "flat")
    return any(kind in profile for kind in ("point(", "disc(", "rectangle("))
