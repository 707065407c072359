"""Frequency sweep of the packaged PlateImpact FMU, one Dask task per run.

Sweeps `base.frequency` (and optionally other FMU parameters) for the plate between its obstacles
and for the same plate without them, and writes a CSV and a plot of the peak free-corner amplitude
against frequency with the library's natural frequencies marked.

    python examples/frequency_sweep.py [--frequencies 5:120:1] [--workers N | --scheduler ADDR | --serial]
                                       [--set name=value ...] [--param name=v1,v2,... ...]
                                       [--stop-time 1.0] [--out out/sweep]

Per run (columns of sweep.csv; times are communication points, one per internal step Δt):
  peak_corner_m     max |u| over both free corners (Lx, 0), (Lx, Ly) in the analysis window, the
                    last N whole forcing periods inside the last half of the horizon
                    (N = floor(f·T/2)); u is the absolute displacement the obstacles bound.
  impacts           rising edges of contact.active_nodes > 0 over the whole run
  impacts_window    the same, inside the analysis window
  dissipated_per_period_J
                    energy the obstacles take out per forcing period in the window (see
                    `dissipation` below): with forcing, energy.total is not conserved by itself,
                    the base works on the plate, so the loss is the base work minus the change of
                    energy.total, counted over the contact steps only (e = 0; see the README).
  energy_change_per_period_J
                    (E(end of window) − E(start))/N: ≈ 0 in a periodic steady state; a plate
                    still growing (the undamped resonance) or still in transient shows here.
  trajectory_sha256 digest of every recorded output: equal digests mean bit-identical runs.

Runs are independent FMU instances and the solver is deterministic, so results do not depend on
where or in which order tasks run; rows are sorted by configuration, swept parameters, frequency.
"""

import argparse
import dataclasses
import hashlib
import io
import itertools
import os
import pathlib
import shutil
import subprocess
import sys
import tempfile
import time
import zipfile

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
DEFAULT_FMU = ROOT / "target" / "fmu" / "PlateImpact.fmu"
OUTPUTS = ["corner1.displacement", "corner2.displacement", "energy.total", "contact.active_nodes"]
CONFIGS = {  # name -> start values that define it
    "obstacles": {"obstacle.lower_enabled": True, "obstacle.upper_enabled": True},
    "free": {"obstacle.lower_enabled": False, "obstacle.upper_enabled": False},
}
ELEMENT = {"argyris": 1, "fvs": 2}
# Parameters the natural frequencies depend on (passed to the modes example).
MODAL = ("plate.", "material.", "mesh.")
COLUMNS = ["config", "params", "base.frequency", "peak_corner_m", "impacts", "impacts_window",
           "periods", "dissipated_per_period_J", "energy_change_per_period_J", "max_active_nodes",
           "trajectory_sha256"]


# ----------------------------------------------------------------------------------------------
# One run (executed on a worker)

_EXTRACTED = {}


def _fmu_dir(fmu_blob, digest):
    """The FMU unpacked once per machine, keyed by its content digest (workers may be remote)."""
    if digest in _EXTRACTED:
        return _EXTRACTED[digest]
    target = pathlib.Path(tempfile.gettempdir()) / f"plateimpact-fmu-{digest[:16]}"
    if not (target / "modelDescription.xml").exists():
        staging = pathlib.Path(tempfile.mkdtemp(prefix="plateimpact-fmu-"))
        with zipfile.ZipFile(io.BytesIO(fmu_blob)) as archive:
            archive.extractall(staging)
        try:
            os.rename(staging, target)  # atomic; another process may have won the race
        except OSError:
            shutil.rmtree(staging, ignore_errors=True)
    _EXTRACTED[digest] = str(target)
    return str(target)


def _rising_edges(flag):
    flag = np.asarray(flag, dtype=bool)
    return int(np.count_nonzero(flag[1:] & ~flag[:-1]) + (1 if flag.size and flag[0] else 0))


