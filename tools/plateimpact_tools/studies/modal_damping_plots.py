"""Plots and the generated part of modal_damping.md, from the CSVs of the modal damping study.

Usage: python -m plateimpact_tools.studies.modal_damping_plots DIR [--quick]. Reads DIR/modal_damping.csv, modal_damping_bands.csv,
modal_damping_meshes.csv, modal_damping_meta.csv and, when present, modal_damping_periods.csv
(`cargo run --release --example modal_damping`); writes DIR/modal_damping_dt.png (each time
average against ω_max·Δt, one line per mesh), DIR/modal_damping_mesh.png (each mesh at its smallest
Δt against its free dofs), DIR/modal_damping_bands.png (the modal energy per band of natural
frequency), DIR/modal_damping_correlation.png (autocorrelation of the per-period series, with
the periods file) and the part of DIR/modal_damping.md between its `generated: modal-damping` markers (the rest of the page is hand-written).

Definitions (σ: a run's spread, the largest of its window, correlation and replica estimates):
- two values *agree to a tolerance* when they differ by at most the tolerance (relative) or by at
  most 2σ of their difference;
- a mesh's *value* is its run at the smallest Δt it ran; it has *settled in Δt* when that run
  agrees with the run at the next larger Δt, or when it did not run two Δt but its Δt is at most
  the largest Δt that every mesh which checked it (ran it and a smaller one) found settled;
- a quantity is *converged* to a tolerance (1 %, else 5 %) for a (scene, ratio) when, on each
  element, the finest mesh has settled in Δt and agrees with the next coarser mesh of its element,
  and the two elements' finest meshes agree, all to that tolerance: the converged value is the
  mean of the two finest, its error bar half their difference plus 2σ;
- the *observed order* in the mesh of an element, from its three finest settled meshes with
  h ∝ (free dofs)^(-1/2): the p with |v₂ − v₁| / |v₃ − v₂| = (h₁^p − h₂^p) / (h₂^p − h₃^p), when
  the differences shrink.
"""

import csv
import math
import sys
from collections import defaultdict
from pathlib import Path

from plateimpact_tools.plotting import pyplot, save

SCENES = ["forced-35hz", "forced-60hz", "aluminium-square"]
SCENE_TITLES = {
    "forced-35hz": "paper's plate, 35 Hz, c = 9 mm",
    "forced-60hz": "paper's plate, 60 Hz, c = 2 mm",
    "aluminium-square": "aluminium square, 40 Hz, c = 4 mm",
}
QUANTITIES = {
    "mean_energy_J": ("mean energy.total", "J", 1.0),
    "rms_corner_m": ("RMS free corner", "mm", 1e3),
    "mean_abs_base_force_N": ("mean |base.force|", "kN", 1e-3),
    "rms_base_force_N": ("RMS base.force", "kN", 1e-3),
    "impacts_per_period": ("impacts per period", "", 1.0),
    "contact_loss_per_period_J": ("energy removed at the obstacles per period", "J", 1.0),
    "modal_share_above_1khz": ("share of the modal energy above 1 kHz", "%", 100.0),
    "modal_share_above_10khz": ("share of the modal energy above 10 kHz", "%", 100.0),
}
TIME_AVERAGES = ["mean_energy_J", "rms_corner_m", "mean_abs_base_force_N", "rms_base_force_N"]
TOLERANCE = 0.01
LOOSE_TOLERANCE = 0.05
BEGIN = ("<!-- generated: modal-damping (python -m plateimpact_tools.studies.modal_damping_plots; "
         "do not edit) -->")
END = "<!-- end generated: modal-damping -->"


