"""Golden results of the packaged FMU, one CSV per shipped scene (scenes/*.json), at every 1 ms
communication point over the scene's horizon. Regenerate them only on purpose, when a change of the
results is understood and wanted:

    cargo run --release --bin package-fmu
    .venv/bin/python tests/fmu/reference/regenerate.py            # rewrites tests/fmu/reference/*.csv
    .venv/bin/python tests/fmu/reference/regenerate.py --sensitivity

`--sensitivity` writes nothing; it measures how far each scene's outputs move under a round-off
perturbation (the base shifted by 1e-15 m), which is what sets the tolerances of
tests/fmu/test_reference.py.
"""

import argparse
import pathlib

import numpy as np
from fmpy import simulate_fmu

from plateimpact_tools import ROOT, SCENES
from plateimpact_tools.scene_values import scene as scene_start_values

HERE = pathlib.Path(__file__).resolve().parent

STEP = 1e-3
OUTPUTS = [
    "corner1.displacement",
    "corner2.displacement",
    "edge_mid.displacement",
    "energy.kinetic",
    "energy.elastic",
    "energy.total",
    "contact.active_nodes",
    "contact.force",
    "base.force",
    "energy.base_work",
    "energy.load_work",
    "energy.contact_loss",
    "energy.damping_loss",
    "contact.impacts",
    "contact.impulse",
    "contact.peak_force",
    "base.mean_force",
    "probe1.displacement",
    "probe2.displacement",
    "probe1.velocity",
    "probe2.velocity",
    "stop1.force",
    "stop1.impulse",
    "stop1.impacts",
]
INTEGERS = ("contact.active_nodes", "contact.impacts", "stop1.impacts")
# Outputs compared as energies (against the scene's largest |energy.total| or flow) and as forces
# (against the scene's largest force of the same kind): see tests/fmu/test_reference.py.
ENERGIES = [
    "energy.kinetic",
    "energy.elastic",
    "energy.total",
    "energy.base_work",
    "energy.load_work",
    "energy.contact_loss",
    "energy.damping_loss",
]
FORCES = [
    "contact.force",
    "base.force",
    "contact.peak_force",
    "contact.impulse",
    "base.mean_force",
    "stop1.force",
    "stop1.impulse",
]
# Displacements compared in metres, and velocities against each one's largest value.
DISPLACEMENTS = [
    "corner1.displacement",
    "corner2.displacement",
    "edge_mid.displacement",
    "probe1.displacement",
    "probe2.displacement",
]
VELOCITIES = ["probe1.velocity", "probe2.velocity"]


def scenes():
    return sorted(p.stem for p in SCENES.glob("*.json"))


def run(fmu, scene, base_shift=0.0):
    """The scene through the FMU: a structured array with time and every output."""
    start, stop = scene_start_values(scene)
    if base_shift:
        start["base.displacement"] = base_shift
    return simulate_fmu(
        fmu,
        start_time=0.0,
        stop_time=stop,
        output_interval=STEP,
        start_values=start,
        output=OUTPUTS,
    )


def write(path, result):
    with open(path, "w") as f:
        f.write(",".join(["time"] + OUTPUTS) + "\n")
        for row in result:
            f.write(
                ",".join(
                    str(int(row[name])) if name in INTEGERS else repr(float(row[name]))
                    for name in ["time"] + OUTPUTS
                )
                + "\n"
            )


def read(path):
    return np.genfromtxt(path, delimiter=",", names=True, deletechars="")


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "PlateImpact.fmu"))
    parser.add_argument("--sensitivity", action="store_true")
    args = parser.parse_args()
    for scene in scenes():
        base = run(args.fmu, scene)
        if not args.sensitivity:
            write(HERE / f"{scene}.csv", base)
            print(f"{scene}: {len(base)} rows written")
            continue
        shifted = run(args.fmu, scene, base_shift=1e-15)
        for name in ENERGIES + FORCES:
            scale = max(np.max(np.abs(base[name])), 1e-300)
            print(
                f"  {name}: moves by {np.max(np.abs(base[name] - shifted[name])) / scale:.1e} of its scale {scale:.4g}"
            )
        for name in INTEGERS:
            print(f"  {name}: {np.count_nonzero(base[name] != shifted[name])} rows differ")
        t = base["time"]
        corner = np.abs(base["corner1.displacement"] - shifted["corner1.displacement"])
        energy = np.abs(base["energy.total"] - shifted["energy.total"]) / max(
            np.max(np.abs(base["energy.total"])), 1e-300
        )
        first = {
            tol: (t[np.argmax(corner > tol)] if np.any(corner > tol) else None)
            for tol in (1e-12, 1e-9, 1e-6)
        }
        print(
            f"{scene}: corner1 moves by at most {corner.max():.2e} m (first beyond 1e-12/1e-9/1e-6 m at "
            f"{first[1e-12]}/{first[1e-9]}/{first[1e-6]} s); energy.total by {energy.max():.2e} of its scale; "
            f"contact steps {int(np.sum(base['contact.active_nodes'] > 0))}"
        )


if __name__ == "__main__":
    main()