def dissipation(energy, active):
    """Energy removed by the obstacles over a record sampled at every internal step.

    With the base moving, the change of energy.total over step k is ΔE_k = W_k − D_k: the work of
    the clamp on the plate minus what the contact removes. On a step with no vertex in contact at
    its start or end D_k = 0, so ΔE_k is the base work exactly (the β = ½ scheme conserves the
    discrete energy otherwise). On contact steps W_k is not observable from the outputs; it is a
    smooth function of time, so it is taken as the linear interpolation of the base work of the
    contact-free steps on either side of each run of contact steps. Returns Σ (Ŵ_k − ΔE_k) over the
    contact steps: exactly 0 without contact, an estimate of the impact losses otherwise (the
    contacts never add energy, for any solver.restitution, so D_k ≥ 0).
    """
    energy = np.asarray(energy, dtype=float)
    active = np.asarray(active) > 0
    d_energy = np.diff(energy)
    contact = active[1:] | active[:-1]
    if not contact.any():
        return 0.0
    steps = np.arange(d_energy.size)
    free = ~contact
    if not free.any():
        return float("nan")
    work = np.interp(steps[contact], steps[free], d_energy[free])
    return float(np.sum(work - d_energy[contact]))


def run_one(fmu_blob, digest, start_values, stop_time):
    """Simulates one parameter set, communicating at every internal step, and returns its summary
    (a dict of plain Python values) and the wall time."""
    import fmpy

    step = float(start_values.get("solver.time_step", 1e-4))
    directory = _fmu_dir(fmu_blob, digest)
    t0 = time.perf_counter()
    result = fmpy.simulate_fmu(directory, start_values=dict(start_values), stop_time=stop_time,
                               output_interval=step, output=OUTPUTS)
    wall = time.perf_counter() - t0
    t = result["time"]
    corners = np.maximum(np.abs(result["corner1.displacement"]),
                         np.abs(result["corner2.displacement"]))
    active = result["contact.active_nodes"]
    energy = result["energy.total"]
    frequency = float(start_values["base.frequency"])
    periods = int(np.floor(frequency * stop_time / 2.0 + 1e-9))
    n_last = len(t) - 1
    if periods > 0:
        first = int(round((stop_time - periods / frequency) / step))
    else:  # not one whole period in the last half: the window is the last half, no per-period terms
        first = int(round(0.5 * stop_time / step))
    window = slice(first, n_last + 1)
    digest_out = hashlib.sha256()
    for name in ["time"] + OUTPUTS:
        digest_out.update(np.ascontiguousarray(result[name]).tobytes())
    summary = {
        "peak_corner_m": float(corners[window].max()),
        "impacts": _rising_edges(active > 0),
        "impacts_window": _rising_edges(active[window] > 0),
        "periods": periods,
        "dissipated_per_period_J": (dissipation(energy[window], active[window]) / periods
                                    if periods else float("nan")),
        "energy_change_per_period_J": (float(energy[n_last] - energy[first]) / periods
                                       if periods else float("nan")),
        "max_active_nodes": int(active.max()),
        "trajectory_sha256": digest_out.hexdigest(),
    }
    return summary, wall


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


def sweep(fmu_path, frequencies, *, fixed=None, param_grid=None, configs=("obstacles", "free"),
          stop_time=1.0, client=None, progress=True):
    """Runs the sweep (serially if client is None, else as Dask tasks) and returns the rows,
    sorted by configuration, swept parameters and frequency, whatever order the runs finish in."""
    fixed = dict(fixed or {})
    param_grid = dict(param_grid or {})
    fmu_blob = pathlib.Path(fmu_path).read_bytes()
    digest = hashlib.sha256(fmu_blob).hexdigest()
    runs = plan(frequencies, configs, param_grid)
    done = {}
    started = time.perf_counter()

    def report(run, summary, wall):
        done[run] = summary
        if progress:
            extra = "".join(f" {k}={v}" for k, v in run.params)
            print(f"[{len(done):>{len(str(len(runs)))}}/{len(runs)}] {run.config:9s} f={run.frequency:g} Hz"
                  f"{extra}: peak {1e3 * summary['peak_corner_m']:.3f} mm, {summary['impacts']} impacts"
                  f" ({wall:.2f} s)", file=sys.stderr, flush=True)

    if client is None:
        for run in runs:
            report(run, *run_one(fmu_blob, digest, start_values_of(run, fixed), stop_time))
    else:
        from distributed import as_completed
        _ship_this_module(client)
        blob = client.scatter(fmu_blob, broadcast=True)
        futures = {}
        for run in runs:
            future = client.submit(run_one, blob, digest, start_values_of(run, fixed),
                                   stop_time, pure=False)
            futures[future] = run
        for future in as_completed(futures):
            report(futures[future], *future.result())
    if progress:
        print(f"{len(runs)} runs in {time.perf_counter() - started:.1f} s", file=sys.stderr)
    rows = []
    for run in runs:
        row = {"config": run.config, "params": run.params, "base.frequency": run.frequency}
        row.update(done[run])
        rows.append(row)
    return rows


