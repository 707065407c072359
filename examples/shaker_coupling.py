"""The plate FMU on an electrodynamic shaker, coupled both ways through a co-simulation master.

The shaker's moving part (armature and head expander) is a mass m_s on a suspension of stiffness
k_s and damping c_s, driven by the coil force F_d(t) = F_0 sin(2 pi f t); it carries the plate's
clamp, so its position x is the plate's base displacement, and the plate pushes back on it with
`base.force` F_b (the force the plate exerts on its base, positive upward):

    m_s x'' + c_s x' + k_s x = F_d(t) + F_b(t).

The drive is at 53 Hz, just below the plate's first resonance (53.8 Hz): the plate's free edge
strikes the obstacles at +-10 mm about twice per period, and the impacts show in F_b.

The master (fmpy's FMU2Slave, communication points t_k = k h) splits the plate's force as
F_b = -m_p x'' + R: the inertia of the plate moving with the shaker (m_p = rho e Lx Ly, what a rigid
plate exerts), which the shaker carries implicitly, as mass (an interface-Jacobian, or added-mass,
correction), and the rest R, the plate's elastic, damping and contact reaction. Four couplings
(--coupling):

* instantaneous: x(t_k), x'(t_k), x''(t_k) to `base.displacement` (fmi2SetRealInputDerivatives),
  the plate steps, then the shaker over [t_k, t_k + h] under R read from `base.force`, the force of
  the plate's last internal step t_k - dt (dt = solver.time_step), extrapolated linearly from its
  last two values. An aliased sample: the residual is first order in h and keeps a dt lag.
* mean: the shaker runs half an internal step behind the plate, over [t_k - dt/2, t_{k+1} - dt/2],
  the window of `base.mean_force` and of the plate's energies (docs/fmu.md, "Coupling both ways").
  The plate steps on the quadratic through the shaker's motion at t_k, extrapolated to t_{k+1};
  then the shaker steps under the constant mean reaction R = base.mean_force + m_p (v_{N1-1/2} -
  v_{N0-1/2})/h of that same step (the rigid part of the mean force, from the plate's discrete base
  velocities, which the master knows from the motion it sent). No lag, but the plate followed an
  extrapolation: first order in h.
* iterated: as mean, then the plate is put back (fmi2SetFMUstate) and steps again on the quadratic
  from the shaker's new motion, the shaker again under the new reaction, and so on (secant steps on
  R) until R changes by less than 1e-12 of the larger of R and the coil force's amplitude (R alone
  would ask, when R passes near zero, for less than the round-off of the plate's force, about
  1e-11 N: a second difference of displacements divided by dt^2); then both are kept. Second
  order in h.
* moments: as iterated, but the shaker gets the line R + beta (s - c) that has both the impulse and
  the first moment M = sum_n R_n (t_n - c) dt of the plate's reaction about the window's centre c
  (beta = 12 M / h^3), so that the force's variation within the step works on the shaker as it
  does on the plate. The FMU has no output for M: here the plate steps through each communication
  step in calls of one internal step (the same quadratic, sampled at each t_n) and M is summed from
  their base.mean_force, an instrument that stands in for such an output (and costs h/dt calls).
  Fixed-point steps on the slope, until it changes by less than 1e-12 of that same scale.

The constant R over a step gives the shaker exactly the impulse the plate gave its base. The work
differs by what no single force per step can carry: the plate's base work is
sum_n (z_{n+1} - z_{n-1})/2 F_n over its internal steps, the shaker's R (x_{k+1} - x_k) less the
inertia's, and the two agree only while the base moves at one velocity; otherwise the variation of
the force within the step works against the variation of the velocity, about a R' h^3 / 12 per step
(a the base's acceleration, R' the reaction's rate; docs/fmu.md, "Coupling both ways").

With the first moment as well (moments), the line force carries that term exactly for a base on
the quadratic plan: sum_n F_n (z_{n+1} - z_{n-1})/2 = x'(c) J + a M + kink, with J the impulse and
the kink F_N0 ((z_{N0+1} - z_{N0-1})/2 - x'(t_k) dt) the first internal step's force working on
the change of acceleration at t_k (z_{N0-1} lies on the previous step's plan). What remains is the
kink, reported as `kinks` (summed from t_1), and the shaker's own path differing from the plan it
sent: under a force that varies within the step its motion is not a quadratic, and the plate
follows at most a quadratic (two input derivatives). No choice of force closes both: a shaker
whose path is exactly the plan (one unknown per step) cannot also honour the impulse and the first
moment (two conditions), which the work on a quadratic needs.

Energy. The shaker is integrated by the implicit midpoint rule (substeps of at most 10 us), whose
discrete energy E_s = m_s v^2/2 + k_s x^2/2 obeys, per substep with dx = x_{j+1} - x_j,

    dE_s = F_d(t_{j+1/2}) dx + F_b,j dx - c_s v_{j+1/2} dx        exactly,

with F_b,j = R(t_{j+1/2}) - m_p (v_{j+1} - v_j)/dt, so the work W_d of the drive, the shaker's
damper loss D_s and the work W_b = sum F_b,j dx of the plate's force on the shaker are exact on the
shaker's side. The plate FMU reports its own balance, d energy.total = d energy.base_work -
d energy.contact_loss - d energy.damping_loss, to round-off. Adding both, the coupled system's
balance is

    W_d = dE_s + D_s + dE_plate + d contact_loss + d damping_loss + R_c,
    R_c = -(d energy.base_work + W_b),

where the residual R_c is the coupling's error: the work the plate says its base did on it, minus
the work the shaker says it did against the plate's force. It shrinks with h. All terms are
differences between the first communication point and the end (the plate's start step, from rest,
has no energy identity); with the mean and iterated couplings the shaker's terms are taken at
t_k - dt/2, where its window ends. The last line printed is this balance.

Usage:
    cargo run --release --bin package-fmu
    .venv/bin/python examples/shaker_coupling.py                 # iterated, h = 0.5 ms, 1 s, writes docs/coupling/
    .venv/bin/python examples/shaker_coupling.py --compare       # the four couplings at h = 2, 1, 0.5 ms
    .venv/bin/python examples/shaker_coupling.py --sweep         # the residual for h = 2 ms to 0.1 ms
    .venv/bin/python examples/shaker_coupling.py --state-cost    # time and size of the FMU state
    .venv/bin/python examples/shaker_coupling.py --coupling mean --h 1e-3 --stop 0.5 --no-plot
"""

