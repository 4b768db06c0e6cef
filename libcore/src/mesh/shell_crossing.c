/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* shell_crossing.c - the last test of the closed-solid check (issue 22): shells that cross
 * or nest wrongly.  A closed, consistently oriented 2-manifold mesh may still not bound a
 * solid: two overlapping boxes pass every edge test (volume 4 against a union of 3.75),
 * and a box inside a box facing the same way counts its inside twice.  The medial surface
 * then takes the inner faces for boundary without a word.
 *
 * Crossing, exactly: a bounding-volume tree over the triangles of non-zero area, traversed
 * against itself; two triangles that share no vertex index cross when an edge of one
 * passes through the other (its ends strictly on both sides of the plane, the piercing
 * point strictly inside: orient3d signs) or, coplanar, when their interiors overlap
 * (orient2d in the plane's dominant projection: edges crossing properly, or a vertex or
 * the centroid of one strictly inside the other).  Strict tests: shells that only touch
 * (a vertex on a face) are not reported.
 *
 * Nesting (shells that do not cross): each connected shell's signed volume and the winding
 * number of one of its vertices with respect to the other shells (solid angles; the point
 * is off every other shell, so the number is an integer up to rounding).  A shell facing
 * out must lie outside all others (winding 0), a cavity facing in inside exactly one
 * (winding 1).  Skipped beyond MAX_NEST_SHELLS shells (cost shells x triangles). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "common/vec3.h"

#define LEAF_TRIS 4
#define MAX_NEST_SHELLS 256

typedef struct tnode {
    double lo[3], hi[3];
    int64_t left, right; /* children, or -1 for a leaf */
    int64_t first, count; /* leaf: ids[first .. first + count) */
} tnode;

typedef struct tree {
    tnode *n;
    int64_t nn;
    int64_t *ids;
    const double *xyz;
    const int64_t *tris;
    double *cen; /* 3 per triangle id: the centroid */
    double *box; /* 6 per triangle id: lo, hi */
} tree;

static void tri_box(const tree *T, int64_t t, double lo[3], double hi[3])
{
    memcpy(lo, T->box + 6 * t, 3 * sizeof(double));
    memcpy(hi, T->box + 6 * t + 3, 3 * sizeof(double));
}

/* Builds the node over ids[first .. first + count): split at the middle of the centroids'
 * extent on its longest axis (in-place partition, O(count)); half by count when that
 * puts everything on one side. */
static int64_t build(tree *T, int64_t first, int64_t count)
{
    int64_t me = T->nn++;
    tnode *nd = &T->n[me];
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < 3; k++) {
        nd->lo[k] = INFINITY;
        nd->hi[k] = -INFINITY;
    }
    for (int64_t i = first; i < first + count; i++) {
        double lo[3], hi[3];
        int64_t t = T->ids[i];
        tri_box(T, t, lo, hi);
        for (int k = 0; k < 3; k++) {
            nd->lo[k] = fmin(nd->lo[k], lo[k]);
            nd->hi[k] = fmax(nd->hi[k], hi[k]);
            clo[k] = fmin(clo[k], T->cen[3 * t + k]);
            chi[k] = fmax(chi[k], T->cen[3 * t + k]);
        }
    }
    nd->first = first;
    nd->count = count;
    nd->left = nd->right = -1;
    if (count <= LEAF_TRIS)
        return me;
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (chi[k] - clo[k] > chi[ax] - clo[ax])
            ax = k;
    double mid = 0.5 * (clo[ax] + chi[ax]);
    int64_t i = first, j = first + count - 1;
    while (i <= j) {
        if (T->cen[3 * T->ids[i] + ax] < mid) {
            i++;
        } else {
            int64_t x = T->ids[i];
            T->ids[i] = T->ids[j];
            T->ids[j--] = x;
        }
    }
    int64_t nl = i - first;
    if (nl == 0 || nl == count)
        nl = count / 2;
    int64_t l = build(T, first, nl), r = build(T, first + nl, count - nl);
    T->n[me].left = l; /* T->n is not reallocated: room for 2 count nodes */
    T->n[me].right = r;
    return me;
}

static int boxes_meet(const tnode *a, const tnode *b)
{
    for (int k = 0; k < 3; k++)
        if (a->hi[k] < b->lo[k] || b->hi[k] < a->lo[k])
            return 0;
    return 1;
}

