"""The write step of the statistics study: plots and the tables of statistics.md, from the CSVs of
the `statistics` binary of studies/ (`studies/src/bin/statistics/`).

Usage: python -m plateimpact_tools.studies.statistics_plots DIR [--quick] [--tables-only]. Reads
DIR/statistics.csv, meshes.csv, replica_check.csv, statistics_meta.csv; writes DIR/statistics_*.png,
beside each the CSV of the data it shows, and the generated tables of DIR/statistics.md (the page
is hand-written; `pages.fill`). Run by
`cargo run --release -p plate_impact_studies --bin statistics`.

Definitions used throughout (statistics.md repeats them):
- two values a ± s_a and b ± s_b *agree* when |a − b| ≤ 2·√(s_a² + s_b²);
- the *reference* of a scene and quantity is its best-resolved run: the finest Argyris mesh at the
  smallest Δt run on it;
- the *error* of a run is |v − v_ref| / |v_ref|, and its *uncertainty* 2·√(s² + s_ref²) / |v_ref|;
- a run *reaches* a tolerance when error + uncertainty ≤ tolerance for it and for every smaller Δt
  on the same mesh (so that a lucky crossing of the reference does not count);
- a quantity *stays within its noise* on a mesh from the largest Δt from which every run on that
  mesh agrees with the mesh's smallest-Δt run (at least the two smallest Δt must agree):
  DIR/statistics_within_noise.csv lists that Δt per scene, quantity and mesh. It is no verdict of
  convergence: with this study's spreads (σ up to 5 %) it is far weaker than the rule of evidence
  (`plateimpact_tools.studies.evidence`, the rule of scripts/converge at 1 %), whose verdicts
  DIR/statistics_verdicts.csv and statistics_ladders.csv hold.
"""

import csv
import math
import sys
from pathlib import Path

from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.studies import evidence, pages

plt = pyplot()

# The source the generated blocks name.
MODULE = "the statistics study's write step"

FORCED = ["forced-35hz-damped", "forced-35hz", "forced-60hz-damped", "forced-60hz"]
SCENE_TITLES = {
    "forced-35hz-damped": "35 Hz, c = 9 mm, ζ₁ = 1 %",
    "forced-35hz": "35 Hz, c = 9 mm, undamped",
    "forced-60hz-damped": "60 Hz, c = 2 mm, ζ₁ = 1 %",
    "forced-60hz": "60 Hz, c = 2 mm, undamped",
    "energy": "energy: released onto the lower obstacle",
}
# quantity -> (label, unit shown, factor from the CSV's SI unit)
QUANTITIES = {
    "rms_corner_m": ("RMS free corner", "mm", 1e3),
    "peak_corner_m": ("peak free corner", "mm", 1e3),
    "impacts_per_period": ("impacts per period", "", 1.0),
    "contact_loss_per_period_J": ("energy removed at the obstacles per period", "J", 1.0),
    "mean_energy_J": ("mean energy.total", "J", 1.0),
    "mean_abs_base_force_N": ("mean |base.force|", "kN", 1e-3),
    "rms_base_force_N": ("RMS base.force", "kN", 1e-3),
    "first_impact_s": ("first impact", "ms", 1e3),
    "energy_0.1s_J": ("energy at 0.1 s", "J", 1.0),
    "energy_0.3s_J": ("energy at 0.3 s", "J", 1.0),
    "impacts_to_0.3s": ("impacts up to 0.3 s", "", 1.0),
}
FORCED_Q = [
    "rms_corner_m",
    "peak_corner_m",
    "impacts_per_period",
    "contact_loss_per_period_J",
    "mean_energy_J",
    "mean_abs_base_force_N",
]
ENERGY_Q = ["first_impact_s", "energy_0.1s_J", "energy_0.3s_J", "impacts_to_0.3s"]
# The forced quantities that can change with Δt (the peak is pinned at the obstacle in every run).
SETTLING_Q = [q for q in FORCED_Q if q != "peak_corner_m"]
COLORS = {"argyris": "tab:blue", "fvs": "tab:red"}
MARKERS = ["o", "s", "^", "D", "v", "P"]
TOLERANCES = (0.01, 0.05)
# Relative errors are drawn no lower than this.
ERROR_FLOOR = 1e-9


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


