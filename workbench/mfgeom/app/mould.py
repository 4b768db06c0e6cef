# SPDX-License-Identifier: LGPL-2.1-or-later
"""Mould tooling from a parting analysis (issue 21): the parting line, the parting and
shut-off surfaces, and the tooling split into core, cavity and side-core inserts, with
the checks every result must pass.  FreeCAD App layer (Part / OCCT booleans); the
demouldability of the blocks is checked with our own draft analysis
(:func:`mfgeom.parting.draft_analysis`) of their moulding faces.

The steps, and the choices made where a mould designer has several:

* **Sides.**  Each face of the part is classified along the parting direction d by its
  Gaussian map (:func:`mfgeom.app.gauss_map.face_gauss`): core (every normal n·d >= 0,
  within the angular tolerance), cavity (n·d <= 0), zero draft (both: a wall parallel to
  d) or straddling (normals on both sides).  A straddling face is split along its
  silhouette n(u, v)·d = 0 (:func:`silhouette_edges`: a plane section where the
  silhouette is planar — sphere, cylinder, cone or torus in the positions where it is —
  else a contour of n·d on a (u, v) grid refined by bisection on the exact normal and
  laid on the surface as a 2-D B-spline), then classified again.  The faces of a side
  core (an undercut the analysis gave a side-core direction) belong to its insert.
* **Zero-draft faces** join the side of their neighbours; where they touch both sides
  (the outer wall of a cup, the wall of a through-hole) they go to ``zero_draft_side``:
  "Cavity" (default) puts the parting line at their +d edge (as high along d as
  possible: the cup's rim), "Core" at their -d edge.
* **Parting line**: the edges between core and cavity faces (silhouettes included),
  chained into closed loops; a loop is *outer* unless its projection along d lies inside
  another loop's (then it bounds a through-hole: *inner*).  Shut-off loops of a side core:
  the edges between its faces and the rest.
* **Parting surface** of an outer loop: the loop lies in a plane normal to d: the block's
  section in that plane minus the loop's inside.  Otherwise *stepped*: that plane face at
  the loop's highest point along d (lowest for zero_draft_side "Core"), with the loop's
  projection as its hole, joined to the loop by a curtain of faces parallel to d (the loop
  extruded along d up to the plane).  For a part without undercuts an outer loop projects
  onto the outline of the part's shadow along d, so the curtain runs outside the part
  (on the side away from the zero-draft walls, which carry the line on their edge).
* **Shut-off surfaces** fill inner loops: a plane face where the loop is planar, else a
  filling surface (``Part.makeFilledFace``).
* **Blocks**: a box around the part, its axes d and the principal axes of the part's
  inertia in the plane normal to d (so the block turns with the part), grown by
  ``margin``; minus the part and the inserts, split by the parting and shut-off surfaces;
  each piece goes to the core or the cavity by the part faces it touches (a piece touching
  both is an error: the surfaces do not separate them).  A side-core insert is the region
  its faces sweep along the side-core direction to the block's boundary, in the block and
  outside the part.
"""

import contextlib
import math
import os
from dataclasses import dataclass, field

import numpy as np

import FreeCAD
import Part

from mfgeom import progress
from mfgeom.errors import InputError, MfgeomError
from mfgeom.parting import DEFAULT_TOL   # the analysis' angular tolerance (0.01 deg)

CORE, CAVITY, ZERO = 1, -1, 0
ZERO_DRAFT_SIDES = ("Cavity", "Core")
# Relative to the part's bounding-box diagonal: points closer than this to the part lie
# on it (OCCT's boolean results are within 1e-7 of their inputs)
ON_PART = 1e-7
# The volume checks' relative tolerance (the issue's 1e-6)
VOLUME_REL = 1e-6
# Silhouette contouring of a non-analytic face: grid cells per parameter direction,
# bisection steps on each crossing cell edge (2^-40 of a cell)
SILHOUETTE_GRID = 96
SILHOUETTE_BISECT = 40
# How far (relative to a face's size) the point that tells which part face a block face
# lies on keeps from the face's boundary (far above ON_PART: unambiguous)
INNER_CLEAR = 1e-3
# A piece of a face split along its silhouette whose normals cross the parting plane by
# at most this (rad) is on the side of its other normals (see parting_line)
SPLIT_SLACK = 1e-2
# A stepped parting surface's plane lies this far (relative to the part's size) beyond
# its loop's extreme point along d
STEP_ABOVE = 1e-3


class MouldError(MfgeomError):
    """The mould cannot be made (the analysis leaves undercuts unresolved, the parting
    line does not close, the surfaces do not separate core and cavity)."""


class MouldInputError(InputError):
    """A bad parameter or source given to a mould feature."""


def _unit(d):
    v = np.asarray([float(c) for c in d], dtype=np.float64)
    n = float(np.linalg.norm(v))
    if not (math.isfinite(n) and n > 0):
        raise MouldInputError("the parting direction must be a finite, non-zero vector")
    return v / n


def _vec(a):
    return FreeCAD.Vector(float(a[0]), float(a[1]), float(a[2]))


def _arr(v):
    return np.array([v.x, v.y, v.z], dtype=np.float64)


# ------------------------------------------------------------------ silhouettes
def _plane_section(face, point, normal):
    """Edges of ``face`` cut by the plane through ``point`` normal to ``normal``."""
    size = face.BoundBox.DiagonalLength * 4 + 1.0
    plane = Part.Plane(_vec(point), _vec(normal)).toShape(-size, size, -size, size)
    return face.section(plane).Edges


def _analytic_silhouette(face, d):
    """The silhouette of an analytic face whose silhouette lies in a known plane, as a
    list of edges (possibly empty: no silhouette inside the face); None where the surface
    is not one of those cases."""
    s = face.Surface
    if isinstance(s, Part.Sphere):
        return _plane_section(face, _arr(s.Center), d)
    if isinstance(s, (Part.Cylinder, Part.Cone, Part.Toroid)):
        axis = _arr(s.Axis)
        centre = _arr(s.Center if not isinstance(s, Part.Cone) else s.Apex)
        along = float(axis @ d)
        if isinstance(s, Part.Toroid) and abs(abs(along) - 1.0) < 1e-12:
            return _plane_section(face, centre, d)   # the two equator circles
        if isinstance(s, Part.Cylinder) or abs(along) < 1e-12:
            # n ⊥ d on the lines in the plane through the axis normal to d's part
            # normal to the axis (a cone: only when its axis is normal to d)
            across = d - along * axis
            return _plane_section(face, centre, across / np.linalg.norm(across))
    return None