/* Does segment pq pass through triangle abc: p and q strictly on both sides of its plane
 * and the piercing point strictly inside it? */
static int segment_pierces(const double *p, const double *q, const double *a, const double *b,
                           const double *c)
{
    int sp = mfg_orient3d(a, b, c, p), sq = mfg_orient3d(a, b, c, q);
    if (sp == 0 || sq == 0 || sp == sq)
        return 0;
    int o1 = mfg_orient3d(p, q, a, b), o2 = mfg_orient3d(p, q, b, c), o3 = mfg_orient3d(p, q, c, a);
    return o1 != 0 && o1 == o2 && o2 == o3;
}

/* Is point p strictly inside the 2-D triangle abc (either orientation)? */
static int inside2(const double p[2], const double a[2], const double b[2], const double c[2])
{
    int o1 = mfg_orient2d(a[0], a[1], b[0], b[1], p[0], p[1]);
    int o2 = mfg_orient2d(b[0], b[1], c[0], c[1], p[0], p[1]);
    int o3 = mfg_orient2d(c[0], c[1], a[0], a[1], p[0], p[1]);
    return o1 != 0 && o1 == o2 && o2 == o3;
}

/* Do coplanar triangles A and B (2-D, projected) overlap in their interiors? */
static int coplanar_overlap(double A[3][2], double B[3][2])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            const double *a = A[i], *b = A[(i + 1) % 3], *c = B[j], *d = B[(j + 1) % 3];
            int s1 = mfg_orient2d(a[0], a[1], b[0], b[1], c[0], c[1]);
            int s2 = mfg_orient2d(a[0], a[1], b[0], b[1], d[0], d[1]);
            int s3 = mfg_orient2d(c[0], c[1], d[0], d[1], a[0], a[1]);
            int s4 = mfg_orient2d(c[0], c[1], d[0], d[1], b[0], b[1]);
            if (s1 * s2 < 0 && s3 * s4 < 0)
                return 1;
        }
    double ca[2] = {0, 0}, cb[2] = {0, 0};
    for (int i = 0; i < 3; i++) {
        if (inside2(B[i], A[0], A[1], A[2]) || inside2(A[i], B[0], B[1], B[2]))
            return 1;
        for (int k = 0; k < 2; k++) {
            ca[k] += A[i][k] / 3;
            cb[k] += B[i][k] / 3;
        }
    }
    return inside2(ca, B[0], B[1], B[2]) || inside2(cb, A[0], A[1], A[2]);
}

/* Do triangles s and t (sharing no vertex index) cross? */
static int triangles_cross(const double *xyz, const int64_t *tris, int64_t s, int64_t t)
{
    const double *P[3], *Q[3];
    for (int c = 0; c < 3; c++) {
        P[c] = xyz + 3 * tris[3 * s + c];
        Q[c] = xyz + 3 * tris[3 * t + c];
    }
    int o0 = mfg_orient3d(P[0], P[1], P[2], Q[0]), o1 = mfg_orient3d(P[0], P[1], P[2], Q[1]);
    int o2 = mfg_orient3d(P[0], P[1], P[2], Q[2]);
    if (o0 == 0 && o1 == 0 && o2 == 0) { /* coplanar: the plane's dominant projection */
        double n[3], u[3], v[3];
        mfg_sub3(P[1], P[0], u);
        mfg_sub3(P[2], P[0], v);
        mfg_cross3(u, v, n);
        int ax = 0;
        for (int k = 1; k < 3; k++)
            if (fabs(n[k]) > fabs(n[ax]))
                ax = k;
        int i0 = (ax + 1) % 3, i1 = (ax + 2) % 3;
        double A[3][2], B[3][2];
        for (int c = 0; c < 3; c++) {
            A[c][0] = P[c][i0], A[c][1] = P[c][i1];
            B[c][0] = Q[c][i0], B[c][1] = Q[c][i1];
        }
        return coplanar_overlap(A, B);
    }
    if ((o0 > 0 && o1 > 0 && o2 > 0) || (o0 < 0 && o1 < 0 && o2 < 0))
        return 0; /* B wholly on one side of A's plane */
    for (int c = 0; c < 3; c++)
        if (segment_pierces(P[c], P[(c + 1) % 3], Q[0], Q[1], Q[2]) ||
            segment_pierces(Q[c], Q[(c + 1) % 3], P[0], P[1], P[2]))
            return 1;
    return 0;
}

