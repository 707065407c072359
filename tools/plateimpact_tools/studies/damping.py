"""The damping figure of docs/damping/: a released plate with and without Rayleigh damping.

Runs the `energy` scene without obstacles (the plate lifted by its preload, released at rest, fixed
base) through `cargo run --release --example scene` undamped and with mass-proportional damping
alpha = 2 zeta omega_1 for zeta_1 = 0.02 (omega_1 from `cargo run --release --example modes`), then
writes

    docs/damping/release.png   the free corner u(Lx, 0) and the discrete energy against t, both runs,
                               with the envelope exp(-zeta_1 omega_1 t) of the first mode

and prints the damping ratio measured from the corner's peaks (log decrement over successive peaks).
Usage: .venv/bin/python -m plateimpact_tools.studies.damping [--out docs/damping]
"""

import argparse
import math
import pathlib
import re
import subprocess
import tempfile

import numpy as np

from plateimpact_tools import ROOT
from plateimpact_tools.plotting import pyplot, save

plt = pyplot()

ZETA = 0.02
STOP = 0.3  # s: about 16 periods of the first mode


def first_angular_frequency():
    """omega_1 (rad/s) of the paper's 10 x 7 Argyris plate, from the modes example."""
    out = subprocess.run(
        ["cargo", "run", "--release", "--quiet", "--example", "modes", "--", "argyris", "10", "7"],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    f1 = float(re.search(r"mode 1: ([0-9.]+) Hz", out).group(1))
    return 2 * math.pi * f1


def run(alpha, workdir):
    """The released plate with damping.mass_proportional = alpha; the CSV columns as arrays."""
    path = pathlib.Path(workdir) / f"release-{alpha}.csv"
    subprocess.run(
        [
            "cargo",
            "run",
            "--release",
            "--quiet",
            "--example",
            "scene",
            "--",
            "energy",
            "obstacle.lower_enabled=false",
            f"stop_time={STOP}",
            f"damping.mass_proportional={alpha}",
            "--out",
            str(path),
        ],
        cwd=ROOT,
        check=True,
        stderr=subprocess.DEVNULL,
    )
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


def measured_zeta(t, u):
    """zeta from the log decrement of the positive peaks of u (least-squares over all of them)."""
    peaks = [i for i in range(1, len(u) - 1) if u[i] > 0 and u[i] >= u[i - 1] and u[i] > u[i + 1]]
    delta = -np.polyfit(np.arange(len(peaks)), np.log(u[peaks]), 1)[0]
    return delta / math.sqrt(4 * math.pi**2 + delta**2), len(peaks)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "damping"))
    out = pathlib.Path(parser.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)
    omega = first_angular_frequency()
    alpha = 2 * ZETA * omega
    with tempfile.TemporaryDirectory() as workdir:
        undamped, damped = run(0.0, workdir), run(alpha, workdir)
    zeta, peaks = measured_zeta(damped["t"], damped["corner1"])
    print(
        f"omega_1 = {omega:.2f} rad/s, alpha = {alpha:.4f} 1/s for zeta_1 = {ZETA}; "
        f"measured from {peaks} peaks: zeta_1 = {zeta:.5f}"
    )

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    t = damped["t"]
    ax1.plot(undamped["t"], 1e3 * undamped["corner1"], lw=0.8, color="0.6", label="undamped")
    ax1.plot(
        t,
        1e3 * damped["corner1"],
        lw=0.9,
        color="C0",
        label=f"Rayleigh, α = {alpha:.2f} 1/s (ζ₁ = {ZETA})",
    )
    envelope = 1e3 * damped["corner1"][0] * np.exp(-ZETA * omega * t)
    ax1.plot(t, envelope, "--", lw=0.8, color="C3", label="exp(−ζ₁ω₁t)")
    ax1.plot(t, -envelope, "--", lw=0.8, color="C3")
    ax1.set_ylabel("corner u(Lx, 0) (mm)")
    ax1.legend(loc="upper right", fontsize=8)
    ax1.set_title(
        f"Released plate, no obstacles (10 × 7 Argyris, Δt = 1e-4 s): measured ζ₁ = {zeta:.4f}"
    )
    ax2.plot(undamped["t"], undamped["energy_total"], lw=0.9, color="0.6", label="undamped")
    ax2.plot(t, damped["energy_total"], lw=0.9, color="C0", label="damped")
    ax2.set_xlabel("t (s)")
    ax2.set_ylabel("discrete energy (J)")
    ax2.legend(loc="upper right", fontsize=8)
    save(fig, out / "release.png", dpi=120)
    print(f"wrote {out / 'release.png'}")


if __name__ == "__main__":
    main()
