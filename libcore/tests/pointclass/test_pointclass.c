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

/* ---- Prepared index on dense and spiky regions ----------------------------------
 * The prepared region refines busy grid cells into a quadtree with "ordered" leaves
 * (edges sorted across a slab, bisection on float heights with a certified bound).
 * Every shape below must give exactly the one-shot answers, for points spread over the
 * box, on vertices, on edges, one ulp off edges, and about tol away from edges. */

typedef struct shape {
    double *xy;
    int64_t off[4097];
    int64_t nrings, nv, cap;
} shape;

static void shape_vertex(shape *s, double x, double y)
{
    if (s->nv == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 1024;
        s->xy = realloc(s->xy, (size_t)s->cap * 2 * sizeof(double));
    }
    s->xy[2 * s->nv] = x;
    s->xy[2 * s->nv + 1] = y;
    s->nv++;
}

static void shape_close_ring(shape *s)
{
    s->nrings++;
    s->off[s->nrings] = s->nv;
}

/* n spikes between radii r_in and r_out around (cx, cy), coordinates rounded to
 * integers when `integral` (for the integer reference). */
static void add_star(shape *s, int n, double cx, double cy, double r_out, double r_in, int integral)
{
    for (int k = 0; k < 2 * n; k++) {
        double t = M_PI * k / n, r = k % 2 ? r_in : r_out;
        double x = cx + r * cos(t), y = cy + r * sin(t);
        shape_vertex(s, integral ? round(x) : x, integral ? round(y) : y);
    }
    shape_close_ring(s);
}

/* A comb: base [0, n (w + gap)] x [0, 1] with n teeth of width w and height h. */
static void add_comb(shape *s, int n, double w, double gap, double h)
{
    shape_vertex(s, 0.0, 0.0);
    shape_vertex(s, n * (w + gap), 0.0);
    for (int k = n - 1; k >= 0; k--) {
        double x0 = k * (w + gap);
        shape_vertex(s, x0 + w, 1.0 + h);
        shape_vertex(s, x0, 1.0 + h);
        if (k > 0)
            shape_vertex(s, x0, 1.0);
    }
    shape_close_ring(s);
}

/* A thick spiral band of `turns` turns (outer arm out, inner arm back). */
static void add_spiral(shape *s, double turns, int steps)
{
    for (int k = 0; k <= steps; k++) {
        double t = 2 * M_PI * turns * k / steps, r = 1.0 + t;
        shape_vertex(s, r * cos(t), r * sin(t));
    }
    for (int k = steps; k >= 0; k--) {
        double t = 2 * M_PI * turns * k / steps, r = 1.0 + t + 2.5;
        shape_vertex(s, r * cos(t), r * sin(t));
    }
    shape_close_ring(s);
}

/* Edges of the shape, for probe points. */
static void shape_edge(const shape *s, int64_t e, double *ax, double *ay, double *bx, double *by)
{
    int64_t r = 0;
    while (s->off[r + 1] <= e)
        r++;
    int64_t f = e + 1 < s->off[r + 1] ? e + 1 : s->off[r];
    *ax = s->xy[2 * e];
    *ay = s->xy[2 * e + 1];
    *bx = s->xy[2 * f];
    *by = s->xy[2 * f + 1];
}

/* Probe points: uniform over the grown box, vertices, on edges, one ulp off them, and
 * about tol away along the edge normal. */
