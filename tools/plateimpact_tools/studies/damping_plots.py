"""Plots and the generated part of damping.md, from the CSVs of the damping study.

Usage: python -m plateimpact_tools.studies.damping_plots DIR [--quick]. Reads DIR/damping.csv, damping_meshes.csv, damping_meta.csv
(`cargo run --release --example statistics -- --study damping`, which runs this); writes
DIR/damping_wp_<quantity>.png, DIR/damping_contact_loss.png and the part of DIR/damping.md between
the markers GENERATED_BEGIN and GENERATED_END (the rest of the page is hand-written).

Each (scene, damping model) pair is a scene of `statistics_plots`, whose definitions this
reuses (agree, reference, error, reaches, settled in Δt). In addition:
- the reference (Argyris 14 × 10 at its smallest Δt) is *converged to a tolerance* when the
  Argyris 14 × 10 run at the next larger Δt and the FVS 14 × 10 run at the reference's Δt are both
  within it (error + uncertainty ≤ tolerance): converged in Δt and, by an independent element, in
  the mesh;
- a quantity has *settled in Δt to a tolerance* on a mesh from the largest Δt from which every
  run on that mesh is within the tolerance of its smallest-Δt run;
- a quantity has *settled in the mesh to a tolerance* from the coarsest Argyris mesh from which
  every finer Argyris mesh, at the smallest Δt they all ran, is within the tolerance of the
  14 × 10 run at that Δt.
"""

import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from plateimpact_tools.studies import statistics_plots as sp  # noqa: E402

SCENES = ["forced-35hz", "forced-60hz"]
SCENE_SHORT = {"forced-35hz": "35 Hz, c = 9 mm", "forced-60hz": "60 Hz, c = 2 mm"}
MODELS = ["none", "alpha", "beta", "rayleigh-1k", "rayleigh-5k", "rayleigh-20k", "modal"]
MODEL_TITLES = {
    "none": "undamped",
    "alpha": "α only, ζ₁ = 1 %",
    "beta": "β only, ζ₁ = 1 %",
    "rayleigh-1k": "Rayleigh ζ = 1 % at f₁, 1 kHz",
    "rayleigh-5k": "Rayleigh ζ = 1 % at f₁, 5 kHz",
    "rayleigh-20k": "Rayleigh ζ = 1 % at f₁, 20 kHz",
    "modal": "modal ζ_m = 1 %",
}
QUANTITIES = ["mean_energy_J", "rms_corner_m", "mean_abs_base_force_N", "rms_base_force_N",
              "impacts_per_period", "contact_loss_per_period_J"]
FINEST = ("argyris", 14, 10)
FVS_FINEST = ("fvs", 14, 10)
BEGIN = "<!-- GENERATED_BEGIN by plateimpact_tools.studies.damping_plots: do not edit below -->"
END = "<!-- GENERATED_END -->"


def load(out):
    """A statistics_plots.Study whose scenes are the (scene, model) pairs, as 'scene/model'."""
    study = sp.Study.__new__(sp.Study)
    study.rows = sp.read(out / "damping.csv")
    for r in study.rows:
        for k in ("dt", "omega_max_dt", "value", "spread", "wall_s"):
            r[k] = float(r[k])
        r["nx"], r["ny"] = int(r["nx"]), int(r["ny"])
        r["mesh"] = (r["element"], r["nx"], r["ny"])
        r["scene"] = f"{r['scene']}/{r['damping']}"
    study.meshes = sp.read(out / "damping_meshes.csv")
    for m in study.meshes:
        m["key"] = (m["element"], int(m["nx"]), int(m["ny"]))
        m["free_dofs"] = int(m["free_dofs"])
        m["omega_max"] = float(m["omega_max_rad_s"])
    study.mesh_keys = [m["key"] for m in sorted(study.meshes,
                                                key=lambda m: (m["element"], m["free_dofs"]))]
    study.meta = {row["key"]: row["value"] for row in sp.read(out / "damping_meta.csv")}
    study.replicas = []
    study.scenes = [f"{s}/{m}" for s in SCENES for m in MODELS
                    if any(r["scene"] == f"{s}/{m}" for r in study.rows)]
    study.reference_mesh = FINEST
    for s in study.scenes:
        scene, model = s.split("/")
        sp.SCENE_TITLES[s] = f"{SCENE_SHORT[scene]}, {MODEL_TITLES[model]}"
    return study