def _nd_grid(face, d, us, vs):
    out = np.empty((len(us), len(vs)))
    for i, u in enumerate(us):
        for j, v in enumerate(vs):
            out[i, j] = _arr(face.normalAt(u, v)) @ d
    return out


def _bisect(face, d, a, b, fa):
    """A point between parameter points a and b where n·d changes sign (fa: its sign at
    a), by bisection on the face's exact normal."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    for _ in range(SILHOUETTE_BISECT):
        m = (a + b) / 2
        fm = _arr(face.normalAt(m[0], m[1])) @ d
        if (fm > 0) == (fa > 0):
            a = m
        else:
            b = m
    return (a + b) / 2


def _contour_silhouette(face, d):
    """Silhouette of a general face: marching squares of n·d on a (u, v) grid, each
    crossing refined by bisection on the exact normal, chained into polylines in (u, v)
    and laid on the surface as interpolating 2-D B-splines (edges with their pcurve on
    the face)."""
    u0, u1, v0, v1 = face.ParameterRange
    us = np.linspace(u0, u1, SILHOUETTE_GRID + 1)
    vs = np.linspace(v0, v1, SILHOUETTE_GRID + 1)
    f = _nd_grid(face, d, us, vs)
    pos = f > 0
    points = {}   # crossing on a grid edge -> (u, v)

    def crossing(key):
        if key not in points:
            (i, j), (k, l) = key
            points[key] = _bisect(face, d, (us[i], vs[j]), (us[k], vs[l]), f[i, j])
        return key

    segments = []
    for i in range(SILHOUETTE_GRID):
        progress.step(i / SILHOUETTE_GRID, "mould: silhouette of a face")
        for j in range(SILHOUETTE_GRID):
            corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)]
            cut = [tuple(sorted((corners[k], corners[(k + 1) % 4])))
                   for k in range(4) if pos[corners[k]] != pos[corners[(k + 1) % 4]]]
            if len(cut) == 2:
                segments.append((crossing(cut[0]), crossing(cut[1])))
            elif len(cut) == 4:   # saddle cell: pair by the centre's sign
                centre = _arr(face.normalAt((us[i] + us[i + 1]) / 2,
                                            (vs[j] + vs[j + 1]) / 2)) @ d
                k0 = 0 if (centre > 0) == pos[corners[0]] else 1
                segments.append((crossing(cut[k0]), crossing(cut[(k0 + 3) % 4])))
                segments.append((crossing(cut[k0 + 1]), crossing(cut[k0 + 2])))
    edges = []
    for chain in _chains(segments):
        uv = [points[k] for k in chain]
        if len(uv) < 2:
            continue
        curve = Part.Geom2d.BSplineCurve2d()
        curve.interpolate([FreeCAD.Base.Vector2d(float(p[0]), float(p[1])) for p in uv])
        edge = curve.toShape(face.Surface, curve.FirstParameter, curve.LastParameter)
        edges.append(edge)
    return edges


def _chains(segments):
    """Polylines (lists of nodes) from undirected segments (pairs of hashable nodes)."""
    nbr = {}
    for a, b in segments:
        nbr.setdefault(a, []).append(b)
        nbr.setdefault(b, []).append(a)
    seen, out = set(), []
    # open chains start at nodes of degree 1, then the closed ones
    for start in [n for n in nbr if len(nbr[n]) == 1] + list(nbr):
        if start in seen:
            continue
        chain, prev, cur = [start], None, start
        seen.add(start)
        while True:
            nxt = [n for n in nbr[cur] if n != prev and n not in seen]
            if not nxt:
                if len(chain) > 2 and start in nbr[cur] and prev is not None:
                    chain.append(start)   # closed
                break
            prev, cur = cur, nxt[0]
            chain.append(cur)
            seen.add(cur)
        out.append(chain)
    return out


def silhouette_edges(face, d):
    """Edges on ``face`` along its silhouette n·d = 0 (see the module docstring)."""
    edges = _analytic_silhouette(face, d)
    return _contour_silhouette(face, d) if edges is None else edges


# ------------------------------------------------------------------ sides
def _face_sides(shape, d, tol, deflection):
    """Per face of ``shape`` its class along d: "positive", "negative", "insufficient"
    (zero draft) or "straddle" (mfgeom.parting.draft_analysis at draft 0)."""
    return draft_classes([(f, f"Face{i + 1}") for i, f in enumerate(shape.Faces)], d, tol,
                         deflection)


def draft_classes(named_faces, d, tol, deflection, ranges=None):
    """mfgeom.parting.draft_analysis at draft 0 of (face, name) pairs along d: per face
    "positive", "negative", "insufficient" (zero draft) or "straddle".  ``ranges``: a
    list that gets each face's (lowest, highest) angle of its normals to the plane."""
    from mfgeom import parting
    from mfgeom.app import gauss_map
    if not named_faces:
        return []
    # sampled maps within half the tolerance of the true normals: a face bounded by its
    # silhouette (normals reaching the plane) must not straddle by its sampling's shrink
    deflection = min(deflection, tol / 2)
    faces = [gauss_map.face_gauss(f, deflection, name) for f, name in named_faces]
    a = parting.draft_analysis(faces, d, 0.0, tol)
    if ranges is not None:
        ranges.extend(zip(a.low, a.high))
    return a.classes


def _trimmed_angle_range(face, d, n=48):
    """(lowest, highest) angle (rad) to the plane normal to d of the normals at the
    points of an n x n (u, v) grid inside the trimmed face and along its edges."""
    u0, u1, v0, v1 = face.ParameterRange
    uv = [(u0 + (u1 - u0) * (i + 0.5) / n, v0 + (v1 - v0) * (j + 0.5) / n)
          for i in range(n) for j in range(n)]
    uv = [(u, v) for u, v in uv if face.isPartOfDomain(u, v)]
    for e in face.Edges:
        for p in _edge_points(e, n):
            uv.append(face.Surface.parameter(p))
    s = []
    for u, v in uv:
        try:
            s.append(float(_arr(face.normalAt(u, v)) @ d))
        except Exception:   # no normal at a singular point (a pole): not a sample
            continue
    if not s:
        return (-math.pi / 2, math.pi / 2)
    s = np.clip(s, -1.0, 1.0)
    return float(np.arcsin(s.min())), float(np.arcsin(s.max()))


