"""One run of the convergence study, executed on a Dask worker (or in the client with --serial):
the scene from one of several starts, then its statistics over windows.

Starts (docs/converge/README.md, "Starts", says why these and what they cannot find). Every start
ends on the same forcing, the built-in sine c·sin(2πf t) of the scene, exactly: what differs is
how the plate gets there. Before its end a start drives the input `base.displacement` with the
difference between the base motion it wants and the built-in sine (with the first two time
derivatives, so that the FMU applies it to second order in the communication step), and sends 0
from its end on, so the measured windows see the scene's own sine whatever the start.

- `abrupt`: the built-in sine from rest: the base starts with the velocity 2πf·c.
- `ramp`: the amplitude grows from 0 to c as sin²(πt/2T) over T = RAMP of the transient (base and
  plate start at rest together), so the plate follows the response that grows from small
  amplitudes.
- `sweep-up`, `sweep-down`: the frequency goes linearly from (1 ∓ SWEEP)·f to f over RAMP of the
  transient, the amplitude ramped in over SWEEP_RAMP of it: a fast frequency sweep that arrives
  on the branch a slow sweep from below (above) would follow.
- `kick`: the abrupt sine, the plate released from a static deflection of KICK of the narrower
  gap (an added `initial.preload_pressure`): a start with energy to spare.
"""

import dataclasses
import math
import sys
import time
import uuid

import numpy as np

from plateimpact_tools.fmu_dask import fmu_dir
from plateimpact_tools.windows import REALS, window_values

# The start of the warning the FMU logs at ExitInitializationMode (src/advice.rs) for settings
# whose impact statistics may not converge; the study passes it on.
ADVICE_PREFIX = "impact statistics may not converge"
# Fractions of the transient: the amplitude ramp and the frequency sweep end at RAMP of it, so
# that 40 % of it (14 forcing periods by default) is left to settle on the scene's own sine.
RAMP = 0.6
# The sweeps' amplitude ramp, a fraction of the transient: short, so that the plate is on a branch
# well before the sweep reaches f.
SWEEP_RAMP = 0.2
# The sweeps start this far from f (relative): beyond the width of the coexistence band the
# project's frequency sweep found on the paper's plate (63.5 to 73.5 Hz, ±7 % about 68.5 Hz).
SWEEP = 0.2
# The kick's static deflection of the free edge, a fraction of the narrower enabled gap (of the
# base amplitude without obstacles): well inside the gap whatever the error of its estimate
# (`kick_pressure`).
KICK = 0.5


@dataclasses.dataclass(frozen=True)
class Start:
    """How a run starts (module docs): an amplitude ramp of `ramp` seconds and a frequency
    sweep from (1 + `sweep`)·f over `sweep_time` seconds, both driven through the input (none
    when `sweep_time` = 0); `preload` Pa added to the scene's initial preload."""

    name: str
    ramp: float = 0.0
    sweep: float = 0.0
    sweep_time: float = 0.0
    preload: float = 0.0

    def drives(self):
        return self.sweep_time > 0


def starts(names, scene, transient):
    """The starts `names` (of START_NAMES) for the start values `scene` and a transient of
    `transient` seconds."""
    made = {
        "abrupt": Start("abrupt"),
        "ramp": Start("ramp", ramp=RAMP * transient, sweep_time=RAMP * transient),
        "sweep-up": Start(
            "sweep-up", ramp=SWEEP_RAMP * transient, sweep=-SWEEP, sweep_time=RAMP * transient
        ),
        "sweep-down": Start(
            "sweep-down", ramp=SWEEP_RAMP * transient, sweep=SWEEP, sweep_time=RAMP * transient
        ),
        "kick": Start("kick", preload=kick_pressure(scene)),
    }
    return [made[name] for name in names]


START_NAMES = ["abrupt", "ramp", "sweep-up", "sweep-down", "kick"]


def kick_pressure(scene):
    """The uniform pressure whose static deflection of the free edge is KICK of the narrower
    enabled gap, towards it: a clamped strip bends under p to w(L) = p·L⁴/(8D), D = E e³/(12(1 −
    ν²)) (cylindrical bending; the plate's free edges and a coarse mesh make it somewhat stiffer,
    so the deflection lands below the target, never past it by more than a few per cent)."""
    get = scene.get
    length, thickness = get("plate.length", 0.4), get("plate.thickness", 0.01)
    young, poisson = get("material.young_modulus", 2.1e11), get("material.poisson_ratio", 0.3)
    gaps = []
    if get("obstacle.upper_enabled", True):
        gaps.append(get("obstacle.upper", 0.01))
    if get("obstacle.lower_enabled", True):
        gaps.append(get("obstacle.lower", -0.01))
    target = (min(gaps, key=abs) if gaps else get("base.amplitude", 0.0)) * KICK
    stiffness = young * thickness**3 / (12 * (1 - poisson**2))
    return target * 8 * stiffness / length**4


