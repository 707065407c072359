"""The write step of the work-precision study: plots and the tables of README.md, from the CSVs of
the `accuracy` binary of studies/ (`studies/src/bin/accuracy/`).

Usage: python -m plateimpact_tools.studies.accuracy_plots DIR [--quick] [--tables-only]. Reads
DIR/runs.csv, frequencies.csv, table1.csv, paper_table1.csv, traces.csv, reference_check.csv,
meta.csv; writes DIR/*.png, beside each the CSV of the data it shows (traces.png shows
traces.csv), and the generated tables of DIR/README.md (the page is hand-written; `pages.fill`).
Run by `cargo run --release -p plate_impact_studies --bin accuracy`.
"""

import csv
import math
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.studies import pages

plt = pyplot()

# The source the generated blocks name.
MODULE = "the accuracy study's write step"
COLORS = {"argyris": "tab:blue", "fvs": "tab:red"}
ELEMENTS = ("argyris", "fvs")
SCENE_TITLES = {
    "free-smooth": "contact-free, smooth base start",
    "free": "contact-free: energy scene, no obstacle",
    "energy": "energy (released onto the lower obstacle)",
    "forced-35hz": "forced, 35 Hz (both obstacles)",
}
H_STYLES = {"free-smooth": "-", "free": "--", "energy": "-.", "forced-35hz": ":"}
RUN_FLOATS = (
    "h",
    "dt",
    "setup_s",
    "stepping_s",
    "wall_s",
    "ref_rms",
    "ref_max",
    "dt_rms",
    "dt_max",
    "h_rms",
    "h_max",
    "energy_end",
    "energy_rel_err",
    "diff_vs_fast",
    "first_contact_s",
    "pre_rms",
    "pre_max",
)


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def num(x):
    return float(x) if x not in ("", None) else None


def fit(points):
    """Least-squares slope of log y against log x."""
    pts = [(x, y) for x, y in points if y is not None and y > 0]
    if len(pts) < 2:
        return float("nan")
    lx, ly = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(lx, ly, 1)[0])


def local_orders(points):
    """Orders between successive levels (points sorted by decreasing x)."""
    return [
        math.log(y0 / y1) / math.log(x0 / x1)
        for (x0, y0), (x1, y1) in zip(points, points[1:])
        if y0 > 0 and y1 > 0
    ]


def fmt(x, digits=2):
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}e}"


class Study:
    """The CSVs of one run of the study and the families of runs the tables and plots compare."""

    def __init__(self, out):
        self.runs = read(out / "runs.csv")
        for r in self.runs:
            for k in RUN_FLOATS:
                r[k] = num(r[k])
            for k in ("nx", "ny", "free_dofs", "steps", "qp_steps"):
                r[k] = int(r[k])
        self.meta = {row["key"]: row["value"] for row in read(out / "meta.csv")}
        self.freqs = read(out / "frequencies.csv")
        self.table1 = read(out / "table1.csv")
        self.paper_times = {
            (row["element"], float(row["dt"])): float(row["cpu_s"])
            for row in read(out / "paper_table1.csv")
        }
        self.traces = read(out / "traces.csv")
        self.checks = {row["scene"]: row for row in read(out / "reference_check.csv")}
        self.scenes = [s for s in SCENE_TITLES if any(r["scene"] == s for r in self.runs)]
        self.fast = [r for r in self.runs if r["strategy"] == "fast"]
        self.paper_mesh = {
            e: tuple(int(v) for v in self.meta[f"paper_mesh_{e}"].split("x")) for e in ELEMENTS
        }
        self.finest = {
            e: max({(r["nx"], r["ny"]) for r in self.fast if r["element"] == e}) for e in ELEMENTS
        }
        self.dt_min = min(r["dt"] for r in self.fast)
        # The smallest Δt run on every mesh of both elements: the level of the space-error study.
        meshes_of = {
            e: {(r["nx"], r["ny"]) for r in self.fast if r["element"] == e} for e in ELEMENTS
        }
        self.dt_h = min(
            dt
            for dt in {r["dt"] for r in self.fast}
            if all(
                {(r["nx"], r["ny"]) for r in self.fast if r["element"] == e and r["dt"] == dt}
                == meshes_of[e]
                for e in ELEMENTS
            )
        )

    def family(self, scene, element, mesh=None, dt=None):
        """The fast runs of a scene and element (on a mesh, at a Δt), the reference left out."""
        return [
            r
            for r in self.fast
            if r["scene"] == scene
            and r["element"] == element
            and r["ref_rms"] > 0
            and (mesh is None or (r["nx"], r["ny"]) == mesh)
            and (dt is None or r["dt"] == dt)
        ]

    def dt_orders(self):
        """(scene, element, mesh, fitted order, local orders, points) of the time error alone on
        the paper's and the finest mesh, fitted over the levels ≥ 4× the mesh's finest Δt."""
        out = []
        for s in self.scenes:
            for e in ELEMENTS:
                for mesh in (self.paper_mesh[e], self.finest[e]):
                    fam = sorted(
                        [r for r in self.family(s, e, mesh=mesh) if r["dt_rms"] is not None],
                        key=lambda r: -r["dt"],
                    )
                    if len(fam) < 2:
                        continue
                    pts = [(r["dt"], r["dt_rms"]) for r in fam]
                    ref_dt = min(
                        r["dt"]
                        for r in self.fast
                        if r["scene"] == s and r["element"] == e and (r["nx"], r["ny"]) == mesh
                    )
                    fitted = [p for p in pts if p[0] >= 4 * ref_dt]
                    out.append((s, e, mesh, fit(fitted), local_orders(pts), pts))
        return out

    def h_orders(self):
        """(scene, element, fitted order, local orders, points) of the space error alone."""
        out = []
        for s in self.scenes:
            for e in ELEMENTS:
                fam = sorted(
                    [r for r in self.family(s, e, dt=self.dt_h) if r["h_rms"] is not None],
                    key=lambda r: -r["h"],
                )
                if len(fam) >= 2:
                    pts = [(r["h"], r["h_rms"]) for r in fam]
                    out.append((s, e, fit(pts), local_orders(pts), pts))
        return out

    def frequency_errors(self):
        """(element, mode) -> [(h, |f/f_ref − 1|)] by decreasing h."""
        by = defaultdict(list)
        for row in self.freqs:
            by[(row["element"], int(row["mode"]))].append(
                (float(row["h"]), abs(float(row["frequency_hz"]) / float(row["reference_hz"]) - 1))
            )
        return {k: sorted(v, reverse=True) for k, v in sorted(by.items())}


