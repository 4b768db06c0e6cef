# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.geometry.sizes: the sweep's defaults scaled to the part (1e-3 of the diagonal,
rounded down to 1 / 2 / 5 x 10^k)."""

import math

import numpy as np
import pytest

from mfgeom.geometry import sizes


@pytest.mark.parametrize("x, want", [(1.0, 1.0), (0.0229, 0.02), (0.0539, 0.05), (0.1, 0.1),
                                     (0.3, 0.2), (0.19999, 0.1), (4.99, 2.0), (5.0, 5.0),
                                     (9.99, 5.0), (12.3, 10.0), (1e-7, 1e-7), (3e5, 2e5)])
def test_round_down_125(x, want):
    assert sizes.round_down_125(x) == pytest.approx(want, rel=1e-12)


def test_round_down_125_is_never_above_and_within_a_factor_2_5():
    for x in np.exp(np.random.default_rng(4).uniform(math.log(1e-9), math.log(1e9), 2000)):
        r = sizes.round_down_125(x)
        assert r <= x * (1 + 1e-12) and r >= x / 2.5 * (1 - 1e-12)
        mantissa = r / 10.0 ** math.floor(math.log10(r) + 1e-12)
        assert min(abs(mantissa - m) for m in (1, 2, 5)) < 1e-9


def test_part_default_is_a_thousandth_of_the_diagonal_rounded_down():
    assert sizes.part_default(math.sqrt(2 ** 2 + 3 ** 2 + 4 ** 2)) == 0.005   # 5.39 mm
    assert sizes.part_default(229.0) == 0.2
    assert sizes.part_default(100.0) == 0.1
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError):
            sizes.part_default(bad)
