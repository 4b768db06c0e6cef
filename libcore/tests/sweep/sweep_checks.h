/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep_checks.h - independent checks of a rotational sweep's result, shared by
 * test_rotsweep.c and the property fuzz target tests/fuzz/fuzz_sweep.c (one copy: a
 * drifted copy of a check is a wrong verdict): turning a point about an axis, the mesh's
 * volume / area / box, an exact orient3d written here (expansion arithmetic, no code
 * shared with the library), the brute-force exact self-intersection count, an exact
 * zero-area test, the generalised winding number and the distance of a point to the mesh. */
#ifndef MFG_SWEEP_CHECKS_H
#define MFG_SWEEP_CHECKS_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mfgeom.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function" /* each includer uses a subset */
#endif

/* ------------------------------------------------------------------------ */
/* Geometry helpers                                                         */
/* ------------------------------------------------------------------------ */

static void unit3(const double v[3], double u[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    u[0] = v[0] / n;
    u[1] = v[1] / n;
    u[2] = v[2] / n;
}

/* p turned by t about the axis through a along the unit vector u (right-handed). */
static void rotate(const double a[3], const double u[3], double t, const double p[3], double out[3])
{
    double v[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double c = cos(t), s = sin(t), d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    for (int i = 0; i < 3; i++)
        out[i] = a[i] + v[i] * c + x[i] * s + u[i] * d * (1 - c);
}

static double dist_to_axis(const double a[3], const double u[3], const double p[3])
{
    double v[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    double d = u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    double r2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - d * d;
    return r2 > 0 ? sqrt(r2) : 0.0;
}

/* Volume (signed tetrahedra about the box centre), area and box of the used vertices. */
static void mesh_measure(const double *xyz, int64_t nv, const int64_t *tri, int64_t nt, double *vol,
                         double *area, double box[6])
{
    (void)nv;
    for (int c = 0; c < 3; c++) {
        box[c] = INFINITY;
        box[3 + c] = -INFINITY;
    }
    for (int64_t i = 0; i < 3 * nt; i++)
        for (int c = 0; c < 3; c++) {
            double x = xyz[3 * tri[i] + c];
            box[c] = fmin(box[c], x);
            box[3 + c] = fmax(box[3 + c], x);
        }
    double o[3] = {0.5 * (box[0] + box[3]), 0.5 * (box[1] + box[4]), 0.5 * (box[2] + box[5])};
    double v6 = 0, a2 = 0;
    for (int64_t t = 0; t < nt; t++) {
        double p[3][3];
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                p[k][c] = xyz[3 * tri[3 * t + k] + c] - o[c];
        v6 += p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) +
              p[0][1] * (p[1][2] * p[2][0] - p[1][0] * p[2][2]) +
              p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
        double e1[3], e2[3];
        for (int c = 0; c < 3; c++) {
            e1[c] = p[1][c] - p[0][c];
            e2[c] = p[2][c] - p[0][c];
        }
        double x = e1[1] * e2[2] - e1[2] * e2[1], y = e1[2] * e2[0] - e1[0] * e2[2],
               z = e1[0] * e2[1] - e1[1] * e2[0];
        a2 += sqrt(x * x + y * y + z * z);
    }
    *vol = v6 / 6;
    *area = a2 / 2;
}

/* ------------------------------------------------------------------------ */
/* Exact orient3d: sign of det[a - d, b - d, c - d], a floating-point filter and an     */
/* expansion-arithmetic fallback (Shewchuk's two-sum / two-product / grow / scale).    */
/* ------------------------------------------------------------------------ */

static void two_sum(double a, double b, double *x, double *y)
{
    double s = a + b, bv = s - a, av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* h = e + b (e non-overlapping, increasing magnitude; so is h), n + 1 terms. */
static int grow(int n, const double *e, double b, double *h)
{
    double q = b;
    for (int i = 0; i < n; i++)
        two_sum(q, e[i], &q, &h[i]);
    h[n] = q;
    return n + 1;
}

/* h = e + f, by growing e by every term of f. */
static int esum(int n, const double *e, int m, const double *f, double *h)
{
    double tmp[512];
    memcpy(tmp, e, (size_t)n * sizeof *e);
    for (int j = 0; j < m; j++) {
        n = grow(n, tmp, f[j], h);
        memcpy(tmp, h, (size_t)n * sizeof *h);
    }
    return n;
}

/* h = e * b: each term's exact product (fma gives its rounding error) as a two-term
 * expansion, summed. */
static int escale(int n, const double *e, double b, double *h)
{
    double acc[512], tmp[512];
    int na = 0;
    for (int i = 0; i < n; i++) {
        double p = e[i] * b, pr[2] = {fma(e[i], b, -p), p};
        na = esum(na, acc, 2, pr, tmp);
        memcpy(acc, tmp, (size_t)na * sizeof *tmp);
    }
    memcpy(h, acc, (size_t)na * sizeof *acc);
    return na;
}

static int emul(int n, const double *e, int m, const double *f, double *h)
{
    double acc[256], part[256], tmp[256];
    int na = 0;
    for (int j = 0; j < m; j++) {
        int np = escale(n, e, f[j], part);
        if (!na) {
            memcpy(acc, part, (size_t)np * sizeof *part);
            na = np;
        } else {
            na = esum(na, acc, np, part, tmp);
            memcpy(acc, tmp, (size_t)na * sizeof *tmp);
        }
    }
    memcpy(h, acc, (size_t)na * sizeof *acc);
    return na;
}

static int esign(int n, const double *e)
{
    for (int i = n - 1; i >= 0; i--)
        if (e[i] != 0)
            return e[i] > 0 ? 1 : -1;
    return 0;
}

/* Drops zero terms (keeps the order). */
static int ecompress(int n, double *e)
{
    int k = 0;
    for (int i = 0; i < n; i++)
        if (e[i] != 0)
            e[k++] = e[i];
    return k;
}

static long n_exact;

/* The sign of det[a - d, b - d, c - d] where the floating-point value is sure of it; 2 where
 * it is not (an exact 0 included). */
static int orient3d_filter(const double *a, const double *b, const double *c, const double *d)
{
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double det = adx * (bdy * cdz - bdz * cdy) + bdx * (cdy * adz - cdz * ady) +
                 cdx * (ady * bdz - adz * bdy);
    double perm = fabs(adx) * (fabs(bdy * cdz) + fabs(bdz * cdy)) +
                  fabs(bdx) * (fabs(cdy * adz) + fabs(cdz * ady)) +
                  fabs(cdx) * (fabs(ady * bdz) + fabs(adz * bdy));
    /* Shewchuk's bound is (7 + 56u) u perm; 16u leaves a wide margin */
    double bound = 16 * 0x1p-53 * perm;
    if (det > bound)
        return 1;
    if (-det > bound)
        return -1;
    return 2;
}

static int orient3d(const double *a, const double *b, const double *c, const double *d)
{
    int sure = orient3d_filter(a, b, c, d);
    if (sure != 2)
        return sure;
    n_exact++;
    /* the nine differences exactly, as two-term expansions */
    double D[3][3][2];
    const double *r[3] = {a, b, c};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double x, y;
            two_sum(r[i][j], -d[j], &x, &y);
            D[i][j][0] = y;
            D[i][j][1] = x;
        }
    /* det = sum over the cyclic (i, j, k) of D[i][0] * (D[j][1] D[k][2] - D[j][2] D[k][1]) */
    double total[256];
    int nt = 0;
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3, k = (i + 2) % 3;
        double p1[64], p2[64], mn[128], term[256], tmp[256];
        int n1 = emul(2, D[j][1], 2, D[k][2], p1);
        int n2 = emul(2, D[j][2], 2, D[k][1], p2);
        for (int q = 0; q < n2; q++)
            p2[q] = -p2[q];
        int nm = esum(n1, p1, n2, p2, mn);
        nm = ecompress(nm, mn);
        if (!nm)
            continue;
        int ntm = emul(nm, mn, 2, D[i][0], term);
        ntm = ecompress(ntm, term);
        if (!ntm)
            continue;
        if (!nt) {
            memcpy(total, term, (size_t)ntm * sizeof *term);
            nt = ntm;
        } else {
            nt = esum(nt, total, ntm, term, tmp);
            nt = ecompress(nt, tmp);
            memcpy(total, tmp, (size_t)nt * sizeof *tmp);
        }
    }
    return esign(nt, total);
}

/* The sign of (b - a) x (c - a) in the plane of coordinates i and j (the orientation of
 * the triangle's projection), exact: a floating-point filter (Shewchuk's bound for
 * orient2d is (3 + 16u) u times the sum of the two products' magnitudes; 8u leaves a
 * margin) and the expansion fallback above. */
static int orient2d_proj(const double *a, const double *b, const double *c, int i, int j)
{
    double l = (b[i] - a[i]) * (c[j] - a[j]), r = (b[j] - a[j]) * (c[i] - a[i]), det = l - r;
    double bound = 8 * 0x1p-53 * (fabs(l) + fabs(r));
    if (det > bound)
        return 1;
    if (-det > bound)
        return -1;
    double d[4][2]; /* b_i - a_i, c_j - a_j, b_j - a_j, c_i - a_i as two-term expansions */
    const double *from[4] = {b, c, b, c};
    const int coord[4] = {i, j, j, i};
    for (int k = 0; k < 4; k++)
        two_sum(from[k][coord[k]], -a[coord[k]], &d[k][1], &d[k][0]);
    double p1[16], p2[16], sum[32];
    int n1 = emul(2, d[0], 2, d[1], p1), n2 = emul(2, d[2], 2, d[3], p2);
    for (int k = 0; k < n2; k++)
        p2[k] = -p2[k];
    return esign(esum(n1, p1, n2, p2, sum), sum);
}

/* Whether triangle abc has zero area, exactly: its normal (b - a) x (c - a) is the zero
 * vector, i.e. its projections on the three coordinate planes are all collinear (a
 * repeated vertex included). */
static int zero_area(const double *a, const double *b, const double *c)
{
    return orient2d_proj(a, b, c, 0, 1) == 0 && orient2d_proj(a, b, c, 1, 2) == 0 &&
           orient2d_proj(a, b, c, 2, 0) == 0;
}

/* The number of zero-area triangles of a mesh (the first one in *first, -1 if none). */
static long zero_area_triangles(const mfg_mesh *m, int64_t *first)
{
    long n = 0;
    *first = -1;
    for (int64_t t = 0; t < m->ntriangles; t++) {
        const int64_t *v = m->triangles + 3 * t;
        if (zero_area(m->vertices + 3 * v[0], m->vertices + 3 * v[1], m->vertices + 3 * v[2]) && !n++)
            *first = t;
    }
    return n;
}

/* ------------------------------------------------------------------------ */
/* Exact triangle-triangle intersection (closed triangles)                  */
/* ------------------------------------------------------------------------ */

/* For points in the plane of a triangle, orient3d against a point e off that plane is the
 * planar orientation (up to one common sign). */
static int on_segment_collinear(const double *p, const double *q, const double *r)
{
    for (int c = 0; c < 3; c++)
        if (r[c] < fmin(p[c], q[c]) || r[c] > fmax(p[c], q[c]))
            return 0;
    return 1;
}

static int seg_seg_coplanar(const double *p, const double *q, const double *r, const double *s,
                            const double *e)
{
    int d1 = orient3d(p, q, r, e), d2 = orient3d(p, q, s, e);
    int d3 = orient3d(r, s, p, e), d4 = orient3d(r, s, q, e);
    if (d1 * d2 < 0 && d3 * d4 < 0)
        return 1;
    return (d1 == 0 && on_segment_collinear(p, q, r)) || (d2 == 0 && on_segment_collinear(p, q, s)) ||
           (d3 == 0 && on_segment_collinear(r, s, p)) || (d4 == 0 && on_segment_collinear(r, s, q));
}

static int point_in_tri_coplanar(const double *p, const double *a, const double *b, const double *c,
                                 const double *e)
{
    int s0 = orient3d(a, b, c, e);
    int s1 = orient3d(a, b, p, e) * s0, s2 = orient3d(b, c, p, e) * s0, s3 = orient3d(c, a, p, e) * s0;
    return s1 >= 0 && s2 >= 0 && s3 >= 0;
}

/* The point e = a + (unit vector k) for the first k that is off the plane of abc: for
 * points in that plane, orient3d against e is their planar orientation.  Returns k, or -1
 * when abc has zero area (orient3d against each such point vanishes). */
static int off_plane(const double *a, const double *b, const double *c, double e[3])
{
    static const double off[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < 3; i++)
            e[i] = a[i] + off[k][i];
        if (orient3d(a, b, c, e) != 0)
            return k;
    }
    return -1;
}

