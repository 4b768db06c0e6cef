# SPDX-License-Identifier: LGPL-2.1-or-later
"""Maps a FreeCAD face and 3-D points into one 2-D domain so libmfgeom can classify them.

This is the pure geometry of the "Classify points" feature: no document, no GUI.
A point is classified through its orthogonal projection onto the face's surface (its
"foot"); its distance to the surface is reported (``max_distance_to_surface``,
``far_count``) and, with ``strict``, a point farther than ``tol`` from the surface is
OUT.  ON means: the foot is within ``tol`` (mm, 3-D Euclidean distance) of the face's
*true* boundary edges, for every tolerance the feature accepts.

The exact boundary, and what "exact" costs
    Each real boundary edge (not a seam, not degenerated) is discretised with a chordal
    deflection of ``DEFLECTION_FRACTION * tol`` (5 %), with no floor, so the polyline
    stays within ``tol`` of the edge and every point farther than ``tol`` from the edge
    lies on the same side of the polyline as of the edge: the polyline's parity is the
    face's parity wherever the answer is not ON.  Whether a point is ON is decided on
    the exact edge curves: points whose distance to the polyline is within
    ``ON_MARGIN * tol`` of ``tol`` are measured against the edges themselves (a
    safeguarded Newton iteration on the edge's curve in each polyline span within
    reach; OCCT's BRepExtrema where an edge has no parametric curve), so "distance to
    the boundary <= tol" is decided to machine precision.  A tolerance is refused
    (``InputError``) below what the face's boundary defines: OCCT's
    Precision::Confusion (``MIN_TOLERANCE`` = 1e-7 mm) or the largest tolerance of the
    face's edges (an edge is only known to within its tolerance).  Only planar faces
    bounded by straight edges accept any tolerance >= 0: their boundary is the polygon.

Planar faces (surface ``Part::GeomPlane``)
    The plane's own parametrisation is an orthonormal frame (origin ``S(0,0)``, axes
    ``S(1,0)-S(0,0)`` and ``S(0,1)-S(0,0)``), so the 2-D domain is the plane itself:
    2-D distances are 3-D distances and points are projected orthogonally onto the
    plane.  Straight edges only: libmfgeom decides IN / ON / OUT in one exact pass with
    the tolerance in mm.  With curved edges: libmfgeom marks the candidates within
    ``tol + margin`` of the polyline and gives the parity of the others; the candidates
    are decided on the exact edges as above.

Curved faces (any other surface): parity in (u, v), ON in 3-D
    The boundary comes from the edges' pcurves (``face.curveOnSurface(edge)``), each
    turned by its edge's orientation and chained end to start into closed loops (the
    wire explorer's order is not always the walking order in (u, v), e.g. on a torus),
    so a seam contributes both of its pcurves (u = umin and u = umin + period) and the
    domain closes.  A point p goes to ``face.Surface.parameter(p)`` (orthogonal
    projection onto the surface), shifted by whole periods so that u lies in
    [umin, umin + period) (likewise v).  Parameters are rescaled to lengths,
    ``x = su * u``, ``y = sv * v``, with su, sv the median lengths of dS/du, dS/dv over
    the metric samples (on a cylinder (x, y) is then an isometry of the developed
    surface).

    IN / OUT: even-odd parity of (x, y) against all pcurves (libmfgeom, tol 0).  On
    periodic surfaces the domain is tiled at -1, 0, +1 periods, so a point near a seam
    or a hole that straddles the seam comes out right on either side.  Seams (edges the
    face's wires use twice) and degenerated edges (a sphere's poles) take part in the
    parity but are not boundary.

    ON, step 1 (the tolerance in parameter units, conservative): libmfgeom marks as
    candidates the points within

        tol_uv = FILTER_SAFETY * tol / sigma_min   (+ the pcurve deflection)

    of the real (non-seam, non-degenerated) pcurves, where sigma_min is the smallest
    singular value of the Jacobian of (x, y) -> S(u, v).  A surface path of length
    <= tol spans at most tol / sigma_min in (x, y), so every point within tol of the
    boundary is a candidate; FILTER_SAFETY = 2 covers the sampling of sigma_min and
    the gap between chordal and on-surface distance.  sigma_min and sigma_max are
    sampled, not bounded: on a 17 x 17 grid over the face's parameter range (nodes
    inside the face only) plus 9 interior points of every non-degenerated pcurve.
    sigma_min is floored at 1e-9 (a pole would make tol_uv infinite; then every point
    is a candidate and step 2 alone decides).
    ON, step 2 (in mm, on the exact edges): for the candidates only, the 3-D distance
    from the foot S(u, v) to the real boundary edges is compared with tol as described
    above.  So ON means the same, in mm, as on planar faces, and a strongly distorted
    parametrisation (wide tol_uv) costs time, not accuracy.

    The pcurves are discretised with deflection ``DEFLECTION_FRACTION * tol /
    sigma_max`` in (x, y), i.e. at most 5 % of the tolerance once mapped to 3-D.
    ``distortion`` = sigma_max / sigma_min is reported per face (1.0 on cylinders).
"""

