# SPDX-License-Identifier: LGPL-2.1-or-later
"""Result colours used by every feature of the workbench (RGB, 0..1), and the colour-vision
check they were chosen with.  FreeCAD-free, so reports and plots outside FreeCAD use the
same colours.

How they were chosen.  A result colour must stay distinct from

* FreeCAD 0.20's selection green (28, 173, 28) and pre-selection yellow (225, 225, 20)
  (View preferences SelectionColor / HighlightColor, the defaults shipped in
  /usr/share/freecad/Gui/PreferencePacks/FreeCAD Classic Colors), else a selected or
  hovered object reads as a result;
* the other result colours of the same feature, also for the ~8 % of men with a red-green
  deficiency: under protanopia and deuteranopia green, yellow, orange and red collapse
  onto one olive-yellow hue and only the blue-yellow axis and lightness remain;
* the default grey of shapes (204, 204, 204) the points lie on and the blue-grey
  background gradient (51, 51, 101) .. (151, 151, 170) around them.

The former IN green / ON orange / OUT red failed all of this: IN was the selection green,
ON and the pre-selection yellow are 3 CIELAB units apart for a deuteranope.  The classes
now use blue (IN, the material), light cyan (ON, the boundary band: lightness sets it
apart from IN for everybody) and wine (OUT), from Okabe & Ito's and Paul Tol's
colour-blind-safe sets.  ``contrast()`` measures it: CIE76 distance in CIELAB after
simulating each vision with Machado, Oliveira & Fernandes (2009), severity 1.
Minimum distances (normal / protanopia / deuteranopia):

* between the three classes: 39 / 32 / 35 (about 2.3 units is "just noticeable");
* from the selection and pre-selection colours: 94 / 91 / 58;

tests/freecad/test_app.py (PaletteTests) keeps them above 30 and 40.
"""

from mfgeom import names


def _rgb(r, g, b):
    return (r / 255.0, g / 255.0, b / 255.0)


# ---------------------------------------------------------------- point classification
IN = _rgb(0, 114, 178)      # Okabe-Ito blue
ON = _rgb(102, 204, 238)    # Tol cyan
OUT = _rgb(136, 34, 85)     # Tol wine (a grey-red)
CLASS_COLORS = {names.OUT: OUT, names.IN: IN, names.ON: ON}
UNKNOWN = _rgb(128, 128, 128)

# ---------------------------------------------------------------- parting (next feature)
# Faces visible from the core side, from the cavity side, and faces neither sees (undercut).
CORE_SIDE = _rgb(68, 119, 170)    # Tol blue
CAVITY_SIDE = _rgb(238, 102, 119)  # Tol red
UNDERCUT = _rgb(51, 34, 136)       # Tol indigo
# Mould tooling (issue 21): the core, cavity and side-core inserts take the side colours
# of the faces they mould; the parting line is drawn thick in near black, the one colour
# at least 48 CIELAB units from both sides, the selection and pre-selection colours and
# the shape grey under normal, protan and deutan vision (vermillion was 11 from the
# selection green for a deuteranope); the parting surface is Tol's sand, half transparent.
MOULD_CORE, MOULD_CAVITY, MOULD_INSERT = CORE_SIDE, CAVITY_SIDE, UNDERCUT
PARTING_LINE = _rgb(20, 20, 20)
PARTING_SURFACE = _rgb(221, 204, 119)
# Set-ups 1..n of a multi-set-up plan, in this order (cycled beyond 8): a qualitative list
# picked greedily, each colour the farthest from the earlier ones and from the FreeCAD
# colours under normal, protan and deutan vision (minimum 18 CIELAB units), then ordered
# so the common plans (2-4 set-ups) get colours that read as surface colours.
SETUP_COLORS = (
    _rgb(0, 114, 178),    # blue
    _rgb(120, 60, 20),    # brown
    _rgb(221, 204, 119),  # sand
    _rgb(102, 204, 238),  # cyan
    _rgb(51, 34, 136),    # indigo
    _rgb(238, 102, 170),  # pink
    _rgb(110, 110, 110),  # dark grey
    _rgb(0, 0, 0),        # black: last, a black face reads as a hole or a shadow
)


