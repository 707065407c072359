"""The coupling outputs through the FMU (docs/fmu.md, "Outputs for coupling"): the energy balance
between communication points, and contact that happens between communication points counted once
whatever the communication steps."""

import numpy as np
import pytest

from conftest import scene_start_values
from test_steps import adaptive_steps, drive

FLOWS = ["energy.base_work", "energy.load_work", "energy.contact_loss", "energy.damping_loss"]
CONTACT = ["contact.impacts", "contact.impulse", "contact.peak_force"]


def forced_with_load(damped=False):
    start, _ = scene_start_values("forced-35hz")
    start["load.pressure"] = 3000.0
    if damped:
        start["damping.mass_proportional"] = 2 * 0.02 * 2 * np.pi * 53.8
    return start


@pytest.mark.parametrize("steps", ["fixed", "random"])
@pytest.mark.parametrize("damped", [False, True], ids=["undamped", "damped"])
def test_the_energy_balance_holds_between_communication_points(new_plate, steps, damped):
    """E(t) - E(t_1) = base work + load work - contact loss - damping loss between the first
    communication point and every later one, over 0.5 s of the forced 35 Hz scene (impacts on both
    obstacles) with a load of 3 kPa changed to -2 kPa half-way."""
    p = new_plate().initialize(forced_with_load(damped))
    sizes = [1e-3] * 500 if steps == "fixed" else adaptive_steps(5, 0.5)
    names = ["energy.total"] + FLOWS + ["contact.active_nodes"]
    half = len(sizes) // 2
    _, first = drive(p, sizes[:half], names)
    p.set("load.pressure", -2000.0)
    _, second = drive(p, sizes[half:], names)
    rows = np.vstack([first, second])
    energy, base, load, contact, damping = rows[:, :5].T
    change = energy - energy[0]
    flows = (base - base[0]) + (load - load[0]) - (contact - contact[0]) - (damping - damping[0])
    scale = np.max(np.abs(energy))
    residual = np.max(np.abs(change - flows)) / scale
    print(f"{steps} h, {'damped' if damped else 'undamped'}: worst balance residual {residual:.2e} of the "
          f"energy scale {scale:.2f} J; base work {base[-1]:.2f} J, load work {load[-1]:.3f} J, "
          f"contact loss {contact[-1]:.2f} J, damping loss {damping[-1]:.2f} J")
    # The scheme's identity holds per internal step to round-off (~1e-13 of the scale per step over
    # 5000 steps), and the interpolation between grid points is linear, so it carries over.
    assert residual <= 1e-9
    assert np.count_nonzero(rows[:, 5]) > 20, "the plate must hit the obstacles"
    assert contact[-1] > 0.01 * scale and np.all(np.diff(contact) >= -1e-12 * scale)
    assert load[-1] != 0.0, "the pressure change must do work"
    assert (damping[-1] > 0.01 * scale) == damped and np.all(np.diff(damping) >= 0.0)


def contact_totals(new_plate, sizes, name):
    p = new_plate(name).initialize(scene_start_values("forced-35hz")[0])
    _, rows = drive(p, sizes, CONTACT)
    impacts, impulse, peak = rows.T
    return int(impacts.sum()), float(impulse.sum()), float(peak[np.argmax(np.abs(peak))]), rows


def test_no_impact_is_lost_between_communication_points(new_plate):
    """The forced 35 Hz scene over 1 s through 0.1 ms, 10 ms and random (0.2 to 1.5 ms) steps: the
    same total impacts, the same total impulse and the same peak force."""
    fine = contact_totals(new_plate, [1e-4] * 10000, "fine")
    impacts, impulse, peak, rows = fine
    assert impacts > 50 and peak != 0.0
    # With 0.1 ms steps every internal step is a communication step.
    assert np.all(rows[:, 0] <= 1)
    for name, sizes in [("coarse", [1e-2] * 100), ("random", adaptive_steps(6, 1.0))]:
        other = contact_totals(new_plate, sizes, name)
        print(f"{name}: {other[0]} impacts, impulse {other[1]:.6e} N s, peak {other[2]:.1f} N; "
              f"0.1 ms steps: {impacts}, {impulse:.6e} N s, {peak:.1f} N")
        assert other[0] == impacts, name
        # The same terms summed in groups of another size: round-off only.
        assert abs(other[1] - impulse) <= 1e-9 * abs(impulse), name
        assert other[2] == peak, name
        assert np.max(other[3][:, 0]) > 1 or name == "random", "10 ms steps must hold several impacts"