static int share_vertex(const int64_t *tris, int64_t s, int64_t t)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (tris[3 * s + i] == tris[3 * t + j])
                return 1;
    return 0;
}

typedef struct crossing {
    int64_t count, a, b; /* how many pairs cross; the first pair (a < b, smallest) */
} crossing;

static void test_pair(const tree *T, int64_t s, int64_t t, crossing *cr)
{
    if (s == t || share_vertex(T->tris, s, t) || !triangles_cross(T->xyz, T->tris, s, t))
        return;
    int64_t a = s < t ? s : t, b = s < t ? t : s;
    if (cr->count++ == 0 || a < cr->a || (a == cr->a && b < cr->b))
        cr->a = a, cr->b = b;
}

/* Every crossing pair, by the tree against itself (a stack of node pairs). */
static int self_collide(const tree *T, crossing *cr)
{
    int64_t *st = NULL, cap = 0, n = 0;
    if (!mfg_grow((void **)&st, &cap, 2, sizeof *st))
        return 0;
    st[n++] = 0;
    st[n++] = 0;
    while (n > 0) {
        int64_t b = st[--n], a = st[--n];
        const tnode *A = &T->n[a], *B = &T->n[b];
        if (a != b && !boxes_meet(A, B))
            continue;
        int64_t push[6];
        int np = 0;
        if (A->left < 0 && B->left < 0) {
            for (int64_t i = 0; i < A->count; i++)
                for (int64_t j = a == b ? i + 1 : 0; j < B->count; j++) {
                    int64_t s = T->ids[A->first + i], t = T->ids[B->first + j];
                    double lo1[3], hi1[3], lo2[3], hi2[3];
                    tri_box(T, s, lo1, hi1);
                    tri_box(T, t, lo2, hi2);
                    int meet = 1;
                    for (int k = 0; k < 3; k++)
                        meet &= !(hi1[k] < lo2[k] || hi2[k] < lo1[k]);
                    if (meet)
                        test_pair(T, s, t, cr);
                }
            continue;
        }
        if (a == b) {
            push[np++] = A->left, push[np++] = A->left;
            push[np++] = A->right, push[np++] = A->right;
            push[np++] = A->left, push[np++] = A->right;
        } else if (B->left < 0 || (A->left >= 0 && A->count >= B->count)) {
            push[np++] = A->left, push[np++] = b;
            push[np++] = A->right, push[np++] = b;
        } else {
            push[np++] = a, push[np++] = B->left;
            push[np++] = a, push[np++] = B->right;
        }
        if (!mfg_grow((void **)&st, &cap, n + np, sizeof *st)) {
            free(st);
            return 0;
        }
        for (int k = 0; k < np; k++)
            st[n++] = push[k];
    }
    free(st);
    return 1;
}

/* Solid angle of triangle abc seen from p (Van Oosterom & Strackee), in units of 4 pi. */
static double solid_angle(const double *p, const double *a, const double *b, const double *c)
{
    double A[3], B[3], C[3];
    mfg_sub3(a, p, A);
    mfg_sub3(b, p, B);
    mfg_sub3(c, p, C);
    double la = mfg_norm3(A), lb = mfg_norm3(B), lc = mfg_norm3(C), bc[3];
    mfg_cross3(B, C, bc);
    double num = mfg_dot3(A, bc);
    double den = la * lb * lc + mfg_dot3(A, B) * lc + mfg_dot3(A, C) * lb + mfg_dot3(B, C) * la;
    return atan2(num, den) / (2 * 3.14159265358979323846);
}