def md(text):
    """Text for a Markdown table cell: its bars escaped."""
    return text.replace("|", "\\|")


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def load(out):
    """Rows of the statistics keyed by (scene, ratio, quantity) → {mesh: [rows by Δt]}."""
    rows = read(out / "modal_damping.csv")
    table = defaultdict(lambda: defaultdict(list))
    for r in rows:
        for k in ("modal_ratio", "dt", "omega_max_dt", "value", "spread", "cpu_s", "step_us",
                  "window_spread", "correlation_spread", "replica_spread", "tau_periods",
                  "set_up_cpu_s"):
            r[k] = float(r[k])
        for k in ("nx", "ny", "free_dofs", "periods", "window_periods", "windows", "replicas"):
            r[k] = int(r[k])
        r["mesh"] = (r["element"], r["nx"], r["ny"])
        table[(r["scene"], r["modal_ratio"], r["quantity"])][r["mesh"]].append(r)
    for by_mesh in table.values():
        for runs in by_mesh.values():
            runs.sort(key=lambda r: -r["dt"])
    return rows, table


def mesh_name(mesh):
    element, nx, ny = mesh
    return f"{'Argyris' if element == 'argyris' else 'FVS'} {nx}×{ny}"


def agree(a, b, tolerance=TOLERANCE):
    difference = abs(a["value"] - b["value"])
    return (difference <= tolerance * abs(b["value"])
            or difference <= 2 * math.hypot(a["spread"], b["spread"]))


def fmt(value, quantity):
    _, unit, scale = QUANTITIES[quantity]
    v = value * scale
    return f"{v:.4g}"


def with_spread(r, quantity):
    _, _, scale = QUANTITIES[quantity]
    return f"{r['value'] * scale:.4g} ± {r['spread'] * scale:.2g}"


def element_meshes(by_mesh, element):
    """The meshes of an element, coarse to fine."""
    return sorted((m for m in by_mesh if m[0] == element), key=lambda m: by_mesh[m][0]["free_dofs"])


def checked_dt(by_mesh, tolerance=TOLERANCE):
    """The largest Δt that every mesh which also ran a smaller Δt found settled: its run at that Δt
    agrees (1 %) with its run at the next smaller one. None when no mesh checked any."""
    dts = sorted({r["dt"] for runs in by_mesh.values() for r in runs}, reverse=True)
    for dt in dts:
        checks = []
        for runs in by_mesh.values():
            at = [i for i, r in enumerate(runs) if r["dt"] == dt]
            if at and at[0] + 1 < len(runs):
                checks.append(agree(runs[at[0]], runs[at[0] + 1], tolerance))
        if checks and all(checks):
            return dt
    return None


def finest_settled(by_mesh, mesh, tolerance=TOLERANCE):
    """(run at the smallest Δt, how it has settled in Δt: "yes" when it agrees with the run at the
    next larger Δt, "others" when it did not run two Δt that agree but its Δt is at most the one
    the other meshes found settled, "" otherwise)."""
    runs = by_mesh[mesh]
    last = runs[-1]
    if len(runs) >= 2 and agree(runs[-2], last, tolerance):
        return last, "yes"
    dt = checked_dt(by_mesh, tolerance)
    if dt is not None and last["dt"] <= dt:
        return last, "others"
    return last, ""
def observed_order(values, hs):
    """p from three values on meshes of sizes hs (coarse to fine), or None."""
    d1, d2 = abs(values[1] - values[0]), abs(values[2] - values[1])
    if d2 == 0 or d1 <= d2:
        return None
    target = d1 / d2

    def ratio(p):
        return (hs[0] ** p - hs[1] ** p) / (hs[1] ** p - hs[2] ** p)

    lo, hi = 0.01, 20.0
    if not ratio(lo) <= target <= ratio(hi):
        return None
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