class Study:
    def __init__(self, out):
        self.rows = read(out / "statistics.csv")
        for r in self.rows:
            for k in ("dt", "omega_max_dt", "value", "spread", "wall_s"):
                r[k] = float(r[k])
            r["nx"], r["ny"] = int(r["nx"]), int(r["ny"])
            r["mesh"] = (r["element"], r["nx"], r["ny"])
        self.meshes = read(out / "meshes.csv")
        for m in self.meshes:
            m["key"] = (m["element"], int(m["nx"]), int(m["ny"]))
            m["free_dofs"] = int(m["free_dofs"])
            m["omega_max"] = float(m["omega_max_rad_s"])
        self.mesh_keys = [
            m["key"] for m in sorted(self.meshes, key=lambda m: (m["element"], m["free_dofs"]))
        ]
        self.meta = {row["key"]: row["value"] for row in read(out / "statistics_meta.csv")}
        self.replicas = read(out / "replica_check.csv")
        self.scenes = [s for s in SCENE_TITLES if any(r["scene"] == s for r in self.rows)]
        argyris = [m for m in self.meshes if m["element"] == "argyris"]
        self.reference_mesh = max(argyris, key=lambda m: m["free_dofs"])["key"]

    def select(self, scene, quantity, mesh=None):
        """Runs of a scene and quantity (on one mesh), by decreasing Δt."""
        return sorted(
            [
                r
                for r in self.rows
                if r["scene"] == scene
                and r["quantity"] == quantity
                and (mesh is None or r["mesh"] == mesh)
            ],
            key=lambda r: -r["dt"],
        )

    def quantities(self, scene):
        return ENERGY_Q if scene == "energy" else FORCED_Q

    def reference(self, scene, quantity):
        return self.select(scene, quantity, self.reference_mesh)[-1]

    def error(self, r):
        """(relative error, its uncertainty) against the reference."""
        ref = self.reference(r["scene"], r["quantity"])
        scale = abs(ref["value"])
        return (
            abs(r["value"] - ref["value"]) / scale,
            2 * math.hypot(r["spread"], ref["spread"]) / scale,
        )

    def within_noise(self, scene, quantity, mesh):
        """The run from which every smaller Δt on the mesh agrees with its smallest-Δt run."""
        runs = self.select(scene, quantity, mesh)
        last = runs[-1]
        start = None
        for i in range(len(runs) - 2, -1, -1):
            if not agree(runs[i], last):
                break
            start = runs[i]
        return start

    def cheapest(self, scene, quantity, tolerance):
        """The cheapest run that reaches the tolerance (see the module docstring), or None."""
        best = None
        ref = self.reference(scene, quantity)
        for mesh in self.mesh_keys:
            runs = self.select(scene, quantity, mesh)
            for i, r in enumerate(runs):
                if r is ref:
                    continue
                if all(sum(self.error(x)) <= tolerance for x in runs[i:] if x is not ref):
                    if best is None or r["wall_s"] < best["wall_s"]:
                        best = r
                    break
        return best


def agree(a, b):
    return abs(a["value"] - b["value"]) <= 2 * math.hypot(a["spread"], b["spread"])


def mesh_name(mesh):
    return f"{'Argyris' if mesh[0] == 'argyris' else 'FVS'} {mesh[1]}×{mesh[2]}"


def shown(quantity, value):
    return value * QUANTITIES[quantity][2]


def unit(quantity):
    u = QUANTITIES[quantity][1]
    return f" ({u})" if u else ""


