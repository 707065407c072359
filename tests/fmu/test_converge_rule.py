"""The convergence rule of scripts/converge (plateimpact_tools.rule) and the grouping of
runs into steady states (plateimpact_tools.converge.states) on synthetic ladders: no FMU runs.

A ladder is walked as the study walks it: after each refinement the rule judges the last three
settings, and the first accepted setting is what the study would recommend. The rule must not
accept a plateau followed by a jump, a branch switch, a slow drift or noise beyond what the
tolerance allows; where it accepts, the printed error bound must contain the true error."""

import math
import random

from plateimpact_tools import rule
from plateimpact_tools.converge import states

TOL = 0.01


def first_accepted(values, spreads, ratio=2.0, tolerance=TOL, warned=None):
    """(index, Judgement) of the first setting the rule accepts walking down the ladder, or
    (None, None). `warned`: per setting, whether the FMU warns there (the study then trusts no
    observed order in a triple that holds such a setting); default nowhere."""
    warned = warned or [False] * len(values)
    for n in range(2, len(values)):
        j = rule.judge(
            values[n - 2 : n + 1],
            spreads[n - 2 : n + 1],
            (ratio, ratio),
            tolerance,
            extrapolate=not any(warned[n - 2 : n + 1]),
        )
        if j.accepted:
            return n, j
    return None, None


def test_the_damped_preset_from_a_coarse_step_does_not_pass_on_its_plateau():
    """The mean energy (J) of the damped preset on Argyris 10 × 7 measured with 8 windows of
    10 periods from Δt = 1e-3 s halving (a run of this study's windows; the window spread
    2.5e-3 J at each; the FMU warns down to 1.25e-4 s): 9.26 and 9.22 agree within 1 %, and one
    passing pair accepted 9.22 J before. The rule refuses the triples up to the jump and after it
    until two pairs agree (9.22 → 8.85 grows; 8.85 → 8.65 → 8.62 has a first change of 2.3 %, at
    settings where the FMU warns) and accepts 8.619 J at Δt = 3.1e-5 s, its bound containing the
    distance to the ladder's last value, at 7.8e-6 s, and so at every later setting. Were the
    observed order trusted at the warned settings, 8.623 J at 6.25e-5 s would pass, also
    within its bound."""
    values = [9.25862, 9.22012, 8.85005, 8.64616, 8.62334, 8.61869, 8.61401, 8.61316]
    spreads = [1.2e-3, 1.9e-3, 2.4e-3, 2.4e-3, 2.5e-3, 2.3e-3, 2.3e-3, 2.2e-3]
    warned = [True] * 4 + [False] * 4
    assert rule.pair_passes(values[0], spreads[0], values[1], spreads[1], TOL)
    n, j = first_accepted(values, spreads, warned=warned)
    assert n == 5, (n, j)
    assert abs(values[n] - values[-1]) <= j.bound
    for k in range(n + 1, len(values)):  # and every later setting with the bound it prints
        j = rule.judge(values[k - 2 : k + 1], spreads[k - 2 : k + 1], (2, 2), TOL)
        assert j.accepted and abs(values[k] - values[-1]) <= j.bound
    n, j = first_accepted(values, spreads)
    assert n == 4 and abs(j.order - 3.16) < 0.01 and abs(values[n] - values[-1]) <= j.bound


