"""Plots and README of the work-precision study, from the CSVs of `examples/studies/accuracy.rs`.

Usage: python -m plateimpact_tools.studies.accuracy_plots DIR [--quick]. Reads DIR/runs.csv, frequencies.csv, table1.csv, traces.csv,
meta.csv; writes DIR/*.png and DIR/README.md. Run by `cargo run --release --example accuracy`.
"""

import csv
import math
import sys
from collections import defaultdict
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# The paper's Table 1 CPU times (s), 140 elements, 1 s of the forced scene, Matlab quadprog, 2010.
PAPER = {("argyris", 1e-3): 80, ("argyris", 1e-4): 870, ("argyris", 1e-5): 8880,
         ("fvs", 1e-3): 120, ("fvs", 1e-4): 1220, ("fvs", 1e-5): 12220}
COLORS = {"argyris": "tab:blue", "fvs": "tab:red"}
SCENE_TITLES = {
    "free-smooth": "contact-free, smooth base start",
    "free": "contact-free: energy scene, no obstacle",
    "energy": "energy (released onto the lower obstacle)",
    "forced-35hz": "forced, 35 Hz (both obstacles)",
}


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
    return [math.log(y0 / y1) / math.log(x0 / x1) for (x0, y0), (x1, y1) in zip(points, points[1:])
            if y0 > 0 and y1 > 0]


def fmt(x, digits=2):
    return "–" if x is None or (isinstance(x, float) and math.isnan(x)) else f"{x:.{digits}e}"