# The parting analysis' visibility sphere: coverage count ramps from light grey (no
# surface sees that direction) to dark blue; the maximum region and the chosen direction
# in magenta: >= 37 CIELAB units from the ramp's ends and >= 106 from the selection and
# pre-selection colours for normal, protan and deutan vision (vermillion was 11 from the
# selection green for a deuteranope).
SPHERE_LOW = _rgb(235, 235, 235)
SPHERE_HIGH = _rgb(34, 68, 136)
SPHERE_MAX = _rgb(255, 0, 255)


# The clearance check (issue 8): solids that interfere with a swept volume.  Magenta, the
# clash colour of interference checks, and the farthest of the warm hues from FreeCAD's
# colours: >= 106 CIELAB units from the selection and pre-selection colours and >= 44
# from the default shape grey and both ends of the background gradient, for normal,
# protan and deutan vision (Tol red, the cavity side, is 29 from the selection green for
# a deuteranope).  tests/freecad/test_clearance_app.py keeps these floors.
INTERFERENCE = _rgb(255, 0, 255)
BACKGROUND = (_rgb(51, 51, 101), _rgb(151, 151, 170))  # FreeCAD 0.20's gradient ends


def setup_color(i):
    """Colour of set-up ``i`` (1-based)."""
    return SETUP_COLORS[(i - 1) % len(SETUP_COLORS)]


# ---------------------------------------------------------------- FreeCAD's own colours
SELECTION = _rgb(28, 173, 28)      # FreeCAD 0.20 default SelectionColor
PRESELECTION = _rgb(225, 225, 20)  # FreeCAD 0.20 default HighlightColor
SHAPE_GREY = _rgb(204, 204, 204)   # FreeCAD 0.20 default DefaultShapeColor

# ---------------------------------------------------------------- colour-vision check
# Machado, Oliveira & Fernandes 2009, severity 1.0, applied to linear RGB.
_VISION = {
    "normal": None,
    "protanopia": ((0.152286, 1.052583, -0.204868), (0.114503, 0.786281, 0.099216),
                   (-0.003882, -0.048116, 1.051998)),
    "deuteranopia": ((0.367322, 0.860646, -0.227968), (0.280085, 0.672501, 0.047413),
                     (-0.011820, 0.042940, 0.968881)),
}
VISIONS = tuple(_VISION)


def _linear(c):
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def _lab(rgb, vision):
    lin = [_linear(c) for c in rgb]
    m = _VISION[vision]
    if m is not None:
        lin = [min(1.0, max(0.0, sum(m[i][j] * lin[j] for j in range(3)))) for i in range(3)]
    x = (0.4124 * lin[0] + 0.3576 * lin[1] + 0.1805 * lin[2]) / 0.95047
    y = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]
    z = (0.0193 * lin[0] + 0.1192 * lin[1] + 0.9505 * lin[2]) / 1.08883

    def f(t):
        return t ** (1.0 / 3.0) if t > 0.008856 else 7.787 * t + 16.0 / 116.0
    return (116.0 * f(y) - 16.0, 500.0 * (f(x) - f(y)), 200.0 * (f(y) - f(z)))


def contrast(a, b, vision="normal"):
    """CIE76 distance in CIELAB between RGB colours ``a`` and ``b`` (0..1) as seen with
    ``vision`` (one of VISIONS)."""
    la, lb = _lab(a, vision), _lab(b, vision)
    return sum((p - q) ** 2 for p, q in zip(la, lb)) ** 0.5