/* Closed segment pq against closed triangle abc (non-degenerate); sp and sq are
 * orient3d(a, b, c, p) and orient3d(a, b, c, q), e is off_plane's point for abc. */
static int seg_tri(const double *p, const double *q, int sp, int sq, const double *a, const double *b,
                   const double *c, const double *e)
{
    if (sp * sq > 0)
        return 0;
    if (sp == 0 && sq == 0) {
        /* coplanar: planar orientations against e */
        return point_in_tri_coplanar(p, a, b, c, e) || point_in_tri_coplanar(q, a, b, c, e) ||
               seg_seg_coplanar(p, q, a, b, e) || seg_seg_coplanar(p, q, b, c, e) ||
               seg_seg_coplanar(p, q, c, a, e);
    }
    int s1 = orient3d(p, q, a, b), s2 = orient3d(p, q, b, c), s3 = orient3d(p, q, c, a);
    return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}

static void cross3(const double u[3], const double v[3], double w[3])
{
    w[0] = u[1] * v[2] - u[2] * v[1];
    w[1] = u[2] * v[0] - u[0] * v[2];
    w[2] = u[0] * v[1] - u[1] * v[0];
}

/* Whether direction n separates a from b (corners relative to a common origin): every
 * corner of a projects below every corner of b, or the other way round, counting each
 * projection's rounding error (of the relative corner and of the dot product, together
 * below 4u of the sum of |n_c x_c|; 8u is used) against it.  Any n will do: it need not
 * be exact. */
