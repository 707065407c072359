"""Runs the packaged FMU on the `forced` scene with fmpy and plots the free-edge deflections.

    .venv/bin/pip install matplotlib
    .venv/bin/python examples/plot_fmu.py [scene] [out.png]
"""

import json
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from fmpy import simulate_fmu  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
scene_name = sys.argv[1] if len(sys.argv) > 1 else "forced"
out = sys.argv[2] if len(sys.argv) > 2 else f"out/{scene_name}.png"

scene = json.loads((ROOT / "scenes" / f"{scene_name}.json").read_text())
start = {
    f"{group}.{key}": ({"argyris": 1, "fvs": 2}[value] if key == "element" else value)
    for group, fields in scene.items()
    if isinstance(fields, dict)
    for key, value in fields.items()
    if f"{group}.{key}" not in ("solver.qp", "solver.linear")
}
result = simulate_fmu(
    str(ROOT / "target" / "fmu" / "PlateImpact.fmu"),
    stop_time=scene["stop_time"],
    start_values=start,
    output=["corner1.displacement", "corner2.displacement", "edge_mid.displacement", "energy.total"],
)
fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, figsize=(8, 6))
for name in ["corner1.displacement", "corner2.displacement", "edge_mid.displacement"]:
    ax1.plot(result["time"], result[name], label=name)
ax1.set_ylabel("deflection (m)")
ax1.legend()
ax2.plot(result["time"], result["energy.total"])
ax2.set_ylabel("energy (J)")
ax2.set_xlabel("time (s)")
fig.suptitle(f"PlateImpact FMU, scene {scene_name}")
pathlib.Path(out).parent.mkdir(parents=True, exist_ok=True)
fig.savefig(out, dpi=120)
print(out)