static int64_t probe_points(const shape *s, double tol, double *pts, int64_t np)
{
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int64_t k = 0; k < s->nv; k++) {
        x0 = fmin(x0, s->xy[2 * k]);
        x1 = fmax(x1, s->xy[2 * k]);
        y0 = fmin(y0, s->xy[2 * k + 1]);
        y1 = fmax(y1, s->xy[2 * k + 1]);
    }
    double gx = 0.05 * (x1 - x0) + tol, gy = 0.05 * (y1 - y0) + tol;
    int64_t m = 0;
    while (m < np) {
        long kind = rng_int(0, 5);
        double x, y;
        if (kind <= 1) {
            x = rng_uniform(x0 - gx, x1 + gx);
            y = rng_uniform(y0 - gy, y1 + gy);
        } else {
            double ax, ay, bx, by;
            shape_edge(s, rng_int(0, s->nv - 1), &ax, &ay, &bx, &by);
            double u = kind == 2 ? 0.0 : rng_uniform(0.0, 1.0);
            x = ax + u * (bx - ax);
            y = ay + u * (by - ay);
            if (kind == 4) {
                x = nextafter(x, rng_int(0, 1) ? INFINITY : -INFINITY);
                y = nextafter(y, rng_int(0, 1) ? INFINITY : -INFINITY);
            } else if (kind == 5) {
                double len = hypot(bx - ax, by - ay), sgn = rng_int(0, 1) ? 1.0 : -1.0;
                double d = tol * (1.0 + rng_uniform(-1e-12, 1e-12));
                if (len > 0) {
                    x += sgn * d * -(by - ay) / len;
                    y += sgn * d * (bx - ax) / len;
                }
            }
        }
        /* Keep inside the accepted range (a step off 0 would be subnormal). */
        pts[2 * m] = fabs(x) < MFG_MIN_COORD ? 0.0 : x;
        pts[2 * m + 1] = fabs(y) < MFG_MIN_COORD ? 0.0 : y;
        m++;
    }
    return m;
}

/* Prepared == one-shot on every probe point; returns the region info. */
static struct mfg_region_info check_shape(const char *label, const shape *s, double tol, int64_t np)
{
    double *pts = malloc((size_t)np * 2 * sizeof(double));
    uint8_t *one = malloc((size_t)np), *prep = malloc((size_t)np);
    struct mfg_region_info info;
    memset(&info, 0, sizeof info);
    probe_points(s, tol, pts, np);
    CHECK_EQ_INT(mfg_classify_points(s->xy, s->off, s->nrings, pts, np, tol, one), MFG_OK);
    mfg_region *reg = NULL;
    CHECK_EQ_INT(mfg_region_new(s->xy, s->off, s->nrings, tol, &reg), MFG_OK);
    CHECK_EQ_INT(mfg_region_classify(reg, pts, np, prep), MFG_OK);
    CHECK_EQ_INT(mfg_region_info(reg, &info), MFG_OK);
    mfg_region_free(reg);
    int64_t bad = 0, counts[3] = {0, 0, 0};
    for (int64_t k = 0; k < np; k++) {
        counts[one[k] < 3 ? one[k] : 0]++;
        if (one[k] != prep[k] && bad++ < 3)
            fprintf(stderr, "%s tol %g: point (%.17g, %.17g) one-shot %d prepared %d\n", label, tol,
                    pts[2 * k], pts[2 * k + 1], one[k], prep[k]);
    }
    CHECK_EQ_INT(bad, 0);
    /* Probe points on edges make ON answers; the uniform ones IN and OUT. */
    int all3 = counts[MFG_ON] > 0 && counts[MFG_OUT] > 0 && (counts[MFG_IN] > 0 || tol >= 0.1);
    if (!all3)
        fprintf(stderr, "%s tol %g: IN %lld OUT %lld ON %lld\n", label, tol, (long long)counts[MFG_IN],
                (long long)counts[MFG_OUT], (long long)counts[MFG_ON]);
    CHECK(all3); /* (a large tol can cover all of a thin shape) */
    /* The info is consistent. */
    CHECK_EQ_INT(info.edge_entries, info.list_entries + info.ordered_entries);
    CHECK(info.nodes >= info.list_leaves + info.ordered_leaves);
    CHECK(info.edge_cells >= 1 && info.edge_cells <= info.columns * info.rows);
    free(pts);
    free(one);
    free(prep);
    return info;
}

static void shape_scale(shape *dst, const shape *src, double scale, double shift)
{
    memset(dst, 0, sizeof *dst);
    for (int64_t k = 0; k < src->nv; k++)
        shape_vertex(dst, src->xy[2 * k] * scale + shift, src->xy[2 * k + 1] * scale + shift);
    memcpy(dst->off, src->off, sizeof src->off);
    dst->nrings = src->nrings;
}