def _edge_faces(shape):
    """{edge index: [face indices]} over the shape's edges (by shared topology)."""
    index = {}
    for k, e in enumerate(shape.Edges):
        index.setdefault(e.hashCode(), []).append((k, e))
    out = {}
    for fi, f in enumerate(shape.Faces):
        for e in f.Edges:
            for k, e2 in index.get(e.hashCode(), ()):
                if e2.isSame(e):
                    out.setdefault(k, []).append(fi)
    return out


def _same_face_index(shape, face):
    for i, f in enumerate(shape.Faces):
        if f.isSame(face):
            return i
    return None


@dataclass
class PartingLine:
    """Result of :func:`parting_line`.  ``shape``: the part (global) with its straddling
    faces split along their silhouettes; ``sides``: per face of ``shape`` CORE, CAVITY,
    or 2 + k for the k-th side core's faces; ``loops``: closed wires of the parting line,
    ``outer`` / ``planar`` per loop; ``shutoff_loops``: per side core its loops;
    ``split_faces``: names of the source faces split along their silhouettes;
    ``zero_draft``: names (in ``shape``) of the zero-draft faces and the side each took."""
    direction: np.ndarray
    shape: Part.Shape
    sides: list
    loops: list
    outer: list
    planar: list
    shutoff_loops: list = field(default_factory=list)
    split_faces: list = field(default_factory=list)
    zero_draft: dict = field(default_factory=dict)
    side_directions: list = field(default_factory=list)


def parting_line(shape, direction, side_cores=(), zero_draft_side="Cavity", tol=DEFAULT_TOL,
                 deflection=1e-3):
    """The parting line of the solid ``shape`` (global) along ``direction`` (core side
    +d).  ``side_cores``: (direction, [face names of ``shape``]) per side core of the
    analysis; their faces are left to the inserts.  Raises MouldError where the line does
    not close."""
    d = _unit(direction)
    if zero_draft_side not in ZERO_DRAFT_SIDES:
        raise MouldInputError(f"zero_draft_side must be one of {ZERO_DRAFT_SIDES}")
    solids = shape.Solids
    if len(solids) != 1 or not solids[0].isValid() or not solids[0].Volume > 0:
        raise MouldInputError("the part must be one valid solid (it has "
                              f"{len(solids)} solids" + (", not valid" if solids and not
                                                          solids[0].isValid() else "") + ")")
    shape = solids[0]
    insert_faces = []   # per side core the Face objects (they are not split)
    all_faces = shape.Faces
    for _s, names in side_cores:
        insert_faces.append([all_faces[int(n[4:]) - 1] for n in names])
    inserted = {f.hashCode() for fs in insert_faces for f in fs}
    classes = _face_sides(shape, d, tol, deflection)
    split_names, tools = [], []
    for i, (f, c) in enumerate(zip(all_faces, classes)):
        progress.step(i / max(len(classes), 1), "mould: silhouettes of the curved faces")
        if c == "straddle" and f.hashCode() not in inserted:
            edges = silhouette_edges(f, d)
            if not edges:
                raise MouldError(f"Face{i + 1} has normals on both sides of the parting "
                                 "plane but no silhouette was found on it")
            tools.extend(edges)
            split_names.append(f"Face{i + 1}")
    if tools:
        fused, _map = shape.generalFuse(tools)
        if len(fused.Solids) != 1:
            raise MouldError("splitting the faces along their silhouettes failed")
        shape = fused.Solids[0]
        ranges = []
        classes = draft_classes([(f, f"Face{i + 1}") for i, f in enumerate(shape.Faces)],
                                d, tol, deflection, ranges)
        # a piece of a split face reaches across its silhouette by the error of the
        # silhouette curve between its refined points (and the split's tolerance): up
        # to SPLIT_SLACK it takes the side of the rest of its normals
        split_faces = shape.Faces
        for i, (lo, hi) in enumerate(ranges):
            if classes[i] == "straddle":
                # the Gaussian map of a trimmed sphere or torus spans its whole (u, v)
                # box: the normals at points of the trimmed face decide
                lo, hi = _trimmed_angle_range(split_faces[i], d)
                if min(-lo, hi) <= SPLIT_SLACK:
                    classes[i] = "positive" if hi > -lo else "negative"
    faces = shape.Faces
    sides = [None] * len(faces)
    for k, fs in enumerate(insert_faces):
        for f in fs:
            i = _same_face_index(shape, f)
            if i is None:
                raise MouldError("a side core's face was lost splitting the silhouettes")
            sides[i] = 2 + k
    for i, c in enumerate(classes):
        if sides[i] is not None:
            continue
        if c == "straddle":
            raise MouldError(f"Face{i + 1} (of the split part) still straddles the "
                             "parting plane after splitting along its silhouette")
        sides[i] = {"positive": CORE, "negative": CAVITY}.get(c, ZERO)
    edge_faces = _edge_faces(shape)
    zero_draft = _assign_zero_draft(sides, edge_faces, zero_draft_side)
    edges = shape.Edges
    line, shutoff, bridges = [], [[] for _ in side_cores], []
    for k, fi in edge_faces.items():
        if len(fi) != 2:
            continue
        a, b = sides[fi[0]], sides[fi[1]]
        if {a, b} == {CORE, CAVITY}:
            line.append(edges[k])
        elif a != b and max(a, b) >= 2:
            for s in {a, b}:
                if s >= 2:
                    shutoff[s - 2].append(edges[k])
            if min(a, b) in (CORE, CAVITY):
                bridges.append(edges[k])
    line += _bridge_open_ends(line, bridges)
    loops = _loops(line, "parting line")
    size = shape.BoundBox.DiagonalLength
    planar = [_normal_plane_height(w, d, size) is not None for w in loops]
    outer = _outer_loops(loops, d)
    return PartingLine(d, shape, sides, loops, outer, planar,
                       [_loops(e, f"side core {k + 1}'s shut-off") for k, e in enumerate(shutoff)],
                       split_names, zero_draft, [_unit(s) for s, _n in side_cores])


