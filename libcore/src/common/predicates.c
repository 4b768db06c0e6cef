/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* predicates.c - exact 2-D predicates: float filter first, expansion arithmetic when the
 * filter cannot certify the sign (Shewchuk, "Adaptive Precision Floating-Point Arithmetic
 * and Fast Robust Geometric Predicates", 1997). Written for mfgeom; no code copied. */
#include <math.h>
#include <stddef.h>

#include "common/expansion.h"
#include "common/predicates.h"

/* Unit roundoff of IEEE double (2^-53). */
#define U 1.1102230246251565e-16

/* Expansion arithmetic (two_sum, scale, sum, product, sign) lives in common/expansion.h,
 * shared with the exact predicates of arrange/. */

/* Largest expansion we ever build: cross^2 with cross up to 16 components -> 512, and
 * the difference against e^2 L^2 (64) -> 576. */
#define EXP_MAX 1024

/* Exact value of p*q + r*s where p, q, r, s are each a difference of two doubles:
 * (p1-p0)(q1-q0) + sgn * (r1-r0)(s1-s0).  Result up to 16 components. */
static int sum_of_diff_products(double p1, double p0, double q1, double q0, double r1,
                                double r0, double s1, double s0, int sgn, double *h)
{
    double p[2], q[2], r[2], s[2], pq[8], rs[8], t1[8], t2[8];
    int plen = expn_diff(p1, p0, p), qlen = expn_diff(q1, q0, q);
    int rlen = expn_diff(r1, r0, r), slen = expn_diff(s1, s0, s);
    int pqlen = expn_mul(plen, p, qlen, q, pq, t1, t2);
    int rslen = expn_mul(rlen, r, slen, s, rs, t1, t2);
    if (sgn < 0)
        return expn_diff_expansions(pqlen, pq, rslen, rs, h);
    return expn_sum(pqlen, pq, rslen, rs, h);
}

/* ---- Predicates ------------------------------------------------------------------- */

static int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy)
{
    double h[16];
    /* (bx-ax)(cy-ay) - (by-ay)(cx-ax) */
    int n = sum_of_diff_products(bx, ax, cy, ay, by, ay, cx, ax, -1, h);
    return expn_sign(n, h);
}

int mfg_orient2d(double ax, double ay, double bx, double by, double cx, double cy)
{
    int sign = mfg_orient2d_filter(ax, ay, bx, by, cx, cy); /* 4u bound: predicates.h */
    return sign ? sign : orient2d_exact(ax, ay, bx, by, cx, cy);
}

int mfg_dot2d(double ax, double ay, double bx, double by, double cx, double cy)
{
    double l = (bx - ax) * (cx - ax);
    double r = (by - ay) * (cy - ay);
    double d = l + r;
    double bound = 4.0 * U * (fabs(l) + fabs(r));
    if (d > bound)
        return 1;
    if (-d > bound)
        return -1;
    double h[16];
    int n = sum_of_diff_products(bx, ax, cx, ax, by, ay, cy, ay, +1, h);
    return expn_sign(n, h);
}

/* Exact sign of |t - a|^2 - tol^2. */
static int point_dist_sign_exact(double tx, double ty, double ax, double ay, double tol)
{
    double d2[16], e2[2], diff[18];
    int n = sum_of_diff_products(ax, tx, ax, tx, ay, ty, ay, ty, +1, d2);
    int elen = expn_product(tol, tol, e2);
    int m = expn_diff_expansions(n, d2, elen, e2, diff);
    return expn_sign(m, diff);
}

/* 1 when |t - a| <= tol exactly. */
static int point_within(double tx, double ty, double ax, double ay, double tol)
{
    double dx = ax - tx, dy = ay - ty;
    double s = dx * dx + dy * dy;
    double e = tol * tol;
    /* s carries <= 4u relative error (all terms non-negative), e <= u: 8u covers both.
     * Tiny magnitudes may be subnormal, where relative bounds fail: go exact. */
    double bound = 8.0 * U * (s + e);
    if (s + e > 1e-280) {
        if (s - e > bound)
            return 0;
        if (e - s > bound)
            return 1;
    }
    return point_dist_sign_exact(tx, ty, ax, ay, tol) <= 0;
}

