# SPDX-License-Identifier: LGPL-2.1-or-later
"""Gaussian maps of a shape's faces and the concave / convex / tangent kind of its edges,
in global coordinates, for mfgeom.parting (FreeCAD App layer).

Every normal comes from OCCT with the face's location applied (``Face.Surface`` is the
located surface) and its orientation (reversed faces); ``shape_of`` bakes the object's
global placement (its containers included) into the shape, so every direction is global.

What is exact and what is sampled (``FaceGauss.shrink`` is 0 where exact):

* plane: one normal — exact.
* cylinder: the normals form a great-circle arc over the face's u range.  The cone spanned by an arc
  shorter than pi is spanned by its end normals, and an arc of pi or more has no half of
  the circle containing it; so samples with gaps <= pi/2 span exactly the arc's cone:
  exact (up to the double rounding of the normals).
* cone: the normals form a small-circle arc, whose cone no finite set of points spans.
  The arc is sampled so that the deviation of the true arc from the great arcs between
  samples (largest at each piece's middle, measured there) is <= ``deflection``;
  shrink = that deviation.
* sphere, torus: normals (cos v cos u, cos v sin u, sin v) in the surface's frame:
  meridians (u fixed) are great circles (exact, gaps <= pi/2), parallels small circles
  (sampled as for cones); a UV grid with shrink = the largest parallel deviation.
* non-rational B-spline and Bezier surfaces, offsets of them (an offset surface has its
  basis surface's normals) and extrusions of non-rational B-spline / Bezier curves
  (S = C(u) + v D): a bound, shrink 0.  The surface restricted to the face's parameter
  box is split into Bezier patches; on each, S_u x S_v is a Bezier patch of degrees
  (2p - 1, 2q - 1) whose control vectors are non-negative combinations of the crosses of
  the control net's differences, so every normal lies in the cone of those control
  vectors (:func:`_net_normals`).  Patches are halved (de Casteljau) while their control
  vectors cost a direction seeing the face's exact normals more than ``deflection`` of
  draft margin.  The face's orientation sign is checked against one ``Face.normalAt``.
  Weights equal to 1e-12 relative count as non-rational (OCCT's lofts).
* anything else (rational B-splines, revolution, other kinds): a UV grid refined
  until shrink <= ``deflection``, shrink = twice the largest angle of a cell's edge
  midpoint or centre normal from the great arc between the neighbouring samples.  This
  is an estimate that assumes the normal varies smoothly inside a cell (true once cells
  are small against the surface's features); it is not a proof, and the tests check it
  against dense sampling of the true face.

Normals are the surface's (``Surface.normal``, 1.6 us a call; ``Face.normalAt`` costs 10 us
to 0.1 ms) times the face's orientation sign.  Where OCCT has no normal (a cone apex, a
sphere pole, a collapsed B-spline edge: an exception, NaN or zero), the point is moved
towards the parameter box's centre until it has one; a face with no normal anywhere
there is skipped and reported ("Face12: no normal at (u, v) = (...), skipped") in the
``warnings`` list of :func:`part_gauss` / :func:`face_gauss`.

The face's parameter box (ParameterRange) is used: for a trimmed face its Gaussian map
is a superset of the face's, which keeps every reported direction valid (conservative).
"""

import math

import numpy as np

import Part

from mfgeom import progress
from mfgeom.parting import FaceGauss

DEFAULT_DEFLECTION = 1e-3   # rad: largest shrink wanted from sampling
DEFAULT_TANGENT_TOL = 1e-4  # rad: edges whose faces' normals differ less are tangent
_MAX_GRID = 129


def shape_of(source, deep=True):
    """A copy of ``source``'s shape in global coordinates: a Part.Shape is taken as is,
    a document object gets its global placement (containers included).  ``deep=False``:
    a new shape object over the same topology and geometry (its own placement; no copy
    of the geometry, which took 0.2 s for 5000 faces) for callers that only read it."""
    if isinstance(source, Part.Shape):
        return source.copy() if deep else Part.Shape(source)
    shape = source.Shape.copy() if deep else Part.Shape(source.Shape)
    if hasattr(source, "getGlobalPlacement"):
        shape.Placement = source.getGlobalPlacement()
    return shape


class NoNormal(ValueError):
    """OCCT gives no normal of a face at (u, v), nor anywhere near it."""

    def __init__(self, u, v):
        super().__init__(f"no normal at (u, v) = ({u:.6g}, {v:.6g})")
        self.u, self.v = u, v


# fractions of the way from a failing (u, v) towards the parameter box's centre tried in
# turn (singular points: a cone apex, a sphere pole, a collapsed B-spline edge)
_NUDGES = (1e-9, 1e-7, 1e-5, 1e-3, 1e-2, 0.1, 0.5)


