"""The cheapest converged settings for a user's scene, every steady state it has (the command
line of `scripts/converge`; docs/converge/README.md is the manual):

    scripts/converge --out DIR --quantity Q [--quantity Q ...] --tolerance REL --budget-seconds S
                     [--mesh] [--scheduler ADDRESS] [--scene FILE] [name=value ...]
                     [--transient S] [--window S] [--windows K] [--dt S] [--starts NAMES]

The scene is FMU start values: `name=value` arguments and/or a JSON or TOML file of them (flat,
{"solver.time_step": 1e-4}, or grouped like scenes/*.json, {"solver": {"time_step": 1e-4}}), the
names of modelDescription.xml; the arguments win over the file.

Quantities (statistics of a forced steady state, over K windows after a transient; every output
is read at the communication points, every h = the ladder's first Δt):

  mean_energy        J    time mean of energy.total
  rms_corner         m    RMS of corner1.displacement, u at the free corner (Lx, 0)
  peak_corner        m    max |u| over both free corners (Lx, 0) and (Lx, Ly)
  rms_base_force     N    RMS of base.mean_force, the plate's force on its base averaged over
                          each communication step (impulse / h)
  damping_loss_rate  W    energy taken out by damping per second: increase of
                          energy.damping_loss over a window / its length
  contact_loss_rate  W    energy taken out at the obstacles per second: the same with
                          energy.contact_loss
  impact_rate        1/s  impacts per second: Σ contact.impacts (internal steps whose contact
                          set went from empty to non-empty) over a window / its length

Per run, value and spread as the statistics study has them (`plateimpact_tools.windows`): the
value is the mean of the K window values (the peak: their maximum), the spread the standard
deviation of the window values / √K (the peak: of the window peaks).

Starts (`--starts`, default all): abrupt, ramp, sweep-up, sweep-down, kick
(`plateimpact_tools.converge.runs`). Method: `plateimpact_tools.converge.study`; the rule:
`plateimpact_tools.rule`; steady states: `plateimpact_tools.converge.states`.

Output: DIR/runs.csv (one row per run and quantity), DIR/report.md, DIR/work_precision.png;
progress on stderr; the last line of stdout `converged: ...` or `not converged: ...`.
"""

import argparse
import pathlib
import sys
import time

from plateimpact_tools import DEFAULT_FMU, scene_values
from plateimpact_tools.converge import report, runs
from plateimpact_tools.converge.study import Study
from plateimpact_tools.fmu_dask import dask_client
from plateimpact_tools.scene_values import parse_value
from plateimpact_tools.windows import QUANTITIES


def load_scene(path):
    """Start values from a JSON or TOML file, flat or grouped (module docs; `scene_values.read`).
    scenes/*.json also hold the library's own settings and the stop time, which are no FMU
    variables: skipped."""
    return scene_values.read(path)[0]


def parse(argv):
    parser = argparse.ArgumentParser(
        prog="scripts/converge",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=__doc__.split("\n\n", 1)[1],
    )
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument(
        "--quantity",
        action="append",
        required=True,
        choices=list(QUANTITIES),
        help="a quantity to converge (repeatable)",
    )
    parser.add_argument("--tolerance", type=float, required=True, help="relative tolerance")
    parser.add_argument(
        "--budget-seconds", type=float, required=True, help="CPU seconds the runs may take"
    )
    parser.add_argument(
        "--mesh", action="store_true", help="after Δt, refine the mesh of the scene's element too"
    )
    parser.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="an existing Dask scheduler (default: a LocalCluster)",
    )
    parser.add_argument("--workers", type=int, help="LocalCluster workers (default: the cores)")
    parser.add_argument("--serial", action="store_true", help="no Dask, one run after the other")
    parser.add_argument("--scene", help="a JSON or TOML file of start values")
    parser.add_argument(
        "--transient",
        type=float,
        help="time skipped before the windows (s); default 35 forcing periods",
    )
    parser.add_argument(
        "--window", type=float, help="length of one window (s); default 10 forcing periods"
    )
    parser.add_argument("--windows", type=int, default=8, help="number of windows K, default 8")
    parser.add_argument(
        "--dt",
        type=float,
        help="the ladder's first Δt (s), also the output interval; default the "
        "scene's solver.time_step",
    )
    parser.add_argument(
        "--starts",
        default=",".join(runs.START_NAMES),
        help=f"the starts run at every setting, comma-separated, of "
        f"{', '.join(runs.START_NAMES)} (default: all)",
    )
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    parser.add_argument("values", nargs="*", metavar="name=value", help="FMU start values")
    return parser, parser.parse_args(argv)


