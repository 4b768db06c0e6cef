# SPDX-License-Identifier: LGPL-2.1-or-later
"""Mould parting directions and 3-axis NC set-up plans from per-face Gaussian maps
(seed 000, section 2.2), FreeCAD-free: numpy and mfgeom.core only.

Input: one :class:`FaceGauss` per face (its unit normals and, where they were sampled,
``shrink``, a bound on the angle by which the face's true normals may leave the cone of
the samples), and the face adjacency with each edge's kind ("concave", "convex",
"tangent").  Faces joined across concave or tangent edges form *concave-connected
surfaces*; the visibility map VM(S) = {d : d.n >= 0 for every normal n of S} of each
surface is computed by the C library.

Tolerances and exactness:

* Samples: a direction d with d.s >= sin(shrink) for every sample s satisfies d.n >= 0
  for every true normal n within ``shrink`` of the samples' cone, so a sampled face's map
  is the library's draft map of its samples with draft = user draft + shrink.  A
  surface's map is the map of its exact faces' normals (one call) intersected with the
  maps of its sampled faces (the library's maximum intersection, kept if it covers all
  of them): a drilled hole's cylinder keeps its exact POINT map though its drill-point
  cone is sampled.
* Angular tolerance ``tol`` (default 1e-6 rad, far below any draft angle): the library
  decides kinds exactly on the doubles it is given, and the normals of a moved part are
  never exactly on a great circle.  Before calling it, each surface's normals are
  *canonicalised* (:func:`canonical_normals`): normals within ``tol`` are merged,
  near-antipodal ones become exact negations, and the great circle carrying the most
  (>= 3 distinct) normal axes within ``tol`` is rotated onto the plane z = 0 of a local
  frame and its normals snapped onto it (z = 0 exactly).  The map is computed in that
  frame and rotated back.  Before that, the exact faces' normals are snapped across the
  whole part (a normal within ``tol`` of an earlier face's normal, or of its negation,
  becomes that normal), so maps of different surfaces meant to meet do meet.  So the
  same faces are covered whether the part is rotated or not, directions rotate with the
  part, and every answer holds up to ``tol`` (with a draft, the library's inscribed draft
  polygons make coverage conservative by up to 1e-4 rad more).
* Ties (equal weight and margin within 1e-9 rad) go to the region covering the
  lexicographically smallest list of surfaces (surfaces are numbered by their lowest
  face), not to the library's coordinate order, so they break the same way for a
  rotated part.
* A surface whose normals are all one normal (a plane, coplanar faces) has
  VM u -VM = the whole sphere at zero draft: it is demouldable along any direction and
  is left out of the maximum intersection (always covered).
* A surface whose normals lie on one great circle (a cylinder wall) has VM and -VM
  meeting at the circle's poles, where the library would count it twice.  The true count
  (each surface once) is recomputed from the cover sets, and if the library's best region
  double-counts, the locally maximal regions at the true count's level are searched.
"""

import math
from dataclasses import dataclass, field

import numpy as np

from mfgeom import core
from mfgeom import progress
from mfgeom.geometry.planar import label_components

# The angular tolerance (rad): 0.01 degree.  CAD data of walls that are vertical by design
# carries normals 1e-6 .. 1e-4 rad off the wall's plane (B-spline fits, STEP round trips);
# within this tolerance such a wall is *zero draft*, not an undercut.
DEFAULT_TOL = math.radians(0.01)
EDGE_KINDS = ("concave", "convex", "tangent")
# Normal components below this are flushed to 0 (they cannot change a unit vector's
# direction by more than 1e-18 rad; the library refuses components below 2^-200)
TINY_COMPONENT = 2.0 ** -60


@dataclass
class FaceGauss:
    """Gaussian map of one face: ``normals`` (m, 3) unit normals (outward, face
    orientation respected); ``shrink`` (rad): bound on how far true normals may lie
    outside the cone of these samples (0 where exact); ``area``; ``name``; ``arcs``
    (optional, (k, 2) indices into normals): pairs whose shorter great arc holds true
    normals of the face (a cylinder's circle, a sphere's meridians), so the worst angle
    (:func:`face_draft`) is measured along them, not only at the normals."""
    normals: np.ndarray
    shrink: float = 0.0
    area: float = 1.0
    name: str = ""
    arcs: object = None

    def __post_init__(self):
        n = np.asarray(self.normals, dtype=np.float64).reshape(-1, 3)
        if len(n) == 0:
            raise ValueError(f"face {self.name or '?'} has no normals")
        lengths = np.linalg.norm(n, axis=1)
        if not np.all(np.isfinite(lengths)) or np.any(lengths == 0):
            raise ValueError(f"face {self.name or '?'} has zero or non-finite normals")
        n = n / lengths[:, None]
        n[np.abs(n) < TINY_COMPONENT] = 0.0   # e.g. -6.2e-65 from OCCT: not an error
        self.normals = n / np.linalg.norm(n, axis=1)[:, None]
        if not (self.shrink >= 0 and math.isfinite(self.shrink)):
            raise ValueError(f"face {self.name or '?'}: shrink must be finite and >= 0")
        if self.arcs is not None:
            arcs = np.asarray(self.arcs, dtype=np.int64).reshape(-1, 2)
            if len(arcs) and (arcs.min() < 0 or arcs.max() >= len(n)):
                raise ValueError(f"face {self.name or '?'}: arc index out of range")
            self.arcs = arcs


# --------------------------------------------------------------- surfaces
def concave_surfaces(nfaces, adjacency):
    """Group faces 0..nfaces-1 into concave-connected surfaces: faces joined across
    concave or tangent edges (union-find).  ``adjacency``: iterable of (i, j, kind).
    Returns (groups, has_concave): groups as sorted lists of face indices, ordered by
    their smallest face; has_concave[g] is True if a concave edge joins two faces of g."""
    pairs, concave_faces = [], []
    for i, j, kind in adjacency:
        if kind not in EDGE_KINDS:
            raise ValueError(f"unknown edge kind {kind!r}")
        if not (0 <= i < nfaces and 0 <= j < nfaces):
            raise ValueError(f"adjacency ({i}, {j}) outside 0..{nfaces - 1}")
        if kind == "convex" or i == j:
            continue
        pairs.append((i, j))
        if kind == "concave":
            concave_faces.append(i)
    ij = np.array(pairs, dtype=np.int64).reshape(-1, 2)
    # labels numbered in order of each component's smallest face (geometry.planar)
    label = label_components(nfaces, ij[:, 0], ij[:, 1]) if nfaces else np.zeros(0, np.int64)
    groups = [[] for _ in range(int(label.max()) + 1 if nfaces else 0)]
    for f in range(nfaces):
        groups[label[f]].append(f)
    has_concave = [False] * len(groups)
    for i in concave_faces:
        has_concave[label[i]] = True
    return groups, has_concave


# --------------------------------------------------------------- canonical normals
def _unit(v):
    return v / np.linalg.norm(v)


