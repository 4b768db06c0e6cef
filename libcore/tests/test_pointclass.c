/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_pointclass.c - point classification: API errors, exact ON, parity, invariance,
 * prepared == one-shot, and agreement with an integer-arithmetic reference. */
#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_test.h"
#include "mfgeom.h"

/* ---- Independent reference on integer inputs -------------------------------------
 * Coordinates are small integers, so every quantity below is an exact int64. The
 * parity rule here is a horizontal ray to +x (the library uses a vertical one), so the
 * two share no code and no convention. */
typedef struct { long long x, y; } ipt;

static int ref_seg_within(ipt t, ipt a, ipt b, long long tol)
{
    long long ux = b.x - a.x, uy = b.y - a.y, wx = t.x - a.x, wy = t.y - a.y;
    long long t2 = tol * tol;
    if (wx * wx + wy * wy <= t2 || (t.x - b.x) * (t.x - b.x) + (t.y - b.y) * (t.y - b.y) <= t2)
        return 1;
    long long len2 = ux * ux + uy * uy, dot = ux * wx + uy * wy;
    if (len2 == 0 || dot <= 0 || dot >= len2)
        return 0;
    long long cross = ux * wy - uy * wx;
    return cross * cross <= t2 * len2;
}

static int ref_classify(const ipt *v, const long long *off, int nrings, ipt t, long long tol)
{
    int par = 0;
    for (int r = 0; r < nrings; r++)
        for (long long k = off[r]; k < off[r + 1]; k++) {
            ipt a = v[k], b = v[k + 1 < off[r + 1] ? k + 1 : off[r]];
            if (ref_seg_within(t, a, b, tol))
                return MFG_ON;
            if ((a.y > t.y) != (b.y > t.y)) {
                /* crossing x > t.x  <=>  sign((b.x-a.x)(t.y-a.y) - (t.x-a.x)(b.y-a.y)) has
                 * the sign of (b.y - a.y) */
                long long c = (b.x - a.x) * (t.y - a.y) - (t.x - a.x) * (b.y - a.y);
                if ((c > 0) == (b.y > a.y))
                    par ^= 1;
            }
        }
    return par ? MFG_IN : MFG_OUT;
}

static int classify1(const double *xy, const int64_t *off, int64_t nr, double x, double y,
                     double tol)
{
    double p[2] = {x, y};
    uint8_t out = 99;
    if (mfg_classify_points(xy, off, nr, p, 1, tol, &out) != MFG_OK)
        return -1;
    return out;
}