def _ship_this_module(client):
    """Lets workers, local or remote, run this file's tasks. Run as a script its functions live in
    __main__ and Dask pickles them by value; imported (as the tests do) they are pickled by
    reference to this module, which the workers then need: upload_file sends it to each of them
    (and to the scheduler, which runs in this process on a LocalCluster)."""
    if __name__ != "__main__":
        client.upload_file(__file__, load=False)  # load=True would reload it in this process too


def local_cluster(workers):
    """A LocalCluster of single-threaded worker processes (one FMU run each at a time).

    The workers' statistical profiler is off: it samples the task thread's Python stack every
    10 ms, and fmpy's per-step loop is Python, so with it on 2 workers on 2 cores were no faster
    than one serial process (measured: 8.5 s against 7.8 s; 5.1 s with it off)."""
    import dask
    from distributed import LocalCluster
    with dask.config.set({"distributed.worker.profile.enabled": False}):
        return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                            dashboard_address=None)


def natural_frequencies(values, count=6):
    """The library's natural frequencies (Hz) of the plate the sweep runs, from the modes example."""
    element = values.get("mesh.element", 1)
    element = {v: k for k, v in ELEMENT.items()}.get(element, element)
    nx, ny = values.get("mesh.nx", 10), values.get("mesh.ny", 7)
    overrides = [f"{k}={_json(v)}" for k, v in sorted(values.items())
                 if k.startswith(MODAL) and k not in ("mesh.element", "mesh.nx", "mesh.ny")]
    command = ["cargo", "run", "--release", "--quiet", "--example", "modes", "--",
               str(element), str(nx), str(ny), *overrides]
    done = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(command)} failed ({done.returncode}): {done.stderr.strip()}")
    text = done.stdout
    found = [float(line.split(":")[1].split()[0]) for line in text.splitlines()
             if line.startswith("mode ")]
    return found[:count]


def _json(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value) if isinstance(value, float) else str(value)


def write_csv(rows, path, param_names):
    header = ["config", *param_names] + COLUMNS[2:]
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for row in rows:
            params = dict(row["params"])
            cells = [row["config"], *[params[n] for n in param_names]]
            cells += [row[c] for c in COLUMNS[2:]]
            f.write(",".join(repr(c) if isinstance(c, float) else str(c) for c in cells) + "\n")


def plot(rows, modes_by_params, path, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 7), sharex=True,
                                   gridspec_kw={"height_ratios": [3, 2]})
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
            ax1.semilogy(f, [1e3 * r["peak_corner_m"] for r in sel], color=color, lw=1.2,
                         label=label, **styles[config])
            if config == "obstacles":
                ax2.plot(f, [r["dissipated_per_period_J"] for r in sel], color=color, lw=1.2,
                         marker="o", ms=3, label="dissipated per period" + suffix)
        for k, fk in enumerate(modes_by_params.get(combo, [])):
            if fmin <= fk <= fmax:
                for ax in (ax1, ax2):
                    ax.axvline(fk, color=color, ls=":", lw=1)
                ax1.annotate(f"f{k + 1} = {fk:.1f} Hz", (fk, 1), xycoords=("data", "axes fraction"),
                             xytext=(3, -12), textcoords="offset points", fontsize=8, color=color)
    ax1.set_ylabel("peak free-corner |u|, last half (mm)")
    ax1.set_title(title, fontsize=10)
    ax1.legend(fontsize=8, loc="upper right")
    ax1.grid(True, which="both", alpha=0.3)
    ax2.set_ylabel("energy dissipated per period (J)")
    ax2.set_xlabel("base frequency (Hz)")
    ax2.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ----------------------------------------------------------------------------------------------
# Command line

