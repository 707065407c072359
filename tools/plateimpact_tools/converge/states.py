"""Steady states: the runs of one setting grouped by what distinguishes the responses they
settled on, and a state's value at every setting of a ladder.

Two runs are in the same state when they agree on whether the plate impacts at all and, for each
quantity compared, their values differ by no more than the tolerance or than 3σ of the difference
(`differ`; the frequency sweep tells its up and down branches apart by the same test). A state is
a connected group of runs under that relation (in the order of the starts, so the grouping is
deterministic). States are named A, B, … by the share of starts that reached them, largest first.

A state is followed down a ladder by its starts: its value at any setting is the mean over the
starts that reached it at the ladder's last setting, and its spread there the larger of their
windows' standard error (the RMS of theirs: starts on one periodic orbit repeat the same windows,
so averaging them removes no noise) and the standard deviation of their values. Where those
starts went to different states (a branch switch along the ladder) that scatter is the distance
between the states and no tolerance passes.
"""

import dataclasses
import math
from collections.abc import Sequence

import numpy as np

# Beyond the tolerance, two runs differ when the gap between their values exceeds this many
# standard deviations of the difference: a chaotic response scatters from run to run, and 3σ
# keeps a chance difference from being called a second state (0.3 % per comparison if Gaussian).
STATE_SIGMAS = 3.0

# A run's statistics at one setting: {quantity: (value, spread)}.
Stats = dict[str, tuple[float, float]]


def differ(
    a: Stats, b: Stats, quantities: Sequence[str], tolerance: float, sigmas: float = STATE_SIGMAS
) -> bool:
    """Whether two runs' statistics show different responses: one impacts (a positive
    `impact_rate`) and the other does not, or a quantity of `quantities` differs by more than
    `tolerance` of the pair's mean magnitude and more than `sigmas` of the difference's spread.
    `a`, `b`: {quantity: (value, spread)}, `impact_rate` among them."""
    if (a["impact_rate"][0] > 0) != (b["impact_rate"][0] > 0):
        return True
    for q in quantities:
        (va, sa), (vb, sb) = a[q], b[q]
        gap = abs(va - vb)
        sigma = math.hypot(sa, sb) if math.isfinite(sa) and math.isfinite(sb) else 0.0
        if gap > max(tolerance * 0.5 * (abs(va) + abs(vb)), sigmas * sigma):
            return True
    return False


@dataclasses.dataclass
class State:
    """A group of starts at one setting: `name` (A, B, …), `starts` (their indices, in start
    order)."""

    name: str
    starts: list[int]


def group(stats: Sequence[Stats], quantities: Sequence[str], tolerance: float) -> list[State]:
    """The states of one setting: `stats` holds per start (in start order) {quantity: (value,
    spread)}; runs are linked when they do not `differ` and each state is a connected group.
    Returns States named by share (largest first, ties by first start)."""
    parent = list(range(len(stats)))

    def root(i: int) -> int:
        while parent[i] != i:
            i = parent[i]
        return i

    for i in range(len(stats)):
        for j in range(i):
            if not differ(stats[i], stats[j], quantities, tolerance):
                parent[root(i)] = root(j)
    groups: dict[int, list[int]] = {}
    for i in range(len(stats)):
        groups.setdefault(root(i), []).append(i)
    ordered = sorted(groups.values(), key=lambda members: (-len(members), members[0]))
    return [State(name_of(k), members) for k, members in enumerate(ordered)]


def name_of(k: int) -> str:
    """A, B, …, Z, AA, AB, …"""
    name = ""
    k += 1
    while k:
        k, rest = divmod(k - 1, 26)
        name = chr(ord("A") + rest) + name
    return name


def state_value(
    stats: Sequence[Stats], members: Sequence[int], quantity: str
) -> tuple[float, float]:
    """(value, spread) of the state made of the starts `members` at a setting whose per-start
    statistics are `stats` (module docs)."""
    values = np.array([stats[m][quantity][0] for m in members])
    spreads = np.array([stats[m][quantity][1] for m in members])
    windows = math.sqrt(float(np.mean(spreads**2)))
    scatter = float(np.std(values, ddof=1)) if len(members) > 1 else 0.0
    return float(values.mean()), max(windows, scatter)


def impacting(stats: Sequence[Stats], members: Sequence[int]) -> tuple[bool, ...]:
    """Whether each of the starts `members` impacts at a setting: a tuple of booleans."""
    return tuple(stats[m]["impact_rate"][0] > 0 for m in members)
