/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* implicit.c - implicit points: their rounded homogeneous coordinates with error bounds
 * (arr_point_prepare), the floating-point filters of the predicates, the shortcuts for
 * points on a plane or line by construction, and the public predicates (filter first,
 * then the exact stage of implicit_exact.c).
 *
 * The filter is a running forward error analysis: every quantity is a pair (v, e), v the
 * double computed, e a bound on |v - exact|.  For a sum or difference
 *   |fl(a + b) - (a + b)| <= e_a + e_b + u |fl(a + b)|,
 * for a product
 *   |fl(a b) - a b| <= |v_a| e_b + |v_b| e_a + e_a e_b + u |fl(a b)|,
 * (u = 2^-53; |fl(x) - x| <= u |fl(x)| holds for a normal result).  Two facts make the
 * bounds rigorous:
 *  - every value v of degree d computed here is an integer multiple of 2^(-50 d) (the
 *    grid, and rounding a multiple of 2^-k to a double gives a multiple of 2^-k), so a
 *    non-zero v is at least 2^-1000 and never subnormal: the relative rounding bound
 *    holds for every value;
 *  - the bounds e themselves are computed in rounded arithmetic (u |v| is exact: a
 *    multiple of 2^-1053 is a double): each other rounding makes a bound smaller by at
 *    most a factor (1 - u), or by an absolute 2^-1075 when the result is subnormal.
 *    Along the at most 2^12 operations of a prepared point and a predicate that is
 *    covered by the factor BOUND_SLACK; the subnormal losses, at most 2^12 of them, each
 *    grown by at most 2^130 (no value here is larger), stay below 2^-933, covered by
 *    the absolute UNDERFLOW_SLACK.
 * A certified sign thus needs |v| > e * BOUND_SLACK + UNDERFLOW_SLACK: values below
 * 2^-900 (only from features a few grid steps wide) always go to the exact stage. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "arrange/implicit.h"
#include "common/expansion.h"
#include "common/predicates.h"

/* Unit roundoff of IEEE double. */
#define U 0x1p-53
/* Covers the rounding of the bound computations themselves (see above). */
#define BOUND_SLACK (1.0 + 0x1p-40)
/* Covers bounds lost to subnormal underflow (see above). */
#define UNDERFLOW_SLACK 0x1p-900
/* arr_coords trusts the rounded quotient h[k] / h[3] when both have a relative error
 * below 2^-55 (u / 4): with the division's own rounding the result is within 2 ulps. */
#define COORD_REL_ERR 0x1p-55

/* ---- Running error arithmetic ---------------------------------------------------- */

typedef struct fv {
    double v; /* the rounded value */
    double e; /* a bound on |v - exact| */
} fv;

static inline fv fv_exact(double x)
{
    fv r = {x, 0.0};
    return r;
}

static inline fv fv_add(fv a, fv b)
{
    double v = a.v + b.v;
    fv r = {v, a.e + b.e + U * fabs(v)};
    return r;
}

static inline fv fv_sub(fv a, fv b)
{
    double v = a.v - b.v;
    fv r = {v, a.e + b.e + U * fabs(v)};
    return r;
}

static inline fv fv_mul(fv a, fv b)
{
    double v = a.v * b.v;
    fv r = {v, fabs(a.v) * b.e + fabs(b.v) * a.e + a.e * b.e + U * fabs(v)};
    return r;
}

/* The sign of the exact value when the bound certifies it, else 0. */
static inline int fv_sign(fv a)
{
    double bound = a.e * BOUND_SLACK + UNDERFLOW_SLACK;
    if (a.v > bound)
        return 1;
    if (-a.v > bound)
        return -1;
    return 0;
}

/* Exact difference of two grid coordinates, rounded (|b - a| <= 32 may need 55 bits). */
static inline fv fv_diff(double a, double b)
{
    return fv_sub(fv_exact(a), fv_exact(b));
}

static inline void fv_diff3(const double *a, const double *b, fv o[3])
{
    for (int k = 0; k < 3; k++)
        o[k] = fv_diff(a[k], b[k]);
}

