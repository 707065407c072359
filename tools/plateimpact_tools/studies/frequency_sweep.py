"""Frequency sweeps of the packaged PlateImpact FMU, as Dask tasks.

Two modes. By default every frequency is a run of its own from rest (one Dask task per run):
sweeps `base.frequency` (and optionally other FMU parameters) for the plate between its obstacles
and for the same plate without them. With `--continuation` one FMU instance per configuration
sweeps the frequencies up and then back down, carrying the plate's state from each frequency to
the next, so that coexisting responses (jumps, hysteresis) show as two branches. Both write a CSV
and a plot with the library's natural frequencies marked.

    python -m plateimpact_tools.studies.frequency_sweep [--frequencies 5:120:1]
        [--workers N | --scheduler ADDR | --serial] [--set name=value ...]
        [--param name=v1,v2,... ...] [--zeta1 Z] [--stop-time 1.0] [--out out/sweep]
    python -m plateimpact_tools.studies.frequency_sweep --continuation [--frequencies 30:90:1]
        [--zeta1 0.01] [--settle 1.5] [--measure 1.0] [...]

Runs from rest (columns of sweep.csv; times are communication points, one per internal step Δt):
  peak_corner_m     max |u| over both free corners (Lx, 0), (Lx, Ly) in the analysis window, the
                    last N whole forcing periods inside the last half of the horizon
                    (N = floor(f·T/2)); u is the absolute displacement the obstacles bound.
  impacts           internal steps whose contact set went from empty to non-empty (the FMU's
                    contact.impacts), over the whole run
  impacts_window    the same, inside the analysis window
  dissipated_per_period_J
                    energy the obstacles take out per forcing period in the window: the change
                    of the FMU's energy.contact_loss over the window, / N.
  energy_change_per_period_J
                    (E(end of window) − E(start))/N: ≈ 0 in a periodic steady state; a plate
                    still growing (the undamped resonance) or still in transient shows here.
  trajectory_sha256 digest of every recorded output: equal digests mean bit-identical runs.

Continuation (columns of continuation.csv): see `continuation_run`. The base is driven through the
input `base.displacement` with a sine whose phase is continuous across frequency changes; see
`BaseSchedule` for why, and for where the frequency changes.

Runs are independent FMU instances and the solver is deterministic, so results do not depend on
where or in which order tasks run; rows are sorted by configuration, swept parameters, frequency
(and direction).
"""

import argparse
import dataclasses
import hashlib
import itertools
import math
import os
import pathlib
import subprocess
import sys
import time

import numpy as np

from plateimpact_tools import DEFAULT_FMU, ROOT
from plateimpact_tools.converge.states import differ
from plateimpact_tools.fmu_dask import dask_client, fmu_dir, run_tasks
from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.scene_values import ELEMENT, parse_value
from plateimpact_tools.windows import last_whole_periods, period_blocks, rms, standard_error

OUTPUTS = [
    "corner1.displacement",
    "corner2.displacement",
    "energy.total",
    "energy.contact_loss",
    "contact.active_nodes",
    "contact.impacts",
]
CONFIGS = {  # name -> start values that define it
    "obstacles": {"obstacle.lower_enabled": True, "obstacle.upper_enabled": True},
    "free": {"obstacle.lower_enabled": False, "obstacle.upper_enabled": False},
}
# Parameters the natural frequencies depend on (passed to the modes example).
MODAL = ("plate.", "material.", "mesh.")
COLUMNS = [
    "config",
    "params",
    "base.frequency",
    "peak_corner_m",
    "impacts",
    "impacts_window",
    "periods",
    "dissipated_per_period_J",
    "energy_change_per_period_J",
    "max_active_nodes",
    "trajectory_sha256",
]


# ----------------------------------------------------------------------------------------------
# One run (executed on a worker)