class _Normals:
    """Outward normals of one face at its surface's parameters: the surface's own normal
    (``Surface.normal``: D1U x D1V normalised, 1.6 us a call) times the face's orientation
    sign.  ``Face.normalAt`` gives the same but costs 10 us on a box side and ~0.1 ms on
    a face with hundreds of holes (it bounds the face from all its edges each call).  The
    sign is the face's Orientation, checked against one ``Face.normalAt`` inside.
    ``at`` never fails where OCCT has no normal (or returns NaN or zero) at a point that
    has a neighbour with one: it moves the point towards the parameter box's centre
    (``_NUDGES``) and raises :class:`NoNormal` only if that fails too."""

    def __init__(self, face, surface=None):
        self.face = face
        self.surface = face.Surface if surface is None else surface
        u0, u1, v0, v1 = face.ParameterRange
        self.centre = ((u0 + u1) / 2, (v0 + v1) / 2)
        self.sign = -1.0 if face.Orientation == "Reversed" else 1.0
        self._sign_checked = False

    def _raw(self, u, v):
        try:
            n = self.surface.normal(u, v)
        except Exception:   # OCCT: "normal not defined" and the like
            return None
        x, y, z = n.x, n.y, n.z
        l2 = x * x + y * y + z * z
        if not (1e-200 < l2 < 1e200):   # also false for NaN
            return None
        return x, y, z

    def check_sign(self):
        """The orientation sign, checked once against Face.normalAt (at the box's centre
        or, where that has no normal, at points towards the box's corners)."""
        if self._sign_checked:
            return self.sign
        self._sign_checked = True
        u0, u1, v0, v1 = self.face.ParameterRange
        uc, vc = self.centre
        for fu, fv in ((0.5, 0.5), (0.3, 0.3), (0.7, 0.7), (0.3, 0.7), (0.7, 0.3)):
            u, v = u0 + fu * (u1 - u0), v0 + fv * (v1 - v0)
            a = self._raw(u, v)
            try:
                b = self.face.normalAt(u, v)
            except Exception:
                continue
            if a is None:
                continue
            d = a[0] * b.x + a[1] * b.y + a[2] * b.z
            if abs(d) > 0.5 * math.sqrt(a[0] ** 2 + a[1] ** 2 + a[2] ** 2):
                self.sign = 1.0 if d > 0 else -1.0
                break
        return self.sign

    def at(self, u, v):
        s = self.check_sign()
        n = self._raw(u, v)
        if n is None:
            uc, vc = self.centre
            for t in _NUDGES:
                n = self._raw(u + (uc - u) * t, v + (vc - v) * t)
                if n is not None:
                    break
            else:
                raise NoNormal(u, v)
        return (s * n[0], s * n[1], s * n[2])


def _evaluator(face):
    return face if isinstance(face, _Normals) else _Normals(face)


def _normals(face, uv):
    """(k, 3) outward normals at the (u, v) pairs (``face``: a Part.Face or a
    :class:`_Normals`); one array built at the end, not one per normal."""
    at = _evaluator(face).at
    return np.array([at(float(u), float(v)) for u, v in uv], dtype=np.float64).reshape(-1, 3)


def _pieces(length, gap):
    return max(1, int(math.ceil(length / gap - 1e-12)))


def _arc_deviations(a, m, b):
    """Angles of the middle samples m from the great circles through a and b (row-wise
    over (k, 3) arrays; where a and b are parallel, the angle of m from a)."""
    c = np.cross(a, b)
    nc = np.sqrt(np.einsum("ij,ij->i", c, c))
    far = np.arccos(np.clip(np.einsum("ij,ij->i", a, m), -1.0, 1.0))
    near = np.arcsin(np.minimum(1.0, np.abs(np.einsum("ij,ij->i", m, c))
                                / np.maximum(nc, 1e-300)))
    return np.where(nc < 1e-15, far, near)


def _parallel_normals(face, us, v):
    """Normals along the parallel v of a surface of revolution (cone, sphere, torus: u is
    the angle about the axis k), at the u values ``us``: n(u) is n(u0) turned about k by
    u - u0, i.e. c + cos(u - u0) a + sin(u - u0) b with c = (n0.k) k, a = n0 - c,
    b = k x n0, which three OCCT normals (at u0, u0 + pi/2, u0 + pi) give exactly:
    c = (n(u0) + n(u0 + pi)) / 2, a = n(u0) - c, b = n(u0 + pi/2) - c."""
    us = np.asarray(us, dtype=np.float64)
    return _parallel_from(_parallel_fit(face, float(us[0]), v), us)


def _parallel_from(fit, us):
    """The normals of a :func:`_parallel_normals` fit (u0, c, a, b) at ``us``."""
    u0, c, a, b = fit
    t = np.asarray(us, dtype=np.float64) - u0
    return c + np.cos(t)[:, None] * a + np.sin(t)[:, None] * b


def _parallel_fit(face, u0, v):
    n = _normals(face, [(u0, v), (u0 + math.pi / 2, v), (u0 + math.pi, v)])
    n /= np.linalg.norm(n, axis=1)[:, None]
    c = (n[0] + n[2]) * 0.5
    return (u0, c, n[0] - c, n[1] - c)


def _small_circle_samples(face, u0, u1, v, deflection):
    """u values along a small circle (v fixed) whose pieces deviate <= deflection from
    great arcs; returns (us, normals at us, deviation).  The normals are those of
    :func:`_parallel_normals` (three OCCT calls per parallel); the pieces double until
    the deviation, measured at each piece's middle, is <= deflection."""
    ev = _evaluator(face)
    k = _pieces(u1 - u0, math.pi / 2)
    fit = _parallel_fit(ev, u0, v)   # the three OCCT normals, once
    while True:
        fine = np.linspace(u0, u1, 2 * k + 1)
        n = _parallel_from(fit, fine)
        a, m = n[::2], n[1::2]
        dev = float(_arc_deviations(a[:-1], m, a[1:]).max())
        if dev <= deflection or k >= 4096:
            return fine[::2], a, dev
        k *= 2


def face_gauss(face, deflection=DEFAULT_DEFLECTION, name="", warnings=None):
    """:class:`mfgeom.parting.FaceGauss` of one face (global, orientation respected).
    A face OCCT cannot evaluate (no normal at a point nor near it, or any other OCCT
    failure): with a ``warnings`` list, "<name>: <why>, skipped" is appended to it and
    None returned; without one, ValueError with that message is raised."""
    try:
        return _face_gauss(face, deflection, name)
    except Exception as exc:   # OCCT errors have several Python types
        msg = f"{name or 'face'}: {exc}, skipped"
        if warnings is None:
            raise ValueError(msg) from exc
        warnings.append(msg)
        return None


