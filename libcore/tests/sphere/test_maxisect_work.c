/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_maxisect_work.c - the maximum / level intersection on maps whose boundaries
 * coincide (issue 17: Mould mode on MSOP_10 and Drilling_1 ran for minutes and grew past
 * 1.5 GB): the answer, checked against coverage counted here at every vertex and circle
 * crossing of the input, and the search's work (cells examined, a private counter)
 * bounded.  Compiles the maximum intersection's sources in directly (the counter is not
 * part of the API). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere/maxisect.h"
#include "maxisect_corpus_maps.h"
#include "mfg_test.h"
#include "mfgeom.h"

/* Before the fix each of these calls examined more than a million cells (then ran out of
 * memory); after it, 35 to 250.  The bound leaves room for changes to the search. */
#define CELL_BOUND 2000

/* The reference's coverage tolerance (radians): above the library's 1e-10, far below
 * the distance between the distinct features of these maps. */
#define REF_TOL 1e-9

static void unit(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l, v[1] /= l, v[2] /= l;
}

static void cross(const double *a, const double *b, double *c)
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Does map (kind, v[0..nv)) hold direction x within REF_TOL?  From mfgeom.h's shapes:
 * a polygon is the intersection of its edges' left half-spaces, an edge the union of its
 * minor arcs, a point one or two directions. */
static int holds(int kind, const double *v, int64_t nv, const double *x)
{
    if (kind == MFG_VM_POINT) {
        for (int64_t k = 0; k < nv; k++) {
            double d[3] = {x[0] - v[3 * k], x[1] - v[3 * k + 1], x[2] - v[3 * k + 2]};
            if (sqrt(dot(d, d)) <= REF_TOL)
                return 1;
        }
        return 0;
    }
    if (kind == MFG_VM_POLYGON) {
        for (int64_t k = 0; k < nv; k++) {
            double n[3];
            cross(v + 3 * k, v + 3 * ((k + 1) % nv), n);
            unit(n);
            if (dot(x, n) < -REF_TOL)
                return 0;
        }
        return 1;
    }
    for (int64_t k = 0; k + 1 < nv; k++) { /* EDGE (none of these maps is closed) */
        const double *a = v + 3 * k, *b = v + 3 * k + 3;
        double n[3], an[3], nb[3];
        cross(a, b, n);
        unit(n);
        if (fabs(dot(x, n)) > REF_TOL)
            continue;
        cross(a, x, an); /* x between a and b on their circle */
        cross(x, b, nb);
        if (dot(an, n) >= -REF_TOL && dot(nb, n) >= -REF_TOL && dot(x, a) + dot(x, b) > 0)
            return 1;
    }
    return 0;
}

static int count_at(const double *V, const int64_t *off, const int32_t *kind, int n,
                    const double *x)
{
    int c = 0;
    for (int i = 0; i < n; i++)
        c += holds(kind[i], V + 3 * off[i], off[i + 1] - off[i], x);
    return c;
}

/* The greatest coverage over every input vertex and every crossing of two of the maps'
 * circles (the maximum of these maps is reached at such a point: their regions are
 * points), and over 2000 random directions. */
static int reference_max(const double *V, const int64_t *off, const int32_t *kind, int n)
{
    int64_t nv = off[n], nc = 0;
    double *circ = malloc((size_t)nv * 3 * sizeof(double));
    for (int i = 0; i < n; i++) {
        int64_t m = off[i + 1] - off[i];
        if (kind[i] == MFG_VM_POINT)
            continue;
        for (int64_t k = 0; k < (kind[i] == MFG_VM_EDGE ? m - 1 : m); k++) {
            cross(V + 3 * (off[i] + k), V + 3 * (off[i] + (k + 1) % m), circ + 3 * nc);
            unit(circ + 3 * nc);
            nc++;
        }
    }
    int best = 0;
    for (int64_t k = 0; k < nv; k++) {
        int c = count_at(V, off, kind, n, V + 3 * k);
        best = c > best ? c : best;
    }
    for (int64_t i = 0; i < nc; i++)
        for (int64_t j = i + 1; j < nc; j++) {
            double x[3];
            cross(circ + 3 * i, circ + 3 * j, x);
            if (dot(x, x) < 1e-20)
                continue; /* the same circle */
            unit(x);
            for (int s = 0; s < 2; s++) {
                int c = count_at(V, off, kind, n, x);
                best = c > best ? c : best;
                x[0] = -x[0], x[1] = -x[1], x[2] = -x[2];
            }
        }
    for (int t = 0; t < 2000; t++) {
        double x[3] = {rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1)};
        if (dot(x, x) < 1e-6)
            continue;
        unit(x);
        int c = count_at(V, off, kind, n, x);
        best = c > best ? c : best;
    }
    free(circ);
    return best;
}