def _distinct_axes(p, cos_t):
    """(axes, k, sign) of unit normals p (m, 3): the distinct axes up to sign (the first
    normal of each kept) and, per normal, the index of its axis and the sign (+-1) with
    which it equals it: normal i is within acos(cos_t) of sign[i] * axes[k[i]].  Blocks of
    normals are compared with the axes found so far in one product each; only normals
    that start a new axis cost a Python step (analytic faces: a handful)."""
    m = len(p)
    buf = np.zeros((max(m, 1), 3))
    count = 0
    k_out = np.zeros(m, dtype=np.int64)
    s_out = np.ones(m)
    for i in range(0, m, 512):
        block = p[i:i + 512]
        if count:
            dots = block @ buf[:count].T
            k = np.argmax(np.abs(dots), axis=1)
            best = dots[np.arange(len(block)), k]
            hit = np.abs(best) >= cos_t
            k_out[i:i + len(block)][hit] = k[hit]
            s_out[i:i + len(block)][hit] = np.where(best[hit] > 0, 1.0, -1.0)
        else:
            hit = np.zeros(len(block), dtype=bool)
        first_new = count
        for j in np.nonzero(~hit)[0]:
            n = block[j]
            if count > first_new:   # axes started by this block's earlier normals
                d2 = buf[first_new:count] @ n
                kk = int(np.argmax(np.abs(d2)))
                if abs(d2[kk]) >= cos_t:
                    k_out[i + j] = first_new + kk
                    s_out[i + j] = 1.0 if d2[kk] > 0 else -1.0
                    continue
            buf[count] = n
            k_out[i + j] = count
            count += 1
    return buf[:count].copy(), k_out, s_out


def fitted_pole(normals, tol):
    """The pole u of the great circle that all ``normals`` lie within ``tol`` of (a
    wall, a cylinder, a ruled B-spline wall), or None: the least singular vector of the
    normals, checked on every normal.  A face with one normal (a plane) has no pole."""
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    if len(n) < 2 or np.all(n @ n[0] >= math.cos(tol)):
        return None
    _, _, vt = np.linalg.svd(n)   # full: 2 normals have a pole too
    u = vt[2]
    if np.max(np.abs(n @ u)) > math.sin(tol):
        return None
    # a sign fixed by the normals' frame, so a rotated face gives the rotated pole
    k = int(np.argmax(np.abs(u)))
    return u if u[k] > 0 else -u


def canonical_normals(normals, tol=DEFAULT_TOL, max_circle_search=96, poles=()):
    """Snap a surface's normals so that degeneracies within ``tol`` become exact.

    Returns (R, local): a rotation R (3x3, rows = local axes) and the snapped normals in
    that frame (local = R @ n; global = local @ R).  Normals within tol are merged
    (first one kept), near-antipodal ones become the exact negation, and the great
    circle holding the most (>= 3) distinct axes within tol is made the plane z = 0
    (those normals get z = 0 exactly).  Every normal moves by at most ~tol.

    Candidate circles: the poles of all pairs of axes (skipped above
    ``max_circle_search`` axes), and ``poles`` (unit vectors: the part's plane normals
    and the fitted poles of its walls, see :func:`build_surfaces`).  A candidate from
    ``poles`` is used as given (not refitted), so a wall's circle snapped about a plane
    normal of the part has that normal, to the last bit, as its pole: the wall's map then
    meets the plane's map exactly (a blade wall and the disc it stands on)."""
    p = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    p = p / np.linalg.norm(p, axis=1)[:, None]
    cos_t, sin_t = math.cos(tol), math.sin(tol)
    axes, which, sign = _distinct_axes(p, cos_t)
    # distinct (axis, sign) pairs in order of first appearance: merged normals are one
    _, first = np.unique(which * 2 + (sign < 0), return_index=True)
    first.sort()
    R = np.eye(3)
    on_circle = np.zeros(len(axes), dtype=bool)
    best, pole, given = 2, None, False
    cands = np.asarray(poles, dtype=np.float64).reshape(-1, 3)
    if len(axes) >= 3 and len(cands):
        counts = (np.abs(axes @ cands.T) <= sin_t).sum(axis=0)
        k = int(np.argmax(counts))
        if counts[k] > best:
            best, pole, given = int(counts[k]), cands[k], True
            on_circle = np.abs(axes @ pole) <= sin_t
    if 3 <= len(axes) <= max_circle_search:
        cross = np.cross(axes[:, None, :], axes[None, :, :])
        norms = np.linalg.norm(cross, axis=2)
        ii, jj = np.nonzero(np.triu(norms > sin_t, 1))
        for i, j in zip(ii, jj):
            u = cross[i, j] / norms[i, j]
            on = np.abs(axes @ u) <= sin_t
            cnt = int(on.sum())
            if cnt > best:
                best, on_circle, pole, given = cnt, on, u, False
    if best >= 3:
        u = pole
        if not given:
            # refine the pole as the best-fit plane of the axes on the circle
            _, _, vt = np.linalg.svd(axes[on_circle])
            u = vt[2] if vt[2] @ pole >= 0 else -vt[2]
            on_circle = np.abs(axes @ u) <= sin_t
        e1 = _unit(axes[on_circle][0] - (axes[on_circle][0] @ u) * u)
        R = np.array([e1, np.cross(u, e1), u])
    local_axes = axes @ R.T
    local_axes[on_circle, 2] = 0.0
    local = sign[first, None] * local_axes[which[first]]
    return R, local


def _memo_key(normals):
    """Key of an array of normals for an analysis' memo: equal doubles, equal key."""
    n = np.ascontiguousarray(normals, dtype=np.float64)
    return n.shape, n.tobytes()


def surface_map(normals, draft=0.0, tol=DEFAULT_TOL, negative=False, memo=None, poles=()):
    """VM (or -VM) of a surface's normals with a draft (rad) as a core.VisibilityMap in
    global coordinates.  At zero draft the normals are canonicalised first (see
    :func:`canonical_normals`); a positive draft map {d : d.p >= sin(draft)} moves
    continuously with the normals, so there they are used as given.  ``memo``: a dict
    shared by the calls of one analysis (the answers are those without it): equal
    normals (a pattern of equal holes or pockets) are mapped once, and VM and -VM of
    the same normals share their canonical frame.  ``poles``: candidate circle poles
    for :func:`canonical_normals`."""
    if draft > 0.0:
        if memo is None:
            return core.visibility_map(normals, draft_angle=draft, negative=negative)
        key = ("map", _memo_key(normals), draft, negative)
        if key not in memo:
            memo[key] = core.visibility_map(normals, draft_angle=draft, negative=negative)
        return memo[key]
    if memo is None:
        R, local = canonical_normals(normals, tol, poles=poles)
    else:
        key = ("canonical", _memo_key(normals), tol, _memo_key(np.reshape(poles, (-1, 3))))
        if key not in memo:
            memo[key] = canonical_normals(normals, tol, poles=poles)
        R, local = memo[key]
        key = ("map", key, negative)
        if key in memo:
            return memo[key]
    vm = core.visibility_map(local, draft_angle=draft, negative=negative)
    vm = core.VisibilityMap(vm.kind, vm.vertices @ R, vm.closed)
    if memo is not None:
        memo[key] = vm
    return vm


def _is_single_normal(normals, tol):
    n = np.asarray(normals)
    return bool(np.all(n @ n[0] >= math.cos(tol)))


# --------------------------------------------------------------- results
@dataclass
class Surface:
    """A concave-connected surface: its faces (indices), weight, whether a concave
    edge joins two of its faces, all its normals, the largest shrink of its sampled
    faces, and its parts: (normals, shrink) — the exact faces' normals together
    (shrink 0), each sampled face apart."""
    faces: list
    weight: float
    has_concave: bool
    normals: np.ndarray
    shrink: float
    parts: list = field(default_factory=list)
    poles: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))