def within(study, r, tolerance):
    return r is not None and sum(study.error(r)) <= tolerance


def reference_status(study, scene, quantity):
    """(Argyris 14 × 10 at the next larger Δt, FVS 14 × 10 at the reference's Δt): the runs that
    test the reference, each None when missing."""
    ref = study.reference(scene, quantity)
    finest = study.select(scene, quantity, FINEST)
    coarser_dt = finest[-2] if len(finest) > 1 else None
    fvs = [r for r in study.select(scene, quantity, FVS_FINEST) if r["dt"] == ref["dt"]]
    return coarser_dt, (fvs[0] if fvs else None)


def dt_settled(study, scene, quantity, mesh, tolerance):
    """The largest Δt from which every run on the mesh is within the tolerance of its
    smallest-Δt run (error + uncertainty against it), or None."""
    runs = study.select(scene, quantity, mesh)
    last = runs[-1]
    start = None
    for r in reversed(runs[:-1]):
        scale = abs(last["value"])
        err = (abs(r["value"] - last["value"]) + 2 * math.hypot(r["spread"], last["spread"])) / scale
        if err > tolerance:
            break
        start = r
    return start


def mesh_settled(study, scene, quantity, tolerance):
    """The coarsest Argyris mesh from which every finer one is within the tolerance of 14 × 10,
    at the smallest Δt all ran, and that Δt; None when the finest alone."""
    argyris = [m for m in study.mesh_keys if m[0] == "argyris"]
    runs = {m: study.select(scene, quantity, m) for m in argyris}
    if any(not r for r in runs.values()):
        return None, None
    dt = max(r[-1]["dt"] for r in runs.values())
    at = {m: next(x for x in runs[m] if x["dt"] == dt) for m in argyris}
    top = at[FINEST]
    start = None
    for m in reversed(argyris[:-1]):
        r = at[m]
        scale = abs(top["value"])
        err = abs(r["value"] - top["value"]) / scale + 2 * math.hypot(r["spread"],
                                                                      top["spread"]) / scale
        if err > tolerance:
            break
        start = m
    return start, dt


def setting(r):
    if r is None:
        return "not reached"
    return f"{sp.mesh_name(r['mesh'])}, Δt = {r['dt']:g} s ({r['wall_s']:.2g} s)"


def rel(study, r, ref):
    if r is None:
        return "–"
    e, u = study.error(r)
    sign = "+" if r["value"] >= ref["value"] else "−"
    return f"{sign}{e:.2%} ± {u:.2%}"


