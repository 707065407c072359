"""The cheapest converged settings for a user's scene: refines the time step Δt (and, with --mesh,
the mesh of the chosen element) of the packaged PlateImpact FMU until the statistics asked for
stop changing, with each run's spread estimated from windows; runs on Dask. The command line is
`scripts/converge` (which runs `python -m plateimpact_tools.converge` with the project's Python
environment):

    scripts/converge --out DIR --quantity Q [--quantity Q ...] --tolerance REL --budget-seconds S
                     [--mesh] [--scheduler ADDRESS] [--scene FILE] [name=value ...]
                     [--transient S] [--window S] [--windows K] [--dt S] [--replicas R]

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

Per run, value and spread as the statistics study (examples/studies/statistics.rs) has them: the value is
the mean of the K window values (the peak: their maximum), the spread the standard deviation of
the window values / √K (the peak: of the window peaks), the standard error of what one run
reports. The check against perturbed replicas (R runs of a candidate setting whose
initial.preload_pressure differs by k·1e-4 Pa, k = 0 … R−1, about 1e-11 m of deflection, as in
the statistics study): its spread is raised to the replicas' standard deviation where larger.

Method (`Study`). Ladder Δt_k = Δt_0/2^k on the scene's mesh, Δt_0 = --dt (default the scene's
solver.time_step). A quantity has converged between two successive settings a (coarser) and b
(finer) when

    |v_a − v_b| + 2·σ_ab ≤ tol·|v_b|,   σ_ab = √(σ_a² + σ_b²),

i.e. they agree within the tolerance and their difference is resolved by the spread (known to 2σ,
about 95 %, inside the tolerance). A count (impact_rate) must also pass at the pair before (a's
coarser neighbour, a): in a periodic response its spread is 0 and equal counts pass, yet it can
change further down (docs/accuracy/damping.md); each ladder then starts with three settings, not
two. When every quantity has converged at the same pair, the replicas of b run; if the pair still
passes with their spread, b is recommended, the finer of the two: for a ladder that converges with
order p ≥ 1 its error is about |v_a − v_b|/(2^p − 1), at most the difference the report gives as
its estimated error. With --mesh the mesh ladder follows at that Δt, (nx, ny) → (⌈1.5·nx⌉,
⌈1.5·ny⌉) with the same test, then the Δt ladder again on the mesh found (from the pair 2Δt, Δt;
with a count 4Δt, 2Δt, Δt), and so on until a ladder passes at its first settings: the recommended
setting is then the finer member both of a passing Δt pair and of a passing mesh pair (a Δt
converged on a coarse mesh need not be on a fine one: the preset's RMS corner changes by 0.6 %
from Δt = 1e-4 to 5e-5 s on Argyris 2 × 1, by 0.9 % on 9 × 5). Runs not yet made at the start of
a ladder run in parallel, as do the replicas. The budget counts the CPU time of the runs (each
worker's thread time); a run is started only if the spent time plus its estimate (`estimate`)
fits, else the study stops: "not converged", with the trend along the last ladder (and, for Δt,
the observed order and extrapolated value) and advice: the FMU's own warning when the finest
setting run logged one at initialization (category logStatusWarning, "impact statistics may not
converge: …", src/advice.rs; the criterion is in docs/accuracy/damping.md), longer windows when the
spread is what fails, else more budget. Each run keeps the FMU's warning, and the report shows
which settings warned.

Output: DIR/runs.csv (one row per run and quantity), DIR/report.md, DIR/work_precision.png;
progress on stderr; the last line of stdout `converged: ...` or `not converged: ...`.
"""

import argparse
import math
import pathlib
import sys
import time
import uuid

import numpy as np

from plateimpact_tools import DEFAULT_FMU
from plateimpact_tools import scene_values
from plateimpact_tools.converge.cost import plate_size, run_cost
from plateimpact_tools.fmu_dask import dask_client, fmu_dir, run_tasks
from plateimpact_tools.plotting import pyplot, save
from plateimpact_tools.scene_values import ELEMENT, parse_value
from plateimpact_tools.windows import QUANTITIES, REALS, value_and_spread, window_values

# Counts: in a periodic response their window spread is 0, so two settings with the same count
# pass, yet the count can still change further down the ladder (docs/accuracy/damping.md, β only
# at 35 Hz: Argyris 14 × 10 counts 2, 2, 2.84 impacts per period at Δt = 1e-4, 1e-5, 1e-6 s).
# They must agree over one more level: both pairs ending at the recommended setting pass.
COUNTS = {"impact_rate"}