static int separates(const double n[3], const double a[3][3], const double b[3][3])
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int w = 0; w < 2; w++)
        for (int k = 0; k < 3; k++) {
            const double *x = w ? b[k] : a[k];
            double d = n[0] * x[0] + n[1] * x[1] + n[2] * x[2];
            double err = 8 * 0x1p-53 * (fabs(n[0] * x[0]) + fabs(n[1] * x[1]) + fabs(n[2] * x[2])) + 0x1p-1000;
            if (!(fabs(d) + err <= 0x1p1000)) /* overflow, NaN */
                return 0;
            lo[w] = fmin(lo[w], d - err);
            hi[w] = fmax(hi[w], d + err);
        }
    return hi[0] < lo[1] || hi[1] < lo[0];
}

/* 1 when a separating axis is found for closed triangles A and B (no common vertex): then
 * they are disjoint; 0 decides nothing.  The axes of the separating axis theorem: the two
 * normals, each normal across each edge of its triangle (what separates triangles in one
 * plane), the cross products of an edge of each (coplanar: no use, nor the normals). */
static int apart(const double *const A[3], const double *const B[3], int coplanar)
{
    double a[3][3], b[3][3], ea[3][3], eb[3][3], nA[3], nB[3], n[3];
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 3; c++) {
            a[k][c] = A[k][c] - A[0][c];
            b[k][c] = B[k][c] - A[0][c];
            ea[k][c] = A[(k + 1) % 3][c] - A[k][c];
            eb[k][c] = B[(k + 1) % 3][c] - B[k][c];
        }
    cross3(ea[0], ea[1], nA);
    cross3(eb[0], eb[1], nB);
    if (!coplanar && (separates(nA, a, b) || separates(nB, a, b)))
        return 1;
    for (int k = 0; k < 3; k++) {
        cross3(nA, ea[k], n);
        if (separates(n, a, b))
            return 1;
        cross3(nB, eb[k], n);
        if (separates(n, a, b))
            return 1;
    }
    for (int i = 0; i < 3 && !coplanar; i++)
        for (int j = 0; j < 3; j++) {
            cross3(ea[i], eb[j], n);
            if (separates(n, a, b))
                return 1;
        }
    return 0;
}