def verdict(by_mesh, quantity, tolerance=TOLERANCE):
    """The converged value and error bar (to `tolerance`), or None, and the text of the finding."""
    finest = {}
    notes = []
    for element in ("argyris", "fvs"):
        meshes = element_meshes(by_mesh, element)
        if not meshes:
            return None, "no runs"
        last, settled = finest_settled(by_mesh, meshes[-1], tolerance)
        finest[element] = last
        if not settled:
            notes.append(f"{mesh_name(meshes[-1])} not settled in Δt at {last['dt']:g} s")
        if len(meshes) >= 2:
            previous, _ = finest_settled(by_mesh, meshes[-2], tolerance)
            if not agree(previous, last, tolerance):
                change = (last["value"] - previous["value"]) / previous["value"]
                notes.append(f"{mesh_name(meshes[-2])} → {mesh_name(meshes[-1])}: {change:+.1%}")
    a, f = finest["argyris"], finest["fvs"]
    if not agree(a, f, tolerance):
        notes.append(f"{mesh_name(a['mesh'])} vs {mesh_name(f['mesh'])}: "
                     f"{(f['value'] - a['value']) / a['value']:+.1%}")
    if notes:
        return None, "not converged: " + "; ".join(notes)
    value = 0.5 * (a["value"] + f["value"])
    bar = 0.5 * abs(a["value"] - f["value"]) + 2 * max(a["spread"], f["spread"])
    return (value, bar), f"converged ({tolerance:.0%})"


def orders(by_mesh):
    found = []
    for element in ("argyris", "fvs"):
        meshes = element_meshes(by_mesh, element)[-3:]
        if len(meshes) < 3:
            continue
        runs = [finest_settled(by_mesh, m) for m in meshes]
        if not all(settled for _, settled in runs):
            continue
        values = [r["value"] for r, _ in runs]
        hs = [r["free_dofs"] ** -0.5 for r, _ in runs]
        p = observed_order(values, hs)
        found.append(f"{element} {p:.1f}" if p is not None else f"{element} –")
    return ", ".join(found) if found else "–"


def convergence_tables(table, scenes, zetas):
    lines = []
    for scene in scenes:
        lines += [f"### {SCENE_TITLES.get(scene, scene)} (`{scene}`)", ""]
        for zeta in zetas:
            if (scene, zeta, "mean_energy_J") not in table:
                continue
            meshes = sorted(table[(scene, zeta, "mean_energy_J")],
                            key=lambda m: (m[0], table[(scene, zeta, "mean_energy_J")][m][0]["free_dofs"]))
            lines += [f"#### ζ = {zeta:g}", "",
                      "Each mesh at its smallest Δt (value ± spread); ‡ where that Δt was not checked "
                      "on this mesh but is one the other meshes found settled (see *Settling in Δt*), "
                      "† where the run has not settled.", "",
                      "| quantity | " + " | ".join(mesh_name(m) for m in meshes)
                      + " | finding | observed order in h |",
                      "|---|" + "---|" * (len(meshes) + 2)]
            for quantity in QUANTITIES:
                by_mesh = table.get((scene, zeta, quantity))
                if not by_mesh:
                    continue
                cells = []
                for m in meshes:
                    last, settled = finest_settled(by_mesh, m)
                    mark = {"yes": "", "others": " ‡"}.get(settled, " †")
                    cells.append(f"{with_spread(last, quantity)}{mark} ({last['dt']:g} s)")
                result, text = verdict(by_mesh, quantity)
                if not result:
                    loose, loose_text = verdict(by_mesh, quantity, LOOSE_TOLERANCE)
                    if loose:
                        result, text = loose, loose_text
                if result:
                    _, _, scale = QUANTITIES[quantity]
                    text = f"{text}: **{result[0] * scale:.4g} ± {result[1] * scale:.2g}**"
                name, unit, _ = QUANTITIES[quantity]
                label = f"{name} ({unit})" if unit else name
                lines.append(f"| {md(label)} | " + " | ".join(cells) + f" | {text} | {orders(by_mesh)} |")
            lines.append("")
    return lines