/* Every region's centre is held by each map of its cover and by no other map, and the
 * cover weighs at least `least`. */
static void check_regions(const mfg_regions *r, const double *V, const int64_t *off,
                          const int32_t *kind, int n, int least)
{
    for (int64_t g = 0; g < r->nregions; g++) {
        const double *x = r->centres + 3 * g;
        int64_t len = r->cover_offsets[g + 1] - r->cover_offsets[g];
        CHECK(len >= least);
        int held = 0;
        for (int64_t k = r->cover_offsets[g]; k < r->cover_offsets[g + 1]; k++) {
            int64_t i = r->cover[k];
            held += holds(kind[i], V + 3 * off[i], off[i + 1] - off[i], x);
        }
        CHECK_EQ_INT(held, len);
        CHECK_EQ_INT(count_at(V, off, kind, n, x), len);
    }
}

/* The maps in reverse order: vertices, offsets and kinds rebuilt. */
static void reversed(const double *V, const int64_t *off, const int32_t *kind, int n,
                     double *V2, int64_t *off2, int32_t *kind2)
{
    off2[0] = 0;
    for (int j = 0; j < n; j++) {
        int i = n - 1 - j;
        int64_t m = off[i + 1] - off[i];
        memcpy(V2 + 3 * off2[j], V + 3 * off[i], (size_t)m * 3 * sizeof(double));
        off2[j + 1] = off2[j] + m;
        kind2[j] = kind[i];
    }
}

/* Region centres of r and r2 (the same maps reversed) agree as sets, and so do the
 * covers (index i of r is n - 1 - i of r2). */
static void check_same(const mfg_regions *r, const mfg_regions *r2, int n)
{
    CHECK_EQ_INT(r2->nregions, r->nregions);
    CHECK(r2->weight == r->weight);
    for (int64_t g = 0; g < r->nregions; g++) {
        int found = 0;
        for (int64_t h = 0; h < r2->nregions && !found; h++) {
            const double *a = r->centres + 3 * g, *b = r2->centres + 3 * h;
            if (fabs(a[0] - b[0]) + fabs(a[1] - b[1]) + fabs(a[2] - b[2]) > 1e-12)
                continue;
            int64_t len = r->cover_offsets[g + 1] - r->cover_offsets[g];
            if (r2->cover_offsets[h + 1] - r2->cover_offsets[h] != len)
                continue;
            int same = 1;
            for (int64_t k = 0; k < len && same; k++) {
                int64_t want = n - 1 - r->cover[r->cover_offsets[g] + k], has = 0;
                for (int64_t q = r2->cover_offsets[h]; q < r2->cover_offsets[h + 1]; q++)
                    has |= r2->cover[q] == want;
                same = (int)has;
            }
            found = same;
        }
        CHECK(found);
    }
}

/* One corpus case: the maximum (and, with level > 0, the level regions) of the maps,
 * checked against the reference, in both orders, with the work bounded. */
