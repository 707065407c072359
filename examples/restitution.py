"""The restitution figures of docs/restitution/: energy and corner trajectory against e.

Runs the `energy` scene (fixed base, preload released above the lower obstacle g1 = -0.01 m)
through `cargo run --release --example scene` for e = 0, 0.25, 0.5, 0.75, 1 at the shipped
dt = 1e-4 s, and e = 1 also at dt = 1e-5 s, then writes

    docs/restitution/energy.png   E_{n+1/2} against t for the five e (and e = 1 at dt = 1e-5)
    docs/restitution/corner.png   the free corner u(Lx, 0) against t for e = 0 and e = 1 (0-0.15 s)

and prints, per run, the energy at the first step and at 1 s and the deepest point the corner
reaches. Usage: .venv/bin/python examples/restitution.py [--out docs/restitution]
"""

import argparse
import pathlib
import subprocess
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parent.parent
RESTITUTIONS = [0.0, 0.25, 0.5, 0.75, 1.0]
CORNER_WINDOW = 0.15  # s: the first impacts, where the two laws part


def run_scene(restitution, time_step, workdir):
    """One run of the energy scene; returns the CSV columns as a dict of arrays."""
    path = pathlib.Path(workdir) / f"energy-e{restitution}-dt{time_step}.csv"
    every = max(1, round(1e-4 / time_step))  # plot at 1e-4 s resolution
    subprocess.run(
        ["cargo", "run", "--release", "--quiet", "--example", "scene", "--", "energy",
         f"solver.restitution={restitution}", f"solver.time_step={time_step}",
         "--every", str(every), "--out", str(path)],
        cwd=ROOT, check=True, stderr=subprocess.DEVNULL,
    )
    data = np.genfromtxt(path, delimiter=",", names=True)
    return {name: data[name] for name in data.dtype.names}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "restitution"))
    out = pathlib.Path(parser.parse_args().out)
    out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as workdir:
        runs = {e: run_scene(e, 1e-4, workdir) for e in RESTITUTIONS}
        fine = run_scene(1.0, 1e-5, workdir)

    print("e      dt     E(first step) J  E(1 s) J  lost J   min corner m")
    table = [(e, 1e-4, r) for e, r in runs.items()] + [(1.0, 1e-5, fine)]
    for e, dt, r in table:
        first, last = r["energy_total"][1], r["energy_total"][-1]
        print(f"{e:<5}  {dt:.0e}  {first:15.4f}  {last:8.4f}  {first - last:7.3f}  "
              f"{r['corner1'].min():.5f}")

    colours = plt.cm.viridis(np.linspace(0.0, 0.9, len(RESTITUTIONS)))
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for colour, (e, r) in zip(colours, runs.items()):
        ax.plot(r["t"][1:], r["energy_total"][1:], color=colour, lw=1.2, label=f"e = {e}")
    ax.plot(fine["t"][1:], fine["energy_total"][1:], color="0.4", lw=1.0, ls="--",
            label="e = 1, Δt = 1e-5 s")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("discrete energy $E_{n+1/2}$ (J)")
    ax.set_title("energy scene (fixed base, Δt = 1e-4 s unless noted): energy against restitution e")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, ncol=2)
    fig.tight_layout()
    fig.savefig(out / "energy.png", dpi=130)

    fig, ax = plt.subplots(figsize=(8, 4.5))
    for e, colour in [(0.0, colours[0]), (1.0, colours[-1])]:
        r = runs[e]
        shown = r["t"] <= CORNER_WINDOW
        ax.plot(r["t"][shown], r["corner1"][shown] * 1e3, color=colour, lw=1.2, label=f"e = {e}")
    ax.axhline(-10.0, color="k", lw=1.0, ls=":", label="lower obstacle g1")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("free corner u(Lx, 0) (mm)")
    ax.set_title(f"energy scene, Δt = 1e-4 s: corner trajectory for e = 0 and e = 1 (first {CORNER_WINDOW} s)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "corner.png", dpi=130)
    print(f"wrote {out / 'energy.png'} and {out / 'corner.png'}")


if __name__ == "__main__":
    main()
