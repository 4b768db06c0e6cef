/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/surface.c - From the chain to the result: the boundary of {w >= 1} by the exact
 * arrangement (arrange/), its points rounded once, and the pieces of each plane merged
 * and triangulated again on their outlines (mesh/planar_merge.c).
 *
 * A plane's pieces: the arrangement's faces of one cluster lie in one plane exactly; the
 * pieces of one planar face of the input (F at t = 0, or B turned by theta) lie in one
 * plane up to the rounding of their cut points, and so do clusters that share a member
 * with such a face: all of them form one group (union-find over the input's planar
 * groups and the clusters). */
#include <stdio.h>

#include "sweep/envelope.h"
#include "mesh/mesh.h"
#include "mesh/planar_merge.h"

static int64_t uf_find(int64_t *uf, int64_t i)
{
    while (uf[i] != i) {
        uf[i] = uf[uf[i]];
        i = uf[i];
    }
    return i;
}

static void uf_join(int64_t *uf, int64_t a, int64_t b)
{
    a = uf_find(uf, a);
    b = uf_find(uf, b);
    if (a < b)
        uf[b] = a;
    else if (b < a)
        uf[a] = b;
}

/* ---- Micro-features ------------------------------------------------------------------ */

/* Where two sheets of the chain cross at a grazing angle (rounding of the soup's points
 * decides on which side a nearly coplanar pair lies), the exact boundary can have pieces
 * far below any tolerance: slivers a few ulps wide, bubbles round one point.  Rounded
 * to doubles they become zero-area or folded triangles and pinched vertices.  Points
 * closer than SW_WELD (unit scale; the tolerance is at least 2^-24) are welded into one,
 * the triangles that lose their area are dropped and pairs of opposite triangles on the
 * same three points cancel: the surface moves by at most SW_WELD, far inside the
 * tolerance's headroom. */
#define SW_WELD 0x1p-40

typedef struct tri_key {
    int64_t s[3];  /* sorted vertices */
    int64_t t;     /* the triangle */
    int sign;      /* +1: its order is an even permutation of s */
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb)
{
    const tri_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->s[k] != b->s[k])
            return a->s[k] < b->s[k] ? -1 : 1;
    return a->t < b->t ? -1 : a->t > b->t;
}

/* Welds x (nv points) and rewrites tri (*nt triangles, grp alongside); 0 when out of
 * memory. */
static int weld(double *x, int64_t nv, int64_t *tri, int64_t *grp, int64_t *nt)
{
    int64_t *uf = malloc((size_t)(nv + 1) * sizeof *uf);
    int64_t *next = malloc((size_t)(nv + 1) * sizeof *next);
    tri_key *keys = malloc((size_t)(*nt + 1) * sizeof *keys);
    hmap grid;
    if (!uf || !next || !keys || !hmap_init(&grid, nv + 1)) {
        free(uf);
        free(next);
        free(keys);
        return 0;
    }
    for (int64_t i = 0; i < nv; i++) {
        uf[i] = i;
        hkey key = mkkey((int64_t)floor(x[3 * i] / SW_WELD), (int64_t)floor(x[3 * i + 1] / SW_WELD),
                         (int64_t)floor(x[3 * i + 2] / SW_WELD), 0);
        next[i] = hmap_get(&grid, &key);
        if (!hmap_put(&grid, &key, i)) {
            free(uf);
            free(next);
            free(keys);
            hmap_free(&grid);
            return 0;
        }
    }
    for (int64_t i = 0; i < nv; i++)
        for (int d = 0; d < 27; d++) {
            hkey key = mkkey((int64_t)floor(x[3 * i] / SW_WELD) + d % 3 - 1,
                             (int64_t)floor(x[3 * i + 1] / SW_WELD) + d / 3 % 3 - 1,
                             (int64_t)floor(x[3 * i + 2] / SW_WELD) + d / 9 - 1, 0);
            for (int64_t j = hmap_get(&grid, &key); j >= 0; j = next[j])
                if (j > i && fabs(x[3 * j] - x[3 * i]) <= SW_WELD &&
                    fabs(x[3 * j + 1] - x[3 * i + 1]) <= SW_WELD &&
                    fabs(x[3 * j + 2] - x[3 * i + 2]) <= SW_WELD)
                    uf_join(uf, i, j);
        }
    hmap_free(&grid);
    int64_t n = 0;
    for (int64_t t = 0; t < *nt; t++) {
        int64_t a = uf_find(uf, tri[3 * t]), b = uf_find(uf, tri[3 * t + 1]),
                c = uf_find(uf, tri[3 * t + 2]);
        if (a == b || b == c || c == a)
            continue;
        tri_key *k = &keys[n];
        int64_t v[3] = {a, b, c};
        /* sort, counting swaps for the orientation */
        int sign = 1;
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 2 - i; j++)
                if (v[j] > v[j + 1]) {
                    int64_t tmp = v[j];
                    v[j] = v[j + 1];
                    v[j + 1] = tmp;
                    sign = -sign;
                }
        memcpy(k->s, v, sizeof v);
        k->t = t;
        k->sign = sign;
        tri[3 * t] = a;
        tri[3 * t + 1] = b;
        tri[3 * t + 2] = c;
        n++;
    }
    qsort(keys, (size_t)n, sizeof *keys, cmp_tri_key);
    int64_t m = 0;
    int64_t *out = malloc((size_t)(n + 1) * sizeof *out);
    int64_t *ogrp = malloc((size_t)(n + 1) * sizeof *ogrp);
    if (!out || !ogrp) {
        free(out);
        free(ogrp);
        free(uf);
        free(next);
        free(keys);
        return 0;
    }
    for (int64_t i = 0; i < n;) {
        int64_t j = i, net = 0;
        while (j < n && !memcmp(keys[j].s, keys[i].s, sizeof keys[i].s))
            net += keys[j++].sign;
        if (net != 0) {
            /* one triangle of the net orientation (the first such) */
            for (int64_t q = i; q < j; q++)
                if (keys[q].sign == (net > 0 ? 1 : -1)) {
                    keys[m++] = keys[q];
                    break;
                }
        }
        i = j;
    }
    /* back into tri / grp in the triangles' original order */
    for (int64_t i = 0; i < m; i++)
        out[i] = keys[i].t;
    qsort(out, (size_t)m, sizeof *out, mfg_cmp_i64);
    for (int64_t i = 0; i < m; i++) {
        int64_t t = out[i];
        memmove(tri + 3 * i, tri + 3 * t, 3 * sizeof *tri);
        ogrp[i] = grp[t];
    }
    memcpy(grp, ogrp, (size_t)m * sizeof *grp);
    *nt = m;
    free(out);
    free(ogrp);
    free(uf);
    free(next);
    free(keys);
    return 1;
}