import argparse
import copy
import math
import pathlib
import shutil
import tempfile
import time

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave

ROOT = pathlib.Path(__file__).resolve().parent.parent
FMU = ROOT / "target" / "fmu" / "PlateImpact.fmu"

# The shaker: 60 kg moving on a 15 Hz suspension damped at 20 %, a 7 kN coil force at 53 Hz.
SHAKER_MASS = 60.0  # kg
SUSPENSION_STIFFNESS = SHAKER_MASS * (2 * math.pi * 15.0) ** 2  # N/m
SUSPENSION_DAMPING = 2 * 0.2 * math.sqrt(SUSPENSION_STIFFNESS * SHAKER_MASS)  # N s/m
DRIVE_AMPLITUDE = 7000.0  # N
DRIVE_FREQUENCY = 53.0  # Hz
COUPLINGS = ("instantaneous", "mean", "iterated", "moments")
SUBSTEP = 1e-5  # s, the longest shaker substep

# The plate: the paper's steel plate (the FMU's defaults) and obstacles at +-10 mm, with Rayleigh
# damping of 1 % from alpha in its first mode (53.8 Hz) and 5 % from beta in its third (335 Hz).
PLATE_LENGTH, PLATE_WIDTH, PLATE_THICKNESS, PLATE_DENSITY = 0.4, 0.2, 0.01, 7770.0
PLATE = {
    "damping.mass_proportional": 2 * 0.01 * 2 * math.pi * 53.8,
    "damping.stiffness_proportional": 2 * 0.05 / (2 * math.pi * 335.0),
}
OUTPUTS = [
    "base.force",
    "base.mean_force",
    "corner1.displacement",
    "energy.total",
    "energy.base_work",
    "energy.contact_loss",
    "energy.damping_loss",
]


