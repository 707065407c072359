"""Main job: the shipped scenes through the packaged FMU, animations of the plate, its modes.

* Through the FMU (fmpy): the paper's scenes `forced` (10 Hz), `forced-35hz`,
  `forced-35hz-damped` (the same with stiffness-proportional damping, ζ₁ = 1 %: the setting whose
  impact statistics converge, docs/accuracy/damping.md) and `energy`, and the scenes of the
  paper's whole model `stud-corner` (a stud under a free corner), `clamped-panel` (a panel clamped
  all round on a central stud) and `inclined-support`, with the FMU parameters set from the scene
  files in `scenes/`: `out/<scene>.csv` (every output, every 1 ms) and `out/<scene>.png`
  (displacements of the corners off the clamp and of the probes placed, the stop's force where
  there is one, energy).
* Through the library (`examples/scene.rs --field`): the displacement at every mesh vertex of
  `forced-35hz` over three forcing periods from 0.4 s, `out/plate-field.json`, rendered as
  `out/plate.gif` (`examples/plate_animation.py`), and of `stud-corner` over two periods,
  `out/stud-corner.gif`. Their corner values and energy are checked against the FMU's outputs at
  the same instants.
* The lowest six mode shapes of the paper's plate (`examples/modes.rs --shapes`):
  `out/modes.json`, plotted as `out/modes.png` (`examples/mode_shapes.py`).

Prints one line per file written.

    python examples/simulate_fmu.py [--fmu target/fmu/PlateImpact.fmu] [--out out] [scene ...]
"""

import argparse
import json
import pathlib
import subprocess
import sys
import time

import fmpy
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mode_shapes  # noqa: E402
import plate_animation  # noqa: E402
from plateimpact_tools import DEFAULT_FMU, ROOT  # noqa: E402
from plateimpact_tools.scene_values import scene as start_values  # noqa: E402

OUTPUTS = [
    "corner1.displacement",
    "corner2.displacement",
    "edge_mid.displacement",
    "probe1.displacement",
    "probe2.displacement",
    "energy.kinetic",
    "energy.elastic",
    "energy.total",
    "contact.active_nodes",
    "contact.force",
    "stop1.force",
]
# The animations: scene, start (s), forcing periods shown, internal steps per frame (0.6 ms at the
# scene's Δt = 0.1 ms: an impact, about 1.8 ms long, spans three frames) and the file.
ANIMATIONS = [
    {"scene": "forced-35hz", "start": 0.4, "periods": 3, "every": 6, "gif": "plate.gif"},
    {"scene": "stud-corner", "start": 0.4, "periods": 2, "every": 5, "gif": "stud-corner.gif"},
]
# The field's free-corner values and the FMU's corner outputs are the same discrete field
# evaluated by two different sums (vertex values against point functionals), so they agree to
# round-off (measured 2e-18 m); a wrong vertex numbering would differ by millimetres.
CORNER_TOLERANCE_M = 1e-12
# The paper's plate (the FMU defaults) for the mode shapes, sampled at 4 points per cell side.
MODES = {"mesh": ["argyris", "10", "7"], "refine": 4}


def shown(path):
    """A path as printed: relative to the working directory when below it."""
    try:
        return path.resolve().relative_to(pathlib.Path.cwd())
    except ValueError:
        return path


def impacts(active):
    """Number of rising edges of `active > 0` (contact episodes seen at the output points)."""
    touching = np.asarray(active) > 0
    return int(np.count_nonzero(touching[1:] & ~touching[:-1]) + touching[0])


def simulate(fmu, scene_name, out_dir):
    """Runs one scene through the FMU; writes its CSV and plot."""
    if scene_name == "default":
        values, stop = {}, 1.0
    else:
        values, stop = start_values(scene_name)
    t0 = time.perf_counter()
    result = fmpy.simulate_fmu(
        fmu, start_values=values, stop_time=stop, output_interval=1e-3, output=OUTPUTS
    )
    wall = time.perf_counter() - t0
    names = result.dtype.names
    csv = out_dir / f"{scene_name}.csv"
    np.savetxt(
        csv,
        np.column_stack([result[n] for n in names]),
        delimiter=",",
        header=",".join(names),
        comments="",
    )
    print(
        f"{shown(csv)}: {len(result)} rows of time and {len(names) - 1} FMU outputs every 1 ms, "
        f"{wall:.2f} s wall time"
    )
    stops = "stop1.force" in names and np.any(result["stop1.force"] != 0)
    fig, axes = plt.subplots(3 if stops else 2, 1, figsize=(9, 8 if stops else 6), sharex=True)
    ax1, ax2 = axes[0], axes[-1]
    for name, label in displacement_curves(values):
        ax1.plot(result["time"], 1e3 * result[name], label=label, lw=0.8)
    ax1.set_ylabel("displacement (mm)")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title(f"PlateImpact FMU, scene '{scene_name}' ({wall:.1f} s wall time)")
    if stops:
        axes[1].plot(result["time"], result["stop1.force"], lw=0.8, color="C3")
        axes[1].set_ylabel("stop 1 force (N)")
    for name in ["energy.kinetic", "energy.elastic", "energy.total"]:
        ax2.plot(result["time"], result[name], label=name, lw=0.8)
    ax2.set_xlabel("time (s)")
    ax2.set_ylabel("energy (J)")
    ax2.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    png = out_dir / f"{scene_name}.png"
    fig.savefig(png, dpi=110)
    plt.close(fig)
    largest = max(np.abs(result[name]).max() for name, _ in displacement_curves(values))
    stop_line = f", stop 1 force up to {np.abs(result['stop1.force']).max():.0f} N" if stops else ""
    print(
        f"{shown(png)}: displacements and energy of '{scene_name}', largest |u| = "
        f"{1e3 * largest:.3f} mm, {impacts(result['contact.active_nodes'])} contact episodes"
        f"{stop_line}, final energy {result['energy.total'][-1]:.3f} J"
    )