# The start of the warning the FMU logs at ExitInitializationMode (src/advice.rs) for settings
# whose impact statistics may not converge; the study passes it on as its advice.
ADVICE_PREFIX = "impact statistics may not converge"
# Replicas differ in initial.preload_pressure by this step (Pa), as in
# examples/studies/statistics.rs.
PERTURBATION_PA = 1e-4
# Confidence factor on the spread of a difference (2σ: about 95 % if Gaussian).
SIGMAS = 2.0
# The mesh ladder's refinement factor per direction: 2.25× the cells per level, about 3.8× the
# CPU per modal step by `run_cost` (n^1.6), where halving the cell size (2) would quadruple the
# cells and cost about 10×; the ladder then lands nearer the coarsest mesh that passes, while an
# error of order p in the cell size still shrinks to 1.5^-p per level (2/3 for p = 1), a change a
# pair can resolve.
MESH_FACTOR = 1.5
# Ladder lengths: Δt_0/2^12 and 5 mesh refinements (a 2 × 1 mesh reaches 16 × 8) are far beyond
# any budget on one machine; they only bound the loop.
MAX_DT_LEVELS = 12
MAX_MESH_LEVELS = 5
# With --mesh: mesh ladder, Δt ladder on the new mesh, … at most this many times each. A round
# that does not close has refined the mesh at least once more, so 4 rounds reach ≥ 1.5^4 ≈ 5 times
# the first round's mesh per direction (26× the cells, about 200× the CPU per modal step by
# `run_cost`, more across the switch to the sparse backend): like the ladder lengths, beyond a
# one-machine budget; the bound only ends the loop (the documented example closes in its first
# round).
MAX_ROUNDS = 4


# ----------------------------------------------------------------------------------------------
# One run (executed on a worker)

_CALLBACKS = []
# instance name -> [(category, message)] of the warnings and errors that instance logged.
_LOGGED = {}


def stderr_callbacks():
    """FMI callbacks whose logger prints the FMU's warnings and errors to stderr (fmpy's default
    prints to stdout, whose last line is the verdict) and keeps them in _LOGGED under the
    instance's name. One per process: fmpy's native logger proxy forwards every message to the last
    Python logger installed; the instance name tells apart runs in the threads of one worker."""
    if not _CALLBACKS:
        from ctypes import byref

        from fmpy.fmi1 import calloc, free
        from fmpy.fmi2 import (fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
        from fmpy.logging import addLoggerProxy

        def log(_env, instance, status, category, message):
            if status >= 1:  # fmi2Warning and worse
                print(f"[{category.decode()}] {message.decode()}", file=sys.stderr, flush=True)
                _LOGGED.setdefault(instance.decode(), []).append(
                    (category.decode(), message.decode()))

        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(log)
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(callbacks))
        _CALLBACKS.append(callbacks)
    return _CALLBACKS[0]


def run_setting(fmu_blob, digest, start_values, h, transient_steps, window_steps, windows):
    """Simulates the scene `start_values` communicating every `h` seconds (a multiple of its Δt):
    `transient_steps` steps, then `windows` windows of `window_steps` steps each. Returns
    ({"windows": {quantity: [K window values]}, "warning": w, "cpu": c}, c), w the FMU's warning
    at initialization that the impact statistics may not converge (None without one), c the CPU
    seconds of this thread (the FMU runs single-threaded in it)."""
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.simulation import apply_start_values

    directory = fmu_dir(fmu_blob, digest)
    md = read_model_description(directory)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    cpu0 = time.thread_time()
    instance = f"converge-{uuid.uuid4().hex}"
    fmu = FMU2Slave(guid=md.guid, unzipDirectory=directory,
                    modelIdentifier=md.coSimulation.modelIdentifier, instanceName=instance)
    n = windows * window_steps
    reals = np.empty((n + 1, len(REALS)))
    impacts = np.zeros(n + 1, dtype=np.int64)
    try:
        fmu.instantiate(callbacks=stderr_callbacks())
        fmu.setupExperiment(startTime=0.0)
        unknown = apply_start_values(fmu, md, dict(start_values))
        if unknown:
            raise ValueError(f"not variables of the FMU: {sorted(unknown)}")
        fmu.enterInitializationMode()
        fmu.exitInitializationMode()
        warning = next((message for category, message in _LOGGED.get(instance, [])
                        if category == "logStatusWarning" and message.startswith(ADVICE_PREFIX)),
                       None)
        real_vrs = [vr[name] for name in REALS]
        impacts_vr = [vr["contact.impacts"]]
        for k in range(transient_steps):
            fmu.doStep(currentCommunicationPoint=k * h, communicationStepSize=h)
        reals[0] = fmu.getReal(real_vrs)
        for j in range(n):
            fmu.doStep(currentCommunicationPoint=(transient_steps + j) * h, communicationStepSize=h)
            reals[j + 1] = fmu.getReal(real_vrs)
            impacts[j + 1] = fmu.getInteger(impacts_vr)[0]
        fmu.terminate()
    finally:
        fmu.freeInstance()
        _LOGGED.pop(instance, None)
    cpu = time.thread_time() - cpu0
    return {"windows": window_values(reals, impacts, window_steps * h, windows),
            "warning": warning, "cpu": cpu}, cpu