def test_the_mass_damped_scene_from_a_coarse_step_never_passes():
    """α only, ζ₁ = 1 % (the same plate and forcing, measured as above): the mean energy turns
    back (9.51, 9.76, 9.73 J: one pair agreed, and was accepted before) and then climbs; no triple
    of the ladder passes. Measured with 4 windows of 0.2 s after 0.5 s, the first three read
    9.507, 9.709, 9.733 J, shrinking changes with an observed order of 3.1, which an extrapolation
    alone would accept at 0.1 %: the first pair's 2.1 % refuses it."""
    values = [9.51070, 9.76142, 9.73079, 12.22942, 12.82790, 22.28414, 28.85110]
    spreads = [9.6e-4, 9.0e-3, 3.4e-3, 0.11, 0.33, 0.62, 0.69]
    assert rule.pair_passes(values[1], spreads[1], values[2], spreads[2], TOL)
    assert first_accepted(values, spreads, warned=[True] * len(values)) == (None, None)
    assert first_accepted(values, spreads) == (None, None)
    short = ([9.50696, 9.70891, 9.73298], [2.1e-3, 4.8e-3, 1.0e-3], (2, 2), TOL)
    j = rule.judge(*short, extrapolate=False)
    assert not j.accepted and j.why == "a pair disagrees"
    assert abs(j.order - 3.1) < 0.05 and j.bound < 0.002 * 9.73298
    assert rule.judge(*short, extrapolate=True).accepted  # why the warning withholds trust


def test_a_plateau_then_a_jump_is_refused_until_the_jump_settles():
    """Two equal values (a pair that passes), then a 7 % jump, then convergence at order 1 to
    8.6: the triple whose last change is the jump is refused as a change after a flat pair, the
    next as turning or not shrinking; the first accepted setting lies beyond the jump and its
    bound contains the error."""
    limit = 8.6
    values = [9.22, 9.22] + [limit + 0.4 * 2.0**-k for k in range(8)]
    spreads = [1e-4] * len(values)
    j = rule.judge(values[:3], spreads[:3], (2, 2), TOL)
    assert not j.accepted and j.why == "a change after a flat pair"
    n, j = first_accepted(values, spreads)
    assert n is not None and n >= 4
    assert abs(values[n] - limit) <= j.bound


def test_a_branch_switch_is_refused():
    """A start that settles on a quiet state (0.186 J) at coarse steps and on an impacting one
    (0.614 J) from a finer step on: the triples that straddle the switch are refused (a jump
    after a flat pair, then a flat pair after a jump whose first change fails the tolerance);
    the impacting state is accepted only once three settings agree on it, whether an observed
    order is trusted or not."""
    values = [0.186, 0.186, 0.186, 0.614, 0.6142, 0.6143, 0.61435]
    spreads = [1e-5] * len(values)
    assert not rule.judge(values[1:4], spreads[1:4], (2, 2), TOL).accepted
    assert not rule.judge(values[2:5], spreads[2:5], (2, 2), TOL).accepted
    n, j = first_accepted(values, spreads)
    assert n == 2  # the quiet state itself converges at the coarse steps: it exists there
    for warned in (None, [True] * 6):
        n, j = first_accepted(values[1:], spreads[1:], warned=warned)
        assert n == 4 and values[1:][n] > 0.6


def test_slow_drift_is_accepted_only_with_a_bound_that_contains_its_error():
    """A value drifting like the contact loss rate (W) of the damped preset, 19 + 140·(Δt/Δt₀)^0.6
    (order 0.6: each halving shrinks the change by 1.5): from the first triple the observed order
    is 0.6 and the bound (|d₂|/(2^0.6 − 1), 1.9 times the last change) stays above 1 % until far
    down the ladder; where it is accepted the bound contains the true error."""
    limit = 19.0
    values = [limit + 140.0 * 2.0 ** (-0.6 * k) for k in range(40)]
    spreads = [1e-6 * v for v in values]
    n, j = first_accepted(values, spreads)
    assert n is not None and n > 10
    assert abs(j.order - 0.6) < 1e-6
    assert abs(values[n] - limit) <= j.bound
    # One pair passing at 1 % happens long before: the old rule would have stopped there.
    early = next(
        k
        for k in range(1, len(values))
        if rule.pair_passes(values[k - 1], spreads[k - 1], values[k], spreads[k], TOL)
    )
    assert early < n and abs(values[early] - limit) > TOL * limit