static inline void fv_cross(const fv a[3], const fv b[3], fv o[3])
{
    fv x = fv_sub(fv_mul(a[1], b[2]), fv_mul(a[2], b[1]));
    fv y = fv_sub(fv_mul(a[2], b[0]), fv_mul(a[0], b[2]));
    fv z = fv_sub(fv_mul(a[0], b[1]), fv_mul(a[1], b[0]));
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static inline fv fv_dot(const fv a[3], const fv b[3])
{
    return fv_add(fv_add(fv_mul(a[0], b[0]), fv_mul(a[1], b[1])), fv_mul(a[2], b[2]));
}

/* The normal (b - a) x (c - a) of the triangle a, b, c (degree 2). */
static inline void fv_normal(const double *a, const double *b, const double *c, fv n[3])
{
    fv e1[3], e2[3];
    fv_diff3(b, a, e1);
    fv_diff3(c, a, e2);
    fv_cross(e1, e2, n);
}

static inline const double *vtx(const double *xyz, int64_t i)
{
    return xyz + 3 * i;
}

/* The homogeneous coordinates of a prepared point as running-error values. */
static inline void point_fv(const arr_point *p, fv X[4])
{
    for (int k = 0; k < 4; k++) {
        X[k].v = p->h[k];
        X[k].e = p->herr[k];
    }
}

/* ---- Preparing a point ----------------------------------------------------------- */

/* The construction in floating point: X[0..2], X[3] = W (the formulas of
 * implicit_exact.c, term for term). */
static void construct_fv(const double *xyz, const arr_point *p, fv X[4])
{
    switch (p->kind) {
    case ARR_EXPLICIT: {
        const double *a = vtx(xyz, p->v[0]);
        for (int k = 0; k < 3; k++)
            X[k] = fv_exact(a[k]);
        X[3] = fv_exact(1.0);
        break;
    }
    case ARR_LPI: {
        /* W = n . (q - p), t = n . (r - p) / W, X = p W + (n . (r - p)) (q - p). */
        const double *a = vtx(xyz, p->v[0]), *b = vtx(xyz, p->v[1]);
        fv n[3], dq[3], dr[3];
        fv_normal(vtx(xyz, p->v[2]), vtx(xyz, p->v[3]), vtx(xyz, p->v[4]), n);
        fv_diff3(b, a, dq);
        fv_diff3(vtx(xyz, p->v[2]), a, dr);
        fv w = fv_dot(n, dq), num = fv_dot(n, dr);
        for (int k = 0; k < 3; k++)
            X[k] = fv_add(fv_mul(fv_exact(a[k]), w), fv_mul(num, dq[k]));
        X[3] = w;
        break;
    }
    case ARR_TPI: {
        /* Cramer: n_i . x = d_i = n_i . a_i; W = det[n0; n1; n2],
         * X = d0 (n1 x n2) + d1 (n2 x n0) + d2 (n0 x n1). */
        fv n[3][3], d[3], c[3][3];
        for (int i = 0; i < 3; i++) {
            const double *a = vtx(xyz, p->v[3 * i]);
            fv_normal(a, vtx(xyz, p->v[3 * i + 1]), vtx(xyz, p->v[3 * i + 2]), n[i]);
            fv av[3] = {fv_exact(a[0]), fv_exact(a[1]), fv_exact(a[2])};
            d[i] = fv_dot(n[i], av);
        }
        for (int i = 0; i < 3; i++)
            fv_cross(n[(i + 1) % 3], n[(i + 2) % 3], c[i]);
        for (int k = 0; k < 3; k++)
            X[k] = fv_add(fv_add(fv_mul(d[0], c[0][k]), fv_mul(d[1], c[1][k])),
                          fv_mul(d[2], c[2][k]));
        X[3] = fv_dot(n[0], c[0]);
        break;
    }
    case ARR_SSI: {
        /* In the projection (i, j): W = (q - p) x (s - r), num = (r - p) x (s - r),
         * X = p W + num (q - p) (the point p + t (q - p), t = num / W, in 3-D). */
        int i = (p->axis + 1) % 3, j = (p->axis + 2) % 3;
        const double *a = vtx(xyz, p->v[0]), *b = vtx(xyz, p->v[1]);
        const double *r = vtx(xyz, p->v[2]), *s = vtx(xyz, p->v[3]);
        fv dq[3], rs_i = fv_diff(s[i], r[i]), rs_j = fv_diff(s[j], r[j]);
        fv rp_i = fv_diff(r[i], a[i]), rp_j = fv_diff(r[j], a[j]);
        fv_diff3(b, a, dq);
        fv w = fv_sub(fv_mul(dq[i], rs_j), fv_mul(dq[j], rs_i));
        fv num = fv_sub(fv_mul(rp_i, rs_j), fv_mul(rp_j, rs_i));
        for (int k = 0; k < 3; k++)
            X[k] = fv_add(fv_mul(fv_exact(a[k]), w), fv_mul(num, dq[k]));
        X[3] = w;
        break;
    }
    default: { /* ARR_LIFT */
        /* n . (x - a) = 0 with x_i = l0, x_j = l1: W = n_axis,
         * X_axis = n_axis a_axis - n_i (l0 - a_i) - n_j (l1 - a_j), X_i = l0 W, X_j = l1 W. */
        int ax = p->axis, i = (ax + 1) % 3, j = (ax + 2) % 3;
        const double *a = vtx(xyz, p->v[0]);
        fv n[3];
        fv_normal(a, vtx(xyz, p->v[1]), vtx(xyz, p->v[2]), n);
        fv w = n[ax];
        X[ax] = fv_sub(fv_sub(fv_mul(w, fv_exact(a[ax])),
                              fv_mul(n[i], fv_diff(p->lift[0], a[i]))),
                       fv_mul(n[j], fv_diff(p->lift[1], a[j])));
        X[i] = fv_mul(fv_exact(p->lift[0]), w);
        X[j] = fv_mul(fv_exact(p->lift[1]), w);
        X[3] = w;
        break;
    }
    }
}

/* The number of explicit vertices a construction uses. */
static int kind_nverts(int kind)
{
    static const int nv[5] = {1, 5, 9, 4, 3};
    return nv[kind];
}

int arr_point_valid(const double *xyz, const arr_point *p)
{
    if (p->kind > ARR_LIFT || p->axis > 2)
        return 0;
    for (int m = 0; m < kind_nverts(p->kind); m++) {
        const double *a = vtx(xyz, p->v[m]);
        if (!arr_on_grid(a[0]) || !arr_on_grid(a[1]) || !arr_on_grid(a[2]))
            return 0;
    }
    if (p->kind == ARR_LIFT && (!arr_on_grid(p->lift[0]) || !arr_on_grid(p->lift[1])))
        return 0;
    return 1;
}

/* The double nearest the top of a compressed expansion, and a bound on its error: the
 * largest component of a compressed expansion is within one ulp (<= 2u of itself) of
 * the value. */
static void round_expansion(int n, const double *e, double *v, double *err)
{
    *v = e[n - 1];
    *err = 2.0 * U * fabs(*v);
}

int arr_point_prepare(const double *xyz, arr_point *p)
{
    p->xok = 0;
    if (!arr_point_valid(xyz, p))
        return 0;
    fv X[4];
    construct_fv(xyz, p, X);
    /* herr with the slacks applied, so that it is a bound by itself (a zero bound is
     * exact: a non-zero error would be a multiple of the grid, far above any bound
     * that can round to zero). */
    for (int k = 0; k < 4; k++) {
        p->h[k] = X[k].v;
        p->herr[k] = X[k].e > 0.0 ? X[k].e * BOUND_SLACK + UNDERFLOW_SLACK : 0.0;
    }
    if (fv_sign(X[3]) != 0)
        return 1;
    /* The rounded W does not certify its sign (a nearly degenerate construction): take
     * all four coordinates from the exact values, so every predicate can rely on the
     * sign of h[3] (and gets tighter bounds for such a point). */
    arr_exact ex;
    if (!arr_point_exact(xyz, p, &ex))
        return 0;
    if (expn_sign(ex.n[3], ex.c[3]) == 0)
        return 0;
    for (int k = 0; k < 4; k++)
        round_expansion(ex.n[k], ex.c[k], &p->h[k], &p->herr[k]);
    return 1;
}

/* ---- Filters ----------------------------------------------------------------------- */

/* The sign of W of a prepared point (certified by arr_point_prepare). */
static inline int wsign(const arr_point *p)
{
    return p->h[3] > 0.0 ? 1 : -1;
}

int arr_orient3d_filter(const arr_points *P, int64_t a, int64_t b, int64_t c, int64_t q)
{
    /* orient3d(a, b, c, q) = -n . (q - a), n = (b - a) x (c - a); for q = X / W it is
     * -sign(W) sign(n . (X - W a)) (implicit_exact.c evaluates the same polynomial). */
    const double *pa = vtx(P->xyz, a);
    const arr_point *pq = &P->pts[q];
    fv n[3], X[4], t[3];
    fv_normal(pa, vtx(P->xyz, b), vtx(P->xyz, c), n);
    point_fv(pq, X);
    for (int k = 0; k < 3; k++)
        t[k] = fv_sub(X[k], fv_mul(X[3], fv_exact(pa[k])));
    return -fv_sign(fv_dot(n, t)) * wsign(pq);
}

int arr_orient2d_filter(const arr_points *P, int64_t p, int64_t q, int64_t r, int axis)
{
    /* det of the rows (X_i, X_j, W) = Wp Wq Wr orient2d(p, q, r), expanded along W. */
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    const arr_point *pt[3] = {&P->pts[p], &P->pts[q], &P->pts[r]};
    fv X[3][4];
    for (int m = 0; m < 3; m++)
        point_fv(pt[m], X[m]);
    fv det = fv_exact(0.0);
    for (int m = 0; m < 3; m++) {
        const fv *u = X[(m + 1) % 3], *v = X[(m + 2) % 3];
        fv minor = fv_sub(fv_mul(u[i], v[j]), fv_mul(u[j], v[i]));
        fv term = fv_mul(X[m][3], minor);
        det = m == 0 ? term : fv_add(det, term);
    }
    return fv_sign(det) * wsign(pt[0]) * wsign(pt[1]) * wsign(pt[2]);
}

int arr_cmp_filter(const arr_points *P, int64_t p, int64_t q, int axis)
{
    /* p[axis] - q[axis] = (Xp Wq - Xq Wp) / (Wp Wq). */
    const arr_point *pp = &P->pts[p], *pq = &P->pts[q];
    fv Xp[4], Xq[4];
    point_fv(pp, Xp);
    point_fv(pq, Xq);
    fv d = fv_sub(fv_mul(Xp[axis], Xq[3]), fv_mul(Xq[axis], Xp[3]));
    return fv_sign(d) * wsign(pp) * wsign(pq);
}

/* ---- Shortcuts: zero by construction --------------------------------------------- */

static inline int in3(int64_t x, int64_t a, int64_t b, int64_t c)
{
    return x == a || x == b || x == c;
}

/* 1 when the vertex triples v[0..2] and {a, b, c} are the same set. */
static inline int same_triangle(const int64_t *v, int64_t a, int64_t b, int64_t c)
{
    return in3(v[0], a, b, c) && in3(v[1], a, b, c) && in3(v[2], a, b, c) &&
           in3(a, v[0], v[1], v[2]) && in3(b, v[0], v[1], v[2]) && in3(c, v[0], v[1], v[2]);
}

/* 1 when q lies on the plane of a, b, c because of how it is built (whatever the
 * coordinates): one of its planes is that triangle, or it is on a line through two of
 * its vertices, or the triangle is degenerate by index. */
static int on_plane_by_construction(const arr_point *q, int64_t a, int64_t b, int64_t c)
{
    if (a == b || b == c || a == c)
        return 1;
    switch (q->kind) {
    case ARR_EXPLICIT:
        return in3(q->v[0], a, b, c);
    case ARR_LPI:
        return same_triangle(q->v + 2, a, b, c) ||
               (in3(q->v[0], a, b, c) && in3(q->v[1], a, b, c));
    case ARR_TPI:
        return same_triangle(q->v, a, b, c) || same_triangle(q->v + 3, a, b, c) ||
               same_triangle(q->v + 6, a, b, c);
    case ARR_SSI:
        return in3(q->v[0], a, b, c) && in3(q->v[1], a, b, c);
    default:
        return same_triangle(q->v, a, b, c);
    }
}

/* 1 when t's projection lies on the projected line through the explicit vertices e1, e2
 * because of how t is built: t is e1 or e2, or on the 3-D line e1 e2 (LPI, SSI), or an
 * SSI of this projection whose second segment is e1 e2. */
static int on_line_by_construction(const arr_point *t, int64_t e1, int64_t e2, int axis)
{
    switch (t->kind) {
    case ARR_EXPLICIT:
        return t->v[0] == e1 || t->v[0] == e2;
    case ARR_LPI:
        return (t->v[0] == e1 && t->v[1] == e2) || (t->v[0] == e2 && t->v[1] == e1);
    case ARR_SSI:
        return (t->v[0] == e1 && t->v[1] == e2) || (t->v[0] == e2 && t->v[1] == e1) ||
               (t->axis == axis &&
                ((t->v[2] == e1 && t->v[3] == e2) || (t->v[2] == e2 && t->v[3] == e1)));
    default:
        return 0;
    }
}

static int collinear_by_construction(const arr_points *P, int64_t p, int64_t q, int64_t r,
                                     int axis)
{
    if (p == q || q == r || p == r)
        return 1;
    const arr_point *pt[3] = {&P->pts[p], &P->pts[q], &P->pts[r]};
    for (int m = 0; m < 3; m++) {
        const arr_point *u = pt[(m + 1) % 3], *v = pt[(m + 2) % 3];
        if (u->kind == ARR_EXPLICIT && v->kind == ARR_EXPLICIT &&
            (u->v[0] == v->v[0] || on_line_by_construction(pt[m], u->v[0], v->v[0], axis)))
            return 1;
    }
    return 0;
}

/* ---- The predicates ---------------------------------------------------------------- */

/* The sign of a rounded value: the answer when the exact stage cannot run (off grid). */
static inline int rounded_sign(double v)
{
    return (v > 0.0) - (v < 0.0);
}

int arr_orient3d(const arr_points *P, int64_t a, int64_t b, int64_t c, int64_t q)
{
    const arr_point *pq = &P->pts[q];
    if (on_plane_by_construction(pq, a, b, c))
        return 0;
    if (pq->kind == ARR_EXPLICIT)
        return mfg_orient3d(vtx(P->xyz, a), vtx(P->xyz, b), vtx(P->xyz, c),
                            vtx(P->xyz, pq->v[0]));
    int s = arr_orient3d_filter(P, a, b, c, q);
    if (s)
        return s;
    s = arr_orient3d_exact(P, a, b, c, q);
    if (s != ARR_NOT_EXACT)
        return s;
    const double *pa = vtx(P->xyz, a);
    fv n[3], X[4], t[3];
    fv_normal(pa, vtx(P->xyz, b), vtx(P->xyz, c), n);
    point_fv(pq, X);
    for (int k = 0; k < 3; k++)
        t[k] = fv_sub(X[k], fv_mul(X[3], fv_exact(pa[k])));
    return -rounded_sign(fv_dot(n, t).v) * wsign(pq);
}

int arr_orient2d(const arr_points *P, int64_t p, int64_t q, int64_t r, int axis)
{
    if (collinear_by_construction(P, p, q, r, axis))
        return 0;
    const arr_point *pp = &P->pts[p], *pq = &P->pts[q], *pr = &P->pts[r];
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    if (pp->kind == ARR_EXPLICIT && pq->kind == ARR_EXPLICIT && pr->kind == ARR_EXPLICIT) {
        const double *a = vtx(P->xyz, pp->v[0]), *b = vtx(P->xyz, pq->v[0]);
        const double *c = vtx(P->xyz, pr->v[0]);
        return mfg_orient2d(a[i], a[j], b[i], b[j], c[i], c[j]);
    }
    int s = arr_orient2d_filter(P, p, q, r, axis);
    if (s)
        return s;
    s = arr_orient2d_exact(P, p, q, r, axis);
    if (s != ARR_NOT_EXACT)
        return s;
    /* Off the grid: the rounded determinant. */
    double d = 0.0;
    const arr_point *pt[3] = {pp, pq, pr};
    for (int m = 0; m < 3; m++) {
        const double *u = pt[(m + 1) % 3]->h, *v = pt[(m + 2) % 3]->h;
        d += pt[m]->h[3] * (u[i] * v[j] - u[j] * v[i]);
    }
    return rounded_sign(d) * wsign(pp) * wsign(pq) * wsign(pr);
}

int arr_cmp(const arr_points *P, int64_t p, int64_t q, int axis)
{
    if (p == q)
        return 0;
    const arr_point *pp = &P->pts[p], *pq = &P->pts[q];
    if (pp->kind == ARR_EXPLICIT && pq->kind == ARR_EXPLICIT) {
        double x = vtx(P->xyz, pp->v[0])[axis], y = vtx(P->xyz, pq->v[0])[axis];
        return (x > y) - (x < y);
    }
    int s = arr_cmp_filter(P, p, q, axis);
    if (s)
        return s;
    s = arr_cmp_exact(P, p, q, axis);
    if (s != ARR_NOT_EXACT)
        return s;
    return rounded_sign(pp->h[axis] * pq->h[3] - pq->h[axis] * pp->h[3]) * wsign(pp) *
           wsign(pq);
}

int arr_same(const arr_points *P, int64_t p, int64_t q)
{
    if (p == q)
        return 1;
    const arr_point *pp = &P->pts[p], *pq = &P->pts[q];
    if (pp->kind == ARR_EXPLICIT && pq->kind == ARR_EXPLICIT) {
        const double *a = vtx(P->xyz, pp->v[0]), *b = vtx(P->xyz, pq->v[0]);
        return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
    }
    for (int k = 0; k < 3; k++)
        if (arr_cmp_filter(P, p, q, k) != 0)
            return 0;
    int s = arr_same_exact(P, p, q);
    if (s != ARR_NOT_EXACT)
        return s;
    double x[3], y[3];
    arr_coords(P, p, x);
    arr_coords(P, q, y);
    return x[0] == y[0] && x[1] == y[1] && x[2] == y[2];
}

void arr_coords(const arr_points *P, int64_t p, double out[3])
{
    arr_point *pt = &P->pts[p];
    if (pt->kind == ARR_EXPLICIT) {
        const double *a = vtx(P->xyz, pt->v[0]);
        out[0] = a[0];
        out[1] = a[1];
        out[2] = a[2];
        return;
    }
    if (pt->xok) {
        memcpy(out, pt->x, sizeof pt->x);
        return;
    }
    /* The rounded quotient when both terms are known to u / 4 (see COORD_REL_ERR). */
    int trusted = pt->herr[3] * BOUND_SLACK + UNDERFLOW_SLACK <= COORD_REL_ERR * fabs(pt->h[3]);
    for (int k = 0; k < 3 && trusted; k++)
        trusted = pt->herr[k] == 0.0 ||
                  pt->herr[k] * BOUND_SLACK + UNDERFLOW_SLACK <= COORD_REL_ERR * fabs(pt->h[k]);
    if (trusted || !arr_coords_exact(P, p, out))
        for (int k = 0; k < 3; k++)
            out[k] = pt->h[k] / pt->h[3];
    memcpy(pt->x, out, sizeof pt->x);
    pt->xok = 1;
}