# ----------------------------------------------------------------------------------------------
# Plots, each with the CSV of what it shows.


def traces_plot(study, out):
    """The reference corner trajectories (their data: traces.csv)."""
    t = np.array([float(row["t"]) for row in study.traces])
    fig, ax = plt.subplots(figsize=(8, 4))
    for s in study.scenes:
        ax.plot(1e3 * t, 1e3 * np.array([float(row[s]) for row in study.traces]), label=s)
    ax.axhline(-10, color="k", lw=0.8, ls=":")
    ax.axhline(10, color="k", lw=0.8, ls=":")
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("corner u(Lx, 0) (mm)")
    ax.set_title(f"Reference corner displacement ({study.meta['reference']})", fontsize=10)
    ax.text(1, -9.5, "obstacles at ±10 mm (forced-35hz); energy has the lower one only", fontsize=7)
    ax.legend(fontsize=8)
    save(fig, out / "traces.png", dpi=110)


def front(points):
    """The lowest error reached within each wall time: the steps of the work-precision front."""
    steps, best = [], math.inf
    for w, err in sorted(points):
        if err < best:
            steps.append((w, err))
            best = err
    return steps


def work_precision_panel(study, ax, s, data):
    """One scene's panel: fixed-Δt families (solid), mesh families (dashed), the front."""
    for e in ELEMENTS:
        rows = study.family(s, e)
        for dt in sorted({r["dt"] for r in rows}, reverse=True):
            fam = sorted(study.family(s, e, dt=dt), key=lambda r: r["free_dofs"])
            decade = abs(math.log10(dt) - round(math.log10(dt))) < 1e-9
            if len(fam) >= 3 and decade:
                ax.plot(
                    [r["wall_s"] for r in fam],
                    [r["ref_rms"] for r in fam],
                    "-o",
                    color=COLORS[e],
                    ms=3,
                    lw=0.9,
                    alpha=0.6,
                )
                r = fam[-1]
                ax.annotate(
                    f"Δt={dt:g}",
                    (r["wall_s"], r["ref_rms"]),
                    fontsize=6,
                    color=COLORS[e],
                    xytext=(3, 0),
                    textcoords="offset points",
                )
        for mesh in (study.paper_mesh[e], study.finest[e]):
            fam = sorted(study.family(s, e, mesh=mesh), key=lambda r: -r["dt"])
            if len(fam) >= 4:
                ax.plot(
                    [r["wall_s"] for r in fam],
                    [r["ref_rms"] for r in fam],
                    "--s",
                    color=COLORS[e],
                    ms=3,
                    lw=0.9,
                )
                ax.annotate(
                    f"{mesh[0]}×{mesh[1]}",
                    (fam[0]["wall_s"], fam[0]["ref_rms"]),
                    fontsize=7,
                    color=COLORS[e],
                    xytext=(0, 4),
                    textcoords="offset points",
                )
        steps = front([(r["wall_s"], r["ref_rms"]) for r in rows if r["ref_rms"] > 0])
        ax.step(
            [p[0] for p in steps],
            [p[1] for p in steps],
            where="post",
            color=COLORS[e],
            lw=2.5,
            alpha=0.5,
            label=f"{e}: front",
        )
        data += [
            [
                s,
                r["element"],
                r["nx"],
                r["ny"],
                r["dt"],
                r["strategy"],
                r["wall_s"],
                r["ref_rms"],
                int((r["wall_s"], r["ref_rms"]) in steps),
            ]
            for r in rows
        ]
    cl = [r for r in study.runs if r["strategy"] == "clarabel" and r["scene"] == s]
    for r in cl:
        ax.plot(r["wall_s"], r["ref_rms"], "x", color=COLORS[r["element"]], ms=9, mew=2)
        data.append(
            [s, r["element"], r["nx"], r["ny"], r["dt"], "clarabel", r["wall_s"], r["ref_rms"], 0]
        )
    if cl:
        ax.plot([], [], "kx", label="clarabel every step")