# ----------------------------------------------------------------------------------------------
# The study (client side)

def observed_order(values):
    """For the last three values of a ladder that halves Δt: the observed order
    p = log2(|v_1 − v_0| / |v_2 − v_1|) and the extrapolated limit v_2 + (v_2 − v_1)/(2^p − 1)
    (Richardson), as text; nothing when the changes do not shrink (no order to speak of)."""
    d1, d2 = values[1] - values[0], values[2] - values[1]
    if d2 == 0 or d1 == 0 or d1 * d2 < 0 or abs(d2) >= abs(d1):
        return ""
    p = math.log2(d1 / d2)
    return f"; observed order {p:.2g}, extrapolated {values[2] + d2 / (2 ** p - 1):.4g}"


def refine_mesh(nx, ny):
    return math.ceil(MESH_FACTOR * nx), math.ceil(MESH_FACTOR * ny)


class Study:
    """The ladders, their runs and the decisions (module docs). A setting is (nx, ny, Δt); a run
    is a setting and its replica index. `run(client)` returns the verdict line; `rows`, `report`
    and `plot` give the outputs."""

    def __init__(self, fmu, scene, quantities, tolerance, budget, *, transient, window, windows,
                 dt0, mesh, replicas, progress=True):
        self.fmu, self.scene, self.quantities = fmu, dict(scene), list(quantities)
        self.tolerance, self.budget, self.mesh, self.replicas = tolerance, budget, mesh, replicas
        self.dt0 = self.h = dt0
        self.transient_steps = round(transient / dt0)
        self.window_steps = max(1, round(window / dt0))
        self.windows = windows
        # Settings a ladder starts with: one more for a count (COUNTS), so that it can settle.
        self.span = 3 if COUNTS & set(self.quantities) else 2
        self.simulated = (self.transient_steps + windows * self.window_steps) * dt0
        self.progress = progress
        self.element = int(self.scene.get("mesh.element", 1))
        self.mesh0 = (int(self.scene.get("mesh.nx", 10)), int(self.scene.get("mesh.ny", 7)))
        self.results = {}  # (nx, ny, dt, replica) -> result of run_setting
        self.order = []  # the runs in the order they were submitted
        self.phase_of = {}  # run -> the ladder that ran it
        self.spent = 0.0
        self.ladders = []  # (name, [settings in ladder order]) in the order they were climbed
        self.passes = {}  # ladder name -> {quantity: the finer setting of its first passing pair}
        self.replica_spread = {}  # setting -> {quantity: standard deviation over the replicas}
        self.recommended = None
        self.verdict = None
        self.trends, self.advice = [], ""

    # -- runs

    def start_values(self, run):
        nx, ny, dt, replica = run
        values = dict(self.scene, **{"mesh.nx": nx, "mesh.ny": ny, "solver.time_step": dt})
        if replica:
            preload = float(self.scene.get("initial.preload_pressure", 0.0))
            values["initial.preload_pressure"] = preload + replica * PERTURBATION_PA
        return values

    def execute(self, client, phase, runs):
        """Runs those of `runs` not run yet, in parallel on the client."""
        runs = [r for r in runs if r not in self.results]
        tasks = [(run, run_setting, (self.start_values(run), self.h, self.transient_steps,
                                     self.window_steps, self.windows)) for run in runs]
        done = run_tasks(self.fmu, tasks, client)
        for run in runs:
            result = done[run]
            self.results[run] = result
            self.order.append(run)
            self.phase_of[run] = phase
            self.spent += result["cpu"]
            if self.progress:
                q = self.quantities[0]
                v, sd = value_and_spread(q, result["windows"][q])
                print(f"  {phase}: {self.describe(run[:3])}"
                      + (f", replica {run[3]}" if run[3] else "")
                      + f": {q} = {v:.6g} ± {sd:.2g}, CPU {result['cpu']:.2f} s; spent "
                      f"{self.spent:.1f} of {self.budget:g} CPU s", file=sys.stderr, flush=True)

    def value(self, setting, quantity):
        """(value, spread) of a setting: the unperturbed run's, the spread raised to the replicas'
        standard deviation where they ran."""
        v, s = value_and_spread(quantity, self.results[setting + (0,)]["windows"][quantity])
        extra = self.replica_spread.get(setting, {}).get(quantity)
        if extra is not None and not math.isnan(extra):
            s = extra if math.isnan(s) else max(s, extra)
        return v, s

    def cost(self, setting):
        return self.results[setting + (0,)]["cpu"]

    def size(self, setting):
        """(free dofs, backend) of a setting's plate, as the FMU reports them (`cost.plate_size`)."""
        nx, ny, _ = setting
        return plate_size(self.fmu, dict(self.scene, **{"mesh.nx": nx, "mesh.ny": ny}))

    def estimate(self, known, setting):
        """CPU seconds of `setting` from those of the run setting `known`: its cost times the
        ratio of the two settings' model costs (`cost.run_cost`), each on the free dofs and the
        backend the FMU reports for its mesh (`size`). Within the modal backend a step grows like
        n^1.6 and the set-up like n^2.2–2.7; across the switch an internal step costs some 50 to 100
        times more (Argyris 20 × 10, 1951 free dofs, modal: 35 µs; 21 × 12, 2428, sparse:
        1655 µs). Halving Δt doubles the internal steps but not the set-up nor the communication
        steps (h is fixed). On small meshes fmpy's cost per output dominates, which the model's
        communication step does not fully hold (docs/converge example: Argyris 4 × 2 → 9 × 5, 5.6×
        the cells, 2.1× the CPU), so there the estimate errs towards stopping early."""
        e, simulated, h = self.element, self.simulated, self.h
        return self.cost(known) * (run_cost(self.size(setting), e, setting[2], simulated, h)
                                   / run_cost(self.size(known), e, known[2], simulated, h))

    # -- decisions

    def check(self, a, b, quantity):
        """(passes, |v_a − v_b|/|v_b|, 2σ_ab/|v_b|) for the pair (a, b) of successive settings."""
        va, sa = self.value(a, quantity)
        vb, sb = self.value(b, quantity)
        sigma = SIGMAS * math.hypot(sa, sb)
        diff = abs(va - vb)
        scale = abs(vb)
        passes = diff + sigma <= self.tolerance * scale
        rel = (lambda x: x / scale if scale > 0 else (0.0 if x == 0 else math.inf))
        return passes, rel(diff), rel(sigma)

    def settled(self, ladder, quantity):
        """Whether `quantity` passes at the ladder's last pair and, for a count (COUNTS), at the
        pair before it too."""
        if not self.check(ladder[-2], ladder[-1], quantity)[0]:
            return False
        return quantity not in COUNTS or (len(ladder) >= 3
                                          and self.check(ladder[-3], ladder[-2], quantity)[0])

    def fits(self, estimate):
        return self.spent + estimate <= self.budget

    def climb(self, client, phase, ladder, refine, levels, reference):
        """Climbs one ladder from the settings `ladder` (≥ 2; those not run yet are run first,
        their cost estimated from the setting `reference`) until every quantity passes at one pair
        (a, b) (a count also at the pair before, `settled`) and, with replicas, still passes with
        the replicas' spread of b. Returns b, or None with the verdict set when the budget or the
        ladder ends first."""
        ladder = list(ladder)
        self.ladders.append((phase, ladder))
        passes = self.passes.setdefault(phase, {})
        missing = [s for s in ladder if s + (0,) not in self.results]
        if missing:
            guess = sum(self.estimate(reference, s) for s in missing) if reference else 0.0
            if reference and not self.fits(guess):
                return self.stop(phase, f"running {', '.join(map(self.describe, missing))} (about "
                                 f"{guess:.3g} CPU s) would exceed the budget")
            self.execute(client, phase, [s + (0,) for s in missing])
        while True:
            b = ladder[-1]
            settled = {q: self.settled(ladder, q) for q in self.quantities}
            for q, ok in settled.items():
                if ok and q not in passes:
                    passes[q] = b
            if all(settled.values()):
                if self.replicas > 1 and b not in self.replica_spread:
                    guess = (self.replicas - 1) * self.cost(b)
                    if not self.fits(guess):
                        return self.stop(phase, f"the replica check of {self.describe(b)} (about "
                                         f"{guess:.3g} CPU s) would exceed the budget")
                    self.execute(client, phase, [b + (k,) for k in range(1, self.replicas)])
                    self.replica_spread[b] = {}
                    for q in QUANTITIES:
                        replicas = [value_and_spread(q, self.results[b + (k,)]["windows"][q])[0]
                                    for k in range(self.replicas)]
                        self.replica_spread[b][q] = float(np.std(replicas, ddof=1))
                    continue  # the pair again, with the replicas' spread
                return b
            if len(ladder) >= levels:
                return self.stop(phase, f"the ladder ended at {self.describe(b)}")
            nxt = refine(b)
            guess = self.estimate(b, nxt)
            if not self.fits(guess):
                return self.stop(phase, f"the next refinement, {self.describe(nxt)} (about "
                                 f"{guess:.3g} CPU s), would exceed the budget")
            ladder.append(nxt)
            self.execute(client, phase, [nxt + (0,)])

    def run(self, client):
        """The Δt ladder; with --mesh then the mesh ladder at the Δt found, then Δt again on the
        mesh found, and so on, until the recommended setting b is the finer member both of a
        passing Δt pair (b with 2Δt) and of a passing mesh pair (b with the previous mesh)."""
        def halve(s):
            return s[0], s[1], s[2] / 2

        def finer_mesh(s):
            return refine_mesh(s[0], s[1]) + (s[2],)

        nx, ny = self.mesh0
        rec = self.climb(client, "dt-1", [(nx, ny, self.dt0 / 2 ** k) for k in range(self.span)],
                         halve, MAX_DT_LEVELS, None)
        meshes = [self.mesh0]  # the mesh ladder so far
        for round_ in range(1, MAX_ROUNDS + 1):
            if rec is None or not self.mesh:
                break
            # The span of meshes ending at rec's (the first round: rec's and the next ones).
            if len(meshes) == 1:
                start = [rec]
                while len(start) < self.span:
                    start.append(finer_mesh(start[-1]))
            else:
                start = [m + rec[2:] for m in meshes[-self.span:-1]] + [rec]
            new = self.climb(client, f"mesh-{round_}", start, finer_mesh,
                             MAX_MESH_LEVELS + 1, rec)
            if new is None or new == rec:
                rec = new
                break
            ladder = self.ladders[-1][1]
            meshes = [s[:2] for s in ladder]
            rec = new
            start = [rec[:2] + (rec[2] * 2 ** k,) for k in range(self.span - 1, -1, -1)]
            new = self.climb(client, f"dt-{round_ + 1}", start, halve, MAX_DT_LEVELS, rec)
            if new is None or new == rec:
                rec = new
                break
            rec = new
        else:
            if self.mesh and rec is not None:
                # Each round moved both ladders: the last Δt found was never checked in the mesh.
                return self.stop(f"dt-{MAX_ROUNDS + 1}", f"the mesh and Δt ladders alternated "
                                 f"{MAX_ROUNDS} times without both passing at one setting")
        if rec is None:
            return self.verdict
        self.recommended = rec
        values = ", ".join(f"{q} = {self.value(rec, q)[0]:.6g} {QUANTITIES[q][0]}"
                           for q in self.quantities)
        self.verdict = (f"converged: {values}; settings {self.settings_text(rec)}; cost "
                        f"{self.cost(rec) / self.simulated:.3g} CPU s per simulated s")
        return self.verdict

    # -- words

    def describe(self, setting):
        nx, ny, dt = setting
        name = {v: k for k, v in ELEMENT.items()}.get(self.element, self.element)
        return f"{name} {nx}x{ny}, Δt = {dt:.4g} s"

    def settings_text(self, setting):
        nx, ny, dt = setting
        return f"mesh.element={self.element} mesh.nx={nx} mesh.ny={ny} solver.time_step={dt:.6g}"

    def stop(self, phase, why):
        ladder = self.ladders[-1][1]
        ladder = [s for s in ladder if s + (0,) in self.results]
        spread_limited = []
        for q in self.quantities:
            unit = QUANTITIES[q][0]
            values = [self.value(s, q)[0] for s in ladder]
            text = " → ".join(f"{v:.4g}" for v in values) + f" {unit}"
            if len(ladder) >= 2:
                ok, diff, sigma = self.check(ladder[-2], ladder[-1], q)
                text += (f" (last refinement {'passes' if ok else 'fails'}: change "
                         f"{100 * diff:.2g} %, 2σ {100 * sigma:.2g} %")
                if ok and not self.settled(ladder, q):
                    text += "; a count also needs the refinement before it to pass"
                if len(values) >= 3 and phase.startswith("dt") and diff > sigma:
                    text += observed_order(values[-3:])  # only for a change the spread resolves
                text += ")"
                if not ok and sigma > self.tolerance:
                    spread_limited.append(q)
            self.trends.append(f"{q} {text}")
        # The finest setting run: smallest Δt, then most cells.
        finest = min(ladder, key=lambda s: (s[2], -s[0] * s[1]))
        warning = self.results[finest + (0,)]["warning"]
        if warning:
            advice = f"the FMU warns at {self.describe(finest)}: {warning}"
        elif spread_limited:
            advice = (f"the spread of {', '.join(spread_limited)} exceeds the tolerance: longer or "
                      "more windows (--window, --windows), or a looser --tolerance")
        else:
            advice = ("the values still move: raise --budget-seconds, start the ladder lower "
                      "(--dt) or loosen --tolerance")
        self.advice = advice
        self.verdict = (f"not converged: {phase}: {why} (spent {self.spent:.1f} of "
                        f"{self.budget:g} CPU s); trend: {'; '.join(self.trends)}; "
                        f"advice: {advice}")
        return None

    # -- outputs

    def rows(self):
        header = ["ladder", "element", "nx", "ny", "dt", "replica", "quantity", "value", "spread",
                  "cpu_s", "simulated_s"]
        lines = [",".join(header)]
        for run in self.order:
            nx, ny, dt, replica = run
            result = self.results[run]
            for q in self.quantities:
                v, s = value_and_spread(q, result["windows"][q])
                lines.append(",".join(str(x) for x in (
                    self.phase_of[run], self.element, nx, ny, repr(dt), replica, q, repr(v),
                    repr(s), f"{result['cpu']:.3f}", repr(self.simulated))))
        return "\n".join(lines) + "\n"

    def report(self, command, where):
        lines = ["# Convergence study", "", f"Command: `{command}`", "",
                 f"Run on {where}. Scene (start values): "
                 + (", ".join(f"`{k}={v}`" for k, v in sorted(self.scene.items())) or "defaults"),
                 "",
                 f"Windows: {self.transient_steps * self.h:.4g} s of transient, then "
                 f"{self.windows} windows of {self.window_steps * self.h:.4g} s; outputs read "
                 f"every {self.h:.4g} s. Tolerance {self.tolerance:g} (relative); a pair of successive "
                 f"settings passes when |v_a − v_b| + {SIGMAS:g}σ_ab ≤ tol·|v_b|. Budget "
                 f"{self.budget:g} CPU s, spent {self.spent:.1f} CPU s in {len(self.order)} runs.",
                 "", f"**{self.verdict}**", ""]
        if self.recommended is not None:
            rec = self.recommended
            partners = [ladder[ladder.index(rec) - 1] for _, ladder in self.ladders
                        if rec in ladder and ladder.index(rec) > 0]
            lines += [f"Recommended: {self.describe(rec)} (`{self.settings_text(rec)}`), "
                      f"{self.cost(rec) / self.simulated:.3g} CPU s per simulated second; checked "
                      f"against {' and '.join(map(self.describe, partners))}.", "",
                      "| quantity | unit | value | estimated error (largest change to it) | "
                      "spread (1σ) | first passing setting per ladder |",
                      "|---|---|---|---|---|---|"]
            for q in self.quantities:
                v, sd = self.value(rec, q)
                error = max(abs(v - self.value(p, q)[0]) for p in partners)
                own = [f"{name}: {self.describe(found[q])}" for name, found in self.passes.items()
                       if q in found]
                lines.append(f"| {q} | {QUANTITIES[q][0]} | {v:.6g} | {error:.3g} "
                             f"({100 * error / abs(v) if v else 0:.2g} %) | {sd:.3g} | "
                             f"{'; '.join(own)} |")
            lines.append("")
            warning = self.results[rec + (0,)]["warning"]
            if warning:
                lines += [f"The FMU warns at the recommended setting: {warning}", ""]
        else:
            lines += ["Trend along the last ladder:", ""] + [f"- {t}" for t in self.trends]
            lines += ["", f"Advice: {self.advice}", ""]
        lines += ["## Runs", "", "| ladder | setting | replica | CPU s | FMU warns | "
                  + " | ".join(f"{q} ({QUANTITIES[q][0]})" for q in self.quantities) + " |",
                  "|---|---|---|---|---|" + "---|" * len(self.quantities)]
        for run in self.order:
            result = self.results[run]
            cells = []
            for q in self.quantities:
                v, sd = value_and_spread(q, result["windows"][q])
                cells.append(f"{v:.6g} ± {sd:.2g}")
            lines.append(f"| {self.phase_of[run]} | {self.describe(run[:3])} | {run[3]} | "
                         f"{result['cpu']:.2f} | {'yes' if result['warning'] else 'no'} | "
                         + " | ".join(cells) + " |")
        lines += ["", f"FMU warns: whether the FMU logged \"{ADVICE_PREFIX} …\" at initialization "
                  "(src/advice.rs, docs/accuracy/damping.md)."]
        if self.replica_spread:
            lines += ["", "Replica check (standard deviation over the replicas against the run's "
                      "window spread):", ""]
            for setting, spreads in self.replica_spread.items():
                for q in self.quantities:
                    _, window = value_and_spread(q, self.results[setting + (0,)]["windows"][q])
                    lines.append(f"- {self.describe(setting)}, {q}: replicas {spreads[q]:.3g}, "
                                 f"windows {window:.3g} {QUANTITIES[q][0]}")
        lines += ["", "Quantities:", ""] + [f"- `{q}` ({u}): {d}" for q, (u, d) in
                                            QUANTITIES.items() if q in self.quantities]
        lines += ["", "Method and definitions: docs/converge/README.md. Plot: work_precision.png.",
                  ""]
        return "\n".join(lines)

    def plot(self, path):
        """Work-precision: each run setting's relative difference from the reference (the
        recommended setting, or else the last one run), with 2σ error bars, against its CPU seconds
        per simulated second; the settings of each ladder joined in ladder order."""
        plt = pyplot()

        fig, ax = plt.subplots(figsize=(7.5, 5))
        colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        styles = ["o-", "s--", "^-.", "v:", "D-", "P--"]
        reference = self.recommended or self.order[-1][:3]
        for i, q in enumerate(self.quantities):
            ref, _ = self.value(reference, q)
            for j, (phase, ladder) in enumerate(self.ladders):
                xs, ys, lo, hi = [], [], [], []
                for s in ladder:
                    if s + (0,) not in self.results:
                        continue
                    v, sd = self.value(s, q)
                    if ref and v != ref:
                        xs.append(self.cost(s) / self.simulated)
                        ys.append(abs(v - ref) / abs(ref))
                        hi.append(SIGMAS * sd / abs(ref))
                        lo.append(min(hi[-1], 0.999 * ys[-1]))  # a log axis has no 0
                if xs:
                    ax.errorbar(xs, ys, yerr=[lo, hi], fmt=styles[j % len(styles)],
                                color=colors[i % len(colors)], ms=4, capsize=2,
                                label=f"{q}, {phase}")
        if self.recommended is not None:
            ax.axvline(self.cost(self.recommended) / self.simulated, color="k", ls=":", lw=1,
                       label=f"recommended, {self.describe(self.recommended)}")
        ax.axhline(self.tolerance, color="gray", lw=1, label=f"tolerance {self.tolerance:g}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU seconds per simulated second")
        ax.set_ylabel(f"|value − value at {self.describe(reference)}| / |that value|")
        ax.set_title(f"PlateImpact convergence study: {self.verdict.split(':')[0]} "
                     f"(tolerance {self.tolerance:g})", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        save(fig, path)


# ----------------------------------------------------------------------------------------------
# Command line

def load_scene(path):
    """Start values from a JSON or TOML file, flat or grouped (module docs; `scene_values.read`).
    scenes/*.json also hold the library's own settings and the stop time, which are no FMU
    variables: skipped."""
    return scene_values.read(path)[0]


def main(argv=None):
    parser = argparse.ArgumentParser(prog="scripts/converge", description=__doc__.splitlines()[0],
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog=__doc__.split("\n\n", 1)[1])
    parser.add_argument("--out", required=True, help="output folder")
    parser.add_argument("--quantity", action="append", required=True, choices=list(QUANTITIES),
                        help="a quantity to converge (repeatable)")
    parser.add_argument("--tolerance", type=float, required=True, help="relative tolerance")
    parser.add_argument("--budget-seconds", type=float, required=True,
                        help="CPU seconds the runs may take")
    parser.add_argument("--mesh", action="store_true",
                        help="after Δt, refine the mesh of the scene's element too")
    parser.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler "
                        "(default: a LocalCluster)")
    parser.add_argument("--workers", type=int, help="LocalCluster workers (default: the cores)")
    parser.add_argument("--serial", action="store_true", help="no Dask, one run after the other")
    parser.add_argument("--scene", help="a JSON or TOML file of start values")
    parser.add_argument("--transient", type=float,
                        help="time skipped before the windows (s); default 35 forcing periods")
    parser.add_argument("--window", type=float,
                        help="length of one window (s); default 10 forcing periods")
    parser.add_argument("--windows", type=int, default=8, help="number of windows K, default 8")
    parser.add_argument("--dt", type=float,
                        help="the ladder's first Δt (s), also the output interval; default the "
                             "scene's solver.time_step")
    parser.add_argument("--replicas", type=int, default=3,
                        help="perturbed runs R of the recommended setting (1: no check), default 3")
    parser.add_argument("--fmu", default=str(DEFAULT_FMU))
    parser.add_argument("values", nargs="*", metavar="name=value", help="FMU start values")
    args = parser.parse_args(argv)

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
    for name, value in list(scene.items()):
        if variables[name].causality != "parameter":
            parser.error(f"{name} is not a parameter of the FMU ({variables[name].causality})")
    if args.tolerance <= 0 or args.budget_seconds <= 0 or args.windows < 2 or args.replicas < 1:
        parser.error("--tolerance and --budget-seconds must be > 0, --windows ≥ 2, --replicas ≥ 1")
    if args.mesh and "mesh.element" not in scene:
        scene["mesh.element"] = 1
    amplitude = float(scene.get("base.amplitude", 0.0))
    period = 1.0 / float(scene.get("base.frequency", float(variables["base.frequency"].start)))
    if amplitude == 0 and (args.transient is None or args.window is None):
        parser.error("the scene has no base forcing (base.amplitude = 0): give --transient and "
                     "--window")
    dt0 = args.dt or float(scene.get("solver.time_step",
                                     float(variables["solver.time_step"].start)))
    study = Study(args.fmu, scene, dict.fromkeys(args.quantity), args.tolerance,
                  args.budget_seconds,
                  transient=args.transient if args.transient is not None else 35 * period,
                  window=args.window if args.window is not None else 10 * period,
                  windows=args.windows, dt0=dt0, mesh=args.mesh, replicas=args.replicas)
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    where = (f"the Dask scheduler {args.scheduler}" if args.scheduler else "one process"
             if args.serial else f"a local Dask cluster")
    started = time.perf_counter()
    with dask_client(args.scheduler, args.workers, args.serial) as client:
        verdict = study.run(client)
    wall = time.perf_counter() - started
    (out / "runs.csv").write_text(study.rows())
    command = "scripts/converge " + " ".join(argv if argv is not None else sys.argv[1:])
    (out / "report.md").write_text(study.report(command, f"{where} ({wall:.1f} s wall)"))
    study.plot(out / "work_precision.png")
    print(f"wrote {out / 'report.md'}, {out / 'runs.csv'}, {out / 'work_precision.png'}; "
          f"{study.spent:.1f} CPU s, {wall:.1f} s wall", file=sys.stderr)
    sys.stdout.flush()
    print(verdict)


if __name__ == "__main__":
    main()
