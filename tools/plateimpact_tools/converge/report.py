"""The study's outputs: runs.csv (one row per run and quantity), report.md (the verdict, the
steady states with their shares and error bounds, the rule's judgement of each ladder, every run)
and work_precision.png."""

from plateimpact_tools import rule
from plateimpact_tools.converge.runs import ADVICE_PREFIX
from plateimpact_tools.converge.states import state_value
from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.windows import QUANTITIES, value_and_spread


def group_names(study, setting):
    """start index -> the name of its state at a run setting."""
    return {k: s.name for s in study.states_at(setting) for k in s.starts}


def rows(study):
    header = [
        "ladder",
        "element",
        "nx",
        "ny",
        "dt",
        "start",
        "state",
        "quantity",
        "value",
        "spread",
        "cpu_s",
        "simulated_s",
    ]
    lines = [",".join(header)]
    names = {}
    for run in study.order:
        nx, ny, dt, k = run
        if run[:3] not in names:
            names[run[:3]] = group_names(study, run[:3])
        result = study.results[run]
        for q in study.quantities:
            v, s = value_and_spread(q, result["windows"][q])
            lines.append(
                ",".join(
                    str(x)
                    for x in (
                        study.phase_of[run],
                        study.element,
                        nx,
                        ny,
                        repr(dt),
                        study.starts[k].name,
                        names[run[:3]][k],
                        q,
                        repr(v),
                        repr(s),
                        f"{result['cpu']:.3f}",
                        repr(study.simulated),
                    )
                )
            )
    return "\n".join(lines) + "\n"


def header(study, command, where):
    starts = ", ".join(s.name for s in study.starts)
    return [
        "# Convergence study",
        "",
        f"Command: `{command}`",
        "",
        f"Run on {where}. Scene (start values): "
        + (", ".join(f"`{k}={v}`" for k, v in sorted(study.scene.items())) or "defaults"),
        "",
        f"Windows: {study.transient_steps * study.h:.4g} s of transient, then "
        f"{study.windows} windows of {study.window_steps * study.h:.4g} s; outputs read "
        f"every {study.h:.4g} s. Starts at every setting: {starts}. Tolerance "
        f"{study.tolerance:g} (relative). Budget {study.budget:g} CPU s, spent "
        f"{study.spent:.1f} CPU s in {len(study.order)} runs.",
        "",
        f"**{study.verdict}**",
        "",
    ]


def states_table(study, setting):
    """The states at `setting` with their starts and, at the recommended setting, each
    quantity's error bound."""
    stats = study.stats(setting)
    lines = [
        "| state | starts | "
        + " | ".join(f"{q} ({QUANTITIES[q][0]})" for q in study.quantities)
        + " |",
        "|---|---|" + "---|" * len(study.quantities),
    ]
    for state in study.states_at(setting):
        cells = []
        for q in study.quantities:
            v, s = state_value(stats, state.starts, q)
            cell = f"{v:.6g} ± {s:.2g} (1σ)"
            if setting == study.recommended:
                bound = study.bounds(state.name, q)
                cell += f"; error ≤ {bound:.3g} ({100 * bound / abs(v) if v else 0:.2g} %)"
            cells.append(cell)
        members = ", ".join(study.starts[k].name for k in state.starts)
        lines.append(
            f"| {state.name} | {len(state.starts)} of {len(study.starts)}: {members} | "
            + " | ".join(cells)
            + " |"
        )
    return lines


