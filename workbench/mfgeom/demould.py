# SPDX-License-Identifier: LGPL-2.1-or-later
"""Demouldability of each face by rays (issue 17), FreeCAD-free: sample points on each
face's triangles, ask :func:`mfgeom.core.ray_blocked` whether the rays along +d (the
core side) and -d (the cavity side) leave the part, and give each face a verdict.

This is the independent reference of the parting analysis: it sees the undercuts a
face's normals cannot (a face shadowed by another part of the solid).

Sampling: every triangle of a face gets at least its centroid; a triangle larger than
``area / samples_per_face`` of its face is cut into L x L similar sub-triangles (L =
round(sqrt(samples_per_face * triangle area / face area)), at most ``max_subdivision``),
each sampled at its centroid; a sample weighs its sub-triangle's area. Samples lie
strictly inside their triangle, lifted off it by ``lift`` times the mesh's size (its
largest |coordinate| or box diagonal) along the triangle's normal (outward for an
outward-oriented mesh, as OCCT's and the library's are): the mould's surface just
outside the part. The lift makes a wall parallel to d (zero draft) free along it even
when rounding (float32 mesh nodes, a rotated part) bends the wall's triangles a hair out
of one plane; with ``lift=0`` such walls are decided on the exact doubles. The triangle
is also passed as the sample's own triangle (ignored by its rays). A ray that passes
exactly through an edge or vertex only ("grazes", e.g. sliding up a wall parallel to d
to the wall's top edge) counts as free, as in the library; the grazing samples are
counted for the report.
"""

import numpy as np

from mfgeom import core
from mfgeom import progress

VERDICTS = ("core", "cavity", "both", "blocked")


class FaceRays:
    """The rays' verdict on one face: ``face`` (its id), ``samples`` (count), ``area`` (of
    its triangles), ``blocked_pos`` / ``blocked_neg`` (area-weighted fraction of the
    samples whose ray along +d / -d crosses the part), ``grazing_pos`` / ``grazing_neg``
    (samples whose ray only grazes an edge or vertex, counted free) and ``verdict``:
    'core' (free along +d only), 'cavity' (free along -d only), 'both' (free both ways: a
    wall parallel to d) or 'blocked' (neither: an undercut for this direction)."""

    __slots__ = ("face", "samples", "area", "blocked_pos", "blocked_neg", "grazing_pos",
                 "grazing_neg", "verdict")

    def __init__(self, face, samples, area, blocked_pos, blocked_neg, grazing_pos,
                 grazing_neg, verdict):
        self.face, self.samples, self.area = int(face), int(samples), float(area)
        self.blocked_pos, self.blocked_neg = float(blocked_pos), float(blocked_neg)
        self.grazing_pos, self.grazing_neg = int(grazing_pos), int(grazing_neg)
        self.verdict = verdict

    def as_dict(self):
        return {name: getattr(self, name) for name in self.__slots__}

    def __repr__(self):
        return (f"FaceRays(face={self.face}, {self.verdict}, samples={self.samples}, "
                f"blocked +d {self.blocked_pos:.3f}, -d {self.blocked_neg:.3f})")


def verdict_of(blocked_pos, blocked_neg, tolerance=0.0):
    """'core', 'cavity', 'both' or 'blocked' from the blocked fractions along +d / -d: a
    side is free when its fraction is at most ``tolerance``."""
    free_pos, free_neg = blocked_pos <= tolerance, blocked_neg <= tolerance
    if free_pos and free_neg:
        return "both"
    if free_pos:
        return "core"
    if free_neg:
        return "cavity"
    return "blocked"


def _subdivision_centroids(level):
    """Barycentric (u, v) of the centroids of the level^2 sub-triangles of the regular
    subdivision of a triangle into level x level similar ones."""
    uv = []
    for i in range(level):
        for j in range(level - i):
            uv.append(((i + 1 / 3) / level, (j + 1 / 3) / level))      # upright
            if i + j <= level - 2:
                uv.append(((i + 2 / 3) / level, (j + 2 / 3) / level))  # upside down
    return np.array(uv, dtype=np.float64)


LIFT = 1e-6


