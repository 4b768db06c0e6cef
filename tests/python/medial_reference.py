# SPDX-License-Identifier: LGPL-2.1-or-later
"""Independent reference for the 2-D medial axis of polygons with holes (no Voronoi code,
no code shared with libcore/src/axis2d/): medial points by bisection along inward
normals of boundary samples (and, at reflex vertices, along the fan of directions
between the two edge normals): the largest s with dist(q + s*n, boundary) == s.  Plus
soundness / completeness checks of an axis given as branches (points, radii).
Written for the 2-D medial axis work before the library's tracer (2026-11-29)."""
import math

import numpy as np

def segments(rings):
    A, B = [], []
    for r in rings:
        r = np.asarray(r, float)
        A.append(r); B.append(np.roll(r, -1, axis=0))
    return np.concatenate(A), np.concatenate(B)


def dist(P, A, B):
    """Distance of points P (m,2) to the union of segments AB (n,2)->(n,2), chunked."""
    P = np.asarray(P, float).reshape(-1, 2)
    out = np.empty(len(P))
    D = B - A; L2 = np.einsum('ij,ij->i', D, D)
    for s in range(0, len(P), 2048):
        Q = P[s:s + 2048, None, :] - A[None]
        t = np.clip(np.einsum('mij,ij->mi', Q, D) / L2, 0, 1)
        R = Q - t[..., None] * D[None]
        out[s:s + 2048] = np.sqrt(np.einsum('mij,mij->mi', R, R).min(axis=1))
    return out


def inside(rings, pts):
    pts = np.asarray(pts, float).reshape(-1, 2)
    res = np.zeros(len(pts), bool)
    A, B = segments(rings)
    for (ax, ay), (bx, by) in zip(A, B):
        c = (ay > pts[:, 1]) != (by > pts[:, 1])
        with np.errstate(divide='ignore', invalid='ignore'):
            xi = ax + (pts[:, 1] - ay) * (bx - ax) / (by - ay)
        res ^= c & (pts[:, 0] < xi)
    return res


def reference_points(rings, h):
    """Medial points (m,2) and radii (m,) from boundary samples spaced <= h."""
    A, B = segments(rings)
    D = B - A; L = np.linalg.norm(D, axis=1); U = D / L[:, None]
    N = np.c_[-U[:, 1], U[:, 0]]                      # left normal
    eps = 1e-7 * max(np.ptp(A[:, 0]), np.ptp(A[:, 1]))
    left_in = inside(rings, (A + B) / 2 + eps * N)
    N[~left_in] *= -1                                 # now inward
    Q, Nq = [], []
    for a, d, l, n in zip(A, U, L, N):
        k = max(2, int(math.ceil(l / h)))
        t = (np.arange(k) + 0.5) / k * l              # open edge: skip the vertices
        Q.append(a + np.outer(t, d)); Nq.append(np.tile(n, (k, 1)))
    # reflex vertices: fan of directions between the normals of the two edges
    off = 0
    for r in rings:
        m = len(r)
        for i in range(m):
            e_in, e_out = off + (i - 1) % m, off + i
            n0, n1 = N[e_in], N[e_out]
            turn = U[e_in, 0] * U[e_out, 1] - U[e_in, 1] * U[e_out, 0]
            # reflex when the boundary turns away from the interior: n0 . U_out < 0 ... use cross with normal side
            if np.dot(n0, U[e_out]) < -1e-12:          # the next edge leaves the interior side: reflex
                a0, a1 = math.atan2(n0[1], n0[0]), math.atan2(n1[1], n1[0])
                da = (a1 - a0 + math.pi) % (2 * math.pi) - math.pi
                k = max(2, int(math.ceil(abs(da) * 1.0 / (h / max(L.max(), 1e-300)) / 8)) + 1)
                k = min(max(k, 8), 256)
                ang = a0 + da * (np.arange(1, k) / k)
                Q.append(np.tile(A[e_out], (k - 1, 1))); Nq.append(np.c_[np.cos(ang), np.sin(ang)])
        off += m
    Q = np.concatenate(Q); Nq = np.concatenate(Nq)
    diam = math.hypot(np.ptp(A[:, 0]), np.ptp(A[:, 1]))
    lo, hi = np.zeros(len(Q)), np.full(len(Q), diam)
    for _ in range(55):
        s = (lo + hi) / 2
        ok = dist(Q + s[:, None] * Nq, A, B) >= s * (1 - 1e-12)
        lo = np.where(ok, s, lo); hi = np.where(ok, hi, s)
    return Q + lo[:, None] * Nq, lo