# ---------------------------------------------------------------- medial surface (issue 9)
# Wall thickness (2 x the medial radius) on the sheets of a medial surface: a sequential
# ramp from thin (dark wine, the "look here" end) through magenta and a pale middle to
# thick (dark blue).  It runs along the blue-yellow / lightness axes that survive red-green
# deficiency and keeps away from green, yellow and orange: every ramp colour is >= 53
# CIELAB units from FreeCAD's selection green and pre-selection yellow for normal, protan
# and deutan vision, and tenths of the ramp differ by >= 9 units (tests/freecad/
# test_medial_app.py keeps these floors).  (Tol's "sunset", tried first, is 1 unit from
# the selection green for a deuteranope at its orange.)
THICKNESS_RAMP = (
    _rgb(125, 0, 60),      # thinnest
    _rgb(200, 60, 130),
    _rgb(240, 170, 210),
    _rgb(235, 235, 245),
    _rgb(130, 170, 225),
    _rgb(40, 80, 170),
    _rgb(20, 30, 90),      # thickest
)
# The wall-thickness analysis (issue 21): thickness inside the user's window [minimum,
# maximum] on the blue half of the thickness ramp (pale: thinnest allowed, dark blue:
# thickest allowed); thin walls (below the minimum) in the ramp's pink, thick ones (above
# the maximum) in brown.  Both are >= 30 CIELAB units from every colour of that half
# ramp, the selection and pre-selection colours and the shape grey, and >= 42 from each
# other, for normal, protan and deutan vision (magenta was 20 from the light blue for a
# deuteranope, vermillion 11 from the selection green).
WALL_RAMP = THICKNESS_RAMP[3:]
THIN_WALL = _rgb(200, 60, 130)
THICK_WALL = _rgb(120, 60, 20)
WALL_MARK = _rgb(0, 0, 0)     # the thinnest and thickest spots' markers and labels


def wall_colors(values, lo, hi):
    """(n, 3) colours of wall thickness ``values`` with the window [lo, hi]: THIN_WALL
    below lo, THICK_WALL above hi, WALL_RAMP in between.  Needs numpy."""
    import numpy as np
    v = np.asarray(values, dtype=np.float64).reshape(-1)
    out = ramp_colors(v, lo, hi, WALL_RAMP) if len(v) else np.zeros((0, 3))
    out[v < lo] = THIN_WALL
    out[v > hi] = THICK_WALL
    return out


# Seams (curves where three or more boundary elements are equidistant) and junctions.
SEAM = _rgb(0, 0, 0)
JUNCTION = _rgb(0, 0, 0)     # drawn as larger points on the seams
# Values this close, relative to their size, are one value on a colour scale or in a
# histogram: the library's radii carry rounding (a 2 mm plate's thickness came out as
# 2.0 and 1.999999999998668), which a scale from minimum to maximum blew up to the ramp's
# two ends and a histogram to ten bins "2 .. 2".
SAME_VALUE = 1e-9


def one_value(lo, hi):
    """True when ``lo`` .. ``hi`` is one value up to rounding (SAME_VALUE, relative)."""
    return hi - lo <= SAME_VALUE * max(abs(lo), abs(hi))


def ramp_color(t, ramp=THICKNESS_RAMP):
    """The colour at ``t`` in [0, 1] (clamped; NaN gives the first colour) of a ramp of
    colours spaced evenly, linearly interpolated in RGB."""
    t = 0.0 if not t >= 0.0 else min(float(t), 1.0)
    x = t * (len(ramp) - 1)
    i = min(int(x), len(ramp) - 2)
    f = x - i
    a, b = ramp[i], ramp[i + 1]
    return tuple(a[k] + (b[k] - a[k]) * f for k in range(3))


def ramp_colors(values, lo, hi, ramp=THICKNESS_RAMP):
    """(n, 3) float colours of ``values`` on the ramp between ``lo`` and ``hi`` (all the
    middle colour when ``lo`` .. ``hi`` is one value, see one_value).  Needs numpy."""
    import numpy as np
    v = np.asarray(values, dtype=np.float64)
    t = (v - lo) / (hi - lo) if not one_value(lo, hi) else np.full(v.shape, 0.5)
    t = np.nan_to_num(np.clip(t, 0.0, 1.0), nan=0.0)
    stops = np.asarray(ramp, dtype=np.float64)
    x = t * (len(stops) - 1)
    i = np.minimum(x.astype(np.int64), len(stops) - 2)
    f = (x - i)[:, None]
    return stops[i] * (1.0 - f) + stops[i + 1] * f


# The colour scale's labelled intervals (ends and quarters): the 3-D view's bar and the
# task panels' text of it use the same ticks.
LEGEND_STEPS = 4


def legend_labels(lo, hi, steps=LEGEND_STEPS):
    """[(t in [0, 1], text)] for the legend's ticks between thickness ``lo`` and ``hi``
    (one tick when they are one value up to rounding)."""
    if one_value(lo, hi):
        return [(0.5, f"{lo:.3g} mm")]
    return [(k / steps, f"{lo + (hi - lo) * k / steps:.3g} mm") for k in range(steps + 1)]