def _chain(k):
    """Arcs (FaceGauss.arcs) 0-1, 1-2, ..., of k normals along one curve."""
    i = np.arange(max(0, k - 1))
    return np.column_stack([i, i + 1])


def _lattice(rows, cols):
    """Arcs of a rows x cols lattice of normals (row by row): along each row (a parallel)
    and along each column (a meridian, a great circle on a sphere or torus)."""
    idx = np.arange(rows * cols).reshape(rows, cols)
    return np.vstack([np.column_stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()]),
                      np.column_stack([idx[:-1, :].ravel(), idx[1:, :].ravel()])])


def _face_gauss(face, deflection, name):
    u0, u1, v0, v1 = face.ParameterRange
    surf = face.Surface
    area = float(face.Area)
    ev = _Normals(face, surf)
    if isinstance(surf, Part.Plane):
        n = _normals(ev, [((u0 + u1) / 2, (v0 + v1) / 2)])
        return FaceGauss(n, 0.0, area, name)
    if isinstance(surf, Part.Cylinder):
        us = np.linspace(u0, u1, _pieces(u1 - u0, math.pi / 2) + 1)
        vm = (v0 + v1) / 2
        return FaceGauss(_normals(ev, [(u, vm) for u in us]), 0.0, area, name,
                         _chain(len(us)))
    if isinstance(surf, Part.Cone):
        vm = (v0 + v1) / 2
        _us, normals, dev = _small_circle_samples(ev, u0, u1, vm, deflection)
        return FaceGauss(normals, dev, area, name, _chain(len(normals)))
    if isinstance(surf, (Part.Sphere, Part.Toroid)):
        # meridians are great circles: gaps <= pi/2 are exact along v
        vs = np.linspace(v0, v1, _pieces(v1 - v0, math.pi / 2) + 1)
        # the parallel farthest from both the equator and the pole (|sin v cos v| max)
        # deviates most for a given u step
        v_worst = max(vs.tolist() + [c for c in (math.pi / 4, -math.pi / 4, 3 * math.pi / 4,
                                                 -3 * math.pi / 4) if v0 <= c <= v1],
                      key=lambda v: abs(math.sin(v) * math.cos(v)))
        us, _, dev = _small_circle_samples(ev, u0, u1, v_worst, deflection)
        normals = np.concatenate([_parallel_normals(ev, us, float(v)) for v in vs])
        return FaceGauss(normals, dev, area, name, _lattice(len(vs), len(us)))
    net = _net_surface(surf, (u0, u1, v0, v1))
    if net is not None:
        normals = _net_normals(net[0], deflection)
        if len(normals):
            ev_net = _Normals(face, net[1])
            return FaceGauss(ev_net.check_sign() * normals, 0.0, area, name)
    return _grid_gauss(ev, deflection, name, area,
                       revolution=isinstance(surf, Part.SurfaceOfRevolution))


# ------------------------------------------------------------------ control nets
_NET_MAX_DEPTH = 8       # halvings of a Bezier patch in each direction, at most
_NET_MAX_PATCHES = 4096  # patches of one face, at most (then no more subdivision)
# ... and their control vectors, at most: a degree 7 x 8 patch (OCCT's pump housing)
# has ~10x a bicubic one's, and 4096 of them took 4 s a face; stopping earlier leaves
# the bound conservative (wider only)
_NET_MAX_CROSSES = 16384


def _non_rational(geom):
    """True when the B-spline / Bezier geometry's weights are all equal (a common factor
    cancels from the derivatives' directions) up to 1e-12 relative: OCCT's lofts give
    weights such as 0.9999999999999998, whose effect on a normal's direction is of that
    order (far below any tolerance of the analysis)."""
    w = np.asarray(geom.getWeights(), dtype=np.float64).ravel()
    return bool(w.size == 0 or (w.min() > 0 and w.max() - w.min() <= 1e-12 * w.max()))


def _poles(geom):
    return np.array([[(p.x, p.y, p.z) for p in row] for row in geom.getPoles()],
                    dtype=np.float64)


def _curve_poles(geom):
    return np.array([(p.x, p.y, p.z) for p in geom.getPoles()], dtype=np.float64)


def _bezier_pieces_1d(count_knots, degree):
    """Pole index ranges of the Bezier pieces of a clamped B-spline whose interior knots
    all have multiplicity ``degree``: piece a uses poles a*degree .. a*degree + degree."""
    return [np.arange(a * degree, a * degree + degree + 1) for a in range(count_knots - 1)]


def _to_bezier_form(geom, axis):
    """Raise the interior knots of one direction of a clamped (segmented) B-spline copy
    (surface: axis "U" / "V"; curve: "") to full multiplicity; returns the number of
    knots, or None where OCCT did not give that form."""
    degree = getattr(geom, f"{axis}Degree" if axis else "Degree")
    knots = getattr(geom, f"get{axis}Knots")()
    mults = getattr(geom, f"get{axis}Multiplicities")()
    insert = getattr(geom, f"insert{axis}Knot")
    for k, m in zip(knots[1:-1], mults[1:-1]):
        if m < degree:
            insert(k, degree - m, 0.0)   # raises the multiplicity by degree - m
    mults = getattr(geom, f"get{axis}Multiplicities")()
    knots = getattr(geom, f"get{axis}Knots")()
    if (mults[0] != degree + 1 or mults[-1] != degree + 1
            or any(m != degree for m in mults[1:-1])):
        return None
    return len(knots)


