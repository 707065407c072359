"""The write step of the damping study: plots and the tables of damping.md, from its CSVs.

Usage: python -m plateimpact_tools.studies.damping_plots DIR [--quick] [--tables-only]. Reads
DIR/damping.csv, damping_meshes.csv, damping_meta.csv
(`cargo run --release -p plate_impact_studies --bin statistics -- --study damping`, which runs
this); writes DIR/damping_wp_<quantity>.png and
DIR/damping_contact_loss.png, beside each the CSV of the data it shows, and the generated tables
of DIR/damping.md (the page is hand-written; `pages.fill`), and the rule's verdicts
(`evidence`): DIR/damping_verdicts.csv (per scene, model, quantity and element) and
DIR/damping_ladders.csv (the rule at every setting).

The model comparison (tables, work-precision plots, contact loss) reads the runs of the plan's
grid and contact-loss parts on the grid's meshes; the finer-reference and threshold parts have a
table each.

Each (scene, damping model) pair is a scene of `statistics_plots`, whose work-precision plots
this reuses. Every verdict is the rule's (`plateimpact_tools.studies.evidence`: a setting is
converged when its Δt ladder and its mesh ladder pass at 1 %, its ± the sum of their bounds),
on every run of the (scene, model), whichever part of the plan ran it. The comparison tables
give each quantity's best-resolved run (Argyris 14 × 10 at its smallest Δt), the same mesh at the
next larger Δt and FVS 14 × 10 at the same Δt against it, the rule's verdict, and where it is
converged the cheapest run within the tolerance of the converged value (its distance plus its
2σ plus the converged value's bound).
"""

import sys
from collections import defaultdict
from pathlib import Path

from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.studies import evidence, pages
from plateimpact_tools.studies import statistics_plots as sp

plt = pyplot()

# The source the generated blocks name.
MODULE = "the damping study's write step"

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
    "beta-half": "β only, ζ₁ = 0.5 %",
}
QUANTITIES = [
    "mean_energy_J",
    "rms_corner_m",
    "mean_abs_base_force_N",
    "rms_base_force_N",
    "impacts_per_period",
    "contact_loss_per_period_J",
]
FINEST = ("argyris", 14, 10)
FVS_FINEST = ("fvs", 14, 10)
# The parts of the plan the model comparison reads (a CSV without parts is all grid).
COMPARED = ("grid", "contact-loss")
# The threshold table: the models, and the forcing and mesh of their Δt series.
THRESHOLD_MODELS = ["beta", "beta-half", "rayleigh-5k", "modal"]
THRESHOLD_AT = ("forced-35hz", ("argyris", 10, 7))
# The finer-reference table: β at 1e-6 s on these meshes.
FINER_MESHES = [
    ("argyris", 10, 7),
    ("argyris", 14, 10),
    ("argyris", 20, 14),
    ("fvs", 14, 10),
    ("fvs", 20, 14),
    ("fvs", 28, 20),
]


def read_rows(out):
    """Every row of damping.csv, numbers parsed, the scene as 'scene/model'."""
    rows = sp.read(out / "damping.csv")
    for r in rows:
        for k in ("dt", "omega_max_dt", "value", "spread", "wall_s"):
            r[k] = float(r[k])
        r["zeta_hf"] = float(r["zeta_hf"]) if r.get("zeta_hf") else None
        r["nx"], r["ny"] = int(r["nx"]), int(r["ny"])
        r["mesh"] = (r["element"], r["nx"], r["ny"])
        r["scene"] = f"{r['scene']}/{r['damping']}"
        r.setdefault("part", "grid")
    return rows


