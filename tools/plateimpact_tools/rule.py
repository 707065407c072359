"""The convergence rule of the study: when the last three settings of a ladder (a, b, c, each a
refinement of the one before) show a value converged to a tolerance, and the error bound printed
with it. docs/converge/README.md ("The rule") explains it; tests/fmu/test_converge_rule.py tries
it on synthetic ladders.

A value v with its spread σ (1σ, from the windows and the starts that reached the state) at each
setting; the changes d₁ = v_b − v_a and d₂ = v_c − v_b, each *significant* when it exceeds both
its noise, 2·σ_d with σ_d = √(σ² + σ²) of its two ends, and a tenth of the tolerance (FLOOR: a
smaller change matters to no one, and its size carries no information about an order). The rule
accepts v_c when

1. the last pair agrees: |d₂| + 2σ_d₂ ≤ tol·|v_c|;
2. the changes shrink: when d₂ is significant, d₁ is significant too and larger (a change that
   appears after a flat pair, or grows, is no convergence: a plateau-then-jump or a branch
   switch);
3. its error bound is within the tolerance: B ≤ tol·|v_c| (below), or with the bound of the
   other kind of ladder (Δt or mesh) that ends at the same setting, their sum;
4. the first pair agrees too, |d₁| + 2σ_d₁ ≤ tol·|v_c|, unless both changes are significant, of
   one sign, and the order p they show may be trusted: p ≤ P_TRUST, and `extrapolate` (the study
   trusts an order where the FMU does not warn at any of the three settings, the regime in which
   the project found its statistics to converge; docs/accuracy/damping.md). Then the bound alone
   judges d₁: a
   large first change is accepted when d₂ has shrunk enough for the extrapolation to bound the
   rest. Elsewhere two agreeing pairs are the least evidence: one agreeing pair is none (the
   damped preset from Δt = 1e-3 s agrees once, 9.26 then 9.22 J, at settings where the FMU
   warns, before falling to 8.61 J), and neither is a triple that looks like a power law there
   (with short windows the mass-damped scene reads 9.51, 9.71, 9.73 J from Δt = 1e-3 s, an
   observed order of 3.1 and an extrapolated error of 0.1 %, and then climbs past 12 J on to
   50 J; the FMU warns at every one of its settings).

The error bound B of v_c is Roache's grid convergence index of the three settings plus the noise
of v_c: B = F·|d₂|/(r^p − 1) + 2σ_c, with F = SAFETY, r the refinement ratio of the last pair
and p the observed order (solved from d₁/d₂ and the two ratios) capped at P_MAX. For a ladder
converging monotonically at an order p ≤ P_MAX in its asymptotic range, the true error of v_c is
|d₂|/(r^p − 1) plus its noise: B contains it with the margin F. When the changes alternate in
sign (the value oscillates about its limit with a shrinking amplitude, as a mesh ladder's often
does) the limit lies between v_b and v_c and B = F·|d₂| + 2σ_c. When d₂ is not significant no
order is observed; then B = F·(|d₂| + 2σ_d₂)/(r^P_MIN − 1) + 2σ_c, which holds for any order
≥ P_MIN.
"""

import dataclasses
import math
from collections.abc import Sequence

# Confidence factor on a spread (2σ: about 95 % if Gaussian).
SIGMAS = 2.0
# Roache's factor of safety for a grid convergence index from three grids.
SAFETY = 1.25
# The largest order believed: the scheme is second order in Δt without contact, first order or
# less across impacts (docs/accuracy/), and an observed order above 2 is taken as 2, which widens
# the bound. The smallest assumed when no order can be observed (changes within the noise).
P_MAX = 2.0
P_MIN = 1.0
# A change below this fraction of the tolerance is treated as no change (module docs).
FLOOR = 0.1
# The largest observed order trusted to stand in for the first pair's agreement. The scheme is
# second order in Δt and impacts cut the elements' order in the cell size; the project's ladders
# show up to 3.1 in Δt and 4.5 in the mesh where both pairs agree anyway. A larger "order" is a
# first change that is a jump (the end of a plateau, a change of branch, the coarsest mesh far off)
# and a second that is what is left after it: no power law to extrapolate (the damped preset's
# mean energy on Argyris 3 × 2, 5 × 3, 8 × 5 reads 9.43, 8.62, 8.61 J: an "order" of 8.7).
P_TRUST = 4.0


