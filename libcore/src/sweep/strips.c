/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/strips.c - The strips that replace S, the contour swept from 0 to theta, and the
 * fins that keep the chain closed where a contour vertex's polylines change kind.
 *
 * The piece u -> v of the contour sweeps the quads (T_j v, T_j u, T_j+1 u, T_j+1 v) between
 * the polylines T of its ends (its first rung v -> u cancels F's edge u -> v, its last
 * R(theta) u -> R(theta) v cancels R(theta) B's).  Its front (where the winding number is
 * lower) faces away from the axis when the piece rises along the axis ((v - u) . k > 0):
 * there the tangent polyline, which runs outside every arc, displaces the strip towards
 * its front; on a falling piece the front faces the axis and the chords do.  A horizontal
 * piece sweeps a flat strip, either kind will do (the one of its neighbours, to save
 * fins).  A quad that is not planar (a piece skew to the axis) is split along the
 * diagonal that lies in front of its ruled surface, so the triangles are displaced
 * forwards too.  At a vertex where pieces of both kinds meet, the chain's boundary along
 * the vertex's two polylines is the closed polygon between them: the fins (triangles
 * between the tangent polyline and the chord polyline, flat, in the plane of the
 * vertex's circle) fill it. */
#include "sweep/envelope.h"

/* Emits the quad p0 p1 p2 p3 (in this order around it) as two triangles split along
 * the diagonal that lies in front (along the quad's normal). */
static int emit_quad(sw_env *e, int64_t p0, int64_t p1, int64_t p2, int64_t p3)
{
    const double *a = e->x + 3 * p0, *b = e->x + 3 * p1, *c = e->x + 3 * p2, *d = e->x + 3 * p3;
    double d02[3], d13[3], n[3], m[3];
    mfg_sub3(c, a, d02);
    mfg_sub3(d, b, d13);
    mfg_cross3(d02, d13, n);
    for (int k = 0; k < 3; k++)
        m[k] = (a[k] + c[k]) - (b[k] + d[k]);
    if (mfg_dot3(m, n) >= 0)
        return sw_emit(e, p0, p1, p2, -1) && sw_emit(e, p0, p2, p3, -1);
    return sw_emit(e, p0, p1, p3, -1) && sw_emit(e, p1, p2, p3, -1);
}

/* The fins of vertex v between its tangent and chord polylines, count times (sign:
 * +1 as listed - boundary = tangent polyline up, chord polyline down - or -1 reversed). */
static int emit_fins(sw_env *e, int64_t v, int count)
{
    int n = e->nsteps;
    for (int rep = 0; rep < (count < 0 ? -count : count); rep++) {
        for (int i = 0; i < n; i++) {
            int64_t r0 = sw_chord_point(e, v, i), mi = sw_apex_point(e, v, i);
            int64_t r1 = sw_chord_point(e, v, i + 1);
            if (r0 < 0 || mi < 0 || r1 < 0)
                return 0;
            int ok = count > 0 ? sw_emit(e, r0, mi, r1, -1) : sw_emit(e, r0, r1, mi, -1);
            if (!ok)
                return 0;
            if (i + 1 < n) {
                int64_t m1 = sw_apex_point(e, v, i + 1);
                if (m1 < 0)
                    return 0;
                ok = count > 0 ? sw_emit(e, mi, m1, r1, -1) : sw_emit(e, mi, r1, m1, -1);
                if (!ok)
                    return 0;
            }
        }
    }
    return 1;
}

