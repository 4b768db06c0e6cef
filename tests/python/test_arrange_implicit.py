# SPDX-License-Identifier: LGPL-2.1-or-later
"""The implicit points of arrange/implicit.h and their predicates, recomputed with exact
rationals (fractions.Fraction) from the definitions in the header, not from the C code.

The C test program libcore/tests/arrange/test_implicit (built with the library, in the
same build tree) writes, in its ``dump`` mode, random, degenerate and nearly degenerate
cases: the explicit vertices (hex floats), the constructions with arr_point_prepare's
answer, and the answers of arr_orient3d, arr_orient2d, arr_cmp, arr_same and arr_coords.
Here every point is located by solving its defining equations directly (a line against a
plane by its parameter, three planes by Gaussian elimination, two projected lines by
elimination, a plane solved for one coordinate) and every predicate is evaluated on the
rational points by its textbook definition."""

import math
import os
import subprocess
from fractions import Fraction

import pytest

from build_tree import build_dir
from mfgeom import core

EXPLICIT, LPI, TPI, SSI, LIFT = range(5)
NVERTS = {EXPLICIT: 1, LPI: 5, TPI: 9, SSI: 4, LIFT: 3}
CASES = 900


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def sign(x):
    return (x > 0) - (x < 0)


def solve(rows):
    """Solution of the square linear system [A | b] (rows of Fractions) by Gaussian
    elimination, or None when A is singular."""
    m = [list(r) for r in rows]
    n = len(m)
    for col in range(n):
        pivot = next((r for r in range(col, n) if m[r][col] != 0), None)
        if pivot is None:
            return None
        m[col], m[pivot] = m[pivot], m[col]
        for r in range(n):
            if r != col and m[r][col] != 0:
                f = m[r][col] / m[col][col]
                m[r] = [x - f * y for x, y in zip(m[r], m[col])]
    return tuple(m[i][n] / m[i][i] for i in range(n))


def locate(kind, axis, vs, lift):
    """The rational position of a construction (vertices vs, lift), None when it does
    not define one point."""
    i, j = (axis + 1) % 3, (axis + 2) % 3
    if kind == EXPLICIT:
        return vs[0]
    if kind == LPI:
        p, q, r, s, t = vs
        n = cross(sub(s, r), sub(t, r))
        den = dot(n, sub(q, p))
        if den == 0:
            return None
        lam = dot(n, sub(r, p)) / den
        return tuple(p[k] + lam * (q[k] - p[k]) for k in range(3))
    if kind == TPI:
        rows = []
        for m in range(3):
            a, b, c = vs[3 * m:3 * m + 3]
            n = cross(sub(b, a), sub(c, a))
            rows.append(list(n) + [dot(n, a)])
        return solve(rows)
    if kind == SSI:
        p, q, r, s = vs
        # p + t (q - p) = r + u (s - r) in the coordinates i, j.
        sol = solve([[q[i] - p[i], r[i] - s[i], r[i] - p[i]],
                     [q[j] - p[j], r[j] - s[j], r[j] - p[j]]])
        if sol is None:
            return None
        t = sol[0]
        return tuple(p[k] + t * (q[k] - p[k]) for k in range(3))
    a, b, c = vs
    n = cross(sub(b, a), sub(c, a))
    if n[axis] == 0:
        return None
    x = [None, None, None]
    x[i], x[j] = lift
    x[axis] = a[axis] - (n[i] * (lift[0] - a[i]) + n[j] * (lift[1] - a[j])) / n[axis]
    return tuple(x)


def det3(a, b, c):
    return dot(a, cross(b, c))


def within_ulps(out, exact, ulps):
    """|out - exact| <= ulps * ulp(exact) (ulp of the double nearest exact)."""
    return abs(Fraction(out) - exact) <= ulps * Fraction(math.ulp(float(exact)))


