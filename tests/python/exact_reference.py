# SPDX-License-Identifier: LGPL-2.1-or-later
"""Independent exact reference for tolerance-based point classification (even-odd rule), used to check libmfgeom.

Derived only from the specification in mfgeom.h, not from the C code:

* The region is a list of rings; each ring is implicitly closed (edge from the last
  vertex back to the first).  The boundary is the union of all closed edge segments
  (zero-length edges are single points).
* A point T is ON when its Euclidean distance to the boundary is <= tol, decided
  exactly; otherwise it is IN when a ray from T crosses the boundary an odd number of
  times (even-odd rule over all rings), else OUT.

Every IEEE double is a dyadic rational, so ``fractions.Fraction(x)`` is exact.  The
fast path (:func:`classify`) converts all inputs with Fraction and then multiplies
them by one common power of two so that every quantity becomes a Python int; all
comparisons are then exact integer comparisons (same values as with Fractions, but
much faster).  :func:`classify_fractions` is the literal Fraction version of the same
definition, kept small and obviously correct; the tests check both agree.
"""

from fractions import Fraction
import math

OUT = 0
IN = 1
ON = 2


def _check_finite(values):
    for v in values:
        if not math.isfinite(v):
            raise ValueError(f"non-finite value {v!r}")


# --------------------------------------------------------------------------- #
# Literal Fraction version (slow, used to cross-check the integer version).   #
# --------------------------------------------------------------------------- #

def seg_dist2_fraction(t, a, b):
    """Exact squared distance from point t to the closed segment ab (Fractions)."""
    tx, ty = t
    ax, ay = a
    bx, by = b
    dx, dy = bx - ax, by - ay
    wx, wy = tx - ax, ty - ay
    length2 = dx * dx + dy * dy
    if length2 == 0:
        return wx * wx + wy * wy
    s = (wx * dx + wy * dy) / length2          # parameter of the orthogonal projection
    s = min(max(s, Fraction(0)), Fraction(1))   # clamp onto the closed segment
    px, py = ax + s * dx, ay + s * dy
    return (tx - px) ** 2 + (ty - py) ** 2


def _edges(rings):
    for ring in rings:
        n = len(ring)
        for i in range(n):
            yield ring[i], ring[(i + 1) % n]


def classify_fractions(rings, points, tol):
    """Literal definition with Fractions: ON iff min distance <= tol, else ray parity."""
    frings = [[(Fraction(float(x)), Fraction(float(y))) for x, y in ring] for ring in rings]
    ftol = Fraction(float(tol))
    tol2 = ftol * ftol
    edges = list(_edges(frings))
    result = []
    for px, py in points:
        t = (Fraction(float(px)), Fraction(float(py)))
        if any(seg_dist2_fraction(t, a, b) <= tol2 for a, b in edges):
            result.append(ON)
            continue
        crossings = 0
        for (ax, ay), (bx, by) in edges:
            if (ay > t[1]) != (by > t[1]):
                xcross = ax + (t[1] - ay) * (bx - ax) / (by - ay)
                if xcross > t[0]:
                    crossings += 1
        result.append(IN if crossings % 2 else OUT)
    return result


# --------------------------------------------------------------------------- #
# Fast exact version: everything scaled to integers by one power of two.      #
# --------------------------------------------------------------------------- #

class ExactRegion:
    """Rings + tolerance converted exactly to a common integer grid."""

    def __init__(self, rings, tol):
        rings = [[(float(x), float(y)) for x, y in ring] for ring in rings]
        tol = float(tol)
        for ring in rings:
            for v in ring:
                _check_finite(v)
        _check_finite([tol])
        if tol < 0:
            raise ValueError("negative tolerance")
        self.rings = rings
        self.tol = tol
        self._shift = None
        self._edges = None

    # The common scale must also cover the points, so it is computed per query batch.
    @staticmethod
    def _exponent(values):
        """Smallest k >= 0 such that every value * 2**k is an integer."""
        k = 0
        for v in values:
            den = Fraction(v).denominator      # a power of two
            k = max(k, den.bit_length() - 1)
        return k

    def _prepare(self, k):
        if self._shift == k:
            return
        scale = 1 << k

        def to_int(v):
            f = Fraction(v) * scale
            assert f.denominator == 1
            return f.numerator

        edges = []
        for ring in self.rings:
            iring = [(to_int(x), to_int(y)) for x, y in ring]
            n = len(iring)
            for i in range(n):
                ax, ay = iring[i]
                bx, by = iring[(i + 1) % n]
                dx, dy = bx - ax, by - ay
                edges.append((ax, ay, bx, by, dx, dy, dx * dx + dy * dy,
                              min(ax, bx), max(ax, bx), min(ay, by), max(ay, by)))
        self._edges = edges
        itol = to_int(self.tol)
        self._itol = itol
        self._tol2 = itol * itol
        self._shift = k

    def classify(self, points):
        points = [(float(x), float(y)) for x, y in points]
        for p in points:
            _check_finite(p)
        values = [self.tol]
        for ring in self.rings:
            for v in ring:
                values.extend(v)
        for p in points:
            values.extend(p)
        k = self._exponent(values)
        self._prepare(k)
        scale = 1 << k
        edges = self._edges
        itol = self._itol
        tol2 = self._tol2
        out = []
        for px, py in points:
            fx = Fraction(px) * scale
            fy = Fraction(py) * scale
            tx, ty = fx.numerator, fy.numerator
            on = False
            crossings = 0
            for (ax, ay, bx, by, dx, dy, length2, xlo, xhi, ylo, yhi) in edges:
                # --- distance test (skipped exactly when the edge's box is > tol away)
                if not (tx < xlo - itol or tx > xhi + itol or ty < ylo - itol or ty > yhi + itol):
                    wx, wy = tx - ax, ty - ay
                    u = wx * dx + wy * dy
                    if u <= 0:                       # nearest point is a (or a == b)
                        d2le = wx * wx + wy * wy <= tol2
                    elif u >= length2:               # nearest point is b
                        ex, ey = tx - bx, ty - by
                        d2le = ex * ex + ey * ey <= tol2
                    else:                            # interior: cross^2 / |d|^2 <= tol^2
                        c = wx * dy - wy * dx
                        d2le = c * c <= tol2 * length2
                    if d2le:
                        on = True
                        break
                # --- crossing of the rightward horizontal ray from T
                if (ay > ty) != (by > ty):
                    # x_cross - tx has the sign of num / (by - ay)
                    num = (ax - tx) * (by - ay) + (ty - ay) * (bx - ax)
                    if (num > 0) == (by - ay > 0) and num != 0:
                        crossings += 1
            if on:
                out.append(ON)
            else:
                out.append(IN if crossings & 1 else OUT)
        return out


def classify(rings, points, tol):
    """Exact classification of ``points`` (iterable of (x, y)) against ``rings``.

    Returns a list of OUT (0), IN (1), ON (2).
    """
    return ExactRegion(rings, tol).classify(points)


def distance2(rings, point):
    """Exact squared distance (Fraction) from ``point`` to the boundary of ``rings``."""
    frings = [[(Fraction(float(x)), Fraction(float(y))) for x, y in ring] for ring in rings]
    t = (Fraction(float(point[0])), Fraction(float(point[1])))
    return min(seg_dist2_fraction(t, a, b) for a, b in _edges(frings))