import math
import time

import numpy as np

import FreeCAD

from mfgeom import core
from mfgeom.errors import InputError

DEFLECTION_FRACTION = 0.05
# Points within ON_MARGIN * tol of the ON threshold (distance to the polyline) are
# measured on the exact edges: 4x the deflection, so an underestimated deflection
# (GCPnts estimates it from samples) still leaves them inside the window.
ON_MARGIN = 4.0 * DEFLECTION_FRACTION
MIN_TOLERANCE = 1e-7  # mm: OCCT's Precision::Confusion, below which points coincide
FILTER_SAFETY = 2.0
METRIC_GRID = 17
EDGE_SAMPLES = 9
SIGMA_FLOOR = 1e-9
NEWTON_STEPS = 60
_POINT_BLOCK = 100_000  # points per block in the ON test (bounds the pair arrays)
_STRAIGHT = ("Part::GeomLine", "Part::GeomLineSegment")


class FaceDomain:
    """A face mapped to 2-D, ready to classify many points with one tolerance.

    Attributes: ``method`` ("plane" or "uv"), ``tol`` (mm), ``tol_2d`` (the tolerance
    handed to libmfgeom, 2-D units: mm on planes, the candidate band tol_uv on curved
    faces), ``distortion`` (sigma_max / sigma_min, 1 on planes), ``rings`` (the 2-D
    boundary, tiled on periodic surfaces), ``boundary_vertices``.
    """

    def __init__(self, face, tol):
        _check_face(face)
        tol = float(tol)
        if not math.isfinite(tol) or tol < 0.0:
            raise ValueError(f"tolerance must be a finite number >= 0 mm, got {tol!r}")
        least = minimum_tolerance(face)
        if tol < least:
            raise InputError(
                f"a tolerance of {tol:g} mm cannot be honoured on this face: its boundary "
                f"is only defined to {least:g} mm (" + (
                    "OCCT's Precision::Confusion" if least == MIN_TOLERANCE
                    else "the tolerance of its edges") + f"); use at least {least:g} mm")
        self.face = face
        self.tol = tol
        self.surface = face.Surface
        self._regions = []
        self._boundary = None
        if getattr(self.surface, "TypeId", "") == "Part::GeomPlane":
            self._build_plane()
        else:
            self._build_uv()
        self.boundary_vertices = int(sum(len(r) for r in self.rings))

    # ------------------------------------------------------------- planar faces
    def _build_plane(self):
        self.method = "plane"
        s = self.surface
        o = np.array(_xyz(s.value(0.0, 0.0)))
        eu = np.array(_xyz(s.value(1.0, 0.0))) - o
        ev = np.array(_xyz(s.value(0.0, 1.0))) - o
        # Part.Plane is parametrised by an orthonormal frame; re-orthonormalise anyway so
        # millimetres stay millimetres whatever produced the surface.
        eu /= np.linalg.norm(eu)
        ev -= eu * float(eu @ ev)
        ev /= np.linalg.norm(ev)
        self._origin, self._eu, self._ev = o, eu, ev
        self._normal = np.cross(eu, ev)
        self.tol_2d = self.tol
        self.distortion = 1.0
        wires = [[e for e in w.OrderedEdges if not e.Degenerated] for w in self.face.Wires]
        self._boundary = _Boundary([e for w in wires for e in w], DEFLECTION_FRACTION * self.tol)
        rings, k = [], 0
        for wire in wires:
            segs = []
            for edge in wire:
                seg = self._plane_xy(self._boundary.polylines[k])
                k += 1
                segs.append(seg[::-1] if edge.Orientation == "Reversed" else seg)
            rings.extend(r for r in _chain(segs, MERGE_FRACTION * DEFLECTION_FRACTION * self.tol)
                         if len(r) >= 3)
        if not rings:
            raise ValueError("the face has no boundary wire that encloses an area")
        self.rings = rings
        if self._boundary.straight:
            self._region = self._new_region(rings, self.tol)  # the polygon is the boundary
            self._parity = None
        else:
            # Candidates within tol + margin of the polyline; parity for the rest.
            self.tol_2d = self.tol * (1.0 + ON_MARGIN)
            self._region = self._new_region(rings, self.tol_2d)
            self._parity = self._new_region(rings, 0.0)

    def _plane_xy(self, xyz):
        d = xyz - self._origin
        return np.column_stack((d @ self._eu, d @ self._ev))

    def plane_xy(self, xyz):
        """The 2-D coordinates (k, 2) of 3-D points (global) in a planar face's domain:
        their projection onto its plane (the inverse of plane_points on the plane)."""
        if self.method != "plane":
            raise ValueError("plane_xy: the face is not planar")
        return self._plane_xy(np.asarray(xyz, dtype=np.float64).reshape(-1, 3))

    def plane_points(self, xy):
        """The 3-D points (global) of 2-D coordinates ``xy`` (k, 2) of a planar face's
        domain: the inverse of the projection (2-D lengths are mm)."""
        if self.method != "plane":
            raise ValueError("plane_points: the face is not planar")
        xy = np.asarray(xy, dtype=np.float64).reshape(-1, 2)
        return self._origin + np.outer(xy[:, 0], self._eu) + np.outer(xy[:, 1], self._ev)

    # ------------------------------------------------------------- curved faces
    def _build_uv(self):
        self.method = "uv"
        face, s = self.face, self.surface
        umin, umax, vmin, vmax = face.ParameterRange
        self._range = (umin, umax, vmin, vmax)
        self.period = (s.UPeriod() if s.isUPeriodic() else None,
                       s.VPeriod() if s.isVPeriodic() else None)

        wires = []  # per wire: [(curve2d, first, last, reversed, real), ...]
        samples = []  # (u, v) where the metric is measured
        seams = _seam_edges(face)
        for wire in face.Wires:
            items = []
            for edge in wire.OrderedEdges:
                pc = face.curveOnSurface(edge)
                if pc is None:
                    raise ValueError("an edge of the face has no curve on its surface "
                                     f"({s.TypeId}); run Part > Check geometry on the shape")
                c2d, a, b = pc
                real = not (edge.Degenerated or _is_in(edge, seams))
                items.append((c2d, a, b, edge.Orientation == "Reversed", real))
                if edge.Degenerated:
                    continue  # a pole: dS/du vanishes there by construction, not in the face
                for k in range(EDGE_SAMPLES):
                    # interior parameters: a seam's ends may sit on a pole
                    p = c2d.value(a + (b - a) * (k + 0.5) / EDGE_SAMPLES)
                    samples.append((p.x, p.y))
            wires.append(items)
        for i in range(METRIC_GRID):
            u = umin + (umax - umin) * (i + 0.5) / METRIC_GRID
            for j in range(METRIC_GRID):
                v = vmin + (vmax - vmin) * (j + 0.5) / METRIC_GRID
                if face.isPartOfDomain(u, v):
                    samples.append((u, v))
        if not samples:
            raise ValueError("the face has no boundary to classify against")
        self._measure_metric(samples)

        su, sv = self.scale
        size_2d = math.hypot(su * (umax - umin), sv * (vmax - vmin))
        # No floor: the parity must be right wherever the answer is not ON.
        defl_2d = DEFLECTION_FRACTION * self.tol / self.sigma[1]
        # GCPnts discretises in raw (u, v); the rescaling stretches chords by <= max(su, sv)
        defl_uv = defl_2d / max(su, sv)
        rings, chains = [], []
        has_seam_or_pole = False
        for items in wires:
            segs = []
            for c2d, a, b, rev, real in items:
                seg = np.array([(p.x * su, p.y * sv)
                                for p in c2d.discretize(Deflection=defl_uv, First=a, Last=b)])
                segs.append(seg[::-1] if rev else seg)
                if real:
                    chains.append(seg)
                else:
                    has_seam_or_pole = True
            rings.extend(r for r in _chain(segs, MERGE_FRACTION * defl_2d) if len(r) >= 3)
        if not rings:
            raise ValueError("the face has no boundary wire that encloses an area in (u, v)")

        shifts = self._tile_shifts()
        self.rings = [r + sh for sh in shifts for r in rings]
        if has_seam_or_pole:
            closed = [c for c in map(_there_and_back, chains) if c is not None]
            real_rings = [c + sh for sh in shifts for c in closed]
        else:
            real_rings = self.rings
        self.tol_2d = min(FILTER_SAFETY * self.tol / self.sigma[0] + defl_2d,
                          1e12 * max(size_2d, 1.0))
        self._parity = self._new_region(self.rings, 0.0)
        self._candidates = self._new_region(real_rings, self.tol_2d) if real_rings else None

        # The ON test measures in 3-D against the real edges.
        self._boundary = _Boundary([e for e in face.Edges
                                    if not (e.Degenerated or _is_in(e, seams))],
                                   DEFLECTION_FRACTION * self.tol)

    def _measure_metric(self, samples):
        """su, sv (median |dS/du|, |dS/dv|) and the extreme singular values of the
        Jacobian of (x, y) = (su u, sv v) -> S over the samples."""
        d1 = [self.face.derivative1At(u, v) for u, v in samples]
        su_vec = np.array([_xyz(a) for a, _b in d1])
        sv_vec = np.array([_xyz(b) for _a, b in d1])
        su = float(np.median(np.linalg.norm(su_vec, axis=1))) or 1.0
        sv = float(np.median(np.linalg.norm(sv_vec, axis=1))) or 1.0
        a = (su_vec * su_vec).sum(1) / (su * su)
        b = (su_vec * sv_vec).sum(1) / (su * sv)
        c = (sv_vec * sv_vec).sum(1) / (sv * sv)
        mid = 0.5 * (a + c)
        rad = np.sqrt(0.25 * (a - c) ** 2 + b ** 2)
        sig_min = max(float(np.sqrt(np.maximum(mid - rad, 0.0)).min()), SIGMA_FLOOR)
        sig_max = max(float(np.sqrt(mid + rad).max()), sig_min)
        self.scale = (su, sv)
        self.sigma = (sig_min, sig_max)
        self.distortion = sig_max / sig_min

    def _tile_shifts(self):
        su, sv = self.scale
        pu, pv = self.period
        us = [0.0] if pu is None else [-pu * su, 0.0, pu * su]
        vs = [0.0] if pv is None else [-pv * sv, 0.0, pv * sv]
        return [np.array([x, y]) for x in us for y in vs]

    def _new_region(self, rings, tol):
        region = core.Region(rings, tol)
        self._regions.append(region)
        return region

    # ------------------------------------------------------------- points
    def project(self, points):
        """Map (m, 3) points into the 2-D domain.

        Returns (xy, foot, distance): 2-D coordinates, the projected 3-D points on the
        surface, and each point's distance to the surface.
        """
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        if not np.all(np.isfinite(pts)):
            raise ValueError("points contain NaN or infinite coordinates")
        if self.method == "plane":
            off = (pts - self._origin) @ self._normal
            return self._plane_xy(pts), pts - np.outer(off, self._normal), np.abs(off)
        s = self.surface
        uv = np.empty((len(pts), 2))
        foot = np.empty((len(pts), 3))
        vec = FreeCAD.Vector
        for i, (x, y, z) in enumerate(pts.tolist()):
            u, v = s.parameter(vec(x, y, z))
            uv[i] = (u, v)
            foot[i] = _xyz(s.value(u, v))
        dist = np.linalg.norm(foot - pts, axis=1)
        umin, _umax, vmin, _vmax = self._range
        pu, pv = self.period
        if pu is not None:
            uv[:, 0] = umin + np.mod(uv[:, 0] - umin, pu)
        if pv is not None:
            uv[:, 1] = vmin + np.mod(uv[:, 1] - vmin, pv)
        return uv * np.array(self.scale), foot, dist

    def classify(self, points):
        """Classify (m, 3) points; returns (classes, distance of each point to the surface).

        ``classes`` is a uint8 array of core.OUT / core.IN / core.ON.
        """
        xy, foot, dist = self.project(points)
        if len(xy) == 0:
            return np.zeros(0, dtype=np.uint8), dist
        if self.method == "plane":
            classes = self._region.classify(xy)
            if self._parity is not None:
                cand = np.nonzero(classes == core.ON)[0]
                if len(cand):
                    on = self._boundary.within(foot[cand], self.tol)
                    classes[cand[~on]] = self._parity.classify(xy[cand[~on]])
            return classes, dist
        classes = self._parity.classify(xy)
        on_seam = np.nonzero(classes == core.ON)[0]
        if len(on_seam):
            # Exactly on a pcurve with tol 0: real edges are settled below; seams and
            # poles are interior, so step off them to read the parity.
            nudge = 1e-9 * max(1.0, float(np.abs(xy).max()))
            again = self._parity.classify(xy[on_seam] + nudge)
            again[again == core.ON] = core.IN
            classes[on_seam] = again
        if self._candidates is not None and self._boundary.segments:
            cand = np.nonzero(self._candidates.classify(xy) == core.ON)[0]
            if len(cand):
                classes[cand[self._boundary.within(foot[cand], self.tol)]] = core.ON
        return classes, dist

    def close(self):
        """Free the C regions now rather than at garbage collection."""
        for region in self._regions:
            region.close()
        self._regions = []