def load(out):
    """A statistics_plots.Study of the compared runs, whose scenes are the (scene, model) pairs,
    as 'scene/model', and `all_rows`, every run."""
    study = sp.Study.__new__(sp.Study)
    study.all_rows = read_rows(out)
    study.rows = [r for r in study.all_rows if r["part"] in COMPARED]
    compared = {r["mesh"] for r in study.rows}
    study.meshes = sp.read(out / "damping_meshes.csv")
    for m in study.meshes:
        m["key"] = (m["element"], int(m["nx"]), int(m["ny"]))
        m["free_dofs"] = int(m["free_dofs"])
        m["omega_max"] = float(m["omega_max_rad_s"])
    study.mesh_keys = [
        m["key"]
        for m in sorted(study.meshes, key=lambda m: (m["element"], m["free_dofs"]))
        if m["key"] in compared
    ]
    study.meta = {row["key"]: row["value"] for row in sp.read(out / "damping_meta.csv")}
    study.replicas = []
    study.scenes = [
        f"{s}/{m}"
        for s in SCENES
        for m in MODELS
        if any(r["scene"] == f"{s}/{m}" for r in study.rows)
    ]
    study.reference_mesh = FINEST
    for s in study.scenes:
        scene, model = s.split("/")
        sp.SCENE_TITLES[s] = f"{SCENE_SHORT[scene]}, {MODEL_TITLES[model]}"
    return study


def reference_status(study, scene, quantity):
    """(Argyris 14 × 10 at the next larger Δt, FVS 14 × 10 at the reference's Δt): the runs that
    test the reference, each None when missing."""
    ref = study.reference(scene, quantity)
    finest = study.select(scene, quantity, FINEST)
    coarser_dt = finest[-2] if len(finest) > 1 else None
    fvs = [r for r in study.select(scene, quantity, FVS_FINEST) if r["dt"] == ref["dt"]]
    return coarser_dt, (fvs[0] if fvs else None)


def study_runs(study):
    """The runs of every (scene/model, quantity) as the rule reads them: every part of the plan."""
    runs = defaultdict(list)
    for r in study.all_rows:
        runs[(r["scene"], r["quantity"])].append(
            evidence.Run(r["element"], r["nx"], r["ny"], r["dt"], r["value"], r["spread"])
        )
    return runs


def verdict_text(v, quantity):
    """The rule's verdict on one quantity, as the tables print it."""
    both = v["both"]
    if both.accepted:
        s = both.setting
        value, bound = sp.shown(quantity, s.run.value), sp.shown(quantity, s.bound)
        return (
            f"converged: {sp.number(value, 5)} ± {sp.number(bound, 2)} "
            f"({100 * bound / abs(value):.2g} %; {sp.mesh_name(s.run.mesh)}, {s.run.dt:g} s)"
        )
    return "not converged"


def verdicts_table(study, verdicts):
    """The rule's verdict on every scene, model and quantity: converged with its value, bound and
    setting, or what failed on each element."""
    lines = [
        "| scene | damping | quantity | the rule (1 %) |",
        "|---|---|---|---|",
    ]
    for scene in SCENES:
        for model in MODELS:
            key = f"{scene}/{model}"
            if key not in study.scenes:
                continue
            for q in QUANTITIES:
                v = verdicts.get((key, q))
                if v is None:
                    continue
                text = verdict_text(v, q)
                if not v["both"].accepted:
                    text += ": " + "; ".join(
                        f"{'Argyris' if e == 'argyris' else 'FVS'}: {v[e].why}"
                        for e in evidence.ELEMENTS
                        if v[e].setting
                    )
                lines.append(
                    f"| {SCENE_SHORT[scene]} | {MODEL_TITLES[model]} | "
                    f"{sp.md_name(q)}{sp.unit(q)} | {text.replace('|', chr(92) + '|')} |"
                )
    return lines


def cheapest_within(study, key, quantity, v, tolerance=evidence.TOLERANCE):
    """The cheapest run (wall time) within `tolerance` of the converged value: its distance plus
    its 2σ plus the converged value's bound; None where the quantity is not converged."""
    both = v["both"]
    if not both.accepted:
        return None
    value, bound = both.value, both.bound
    best = None
    for r in study.select(key, quantity):
        if abs(r["value"] - value) + 2 * r["spread"] + bound <= tolerance * abs(value):
            if best is None or r["wall_s"] < best["wall_s"]:
                best = r
    return best


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