def drive(t):
    """The coil force F_d(t) (N)."""
    return DRIVE_AMPLITUDE * math.sin(2 * math.pi * DRIVE_FREQUENCY * t)


class Shaker:
    """The shaker's moving part, integrated by the implicit midpoint rule with exact energy
    bookkeeping, carrying the plate's inertia -m_p x'' implicitly (module docs)."""

    def __init__(self, plate_mass):
        self.plate_mass = plate_mass
        self.x = self.v = self.a = 0.0
        self.drive_work = self.damper_loss = self.plate_work = 0.0

    def energy(self):
        return 0.5 * SHAKER_MASS * self.v**2 + 0.5 * SUSPENSION_STIFFNESS * self.x**2

    def ahead(self, tau):
        """(x, v) extrapolated by tau (s) with the last substep's acceleration."""
        return self.x + self.v * tau + 0.5 * self.a * tau * tau, self.v + self.a * tau

    def advance(self, t, h, rest):
        """Over [t, t + h] under the plate's force -m_p x'' + rest(s), s in [0, h] (N)."""
        n = max(1, math.ceil(h / SUBSTEP - 1e-9))
        dt = h / n
        m, c, k = SHAKER_MASS + self.plate_mass, SUSPENSION_DAMPING, SUSPENSION_STIFFNESS
        for j in range(n):
            f_drive, r = drive(t + (j + 0.5) * dt), rest((j + 0.5) * dt)
            # Midpoint velocity of m (v1 - v0) = dt (F - c vm - k (x0 + x1)/2), x1 = x0 + dt vm.
            vm = (2 * m * self.v + dt * (f_drive + r - k * self.x)) / (
                2 * m + dt * c + 0.5 * k * dt * dt
            )
            dx, v1 = dt * vm, 2 * vm - self.v
            self.a = (v1 - self.v) / dt
            self.drive_work += f_drive * dx
            self.plate_work += (r - self.plate_mass * self.a) * dx
            self.damper_loss += c * vm * dx
            self.x, self.v = self.x + dx, v1


class Interface:
    """The plate's base motion the master sends over one communication step and what it reads back:
    the quadratic z(t_k + tau) = x_k + v_k tau + a_k tau^2 / 2 through the shaker's position and
    velocity at t_k that lands on its position x_{k+1} at t_{k+1} (the FMU follows a sample and its
    two derivatives exactly, docs/fmu.md), and the plate's reaction without the inertia of its rigid
    motion, from the mean force."""

    def __init__(self, plate_mass, dt):
        self.plate_mass, self.dt = plate_mass, dt
        self.grid_velocity = 0.0  # (z_N - z_{N-1}) / dt at the last communication point: at rest
        self.previous_plan = (0.0, 0.0, 0.0)  # the plan of the last step: at rest

    def plan(self, x0, v0, x1, h):
        """(x_k, v_k, a_k) for a step of h from (x0, v0) to x1."""
        return x0, v0, 2.0 * (x1 - x0 - v0 * h) / (h * h)

    def end_velocity(self, plan, h):
        """(z_N - z_{N-1}) / dt at the end of a step of h along `plan`: v_k + a_k (h - dt/2)."""
        _, v0, a = plan
        return v0 + a * (h - 0.5 * self.dt)

    def rest_moment(self, moment, plan, h):
        """The first moment of the reaction R about the window's centre c, sum_n R_n (t_n - c) dt,
        from the force's: R_n = F_n + m_p (z_{n+1} - 2 z_n + z_{n-1}) / dt^2, whose rigid part sums
        by parts to m_p [(s_N1 + s_N0) (h - dt)/2 - (z_{N1-1} - z_{N0})], s the grid velocities
        before and after the step."""
        x0, v0, a = plan
        tail = h - self.dt
        moved = v0 * tail + 0.5 * a * tail * tail
        return moment + self.plate_mass * (
            (self.end_velocity(plan, h) + self.grid_velocity) * 0.5 * tail - moved
        )

    def rest(self, mean_force, plan, h):
        """The plate's mean reaction R over the step without its rigid inertia: the mean force plus
        m_p (v_{N1-1/2} - v_{N0-1/2}) / h, exactly the rigid part -m_p d^2z/dt^2 of the force's
        impulse on the grid (docs/fmu.md, "Coupling both ways")."""
        return mean_force + self.plate_mass * (self.end_velocity(plan, h) - self.grid_velocity) / h