class Classification:
    """The result of :func:`classify_points_on_face` (plain data).

    ``far_count``: points farther than the tolerance from the face's surface (OUT when
    ``strict``, else classified by their projection); ``max_distance_to_surface`` in mm.
    """

    def __init__(self, classes, distance, domain, seconds, strict):
        self.classes = classes
        self.counts = {
            "in": int(np.count_nonzero(classes == core.IN)),
            "on": int(np.count_nonzero(classes == core.ON)),
            "out": int(np.count_nonzero(classes == core.OUT)),
        }
        self.max_distance_to_surface = float(distance.max()) if len(distance) else 0.0
        self.far_count = int(np.count_nonzero(distance > off_surface_distance(domain.tol)))
        self.strict = bool(strict)
        self.method = domain.method
        self.tol = domain.tol
        self.tol_2d = domain.tol_2d
        self.distortion = domain.distortion
        self.boundary_vertices = domain.boundary_vertices
        self.seconds = seconds

    def surface_report(self):
        """(is_warning, text) about the points' distance to the surface, for the Report
        view: a warning when points farther than the tolerance were classified by their
        projection, a note when strict made them OUT, else just the largest distance."""
        far, dmax, tol = self.far_count, self.max_distance_to_surface, self.tol
        if not far:
            return False, f"largest distance of a point to the face's surface {dmax:g} mm"
        what = f"{far} point{'s' if far != 1 else ''} farther than the tolerance ({tol:g} mm) " \
               f"from the face's surface (largest distance {dmax:g} mm)"
        if self.strict:
            return False, f"{what}: OUT (Strict)"
        return True, (f"{what} classified by their projection onto the surface; "
                      "set Strict to make them OUT")


