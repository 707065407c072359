"""examples/shaker_coupling.py, the plate FMU coupled both ways to a shaker, on a short horizon:
the coupled system's power balance closes up to the coupling residual, which shrinks with h, first
order with the instantaneous base.force, second order with base.mean_force iterated, and smaller
again with the force's first moment."""

import importlib.util

from conftest import ROOT


def load_example():
    spec = importlib.util.spec_from_file_location(
        "shaker_coupling", ROOT / "examples" / "shaker_coupling.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_the_coupling_residual_shrinks_with_the_communication_step(fmu_path):
    example = load_example()
    residuals = []
    for h in (1e-3, 5e-4, 2.5e-4):
        _, balance = example.run(h, 0.3, fmu_path, "instantaneous")
        print(example.balance_line(h, balance))
        assert balance["impacts"] >= 10, "the plate must strike the obstacles"
        # What is left besides the coupling residual is the plate's own balance: round-off
        # (~1e-13 of the energy per internal step over 3000 steps).
        assert abs(balance["closure"]) <= 1e-9 * balance["drive"]
        residuals.append(abs(balance["residual"]))
    # Measured 7.7, 1.8 and 0.80 J of a drive's work of 72 to 75 J: at least a factor 1.5 per halving.
    assert residuals[0] > 1.5 * residuals[1] > 2.25 * residuals[2], residuals
    assert residuals[2] < 0.02 * balance["drive"]


def test_the_iterated_mean_force_coupling_is_second_order(fmu_path):
    """base.mean_force iterated over each step from the saved FMU state: the residual falls by
    about 4 per halving of h, below a quarter of the instantaneous coupling's at h = 0.5 ms, in a
    few plate steps per communication step."""
    example = load_example()
    residuals = []
    for h in (1e-3, 5e-4):
        _, balance = example.run(h, 0.3, fmu_path, "iterated")
        print(example.balance_line(h, balance), balance["iterations"])
        assert balance["impacts"] >= 10, "the plate must strike the obstacles"
        assert abs(balance["closure"]) <= 1e-9 * balance["drive"]
        # Measured 3.0 plate steps per communication step on average, 5 at most.
        assert balance["iterations"][0] <= 4 and balance["iterations"][1] <= 10
        residuals.append(abs(balance["residual"]))
    # Measured 0.50 and 0.10 J (6.7e-3 and 1.4e-3 of a drive's work of 75 J): second order, with room.
    assert residuals[0] > 3 * residuals[1], residuals
    _, instantaneous = example.run(5e-4, 0.3, fmu_path, "instantaneous")
    # Measured 0.80 J.
    assert residuals[1] < 0.25 * abs(instantaneous["residual"]), (
        residuals,
        instantaneous["residual"],
    )


def test_the_first_moment_of_the_force_cuts_the_iterated_residual(fmu_path):
    """The moments coupling (the reaction's first moment over each step, measured by internal-step
    calls, as a line force on the shaker): well below the iterated coupling's residual at h = 1 ms,
    the plate's own balance still closed."""
    example = load_example()
    _, moments = example.run(1e-3, 0.3, fmu_path, "moments")
    _, iterated = example.run(1e-3, 0.3, fmu_path, "iterated")
    print(example.balance_line(1e-3, moments), moments["iterations"], moments["kinks"])
    assert abs(moments["closure"]) <= 1e-9 * moments["drive"]
    # Measured 8.6 fixed-point steps on average, 12 at most.
    assert moments["iterations"][0] <= 15
    # Measured 0.072 J against 0.50 J (0.14 of it).
    assert abs(moments["residual"]) < 0.3 * abs(iterated["residual"]), (
        moments["residual"],
        iterated["residual"],
    )