def polyline_nearest(P, branches):
    """For points P: distance to the nearest branch chord and the radius interpolated there."""
    S0 = np.concatenate([b[0][:-1] for b in branches]); S1 = np.concatenate([b[0][1:] for b in branches])
    R0 = np.concatenate([b[1][:-1] for b in branches]); R1 = np.concatenate([b[1][1:] for b in branches])
    D = S1 - S0; L2 = np.maximum(np.einsum('ij,ij->i', D, D), 1e-300)
    dbest = np.empty(len(P)); rbest = np.empty(len(P))
    for s in range(0, len(P), 1024):
        Q = P[s:s + 1024, None, :] - S0[None]
        t = np.clip(np.einsum('mij,ij->mi', Q, D) / L2, 0, 1)
        R = Q - t[..., None] * D[None]
        dd = np.einsum('mij,mij->mi', R, R)
        j = dd.argmin(axis=1)
        dbest[s:s + 1024] = np.sqrt(dd[np.arange(len(j)), j])
        tj = t[np.arange(len(j)), j]
        rbest[s:s + 1024] = R0[j] + tj * (R1[j] - R0[j])
    return dbest, rbest


def check_axis(rings, branches, tol, h=None):
    """Soundness + completeness of an axis (list of (points (k,2), radii (k,))) within tol."""
    A, B = segments(rings)
    P = np.concatenate([b[0] for b in branches]); R = np.concatenate([b[1] for b in branches])
    # also the chord midpoints (sampling error shows there)
    M = np.concatenate([(b[0][1:] + b[0][:-1]) / 2 for b in branches])
    MR = np.concatenate([(b[1][1:] + b[1][:-1]) / 2 for b in branches])
    d = dist(P, A, B)
    rad_err = np.abs(d - R).max()
    ins = inside(rings, P) | (d <= tol)
    # medial test: pushing a point by tol away from its nearest foot must not gain the full tol
    D = B - A; L2 = np.einsum('ij,ij->i', D, D)
    Qv = P[:, None, :] - A[None]; t = np.clip(np.einsum('mij,ij->mi', Qv, D) / L2, 0, 1)
    F = A[None] + t[..., None] * D[None]; dd = np.linalg.norm(P[:, None] - F, axis=2)
    j = dd.argmin(axis=1); foot = F[np.arange(len(P)), j]
    away = P - foot; nrm = np.linalg.norm(away, axis=1)
    medial = np.ones(len(P), bool)
    big = nrm > 10 * tol
    Pp = P[big] + tol * away[big] / nrm[big, None]
    medial[big] = dist(Pp, A, B) < d[big] + 0.99 * tol
    dm = dist(M, A, B)
    res = dict(points=len(P), max_radius_error=float(rad_err), max_mid_radius_error=float(np.abs(dm - MR).max()),
               outside=int((~ins).sum()), not_medial=int((~medial).sum()))
    Pref, Rref = reference_points(rings, h or tol * 20)
    keep = Rref >= tol          # at sharp convex tips the bisection is ill-conditioned: skip r < tol
    Pref, Rref = Pref[keep], Rref[keep]
    dn, rn = polyline_nearest(Pref, branches)
    res.update(ref_points=len(Pref), max_ref_to_axis=float(dn.max()), max_ref_radius_diff=float(np.abs(rn - Rref)[dn <= tol].max() if (dn <= tol).any() else np.nan),
               ref_missed=int((dn > tol).sum()))
    return res