def base_motion(start, amplitude, frequency, t):
    """(z, ż, z̈) of the base a start wants at time t < its sweep time: amplitude·A(t)·sin φ(t),
    A = sin²(πt/2T) over the ramp T, φ the phase of the frequency going linearly from
    (1 + sweep)·f to f, offset so that it meets the built-in sine's phase 2πf·t at the sweep's
    end (value and velocity then continuous)."""
    omega, s, ts = 2 * math.pi * frequency, start.sweep, start.sweep_time
    psi = -omega * s * ts / 2
    phi = psi + omega * (t + s * (t - t * t / (2 * ts)))
    dphi = omega * (1 + s * (1 - t / ts))
    ddphi = -omega * s / ts
    if t < start.ramp:
        k = math.pi / (2 * start.ramp)
        a, da, dda = math.sin(k * t) ** 2, k * math.sin(2 * k * t), 2 * k * k * math.cos(2 * k * t)
    else:
        a, da, dda = 1.0, 0.0, 0.0
    sin, cos = math.sin(phi), math.cos(phi)
    return (
        amplitude * a * sin,
        amplitude * (da * sin + a * dphi * cos),
        amplitude * (dda * sin + 2 * da * dphi * cos + a * (ddphi * cos - dphi * dphi * sin)),
    )


def input_drive(start, amplitude, frequency, t):
    """The input (z, ż, z̈) at time t: what the start wants less the built-in sine before its
    sweep time, 0 from then on."""
    if t >= start.sweep_time:
        return 0.0, 0.0, 0.0
    z, dz, ddz = base_motion(start, amplitude, frequency, t)
    omega = 2 * math.pi * frequency
    sin, cos = math.sin(omega * t), math.cos(omega * t)
    return (
        z - amplitude * sin,
        dz - amplitude * omega * cos,
        ddz + amplitude * omega * omega * sin,
    )


_CALLBACKS: list[object] = []
# instance name -> [(category, message)] of the warnings and errors that instance logged.
_LOGGED: dict[str, list[tuple[str, str]]] = {}


def stderr_callbacks():
    """FMI callbacks whose logger prints the FMU's warnings and errors to stderr (fmpy's default
    prints to stdout, whose last line is the verdict) and keeps them in _LOGGED under the
    instance's name. One per process: fmpy's native logger proxy forwards every message to the last
    Python logger installed; the instance name tells apart runs in the threads of one worker."""
    if not _CALLBACKS:
        from ctypes import byref

        from fmpy.fmi1 import calloc, free
        from fmpy.fmi2 import (
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
        )
        from fmpy.logging import addLoggerProxy

        def log(_env, instance, status, category, message):
            if status >= 1:  # fmi2Warning and worse
                print(f"[{category.decode()}] {message.decode()}", file=sys.stderr, flush=True)
                _LOGGED.setdefault(instance.decode(), []).append(
                    (category.decode(), message.decode())
                )

        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(log)
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(callbacks))
        _CALLBACKS.append(callbacks)
    return _CALLBACKS[0]


def run_setting(fmu_blob, digest, start_values, start, h, transient_steps, window_steps, windows):
    """Simulates the scene `start_values` from `start` (a Start), communicating every `h` seconds
    (a multiple of its Δt): `transient_steps` steps, then `windows` windows of `window_steps`
    steps each. Returns ({"windows": {quantity: [K window values]}, "warning": w, "cpu": c}, c),
    w the FMU's warning at initialization that the impact statistics may not converge (None
    without one), c the CPU seconds of this thread (the FMU runs single-threaded in it)."""
    from fmpy import read_model_description
    from fmpy.fmi2 import FMU2Slave
    from fmpy.simulation import apply_start_values

    directory = fmu_dir(fmu_blob, digest)
    md = read_model_description(directory)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    cpu0 = time.thread_time()
    instance = f"converge-{uuid.uuid4().hex}"
    fmu = FMU2Slave(
        guid=md.guid,
        unzipDirectory=directory,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=instance,
    )
    values = dict(start_values)
    if start.preload:
        values["initial.preload_pressure"] = (
            values.get("initial.preload_pressure", 0.0) + start.preload
        )
    amplitude = float(values.get("base.amplitude", 0.0))
    frequency = float(values.get("base.frequency", 10.0))
    n = windows * window_steps
    reals = np.empty((n + 1, len(REALS)))
    impacts = np.zeros(n + 1, dtype=np.int64)
    try:
        fmu.instantiate(callbacks=stderr_callbacks())
        fmu.setupExperiment(startTime=0.0)
        unknown = apply_start_values(fmu, md, values)
        if unknown:
            raise ValueError(f"not variables of the FMU: {sorted(unknown)}")
        z_vr = [vr["base.displacement"]]
        drive_steps = math.ceil(start.sweep_time / h) if start.drives() else 0

        def send(k):
            z, dz, ddz = input_drive(start, amplitude, frequency, k * h)
            fmu.setReal(z_vr, [z])
            fmu.setRealInputDerivatives(z_vr * 2, [1, 2], [dz, ddz])

        fmu.enterInitializationMode()
        if drive_steps:
            send(0)
        fmu.exitInitializationMode()
        warning = next(
            (
                message
                for category, message in _LOGGED.get(instance, [])
                if category == "logStatusWarning" and message.startswith(ADVICE_PREFIX)
            ),
            None,
        )
        real_vrs = [vr[name] for name in REALS]
        impacts_vr = [vr["contact.impacts"]]
        for k in range(transient_steps):
            if 0 < k <= drive_steps:
                send(k)
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
    return {
        "windows": window_values(reals, impacts, window_steps * h, windows),
        "warning": warning,
        "cpu": cpu,
    }, cpu