def number(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "–"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def with_spread(quantity, r):
    return f"{number(shown(quantity, r['value']), 4)} ± {number(shown(quantity, r['spread']), 2)}"


# ----------------------------------------------------------------------------------------------
# Plots


def work_precision(study, out, scenes_of_panels, quantity_of_panels, name, title, dpi=100):
    """Error against wall time, one panel per (scene, quantity)."""
    n = len(scenes_of_panels)
    cols = 2 if n > 1 else 1
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(6.2 * cols, 4.6 * rows), squeeze=False)
    data = []
    for ax, scene, quantity in zip(axes.flat, scenes_of_panels, quantity_of_panels):
        ref = study.reference(scene, quantity)
        errors = [study.error(r)[0] for r in study.select(scene, quantity) if r is not ref]
        # The axis starts a little below the smallest error; bars that reach below it (errors
        # consistent with 0) end at its bottom.
        floor = max(ERROR_FLOOR, 0.3 * min((e for e in errors if e > 0), default=1.0))
        for element in ("argyris", "fvs"):
            meshes = [m for m in study.mesh_keys if m[0] == element]
            for k, mesh in enumerate(meshes):
                runs = [
                    r
                    for r in study.select(scene, quantity, mesh)
                    if r is not study.reference(scene, quantity)
                ]
                if not runs:
                    continue
                err = [study.error(r) for r in runs]
                data += [
                    [scene, quantity, *mesh, r["dt"], r["wall_s"], e, u]
                    for r, (e, u) in zip(runs, err)
                ]
                y = [max(e, floor) for e, _ in err]
                lo = [yy - max(e - u, floor) for yy, (e, u) in zip(y, err)]
                hi = [u for _, u in err]
                ax.errorbar(
                    [r["wall_s"] for r in runs],
                    y,
                    yerr=[lo, hi],
                    color=COLORS[element],
                    marker=MARKERS[k % len(MARKERS)],
                    ms=4,
                    lw=0.9,
                    elinewidth=0.6,
                    capsize=1.5,
                    alpha=0.85,
                    label=mesh_name(mesh),
                )
                first, last = runs[0], runs[-1]
                for r, yy in ((first, y[0]), (last, y[-1])):
                    ax.annotate(
                        f"{r['dt']:g}",
                        (r["wall_s"], yy),
                        fontsize=5.5,
                        color=COLORS[element],
                        xytext=(2, 2),
                        textcoords="offset points",
                    )
        for tol in TOLERANCES:
            ax.axhline(tol, color="k", lw=0.7, ls=":")
            ax.annotate(
                f"{tol:.0%}",
                (1, tol),
                xycoords=("axes fraction", "data"),
                fontsize=7,
                xytext=(-18, 2),
                textcoords="offset points",
            )
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(bottom=floor)
        ax.set_xlabel("wall time of one run (s)")
        ax.set_ylabel("relative error vs best-resolved run")
        ax.set_title(
            f"{QUANTITIES[quantity][0]} — {SCENE_TITLES[scene]}\nreference "
            f"{mesh_name(ref['mesh'])}, Δt = {ref['dt']:g} s: "
            f"{with_spread(quantity, ref)}{unit(quantity)}",
            fontsize=8,
        )
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=6, ncol=2, loc="lower left")
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.suptitle(
        title + " (bars: 2σ of the difference; labels: Δt of the first and last run of each mesh)",
        fontsize=9,
    )
    save(fig, out / name, dpi=dpi)
    pages.figure_data(
        out / name,
        [
            "scene",
            "quantity",
            "element",
            "nx",
            "ny",
            "dt",
            "wall_s",
            "relative_error",
            "uncertainty_2sigma",
        ],
        data,
    )


def against_omega_dt(study, out, grid, name):
    """Each quantity against ω_max·Δt, one line per mesh, 2σ bars: does it settle at ω_max·Δt ≈ 1?
    `grid` holds rows of (scene, quantity) panels."""
    nrows, ncols = len(grid), len(grid[0])
    fig, axes = plt.subplots(nrows, ncols, figsize=(4.2 * ncols, 2.9 * nrows + 0.6), squeeze=False)
    data = []
    for i, row in enumerate(grid):
        for j, (scene, quantity) in enumerate(row):
            ax = axes[i][j]
            for element in ("argyris", "fvs"):
                meshes = [m for m in study.mesh_keys if m[0] == element]
                for k, mesh in enumerate(meshes):
                    runs = study.select(scene, quantity, mesh)
                    data += [
                        [
                            scene,
                            quantity,
                            *mesh,
                            r["dt"],
                            r["omega_max_dt"],
                            r["value"],
                            r["spread"],
                        ]
                        for r in runs
                    ]
                    ax.errorbar(
                        [r["omega_max_dt"] for r in runs],
                        [shown(quantity, r["value"]) for r in runs],
                        yerr=[2 * shown(quantity, r["spread"]) for r in runs],
                        color=COLORS[element],
                        marker=MARKERS[k % len(MARKERS)],
                        ms=3,
                        lw=0.8,
                        elinewidth=0.6,
                        capsize=1.5,
                        alpha=0.85,
                        label=mesh_name(mesh),
                    )
            ax.axvline(1.0, color="k", lw=0.7, ls=":")
            ax.set_xscale("log")
            ax.invert_xaxis()
            ax.grid(True, alpha=0.3)
            if i == 0 or nrows == 1:
                ax.set_title(
                    SCENE_TITLES[scene] if nrows > 1 else QUANTITIES[quantity][0], fontsize=9
                )
            if j == 0 or nrows == 1:
                ax.set_ylabel(QUANTITIES[quantity][0] + unit(quantity), fontsize=8)
            if i == nrows - 1:
                ax.set_xlabel("ω_max·Δt (resolved right of the dotted line)", fontsize=8)
    axes[0][0].legend(fontsize=6, ncol=2)
    save(fig, out / name, dpi=90)
    pages.figure_data(
        out / name,
        ["scene", "quantity", "element", "nx", "ny", "dt", "omega_max_dt", "value", "spread"],
        data,
    )