static void test_errors(void)
{
    double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
    int64_t off[] = {0, 4};
    double pts[] = {0.5, 0.5};
    uint8_t out[1] = {77};
    CHECK_EQ_INT(mfg_classify_points(NULL, off, 1, pts, 1, 0.1, out), MFG_ERR_NULL);
    CHECK(strstr(mfg_last_error(), "xy") != NULL);
    CHECK_EQ_INT(mfg_classify_points(sq, NULL, 1, pts, 1, 0.1, out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 0, pts, 1, 0.1, out), MFG_ERR_DEGENERATE);
    CHECK(strstr(mfg_last_error(), "no rings") != NULL);
    int64_t off2[] = {0, 2};
    CHECK_EQ_INT(mfg_classify_points(sq, off2, 1, pts, 1, 0.1, out), MFG_ERR_DEGENERATE);
    CHECK(strstr(mfg_last_error(), "at least 3") != NULL);
    int64_t off3[] = {0, 4, 3};
    CHECK_EQ_INT(mfg_classify_points(sq, off3, 2, pts, 1, 0.1, out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, pts, 1, -0.1, out), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "tolerance") != NULL);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, pts, 1, NAN, out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, pts, 1, INFINITY, out), MFG_ERR_INVALID);
    double bad[] = {0, 0, 1, NAN, 1, 1, 0, 1};
    CHECK_EQ_INT(mfg_classify_points(bad, off, 1, pts, 1, 0.1, out), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "vertex 1") != NULL);
    double badp[] = {0.5, INFINITY};
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, badp, 1, 0.1, out), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "point 0") != NULL);
    double huge[] = {0, 0, 1e300, 0, 1, 1};
    int64_t off4[] = {0, 3};
    CHECK_EQ_INT(mfg_classify_points(huge, off4, 1, pts, 1, 0.1, out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, NULL, 1, 0.1, out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, pts, 1, 0.1, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, pts, -1, 0.1, out), MFG_ERR_INVALID);
    CHECK_EQ_INT(out[0], 77); /* nothing half-written */
    CHECK_EQ_INT(mfg_classify_points(sq, off, 1, NULL, 0, 0.1, NULL), MFG_OK);
    CHECK(mfg_last_error()[0] == '\0');

    mfg_region *r = (mfg_region *)&out; /* must be left untouched on failure */
    CHECK_EQ_INT(mfg_region_new(sq, off2, 1, 0.1, &r), MFG_ERR_DEGENERATE);
    CHECK(r == (mfg_region *)&out);
    CHECK_EQ_INT(mfg_region_new(sq, off, 1, 0.1, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_region_classify(NULL, pts, 1, out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_region_new(sq, off, 1, 0.1, &r), MFG_OK);
    CHECK_EQ_INT(mfg_region_classify(r, badp, 1, out), MFG_ERR_INVALID);
    CHECK_EQ_INT(out[0], 77);
    mfg_region_free(r);
    mfg_region_free(NULL);
    CHECK(strcmp(mfg_status_str(MFG_ERR_NOMEM), "out of memory") == 0);
    CHECK(strcmp(mfg_version(), "0.1.0") == 0);
}

/* Square with a square hole; exact ON on edges, vertices, and at distance tol. */
static void test_square_with_hole(void)
{
    double xy[] = {0, 0, 4, 0, 4, 4, 0, 4, 1, 1, 3, 1, 3, 3, 1, 3};
    int64_t off[] = {0, 4, 8};
    CHECK_EQ_INT(classify1(xy, off, 2, 0.5, 0.5, 0), MFG_IN);
    CHECK_EQ_INT(classify1(xy, off, 2, 2, 2, 0), MFG_OUT);
    CHECK_EQ_INT(classify1(xy, off, 2, 5, 5, 0), MFG_OUT);
    CHECK_EQ_INT(classify1(xy, off, 2, 0, 2, 0), MFG_ON);
    CHECK_EQ_INT(classify1(xy, off, 2, 4, 4, 0), MFG_ON);
    CHECK_EQ_INT(classify1(xy, off, 2, 1, 2, 0), MFG_ON);
    CHECK_EQ_INT(classify1(xy, off, 2, 0.5, 2, 0), MFG_IN); /* ray through vertex column */
    CHECK_EQ_INT(classify1(xy, off, 2, 1, 0.5, 0), MFG_IN); /* x equals hole vertices' x */
    CHECK_EQ_INT(classify1(xy, off, 2, 3, 3.5, 0), MFG_IN);
    CHECK_EQ_INT(classify1(xy, off, 2, 0.5, 2, 0.5), MFG_ON);  /* exactly tol away */
    CHECK_EQ_INT(classify1(xy, off, 2, 0.5, 2, nextafter(0.5, 0)), MFG_IN);
    /* Near convex corners: inside the tol box, outside the tol disc. */
    CHECK_EQ_INT(classify1(xy, off, 2, 0.6, 0.6, 0.5), MFG_IN);  /* 0.566 from (1,1) */
    CHECK_EQ_INT(classify1(xy, off, 2, 4.4, 4.4, 0.5), MFG_OUT); /* 0.566 from (4,4) */
    /* (4.375, 4.5) is exactly 0.625 from the corner (4,4) (binary-exact values). */
    CHECK_EQ_INT(classify1(xy, off, 2, 4.375, 4.5, 0.625), MFG_ON);
    CHECK_EQ_INT(classify1(xy, off, 2, 4.375, 4.5, nextafter(0.625, 0)), MFG_OUT);
}

/* Self-intersecting pentagram: the centre pentagon is covered twice, so OUT. */
static void test_pentagram(void)
{
    double xy[10];
    for (int k = 0; k < 5; k++) {
        double a = M_PI / 2 + k * 4 * M_PI / 5;
        xy[2 * k] = cos(a);
        xy[2 * k + 1] = sin(a);
    }
    int64_t off[] = {0, 5};
    CHECK_EQ_INT(classify1(xy, off, 1, 0, 0, 0), MFG_OUT);
    CHECK_EQ_INT(classify1(xy, off, 1, 0, 0.8, 0), MFG_IN); /* a tip */
    CHECK_EQ_INT(classify1(xy, off, 1, 0, 0.8, 0.5), MFG_ON);
}

/* Random rings with integer vertices and integer/half-integer test points, against the
 * integer reference, for tol in {0, 1, 2}; coordinates are scaled by 2 in the
 * reference so half-integers stay integers. */
static void test_random_against_reference(void)
{
    enum { NV = 60, NP = 400 };
    double xy[2 * NV];
    ipt iv[NV];
    int disagreements = 0, checks = 0, counts[3] = {0, 0, 0};
    for (int trial = 0; trial < 300; trial++) {
        int nrings = (int)rng_int(1, 3);
        long long off[4];
        int64_t off64[4];
        off[0] = off64[0] = 0;
        for (int r = 0; r < nrings; r++) {
            long long cnt = rng_int(3, NV / 3);
            off[r + 1] = off64[r + 1] = off[r] + cnt;
        }
        long long n = off[nrings];
        long span = trial % 2 ? 6 : 20; /* small spans make many ties */
        for (long long k = 0; k < n; k++) {
            long x = rng_int(-span, span), y = rng_int(-span, span);
            iv[k].x = 2 * x;
            iv[k].y = 2 * y;
            xy[2 * k] = (double)x;
            xy[2 * k + 1] = (double)y;
        }
        long long tol2 = rng_int(0, 2);
        double tol = (double)tol2 * 0.5; /* 0, 0.5 or 1 in half units */
        double pts[2 * NP];
        uint8_t got[NP], prep[NP];
        for (int k = 0; k < NP; k++) {
            pts[2 * k] = (double)rng_int(-2 * span - 2, 2 * span + 2) * 0.5;
            pts[2 * k + 1] = (double)rng_int(-2 * span - 2, 2 * span + 2) * 0.5;
        }
        CHECK_EQ_INT(mfg_classify_points(xy, off64, nrings, pts, NP, tol, got), MFG_OK);
        mfg_region *reg = NULL;
        CHECK_EQ_INT(mfg_region_new(xy, off64, nrings, tol, &reg), MFG_OK);
        CHECK_EQ_INT(mfg_region_classify(reg, pts, NP, prep), MFG_OK);
        mfg_region_free(reg);
        for (int k = 0; k < NP; k++) {
            ipt t = {(long long)(pts[2 * k] * 2), (long long)(pts[2 * k + 1] * 2)};
            int want = ref_classify(iv, off, nrings, t, tol2);
            checks++;
            counts[want]++;
            if (got[k] != want || prep[k] != want) {
                if (disagreements++ < 5)
                    fprintf(stderr, "trial %d point (%g, %g) tol %g: ref %d one-shot %d prepared %d\n",
                            trial, pts[2 * k], pts[2 * k + 1], tol, want, got[k], prep[k]);
            }
        }
    }
    CHECK_EQ_INT(disagreements, 0);
    /* The cases must actually exercise all three answers. */
    CHECK(counts[MFG_IN] > checks / 20 && counts[MFG_ON] > checks / 20 && counts[MFG_OUT] > checks / 20);
}

/* Rotating the start vertex, reversing rings and permuting rings never changes answers. */
static void test_invariance(void)
{
    enum { NV = 200, NP = 3000 };
    double xy[2 * NV], xy2[2 * NV], pts[2 * NP];
    uint8_t a[NP], b[NP];
    int bad = 0;
    for (int trial = 0; trial < 40; trial++) {
        /* Random star-shaped ring plus a random self-intersecting ring. */
        int n1 = (int)rng_int(3, 120), n2 = (int)rng_int(3, NV - n1);
        for (int k = 0; k < n1; k++) {
            double ang = 2 * M_PI * k / n1, rad = rng_uniform(0.2, 1.0);
            xy[2 * k] = rad * cos(ang);
            xy[2 * k + 1] = rad * sin(ang);
        }
        for (int k = n1; k < n1 + n2; k++) {
            xy[2 * k] = rng_uniform(-1, 1);
            xy[2 * k + 1] = rng_uniform(-1, 1);
        }
        int64_t off[] = {0, n1, n1 + n2};
        double tol = trial % 3 == 0 ? 0.0 : rng_uniform(0, 0.05);
        for (int k = 0; k < NP; k++) {
            if (k % 3 == 0) { /* on or next to an edge */
                int e = (int)rng_int(0, n1 - 1), f = (e + 1) % n1;
                double s = rng_uniform(0, 1);
                pts[2 * k] = xy[2 * e] + s * (xy[2 * f] - xy[2 * e]) + rng_uniform(-1, 1) * tol;
                pts[2 * k + 1] = xy[2 * e + 1] + s * (xy[2 * f + 1] - xy[2 * e + 1]);
            } else {
                pts[2 * k] = rng_uniform(-1.1, 1.1);
                pts[2 * k + 1] = rng_uniform(-1.1, 1.1);
            }
        }
        CHECK_EQ_INT(mfg_classify_points(xy, off, 2, pts, NP, tol, a), MFG_OK);
        /* ring 2 first, ring 1 reversed and rotated */
        int rot = (int)rng_int(0, n1 - 1);
        for (int k = 0; k < n2; k++) {
            xy2[2 * k] = xy[2 * (n1 + k)];
            xy2[2 * k + 1] = xy[2 * (n1 + k) + 1];
        }
        for (int k = 0; k < n1; k++) {
            int src = ((n1 - 1 - k) + rot) % n1;
            xy2[2 * (n2 + k)] = xy[2 * src];
            xy2[2 * (n2 + k) + 1] = xy[2 * src + 1];
        }
        int64_t off2[] = {0, n2, n1 + n2};
        CHECK_EQ_INT(mfg_classify_points(xy2, off2, 2, pts, NP, tol, b), MFG_OK);
        for (int k = 0; k < NP; k++)
            bad += a[k] != b[k];
        mfg_region *reg = NULL;
        CHECK_EQ_INT(mfg_region_new(xy2, off2, 2, tol, &reg), MFG_OK);
        CHECK_EQ_INT(mfg_region_classify(reg, pts, NP, b), MFG_OK);
        mfg_region_free(reg);
        for (int k = 0; k < NP; k++)
            bad += a[k] != b[k];
    }
    CHECK_EQ_INT(bad, 0);
}

/* Degenerate regions: a ring of identical points, a collinear ring, a repeated
 * closing vertex. */
static void test_degenerate_rings(void)
{
    double same[] = {1, 1, 1, 1, 1, 1};
    int64_t off[] = {0, 3};
    CHECK_EQ_INT(classify1(same, off, 1, 1, 1, 0), MFG_ON);
    CHECK_EQ_INT(classify1(same, off, 1, 1.5, 1, 0.5), MFG_ON);
    CHECK_EQ_INT(classify1(same, off, 1, 1.5, 1, 0.25), MFG_OUT);
    double line[] = {0, 0, 1, 1, 2, 2};
    CHECK_EQ_INT(classify1(line, off, 1, 0.5, 0.5, 0), MFG_ON);
    CHECK_EQ_INT(classify1(line, off, 1, 0.5, 0.6, 0), MFG_OUT);
    double closed[] = {0, 0, 2, 0, 2, 2, 0, 0};
    int64_t off4[] = {0, 4};
    CHECK_EQ_INT(classify1(closed, off4, 1, 1.5, 0.5, 0), MFG_IN);
    CHECK_EQ_INT(classify1(closed, off4, 1, 0.5, 1.5, 0), MFG_OUT);
    mfg_region *r = NULL;
    double p[] = {1, 1, 1.5, 1, 0.5, 0.5, 3, 3, 1.5, 0.5, 0.5, 1.5};
    uint8_t o[6];
    CHECK_EQ_INT(mfg_region_new(same, off, 1, 0.5, &r), MFG_OK);
    CHECK_EQ_INT(mfg_region_classify(r, p, 2, o), MFG_OK);
    CHECK(o[0] == MFG_ON && o[1] == MFG_ON);
    mfg_region_free(r);
    CHECK_EQ_INT(mfg_region_new(closed, off4, 1, 0.0, &r), MFG_OK);
    CHECK_EQ_INT(mfg_region_classify(r, p, 6, o), MFG_OK);
    CHECK(o[0] == MFG_ON && o[1] == MFG_IN && o[2] == MFG_ON && o[3] == MFG_OUT && o[4] == MFG_IN &&
          o[5] == MFG_OUT);
    mfg_region_free(r);
}

/* Large translations and scales: exactness must hold away from the origin. */
static void test_scales(void)
{
    for (int e = -30; e <= 150; e += 30) {
        double s = ldexp(1.0, e), o = 3 * s;
        double xy[] = {o, o, o + 4 * s, o, o + 4 * s, o + 4 * s, o, o + 4 * s};
        int64_t off[] = {0, 4};
        CHECK_EQ_INT(classify1(xy, off, 1, o + 2 * s, o + 2 * s, s), MFG_IN);
        CHECK_EQ_INT(classify1(xy, off, 1, o + 2 * s, o + s, s), MFG_ON);
        CHECK_EQ_INT(classify1(xy, off, 1, o + 2 * s, o + s, nextafter(s, 0)), MFG_IN);
        CHECK_EQ_INT(classify1(xy, off, 1, o - 0.6 * s, o - 0.8 * s, s), MFG_ON);
        CHECK_EQ_INT(classify1(xy, off, 1, o - 0.75 * s, o - 0.75 * s, s), MFG_OUT);
    }
}

/* Reentrancy: threads sharing one prepared region agree with a serial run. */
typedef struct {
    const mfg_region *reg;
    const double *pts;
    int n;
    uint8_t *out;
    int status;
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    j->status = mfg_region_classify(j->reg, j->pts, j->n, j->out);
    return NULL;
}

static void test_threads(void)
{
    enum { NV = 500, NP = 20000 };
    static double xy[2 * NV], pts[2 * NP];
    static uint8_t serial[NP], par[4][NP];
    for (int k = 0; k < NV; k++) {
        double a = 2 * M_PI * k / NV, r = k % 2 ? 1.0 : 0.3;
        xy[2 * k] = r * cos(a);
        xy[2 * k + 1] = r * sin(a);
    }
    for (int k = 0; k < 2 * NP; k++)
        pts[k] = rng_uniform(-1.1, 1.1);
    int64_t off[] = {0, NV};
    mfg_region *reg = NULL;
    CHECK_EQ_INT(mfg_region_new(xy, off, 1, 1e-3, &reg), MFG_OK);
    CHECK_EQ_INT(mfg_classify_points(xy, off, 1, pts, NP, 1e-3, serial), MFG_OK);
    pthread_t th[4];
    job jobs[4];
    for (int t = 0; t < 4; t++) {
        jobs[t] = (job){reg, pts, NP, par[t], -1};
        pthread_create(&th[t], NULL, run_job, &jobs[t]);
    }
    for (int t = 0; t < 4; t++) {
        pthread_join(th[t], NULL);
        CHECK_EQ_INT(jobs[t].status, MFG_OK);
        CHECK(memcmp(par[t], serial, NP) == 0);
    }
    mfg_region_free(reg);
}

int main(void)
{
    test_errors();
    test_square_with_hole();
    test_pentagram();
    test_random_against_reference();
    test_invariance();
    test_degenerate_rings();
    test_scales();
    test_threads();
    return mfg_test_report("test_pointclass");
}