def _segment_box(geom, box):
    """geom.segment to the box, clamped to its bounds where it is not periodic."""
    b = geom.bounds()
    u0, u1, v0, v1 = box
    if not geom.isUPeriodic():
        u0, u1 = max(u0, b[0]), min(u1, b[1])
    if not geom.isVPeriodic():
        v0, v1 = max(v0, b[2]), min(v1, b[3])
    geom.segment(u0, u1, v0, v1)


def _net_surface(surf, box):
    """(nets, natural): the (N, p+1, q+1, 3) Bezier control nets of ``surf`` restricted to
    the parameter box, whose D1U x D1V directions are those of the surface ``natural``
    (its own normal, before the face's orientation), or None when the surface has no such
    net: rational, neither B-spline nor Bezier (nor an offset of one, nor an extrusion of
    a non-rational B-spline / Bezier curve), or OCCT refused a step."""
    try:
        if isinstance(surf, Part.OffsetSurface):
            # an offset surface's normals are its basis surface's (same parameters)
            basis = surf.BasisSurface
            inner = _net_surface(basis, box)
            return None if inner is None else (inner[0], basis)
        if isinstance(surf, Part.BezierSurface):
            if not _non_rational(surf):
                return None
            s = surf.copy()
            if tuple(box) != (0.0, 1.0, 0.0, 1.0):
                s.segment(*[min(1.0, max(0.0, x)) for x in box])
            return _poles(s)[None], surf
        if isinstance(surf, Part.BSplineSurface):
            if not _non_rational(surf):
                return None
            s = surf.copy()
            if s.isUPeriodic() or s.isVPeriodic():
                _segment_box(s, box)   # may cross the seam
            if s.isUPeriodic():
                s.setUNotPeriodic()
            if s.isVPeriodic():
                s.setVNotPeriodic()
            _segment_box(s, box)       # clamped ends (setXNotPeriodic does not clamp)
            nku = _to_bezier_form(s, "U")
            nkv = _to_bezier_form(s, "V")
            if nku is None or nkv is None:
                return None
            P = _poles(s)
            p, q = s.UDegree, s.VDegree
            if P.shape[:2] != ((nku - 1) * p + 1, (nkv - 1) * q + 1):
                return None
            nets = [P[iu][:, iv] for iu in _bezier_pieces_1d(nku, p)
                    for iv in _bezier_pieces_1d(nkv, q)]
            return np.stack(nets), surf
        if isinstance(surf, Part.SurfaceOfExtrusion):
            # S(u, v) = C(u) + v D: D1U x D1V = C'(u) x D; the net of C's Bezier pieces
            # times the segment [v0, v1] of the line
            c = surf.BasisCurve
            d = surf.Direction
            d = np.array((d.x, d.y, d.z), dtype=np.float64)
            u0, u1, v0, v1 = box
            if isinstance(c, Part.BezierCurve):
                if not _non_rational(c):
                    return None
                c = c.copy()
                c.segment(max(0.0, u0), min(1.0, u1))
                pieces = _curve_poles(c)[None]
            elif isinstance(c, Part.BSplineCurve):
                if not _non_rational(c):
                    return None
                c = c.copy()
                if c.isPeriodic():
                    c.segment(u0, u1)
                    c.setNotPeriodic()
                lo, hi = c.FirstParameter, c.LastParameter
                c.segment(u0 if c.isPeriodic() else max(u0, lo),
                          u1 if c.isPeriodic() else min(u1, hi))
                nk = _to_bezier_form(c, "")
                if nk is None:
                    return None
                P = _curve_poles(c)
                if len(P) != (nk - 1) * c.Degree + 1:
                    return None
                pieces = np.stack([P[i] for i in _bezier_pieces_1d(nk, c.Degree)])
            else:
                return None
            nets = np.stack([pieces + v0 * d, pieces + v1 * d], axis=2)
            return nets, surf
    except Exception:   # OCCT refused a copy / segment / knot insertion: sample instead
        return None
    return None


def _split(nets, axis):
    """de Casteljau halves of Bezier nets (N, p+1, q+1, 3) along axis 1 (u) or 2 (v)."""
    a = nets if axis == 1 else nets.swapaxes(1, 2)
    deg = a.shape[1] - 1
    left = np.empty_like(a)
    right = np.empty_like(a)
    left[:, 0] = a[:, 0]
    right[:, deg] = a[:, deg]
    cur = a
    for r in range(1, deg + 1):
        cur = (cur[:, :-1] + cur[:, 1:]) * 0.5
        left[:, r] = cur[:, 0]
        right[:, deg - r] = cur[:, -1]
    if axis == 1:
        return left, right
    return left.swapaxes(1, 2), right.swapaxes(1, 2)