/* 1 when orient3d(p, q, r, x) is surely s (by the filter alone) for each of the n points x. */
static int all_on_side(const double *p, const double *q, const double *r, const double *const *X, int n, int s)
{
    for (int k = 0; k < n; k++)
        if (orient3d_filter(p, q, r, X[k]) != s)
            return 0;
    return 1;
}

/* The same for closed triangles with one common vertex v = A[ia] = B[ib]: 1 when the
 * filter alone finds a plane through v with one triangle on its closed side and the other
 * corners of the other strictly on the other side; then they meet in v only.  Tried: each
 * one's plane (not for two in one plane), and the planes through an edge of each from v,
 * perpendicular to its triangle (v, the edge's other end and a point off v along the
 * normal: the planes' own points are on them exactly, however the normal rounds), the
 * third corner surely on one side. */
static int apart_at(const double *const A[3], int ia, const double *const B[3], int ib, int coplanar)
{
    for (int swap = 0; swap < 2; swap++) {
        const double *const *P = swap ? B : A, *const *Q = swap ? A : B;
        int ip = swap ? ib : ia, iq = swap ? ia : ib;
        const double *v = P[ip], *X[2] = {Q[(iq + 1) % 3], Q[(iq + 2) % 3]};
        if (!coplanar) {
            int s = orient3d_filter(P[0], P[1], P[2], X[0]);
            if (s != 2 && all_on_side(P[0], P[1], P[2], X + 1, 1, s))
                return 1;
        }
        double e1[3], e2[3], nP[3], e[3];
        for (int c = 0; c < 3; c++) {
            e1[c] = P[(ip + 1) % 3][c] - v[c];
            e2[c] = P[(ip + 2) % 3][c] - v[c];
        }
        cross3(e1, e2, nP);
        double len = sqrt(nP[0] * nP[0] + nP[1] * nP[1] + nP[2] * nP[2]);
        double size = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
        if (!(len > 0) || !(size > 0))
            continue;
        for (int c = 0; c < 3; c++)
            e[c] = v[c] + nP[c] * (size / len);
        for (int k = 1; k <= 2; k++) {
            const double *x = P[(ip + k) % 3], *r = P[(ip + 3 - k) % 3];
            int s = orient3d_filter(v, x, e, r);
            if (s != 2 && all_on_side(v, x, e, X, 2, -s))
                return 1;
        }
    }
    return 0;
}