def run_one(fmu_blob, digest, start_values, stop_time):
    """Simulates one parameter set, communicating at every internal step, and returns its summary
    (a dict of plain Python values) and the wall time."""
    import fmpy

    step = float(start_values.get("solver.time_step", 1e-4))
    directory = fmu_dir(fmu_blob, digest)
    t0 = time.perf_counter()
    result = fmpy.simulate_fmu(
        directory,
        start_values=dict(start_values),
        stop_time=stop_time,
        output_interval=step,
        output=OUTPUTS,
    )
    wall = time.perf_counter() - t0
    t = result["time"]
    corners = np.maximum(
        np.abs(result["corner1.displacement"]), np.abs(result["corner2.displacement"])
    )
    active = result["contact.active_nodes"]
    energy = result["energy.total"]
    first, periods = last_whole_periods(float(start_values["base.frequency"]), stop_time, step)
    n_last = len(t) - 1
    window = slice(first, n_last + 1)
    digest_out = hashlib.sha256()
    for name in ["time"] + OUTPUTS:
        digest_out.update(np.ascontiguousarray(result[name]).tobytes())
    impacts = np.asarray(result["contact.impacts"])
    loss = result["energy.contact_loss"]
    summary = {
        "peak_corner_m": float(corners[window].max()),
        "impacts": int(impacts.sum()),
        # The impacts of the step that ends at the window's first point happened before it.
        "impacts_window": int(impacts[first + 1 :].sum()),
        "periods": periods,
        "dissipated_per_period_J": (
            float(loss[n_last] - loss[first]) / periods if periods else float("nan")
        ),
        "energy_change_per_period_J": (
            float(energy[n_last] - energy[first]) / periods if periods else float("nan")
        ),
        "max_active_nodes": int(active.max()),
        "trajectory_sha256": digest_out.hexdigest(),
    }
    return summary, wall


# ----------------------------------------------------------------------------------------------
# Continuation: one instance sweeps up and down, carrying the plate's state (executed on a worker)


class BaseSchedule:
    """The base motion z(t) = c·sin φ(t) of a continuation sweep: frequency f_j during dwell j,
    phase continuous, every dwell ending at a crest of the sine.

    Why the input and not the FMU state. `base.frequency` is a fixed parameter, so the built-in
    sine cannot change frequency within an instance; and an FMU state saved at one frequency is
    refused by an instance of another (the state carries the fixed parameters, and they must
    match). Even if it were accepted, the built-in sine c·sin(2πf t) of the new frequency would
    jump at the switch time t_s, from c·sin(2πf_old t_s) to c·sin(2πf_new t_s): an impulsive base
    motion that is no part of a sweep. So the built-in amplitude is 0 and this schedule drives
    `base.displacement`, sending ż and z̈ with fmi2SetRealInputDerivatives (the FMU then applies
    z to O((ωh)³·c) per communication step h, 1e-5·c at 60 Hz and h = 1e-4 s).

    Where the frequency changes. z is continuous at every switch because φ is. The base velocity
    c·2πf·cos φ would jump by c·2π·Δf·cos φ; switching at a crest (cos φ = 0, the base at rest)
    keeps it continuous up to the communication grid: the switch is the communication time
    nearest a crest, where |cos φ| ≤ πfh. The sweep starts at a crest too, z(0) = c with the plate at rest, so the base
    starts at rest, as the plate (the built-in sine starts with velocity 2πfc instead).
    """

    def __init__(self, amplitude, h):
        self.amplitude, self.h = amplitude, h  # c (m) and the communication step (s)
        self.step = 0  # communication point where the current dwell starts
        self.phase = math.pi / 2  # φ there
        self.omega = 0.0

    def tune(self, frequency):
        """Sets the frequency (Hz) of the dwell that starts at the current step."""
        self.omega = 2 * math.pi * frequency

    def dwell_steps(self, periods):
        """Communication steps from here to the crest nearest to `periods` periods on."""
        target = self.phase + 2 * math.pi * periods
        crest = math.pi / 2 + math.pi * round((target - math.pi / 2) / math.pi)
        return max(1, round((crest - self.phase) / (self.omega * self.h)))

    def at(self, k):
        """(z, ż, z̈) at communication step k of the current dwell."""
        phi = self.phase + self.omega * k * self.h
        c, w = self.amplitude, self.omega
        return c * math.sin(phi), c * w * math.cos(phi), -c * w * w * math.sin(phi)

    def advance(self, steps):
        """Ends the current dwell after `steps` communication steps."""
        self.phase += self.omega * steps * self.h
        self.step += steps