def mesh_size(vertices):
    """The length ``lift`` is a fraction of: the mesh's largest |coordinate| or its box
    diagonal, whichever is larger (0 for no vertices)."""
    v = np.asarray(vertices, dtype=np.float64).reshape(-1, 3)
    if not len(v):
        return 0.0
    return max(float(np.abs(v).max()), float(np.linalg.norm(v.max(0) - v.min(0))))


def sample_points(vertices, triangles, face_ids, samples_per_face=64, max_subdivision=8,
                  lift=LIFT):
    """(points (m, 3), own triangle (m,), weight (m,)) sampling every face as described in
    the module doc."""
    v = np.asarray(vertices, dtype=np.float64)
    t = np.asarray(triangles, dtype=np.int64)
    f = np.asarray(face_ids, dtype=np.int64)
    a, b, c = v[t[:, 0]], v[t[:, 1]], v[t[:, 2]]
    normal = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(normal, axis=1)
    unit = np.divide(normal, 2 * area[:, None], out=np.zeros_like(normal),
                     where=area[:, None] > 0)
    if len(v):
        unit *= lift * mesh_size(v)
    faces, inverse = np.unique(f, return_inverse=True)
    face_area = np.bincount(inverse, weights=area, minlength=len(faces))
    share = np.divide(area, face_area[inverse], out=np.zeros_like(area),
                      where=face_area[inverse] > 0)
    level = np.clip(np.rint(np.sqrt(samples_per_face * share)), 1, max_subdivision).astype(int)
    points, own, weight = [], [], []
    for lv in np.unique(level):
        sel = np.nonzero(level == lv)[0]
        uv = _subdivision_centroids(int(lv))
        ab, ac = (b - a)[sel], (c - a)[sel]
        p = (a[sel][:, None, :] + uv[:, 0][None, :, None] * ab[:, None, :]
             + uv[:, 1][None, :, None] * ac[:, None, :] + unit[sel][:, None, :])
        points.append(p.reshape(-1, 3))
        own.append(np.repeat(sel, len(uv)))
        weight.append(np.repeat(area[sel] / len(uv), len(uv)))
    if not points:
        return np.zeros((0, 3)), np.zeros(0, dtype=np.int64), np.zeros(0)
    return np.vstack(points), np.concatenate(own), np.concatenate(weight)


def face_demouldability(vertices, triangles, face_ids, direction, samples_per_face=64,
                        max_subdivision=8, tolerance=0.0, lift=LIFT):
    """Per face (in increasing face id) a :class:`FaceRays` for the triangle mesh
    (``vertices`` (n, 3), ``triangles`` (t, 3), counter-clockwise seen from outside: the samples are
    lifted outward, see the module doc) whose triangle k belongs to face
    ``face_ids[k]``, along ``direction``. The mesh should be one welded surface
    (neighbouring faces sharing their edges' nodes) so that no ray slips through a crack
    between faces. ``tolerance``: the blocked fraction a side may have and still count
    as free (0: any blocked sample blocks)."""
    t = np.asarray(triangles, dtype=np.int64).reshape(-1, 3)
    f = np.asarray(face_ids, dtype=np.int64).reshape(-1)
    if len(f) != len(t):
        raise ValueError(f"face_ids has {len(f)} entries for {len(t)} triangles")
    points, own, weight = sample_points(vertices, t, f, samples_per_face, max_subdivision,
                                        lift)
    bits = core.ray_blocked(vertices, t, points, own, direction, progress=progress.current())
    faces, inverse = np.unique(f[own], return_inverse=True)
    n = len(faces)
    total = np.bincount(inverse, weights=weight, minlength=n)

    def fraction(mask):
        w = np.bincount(inverse, weights=weight * mask, minlength=n)
        return np.divide(w, total, out=np.zeros(n), where=total > 0)

    pos = fraction((bits & core.RAY_BLOCKED_POS) != 0)
    neg = fraction((bits & core.RAY_BLOCKED_NEG) != 0)
    gpos = np.bincount(inverse, weights=(bits & core.RAY_GRAZES_POS) != 0, minlength=n)
    gneg = np.bincount(inverse, weights=(bits & core.RAY_GRAZES_NEG) != 0, minlength=n)
    count = np.bincount(inverse, minlength=n)
    return [FaceRays(faces[k], count[k], total[k], pos[k], neg[k], gpos[k], gneg[k],
                     verdict_of(pos[k], neg[k], tolerance)) for k in range(n)]