static const double *sort_box; /* for cmp_low_x: the triangles' boxes */
static const double *sort_xyz; /* for cmp_xyz: the vertices */
static const int64_t *sort_tri; /* for cmp_edge: the triangles */

static int cmp_xyz(const void *pa, const void *pb)
{
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    for (int c = 0; c < 3; c++) {
        double xa = sort_xyz[3 * a + c], xb = sort_xyz[3 * b + c];
        if (xa != xb)
            return xa < xb ? -1 : 1;
    }
    return (a > b) - (a < b);
}

/* Edges as 3 t + k (corner k to corner k + 1 of triangle t), by their two vertices. */
static int cmp_edge(const void *pa, const void *pb)
{
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    int64_t a0 = sort_tri[a], a1 = sort_tri[a - a % 3 + (a + 1) % 3];
    int64_t b0 = sort_tri[b], b1 = sort_tri[b - b % 3 + (b + 1) % 3];
    int64_t alo = a0 < a1 ? a0 : a1, ahi = a0 < a1 ? a1 : a0, blo = b0 < b1 ? b0 : b1, bhi = b0 < b1 ? b1 : b0;
    if (alo != blo)
        return alo < blo ? -1 : 1;
    if (ahi != bhi)
        return ahi < bhi ? -1 : 1;
    return (a > b) - (a < b);
}

static int64_t uf_find(int64_t *parent, int64_t x)
{
    while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
    return x;
}

static int cmp_low_x(const void *pa, const void *pb)
{
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    double xa = sort_box[6 * a], xb = sort_box[6 * b];
    return xa < xb ? -1 : xa > xb ? 1 : (a > b) - (a < b);
}

/* Checks every pair of triangles of the mesh whose boxes overlap:
 *  - no common vertex: the closed triangles are disjoint;
 *  - one common vertex: the side opposite it in each misses the other triangle;
 *  - a common edge: the two are not folded onto each other (coplanar, same side).
 * Returns the number of bad pairs; prints the first.
 * Every pair is decided exactly.  Results with many long thin triangles (each one's box
 * overlaps many others, and an orient3d that is exactly 0 - coplanar or touching corners -
 * always takes the slow exact path) made it slow; so a pair is first tried for a plane or
 * axis that separates it, found in floating point with its rounding bounded (apart,
 * apart_at): such a pair cannot meet, and only the others reach the exact predicates.
 * There, triangles joined across an edge, the apex of one in the other's plane, lie in
 * one plane (a patch): for two of one patch each corner's side of the other's plane is 0
 * without computing it; otherwise it is computed once per pair, not once per segment, and
 * a triangle strictly on one side of the other's plane (but for the common vertex) cannot
 * meet it. */
/* Set by a caller that reports the count itself (the battery): no message then. */
static int self_intersections_quiet;