def displacement_curves(values):
    """(output, label) of the displacements a scene's plot shows: the corners and edge midpoint
    unless the whole x = Lx edge is clamped (then they follow the base), and the probes the scene
    places (off their start at the corner (0, 0))."""
    curves = []
    if values.get("plate.clamp", "xmin").strip() not in ("all", "xmax"):
        curves += [
            ("corner1.displacement", "corner (Lx, 0)"),
            ("corner2.displacement", "corner (Lx, Ly)"),
            ("edge_mid.displacement", "edge midpoint (Lx, Ly/2)"),
        ]
    for k in (1, 2):
        x, y = values.get(f"probe{k}.x", 0.0), values.get(f"probe{k}.y", 0.0)
        if (x, y) != (0.0, 0.0):
            curves.append((f"probe{k}.displacement", f"probe {k} ({x:g}, {y:g}) m"))
    return curves


def run_example(name, args):
    """Runs a Rust example of this crate in release mode; its log is shown only if it fails."""
    command = ["cargo", "run", "--release", "--quiet", "--example", name, "--", *args]
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"{' '.join(command)} failed:\n{done.stderr}")
    return done.stdout


def compare_with_fmu(fmu, field, values):
    """Largest differences between the field's free corners and energy and the FMU's outputs at
    the same instants (the FMU is run with the field's frame interval as communication step)."""
    frames = field["frames"]
    interval = frames[1]["t"] - frames[0]["t"]
    result = fmpy.simulate_fmu(
        fmu,
        start_values=values,
        stop_time=frames[-1]["t"],
        output_interval=interval,
        output=["corner1.displacement", "corner2.displacement", "energy.total"],
    )
    xy = np.array(field["vertices"])
    corners = [
        int(
            np.flatnonzero(
                np.all(np.isclose(xy, [field["length"], y], rtol=0, atol=1e-12), axis=1)
            )[0]
        )
        for y in (0.0, field["width"])
    ]
    corner_gap, energy_gap, matched = 0.0, 0.0, 0
    for frame in frames:
        row = np.flatnonzero(np.abs(result["time"] - frame["t"]) < 1e-9 * interval)
        if len(row) == 0:
            continue
        r = result[row[0]]
        matched += 1
        for vertex, name in zip(corners, ["corner1.displacement", "corner2.displacement"]):
            corner_gap = max(corner_gap, abs(frame["u"][vertex] - r[name]))
        energy_gap = max(energy_gap, abs(frame["energy"] - r["energy.total"]))
    if matched < len(frames) // 2:
        sys.exit(f"only {matched} of {len(frames)} field frames fall on FMU output times")
    if corner_gap > CORNER_TOLERANCE_M:
        sys.exit(
            f"the field's free corners differ from the FMU's corner outputs by "
            f"{corner_gap:.3g} m (limit {CORNER_TOLERANCE_M:g} m)"
        )
    return matched, corner_gap, energy_gap


def animate(fmu, out_dir, animation):
    """The plate's field from the library, checked against the FMU, rendered as a GIF."""
    scene = animation["scene"]
    values, _ = start_values(scene)
    stop = animation["start"] + animation["periods"] / values["base.frequency"]
    path = out_dir / f"{pathlib.Path(animation['gif']).stem}-field.json"
    run_example(
        "scene",
        [
            scene,
            f"stop_time={stop!r}",
            "--from",
            str(animation["start"]),
            "--every",
            str(animation["every"]),
            "--field",
            str(path),
        ],
    )
    field = json.loads(path.read_text())
    matched, corner_gap, energy_gap = compare_with_fmu(fmu, field, values)
    frames = field["frames"]
    print(
        f"{shown(path)}: '{scene}' from the library, {len(frames)} frames of u at "
        f"{len(field['vertices'])} vertices, t = {frames[0]['t']:.4f} to "
        f"{frames[-1]['t']:.4f} s; "
        f"at {matched} frames the free corners equal the FMU's outputs to {corner_gap:.1e} m "
        f"and the energy to {energy_gap:.1e} J"
    )
    gif = out_dir / animation["gif"]
    print(plate_animation.summary(shown(gif), plate_animation.render(field, gif)))


def plot_modes(out_dir):
    """The lowest mode shapes of the paper's plate."""
    path = out_dir / "modes.json"
    run_example("modes", [*MODES["mesh"], "--shapes", str(path), "--refine", str(MODES["refine"])])
    data = json.loads(path.read_text())
    print(
        f"{shown(path)}: {len(data['shapes'])} mode shapes of the {data['element']} "
        f"{data['nx']} × {data['ny']} plate on a {len(data['x'])} × {len(data['y'])} grid"
    )
    png = out_dir / "modes.png"
    print(mode_shapes.summary(shown(png), mode_shapes.render(data, png)))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    parser.add_argument("--out", default=str(ROOT / "out"))
    parser.add_argument(
        "scenes",
        nargs="*",
        default=[
            "forced",
            "forced-35hz",
            "forced-35hz-damped",
            "energy",
            "stud-corner",
            "clamped-panel",
            "inclined-support",
        ],
        help="scenes run through the FMU (file stems of scenes/, or default)",
    )
    args = parser.parse_args()
    out_dir = pathlib.Path(args.out)
    out_dir.mkdir(parents=True, exist_ok=True)
    for scene_name in args.scenes:
        simulate(args.fmu, scene_name, out_dir)
    for animation in ANIMATIONS:
        animate(args.fmu, out_dir, animation)
    plot_modes(out_dir)


if __name__ == "__main__":
    main()