def _bridge_open_ends(line, bridges):
    """Edges closing the parting line where a side core's faces interrupt it (an inclined
    hole through the rim): each open end of the core / cavity edges is joined to the
    nearest other open end along the edges between the insert's faces and the part's
    other faces (a shortest path by length).  Returns the edges to add."""
    import heapq

    def key(v):
        return v.hashCode()

    degree = {}
    for e in line:
        for v in (e.Vertexes[0], e.Vertexes[-1]):
            degree[key(v)] = degree.get(key(v), 0) + 1
    open_ends = {k for k, n in degree.items() if n % 2}
    if not open_ends or not bridges:
        return []
    graph = {}
    for i, e in enumerate(bridges):
        a, b = key(e.Vertexes[0]), key(e.Vertexes[-1])
        graph.setdefault(a, []).append((b, e.Length, i))
        graph.setdefault(b, []).append((a, e.Length, i))
    added, used = [], set()
    for start in sorted(open_ends):
        if start not in open_ends:
            continue
        dist, prev, heap = {start: 0.0}, {}, [(0.0, start)]
        end = None
        while heap:
            du, u = heapq.heappop(heap)
            if du > dist.get(u, math.inf):
                continue
            if u != start and u in open_ends:
                end = u
                break
            for v, w, i in graph.get(u, ()):
                if i not in used and du + w < dist.get(v, math.inf):
                    dist[v], prev[v] = du + w, (u, i)
                    heapq.heappush(heap, (du + w, v))
        if end is None:
            continue   # left open: _loops names where
        v = end
        while v != start:
            u, i = prev[v]
            used.add(i)
            added.append(bridges[i])
            v = u
        open_ends -= {start, end}
    return added


def _assign_zero_draft(sides, edge_faces, zero_draft_side):
    """Gives each connected set of zero-draft faces the side of its neighbours, or
    ``zero_draft_side`` where it touches both or neither.  Returns {face index: side}."""
    nbr = {}
    for fi in edge_faces.values():
        if len(fi) == 2:
            a, b = fi
            nbr.setdefault(a, set()).add(b)
            nbr.setdefault(b, set()).add(a)
    default = CAVITY if zero_draft_side == "Cavity" else CORE
    out = {}
    for start in range(len(sides)):
        if sides[start] != ZERO or start in out:
            continue
        group, stack, touch = {start}, [start], set()
        while stack:
            i = stack.pop()
            for j in nbr.get(i, ()):
                if sides[j] == ZERO and j not in group:
                    group.add(j)
                    stack.append(j)
                elif sides[j] in (CORE, CAVITY):
                    touch.add(sides[j])
        side = touch.pop() if len(touch) == 1 else default
        for i in group:
            out[i] = side
    for i, s in out.items():
        sides[i] = s
    return out


def _loops(edges, what):
    """Closed wires from ``edges``; MouldError naming ``what`` if a chain stays open."""
    if not edges:
        return []
    out = []
    for chain in Part.sortEdges(edges):
        wire = Part.Wire(chain)
        if not wire.isClosed():
            ends = [v.Point for v in wire.Vertexes]
            raise MouldError(f"the {what} does not close (a chain of {len(chain)} edges "
                             f"ends near {tuple(round(c, 4) for c in ends[0])})")
        out.append(wire)
    return out


def _edge_points(edge, n):
    """n points along ``edge``; its vertices for a degenerate edge (a sphere's pole),
    which OCCT cannot discretise."""
    if getattr(edge, "Degenerated", edge.Length == 0):
        return [v.Point for v in edge.Vertexes]
    try:
        return edge.discretize(n)
    except Part.OCCError:   # a seam or pole edge OCCT will not walk: its ends
        return [v.Point for v in edge.Vertexes]


def extent_along(wire, d, n=128):
    """(lowest, highest) of p . d along the wire's edges: the best of n samples per edge
    refined by golden-section search on the edge's parameter (points along the edges
    alone miss the extremes by their spacing, differently in every placement; OCCT's
    optimal box of a B-spline is only as tight as its tolerance)."""
    lo, hi = math.inf, -math.inf
    for e in wire.Edges:
        if getattr(e, "Degenerated", e.Length == 0):
            p = _arr(e.Vertexes[0].Point) @ d
            lo, hi = min(lo, p), max(hi, p)
            continue
        t0, t1 = e.FirstParameter, e.LastParameter
        ts = np.linspace(t0, t1, n + 1)
        h = np.array([_arr(e.valueAt(float(t))) @ d for t in ts])
        for sign in (1.0, -1.0):
            k = int(np.argmax(sign * h))
            a, b = ts[max(k - 1, 0)], ts[min(k + 1, n)]
            f = lambda t: sign * float(_arr(e.valueAt(t)) @ d)   # noqa: E731
            g = (math.sqrt(5) - 1) / 2
            x1, x2 = b - g * (b - a), a + g * (b - a)
            f1, f2 = f(x1), f(x2)
            for _ in range(60):
                if f1 < f2:
                    a, x1, f1 = x1, x2, f2
                    x2 = a + g * (b - a)
                    f2 = f(x2)
                else:
                    b, x2, f2 = x2, x1, f1
                    x1 = b - g * (b - a)
                    f1 = f(x1)
            best = sign * max(f1, f2, sign * h[k])
            lo, hi = (min(lo, best), hi) if sign < 0 else (lo, max(hi, best))
    return float(lo), float(hi)


def _normal_plane_height(wire, d, size):
    """The height along d of the plane normal to d holding ``wire``, or None."""
    lo, hi = extent_along(wire, d)
    if hi - lo <= ON_PART * max(size, 1.0):
        return (hi + lo) / 2
    return None


def _inertia(solid):
    """The solid's inertia tensor about its centre of mass (3 x 3); OCCT gives it with
    the sign of the solid's orientation (negative for a reversed solid)."""
    m = solid.MatrixOfInertia
    t = np.array([[m.A11, m.A12, m.A13], [m.A21, m.A22, m.A23], [m.A31, m.A32, m.A33]])
    return -t if np.trace(t) < 0 else t


def plane_basis(d):
    """(e1, e2): an orthonormal basis of the plane normal to the unit d, e1 the global
    axis least aligned with d projected into it, e2 = d x e1."""
    ref = np.eye(3)[int(np.argmin(np.abs(d)))]
    e1 = ref - (ref @ d) * d
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(d, e1)


