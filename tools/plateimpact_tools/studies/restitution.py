"""The restitution study of docs/restitution/: the default impact law in the `energy` scene.

Runs the `energy` scene (fixed base, preload released above the lower obstacle g1 = -0.01 m,
10 x 7 Argyris) through `cargo run --release -p plate_impact_studies --bin restitution` and
writes

    docs/restitution/energy.png       E_{n+1/2} against t for several e (dt = 1e-4 s), and the energy
                                      kept at 1 s against e beside the former position-level law
    docs/restitution/corner.png       the free corner u(Lx, 0) against t for e = 0, 0.5 and 1
    docs/restitution/penetration.png  how far vertices pass the obstacle, and how far above it
                                      contacts turn, against dt (e = 0.5 and 1)

and prints the numbers of the tables in docs/restitution/README.md. Usage:
.venv/bin/python -m plateimpact_tools.studies.restitution [--out docs/restitution]   (about a minute)
"""

import argparse
import json
import pathlib
import subprocess
import tempfile

import numpy as np

from plateimpact_tools import ROOT
from plateimpact_tools.plotting import finish_axes, pyplot, save

plt = pyplot()

RESTITUTIONS = [0.0, 0.25, 0.5, 0.75, 0.9, 1.0]
TIME_STEPS = [1e-4, 5e-5, 2.5e-5, 1e-5]
CORNER_WINDOW = 0.15  # s: the first impacts
GAP = 0.01  # m: the energy scene's distance from the rest position to g1
# The former Paoli-Schatzman law (the bound on (u_{n+1} + e u_{n-1})/(1 + e)), measured with the
# code before Newton's law replaced it: E at 1 s over E at the first step (31.98 J), and the
# deepest vertex below g1 at dt = 1e-4 and 1e-5 s with e = 1.
FORMER_KEPT = {
    0.0: 9.82 / 31.98,
    0.25: 12.65 / 31.98,
    0.5: 12.81 / 31.98,
    0.75: 21.09 / 31.98,
    1.0: 109.60 / 31.98,
}
FORMER_PENETRATION = {1e-4: 1.37e-3, 1e-5: 0.16e-3}


