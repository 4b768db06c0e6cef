/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_visibility.c - unit tests of mfg_visibility_map against the definition
 * VM(P) = { d : d.p >= 0 for all p in P }: constructed kinds, error statuses, dense
 * sampling on random caps, permutation invariance, near-duplicates and 10^6 normals;
 * hulls of integer normals against an exact gift-wrapping reference (128-bit integers),
 * and large degenerate cones (tessellated cones with an opposite normal, cylinders). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mfg_test.h"
#include "mfgeom.h"

/* ---- small vector helpers ------------------------------------------------------------ */

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double *a, const double *b, double *o)
{
    double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
           z = a[0] * b[1] - a[1] * b[0];
    o[0] = x, o[1] = y, o[2] = z;
}

static void unit3(double *a)
{
    double r = sqrt(dot3(a, a));
    a[0] /= r, a[1] /= r, a[2] /= r;
}

/* Fibonacci lattice: n nearly uniform directions. */
static double *fibonacci(int64_t n)
{
    double *d = malloc((size_t)n * 3 * sizeof(double));
    const double ga = M_PI * (3.0 - sqrt(5.0));
    for (int64_t i = 0; i < n; i++) {
        double z = 1.0 - 2.0 * ((double)i + 0.5) / (double)n, r = sqrt(fmax(0.0, 1 - z * z));
        d[3 * i] = r * cos(ga * (double)i);
        d[3 * i + 1] = r * sin(ga * (double)i);
        d[3 * i + 2] = z;
    }
    return d;
}

/* A right-handed orthonormal frame (e1, e2) completing unit c. */
static void frame(const double *c, double *e1, double *e2)
{
    double a[3] = {1, 0, 0};
    if (fabs(c[0]) > 0.9)
        a[0] = 0, a[1] = 1;
    cross3(c, a, e1);
    unit3(e1);
    cross3(c, e1, e2);
}

/* A uniform random direction in the cap of angular radius rad about unit c. */
static void cap_sample(const double *c, double rad, double *out)
{
    double e1[3], e2[3];
    frame(c, e1, e2);
    double z = rng_uniform(cos(rad), 1.0), r = sqrt(fmax(0.0, 1 - z * z));
    double phi = rng_uniform(0, 2 * M_PI);
    for (int i = 0; i < 3; i++)
        out[i] = z * c[i] + r * (cos(phi) * e1[i] + sin(phi) * e2[i]);
}

static void random_dir(double *out)
{
    do {
        for (int i = 0; i < 3; i++)
            out[i] = rng_uniform(-1, 1);
    } while (dot3(out, out) > 1 || dot3(out, out) < 1e-6);
    unit3(out);
}

/* min over the normals of d . p^ (the definition of VM). */
static double min_dot(const double *d, const double *pn, int64_t m)
{
    double best = 2;
    for (int64_t j = 0; j < m; j++)
        best = fmin(best, dot3(d, pn + 3 * j));
    return best;
}

static double *normalised(const double *p, int64_t m)
{
    double *pn = malloc((size_t)m * 3 * sizeof(double));
    memcpy(pn, p, (size_t)m * 3 * sizeof(double));
    for (int64_t i = 0; i < m; i++)
        unit3(pn + 3 * i);
    return pn;
}

/* Our containment test for a CCW convex polygon: d.(v_i x v_i+1) >= -tol on every edge. */
static int in_polygon(const double *d, const mfg_spoly *s, double tol)
{
    for (int64_t i = 0; i < s->nvertices; i++) {
        double n[3];
        cross3(s->vertices + 3 * i, s->vertices + 3 * ((i + 1) % s->nvertices), n);
        if (dot3(d, n) < -tol)
            return 0;
    }
    return 1;
}

/* Checks a map against the definition.  Every vertex in VM; for a polygon: every edge on
 * a great circle GC(p) of one normal, convex and CCW, and dense samples (nsamp global +
 * nsamp near the map) strictly in VM are inside, strictly outside are outside.  Returns
 * the number of failed sub-checks (also counted by CHECK). */
static int check_vm(const double *p, int64_t m, const mfg_spoly *s, int64_t nsamp)
{
    int before = mfg_test_failures;
    double *pn = normalised(p, m);
    for (int64_t i = 0; i < s->nvertices; i++) {
        const double *v = s->vertices + 3 * i;
        CHECK(fabs(dot3(v, v) - 1) < 1e-14);
        CHECK(min_dot(v, pn, m) >= -1e-12);
    }
    double *fib = fibonacci(nsamp);
    int64_t strict_in = 0, bad_in = 0, bad_out = 0;
    double centre[3] = {0, 0, 0}, rad = M_PI;
    if (s->kind == MFG_VM_POLYGON) {
        for (int64_t i = 0; i < s->nvertices; i++)
            for (int c = 0; c < 3; c++)
                centre[c] += s->vertices[3 * i + c];
        if (dot3(centre, centre) > 1e-12) {
            unit3(centre);
            rad = 0;
            for (int64_t i = 0; i < s->nvertices; i++)
                rad = fmax(rad, acos(fmin(1, dot3(centre, s->vertices + 3 * i))));
            rad = fmin(M_PI, 1.5 * rad + 1e-3);
        } else {
            centre[2] = 1;
        }
    }
    double best = -2, best_d[3] = {0, 0, 1};
    for (int64_t k = 0; k < 2 * nsamp; k++) {
        double d[3];
        if (k < nsamp)
            memcpy(d, fib + 3 * k, sizeof d);
        else if (s->kind == MFG_VM_POLYGON)
            cap_sample(centre, rad, d);
        else
            break;
        double md = min_dot(d, pn, m);
        if (md > best) {
            best = md;
            memcpy(best_d, d, sizeof d);
        }
        if (md > 1e-9) {
            strict_in++;
            if (s->kind != MFG_VM_POLYGON || !in_polygon(d, s, 1e-12))
                bad_in++;
        } else if (md < -1e-9 && s->kind == MFG_VM_POLYGON && in_polygon(d, s, 1e-12)) {
            bad_out++;
        }
    }
    CHECK_EQ_INT(bad_in, 0);
    CHECK_EQ_INT(bad_out, 0);
    if (s->kind == MFG_VM_POLYGON) {
        int64_t n = s->nvertices;
        CHECK(n >= 3);
        for (int64_t i = 0; i < n; i++) {
            const double *a = s->vertices + 3 * i, *b = s->vertices + 3 * ((i + 1) % n);
            int on_gc = 0;
            for (int64_t j = 0; j < m && !on_gc; j++)
                on_gc = fabs(dot3(a, pn + 3 * j)) < 1e-12 && fabs(dot3(b, pn + 3 * j)) < 1e-12;
            CHECK(on_gc);
            double cr[3];
            cross3(a, b, cr);
            CHECK(dot3(cr, cr) > 1e-28 && (dot3(a, b) > 0 || dot3(cr, cr) > 1e-18));
            for (int64_t k = 0; k < n; k++) /* convex, interior on the left */
                CHECK(dot3(s->vertices + 3 * k, cr) >= -1e-12);
        }
        if (strict_in > 0)
            CHECK(in_polygon(best_d, s, -1e-15)); /* deepest sample strictly left */
    }
    free(fib);
    free(pn);
    return mfg_test_failures - before;
}

static mfg_spoly *vm(const double *p, int64_t m, double draft)
{
    mfg_spoly *s = NULL;
    mfg_status st = mfg_visibility_map(p, m, draft, &s);
    CHECK_EQ_INT(st, MFG_OK);
    if (st != MFG_OK) {
        fprintf(stderr, "  mfg_visibility_map: %s\n", mfg_last_error());
        return NULL;
    }
    return s;
}

/* ---- constructed kinds ---------------------------------------------------------------- */