/* Exact sign of cross^2 - tol^2 * |b - a|^2, cross = (b - a) x (t - a). */
static int line_dist_sign_exact(double tx, double ty, double ax, double ay, double bx,
                                double by, double tol)
{
    double cross[16], cross2[EXP_MAX / 2], len2[16], e2[2], rhs[64];
    double diff[EXP_MAX], t1[EXP_MAX / 2], t2[EXP_MAX / 2];
    int cn = sum_of_diff_products(bx, ax, ty, ay, by, ay, tx, ax, -1, cross);
    int c2n = expn_mul(cn, cross, cn, cross, cross2, t1, t2);
    int ln = sum_of_diff_products(bx, ax, bx, ax, by, ay, by, ay, +1, len2);
    int en = expn_product(tol, tol, e2);
    int rn = expn_mul(ln, len2, en, e2, rhs, t1, t2);
    int dn = expn_diff_expansions(c2n, cross2, rn, rhs, diff);
    return expn_sign(dn, diff);
}

int mfg_segment_within(double tx, double ty, double ax, double ay, double bx, double by,
                       double tol)
{
    /* The nearest point of the segment is an endpoint unless the foot of the
     * perpendicular falls strictly inside; the distance is then |cross| / |b - a|. */
    if (point_within(tx, ty, ax, ay, tol) || point_within(tx, ty, bx, by, tol))
        return 1;
    if (ax == bx && ay == by)
        return 0;
    if (mfg_dot2d(ax, ay, bx, by, tx, ty) <= 0 || mfg_dot2d(bx, by, ax, ay, tx, ty) <= 0)
        return 0;
    double ux = bx - ax, uy = by - ay;
    double l = ux * (ty - ay), r = uy * (tx - ax);
    double c = l - r;
    double cerr = 4.0 * U * (fabs(l) + fabs(r));
    double len2 = ux * ux + uy * uy; /* <= 4u relative error */
    double rhs = tol * tol * len2;    /* <= 7u relative error */
    double ac = fabs(c);
    if (ac + rhs > 1e-280 && rhs < 1e280) {
        double lo = ac > cerr ? (ac - cerr) * (ac - cerr) * (1.0 - 4.0 * U) : 0.0;
        double hi = (ac + cerr) * (ac + cerr) * (1.0 + 4.0 * U);
        if (lo > rhs * (1.0 + 16.0 * U))
            return 0;
        if (hi < rhs * (1.0 - 16.0 * U))
            return 1;
    }
    return line_dist_sign_exact(tx, ty, ax, ay, bx, by, tol) <= 0;
}

/* ---- Sphere predicates ------------------------------------------------------------ */

/* Exact x*(p*q - r*s) as an expansion (up to 8 components); callers sum three. */
static int cofactor_term(double x, double p, double q, double r, double s, double *h)
{
    double pq[2], rs[2], d[4];
    int pqn = expn_product(p, q, pq), rsn = expn_product(r, s, rs);
    int n = expn_diff_expansions(pqn, pq, rsn, rs, d);
    return expn_scale(n, d, x, h);
}

/* Exact det[a, b, c] on raw coordinates, as an expansion of up to 24 components. */
static int det3_expansion(const double a[3], const double b[3], const double c[3], double *h)
{
    double t0[8], t1[8], t2[8], s01[16];
    int n0 = cofactor_term(a[0], b[1], c[2], b[2], c[1], t0);
    int n1 = cofactor_term(a[1], b[2], c[0], b[0], c[2], t1);
    int n2 = cofactor_term(a[2], b[0], c[1], b[1], c[0], t2);
    int n01 = expn_sum(n0, t0, n1, t1, s01);
    return expn_sum(n01, s01, n2, t2, h);
}