def table(study, scene):
    lines = [
        f"#### {SCENE_SHORT[scene]} (`{scene}`)",
        "",
        "| damping | quantity | reference (Argyris 14 × 10) | same, next larger Δt | FVS 14 × 10 "
        "| settled in Δt (1 %) on Argyris 14 × 10 from | settled in mesh (1 %) from | cheapest 1 % "
        "| cheapest 5 % |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for model in MODELS:
        key = f"{scene}/{model}"
        if key not in study.scenes:
            continue
        for q in QUANTITIES:
            if not study.select(key, q, FINEST):
                continue
            ref = study.reference(key, q)
            coarser, fvs = reference_status(study, key, q)
            settled = dt_settled(study, key, q, FINEST, 0.01)
            mesh_from, mesh_dt = mesh_settled(study, key, q, 0.01)
            cheap = []
            for tol in sp.TOLERANCES:
                ok = within(study, coarser, tol) and within(study, fvs, tol)
                cheap.append(setting(study.cheapest(key, q, tol)) if ok
                             else "no reference to this tolerance")
            lines.append(
                f"| {MODEL_TITLES[model]} | {sp.md_name(q)}{sp.unit(q)} "
                f"| {sp.with_spread(q, ref)} at {ref['dt']:g} s | {rel(study, coarser, ref)} "
                f"| {rel(study, fvs, ref)} "
                f"| {'Δt = ' + format(settled['dt'], 'g') + ' s' if settled else 'no'} "
                f"| {sp.mesh_name(mesh_from) + ' (Δt = ' + format(mesh_dt, 'g') + ' s)' if mesh_from else 'no'} "
                f"| {cheap[0]} | {cheap[1]} |")
    return lines


def contact_loss_table(study, model):
    """Energy removed at the obstacles per period (J): one row per mesh, one column per Δt."""
    q = "contact_loss_per_period_J"
    runs = [r for s in SCENES for r in study.select(f"{s}/{model}", q)]
    steps = sorted({r["dt"] for r in runs}, reverse=True)
    lines = [f"#### Energy removed at the obstacles per period (J), {MODEL_TITLES[model]}", "",
             "| scene | mesh | " + " | ".join(f"Δt = {dt:g} s" for dt in steps) + " |",
             "|---|---|" + "---|" * len(steps)]
    for scene in SCENES:
        for mesh in study.mesh_keys:
            by_dt = {r["dt"]: r for r in study.select(f"{scene}/{model}", q, mesh)}
            if by_dt:
                cells = [sp.number(by_dt[dt]["value"], 4) if dt in by_dt else "" for dt in steps]
                lines.append(f"| {SCENE_SHORT[scene]} | {sp.mesh_name(mesh)} | "
                             + " | ".join(cells) + " |")
    return lines


def contact_loss_plot(study, out):
    """Contact loss per period against Δt, per mesh, one panel per (scene, model)."""
    models = [m for m in ("beta", "rayleigh-1k", "rayleigh-5k", "rayleigh-20k")
              if any(f"{s}/{m}" in study.scenes for s in SCENES)]
    fig, axes = plt.subplots(len(SCENES), len(models), figsize=(4.2 * len(models), 7.6),
                             squeeze=False)
    q = "contact_loss_per_period_J"
    for i, scene in enumerate(SCENES):
        for j, model in enumerate(models):
            ax = axes[i][j]
            key = f"{scene}/{model}"
            for element in ("argyris", "fvs"):
                meshes = [m for m in study.mesh_keys if m[0] == element]
                for k, mesh in enumerate(meshes):
                    runs = study.select(key, q, mesh)
                    if runs:
                        ax.errorbar([r["dt"] for r in runs], [r["value"] for r in runs],
                                    yerr=[2 * r["spread"] for r in runs],
                                    color=sp.COLORS[element], marker=sp.MARKERS[k % 6], ms=4,
                                    lw=0.9, capsize=1.5, label=sp.mesh_name(mesh))
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.invert_xaxis()
            ax.set_xlabel("Δt (s)")
            ax.set_ylabel("contact loss per period (J)")
            ax.set_title(sp.SCENE_TITLES.get(key, key), fontsize=8)
            ax.grid(True, which="major", alpha=0.3)
            ax.legend(fontsize=6, ncol=2)
    fig.suptitle("Energy removed at the obstacles per forcing period against Δt (bars: 2σ)",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "damping_contact_loss.png", dpi=100)
    plt.close(fig)


def main():
    out = Path(sys.argv[1])
    study = load(out)
    for q in QUANTITIES:
        panels = [s for m in MODELS for s in (f"{sc}/{m}" for sc in SCENES) if s in study.scenes
                  and study.select(s, q, FINEST)]
        if panels:
            # 14 panels: a lower resolution keeps each file near 0.5 MB, still legible.
            sp.work_precision(study, out, panels, [q] * len(panels), f"damping_wp_{q}.png",
                              f"Work-precision per damping model: {sp.md_name(q)}", dpi=75)
    contact_loss_plot(study, out)
    generated = [BEGIN, "",
                 f"Runs: {len(study.rows) // len(set(r['quantity'] for r in study.rows))}, "
                 f"{sum(r['wall_s'] for r in study.rows if r['quantity'] == 'mean_energy_J'):.0f} s "
                 "of wall time in all (the sum of the runs' wall times).", ""]
    for scene in SCENES:
        if any(s.startswith(scene + "/") for s in study.scenes):
            generated += table(study, scene) + [""]
    for model in ("beta", "rayleigh-5k"):
        if any(f"{s}/{model}" in study.scenes for s in SCENES):
            generated += contact_loss_table(study, model) + [""]
    generated.append(END)
    page = out / "damping.md"
    text = page.read_text() if page.exists() else f"# Damping study\n\n{BEGIN}\n{END}\n"
    head, _, rest = text.partition(BEGIN)
    _, _, tail = rest.partition(END)
    page.write_text(head + "\n".join(generated) + tail)


if __name__ == "__main__":
    main()