@dataclasses.dataclass(frozen=True)
class Judgement:
    """What the rule says of the last three settings: `accepted`, the error bound `bound` of
    v_c (absolute, same unit), the observed order (None when the last change is within its
    noise or the changes alternate), and `why` (a short reason when rejected)."""

    accepted: bool
    bound: float
    order: float | None
    why: str = ""


def observed_order(d1: float, d2: float, r1: float, r2: float) -> float:
    """The order p with d₁/d₂ = r₂^p·(r₁^p − 1)/(r₂^p − 1): the two changes of a value
    v = v∞ + C·h^p over three settings whose step h shrinks by r₁ then r₂ (r₁ = r₂ = r gives
    p = log_r(d₁/d₂)). For same-signed changes with |d₂| < |d₁|; bisection on p ∈ (0, 30]."""
    target = abs(d1 / d2)

    def ratio(p: float) -> float:
        return r2**p * (r1**p - 1) / (r2**p - 1)

    lo, hi = 1e-9, 30.0
    if ratio(hi) < target:
        return hi
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if ratio(mid) < target:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def judge(
    values: Sequence[float],
    spreads: Sequence[float],
    ratios: tuple[float, float],
    tolerance: float,
    extrapolate: bool = True,
    taken: float = 0.0,
) -> Judgement:
    """The rule (module docs) on a ladder's last three settings: `values` v_a, v_b, v_c,
    `spreads` their 1σ, `ratios` (r₁, r₂) the refinement ratios a → b and b → c (2 for halving
    Δt; the ratio of the cell sizes for a mesh), `tolerance` relative; `extrapolate`: whether an
    observed order may stand in for the first pair's agreement (point 4); `taken`: the part of
    the tolerance (absolute) another bound of v_c already takes (point 3 asks B + taken ≤
    tol·|v_c|)."""
    (va, vb, vc), (sa, sb, sc), (r1, r2) = values, spreads, ratios
    scale = abs(vc)
    d1, d2 = vb - va, vc - vb
    s1, s2 = math.hypot(sa, sb), math.hypot(sb, sc)
    noise = SIGMAS * sc
    if not all(math.isfinite(x) for x in (va, vb, vc, s1, s2)):
        return Judgement(False, math.inf, None, "no spread to judge by")
    floor = FLOOR * tolerance * scale
    significant1 = abs(d1) > max(SIGMAS * s1, floor)
    significant2 = abs(d2) > max(SIGMAS * s2, floor)
    if significant2 and not significant1:
        return Judgement(False, math.inf, None, "a change after a flat pair")
    if significant2 and abs(d2) >= abs(d1):
        return Judgement(False, math.inf, None, "the changes do not shrink")
    order = None
    if not significant2:
        bound = SAFETY * (abs(d2) + SIGMAS * s2) / (r2**P_MIN - 1) + noise
    elif d1 * d2 < 0:  # an oscillation about the limit: it lies between v_b and v_c
        bound = SAFETY * abs(d2) + noise
    else:
        order = observed_order(d1, d2, r1, r2)
        bound = SAFETY * abs(d2) / (r2 ** min(order, P_MAX) - 1) + noise
    trusted = extrapolate and order is not None and order <= P_TRUST
    pairs = [(d2, s2)] if trusted else [(d1, s1), (d2, s2)]
    if any(abs(d) + SIGMAS * s > tolerance * scale for d, s in pairs):
        return Judgement(False, bound, order, "a pair disagrees")
    if bound + taken > tolerance * scale:
        return Judgement(False, bound, order, "the error bound exceeds the tolerance")
    return Judgement(True, bound, order)


def pair_passes(va: float, sa: float, vb: float, sb: float, tolerance: float) -> bool:
    """One pair of successive settings agrees: |v_a − v_b| + 2σ_ab ≤ tol·|v_b|."""
    return abs(va - vb) + SIGMAS * math.hypot(sa, sb) <= tolerance * abs(vb)