def work_precision_plot(study, out):
    """Total RMS corner error against wall time, one panel per scene."""
    fig, axes = plt.subplots(2, 2, figsize=(12, 9), squeeze=False)
    data = []
    for ax, s in zip(axes.flat, study.scenes):
        work_precision_panel(study, ax, s, data)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(SCENE_TITLES[s], fontsize=10)
        ax.set_xlabel("wall time of the run (s)")
        ax.set_ylabel("RMS corner error vs reference (m)")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    for ax in list(axes.flat)[len(study.scenes) :]:
        ax.axis("off")
    fig.suptitle(
        "Work-precision: solid = fixed Δt, mesh refined; dashed = fixed mesh, Δt refined",
        fontsize=11,
    )
    save(fig, out / "work_precision.png", dpi=110)
    pages.figure_data(
        out / "work_precision.png",
        ["scene", "element", "nx", "ny", "dt", "strategy", "wall_s", "ref_rms", "on_front"],
        data,
    )


def convergence_dt_plot(study, out, dt_orders):
    """The time error alone against Δt, on the paper's and the finest mesh."""
    fig, axes = plt.subplots(
        1, len(study.scenes), figsize=(4 * len(study.scenes), 4), squeeze=False
    )
    data = []
    for ax, s in zip(axes[0], study.scenes):
        for scene, e, mesh, _, _, pts in dt_orders:
            if scene != s:
                continue
            style = "-o" if mesh == study.paper_mesh[e] else ":s"
            ax.loglog(*zip(*pts), style, color=COLORS[e], ms=3, label=f"{e} {mesh[0]}×{mesh[1]}")
            data += [[s, e, mesh[0], mesh[1], dt, err] for dt, err in pts]
        x = np.array([1e-3, 1e-5])
        ax.loglog(x, 1e-3 * (x / 1e-3) ** 2, "k:", lw=0.8, label="slope 2")
        ax.set_title(SCENE_TITLES[s], fontsize=9)
        ax.set_xlabel("Δt (s)")
        ax.set_ylabel("RMS corner error vs same mesh, finest Δt (m)")
        ax.legend(fontsize=7)
    save(fig, out / "convergence_dt.png", dpi=110)
    pages.figure_data(
        out / "convergence_dt.png", ["scene", "element", "nx", "ny", "dt", "dt_rms"], data
    )