static void test_prepared_spiky(void)
{
    static const double tols[] = {0.0, 1e-9, 1e-3, 0.2};
    for (int ti = 0; ti < 4; ti++) {
        double tol = tols[ti];
        shape s;
        /* Stars: few and many spikes, the 1000-spike star of the benchmark. */
        int spikes[] = {7, 250, 2000};
        for (int k = 0; k < 3; k++) {
            memset(&s, 0, sizeof s);
            add_star(&s, spikes[k], 0.0, 0.0, 1.0, 0.2, 0);
            struct mfg_region_info info = check_shape("star", &s, tol, 20000);
            if (k == 2 && tol < 1e-6) /* the index must really use ordered slabs */
                CHECK(info.ordered_leaves > 0 && info.ordered_entries > info.edge_entries / 2);
            free(s.xy);
        }
        memset(&s, 0, sizeof s);
        add_spiral(&s, 12.0, 3000);
        check_shape("spiral", &s, tol, 20000);
        free(s.xy);
        memset(&s, 0, sizeof s);
        add_comb(&s, 800, 0.3, 0.7, 50.0);
        check_shape("comb", &s, tol, 20000);
        free(s.xy);
        /* Many tiny holes (squares and triangles) in a square, some touching. */
        memset(&s, 0, sizeof s);
        shape_vertex(&s, -1.0, -1.0);
        shape_vertex(&s, 101.0, -1.0);
        shape_vertex(&s, 101.0, 101.0);
        shape_vertex(&s, -1.0, 101.0);
        shape_close_ring(&s);
        for (int h = 0; h < 1500; h++) {
            double cx = rng_int(0, 199) * 0.5, cy = rng_int(0, 199) * 0.5, r = rng_uniform(0.01, 0.3);
            shape_vertex(&s, cx - r, cy - r);
            shape_vertex(&s, cx + r, cy - r);
            shape_vertex(&s, cx + (h % 2 ? 0.0 : r), cy + r);
            if (h % 2 == 0)
                shape_vertex(&s, cx - r, cy + r);
            shape_close_ring(&s);
        }
        check_shape("holes", &s, tol, 20000);
        /* Huge and tiny scales, shifted away from the origin. */
        for (int e = -150; e <= 150; e += 100) {
            shape t;
            shape_scale(&t, &s, ldexp(1.0, e), 3.0 * ldexp(1.0, e + 7));
            check_shape("holes scaled", &t, tol * ldexp(1.0, e), 10000);
            free(t.xy);
        }
        free(s.xy);
    }
}

/* Thousands of spikes inside one grid cell (a big frame sets the cell size): the cell's
 * quadtree must go deep, and still answer exactly. */
static void test_prepared_deep_cell(void)
{
    for (int ti = 0; ti < 3; ti++) {
        double tol = ti == 0 ? 0.0 : (ti == 1 ? 1e-12 : 1e-6);
        shape s;
        memset(&s, 0, sizeof s);
        shape_vertex(&s, 0.0, 0.0);
        shape_vertex(&s, 1000.0, 0.0);
        shape_vertex(&s, 1000.0, 1000.0);
        shape_vertex(&s, 0.0, 1000.0);
        shape_close_ring(&s);
        add_star(&s, 3000, 500.3, 500.7, 0.4, 0.05, 0);
        struct mfg_region_info info = check_shape("deep", &s, tol, 5000);
        CHECK(info.max_depth >= 4);
        CHECK(info.ordered_leaves > 10);
        /* Most queries near the star: half of them inside its box. */
        enum { NP = 40000 };
        static double pts[2 * NP];
        static uint8_t one[NP], prep[NP];
        for (int k = 0; k < NP; k++) {
            pts[2 * k] = 500.3 + rng_uniform(-0.45, 0.45);
            pts[2 * k + 1] = 500.7 + rng_uniform(-0.45, 0.45);
        }
        mfg_region *reg = NULL;
        CHECK_EQ_INT(mfg_region_new(s.xy, s.off, s.nrings, tol, &reg), MFG_OK);
        CHECK_EQ_INT(mfg_region_classify(reg, pts, NP, prep), MFG_OK);
        mfg_region_free(reg);
        CHECK_EQ_INT(mfg_classify_points(s.xy, s.off, s.nrings, pts, NP, tol, one), MFG_OK);
        CHECK(memcmp(one, prep, NP) == 0);
        free(s.xy);
    }
}

