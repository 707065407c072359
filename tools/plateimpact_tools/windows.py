"""Statistics of a steady state over windows of a recorded run: one definition for
scripts/converge and the frequency sweep.

A record holds outputs sampled at communication points: row 0 at the start of the measured span,
row j after its j-th step. A count (`contact.impacts`) belongs to the step that ends at its row,
so the impacts inside a span that starts at row a are those of rows a+1, a+2, …. A span of
K windows is split into K equal runs of whole steps; a window's value of a time average uses the
samples after its own steps (rows a+1 … b), a rate the change of a cumulative output across it
(row b minus row a) over its length.

The spread of a statistic over K windows is the standard deviation of the window values; the
standard error of their mean, that spread / √K, is what the value of the whole span is known to
if the windows are independent (the statistics study, docs/accuracy/statistics.md).
"""

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

# The steady-state quantities of scripts/converge: name -> (unit, one-line definition).
QUANTITIES = {
    "mean_energy": ("J", "time mean of energy.total"),
    "rms_corner": ("m", "RMS of corner1.displacement u(Lx, 0)"),
    "peak_corner": ("m", "max |u| over the free corners (Lx, 0), (Lx, Ly)"),
    "rms_base_force": ("N", "RMS of base.mean_force"),
    "damping_loss_rate": ("W", "energy.damping_loss gained per second"),
    "contact_loss_rate": ("W", "energy.contact_loss gained per second"),
    "impact_rate": ("1/s", "contact.impacts per second"),
}
# The Real outputs `window_values` reads, in the order of its record's columns.
REALS = [
    "corner1.displacement",
    "corner2.displacement",
    "energy.total",
    "energy.damping_loss",
    "energy.contact_loss",
    "base.mean_force",
]


def rms(x: ArrayLike) -> float:
    """Root mean square of the samples x."""
    return float(np.sqrt(np.mean(np.asarray(x) ** 2)))


def standard_error(values: Sequence[float] | np.ndarray) -> float:
    """Standard deviation of `values` (ddof = 1) / √K: the standard error of their mean; NaN for
    fewer than two values."""
    k = len(values)
    return float(np.std(values, ddof=1) / math.sqrt(k)) if k > 1 else math.nan


def window_values(
    reals: Sequence[Sequence[float]] | np.ndarray, impacts: np.ndarray, length: float, windows: int
) -> dict[str, list[float]]:
    """Each quantity of QUANTITIES in each window: `reals` holds REALS at the first window's start
    and after each step, `impacts` the impacts of the step ending at each sample, `length` (s) is
    one window's duration."""
    c1, c2, energy, damping, contact, force = np.asarray(reals).T
    steps = (len(reals) - 1) // windows
    out: dict[str, list[float]] = {q: [] for q in QUANTITIES}
    for i in range(windows):
        a, b = i * steps, (i + 1) * steps  # the samples after the window's steps: a+1 … b
        inside = slice(a + 1, b + 1)
        out["mean_energy"].append(float(np.mean(energy[inside])))
        out["rms_corner"].append(rms(c1[inside]))
        out["peak_corner"].append(float(max(np.abs(c1[inside]).max(), np.abs(c2[inside]).max())))
        out["rms_base_force"].append(rms(force[inside]))
        out["damping_loss_rate"].append(float(damping[b] - damping[a]) / length)
        out["contact_loss_rate"].append(float(contact[b] - contact[a]) / length)
        out["impact_rate"].append(float(impacts[inside].sum()) / length)
    return out


def value_and_spread(quantity: str, values: ArrayLike) -> tuple[float, float]:
    """A run's value and spread from its window values: the mean and its standard error, or for
    the peak (a maximum, not a mean) the largest window peak and the standard deviation of the
    window peaks."""
    values = np.asarray(values, dtype=float)
    if quantity == "peak_corner":
        k = len(values)
        return float(values.max()), float(np.std(values, ddof=1)) if k > 1 else math.nan
    return float(values.mean()), standard_error(values)


def last_whole_periods(frequency: float, stop_time: float, step: float) -> tuple[int, int]:
    """The analysis window of a run from rest of `stop_time` seconds sampled every `step`: the
    last N = ⌊f·T/2⌋ whole forcing periods, so inside the run's last half. Returns (first row,
    N); with no whole period in the last half, the last half and N = 0."""
    periods = int(np.floor(frequency * stop_time / 2.0 + 1e-9))
    if periods > 0:
        return int(round((stop_time - periods / frequency) / step)), periods
    return int(round(0.5 * stop_time / step)), 0


def period_blocks(
    periods: int, blocks: int, periods_per_step: float, steps: int
) -> list[tuple[int, int]]:
    """Row bounds of `blocks` blocks of whole forcing periods in a span of `periods` periods and
    `steps` steps (`periods_per_step` = f·h): block k holds periods [round(kP/B), round((k+1)P/B)),
    to the nearest step, as (a, b) slices of the rows after the span's first."""
    edges = [
        min(steps, round(round(k * periods / blocks) / periods_per_step)) for k in range(blocks + 1)
    ]
    return [(a, b) for a, b in zip(edges, edges[1:]) if b > a]
