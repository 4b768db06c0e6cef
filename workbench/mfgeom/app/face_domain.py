# SPDX-License-Identifier: LGPL-2.1-or-later
"""Maps a FreeCAD face and 3-D points into one 2-D domain so libmfgeom can classify them.

This is the pure geometry of the "Classify points" feature: no document, no GUI.
A point is classified through its orthogonal projection onto the face's surface (so
points should lie on or near that surface); its offset from the surface is ignored
for the class and reported as ``max_distance_to_surface``.  ON means: the projected
point is within ``tol`` (mm, 3-D Euclidean distance) of the face's boundary edges.
The boundary is discretised with a chordal deflection of ``DEFLECTION_FRACTION * tol``
(5 % of the tolerance), so "the boundary" is exact to within 5 % of the tolerance.

Planar faces (surface ``Part::GeomPlane``)
    The plane's own parametrisation is an orthonormal frame (origin ``S(0,0)``, axes
    ``S(1,0)-S(0,0)`` and ``S(0,1)-S(0,0)``), so the 2-D domain is the plane itself:
    2-D distances are 3-D distances, points are projected orthogonally onto the plane,
    and libmfgeom decides IN / ON / OUT in one exact pass with the tolerance in mm.

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
    ON, step 2 (exact, in mm): for the candidates only, the 3-D distance from the
    projected point S(u, v) to the real boundary edges (discretised in 3-D) is compared
    with tol.  So ON means the same, in mm, as on planar faces, and a strongly
    distorted parametrisation (wide tol_uv) costs time, not accuracy.

    The pcurves are discretised with deflection ``DEFLECTION_FRACTION * tol /
    sigma_max`` in (x, y), i.e. at most 5 % of the tolerance once mapped to 3-D.
    ``distortion`` = sigma_max / sigma_min is reported per face (1.0 on cylinders).

With ``tol == 0`` the deflection falls back to 1e-6 of the face's size, and ON means
"on the discretised boundary".
"""

import math
import time

import numpy as np

import FreeCAD

from mfgeom import core

DEFLECTION_FRACTION = 0.05
FILTER_SAFETY = 2.0
METRIC_GRID = 17
EDGE_SAMPLES = 9
SIGMA_FLOOR = 1e-9
_CHUNK = 1_000_000  # point-segment pairs per numpy block in the exact 3-D ON test


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
        self.face = face
        self.tol = tol
        self.surface = face.Surface
        self._size = max(face.BoundBox.DiagonalLength, 1e-9)
        self._regions = []
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
        defl = self._deflection_3d()
        rings = []
        for wire in self.face.Wires:
            segs = []
            for edge in wire.OrderedEdges:
                if edge.Degenerated:
                    continue
                xyz = np.array([_xyz(p) for p in edge.discretize(Deflection=defl)])
                seg = self._plane_xy(xyz)
                segs.append(seg[::-1] if edge.Orientation == "Reversed" else seg)
            rings.extend(r for r in _chain(segs) if len(r) >= 3)
        if not rings:
            raise ValueError("the face has no boundary wire that encloses an area")
        self.rings = rings
        self._region = self._new_region(rings, self.tol)

    def _plane_xy(self, xyz):
        d = xyz - self._origin
        return np.column_stack((d @ self._eu, d @ self._ev))

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
        defl_2d = max(DEFLECTION_FRACTION * self.tol / self.sigma[1], 1e-6 * size_2d)
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
            rings.extend(r for r in _chain(segs) if len(r) >= 3)
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

        # The exact ON test measures in 3-D against the real edges.
        defl = self._deflection_3d()
        a_list, b_list = [], []
        for edge in face.Edges:
            if edge.Degenerated or _is_in(edge, seams):
                continue
            p = np.array([_xyz(q) for q in edge.discretize(Deflection=defl)], dtype=np.float64)
            if len(p) >= 2:
                a_list.append(p[:-1])
                b_list.append(p[1:])
        self._seg_a = np.concatenate(a_list) if a_list else np.zeros((0, 3))
        self._seg_b = np.concatenate(b_list) if b_list else np.zeros((0, 3))

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

    def _deflection_3d(self):
        return max(DEFLECTION_FRACTION * self.tol, 1e-6 * self._size)

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
            return self._region.classify(xy), dist
        classes = self._parity.classify(xy)
        on_seam = np.nonzero(classes == core.ON)[0]
        if len(on_seam):
            # Exactly on a pcurve with tol 0: real edges are settled below; seams and
            # poles are interior, so step off them to read the parity.
            nudge = 1e-9 * max(1.0, float(np.abs(xy).max()))
            again = self._parity.classify(xy[on_seam] + nudge)
            again[again == core.ON] = core.IN
            classes[on_seam] = again
        if self._candidates is not None and len(self._seg_a):
            cand = np.nonzero(self._candidates.classify(xy) == core.ON)[0]
            if len(cand):
                d3 = _distance_to_segments(foot[cand], self._seg_a, self._seg_b)
                classes[cand[d3 <= self.tol]] = core.ON
        return classes, dist

    def close(self):
        """Free the C regions now rather than at garbage collection."""
        for region in self._regions:
            region.close()
        self._regions = []