def classify_points_on_face(face, points, tol, strict=False):
    """Classify 3-D points (an (m, 3) array-like) against ``face`` with tolerance ``tol`` mm.

    ``strict``: a point farther than ``tol`` (at least 1e-7 mm) from the face's surface is
    OUT (else it is classified by its orthogonal projection onto the surface)."""
    t0 = time.perf_counter()
    domain = FaceDomain(face, tol)
    try:
        classes, dist = domain.classify(points)
    finally:
        domain.close()
    if strict:
        classes[dist > off_surface_distance(domain.tol)] = core.OUT
    return Classification(classes, dist, domain, time.perf_counter() - t0, strict)


def off_surface_distance(tol):
    """Farther than this from the surface, a point is off it (OUT when strict): the
    tolerance, but at least OCCT's Precision::Confusion, so that at tolerance 0 a point
    on a tilted plane is not OUT for the rounding of its projection."""
    return max(tol, MIN_TOLERANCE)


def minimum_tolerance(face):
    """The smallest tolerance (mm) ON can be decided with on ``face``: 0 for a planar face
    bounded by straight edges (the polygon is exact), else the larger of OCCT's
    Precision::Confusion and the tolerances of the face's real boundary edges."""
    _check_face(face)
    planar = getattr(face.Surface, "TypeId", "") == "Part::GeomPlane"
    edges = [e for e in face.Edges if not e.Degenerated]
    if planar and all(_is_straight(e) for e in edges):
        return 0.0
    seams = _seam_edges(face)
    return max([MIN_TOLERANCE] + [e.Tolerance for e in edges if not _is_in(e, seams)])