def main():
    out = Path(sys.argv[1])
    runs = read(out / "runs.csv")
    for r in runs:
        for k in ("h", "dt", "setup_s", "stepping_s", "wall_s", "ref_rms", "ref_max", "dt_rms",
                  "dt_max", "h_rms", "h_max", "energy_end", "energy_rel_err", "diff_vs_fast",
                  "first_contact_s", "pre_rms", "pre_max"):
            r[k] = num(r[k])
        for k in ("nx", "ny", "free_dofs", "steps", "qp_steps"):
            r[k] = int(r[k])
    meta = {row["key"]: row["value"] for row in read(out / "meta.csv")}
    freqs = read(out / "frequencies.csv")
    table1 = read(out / "table1.csv")
    traces = read(out / "traces.csv")
    scenes = [s for s in SCENE_TITLES if any(r["scene"] == s for r in runs)]
    elements = ["argyris", "fvs"]
    fast = [r for r in runs if r["strategy"] == "fast"]
    paper_mesh = {e: tuple(int(v) for v in meta[f"paper_mesh_{e}"].split("x")) for e in elements}
    finest = {e: max({(r["nx"], r["ny"]) for r in fast if r["element"] == e}) for e in elements}
    dt_min = min(r["dt"] for r in fast)
    # Smallest Δt run on every mesh of both elements: the level of the space-error study.
    meshes_of = {e: {(r["nx"], r["ny"]) for r in fast if r["element"] == e} for e in elements}
    dt_h = min(dt for dt in {r["dt"] for r in fast}
               if all({(r["nx"], r["ny"]) for r in fast if r["element"] == e and r["dt"] == dt}
                      == meshes_of[e] for e in elements))

    def family(scene, element, mesh=None, dt=None):
        rows = [r for r in fast if r["scene"] == scene and r["element"] == element
                and r["ref_rms"] > 0  # the reference itself
                and (mesh is None or (r["nx"], r["ny"]) == mesh) and (dt is None or r["dt"] == dt)]
        return rows

    # 1. Reference trajectories.
    t = np.array([float(row["t"]) for row in traces])
    fig, ax = plt.subplots(figsize=(8, 4))
    for s in scenes:
        ax.plot(1e3 * t, 1e3 * np.array([float(row[s]) for row in traces]), label=s)
    ax.axhline(-10, color="k", lw=0.8, ls=":")
    ax.axhline(10, color="k", lw=0.8, ls=":")
    ax.set_xlabel("t (ms)")
    ax.set_ylabel("corner u(Lx, 0) (mm)")
    ax.set_title(f"Reference corner displacement ({meta['reference']})", fontsize=10)
    ax.text(1, -9.5, "obstacles at ±10 mm (forced-35hz); energy has the lower one only", fontsize=7)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "traces.png", dpi=110)
    plt.close(fig)

    # 2. Work-precision: total RMS corner error against wall time.
    fig, axes = plt.subplots(2, 2, figsize=(12, 9), squeeze=False)
    for ax, s in zip(axes.flat, scenes):
        for e in elements:
            rows = family(s, e)
            dts = sorted({r["dt"] for r in rows}, reverse=True)
            # Δt families (mesh varies): solid, for the decades of Δt.
            for dt in dts:
                fam = sorted(family(s, e, dt=dt), key=lambda r: r["free_dofs"])
                decade = abs(math.log10(dt) - round(math.log10(dt))) < 1e-9
                if len(fam) >= 3 and decade:
                    ax.plot([r["wall_s"] for r in fam], [r["ref_rms"] for r in fam], "-o",
                            color=COLORS[e], ms=3, lw=0.9, alpha=0.6)
                    r = fam[-1]
                    ax.annotate(f"Δt={dt:g}", (r["wall_s"], r["ref_rms"]), fontsize=6,
                                color=COLORS[e], xytext=(3, 0), textcoords="offset points")
            # mesh families (Δt varies): dashed, for the paper's mesh and the finest.
            for mesh in (paper_mesh[e], finest[e]):
                fam = sorted(family(s, e, mesh=mesh), key=lambda r: -r["dt"])
                if len(fam) >= 4:
                    ax.plot([r["wall_s"] for r in fam], [r["ref_rms"] for r in fam], "--s",
                            color=COLORS[e], ms=3, lw=0.9)
                    ax.annotate(f"{mesh[0]}×{mesh[1]}", (fam[0]["wall_s"], fam[0]["ref_rms"]),
                                fontsize=7, color=COLORS[e], xytext=(0, 4),
                                textcoords="offset points")
            # The front: lowest error reached within each wall time.
            pts = sorted((r["wall_s"], r["ref_rms"]) for r in rows if r["ref_rms"] > 0)
            front, best = [], math.inf
            for w, err in pts:
                if err < best:
                    front.append((w, err))
                    best = err
            ax.step([p[0] for p in front], [p[1] for p in front], where="post", color=COLORS[e],
                    lw=2.5, alpha=0.5, label=f"{e}: front")
        cl = [r for r in runs if r["strategy"] == "clarabel" and r["scene"] == s]
        for r in cl:
            ax.plot(r["wall_s"], r["ref_rms"], "x", color=COLORS[r["element"]], ms=9, mew=2)
        if cl:
            ax.plot([], [], "kx", label="clarabel every step")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(SCENE_TITLES[s], fontsize=10)
        ax.set_xlabel("wall time of the run (s)")
        ax.set_ylabel("RMS corner error vs reference (m)")
        ax.grid(True, which="major", alpha=0.3)
        ax.legend(fontsize=7, loc="lower left")
    for ax in list(axes.flat)[len(scenes):]:
        ax.axis("off")
    fig.suptitle("Work-precision: solid = fixed Δt, mesh refined; dashed = fixed mesh, Δt refined",
                 fontsize=11)
    fig.tight_layout()
    fig.savefig(out / "work_precision.png", dpi=110)
    plt.close(fig)

    # 3. Time error alone against Δt (paper mesh and finest mesh).
    fig, axes = plt.subplots(1, len(scenes), figsize=(4 * len(scenes), 4), squeeze=False)
    dt_orders = []
    for ax, s in zip(axes[0], scenes):
        for e in elements:
            for mesh, style in ((paper_mesh[e], "-o"), (finest[e], ":s")):
                fam = sorted([r for r in family(s, e, mesh=mesh) if r["dt_rms"] is not None],
                             key=lambda r: -r["dt"])
                if len(fam) < 2:
                    continue
                pts = [(r["dt"], r["dt_rms"]) for r in fam]
                ax.loglog(*zip(*pts), style, color=COLORS[e], ms=3, label=f"{e} {mesh[0]}×{mesh[1]}")
                # Fit over the levels at least 4× the finest Δt of the family (its own reference).
                ref_dt = min(r["dt"] for r in fast if r["scene"] == s and r["element"] == e
                             and (r["nx"], r["ny"]) == mesh)
                fitted = [p for p in pts if p[0] >= 4 * ref_dt]
                dt_orders.append((s, e, mesh, fit(fitted), local_orders(pts), pts))
        x = np.array([1e-3, 1e-5])
        ax.loglog(x, 1e-3 * (x / 1e-3) ** 2, "k:", lw=0.8, label="slope 2")
        ax.set_title(SCENE_TITLES[s], fontsize=9)
        ax.set_xlabel("Δt (s)")
        ax.set_ylabel("RMS corner error vs same mesh, finest Δt (m)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "convergence_dt.png", dpi=110)
    plt.close(fig)

    # 4. Space error alone against h at the finest Δt, and natural frequencies against h.
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    h_orders = []
    for s in scenes:
        for e in elements:
            fam = sorted([r for r in family(s, e, dt=dt_h) if r["h_rms"] is not None],
                         key=lambda r: -r["h"])
            if len(fam) < 2:
                continue
            pts = [(r["h"], r["h_rms"]) for r in fam]
            axes[0].loglog(*zip(*pts), marker="o", color=COLORS[e], ms=3,
                           ls={"free-smooth": "-", "free": "--", "energy": "-.",
                               "forced-35hz": ":"}[s], label=f"{e}, {s}")
            h_orders.append((s, e, fit(pts), local_orders(pts), pts))
    axes[0].set_xlabel("h = Lx / nx (m)")
    axes[0].set_ylabel(f"RMS corner error vs finest mesh, Δt = {dt_h:g} s (m)")
    axes[0].legend(fontsize=7)
    freq_orders = []
    by = defaultdict(list)
    for row in freqs:
        by[(row["element"], int(row["mode"]))].append(
            (float(row["h"]), abs(float(row["frequency_hz"]) / float(row["reference_hz"]) - 1)))
    for (e, mode), pts in sorted(by.items()):
        pts.sort(reverse=True)
        axes[1].loglog(*zip(*pts), "-o", color=COLORS[e], ms=3, alpha=1 - 0.12 * (mode - 1),
                       label=f"{e}" if mode == 1 else None)
        axes[1].annotate(str(mode), pts[-1], fontsize=7, color=COLORS[e])
        freq_orders.append((e, mode, fit(pts), pts))
    axes[1].set_xlabel("h = Lx / nx (m)")
    axes[1].set_ylabel("|f / f_ref − 1|, modes 1–6 (labelled)")
    axes[1].set_title("natural frequencies vs docs/elements.md §7", fontsize=9)
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "convergence_h.png", dpi=110)
    plt.close(fig)

    write_readme(out, meta, runs, fast, scenes, dt_orders, h_orders, freq_orders, freqs, table1,
                 paper_mesh, finest, dt_min, dt_h)