def test_the_bound_contains_the_error_of_accepted_power_laws():
    """Noise-free ladders v = L + C·h^p with orders 0.5 to 3 in Δt (ratio 2) and in the mesh
    (ratio 1.5), either sign, the observed order trusted or not: wherever the rule accepts, the
    bound contains |v − L|; an observed order above P_MAX is capped, which only widens the
    bound."""
    accepted = 0
    for ratio in (2.0, 1.5):
        for p in (0.5, 0.8, 1.0, 1.5, 2.0, 3.0):
            for c in (0.5, -0.3):
                values = [10.0 + c * ratio ** (-p * k) for k in range(30)]
                for warned in (None, [True] * 30):
                    n, j = first_accepted(values, [0.0] * len(values), ratio, warned=warned)
                    assert n is not None, (ratio, p, c)
                    assert abs(values[n] - 10.0) <= j.bound, (ratio, p, c, j)
                    accepted += 1
    assert accepted == 48


def test_noisy_chaotic_values_are_bounded_at_their_noise():
    """A chaotic statistic: the limit 5.0 plus Gaussian noise of 1σ = 0.1 % at every setting,
    no discretisation error, its spread given as that σ. Over 2000 seeded ladders the rule
    accepts most at once (the changes lie within the noise) and its bound then contains the
    true error at least as often as 2σ of a Gaussian would (95 %); with 1σ = 1 % (the
    tolerance) it accepts none."""
    rng = random.Random(20250101)
    limit, inside, accepted = 5.0, 0, 0
    for _ in range(2000):
        sigma = 0.001 * limit
        values = [rng.gauss(limit, sigma) for _ in range(3)]
        j = rule.judge(values, [sigma] * 3, (2, 2), TOL)
        if j.accepted:
            accepted += 1
            inside += abs(values[-1] - limit) <= j.bound
    assert accepted > 1600
    assert inside >= 0.95 * accepted
    for _ in range(200):
        sigma = 0.01 * limit
        values = [rng.gauss(limit, sigma) for _ in range(3)]
        assert not rule.judge(values, [sigma] * 3, (2, 2), TOL).accepted


def test_an_oscillation_about_the_limit_is_bounded_by_its_last_change():
    """The mean energy of the damped preset along a mesh ladder (Argyris 5 × 3, 8 × 5, 12 × 8:
    8.623, 8.608, 8.609 J) turns back by 1e-3 J; decaying oscillations L + C·(−q)^k with
    q = 0.3 to 0.8 are accepted with a bound that contains the error; an oscillation that does
    not decay (q = 1) is refused."""
    j = rule.judge([8.623, 8.608, 8.609], [1e-5] * 3, (1.5, 1.5), TOL)
    assert j.accepted and j.order is None and j.bound < 3e-3
    for q in (0.3, 0.5, 0.8):
        values = [7.0 + 0.5 * (-q) ** k for k in range(40)]
        n, j = first_accepted(values, [0.0] * 40)
        assert n is not None and abs(values[n] - 7.0) <= j.bound, (q, n, j)
    values = [7.0 + 0.01 * (-1) ** k for k in range(10)]
    assert first_accepted(values, [0.0] * 10) == (None, None)


def test_an_order_beyond_belief_is_no_extrapolation():
    """The damped preset's mean energy on Argyris 3 × 2, 5 × 3, 8 × 5 (J): a first change of
    9.4 % and an "order" of 8.7, which would extrapolate to a 0.13 % bound: refused, the first
    pair disagreeing; the triple one mesh further (8.62, 8.608, 8.609) passes."""
    ratios = ((15 / 6) ** 0.5, (40 / 15) ** 0.5)
    j = rule.judge([9.43007, 8.62317, 8.60807], [1e-5] * 3, ratios, TOL)
    assert j.order > rule.P_TRUST and not j.accepted and j.why == "a pair disagrees"
    ratios = ((40 / 15) ** 0.5, (96 / 40) ** 0.5)
    assert rule.judge([8.62317, 8.60807, 8.60926], [1e-5] * 3, ratios, TOL).accepted