int mfg_orient3(const double a[3], const double b[3], const double c[3])
{
    double m0 = b[1] * c[2] - b[2] * c[1];
    double m1 = b[2] * c[0] - b[0] * c[2];
    double m2 = b[0] * c[1] - b[1] * c[0];
    double det = a[0] * m0 + a[1] * m1 + a[2] * m2;
    /* Each minor has <= 2u relative error of |b_i c_j| + |b_j c_i|; the products and the
     * sum add 3u more: 8u on the sum of absolute terms is a safe bound. */
    double perm = fabs(a[0]) * (fabs(b[1] * c[2]) + fabs(b[2] * c[1])) +
                  fabs(a[1]) * (fabs(b[2] * c[0]) + fabs(b[0] * c[2])) +
                  fabs(a[2]) * (fabs(b[0] * c[1]) + fabs(b[1] * c[0]));
    double bound = 8.0 * U * perm;
    if (perm > 1e-250) {
        if (det > bound)
            return 1;
        if (-det > bound)
            return -1;
    }
    double s[24];
    int n = det3_expansion(a, b, c, s);
    return expn_sign(n, s);
}

int mfg_orient3d(const double a[3], const double b[3], const double c[3], const double d[3])
{
    double adx = a[0] - d[0], ady = a[1] - d[1], adz = a[2] - d[2];
    double bdx = b[0] - d[0], bdy = b[1] - d[1], bdz = b[2] - d[2];
    double cdx = c[0] - d[0], cdy = c[1] - d[1], cdz = c[2] - d[2];
    double bc = bdx * cdy - cdx * bdy, ca = cdx * ady - adx * cdy, ab = adx * bdy - bdx * ady;
    double det = adz * bc + bdz * ca + cdz * ab;
    double perm = (fabs(bdx * cdy) + fabs(cdx * bdy)) * fabs(adz) +
                  (fabs(cdx * ady) + fabs(adx * cdy)) * fabs(bdz) +
                  (fabs(adx * bdy) + fabs(bdx * ady)) * fabs(cdz);
    /* Shewchuk's o3derrboundA = (7 + 56u) u on the permanent of the differences (each
     * difference rounds once, then the 3x3 determinant's products and sums). */
    double bound = (7.0 + 56.0 * U) * U * perm;
    if (perm > 1e-250 && perm < 1e250) {
        if (det > bound)
            return 1;
        if (-det > bound)
            return -1;
    }
    /* Exact: the four determinants of the raw coordinates (no rounded difference). */
    double acd[24], abc[24], bcd[24], abd[24], s1[48], s2[48], s[96];
    int n_acd = det3_expansion(a, c, d, acd), n_abc = det3_expansion(a, b, c, abc);
    int n_bcd = det3_expansion(b, c, d, bcd), n_abd = det3_expansion(a, b, d, abd);
    int n1 = expn_sum(n_acd, acd, n_abc, abc, s1);
    int n2 = expn_sum(n_bcd, bcd, n_abd, abd, s2);
    int n = expn_diff_expansions(n1, s1, n2, s2, s);
    return expn_sign(n, s);
}

int mfg_orient3d_vec(const double o[3], const double a[3], const double b[3], const double v[3])
{
    double ax = a[0] - o[0], ay = a[1] - o[1], az = a[2] - o[2];
    double bx = b[0] - o[0], by = b[1] - o[1], bz = b[2] - o[2];
    double det = v[0] * (ay * bz - az * by) + v[1] * (az * bx - ax * bz) +
                 v[2] * (ax * by - ay * bx);
    double perm = fabs(v[0]) * (fabs(ay * bz) + fabs(az * by)) +
                  fabs(v[1]) * (fabs(az * bx) + fabs(ax * bz)) +
                  fabs(v[2]) * (fabs(ax * by) + fabs(ay * bx));
    /* Two columns are rounded differences, the third is exact: fewer roundings than in
     * orient3d, so its bound (7 + 56u) u on the permanent holds a fortiori. */
    double bound = (7.0 + 56.0 * U) * U * perm;
    if (perm > 1e-250 && perm < 1e250) {
        if (det > bound)
            return 1;
        if (-det > bound)
            return -1;
    }
    /* Exact: det[a - o, b - o, v] = det[a, b, v] + det[o, a, v] + det[b, o, v]. */
    double abv[24], oav[24], bov[24], s1[48], s[72];
    int n_abv = det3_expansion(a, b, v, abv), n_oav = det3_expansion(o, a, v, oav);
    int n_bov = det3_expansion(b, o, v, bov);
    int n1 = expn_sum(n_abv, abv, n_oav, oav, s1);
    int n = expn_sum(n1, s1, n_bov, bov, s);
    return expn_sign(n, s);
}

