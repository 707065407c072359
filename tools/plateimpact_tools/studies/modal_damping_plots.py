"""Plots and the generated part of modal_damping.md, from the CSVs of the modal damping study.

Usage: python -m plateimpact_tools.studies.modal_damping_plots DIR [--tables-only]. Reads
DIR/modal_damping.csv, modal_damping_bands.csv, modal_damping_meshes.csv, modal_damping_meta.csv
and, when present, modal_damping_periods.csv
(`cargo run --release -p plate_impact_studies --bin modal_damping`);
writes DIR/modal_damping_verdicts.csv (the rule's verdict on every scene, ratio, quantity and
element, `plateimpact_tools.studies.evidence`), DIR/modal_damping_ladders.csv (the rule at every
setting: its Δt and mesh ladders and what it said of each), the part of DIR/modal_damping.md between its
`generated: modal-damping` markers (the rest of the page is hand-written) and, unless
--tables-only, DIR/modal_damping_dt.png (each time average against ω_max·Δt, one line per mesh),
DIR/modal_damping_mesh.png (each mesh at its smallest Δt against its free dofs),
DIR/modal_damping_bands.png (the modal energy per band of natural frequency) and
DIR/modal_damping_correlation.png (autocorrelation of the per-period series, with the periods
file).

A run's σ is its spread, the largest of its window, correlation and replica estimates. Every
verdict (converged or not, the ± bound, the observed order) is the rule's, through
`evidence`: one tolerance, meshes compared at one Δt, the bound the sum of the Δt and mesh
bounds.
"""

import csv
import sys
from collections import defaultdict
from pathlib import Path

from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.studies import evidence

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
BEGIN = (
    "<!-- generated: modal-damping (python -m plateimpact_tools.studies.modal_damping_plots; "
    "do not edit) -->"
)
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
        for k in (
            "modal_ratio",
            "dt",
            "omega_max_dt",
            "value",
            "spread",
            "cpu_s",
            "step_us",
            "window_spread",
            "correlation_spread",
            "replica_spread",
            "tau_periods",
            "set_up_cpu_s",
        ):
            r[k] = float(r[k])
        for k in ("nx", "ny", "free_dofs", "periods", "window_periods", "windows", "replicas"):
            r[k] = int(r[k])
        r["mesh"] = (r["element"], r["nx"], r["ny"])
        table[(r["scene"], r["modal_ratio"], r["quantity"])][r["mesh"]].append(r)
    for by_mesh in table.values():
        for runs in by_mesh.values():
            runs.sort(key=lambda r: -r["dt"])
    return rows, table


mesh_name = evidence.mesh_name


def with_spread(r, quantity):
    _, _, scale = QUANTITIES[quantity]
    return f"{r['value'] * scale:.4g} ± {r['spread'] * scale:.2g}"


def element_meshes(by_mesh, element):
    """The meshes of an element, coarse to fine."""
    return sorted((m for m in by_mesh if m[0] == element), key=lambda m: by_mesh[m][0]["free_dofs"])


def evidence_runs(by_mesh):
    """The runs of one (scene, ratio, quantity) as the rule reads them."""
    return [
        evidence.Run(r["element"], r["nx"], r["ny"], r["dt"], r["value"], r["spread"])
        for runs in by_mesh.values()
        for r in runs
    ]


def study_runs(table):
    """The runs of every (scene, ratio, quantity) of the study, in the CSV's order, as the rule
    reads them."""
    return {
        (scene, f"{zeta:g}", quantity): evidence_runs(by_mesh)
        for (scene, zeta, quantity), by_mesh in table.items()
    }


def verdict_text(verdicts, quantity):
    """The finding of the rule (`evidence`) for one quantity, as the tables print it."""
    both = verdicts["both"]
    _, unit, scale = QUANTITIES[quantity]
    if both.accepted:
        s = both.setting
        return (
            f"converged: **{s.run.value * scale:.4g} ± {s.bound * scale:.2g}** "
            f"({evidence.mesh_name(s.run.mesh)}, {s.run.dt:g} s)"
        )
    parts = [
        f"{'Argyris' if e == 'argyris' else 'FVS'}: {verdicts[e].why}"
        for e in evidence.ELEMENTS
        if verdicts[e].setting
    ]
    if "disagree" in both.why:
        parts = [both.why]
    return "not converged: " + "; ".join(parts)