class Checker:
    """Replays the dump: checks every answer and counts what was covered."""

    def __init__(self):
        self.counts = {}
        self.zeros = {}
        self.failures = []
        self.vertices = {}
        self.points = {}

    def count(self, what, answer=None):
        self.counts[what] = self.counts.get(what, 0) + 1
        if answer == 0:
            self.zeros[what] = self.zeros.get(what, 0) + 1

    def fail(self, line, want):
        if len(self.failures) < 20:
            self.failures.append(f"{line!r}: expected {want}")

    def line(self, text):
        w = text.split()
        tag = w[0]
        if tag == "CASE":
            self.vertices, self.points = {}, {}
        elif tag == "V":
            self.vertices[int(w[1])] = tuple(Fraction(float.fromhex(x)) for x in w[2:5])
        elif tag == "P":
            i, kind, axis = int(w[1]), int(w[2]), int(w[3])
            vs = [self.vertices[int(x)] for x in w[4:4 + NVERTS[kind]]]
            lift = (Fraction(float.fromhex(w[13])), Fraction(float.fromhex(w[14])))
            ok = int(w[15])
            x = locate(kind, axis, vs, lift)
            self.count(f"point {kind}", ok)
            if (x is not None) != bool(ok):
                self.fail(text, f"prepare {int(x is not None)}")
            if ok:
                self.points[i] = x
        elif tag == "O3":
            a, b, c = (self.vertices[int(x)] for x in w[1:4])
            q = self.points[int(w[4])]
            want = sign(det3(sub(a, q), sub(b, q), sub(c, q)))
            self.count("orient3d", want)
            if int(w[5]) != want:
                self.fail(text, want)
        elif tag == "O2":
            p, q, r = (self.points[int(x)] for x in w[1:4])
            axis = int(w[4])
            i, j = (axis + 1) % 3, (axis + 2) % 3
            want = sign((q[i] - p[i]) * (r[j] - p[j]) - (q[j] - p[j]) * (r[i] - p[i]))
            self.count("orient2d", want)
            if int(w[5]) != want:
                self.fail(text, want)
        elif tag == "CMP":
            p, q = self.points[int(w[1])], self.points[int(w[2])]
            axis = int(w[3])
            want = sign(p[axis] - q[axis])
            self.count("cmp", want)
            if int(w[4]) != want:
                self.fail(text, want)
        elif tag == "SAME":
            want = int(self.points[int(w[1])] == self.points[int(w[2])])
            self.count("same", 1 - want)
            if int(w[3]) != want:
                self.fail(text, want)
        elif tag == "XYZ":
            x = self.points[int(w[1])]
            out = [float.fromhex(v) for v in w[2:5]]
            self.count("coords")
            if not all(within_ulps(o, e, 2) for o, e in zip(out, x)):
                self.fail(text, [float(e) for e in x])
        else:
            raise AssertionError(f"unknown dump line {text!r}")


@pytest.fixture(scope="module")
def replay():
    build = build_dir()
    if build is None:
        pytest.skip(f"{core.library_path} is not in a CMake build tree: no test_implicit")
    program = os.path.join(build, "libcore", "tests", "arrange", "test_implicit")
    assert os.path.isfile(program), (
        f"{program} is missing, but the library comes from the build tree {build}: "
        f"build it with  cmake --build {build} --target test_implicit")
    proc = subprocess.run([program, "dump", str(CASES)], capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 0, proc.stderr
    checker = Checker()
    for text in proc.stdout.splitlines():
        checker.line(text)
    return checker


def test_every_answer_matches_the_rationals(replay):
    assert not replay.failures, "\n".join(replay.failures)


def test_the_dump_covers_every_kind_and_predicate(replay):
    for kind in range(5):
        assert replay.counts.get(f"point {kind}", 0) >= 50, replay.counts
        # constructions refused as degenerate (W = 0) are checked too
        assert replay.zeros.get(f"point {kind}", 0) >= 1 or kind == EXPLICIT, replay.zeros
    for what in ("orient3d", "orient2d", "cmp", "same"):
        assert replay.counts.get(what, 0) >= 300, replay.counts
        # exactly degenerate answers (zero; for same: different points) are covered
        assert replay.zeros.get(what, 0) >= 50, replay.zeros
    assert replay.counts.get("coords", 0) >= 300


def test_solver_reference_sanity():
    """The rational reference itself: a TPI of the three coordinate planes shifted, an
    LPI of an axis line, and a lift, all at known points."""
    F = Fraction
    o, x, y, z = (F(1), F(2), F(3)), (F(2), F(2), F(3)), (F(1), F(3), F(3)), (F(1), F(2), F(4))
    tpi = locate(TPI, 0, [o, y, z, o, z, x, o, x, y], None)
    assert tpi == o
    lpi = locate(LPI, 0, [(F(0), F(2), F(3)), (F(5), F(2), F(3)), o, y, z], None)
    assert lpi == o
    assert locate(LIFT, 2, [o, x, y], (F(7), F(9))) == (F(7), F(9), F(3))
    ssi = locate(SSI, 2, [(F(0), F(0), F(1)), (F(2), F(2), F(3)),
                          (F(0), F(2), F(0)), (F(2), F(0), F(0))], None)
    assert ssi == (F(1), F(1), F(2))
    assert locate(LPI, 0, [o, (F(1), F(3), F(3)), o, y, z], None) is None  # in the plane
