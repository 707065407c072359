"""Cost against mesh size: the table, the fitted growth exponents and the log-log plot of
docs/scale/README.md, from the CSV that `cargo bench --bench solver -- --scale` prints.

The bench runs `forced-35hz` (dt = 1e-4 s, 0.05 s: 500 steps, about 70 of them with contact) on
meshes from 10 x 7 to 100 x 50 for both elements, each in a process of its own, with the backend
that `solver.linear = auto` picks. On a shared machine timings only get slower, so several runs
are combined by taking, per mesh, the smallest of each timing (and the median of each memory
peak). Usage:

    cargo bench --bench solver -- --scale > run1.csv   (repeat: run2.csv, ...)
    .venv/bin/python -m plateimpact_tools.studies.scale_plots run1.csv run2.csv ... [--out docs/scale]

writes docs/scale/scale.csv (the combined runs) and docs/scale/scale.png, and prints the table and
the exponents of the fits  cost = c * n^p  over the meshes each backend runs (n = free dofs).
"""

import argparse
import csv
import pathlib
import statistics

import numpy as np

from plateimpact_tools import ROOT
from plateimpact_tools.plotting import pyplot, save

plt = pyplot()

TIMINGS = ["assembly_s", "setup_s", "us_per_step", "free_us", "qp_us"]
MEMORY = ["peak_setup_mib", "peak_end_mib"]
ELEMENTS = ["Argyris", "Fvs"]
COLORS = {"Argyris": "tab:blue", "Fvs": "tab:orange"}
MARKERS = {"Modal": "s", "Sparse": "o"}


def read_runs(paths):
    """The rows of every run, grouped by case."""
    runs = {}
    for path in paths:
        with open(path, newline="") as f:
            for row in csv.DictReader(line for line in f if not line.startswith("|")):
                runs.setdefault(row["case"], []).append(row)
    return runs


def combine(rows):
    """One row per case: the smallest timing and the median memory peak over the runs."""
    first = dict(rows[0])
    for key in TIMINGS:
        first[key] = min(float(r[key]) for r in rows)
    for key in MEMORY:
        first[key] = statistics.median(float(r[key]) for r in rows)
    for key in [
        "nx",
        "ny",
        "free_dofs",
        "constrained",
        "steps",
        "free_steps",
        "qp_steps",
        "most_active",
    ]:
        first[key] = int(first[key])
    first["runs"] = len(rows)
    return first


def number(v):
    """A figure for the table: three significant digits, whole numbers from 100 on."""
    return f"{v:.0f}" if v >= 100 else f"{v:.3g}"


def fit(points):
    """The exponent p and factor c of the least-squares line log y = log c + p log n."""
    n, y = np.log([p[0] for p in points]), np.log([p[1] for p in points])
    p, log_c = np.polyfit(n, y, 1)
    return p, float(np.exp(log_c))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "runs", nargs="+", help="CSV output of `cargo bench --bench solver -- --scale`"
    )
    parser.add_argument("--out", default=str(ROOT / "docs" / "scale"))
    args = parser.parse_args()
    out = pathlib.Path(args.out)
    rows = sorted(
        (combine(r) for r in read_runs(args.runs).values()),
        key=lambda r: (r["element"], r["free_dofs"]),
    )

    columns = [
        "case",
        "element",
        "nx",
        "ny",
        "backend",
        "free_dofs",
        "constrained",
        "assembly_s",
        "setup_s",
        "steps",
        "us_per_step",
        "free_steps",
        "free_us",
        "qp_steps",
        "qp_us",
        "most_active",
        "peak_setup_mib",
        "peak_end_mib",
        "runs",
    ]
    with open(out / "scale.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)

    print(
        "| mesh | backend | free dofs | constrained | set-up s (assembly + backend) | "
        "µs per contact-free step | µs per step with contact | µs per step, all | "
        "peak MiB after set-up / at end |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        setup = r["assembly_s"] + r["setup_s"]
        print(
            f"| {r['element']} {r['nx']} × {r['ny']} | {r['backend'].lower()} | {r['free_dofs']} | "
            f"{r['constrained']} | {setup:.2f} ({r['assembly_s']:.2f} + {r['setup_s']:.2f}) | "
            f"{number(r['free_us'])} | {number(r['qp_us'])} ({r['qp_steps']} steps, up to "
            f"{r['most_active']} contacts) | {number(r['us_per_step'])} | "
            f"{r['peak_setup_mib']:.0f} / {r['peak_end_mib']:.0f} |"
        )

    quantities = [
        ("free_us", "µs per contact-free step"),
        ("qp_us", "µs per step with contact"),
        ("setup", "set-up s"),
        ("peak_end_mib", "peak MiB"),
    ]
    print()
    print(
        "| element | backend | meshes (free dofs) | " + " | ".join(q[1] for q in quantities) + " |"
    )
    print("|---|---|---|" + "---|" * len(quantities))
    for element in ELEMENTS:
        for backend in MARKERS:
            group = [r for r in rows if r["element"] == element and r["backend"] == backend]
            if len(group) < 2:
                continue
            exponents = []
            for key, _ in quantities:
                value = (
                    (lambda r: r["assembly_s"] + r["setup_s"])
                    if key == "setup"
                    else (lambda r, key=key: r[key])
                )
                p, _ = fit([(r["free_dofs"], value(r)) for r in group])
                exponents.append(f"n^{p:.2f}")
            span = f"{group[0]['free_dofs']}–{group[-1]['free_dofs']}"
            print(f"| {element} | {backend.lower()} | {span} | " + " | ".join(exponents) + " |")

    figure, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    for element in ELEMENTS:
        for backend, marker in MARKERS.items():
            group = [r for r in rows if r["element"] == element and r["backend"] == backend]
            if not group:
                continue
            n = [r["free_dofs"] for r in group]
            color = COLORS[element]
            label = f"{element} ({backend.lower()})"
            axes[0].loglog(
                n,
                [r["free_us"] for r in group],
                marker=marker,
                color=color,
                label=f"{label}, contact-free",
            )
            axes[0].loglog(
                n,
                [r["qp_us"] for r in group],
                marker=marker,
                color=color,
                linestyle="--",
                label=f"{label}, with contact",
            )
            axes[1].loglog(
                n,
                [r["assembly_s"] + r["setup_s"] for r in group],
                marker=marker,
                color=color,
                label=label,
            )
            axes[2].loglog(
                n, [r["peak_end_mib"] for r in group], marker=marker, color=color, label=label
            )
    titles = [
        "cost of a step (µs)",
        "set-up: assembly and backend (s)",
        "peak resident memory (MiB)",
    ]
    for axis, title in zip(axes, titles):
        axis.set_xlabel("free dofs n")
        axis.set_title(title)
        axis.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    axes[1].legend(fontsize=8)
    axes[2].legend(fontsize=8)
    figure.suptitle(
        "forced-35hz, Δt = 1e-4 s, 500 steps, meshes 10 × 7 to 100 × 50 "
        "(squares: modal backend, circles: sparse)"
    )
    save(figure, out / "scale.png")


if __name__ == "__main__":
    main()