/* Exact a . b as an expansion of up to 6 components. */
static int dot3_expansion(const double a[3], const double b[3], double *e)
{
    double h[6], t[2];
    int n = expn_product(a[0], b[0], e);
    for (int k = 1; k < 3; k++) {
        int tn = expn_product(a[k], b[k], t);
        n = expn_sum(n, e, tn, t, h);
        for (int i = 0; i < n; i++)
            e[i] = h[i];
    }
    return n;
}

int mfg_cross_dot_sign(const double a[3], const double b[3], const double c[3],
                       const double d[3])
{
    double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
    double bd = b[0] * d[0] + b[1] * d[1] + b[2] * d[2];
    double ad = a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
    double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
    double acm = fabs(a[0] * c[0]) + fabs(a[1] * c[1]) + fabs(a[2] * c[2]);
    double bdm = fabs(b[0] * d[0]) + fabs(b[1] * d[1]) + fabs(b[2] * d[2]);
    double adm = fabs(a[0] * d[0]) + fabs(a[1] * d[1]) + fabs(a[2] * d[2]);
    double bcm = fabs(b[0] * c[0]) + fabs(b[1] * c[1]) + fabs(b[2] * c[2]);
    double v = ac * bd - ad * bc;
    double mag = acm * bdm + adm * bcm;
    /* Each dot carries <= 3u of its absolute sum, each product 7u, the difference 1u
     * more: 16u on the sum of absolute products bounds the error. */
    double bound = 16.0 * U * mag;
    if (mag > 1e-250 && mag < 1e250) {
        if (v > bound)
            return 1;
        if (-v > bound)
            return -1;
    }
    double eac[6], ebd[6], ead[6], ebc[6], p[72], q[72], s[144], t1[72], t2[72];
    int nac = dot3_expansion(a, c, eac), nbd = dot3_expansion(b, d, ebd);
    int nad = dot3_expansion(a, d, ead), nbc = dot3_expansion(b, c, ebc);
    int np = expn_mul(nac, eac, nbd, ebd, p, t1, t2);
    int nqq = expn_mul(nad, ead, nbc, ebc, q, t1, t2);
    int ns = expn_diff_expansions(np, p, nqq, q, s);
    return expn_sign(ns, s);
}

/* Exact test p*q == r*s: the (rounded product, error) pair of a product is unique. */
static int products_equal(double p, double q, double r, double s)
{
    double h1, l1, h2, l2;
    expn_two_product(p, q, &h1, &l1);
    expn_two_product(r, s, &h2, &l2);
    return h1 == h2 && l1 == l2;
}

int mfg_parallel3(const double a[3], const double b[3])
{
    if (!products_equal(a[1], b[2], a[2], b[1]) || !products_equal(a[2], b[0], a[0], b[2]) ||
        !products_equal(a[0], b[1], a[1], b[0]))
        return 0;
    return mfg_dot3_sign(a, b);
}

int mfg_dot3_sign(const double a[3], const double b[3])
{
    double p0 = a[0] * b[0], p1 = a[1] * b[1], p2 = a[2] * b[2];
    double d = p0 + p1 + p2;
    double mag = fabs(p0) + fabs(p1) + fabs(p2);
    double bound = 4.0 * U * mag;
    if (mag > 1e-250) {
        if (d > bound)
            return 1;
        if (-d > bound)
            return -1;
    }
    double e[6];
    int n = dot3_expansion(a, b, e);
    return expn_sign(n, e);
}

/* p*q - r*s accurately: the rounding errors of both products are carried along. */
static double diff_of_products(double p, double q, double r, double s)
{
    double h1, l1, h2, l2;
    expn_two_product(p, q, &h1, &l1);
    expn_two_product(r, s, &h2, &l2);
    return (h1 - h2) + (l1 - l2);
}

void mfg_cross3_accurate(const double a[3], const double b[3], double out[3])
{
    double x = diff_of_products(a[1], b[2], a[2], b[1]);
    double y = diff_of_products(a[2], b[0], a[0], b[2]);
    double z = diff_of_products(a[0], b[1], a[1], b[0]);
    out[0] = x;
    out[1] = y;
    out[2] = z;
}