int sw_surface(sw_env *e, double **ox, int64_t *nox, int64_t **ot, int64_t *not_)
{
    static const arr_stages stages = {
        {"sweep: intersections", "sweep: faces", "sweep: boundary"}, {0.3, 0.55, 0.8, 0.9}};
    arr_table T;
    arr_face *F = NULL;
    int64_t nf = 0, *tcl = NULL, ncl = 0;
#ifdef ARR_DEBUG
    fprintf(stderr, "soup: %lld triangles, %lld vertices (input %lld)\n", (long long)e->nst,
            (long long)e->nv, (long long)e->nin);
#endif
    mfg_status st = arr_union_boundary(e->x, e->nv, e->st, e->nst, e->prog, &stages, &T, &F,
                                       &nf, &tcl, &ncl);
    if (st != MFG_OK) {
        e->st_code = st;
        return 0;
    }
    int64_t G = e->ngroups;
    int64_t *uf = malloc((size_t)(G + ncl + 1) * sizeof *uf);
    int64_t *map = malloc((size_t)(T.npts + 1) * sizeof *map);
    double *x = malloc((size_t)(3 * 3 * nf + 3) * sizeof *x);
    int64_t *tri = malloc((size_t)(3 * nf + 3) * sizeof *tri);
    int64_t *grp = malloc((size_t)(nf + 1) * sizeof *grp);
    int ok = uf && map && x && tri && grp;
    if (ok) {
        for (int64_t i = 0; i < G + ncl; i++)
            uf[i] = i;
        for (int64_t t = 0; t < e->nst; t++)
            if (e->sgroup[t] >= 0 && tcl[t] >= 0)
                uf_join(uf, e->sgroup[t], G + tcl[t]);
        for (int64_t i = 0; i < T.npts; i++)
            map[i] = -1;
        int64_t nv = 0;
        arr_points P = arr_view(&T);
        for (int64_t f = 0; f < nf; f++) {
            for (int k = 0; k < 3; k++) {
                int64_t p = F[f].v[k];
                if (map[p] < 0) {
                    map[p] = nv;
                    arr_coords(&P, p, x + 3 * nv);
                    nv++;
                }
                tri[3 * f + k] = map[p];
            }
            grp[f] = uf_find(uf, G + F[f].cluster);
        }
        mfg_mesh_report rep;
        st = weld(x, nv, tri, grp, &nf) ? mfg_mesh_check_closed(x, nv, tri, nf, &rep)
                                         : MFG_ERR_NOMEM;
        if (st == MFG_OK) {
            int64_t ntri = nf;
            if (!mfg_merge_planar_groups(x, nv, tri, &ntri, grp, NULL))
                st = MFG_ERR_NOMEM;
            nf = ntri;
        } else if (st != MFG_ERR_NOMEM) {
            char why[256];
            snprintf(why, sizeof why, "%s", mfg_last_error());
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the boundary is not a closed "
                          "2-manifold (%s); please report this input", why);
#ifdef ARR_DEBUG
            if (getenv("MFG_SWEEP_NOCHECK"))
                st = MFG_OK;
#endif
        }
        if (st == MFG_OK) {
            *ox = x;
            *nox = nv;
            *ot = tri;
            *not_ = nf;
            x = NULL;
            tri = NULL;
        } else {
            e->st_code = st == MFG_ERR_NOMEM
                             ? mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory")
                             : st;
            ok = 0;
        }
    } else {
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    }
    free(uf);
    free(map);
    free(x);
    free(tri);
    free(grp);
    free(F);
    free(tcl);
    arr_table_free(&T);
    return ok;
}