def _cross(a, b):
    """np.cross of (..., 3) arrays, without its per-call overhead."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def _unit_rows(c, floor):
    """Rows of c scaled to unit length; rows shorter than floor: NaN."""
    n = np.sqrt(np.einsum("...i,...i->...", c, c))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where((n > floor)[..., None], c / n[..., None], np.nan)


class _Cone:
    """The convex cone of unit vectors added so far: a spanning set of them and, while it
    lies in a half-space, its visibility map (the library's); a vector x with x.v > 0
    for every vertex v of the map is inside the cone already and is not kept.  Once the
    map is empty nothing can be pruned: vectors are only collected."""

    def __init__(self):
        self._rays = np.zeros((0, 3))
        self._hulled = True
        self._pending = []
        self.vm = None

    def add(self, x):
        from mfgeom import core
        if not len(x):
            return
        if self.vm is not None and self.vm.kind != "polygon":
            # no half-space holds the cone (its map is empty): nothing to prune with;
            # the extreme rays are taken once, when asked for
            self._pending.append(x)
            return
        if self.vm is not None:
            x = x[~np.all(x @ self.vm.vertices.T > 1e-12, axis=1)]
            if not len(x):
                return
        # the library's map takes any spanning set: the hull is taken when asked for
        self._rays = np.concatenate([self._rays, x])
        self._hulled = False
        self.vm = core.visibility_map(self._rays)

    @property
    def rays(self):
        """The extreme rays (a spanning set before :meth:`hull`)."""
        if self._pending:
            self._rays = np.concatenate([self._rays] + self._pending)
            self._pending = []
            self._hulled = False
        return self._rays

    def hull(self):
        rays = self.rays
        if not self._hulled:
            self._rays = _cone_rays(rays)
            self._hulled = True
        return self._rays

    def seeing_directions(self):
        """Directions d with d.n >= 0 for every vector n of the cone: the vertices of its
        visibility map, their and its edges' midpoints, its centre (the vertices' mean)
        and the midpoints between the centre and those (all from the map alone, so the
        same for a rotated part); None when the map is empty (no direction sees all the
        vectors: a wider cone changes nothing then)."""
        if self.vm is None or self.vm.kind == "null" or not len(self.vm.vertices):
            return None
        v = self.vm.vertices
        if len(v) > 32:   # a criterion, not a bound: 32 of them, evenly spread, suffice
            v = v[np.linspace(0, len(v), 33)[:-1].astype(int)]
        pts = [v, v + np.roll(v, -1, axis=0)]
        centre = v.sum(axis=0)
        if np.linalg.norm(centre) > 1e-9:
            centre = centre / np.linalg.norm(centre)
            pts += [centre[None], pts[0] + centre, _unit_rows(pts[1], 1e-30) + centre]
        w = np.concatenate(pts)
        w = w[np.linalg.norm(w, axis=1) > 1e-9]
        return w / np.linalg.norm(w, axis=1)[:, None]


def _normal_patch_weights(p, q):
    """(2p * 2q, p (q+1) (p+1) q) matrix taking the crosses Du_ij x Dv_kl of a Bezier
    patch of degrees (p, q) (Du_ij = P_i+1,j - P_ij, i < p, j <= q; Dv_kl = P_k,l+1 - P_kl)
    to the Bernstein coefficients of its normal patch N = S_u x S_v / (p q), of degrees
    (2p - 1, 2q - 1): B_i^(p-1) B_k^p = C(p-1, i) C(p, k) / C(2p-1, i+k) B_(i+k)^(2p-1), and
    the same in v.  The weights are non-negative."""
    key = (p, q)
    if key in _WEIGHTS:
        return _WEIGHTS[key]
    c = math.comb
    w = np.zeros((2 * p, 2 * q, p, q + 1, p + 1, q))
    for i in range(p):
        for j in range(q + 1):
            for k in range(p + 1):
                for l in range(q):
                    w[i + k, j + l, i, j, k, l] = (c(p - 1, i) * c(p, k) / c(2 * p - 1, i + k)
                                                   * c(q, j) * c(q - 1, l) / c(2 * q - 1, j + l))
    _WEIGHTS[key] = w.reshape(4 * p * q, -1)
    return _WEIGHTS[key]


_WEIGHTS = {}


def _net_normals(nets, deflection):
    """Unit normal directions whose convex cone holds D1U x D1V of every point of the
    Bezier patches ``nets`` (N, p+1, q+1, 3): S_u is p times the Bezier patch of the
    u-hodograph control vectors (differences of consecutive poles along u), S_v likewise,
    so the normal S_u x S_v is a Bezier patch of degrees (2p - 1, 2q - 1) whose control
    vectors are non-negative combinations of the crosses of those differences
    (:func:`_normal_patch_weights`); the normals lie in the cone of its control vectors.

    Refinement: the corner normals of every patch are exact normals of the surface; a
    patch is halved in u and v (de Casteljau) while its crosses cost a direction that
    sees all exact normals found so far more than ``deflection`` of its draft margin
    (asin(min d.n) on the exact normals minus that on the crosses, over the directions of
    :meth:`_Cone.seeing_directions`), up to _NET_MAX_DEPTH halvings or _NET_MAX_PATCHES
    patches.  Patches inside the face's cone are not refined: only the cone's boundary
    matters.  Zero crosses (collapsed edges) are dropped; the returned set is the
    extreme rays of the accepted patches' control vectors (or, when no direction sees
    all exact normals, those: their cone is then the whole space)."""
    if nets.shape[1] < 2 or nets.shape[2] < 2:
        return np.zeros((0, 3))
    scale = float(np.ptp(nets.reshape(-1, 3), axis=0).max()) or 1.0
    floor = (1e-12 * scale) ** 2   # crosses are products of two differences
    out, truth = [], _Cone()
    weights = _normal_patch_weights(nets.shape[1] - 1, nets.shape[2] - 1)
    accepted = 0
    cur = nets
    for depth in range(_NET_MAX_DEPTH + 1):
        k = len(cur)
        du = cur[:, 1:] - cur[:, :-1]            # (k, p, q+1, 3)
        dv = cur[:, :, 1:] - cur[:, :, :-1]      # (k, p+1, q, 3)
        raw = _cross(du.reshape(k, -1, 1, 3), dv.reshape(k, 1, -1, 3)).reshape(k, -1, 3)
        crosses = _unit_rows(np.matmul(weights, raw), floor)
        corners = _unit_rows(np.stack([_cross(du[:, 0, 0], dv[:, 0, 0]),
                                       _cross(du[:, -1, 0], dv[:, -1, 0]),
                                       _cross(du[:, 0, -1], dv[:, 0, -1]),
                                       _cross(du[:, -1, -1], dv[:, -1, -1])], axis=1), floor)
        c = corners.reshape(-1, 3)
        truth.add(c[~np.isnan(c[:, 0])])
        W = truth.seeing_directions() if depth < _NET_MAX_DEPTH else None
        if W is None:
            bad = np.zeros(k, dtype=bool)
        else:
            # the draft margin each direction has on the exact normals, and on the crosses
            m_true = np.arcsin(np.clip((truth.rays @ W.T).min(axis=0), -1, 1))  # (|W|,)
            excess = np.empty(k)
            step = max(1, 60000 // (crosses.shape[1] * len(W)))
            for i in range(0, k, step):
                proj = crosses[i:i + step] @ W.T
                proj[np.isnan(proj)] = 1.0   # dropped (zero) crosses
                low = proj.min(axis=1)
                excess[i:i + step] = (m_true[None, :]
                                      - np.arcsin(np.clip(low, -1, 1))).max(axis=1)
            bad = excess > deflection
            if (4 * int(bad.sum()) + accepted > _NET_MAX_PATCHES
                    or (4 * int(bad.sum()) + accepted) * crosses.shape[1] > _NET_MAX_CROSSES):
                bad[:] = False
        accepted += int((~bad).sum())
        good = crosses[~bad].reshape(-1, 3)
        out.append(good[~np.isnan(good[:, 0])])
        if not bad.any():
            break
        a, b = _split(cur[bad], 1)
        halves = np.concatenate([a, b])
        a, b = _split(halves, 2)
        cur = np.concatenate([a, b])
    vm = truth.vm
    if vm is not None and vm.kind == "null":
        # no direction sees all the exact normals: their cone is the whole space, which
        # holds every normal (the map is empty whatever is added)
        return truth.hull()
    crosses = np.concatenate(out)
    if vm is not None and vm.kind == "polygon":
        # crosses strictly inside the exact normals' cone (which the crosses' cone holds)
        # add nothing to it
        crosses = crosses[~np.all(crosses @ vm.vertices.T > 1e-12, axis=1)]
    return _cone_rays(np.concatenate([truth.rays, crosses]))


def _hull_2d(pts):
    """Indices of the convex hull's vertices of 2-D points (monotone chain; collinear
    points dropped)."""
    order = np.lexsort((pts[:, 1], pts[:, 0]))
    if len(order) <= 2:
        return list(order)
    P = pts.tolist()

    def chain(seq):
        h = []
        for i in seq:
            x, y = P[i]
            while len(h) >= 2:
                ax, ay = P[h[-2]]
                bx, by = P[h[-1]]
                if (bx - ax) * (y - ay) - (by - ay) * (x - ax) <= 0:
                    h.pop()
                else:
                    break
            h.append(i)
        return h
    lower = chain(order.tolist())
    upper = chain(order[::-1].tolist())
    return lower[:-1] + upper[:-1]


_PREFILTER = np.array([(math.cos(a), math.sin(a))
                       for a in np.linspace(0, 2 * math.pi, 33)[:-1]])


def _cone_rays(s):
    """A subset of the unit vectors s (rows) with the same convex cone.  Where they all lie
    within 84 deg of their mean direction m: the vertices of the convex hull of their
    central projection onto the plane tangent at m (great circles project to lines, so
    those are the extreme rays).  Else s is split by its nearest of the six axis
    directions +-x, +-y, +-z (each part within 55 deg of its axis) and each part reduced
    so (the union of the parts' extreme rays spans the whole cone).  Points inside the
    polygon of the extreme points in 32 directions are dropped before the hull."""
    if len(s) <= 4:
        return s
    s = np.unique(s, axis=0)
    m = s.sum(axis=0)
    norm = math.sqrt(float(m @ m))
    if norm > 0:
        m = m / norm
        if float((s @ m).min()) > 0.1:
            return _projected_hull(s, m)
    keep = []
    which = np.argmax(np.abs(s), axis=1)
    positive = s[np.arange(len(s)), which] > 0
    for ax in range(3):
        for sign in (1.0, -1.0):
            part = s[(which == ax) & ((positive) == (sign > 0))]
            if len(part):
                axis = np.zeros(3)
                axis[ax] = sign
                keep.append(_projected_hull(part, axis))
    return np.concatenate(keep)


def _projected_hull(s, m):
    """The rows of s (unit, all with s.m > 0) that are extreme rays of their cone."""
    if len(s) <= 3:
        return s
    mx, my, mz = float(m[0]), float(m[1]), float(m[2])
    # e1 = m x (x or y axis), e2 = m x e1: an orthonormal frame of the tangent plane
    e1 = (0.0, mz, -my) if abs(mx) < 0.9 else (-mz, 0.0, mx)
    l1 = math.sqrt(e1[0] ** 2 + e1[1] ** 2 + e1[2] ** 2)
    e1 = np.array(e1) / l1
    e2 = np.array((my * e1[2] - mz * e1[1], mz * e1[0] - mx * e1[2], mx * e1[1] - my * e1[0]))
    d = s @ m
    pts = np.stack([s @ e1, s @ e2], axis=1) / d[:, None]
    # prefilter (Akl-Toussaint): the extreme points in _PREFILTER directions are hull
    # vertices (in counter-clockwise order); points strictly inside their polygon are not
    ext = pts[np.argmax(pts @ _PREFILTER.T, axis=0)]
    e = np.roll(ext, -1, axis=0) - ext
    cr = (e[:, 0][None, :] * (pts[:, 1][:, None] - ext[:, 1][None, :])
          - e[:, 1][None, :] * (pts[:, 0][:, None] - ext[:, 0][None, :]))
    margin = 1e-12 * (np.abs(e).sum(axis=1) + 1e-300)
    cand = np.nonzero(~np.all(cr > margin[None, :], axis=1))[0]
    if len(cand) <= 2:
        return s[cand]
    return s[cand[_hull_2d(pts[cand])]]


# ------------------------------------------------------------------ sampled faces
def _plane_deviation(a, b, m):
    """Angles of normals m from the great circles through a and b (row-wise)."""
    c = np.cross(a, b)
    nc = np.linalg.norm(c, axis=-1)
    far = np.arccos(np.clip(np.sum(a * m, axis=-1), -1.0, 1.0))
    near = np.arcsin(np.clip(np.abs(np.sum(m * c, axis=-1)) / np.maximum(nc, 1e-300), 0, 1))
    return np.where(nc > 1e-12, near, far)


def _grid_normals(ev, us, vs, revolution):
    """(len(us), len(vs), 3) normals on the grid us x vs; for a surface of revolution
    (u the angle about its axis) each parallel from three OCCT normals
    (:func:`_parallel_normals`)."""
    if revolution:
        return np.stack([_parallel_normals(ev, us, float(v)) for v in vs], axis=1)
    return _normals(ev, [(u, v) for u in us for v in vs]).reshape(len(us), len(vs), 3)


def _grid_gauss(face, deflection, name, area, revolution=False):
    """UV grid of k x k cells; the normals at the cells' edge midpoints and centres (a
    grid twice as fine) measure how far the surface's normals leave the great arcs
    between neighbouring samples; shrink = twice the largest such deviation (the factor
    covers the deviation's peak not being exactly at a midpoint).  k doubles until
    shrink <= deflection (or the grid reaches 128 x 128 cells); each doubling keeps the
    normals already evaluated (linspace of 4k + 1 points holds that of 2k + 1 exactly).
    ``revolution``: the face's surface is one of revolution (u about its axis)."""
    ev = _evaluator(face)
    u0, u1, v0, v1 = ev.face.ParameterRange
    k = 8
    us = np.linspace(u0, u1, 2 * k + 1)
    vs = np.linspace(v0, v1, 2 * k + 1)
    fine = _grid_normals(ev, us, vs, revolution)
    while True:
        n = fine[::2, ::2]
        dev = max(_plane_deviation(n[:-1, :], n[1:, :], fine[1::2, ::2]).max(),
                  _plane_deviation(n[:, :-1], n[:, 1:], fine[::2, 1::2]).max(),
                  np.minimum(_plane_deviation(n[:-1, :-1], n[1:, 1:], fine[1::2, 1::2]),
                             _plane_deviation(n[1:, :-1], n[:-1, 1:], fine[1::2, 1::2])).max())
        shrink = 2.0 * float(dev)
        if shrink <= deflection or k >= _MAX_GRID - 1:
            return FaceGauss(n.reshape(-1, 3), shrink, area, name)
        k *= 2
        us = np.linspace(u0, u1, 2 * k + 1)
        vs = np.linspace(v0, v1, 2 * k + 1)
        if revolution:
            fine = _grid_normals(ev, us, vs, True)
            continue
        finer = np.empty((2 * k + 1, 2 * k + 1, 3))
        finer[::2, ::2] = fine
        odd_u = [(u, v) for u in us[1::2] for v in vs]
        finer[1::2, :] = _normals(ev, odd_u).reshape(k, 2 * k + 1, 3)
        odd_v = [(u, v) for u in us[::2] for v in vs[1::2]]
        finer[::2, 1::2] = _normals(ev, odd_v).reshape(k + 1, k, 3)
        fine = finer


def _oriented_tangent(edge, face, t, in_face=None):
    """Tangent of ``edge`` at t as the edge runs in ``face`` (face on its left, seen
    from the face's outward normal): OCCT orients a face's edges that way.
    ``in_face``: the edge as ``face.Edges`` lists it (its first occurrence), when the
    caller already has it (else the face's edges are searched: O(edges of the face))."""
    if in_face is None:
        in_face = next((e for e in face.Edges if e.isSame(edge)), None)
        if in_face is None:
            raise ValueError("edge not in face")
    tan = in_face.tangentAt(t)
    sign = -1.0 if in_face.Orientation == "Reversed" else 1.0
    return (sign * tan.x, sign * tan.y, sign * tan.z)


class _FaceNormals:
    """Outward normals of one face at points of its edges, for :func:`adjacency`: the
    point's (u, v) from the edge's curve on the face (its pcurve: 2.5 us; projecting the
    point onto a B-spline surface, ``Surface.parameter``, took ~1 ms), the normal from
    :class:`_Normals` (the surface's normal with the face's sign, nudged inside where
    OCCT has none); a plane's normal is evaluated once."""

    def __init__(self, face):
        self.face = face
        self.surface = face.Surface
        self.plane = isinstance(self.surface, Part.Plane)
        self.normal = None
        self.normals = _Normals(face, self.surface)

    def at(self, p, edge=None, t=None):
        """The normal at the point p of the face, which is ``edge`` (as the face lists
        it) at its parameter t when those are given."""
        if self.normal is not None:
            return self.normal
        uv = None
        if edge is not None:
            try:
                pc = self.face.curveOnSurface(edge)
                if pc is not None:
                    q = pc[0].value(t)
                    uv = (q.x, q.y)
            except Exception:   # no pcurve: project instead
                uv = None
        if uv is None:
            uv = self.surface.parameter(p)
        x, y, z = self.normals.at(float(uv[0]), float(uv[1]))
        length = math.sqrt(x * x + y * y + z * z)
        n = (x / length, y / length, z / length)
        if self.plane:
            self.normal = n
        return n


def edge_kind(edge, f1, f2, tangent_tol=DEFAULT_TANGENT_TOL, in_f1=None, normals=None,
              in_f2=None):
    """'concave', 'convex' or 'tangent' for the edge shared by faces f1 and f2, from
    their outward normals at the edge's middle: with T the edge's tangent as it runs in
    f1, the dihedral is convex when (n1 x n2) . T > 0 (f2 turns away from the material).
    ``in_f1`` / ``in_f2`` (the edge as f1.Edges / f2.Edges list it) and ``normals`` (a
    :class:`_FaceNormals` of f1 and one of f2) spare the searches and repeated OCCT
    evaluations when the caller has them (:func:`adjacency`).  Plain float arithmetic
    on 3-vectors: numpy's per-call overhead was most of the cost."""
    t0, t1 = edge.ParameterRange
    t = (t0 + t1) / 2
    p = edge.valueAt(t)
    n1, n2 = normals if normals is not None else (_FaceNormals(f1), _FaceNormals(f2))
    a = n1.at(p, in_f1 if in_f1 is not None else edge, t)
    b = n2.at(p, in_f2 if in_f2 is not None else edge, t)
    c = (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])
    if math.atan2(math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]),
                  a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) <= tangent_tol:
        return "tangent"
    tan = _oriented_tangent(edge, f1, t, in_f1)
    return "convex" if c[0] * tan[0] + c[1] * tan[1] + c[2] * tan[2] > 0 else "concave"