def dt_order(runs):
    """The observed order in Δt from a mesh's three smallest Δt (ratio 10): exact when the last
    difference exceeds 2σ, else a lower bound from 2σ (written ≥); None without three runs or
    when the first difference is itself within 2σ."""
    if len(runs) < 3:
        return None
    a, b, c = runs[-3:]
    ratio = a["dt"] / b["dt"]
    d1, d2 = abs(b["value"] - a["value"]), abs(c["value"] - b["value"])
    noise1 = 2 * math.hypot(a["spread"], b["spread"])
    noise2 = 2 * math.hypot(b["spread"], c["spread"])
    if d1 <= noise1:
        return None
    if d2 > noise2:
        return f"{math.log(d1 / d2) / math.log(ratio):.1f}"
    return f"≥ {math.log(d1 / noise2) / math.log(ratio):.1f}"


def dt_table(table, scenes, zetas):
    """Each mesh's mean energy and RMS base force at every Δt it ran, where it settled."""
    dts = sorted({r["dt"] for by_mesh in table.values() for runs in by_mesh.values() for r in runs},
                 reverse=True)
    lines = []
    for quantity in ("mean_energy_J", "rms_base_force_N"):
        name, unit, scale = QUANTITIES[quantity]
        lines += [f"{name} ({unit}) at each Δt; *settled from*: the largest Δt from which every "
                  "smaller Δt agrees (1 %) with it; order: observed order in Δt from the three "
                  "smallest.", "",
                  "| scene | ζ | mesh | " + " | ".join(f"{dt:g} s" for dt in dts)
                  + " | settled from (ω_max·Δt) | order |",
                  "|---|---|---|" + "---|" * (len(dts) + 2)]
        for scene in scenes:
            for zeta in zetas:
                by_mesh = table.get((scene, zeta, quantity), {})
                for element in ("argyris", "fvs"):
                    for mesh in element_meshes(by_mesh, element):
                        runs = by_mesh[mesh]
                        at = {r["dt"]: r for r in runs}
                        cells = [f"{at[dt]['value'] * scale:.4g}" if dt in at else "" for dt in dts]
                        settled = [r for i, r in enumerate(runs)
                                   if all(agree(later, r) for later in runs[i + 1:])]
                        first = settled[0] if len(runs) >= 2 and settled[0] is not runs[-1] else None
                        where = (f"{first['dt']:g} s ({first['omega_max_dt']:.3g})" if first
                                 else "no")
                        lines.append(f"| {scene} | {zeta:g} | {mesh_name(mesh)} | "
                                     + " | ".join(cells) + f" | {where} | {dt_order(runs) or '–'} |")
        lines.append("")
    return lines