/* Many edges through one point (a fan of spikes sharing the centre vertex) cannot be
 * ordered near the centre: the quadtree stops at its depth limit with a plain list. */
static void test_prepared_fan(void)
{
    shape s;
    memset(&s, 0, sizeof s);
    for (int k = 0; k < 400; k++) {
        double t0 = 2 * M_PI * k / 400, t1 = 2 * M_PI * (k + 0.5) / 400;
        shape_vertex(&s, 0.0, 0.0);
        shape_vertex(&s, cos(t0), sin(t0));
        shape_vertex(&s, cos(t1), sin(t1));
    }
    shape_close_ring(&s);
    for (int ti = 0; ti < 3; ti++)
        check_shape("fan", &s, ti == 0 ? 0.0 : (ti == 1 ? 1e-10 : 1e-3), 20000);
    free(s.xy);
}

/* Fuzz (fuzz_api) finding: degenerate lists the quadtree cannot separate.  Copies of one
 * segment, and overlapping collinear edges, lie in two or three children at every level,
 * so splitting them ran to the depth limit and filled the entry budget (~10 times the
 * grid's entries, 10^4 nodes for 116 vertices; 6 s a build under ASan).  The answers must
 * stay the one-shot ones, and the quadtree small:
 *  - the fuzz input: five rings repeating a 7-point cycle (7 distinct segments in all,
 *    many copies of each) after a vertex (12, 0) and a run of (0, 0) vertices
 *    (zero-length edges): at most 7 distinct segments per cell, so no cell is split;
 *  - a square and a ring of 200 collinear, overlapping edges (all distinct): at most 5
 *    times the grid's entries (was 9.6). */
static void test_prepared_degenerate_bundles(void)
{
    shape s;
    memset(&s, 0, sizeof s);
    for (int64_t k = 0; k < 116; k++) /* the harness: 96 coordinates read, then k % 7 */
        shape_vertex(&s, 2 * k < 96 ? (k == 0 ? 12.0 : 0.0) : (double)((2 * k) % 7),
                     2 * k + 1 < 96 ? 0.0 : (double)((2 * k + 1) % 7));
    const int64_t ends[] = {23, 46, 69, 92, 116};
    for (int r = 0; r < 5; r++) {
        s.nrings++;
        s.off[s.nrings] = ends[r];
    }
    for (int ti = 0; ti < 2; ti++) {
        struct mfg_region_info info = check_shape("bundles", &s, ti ? 0.0625 : 0.0, 5000);
        CHECK_EQ_INT(info.edge_entries, info.grid_entries);
        CHECK_EQ_INT(info.max_depth, 0);
    }
    free(s.xy);

    memset(&s, 0, sizeof s);
    shape_vertex(&s, -1, -1);
    shape_vertex(&s, 11, -1);
    shape_vertex(&s, 11, 1);
    shape_vertex(&s, -1, 1);
    shape_close_ring(&s);
    for (int k = 0; k < 200; k++)
        shape_vertex(&s, k % 2 ? 10.0 - (k / 2) * 0.037 : (k / 2) * 0.041, 0.3137);
    shape_close_ring(&s);
    struct mfg_region_info info = check_shape("collinear", &s, 0.0, 5000);
    CHECK(info.edge_entries <= 5 * info.grid_entries);
    if (info.edge_entries > 5 * info.grid_entries)
        fprintf(stderr, "collinear: %lld entries for %lld in the grid\n", (long long)info.edge_entries,
                (long long)info.grid_entries);
    free(s.xy);
}