def _frame(d, shape):
    """Block axes (e1, e2, d): e1, e2 the principal axes of the part's inertia in the
    plane normal to d (the projection of a global axis where they are not distinct)."""
    inertia = _inertia(shape)
    a, b = plane_basis(d)
    q = np.array([[a @ inertia @ a, a @ inertia @ b], [b @ inertia @ a, b @ inertia @ b]])
    w, vecs = np.linalg.eigh(q)
    if abs(w[1] - w[0]) > 1e-6 * max(abs(w).max(), 1e-300):
        # the sign does not change the box (its extents are taken along +-e1 alike)
        e1 = vecs[0, 0] * a + vecs[1, 0] * b
        e1 /= np.linalg.norm(e1)
        if e1 @ a < 0:
            e1 = -e1
    else:
        e1 = a
    return e1, np.cross(d, e1), d


def _projected_polygon(wire, e1, e2, n=64):
    """The wire as a polygon of n points per edge, projected onto the plane (e1, e2)."""
    p = np.array([[q.x, q.y, q.z] for e in wire.Edges for q in _edge_points(e, n)])
    return np.column_stack([p @ e1, p @ e2])


def _inside_polygon(q, poly):
    x, y = q
    inside = False
    n = len(poly)
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def _outer_loops(loops, d):
    e1, e2 = plane_basis(d)
    polys = [_projected_polygon(w, e1, e2) for w in loops]
    out = []
    for i, p in enumerate(polys):
        probe = p[0]
        out.append(not any(j != i and _inside_polygon(probe, q) for j, q in enumerate(polys)))
    return out


# ------------------------------------------------------------------ blocks and surfaces
@dataclass
class Block:
    """The mould block: a box with axes (e1, e2, d), as a solid, and its extent."""
    solid: Part.Shape
    axes: tuple
    lo: np.ndarray   # corner in the (e1, e2, d) frame
    hi: np.ndarray
    part_size: float = 0.0   # the diagonal of the part's own box in this frame


def mould_block(shape, d, margin):
    """The box around ``shape`` in the frame of :func:`_frame`, grown by ``margin``."""
    margin = float(margin)
    if not (math.isfinite(margin) and margin > 0):
        raise MouldInputError(f"the margin must be a positive length (got {margin})")
    axes = _frame(d, shape)
    rot = np.column_stack(axes)            # local -> global
    # the part's exact extents in the block's frame: turned into it, OCCT's optimal box
    # (from the geometry, not a triangulation or points along the edges)
    local = shape.copy()
    m = np.eye(4)
    m[:3, :3] = rot.T
    local.transformShape(FreeCAD.Matrix(*[float(x) for x in m.ravel()]))
    box = local.optimalBoundingBox(False)
    lo = np.array([box.XMin, box.YMin, box.ZMin]) - margin
    hi = np.array([box.XMax, box.YMax, box.ZMax]) + margin
    size = hi - lo
    box = Part.makeBox(float(size[0]), float(size[1]), float(size[2]))
    origin = rot @ lo
    m = FreeCAD.Matrix(*[float(x) for x in np.vstack([np.column_stack([rot, origin]),
                                                       [0.0, 0.0, 0.0, 1.0]]).ravel()])
    box.Placement = FreeCAD.Placement(m)
    part_size = float(np.linalg.norm(hi - lo - 2 * margin))
    return Block(box, axes, lo, hi, part_size)


def _plane_rect(block, height, grow=1.05):
    """The face normal to d at ``height`` covering the block's section (a little more)."""
    e1, e2, d = block.axes
    c = (block.lo + block.hi) / 2
    half = (block.hi - block.lo) / 2 * grow + 1e-9
    corners = []
    for s1, s2 in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
        corners.append(_vec((c[0] + s1 * half[0]) * e1 + (c[1] + s2 * half[1]) * e2 +
                            height * d))
    return Part.Face(Part.makePolygon(corners + [corners[0]]))


def parting_surfaces(line, block, zero_draft_side="Cavity"):
    """Per outer loop of ``line`` its parting surface (a shape of faces), per inner loop
    its shut-off surface: (parting, shutoff) lists."""
    d = line.direction
    size = block.part_size   # turns with the part (an axis-aligned box does not)
    parting, shutoff = [], []
    for wire, outer in zip(line.loops, line.outer):
        h = _normal_plane_height(wire, d, size)
        if not outer:
            shutoff.append(_fill(wire, h is not None))
            continue
        if h is not None:
            parting.append(_plane_rect(block, h).cut(Part.Face(wire)))
            continue
        h_lo, h_hi = extent_along(wire, d)
        up = zero_draft_side == "Cavity"
        # a step of STEP_ABOVE x size beyond the line's extreme point: a plane through
        # that point would touch the curtain there instead of crossing it
        step = STEP_ABOVE * size
        h0 = h_hi + step if up else h_lo - step
        reach = float(block.hi[2] - block.lo[2]) * 2 + size
        # edges parallel to d (a vertical step of the line) have no curtain: they
        # project to a point
        steps = [_parallel_to(e, d, ON_PART * size) for e in wire.Edges]
        slanted = [e for e, parallel in zip(wire.Edges, steps) if not parallel]
        curtain_full = Part.makeCompound(
            [e.extrude(_vec(d * (reach if up else -reach))) for e in slanted])
        rect = _plane_rect(block, h0)
        curtain = [_curtain_face(e, d, h0, size) for e in slanted]
        if all(c is not None for c in curtain):
            # every edge lies in a plane parallel to d: the outline is the polygon of the
            # loop's corners moved to h0 (exact; a section of the extrusions approximates),
            # corners that land on the one before (the ends of a vertical step) once
            corners = []
            for v in wire.OrderedVertexes:
                p = _arr(v.Point)
                q = p + (h0 - p @ d) * d
                if not corners or np.linalg.norm(q - corners[-1]) > ON_PART * size:
                    corners.append(q)
            if len(corners) > 1 and np.linalg.norm(corners[0] - corners[-1]) <= ON_PART * size:
                corners.pop()
            corners = [_vec(q) for q in corners]
            holes = [Part.makePolygon(corners + [corners[0]])]
        else:
            slab_lo, slab_hi = (h_lo - 1.0, h0) if up else (h0, h_hi + 1.0)
            curtain = curtain_full.common(_slab(block, slab_lo, slab_hi)).Faces
            holes = [Part.Wire(c) for c in Part.sortEdges(curtain_full.section(rect).Edges)]
        plane = rect
        for hole in holes:
            try:
                plane = plane.cut(Part.Face(hole))
            except Part.OCCError:
                raise MouldError(
                    "no stepped parting surface: the parting line's projection along d "
                    "folds back on itself (the line leaves the outline of the part's "
                    "shadow, e.g. down a notch and up again)") from None
        parting.append(Part.makeCompound(plane.Faces + curtain))
    return parting, shutoff