mfg_status mfg_mesh_shells_problem(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt)
{
    mfg_status st = MFG_OK;
    tree T;
    memset(&T, 0, sizeof T);
    T.xyz = xyz;
    T.tris = tris;
    int64_t *comp = malloc((size_t)(nv + 1) * sizeof *comp);
    T.ids = malloc((size_t)(nt + 1) * sizeof *T.ids);
    T.cen = malloc((size_t)(3 * nt + 1) * sizeof *T.cen);
    T.box = malloc((size_t)(6 * nt + 1) * sizeof *T.box);
    T.n = malloc((size_t)(2 * nt + 1) * sizeof *T.n);
    if (!comp || !T.ids || !T.cen || !T.box || !T.n) {
        st = mfg_fail(MFG_ERR_NOMEM, "out of memory checking the shells of %lld triangles", (long long)nt);
        goto done;
    }
    int64_t m = 0;
    for (int64_t t = 0; t < nt; t++) {
        const double *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1], *c = xyz + 3 * tris[3 * t + 2];
        if (mfg_triangle_zero_area(a, b, c))
            continue;
        for (int k = 0; k < 3; k++) {
            T.cen[3 * t + k] = (a[k] + b[k] + c[k]) / 3;
            T.box[6 * t + k] = fmin(a[k], fmin(b[k], c[k]));
            T.box[6 * t + 3 + k] = fmax(a[k], fmax(b[k], c[k]));
        }
        T.ids[m++] = t;
    }
    crossing cr = {0, -1, -1};
    if (m > 1) {
        build(&T, 0, m);
        if (!self_collide(&T, &cr)) {
            st = mfg_fail(MFG_ERR_NOMEM, "out of memory checking the shells of %lld triangles", (long long)nt);
            goto done;
        }
    }
    if (cr.count) {
        st = mfg_fail(MFG_ERR_INVALID,
                      "shells cross: triangles %lld and %lld intersect (%lld crossing pairs; "
                      "overlapping or self-intersecting shells: unite them first)",
                      (long long)cr.a, (long long)cr.b, (long long)cr.count);
        goto done;
    }
    /* Shells: vertices joined through their triangles. */
    for (int64_t v = 0; v < nv; v++)
        comp[v] = v;
    for (int64_t t = 0; t < nt; t++) {
        mfg_uf_union(comp, tris[3 * t], tris[3 * t + 1]);
        mfg_uf_union(comp, tris[3 * t], tris[3 * t + 2]);
    }
    int64_t roots[MAX_NEST_SHELLS], rep[MAX_NEST_SHELLS], nsh = 0;
    double vol[MAX_NEST_SHELLS];
    for (int64_t t = 0; t < nt && nsh <= MAX_NEST_SHELLS; t++) {
        int64_t r = mfg_uf_find(comp, tris[3 * t]), k = 0;
        while (k < nsh && roots[k] != r)
            k++;
        if (k == nsh) {
            if (nsh == MAX_NEST_SHELLS) {
                nsh++; /* too many: the nesting test is skipped */
                break;
            }
            roots[nsh] = r, rep[nsh] = t, vol[nsh] = 0;
            nsh++;
        }
        double cr3[3];
        const double *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1], *c = xyz + 3 * tris[3 * t + 2];
        mfg_cross3(b, c, cr3);
        vol[k] += mfg_dot3(a, cr3);
    }
    if (nsh < 2 || nsh > MAX_NEST_SHELLS)
        goto done;
    for (int64_t k = 0; k < nsh; k++) {
        const double *p = xyz + 3 * tris[3 * rep[k]];
        double w = 0;
        for (int64_t t = 0; t < nt; t++) {
            if (mfg_uf_find(comp, tris[3 * t]) == roots[k])
                continue;
            w += solid_angle(p, xyz + 3 * tris[3 * t], xyz + 3 * tris[3 * t + 1], xyz + 3 * tris[3 * t + 2]);
        }
        long wi = lround(w);
        if (fabs(w - (double)wi) > 0.25)
            continue; /* rounding too large to tell (a shell all but touching another) */
        long want = vol[k] > 0 ? 0 : 1;
        if (wi != want) {
            st = mfg_fail(MFG_ERR_INVALID,
                          "nested shells: the shell of triangle %lld (%s) lies %s (winding number %ld): "
                          "a solid's shells must not overlap",
                          (long long)rep[k], vol[k] > 0 ? "facing out" : "a cavity facing in",
                          vol[k] > 0 ? "inside another shell" : "outside every solid shell", wi);
            goto done;
        }
    }
done:
    free(comp);
    free(T.ids);
    free(T.cen);
    free(T.box);
    free(T.n);
    return st;
}