static void corpus_case(const char *name, const double *V, const int64_t *off,
                        const int32_t *kind, int n, int expect_max, double level)
{
    int best = reference_max(V, off, kind, n);
    CHECK_EQ_INT(best, expect_max);
    double *V2 = malloc((size_t)off[n] * 3 * sizeof(double));
    int64_t *off2 = malloc((size_t)(n + 1) * sizeof(int64_t));
    int32_t *kind2 = malloc((size_t)n * sizeof(int32_t));
    reversed(V, off, kind, n, V2, off2, kind2);
    for (int mode = MODE_MAX; mode <= (level > 0 ? MODE_LEVEL : MODE_MAX); mode++) {
        mfg_regions *r = NULL, *r2 = NULL;
        int64_t cells = -1, cells2 = -1;
        CHECK_EQ_INT(mfg_maxisect_run(mode, &(ms_input){V, off, kind, NULL, n, NULL}, level, &r, &cells),
                     MFG_OK);
        CHECK_EQ_INT(mfg_maxisect_run(mode, &(ms_input){V2, off2, kind2, NULL, n, NULL}, level, &r2, &cells2),
                     MFG_OK);
        printf("%s %s: %lld regions, weight %g, %lld cells (reversed: %lld)\n", name,
               mode == MODE_MAX ? "max" : "level", r ? (long long)r->nregions : -1LL,
               r ? r->weight : -1.0, (long long)cells, (long long)cells2);
        CHECK(cells > 0 && cells <= CELL_BOUND);
        CHECK(cells2 > 0 && cells2 <= CELL_BOUND);
        if (r && r2) {
            CHECK(r->nregions >= 1);
            if (mode == MODE_MAX)
                CHECK(r->weight == best);
            else
                CHECK(r->weight == level);
            check_regions(r, V, off, kind, n, mode == MODE_MAX ? best : (int)ceil(level));
            check_same(r, r2, n);
        }
        mfg_regions_free(r);
        mfg_regions_free(r2);
    }
    free(V2);
    free(off2);
    free(kind2);
}

/* n hemispheres, half HS(+z) and half HS(-z), each a triangle on the equator turned by
 * its own angle: every boundary lies on the equator, which is the maximum (all n). */
static void shared_circle(int n)
{
    double *V = malloc((size_t)n * 9 * sizeof(double));
    int64_t *off = malloc((size_t)(n + 1) * sizeof(int64_t));
    int32_t *kind = malloc((size_t)n * sizeof(int32_t));
    off[0] = 0;
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            double t = i + (i % 2 ? -1.0 : 1.0) * k * 2.0 * M_PI / 3.0;
            V[9 * i + 3 * k] = cos(t);
            V[9 * i + 3 * k + 1] = sin(t);
            V[9 * i + 3 * k + 2] = 0.0;
        }
        off[i + 1] = off[i] + 3;
        kind[i] = MFG_VM_POLYGON;
    }
    mfg_regions *r = NULL;
    int64_t cells = -1;
    CHECK_EQ_INT(mfg_maxisect_run(MODE_MAX, &(ms_input){V, off, kind, NULL, n, NULL}, 0.0, &r, &cells),
                 MFG_OK);
    printf("%d hemispheres on one circle: %lld cells\n", n, (long long)cells);
    CHECK(cells > 0 && cells <= CELL_BOUND);
    if (r) {
        CHECK(r->weight == n);
        CHECK_EQ_INT(r->nregions, 1);
        if (r->nregions == 1) {
            CHECK_EQ_INT(r->kinds[0], MFG_VM_EDGE);
            CHECK_EQ_INT(r->closed[0], 1); /* the whole equator */
            CHECK(fabs(r->centres[2]) <= 1e-12);
            CHECK_EQ_INT(r->cover_offsets[1], n);
        }
    }
    mfg_regions_free(r);
    free(V);
    free(off);
    free(kind);
}

int main(void)
{
    /* Expected maxima from the reference (coverage counted here), checked again above. */
    corpus_case("MSOP_10", MSOP_V, MSOP_OFF, MSOP_KIND, MSOP_N, 39, 0.0);
    corpus_case("Drilling_1", DRILL_V, DRILL_OFF, DRILL_KIND, DRILL_N, 41, DRILL_LEVEL);
    shared_circle(40);
    shared_circle(64);
    return mfg_test_report("maxisect_work");
}