def _parallel_to(edge, d, eps):
    """Whether ``edge`` runs along d (all its points on one line parallel to d)."""
    p = np.array([[q.x, q.y, q.z] for q in _edge_points(edge, 16)])
    off = p - p[0]
    off -= np.outer(off @ d, d)
    return float(np.linalg.norm(off, axis=1).max()) <= eps


def _curtain_face(edge, d, h0, size):
    """The face between ``edge`` and its projection onto the plane at height h0 along d,
    as a plane face where the edge lies in a plane parallel to d (the top edge of a
    zero-draft wall: the curtain continues the wall, and OCCT's booleans find two plane
    faces of one plane where an extrusion would meet the wall tangentially); None
    otherwise (or where the edge folds back along the plane)."""
    a, b = _arr(edge.Vertexes[0].Point), _arr(edge.Vertexes[-1].Point)
    along = b - a
    along -= (along @ d) * d
    if np.linalg.norm(along) <= ON_PART * size:
        return None
    along /= np.linalg.norm(along)
    pts = np.array([[q.x, q.y, q.z] for q in edge.discretize(64)])
    off = (pts - a) @ np.cross(d, along)    # distance from the plane through a, d, along
    t = (pts - a) @ along
    if np.abs(off).max() > ON_PART * size or np.any(np.diff(t) < 0):
        return None
    a2, b2 = a + (h0 - a @ d) * d, b + (h0 - b @ d) * d
    rim = [edge]
    for p, q in ((b, b2), (b2, a2), (a2, a)):
        if np.linalg.norm(q - p) > ON_PART * size:
            rim.append(Part.makeLine(_vec(p), _vec(q)))
    try:
        return Part.Face(Part.Wire(Part.__sortEdges__(rim)))
    except Exception:   # OCCT: not a closed planar wire after all
        return None


def _slab(block, h_lo, h_hi):
    e1, e2, d = block.axes
    lo = np.array([block.lo[0] - 1.0, block.lo[1] - 1.0, h_lo])
    hi = np.array([block.hi[0] + 1.0, block.hi[1] + 1.0, h_hi])
    corners = [_vec(lo[0] * e1 + lo[1] * e2 + lo[2] * d), _vec(hi[0] * e1 + lo[1] * e2 + lo[2] * d),
               _vec(hi[0] * e1 + hi[1] * e2 + lo[2] * d), _vec(lo[0] * e1 + hi[1] * e2 + lo[2] * d)]
    base = Part.Face(Part.makePolygon(corners + [corners[0]]))
    return base.extrude(_vec(d * (hi[2] - lo[2])))


def _fill(wire, planar):
    """The shut-off surface of an inner loop: its plane face, else a filling surface."""
    try:
        return Part.Face(wire) if planar else Part.makeFilledFace(wire.Edges)
    except Part.OCCError as exc:
        raise MouldError(f"no shut-off surface for an inner loop of {len(wire.Edges)} edges "
                         f"({' '.join(str(exc).split())})") from None


# ------------------------------------------------------------------ tooling split
def _inner_point(face):
    """A point inside ``face``, on its surface and clear of its boundary by INNER_CLEAR x
    its size: a point on the boundary may lie on the part's edge between faces of two
    sides (a curtain's middle on its parting line).  The middle of its parameter range
    where that is inside and clear, else a point stepped inward from the middle of its
    longest edge (a ring around a hole has no middle).  (A tessellation per face cost
    0.17 s on a 90-face part.)"""
    size = max(face.BoundBox.DiagonalLength, 1e-300)
    step = INNER_CLEAR * size
    rim = Part.makeCompound(face.Edges)

    def clear(u, v):
        if not face.isPartOfDomain(u, v):
            return None
        p = face.valueAt(u, v)
        return p if rim.distToShape(Part.Vertex(p))[0] > step / 2 else None

    u0, u1, v0, v1 = face.ParameterRange
    p = clear((u0 + u1) / 2, (v0 + v1) / 2)
    if p is not None:
        return p
    for e in sorted(face.Edges, key=lambda e: -e.Length):
        if e.Length <= step:
            break
        t = (e.FirstParameter + e.LastParameter) / 2
        m, tangent = e.valueAt(t), e.tangentAt(t)
        u, v = face.Surface.parameter(m)
        inward = face.normalAt(u, v).cross(tangent)
        if inward.Length == 0:
            continue
        inward.normalize()
        for sign in (1.0, -1.0):
            u, v = face.Surface.parameter(m + inward * (sign * step))
            p = clear(u, v)
            if p is not None:
                return p
    return face.CenterOfMass


def _part_face_at(part, point, eps, boxes=None):
    """Index of the part's face ``point`` lies on (within ``eps``), or None.  ``boxes``:
    :func:`_face_boxes` of the part.  The candidates are the faces whose (grown) box
    holds the point; on each the point is projected onto the surface and must come back
    within eps, at parameters inside the trimmed face (a distance to each candidate
    took 1.5 ms a call, and a face bounding many holes is everybody's candidate)."""
    lo, hi, faces = _face_boxes(part, eps) if boxes is None else boxes
    p = _arr(point)
    hits = np.flatnonzero(np.all((lo <= p) & (p <= hi), axis=1))
    # smallest boxes first: a face bounding many holes is everybody's candidate and the
    # slowest to test (its domain check walks every hole)
    for i in hits[np.argsort(np.prod(hi[hits] - lo[hits], axis=1), kind="stable")]:
        if _on_face(faces[int(i)], point, eps):
            return int(i)
    return None


def _on_face(face, point, eps):
    s = face.Surface
    try:
        u, v = s.parameter(point)
    except Exception:   # OCCT found no projection
        return False
    if (s.value(u, v) - point).Length > eps:
        return False
    # a periodic surface gives (u, v) in its first period; the face's may be another
    us = [u] + ([u - s.UPeriod(), u + s.UPeriod()] if s.isUPeriodic() else [])
    vs = [v] + ([v - s.VPeriod(), v + s.VPeriod()] if s.isVPeriodic() else [])
    return any(face.isPartOfDomain(a, b) for a in us for b in vs)


