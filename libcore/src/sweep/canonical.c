/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/canonical.c - The input in a canonical order, so that the result does not depend
 * on the caller's triangle order, start corners or vertex numbering (issue 20: "the
 * triangle set does not depend on the input's triangle order or vertex numbering").
 *
 * Every later stage breaks ties by vertex and triangle numbers (the decomposition's cuts,
 * the walls' order, the output's numbering by first use), so the sweep runs on a copy
 * numbered canonically instead of making each tie-break order-free:
 *   - vertices sorted by their coordinates (x, then y, then z; exactly equal positions,
 *     which a closed 2-manifold may have only at pinched vertices, keep the caller's
 *     relative order: the one case where the numbering still matters);
 *   - each triangle's corners rotated (orientation kept) so that its smallest vertex
 *     comes first, and the triangles sorted by their three vertices.
 * A permutation of the caller's arrays then gives bit-identical internal input, hence a
 * bit-identical result (vertices numbered by first use in the canonical triangles). */
#include "sweep/envelope.h"

static int cmp_coord(const double *a, const double *b)
{
    for (int k = 0; k < 3; k++) {
        /* -0.0 and 0.0 are the same position: compare as numbers */
        if (a[k] < b[k])
            return -1;
        if (a[k] > b[k])
            return 1;
    }
    return 0;
}

/* Merge sort of vertex ids by coordinates (stable: equal positions keep their order);
 * qsort is not stable and has no context argument in C11. */
static void sort_vertices(const double *xyz, int64_t *ids, int64_t *tmp, int64_t n)
{
    for (int64_t width = 1; width < n; width *= 2) {
        for (int64_t lo = 0; lo < n; lo += 2 * width) {
            int64_t mid = lo + width < n ? lo + width : n;
            int64_t hi = lo + 2 * width < n ? lo + 2 * width : n;
            int64_t i = lo, j = mid, k = lo;
            while (i < mid && j < hi)
                tmp[k++] = cmp_coord(xyz + 3 * ids[j], xyz + 3 * ids[i]) < 0 ? ids[j++] : ids[i++];
            while (i < mid)
                tmp[k++] = ids[i++];
            while (j < hi)
                tmp[k++] = ids[j++];
        }
        memcpy(ids, tmp, (size_t)n * sizeof *ids);
    }
}

static int cmp_triangle(const void *pa, const void *pb)
{
    const int64_t *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

int sw_canonical_input(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt,
                       double **out_xyz, int64_t **out_tris)
{
    *out_xyz = NULL;
    *out_tris = NULL;
    int64_t *ids = malloc((size_t)(nv + 1) * sizeof *ids);
    int64_t *tmp = malloc((size_t)(nv + 1) * sizeof *tmp);
    double *cx = malloc((size_t)(3 * nv + 1) * sizeof *cx);
    int64_t *ct = malloc((size_t)(3 * nt + 1) * sizeof *ct);
    if (!ids || !tmp || !cx || !ct) {
        free(ids);
        free(tmp);
        free(cx);
        free(ct);
        return 0;
    }
    for (int64_t i = 0; i < nv; i++)
        ids[i] = i;
    sort_vertices(xyz, ids, tmp, nv);
    int64_t *rank = tmp; /* reused: rank[old id] = new id */
    for (int64_t i = 0; i < nv; i++) {
        rank[ids[i]] = i;
        memcpy(cx + 3 * i, xyz + 3 * ids[i], 3 * sizeof *cx);
    }
    for (int64_t t = 0; t < nt; t++) {
        int64_t a = rank[tris[3 * t]], b = rank[tris[3 * t + 1]], c = rank[tris[3 * t + 2]];
        /* rotate (not reflect): the smallest first keeps the orientation */
        if (b < a && b < c) {
            int64_t x = a;
            a = b;
            b = c;
            c = x;
        } else if (c < a && c < b) {
            int64_t x = c;
            c = b;
            b = a;
            a = x;
        }
        ct[3 * t] = a;
        ct[3 * t + 1] = b;
        ct[3 * t + 2] = c;
    }
    if (nt > 1)
        qsort(ct, (size_t)nt, 3 * sizeof *ct, cmp_triangle);
    free(ids);
    free(tmp);
    *out_xyz = cx;
    *out_tris = ct;
    return 1;
}