def table(study, scene, verdicts):
    lines = [
        f"#### {SCENE_SHORT[scene]} (`{scene}`)",
        "",
        "| damping | quantity | best resolved (Argyris 14 × 10) | same, next larger Δt | FVS 14 × 10 "
        "| the rule (1 %) | cheapest within 1 % of the converged value |",
        "|---|---|---|---|---|---|---|",
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
            v = verdicts[(key, q)]
            cheap = cheapest_within(study, key, q, v)
            lines.append(
                f"| {MODEL_TITLES[model]} | {sp.md_name(q)}{sp.unit(q)} "
                f"| {sp.with_spread(q, ref)} at {ref['dt']:g} s | {rel(study, coarser, ref)} "
                f"| {rel(study, fvs, ref)} | {verdict_text(v, q)} "
                f"| {setting(cheap) if cheap else '–'} |"
            )
    return lines


def contact_loss_table(study, model):
    """Energy removed at the obstacles per period (J): one row per mesh, one column per Δt."""
    q = "contact_loss_per_period_J"
    runs = [r for s in SCENES for r in study.select(f"{s}/{model}", q)]
    steps = sorted({r["dt"] for r in runs}, reverse=True)
    lines = [
        f"#### Energy removed at the obstacles per period (J), {MODEL_TITLES[model]}",
        "",
        "| scene | mesh | " + " | ".join(f"Δt = {dt:g} s" for dt in steps) + " |",
        "|---|---|" + "---|" * len(steps),
    ]
    for scene in SCENES:
        for mesh in study.mesh_keys:
            by_dt = {r["dt"]: r for r in study.select(f"{scene}/{model}", q, mesh)}
            if by_dt:
                cells = [sp.number(by_dt[dt]["value"], 4) if dt in by_dt else "" for dt in steps]
                lines.append(
                    f"| {SCENE_SHORT[scene]} | {sp.mesh_name(mesh)} | " + " | ".join(cells) + " |"
                )
    return lines


def contact_loss_plot(study, out):
    """Contact loss per period against Δt, per mesh, one panel per (scene, model)."""
    models = [
        m
        for m in ("beta", "rayleigh-1k", "rayleigh-5k", "rayleigh-20k")
        if any(f"{s}/{m}" in study.scenes for s in SCENES)
    ]
    fig, axes = plt.subplots(
        len(SCENES), len(models), figsize=(4.2 * len(models), 7.6), squeeze=False
    )
    q = "contact_loss_per_period_J"
    data = []
    for i, scene in enumerate(SCENES):
        for j, model in enumerate(models):
            ax = axes[i][j]
            key = f"{scene}/{model}"
            for element in ("argyris", "fvs"):
                meshes = [m for m in study.mesh_keys if m[0] == element]
                for k, mesh in enumerate(meshes):
                    runs = study.select(key, q, mesh)
                    data += [[scene, model, *mesh, r["dt"], r["value"], r["spread"]] for r in runs]
                    if runs:
                        ax.errorbar(
                            [r["dt"] for r in runs],
                            [r["value"] for r in runs],
                            yerr=[2 * r["spread"] for r in runs],
                            color=sp.COLORS[element],
                            marker=sp.MARKERS[k % 6],
                            ms=4,
                            lw=0.9,
                            capsize=1.5,
                            label=sp.mesh_name(mesh),
                        )
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.invert_xaxis()
            ax.set_xlabel("Δt (s)")
            ax.set_ylabel("contact loss per period (J)")
            ax.set_title(sp.SCENE_TITLES.get(key, key), fontsize=8)
            ax.grid(True, which="major", alpha=0.3)
            ax.legend(fontsize=6, ncol=2)
    fig.suptitle(
        "Energy removed at the obstacles per forcing period against Δt (bars: 2σ)", fontsize=9
    )
    save(fig, out / "damping_contact_loss.png", dpi=100)
    pages.figure_data(
        out / "damping_contact_loss.png",
        ["scene", "model", "element", "nx", "ny", "dt", "value", "spread"],
        data,
    )


def signed(x):
    """x with two decimals and its sign, a minus sign (−) below zero."""
    return f"+{x:.2f}" if x >= 0 else f"−{-x:.2f}"


def threshold_table(study):
    """The Δt series behind the start-up warning's threshold: ζ_hf, the mean energy (and its
    change from the series' smallest Δt), impacts per period and the RMS corner."""
    lines = [
        "| damping | Δt (s) | ζ_hf | mean energy.total (J) | against the smallest Δt | "
        "impacts per period | RMS corner (mm) |",
        "|---|---|---|---|---|---|---|",
    ]
    scene, mesh = THRESHOLD_AT
    for model in THRESHOLD_MODELS:
        key = f"{scene}/{model}"

        def series(q, key=key):
            return sorted(
                (
                    r
                    for r in study.all_rows
                    if r["scene"] == key and r["mesh"] == mesh and r["quantity"] == q
                ),
                key=lambda r: -r["dt"],
            )

        energy = series("mean_energy_J")
        impacts = {r["dt"]: r for r in series("impacts_per_period")}
        corner = {r["dt"]: r for r in series("rms_corner_m")}
        for k, r in enumerate(energy):
            change = signed(100 * (r["value"] / energy[-1]["value"] - 1))
            lines.append(
                f"| {MODEL_TITLES[model] if k == 0 else ''} | {r['dt']:g} | {r['zeta_hf']:.3g} | "
                f"{sp.with_spread('mean_energy_J', r)} | {change} % | "
                f"{sp.with_spread('impacts_per_period', impacts[r['dt']])} | "
                f"{sp.with_spread('rms_corner_m', corner[r['dt']])} |"
            )
    return lines


def finer_table(study):
    """β at 1e-6 s on meshes finer than the reference's: each value and its difference from the
    reference, Argyris 14 × 10."""
    lines = [
        "| scene | quantity | " + " | ".join(sp.mesh_name(m) for m in FINER_MESHES) + " |",
        "|---|---|" + "---|" * len(FINER_MESHES),
    ]
    for scene in SCENES:
        for q in QUANTITIES[:4]:
            at = {
                r["mesh"]: r
                for r in study.all_rows
                if r["scene"] == f"{scene}/beta" and r["quantity"] == q and r["dt"] == 1e-6
            }
            ref = at.get(FINEST)
            cells = []
            for m in FINER_MESHES:
                r = at.get(m)
                if r is None or ref is None:
                    cells.append("–")
                elif m == FINEST:
                    cells.append(f"{sp.number(sp.shown(q, r['value']), 5)} (reference)")
                else:
                    change = 100 * (r["value"] / ref["value"] - 1)
                    cells.append(f"{sp.number(sp.shown(q, r['value']), 5)} ({signed(change)} %)")
            lines.append(
                f"| {SCENE_SHORT[scene]} | {sp.md_name(q)}{sp.unit(q)} | "
                + " | ".join(cells)
                + " |"
            )
    return lines


def tables(study, verdicts):
    """The generated tables of damping.md, by block name."""
    out = {}
    for scene in SCENES:
        out[f"compare-{scene.removeprefix('forced-')}"] = table(study, scene, verdicts)
    for model in ("beta", "rayleigh-5k"):
        out[f"contact-loss-{model}"] = contact_loss_table(study, model)
    out["threshold"] = threshold_table(study)
    out["verdicts"] = verdicts_table(study, verdicts)
    out["finer-reference"] = finer_table(study)
    return out


def plots(study, out):
    for q in QUANTITIES:
        panels = [
            s
            for m in MODELS
            for s in (f"{sc}/{m}" for sc in SCENES)
            if s in study.scenes and study.select(s, q, FINEST)
        ]
        if panels:
            # 14 panels: a lower resolution keeps each file near 0.5 MB, still legible.
            sp.work_precision(
                study,
                out,
                panels,
                [q] * len(panels),
                f"damping_wp_{q}.png",
                f"Work-precision per damping model: {sp.md_name(q)}",
                dpi=75,
            )
    contact_loss_plot(study, out)


def main():
    """Plots (with their data) and the tables of DIR/damping.md; `--tables-only` writes the
    tables alone (the check that the committed tables follow from the committed CSVs)."""
    out = Path(sys.argv[1])
    study = load(out)
    if "--tables-only" not in sys.argv[2:]:
        plots(study, out)
    runs = study_runs(study)
    verdicts = {key: evidence.judge(r) for key, r in runs.items()}
    evidence.write(
        out / "damping_verdicts.csv",
        {(*key[0].split("/"), key[1]): v for key, v in verdicts.items()},
    )
    evidence.write_ladders(
        out / "damping_ladders.csv", {(*key[0].split("/"), key[1]): r for key, r in runs.items()}
    )
    pages.fill(out / "damping.md", tables(study, verdicts), MODULE)


if __name__ == "__main__":
    main()