static long self_intersections(const mfg_mesh *m, const char *name)
{
    int64_t nt = m->ntriangles, nv = m->nvertices;
    const double *V = m->vertices;
    /* vertices at the same point count as one: copies of a vertex where two sheets of SV
     * touch (a pinch) are then a shared vertex, not an intersection */
    int64_t *byxyz = malloc((size_t)(nv + 1) * sizeof *byxyz), *canon = malloc((size_t)(nv + 1) * sizeof *canon);
    for (int64_t v = 0; v < nv; v++)
        byxyz[v] = v;
    sort_xyz = V;
    qsort(byxyz, (size_t)nv, sizeof *byxyz, cmp_xyz);
    long copies = 0;
    for (int64_t i = 0; i < nv; i++) {
        int same = i > 0 && !memcmp(V + 3 * byxyz[i], V + 3 * byxyz[i - 1], 3 * sizeof *V);
        canon[byxyz[i]] = same ? canon[byxyz[i - 1]] : byxyz[i];
        copies += same;
    }
    int64_t *T = malloc((size_t)(3 * nt + 1) * sizeof *T);
    for (int64_t i = 0; i < 3 * nt; i++)
        T[i] = canon[m->triangles[i]];
    free(byxyz);
    free(canon);
    if (copies && !self_intersections_quiet)
        printf("  note %s: %ld vertices repeat another's coordinates\n", name, copies);
    double *box = malloc((size_t)(6 * nt + 1) * sizeof *box);
    double *eoff = malloc((size_t)(3 * nt + 1) * sizeof *eoff); /* off_plane's point per triangle */
    unsigned char *deg = calloc((size_t)nt + 1, 1);
    for (int64_t t = 0; t < nt; t++) {
        for (int c = 0; c < 3; c++) {
            box[6 * t + c] = INFINITY;
            box[6 * t + 3 + c] = -INFINITY;
        }
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++) {
                double x = V[3 * T[3 * t + k] + c];
                box[6 * t + c] = fmin(box[6 * t + c], x);
                box[6 * t + 3 + c] = fmax(box[6 * t + 3 + c], x);
            }
        deg[t] = off_plane(V + 3 * T[3 * t], V + 3 * T[3 * t + 1], V + 3 * T[3 * t + 2], eoff + 3 * t) < 0;
    }
    /* patches: triangles sharing an edge (two common vertices), neither of zero area, the
     * apex of one in the plane of the other, are in one plane */
    int64_t *patch = malloc((size_t)(nt + 1) * sizeof *patch), *edges = malloc((size_t)(3 * nt + 1) * sizeof *edges);
    for (int64_t t = 0; t < nt; t++)
        patch[t] = t;
    for (int64_t i = 0; i < 3 * nt; i++)
        edges[i] = i;
    sort_tri = T;
    qsort(edges, (size_t)(3 * nt), sizeof *edges, cmp_edge);
    for (int64_t i = 0, j; i < 3 * nt; i = j) {
        for (j = i + 1; j < 3 * nt; j++) {
            int64_t a = edges[i], b = edges[j];
            int64_t a0 = T[a], a1 = T[a - a % 3 + (a + 1) % 3], b0 = T[b], b1 = T[b - b % 3 + (b + 1) % 3];
            if (!((a0 == b0 && a1 == b1) || (a0 == b1 && a1 == b0)))
                break;
        }
        for (int64_t x = i; x < j; x++)
            for (int64_t y = x + 1; y < j; y++) {
                int64_t u = edges[x] / 3, w = edges[y] / 3;
                if (u == w || deg[u] || deg[w] || uf_find(patch, u) == uf_find(patch, w))
                    continue;
                const double *apex = V + 3 * T[3 * w + (edges[y] % 3 + 2) % 3];
                if (orient3d(V + 3 * T[3 * u], V + 3 * T[3 * u + 1], V + 3 * T[3 * u + 2], apex) == 0)
                    patch[uf_find(patch, u)] = uf_find(patch, w);
            }
    }
    for (int64_t t = 0; t < nt; t++)
        patch[t] = uf_find(patch, t);
    free(edges);
    /* sweep along x: triangles sorted by their boxes' low x; a pair is looked at only
     * when the boxes overlap in x (then in y and z) */
    int64_t *order = malloc((size_t)(nt + 1) * sizeof *order);
    for (int64_t t = 0; t < nt; t++)
        order[t] = t;
    sort_box = box;
    qsort(order, (size_t)nt, sizeof *order, cmp_low_x);
    long bad = 0;
    for (int64_t is_ = 0; is_ < nt; is_++) {
        int64_t s = order[is_];
        if (deg[s])
            continue;
        for (int64_t it_ = is_ + 1; it_ < nt && box[6 * order[it_]] <= box[6 * s + 3]; it_++) {
            int64_t t = order[it_];
            if (deg[t])
                continue;
            const double *bs = box + 6 * s, *bt = box + 6 * t;
            if (bs[1] > bt[4] || bt[1] > bs[4] || bs[2] > bt[5] || bt[2] > bs[5])
                continue;
            const int64_t *ts = T + 3 * s, *tt = T + 3 * t;
            int shared = 0, is = -1, it = -1;
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    if (ts[i] == tt[j]) {
                        shared++;
                        is = i;
                        it = j;
                    }
            const double *A[3], *B[3], *eA = eoff + 3 * s, *eB = eoff + 3 * t;
            for (int i = 0; i < 3; i++) {
                A[i] = V + 3 * ts[i];
                B[i] = V + 3 * tt[i];
            }
            /* sa[i]: A[i]'s side of B's plane, sb[i]: B[i]'s of A's (in one patch: 0) */
            int coplanar = patch[s] == patch[t], sa[3] = {0, 0, 0}, sb[3] = {0, 0, 0};
            int hit = 0;
            const char *what = "";
            if (shared == 0) {
                if (apart(A, B, coplanar))
                    continue;
                for (int i = 0; i < 3 && !coplanar; i++)
                    sb[i] = orient3d(A[0], A[1], A[2], B[i]);
                if (sb[0] * sb[1] > 0 && sb[1] * sb[2] > 0)
                    continue;
                for (int i = 0; i < 3 && !coplanar; i++)
                    sa[i] = orient3d(B[0], B[1], B[2], A[i]);
                if (sa[0] * sa[1] > 0 && sa[1] * sa[2] > 0)
                    continue;
                for (int i = 0; i < 3 && !hit; i++)
                    hit = seg_tri(A[i], A[(i + 1) % 3], sa[i], sa[(i + 1) % 3], B[0], B[1], B[2], eB) ||
                          seg_tri(B[i], B[(i + 1) % 3], sb[i], sb[(i + 1) % 3], A[0], A[1], A[2], eA);
                what = "disjoint triangles meet";
            } else if (shared == 1) {
                int a1 = (is + 1) % 3, a2 = (is + 2) % 3, b1 = (it + 1) % 3, b2 = (it + 2) % 3;
                if (apart_at(A, is, B, it, coplanar))
                    continue;
                if (!coplanar) {
                    sb[b1] = orient3d(A[0], A[1], A[2], B[b1]);
                    sb[b2] = orient3d(A[0], A[1], A[2], B[b2]);
                    if (sb[b1] * sb[b2] > 0)
                        continue;
                    sa[a1] = orient3d(B[0], B[1], B[2], A[a1]);
                    sa[a2] = orient3d(B[0], B[1], B[2], A[a2]);
                    if (sa[a1] * sa[a2] > 0)
                        continue;
                }
                hit = seg_tri(A[a1], A[a2], sa[a1], sa[a2], B[0], B[1], B[2], eB) ||
                      seg_tri(B[b1], B[b2], sb[b1], sb[b2], A[0], A[1], A[2], eA);
                what = "triangles with one common vertex meet beyond it";
            } else if (shared == 2) {
                /* the apexes: the corner of each not on the common edge */
                int as = -1, at = -1;
                for (int i = 0; i < 3; i++) {
                    if (ts[i] != tt[0] && ts[i] != tt[1] && ts[i] != tt[2])
                        as = i;
                    if (tt[i] != ts[0] && tt[i] != ts[1] && tt[i] != ts[2])
                        at = i;
                }
                const double *p = A[(as + 1) % 3], *q = A[(as + 2) % 3];
                if (coplanar || orient3d(A[0], A[1], A[2], B[at]) == 0) {
                    /* coplanar: folded when both apexes are on the same side of pq */
                    hit = orient3d(p, q, A[as], eA) * orient3d(p, q, B[at], eA) > 0;
                    what = "triangles with a common edge folded onto each other";
                }
            } else {
                hit = 1;
                what = "two triangles on the same three vertices";
            }
            if (hit && bad++ == 0 && !self_intersections_quiet) {
                fprintf(stderr, "%s: self-intersection: %s: triangles %lld and %lld\n", name, what,
                        (long long)s, (long long)t);
                for (int i = 0; i < 3; i++)
                    fprintf(stderr, "    %lld (%.17g, %.17g, %.17g)   %lld (%.17g, %.17g, %.17g)\n",
                            (long long)ts[i], A[i][0], A[i][1], A[i][2], (long long)tt[i], B[i][0], B[i][1],
                            B[i][2]);
            }
        }
    }
    free(order);
    free(box);
    free(eoff);
    free(deg);
    free(patch);
    free(T);
    return bad;
}