def convergence_tables(table, verdicts, scenes, zetas):
    lines = []
    for scene in scenes:
        lines += [f"### {SCENE_TITLES.get(scene, scene)} (`{scene}`)", ""]
        for zeta in zetas:
            if (scene, zeta, "mean_energy_J") not in table:
                continue
            meshes = sorted(
                table[(scene, zeta, "mean_energy_J")],
                key=lambda m: (m[0], table[(scene, zeta, "mean_energy_J")][m][0]["free_dofs"]),
            )
            lines += [
                f"#### ζ = {zeta:g}",
                "",
                "Each mesh at its smallest Δt (value ± spread); the finding is the rule's "
                f"(`evidence`, tolerance {evidence.TOLERANCE:.0%}): converged with its value "
                "± the sum of its Δt and mesh bounds, or what failed.",
                "",
                "| quantity | " + " | ".join(mesh_name(m) for m in meshes) + " | finding |",
                "|---|" + "---|" * (len(meshes) + 1),
            ]
            for quantity in QUANTITIES:
                by_mesh = table.get((scene, zeta, quantity))
                if not by_mesh:
                    continue
                cells = [
                    f"{with_spread(by_mesh[m][-1], quantity)} ({by_mesh[m][-1]['dt']:g} s)"
                    for m in meshes
                ]
                text = verdict_text(verdicts[(scene, f"{zeta:g}", quantity)], quantity)
                name, unit, _ = QUANTITIES[quantity]
                label = f"{name} ({unit})" if unit else name
                lines.append(f"| {md(label)} | " + " | ".join(cells) + f" | {md(text)} |")
            lines.append("")
    return lines


def dt_judgement(runs):
    """The rule on a mesh's Δt ladder ending at its smallest Δt (`evidence.judge_ladder`), or None
    with fewer than three Δt."""
    if len(runs) < 3:
        return None
    ladder = [
        evidence.Run(r["element"], r["nx"], r["ny"], r["dt"], r["value"], r["spread"])
        for r in runs[-3:]
    ]
    return evidence.judge_ladder(ladder, lambda a, b: a.dt / b.dt, evidence.TOLERANCE).judgement