CONTINUATION_OUTPUTS = [
    "corner1.displacement",
    "corner2.displacement",
    "energy.total",
    "energy.contact_loss",
    "base.force",
]
CONTINUATION_COUNTS = ["contact.impacts", "contact.active_nodes"]
CONTINUATION_COLUMNS = [
    "config",
    "params",
    "direction",
    "base.frequency",
    "periods",
    "rms_corner_m",
    "rms_corner_spread_m",
    "peak_corner_m",
    "impacts_per_period",
    "dissipated_per_period_J",
    "energy_change_per_period_J",
    "mean_energy_J",
    "mean_abs_base_force_N",
    "max_active_nodes",
]


def continuation_run(
    fmu_blob, digest, start_values, frequencies, amplitude, settle, measure, step=None
):
    """One FMU instance, communicating every `step` seconds (default: every internal step Δt; a
    multiple of Δt keeps the communication points on the grid), dwells at each frequency of
    `frequencies` in turn (Hz, ascending), then at each again in descending order, with the base
    of `BaseSchedule` (amplitude c = `amplitude`, m). A dwell lasts about `settle` + `measure`
    seconds of whole periods; over its last round(f·measure) periods it reports (one row):

      rms_corner_m, peak_corner_m   RMS of u(Lx, 0), and max |u| over both free corners
      rms_corner_spread_m           its spread: the standard deviation of the RMS over
                                    RMS_BLOCKS blocks of whole periods of the window, / √RMS_BLOCKS
      impacts_per_period            Σ contact.impacts / periods
      dissipated_per_period_J       change of energy.contact_loss / periods
      energy_change_per_period_J    change of energy.total / periods (≈ 0 once settled)
      mean_energy_J, mean_abs_base_force_N, max_active_nodes

    Returns (rows, wall time)."""
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.simulation import apply_start_values

    directory = fmu_dir(fmu_blob, digest)
    md = read_model_description(directory)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    h = step or float(start_values.get("solver.time_step", 1e-4))
    values = dict(start_values, **{"base.amplitude": 0.0})
    schedule = BaseSchedule(amplitude, h)
    t0 = time.perf_counter()
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=directory,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="continuation",
    )
    rows = []
    try:
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        unknown = apply_start_values(fmu, md, values)
        if unknown:
            raise ValueError(f"not variables of the FMU: {sorted(unknown)}")
        fmu.enterInitializationMode()
        z_vr = [vr["base.displacement"]]
        out_vrs = [vr[n] for n in CONTINUATION_OUTPUTS]
        count_vrs = [vr[n] for n in CONTINUATION_COUNTS]

        def send(k):
            z, dz, ddz = schedule.at(k)
            fmu.setReal(z_vr, [z])
            fmu.setRealInputDerivatives(z_vr * 2, [1, 2], [dz, ddz])

        schedule.tune(frequencies[0])
        send(0)  # the initial base position, z(0) = c, with the plate at rest
        fmu.exitInitializationMode()
        for direction, order in (("up", frequencies), ("down", frequencies[::-1])):
            for f in order:
                periods = max(1, round(f * measure))
                schedule.tune(f)
                steps = schedule.dwell_steps(round(f * settle) + periods)
                # Samples at the window's start and at each of its steps (the counts belong to
                # the step that ends at the sample).
                first = max(1, steps - round(periods / (f * h)))
                record = np.empty((steps - first + 1, len(out_vrs)))
                counts = np.empty((steps - first + 1, len(count_vrs)), dtype=np.int64)
                for k in range(steps):
                    send(k)
                    fmu.doStep(
                        currentCommunicationPoint=(schedule.step + k) * h, communicationStepSize=h
                    )
                    if k + 1 >= first:
                        record[k + 1 - first] = fmu.getReal(out_vrs)
                        counts[k + 1 - first] = fmu.getInteger(count_vrs)
                schedule.advance(steps)
                rows.append(dwell_summary(direction, f, periods, record, counts, f * h))
        fmu.terminate()
    finally:
        fmu.freeInstance()
    return rows, time.perf_counter() - t0