class Classification:
    """The result of :func:`classify_points_on_face` (plain data)."""

    def __init__(self, classes, distance, domain, seconds):
        self.classes = classes
        self.counts = {
            "in": int(np.count_nonzero(classes == core.IN)),
            "on": int(np.count_nonzero(classes == core.ON)),
            "out": int(np.count_nonzero(classes == core.OUT)),
        }
        self.max_distance_to_surface = float(distance.max()) if len(distance) else 0.0
        self.method = domain.method
        self.tol = domain.tol
        self.tol_2d = domain.tol_2d
        self.distortion = domain.distortion
        self.boundary_vertices = domain.boundary_vertices
        self.seconds = seconds


def classify_points_on_face(face, points, tol):
    """Classify 3-D points (an (m, 3) array-like) against ``face`` with tolerance ``tol`` mm."""
    t0 = time.perf_counter()
    domain = FaceDomain(face, tol)
    try:
        classes, dist = domain.classify(points)
    finally:
        domain.close()
    return Classification(classes, dist, domain, time.perf_counter() - t0)


# ----------------------------------------------------------------- helpers
def _check_face(face):
    if getattr(face, "ShapeType", None) != "Face":
        kind = getattr(face, "ShapeType", type(face).__name__)
        raise TypeError(f"expected a face, got {kind}")
    if face.isNull():
        raise ValueError("the face is a null shape")


def _xyz(v):
    return (v.x, v.y, v.z)


def _clean_ring(ring):
    """Drop consecutive duplicates and a repeated closing vertex (harmless, but wasted work)."""
    if len(ring) == 0:
        return ring
    keep = np.ones(len(ring), dtype=bool)
    keep[1:] = np.any(ring[1:] != ring[:-1], axis=1)
    ring = ring[keep]
    if len(ring) > 1 and np.all(ring[0] == ring[-1]):
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


def _chain(segs):
    """Join oriented polylines end to start into closed rings.

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
        rings.append(_clean_ring(np.concatenate(ring)))
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


def _distance_to_segments(p, a, b):
    """Euclidean distance from each point p[i] to the nearest segment [a[j], b[j]] (3-D)."""
    ab = b - a
    len2 = (ab * ab).sum(1)
    len2[len2 == 0.0] = 1.0  # a zero-length segment is its endpoint: t clamps to 0
    out = np.empty(len(p))
    step = max(1, _CHUNK // max(1, len(a)))
    for s in range(0, len(p), step):
        q = p[s:s + step, None, :]
        t = np.clip(((q - a) * ab).sum(-1) / len2, 0.0, 1.0)
        d = q - (a + t[..., None] * ab)
        out[s:s + step] = np.sqrt((d * d).sum(-1).min(1))
    return out
