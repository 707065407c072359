"""The cheapest converged settings for a user's scene: refines the time step Δt (and, with --mesh,
the mesh of the chosen element) of the packaged PlateImpact FMU, each setting run from several
starts, until every steady state the starts reach has stopped changing in every statistic asked
for. docs/converge/README.md is the manual; this is the method.

Settings and ladders. A setting is (nx, ny, Δt); the Δt ladder halves Δt from Δt_0 (--dt, default
the scene's solver.time_step) on the scene's mesh; with --mesh the mesh ladder then refines the
mesh of the scene's element at the Δt found, (nx, ny) → (⌈1.5·nx⌉, ⌈1.5·ny⌉), then the Δt ladder
again on the mesh found, from (4Δt, 2Δt, Δt), and so on until a ladder passes at its first three
settings: the recommended setting is the last of both a passing Δt ladder and a passing mesh
ladder (a Δt converged on a coarse mesh need not be on a fine one: the preset's RMS corner changes
by 0.6 % from Δt = 1e-4 to 5e-5 s on Argyris 2 × 1, by 0.9 % on 9 × 5).

At every setting each start of `runs.starts` runs (in parallel on Dask); the runs are grouped
into steady states (`states.group`) at the ladder's last setting, and each state is followed down
the ladder by its starts (`states.state_value`). A ladder passes when, for every state and every
quantity, the rule of `rule.judge` accepts the last three settings (trusting an observed order of
convergence only where the FMU does not warn at any of them) and the state's starts impact at
all three settings or at none (a branch switch between impacting and quiet states is no
convergence). Each ladder therefore starts with three settings run at once.

Budget: the CPU time of the runs (each worker's thread time) is added up; a setting is started
only if the spent time plus its estimate (`estimate`, the cost model of `cost`) fits, else the
study stops: "not converged", with each state's trend and advice: the FMU's own warning when the
finest setting run logged one at initialization (category logStatusWarning, "impact statistics
may not converge: …", src/advice.rs; the criterion is in docs/accuracy/damping.md), longer windows
when the spread is what fails, else more budget.
"""

import math
import sys

from plateimpact_tools import rule
from plateimpact_tools.converge import runs
from plateimpact_tools.converge.cost import plate_size, run_cost
from plateimpact_tools.converge.states import group, impacting, state_value
from plateimpact_tools.fmu_dask import run_tasks
from plateimpact_tools.scene_values import ELEMENT
from plateimpact_tools.windows import QUANTITIES, value_and_spread

# Quantities that always take part in telling states apart, besides those asked for: whether and
# how often the plate impacts, how much it moves and how much energy it holds.
GROUPING = ["impact_rate", "rms_corner", "mean_energy"]
# The mesh ladder's refinement factor per direction: 2.25× the cells per level, about 4× the CPU
# per modal internal step by `cost.run_cost` (n^1.7), where halving the cell size (2) would
# quadruple the cells and cost about 10×; the ladder then lands nearer the coarsest mesh that passes, while
# an error of order p in the cell size still shrinks to 1.5^-p per level (2/3 for p = 1), a change
# the rule can resolve.
MESH_FACTOR = 1.5
# Settings a ladder starts with: the rule judges three.
SPAN = 3
# Ladder lengths: Δt_0/2^12 and 5 mesh refinements (a 2 × 1 mesh reaches 16 × 8) are far beyond
# any budget on one machine; they only bound the loop.
MAX_DT_LEVELS = 12
MAX_MESH_LEVELS = 5
# With --mesh: mesh ladder, Δt ladder on the new mesh, … at most this many times each. A round
# that does not close has refined the mesh at least once more, so 4 rounds reach ≥ 1.5^4 ≈ 5 times
# the first round's mesh per direction (26× the cells, about 200× the CPU per modal step): like the
# ladder lengths, beyond a one-machine budget; the bound only ends the loop.
MAX_ROUNDS = 4


def refine_mesh(nx, ny):
    return math.ceil(MESH_FACTOR * nx), math.ceil(MESH_FACTOR * ny)