# Blocks of whole periods over which the spread of a dwell's RMS corner is estimated.
RMS_BLOCKS = 4


def dwell_summary(direction, frequency, periods, record, counts, periods_per_step):
    """The row of one dwell from its measured window: `record` and `counts` hold
    CONTINUATION_OUTPUTS and CONTINUATION_COUNTS at the window's start and after each of its
    steps, `periods_per_step` = f·h."""
    energy, loss = record[:, 2], record[:, 3]
    corner1, corner2, _, _, force = record[1:].T
    impacts, active = counts[1:].T
    blocks = [
        rms(corner1[a:b])
        for a, b in period_blocks(periods, RMS_BLOCKS, periods_per_step, len(corner1))
    ]
    return {
        "direction": direction,
        "base.frequency": frequency,
        "periods": periods,
        "rms_corner_m": rms(corner1),
        "rms_corner_spread_m": standard_error(blocks),
        "peak_corner_m": float(np.max(np.maximum(np.abs(corner1), np.abs(corner2)))),
        "impacts_per_period": float(impacts.sum()) / periods,
        "dissipated_per_period_J": float(loss[-1] - loss[0]) / periods,
        "energy_change_per_period_J": float(energy[-1] - energy[0]) / periods,
        "mean_energy_J": float(np.mean(energy)),
        "mean_abs_base_force_N": float(np.mean(np.abs(force))),
        "max_active_nodes": int(active.max()),
    }


# ----------------------------------------------------------------------------------------------
# The sweep (client side)


@dataclasses.dataclass(frozen=True)
class Run:
    config: str
    params: tuple  # ((name, value), ...) of the --param dimensions, in command-line order
    frequency: float

    def sort_key(self):
        return (self.config, self.params, self.frequency)


def plan(frequencies, configs, param_grid):
    """Every run of the sweep, in the canonical (sorted) order."""
    names = list(param_grid)
    combos = [tuple(zip(names, values)) for values in itertools.product(*param_grid.values())]
    runs = [Run(c, p, float(f)) for c in configs for p in combos for f in frequencies]
    return sorted(runs, key=Run.sort_key)


def start_values_of(run, fixed):
    values = dict(fixed)
    values.update(CONFIGS[run.config])
    values.update(dict(run.params))
    values["base.frequency"] = run.frequency
    return values


def sweep(
    fmu_path,
    frequencies,
    *,
    fixed=None,
    param_grid=None,
    configs=("obstacles", "free"),
    stop_time=1.0,
    client=None,
    progress=True,
):
    """Runs the sweep from rest (serially if client is None, else as Dask tasks) and returns the
    rows, sorted by configuration, swept parameters and frequency, whatever order the runs finish
    in."""
    fixed = dict(fixed or {})
    runs = plan(frequencies, configs, dict(param_grid or {}))

    def describe(run, summary):
        return (
            f"{run.config:9s} f={run.frequency:g} Hz{_params_text(run.params)}: peak "
            f"{1e3 * summary['peak_corner_m']:.3f} mm, {summary['impacts']} impacts"
        )

    done = run_tasks(
        fmu_path,
        [(run, run_one, (start_values_of(run, fixed), stop_time)) for run in runs],
        client,
        progress and describe,
    )
    rows = []
    for run in runs:
        row = {"config": run.config, "params": run.params, "base.frequency": run.frequency}
        row.update(done[run])
        rows.append(row)
    return rows


def continuation(
    fmu_path,
    frequencies,
    *,
    amplitude,
    fixed=None,
    param_grid=None,
    configs=("obstacles", "free"),
    settle=1.5,
    measure=1.0,
    step=None,
    client=None,
    progress=True,
):
    """Runs one continuation sweep (`continuation_run`: up, then down) per configuration and
    swept parameter set, serially or as Dask tasks, and returns their rows: by configuration and
    parameters, then in sweep order (up, ascending; then down, descending)."""
    fixed = dict(fixed or {})
    frequencies = sorted(float(f) for f in frequencies)
    runs = plan([0.0], configs, dict(param_grid or {}))  # one per configuration and parameters
    tasks = []
    for run in runs:
        values = start_values_of(run, fixed)
        del values["base.frequency"]
        tasks.append(
            (run, continuation_run, (values, frequencies, amplitude, settle, measure, step))
        )

    def describe(run, rows):
        return f"{run.config}{_params_text(run.params)}: {len(rows)} dwells"

    done = run_tasks(fmu_path, tasks, client, progress and describe)
    return [dict(row, config=run.config, params=run.params) for run in runs for row in done[run]]