# ----------------------------------------------------------------------------------------------
# statistics.md

# The paper's Argyris mesh (140 triangles), which the reading compares with.
PAPER_MESH = ("argyris", 10, 7)


def md_name(quantity):
    """The quantity's label for Markdown (its pipes escaped, so that tables keep their cells)."""
    return QUANTITIES[quantity][0].replace("|", "\\|")


def fit_slope(points):
    """Least-squares slope of log y against log x."""
    n = len(points)
    lx = [math.log(x) for x, _ in points]
    ly = [math.log(y) for _, y in points]
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((x - mx) ** 2 for x in lx)
    return sum((x - mx) * (y - my) for x, y in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def median(xs):
    xs = sorted(xs)
    return xs[len(xs) // 2] if len(xs) % 2 else 0.5 * (xs[len(xs) // 2 - 1] + xs[len(xs) // 2])


def settling_points(study, scenes, quantities):
    """(ω_max, settled run) for every (scene, quantity, mesh) that settled, and the count tried."""
    omega = {m["key"]: m["omega_max"] for m in study.meshes}
    found, tried = [], 0
    for scene in scenes:
        for q in quantities:
            for mesh in study.mesh_keys:
                tried += 1
                r = study.within_noise(scene, q, mesh)
                if r is not None:
                    found.append((omega[mesh], r))
    return found, tried


def run_at(study, scene, quantity, mesh, dt):
    return next((r for r in study.select(scene, quantity, mesh) if r["dt"] == dt), None)


def cheapest_table(study):
    """The cheapest setting that reaches 1 % and 5 %, per scene and quantity (or the closest)."""
    lines = ["| scene | quantity | 1 % | 5 % |", "|---|---|---|---|"]
    for scene in study.scenes:
        for q in study.quantities(scene):
            if q == "peak_corner_m":
                continue
            cells = []
            ref = study.reference(scene, q)
            floor = 2 * math.sqrt(2) * ref["spread"] / abs(ref["value"])
            for tol in TOLERANCES:
                r = study.cheapest(scene, q, tol)
                if r is None:
                    closest = min(
                        (x for x in study.select(scene, q) if x is not ref),
                        key=lambda x: sum(study.error(x)),
                    )
                    e, u = study.error(closest)
                    why = f"; 2σ of two runs' difference {floor:.1%}" if floor > tol else ""
                    cells.append(
                        f"not reached at any tested cost (closest: "
                        f"{mesh_name(closest['mesh'])}, Δt = {closest['dt']:g} s, "
                        f"{e:.1%} ± {u:.1%}{why})"
                    )
                else:
                    e, u = study.error(r)
                    cells.append(
                        f"{mesh_name(r['mesh'])}, Δt = {r['dt']:g} s (ω_max·Δt = "
                        f"{r['omega_max_dt']:.3g}): **{r['wall_s']:.3g} s**; error "
                        f"{e:.2%} ± {u:.2%}"
                    )
            lines.append(f"| {scene} | {md_name(q)} | {cells[0]} | {cells[1]} |")
    return lines


def paper_table(study):
    """The paper's 140-element meshes at its Δt against the best-resolved run."""
    paper = [PAPER_MESH, ("fvs", 14, 10)]
    head = [(m, dt) for m in paper for dt in (1e-3, 1e-4) if m in study.mesh_keys]
    lines = [
        "| scene | quantity | "
        + " | ".join(f"{mesh_name(m)}, Δt = {dt:g} s" for m, dt in head)
        + " |",
        "|---|---|" + "---|" * len(head),
    ]
    for scene in study.scenes:
        for q in study.quantities(scene):
            if q == "peak_corner_m":
                continue
            cells = []
            for m, dt in head:
                r = run_at(study, scene, q, m, dt)
                e, u = study.error(r) if r else (None, None)
                cells.append("–" if r is None else f"{e:.1%} ± {u:.1%}")
            lines.append(f"| {scene} | {md_name(q)} | " + " | ".join(cells) + " |")
    return lines


def settled_quantities(scene):
    return SETTLING_Q if scene != "energy" else ENERGY_Q


def settling_table(study):
    """Per scene and quantity: on how many meshes it settles in Δt, at which ω_max·Δt, and the
    exponent of Δt_settle ∝ ω_max^p."""
    lines = [
        "| scene | quantity | within its noise on | ω_max·Δt from which: min / median / max | p |",
        "|---|---|---|---|---|",
    ]
    for scene in study.scenes:
        for q in settled_quantities(scene):
            found, tried = settling_points(study, [scene], [q])
            wdt = [r["omega_max_dt"] for _, r in found]
            p = fit_slope([(wm, r["dt"]) for wm, r in found]) if len(found) >= 3 else None
            span = f"{min(wdt):.2g} / {median(wdt):.2g} / {max(wdt):.3g}" if wdt else "–"
            lines.append(
                f"| {scene} | {md_name(q)} | {len(found)} of {tried} meshes | {span} | "
                f"{'–' if p is None else f'{p:.2f}'} |"
            )
    return lines


def settling_by_mesh_table(study):
    """ω_max·Δt from which each quantity has settled, mesh by mesh."""
    lines = [
        "| scene | quantity | " + " | ".join(mesh_name(m) for m in study.mesh_keys) + " |",
        "|---|---|" + "---|" * len(study.mesh_keys),
    ]
    for scene in study.scenes:
        for q in settled_quantities(scene):
            cells = []
            for mesh in study.mesh_keys:
                runs_m = study.select(scene, q, mesh)
                st = study.within_noise(scene, q, mesh)
                cells.append(
                    ("no" if st is None else f"{st['omega_max_dt']:.3g}")
                    + f" [{runs_m[-1]['omega_max_dt']:.2g}]"
                )
            lines.append(f"| {scene} | {md_name(q)} | " + " | ".join(cells) + " |")
    return lines


def mesh_table(study):
    """Each mesh at its smallest Δt, and whether it agrees with the next coarser one."""
    lines = [
        "| scene | quantity | "
        + " | ".join(mesh_name(m) for m in study.mesh_keys)
        + " | finest FVS vs finest Argyris |",
        "|---|---|" + "---|" * (len(study.mesh_keys) + 1),
    ]
    for scene in study.scenes:
        for q in study.quantities(scene):
            if q == "peak_corner_m":
                continue
            cells, previous = [], {}
            for mesh in study.mesh_keys:
                r = study.select(scene, q, mesh)[-1]
                mark = ""
                if mesh[0] in previous:
                    mark = " ✓" if agree(r, previous[mesh[0]]) else " ✗"
                previous[mesh[0]] = r
                cells.append(with_spread(q, r) + mark)
            both = "agree" if agree(previous["argyris"], previous["fvs"]) else "differ"
            lines.append(
                f"| {scene} | {md_name(q)}{unit(q)} | " + " | ".join(cells) + f" | {both} |"
            )
    return lines


def reference_table(study):
    """The best-resolved run of each scene and quantity."""
    lines = ["| scene | quantity | value ± spread | relative spread |", "|---|---|---|---|"]
    for scene in study.scenes:
        for q in study.quantities(scene):
            ref = study.reference(scene, q)
            rel = ref["spread"] / abs(ref["value"])
            lines.append(f"| {scene} | {md_name(q)}{unit(q)} | {with_spread(q, ref)} | {rel:.2%} |")
    return lines


def meshes_table(study):
    """The meshes, their first and highest frequencies and the Δt range run on each."""
    lines = [
        "| mesh | free dofs | f₁ (Hz) | ω_max (rad/s) | Δt run (s) | ω_max·Δt at the smallest Δt |",
        "|---|---|---|---|---|---|",
    ]
    for m in sorted(study.meshes, key=lambda m: (m["element"], m["free_dofs"])):
        dts = sorted({r["dt"] for r in study.rows if r["mesh"] == m["key"]}, reverse=True)
        lines.append(
            f"| {mesh_name(m['key'])} | {m['free_dofs']} | "
            f"{float(m['omega1_rad_s']) / (2 * math.pi):.3f} | {m['omega_max']:.3g} | "
            f"{dts[0]:g} … {dts[-1]:g} | {m['omega_max'] * dts[-1]:.2f} |"
        )
    return lines


def replica_table(study):
    """The window estimate of the spread against perturbed replicas, per setting."""
    lines = [
        "| scene | mesh | Δt | " + " | ".join(md_name(q) for q in SETTLING_Q) + " |",
        "|---|---|---|" + "---|" * len(SETTLING_Q),
    ]

    def setting(r):
        return (r["scene"], (r["element"], int(r["nx"]), int(r["ny"])), float(r["dt"]))

    settings = []
    for r in study.replicas:
        if setting(r) not in settings:
            settings.append(setting(r))
    for key in settings:
        cells = []
        for q in SETTLING_Q:
            r = next(r for r in study.replicas if setting(r) == key and r["quantity"] == q)
            win, rep = float(r["window_spread"]), float(r["replica_std"])
            ratio = f"{rep / win:.2f}" if win > 0 else "–"
            cells.append(f"{number(shown(q, win), 2)} / {number(shown(q, rep), 2)} ({ratio})")
        lines.append(f"| {key[0]} | {mesh_name(key[1])} | {key[2]:g} | " + " | ".join(cells) + " |")
    return lines


def tables(study):
    """The generated tables of statistics.md, by block name."""
    return {
        "cheapest": cheapest_table(study),
        "paper-settings": paper_table(study),
        "settling": settling_table(study),
        "settling-by-mesh": settling_by_mesh_table(study),
        "mesh-convergence": mesh_table(study),
        "reference": reference_table(study),
        "meshes": meshes_table(study),
        "replica-check": replica_table(study),
    }


def write_evidence(study, out):
    """The rule's verdicts (statistics_verdicts.csv, statistics_ladders.csv) and where every scene,
    quantity and mesh stays within its noise (statistics_within_noise.csv: the Δt, empty where
    even the two smallest disagree, and ω_max·Δt there)."""
    runs = {}
    for r in study.rows:
        runs.setdefault((r["scene"], "", r["quantity"]), []).append(
            evidence.Run(r["element"], r["nx"], r["ny"], r["dt"], r["value"], r["spread"])
        )
    evidence.write(
        out / "statistics_verdicts.csv", {key: evidence.judge(r) for key, r in runs.items()}
    )
    evidence.write_ladders(out / "statistics_ladders.csv", runs)
    with open(out / "statistics_within_noise.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["scene", "quantity", "mesh", "within_noise_dt", "omega_max_dt"])
        for scene in study.scenes:
            for q in study.quantities(scene):
                for mesh in study.mesh_keys:
                    if not study.select(scene, q, mesh):
                        continue
                    r = study.within_noise(scene, q, mesh)
                    name = f"{mesh[0]}:{mesh[1]}x{mesh[2]}"
                    writer.writerow(
                        [
                            scene,
                            q,
                            name,
                            f"{r['dt']:g}" if r else "",
                            f"{r['omega_max_dt']:.6g}" if r else "",
                        ]
                    )


def main():
    """Plots (with their data), the rule's verdicts and the tables of DIR/statistics.md;
    `--tables-only` writes the tables and verdicts alone (the check that the committed ones follow
    from the committed CSVs)."""
    out = Path(sys.argv[1])
    study = Study(out)
    if "--tables-only" not in sys.argv[2:]:
        plots(study, out)
    write_evidence(study, out)
    pages.fill(out / "statistics.md", tables(study), MODULE)


def plots(study, out):
    forced = [s for s in FORCED if s in study.scenes]
    for q in SETTLING_Q:
        if forced:
            work_precision(
                study,
                out,
                forced,
                [q] * len(forced),
                f"statistics_wp_{q}.png",
                f"Work-precision: {md_name(q)}",
            )
    if "energy" in study.scenes:
        work_precision(
            study,
            out,
            ["energy"] * len(ENERGY_Q),
            ENERGY_Q,
            "statistics_wp_energy.png",
            "Work-precision of the energy scene",
        )
        against_omega_dt(
            study, out, [[("energy", q) for q in ENERGY_Q]], "statistics_settling_energy.png"
        )
    if forced:
        against_omega_dt(
            study,
            out,
            [[(s, q) for s in forced] for q in SETTLING_Q],
            "statistics_settling_forced.png",
        )


if __name__ == "__main__":
    main()
