# SPDX-License-Identifier: LGPL-2.1-or-later
"""Lengths scaled to a part, FreeCAD-free (tested by pytest): the rotational sweep's
default tolerance and deflection, a thousandth of the part's bounding-box diagonal
rounded down to 1, 2 or 5 times a power of ten (see docs/sweep.md for why)."""

import math

# The default tolerance and deflection, as a fraction of the part's diagonal.
PART_FRACTION = 1e-3


def round_down_125(x: float) -> float:
    """The largest of 1, 2, 5 times a power of ten not above ``x`` (> 0): a value a user
    reads at a glance, never coarser than ``x``."""
    if not (x > 0.0 and math.isfinite(x)):
        raise ValueError(f"a positive finite length is needed, got {x!r}")
    power = 10.0 ** math.floor(math.log10(x))
    for step in (5.0, 2.0, 1.0):
        # the tolerance: log10 rounds (0.3 -> 0.29999...)
        if step * power <= x * (1.0 + 1e-12):
            return float(f"{step * power:.12g}")
    return float(f"{power / 2.0:.12g}")   # x just below the power: 0.5 of it


def part_default(diagonal: float, fraction: float = PART_FRACTION) -> float:
    """The default length for a part of bounding-box ``diagonal`` (mm):
    round_down_125(fraction * diagonal)."""
    return round_down_125(fraction * diagonal)