def parse_value(name, text, variables):
    kind = variables[name].type if name in variables else None
    if kind is None:
        raise SystemExit(f"{name} is not a variable of the FMU")
    if kind == "Boolean":
        if text.lower() not in ("true", "false", "1", "0"):
            raise SystemExit(f"{name} is Boolean: true or false, not {text}")
        return text.lower() in ("true", "1")
    if kind == "Enumeration":
        return ELEMENT[text] if text in ELEMENT else int(text)
    if kind == "Integer":
        return int(text)
    return float(text)


def parse_frequencies(text):
    if ":" in text:
        start, stop, step = (float(x) for x in text.split(":"))
        count = int(round((stop - start) / step)) + 1
        return [round(start + i * step, 12) for i in range(count)]
    return [float(x) for x in text.split(",")]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    parser.add_argument("--frequencies", default="5:120:1",
                        help="start:stop:step or a comma list, Hz (default 5:120:1)")
    parser.add_argument("--amplitude", type=float, default=0.002,
                        help="base.amplitude c (m), default 0.002 (inside the ±0.01 m gap)")
    parser.add_argument("--stop-time", type=float, default=1.0, help="horizon T (s), default 1")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                        help="a fixed FMU parameter (repeatable)")
    parser.add_argument("--param", action="append", default=[], metavar="NAME=V1,V2,...",
                        help="a further swept FMU parameter (repeatable; cartesian product)")
    parser.add_argument("--configs", default="obstacles,free",
                        help="obstacles, free or both (default): the plate with/without obstacles")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--workers", type=int, default=os.cpu_count(),
                       help="LocalCluster worker processes (default: the cores)")
    group.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler")
    group.add_argument("--serial", action="store_true", help="no Dask, one run after the other")
    parser.add_argument("--no-modes", action="store_true", help="do not mark natural frequencies")
    parser.add_argument("--out", default=str(ROOT / "out" / "sweep"),
                        help="output folder for sweep.csv and sweep.png")
    args = parser.parse_args(argv)

    from fmpy import read_model_description
    variables = {v.name: v for v in read_model_description(args.fmu).modelVariables}
    fixed = {"base.amplitude": args.amplitude}
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
    frequencies = parse_frequencies(args.frequencies)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    client = cluster = None
    if args.scheduler:
        from distributed import Client
        client = Client(args.scheduler)
    elif not args.serial:
        from distributed import Client
        cluster = local_cluster(args.workers)
        client = Client(cluster)
    try:
        where = (f"scheduler {args.scheduler}" if args.scheduler else
                 "serial" if args.serial else f"LocalCluster, {args.workers} workers")
        print(f"sweep: {len(frequencies)} frequencies x {len(configs)} configurations"
              f" x {int(np.prod([len(v) for v in grid.values()]))} parameter sets on {where}",
              file=sys.stderr)
        rows = sweep(args.fmu, frequencies, fixed=fixed, param_grid=grid, configs=configs,
                     stop_time=args.stop_time, client=client)
    finally:
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()

    modes = {}
    if not args.no_modes:
        for combo in sorted({row["params"] for row in rows}):
            values = dict(fixed)
            values.update(dict(combo))
            try:
                modes[combo] = natural_frequencies(values)
            except (OSError, RuntimeError) as e:
                print(f"natural frequencies not marked: {e}", file=sys.stderr)
    write_csv(rows, out / "sweep.csv", list(grid))
    settings = ", ".join(f"{k}={v}" for k, v in sorted(fixed.items()))
    plot(rows, modes, out / "sweep.png",
         f"PlateImpact frequency sweep, T = {args.stop_time:g} s ({settings})")
    for combo, fs in modes.items():
        extra = "".join(f" {k}={v}" for k, v in combo)
        print(f"natural frequencies{extra}: " + ", ".join(f"{f:.2f}" for f in fs) + " Hz",
              file=sys.stderr)
    for config in configs:
        for combo in sorted({row["params"] for row in rows}):
            sel = [r for r in rows if r["config"] == config and r["params"] == combo]
            best = max(sel, key=lambda r: r["peak_corner_m"])
            extra = "".join(f" {k}={v}" for k, v in combo)
            print(f"{config}{extra}: largest response {1e3 * best['peak_corner_m']:.3f} mm at "
                  f"{best['base.frequency']:g} Hz", file=sys.stderr)
    print(f"wrote {out / 'sweep.csv'} and {out / 'sweep.png'}", file=sys.stderr)


if __name__ == "__main__":
    main()
