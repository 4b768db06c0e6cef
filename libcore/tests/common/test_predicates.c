/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_predicates.c - the exact predicates against integer arithmetic and hard cases. */
#include <math.h>
#include <stdint.h>

#include "mfg_test.h"
#include "common/predicates.h"

static int sgn_ll(long long v) { return (v > 0) - (v < 0); }

/* Integer inputs below 2^20: every product fits int64, so this is an exact reference. */
static void test_orient_integer(void)
{
    for (int k = 0; k < 200000; k++) {
        long long a[6];
        for (int i = 0; i < 6; i++)
            a[i] = rng_int(-20, 20);
        long long det = (a[2] - a[0]) * (a[5] - a[1]) - (a[3] - a[1]) * (a[4] - a[0]);
        CHECK_EQ_INT(mfg_orient2d((double)a[0], (double)a[1], (double)a[2], (double)a[3],
                                  (double)a[4], (double)a[5]),
                     sgn_ll(det));
        long long dot = (a[2] - a[0]) * (a[4] - a[0]) + (a[3] - a[1]) * (a[5] - a[1]);
        CHECK_EQ_INT(mfg_dot2d((double)a[0], (double)a[1], (double)a[2], (double)a[3],
                               (double)a[4], (double)a[5]),
                     sgn_ll(dot));
    }
}

/* Points on a line through two doubles, nudged by one ulp: naive float orientation
 * gets many of these wrong; the exact answer is consistent under permutation. */
static void test_orient_near_degenerate(void)
{
    double ax = 0.5, ay = 0.5, bx = 12.0, by = 12.0;
    int errors = 0;
    for (int i = 0; i < 256; i++)
        for (int j = 0; j < 256; j++) {
            double cx = 0.5 + (double)i * ldexp(1.0, -53); /* ulp of 0.5 is 2^-53 */
            double cy = 0.5 + (double)j * ldexp(1.0, -53);
            int s = mfg_orient2d(ax, ay, bx, by, cx, cy);
            /* Exact: sign of (b-a)x(c-a) = 11.5*(cy-0.5) - 11.5*(cx-0.5) = sign(cy - cx). */
            int want = (cy > cx) - (cy < cx);
            errors += s != want;
            /* Cyclic permutations give the same sign, swaps the opposite. */
            errors += mfg_orient2d(bx, by, cx, cy, ax, ay) != s;
            errors += mfg_orient2d(bx, by, ax, ay, cx, cy) != -s;
        }
    CHECK_EQ_INT(errors, 0);
}

/* distance <= tol against integer reference: dist^2 <= tol^2 decided in int64. */
static int ref_within(long long tx, long long ty, long long ax, long long ay, long long bx,
                      long long by, long long tol)
{
    long long ux = bx - ax, uy = by - ay, wx = tx - ax, wy = ty - ay;
    long long t2 = tol * tol;
    if (wx * wx + wy * wy <= t2)
        return 1;
    if ((tx - bx) * (tx - bx) + (ty - by) * (ty - by) <= t2)
        return 1;
    long long len2 = ux * ux + uy * uy;
    long long dot = ux * wx + uy * wy;
    if (len2 == 0 || dot <= 0 || dot >= len2)
        return 0;
    long long cross = ux * wy - uy * wx;
    return cross * cross <= t2 * len2;
}

static void test_within_integer(void)
{
    for (int k = 0; k < 300000; k++) {
        long long v[7];
        for (int i = 0; i < 6; i++)
            v[i] = rng_int(-30, 30);
        v[6] = rng_int(0, 12);
        CHECK_EQ_INT(mfg_segment_within((double)v[0], (double)v[1], (double)v[2], (double)v[3],
                                        (double)v[4], (double)v[5], (double)v[6]),
                     ref_within(v[0], v[1], v[2], v[3], v[4], v[5], v[6]));
    }
}