/* A dense integer star against the independent integer reference (exact arithmetic):
 * checks the prepared answers themselves, not only their agreement.  Coordinates stay
 * below 2^15 so the reference's squared cross products fit in int64. */
static void test_prepared_star_reference(void)
{
    enum { NSP = 1500, NV = 2 * NSP, NP = 3000 };
    shape s;
    memset(&s, 0, sizeof s);
    add_star(&s, NSP, 0.0, 0.0, 10000.0, 2000.0, 1);
    static ipt iv[NV];
    long long off[2] = {0, NV};
    for (int k = 0; k < NV; k++) {
        iv[k].x = 2 * (long long)s.xy[2 * k];
        iv[k].y = 2 * (long long)s.xy[2 * k + 1];
    }
    static double pts[2 * NP];
    static uint8_t prep[NP];
    for (long long tol2 = 0; tol2 <= 2; tol2++) {
        for (int k = 0; k < NP; k++) {
            if (k % 3 == 0) { /* on or next to an edge's integer points */
                int e = (int)rng_int(0, NV - 1), f = (e + 1) % NV;
                long long i = rng_int(0, 8);
                pts[2 * k] = (double)((iv[e].x * (8 - i) + iv[f].x * i) / 8 + rng_int(-2, 2)) * 0.5;
                pts[2 * k + 1] = (double)((iv[e].y * (8 - i) + iv[f].y * i) / 8 + rng_int(-2, 2)) * 0.5;
            } else {
                pts[2 * k] = (double)rng_int(-21000, 21000) * 0.5;
                pts[2 * k + 1] = (double)rng_int(-21000, 21000) * 0.5;
            }
        }
        mfg_region *reg = NULL;
        CHECK_EQ_INT(mfg_region_new(s.xy, s.off, 1, 0.5 * (double)tol2, &reg), MFG_OK);
        CHECK_EQ_INT(mfg_region_classify(reg, pts, NP, prep), MFG_OK);
        struct mfg_region_info info;
        CHECK_EQ_INT(mfg_region_info(reg, &info), MFG_OK);
        CHECK(info.ordered_leaves > 0);
        mfg_region_free(reg);
        int bad = 0, on = 0;
        for (int k = 0; k < NP; k++) {
            ipt t = {(long long)(pts[2 * k] * 2), (long long)(pts[2 * k + 1] * 2)};
            int want = ref_classify(iv, off, 1, t, tol2);
            on += want == MFG_ON;
            if (prep[k] != want && bad++ < 3)
                fprintf(stderr, "integer star tol %g: point (%g, %g) reference %d prepared %d\n",
                        0.5 * (double)tol2, pts[2 * k], pts[2 * k + 1], want, prep[k]);
        }
        CHECK_EQ_INT(bad, 0);
        CHECK(on > 0);
    }
    free(s.xy);
}

static void test_region_info_errors(void)
{
    double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
    int64_t off[] = {0, 4};
    mfg_region *r = NULL;
    struct mfg_region_info info;
    CHECK_EQ_INT(mfg_region_new(sq, off, 1, 0.0, &r), MFG_OK);
    CHECK_EQ_INT(mfg_region_info(NULL, &info), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_region_info(r, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_region_info(r, &info), MFG_OK);
    int64_t st[4];
    CHECK_EQ_INT(mfg_region_stats(r, st), MFG_OK);
    CHECK(st[0] == info.columns && st[1] == info.rows && st[2] == info.edge_cells &&
          st[3] == info.edge_entries);
    CHECK(info.bytes > 0 && info.max_depth >= 0 && info.max_list <= 4);
    mfg_region_free(r);
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
    test_prepared_spiky();
    test_prepared_deep_cell();
    test_prepared_fan();
    test_prepared_degenerate_bundles();
    test_prepared_star_reference();
    test_region_info_errors();
    return mfg_test_report("test_pointclass");
}