def convergence_h_plot(study, out, h_orders):
    """The space error alone against h, and the natural frequencies' errors against h."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    data = []
    for s, e, _, _, pts in h_orders:
        axes[0].loglog(
            *zip(*pts), marker="o", color=COLORS[e], ms=3, ls=H_STYLES[s], label=f"{e}, {s}"
        )
        data += [["space error", s, e, "", h, err] for h, err in pts]
    axes[0].set_xlabel("h = Lx / nx (m)")
    axes[0].set_ylabel(f"RMS corner error vs finest mesh, Δt = {study.dt_h:g} s (m)")
    axes[0].legend(fontsize=7)
    for (e, mode), pts in study.frequency_errors().items():
        axes[1].loglog(
            *zip(*pts),
            "-o",
            color=COLORS[e],
            ms=3,
            alpha=1 - 0.12 * (mode - 1),
            label=f"{e}" if mode == 1 else None,
        )
        axes[1].annotate(str(mode), pts[-1], fontsize=7, color=COLORS[e])
        data += [["frequency error", "", e, mode, h, err] for h, err in pts]
    axes[1].set_xlabel("h = Lx / nx (m)")
    axes[1].set_ylabel("|f / f_ref − 1|, modes 1–6 (labelled)")
    axes[1].set_title("natural frequencies vs docs/elements.md §7", fontsize=9)
    axes[1].legend(fontsize=7)
    save(fig, out / "convergence_h.png", dpi=110)
    pages.figure_data(
        out / "convergence_h.png", ["panel", "scene", "element", "mode", "h", "error"], data
    )


# ----------------------------------------------------------------------------------------------
# The tables of README.md.


def reference_check_table(study):
    lines = [
        "| scene | time: reference vs next larger Δt (m) | space: vs Argyris "
        + study.meta["check_mesh"]
        + " at the same Δt (m) | other element: finest FVS vs "
        "reference (m) |",
        "|---|---|---|---|",
    ]
    for s in study.scenes:
        c = study.checks.get(s)
        if c is not None:
            lines.append(
                f"| {s} | {fmt(num(c['time_rms']))} / {fmt(num(c['time_max']))} (Δt = "
                f"{c['time_dt']}) | {fmt(num(c['space_rms']))} / {fmt(num(c['space_max']))} | "
                f"{fmt(num(c['fvs_rms']))} / {fmt(num(c['fvs_max']))} |"
            )
    return lines


def orders_dt_table(dt_orders):
    lines = [
        "| scene | element | mesh | fitted order | local orders | error at Δt = 1e-3 → "
        "smallest fitted (m) |",
        "|---|---|---|---|---|---|",
    ]
    for s, e, mesh, order, local, pts in dt_orders:
        fitted = [p for p in pts if p[0] >= 4 * min(p[0] for p in pts) / 2]
        lines.append(
            f"| {s} | {e} | {mesh[0]}×{mesh[1]} | {order:.2f} | "
            f"{' '.join(f'{o:.1f}' for o in local)} | {fmt(pts[0][1])} → "
            f"{fmt(fitted[-1][1])} |"
        )
    return lines


def first_impact_table(study):
    scenes = [
        s for s in study.scenes if any(r["first_contact_s"] for r in study.fast if r["scene"] == s)
    ]
    head = " | ".join(f"{s} {e}: first contact (ms), error (m)" for s in scenes for e in ELEMENTS)
    lines = [f"| Δt | {head} |", "|---|" + "---|" * (2 * len(scenes))]
    for dt in sorted({r["dt"] for r in study.fast}, reverse=True):
        cells = []
        for s in scenes:
            for e in ELEMENTS:
                r = next(
                    (
                        r
                        for r in study.fast
                        if r["scene"] == s
                        and r["element"] == e
                        and (r["nx"], r["ny"]) == study.paper_mesh[e]
                        and r["dt"] == dt
                    ),
                    None,
                )
                cells.append(
                    "–"
                    if r is None or r["first_contact_s"] is None
                    else f"{1e3 * r['first_contact_s']:.3f}, {fmt(r['pre_rms'])}"
                )
        lines.append(f"| {dt:g} | " + " | ".join(cells) + " |")
    return lines


def orders_h_table(h_orders):
    lines = [
        "| scene | element | fitted order | local orders | error, coarsest → second finest (m) |",
        "|---|---|---|---|---|",
    ]
    for s, e, order, local, pts in h_orders:
        lines.append(
            f"| {s} | {e} | {order:.2f} | {' '.join(f'{o:.1f}' for o in local)} | "
            f"{fmt(pts[0][1])} → {fmt(pts[-1][1])} |"
        )
    return lines


def frequencies_table(study):
    lines = [
        "| element | mesh | free dofs | "
        + " | ".join(f"f{k} rel. err" for k in range(1, 7))
        + " |",
        "|---|---|---|" + "---|" * 6,
    ]
    rows = defaultdict(dict)
    for row in study.freqs:
        key = (row["element"], int(row["nx"]), int(row["ny"]), int(row["free_dofs"]))
        rows[key][int(row["mode"])] = float(row["frequency_hz"]) / float(row["reference_hz"]) - 1
    for (e, nx, ny, n), errs in rows.items():
        lines.append(
            f"| {e} | {nx}×{ny} | {n} | "
            + " | ".join(f"{errs[k]:+.1e}" for k in range(1, 7))
            + " |"
        )
    return lines


def frequency_orders_table(study):
    lines = ["| element | fitted order in h of the frequency error, modes 1–6 |", "|---|---|"]
    orders = study.frequency_errors()
    for e in ELEMENTS:
        lines.append(
            f"| {e} | "
            + ", ".join(f"{fit(pts):.1f}" for (ee, _), pts in orders.items() if ee == e)
            + " |"
        )
    return lines


def energy_end_table(study):
    lines = [
        "| scene | element | mesh | Δt | energy (J) | rel. error |",
        "|---|---|---|---|---|---|",
    ]
    for s in study.scenes:
        for e in ELEMENTS:
            sel = [
                r
                for r in study.fast
                if r["scene"] == s
                and r["element"] == e
                and (
                    r["dt"] == study.dt_min
                    or ((r["nx"], r["ny"]) == study.paper_mesh[e] and r["dt"] in (1e-3, 1e-4, 1e-5))
                )
            ]
            for r in sorted(sel, key=lambda r: (r["free_dofs"], -r["dt"])):
                lines.append(
                    f"| {s} | {e} | {r['nx']}×{r['ny']} | {r['dt']:g} | "
                    f"{r['energy_end']:.5g} | {fmt(r['energy_rel_err'])} |"
                )
    return lines


def table1_table(study):
    """Our Table 1 wall times beside the paper's; clarabel extrapolated where not run."""
    lines = [
        "| element | mesh | Δt | steps | steps with a QP | ours, fast path (s) | ours, "
        "clarabel every step (s) | paper (s) | paper / ours (fast) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    t1 = defaultdict(dict)
    for row in study.table1:
        t1[(row["element"], row["nx"], row["ny"], float(row["dt"]))][row["strategy"]] = row
    per_qp_step = {
        e: float(d["clarabel"]["wall_s"]) / max(int(d["clarabel"]["qp_steps"]), 1)
        for (e, _, _, _), d in t1.items()
        if "clarabel" in d
    }
    for (e, nx, ny, dt), d in sorted(t1.items(), key=lambda kv: (kv[0][0], -kv[0][3])):
        f, c = d["fast"], d.get("clarabel")
        paper = study.paper_times.get((e, dt))
        ratio = f"{paper / float(f['wall_s']):.0f}×" if paper else "–"
        if c:
            cl = f"{float(c['wall_s']):.1f}"
        elif e in per_qp_step:
            cl = f"≈ {per_qp_step[e] * int(f['steps']):.0f} (extrapolated, not run)"
        else:
            cl = "–"
        lines.append(
            f"| {e} | {nx}×{ny} | {dt:g} | {f['steps']} | {f['qp_steps']} | "
            f"{float(f['wall_s']):.3f} | {cl} | {f'{paper:g}' if paper else '–'} | "
            f"{ratio} |"
        )
    return lines


def clarabel_table(study):
    lines = [
        "| scene | element | mesh | Δt | steps with a QP | max |diff| vs fast (m) | RMS error "
        "vs reference (m) | fast (s) | clarabel (s) | ratio |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in study.runs:
        if r["strategy"] != "clarabel":
            continue
        f = next(
            x
            for x in study.fast
            if all(x[k] == r[k] for k in ("scene", "element", "nx", "ny", "dt"))
        )
        lines.append(
            f"| {r['scene']} | {r['element']} | {r['nx']}×{r['ny']} | {r['dt']:g} | "
            f"{r['qp_steps']} | {fmt(r['diff_vs_fast'])} | {fmt(r['ref_rms'])} | "
            f"{f['wall_s']:.3f} | {r['wall_s']:.2f} | {r['wall_s'] / f['wall_s']:.0f}× |"
        )
    return lines


def tables(study, dt_orders, h_orders):
    """The generated tables of README.md, by block name."""
    return {
        "reference-check": reference_check_table(study),
        "orders-dt": orders_dt_table(dt_orders),
        "first-impact": first_impact_table(study),
        "orders-h": orders_h_table(h_orders),
        "frequencies": frequencies_table(study),
        "frequency-orders": frequency_orders_table(study),
        "energy-end": energy_end_table(study),
        "table1": table1_table(study),
        "clarabel": clarabel_table(study),
    }


def main():
    """Plots (with their data) and the tables of DIR/README.md; `--tables-only` writes the tables
    alone (the check that the committed tables follow from the committed CSVs)."""
    out = Path(sys.argv[1])
    study = Study(out)
    dt_orders, h_orders = study.dt_orders(), study.h_orders()
    if "--tables-only" not in sys.argv[2:]:
        traces_plot(study, out)
        work_precision_plot(study, out)
        convergence_dt_plot(study, out, dt_orders)
        convergence_h_plot(study, out, h_orders)
    pages.fill(out / "README.md", tables(study, dt_orders, h_orders), MODULE)


if __name__ == "__main__":
    main()
