# SPDX-License-Identifier: LGPL-2.1-or-later
"""mfgeom.palette.legend_labels (the thickness colour scale's ticks, shared by the 3-D
view's bar and the task panels' text; FreeCAD-free since it left gui/medial_view.py)."""

from mfgeom import palette


def test_quarters_between_two_thicknesses():
    assert palette.legend_labels(2.0, 6.0) == [
        (0.0, "2 mm"), (0.25, "3 mm"), (0.5, "4 mm"), (0.75, "5 mm"), (1.0, "6 mm")]


def test_fewer_steps():
    assert palette.legend_labels(0.5, 1.5, steps=2) == [(0.0, "0.5 mm"), (0.5, "1 mm"),
                                                        (1.0, "1.5 mm")]


def test_one_value_up_to_rounding_is_one_tick():
    # the library's radii of a 2 mm plate: 2.0 and 1.999999999998668
    assert palette.legend_labels(1.999999999998668, 2.0) == [(0.5, "2 mm")]
    assert len(palette.legend_labels(1.99, 2.0)) == palette.LEGEND_STEPS + 1