/* ------------------------------------------------------------------------ */
/* Winding number of the result mesh at a point (solid angles)              */
/* ------------------------------------------------------------------------ */

static double winding(const mfg_mesh *m, const double p[3])
{
    double sum = 0;
    for (int64_t t = 0; t < m->ntriangles; t++) {
        double a[3], b[3], c[3];
        for (int i = 0; i < 3; i++) {
            a[i] = m->vertices[3 * m->triangles[3 * t] + i] - p[i];
            b[i] = m->vertices[3 * m->triangles[3 * t + 1] + i] - p[i];
            c[i] = m->vertices[3 * m->triangles[3 * t + 2] + i] - p[i];
        }
        double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        double den = la * lb * lc + (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) * lc +
                     (a[0] * c[0] + a[1] * c[1] + a[2] * c[2]) * lb +
                     (b[0] * c[0] + b[1] * c[1] + b[2] * c[2]) * la;
        sum += 2 * atan2(det, den);
    }
    return sum / (4 * M_PI);
}

/* Distance from p to the segment ab. */
static double seg_dist(const double *p, const double *a, const double *b)
{
    double ab[3], ap[3], e[3];
    for (int i = 0; i < 3; i++) {
        ab[i] = b[i] - a[i];
        ap[i] = p[i] - a[i];
    }
    double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double s = l2 > 0 ? (ab[0] * ap[0] + ab[1] * ap[1] + ab[2] * ap[2]) / l2 : 0;
    s = s < 0 ? 0 : s > 1 ? 1 : s;
    for (int i = 0; i < 3; i++)
        e[i] = ap[i] - s * ab[i];
    return sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
}