def write_readme(out, meta, runs, fast, scenes, dt_orders, h_orders, freq_orders, freqs, table1,
                 paper_mesh, finest, dt_min, dt_h):
    L = []
    w = L.append
    w("# Work-precision study of PlateImpact\n")
    w("Generated by `cargo run --release --example accuracy` (code: `examples/studies/accuracy.rs`, "
      "`tools/plateimpact_tools/studies/accuracy_plots.py`); every number below is read from the CSVs in this directory. "
      "Do not edit by hand.\n")
    w(f"- {len(runs)} runs of {meta['horizon']} s each ({sum(r['strategy'] == 'clarabel' for r in runs)} "
      f"with clarabel on every step), run one after the other in one process on a 2-core x86_64 development machine; "
      f"the whole study took {float(meta['total_s']):.0f} s. Wall time = `Stepper::new` (assembly, "
      "dense eigenbasis, initial state) + the step loop, measured with `std::time::Instant`.")
    w(f"- Scenes: {', '.join('`' + s + '` (' + SCENE_TITLES[s] + ')' for s in scenes)}.")
    sweep = (f"; also {meta['dt_sweep']} s on the paper's meshes and the finest"
             if meta["dt_sweep"].strip() else "")
    w(f"- Meshes: Argyris {', '.join(meta['meshes_argyris'].split())}; "
      f"FVS {', '.join(meta['meshes_fvs'].split())}; the paper's 140-element meshes are "
      f"{paper_mesh['argyris'][0]}×{paper_mesh['argyris'][1]} Argyris (2 triangles per cell) and "
      f"{paper_mesh['fvs'][0]}×{paper_mesh['fvs'][1]} FVS. Δt on every mesh: {meta['dt_grid']} s"
      f"{sweep}.")
    w(f"- Horizon {meta['horizon']} s, long enough for several impacts; contact episodes on the "
      f"reference (a vertex touching after a step with none in contact): {meta['impacts']}.")
    w("- Corner error: u(Lx, 0, t) on a common grid of 1e-4 s (runs with Δt > 1e-4 s linearly "
      "interpolated between their steps, an O(Δt²) reconstruction), RMS and max over the horizon. "
      "`ref_*`: against the scene's reference; `dt_*`: against the same mesh at its finest Δt "
      "(time error alone); `h_*`: against the same element's finest mesh at the same Δt (space "
      "error alone). Energy: relative difference of the discrete energy at the end.\n")
    w("Files: `runs.csv` (every run), `frequencies.csv`, `table1.csv`, `traces.csv`, "
      "`meta.csv`; plots `work_precision.png`, `convergence_dt.png`, `convergence_h.png`, "
      "`traces.png`.\n")

    w("## Reference and its self-convergence check\n")
    w(f"Reference of each scene: {meta['reference']}. Argyris is the more accurate element per dof "
      "(frequencies below), so its finest mesh at the smallest Δt is the best solution we have. "
      "How far the reference itself is from the converged solution, per scene (RMS / max of the "
      "corner over the horizon):\n")
    w("| scene | time: reference vs next larger Δt (m) | space: vs Argyris " + meta["check_mesh"]
      + " at the same Δt (m) | other element: finest FVS vs reference (m) |")
    w("|---|---|---|---|")
    checks = {row["scene"]: row for row in read(out / "reference_check.csv")}
    for s in scenes:
        c = checks.get(s)
        if c is None:
            continue
        w(f"| {s} | {fmt(num(c['time_rms']))} / {fmt(num(c['time_max']))} (Δt = {c['time_dt']}) | "
          f"{fmt(num(c['space_rms']))} / {fmt(num(c['space_max']))} | "
          f"{fmt(num(c['fvs_rms']))} / {fmt(num(c['fvs_max']))} |")
    w("\nWith order p in Δt and a step ratio q, the reference's own time error is about that "
      "difference / (q^p − 1); "
      "errors of runs that come within a few times these numbers of the reference are not "
      "resolved by it.\n")

    w("## Observed orders in Δt (time error alone)\n")
    w("Fitted slope of the RMS corner error against Δt over the levels ≥ 4× the family's finest Δt "
      "(its own reference), and the local orders between successive levels (Δt decreasing).\n")
    w("| scene | element | mesh | fitted order | local orders | error at Δt = 1e-3 → smallest fitted (m) |")
    w("|---|---|---|---|---|---|")
    for s, e, mesh, order, local, pts in dt_orders:
        fitted = [p for p in pts if p[0] >= 4 * min(p[0] for p in pts) / 2]
        w(f"| {s} | {e} | {mesh[0]}×{mesh[1]} | {order:.2f} | "
          f"{' '.join(f'{o:.1f}' for o in local)} | {fmt(pts[0][1])} → {fmt(fitted[-1][1])} |")
    w("")
    impact_scenes = [s for s in scenes if any(r["first_contact_s"] for r in fast if r["scene"] == s)]
    if impact_scenes:
        w("### Up to the first impact\n")
        w("Time of the first step with a vertex in contact, and the RMS corner error against the "
          "reference over [0, the reference's first contact], on the paper's meshes.\n")
        head = " | ".join(f"{s} {e}: first contact (ms), error (m)" for s in impact_scenes
                          for e in ("argyris", "fvs"))
        w(f"| Δt | {head} |")
        w("|---|" + "---|" * (2 * len(impact_scenes)))
        for dt in sorted({r["dt"] for r in fast}, reverse=True):
            cells = []
            for s in impact_scenes:
                for e in ("argyris", "fvs"):
                    r = next((r for r in fast if r["scene"] == s and r["element"] == e and
                              (r["nx"], r["ny"]) == paper_mesh[e] and r["dt"] == dt), None)
                    cells.append("–" if r is None or r["first_contact_s"] is None else
                                 f"{1e3 * r['first_contact_s']:.3f}, {fmt(r['pre_rms'])}")
            w(f"| {dt:g} | " + " | ".join(cells) + " |")
        w("")
    w(f"## Observed orders in h (space error alone, Δt = {dt_h:g} s)\n")
    w("| scene | element | fitted order | local orders | error, coarsest → second finest (m) |")
    w("|---|---|---|---|---|")
    for s, e, order, local, pts in h_orders:
        w(f"| {s} | {e} | {order:.2f} | {' '.join(f'{o:.1f}' for o in local)} | "
          f"{fmt(pts[0][1])} → {fmt(pts[-1][1])} |")
    w("\nNatural frequencies against the converged values of [docs/elements.md](../elements.md) §7 "
      "(53.821, 231.63, 335.41, 753.91, 941.26, 1447.8 Hz):\n")
    w("| element | mesh | free dofs | " + " | ".join(f"f{k} rel. err" for k in range(1, 7)) + " |")
    w("|---|---|---|" + "---|" * 6)
    rows = defaultdict(dict)
    for row in freqs:
        rows[(row["element"], int(row["nx"]), int(row["ny"]), int(row["free_dofs"]))][int(row["mode"])] = \
            float(row["frequency_hz"]) / float(row["reference_hz"]) - 1
    for (e, nx, ny, n), errs in rows.items():
        w(f"| {e} | {nx}×{ny} | {n} | " + " | ".join(f"{errs[k]:+.1e}" for k in range(1, 7)) + " |")
    w("\n| element | fitted order in h of the frequency error, modes 1–6 |")
    w("|---|---|")
    for e in ("argyris", "fvs"):
        w(f"| {e} | " + ", ".join(f"{o:.1f}" for ee, _, o, _ in freq_orders if ee == e) + " |")
    w("")

    w("## Energy at the end of the horizon\n")
    w("Relative difference of the discrete energy at t = horizon from the reference's, finest Δt "
      "on each mesh and Δt = 1e-3 / 1e-4 / 1e-5 on the paper's meshes.\n")
    w("| scene | element | mesh | Δt | energy (J) | rel. error |")
    w("|---|---|---|---|---|---|")
    for s in scenes:
        for e in ("argyris", "fvs"):
            sel = [r for r in fast if r["scene"] == s and r["element"] == e and
                   ((r["dt"] == dt_min) or ((r["nx"], r["ny"]) == paper_mesh[e] and r["dt"] in (1e-3, 1e-4, 1e-5)))]
            for r in sorted(sel, key=lambda r: (r["free_dofs"], -r["dt"])):
                w(f"| {s} | {e} | {r['nx']}×{r['ny']} | {r['dt']:g} | {r['energy_end']:.5g} | "
                  f"{fmt(r['energy_rel_err'])} |")
    w("")

    w("## The paper's Table 1: 140 elements, 1 s of the `forced` scene (10 Hz)\n")
    w(f"Our wall times (set-up included) beside the paper's CPU times (2010 laptop, Matlab quadprog).\n")
    w("| element | mesh | Δt | steps | steps with a QP | ours, fast path (s) | ours, clarabel every step (s) | paper (s) | paper / ours (fast) |")
    w("|---|---|---|---|---|---|---|---|---|")
    t1 = defaultdict(dict)
    for row in table1:
        t1[(row["element"], row["nx"], row["ny"], float(row["dt"]))][row["strategy"]] = row
    # clarabel per constrained step, from the runs that were made, for the extrapolated entries.
    per_qp_step = {}
    for (e, nx, ny, dt), d in t1.items():
        if "clarabel" in d:
            c = d["clarabel"]
            per_qp_step[e] = float(c["wall_s"]) / max(int(c["qp_steps"]), 1)
    for (e, nx, ny, dt), d in sorted(t1.items(), key=lambda kv: (kv[0][0], -kv[0][3])):
        f, c = d["fast"], d.get("clarabel")
        paper = PAPER.get((e, dt))
        ratio = f"{paper / float(f['wall_s']):.0f}×" if paper else "–"
        if c:
            cl = f"{float(c['wall_s']):.1f}"
        elif e in per_qp_step:
            cl = f"≈ {per_qp_step[e] * int(f['steps']):.0f} (extrapolated, not run)"
        else:
            cl = "–"
        w(f"| {e} | {nx}×{ny} | {dt:g} | {f['steps']} | {f['qp_steps']} | {float(f['wall_s']):.3f} | "
          f"{cl} | {paper if paper else '–'} | {ratio} |")
    w("\nExtrapolated clarabel times: the measured clarabel time per step at Δt = 1e-3 times the "
      "number of steps (with obstacles every step is constrained, so clarabel runs on every step; "
      "the fast path runs a QP only on the steps counted in its column).\n")

    w("## Second strategy: clarabel on every constrained step\n")
    w("Same scene, mesh and Δt as a fast run; the trajectories agree to the `max |diff|` column, "
      "so the error is the same and only the time differs.\n")
    w("| scene | element | mesh | Δt | steps with a QP | max |diff| vs fast (m) | RMS error vs reference (m) | fast (s) | clarabel (s) | ratio |")
    w("|---|---|---|---|---|---|---|---|---|---|")
    for r in runs:
        if r["strategy"] != "clarabel":
            continue
        f = next(x for x in fast if all(x[k] == r[k] for k in ("scene", "element", "nx", "ny", "dt")))
        w(f"| {r['scene']} | {r['element']} | {r['nx']}×{r['ny']} | {r['dt']:g} | {r['qp_steps']} | "
          f"{fmt(r['diff_vs_fast'])} | {fmt(r['ref_rms'])} | {f['wall_s']:.3f} | {r['wall_s']:.2f} | "
          f"{r['wall_s'] / f['wall_s']:.0f}× |")
    w("")

    w("## Plots\n")
    w("![work-precision](work_precision.png)\n")
    w("![time error](convergence_dt.png)\n")
    w("![space error and frequencies](convergence_h.png)\n")
    w("![reference trajectories](traces.png)\n")

    w("## Reading\n")
    w(reading(out, meta, fast, runs, scenes, dt_orders, h_orders, table1, paper_mesh, dt_h, freqs))
    (out / "README.md").write_text("\n".join(L) + "\n")