def run(workdir, restitution, time_step=1e-4, law="auto", csv=True):
    """One run of the energy scene; returns (summary dict, trajectory dict or None)."""
    args = [
        "cargo",
        "run",
        "--release",
        "--quiet",
        "-p",
        "plate_impact_studies",
        "--bin",
        "restitution",
        "--",
        "energy",
        f"solver.restitution={restitution}",
        f"solver.time_step={time_step}",
        f"solver.impact_law={law}",
    ]
    path = pathlib.Path(workdir) / f"e{restitution}-dt{time_step}-{law}.csv"
    if csv:
        args += ["--csv", str(path), "--every", str(max(1, round(1e-4 / time_step)))]
    result = subprocess.run(args, cwd=ROOT, check=True, capture_output=True, text=True)
    summary = json.loads(result.stdout)
    if not csv:
        return summary, None
    data = np.genfromtxt(path, delimiter=",", names=True)
    return summary, {name: data[name] for name in data.dtype.names}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "restitution"))
    out = pathlib.Path(parser.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as workdir:
        runs = {e: run(workdir, e) for e in RESTITUTIONS}
        newton_zero = run(workdir, 0.0, law="newton")
        by_step = {
            (e, dt): run(workdir, e, dt, csv=False)[0] for e in (0.5, 1.0) for dt in TIME_STEPS
        }

    print(
        "e     law     E first (J)  E at 1 s (J)  kept   largest rise (J)  contact steps  "
        "penetration (m)  turn height (m)"
    )
    rows = [(e, "auto", s) for e, (s, _) in runs.items()] + [(0.0, "newton", newton_zero[0])]
    for e, law, s in rows:
        print(
            f"{e:<5} {law:<7} {s['energy_first']:11.4f}  {s['energy_last']:12.4f}  "
            f"{s['energy_last'] / s['energy_first']:5.3f}  {s['worst_rise']:16.1e}  "
            f"{s['contact_steps']:13d}  {s['penetration']:15.1e}  {s['standoff']:.2e}"
        )
    print("e    dt       penetration (m)  turn height (m)  E at 1 s / E first")
    for (e, dt), s in by_step.items():
        print(
            f"{e:<4} {dt:.1e}  {s['penetration']:15.1e}  {s['standoff']:15.2e}  "
            f"{s['energy_last'] / s['energy_first']:.4f}"
        )

    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(RESTITUTIONS)))
    fig, (ax, bars) = plt.subplots(1, 2, figsize=(11, 4.5), gridspec_kw={"width_ratios": [3, 2]})
    for colour, (e, (_, r)) in zip(colours, runs.items()):
        label = "e = 0 (paper)" if e == 0.0 else f"e = {e}"
        ax.plot(r["t"][1:], r["energy_total"][1:], color=colour, lw=1.2, label=label)
    ax.plot(
        newton_zero[1]["t"][1:],
        newton_zero[1]["energy_total"][1:],
        color="0.5",
        lw=1.0,
        ls="--",
        label="e = 0, Newton's law",
    )
    finish_axes(
        ax,
        "t (s)",
        "discrete energy $E_{n+1/2}$ (J)",
        "energy scene, Δt = 1e-4 s: default law",
        columns=2,
    )
    shown = [e for e in RESTITUTIONS if e in FORMER_KEPT]
    x = np.arange(len(shown))
    kept = [runs[e][0]["energy_last"] / runs[e][0]["energy_first"] for e in shown]
    bars.bar(x - 0.2, kept, 0.4, color="tab:blue", label="default law")
    bars.bar(
        x + 0.2,
        [FORMER_KEPT[e] for e in shown],
        0.4,
        color="tab:red",
        label="former position-level law",
    )
    bars.axhline(1.0, color="k", lw=0.8, ls=":")
    bars.set_xticks(x, [f"{e}" for e in shown])
    bars.set_yscale("log")
    finish_axes(
        bars, "restitution e", "E at 1 s / E at the first step", "energy kept over 1 s", axis="y"
    )
    save(fig, out / "energy.png", dpi=130)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for e, colour in [(0.0, colours[0]), (0.5, colours[2]), (1.0, colours[-1])]:
        r = runs[e][1]
        window = r["t"] <= CORNER_WINDOW
        ax.plot(r["t"][window], r["corner1"][window] * 1e3, color=colour, lw=1.2, label=f"e = {e}")
    ax.axhline(-10.0, color="k", lw=1.0, ls=":", label="lower obstacle g1")
    finish_axes(
        ax,
        "t (s)",
        "free corner u(Lx, 0) (mm)",
        f"energy scene, Δt = 1e-4 s: the corner over the first {CORNER_WINDOW} s",
    )
    save(fig, out / "corner.png", dpi=130)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for e, colour in [(0.5, colours[2]), (1.0, colours[-1])]:
        turn = [by_step[(e, dt)]["standoff"] / GAP for dt in TIME_STEPS]
        depth = [max(by_step[(e, dt)]["penetration"], 1e-18) / GAP for dt in TIME_STEPS]
        ax.loglog(TIME_STEPS, turn, "o-", color=colour, label=f"e = {e}: highest turn above g1")
        ax.loglog(
            TIME_STEPS, depth, "s--", color=colour, label=f"e = {e}: deepest below g1 (round-off)"
        )
    former = sorted(FORMER_PENETRATION)
    ax.loglog(
        former,
        [FORMER_PENETRATION[dt] / GAP for dt in former],
        "x:",
        color="tab:red",
        label="former law, e = 1: deepest below g1",
    )
    ax.loglog(
        TIME_STEPS,
        [0.02] * len(TIME_STEPS),
        color="0.6",
        lw=0.8,
        ls="-.",
        label="2 % of the gap (the penetration target)",
    )
    finish_axes(
        ax,
        "Δt (s)",
        "distance from g1 / gap",
        "energy scene, 1 s: where contacts turn, against Δt",
        which="both",
    )
    save(fig, out / "penetration.png", dpi=130)
    print(f"wrote {out / 'energy.png'}, {out / 'corner.png'} and {out / 'penetration.png'}")


if __name__ == "__main__":
    main()