/* Distance from p to the closed triangle abc: the distance to its plane when p projects
 * inside it, else to the nearest side.  Written for slivers (the sweep's strips are
 * 1e-6 wide and metres long): the normal is the cross product at the corner between the
 * two shortest sides, and "projects inside" is the sign of (side x (p - corner)) . n per
 * side, both well conditioned there; Ericson's region test by differences of dot
 * products is not (2026-12-06: a point 3e-16 off a 1.8 x 2e-6 strip came out 2.5e-5
 * from it, and the battery called a conservative result "outside by 1e-5 tol"). */
static double tri_dist(const double *p, const double *a, const double *b, const double *c)
{
    const double *V[3] = {a, b, c};
    double len[3]; /* len[i]: the side opposite V[i] */
    for (int i = 0; i < 3; i++) {
        const double *x = V[(i + 1) % 3], *y = V[(i + 2) % 3];
        len[i] = (x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) + (x[2] - y[2]) * (x[2] - y[2]);
    }
    int o = 0; /* the corner opposite the longest side: between the two shortest */
    for (int i = 1; i < 3; i++)
        if (len[i] > len[o])
            o = i;
    const double *q0 = V[o], *q1 = V[(o + 1) % 3], *q2 = V[(o + 2) % 3];
    double e1[3], e2[3], n[3];
    for (int i = 0; i < 3; i++) {
        e1[i] = q1[i] - q0[i];
        e2[i] = q2[i] - q0[i];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    int inside = nn > 0;
    for (int i = 0; i < 3 && inside; i++) {
        const double *x = V[i], *y = V[(i + 1) % 3];
        double s[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
        double w[3] = {p[0] - x[0], p[1] - x[1], p[2] - x[2]};
        double cx[3] = {s[1] * w[2] - s[2] * w[1], s[2] * w[0] - s[0] * w[2], s[0] * w[1] - s[1] * w[0]};
        inside = cx[0] * n[0] + cx[1] * n[1] + cx[2] * n[2] >= 0;
    }
    if (inside)
        return fabs((p[0] - q0[0]) * n[0] + (p[1] - q0[1]) * n[1] + (p[2] - q0[2]) * n[2]) / nn;
    return fmin(seg_dist(p, a, b), fmin(seg_dist(p, b, c), seg_dist(p, c, a)));
}

static double mesh_dist(const mfg_mesh *m, const double p[3])
{
    double best = INFINITY;
    for (int64_t t = 0; t < m->ntriangles; t++)
        best = fmin(best, tri_dist(p, m->vertices + 3 * m->triangles[3 * t], m->vertices + 3 * m->triangles[3 * t + 1],
                                   m->vertices + 3 * m->triangles[3 * t + 2]));
    return best;
}

#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

#endif