def correlation_table(rows):
    """τ per scene, ratio and quantity: the median and largest over the runs, in periods."""
    taus = defaultdict(list)
    spreads = defaultdict(list)
    for r in rows:
        if r["quantity"] in TIME_AVERAGES + ["impacts_per_period"]:
            taus[(r["scene"], r["modal_ratio"], r["quantity"])].append(r["tau_periods"])
            if r["replicas"] >= 2 and r["window_spread"] > 0:
                spreads[(r["scene"], r["modal_ratio"], r["quantity"])].append(
                    (r["window_spread"], r["correlation_spread"], r["replica_spread"], r["replicas"]))
    lines = ["| scene | ζ | quantity | τ median (periods) | τ largest | window (periods) | "
             "replica / window spread |", "|---|---|---|---|---|---|---|"]
    windows = {(r["scene"]): r["window_periods"] for r in rows}
    for key in sorted(taus):
        scene, zeta, quantity = key
        values = sorted(taus[key])
        median = values[len(values) // 2]
        ratio = ", ".join(f"{rep / win:.2f} ({n})" for win, _, rep, n in spreads.get(key, []))
        lines.append(f"| {scene} | {zeta:g} | {md(QUANTITIES[quantity][0])} | {median:.2f} | "
                     f"{values[-1]:.2f} | {windows[scene]} | {ratio or '–'} |")
    return lines


def band_table(bands, scenes, zetas):
    lines = ["| scene | ζ | mesh | Δt (s) | share above 1 kHz | above 10 kHz | above 100 kHz |",
             "|---|---|---|---|---|---|---|"]
    for scene in scenes:
        for zeta in zetas:
            for mesh, dt, by_band in finest_bands(bands, scene, zeta):
                share = lambda low: sum(s for (lo, s) in by_band if lo >= low)  # noqa: E731
                lines.append(f"| {scene} | {zeta:g} | {mesh_name(mesh)} | {dt:g} | "
                             f"{share(1e3):.1%} | {share(1e4):.2%} | {share(1e5):.3%} |")
    return lines


def finest_bands(bands, scene, zeta):
    """Per mesh (coarse to fine, by element): its smallest Δt's [(band low edge, share)]."""
    by_mesh = defaultdict(lambda: defaultdict(list))
    for b in bands:
        if b["scene"] == scene and float(b["modal_ratio"]) == zeta:
            mesh = (b["element"], int(b["nx"]), int(b["ny"]))
            by_mesh[mesh][float(b["dt"])].append((float(b["band_low_hz"]), float(b["share"])))
    result = []
    for mesh in sorted(by_mesh, key=lambda m: (m[0], m[1] * m[2])):
        dt = min(by_mesh[mesh])
        result.append((mesh, dt, sorted(by_mesh[mesh][dt])))
    return result


def plot_dt(table, scenes, zetas, out):
    quantities = TIME_AVERAGES + ["impacts_per_period", "modal_share_above_1khz"]
    fig, axes = pyplot().subplots(len(quantities), len(scenes) * len(zetas),
                             figsize=(3.2 * len(scenes) * len(zetas), 2.4 * len(quantities)),
                             squeeze=False)
    for row, quantity in enumerate(quantities):
        name, unit, scale = QUANTITIES[quantity]
        for col, (scene, zeta) in enumerate((s, z) for s in scenes for z in zetas):
            ax = axes[row][col]
            by_mesh = table.get((scene, zeta, quantity), {})
            for mesh, runs in sorted(by_mesh.items(), key=lambda kv: (kv[0][0], kv[1][0]["free_dofs"])):
                ax.errorbar([r["omega_max_dt"] for r in runs], [r["value"] * scale for r in runs],
                            yerr=[2 * r["spread"] * scale for r in runs],
                            marker="o" if mesh[0] == "argyris" else "s", ms=3, capsize=2,
                            ls="-" if mesh[0] == "argyris" else "--", label=mesh_name(mesh))
            ax.set_xscale("log")
            if row == 0:
                ax.set_title(f"{scene}, ζ = {zeta:g}", fontsize=8)
            if col == 0:
                ax.set_ylabel(f"{name} ({unit})" if unit else name, fontsize=7)
            if row == len(quantities) - 1:
                ax.set_xlabel("ω_max·Δt")
            ax.tick_params(labelsize=6)
            if row == 0 and col == 0:
                ax.legend(fontsize=5)
    save(fig, out / "modal_damping_dt.png", dpi=90)


def plot_mesh(table, scenes, zetas, out):
    quantities = TIME_AVERAGES + ["modal_share_above_1khz"]
    fig, axes = pyplot().subplots(len(scenes), len(quantities), figsize=(3.4 * len(quantities),
                                                                   2.8 * len(scenes)), squeeze=False)
    for row, scene in enumerate(scenes):
        for col, quantity in enumerate(quantities):
            name, unit, scale = QUANTITIES[quantity]
            ax = axes[row][col]
            for zeta in zetas:
                by_mesh = table.get((scene, zeta, quantity), {})
                for element, marker in (("argyris", "o"), ("fvs", "s")):
                    meshes = element_meshes(by_mesh, element)
                    runs = [by_mesh[m][-1] for m in meshes]
                    if runs:
                        ax.errorbar([r["free_dofs"] for r in runs], [r["value"] * scale for r in runs],
                                    yerr=[2 * r["spread"] * scale for r in runs], marker=marker,
                                    ms=3, capsize=2, ls="-" if element == "argyris" else "--",
                                    label=f"ζ = {zeta:g}, {element}")
            ax.set_xscale("log")
            ax.set_title(f"{scene}: {name}", fontsize=8)
            ax.set_xlabel("free dofs", fontsize=7)
            if unit:
                ax.set_ylabel(unit, fontsize=7)
            ax.tick_params(labelsize=6)
            if row == 0 and col == 0:
                ax.legend(fontsize=5)
    save(fig, out / "modal_damping_mesh.png", dpi=90)


def plot_bands(bands, scenes, zetas, out):
    fig, axes = pyplot().subplots(len(zetas), len(scenes), figsize=(4.2 * len(scenes), 3.0 * len(zetas)),
                             squeeze=False)
    for row, zeta in enumerate(zetas):
        for col, scene in enumerate(scenes):
            ax = axes[row][col]
            for mesh, dt, by_band in finest_bands(bands, scene, zeta):
                lows = [max(lo, 30.0) for lo, _ in by_band]
                ax.step(lows, [max(s, 1e-9) for _, s in by_band], where="post",
                        ls="-" if mesh[0] == "argyris" else "--",
                        label=f"{mesh_name(mesh)}, {dt:g} s")
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.set_ylim(1e-7, 1.5)
            ax.set_title(f"{scene}, ζ = {zeta:g}", fontsize=8)
            ax.set_xlabel("band of natural frequency, lower edge (Hz)", fontsize=7)
            ax.set_ylabel("share of the modal energy", fontsize=7)
            ax.tick_params(labelsize=6)
            if ax.get_lines():
                ax.legend(fontsize=5)
            else:  # a (scene, ratio) the study did not run
                ax.text(0.5, 0.5, "not run", transform=ax.transAxes, ha="center", fontsize=8)
    save(fig, out / "modal_damping_bands.png", dpi=90)


def autocorrelation(xs, lags):
    n = len(xs)
    mean = sum(xs) / n
    c = [x - mean for x in xs]
    var = sum(x * x for x in c) / n
    if var == 0:
        return [1.0] + [0.0] * lags
    return [sum(c[i] * c[i + t] for i in range(n - t)) / n / var for t in range(lags + 1)]


def plot_correlation(out, transient_s):
    path = out / "modal_damping_periods.csv"
    if not path.exists():
        return False
    series = defaultdict(lambda: defaultdict(list))
    frequency = {"forced-35hz": 35.0, "forced-60hz": 60.0, "aluminium-square": 40.0}
    for r in read(path):
        if r["replica"] != "0":
            continue
        key = (r["scene"], float(r["modal_ratio"]), f"{mesh_name((r['element'], r['nx'], r['ny']))}",
               float(r["dt"]))
        if int(r["period"]) >= transient_s * frequency.get(r["scene"], 1.0):
            for q in ("mean_energy_J", "rms_corner_m", "mean_abs_base_force_N"):
                series[key][q].append(float(r[q]))
    quantities = ["mean_energy_J", "rms_corner_m", "mean_abs_base_force_N"]
    fig, axes = pyplot().subplots(1, len(quantities), figsize=(4.2 * len(quantities), 3.0), squeeze=False)
    for col, q in enumerate(quantities):
        ax = axes[0][col]
        for key, by_q in sorted(series.items()):
            rho = autocorrelation(by_q[q], 20)
            ax.plot(range(len(rho)), rho, marker=".", label=f"{key[0]}, ζ = {key[1]:g}, {key[2]}, {key[3]:g} s")
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"per-period {QUANTITIES[q][0]}", fontsize=8)
        ax.set_xlabel("lag (forcing periods)", fontsize=7)
        ax.set_ylabel("autocorrelation", fontsize=7)
        ax.tick_params(labelsize=6)
        if col == 0:
            ax.legend(fontsize=5)
    save(fig, out / "modal_damping_correlation.png", dpi=90)
    return True