static void test_kinds(void)
{
    mfg_spoly *s;
    double one[3] = {0.3, -0.4, 0.8};
    if ((s = vm(one, 1, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        CHECK_EQ_INT(s->nvertices, 3);
        check_vm(one, 1, s, 20000);
        mfg_spoly_free(s);
    }
    double two[6] = {0, 0, 1, 1, 0.2, 0.1};
    if ((s = vm(two, 2, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        CHECK_EQ_INT(s->nvertices, 4);
        check_vm(two, 2, s, 20000);
        mfg_spoly_free(s);
    }
    double anti[6] = {0, 0.6, 0.8, 0, -0.6, -0.8};
    if ((s = vm(anti, 2, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_EDGE);
        CHECK_EQ_INT(s->closed, 1);
        CHECK_EQ_INT(s->nvertices, 3);
        for (int i = 0; i < 3 && s->nvertices == 3; i++) {
            CHECK(fabs(dot3(s->vertices + 3 * i, anti)) < 1e-15);
            CHECK(fabs(dot3(s->vertices + 3 * i, s->vertices + 3 * ((i + 1) % 3)) + 0.5) < 1e-14);
        }
        check_vm(anti, 2, s, 20000);
        mfg_spoly_free(s);
    }
    double half[9] = {0, 0, 1, 0, 0, -1, 1, 1, 0.5};
    if ((s = vm(half, 3, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_EDGE);
        CHECK_EQ_INT(s->closed, 0);
        CHECK_EQ_INT(s->nvertices, 3);
        if (s->nvertices == 3) {
            const double *v = s->vertices;
            CHECK(fabs(v[0] + v[6]) < 1e-14 && fabs(v[1] + v[7]) < 1e-14 && fabs(v[8]) < 1e-15);
            CHECK(fabs(v[3] - sqrt(0.5)) < 1e-14 && fabs(v[4] - sqrt(0.5)) < 1e-14);
        }
        check_vm(half, 3, s, 20000);
        mfg_spoly_free(s);
    }
    /* three normals on the equator in no half of it: both poles */
    double ring[12] = {1, 0, 0, cos(2.3), sin(2.3), 0, cos(4.0), sin(4.0), 0, 0.2, 0.3, -0.5};
    if ((s = vm(ring, 3, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_POINT);
        CHECK_EQ_INT(s->nvertices, 2);
        if (s->nvertices == 2)
            CHECK(fabs(fabs(s->vertices[2]) - 1) < 1e-15 && s->vertices[2] == -s->vertices[5]);
        check_vm(ring, 3, s, 20000);
        mfg_spoly_free(s);
    }
    if ((s = vm(ring, 4, 0))) { /* plus one below the equator: the south pole */
        CHECK_EQ_INT(s->kind, MFG_VM_POINT);
        CHECK_EQ_INT(s->nvertices, 1);
        if (s->nvertices == 1)
            CHECK(fabs(s->vertices[2] + 1) < 1e-15);
        check_vm(ring, 4, s, 20000);
        mfg_spoly_free(s);
    }
    double tetra[12] = {1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1};
    if ((s = vm(tetra, 4, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_NULL);
        CHECK_EQ_INT(s->nvertices, 0);
        check_vm(tetra, 4, s, 20000);
        mfg_spoly_free(s);
    }
    double box[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    if ((s = vm(box, 6, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_NULL);
        mfg_spoly_free(s);
    }
    double pocket[15] = {0, 0, 1, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0};
    if ((s = vm(pocket, 5, 0))) {
        CHECK_EQ_INT(s->kind, MFG_VM_POINT);
        CHECK_EQ_INT(s->nvertices, 1);
        if (s->nvertices == 1)
            CHECK(fabs(s->vertices[2] - 1) < 1e-15);
        mfg_spoly_free(s);
    }
}

/* ---- error statuses ------------------------------------------------------------------- */

static void expect_error(const double *p, int64_t m, double draft, int with_out,
                         mfg_status want)
{
    mfg_spoly sentinel_obj, *sentinel = &sentinel_obj, *out = sentinel;
    mfg_status st = mfg_visibility_map(p, m, draft, with_out ? &out : NULL);
    CHECK_EQ_INT(st, want);
    CHECK(mfg_last_error()[0] != '\0');
    CHECK(out == sentinel); /* output untouched */
}

static void test_errors(void)
{
    double ok[6] = {0, 0, 1, 1, 0, 0};
    double nan_[6] = {0, 0, 1, NAN, 0, 0};
    double inf_[6] = {0, 0, 1, 0, INFINITY, 0};
    double zero[6] = {0, 0, 1, 0, 0, 0};
    double huge[6] = {0, 0, 1, 1e300, 0, 0};
    expect_error(ok, 2, 0, 0, MFG_ERR_NULL);
    expect_error(NULL, 2, 0, 1, MFG_ERR_NULL);
    expect_error(ok, 0, 0, 1, MFG_ERR_DEGENERATE);
    {
        mfg_spoly *out = (mfg_spoly *)ok;
        mfg_status st = mfg_visibility_map(ok, -3, 0, &out);
        CHECK(st == MFG_ERR_DEGENERATE || st == MFG_ERR_INVALID);
        CHECK(out == (mfg_spoly *)ok);
    }
    expect_error(nan_, 2, 0, 1, MFG_ERR_INVALID);
    expect_error(inf_, 2, 0, 1, MFG_ERR_INVALID);
    expect_error(zero, 2, 0, 1, MFG_ERR_INVALID);
    expect_error(huge, 2, 0, 1, MFG_ERR_INVALID);
    expect_error(ok, 2, M_PI / 2, 1, MFG_ERR_INVALID);
    expect_error(ok, 2, 2.0, 1, MFG_ERR_INVALID);
    expect_error(ok, 2, -0.1, 1, MFG_ERR_INVALID);
    expect_error(ok, 2, NAN, 1, MFG_ERR_INVALID);
    expect_error(ok, 2, INFINITY, 1, MFG_ERR_INVALID);
    /* a failure leaves nothing behind: the next call succeeds */
    mfg_spoly *s = vm(ok, 2, 0);
    mfg_spoly_free(s);
    mfg_spoly_free(NULL);
}

/* ---- random caps, permutations, duplicates -------------------------------------------- */

static double *cap_normals(int64_t m, const double *c, double rad)
{
    double *p = malloc((size_t)m * 3 * sizeof(double));
    for (int64_t i = 0; i < m; i++) {
        cap_sample(c, rad, p + 3 * i);
        double len = rng_uniform(0.1, 10); /* lengths do not matter */
        for (int k = 0; k < 3; k++)
            p[3 * i + k] *= len;
    }
    return p;
}

static void test_random_caps(void)
{
    for (int trial = 0; trial < 12; trial++) {
        int64_t m = (int64_t[]){3, 5, 10, 40, 200, 1000}[trial % 6];
        double c[3];
        random_dir(c);
        double rad = rng_uniform(0.05, 89.0 * M_PI / 180);
        double *p = cap_normals(m, c, rad);
        mfg_spoly *s = vm(p, m, 0);
        if (s) {
            CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
            if (check_vm(p, m, s, 30000))
                fprintf(stderr, "  random cap trial %d (m = %lld) failed\n", trial, (long long)m);
            CHECK(in_polygon(c, s, -1e-15)); /* the cap's centre is strictly inside */
            mfg_spoly_free(s);
        }
        free(p);
    }
}

/* Same set of vertices (as points, 1e-12), whatever the order. */
static int same_vertex_set(const mfg_spoly *a, const mfg_spoly *b)
{
    if (a->kind != b->kind || a->nvertices != b->nvertices)
        return 0;
    for (int pass = 0; pass < 2; pass++) {
        const mfg_spoly *x = pass ? b : a, *y = pass ? a : b;
        for (int64_t i = 0; i < x->nvertices; i++) {
            int found = 0;
            for (int64_t j = 0; j < y->nvertices && !found; j++) {
                double dx = x->vertices[3 * i] - y->vertices[3 * j],
                       dy = x->vertices[3 * i + 1] - y->vertices[3 * j + 1],
                       dz = x->vertices[3 * i + 2] - y->vertices[3 * j + 2];
                found = sqrt(dx * dx + dy * dy + dz * dz) <= 1e-12;
            }
            if (!found)
                return 0;
        }
    }
    return 1;
}

static void shuffle(double *p, int64_t m)
{
    for (int64_t i = m - 1; i > 0; i--) {
        int64_t j = rng_int(0, i);
        double t[3];
        memcpy(t, p + 3 * i, sizeof t);
        memcpy(p + 3 * i, p + 3 * j, sizeof t);
        memcpy(p + 3 * j, t, sizeof t);
    }
}

static void test_permutation_invariance(void)
{
    for (int trial = 0; trial < 6; trial++) {
        int64_t m = 30 + 40 * trial;
        double c[3];
        random_dir(c);
        double *p = cap_normals(m, c, rng_uniform(0.2, 1.4));
        mfg_spoly *s = vm(p, m, 0);
        for (int k = 0; k < 4 && s; k++) {
            shuffle(p, m);
            mfg_spoly *t = vm(p, m, 0);
            if (t) {
                CHECK(same_vertex_set(s, t));
                mfg_spoly_free(t);
            }
        }
        mfg_spoly_free(s);
        free(p);
    }
    /* degenerate kinds too: the whole circle's three points may be anywhere on it, but
     * an arc and the points are unique */
    double half[12] = {0, 0, 1, 0, 0, -1, 1, 1, 0.5, 0.5, 1, -0.25};
    mfg_spoly *s = vm(half, 4, 0);
    for (int k = 0; k < 6 && s; k++) {
        shuffle(half, 4);
        mfg_spoly *t = vm(half, 4, 0);
        if (t) {
            CHECK_EQ_INT(t->kind, MFG_VM_EDGE);
            CHECK(same_vertex_set(s, t));
            mfg_spoly_free(t);
        }
    }
    mfg_spoly_free(s);
}

static void test_duplicates(void)
{
    /* exact duplicates and power-of-two multiples are the same directions */
    double c[3] = {0.1, 0.2, 1};
    unit3(c);
    double *p = cap_normals(12, c, 0.8);
    double *q = malloc(36 * 3 * sizeof(double));
    for (int i = 0; i < 12; i++)
        for (int k = 0; k < 3; k++) {
            q[3 * i + k] = p[3 * i + k];
            q[36 + 3 * i + k] = p[3 * i + k];
            q[72 + 3 * i + k] = 4.0 * p[3 * i + k];
        }
    mfg_spoly *a = vm(p, 12, 0), *b = vm(q, 36, 0);
    if (a && b)
        CHECK(same_vertex_set(a, b));
    mfg_spoly_free(a);
    mfg_spoly_free(b);
    free(q);
    /* p and the rounded 3p: almost, but not exactly, parallel */
    double pr[6] = {0.09420654213039938, 0.7572164061532809, 0.6463346205118081,
                    0.28261962639119814, 2.2716492184598427, 1.9390038615354244};
    mfg_spoly *s = vm(pr, 2, 0);
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        check_vm(pr, 2, s, 20000);
        mfg_spoly_free(s);
    }
    /* near-duplicates: copies perturbed by a few ulps */
    for (int trial = 0; trial < 6; trial++) {
        int64_t m = 8;
        double cc[3];
        random_dir(cc);
        double *base = cap_normals(m, cc, rng_uniform(0.2, 1.3));
        double *nd = malloc((size_t)(4 * m) * 3 * sizeof(double));
        for (int64_t i = 0; i < 4 * m; i++)
            for (int k = 0; k < 3; k++) {
                double x = base[3 * (i % m) + k];
                int steps = i < m ? 0 : (int)rng_int(-4, 4);
                for (int st = 0; st < abs(steps); st++)
                    x = nextafter(x, steps > 0 ? INFINITY : -INFINITY);
                nd[3 * i + k] = x;
            }
        s = vm(nd, 4 * m, 0);
        if (s) {
            CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
            if (check_vm(nd, 4 * m, s, 20000))
                fprintf(stderr, "  near-duplicate trial %d failed\n", trial);
            mfg_spoly_free(s);
        }
        free(nd);
        free(base);
    }
    free(p);
}

/* ---- many hull vertices, draft, large inputs ---------------------------------------- */

static void test_many_hull_vertices(void)
{
    int64_t ks[] = {64, 65, 100, 1000};
    for (int t = 0; t < 4; t++) {
        int64_t k = ks[t];
        double *p = malloc((size_t)k * 3 * sizeof(double));
        for (int64_t i = 0; i < k; i++) {
            double a = 2 * M_PI * (double)i / (double)k;
            p[3 * i] = 0.5 * cos(a);
            p[3 * i + 1] = 0.5 * sin(a);
            p[3 * i + 2] = sqrt(0.75);
        }
        mfg_spoly *s = vm(p, k, 0);
        if (s) {
            CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
            CHECK_EQ_INT(s->nvertices, k);
            double c = cos(M_PI / (double)k), z = c / sqrt(c * c + 3);
            for (int64_t i = 0; i < s->nvertices; i++)
                CHECK(fabs(s->vertices[3 * i + 2] - z) < 1e-12);
            check_vm(p, k, s, 20000);
            mfg_spoly_free(s);
        }
        free(p);
    }
}

static void test_draft(void)
{
    for (int trial = 0; trial < 8; trial++) {
        int64_t m = (int64_t[]){1, 2, 3, 6, 30, 1, 2, 100}[trial];
        double c[3];
        random_dir(c);
        double *p = cap_normals(m, c, rng_uniform(0.05, 0.9));
        double alpha = rng_uniform(0.01, 0.4), sa = sin(alpha);
        mfg_spoly *s = vm(p, m, alpha);
        if (s) {
            CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
            double *pn = normalised(p, m);
            for (int64_t i = 0; i < s->nvertices; i++)
                CHECK(min_dot(s->vertices + 3 * i, pn, m) >= sa - 1e-12);
            /* directions deeper than 2e-4 in the drafted set are inside the polygon */
            int64_t deep = 0, missed = 0;
            for (int k = 0; k < 100000; k++) {
                double d[3];
                cap_sample(c, M_PI / 2, d);
                if (min_dot(d, pn, m) >= sa + 2e-4) {
                    deep++;
                    missed += !in_polygon(d, s, 1e-12);
                }
            }
            CHECK(deep > 0);
            CHECK_EQ_INT(missed, 0);
            if (missed)
                fprintf(stderr, "  draft trial %d (m = %lld, alpha = %.17g): %lld of %lld "
                                "deep directions missed\n",
                        trial, (long long)m, alpha, (long long)missed, (long long)deep);
            free(pn);
            mfg_spoly_free(s);
        }
        free(p);
    }
    /* a degenerate map has no direction strictly inside: drafted, it is empty */
    double anti[6] = {0, 0, 1, 0, 0, -1};
    mfg_spoly *s = vm(anti, 2, 0.1);
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_NULL);
        mfg_spoly_free(s);
    }
}

static void test_million_normals(void)
{
    const int64_t m = 1000000;
    double c[3] = {0.3, -0.2, 1};
    unit3(c);
    double *p = cap_normals(m, c, 1.2);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    mfg_spoly *s = vm(p, m, 0);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    double secs = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (s) {
        printf("  10^6 normals: %lld vertices in %.3f s\n", (long long)s->nvertices, secs);
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        double *pn = normalised(p, m);
        /* every vertex satisfies all 10^6 constraints and is tight on two of them */
        for (int64_t i = 0; i < s->nvertices; i++) {
            const double *v = s->vertices + 3 * i;
            int64_t tight = 0;
            double lo = 2;
            for (int64_t j = 0; j < m; j++) {
                double x = dot3(v, pn + 3 * j);
                lo = fmin(lo, x);
                tight += fabs(x) < 1e-12;
            }
            CHECK(lo >= -1e-12);
            CHECK(tight >= 2);
        }
        CHECK(in_polygon(c, s, -1e-15));
        free(pn);
        mfg_spoly_free(s);
    }
    free(p);
}

/* ---- exact reference hulls on integer normals --------------------------------------- */

/* Normals with integer coordinates below 2^19 make every determinant and dot product an
 * exact 128-bit integer: a reference independent of the library's predicates. */
typedef __int128 i128;

static i128 idot(const double *a, const double *b)
{
    return (i128)(int64_t)a[0] * (int64_t)b[0] + (i128)(int64_t)a[1] * (int64_t)b[1] +
           (i128)(int64_t)a[2] * (int64_t)b[2];
}

static void icross(const double *a, const double *b, i128 o[3])
{
    int64_t a0 = (int64_t)a[0], a1 = (int64_t)a[1], a2 = (int64_t)a[2];
    int64_t b0 = (int64_t)b[0], b1 = (int64_t)b[1], b2 = (int64_t)b[2];
    o[0] = (i128)a1 * b2 - (i128)a2 * b1;
    o[1] = (i128)a2 * b0 - (i128)a0 * b2;
    o[2] = (i128)a0 * b1 - (i128)a1 * b0;
}

static int sign128(i128 x)
{
    return (x > 0) - (x < 0);
}

static int iorient(const double *a, const double *b, const double *c) /* sign det[a,b,c] */
{
    i128 n[3];
    icross(b, c, n);
    return sign128(n[0] * (int64_t)a[0] + n[1] * (int64_t)a[1] + n[2] * (int64_t)a[2]);
}

/* sign of (a x b).(c x d) = (a.c)(b.d) - (a.d)(b.c) */
static int icross_dot(const double *a, const double *b, const double *c, const double *d)
{
    return sign128(idot(a, c) * idot(b, d) - idot(a, d) * idot(b, c));
}

static int same_ray(const double *a, const double *b)
{
    i128 n[3];
    icross(a, b, n);
    return n[0] == 0 && n[1] == 0 && n[2] == 0 && idot(a, b) > 0;
}

/* The hull of integer normals p (pointed: c.p > 0 for all, else -1) by gift wrapping:
 * from the lexicographically first projection (x = p.e1 / p.c, then y = p.e2 / p.c;
 * e1, e2, c independent), the next vertex is the normal with every other one left of or
 * on the great circle to it, the farthest one among those on it.  Writes the indices
 * counter-clockwise to idx and returns their number.  O(m h), exact. */
static int64_t reference_hull(const double *p, int64_t m, const double *c, int64_t *idx)
{
    for (int64_t i = 0; i < m; i++)
        if (idot(c, p + 3 * i) <= 0)
            return -1;
    double e[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    int skip = fabs(c[0]) >= fabs(c[1]) && fabs(c[0]) >= fabs(c[2]) ? 0
               : fabs(c[1]) >= fabs(c[2])                           ? 1
                                                                    : 2;
    const double *e1 = e[skip == 0 ? 1 : 0], *e2 = e[skip == 2 ? 1 : 2];
    int64_t s = 0;
    for (int64_t i = 1; i < m; i++) {
        int x = icross_dot(p + 3 * i, p + 3 * s, e1, c); /* sign(x_i - x_s) */
        if (x < 0 || (x == 0 && icross_dot(p + 3 * i, p + 3 * s, e2, c) < 0))
            s = i;
    }
    int64_t h = 0, cur = s;
    do {
        int64_t cand = -1;
        for (int64_t k = 0; k < m; k++) {
            const double *q = p + 3 * k;
            if (same_ray(p + 3 * cur, q))
                continue;
            if (cand < 0) {
                cand = k;
                continue;
            }
            int o = iorient(p + 3 * cur, p + 3 * cand, q);
            /* q beyond cand along the same great circle: the angle cur -> q is larger */
            if (o < 0 || (o == 0 && icross_dot(p + 3 * cand, q, p + 3 * cur, p + 3 * cand) > 0))
                cand = k;
        }
        if (cand < 0 || h >= m)
            return -2;
        idx[h++] = cand;
        cur = cand;
    } while (!same_ray(p + 3 * cur, p + 3 * s));
    return h;
}

/* The map's vertices from the reference hull, u_i x u_i+1 (exact integers, then unit),
 * matched against s cyclically; returns the largest deviation (INFINITY: other kind or
 * count). */
static double reference_deviation(const double *p, const int64_t *idx, int64_t h,
                                  const mfg_spoly *s)
{
    if (s->kind != MFG_VM_POLYGON || s->nvertices != h || h < 3)
        return INFINITY;
    double *w = malloc((size_t)h * 3 * sizeof(double));
    for (int64_t i = 0; i < h; i++) {
        i128 n[3];
        icross(p + 3 * idx[i], p + 3 * idx[(i + 1) % h], n);
        long double x = (long double)n[0], y = (long double)n[1], z = (long double)n[2];
        long double r = sqrtl(x * x + y * y + z * z);
        w[3 * i] = (double)(x / r), w[3 * i + 1] = (double)(y / r), w[3 * i + 2] = (double)(z / r);
    }
    double best = INFINITY;
    for (int64_t off = 0; off < h; off++) { /* the output may start at any vertex */
        double d0 = 0;
        for (int k = 0; k < 3; k++)
            d0 = fmax(d0, fabs(s->vertices[3 * off + k] - w[k]));
        if (d0 > 1e-9)
            continue;
        double worst = 0;
        for (int64_t i = 0; i < h && worst < best; i++)
            for (int k = 0; k < 3; k++)
                worst = fmax(worst, fabs(s->vertices[3 * ((i + off) % h) + k] - w[3 * i + k]));
        best = fmin(best, worst);
    }
    free(w);
    return best;
}

static void random_rotation(double r[9])
{
    double a[3], b[3], c[3];
    random_dir(a);
    do {
        random_dir(b);
        cross3(a, b, c);
    } while (dot3(c, c) < 1e-2);
    unit3(c);
    cross3(c, a, b);
    memcpy(r, a, sizeof a), memcpy(r + 3, b, sizeof b), memcpy(r + 6, c, sizeof c);
}

/* x -> round(scale * R x): rotated to the integer lattice. */
static void lattice(const double r[9], double scale, const double x[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = nearbyint(scale * dot3(r + 3 * i, x));
}

/* Compares the map of integer normals with the reference hull; returns 1 when it matched. */
static int matches_reference(const double *p, int64_t m, const double *c, const char *what)
{
    int64_t *idx = malloc((size_t)m * sizeof(int64_t));
    int64_t h = reference_hull(p, m, c, idx);
    CHECK(h >= 3); /* the construction keeps every case pointed and full */
    mfg_spoly *s = vm(p, m, 0);
    double dev = h >= 3 && s ? reference_deviation(p, idx, h, s) : INFINITY;
    CHECK(dev < 1e-13);
    if (!(dev < 1e-13))
        fprintf(stderr, "  %s (m = %lld): reference hull %lld vertices, map kind %d with %lld, "
                        "deviation %g\n", what, (long long)m, (long long)h, s ? s->kind : -1,
                (long long)(s ? s->nvertices : -1), dev);
    mfg_spoly_free(s);
    free(idx);
    return dev < 1e-13;
}

static void test_reference_hulls(void)
{
    const double R = 262144.0; /* 2^18: coordinates below 2^19 */
    int64_t sizes[] = {10, 47, 48, 49, 50, 97, 333, 1000, 2000};
    for (int trial = 0; trial < 36; trial++) {
        int64_t n = sizes[trial % 9], m = 0;
        int shape = trial / 9; /* tessellated cone, + inside and repeats, + outliers, cap */
        double rot[9], axis[3] = {0, 0, 1}, c[3];
        random_rotation(rot);
        double *p = malloc((size_t)(4 * n + 8) * 3 * sizeof(double));
        double r = rng_uniform(0.05, 1.5), x[3];
        int ordered = trial % 2;
        for (int64_t i = 0; i < n; i++) {
            double ph = ordered ? 2 * M_PI * (double)i / (double)n : rng_uniform(0, 2 * M_PI);
            double rr = shape == 3 ? r * sqrt(rng_uniform(0, 1)) : shape == 2 ? 80 * M_PI / 180 : r;
            x[0] = sin(rr) * cos(ph), x[1] = sin(rr) * sin(ph), x[2] = cos(rr);
            lattice(rot, R, x, p + 3 * m++);
            if (shape == 1 && i % 3 == 0) { /* an inside normal and an exact repeat 3p */
                double in[3] = {0.3 * x[0], 0.3 * x[1], x[2]};
                lattice(rot, R, in, p + 3 * m++);
                for (int k = 0; k < 3; k++)
                    p[3 * m + k] = 3 * p[3 * (m - 2) + k];
                m++;
            }
            if (shape == 1 && i % 3 == 1) { /* the same doubles again, and 4p */
                memcpy(p + 3 * m, p + 3 * (m - 1), 3 * sizeof(double));
                for (int k = 0; k < 3; k++)
                    p[3 * m + 3 + k] = 4 * p[3 * (m - 1) + k];
                m += 2;
            }
            if (shape == 2 && i % 5 == 0) { /* below the circle's plane on one side */
                double ps = rng_uniform(-0.3, 0.3), o[3] = {cos(ps), sin(ps), -0.05};
                lattice(rot, R, o, p + 3 * m++);
            }
        }
        if (shape == 2) { /* the circle's axis would be outside these normals' map */
            axis[0] = cos(82 * M_PI / 180), axis[2] = sin(82 * M_PI / 180);
        }
        lattice(rot, R, axis, c);
        if (!ordered)
            shuffle(p, m);
        char what[64];
        snprintf(what, sizeof what, "reference trial %d (shape %d)", trial, shape);
        matches_reference(p, m, c, what);
        free(p);
    }
    /* corners and normals exactly on each edge's great circle, (k - t) u_i + t u_i+1: only
     * the corners are vertices (a hull of 60 or 200 corners is built in batches) */
    for (int trial = 0; trial < 6; trial++) {
        int64_t nc = (int64_t[]){5, 5, 60, 60, 200, 200}[trial];
        int64_t k = (int64_t[]){3, 100, 4, 30, 3, 10}[trial], m = 0;
        double rot[9], z[3] = {0, 0, 1}, c[3];
        random_rotation(rot);
        double *u = malloc((size_t)nc * 3 * sizeof(double));
        for (int64_t i = 0; i < nc; i++) {
            double t = 2 * M_PI * ((double)i + rng_uniform(0, 0.3)) / (double)nc;
            double x[3] = {0.6 * cos(t), 0.6 * sin(t), 0.8};
            lattice(rot, 1e5, x, u + 3 * i);
        }
        lattice(rot, 1e5, z, c);
        double *p = malloc((size_t)(nc * k) * 3 * sizeof(double));
        for (int64_t i = 0; i < nc; i++)
            for (int64_t t = 0; t < k; t++, m++)
                for (int j = 0; j < 3; j++)
                    p[3 * m + j] = (double)(k - t) * u[3 * i + j] + (double)t * u[3 * ((i + 1) % nc) + j];
        if (trial % 2)
            shuffle(p, m);
        if (matches_reference(p, m, c, "normals along the edges") && nc == 5) {
            mfg_spoly *s = vm(p, m, 0);
            if (s)
                CHECK_EQ_INT(s->nvertices, 5);
            mfg_spoly_free(s);
        }
        free(p);
        free(u);
    }
    /* nearly hemispherical: (R cos t, R sin t, 1), a map of radius about 1/R, each
     * coordinate permutation and sign pattern */
    for (int trial = 0; trial < 6; trial++) {
        int64_t m = (int64_t[]){60, 200, 700, 1500, 2000, 120}[trial];
        double *p = malloc((size_t)m * 3 * sizeof(double)), c[3] = {0, 0, 0};
        int perm = trial % 3, flip = trial % 2 ? -1 : 1;
        for (int64_t i = 0; i < m; i++) {
            double t = 2 * M_PI * (double)i / (double)m + (trial >= 3 ? rng_uniform(0, 1e-3) : 0);
            double v[3] = {nearbyint(R * cos(t)), nearbyint(R * sin(t)), 1};
            for (int k = 0; k < 3; k++)
                p[3 * i + (k + perm) % 3] = flip * v[k];
        }
        c[(2 + perm) % 3] = flip;
        if (trial >= 3)
            shuffle(p, m);
        matches_reference(p, m, c, "nearly hemispherical");
        free(p);
    }
}

/* Circles of normals 0.88e-9 rad short of the equator: the map is a cap of that radius.
 * Every normal is a vertex (the arcs between neighbours bulge by about
 * (2 pi / m)^2 cot(r) / 8 > 1e-13, far above rounding).  The centre of such a hull's
 * vertex subset can lie next to its boundary; an inscribed "cap" of radius below 1e-8
 * has cos r = 1 in floating point, and a later vertex at that centre, dot = 1 + 2^-52,
 * was skipped as inside (these m lost one vertex). */
static void test_nearly_hemispherical_cones(void)
{
    int64_t ms[] = {120, 155, 219, 237, 399};
    for (int t = 0; t < 5; t++) {
        int64_t m = ms[t];
        double r = M_PI / 2 - 0.88e-9, *p = malloc((size_t)m * 3 * sizeof(double));
        for (int64_t i = 0; i < m; i++) {
            double ph = 2 * M_PI * (double)i / (double)m;
            p[3 * i] = sin(r) * cos(ph), p[3 * i + 1] = sin(r) * sin(ph), p[3 * i + 2] = cos(r);
        }
        mfg_spoly *s = vm(p, m, 0);
        if (s) {
            CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
            CHECK_EQ_INT(s->nvertices, m);
            /* a regular m-gon of inradius 0.88e-9 about the pole */
            for (int64_t i = 0; i < s->nvertices; i++) {
                const double *v = s->vertices + 3 * i;
                double rho = atan2(sqrt(v[0] * v[0] + v[1] * v[1]), v[2]);
                CHECK(fabs(rho - 0.88e-9 / cos(M_PI / (double)m)) < 1e-14);
            }
            mfg_spoly_free(s);
        }
        free(p);
    }
}

/* ---- large degenerate cones: the kinds stay exact ----------------------------------- */

/* Normals on the circle of angular radius r about e3 (t_i = 2 pi i / n + phase), rotated. */
static double *tessellated_cone(int64_t n, double r, const double rot[9], double phase)
{
    double *p = malloc((size_t)(n + 2) * 3 * sizeof(double));
    for (int64_t i = 0; i < n; i++) {
        double t = 2 * M_PI * (double)i / (double)n + phase;
        double x[3] = {sin(r) * cos(t), sin(r) * sin(t), cos(r)};
        for (int k = 0; k < 3; k++)
            p[3 * i + k] = dot3(rot + 3 * k, x);
    }
    return p;
}

static void test_large_degenerate(void)
{
    for (int trial = 0; trial < 6; trial++) {
        int64_t n = (int64_t[]){100, 1000, 3000}[trial % 3];
        double rot[9], axis[3];
        random_rotation(rot);
        for (int k = 0; k < 3; k++)
            axis[k] = rot[3 * k + 2];
        double *p = tessellated_cone(n, rng_uniform(0.2, 1.3), rot, 0.1);
        /* every normal a vertex: an n-gon */
        mfg_spoly *s = vm(p, n, 0);
        if (s) {
            CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
            CHECK_EQ_INT(s->nvertices, n);
            CHECK(in_polygon(axis, s, -1e-15));
            mfg_spoly_free(s);
        }
        /* plus the opposite of the axis, first, in the middle or last: no direction */
        for (int where = 0; where < 3; where++) {
            int64_t at = (int64_t[]){0, n / 2, n}[where];
            double *q = malloc((size_t)(n + 1) * 3 * sizeof(double));
            memcpy(q, p, (size_t)at * 3 * sizeof(double));
            for (int k = 0; k < 3; k++)
                q[3 * at + k] = -axis[k];
            memcpy(q + 3 * (at + 1), p + 3 * at, (size_t)(n - at) * 3 * sizeof(double));
            if ((s = vm(q, n + 1, 0))) {
                CHECK_EQ_INT(s->kind, MFG_VM_NULL);
                mfg_spoly_free(s);
            }
            /* the opposite of one normal instead: the map shrinks to that normal's edge,
             * from u_j-1 x u_j to u_j x u_j+1 */
            int64_t j = (int64_t[]){1, n / 3, n - 1}[where];
            for (int k = 0; k < 3; k++)
                q[3 * at + k] = -p[3 * j + k];
            if ((s = vm(q, n + 1, 0))) {
                CHECK_EQ_INT(s->kind, MFG_VM_EDGE);
                CHECK_EQ_INT(s->closed, 0);
                if (s->kind == MFG_VM_EDGE && s->nvertices == 3) {
                    double e0[3], e1[3];
                    cross3(p + 3 * ((j + n - 1) % n), p + 3 * j, e0);
                    cross3(p + 3 * j, p + 3 * ((j + 1) % n), e1);
                    unit3(e0), unit3(e1);
                    const double *a = s->vertices, *b = s->vertices + 6;
                    double d1 = fmax(fmax(fabs(a[0] - e0[0]), fabs(a[1] - e0[1])), fabs(a[2] - e0[2])) +
                                fmax(fmax(fabs(b[0] - e1[0]), fabs(b[1] - e1[1])), fabs(b[2] - e1[2]));
                    double d2 = fmax(fmax(fabs(a[0] - e1[0]), fabs(a[1] - e1[1])), fabs(a[2] - e1[2])) +
                                fmax(fmax(fabs(b[0] - e0[0]), fabs(b[1] - e0[1])), fabs(b[2] - e0[2]));
                    CHECK(fmin(d1, d2) < 1e-12);
                    for (int v = 0; v < 3; v++)
                        CHECK(fabs(dot3(s->vertices + 3 * v, p + 3 * j)) < 1e-12);
                }
                mfg_spoly_free(s);
            }
            free(q);
        }
        free(p);
        /* a cylinder: normals on a great circle (exactly: integer combinations i a + j b
         * of two integer vectors); all around: both poles (POINT); all around plus one
         * end face: the pole above it; one half with its two ends exactly opposite: the
         * half circle (EDGE) */
        double ia[3], ib[3], pole[3];
        for (int k = 0; k < 3; k++)
            ia[k] = (double)rng_int(-1000, 1000), ib[k] = (double)rng_int(-1000, 1000);
        cross3(ia, ib, pole);
        unit3(pole);
        p = malloc((size_t)(n + 1) * 3 * sizeof(double));
        for (int64_t i = 0; i < n; i++) {
            double t = 2 * M_PI * (double)i / (double)n, ci = nearbyint(1000 * cos(t)),
                   si = nearbyint(1000 * sin(t));
            for (int k = 0; k < 3; k++)
                p[3 * i + k] = ci * ia[k] + si * ib[k];
        }
        if (trial % 2)
            shuffle(p, n);
        if ((s = vm(p, n, 0))) {
            CHECK_EQ_INT(s->kind, MFG_VM_POINT);
            CHECK_EQ_INT(s->nvertices, 2);
            if (s->nvertices == 2)
                CHECK(fabs(fabs(dot3(s->vertices, pole)) - 1) < 1e-12 &&
                      fabs(dot3(s->vertices + 3, pole) + dot3(s->vertices, pole)) < 1e-12);
            mfg_spoly_free(s);
        }
        cross3(ia, ib, p + 3 * n); /* exact: integers below 2^22 */
        if ((s = vm(p, n + 1, 0))) {
            CHECK_EQ_INT(s->kind, MFG_VM_POINT);
            CHECK_EQ_INT(s->nvertices, 1);
            if (s->nvertices == 1)
                CHECK(dot3(s->vertices, pole) > 1 - 1e-12);
            mfg_spoly_free(s);
        }
        int64_t half = 0; /* t in [0, pi): i a + j b with j >= 0, then -1000 a */
        for (int64_t i = 0; i < n; i++) {
            double t = 2 * M_PI * (double)i / (double)n;
            if (t >= M_PI)
                continue;
            double ci = nearbyint(1000 * cos(t)), si = nearbyint(1000 * sin(t));
            for (int k = 0; k < 3; k++)
                p[3 * half + k] = ci * ia[k] + si * ib[k];
            half++;
        }
        for (int k = 0; k < 3; k++)
            p[3 * half + k] = -1000 * ia[k];
        half++;
        if (trial % 2)
            shuffle(p, half);
        if ((s = vm(p, half, 0))) {
            CHECK_EQ_INT(s->kind, MFG_VM_EDGE);
            CHECK_EQ_INT(s->closed, 0);
            check_vm(p, half, s, 20000);
            mfg_spoly_free(s);
        }
        free(p);
    }
    /* near-duplicates of every normal (3p rounded, a few ulps off) on a large cone: merged
     * in the output to the clean cone's map */
    double rot[9];
    random_rotation(rot);
    int64_t n = 500;
    double *p = tessellated_cone(n, 0.9, rot, 0.0);
    double *q = malloc((size_t)(3 * n) * 3 * sizeof(double));
    for (int64_t i = 0; i < 3 * n; i++)
        for (int k = 0; k < 3; k++) {
            double x = p[3 * (i % n) + k];
            q[3 * i + k] = i < n ? x : i < 2 * n ? 3 * x : nextafter(x, i % 2 ? 2.0 : -2.0);
        }
    shuffle(q, 3 * n);
    mfg_spoly *a = vm(p, n, 0), *b = vm(q, 3 * n, 0);
    if (a && b) {
        CHECK_EQ_INT(b->kind, MFG_VM_POLYGON);
        CHECK_EQ_INT(b->nvertices, n);
        double worst = 0; /* every vertex of b within 1e-10 of one of a */
        for (int64_t i = 0; i < b->nvertices; i++) {
            double near = INFINITY;
            for (int64_t j = 0; j < a->nvertices; j++) {
                double d = 0;
                for (int k = 0; k < 3; k++)
                    d = fmax(d, fabs(b->vertices[3 * i + k] - a->vertices[3 * j + k]));
                near = fmin(near, d);
            }
            worst = fmax(worst, near);
        }
        CHECK(worst < 1e-10);
    }
    mfg_spoly_free(a);
    mfg_spoly_free(b);
    free(q);
    free(p);
}

/* Drafted maps of many hull normals against the definition: every vertex meets the draft
 * for every normal, every direction 2e-4 deeper than the draft is inside, the polygon is
 * convex and counter-clockwise, and it is empty exactly when the draft exceeds the map's
 * inscribed radius (up to 1e-6). */
static void test_draft_many_normals(void)
{
    for (int trial = 0; trial < 16; trial++) {
        int64_t m = (int64_t[]){40, 300, 2000, 5000}[trial % 4];
        double rot[9], axis[3], r = rng_uniform(0.3, 1.3);
        random_rotation(rot);
        for (int k = 0; k < 3; k++)
            axis[k] = rot[3 * k + 2];
        double *p;
        if (trial < 8) { /* a tessellated cone, its map a regular m-gon */
            p = tessellated_cone(m, r, rot, 0.0);
        } else { /* normals in a cap squeezed to an ellipse: caps of unequal reach */
            p = malloc((size_t)m * 3 * sizeof(double));
            for (int64_t i = 0; i < m; i++) {
                double t = rng_uniform(0, 2 * M_PI), rr = r * sqrt(rng_uniform(0, 1));
                double x[3] = {sin(rr) * cos(t), 0.4 * sin(rr) * sin(t), cos(rr)};
                for (int k = 0; k < 3; k++)
                    p[3 * i + k] = dot3(rot + 3 * k, x);
            }
        }
        double *pn = normalised(p, m), deepest = -2;
        /* the map's inscribed radius, from the deepest of dense samples about the axis */
        for (int k = 0; k < 20000; k++) {
            double d[3];
            cap_sample(axis, M_PI / 2 - r + 0.01, d);
            deepest = fmax(deepest, min_dot(d, pn, m));
        }
        double inradius = asin(fmin(1.0, deepest));
        double alpha = inradius * (trial % 2 ? rng_uniform(0.05, 0.9) : 1.05);
        double sa = sin(alpha);
        mfg_spoly *s = vm(p, m, alpha);
        if (s) {
            if (alpha > inradius) {
                CHECK_EQ_INT(s->kind, MFG_VM_NULL);
            } else if (alpha < inradius - 1e-6) {
                CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
                int64_t n = s->nvertices, missed = 0, deep = 0;
                for (int64_t i = 0; i < n; i++) {
                    CHECK(min_dot(s->vertices + 3 * i, pn, m) >= sa - 1e-12);
                    double e[3];
                    cross3(s->vertices + 3 * i, s->vertices + 3 * ((i + 1) % n), e);
                    for (int64_t j = i % 7; j < n; j += 1 + n / 64) /* a sample of them */
                        CHECK(dot3(s->vertices + 3 * j, e) >= -1e-15);
                }
                for (int k = 0; k < 20000; k++) {
                    double d[3];
                    cap_sample(axis, M_PI / 2 - r + 0.01, d);
                    if (min_dot(d, pn, m) >= sa + 2e-4) {
                        deep++;
                        missed += !in_polygon(d, s, 1e-12);
                    }
                }
                CHECK_EQ_INT(missed, 0);
                if (missed)
                    fprintf(stderr, "  draft trial %d (m = %lld): %lld of %lld deep directions "
                                    "outside\n", trial, (long long)m, (long long)missed,
                            (long long)deep);
            }
            mfg_spoly_free(s);
        }
        free(pn);
        free(p);
    }
}

/* Angular distance from unit x to a CCW convex polygon (0 inside). */
static double polygon_distance(const double *x, const mfg_spoly *s)
{
    int64_t n = s->nvertices;
    if (in_polygon(x, s, 0.0))
        return 0.0;
    double best = 4.0;
    for (int64_t i = 0; i < n; i++) {
        const double *a = s->vertices + 3 * i, *b = s->vertices + 3 * ((i + 1) % n);
        double e[3], p[3], t[3];
        cross3(a, b, e);
        unit3(e);
        double h = dot3(x, e);
        for (int k = 0; k < 3; k++)
            p[k] = x[k] - h * e[k];
        cross3(a, p, t);
        double in_a = dot3(t, e);
        cross3(p, b, t);
        if (in_a >= 0 && dot3(t, e) >= 0)
            best = fmin(best, asin(fmin(1.0, fabs(h))));
        else
            best = fmin(best, fmin(acos(fmin(1.0, dot3(x, a))), acos(fmin(1.0, dot3(x, b)))));
    }
    return best;
}

/* The largest distance from the polygon of D's true corners: the meeting points of two
 * caps' circles that lie in every cap (an exact corner is where sampling by chords can
 * lose most: the old clipping lost up to 7e-4 rad at sharp corners). */
static double worst_corner_distance(const double *pn, int64_t m, double sa, const mfg_spoly *s)
{
    double worst = 0.0;
    for (int64_t i = 0; i < m; i++)
        for (int64_t j = 0; j < m; j++) {
            const double *a = pn + 3 * i, *b = pn + 3 * j;
            double g = dot3(a, b), w[3], x[3];
            cross3(a, b, w);
            if (i == j || g <= -1.0 || dot3(w, w) < 1e-24)
                continue;
            double f = sa / (1.0 + g), t2 = 1.0 - 2.0 * sa * f;
            if (t2 < 0.0)
                continue;
            unit3(w);
            for (int k = 0; k < 3; k++)
                x[k] = f * (a[k] + b[k]) + sqrt(t2) * w[k];
            if (min_dot(x, pn, m) >= sa - 1e-12)
                worst = fmax(worst, polygon_distance(x, s));
        }
    return worst;
}

/* Checks a drafted map against its definition D = { d : d.p^ >= sin a }: every vertex in
 * D (within 1e-12), the polygon convex and counter-clockwise, and every sample of D deeper
 * than 2e-4 (a margin of twice MFG_DRAFT_TOL) inside it; a NULL map has no such sample;
 * for up to 60 normals, D's corners within MFG_DRAFT_TOL of the polygon.  Samples:
 * uniform directions and directions about centre.  Returns 1 when all hold. */
static int drafted_map_ok(const double *p, int64_t m, double a, const mfg_spoly *s,
                          const double *centre, int nsamp)
{
    double *pn = normalised(p, m), sa = sin(a), deep_s = sin(fmin(a + 2e-4, M_PI / 2));
    int ok = 1;
    int64_t n = s->kind == MFG_VM_POLYGON ? s->nvertices : 0;
    if (s->kind != MFG_VM_POLYGON && s->kind != MFG_VM_NULL)
        ok = 0;
    for (int64_t i = 0; i < n && ok; i++) {
        if (min_dot(s->vertices + 3 * i, pn, m) < sa - 1e-12)
            ok = 0;
        double e[3];
        cross3(s->vertices + 3 * i, s->vertices + 3 * ((i + 1) % n), e);
        for (int64_t j = 0; j < n; j++)
            if (dot3(s->vertices + 3 * j, e) < -1e-15)
                ok = 0;
    }
    for (int k = 0; k < nsamp && ok; k++) {
        double d[3];
        if (k % 2)
            random_dir(d);
        else
            cap_sample(centre, rng_uniform(0, M_PI / 2), d);
        if (min_dot(d, pn, m) >= deep_s && (n == 0 || !in_polygon(d, s, 1e-12)))
            ok = 0;
    }
    if (ok && n > 0 && m <= 60 && worst_corner_distance(pn, m, sa, s) > MFG_DRAFT_TOL)
        ok = 0;
    free(pn);
    return ok;
}

/* The raw-API fuzz case: 12 normals of a long, thin hull, draft 0.3.  The deque of caps
 * (commit e4acd45) kept caps whose corners lay outside other caps and returned a
 * 188-gon with a vertex at d.p^ = -0.73, where the draft asks sin 0.3 = 0.2955. */
static void test_draft_fuzz_case(void)
{
    static const double p[36] = {
        -0x1.4p-2, -0x1.cp-4, 0x1.18p+0, 0x1.3p-2, -0x1.2p-3, 0x1.1p+0,
        0x1.1p-2, -0x1.6p-3, 0x1.08p+0, -0x1.c4p+0, -0x1.ap-3, 1,
        0x1.ap-3, -0x1.ep-3, 0x1.fp-1, 0x1.6p-3, -0x1.1p-2, 0x1.ep-1,
        0x1.2p-3, -0x1.3p-2, 0x1.dp-1, 0x1.cp-4, 0x1.4p-2, 0x1.cp-1,
        0x1.4p-4, 0x1.2p-2, 0x1.bp-1, 0x1.8p-5, 0x1p-2, 0x1.ap-1,
        0x1p-6, 0x1.cp-3, 0x1.9p-1, 0x1.fcp+0, 0x1.8p-3, 0x1.8p-1};
    mfg_spoly *s = vm(p, 12, 0.3);
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        double c[3] = {0, 0, 1};
        CHECK(drafted_map_ok(p, 12, 0.3, s, c, 200000));
        mfg_spoly_free(s);
    }
}

/* A long thin hull (11 normals, draft 0.72) whose deque boundary is not certified: the
 * plain clipping of cap polygons cut 7e-4 rad off a sharp corner of D (the chords of two
 * caps meeting at a small angle), seven times MFG_DRAFT_TOL.  The caps along the clipped
 * polygon, certified, now give the boundary with its exact corners. */
static void test_draft_sharp_corner(void)
{
    static const double p[33] = {
        0x1.f4725f230457ep-3, -0x1.0bae81cd35283p+0, 0x1.129408f18d493p-2,
        -0x1.735f5e2efdb22p-4, -0x1.efb24f65c99edp-1, 0x1.11bdc451a900fp-2,
        0x1.060f6b8884efcp-1, -0x1.1b12dc5e611dbp+0, 0x1.197d0de4533c2p-2,
        -0x1.ee2c0a3feb902p-1, -0x1.8948f99fc7b80p-1, 0x1.07962643229a0p-2,
        -0x1.557a795536723p+0, -0x1.5db3ef494e240p-1, 0x1.0624b581fae90p-2,
        -0x1.d8858dbf63946p-1, -0x1.8dd24e0e83dabp-1, 0x1.0b01fd9db9dfdp-2,
        0x1.8bc9b2d269d62p-1, -0x1.2ada489a7d780p+0, 0x1.15ac1f1b40f62p-2,
        0x1.bf53c38b9cf40p-1, -0x1.308cad8e6ec6ap+0, 0x1.199fb9ff791f2p-2,
        -0x1.029bc2f08c23ep+0, -0x1.83a7e065085f7p-1, 0x1.09975350a82a3p-2,
        -0x1.c4505eb6f56c4p-1, -0x1.92bcdf984963ep-1, 0x1.09640cd862ad2p-2,
        -0x1.253860e2b4e18p-1, -0x1.b6a0ec78568dcp-1, 0x1.10826c62e0947p-2};
    const double a = 0x1.71919c0c7bfcdp-1;
    mfg_spoly *s = vm(p, 11, a);
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        double *pn = normalised(p, 11), c[3] = {0, 0, 0};
        for (int i = 0; i < 33; i++)
            c[i % 3] += pn[i];
        unit3(c);
        if (s->kind == MFG_VM_POLYGON) {
            double worst = worst_corner_distance(pn, 11, sin(a), s);
            CHECK(worst <= MFG_DRAFT_TOL);
            if (worst > MFG_DRAFT_TOL)
                fprintf(stderr, "  sharp corner %.3g rad from the polygon\n", worst);
        }
        CHECK(drafted_map_ok(p, 11, a, s, c, 100000));
        free(pn);
        mfg_spoly_free(s);
    }
}

/* Three close normals and a wide drafted map (cap radius 1.1 rad): its corners are far
 * apart and unevenly spread, so their mean was no centre to measure their order about,
 * the certified boundary was refused twice and the clipped polygon (4e-5 rad short of
 * D's corners) came back.  About the centre of the smallest cap around the normals (a
 * point of D) the boundary is certified and D's three corners are vertices. */
static void test_draft_wide_map_corners(void)
{
    static const double p[9] = {
        -0x1.ce7dd62ffc1e4p-2, -0x1.e6d2e039cd892p-1, 0x1.abb82df21f1f0p-2,
        -0x1.36c193a97d8e5p-1, -0x1.6d237966a700bp-1, 0x1.b7847a0945d3ap-2,
        -0x1.b4ffdbe1ed34cp-2, -0x1.f864e608d5846p-1, 0x1.ae450db3ab0abp-2};
    const double a = 0x1.d30473f80adc8p-2;
    mfg_spoly *s = vm(p, 3, a);
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_POLYGON);
        if (s->kind == MFG_VM_POLYGON) {
            double *pn = normalised(p, 3), c[3] = {0, 0, 0};
            for (int i = 0; i < 9; i++)
                c[i % 3] += pn[i];
            unit3(c);
            /* 1e-6: the caps' 1e-12 hair moves a corner of nearly tangent circles more */
            CHECK(worst_corner_distance(pn, 3, sin(a), s) < 1e-6);
            CHECK(drafted_map_ok(p, 3, a, s, c, 100000));
            free(pn);
        }
        mfg_spoly_free(s);
    }
}

/* Drafted maps of random hulls (3..200 normals) against the definition, random drafts
 * in [0, pi/2): caps, long thin hulls (where the deque failed), hulls near a hemisphere
 * and loose clusters. */
static void test_draft_random_hulls(void)
{
    int failed = 0;
    for (int trial = 0; trial < 240; trial++) {
        int64_t m = 3 + (int64_t)rng_uniform(0, 197.99);
        double rot[9], x[3], *p = malloc((size_t)m * 3 * sizeof(double));
        random_rotation(rot);
        double len = rng_uniform(0.2, 1.5), wid = pow(10.0, rng_uniform(-4, -0.5));
        double rad = rng_uniform(0.05, 1.5), zmax = rng_uniform(0.001, 0.3);
        for (int64_t i = 0; i < m; i++) {
            double t = rng_uniform(0, 2 * M_PI), rr = rad * sqrt(rng_uniform(0, 1));
            switch (trial % 4) {
            case 0: /* a cap */
                x[0] = sin(rr) * cos(t), x[1] = sin(rr) * sin(t), x[2] = cos(rr);
                break;
            case 1: /* long and thin */
                x[0] = rng_uniform(-len, len), x[1] = rng_uniform(-wid, wid), x[2] = 1;
                break;
            case 2: /* near a hemisphere's rim */
                x[0] = cos(t), x[1] = sin(t), x[2] = rng_uniform(0.001, zmax);
                break;
            default: /* a loose cluster */
                x[0] = rng_uniform(-1, 1) * rad, x[1] = rng_uniform(-1, 1) * rad;
                x[2] = fmax(0.05, 1 + rng_uniform(-1, 1) * rad);
            }
            for (int k = 0; k < 3; k++)
                p[3 * i + k] = dot3(rot + 3 * k, x);
        }
        double axis[3] = {rot[2], rot[5], rot[8]};
        double a = rng_uniform(0, 1.5) * rng_uniform(0, 1);
        mfg_spoly *s = vm(p, m, a);
        if (s) {
            int ok = drafted_map_ok(p, m, a, s, axis, 6000);
            CHECK(ok);
            if (!ok && failed++ < 5)
                fprintf(stderr, "  random draft trial %d (m = %lld, a = %.17g) wrong\n", trial,
                        (long long)m, a);
            mfg_spoly_free(s);
        }
        free(p);
    }
}

/* Found by fuzzing: normals q and -q (so the map lies on GC(q)) and others whose
 * projections onto the plane of GC(q) form a wedge all but a half-plane (sizes 2^37 and
 * 2^-23).  The arc's midpoint, taken as the bisector of the wedge's sides, cancelled to
 * zero: MFG_ERR_INTERNAL "degenerate arc".  Now a short arc on GC(q) in the map. */
static void test_nearly_half_plane_arc(void)
{
    const double t = 0x1.0cp-23, w = -0x1.78p-10;
    double p[22 * 3] = {-0x1.88p+2, -0x1.88p+4, -0x1.88p+4, -0x1.88p+37, -0x1p-29, t};
    int64_t m = 2;
    for (int i = 0; i < 8; i++, m++) {
        p[3 * m] = t, p[3 * m + 1] = t;
        p[3 * m + 2] = i == 3 ? 0x1.6cp-23 : i == 7 ? 0x1.0cp-9 : t;
    }
    for (int i = 0; i < 12; i++, m++)
        p[3 * m] = p[3 * m + 1] = p[3 * m + 2] = w;
    mfg_spoly *s = vm(p, m, 0.0);
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_EDGE);
        double *pn = normalised(p, m), q[3] = {1, 1, 1};
        unit3(q);
        for (int64_t i = 0; i < s->nvertices; i++) {
            CHECK(min_dot(s->vertices + 3 * i, pn, m) >= -1e-12);
            CHECK(fabs(dot3(s->vertices + 3 * i, q)) < 1e-12);
        }
        free(pn);
        mfg_spoly_free(s);
    }
    s = vm(p, m, 0.3); /* no direction strictly inside: drafted, empty */
    if (s) {
        CHECK_EQ_INT(s->kind, MFG_VM_NULL);
        mfg_spoly_free(s);
    }
}

int main(void)
{
    test_kinds();
    test_errors();
    test_random_caps();
    test_permutation_invariance();
    test_duplicates();
    test_many_hull_vertices();
    test_reference_hulls();
    test_nearly_hemispherical_cones();
    test_large_degenerate();
    test_draft();
    test_draft_many_normals();
    test_draft_fuzz_case();
    test_draft_sharp_corner();
    test_draft_wide_map_corners();
    test_draft_random_hulls();
    test_nearly_half_plane_arc();
    test_million_normals();
    return mfg_test_report("test_visibility");
}
