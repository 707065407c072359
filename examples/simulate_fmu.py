"""Main job: simulate the packaged FMU with fmpy and plot the results.

Runs the default scene (the FMU's start values) and the paper's scenes (`forced` at 10 and
35 Hz, `energy`) by setting the FMU parameters from the scene files in `scenes/`, then writes
`out/<scene>.csv` and `out/<scene>.png` (free-corner and edge-midpoint displacements, energy).

    python examples/simulate_fmu.py [--fmu target/fmu/PlateImpact.fmu] [--out out]
"""

import argparse
import json
import pathlib
import time

import fmpy
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
OUTPUTS = ["corner1.displacement", "corner2.displacement", "edge_mid.displacement",
           "energy.kinetic", "energy.elastic", "energy.total", "contact.active_nodes", "contact.force"]
# Scene fields that are settings of the Rust examples, not FMU variables.
NOT_FMU = {"stop_time", "solver.qp", "solver.linear"}
ELEMENT = {"argyris": 1, "fvs": 2}


def flatten(tree, prefix=""):
    for key, value in tree.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            yield from flatten(value, name + ".")
        else:
            yield name, value


def start_values(scene_name):
    """FMU start values of a scene file (all of its FMU parameters), and its stop time."""
    scene = json.loads((ROOT / "scenes" / f"{scene_name}.json").read_text())
    values = {k: v for k, v in flatten(scene) if k not in NOT_FMU}
    values["mesh.element"] = ELEMENT[values["mesh.element"]]
    return values, scene["stop_time"]


def simulate(fmu, scene_name, out_dir):
    if scene_name == "default":
        values, stop = {}, 1.0
    else:
        values, stop = start_values(scene_name)
    t0 = time.perf_counter()
    result = fmpy.simulate_fmu(fmu, start_values=values, stop_time=stop, output_interval=1e-3,
                               output=OUTPUTS)
    wall = time.perf_counter() - t0
    names = result.dtype.names
    np.savetxt(out_dir / f"{scene_name}.csv", np.column_stack([result[n] for n in names]),
               delimiter=",", header=",".join(names), comments="")
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    for name, label in [("corner1.displacement", "corner (Lx, 0)"),
                        ("corner2.displacement", "corner (Lx, Ly)"),
                        ("edge_mid.displacement", "edge midpoint (Lx, Ly/2)")]:
        ax1.plot(result["time"], 1e3 * result[name], label=label, lw=0.8)
    ax1.set_ylabel("displacement (mm)")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title(f"PlateImpact FMU, scene '{scene_name}' ({wall:.1f} s wall time)")
    for name in ["energy.kinetic", "energy.elastic", "energy.total"]:
        ax2.plot(result["time"], result[name], label=name, lw=0.8)
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("energy (J)")
    ax2.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(out_dir / f"{scene_name}.png", dpi=110)
    plt.close(fig)
    print(f"{scene_name}: {len(result)} output points, {wall:.2f} s, "
          f"max |corner1| = {1e3 * np.abs(result['corner1.displacement']).max():.3f} mm, "
          f"final energy {result['energy.total'][-1]:.3f} J -> {out_dir / (scene_name + '.png')}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", default=str(ROOT / "target" / "fmu" / "PlateImpact.fmu"))
    parser.add_argument("--out", default=str(ROOT / "out"))
    parser.add_argument("scenes", nargs="*", default=["default", "forced", "forced-35hz", "energy"])
    args = parser.parse_args()
    out_dir = pathlib.Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    for scene_name in args.scenes:
        simulate(args.fmu, scene_name, out_dir)


if __name__ == "__main__":
    main()