int sw_build_strips(sw_env *e)
{
    hmap deg; /* contour vertex -> index into counts */
    int64_t *cnt = NULL, ncnt = 0, capcnt = 0;
    if (!hmap_init(&deg, 2 * e->nce + 1))
        goto nomem;
    /* per vertex: rising (tangent) and falling (chord) pieces at it, then the balance of
     * tangent pieces out minus in */
    for (int64_t i = 0; i < 2 * e->nce; i++) {
        hkey key = mkkey(e->ce[i], 0, 0, 0);
        if (hmap_get(&deg, &key) < 0) {
            if (!mfg_grow((void **)&cnt, &capcnt, 3 * (ncnt + 1), sizeof *cnt) ||
                !hmap_put(&deg, &key, ncnt))
                goto nomem;
            cnt[3 * ncnt] = cnt[3 * ncnt + 1] = cnt[3 * ncnt + 2] = 0;
            ncnt++;
        }
    }
    for (int64_t i = 0; i < e->nce; i++)
        if (e->ckind[i] >= 0)
            for (int s = 0; s < 2; s++) {
                hkey key = mkkey(e->ce[2 * i + s], 0, 0, 0);
                cnt[3 * hmap_get(&deg, &key) + e->ckind[i]]++;
            }
    for (int64_t i = 0; i < e->nce; i++) {
        if (e->ckind[i] >= 0)
            continue;
        hkey ku = mkkey(e->ce[2 * i], 0, 0, 0), kv = mkkey(e->ce[2 * i + 1], 0, 0, 0);
        const int64_t *cu = cnt + 3 * hmap_get(&deg, &ku), *cv = cnt + 3 * hmap_get(&deg, &kv);
        e->ckind[i] = cu[SW_TANGENT] == 0 && cv[SW_TANGENT] == 0 &&
                              cu[SW_CHORD] + cv[SW_CHORD] > 0
                          ? SW_CHORD
                          : SW_TANGENT;
    }
    for (int64_t i = 0; i < e->nce; i++) {
        if ((i & 255) == 0 && !mfg_prog_poll(e->prog, (double)i, (double)e->nce)) {
            e->st_code = MFG_ERR_CANCELLED;
            goto fail;
        }
        int64_t u = e->ce[2 * i], v = e->ce[2 * i + 1];
        int kind = e->ckind[i], len = sw_track_len(e, kind);
        if ((int64_t)e->nst + 2 * (int64_t)len > SW_MAX_SOUP) {
            e->st_code = mfg_fail(MFG_ERR_INVALID, "rotational sweep: the tolerance asks for "
                                  "more than %d strip triangles (%d steps along %lld contour "
                                  "pieces): choose a coarser tolerance", SW_MAX_SOUP,
                                  e->nsteps, (long long)e->nce);
            goto fail;
        }
        int64_t pu = u, pv = v;
        for (int j = 1; j < len; j++) {
            int64_t qu = sw_track_point(e, u, kind, j), qv = sw_track_point(e, v, kind, j);
            if (qu < 0 || qv < 0 || !emit_quad(e, pv, pu, qu, qv))
                goto nomem;
            pu = qu;
            pv = qv;
        }
        hkey ku = mkkey(u, 0, 0, 0), kv = mkkey(v, 0, 0, 0);
        int64_t iu = hmap_get(&deg, &ku), iv = hmap_get(&deg, &kv);
        if (kind == SW_TANGENT) {
            cnt[3 * iu + 2]++; /* out of u */
            cnt[3 * iv + 2]--; /* into v */
        }
    }
    /* fins: the boundary along a vertex's polylines is balance x (tangent up - chord up);
     * the fins as listed have boundary tangent up - chord down, so -balance of them */
    for (int64_t i = 0; i < 2 * e->nce; i++) {
        hkey key = mkkey(e->ce[i], 0, 0, 0);
        int64_t j = hmap_get(&deg, &key);
        if (cnt[3 * j + 2] != 0) {
            if (!emit_fins(e, e->ce[i], (int)-cnt[3 * j + 2]))
                goto nomem;
            cnt[3 * j + 2] = 0; /* once per vertex */
        }
    }
    hmap_free(&deg);
    free(cnt);
    return 1;
nomem:
    e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
fail:
    hmap_free(&deg);
    free(cnt);
    return 0;
}