def scene_of(parser, args):
    """The start values of the command line: --scene's file, then the name=value arguments."""
    from fmpy import read_model_description

    variables = {v.name: v for v in read_model_description(args.fmu).modelVariables}
    scene = {}
    if args.scene:
        for name, value in load_scene(args.scene).items():
            scene[name] = parse_value(name, value, variables)
    for item in args.values:
        name, eq, text = item.partition("=")
        if not eq:
            parser.error(f"{item}: expected name=value")
        scene[name] = parse_value(name, text, variables)
    for name in scene:
        if variables[name].causality != "parameter":
            parser.error(f"{name} is not a parameter of the FMU ({variables[name].causality})")
    return scene, variables


def main(argv=None):
    parser, args = parse(argv)
    scene, variables = scene_of(parser, args)
    starts = [s for s in args.starts.split(",") if s]
    if args.tolerance <= 0 or args.budget_seconds <= 0 or args.windows < 2:
        parser.error("--tolerance and --budget-seconds must be > 0, --windows ≥ 2")
    if (
        not starts
        or any(s not in runs.START_NAMES for s in starts)
        or len(set(starts)) < len(starts)
    ):
        parser.error(f"--starts: distinct names of {', '.join(runs.START_NAMES)}")
    if args.mesh and "mesh.element" not in scene:
        scene["mesh.element"] = 1
    amplitude = float(scene.get("base.amplitude", 0.0))
    period = 1.0 / float(scene.get("base.frequency", float(variables["base.frequency"].start)))
    if amplitude == 0 and (args.transient is None or args.window is None):
        parser.error(
            "the scene has no base forcing (base.amplitude = 0): give --transient and --window"
        )
    dt0 = args.dt or float(
        scene.get("solver.time_step", float(variables["solver.time_step"].start))
    )
    study = Study(
        args.fmu,
        scene,
        dict.fromkeys(args.quantity),
        args.tolerance,
        args.budget_seconds,
        transient=args.transient if args.transient is not None else 35 * period,
        window=args.window if args.window is not None else 10 * period,
        windows=args.windows,
        dt0=dt0,
        mesh=args.mesh,
        start_names=starts,
    )
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    where = (
        f"the Dask scheduler {args.scheduler}"
        if args.scheduler
        else "one process"
        if args.serial
        else "a local Dask cluster"
    )
    started = time.perf_counter()
    with dask_client(args.scheduler, args.workers, args.serial) as client:
        verdict = study.run(client)
    wall = time.perf_counter() - started
    (out / "runs.csv").write_text(report.rows(study))
    command = "scripts/converge " + " ".join(argv if argv is not None else sys.argv[1:])
    (out / "report.md").write_text(report.markdown(study, command, f"{where} ({wall:.1f} s wall)"))
    report.plot(study, out / "work_precision.png")
    print(
        f"wrote {out / 'report.md'}, {out / 'runs.csv'}, {out / 'work_precision.png'}; "
        f"{study.spent:.1f} CPU s in {len(study.order)} runs, {wall:.1f} s wall",
        file=sys.stderr,
    )
    sys.stdout.flush()
    print(verdict)