def adjacency(shape, tangent_tol=DEFAULT_TANGENT_TOL, only=None, warnings=None):
    """[(i, j, kind)] for every edge shared by faces i < j of ``shape`` (0-based).
    Linear in the number of edges: each face's edges are listed once, and each shared
    edge remembers how it runs in each of its faces (no search of a face's edges per
    shared edge, which was quadratic on faces with many holes).  ``only``: a set of face
    indices: edges between those faces only.  An edge OCCT cannot classify (no normal
    at its middle nor near it) is taken as concave (it joins its faces into one
    surface, the conservative choice) with "FaceI/FaceJ: <why>, taken as concave"
    appended to ``warnings`` (a list; without one the error is raised)."""
    faces = shape.Faces
    # hash code -> [[edge, {owner face: the edge as that face lists it}], ...]: different
    # edges may share a hash code (OCCT's are pointer-based; seen on a 4999-face part),
    # so isSame decides
    buckets = {}
    for i, f in enumerate(faces):
        if only is not None and i not in only:
            continue
        for e in f.Edges:
            if e.Degenerated:
                continue
            bucket = buckets.setdefault(e.hashCode(), [])
            entry = next((x for x in bucket if x[0].isSame(e)), None)
            if entry is None:
                entry = [e, {}]
                bucket.append(entry)
            entry[1].setdefault(i, e)   # the first occurrence, as face.Edges lists it
    normals = {}

    def normals_of(i):
        if i not in normals:
            normals[i] = _FaceNormals(faces[i])
        return normals[i]
    out = []
    for bucket in buckets.values():
        for edge, owners in bucket:
            lst = list(owners)
            for a in range(len(lst)):
                for b in range(a + 1, len(lst)):
                    i, j = lst[a], lst[b]
                    try:
                        kind = edge_kind(edge, faces[i], faces[j], tangent_tol, owners[i],
                                         (normals_of(i), normals_of(j)), owners[j])
                    except Exception as exc:
                        if warnings is None:
                            raise
                        warnings.append(f"Face{i + 1}/Face{j + 1}: {exc}, taken as concave")
                        kind = "concave"
                    out.append((i, j, kind))
    return sorted(out)