def plateau(rows, key):
    """(x at which the error first comes within 1.5× of the family's smallest, that smallest)."""
    rows = sorted(rows, key=lambda r: -r[key])
    best = min(r["ref_rms"] for r in rows)
    first = next(r for r in rows if r["ref_rms"] <= 1.5 * best)
    return first, best


def reading(out_dir, meta, fast, runs, scenes, dt_orders, h_orders, table1, paper_mesh, dt_h,
            freqs):
    """The short reading, with its numbers taken from the data."""
    order = {(s, e, m): o for s, e, m, o, _, _ in dt_orders}
    by_mesh = defaultdict(list)
    for row in freqs:
        by_mesh[(row["element"], int(row["free_dofs"]))].append(
            abs(float(row["frequency_hz"]) / float(row["reference_hz"]) - 1))

    fvs_n = max(k[1] for k in by_mesh if k[0] == "fvs")
    arg_n = max((k[1] for k in by_mesh if k[0] == "argyris" and k[1] <= fvs_n),
                default=min(k[1] for k in by_mesh if k[0] == "argyris"))
    per_mode = [f / a if a > 0 else float("nan") for f, a in
                zip(by_mesh[("fvs", fvs_n)], by_mesh[("argyris", arg_n)])]
    ratio_lo, ratio_hi = min(per_mode), max(per_mode)
    comparable = f"Argyris {arg_n} free dofs, FVS {fvs_n}"

    def rng(e, which):
        n = sorted(k[1] for k in by_mesh if k[0] == e)
        errs = by_mesh[(e, n[0] if which == "coarse" else n[-1])]
        return f"{min(errs):.0e}–{max(errs):.0e}"

    horder = {(s, e): o for s, e, o, _, _ in h_orders}
    P = []

    def orders(scene, mesh_of=paper_mesh):
        return " and ".join(f"{order.get((scene, e, mesh_of[e]), float('nan')):.2f} ({e})"
                            for e in ("argyris", "fvs"))

    if "free-smooth" in scenes:
        P.append(
            "**Time, without contact.** The smooth control case (`free-smooth`: base moved by "
            "c(1 − cos 2πft)²/4, so no mode is hit impulsively) is second order in Δt over the whole "
            f"range 1e-3 → 1e-6 s: fitted orders {orders('free-smooth')} on the paper's meshes, the "
            "same on the finest. This is what `--quick` asserts (within 0.2 of 2).")
    if "free" in scenes:
        P.append(
            "The contact-free `energy` scene (`free`) is **not** observed second order: "
            f"{orders('free')}, with local orders wandering between about 1 and 2. Its initial "
            "state, the static deflection under a uniform pressure released at once, excites every "
            "mode of the mesh with an amplitude that falls only like a power of its frequency; each "
            "mode is second order only once ω·Δt ≪ 1, while a bending wave of wavelength about h "
            "already has a frequency of order √(D/ρe)(π/h)²/2π, tens of kHz on these meshes, and "
            "the element-internal modes lie higher still. The corner error is then a sum over "
            "partly resolved modes and shows a fractional order (about 1.4–1.5); `--quick` asserts "
            "only that it stays above 1.2. The smooth case above shows that the scheme itself is "
            "second order when the stiff modes are not excited.")
    checks = {row["scene"]: row for row in read(out_dir / "reference_check.csv")}
    for scene in ("energy", "forced-35hz"):
        if scene not in scenes:
            continue
        rows = {e: sorted([r for r in fast if r["scene"] == scene and r["element"] == e
                           and (r["nx"], r["ny"]) == paper_mesh[e]], key=lambda r: -r["dt"])
                for e in ("argyris", "fvs")}
        a = rows["argyris"]
        c = checks.get(scene, {})
        pre = [r for r in a if r["pre_rms"] is not None]
        pre_floor = plateau([dict(r, ref_rms=r["pre_rms"]) for r in pre], "dt") if pre else None
        decades = [r for r in a if abs(math.log10(r["dt"]) - round(math.log10(r["dt"]))) < 1e-9]
        energies = ", ".join(f"{r['energy_end']:.1f}" for r in decades)
        energy_dts = ", ".join(f"{r['dt']:g}" for r in decades)
        ref = min((r for r in fast if r["scene"] == scene and r["element"] == "argyris"),
                  key=lambda r: (-r["free_dofs"], r["dt"]))
        P.append(
            f"**Time, with impacts (`{scene}`).** No convergence order can honestly be read off the "
            f"whole trajectory: fitted orders in Δt {orders(scene)}, local orders erratic and often "
            f"negative, and the RMS corner error of the paper's meshes stays at "
            f"{min(r['dt_rms'] for r in a if r['dt_rms']):.0e}–{max(r['dt_rms'] for r in a if r['dt_rms']):.0e} m "
            "over three decades of Δt. The reference is not converged either: it differs from the "
            f"same mesh at Δt = {c.get('time_dt', '?')} s by {fmt(num(c.get('time_rms')))} m RMS and "
            f"from the finer Argyris {meta['check_mesh']} mesh by {fmt(num(c.get('space_rms')))} m, as "
            "much as the errors it is meant to measure. After the first impacts every vertex "
            f"touches and leaves the obstacle many times ({ref['impacts']} contact episodes in "
            f"{meta['horizon']} s on the reference, {ref['qp_steps']} steps with a QP), and which vertex touches in which step depends on Δt "
            "and h, so runs that differ in resolution drift apart. What does converge is the motion "
            "up to the first impact: its error falls with Δt (table above) until it reaches the "
            "space error of the mesh"
            + (f" ({pre_floor[1]:.1e} m for Argyris {paper_mesh['argyris'][0]}×"
               f"{paper_mesh['argyris'][1]} from Δt = {pre_floor[0]['dt']:g} s on)"
               if pre_floor and pre_floor[0]["dt"] > min(r["dt"] for r in pre) else
               f" (here it is still falling at the smallest Δt, {pre[-1]['pre_rms']:.1e} m)"
               if pre else "")
            + ", and the first contact time agrees to within a step. The discrete energy at the "
            f"end has not settled either: at Δt = {energy_dts} s it is {energies} J (Argyris "
            f"{paper_mesh['argyris'][0]}×{paper_mesh['argyris'][1]})"
            + ("; with a fixed base the only loss is the β = ½, e = 0 scheme's dissipation at the "
               "impacts, which shrinks with Δt only slowly." if scene == "energy" else
               ", the balance of the base's input and the impacts' dissipation."))
    if h_orders:
        P.append(
            f"**Space.** At Δt = {dt_h:g} s, the RMS corner error against the finest mesh of the same "
            "element falls with fitted orders in h of "
            + "; ".join(f"{s}: {horder.get((s, 'argyris'), float('nan')):.1f} (Argyris), "
                        f"{horder.get((s, 'fvs'), float('nan')):.1f} (FVS)" for s in scenes)
            + ". These are measured against each element's own finest mesh, so the last level is "
            "optimistic; the two elements' finest meshes differ by the amounts in the "
            "self-convergence table. For Argyris these orders are well below what quintic "
            "polynomials give for a smooth solution; we did not investigate why (the singular "
            "behaviour at the clamped–free corners is a likely cause). With impacts the space error "
            "is not monotone, for the same reason as in time. Natural frequencies (relative error, "
            "modes 1–6; the reference values carry 5 significant digits, about 1e-5): "
            + "; ".join(f"{e} {rng(e, 'coarse')} on the coarsest mesh, {rng(e, 'fine')} on the finest"
                        for e in ("argyris", "fvs"))
            + f". At similar dof counts ({comparable}) Argyris is {ratio_lo:.0f}× to {ratio_hi:.0f}× "
            "more accurate depending on the mode; FVS is weakest on modes 2, 4 and 6.")
    cl = [r for r in runs if r["strategy"] == "clarabel"]
    if cl:
        pairs = []
        for r in cl:
            f = next(x for x in fast if all(x[k] == r[k] for k in ("scene", "element", "nx", "ny", "dt")))
            pairs.append((r["wall_s"] / f["wall_s"], r["diff_vs_fast"], r))
        lo, hi = min(p[0] for p in pairs), max(p[0] for p in pairs)
        diff = max(p[1] for p in pairs)
        P.append(
            f"**Fast path against clarabel on every step.** Same trajectories (largest corner "
            f"difference {diff:.1e} m, far below every error in the tables), {lo:.0f}× to {hi:.0f}× "
            "the wall time. With obstacles every step is constrained, so clarabel pays its ~25 ms "
            "on each step, while the fast path proves most steps contact-free by a cheap screening "
            "and solves the contact steps by an exact active-set method.")
    t1 = [row for row in table1 if row["strategy"] == "fast"]
    t1c = [row for row in table1 if row["strategy"] == "clarabel"]
    if t1:
        ratios = [PAPER[(row["element"], float(row["dt"]))] / float(row["wall_s"]) for row in t1
                  if (row["element"], float(row["dt"])) in PAPER]
        cratios = [PAPER[(row["element"], float(row["dt"]))] / float(row["wall_s"]) for row in t1c
                   if (row["element"], float(row["dt"])) in PAPER]
        if ratios:
            P.append(
                ("(Quick run: shortened horizon and smaller meshes, not comparable with the paper.) "
                 if meta.get("quick") == "true" else "") +
                f"**Table 1.** The paper's 140-element runs take {min(float(r['wall_s']) for r in t1):.2f}–"
                f"{max(float(r['wall_s']) for r in t1):.2f} s here with the fast path, "
                f"{min(ratios):.0f}× to {max(ratios):.0f}× less than the paper's 2010 Matlab times. "
                "Most of that is the method, not the hardware: with clarabel on every step, as the "
                "paper did with quadprog, the same runs are only "
                + (f"{min(cratios):.0f}× to {max(cratios):.0f}×" if cratios else "(not run)")
                + " faster than the paper's times (measured at Δt = "
                + ", ".join(sorted({f"{float(r['dt']):g}" for r in t1c})) + " s).")
    # Set-up share and the smallest errors reached.
    parts = []
    for e in ("argyris", "fvs"):
        fam = sorted([r for r in fast if r["scene"] == "free" and r["element"] == e
                      and (r["nx"], r["ny"]) == paper_mesh[e]], key=lambda r: -r["dt"])
        if fam:
            parts.append(f"{e} {paper_mesh[e][0]}×{paper_mesh[e][1]}: "
                         f"{fam[0]['setup_s'] / fam[0]['wall_s']:.0%} at Δt = {fam[0]['dt']:g} s, "
                         f"{fam[-1]['setup_s'] / fam[-1]['wall_s']:.0%} at {fam[-1]['dt']:g} s")
    best = []
    for scene in scenes:
        others = [r for r in fast if r["scene"] == scene and r["ref_rms"] > 0 and
                  not (r["element"] == "argyris" and (r["nx"], r["ny"]) == max(
                      (x["nx"], x["ny"]) for x in fast if x["element"] == "argyris"))]
        if others:
            r = min(others, key=lambda r: r["ref_rms"])
            best.append(f"`{scene}` {r['ref_rms']:.1e} m ({r['element']} {r['nx']}×{r['ny']}, "
                        f"Δt = {r['dt']:g} s, {r['wall_s']:.2f} s)")
    P.append(
        "**Where the effort goes.** Set-up (assembly and the dense eigen-decomposition, which "
        "grows like n³) is the share of the wall time in the contact-free runs: "
        + "; ".join(parts)
        + ". So refining Δt is nearly free until about 1e-5 s, and the work-precision front of "
        "the smooth cases is a fine Δt on a moderate mesh. Smallest RMS corner error against the "
        "reference among runs on other meshes than the reference's: " + "; ".join(best)
        + ". For the impact scenes these numbers are at or below the reference's own "
        "uncertainty: beyond the paper's resolution (140 elements, Δt = 1e-4 to 1e-5 s), refining "
        "buys no measurable accuracy of the corner trajectory over 0.1 s.")
    return "\n\n".join(P) + "\n"


if __name__ == "__main__":
    main()