@dataclass
class Direction:
    """One direction of a result: unit ``direction``, ``margin`` (rad, how far it may
    move and keep its surfaces covered), ``surfaces`` (indices) and ``faces`` (indices)."""
    direction: np.ndarray
    margin: float
    surfaces: list
    faces: list
    weight: float = 0.0


@dataclass
class PartingResult:
    """Result of :func:`mould_parting` or :func:`nc_setups`.

    Mould: ``direction``/``margin`` the parting direction; ``side[s]`` for each surface:
    +1 core side (demoulded along +d), -1 cavity side (-d), 0 either (parallel to d),
    None if not covered; ``undercuts`` (surface indices: the uncovered ones),
    ``insufficient_draft`` (surfaces with an insufficient or zero draft face),
    ``face_angle``/``face_role`` per face (see :func:`face_draft`),
    ``insufficient_draft_faces`` (zero draft included) and ``zero_draft_faces`` (face
    indices), ``side_cores`` (greedy
    cover of the undercuts, list of :class:`Direction`), ``unresolved`` (surfaces no
    single direction demoulds).  NC: ``setups`` (first the main one), ``unresolved``
    (pocket surfaces no 3-axis direction reaches), ``considered`` (the surfaces taken
    into account).  ``covered``: surfaces covered by ``direction``; ``count``/``total``
    their weight and the weight of all considered surfaces."""
    mode: str
    surfaces: list
    direction: np.ndarray = None
    margin: float = 0.0
    covered: list = field(default_factory=list)
    count: float = 0.0
    total: float = 0.0
    considered: list = field(default_factory=list)
    side: list = field(default_factory=list)
    undercuts: list = field(default_factory=list)
    insufficient_draft: list = field(default_factory=list)
    side_cores: list = field(default_factory=list)
    setups: list = field(default_factory=list)
    unresolved: list = field(default_factory=list)
    face_angle: list = field(default_factory=list)
    face_role: list = field(default_factory=list)
    insufficient_draft_faces: list = field(default_factory=list)
    zero_draft_faces: list = field(default_factory=list)
    ray_blocked: list = field(default_factory=list)
    shadowed_faces: list = field(default_factory=list)

    def faces_of(self, surfaces):
        return sorted(f for s in surfaces for f in self.surfaces[s].faces)


def build_surfaces(faces, adjacency, weighting="count", tol=DEFAULT_TOL):
    """Concave-connected :class:`Surface` list from FaceGauss objects and adjacency."""
    if weighting not in ("count", "area"):
        raise ValueError(f"weighting must be 'count' or 'area', got {weighting!r}")
    groups, has_concave = concave_surfaces(len(faces), adjacency)
    exact = [None if f.shrink > tol else f.normals for f in faces]
    snapped = _snap_across_faces(exact, tol)
    poles = part_poles(snapped, tol)
    out = []
    for g, hc in zip(groups, has_concave):
        normals = np.concatenate([faces[f].normals if snapped[f] is None else snapped[f]
                                  for f in g])
        weight = 1.0 if weighting == "count" else float(sum(faces[f].area for f in g))
        # a shrink within tol is below what the answer promises anyway: treated as exact
        exact_normals = [snapped[f] for f in g if snapped[f] is not None]
        parts = [(np.concatenate(exact_normals), 0.0)] if exact_normals else []
        # the answer holds up to tol: a sampled face's map is shrunk by what its shrink
        # exceeds tol
        parts += [(faces[f].normals, faces[f].shrink - tol) for f in g if snapped[f] is None]
        shrink = max(p[1] for p in parts)
        out.append(Surface(g, weight, hc, normals, shrink, parts, poles))
    return out


def surface_vm(surf, draft, tol=DEFAULT_TOL, negative=False, memo=None):
    """VM(S) (or -VM(S)) of a :class:`Surface` with a draft: its exact part through
    :func:`surface_map`, intersected with its sampled faces' maps shrunk by their own
    shrink (so a sampled face does not shrink its exact neighbours' maps).  ``memo``
    (see :func:`surface_map`): surfaces with equal parts are mapped once."""
    if memo is not None:
        key = ("vm", tuple((_memo_key(n), shrink) for n, shrink in surf.parts), draft, tol,
               negative, _memo_key(surf.poles))
        if key not in memo:
            memo[key] = _surface_vm(surf, draft, tol, negative, memo)
        return memo[key]
    return _surface_vm(surf, draft, tol, negative, None)


def _surface_vm(surf, draft, tol, negative, memo):
    maps = [surface_map(n, draft + shrink, tol, negative, memo, surf.poles)
            for n, shrink in surf.parts]
    if len(maps) == 1 or any(m.kind == "null" for m in maps):
        return maps[0] if len(maps) == 1 else core.VisibilityMap("null", np.zeros((0, 3)))
    res = core.max_intersection(maps, progress=progress.current())
    if res.count < len(maps):
        return core.VisibilityMap("null", np.zeros((0, 3)))
    if len(res.regions) == 1:
        return core.VisibilityMap(res.kinds[0], res.regions[0], res.closed[0])
    # Only two antipodal points can be a disconnected intersection: keep their pair.
    if all(k == "point" for k in res.kinds):
        return core.VisibilityMap("point", np.vstack(res.regions))
    raise core.MfgError("internal", f"intersection of one surface's maps has "
                        f"{len(res.regions)} regions")


def _snap_across_faces(normals, tol):
    """The exact faces' normals (None for sampled faces) with every normal within tol of
    an earlier one (in face order) replaced by it, or by its exact negation when
    antipodal: so faces meant to share a normal (two pockets' floors, a wall and the
    opposite wall) give maps that meet exactly, not 1e-9 apart, and coverage between
    surfaces is decided within tol too (the library's own tolerance is 1e-10 rad)."""
    given = [n for n in normals if n is not None]
    if not given:
        return list(normals)
    allnormals = np.concatenate(given)
    axes, which, sign = _distinct_axes(allnormals, math.cos(tol))
    snapped = sign[:, None] * axes[which]
    out, at = [], 0
    for n in normals:
        if n is None:
            out.append(None)
            continue
        out.append(snapped[at:at + len(n)])
        at += len(n)
    return out


def part_poles(normals, tol):
    """Candidate circle poles of a part for :func:`canonical_normals`: the distinct plane
    normals (faces with one normal; ``normals`` as snapped by :func:`_snap_across_faces`,
    None for sampled faces) and the fitted poles (:func:`fitted_pole`) of the other
    faces, each within tol of an earlier candidate (or of its negation) replaced by it:
    a B-spline wall standing on a plane gets that plane's normal as its pole, bit for bit."""
    cands = []
    for n in normals:
        if n is not None and len(n) and np.all(n @ n[0] >= math.cos(tol)):
            cands.append(n[0])
    for n in normals:
        if n is not None:
            u = fitted_pole(n, tol)
            if u is not None:
                cands.append(u)
    if not cands:
        return np.zeros((0, 3))
    c = np.asarray(cands)
    return _distinct_axes(c, math.cos(tol))[0]   # plane normals first: they are kept


# Draft maps are polygons inscribed in small circles (within 1e-4 rad, mfgeom.h), so
# their regions' margins differ by that much between a part and its rotated copy.
DRAFT_TIE = 2e-4
# A direction counts as in a map within this (sin of an angle): the library's own
# angular tolerance MFG_SPHERE_TOL is 1e-10 rad
CONTAINS_TOL = 1e-9
# Projected areas within this fraction of each other are a tie (then margins decide)
PREFER_TIE = 1e-6