def part_gauss(source, deflection=DEFAULT_DEFLECTION, tangent_tol=DEFAULT_TANGENT_TOL,
               face_names=None, warnings=None):
    """(faces, adjacency, shape): a FaceGauss per face of ``source`` (named "FaceN" as
    in the source's shape), the edge adjacency with kinds (indices into ``faces``), and
    the global shape they were computed on (sharing the source's geometry: copy it before
    changing it).  ``face_names`` (e.g. ["Face3", "Face7"]):
    only those faces, joined only across edges they share with each other.
    A face OCCT cannot evaluate is left out of ``faces`` (and of the adjacency), with
    "FaceN: <why>, skipped" appended to ``warnings`` when a list is given; without one,
    ValueError with that message is raised (the part's other faces are not analysed).
    An edge that cannot be classified is taken as concave, warned (:func:`adjacency`)."""
    shape = shape_of(source, deep=False)   # only read here
    all_faces = shape.Faces
    if face_names is None:
        chosen = list(range(len(all_faces)))
    else:
        chosen = []
        for name in face_names:
            if not (name.startswith("Face") and name[4:].isdigit()
                    and 1 <= int(name[4:]) <= len(all_faces)):
                raise ValueError(f"{name!r} is not a face of a shape with {len(all_faces)} faces")
            if int(name[4:]) - 1 not in chosen:
                chosen.append(int(name[4:]) - 1)
        chosen.sort()
        if not chosen:
            raise ValueError("no faces given")
    faces, kept = [], []
    for k, i in enumerate(chosen):
        progress.step(k / len(chosen), "parting: Gaussian maps of the faces")
        g = face_gauss(all_faces[i], deflection, f"Face{i + 1}", warnings)
        if g is not None:
            faces.append(g)
            kept.append(i)
    index = {i: k for k, i in enumerate(kept)}
    adj = [(index[i], index[j], kind)
           for i, j, kind in adjacency(shape, tangent_tol, set(kept), warnings)]
    return faces, adj, shape