def run(h, stop, fmu=FMU, coupling="iterated", tolerance=1e-12, max_iterations=50):
    """The coupled run with communication step `h` (s) up to `stop` (s) and the `coupling` of the
    module docs: the recorded traces and the terms of the power balance (J) between the first
    communication point and the end, with the iterations (iterated coupling)."""
    if coupling not in COUPLINGS:
        raise ValueError(f"coupling {coupling!r}: must be one of {COUPLINGS}")
    md = read_model_description(str(fmu))
    unzipdir = extract(str(fmu), unzipdir=tempfile.mkdtemp(prefix="shaker-"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    plate = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="plate",
    )
    iterations = []
    try:
        plate.instantiate()
        plate.setupExperiment(startTime=0.0, stopTime=stop)
        plate.setReal([vr[n] for n in PLATE], list(PLATE.values()))
        plate.enterInitializationMode()
        plate.exitInitializationMode()
        lag = plate.getReal([vr["solver.time_step"]])[0]
        if coupling != "instantaneous" and abs(h / lag - round(h / lag)) > 1e-9 * h / lag:
            # The mean force's window and the rigid part of its impulse are those of whole internal steps.
            raise ValueError(
                f"the {coupling} coupling needs h a multiple of solver.time_step = {lag} s, not {h} s"
            )
        plate_mass = PLATE_DENSITY * PLATE_THICKNESS * PLATE_LENGTH * PLATE_WIDTH
        shaker = Shaker(plate_mass)
        interface = Interface(plate_mass, lag)
        steps = round(stop / h)
        out = {
            name: np.empty(steps + 1)
            for name in ["time", "shaker", "contact.impacts", "residual"] + OUTPUTS
        }
        output_vrs = [vr[n] for n in OUTPUTS]
        displacement = vr["base.displacement"]

        def record(k):
            out["time"][k], out["shaker"][k] = k * h, shaker.x
            for name, value in zip(OUTPUTS, plate.getReal(output_vrs)):
                out[name][k] = value
            out["contact.impacts"][k] = plate.getInteger([vr["contact.impacts"]])[0]
            if coupling == "moments" and k > 0:
                # The plate stepped in internal-step calls: the step's impacts and mean force are theirs.
                out["contact.impacts"][k], out["base.mean_force"][k] = (
                    sub_step["impacts"],
                    sub_step["mean_force"],
                )
            out["residual"][k] = -(out["energy.base_work"][k] + shaker.plate_work)

        def step_plate(t, plan):
            x, v, a = plan
            plate.setReal([displacement], [x])
            plate.setRealInputDerivatives([displacement] * 2, [1, 2], [v, a])
            plate.doStep(currentCommunicationPoint=t, communicationStepSize=h)
            return plate.getReal([vr["base.mean_force"]])[0]

        def step_plate_moments(t, plan):
            """The plate over the step along `plan` in calls of one internal step each (the same
            quadratic, sampled at each t_n): the mean force and the first moment of the forces about
            the window's centre, sum_n F_n (t_n - c) dt, c = t_k + (h - dt)/2 (module docs)."""
            x, v, a = plan
            steps = round(h / lag)
            forces, sub_step["impacts"] = [], 0
            for n in range(steps):
                tau = n * lag
                plate.setReal([displacement], [x + v * tau + 0.5 * a * tau * tau])
                plate.setRealInputDerivatives([displacement] * 2, [1, 2], [v + a * tau, a])
                plate.doStep(currentCommunicationPoint=t + tau, communicationStepSize=lag)
                forces.append(plate.getReal([vr["base.mean_force"]])[0])
                sub_step["impacts"] += plate.getInteger([vr["contact.impacts"]])[0]
            forces = np.array(forces)
            sub_step["mean_force"] = float(forces.mean())
            offsets = (np.arange(steps) - 0.5 * (steps - 1)) * lag
            # The kink: the first force's work beyond v dt, F_N0 ((z_{N0+1} - z_{N0-1})/2 - v dt),
            # z_{N0-1} from the previous step's plan (module docs).
            before = interface.previous_plan
            z_before = before[0] + before[1] * (h - lag) + 0.5 * before[2] * (h - lag) ** 2
            kinks[k] = forces[0] * (0.5 * (x + v * lag + 0.5 * a * lag * lag - z_before) - v * lag)
            return float(forces.mean()), float((forces * offsets).sum() * lag)

        record(0)
        first, sent_acceleration, last_rest = None, 0.0, None
        kinks = np.zeros(steps)  # moments coupling: the kink term of each step (J)
        sub_step = {}  # moments coupling: the impacts and the mean force of the last step's calls
        for k in range(steps):
            t = k * h
            if coupling == "instantaneous":
                # The plate's reaction at t_k - dt without the inertia of the acceleration it was given.
                rest = out["base.force"][k] + shaker.plate_mass * sent_acceleration
                slope = 0.0 if last_rest is None else (rest - last_rest) / h
                last_rest, sent_acceleration = rest, shaker.a
                step_plate(t, (shaker.x, shaker.v, sent_acceleration))
                shaker.advance(t, h, lambda s, r=rest, d=slope: r + d * (s + lag))
            else:
                # The shaker runs half an internal step behind the plate, over [t_k - dt/2,
                # t_{k+1} - dt/2]: the window of the plate's base.mean_force and of its energies
                # (module docs). The plate first, on the plan from the shaker's motion at t_k and
                # its landing at t_{k+1} (at first extrapolated from t_k - dt/2), then the shaker
                # under the plate's mean reaction (mean). Iterated: the plate again, from its saved
                # state, on the plan from the shaker's new run, until the reaction stops changing.
                start = copy.copy(shaker)
                state = plate.getFMUstate() if coupling in ("iterated", "moments") else None
                centre = t + 0.5 * (h - lag)  # of the window of the plate's forces
                lead = 0.0 if k == 0 else 0.5 * lag  # from the shaker's time to t_k

                def shaken(r, slope=0.0):
                    """The shaker over its window under the reaction r + slope (s - c), and the
                    plan of the plate's base it gives: from its motion at t_k to its landing at t_{k+1}."""
                    moved = copy.copy(start)
                    if lead > 0.0:
                        moved.advance(t - lead, lead, lambda s: r + slope * (t - lead + s - centre))
                    at_point = moved.ahead(0.0)
                    moved.advance(t, h - 0.5 * lag, lambda s: r + slope * (t + s - centre))
                    return moved, interface.plan(*at_point, moved.ahead(0.5 * lag)[0], h)

                def reaction(plan):
                    """(R, slope) of the plate's step along plan: the mean reaction and, for the
                    moments coupling, the slope of the line with the reaction's first moment."""
                    if coupling != "moments":
                        return interface.rest(step_plate(t, plan), plan, h), 0.0
                    mean, moment = step_plate_moments(t, plan)
                    return interface.rest(mean, plan, h), 12.0 * interface.rest_moment(
                        moment, plan, h
                    ) / h**3

                plan = interface.plan(*start.ahead(lead), start.ahead(lead + h)[0], h)
                guess, slope = reaction(plan)
                last = None  # (guess, change) of the previous iterate
                for iteration in range(1, max_iterations + 1):  # noqa: B007 (read after the loop)
                    shaker, plan = shaken(guess, slope)
                    if coupling == "mean":
                        break
                    plate.setFMUstate(state)
                    rest, new_slope = reaction(plan)
                    change = rest - guess
                    scale = max(DRIVE_AMPLITUDE, abs(rest))
                    settled = abs(new_slope - slope) * h <= tolerance * scale
                    slope = new_slope
                    if abs(change) <= tolerance * scale and settled:
                        if coupling == "moments":
                            shaker, plan = shaken(rest, slope)
                        break
                    # The next reaction: a secant step on change(guess) = 0, the plain update first.
                    following = rest
                    if last is not None and change != last[1]:
                        following = guess - change * (guess - last[0]) / (change - last[1])
                    last, guess = (guess, change), following
                else:
                    raise RuntimeError(
                        f"t = {t} s: no convergence in {max_iterations} iterations ({change:.1e} N)"
                    )
                if state is not None:
                    plate.freeFMUstate(state)
                iterations.append(iteration)
                interface.grid_velocity = interface.end_velocity(plan, h)
                interface.previous_plan = plan
            record(k + 1)
            if first is None:
                first = (shaker.energy(), shaker.drive_work, shaker.damper_loss, shaker.plate_work)
        plate.terminate()
    finally:
        plate.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)

    def change(name):
        return out[name][-1] - out[name][1]

    energy0, drive0, damper0, plate_work0 = first
    balance = {
        "drive": shaker.drive_work - drive0,
        "shaker": shaker.energy() - energy0,
        "shaker_damper": shaker.damper_loss - damper0,
        "plate": change("energy.total"),
        "contact_loss": change("energy.contact_loss"),
        "plate_damping": change("energy.damping_loss"),
    }
    balance["residual"] = -(change("energy.base_work") + (shaker.plate_work - plate_work0))
    # Moments coupling: the part of the residual that is the kink terms (from t_1 on, as the balance).
    balance["kinks"] = float(kinks[1:].sum()) if coupling == "moments" else None
    accounted = sum(
        balance[k] for k in ("shaker", "shaker_damper", "plate", "contact_loss", "plate_damping")
    )
    # What is left once the coupling residual is counted: the plate's own balance, to round-off.
    balance["closure"] = balance["drive"] - accounted - balance["residual"]
    balance["impacts"] = int(out["contact.impacts"].sum())
    balance["iterations"] = (
        (float(np.mean(iterations)), int(np.max(iterations)))
        if coupling in ("iterated", "moments")
        else None
    )
    return out, balance


