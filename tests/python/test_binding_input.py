# SPDX-License-Identifier: LGPL-2.1-or-later
"""Tests of the binding's one input conversion (core._as_float_array): every public
function rejects strings, booleans, complex numbers and None with TypeError (numpy would
convert or truncate them silently) and numbers no double can hold with ValueError."""

import numpy as np
import pytest

from mfgeom import core

SQ = [np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)]
PTS = [[0.5, 0.5], [2.0, 2.0]]
NORMALS = [[0, 0, 1.0], [0.3, 0, 1.0], [0, 0.3, 1.0]]
TRI = [[1.0, 0, 0.2], [0, 1.0, 0.2], [-1.0, -1.0, 0.2]]
HUGE = 10 ** 400                       # an int no double holds: OverflowError in float()

# (what, value) for each kind of bad array; the expected exception
BAD_ARRAYS = [
    ("complex", lambda shape: np.full(shape, 0.5 + 0.25j), TypeError),
    ("complex-zero-imag", lambda shape: np.full(shape, 0.5 + 0j), TypeError),
    ("bool", lambda shape: np.ones(shape, dtype=bool), TypeError),
    ("str", lambda shape: np.full(shape, "0.5"), TypeError),
    ("bytes", lambda shape: np.full(shape, b"0.5"), TypeError),
    ("None", lambda shape: np.full(shape, None, dtype=object), TypeError),
    ("huge-int", lambda shape: np.full(shape, HUGE, dtype=object), ValueError),
]
BAD_SCALARS = [("str", "0.1", TypeError), ("bytes", b"0.1", TypeError),
               ("bool", True, TypeError), ("complex", 0.1 + 0j, TypeError),
               ("None", None, TypeError), ("list", [0.1], TypeError),
               ("huge-int", HUGE, ValueError)]


def _ids(cases):
    return [c[0] for c in cases]


@pytest.mark.parametrize("name,make,exc", BAD_ARRAYS, ids=_ids(BAD_ARRAYS))
def test_bad_arrays_everywhere(name, make, exc):
    calls = {
        "classify_points(points)": lambda: core.classify_points(SQ, make((2, 2)), 0.0),
        "classify_points(rings)": lambda: core.classify_points([make((4, 2))], PTS, 0.0),
        "Region(rings)": lambda: core.Region([make((4, 2))], 0.0),
        "Region.classify": lambda: core.Region(SQ, 0.0).classify(make((2, 2))),
        "visibility_map": lambda: core.visibility_map(make((3, 3))),
        "max_intersection(maps)": lambda: core.max_intersection([TRI, make((3, 3))]),
        "max_intersection(VisibilityMap)": lambda: core.max_intersection(
            [core.VisibilityMap("polygon", make((3, 3)))]),
        "max_intersection(weights)": lambda: core.max_intersection([TRI, TRI], make((2,))),
        "level_regions(weights)": lambda: core.level_regions([TRI, TRI], 1, make((2,))),
        "min_intersection(weights)": lambda: core.min_intersection([TRI, TRI], make((2,))),
    }
    for what, call in calls.items():
        with pytest.raises(exc):
            call()
            pytest.fail(f"{what} accepted {name}")


@pytest.mark.parametrize("name,value,exc", BAD_SCALARS, ids=_ids(BAD_SCALARS))
def test_bad_scalars_everywhere(name, value, exc):
    calls = {
        "classify_points(tol)": lambda: core.classify_points(SQ, PTS, value),
        "Region(tol)": lambda: core.Region(SQ, value),
        "visibility_map(draft_angle)": lambda: core.visibility_map(NORMALS, value),
        "level_regions(level)": lambda: core.level_regions([TRI, TRI], value),
    }
    for what, call in calls.items():
        with pytest.raises(exc):
            call()
            pytest.fail(f"{what} accepted {name}")


def test_complex_part_is_not_dropped():
    """Before: np.array([[0.5 + 3j, 0.5]]) classified as the point (0.5, 0.5)."""
    with pytest.raises(TypeError, match="complex"):
        core.classify_points(SQ, np.array([[0.5 + 3j, 0.5]]), 0.0)


def test_huge_int_is_value_error_with_the_name():
    with pytest.raises(ValueError, match="points.*too large for a double"):
        core.classify_points(SQ, [[HUGE, 0]], 0.0)
    with pytest.raises(ValueError, match="tol"):
        core.classify_points(SQ, PTS, HUGE)


def test_long_double_overflow_is_value_error():
    big = np.array([[0.5, 0.5]], dtype=np.longdouble)
    if np.finfo(np.longdouble).max <= np.finfo(np.float64).max:
        pytest.skip("long double is double here")
    with pytest.raises(ValueError, match="too large"):
        core.classify_points(SQ, big * np.longdouble(1e300) ** 2, 0.0)


def test_good_inputs_of_every_numeric_kind_agree():
    ref = core.classify_points(SQ, PTS, 0.0)
    for pts in (np.array(PTS, np.float32), np.array([[0, 0], [2, 2]], np.int32),
                np.array([[0, 0], [2, 2]], np.uint64), np.array(PTS, np.longdouble),
                [[np.float64(0.5), 0.5], [2, 2.0]],
                np.array([[0.5, 0.5], [2, 2]], dtype=object)):
        got = core.classify_points(SQ, pts, np.float32(0))
        assert got.tolist() == core.classify_points(SQ, np.asarray(pts, float), 0.0).tolist()
    assert ref.tolist() == [core.IN, core.OUT]
    # a Python int beyond int64 that a double holds is a number like any other
    assert core.classify_points(SQ, [[10 ** 20, 0]], 10 ** 19).tolist() == [core.OUT]
    assert core.level_regions([TRI, TRI], 2, [1, 1]).count == 2


def test_float64_input_is_not_copied():
    pts = np.ascontiguousarray(np.random.default_rng(1).random((1000, 2)))
    assert core._as_float_array(pts, "points") is pts