def cost_table(rows):
    """CPU µs per step by mesh and Δt (the median over scenes and ratios) and set-up CPU s."""
    steps = defaultdict(list)
    set_up = defaultdict(list)
    dofs = {}
    for r in rows:
        if r["quantity"] == "mean_energy_J":
            steps[(r["mesh"], r["dt"])].append(r["step_us"])
            set_up[r["mesh"]].append(r["set_up_cpu_s"])
            dofs[r["mesh"]] = r["free_dofs"]
    dts = sorted({dt for _, dt in steps}, reverse=True)
    lines = ["| mesh | free dofs | set-up (CPU s) | " + " | ".join(f"µs/step at {dt:g} s" for dt in dts)
             + " |", "|---|---|---|" + "---|" * len(dts)]
    for mesh in sorted(set_up, key=lambda m: (m[0], dofs[m])):
        cells = []
        for dt in dts:
            values = sorted(steps.get((mesh, dt), []))
            cells.append(f"{values[len(values) // 2]:.2f}" if values else "")
        s = sorted(set_up[mesh])
        lines.append(f"| {mesh_name(mesh)} | {dofs[mesh]} | {s[len(s) // 2]:.2f} | "
                     + " | ".join(cells) + " |")
    return lines


def main():
    out = Path(sys.argv[1])
    rows, table = load(out)
    meta = {r["key"]: r["value"] for r in read(out / "modal_damping_meta.csv")}
    bands = read(out / "modal_damping_bands.csv")
    scenes = [s for s in SCENES if any(r["scene"] == s for r in rows)]
    zetas = sorted({r["modal_ratio"] for r in rows})
    plot_dt(table, scenes, zetas, out)
    plot_mesh(table, scenes, zetas, out)
    plot_bands(bands, scenes, zetas, out)
    correlation = plot_correlation(out, float(meta.get("transient_s", 1.0)))
    cpu = sum(r["cpu_s"] for r in rows if r["quantity"] == "mean_energy_J")
    runs = sum(1 for r in rows if r["quantity"] == "mean_energy_J")
    # The meta file's commit: one, or those of the processes that ran, separated by ';'.
    commits = ", ".join(c.strip()[:12] for c in meta.get("commit", "?").split(";"))
    lines = [BEGIN, "",
             f"Runs: {runs}, {cpu:.0f} CPU s in all (commit {commits}); "
             f"left out for cost: {meta.get('left_out') or 'none'}.", "",
             "## Convergence, scene by scene", ""]
    lines += convergence_tables(table, scenes, zetas)
    lines += ["## Settling in Δt", ""] + dt_table(table, scenes, zetas)
    lines += ["## Correlation times and windows", ""] + correlation_table(rows) + [""]
    lines += ["## Where the energy sits", "",
              "Share of the modal energy (Σ over modes of ½q̇² + ½ω²q², averaged over the steady "
              "state) above fixed natural frequencies, each mesh at its smallest Δt.", ""]
    lines += band_table(bands, scenes, zetas) + [""]
    lines += ["![modal energy per band](modal_damping_bands.png)", "",
              "![time averages against ω_max·Δt](modal_damping_dt.png)", "",
              "![each mesh at its smallest Δt](modal_damping_mesh.png)", ""]
    if correlation:
        lines += ["![autocorrelation of the per-period values](modal_damping_correlation.png)", ""]
    lines += ["## Cost", ""] + cost_table(rows) + ["", END]
    page = out / "modal_damping.md"
    text = page.read_text() if page.exists() else f"# Modal damping\n\n{BEGIN}\n{END}\n"
    if BEGIN not in text:
        text += f"\n{BEGIN}\n{END}\n"
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1] if END in rest else ""
    page.write_text(head + "\n".join(lines) + tail)


if __name__ == "__main__":
    main()