def dt_table(table, scenes, zetas):
    """Each mesh's mean energy and RMS base force at every Δt it ran, and the rule on its three
    smallest Δt."""
    dts = sorted(
        {r["dt"] for by_mesh in table.values() for runs in by_mesh.values() for r in runs},
        reverse=True,
    )
    lines = []
    for quantity in ("mean_energy_J", "rms_base_force_N"):
        name, unit, scale = QUANTITIES[quantity]
        lines += [
            f"{name} ({unit}) at each Δt; *rule on Δt*: the rule (tolerance "
            f"{evidence.TOLERANCE:.0%}) on the mesh's three smallest Δt, accepted with its "
            "bound or what failed; order: the order the rule observed there (– where the "
            "last change is within its noise or the changes alternate).",
            "",
            "| scene | ζ | mesh | "
            + " | ".join(f"{dt:g} s" for dt in dts)
            + " | rule on Δt | order |",
            "|---|---|---|" + "---|" * (len(dts) + 2),
        ]
        for scene in scenes:
            for zeta in zetas:
                by_mesh = table.get((scene, zeta, quantity), {})
                for element in ("argyris", "fvs"):
                    for mesh in element_meshes(by_mesh, element):
                        runs = by_mesh[mesh]
                        at = {r["dt"]: r for r in runs}
                        cells = [f"{at[dt]['value'] * scale:.4g}" if dt in at else "" for dt in dts]
                        j = dt_judgement(runs)
                        if j is None:
                            where, order = "fewer than three Δt", "–"
                        else:
                            where = (
                                f"accepted, ± {100 * j.bound / abs(runs[-1]['value']):.2g} %"
                                if j.accepted
                                else j.why
                            )
                            order = f"{j.order:.1f}" if j.order is not None else "–"
                        lines.append(
                            f"| {scene} | {zeta:g} | {mesh_name(mesh)} | "
                            + " | ".join(cells)
                            + f" | {where} | {order} |"
                        )
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
                    (
                        r["window_spread"],
                        r["correlation_spread"],
                        r["replica_spread"],
                        r["replicas"],
                    )
                )
    lines = [
        "| scene | ζ | quantity | τ median (periods) | τ largest | window (periods) | "
        "replica / window spread |",
        "|---|---|---|---|---|---|---|",
    ]
    windows = {(r["scene"]): r["window_periods"] for r in rows}
    for key in sorted(taus):
        scene, zeta, quantity = key
        values = sorted(taus[key])
        median = values[len(values) // 2]
        ratio = ", ".join(f"{rep / win:.2f} ({n})" for win, _, rep, n in spreads.get(key, []))
        lines.append(
            f"| {scene} | {zeta:g} | {md(QUANTITIES[quantity][0])} | {median:.2f} | "
            f"{values[-1]:.2f} | {windows[scene]} | {ratio or '–'} |"
        )
    return lines


def band_table(bands, scenes, zetas):
    lines = [
        "| scene | ζ | mesh | Δt (s) | share above 1 kHz | above 10 kHz | above 100 kHz |",
        "|---|---|---|---|---|---|---|",
    ]
    for scene in scenes:
        for zeta in zetas:
            for mesh, dt, by_band in finest_bands(bands, scene, zeta):

                def share(low, by_band=by_band):
                    return sum(s for (lo, s) in by_band if lo >= low)

                lines.append(
                    f"| {scene} | {zeta:g} | {mesh_name(mesh)} | {dt:g} | "
                    f"{share(1e3):.1%} | {share(1e4):.2%} | {share(1e5):.3%} |"
                )
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
    fig, axes = pyplot().subplots(
        len(quantities),
        len(scenes) * len(zetas),
        figsize=(3.2 * len(scenes) * len(zetas), 2.4 * len(quantities)),
        squeeze=False,
    )
    for row, quantity in enumerate(quantities):
        name, unit, scale = QUANTITIES[quantity]
        for col, (scene, zeta) in enumerate((s, z) for s in scenes for z in zetas):
            ax = axes[row][col]
            by_mesh = table.get((scene, zeta, quantity), {})
            for mesh, runs in sorted(
                by_mesh.items(), key=lambda kv: (kv[0][0], kv[1][0]["free_dofs"])
            ):
                ax.errorbar(
                    [r["omega_max_dt"] for r in runs],
                    [r["value"] * scale for r in runs],
                    yerr=[2 * r["spread"] * scale for r in runs],
                    marker="o" if mesh[0] == "argyris" else "s",
                    ms=3,
                    capsize=2,
                    ls="-" if mesh[0] == "argyris" else "--",
                    label=mesh_name(mesh),
                )
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
    fig, axes = pyplot().subplots(
        len(scenes),
        len(quantities),
        figsize=(3.4 * len(quantities), 2.8 * len(scenes)),
        squeeze=False,
    )
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
                        ax.errorbar(
                            [r["free_dofs"] for r in runs],
                            [r["value"] * scale for r in runs],
                            yerr=[2 * r["spread"] * scale for r in runs],
                            marker=marker,
                            ms=3,
                            capsize=2,
                            ls="-" if element == "argyris" else "--",
                            label=f"ζ = {zeta:g}, {element}",
                        )
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
    fig, axes = pyplot().subplots(
        len(zetas), len(scenes), figsize=(4.2 * len(scenes), 3.0 * len(zetas)), squeeze=False
    )
    for row, zeta in enumerate(zetas):
        for col, scene in enumerate(scenes):
            ax = axes[row][col]
            for mesh, dt, by_band in finest_bands(bands, scene, zeta):
                lows = [max(lo, 30.0) for lo, _ in by_band]
                ax.step(
                    lows,
                    [max(s, 1e-9) for _, s in by_band],
                    where="post",
                    ls="-" if mesh[0] == "argyris" else "--",
                    label=f"{mesh_name(mesh)}, {dt:g} s",
                )
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
    series = defaultdict(lambda: defaultdict(list))
    frequency = {"forced-35hz": 35.0, "forced-60hz": 60.0, "aluminium-square": 40.0}
    for r in read(path):
        if r["replica"] != "0":
            continue
        key = (
            r["scene"],
            float(r["modal_ratio"]),
            f"{mesh_name((r['element'], r['nx'], r['ny']))}",
            float(r["dt"]),
        )
        if int(r["period"]) >= transient_s * frequency.get(r["scene"], 1.0):
            for q in ("mean_energy_J", "rms_corner_m", "mean_abs_base_force_N"):
                series[key][q].append(float(r[q]))
    quantities = ["mean_energy_J", "rms_corner_m", "mean_abs_base_force_N"]
    fig, axes = pyplot().subplots(
        1, len(quantities), figsize=(4.2 * len(quantities), 3.0), squeeze=False
    )
    for col, q in enumerate(quantities):
        ax = axes[0][col]
        for key, by_q in sorted(series.items()):
            rho = autocorrelation(by_q[q], 20)
            ax.plot(
                range(len(rho)),
                rho,
                marker=".",
                label=f"{key[0]}, ζ = {key[1]:g}, {key[2]}, {key[3]:g} s",
            )
        ax.axhline(0, color="k", lw=0.5)
        ax.set_title(f"per-period {QUANTITIES[q][0]}", fontsize=8)
        ax.set_xlabel("lag (forcing periods)", fontsize=7)
        ax.set_ylabel("autocorrelation", fontsize=7)
        ax.tick_params(labelsize=6)
        if col == 0:
            ax.legend(fontsize=5)
    save(fig, out / "modal_damping_correlation.png", dpi=90)


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
    lines = [
        "| mesh | free dofs | set-up (CPU s) | "
        + " | ".join(f"µs/step at {dt:g} s" for dt in dts)
        + " |",
        "|---|---|---|" + "---|" * len(dts),
    ]
    for mesh in sorted(set_up, key=lambda m: (m[0], dofs[m])):
        cells = []
        for dt in dts:
            values = sorted(steps.get((mesh, dt), []))
            cells.append(f"{values[len(values) // 2]:.2f}" if values else "")
        s = sorted(set_up[mesh])
        lines.append(
            f"| {mesh_name(mesh)} | {dofs[mesh]} | {s[len(s) // 2]:.2f} | "
            + " | ".join(cells)
            + " |"
        )
    return lines


def main():
    out = Path(sys.argv[1])
    tables_only = "--tables-only" in sys.argv[2:]
    rows, table = load(out)
    meta = {r["key"]: r["value"] for r in read(out / "modal_damping_meta.csv")}
    bands = read(out / "modal_damping_bands.csv")
    scenes = [s for s in SCENES if any(r["scene"] == s for r in rows)]
    zetas = sorted({r["modal_ratio"] for r in rows})
    runs_of = study_runs(table)
    verdicts = {key: evidence.judge(runs) for key, runs in runs_of.items()}
    evidence.write(out / "modal_damping_verdicts.csv", verdicts)
    evidence.write_ladders(out / "modal_damping_ladders.csv", runs_of)
    correlation = (out / "modal_damping_periods.csv").exists()
    if not tables_only:
        plot_dt(table, scenes, zetas, out)
        plot_mesh(table, scenes, zetas, out)
        plot_bands(bands, scenes, zetas, out)
        plot_correlation(out, float(meta.get("transient_s", 1.0)))
    cpu = sum(r["cpu_s"] for r in rows if r["quantity"] == "mean_energy_J")
    runs = sum(1 for r in rows if r["quantity"] == "mean_energy_J")
    # The meta file's commit: one, or those of the processes that ran, separated by ';'.
    commits = ", ".join(c.strip()[:12] for c in meta.get("commit", "?").split(";"))
    lines = [
        BEGIN,
        "",
        f"Runs: {runs}, {cpu:.0f} CPU s in all (commit {commits}); "
        f"left out for cost: {meta.get('left_out') or 'none'}.",
        "",
        "## Convergence, scene by scene",
        "",
    ]
    lines += convergence_tables(table, verdicts, scenes, zetas)
    lines += ["## Settling in Δt", ""] + dt_table(table, scenes, zetas)
    lines += ["## Correlation times and windows", ""] + correlation_table(rows) + [""]
    lines += [
        "## Where the energy sits",
        "",
        "Share of the modal energy (Σ over modes of ½q̇² + ½ω²q², averaged over the steady "
        "state) above fixed natural frequencies, each mesh at its smallest Δt.",
        "",
    ]
    lines += band_table(bands, scenes, zetas) + [""]
    lines += [
        "![modal energy per band](modal_damping_bands.png)",
        "",
        "![time averages against ω_max·Δt](modal_damping_dt.png)",
        "",
        "![each mesh at its smallest Δt](modal_damping_mesh.png)",
        "",
    ]
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