class _Boundary:
    """The real boundary edges of a face in 3-D: a polyline within ``deflection`` of each
    edge for the fast distance test, and the edges' exact curves for the decision.

    The polyline comes from OCCT's GCPnts (``Edge.discretize(Deflection=...)``); the
    exact distance is minimised over the polyline spans within reach of a point, each
    span [t_j, t_j+1] (parameters of its vertices on the edge's curve) by a safeguarded
    Newton iteration on (C(t) - q) . C'(t) = 0; span ends count too, so the distance to
    a trimmed edge includes its end points.
    """

    def __init__(self, edges, deflection):
        self.edges = list(edges)
        straight = [_is_straight(e) for e in self.edges]
        self.straight = all(straight)
        self.polylines, a_list, b_list, owner, index = [], [], [], [], []
        for k, edge in enumerate(self.edges):
            if straight[k]:  # exact as a segment, whatever the deflection
                p = np.array([_xyz(edge.valueAt(edge.FirstParameter)),
                              _xyz(edge.valueAt(edge.LastParameter))])
            else:
                p = np.array([_xyz(q) for q in edge.discretize(Deflection=deflection)],
                             dtype=np.float64)
            self.polylines.append(p)
            if len(p) >= 2:
                a_list.append(p[:-1])
                b_list.append(p[1:])
                owner.append(np.full(len(p) - 1, k))
                index.append(np.arange(len(p) - 1))
        self.segments = int(sum(len(a) for a in a_list))
        self._a = np.concatenate(a_list) if a_list else np.zeros((0, 3))
        self._b = np.concatenate(b_list) if b_list else np.zeros((0, 3))
        self._owner = np.concatenate(owner) if owner else np.zeros(0, dtype=int)
        self._index = np.concatenate(index) if index else np.zeros(0, dtype=int)
        self._straight = straight
        self._curves = {}  # edge index -> Geom curve, or None (no parametric access)
        self._params = {}  # (edge index, vertex index) -> parameter on the edge
        self._grid = None

    def within(self, points, tol):
        """Boolean mask: is each (3-D) point within ``tol`` of the true edges?"""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
        out = np.zeros(len(points), dtype=bool)
        if not self.segments or not len(points):
            return out
        margin = ON_MARGIN * tol
        reach = tol + margin
        if self._grid is None or self._grid.reach != reach:
            self._grid = _SegmentGrid(self._a, self._b, reach)
        for s in range(0, len(points), _POINT_BLOCK):
            block = points[s:s + _POINT_BLOCK]
            pt, seg = self._grid.pairs(block)
            d, lam = _pair_distances(block[pt], self._a[seg], self._b[seg])
            d_poly = np.full(len(block), np.inf)
            np.minimum.at(d_poly, pt, d)
            sure = d_poly <= tol - margin  # deep inside the band: the polyline suffices
            unsure = (d_poly > tol - margin) & (d_poly <= reach)
            # The exact distance of an unsure point: the minimum over the spans within reach
            best = np.full(len(block), np.inf)
            for i in np.nonzero(unsure[pt] & (d <= reach))[0]:
                p, g = int(pt[i]), int(seg[i])
                k = int(self._owner[g])
                if self._straight[k]:
                    dist = float(d[i])  # the segment is the edge
                else:
                    dist = self._span_distance(k, int(self._index[g]), block[p], float(lam[i]))
                best[p] = min(best[p], dist)
            out[s:s + len(block)] = sure | (unsure & (best <= tol))
        return out

    def _span_distance(self, k, j, q, lam):
        edge = self.edges[k]
        span = self._span(k, j)
        if span is None:  # no parametric curve: OCCT's exact distance to the whole edge
            import Part
            return float(Part.Vertex(FreeCAD.Vector(*q)).distToShape(edge)[0])
        ta, tb = span
        return _nearest_on_span(edge, q, ta, tb, ta + lam * (tb - ta))

    def _span(self, k, j):
        """Parameters (ta, tb) of polyline vertices j, j+1 of edge k, or None."""
        edge = self.edges[k]
        if k not in self._curves:
            try:
                curve = edge.Curve
                mid = self.polylines[k][len(self.polylines[k]) // 2]
                t0 = curve.parameter(FreeCAD.Vector(*mid))
                ok = _dist(edge.valueAt(t0), mid) <= 1e-9 * (1.0 + edge.Length)
            except Exception:  # noqa: BLE001 -- OCCT raises several kinds; any means "no curve"
                curve, ok = None, False
            self._curves[k] = curve if ok else None
        curve = self._curves[k]
        if curve is None:
            return None
        first, last = edge.FirstParameter, edge.LastParameter
        # GCPnts walks from the first to the last parameter whatever the orientation,
        # so the polyline's ends are the edge's ends.
        n = len(self.polylines[k])
        ta = first if j == 0 else self._param(k, j, curve)
        tb = last if j + 1 == n - 1 else self._param(k, j + 1, curve)
        if curve.isPeriodic():
            per = curve.period()
            if j > 0:
                ta = first + math.fmod(ta - first, per) % per
            if j + 1 < n - 1:
                tb = ta + math.fmod(tb - ta, per) % per
        ta, tb = min(max(ta, first), last), min(max(tb, first), last)
        return (ta, tb) if ta <= tb else (tb, ta)

    def _param(self, k, j, curve):
        key = (k, j)
        if key not in self._params:
            self._params[key] = curve.parameter(FreeCAD.Vector(*self.polylines[k][j]))
        return self._params[key]


# ----------------------------------------------------------------- helpers
def _nearest_on_span(edge, q, ta, tb, t):
    """Distance from q to the edge's curve over [ta, tb]: Newton on
    f(t) = (C(t) - q) . C'(t), kept inside a bracket that shrinks with f's sign (the
    span is far below the curve's features, so f changes sign at most once in it),
    bisecting when a step leaves it; the span's ends are candidates too."""
    qx, qy, qz = q
    best = min(_dist(edge.valueAt(ta), q), _dist(edge.valueAt(tb), q))
    lo, hi = ta, tb
    for _ in range(NEWTON_STEPS):
        c, d1, d2 = edge.valueAt(t), edge.derivative1At(t), edge.derivative2At(t)
        rx, ry, rz = c.x - qx, c.y - qy, c.z - qz
        best = min(best, math.sqrt(rx * rx + ry * ry + rz * rz))
        f = rx * d1.x + ry * d1.y + rz * d1.z
        if f > 0.0:
            hi = t
        elif f < 0.0:
            lo = t
        else:
            break
        h = d1.x * d1.x + d1.y * d1.y + d1.z * d1.z + rx * d2.x + ry * d2.y + rz * d2.z
        nxt = t - f / h if h > 0.0 else 0.5 * (lo + hi)
        if not lo < nxt < hi:
            nxt = 0.5 * (lo + hi)
        if abs(nxt - t) <= 4e-16 * max(abs(t), abs(ta), abs(tb), 1.0):
            break
        t = nxt
    return best


def _dist(v, q):
    return math.sqrt((v.x - q[0]) ** 2 + (v.y - q[1]) ** 2 + (v.z - q[2]) ** 2)


def _is_straight(edge):
    try:
        return edge.Curve.TypeId in _STRAIGHT
    except Exception:  # noqa: BLE001 -- "undefined curve type": treat as curved
        return False


def _pair_distances(q, a, b):
    """Distance from each point q[i] to the segment [a[i], b[i]] and the fraction along
    the segment of the nearest point."""
    ab = b - a
    len2 = (ab * ab).sum(1)
    len2[len2 == 0.0] = 1.0  # a zero-length segment is its endpoint: t clamps to 0
    t = np.clip(((q - a) * ab).sum(1) / len2, 0.0, 1.0)
    d = q - (a + t[:, None] * ab)
    return np.sqrt((d * d).sum(1)), t


class _SegmentGrid:
    """Segments bucketed on a uniform 3-D grid, each in every cell its box grown by
    ``reach`` touches, so a point meets only the segments that can be within reach of
    it (measuring every point against every segment took seconds for 10^4 points near
    a finely discretised edge).  Cells are hashed, so the grid has no extent limit; a
    collision only adds segments to measure.  Segments that would fill more than
    MAX_CELLS cells (long straight edges) are measured against every point."""

    MAX_CELLS = 64

    def __init__(self, a, b, reach):
        self.reach = reach
        lengths = np.linalg.norm(b - a, axis=1)
        self.cell = max(float(np.median(lengths)) if len(a) else 0.0, reach, 1e-300)
        lo = np.floor((np.minimum(a, b) - reach) / self.cell).astype(np.int64)
        hi = np.floor((np.maximum(a, b) + reach) / self.cell).astype(np.int64)
        span = hi - lo + 1
        count = span.prod(axis=1)
        big = count > self.MAX_CELLS
        self.everywhere = np.nonzero(big)[0]
        segs = np.nonzero(~big)[0]
        count, lo, span = count[segs], lo[segs], span[segs]
        seg = np.repeat(segs, count)
        local = np.arange(int(count.sum())) - np.repeat(np.cumsum(count) - count, count)
        sy, sz = np.repeat(span[:, 1], count), np.repeat(span[:, 2], count)
        cells = np.repeat(lo, count, axis=0) + np.column_stack(
            (local // (sy * sz), (local // sz) % sy, local % sz))
        keys = _cell_keys(cells)
        order = np.argsort(keys, kind="stable")
        self._keys, self._segs = keys[order], seg[order]

    def pairs(self, points):
        """(point index, segment index) of every segment near each point."""
        keys = _cell_keys(np.floor(points / self.cell).astype(np.int64))
        left = np.searchsorted(self._keys, keys, "left")
        n = np.searchsorted(self._keys, keys, "right") - left
        pt = np.repeat(np.arange(len(points)), n)
        seg = self._segs[np.repeat(left, n) + np.arange(int(n.sum()))
                         - np.repeat(np.cumsum(n) - n, n)]
        if len(self.everywhere):
            pt = np.concatenate([pt, np.repeat(np.arange(len(points)), len(self.everywhere))])
            seg = np.concatenate([seg, np.tile(self.everywhere, len(points))])
        return pt, seg


def _cell_keys(cells):
    # Wrapping int64 arithmetic is intended: a hash.
    with np.errstate(over="ignore"):
        return (cells[:, 0] * 73856093) ^ (cells[:, 1] * 19349663) ^ (cells[:, 2] * 83492791)


def _check_face(face):
    if getattr(face, "ShapeType", None) != "Face":
        kind = getattr(face, "ShapeType", type(face).__name__)
        raise TypeError(f"expected a face, got {kind}")
    if face.isNull():
        raise ValueError("the face is a null shape")


def _xyz(v):
    return (v.x, v.y, v.z)


# Ring vertices closer than this fraction of the boundary's deflection are one vertex.
MERGE_FRACTION = 0.02


def _clean_ring(ring, eps=0.0):
    """Drop vertices within ``eps`` of the previous one, and a closing vertex within
    ``eps`` of the first.  Not only exact duplicates: a closed edge's polyline ends at
    cos(2 pi) = 1 + 5e-14 of its start, and chained pieces meet within the edge
    tolerance; such a near-duplicate makes an edge of 1e-14 whose neighbours all but touch,
    which the medial axis (exact) refuses as a ring touching itself.  ``eps`` is a small
    fraction of the deflection the polyline already has, so nothing moves noticeably."""
    if len(ring) == 0:
        return ring
    keep = np.ones(len(ring), dtype=bool)
    step = np.diff(ring, axis=0)
    keep[1:] = np.any(step != 0, axis=1) & (np.hypot(step[:, 0], step[:, 1]) > eps)
    ring = ring[keep]
    while len(ring) > 1 and (np.all(ring[0] == ring[-1]) or float(np.hypot(*(ring[-1] - ring[0]))) <= eps):
        ring = ring[:-1]
    return ring


def _seam_edges(face):
    """Edges that the face's wires use twice (once each way): the face wraps around them.

    Not ``Edge.isSeam(face)``: that only says the edge has two pcurves on the surface,
    which is also true of the edge between two faces that a boolean split at the seam
    of one surface, and there the edge is real boundary of each face.
    """
    seen, seams = {}, []
    for wire in face.Wires:
        for edge in wire.OrderedEdges:
            bucket = seen.setdefault(edge.hashCode(), [])
            if any(edge.isSame(other) for other in bucket):
                if not _is_in(edge, seams):
                    seams.append(edge)
            else:
                bucket.append(edge)
    return seams


def _is_in(edge, edges):
    return any(edge.isSame(other) for other in edges)


def _chain(segs, eps=0.0):
    """Join oriented polylines end to start into closed rings (vertices within ``eps``
    merged: :func:`_clean_ring`).

    The order of a wire's edges in (u, v) is not always the walking order (on a torus
    every seam edge starts and ends at the same vertex, so the wire explorer may list
    them in any order), so when the next piece in the list does not start where the
    ring ends, the piece whose start (or, reversed, end) is nearest is taken.  Once the
    ring is closed and nothing starts at its end, what is left forms another ring.
    """
    pending = [np.asarray(s, dtype=np.float64).reshape(-1, 2) for s in segs]
    pending = [s for s in pending if len(s)]
    rings = []
    while pending:
        ring = [pending.pop(0)]
        start = ring[0][0]
        gap = _gap(ring + pending)
        while pending:
            end = ring[-1][-1]
            if float(np.hypot(*(pending[0][0] - end))) <= gap:
                ring.append(pending.pop(0))  # the usual case: already in walking order
                continue
            d_start = [float(np.hypot(*(s[0] - end))) for s in pending]
            d_end = [float(np.hypot(*(s[-1] - end))) for s in pending]
            i, j = int(np.argmin(d_start)), int(np.argmin(d_end))
            closing = float(np.hypot(*(end - start)))
            if closing <= gap and min(d_start[i], d_end[j]) > gap:
                break  # closed, and no piece continues here: the rest is another loop
            if d_start[i] <= d_end[j]:
                ring.append(pending.pop(i))
            else:
                ring.append(pending.pop(j)[::-1])
        rings.append(_clean_ring(np.concatenate(ring), eps))
    return rings


def _gap(pieces):
    """How close two piece ends must be to count as joined: 1e-4 of the wire's extent,
    loose enough for pcurves of intersection edges (whose ends miss each other by up to
    the edge tolerance) and far below any feature of the wire.  It only steers the
    chaining; the geometry is never snapped."""
    pts = np.concatenate(pieces)
    return 1e-4 * max(float(np.ptp(pts, axis=0).max()), 1e-300)


def _there_and_back(chain):
    """A polyline walked there and back: a closed ring of zero area.  Its distance field
    is the polyline's and it never changes even-odd parity, which is how the ON-only
    boundary (real edges without seams) is handed to libmfgeom."""
    # Only consecutive duplicates go: a closed chain keeps its closing vertex, else the
    # walk would skip its last segment.
    keep = np.ones(len(chain), dtype=bool)
    keep[1:] = np.any(chain[1:] != chain[:-1], axis=1)
    chain = chain[keep]
    if len(chain) == 0:
        return None
    if len(chain) == 1:
        chain = np.vstack([chain, chain])
    if len(chain) == 2:  # libmfgeom wants >= 3 vertices per ring
        chain = np.vstack([chain[0], 0.5 * (chain[0] + chain[1]), chain[1]])
    return np.vstack([chain, chain[-2:0:-1]])