def _params_text(params):
    return "".join(f" {k}={v}" for k, v in params)


def natural_frequencies(values, count=6):
    """The library's natural frequencies (Hz) of the plate the sweep runs, from the modes example."""
    element = values.get("mesh.element", 1)
    element = {v: k for k, v in ELEMENT.items()}.get(element, element)
    nx, ny = values.get("mesh.nx", 10), values.get("mesh.ny", 7)
    overrides = [
        f"{k}={_json(v)}"
        for k, v in sorted(values.items())
        if k.startswith(MODAL) and k not in ("mesh.element", "mesh.nx", "mesh.ny")
    ]
    command = [
        "cargo",
        "run",
        "--release",
        "--quiet",
        "--example",
        "modes",
        "--",
        str(element),
        str(nx),
        str(ny),
        *overrides,
    ]
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({done.returncode}): {done.stderr.strip()}")
    text = done.stdout
    found = [
        float(line.split(":")[1].split()[0])
        for line in text.splitlines()
        if line.startswith("mode ")
    ]
    return found[:count]


def _json(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def write_csv(rows, path, param_names, columns=COLUMNS):
    """One line per row: config, the swept parameters, then columns[2:]."""
    header = ["config", *param_names] + columns[2:]
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            params = dict(row["params"])
            cells = [row["config"], *[params[n] for n in param_names]]
            cells += [row[c] for c in columns[2:]]
            f.write(",".join(repr(c) if isinstance(c, float) else str(c) for c in cells) + "\n")


# Up and down branches differ at a frequency when their RMS corners differ by more than this
# fraction of their mean and by more than BRANCH_SIGMAS of the spread of their difference, or when
# one branch impacts and the other does not. What is left of the previous dwell after the settling
# time decays like exp(-alpha*settle/2) of the jump, 0.7 % of it with alpha for 1 % in the first
# mode and 1.5 s: 3 % leaves a margin to it. A chaotic impacting response scatters from window to
# window; its spread (rms_corner_spread_m) measures by how much, and 3σ of the difference keeps a
# chance difference from being called a second branch (0.3 % per frequency if Gaussian).
BRANCH_TOLERANCE = 0.03
BRANCH_SIGMAS = 3.0


def branches_differ(up, down):
    """Whether the up and down rows of one frequency show different responses: the test that
    tells the steady states of scripts/converge apart (`converge.states.differ`), on the RMS
    corner with BRANCH_TOLERANCE and BRANCH_SIGMAS."""

    def stats(row):
        return {
            "impact_rate": (row["impacts_per_period"], 0.0),
            "rms_corner": (row["rms_corner_m"], row["rms_corner_spread_m"]),
        }

    return differ(stats(up), stats(down), ["rms_corner"], BRANCH_TOLERANCE, BRANCH_SIGMAS)


def hysteresis(rows):
    """Per (config, params): the frequencies at which the up and down branches differ."""
    found = {}
    for key in sorted({(r["config"], r["params"]) for r in rows}):
        sel = [r for r in rows if (r["config"], r["params"]) == key]
        up = {r["base.frequency"]: r for r in sel if r["direction"] == "up"}
        down = {r["base.frequency"]: r for r in sel if r["direction"] == "down"}
        found[key] = [f for f in sorted(up) if f in down and branches_differ(up[f], down[f])]
    return found


def plot_continuation(rows, modes_by_params, path, title):
    """RMS and peak corner, impacts and dissipation per period against frequency, up and down."""
    plt = pyplot()

    fig, axes = plt.subplots(
        4, 1, figsize=(9, 11), sharex=True, gridspec_kw={"height_ratios": [3, 2, 2, 2]}
    )
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    keys = sorted({(r["config"], r["params"]) for r in rows})
    differ = hysteresis(rows)
    panels = [
        ("rms_corner_m", 1e3, "RMS corner u(Lx, 0) (mm)"),
        ("peak_corner_m", 1e3, "peak free-corner |u| (mm)"),
        ("impacts_per_period", 1.0, "impacts per period"),
        ("dissipated_per_period_J", 1.0, "removed at the obstacles\nper period (J)"),
    ]
    for i, key in enumerate(keys):
        color = colors[i % len(colors)]
        label = ("with obstacles" if key[0] == "obstacles" else "without obstacles") + "".join(
            f", {k}={v}" for k, v in key[1]
        )
        for direction, style in (
            ("up", dict(ls="-", marker="^")),
            ("down", dict(ls="--", marker="v")),
        ):
            sel = [
                r for r in rows if (r["config"], r["params"]) == key and r["direction"] == direction
            ]
            sel.sort(key=lambda r: r["base.frequency"])
            f = [r["base.frequency"] for r in sel]
            for ax, (column, scale, _) in zip(axes, panels):
                ax.plot(
                    f,
                    [scale * r[column] for r in sel],
                    color=color,
                    lw=1.1,
                    ms=3.5,
                    label=f"{label}, sweeping {direction}",
                    **style,
                )
        for f in differ[key]:
            for ax in axes:
                ax.axvspan(f - 0.5, f + 0.5, color=color, alpha=0.12, lw=0)
    for combo in {k[1] for k in keys}:
        for k, fk in enumerate(modes_by_params.get(combo, [])):
            if (
                min(r["base.frequency"] for r in rows)
                <= fk
                <= max(r["base.frequency"] for r in rows)
            ):
                for ax in axes:
                    ax.axvline(fk, color="k", ls=":", lw=1)
                axes[0].annotate(
                    f"f{k + 1} = {fk:.1f} Hz",
                    (fk, 1),
                    xycoords=("data", "axes fraction"),
                    xytext=(3, -12),
                    textcoords="offset points",
                    fontsize=8,
                )
    for ax, (_, _, ylabel) in zip(axes, panels):
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
    axes[0].set_yscale("log")
    axes[0].legend(fontsize=7, loc="upper right")
    axes[0].set_title(
        title + "\nshaded: the two branches differ (RMS by more than "
        f"{BRANCH_TOLERANCE:.0%} and {BRANCH_SIGMAS:g}σ, or only one impacts)",
        fontsize=9,
    )
    axes[-1].set_xlabel("base frequency (Hz)")
    save(fig, path)


def plot(rows, modes_by_params, path, title):
    plt = pyplot()

    fig, (ax1, ax2) = plt.subplots(
        2, 1, figsize=(9, 7), sharex=True, gridspec_kw={"height_ratios": [3, 2]}
    )
    combos = sorted({row["params"] for row in rows})
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    styles = {"obstacles": dict(ls="-", marker="o", ms=3), "free": dict(ls="--", marker="", ms=0)}
    fmin = min(r["base.frequency"] for r in rows)
    fmax = max(r["base.frequency"] for r in rows)
    for i, combo in enumerate(combos):
        color = colors[i % len(colors)]
        suffix = "".join(f", {k}={v}" for k, v in combo)
        for config in ("obstacles", "free"):
            sel = [r for r in rows if r["params"] == combo and r["config"] == config]
            if not sel:
                continue
            f = [r["base.frequency"] for r in sel]
            label = ("with obstacles" if config == "obstacles" else "without obstacles") + suffix
            ax1.semilogy(
                f,
                [1e3 * r["peak_corner_m"] for r in sel],
                color=color,
                lw=1.2,
                label=label,
                **styles[config],
            )
            if config == "obstacles":
                ax2.plot(
                    f,
                    [r["dissipated_per_period_J"] for r in sel],
                    color=color,
                    lw=1.2,
                    marker="o",
                    ms=3,
                    label="dissipated per period" + suffix,
                )
        for k, fk in enumerate(modes_by_params.get(combo, [])):
            if fmin <= fk <= fmax:
                for ax in (ax1, ax2):
                    ax.axvline(fk, color=color, ls=":", lw=1)
                ax1.annotate(
                    f"f{k + 1} = {fk:.1f} Hz",
                    (fk, 1),
                    xycoords=("data", "axes fraction"),
                    xytext=(3, -12),
                    textcoords="offset points",
                    fontsize=8,
                    color=color,
                )
    ax1.set_ylabel("peak free-corner |u|, last half (mm)")
    ax1.set_title(title, fontsize=10)
    ax1.legend(fontsize=8, loc="upper right")
    ax1.grid(True, which="both", alpha=0.3)
    ax2.set_ylabel("energy dissipated per period (J)")
    ax2.set_xlabel("base frequency (Hz)")
    ax2.grid(True, alpha=0.3)
    save(fig, path)


# ----------------------------------------------------------------------------------------------
# Command line


def parse_frequencies(text):
    if ":" in text:
        start, stop, step = (float(x) for x in text.split(":"))
        count = int(round((stop - start) / step)) + 1
        return [round(start + i * step, 12) for i in range(count)]
    return [float(x) for x in text.split(",")]


def main(argv=None):
    parser = argparse.ArgumentParser(
        description=__doc__.splitlines()[0], formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    parser.add_argument(
        "--continuation",
        action="store_true",
        help="one instance per configuration sweeps up then down, carrying its "
        "state (writes continuation.csv and continuation.png)",
    )
    parser.add_argument(
        "--frequencies",
        help="start:stop:step or a comma list, Hz (default 5:120:1; with --continuation 30:90:1)",
    )
    parser.add_argument(
        "--amplitude",
        type=float,
        default=0.002,
        help="base amplitude c (m), default 0.002 (inside the ±0.01 m gap)",
    )
    parser.add_argument(
        "--zeta1",
        type=float,
        help="damping ratio of the first mode: sets damping.mass_proportional to "
        "2·zeta1·ω₁ with the library's ω₁ of the plate of the fixed "
        "parameters (default 0, the paper's undamped plate; with "
        "--continuation 0.01)",
    )
    parser.add_argument(
        "--stop-time",
        type=float,
        default=1.0,
        help="horizon T (s) of each run from rest, default 1",
    )
    parser.add_argument(
        "--settle",
        type=float,
        default=1.5,
        help="with --continuation: time (s) at each frequency before measuring",
    )
    parser.add_argument(
        "--measure",
        type=float,
        default=1.0,
        help="with --continuation: time (s) measured at each frequency",
    )
    parser.add_argument(
        "--comm-step",
        type=float,
        help="with --continuation: communication step (s), a multiple of "
        "solver.time_step (default: solver.time_step)",
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a fixed FMU parameter (repeatable)",
    )
    parser.add_argument(
        "--param",
        action="append",
        default=[],
        metavar="NAME=V1,V2,...",
        help="a further swept FMU parameter (repeatable; cartesian product)",
    )
    parser.add_argument(
        "--configs",
        default="obstacles,free",
        help="obstacles, free or both (default): the plate with/without obstacles",
    )
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--workers",
        type=int,
        default=os.cpu_count(),
        help="LocalCluster worker processes (default: the cores)",
    )
    group.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler")
    group.add_argument("--serial", action="store_true", help="no Dask, one run after the other")
    parser.add_argument("--no-modes", action="store_true", help="do not mark natural frequencies")
    parser.add_argument(
        "--out", default=str(ROOT / "out" / "sweep"), help="output folder for the CSV and the plot"
    )
    args = parser.parse_args(argv)

    from fmpy import read_model_description

    variables = {v.name: v for v in read_model_description(args.fmu).modelVariables}
    fixed = {}
    for item in args.set:
        name, _, text = item.partition("=")
        fixed[name] = parse_value(name, text, variables)
    grid = {}
    for item in args.param:
        name, _, text = item.partition("=")
        grid[name] = [parse_value(name, t, variables) for t in text.split(",")]
    configs = tuple(c for c in args.configs.split(",") if c)
    unknown = set(configs) - set(CONFIGS)
    if unknown:
        raise SystemExit(f"unknown configuration(s) {sorted(unknown)}: use obstacles and/or free")
    zeta1 = args.zeta1 if args.zeta1 is not None else (0.01 if args.continuation else 0.0)
    if zeta1 < 0:
        raise SystemExit(f"--zeta1 = {zeta1} must be >= 0")
    if zeta1 > 0:
        if "damping.mass_proportional" in fixed:
            raise SystemExit("give --zeta1 or --set damping.mass_proportional, not both")
        omega1 = 2 * math.pi * natural_frequencies(fixed, count=1)[0]
        fixed["damping.mass_proportional"] = 2 * zeta1 * omega1
    frequencies = parse_frequencies(
        args.frequencies or ("30:90:1" if args.continuation else "5:120:1")
    )
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    with dask_client(args.scheduler, args.workers, args.serial) as client:
        where = (
            f"scheduler {args.scheduler}"
            if args.scheduler
            else "serial"
            if args.serial
            else f"LocalCluster, {args.workers} workers"
        )
        print(
            f"{'continuation' if args.continuation else 'sweep'}: {len(frequencies)} frequencies"
            f" x {len(configs)} configurations x {int(np.prod([len(v) for v in grid.values()]))}"
            f" parameter sets on {where}",
            file=sys.stderr,
        )
        if args.continuation:
            rows = continuation(
                args.fmu,
                frequencies,
                amplitude=args.amplitude,
                fixed=fixed,
                param_grid=grid,
                configs=configs,
                settle=args.settle,
                measure=args.measure,
                step=args.comm_step,
                client=client,
            )
        else:
            fixed["base.amplitude"] = args.amplitude
            rows = sweep(
                args.fmu,
                frequencies,
                fixed=fixed,
                param_grid=grid,
                configs=configs,
                stop_time=args.stop_time,
                client=client,
            )

    modes = {}
    if not args.no_modes:
        for combo in sorted({row["params"] for row in rows}):
            values = dict(fixed)
            values.update(dict(combo))
            try:
                modes[combo] = natural_frequencies(values)
            except (OSError, RuntimeError) as e:
                print(f"natural frequencies not marked: {e}", file=sys.stderr)
    for combo, fs in modes.items():
        extra = _params_text(combo)
        print(
            f"natural frequencies{extra}: " + ", ".join(f"{f:.2f}" for f in fs) + " Hz",
            file=sys.stderr,
        )
    settings = ", ".join(
        f"{k}={v:.6g}" if isinstance(v, float) else f"{k}={v}" for k, v in sorted(fixed.items())
    )
    if args.continuation:
        write_csv(rows, out / "continuation.csv", list(grid), CONTINUATION_COLUMNS)
        plot_continuation(
            rows,
            modes,
            out / "continuation.png",
            f"PlateImpact swept up then down, c = {args.amplitude * 1e3:g} mm, "
            f"ζ₁ = {zeta1:g}, {args.settle:g} s + {args.measure:g} s per frequency"
            + (f" ({settings})" if settings else ""),
        )
        for (config, combo), fs in hysteresis(rows).items():
            extra = _params_text(combo)
            print(
                f"{config}{extra}: up and down branches differ at "
                + (", ".join(f"{f:g}" for f in fs) + " Hz" if fs else "no frequency"),
                file=sys.stderr,
            )
        print(f"wrote {out / 'continuation.csv'} and {out / 'continuation.png'}", file=sys.stderr)
        return
    write_csv(rows, out / "sweep.csv", list(grid))
    plot(
        rows,
        modes,
        out / "sweep.png",
        f"PlateImpact frequency sweep, T = {args.stop_time:g} s ({settings})",
    )
    for config in configs:
        for combo in sorted({row["params"] for row in rows}):
            sel = [r for r in rows if r["config"] == config and r["params"] == combo]
            best = max(sel, key=lambda r: r["peak_corner_m"])
            extra = _params_text(combo)
            print(
                f"{config}{extra}: largest response {1e3 * best['peak_corner_m']:.3f} mm at "
                f"{best['base.frequency']:g} Hz",
                file=sys.stderr,
            )
    print(f"wrote {out / 'sweep.csv'} and {out / 'sweep.png'}", file=sys.stderr)


if __name__ == "__main__":
    main()