def judgements_table(study):
    """Per ladder, state and quantity: the last three values and what the rule said."""
    lines = [
        "| ladder | settings | state | quantity | values | observed order | error bound | rule |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for phase, ladder in study.ladders:
        if phase not in study.judgements:
            continue
        states, verdicts = study.judgements[phase]
        run = [s for s in ladder if s + (0,) in study.results][-3:]
        for state in states:
            for q in study.quantities:
                values, _ = study.state_ladder(run, state.starts, q)
                j = verdicts[state.name][q]
                order = f"{j.order:.2g}" if j.order is not None else "—"
                bound = f"{j.bound:.3g}" if j.bound != float("inf") else "—"
                lines.append(
                    f"| {phase} | {' → '.join(study.describe(s) for s in run)} | "
                    f"{state.name} | {q} | {' → '.join(f'{v:.6g}' for v in values)} | "
                    f"{order} | {bound} | {'accepted' if j.accepted else j.why} |"
                )
    return lines


def runs_table(study):
    lines = [
        "| ladder | setting | start | state | CPU s | FMU warns | "
        + " | ".join(f"{q} ({QUANTITIES[q][0]})" for q in study.quantities)
        + " |",
        "|---|---|---|---|---|---|" + "---|" * len(study.quantities),
    ]
    names = {}
    for run in study.order:
        if run[:3] not in names:
            names[run[:3]] = group_names(study, run[:3])
        result = study.results[run]
        cells = []
        for q in study.quantities:
            v, sd = value_and_spread(q, result["windows"][q])
            cells.append(f"{v:.6g} ± {sd:.2g}")
        lines.append(
            f"| {study.phase_of[run]} | {study.describe(run[:3])} | "
            f"{study.starts[run[3]].name} | {names[run[:3]][run[3]]} | "
            f"{result['cpu']:.2f} | {'yes' if result['warning'] else 'no'} | "
            + " | ".join(cells)
            + " |"
        )
    return lines


def markdown(study, command, where):
    lines = header(study, command, where)
    last = study.recommended or next(
        s for s in reversed(study.ladders[-1][1]) if s + (0,) in study.results
    )
    if study.recommended is not None:
        lines += [
            f"Recommended: {study.describe(last)} (`{study.settings_text(last)}`), "
            f"{study.cost(last) / study.simulated:.3g} CPU s per simulated second of one "
            "run. The error bound of a value is the sum of its bounds from the Δt ladder "
            "and, with --mesh, the mesh ladder that end here (docs/converge/README.md, "
            "*The rule*).",
            "",
        ]
    else:
        lines += ["Trend along the last ladder:", ""] + [f"- {t}" for t in study.trends]
        lines += ["", f"Advice: {study.advice}", ""]
    lines += [f"## Steady states at {study.describe(last)}", ""] + states_table(study, last)
    warning = study.warning(last)
    lines += [
        "",
        f"The FMU warns at these settings: {warning}"
        if warning
        else "The FMU does not warn at these settings.",
        "",
    ]
    lines += [
        "## The rule on each ladder",
        "",
        f"The last three settings of each ladder, per state (its starts at the ladder's "
        f"last setting) and quantity; a pair of changes is judged resolved beyond "
        f"{rule.SIGMAS:g}σ; bounds in the quantity's unit.",
        "",
    ] + judgements_table(study)
    lines += ["", "## Runs", ""] + runs_table(study)
    lines += [
        "",
        f"State: the state its run belongs to at its own setting. FMU warns: whether "
        f'the FMU logged "{ADVICE_PREFIX} …" at initialization (src/advice.rs, '
        "docs/accuracy/damping.md).",
    ]
    lines += ["", "Quantities:", ""] + [
        f"- `{q}` ({u}): {d}" for q, (u, d) in QUANTITIES.items() if q in study.quantities
    ]
    lines += ["", "Method and definitions: docs/converge/README.md. Plot: work_precision.png.", ""]
    return "\n".join(lines)


def plot(study, path):
    """Work-precision: per state and quantity, each setting's relative difference from the
    state's value at the reference (the recommended setting, or else the last one run), with 2σ
    error bars, against the CPU seconds per simulated second of one run; the settings of each
    ladder joined in ladder order."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    styles = ["o-", "s--", "^-.", "v:", "D-", "P--"]
    reference = study.recommended or study.order[-1][:3]
    states = study.states_at(reference)
    curve = 0
    for state in states:
        for q in study.quantities:
            ref = state_value(study.stats(reference), state.starts, q)[0]
            for j, (phase, ladder) in enumerate(study.ladders):
                xs, ys, lo, hi = [], [], [], []
                for s in ladder:
                    if s + (0,) not in study.results:
                        continue
                    v, sd = state_value(study.stats(s), state.starts, q)
                    if ref and v != ref:
                        xs.append(study.cost(s) / study.simulated)
                        ys.append(abs(v - ref) / abs(ref))
                        hi.append(rule.SIGMAS * sd / abs(ref))
                        lo.append(min(hi[-1], 0.999 * ys[-1]))  # a log axis has no 0
                if xs:
                    label = f"{state.name}: {q}, {phase}" if len(states) > 1 else f"{q}, {phase}"
                    ax.errorbar(
                        xs,
                        ys,
                        yerr=[lo, hi],
                        fmt=styles[j % len(styles)],
                        color=colors[curve % len(colors)],
                        ms=4,
                        capsize=2,
                        label=label,
                    )
            curve += 1
    if study.recommended is not None:
        ax.axvline(
            study.cost(study.recommended) / study.simulated,
            color="k",
            ls=":",
            lw=1,
            label=f"recommended, {study.describe(study.recommended)}",
        )
    ax.axhline(study.tolerance, color="gray", lw=1, label=f"tolerance {study.tolerance:g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU seconds per simulated second of one run")
    ax.set_ylabel(f"|value − value at {study.describe(reference)}| / |that value|")
    ax.set_title(
        f"PlateImpact convergence study: {study.verdict.split(':')[0]} "
        f"(tolerance {study.tolerance:g}, {len(states)} steady state"
        f"{'s' if len(states) > 1 else ''})",
        fontsize=10,
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    save(fig, path)
