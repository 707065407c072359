"""The input `base.displacement`: a sine fed by fmpy agrees with the built-in sine.

Tolerances, derived from the interpolation rule (src/simulation/input.rs). Over a communication step h
the applied base extrapolates the last slope and blends out the mismatch, so for a smooth input
whose slope is known it errs by at most 2 max|z''| h^2 = 2 c (2 pi f)^2 h^2: second order. At the
first step no slope is known unless the importer sends one with fmi2SetRealInputDerivatives: a
sine starts with z'(0) = 2 pi f c, the applied base lags by up to z'(0) h during that step, and the
plate's modes near 1/h (here the first two) ring with that amplitude afterwards: first order,
bounded by 3 z'(0) h (the displacement pulse z'(0) h, times at most 2 for a mode's response to a
pulse, times the corner's modal participation, below 1.5). Both are checked: first order without
derivatives, second order with the slope sent.
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


def test_without_derivatives_the_unknown_start_slope_gives_first_order(fmu_path):
    start_slope = 2 * math.pi * F * C
    errors = {h: difference(fmu_path, h) for h in (2e-3, 1e-3)}
    for h, diff in errors.items():
        assert diff < 3 * start_slope * h, f"h = {h}: difference {diff} above 3 z'(0) h"
    ratio = errors[2e-3] / errors[1e-3]
    assert 1.5 < ratio < 2.6, f"ratio {ratio}: expected first order"


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
            p.fmu.setRealInputDerivatives(
                [vr] * len(orders), orders, [derivatives[o] for o in orders]
            )
        p.step(h)
        out.append(p.get("corner1.displacement"))
    return np.array(out)


@pytest.mark.parametrize("orders", [[1], [1, 2]])
def test_with_the_slope_sent_the_agreement_is_second_order(fmu_path, new_plate, orders):
    errors = []
    for h in (2e-3, 1e-3):
        builtin = run(fmu_path, h, False)["corner1.displacement"][1:]
        diff = np.max(np.abs(manual_run(new_plate, h, orders) - builtin))
        bound = 2 * C * (2 * math.pi * F) ** 2 * h**2
        assert diff < 10 * bound, f"h = {h}: difference {diff} above 10 x {bound}"
        errors.append(diff)
    assert errors[0] / errors[1] > 3.0, f"ratio {errors[0] / errors[1]}: not second order"