def balance_line(h, b):
    return (
        f"power balance over [h, T] with h = {h * 1e3:g} ms: drive {b['drive']:.4f} J = shaker "
        f"{b['shaker']:.4f} J + shaker damper {b['shaker_damper']:.4f} J + plate {b['plate']:.4f} J "
        f"+ contacts {b['contact_loss']:.4f} J + plate damping {b['plate_damping']:.4f} J "
        f"+ coupling residual {b['residual']:.3e} J ({abs(b['residual']) / b['drive']:.2e} of the drive's work)"
    )


def plot(out, path):
    """Shaker motion, plate corner and the forces on the shaker: the whole run on the left, the
    last three drive periods on the right."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    t = out["time"]
    zoom = t >= t[-1] - 3 / DRIVE_FREQUENCY
    fig, axes = plt.subplots(
        3, 2, figsize=(11, 7.5), sharex="col", gridspec_kw={"width_ratios": [2, 1]}
    )
    for column, keep in enumerate([np.ones_like(t, dtype=bool), zoom]):
        tt = t[keep]
        axes[0, column].plot(tt, 1e3 * out["shaker"][keep], color="tab:blue")
        axes[1, column].plot(tt, 1e3 * out["corner1.displacement"][keep], color="tab:green", lw=0.8)
        for g in (-10, 10):
            axes[1, column].axhline(g, color="k", lw=0.8, ls="--")
        axes[2, column].plot(
            tt, [drive(s) for s in tt], color="tab:gray", lw=0.8, label="coil force"
        )
        axes[2, column].plot(
            tt,
            out["base.force"][keep],
            color="tab:red",
            lw=0.7,
            label="base.force (plate on shaker)",
        )
        axes[2, column].step(
            tt,
            out["base.mean_force"][keep],
            where="pre",
            color="tab:blue",
            lw=0.7,
            label="base.mean_force over each step",
        )
        hits = tt[out["contact.impacts"][keep] > 0]
        low = axes[2, column].get_ylim()[0]
        axes[2, column].plot(hits, np.full(len(hits), low), "|", color="k", ms=8, label="impacts")
        axes[2, column].set_xlabel("t (s)")
    axes[0, 0].set_ylabel("shaker x (mm)")
    axes[1, 0].set_ylabel("plate corner u(Lx, 0) (mm)")
    axes[2, 0].set_ylabel("force on the shaker (N)")
    axes[2, 0].legend(loc="upper left", fontsize=8, ncol=3)
    axes[0, 1].set_title("last three drive periods", fontsize=10)
    fig.suptitle(
        f"Plate FMU on a shaker driven at {DRIVE_FREQUENCY:g} Hz, coupled both ways "
        f"(h = {1e3 * (t[1] - t[0]):g} ms)"
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_modes(runs, path):
    """The couplings: the coupling residual over time at the coarsest step (left) and its
    final value against the communication step (right), as fractions of the drive's work."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colors = {
        "instantaneous": "tab:red",
        "mean": "tab:orange",
        "iterated": "tab:blue",
        "moments": "tab:green",
    }
    steps = sorted({h for h, _ in runs}, reverse=True)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for mode in COUPLINGS:
        out, b = runs[(steps[0], mode)]
        residual = out["residual"][1:] - out["residual"][1]
        left.plot(out["time"][1:], residual / b["drive"], color=colors[mode], label=mode)
        fractions = [
            abs(runs[(h, mode)][1]["residual"]) / runs[(h, mode)][1]["drive"] for h in steps
        ]
        right.loglog([1e3 * h for h in steps], fractions, "o-", color=colors[mode], label=mode)
        if mode in ("iterated", "moments"):
            for h, f in zip(steps, fractions):
                mean, most = runs[(h, mode)][1]["iterations"]
                right.annotate(
                    f"{mean:.1f} it.",
                    (1e3 * h, f),
                    textcoords="offset points",
                    xytext=(5, 4),
                    fontsize=8,
                    color=colors[mode],
                )
    left.axhline(0.0, color="k", lw=0.6)
    left.set_xlabel("t (s)")
    left.set_ylabel("coupling residual / drive's work")
    left.set_title(f"h = {1e3 * steps[0]:g} ms", fontsize=10)
    left.legend(fontsize=8)
    right.set_xticks([1e3 * h for h in steps], [f"{1e3 * h:g}" for h in steps])
    right.minorticks_off()
    right.set_xlabel("communication step h (ms)")
    right.set_ylabel("|coupling residual| / drive's work")
    right.set_title(f"over {runs[(steps[0], COUPLINGS[0])][0]['time'][-1]:g} s", fontsize=10)
    right.legend(fontsize=8)
    fig.suptitle(
        "Plate FMU on the shaker: instantaneous base.force, base.mean_force, iterated, and with the force's first moment"
    )
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def state_cost(fmu=FMU, repeats=200):
    """Mean wall time (s) of fmi2GetFMUstate, fmi2SetFMUstate and fmi2SerializeFMUstate on the
    shaker scene's plate (the paper's mesh) after 0.1 s, and the serialized state's size (bytes)."""
    md = read_model_description(str(fmu))
    unzipdir = extract(str(fmu), unzipdir=tempfile.mkdtemp(prefix="shaker-"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    plate = FMU2Slave(
        guid=md.guid,
        unzipDirectory=unzipdir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="plate",
    )
    try:
        plate.instantiate()
        plate.setupExperiment(startTime=0.0)
        plate.setReal([vr[n] for n in PLATE], list(PLATE.values()))
        plate.enterInitializationMode()
        plate.exitInitializationMode()
        for k in range(100):
            plate.setReal(
                [vr["base.displacement"]],
                [1e-3 * math.sin(2 * math.pi * DRIVE_FREQUENCY * k * 1e-3)],
            )
            plate.doStep(k * 1e-3, 1e-3)
        state = plate.getFMUstate()
        timings = {}
        for name, call in [
            ("get", lambda: plate.freeFMUstate(plate.getFMUstate())),
            ("set", lambda: plate.setFMUstate(state)),
            ("serialize", lambda: plate.serializeFMUstate(state)),
        ]:
            began = time.perf_counter()
            for _ in range(repeats):
                call()
            timings[name] = (time.perf_counter() - began) / repeats
        timings["bytes"] = len(plate.serializeFMUstate(state))
        began = time.perf_counter()
        for _ in range(repeats):
            plate.doStep(0.1, 1e-3)
            plate.setFMUstate(state)
        timings["step"] = (time.perf_counter() - began) / repeats - timings["set"]
        plate.freeFMUstate(state)
        plate.terminate()
    finally:
        plate.freeInstance()
        shutil.rmtree(unzipdir, ignore_errors=True)
    return timings


def main():
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--fmu", default=str(FMU))
    parser.add_argument("--h", type=float, default=5e-4, help="communication step (s)")
    parser.add_argument("--stop", type=float, default=1.0, help="horizon (s)")
    parser.add_argument(
        "--coupling",
        choices=COUPLINGS,
        default="iterated",
        help="what the master feeds back (default: iterated, the smallest residual)",
    )
    parser.add_argument(
        "--out", default=str(ROOT / "docs" / "coupling"), help="directory of the plots"
    )
    parser.add_argument("--no-plot", action="store_true")
    parser.add_argument("--sweep", action="store_true", help="the residual for h = 2 ms to 0.1 ms")
    parser.add_argument(
        "--compare",
        action="store_true",
        help="the four couplings at h = 2, 1, 0.5 ms (table, and the plot coupling_modes.png)",
    )
    parser.add_argument("--state-cost", action="store_true", help="time and size of the FMU state")
    args = parser.parse_args()
    if args.state_cost:
        c = state_cost(args.fmu)
        print(
            f"FMU state of the paper's mesh: get {1e6 * c['get']:.1f} us, set {1e6 * c['set']:.1f} us, "
            f"serialize {1e6 * c['serialize']:.1f} us, {c['bytes']} bytes serialized; "
            f"one 1 ms doStep {1e6 * c['step']:.1f} us"
        )
    if args.sweep:
        for h in (2e-3, 1e-3, 5e-4, 2e-4, 1e-4):
            _, b = run(h, args.stop, args.fmu, args.coupling)
            print(
                f"h = {h * 1e3:5.2f} ms: residual {b['residual']:+.4e} J ({abs(b['residual']) / b['drive']:.2e} "
                f"of the drive's {b['drive']:.3f} J), {b['impacts']} impacts"
            )
    if args.compare:
        runs = {}
        print(
            "| h | coupling | residual (J) | of the drive's work | drive (J) | impacts | iterations (mean, max) | kink terms (J) |"
        )
        print("|---|---|---|---|---|---|---|---|")
        for h in (2e-3, 1e-3, 5e-4):
            for mode in COUPLINGS:
                runs[(h, mode)] = run(h, args.stop, args.fmu, mode)
                b = runs[(h, mode)][1]
                its = (
                    "-"
                    if b["iterations"] is None
                    else f"{b['iterations'][0]:.2f}, {b['iterations'][1]}"
                )
                kinks = "-" if b["kinks"] is None else f"{b['kinks']:+.3e}"
                print(
                    f"| {1e3 * h:g} ms | {mode} | {b['residual']:+.3e} | {abs(b['residual']) / b['drive']:.2e} | "
                    f"{b['drive']:.2f} | {b['impacts']} | {its} | {kinks} |",
                    flush=True,
                )
        if not args.no_plot:
            plot_modes(runs, pathlib.Path(args.out) / "coupling_modes.png")
    out, b = run(args.h, args.stop, args.fmu, args.coupling)
    if not args.no_plot:
        plot(out, pathlib.Path(args.out) / "shaker_coupling.png")
    iterations = (
        ""
        if b["iterations"] is None
        else f"; {b['iterations'][0]:.2f} iterations per step (at most {b['iterations'][1]})"
    )
    print(
        f"{args.coupling} coupling: {b['impacts']} impacts; the plate's own balance closes to {b['closure']:.1e} J"
        f"{iterations}"
    )
    print(balance_line(args.h, b))


if __name__ == "__main__":
    main()