def projected_area(faces, d):
    """Area of the part's shadow on the plane normal to d, from its faces' normals and
    areas: a closed solid's shadow is half the integral of |n.d| over its boundary, and
    a face's integral is taken as its area times the mean |s.d| over its normal samples
    (exact for planes; for curved faces an estimate, which is all a tie-break needs)."""
    d = np.asarray(d, dtype=np.float64)
    return 0.5 * sum(f.area * float(np.mean(np.abs(f.normals @ d))) for f in faces)


def _reference_axes(surfaces):
    """Up to three independent normals of the part, in face order: rotate with the part,
    so ordering tied directions by them is rotation-invariant."""
    axes = []
    for surf in surfaces:
        for n in surf.normals[:1]:
            basis = np.array(axes + [n])
            if np.linalg.matrix_rank(basis, tol=0.1) == len(basis):
                axes.append(n)
        if len(axes) == 3:
            break
    return axes


def _best_region(maps, owner, weights, refs=(), tie_margin=1e-9, prefer=None):
    """The region covering the greatest weight of distinct surfaces (each surface once,
    though it may own two maps).  Returns (direction, margin, covered surface set)
    or None if no map has a direction.  ``prefer``: a function of a direction, larger
    is better (the projected area: the shortest draw), deciding between equally heavy
    regions before their margins do."""
    if not any(m.kind != "null" for m in maps):
        return None
    w_maps = np.array([weights[o] for o in owner], dtype=np.float64)
    res = core.max_intersection(maps, weights=w_maps, progress=progress.current())

    def true_weight(cover):
        return sum(weights[s] for s in {owner[i] for i in cover})

    cands = [(true_weight(c), float(m), i) for i, (c, m) in enumerate(zip(res.covers, res.margins))]
    best_w = max(c[0] for c in cands)
    regions = res
    if best_w < float(res.count) * (1 - 1e-12) - 1e-12:
        # The library's best double-counts surfaces whose VM and -VM touch; every region
        # of true weight >= best_w has library weight >= best_w and contains a locally
        # maximal one, so search those.
        regions = core.level_regions(maps, level=best_w * (1 - 1e-12), weights=w_maps,
                                     progress=progress.current())
        cands = [(true_weight(c), float(m), i)
                 for i, (c, m) in enumerate(zip(regions.covers, regions.margins))]
        best_w = max(c[0] for c in cands)
    # Heaviest first, then widest margin (equal within tie_margin), then the smallest
    # set of surfaces, then the direction most along the part's reference axes: not the
    # library's order, which depends on coordinates, so ties (symmetric parts) break the
    # same way when the part is rotated.
    top = max(c[0] for c in cands)
    # explicit candidates: (weight, margin, centre, cover map indices)
    heavy = [c for c in cands if c[0] >= top * (1 - 1e-12)]
    cands = [(c[0], c[1], _unit(np.asarray(regions.centres[c[2]], dtype=np.float64)),
              tuple(regions.covers[c[2]])) for c in heavy]
    # An arc region (margin 0: e.g. the great circle of directions along a slot) has
    # no rotation-invariant centre: the library's depends on coordinates.  Its points
    # nearest the part's reference axes (and, for an open arc, its ends) compete too.
    for c in heavy:
        i = c[2]
        if regions.kinds[i] != "edge":
            continue
        pts = np.asarray(regions.regions[i], dtype=np.float64).reshape(-1, 3)
        cover = tuple(regions.covers[i])
        extra = [] if regions.closed[i] else [pts[0], pts[-1]]
        if len(pts) >= 2:
            pole = np.cross(pts[0], pts[len(pts) // 2 if len(pts) > 2 else 1])
            if np.linalg.norm(pole) > 1e-9:
                pole = _unit(pole)
                for r in refs:
                    q = np.asarray(r) - (np.asarray(r) @ pole) * pole
                    if np.linalg.norm(q) > 1e-9:
                        extra += [_unit(q), -_unit(q)]
        for q in extra:
            q = _unit(q)
            if all(maps[k].contains(q, tol=CONTAINS_TOL)[0] for k in cover):
                cands.append((c[0], c[1], q, cover))
    # A point region of maps that are antipodal point pairs (a through bore, a slot
    # open at both ends) is reported at one of its two points, whichever the library's
    # coordinate order meets first; the other point is as good when every cover map
    # holds it, so both compete and the keys below decide (the same for a rotated part).
    for w, m, c, cover in list(cands):
        if m <= tie_margin and all(maps[k].contains(-c, tol=CONTAINS_TOL)[0] for k in cover):
            cands.append((w, m, -c, cover))
    if prefer is not None and len(cands) > 1:
        score = [prefer(c[2]) for c in cands]
        most = max(score)
        cands = [c for c, sc in zip(cands, score) if sc >= most * (1 - PREFER_TIE)]
    widest = max(c[1] for c in cands)
    cands = [c for c in cands if c[1] >= widest - tie_margin]

    def key(c):
        return (sorted({owner[k] for k in c[3]}),
                tuple(-round(float(c[2] @ r), 6) for r in refs))
    w, margin, centre, cover = min(cands, key=key)
    return centre, float(margin), {owner[k] for k in cover}


def _greedy_cover(surfaces, candidates, draft, tol, memo=None):
    """Greedy cover of ``candidates`` (surface indices) with positive maps: repeated
    maximum intersection on the surfaces not yet covered.  Returns (directions,
    unresolved) — unresolved: surfaces whose map is empty.  ``memo``: see
    :func:`surface_map`."""
    maps, owner = [], []
    unresolved = []
    for s in candidates:
        vm = surface_vm(surfaces[s], draft, tol, memo=memo)
        if vm.kind == "null":
            unresolved.append(s)
        else:
            maps.append(vm)
            owner.append(s)
    weights = {s: surfaces[s].weight for s in candidates}
    refs = _reference_axes(surfaces)
    tie_margin = DRAFT_TIE if draft > 0 or any(surfaces[s].shrink for s in candidates) else 1e-9
    out = []
    remaining = list(range(len(maps)))
    while remaining:
        sub_maps = [maps[i] for i in remaining]
        sub_owner = [owner[i] for i in remaining]
        d, margin, covered = _best_region(sub_maps, sub_owner, weights, refs, tie_margin)
        cov = sorted(covered)
        out.append(Direction(d, margin, cov, sorted(f for s in cov for f in surfaces[s].faces),
                             float(sum(weights[s] for s in cov))))
        remaining = [i for i in remaining if owner[i] not in covered]
    return out, sorted(unresolved)


def _check_common(draft, tol, name):
    if not (0.0 <= draft < math.pi / 2):
        raise ValueError(f"{name} must be in [0, pi/2) radians, got {draft}")
    if not (0.0 < tol < 1e-2):
        raise ValueError(f"tol must be in (0, 0.01) radians, got {tol}")


# --------------------------------------------------------------- mould mode
def _sides(surfaces, covered, d, tol):
    """+1 core (all normals n.d >= 0), -1 cavity (n.d <= 0), 0 both (parallel to d)."""
    side = [None] * len(surfaces)
    eps = 4 * math.sin(tol)
    for s in covered:
        dots = surfaces[s].normals @ d
        lo, hi = float(dots.min()), float(dots.max())
        side[s] = 0 if (lo > -eps and hi < eps) else (1 if lo >= -eps else -1)
    return side


def _core_score(surfaces, side):
    """(pocket weight, all weight) on the core side minus that on the cavity side, then
    the side of the first surface on one (so a tie still picks the same sign for a
    rotated part)."""
    pockets = sum(surfaces[s].weight * x for s, x in enumerate(side)
                  if x and surfaces[s].has_concave)
    every = sum(surfaces[s].weight * x for s, x in enumerate(side) if x)
    first = next((x for x in side if x), 0)
    return (pockets, every, first)


def _arc_extremes(normals, d, arcs=None):
    """(lowest, highest) of n.d over a face's normals and the great arcs between the
    pairs of them ``arcs`` names (FaceGauss.arcs: arcs of the face's true normals, e.g.
    a cylinder's circle given by its normals every <= 90 deg).  On an arc a-b the
    extremes of x.d lie at -+p/|p| (p: d projected on the plane of a and b) when that
    point lies on the arc: a cylinder's worst normal usually lies between two given
    ones (corpus part Pump_Nut, Face16: -63.4 deg, where its 5 normals gave -49.1)."""
    dots = normals @ d
    lo, hi = float(dots.min()), float(dots.max())
    if arcs is not None and len(arcs):
        a, b = normals[arcs[:, 0]], normals[arcs[:, 1]]
        m = np.cross(a, b)
        mm = np.einsum("ij,ij->i", m, m)
        good = mm > 1e-24
        a, b, m, mm = a[good], b[good], m[good], mm[good]
        p = d[None, :] - (m @ d)[:, None] * m / mm[:, None]
        plen = np.linalg.norm(p, axis=1)
        ok = plen > 1e-300
        x = np.zeros_like(p)
        x[ok] = p[ok] / plen[ok, None]
        for sgn in (-1.0, 1.0):
            y = sgn * x
            # y on the shorter arc a-b: a x y and y x b both along m
            on = (ok & (np.einsum("ij,ij->i", np.cross(a, y), m) >= 0)
                  & (np.einsum("ij,ij->i", np.cross(y, b), m) >= 0))
            if on.any():
                if sgn < 0:
                    lo = min(lo, float(-plen[on].max()))
                else:
                    hi = max(hi, float(plen[on].max()))
    return max(-1.0, min(1.0, lo)), max(-1.0, min(1.0, hi))


def _angle_range(face, shrink, d, sign=1.0):
    """(lowest, highest) angle (rad) of a face's normals (a FaceGauss: its normals and
    the arcs between them, :func:`_arc_extremes`) to the plane normal to d, on the side
    ``sign`` (+1: n.d, -1: -n.d), widened by ``shrink`` (the bound on how far its true
    normals may lie outside its samples' cone)."""
    lo, hi = _arc_extremes(face.normals, sign * np.asarray(d, dtype=np.float64), face.arcs)
    return (math.asin(lo) - shrink, math.asin(hi) + shrink)


def face_draft(faces, surfaces, covered, side, d, draft_angle, tol):
    """Per face: (worst angle, role) at the parting direction d.

    The worst angle (rad) is the lowest angle of the face's normals to the parting
    plane on the side that demoulds it (its surface's side; for an uncovered surface the
    better of +-d over the whole surface), so negative = undercut by that much, and
    CAD noise on a vertical wall shows as -0.0001 deg against a real undercut's -30.
    Roles: "zero_draft" (every normal within ``tol`` of the parting plane: a wall with no
    draft, demouldable but not drafted), "insufficient_draft" (covered, but the worst
    normal makes less than ``draft_angle`` - tol with the plane), "core" (+d),
    "cavity" (-d), "undercut" (its surface is not covered)."""
    angle = [0.0] * len(faces)
    role = [""] * len(faces)
    if d is None:
        for surf in surfaces:
            for f in surf.faces:
                angle[f], role[f] = -math.pi / 2, "undercut"
        return angle, role
    limit = tol * (1 + 1e-9) + 1e-15
    for s, surf in enumerate(surfaces):
        sgn = side[s]
        if sgn is None:
            # the side that demoulds the surface best
            dots = surf.normals @ d
            sgn = 1.0 if float(dots.min()) >= float((-dots).min()) else -1.0
        for f in surf.faces:
            g = faces[f]
            shrink = max(0.0, g.shrink - tol)   # what the tolerance does not absorb
            own = sgn if sgn != 0 else (1.0 if float(np.mean(g.normals @ d)) >= 0 else -1.0)
            lo, hi = _angle_range(g, shrink, d, own)
            angle[f] = lo
            if side[s] is None:
                role[f] = "undercut"
            elif max(abs(lo), abs(hi)) <= limit:
                role[f] = "zero_draft"
            elif draft_angle > 0 and lo < draft_angle - limit:
                role[f] = "insufficient_draft"
            else:
                role[f] = "core" if own > 0 else "cavity"
    return angle, role


def mould_parting(faces, adjacency, draft_angle=0.0, weighting="count", tol=DEFAULT_TOL):
    """Mould parting direction (seed 000 s.2.2): each concave-connected surface S gives
    VM(S) and -VM(S); the parting direction d is the representative direction of their
    maximum intersection (each surface counted once, weighted by ``weighting`` "count"
    or "area").  Covered surfaces are on the core side (+d) or the cavity side (-d); the
    others are undercuts, covered greedily by side-core directions (positive maps: a
    slider moving along e releases the faces with e.n >= 0).

    The direction is chosen without the draft, within the angular tolerance ``tol``
    (maps of normals snapped within tol, see :func:`canonical_normals`): a mould maker
    picks the draw, then drafts the walls.  ``draft_angle`` then classifies each face
    (:func:`face_draft`): faces of covered surfaces whose worst normal makes less than
    the draft with the parting plane are *insufficient draft*, walls within tol of the
    plane are *zero draft* (listed with them).  So a box at 1 degree keeps +-z with its
    four walls listed, instead of the body diagonal that "drafts" all six faces by 35
    degrees.  Equally heavy regions are decided by the shortest draw (the largest
    projected area, :func:`projected_area`), then the widest margin."""
    _check_common(draft_angle, tol, "draft_angle")
    surfaces = build_surfaces(faces, adjacency, weighting, tol)
    weights = {s: surf.weight for s, surf in enumerate(surfaces)}
    memo = {}   # equal surfaces (repeated features) mapped once
    maps, owner, free = [], [], []
    for s, surf in enumerate(surfaces):
        if surf.shrink == 0.0 and _is_single_normal(surf.normals, tol):
            free.append(s)  # VM u -VM is the whole sphere
            continue
        for negative in (False, True):
            maps.append(surface_vm(surf, 0.0, tol, negative, memo))
            owner.append(s)
    result = PartingResult("Mould", surfaces, considered=list(range(len(surfaces))),
                           total=float(sum(weights.values())))

    def shadow(d):
        return projected_area(faces, d)
    drafted = any(surf.shrink for surf in surfaces)
    best = (_best_region(maps, owner, weights, _reference_axes(surfaces),
                         DRAFT_TIE if drafted else 1e-9, prefer=shadow) if maps else None)
    if best is None:
        # no map has a direction: every surface is free (planes only); any direction
        # demoulds them, so take the free normal with the shortest draw (largest
        # projected area), then the heaviest surface, then face order
        if free:
            s = max(free, key=lambda k: (round(shadow(surfaces[k].normals[0]), 9),
                                         weights[k], -k))
            d, margin, covered = surfaces[s].normals[0].copy(), 0.0, set()
        else:
            d, margin, covered = None, 0.0, set()
    else:
        d, margin, covered = best
    covered = set(covered) | set(free) if d is not None else set()
    side = _sides(surfaces, covered, d, tol)
    if d is not None and _core_score(surfaces, side) < (0.0, 0.0, 0):
        # +d and -d are the same parting; take the sign that puts the pockets (and then
        # most weight) on the core side, so the answer does not depend on tie order
        d = -d
        side = [None if x is None else -x for x in side]
    result.direction, result.margin = d, margin
    result.covered = sorted(covered)
    result.count = float(sum(weights[s] for s in covered))
    result.side = side
    result.face_angle, result.face_role = face_draft(faces, surfaces, covered, side, d,
                                                     draft_angle, tol)
    drafty = ("zero_draft", "insufficient_draft")
    result.insufficient_draft_faces = [f for f, r in enumerate(result.face_role) if r in drafty]
    result.zero_draft_faces = [f for f, r in enumerate(result.face_role) if r == "zero_draft"]
    result.insufficient_draft = sorted({s for s, surf in enumerate(surfaces)
                                        for f in surf.faces if result.face_role[f] in drafty})
    result.undercuts = [s for s in range(len(surfaces)) if s not in covered]
    result.side_cores, result.unresolved = _greedy_cover(surfaces, result.undercuts, 0.0,
                                                         tol, memo)
    return result


# --------------------------------------------------------------- ray check
# A face the normals call demouldable is flagged when the rays of more than this
# fraction of its area are blocked on its side (a few samples at a fillet's edge may
# touch the tessellation's chords; a shadowed face is blocked over much of its area)
RAY_BLOCKED_FRACTION = 0.02


def apply_ray_check(result, faces, rays, min_fraction=RAY_BLOCKED_FRACTION):
    """Compare a Mould result with the ray check (:mod:`mfgeom.demould`): ``rays`` maps
    a face name ("Face7") to its FaceRays at ``result.direction``.  Sets, per face of
    ``faces``, ``result.ray_blocked`` (the blocked fraction on the face's own side: +d for
    the core side, -d for the cavity side, the lesser for zero draft, the lesser too for
    undercuts) and ``result.shadowed_faces``: faces the normals call demouldable (core,
    cavity, zero or insufficient draft) whose rays are blocked over more than
    ``min_fraction`` of their area, so another part of the solid stands in the way (an
    undercut the normals cannot see).  Returns the shadowed face indices."""
    blocked = [None] * len(faces)
    shadowed = []
    for f, g in enumerate(faces):
        r = rays.get(g.name)
        if r is None or r.samples == 0:
            continue
        role = result.face_role[f] if result.face_role else ""
        if role == "core":
            b = r.blocked_pos
        elif role == "cavity":
            b = r.blocked_neg
        else:
            b = min(r.blocked_pos, r.blocked_neg)
        blocked[f] = float(b)
        if role in ("core", "cavity", "zero_draft", "insufficient_draft") and b > min_fraction:
            shadowed.append(f)
    result.ray_blocked = blocked
    result.shadowed_faces = shadowed
    return shadowed


# --------------------------------------------------------------- draft analysis
DRAFT_CLASSES = ("positive", "negative", "insufficient", "straddle")


@dataclass
class DraftAnalysis:
    """Result of :func:`draft_analysis`: per face its class (:data:`DRAFT_CLASSES`) and
    its normals' lowest and highest angle (rad) to the plane normal to ``direction``
    (positive: the normal leans along +d)."""
    direction: np.ndarray
    draft_angle: float
    classes: list
    low: list
    high: list


def draft_analysis(faces, direction, draft_angle=0.0, tol=DEFAULT_TOL):
    """Draft analysis for a pull direction the user gives (as SolidWorks' or the DFM
    workbench's): a face is "positive" when every normal makes at least ``draft_angle``
    (- tol) with the parting plane on the +d side, "negative" the same on the -d side,
    "straddle" when its normals lie on both sides beyond tol (it needs a split line),
    else "insufficient" (some normal between -draft and +draft; a wall within tol of
    the plane is insufficient at any draft, 0 included)."""
    _check_common(draft_angle, tol, "draft_angle")
    d = np.asarray(direction, dtype=np.float64).reshape(3)
    length = float(np.linalg.norm(d))
    if not (math.isfinite(length) and length > 0):
        raise ValueError("the pull direction must be a finite, non-zero vector")
    d = d / length
    limit = tol * (1 + 1e-9) + 1e-15
    classes, low, high = [], [], []
    for g in faces:
        shrink = max(0.0, g.shrink - tol)   # what the tolerance does not absorb
        lo, hi = _angle_range(g, shrink, d)
        low.append(lo)
        high.append(hi)
        if max(abs(lo), abs(hi)) <= limit:
            classes.append("insufficient")
        elif lo >= draft_angle - limit:
            classes.append("positive")
        elif hi <= -draft_angle + limit:
            classes.append("negative")
        elif lo < -limit and hi > limit:
            classes.append("straddle")
        else:
            classes.append("insufficient")
    return DraftAnalysis(d, draft_angle, classes, low, high)


# --------------------------------------------------------------- NC 3-axis mode
def nc_setups(faces, adjacency, tilt=0.0, weighting="count", all_faces=False,
              tol=DEFAULT_TOL):
    """3-axis NC set-up plan (seed 000 s.2.2): the pocket surfaces (concave-connected
    surfaces with a concave edge; ``all_faces``: every surface) and their positive maps
    shrunk by ``tilt`` (rad, a tool-axis allowance: the tool may lean that far and still
    reach; growing maps is not supported by the library) plus their samples' shrink.
    The main set-up is their maximum intersection; the plan repeats it greedily on the
    surfaces not yet covered.  ``setups`` lists each :class:`Direction`."""
    _check_common(tilt, tol, "tilt")
    surfaces = build_surfaces(faces, adjacency, weighting, tol)
    considered = [s for s, surf in enumerate(surfaces) if all_faces or surf.has_concave]
    result = PartingResult("NC3Axis", surfaces, considered=considered,
                           total=float(sum(surfaces[s].weight for s in considered)))
    result.setups, result.unresolved = _greedy_cover(surfaces, considered, tilt, tol, {})
    if result.setups:
        main = result.setups[0]
        result.direction, result.margin = main.direction, main.margin
        result.covered, result.count = list(main.surfaces), main.weight
    return result


# --------------------------------------------------------------- references for tests
def fibonacci_sphere(n):
    """n nearly uniform unit directions (golden-angle spiral)."""
    k = np.arange(n) + 0.5
    z = 1 - 2 * k / n
    r = np.sqrt(np.maximum(0.0, 1 - z * z))
    phi = k * math.pi * (3 - math.sqrt(5))
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


# --------------------------------------------------------------- reports
REPORT_VERSION = 2   # 2: face roles zero_draft / insufficient_draft, worst angles
CSV_COLUMNS = ("face", "surface", "role", "group", "dx", "dy", "dz", "margin_deg",
               "area", "shrink_deg", "worst_angle_deg")
SUMMARY_FACES = 12   # face names a summary line lists before "... (+N more)"


def _dir_list(d):
    return None if d is None else [float(c) for c in np.asarray(d, dtype=np.float64)]


def _entry(entry, faces):
    return {"direction": _dir_list(entry.direction), "margin_deg": math.degrees(entry.margin),
            "weight": float(entry.weight), "surfaces": list(entry.surfaces),
            "faces": [faces[f].name or f"#{f}" for f in entry.faces]}


def report(result, faces, draft_angle=0.0, weighting="count", all_faces=False,
           tol=DEFAULT_TOL, source="", timings=None, warnings=()):
    """The result of :func:`mould_parting` or :func:`nc_setups` as a plain dict (JSON
    types only), for the Report view, the exports and the CLI.

    ``faces``: the FaceGauss list the result was computed from (names, areas,
    shrinks); ``draft_angle`` (rad; NC3Axis: the tilt), ``weighting``, ``all_faces``,
    ``tol`` (rad): the options used; ``source``: a label or file name; ``timings``:
    optional {stage: seconds}.  Keys: the options, ``direction`` (unit, global) and
    ``margin_deg``, ``covered_count``/``total_count`` (surfaces), ``covered_weight``/
    ``total_weight``, ``surfaces`` (each: faces, weight, has_concave, role), ``faces``
    (each: name, surface, role, group, area, shrink_deg), Mould: ``core_faces``,
    ``cavity_faces``, ``undercut_faces``, ``insufficient_draft_faces``, ``side_cores``;
    NC3Axis: ``setups`` (main first); both: ``unresolved_faces``, ``notes``.
    Face roles: Mould "core" (+d), "cavity" (-d), "zero_draft" (within the angular
    tolerance of the parting plane), "insufficient_draft" (less than the draft),
    "undercut", "unresolved", each with ``worst_angle_deg`` (see :func:`face_draft`);
    ``worst_faces`` lists the faces that are not core or cavity, worst angle first;
    NC3Axis "setup", "unresolved", "not_considered"."""
    r = result
    if isinstance(r, DraftAnalysis):
        rep = _draft_report(r, faces, tol, source, timings)
        rep["warnings"] = [str(w) for w in warnings]
        return rep

    def names(indices):
        return [faces[f].name or f"#{f}" for f in sorted(indices)]

    def faces_of(surfs):
        return names([f for s in surfs for f in r.surfaces[s].faces])

    covered = set(r.covered)
    role = [None] * len(r.surfaces)
    group = [""] * len(r.surfaces)
    if r.mode == "Mould":
        side_name = {1: "core", -1: "cavity", 0: "either"}
        for s in range(len(r.surfaces)):
            if s in covered:
                role[s], group[s] = side_name[r.side[s]], "main"
        for s in r.undercuts:
            role[s] = "undercut"
        for k, c in enumerate(r.side_cores, 1):
            for s in c.surfaces:
                group[s] = f"side_core_{k}"
    else:
        considered = set(r.considered)
        for s in range(len(r.surfaces)):
            role[s] = "setup" if s in considered else "not_considered"
        for k, c in enumerate(r.setups, 1):
            for s in c.surfaces:
                group[s] = f"setup_{k}"
    for s in r.unresolved:
        role[s] = "unresolved"
    face_rows = []
    for s, surf in enumerate(r.surfaces):
        for f in surf.faces:
            row = {"name": faces[f].name or f"#{f}", "index": f, "surface": s,
                   "role": role[s], "group": group[s], "area": float(faces[f].area),
                   "shrink_deg": math.degrees(faces[f].shrink)}
            if r.mode == "Mould" and r.face_role:
                row["role"] = "unresolved" if role[s] == "unresolved" else r.face_role[f]
                row["worst_angle_deg"] = math.degrees(r.face_angle[f])
                if r.ray_blocked and r.ray_blocked[f] is not None:
                    row["ray_blocked"] = r.ray_blocked[f]
                    row["shadowed"] = f in r.shadowed_faces
            face_rows.append(row)
    face_rows.sort(key=lambda row: row["index"])
    sampled = [f for f in faces if f.shrink > 0]
    notes = []
    if sampled:
        notes.append(f"normals of {len(sampled)} curved faces are sampled; their maps are "
                     f"shrunk by up to {math.degrees(max(f.shrink for f in sampled)):.3g} deg "
                     "so every direction holds on the true faces")
    notes.append(f"answers hold up to the angular tolerance {tol:.3g} rad")
    rep = {
        "report_version": REPORT_VERSION,
        "source": str(source),
        "mode": r.mode,
        "draft_angle_deg": math.degrees(draft_angle),
        "weighting": str(weighting).lower(),
        "all_faces": bool(all_faces),
        "angular_tolerance_rad": float(tol),
        "direction": _dir_list(r.direction),
        "margin_deg": math.degrees(r.margin),
        "covered_count": len(covered),
        "total_count": len(r.considered),
        "covered_weight": float(r.count),
        "total_weight": float(r.total),
        "face_count": len(faces),
        "surfaces": [{"index": s, "faces": names(surf.faces), "weight": float(surf.weight),
                      "has_concave": bool(surf.has_concave), "role": role[s],
                      "group": group[s]} for s, surf in enumerate(r.surfaces)],
        "faces": face_rows,
        "unresolved_faces": faces_of(r.unresolved),
        "max_shrink_deg": math.degrees(max((f.shrink for f in faces), default=0.0)),
        "sampled_faces": [f.name for f in sampled],
        "notes": notes,
    }
    if r.mode == "Mould":
        by_role = {}
        for row in face_rows:
            by_role.setdefault(row["role"], []).append(row["name"])
        rep.update({
            "core_faces": by_role.get("core", []),
            "cavity_faces": by_role.get("cavity", []),
            "undercut_faces": faces_of(r.undercuts),
            "insufficient_draft_faces": names(r.insufficient_draft_faces),
            "zero_draft_faces": names(r.zero_draft_faces),
            # the ray check (if run): faces the normals call demouldable, blocked by rays
            "ray_checked": bool(r.ray_blocked),
            "shadowed_faces": names(r.shadowed_faces),
            "side_cores": [_entry(c, faces) for c in r.side_cores],
            # uncovered faces, worst first: the angle tells a 30 degree undercut from
            # CAD noise of 0.001 degree
            "worst_faces": [{"name": row["name"], "role": row["role"],
                             "worst_angle_deg": row["worst_angle_deg"]}
                            for row in sorted((x for x in face_rows
                                               if x["role"] not in ("core", "cavity")),
                                              key=lambda x: x["worst_angle_deg"])],
        })
    else:
        rep["setups"] = [_entry(c, faces) for c in r.setups]
    if timings:
        rep["timings_s"] = {str(k): float(v) for k, v in timings.items()}
    # faces skipped or approximated by the Gauss maps (e.g. no normal at a singular
    # point): the part is analysed all the same
    rep["warnings"] = [str(w) for w in warnings]
    return rep


def _draft_report(a, faces, tol, source, timings):
    """:func:`report` of a :class:`DraftAnalysis`: per face its class ("role") and its
    normals' lowest and highest angle to the parting plane."""
    rows = [{"name": g.name or f"#{i}", "index": i, "surface": -1, "role": c, "group": "main",
             "area": float(g.area), "shrink_deg": math.degrees(g.shrink),
             "worst_angle_deg": math.degrees(lo), "highest_angle_deg": math.degrees(hi)}
            for i, (g, c, lo, hi) in enumerate(zip(faces, a.classes, a.low, a.high))]
    rep = {"report_version": REPORT_VERSION, "source": str(source), "mode": "Draft",
           "draft_angle_deg": math.degrees(a.draft_angle), "weighting": "count",
           "all_faces": True, "angular_tolerance_rad": float(tol),
           "direction": _dir_list(a.direction), "margin_deg": 0.0,
           "face_count": len(faces), "surfaces": [], "faces": rows, "unresolved_faces": [],
           "max_shrink_deg": math.degrees(max((f.shrink for f in faces), default=0.0)),
           "notes": [f"answers hold up to the angular tolerance {tol:.3g} rad"]}
    for c in DRAFT_CLASSES:
        rep[f"{c}_faces"] = [row["name"] for row in rows if row["role"] == c]
    rep["covered_count"] = len(rep["positive_faces"]) + len(rep["negative_faces"])
    rep["total_count"] = len(faces)
    rep["covered_weight"], rep["total_weight"] = float(rep["covered_count"]), float(len(faces))
    rep["worst_faces"] = [{"name": r["name"], "role": r["role"],
                           "worst_angle_deg": r["worst_angle_deg"]}
                          for r in rows if r["role"] in ("insufficient", "straddle")]
    if timings:
        rep["timings_s"] = {str(k): float(v) for k, v in timings.items()}
    return rep


def report_text(rep):
    """A short human-readable summary of a :func:`report` dict (Report view, .txt)."""
    if rep["mode"] == "Draft":
        d = rep["direction"]
        names = [f"{w['name']} ({w['role']}, {w['worst_angle_deg']:+.3g} deg)"
                 for w in rep["worst_faces"]]
        more = f" ... (+{len(names) - SUMMARY_FACES} more)" if len(names) > SUMMARY_FACES else ""
        lines = [f"Draft analysis of {rep['source'] or 'the part'} along "
                 f"({d[0]:+.6f}, {d[1]:+.6f}, {d[2]:+.6f}) at {rep['draft_angle_deg']:g} deg: "
                 f"{rep['face_count']} faces",
                 "  " + ", ".join(f"{len(rep[c + '_faces'])} {c}" for c in DRAFT_CLASSES)]
        if names:
            lines.append("  needing draft: " + " ".join(names[:SUMMARY_FACES]) + more)
        return "\n".join(lines) + "\n"
    def vec(d):
        return "none" if d is None else "(" + ", ".join(f"{c:+.6f}" for c in d) + ")"
    lines = [f"Parting analysis ({rep['mode']}) of {rep['source'] or 'the part'}: "
             f"{rep['face_count']} faces, {len(rep['surfaces'])} concave-connected surfaces",
             f"  options: {'tilt' if rep['mode'] == 'NC3Axis' else 'draft'} "
             f"{rep['draft_angle_deg']:g} deg, weighting {rep['weighting']}"
             + (", all faces" if rep["mode"] == "NC3Axis" and rep["all_faces"] else ""),
             f"  direction {vec(rep['direction'])}, margin {rep['margin_deg']:.4g} deg, "
             f"covers {rep['covered_count']} of {rep['total_count']} surfaces"]
    def listing(items, most=SUMMARY_FACES):
        items = list(items)
        more = f" ... (+{len(items) - most} more)" if len(items) > most else ""
        return " ".join(items[:most]) + more
    if rep["mode"] == "Mould":
        zero = set(rep.get("zero_draft_faces", []))
        lines.append(f"  faces: {len(rep['core_faces'])} core side (+d), "
                     f"{len(rep['cavity_faces'])} cavity side (-d), {len(zero)} zero draft, "
                     f"{len(rep['insufficient_draft_faces']) - len(zero)} below the draft, "
                     f"{len(rep['undercut_faces'])} undercut")
        if rep.get("ray_checked"):
            shadowed = rep.get("shadowed_faces", [])
            lines.append("  ray check: " + (f"{len(shadowed)} faces demouldable by their "
                                            f"normals are blocked by the part: "
                                            f"{listing(shadowed)}" if shadowed else
                                            "agrees with the normals on every face"))
        worst = rep.get("worst_faces", [])
        if worst:
            lines.append("  worst faces (angle of the worst normal to the parting plane, "
                         "negative = undercut): " + listing(
                             [f"{w['name']} {w['worst_angle_deg']:+.3g} deg ({w['role']})"
                              for w in worst]))
        for k, c in enumerate(rep["side_cores"], 1):
            lines.append(f"  side core {k}: {vec(c['direction'])}, margin "
                         f"{c['margin_deg']:.4g} deg: {listing(c['faces'])}")
    else:
        for k, c in enumerate(rep["setups"], 1):
            lines.append(f"  set-up {k}: {vec(c['direction'])}, margin {c['margin_deg']:.4g} "
                         f"deg: {listing(c['faces'])}")
    if rep["unresolved_faces"]:
        lines.append(f"  no single direction: {listing(rep['unresolved_faces'])}")
    for w in rep.get("warnings", [])[:SUMMARY_FACES]:
        lines.append(f"  warning: {w}")
    if len(rep.get("warnings", [])) > SUMMARY_FACES:
        lines.append(f"  ... (+{len(rep['warnings']) - SUMMARY_FACES} more warnings)")
    for note in rep["notes"]:
        lines.append(f"  note: {note}")
    if rep.get("timings_s"):
        lines.append("  time: " + ", ".join(f"{k} {1e3 * v:.1f} ms"
                                            for k, v in rep["timings_s"].items()))
    return "\n".join(lines) + "\n"


def write_report_json(path, rep):
    """Write a :func:`report` dict (or a list of them) as JSON (indented, UTF-8)."""
    import json
    with open(path, "w", encoding="utf-8") as out:
        json.dump(rep, out, indent=1)
        out.write("\n")


def write_report_csv(path, rep):
    """Write one row per face (columns :data:`CSV_COLUMNS`, plus ``source`` and ``mode``
    first) of a :func:`report` dict or a list of them: the face, its concave-connected
    surface, its role, its group (main, side_core_k, setup_k) and that group's direction
    and margin."""
    import csv
    import io
    from mfgeom.fileio import write_atomic
    reps = rep if isinstance(rep, list) else [rep]
    out = io.StringIO(newline="")
    w = csv.writer(out)
    w.writerow(("source", "mode") + CSV_COLUMNS)
    for r in reps:
        dirs = _group_directions(r)
        for row in r["faces"]:
            d, m = dirs.get(row["group"], (None, None))
            d = d if d is not None else ["", "", ""]
            w.writerow([r["source"], r["mode"], row["name"], row["surface"], row["role"],
                        row["group"], *[f"{c:.15g}" if c != "" else "" for c in d],
                        "" if m is None else f"{m:.9g}", f"{row['area']:.9g}",
                        f"{row['shrink_deg']:.6g}",
                        f"{row['worst_angle_deg']:.6g}" if "worst_angle_deg" in row
                        else ""])
    write_atomic(path, out.getvalue(), newline="")   # whole, then renamed into place


def _group_directions(rep):
    """{group: (direction, margin_deg)} of a report read back from JSON."""
    out = {"main": (rep["direction"], rep["margin_deg"])}
    kind = "side_core" if rep["mode"] == "Mould" else "setup"
    for k, c in enumerate(rep.get("side_cores" if kind == "side_core" else "setups", []), 1):
        out[f"{kind}_{k}"] = (c["direction"], c["margin_deg"])
    return out
