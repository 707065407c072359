"""Plots the lowest six mode shapes written by `examples/modes.rs --shapes`.

One 3D surface per mode, coloured by the normalised deflection, with the clamped edge x = 0 drawn
in black and the natural frequency in the title.

    python examples/mode_shapes.py SHAPES.json [--out docs/modes.png]
"""

import argparse
import json
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def render(data, out_path):
    """Writes the figure; returns the frequencies it shows (Hz)."""
    x = 1e3 * np.array(data["x"])
    y = 1e3 * np.array(data["y"])
    X, Y = np.meshgrid(x, y)
    shapes = np.array(data["shapes"])
    frequencies = data["frequencies_hz"]
    fig = plt.figure(figsize=(10, 6.2))
    mesh = f"{data['element']} {data['nx']} × {data['ny']}"
    sampling = (
        f"sampled at {data['refine']} points per cell side"
        if data["refine"] > 1
        else "vertex values"
    )
    fig.suptitle(
        f"Lowest {len(shapes)} modes of the clamped plate ({mesh}, {sampling}); "
        "shapes scaled to max |φ| = 1",
        fontsize=11,
    )
    for k, (phi, f) in enumerate(zip(shapes, frequencies)):
        ax = fig.add_subplot(2, 3, k + 1, projection="3d")
        ax.plot_surface(
            X,
            Y,
            phi,
            cmap="coolwarm",
            vmin=-1,
            vmax=1,
            rstride=1,
            cstride=1,
            linewidth=0,
            antialiased=True,
        )
        ax.plot([0, 0], [y[0], y[-1]], [0, 0], color="black", linewidth=2.5)
        ax.set_box_aspect((x[-1], y[-1], 0.35 * x[-1]))
        ax.set(zlim=(-1, 1), xticks=[0, x[-1]], yticks=[0, y[-1]], zticks=[-1, 0, 1])
        ax.tick_params(labelsize=7, pad=0)
        ax.set_xlabel("x (mm)", fontsize=8, labelpad=-4)
        ax.set_ylabel("y (mm)", fontsize=8, labelpad=-4)
        ax.view_init(elev=24, azim=-58)
        ax.set_title(f"mode {k + 1}: {f:.1f} Hz", fontsize=10, pad=0)
    fig.text(0.5, 0.02, "black: the clamped edge x = 0", ha="center", fontsize=9)
    fig.subplots_adjust(left=0.0, right=1.0, bottom=0.04, top=0.9, wspace=0.0, hspace=0.08)
    fig.savefig(out_path, dpi=90)
    plt.close(fig)
    return frequencies


def summary(path, frequencies):
    """One line that says what the figure shows."""
    listed = ", ".join(f"{f:.1f}" for f in frequencies)
    return f"{path}: mode shapes 1 to {len(frequencies)} at {listed} Hz"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shapes", help="JSON written by examples/modes.rs --shapes")
    parser.add_argument("--out", default="out/modes.png")
    args = parser.parse_args()
    data = json.loads(pathlib.Path(args.shapes).read_text())
    print(summary(args.out, render(data, args.out)))


if __name__ == "__main__":
    main()