/* Distance exactly tol, and one ulp of tol either side, at many scales. */
static void test_within_boundary(void)
{
    for (int e = -40; e <= 40; e += 5) {
        double s = ldexp(1.0, e);
        /* 3-4-5 triangle: |(3s, 4s) - 0| = 5s exactly. */
        CHECK(mfg_segment_within(0, 0, 3 * s, 4 * s, 10 * s, 4 * s, 5 * s) == 1);
        CHECK(mfg_segment_within(0, 0, 3 * s, 4 * s, 10 * s, 4 * s, nextafter(5 * s, 0)) == 0);
        /* Perpendicular distance 4s to the segment y = 4s (foot at x = 0 inside). */
        CHECK(mfg_segment_within(0, 0, -7 * s, 4 * s, 9 * s, 4 * s, 4 * s) == 1);
        CHECK(mfg_segment_within(0, 0, -7 * s, 4 * s, 9 * s, 4 * s, nextafter(4 * s, 0)) == 0);
        /* Slanted line at distance 1/sqrt(2)*s: tol^2 vs 0.5 s^2 is never exact in
         * doubles, so the neighbouring doubles of sqrt(0.5)s decide differently. */
        double r = sqrt(0.5) * s;
        int lo = mfg_segment_within(0, 0, -5 * s, 6 * s, 6 * s, -5 * s, nextafter(r, 0));
        int hi = mfg_segment_within(0, 0, -5 * s, 6 * s, 6 * s, -5 * s, nextafter(r, 10 * s));
        CHECK(lo == 0 && hi == 1);
    }
}

/* det3 and dot3 against int64 arithmetic on small integers, including many zeros. */
static void test_sphere_integer(void)
{
    int bad = 0;
    for (int k = 0; k < 200000; k++) {
        long long v[9];
        double a[3], b[3], c[3];
        for (int i = 0; i < 9; i++)
            v[i] = rng_int(-6, 6);
        for (int i = 0; i < 3; i++) {
            a[i] = (double)v[i];
            b[i] = (double)v[3 + i];
            c[i] = (double)v[6 + i];
        }
        long long det = v[0] * (v[4] * v[8] - v[5] * v[7]) + v[1] * (v[5] * v[6] - v[3] * v[8]) +
                        v[2] * (v[3] * v[7] - v[4] * v[6]);
        long long dot = v[0] * v[3] + v[1] * v[4] + v[2] * v[5];
        bad += mfg_orient3(a, b, c) != sgn_ll(det);
        bad += mfg_dot3_sign(a, b) != sgn_ll(dot);
    }
    CHECK_EQ_INT(bad, 0);
}

/* Three nearly coplanar unit-ish vectors: c = a + b moved by i ulps off the plane.
 * The exact sign is known from the construction (a, b, e_z orthogonal layout). */
static void test_sphere_near_coplanar(void)
{
    int bad = 0;
    double a[3] = {0.6, 0.8, 0.0}, b[3] = {-0.8, 0.6, 0.0};
    for (int i = -64; i <= 64; i++) {
        /* c in the xy-plane except for a z of i * 2^-80: det[a,b,c] = c_z * det2(a,b) =
         * c_z * (0.6*0.6 + 0.8*0.8) whose sign is sign(i) (0.36+0.64 rounds to 1). */
        double c[3] = {0.3 + 1e-17 * i, -0.2, ldexp((double)i, -80)};
        int want = (i > 0) - (i < 0);
        bad += mfg_orient3(a, b, c) != want;
        bad += mfg_orient3(b, c, a) != want; /* cyclic */
        bad += mfg_orient3(b, a, c) != -want; /* swap */
    }
    CHECK_EQ_INT(bad, 0);
    /* duplicated and antipodal inputs are exactly degenerate */
    double p[3] = {0.1, 0.2, 0.9747}, q[3] = {-0.1, -0.2, -0.9747}, r[3] = {0.3, -0.5, 0.1};
    CHECK_EQ_INT(mfg_orient3(p, p, r), 0);
    CHECK_EQ_INT(mfg_orient3(p, q, r), 0);
    CHECK_EQ_INT(mfg_dot3_sign(p, q), -1);
}

int main(void)
{
    test_sphere_integer();
    test_sphere_near_coplanar();
    test_orient_integer();
    test_orient_near_degenerate();
    test_within_integer();
    test_within_boundary();
    return mfg_test_report("test_predicates");
}
