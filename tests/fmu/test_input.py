"""The input `base.displacement`: a sine fed by fmpy agrees with the built-in sine.

Tolerance, derived from the interpolation rule (src/fmi/input.rs): for a sampled input z with
communication step h the applied base errs by at most 2 max|z''| h^2 = 2 c (2 pi f)^2 h^2 after the
first two steps. The absolute deflection of the plate follows the base quasi-statically at these
frequencies (the first mode is far above f), so the outputs differ by a small multiple of that
bound, plus the free vibration started by the first step (which has no slope yet), of order
omega_1 |z'(0)| h^2, also second order. We allow 10 times the bound (the stand-in simulation
measures about 3.2 times it at h = 2e-3, 1e-3 and 5e-4). Halving h must divide the difference
by about 4 (second order).
"""

import math

import numpy as np
import pytest
from fmpy import simulate_fmu

C = 0.002  # m, small enough to stay clear of the obstacles: the response is smooth
F = 10.0  # Hz
STOP = 0.2
NO_OBSTACLES = {"obstacle.lower_enabled": False, "obstacle.upper_enabled": False}


def run(fmu_path, h, through_input, derivatives=False):
    if through_input:
        t = np.arange(0.0, STOP + h / 2, h)
        signal = np.array(
            list(zip(t, C * np.sin(2 * math.pi * F * t))),
            dtype=[("time", np.float64), ("base.displacement", np.float64)],
        )
        start = dict(NO_OBSTACLES)
    else:
        signal = None
        start = dict(NO_OBSTACLES, **{"base.amplitude": C, "base.frequency": F})
    return simulate_fmu(
        fmu_path,
        stop_time=STOP,
        output_interval=h,
        start_values=start,
        input=signal,
        set_input_derivatives=derivatives,
        output=["corner1.displacement", "edge_mid.displacement"],
    )


def difference(fmu_path, h, derivatives=False):
    builtin = run(fmu_path, h, False)
    sampled = run(fmu_path, h, True, derivatives)
    assert len(builtin) == len(sampled)
    return float(np.max(np.abs(builtin["corner1.displacement"] - sampled["corner1.displacement"])))


@pytest.mark.parametrize("h", [1e-3, 5e-4])
def test_input_sine_agrees_with_builtin_sine(fmu_path, h):
    bound = 2 * C * (2 * math.pi * F) ** 2 * h**2
    diff = difference(fmu_path, h)
    assert diff < 10 * bound, f"h = {h}: difference {diff} above 10 x {bound}"


def test_agreement_is_second_order_in_the_communication_step(fmu_path):
    coarse = difference(fmu_path, 2e-3)
    fine = difference(fmu_path, 1e-3)
    assert coarse / fine > 3.0, f"ratio {coarse / fine}: not second order"


def manual_run(new_plate, h, orders):
    """Drives the FMU step by step, sending the exact derivatives of the given orders."""
    w = 2 * math.pi * F
    p = new_plate().initialize(NO_OBSTACLES)
    vr = p.vr("base.displacement")
    out = []
    for k in range(round(STOP / h)):
        t = k * h
        p.set("base.displacement", C * math.sin(w * t))
        derivatives = {1: C * w * math.cos(w * t), 2: -C * w * w * math.sin(w * t)}
        if orders:
            p.fmu.setRealInputDerivatives([vr] * len(orders), orders, [derivatives[o] for o in orders])
        p.step(h)
        out.append(p.get("corner1.displacement"))
    return np.array(out)


@pytest.mark.parametrize("orders", [[], [1], [1, 2]])
def test_input_derivatives_are_used(fmu_path, new_plate, orders):
    h = 1e-3
    builtin = run(fmu_path, h, False)["corner1.displacement"][1:]
    diff = np.max(np.abs(manual_run(new_plate, h, orders) - builtin))
    bound = 2 * C * (2 * math.pi * F) ** 2 * h**2
    assert diff < 10 * bound
    if orders == [1, 2]:
        # Exact first and second derivatives: the applied base errs by O(h^3) only.
        without = np.max(np.abs(manual_run(new_plate, h, []) - builtin))
        assert diff < without / 5, (diff, without)