def _face_boxes(part, eps):
    """(lo, hi, faces): arrays of the faces' bounding boxes, grown (OCCT may take a face's
    box from its triangulation, which lies inside a curved face by its chordal
    deflection), and the faces (``part.Faces`` builds a new list on every call)."""
    lo, hi = [], []
    faces = part.Faces
    for f in faces:
        b = f.BoundBox
        curved = not isinstance(f.Surface, Part.Plane)
        grow = 2 * eps + (0.05 * b.DiagonalLength if curved else 0.0)
        lo.append([b.XMin - grow, b.YMin - grow, b.ZMin - grow])
        hi.append([b.XMax + grow, b.YMax + grow, b.ZMax + grow])
    return np.array(lo), np.array(hi), faces


def moulding_faces(solid, part, eps):
    """[(face of ``solid`` lying on the part, index of the part's face)]."""
    out = []
    boxes = _face_boxes(part, eps)
    faces = solid.Faces
    for k, f in enumerate(faces):
        progress.step(k / len(faces), "mould: which part faces each block moulds")
        i = _part_face_at(part, _inner_point(f), eps, boxes)
        if i is not None:
            out.append((f, i))
    return out


def _fuse(solids):
    if not solids:
        return None
    if len(solids) == 1:
        return solids[0]
    return solids[0].fuse(solids[1:]).removeSplitter()


def side_core_inserts(line, block, space, tol=DEFAULT_TOL, deflection=1e-3):
    """Per side core the insert: the region its faces sweep along its direction to the
    block's boundary, within ``space`` (block minus part), kept where it touches them."""
    part = line.shape
    eps = ON_PART * part.BoundBox.DiagonalLength
    reach = float(np.linalg.norm(block.hi - block.lo)) * 2
    inserts = []
    for k, s in enumerate(line.side_directions):
        faces = [f for f, side in zip(part.Faces, line.sides) if side == 2 + k]
        # only faces facing along s sweep a volume (a wall parallel to s, such as a
        # hole's, gives OCCT a degenerate prism with a negative "volume")
        classes = draft_classes([(f, "") for f in faces], s, tol, deflection)
        prisms = []
        for f, c in zip(faces, classes):
            if c != "positive":
                continue
            g = f.extrude(_vec(s * reach))
            if g.Solids and g.isValid() and g.Volume > eps ** 3:
                prisms.extend(g.Solids)
        if not prisms:
            raise MouldError(f"side core {k + 1}: its faces sweep no volume along "
                             f"{tuple(round(float(c), 6) for c in s)}")
        region = _fuse(prisms).common(space)
        keep = [sol for sol in region.Solids
                if any(f.distToShape(sol)[0] <= eps for f in faces)]
        if not keep:
            raise MouldError(f"side core {k + 1}: its insert does not touch its faces")
        inserts.append(_fuse(keep))
    return inserts


@dataclass
class MouldResult:
    """Core, cavity and inserts (solids), the block and the surfaces that split it, and
    the checks (:func:`check_mould`)."""
    core: Part.Shape
    cavity: Part.Shape
    inserts: list
    block: Block
    parting: list
    shutoff: list
    line: PartingLine
    checks: dict = field(default_factory=dict)


def mould_blocks(line, margin, zero_draft_side="Cavity", tol=DEFAULT_TOL, deflection=1e-3):
    """Core, cavity and inserts of the part of ``line`` in a block grown by ``margin``,
    checked (:func:`check_mould`; MouldError if a check fails)."""
    part = line.shape
    block = mould_block(part, line.direction, margin)
    parting, shutoff = parting_surfaces(line, block, zero_draft_side)
    if not parting:
        raise MouldError("the parting line has no outer loop")
    progress.step(0.0, "mould: block minus part")
    space = block.solid.cut(part)
    progress.step(0.0, "mould: side-core inserts")
    inserts = side_core_inserts(line, block, space, tol, deflection)
    if inserts:
        space = space.cut(inserts)
    # the surfaces minus the part: OCCT's general fuse left a piece unbuilt where a
    # surface met the part's faces in their plane (a curtain continuing a zero-draft
    # wall); cut first, the surfaces only touch the part along the parting line
    tools = [Part.makeCompound(parting + shutoff).cut(part)]   # one boolean for all
    progress.step(0.0, "mould: splitting the block")
    pieces = space.generalFuse(tools)[0].Solids
    eps = ON_PART * part.BoundBox.DiagonalLength
    core, cavity = [], []
    for n, piece in enumerate(pieces):
        touched = {line.sides[i] for _f, i in moulding_faces(piece, part, eps)}
        touched &= {CORE, CAVITY}
        if touched == {CORE, CAVITY}:
            raise MouldError("the parting surfaces do not separate the core from the cavity "
                             f"(one piece of the block touches faces of both, of {len(pieces)})")
        if not touched:   # only the block: by its side of the parting plane
            c = _arr(piece.CenterOfMass) @ line.direction
            touched = {CORE if c > (block.lo[2] + block.hi[2]) / 2 else CAVITY}
        (core if CORE in touched else cavity).append(piece)
    result = MouldResult(_fuse(core), _fuse(cavity), inserts, block, parting, shutoff, line)
    if result.core is None or result.cavity is None:
        raise MouldError("the split left no " + ("core" if result.core is None else "cavity"))
    result.checks = check_mould(result, tol, deflection)
    failed = [k for k, v in result.checks.items() if isinstance(v, dict) and not v.get("ok")]
    if failed:
        raise MouldError("mould check failed: " + "; ".join(
            f"{k}: {result.checks[k]['why']}" for k in failed))
    return result