def test_the_other_ladders_bound_counts_against_the_tolerance():
    """A Δt triple whose own bound is 0.85 % of the value (the RMS corner of the documented
    example on Argyris 14 × 8) passes alone and fails when the mesh ladder ending at the same
    setting already takes 0.16 %: the sum of the two bounds must be within the tolerance."""
    values, spreads = [0.00692598, 0.00685871, 0.00682145], [3e-8] * 3
    alone = rule.judge(values, spreads, (2, 2), TOL)
    assert alone.accepted and 0.008 < alone.bound / values[-1] < 0.009
    j = rule.judge(values, spreads, (2, 2), TOL, taken=1.06e-5)
    assert not j.accepted and j.why == "the error bound exceeds the tolerance"


def test_the_order_solves_unequal_ratios():
    """v = 1 + h^1.7 on cell sizes 1, 1/1.5, 1/(1.5·1.6): the order solved from the two changes
    and the two ratios is 1.7, and log_r(d₁/d₂) for equal ratios."""
    h = [1.0, 1 / 1.5, 1 / 2.4]
    v = [1 + x**1.7 for x in h]
    assert abs(rule.observed_order(v[1] - v[0], v[2] - v[1], 1.5, 1.6) - 1.7) < 1e-9
    assert abs(rule.observed_order(0.4, 0.1, 2.0, 2.0) - 2.0) < 1e-9


def run(energy, rms, impacts, spread=1e-4):
    return {
        "mean_energy": (energy, spread * energy),
        "rms_corner": (rms, spread * rms),
        "impact_rate": (impacts, 0.0),
    }


def test_runs_group_into_states_by_impacts_and_values():
    """Five starts at one setting: three on an impacting state (two impacts per period at
    68 Hz), two on a quiet one, the quiet pair 0.02 % apart (within the tolerance): two states,
    the larger named A. A third value 5 % off is a state of its own; so is a run that impacts
    with the quiet run's values."""
    stats = [
        run(16.07, 7.42e-3, 136.0),
        run(5.581, 4.58e-3, 0.0),
        run(16.07, 7.42e-3, 136.0),
        run(5.582, 4.58e-3, 0.0),
        run(16.07, 7.42e-3, 136.0),
    ]
    found = states.group(stats, ["mean_energy", "rms_corner", "impact_rate"], TOL)
    assert [(s.name, s.starts) for s in found] == [("A", [0, 2, 4]), ("B", [1, 3])]
    value, spread = states.state_value(stats, [1, 3], "mean_energy")
    assert abs(value - 5.5815) < 1e-12 and spread > 0
    stats.append(run(16.07 * 1.05, 7.42e-3, 136.0))
    stats.append(run(5.581, 4.58e-3, 3.0))
    found = states.group(stats, ["mean_energy", "rms_corner", "impact_rate"], TOL)
    assert [s.starts for s in found] == [[0, 2, 4], [1, 3], [5], [6]]
    assert [s.name for s in found] == ["A", "B", "C", "D"]


def test_a_state_whose_starts_split_has_the_spread_of_the_split():
    """Followed down a ladder by its starts, a state whose two starts were on different states
    at a coarser setting gets their scatter as its spread there, and no pair can pass."""
    coarse = [run(0.186, 1e-3, 0.0), run(0.614, 2e-3, 20.0)]
    value, spread = states.state_value(coarse, [0, 1], "mean_energy")
    assert abs(value - 0.4) < 1e-12
    assert spread > 0.2
    assert not rule.pair_passes(value, spread, 0.614, 1e-5, TOL)
    assert states.name_of(0) == "A" and states.name_of(25) == "Z" and states.name_of(26) == "AA"
    assert not math.isnan(spread)