def refinement_ratio(a, b):
    """How much finer setting b is than a: the ratio of the time steps, or of the cell sizes
    (the square root of the ratio of the cell counts, for a mesh refined in both directions)."""
    if a[:2] == b[:2]:
        return a[2] / b[2]
    return math.sqrt((b[0] * b[1]) / (a[0] * a[1]))


class Study:
    """The ladders, their runs and the decisions (module docs). A run is (nx, ny, Δt, start
    index). `run(client)` returns the verdict line; `plateimpact_tools.converge.report` writes
    the outputs."""

    def __init__(
        self,
        fmu,
        scene,
        quantities,
        tolerance,
        budget,
        *,
        transient,
        window,
        windows,
        dt0,
        mesh,
        start_names=tuple(runs.START_NAMES),
        progress=True,
    ):
        self.fmu, self.scene, self.quantities = fmu, dict(scene), list(quantities)
        self.tolerance, self.budget, self.mesh = tolerance, budget, mesh
        self.dt0 = self.h = dt0
        self.transient_steps = round(transient / dt0)
        self.window_steps = max(1, round(window / dt0))
        self.windows = windows
        self.simulated = (self.transient_steps + windows * self.window_steps) * dt0
        self.starts = runs.starts(start_names, self.scene, self.transient_steps * dt0)
        self.compared = list(dict.fromkeys(GROUPING + self.quantities))
        self.progress = progress
        self.element = int(self.scene.get("mesh.element", 1))
        self.mesh0 = (int(self.scene.get("mesh.nx", 10)), int(self.scene.get("mesh.ny", 7)))
        self.results = {}  # (nx, ny, dt, start) -> result of runs.run_setting
        self.order = []  # the runs in the order they were submitted
        self.phase_of = {}  # run -> the ladder that ran it
        self.spent = 0.0
        self.ladders = []  # (name, [settings in ladder order]) in the order they were climbed
        self.judgements = {}  # ladder name -> (states, {state: {quantity: Judgement}}), last
        self.recommended = None
        self.verdict = None
        self.trends, self.advice = [], ""

    # -- runs

    def start_values(self, setting):
        nx, ny, dt = setting
        return dict(self.scene, **{"mesh.nx": nx, "mesh.ny": ny, "solver.time_step": dt})

    def execute(self, client, phase, settings):
        """Runs every start of each of `settings` not run yet, in parallel on the client."""
        todo = [
            s + (k,)
            for s in settings
            for k in range(len(self.starts))
            if s + (k,) not in self.results
        ]
        tasks = [
            (
                run,
                runs.run_setting,
                (
                    self.start_values(run[:3]),
                    self.starts[run[3]],
                    self.h,
                    self.transient_steps,
                    self.window_steps,
                    self.windows,
                ),
            )
            for run in todo
        ]
        done = run_tasks(self.fmu, tasks, client)
        for run in todo:
            result = done[run]
            self.results[run] = result
            self.order.append(run)
            self.phase_of[run] = phase
            self.spent += result["cpu"]
        for setting in dict.fromkeys(run[:3] for run in todo):
            if self.progress:
                states = self.states_at(setting)
                q = self.quantities[0]
                stats = self.stats(setting)
                shown = "; ".join(
                    f"{s.name} ({len(s.starts)}/{len(self.starts)}) {q} = "
                    f"{state_value(stats, s.starts, q)[0]:.6g}"
                    for s in states
                )
                print(
                    f"  {phase}: {self.describe(setting)}: {shown}; spent {self.spent:.1f} of "
                    f"{self.budget:g} CPU s",
                    file=sys.stderr,
                    flush=True,
                )

    def stats(self, setting):
        """Per start (in start order) {quantity: (value, spread)} at a run setting."""
        return [
            {q: value_and_spread(q, self.results[setting + (k,)]["windows"][q]) for q in QUANTITIES}
            for k in range(len(self.starts))
        ]

    def states_at(self, setting):
        return group(self.stats(setting), self.compared, self.tolerance)

    def cost(self, setting):
        """CPU seconds of one run of a setting: the mean over its starts."""
        return sum(self.results[setting + (k,)]["cpu"] for k in range(len(self.starts))) / len(
            self.starts
        )

    def warning(self, setting):
        return self.results[setting + (0,)]["warning"]

    def size(self, setting):
        """(free dofs, backend) of a setting's plate, as the FMU reports them (`cost.plate_size`)."""
        nx, ny, _ = setting
        return plate_size(self.fmu, dict(self.scene, **{"mesh.nx": nx, "mesh.ny": ny}))

    def estimate(self, known, setting):
        """CPU seconds of one run of `setting` from the runs of the run setting `known`: their
        cost times the ratio of the two settings' model costs (`cost.run_cost`), each on the free
        dofs and the backend the FMU reports for its mesh (`size`). Within the modal backend an
        internal step grows like n^1.5–2.0 and the set-up like n^2.3–2.9, with laws of their own
        above 2000 free dofs (`cost.regime`: the large basis's eigensolver and stand-ins); across
        the switch to sparse an internal step costs some 80 times more (Argyris 20 × 10, 1951 free
        dofs, modal: 9.1 µs; 21 × 12, 2428, sparse: 710 µs). A communication step with the reads
        grows with the plate too, doStep forming and checking the outputs (14 µs on Argyris
        10 × 7, 264 µs on 21 × 12). Halving Δt doubles the internal steps but not the set-up nor
        the communication steps (h is fixed). The study reads no outputs in the transient, which
        the model does not know: it overestimates a run by about the transient's reads, 4–5 µs a
        communication step (Argyris 14 × 8 at Δt = h = 1e-4 s with the default windows: 1.49 CPU s
        for 1.41 measured), most of which cancels in the ratio."""
        e, simulated, h = self.element, self.simulated, self.h
        return self.cost(known) * (
            run_cost(self.size(setting), e, setting[2], simulated, h)
            / run_cost(self.size(known), e, known[2], simulated, h)
        )

    def fits(self, estimate):
        return self.spent + estimate <= self.budget

    # -- decisions

    def state_ladder(self, ladder, members, quantity):
        """(values, spreads) of the state of the starts `members` along the run settings of
        `ladder`."""
        pairs = [state_value(self.stats(s), members, quantity) for s in ladder]
        return [v for v, _ in pairs], [s for _, s in pairs]

    def other_bounds(self, ladder):
        """{state: {quantity: bound}} of the passing ladder of the other kind (mesh for a Δt
        ladder, Δt for a mesh ladder) that ends at this ladder's last setting, if one does."""
        kind = ladder[0][:2] == ladder[-1][:2]  # a Δt ladder keeps its mesh
        for phase, other in self.ladders:
            if (
                other is not ladder
                and other[-1] == ladder[-1]
                and phase in self.judgements
                and (other[0][:2] == other[-1][:2]) != kind
            ):
                verdicts = self.judgements[phase][1]
                if all(j.accepted for per in verdicts.values() for j in per.values()):
                    return {
                        name: {q: j.bound for q, j in per.items()} for name, per in verdicts.items()
                    }
        return {}

    def judge(self, ladder):
        """(states at the ladder's last setting, {state name: {quantity: rule.Judgement}}): the
        rule on the last three settings of each state's ladder (module docs). Where a passing
        ladder of the other kind ends at the same setting, its bound counts against this one's:
        the errors in Δt and in the mesh add, and their sum must be within the tolerance."""
        last = ladder[-1]
        states = self.states_at(last)
        # An observed order is trusted only where the FMU does not warn (`rule`, point 4).
        trusted = not any(self.warning(s) for s in ladder[-SPAN:])
        other = self.other_bounds(ladder)
        verdicts = {}
        for state in states:
            verdicts[state.name] = {}
            for q in self.quantities:
                if len(ladder) < SPAN:
                    verdicts[state.name][q] = rule.Judgement(
                        False, math.inf, None, "fewer than three settings"
                    )
                    continue
                values, spreads = self.state_ladder(ladder[-SPAN:], state.starts, q)
                ratios = (refinement_ratio(*ladder[-3:-1]), refinement_ratio(*ladder[-2:]))
                taken = other.get(state.name, {}).get(q, 0.0)
                verdicts[state.name][q] = rule.judge(
                    values, spreads, ratios, self.tolerance, extrapolate=trusted, taken=taken
                )
            signatures = {impacting(self.stats(s), state.starts) for s in ladder[-SPAN:]}
            if len(signatures) > 1 or len(set(next(iter(signatures)))) > 1:
                for q, j in verdicts[state.name].items():
                    verdicts[state.name][q] = rule.Judgement(
                        False, j.bound, j.order, "its starts impact at one setting, not another"
                    )
        return states, verdicts

    def passes(self, phase, ladder):
        states, verdicts = self.judge(ladder)
        self.judgements[phase] = (states, verdicts)
        return all(j.accepted for per_state in verdicts.values() for j in per_state.values())

    def climb(self, client, phase, ladder, refine, levels, reference):
        """Climbs one ladder from the settings `ladder` (those not run yet are run first, their
        cost estimated from the setting `reference`) until `passes`. Returns its last setting, or
        None with the verdict set when the budget or the ladder ends first."""
        ladder = list(ladder)
        self.ladders.append((phase, ladder))
        missing = [s for s in ladder if s + (0,) not in self.results]
        if missing:
            guess = (
                len(self.starts) * sum(self.estimate(reference, s) for s in missing)
                if reference
                else 0.0
            )
            if reference and not self.fits(guess):
                return self.stop(
                    phase,
                    f"running {', '.join(map(self.describe, missing))} (about "
                    f"{guess:.3g} CPU s) would exceed the budget",
                )
            self.execute(client, phase, missing)
        while not self.passes(phase, ladder):
            b = ladder[-1]
            if len(ladder) >= levels:
                return self.stop(phase, f"the ladder ended at {self.describe(b)}")
            nxt = refine(b)
            guess = len(self.starts) * self.estimate(b, nxt)
            if not self.fits(guess):
                return self.stop(
                    phase,
                    f"the next refinement, {self.describe(nxt)} (about "
                    f"{guess:.3g} CPU s), would exceed the budget",
                )
            ladder.append(nxt)
            self.execute(client, phase, [nxt])
        return ladder[-1]

    def run(self, client):
        """The Δt ladder; with --mesh then the mesh ladder at the Δt found, then Δt again on the
        mesh found, and so on, until the recommended setting closes both a passing Δt ladder and
        a passing mesh ladder."""

        def halve(s):
            return s[0], s[1], s[2] / 2

        def finer_mesh(s):
            return refine_mesh(s[0], s[1]) + (s[2],)

        nx, ny = self.mesh0
        rec = self.climb(
            client,
            "dt-1",
            [(nx, ny, self.dt0 / 2**k) for k in range(SPAN)],
            halve,
            MAX_DT_LEVELS,
            None,
        )
        meshes = [self.mesh0]  # the mesh ladder so far
        for round_ in range(1, MAX_ROUNDS + 1):
            if rec is None or not self.mesh:
                break
            if len(meshes) == 1:  # the first round: rec's mesh and the next ones
                start = [rec]
                while len(start) < SPAN:
                    start.append(finer_mesh(start[-1]))
            else:
                start = [m + rec[2:] for m in meshes[-SPAN:-1]] + [rec]
            new = self.climb(client, f"mesh-{round_}", start, finer_mesh, MAX_MESH_LEVELS + 1, rec)
            if new is None or new == rec:
                rec = new
                break
            meshes = [s[:2] for s in self.ladders[-1][1]]
            rec = new
            start = [rec[:2] + (rec[2] * 2**k,) for k in range(SPAN - 1, -1, -1)]
            new = self.climb(client, f"dt-{round_ + 1}", start, halve, MAX_DT_LEVELS, rec)
            if new is None or new == rec:
                rec = new
                break
            rec = new
        else:
            if self.mesh and rec is not None:
                # Each round moved both ladders: the last Δt found was never checked in the mesh.
                return self.stop(
                    f"dt-{MAX_ROUNDS + 1}",
                    f"the mesh and Δt ladders alternated "
                    f"{MAX_ROUNDS} times without both passing at one setting",
                )
        if rec is None:
            return self.verdict
        self.recommended = rec
        self.verdict = self.converged_line(rec)
        return self.verdict

    # -- words

    def describe(self, setting):
        nx, ny, dt = setting
        name = {v: k for k, v in ELEMENT.items()}.get(self.element, self.element)
        return f"{name} {nx}x{ny}, Δt = {dt:.4g} s"

    def settings_text(self, setting):
        nx, ny, dt = setting
        return f"mesh.element={self.element} mesh.nx={nx} mesh.ny={ny} solver.time_step={dt:.6g}"

    def bounds(self, state_name, quantity):
        """The error bound of a state's value at the recommended setting: the sum of the bounds
        of the passing ladders that end there (Δt and, with --mesh, mesh; the errors in Δt and in
        the mesh add)."""
        total = 0.0
        for phase, ladder in self.ladders:
            if ladder[-1] == self.recommended and phase in self.judgements:
                verdicts = self.judgements[phase][1]
                if state_name in verdicts and verdicts[state_name][quantity].accepted:
                    total += verdicts[state_name][quantity].bound
        return total

    def warning_text(self, setting):
        warning = self.warning(setting)
        if warning:
            return f"the FMU warns at these settings ({runs.ADVICE_PREFIX}: see report.md)"
        return "the FMU does not warn at these settings"

    def converged_line(self, rec):
        states = self.states_at(rec)
        stats = self.stats(rec)

        def values(state):
            parts = []
            for q in self.quantities:
                v = state_value(stats, state.starts, q)[0]
                bound = self.bounds(state.name, q)
                parts.append(
                    f"{q} = {v:.6g} {QUANTITIES[q][0]} ± {100 * bound / abs(v) if v else 0:.2g} %"
                )
            return ", ".join(parts)

        n = len(self.starts)
        if len(states) == 1:
            found = f"{values(states[0])}; one steady state ({n} of {n} starts)"
        else:
            found = f"{len(states)} steady states: " + "; ".join(
                f"{s.name} ({len(s.starts)} of {n} starts) {values(s)}" for s in states
            )
        return (
            f"converged: {found}; settings {self.settings_text(rec)}; cost "
            f"{self.cost(rec) / self.simulated:.3g} CPU s per simulated s; "
            f"{self.warning_text(rec)}"
        )

    def stop(self, phase, why):
        """Ends the study `not converged`: each state's trend along the last ladder and advice."""
        ladder = [s for s in self.ladders[-1][1] if s + (0,) in self.results]
        states, verdicts = self.judgements.get(phase) or self.judge(ladder)
        spread_limited = []
        self.trends = []
        for state in states:
            texts = []
            for q in self.quantities:
                values, spreads = self.state_ladder(ladder, state.starts, q)
                text = f"{q} " + " → ".join(f"{v:.4g}" for v in values) + f" {QUANTITIES[q][0]}"
                j = verdicts[state.name][q]
                text += " (accepted)" if j.accepted else f" ({j.why})"
                texts.append(text)
                if not j.accepted and 2 * spreads[-1] > self.tolerance * abs(values[-1]):
                    spread_limited.append(q)
            label = (
                f"{state.name} ({len(state.starts)} of {len(self.starts)} starts) "
                if len(states) > 1
                else ""
            )
            self.trends.append(label + "; ".join(texts))
        finest = min(ladder, key=lambda s: (s[2], -s[0] * s[1]))
        warning = self.warning(finest)
        if warning:
            advice = f"the FMU warns at {self.describe(finest)}: {warning}"
        elif spread_limited:
            advice = (
                f"the spread of {', '.join(dict.fromkeys(spread_limited))} exceeds the "
                "tolerance: longer or more windows (--window, --windows), or a looser "
                "--tolerance"
            )
        else:
            advice = (
                "the values still move: raise --budget-seconds, start the ladder lower "
                "(--dt) or loosen --tolerance"
            )
        self.advice = advice
        found = (
            f"{len(states)} steady states at {self.describe(ladder[-1])}; "
            if len(states) > 1
            else ""
        )
        self.verdict = (
            f"not converged: {phase}: {why} (spent {self.spent:.1f} of "
            f"{self.budget:g} CPU s); {found}trend: {' | '.join(self.trends)}; "
            f"advice: {advice}"
        )
        return None