def check_mould(result, tol=DEFAULT_TOL, deflection=1e-3):
    """The issue's checks: core ∪ cavity ∪ inserts ∪ part = block (volumes to 1e-6
    relative), no two of them overlap in volume, each is a valid solid, and each block is
    demouldable along its own direction by our draft analysis of its moulding faces
    (the faces it shares with the part, with the part's outward normals): the core's
    all drafted along +d or zero draft, the cavity's along -d, an insert's along its
    side-core direction.  Returns {check: {"ok", "why", ...}}."""
    part = result.line.shape
    d = result.line.direction
    block_v = result.block.solid.Volume
    eps = ON_PART * part.BoundBox.DiagonalLength
    named = [("core", result.core, d), ("cavity", result.cavity, -d)]
    named += [(f"insert {k + 1}", s, result.line.side_directions[k])
              for k, s in enumerate(result.inserts)]
    checks = {}
    total = part.Volume + sum(s.Volume for _n, s, _d in named)
    checks["volume"] = {"ok": abs(total - block_v) <= VOLUME_REL * block_v,
                        "block": block_v, "sum": total,
                        "why": f"core + cavity + inserts + part = {total:.9g}, block "
                               f"{block_v:.9g}"}
    worst = 0.0
    # core, cavity and inserts pairwise (each is cut from the block minus the part, so
    # with the volume sum above none overlaps the part; a common with the part took as
    # long as the rest of the mould on a 2 000-face part)
    pairs = [(a, b) for i, a in enumerate(named) for b in named[i + 1:]]
    for (na, sa, _da), (nb, sb, _db) in pairs:
        worst = max(worst, sa.common(sb).Volume)
    checks["overlap"] = {"ok": worst <= VOLUME_REL * block_v, "largest": worst,
                         "why": f"two of them share {worst:.3g} mm^3"}
    bad = [n for n, s, _d in named if not (s.isValid() and s.Solids and s.Volume > 0)]
    checks["valid"] = {"ok": not bad, "why": f"not valid solids: {', '.join(bad)}"}
    for n, s, pull in named:
        g = [(f.reversed(), f"{n} face {k + 1}")
             for k, (f, _i) in enumerate(moulding_faces(s, part, eps))]
        classes = draft_classes(g, pull, tol, deflection)
        # a face the Gaussian maps call wrong is looked at where it is: the map of a
        # trimmed sphere or torus spans its whole (u, v) box; normals inside the trim may
        # cross the plane by a split's slack (the silhouette curve's error)
        wrong = [x[1] for x, c in zip(g, classes) if c not in ("positive", "insufficient")
                 and _trimmed_angle_range(x[0], pull)[0] < -SPLIT_SLACK]
        checks[f"demould {n}"] = {"ok": not wrong, "faces": len(g),
                                  "why": f"{len(wrong)} of {len(g)} moulding faces are not "
                                         f"drafted along its direction ({', '.join(wrong[:5])})"}
    return checks


# ------------------------------------------------------------------ STEP export
def write_step(shape, path):
    """``shape`` to the STEP file ``path`` through a temporary file renamed into place, so
    a failure (disk full, an OCCT error) leaves no truncated file."""
    tmp = f"{path}.tmp-{os.getpid()}.step"   # OCCT picks the format by the suffix
    try:
        shape.exportStep(tmp)
        if not os.path.isfile(tmp) or os.path.getsize(tmp) == 0:
            raise OSError(f"OCCT wrote nothing to {tmp}")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def export_step_files(core, cavity, inserts, directory, stem):
    """``<stem>_core.step``, ``_cavity.step``, ``_insert<k>.step`` in ``directory``
    (:func:`write_step` each); all or none: a failure removes the ones written.  Returns
    {"core": path, "cavity": path, "insert1": path, ...}."""
    parts = [("core", core), ("cavity", cavity)]
    parts += [(f"insert{k + 1}", s) for k, s in enumerate(inserts)]
    files = {}
    try:
        for what, shape in parts:
            target = os.path.join(directory, f"{stem}_{what}.step")
            write_step(shape, target)
            files[what] = target
    except BaseException:
        for f in files.values():
            if os.path.exists(f):
                os.remove(f)
        raise
    return files


# ------------------------------------------------------------------ from a bare shape
def thinnest_axis(shape):
    """The principal axis of the part's inertia with the largest moment (the normal of a
    plate, the axis across a knob's handle and ball): the parting direction where the
    analysis finds none.  Ties go to the one nearest global +z, then +y."""
    w, vecs = np.linalg.eigh(_inertia(shape.Solids[0]))
    top = vecs[:, [k for k in range(3) if w[k] >= w[2] * (1 - 1e-9)]]
    d = None
    for axis in (np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])):
        # the global axis projected into the (possibly tied) eigenspace
        p = top @ (top.T @ axis)
        if np.linalg.norm(p) > 1e-6:
            d = p / np.linalg.norm(p)
            break
    d = top[:, 0] if d is None else d
    return d if d[int(np.argmax(np.abs(d)))] > 0 else -d
@contextlib.contextmanager
def undercut_hint(unresolved):
    """A MouldError raised inside names the faces the analysis left unresolved (no
    single direction demoulds them).  They are not refused up front: a face with normals
    on both sides of the parting plane is unresolved to the analysis (it does not split
    faces) and demoulds once split along its silhouette; a true undercut shows up as a
    block that touches both sides or fails its demould check."""
    try:
        yield
    except MouldError as exc:
        if not unresolved:
            raise
        more = f" (+{len(unresolved) - 6} more)" if len(unresolved) > 6 else ""
        raise MouldError(f"{exc}; the analysis found no direction for "
                         f"{', '.join(unresolved[:6])}{more}: undercuts need a side core "
                         "or a change of the part") from None
def analyse_and_mould(shape, margin, zero_draft_side="Cavity", tol=None, deflection=1e-3,
                      draft_angle=0.0):
    """Mould parting analysis of the solid ``shape`` (global; mfgeom.parting.mould_parting
    on its Gaussian maps, as the PartingAnalysis feature without its ray check; where it
    finds no direction, :func:`thinnest_axis`), then :func:`parting_line` and
    :func:`mould_blocks`.  Returns (MouldResult, timings)."""
    import time
    from mfgeom import parting
    from mfgeom.app import gauss_map
    tol = parting.DEFAULT_TOL if tol is None else tol
    t0 = time.perf_counter()
    faces, adj, shape = gauss_map.part_gauss(shape, deflection)
    r = parting.mould_parting(faces, adj, draft_angle=draft_angle, tol=tol)
    if r.direction is None:
        # every surface straddles the parting plane of every direction (a part of curved
        # faces, such as the knob): the analysis does not split faces, the mould does
        direction, unresolved, side_cores = thinnest_axis(shape), [], []
    else:
        direction = r.direction
        unresolved = [faces[f].name for s in r.unresolved for f in r.surfaces[s].faces]
        side_cores = [(c.direction, [faces[f].name for f in c.faces]) for c in r.side_cores]
    t1 = time.perf_counter()
    with undercut_hint(unresolved):
        line = parting_line(shape, direction, side_cores, zero_draft_side, tol, deflection)
        t2 = time.perf_counter()
        result = mould_blocks(line, margin, zero_draft_side, tol, deflection)
    t3 = time.perf_counter()
    return result, {"analysis_s": t1 - t0, "parting_line_s": t2 - t1, "blocks_s": t3 - t2}
