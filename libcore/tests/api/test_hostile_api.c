/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_hostile_api.c - every public entry point against hostile counts, offsets, NULL
 * pointers and non-finite values: a clean error with a detail, outputs untouched. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "mfg_test.h"
#include "mfgeom.h"

/*
 * A count the caller cannot possibly own memory for (count * element size beyond the
 * address space) or an offset sequence that is not 0, non-decreasing, ... must be
 * rejected before anything is read through it: otherwise the library computes sizes
 * that wrap (offsets {0, 4, INT64_MIN + 2} once gave a 32-byte allocation and a heap
 * overflow) or walks far past the caller's arrays.  Zero counts may instead be
 * MFG_ERR_DEGENERATE ("no rings", "no normals"), as documented.
 */

#define BIT(s) (1u << (s))
#define ANY_ERR (BIT(MFG_ERR_NULL) | BIT(MFG_ERR_INVALID) | BIT(MFG_ERR_DEGENERATE))
#define OUT_SENTINEL 0xA5

static const int64_t HUGE_COUNTS[] = {INT64_MAX, INT64_MAX - 1, (int64_t)1 << 62, (int64_t)1 << 60,
                                      (int64_t)1 << 59};
static const int64_t NEGATIVE_COUNTS[] = {-1, -2, -3, INT64_MIN, INT64_MIN + 1, -((int64_t)1 << 40)};
static const double BAD_REALS[] = {NAN, -NAN, INFINITY, -INFINITY, 1e300, -1e300, 1e-300};

/* Status in the allowed set, a detail message, a known status name. */
static void expect(mfg_status st, unsigned allowed, const char *what, long long which)
{
    mfg_test_checks++;
    if (!(BIT(st) & allowed)) {
        mfg_test_failures++;
        fprintf(stderr, "%s [%lld]: status %d (%s), detail \"%s\"\n", what, which, (int)st,
                mfg_status_str(st), mfg_last_error());
        return;
    }
    if (st != MFG_OK) {
        const char *msg = mfg_last_error();
        if (!msg || !msg[0]) {
            mfg_test_failures++;
            fprintf(stderr, "%s [%lld]: status %d without mfg_last_error() detail\n", what, which,
                    (int)st);
        }
    }
}

static int untouched(const uint8_t *out, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (out[i] != OUT_SENTINEL)
            return 0;
    return 1;
}

/* ------------------------------------------------------------------------ */
/* Offset sequences that must be rejected (one ring/polygon of 3 or 4 vertices is
 * fine, the rest is hostile).  Every sequence has nrings + 1 entries.               */
/* ------------------------------------------------------------------------ */

typedef struct bad_offsets {
    int64_t off[4];
    int64_t n; /* nrings / npolys */
    const char *why;
} bad_offsets;

static const bad_offsets BAD_OFFSETS[] = {
    {{0, 4, INT64_MIN + 2}, 2, "wraps: 4 -> INT64_MIN + 2 (issue 6 repro)"},
    {{0, 3, INT64_MIN + 2}, 2, "wraps: 3 -> INT64_MIN + 2"},
    {{0, 4, INT64_MIN}, 2, "4 -> INT64_MIN"},
    {{0, INT64_MAX}, 1, "INT64_MAX vertices"},
    {{0, INT64_MAX - 1}, 1, "INT64_MAX - 1 vertices"},
    {{0, 4, INT64_MAX}, 2, "second ring of INT64_MAX - 4 vertices"},
    {{0, INT64_MAX, 4}, 2, "INT64_MAX then back to 4"},
    {{0, INT64_MAX, INT64_MIN}, 2, "INT64_MAX then INT64_MIN"},
    {{0, (int64_t)1 << 62}, 1, "2^62 vertices"},
    {{0, ((int64_t)1 << 61) + 3}, 1, "2^61 + 3 vertices (16 bytes each wraps)"},
    {{0, ((int64_t)1 << 60) + 4}, 1, "2^60 + 4 vertices"},
    {{0, 4, 3}, 2, "decreasing"},
    {{0, 4, 8, 7}, 3, "decreasing at the end"},
    {{0, -4}, 1, "negative"},
    {{0, 4, -1}, 2, "negative after positive"},
    {{1, 5}, 1, "not starting at 0"},
    {{-1, 3}, 1, "starting at -1"},
    {{INT64_MIN, 4}, 1, "starting at INT64_MIN"},
    {{INT64_MAX, 4}, 1, "starting at INT64_MAX"},
    {{4, 0}, 1, "starting at 4, going back to 0"},
};
#define NBAD_OFFSETS (sizeof BAD_OFFSETS / sizeof BAD_OFFSETS[0])

/* ------------------------------------------------------------------------ */
/* Point classification                                                     */
/* ------------------------------------------------------------------------ */

/* Two rings of 4 (enough vertices for every "small" offset above: at most 8). */
static const double RINGS[16] = {0, 0, 4, 0, 4, 4, 0, 4, 1, 1, 3, 1, 3, 3, 1, 3};
static const int64_t GOOD_OFF[2] = {0, 4};
static const double PTS[4] = {0.5, 0.5, 2, 2};

static void classify_expect(const double *xy, const int64_t *off, int64_t nrings, const double *pts,
                            int64_t np, double tol, int null_out, unsigned allowed, const char *what,
                            long long which)
{
    uint8_t out[8];
    memset(out, OUT_SENTINEL, sizeof out);
    mfg_status st = mfg_classify_points(xy, off, nrings, pts, np, tol, null_out ? NULL : out);
    expect(st, allowed, what, which);
    if (st != MFG_OK && !untouched(out, sizeof out)) {
        mfg_test_failures++;
        fprintf(stderr, "%s [%lld]: out written on failure\n", what, which);
    }
}

static void region_new_expect(const double *xy, const int64_t *off, int64_t nrings, double tol,
                              unsigned allowed, const char *what, long long which)
{
    mfg_region *sentinel = (mfg_region *)(uintptr_t)&sentinel, *r = sentinel;
    mfg_status st = mfg_region_new(xy, off, nrings, tol, &r);
    expect(st, allowed, what, which);
    if (st == MFG_OK) {
        mfg_region_free(r);
    } else if (r != sentinel) {
        mfg_test_failures++;
        fprintf(stderr, "%s [%lld]: out_region written on failure\n", what, which);
    }
}

static void test_pointclass_offsets(void)
{
    for (size_t c = 0; c < NBAD_OFFSETS; c++) {
        const bad_offsets *b = &BAD_OFFSETS[c];
        classify_expect(RINGS, b->off, b->n, PTS, 2, 0.1, 0, BIT(MFG_ERR_INVALID), b->why, (long long)c);
        region_new_expect(RINGS, b->off, b->n, 0.1, BIT(MFG_ERR_INVALID), b->why, (long long)c);
    }
    /* The message names the problem. */
    int64_t wrap[3] = {0, 4, INT64_MIN + 2};
    uint8_t out[2];
    CHECK_EQ_INT(mfg_classify_points(RINGS, wrap, 2, PTS, 2, 0.1, out), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "ring_offsets") != NULL);
}

static void test_pointclass_counts(void)
{
    /* nrings: negative or beyond anything the offsets array could hold.  The offsets
     * given are fine for one ring, so a huge nrings must be refused before they are
     * walked past their end. */
    for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++) {
        classify_expect(RINGS, GOOD_OFF, NEGATIVE_COUNTS[i], PTS, 2, 0.1, 0, BIT(MFG_ERR_INVALID),
                        "classify nrings < 0", NEGATIVE_COUNTS[i]);
        region_new_expect(RINGS, GOOD_OFF, NEGATIVE_COUNTS[i], 0.1, BIT(MFG_ERR_INVALID),
                          "region_new nrings < 0", NEGATIVE_COUNTS[i]);
    }
    for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++) {
        classify_expect(RINGS, GOOD_OFF, HUGE_COUNTS[i], PTS, 2, 0.1, 0, BIT(MFG_ERR_INVALID),
                        "classify huge nrings", HUGE_COUNTS[i]);
        region_new_expect(RINGS, GOOD_OFF, HUGE_COUNTS[i], 0.1, BIT(MFG_ERR_INVALID),
                          "region_new huge nrings", HUGE_COUNTS[i]);
    }
    classify_expect(RINGS, GOOD_OFF, 0, PTS, 2, 0.1, 0, BIT(MFG_ERR_DEGENERATE), "classify nrings 0", 0);
    region_new_expect(RINGS, GOOD_OFF, 0, 0.1, BIT(MFG_ERR_DEGENERATE), "region_new nrings 0", 0);

    /* npoints: negative or impossibly many (2 * npoints overflowed once). */
    for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++)
        classify_expect(RINGS, GOOD_OFF, 1, PTS, NEGATIVE_COUNTS[i], 0.1, 0, BIT(MFG_ERR_INVALID),
                        "classify npoints < 0", NEGATIVE_COUNTS[i]);
    for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++)
        classify_expect(RINGS, GOOD_OFF, 1, PTS, HUGE_COUNTS[i], 0.1, 0, BIT(MFG_ERR_INVALID),
                        "classify huge npoints", HUGE_COUNTS[i]);
    /* zero points: nothing to do, pts and out may be NULL */
    classify_expect(RINGS, GOOD_OFF, 1, NULL, 0, 0.1, 1, BIT(MFG_OK), "classify npoints 0", 0);

    mfg_region *r = NULL;
    CHECK_EQ_INT(mfg_region_new(RINGS, GOOD_OFF, 1, 0.1, &r), MFG_OK);
    if (!r)
        return;
    uint8_t out[8];
    for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++) {
        memset(out, OUT_SENTINEL, sizeof out);
        expect(mfg_region_classify(r, PTS, NEGATIVE_COUNTS[i], out), BIT(MFG_ERR_INVALID),
               "region_classify npoints < 0", NEGATIVE_COUNTS[i]);
        CHECK(untouched(out, sizeof out));
    }
    for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++) {
        memset(out, OUT_SENTINEL, sizeof out);
        expect(mfg_region_classify(r, PTS, HUGE_COUNTS[i], out), BIT(MFG_ERR_INVALID),
               "region_classify huge npoints", HUGE_COUNTS[i]);
        CHECK(untouched(out, sizeof out));
    }
    expect(mfg_region_classify(r, NULL, 0, NULL), BIT(MFG_OK), "region_classify npoints 0", 0);
    memset(out, OUT_SENTINEL, sizeof out);
    expect(mfg_region_classify(r, NULL, 2, out), BIT(MFG_ERR_NULL), "region_classify pts NULL", 0);
    CHECK(untouched(out, sizeof out));
    expect(mfg_region_classify(r, PTS, 2, NULL), BIT(MFG_ERR_NULL), "region_classify out NULL", 0);
    expect(mfg_region_classify(NULL, PTS, 2, out), BIT(MFG_ERR_NULL), "region_classify region NULL", 0);
    CHECK(untouched(out, sizeof out));
    for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
        double bad[4] = {0.5, 0.5, 2, 2};
        bad[1 + (i & 2)] = BAD_REALS[i];
        memset(out, OUT_SENTINEL, sizeof out);
        expect(mfg_region_classify(r, bad, 2, out), BIT(MFG_ERR_INVALID), "region_classify bad point", (long long)i);
        CHECK(untouched(out, sizeof out));
    }
    int64_t stats[4] = {-7, -7, -7, -7};
    expect(mfg_region_stats(NULL, stats), BIT(MFG_ERR_NULL), "region_stats region NULL", 0);
    CHECK(stats[0] == -7 && stats[1] == -7 && stats[2] == -7 && stats[3] == -7);
    expect(mfg_region_stats(r, NULL), BIT(MFG_ERR_NULL), "region_stats stats NULL", 0);
    expect(mfg_region_stats(r, stats), BIT(MFG_OK), "region_stats", 0);
    CHECK(stats[0] >= 1 && stats[1] >= 1);
    mfg_region_free(r);
    mfg_region_free(NULL);
}

static void test_pointclass_null_and_values(void)
{
    classify_expect(NULL, GOOD_OFF, 1, PTS, 2, 0.1, 0, BIT(MFG_ERR_NULL), "classify xy NULL", 0);
    classify_expect(RINGS, NULL, 1, PTS, 2, 0.1, 0, BIT(MFG_ERR_NULL), "classify offsets NULL", 0);
    classify_expect(RINGS, GOOD_OFF, 1, NULL, 2, 0.1, 0, BIT(MFG_ERR_NULL), "classify pts NULL", 0);
    classify_expect(RINGS, GOOD_OFF, 1, PTS, 2, 0.1, 1, BIT(MFG_ERR_NULL), "classify out NULL", 0);
    region_new_expect(NULL, GOOD_OFF, 1, 0.1, BIT(MFG_ERR_NULL), "region_new xy NULL", 0);
    region_new_expect(RINGS, NULL, 1, 0.1, BIT(MFG_ERR_NULL), "region_new offsets NULL", 0);
    expect(mfg_region_new(RINGS, GOOD_OFF, 1, 0.1, NULL), BIT(MFG_ERR_NULL), "region_new out NULL", 0);
    /* NULL offsets together with a hostile count: still a clean error */
    classify_expect(RINGS, NULL, INT64_MAX, PTS, 2, 0.1, 0, ANY_ERR, "classify offsets NULL, huge nrings", 0);
    region_new_expect(RINGS, NULL, -1, 0.1, ANY_ERR, "region_new offsets NULL, nrings -1", 0);

    for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
        double tol = BAD_REALS[i];
        classify_expect(RINGS, GOOD_OFF, 1, PTS, 2, tol, 0, BIT(MFG_ERR_INVALID), "classify bad tol", (long long)i);
        region_new_expect(RINGS, GOOD_OFF, 1, tol, BIT(MFG_ERR_INVALID), "region_new bad tol", (long long)i);
        double xy[8];
        memcpy(xy, RINGS, sizeof xy);
        xy[(3 * i + 1) % 8] = BAD_REALS[i];
        classify_expect(xy, GOOD_OFF, 1, PTS, 2, 0.1, 0, BIT(MFG_ERR_INVALID), "classify bad vertex", (long long)i);
        region_new_expect(xy, GOOD_OFF, 1, 0.1, BIT(MFG_ERR_INVALID), "region_new bad vertex", (long long)i);
        double pts[4] = {0.5, 0.5, 2, 2};
        pts[i & 3] = BAD_REALS[i];
        classify_expect(RINGS, GOOD_OFF, 1, pts, 2, 0.1, 0, BIT(MFG_ERR_INVALID), "classify bad point", (long long)i);
    }
    classify_expect(RINGS, GOOD_OFF, 1, PTS, 2, -0.1, 0, BIT(MFG_ERR_INVALID), "classify tol < 0", 0);
    region_new_expect(RINGS, GOOD_OFF, 1, -0.1, BIT(MFG_ERR_INVALID), "region_new tol < 0", 0);
}

/* ------------------------------------------------------------------------ */
/* Visibility maps                                                          */
/* ------------------------------------------------------------------------ */

static void vm_expect(const double *normals, int64_t m, double draft, int null_out, unsigned allowed,
                      const char *what, long long which)
{
    mfg_spoly *sentinel = (mfg_spoly *)(uintptr_t)&sentinel, *map = sentinel;
    mfg_status st = mfg_visibility_map(normals, m, draft, null_out ? NULL : &map);
    expect(st, allowed, what, which);
    if (st == MFG_OK) {
        mfg_spoly_free(map);
    } else if (map != sentinel) {
        mfg_test_failures++;
        fprintf(stderr, "%s [%lld]: out_map written on failure\n", what, which);
    }
}

static void test_visibility(void)
{
    static const double N3[9] = {0, 0, 1, 0.3, 0, 1, 0, 0.3, 1};
    for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++)
        vm_expect(N3, NEGATIVE_COUNTS[i], 0.0, 0, BIT(MFG_ERR_INVALID), "visibility m < 0", NEGATIVE_COUNTS[i]);
    for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++)
        vm_expect(N3, HUGE_COUNTS[i], 0.0, 0, BIT(MFG_ERR_INVALID), "visibility huge m", HUGE_COUNTS[i]);
    vm_expect(N3, 0, 0.0, 0, BIT(MFG_ERR_DEGENERATE), "visibility m 0", 0);
    vm_expect(NULL, 3, 0.0, 0, BIT(MFG_ERR_NULL), "visibility normals NULL", 0);
    vm_expect(N3, 3, 0.0, 1, BIT(MFG_ERR_NULL), "visibility out NULL", 0);
    for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
        if (BAD_REALS[i] != 1e-300) /* a tiny draft angle is a valid angle */
            vm_expect(N3, 3, BAD_REALS[i], 0, BIT(MFG_ERR_INVALID), "visibility bad draft", (long long)i);
        double n[9];
        memcpy(n, N3, sizeof n);
        n[(2 * i + 1) % 9] = BAD_REALS[i];
        vm_expect(n, 3, 0.0, 0, BIT(MFG_ERR_INVALID), "visibility bad normal", (long long)i);
    }
    vm_expect(N3, 3, -0.1, 0, BIT(MFG_ERR_INVALID), "visibility draft < 0", 0);
    vm_expect(N3, 3, 2.0, 0, BIT(MFG_ERR_INVALID), "visibility draft >= pi/2", 0);
    mfg_spoly_free(NULL);
}

/* ------------------------------------------------------------------------ */
/* Maximum / level / minimum intersection                                   */
/* ------------------------------------------------------------------------ */

/* Three octant-like triangles (9 vertices: enough for every small offset above). */
static const double SV[27] = {1, 0, 0, 0, 1, 0, 0, 0, 1,   0, 1, 0, -1, 0, 0, 0, 0, 1,
                              /* unit vectors: (0.9, 0.1, 0), (0.1, 0.9, 0), (0.1, 0.1, 1) normalised */
                              0.9938837346736189, 0.11043152607484655, 0, 0.11043152607484655, 0.9938837346736189, 0,
                              0.09901475429766743, 0.09901475429766743, 0.9901475429766743};
static const int64_t SOFF[4] = {0, 3, 6, 9};
static const int32_t SKINDS[4] = {MFG_VM_POLYGON, MFG_VM_POLYGON, MFG_VM_POLYGON, MFG_VM_POLYGON};

enum { MAXI, LEVEL, MINI };
static const char *const SPHERE_FN[3] = {"max_intersection", "level_regions", "min_intersection"};

static mfg_status sphere_call(int fn, const double *v, const int64_t *off, const int32_t *kinds,
                              const int32_t *closed, int64_t n, const double *w, double level,
                              mfg_regions **out)
{
    switch (fn) {
    case MAXI: return mfg_max_intersection(v, off, kinds, closed, n, w, out);
    case LEVEL: return mfg_level_regions(v, off, kinds, closed, n, w, level, out);
    default: return mfg_min_intersection(v, off, kinds, closed, n, w, out);
    }
}

static void sphere_expect(int fn, const double *v, const int64_t *off, const int32_t *kinds,
                          const int32_t *closed, int64_t n, const double *w, double level,
                          int null_out, unsigned allowed, const char *what, long long which)
{
    mfg_regions *sentinel = (mfg_regions *)(uintptr_t)&sentinel, *r = sentinel;
    mfg_status st = sphere_call(fn, v, off, kinds, closed, n, w, level, null_out ? NULL : &r);
    char label[160];
    snprintf(label, sizeof label, "%s: %s", SPHERE_FN[fn], what);
    expect(st, allowed, label, which);
    if (st == MFG_OK) {
        mfg_regions_free(r);
    } else if (r != sentinel) {
        mfg_test_failures++;
        fprintf(stderr, "%s [%lld]: out written on failure\n", label, which);
    }
}

static void test_sphere(void)
{
    for (int fn = 0; fn < 3; fn++) {
        /* the good input works (so the failures below are the hostile value's) */
        sphere_expect(fn, SV, SOFF, SKINDS, NULL, 3, NULL, 1.0, 0, BIT(MFG_OK), "good input", 0);
        for (size_t c = 0; c < NBAD_OFFSETS; c++) {
            const bad_offsets *b = &BAD_OFFSETS[c];
            sphere_expect(fn, SV, b->off, SKINDS, NULL, b->n, NULL, 1.0, 0, BIT(MFG_ERR_INVALID), b->why,
                          (long long)c);
        }
        for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++)
            sphere_expect(fn, SV, SOFF, SKINDS, NULL, NEGATIVE_COUNTS[i], NULL, 1.0, 0, BIT(MFG_ERR_INVALID),
                          "npolys < 0", NEGATIVE_COUNTS[i]);
        for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++)
            sphere_expect(fn, SV, SOFF, SKINDS, NULL, HUGE_COUNTS[i], NULL, 1.0, 0, BIT(MFG_ERR_INVALID),
                          "huge npolys", HUGE_COUNTS[i]);
        sphere_expect(fn, SV, SOFF, SKINDS, NULL, 0, NULL, 1.0, 0, BIT(MFG_ERR_DEGENERATE), "npolys 0", 0);

        sphere_expect(fn, NULL, SOFF, SKINDS, NULL, 3, NULL, 1.0, 0, BIT(MFG_ERR_NULL), "vertices NULL", 0);
        sphere_expect(fn, SV, NULL, SKINDS, NULL, 3, NULL, 1.0, 0, BIT(MFG_ERR_NULL), "offsets NULL", 0);
        sphere_expect(fn, SV, SOFF, NULL, NULL, 3, NULL, 1.0, 0, BIT(MFG_ERR_NULL), "kinds NULL", 0);
        sphere_expect(fn, SV, SOFF, SKINDS, NULL, 3, NULL, 1.0, 1, BIT(MFG_ERR_NULL), "out NULL", 0);
        sphere_expect(fn, SV, NULL, SKINDS, NULL, INT64_MAX, NULL, 1.0, 0, ANY_ERR, "offsets NULL, huge npolys", 0);

        static const int32_t BAD_KINDS[] = {-1, 4, 7, INT32_MIN, INT32_MAX};
        for (size_t i = 0; i < sizeof BAD_KINDS / sizeof BAD_KINDS[0]; i++) {
            int32_t kinds[3] = {MFG_VM_POLYGON, MFG_VM_POLYGON, MFG_VM_POLYGON};
            kinds[i % 3] = BAD_KINDS[i];
            sphere_expect(fn, SV, SOFF, kinds, NULL, 3, NULL, 1.0, 0, BIT(MFG_ERR_INVALID), "bad kind",
                          BAD_KINDS[i]);
        }
        for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
            double v[27];
            memcpy(v, SV, sizeof v);
            v[(4 * i + 2) % 27] = BAD_REALS[i];
            sphere_expect(fn, v, SOFF, SKINDS, NULL, 3, NULL, 1.0, 0, BIT(MFG_ERR_INVALID), "bad vertex",
                          (long long)i);
            if (BAD_REALS[i] == 1e-300 || BAD_REALS[i] == 1e300)
                continue; /* huge weights are the scaling item's (issue 6), tiny ones are valid */
            double w[3] = {1, 1, 1};
            w[i % 3] = BAD_REALS[i];
            sphere_expect(fn, SV, SOFF, SKINDS, NULL, 3, w, 1.0, 0, BIT(MFG_ERR_INVALID), "bad weight",
                          (long long)i);
        }
        double negw[3] = {1, -1, 1};
        sphere_expect(fn, SV, SOFF, SKINDS, NULL, 3, negw, 1.0, 0, BIT(MFG_ERR_INVALID), "weight < 0", 0);
    }
    for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
        if (BAD_REALS[i] == 1e-300)
            continue; /* a tiny level is a valid level */
        sphere_expect(LEVEL, SV, SOFF, SKINDS, NULL, 3, NULL, BAD_REALS[i], 0, BIT(MFG_ERR_INVALID), "bad level",
                      (long long)i);
    }
    mfg_regions_free(NULL);
}

/* ------------------------------------------------------------------------ */
/* Rotational sweep                                                         */
/* ------------------------------------------------------------------------ */

/* A 2 x 1 x 1 box: vertex k = (x, y, z) from its bits (x: bit 0, y: bit 1, z: bit 2), 12
 * triangles counter-clockwise seen from outside. */
static const double BOX_XYZ[24] = {0, 0, 0, 2, 0, 0, 0, 1, 0, 2, 1, 0, 0, 0, 1, 2, 0, 1, 0, 1, 1, 2, 1, 1};
static const int64_t BOX_TRI[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                    2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
static const double AXP[3] = {0, 0, 0}, AXD[3] = {0, 0, 1};

/* One call with everything else valid; the status in the allowed set, a detail on
 * failure, and neither *out_mesh nor *out_stats written on failure. */
static mfg_status sweep_expect(const double *xyz, int64_t nv, const int64_t *tri, int64_t nt, const double *ap,
                               const double *ad, double angle, double tol, int null_out, unsigned allowed,
                               const char *what, long long which)
{
    mfg_mesh *sentinel = (mfg_mesh *)(uintptr_t)&sentinel, *res = sentinel;
    mfg_sweep_stats stats;
    memset(&stats, OUT_SENTINEL, sizeof stats);
    mfg_status st = mfg_rotational_sweep(xyz, nv, tri, nt, ap, ad, angle, tol, null_out ? NULL : &res, &stats);
    char label[160];
    snprintf(label, sizeof label, "rotational_sweep: %s", what);
    expect(st, allowed, label, which);
    if (st == MFG_OK) {
        mfg_mesh_free(res);
    } else {
        if (res != sentinel) {
            mfg_test_failures++;
            fprintf(stderr, "%s [%lld]: out_mesh written on failure\n", label, which);
        }
        if (!untouched((const uint8_t *)&stats, sizeof stats)) {
            mfg_test_failures++;
            fprintf(stderr, "%s [%lld]: out_stats written on failure\n", label, which);
        }
    }
    return st;
}

/* The detail of the last call contains `text`. */
static void detail_has(const char *text, const char *what)
{
    mfg_test_checks++;
    if (!strstr(mfg_last_error(), text)) {
        mfg_test_failures++;
        fprintf(stderr, "rotational_sweep: %s: detail \"%s\" does not mention \"%s\"\n", what, mfg_last_error(),
                text);
    }
}

static void test_sweep(void)
{
    /* A valid call is not refused (the result itself is test_rotsweep's). */
    const unsigned accepted = BIT(MFG_OK) | BIT(MFG_ERR_INTERNAL) | BIT(MFG_ERR_NOMEM);
    sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, AXD, M_PI / 2, 0.01, 0, accepted, "good input", 0);

    /* NULL pointers (out_stats may be NULL: tested in test_rotsweep) */
    sweep_expect(NULL, 8, BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_NULL), "xyz NULL", 0);
    sweep_expect(BOX_XYZ, 8, NULL, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_NULL), "triangles NULL", 0);
    sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, NULL, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_NULL), "axis_point NULL", 0);
    sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, NULL, 1.0, 0.01, 0, BIT(MFG_ERR_NULL), "axis_direction NULL", 0);
    sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 1, BIT(MFG_ERR_NULL), "out_mesh NULL", 0);
    sweep_expect(NULL, INT64_MAX, NULL, INT64_MAX, AXP, AXD, 1.0, 0.01, 0, ANY_ERR, "NULL arrays, huge counts", 0);
    sweep_expect(NULL, -1, BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, ANY_ERR, "xyz NULL, nvertices -1", 0);

    /* counts: negative, beyond 2^40 (no caller owns that memory), zero */
    static const int64_t BEYOND[] = {((int64_t)1 << 40) + 1, (int64_t)1 << 41};
    for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++) {
        sweep_expect(BOX_XYZ, NEGATIVE_COUNTS[i], BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                     "nvertices < 0", NEGATIVE_COUNTS[i]);
        sweep_expect(BOX_XYZ, 8, BOX_TRI, NEGATIVE_COUNTS[i], AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                     "ntriangles < 0", NEGATIVE_COUNTS[i]);
    }
    for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++) {
        sweep_expect(BOX_XYZ, HUGE_COUNTS[i], BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                     "huge nvertices", HUGE_COUNTS[i]);
        sweep_expect(BOX_XYZ, 8, BOX_TRI, HUGE_COUNTS[i], AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                     "huge ntriangles", HUGE_COUNTS[i]);
    }
    for (size_t i = 0; i < sizeof BEYOND / sizeof BEYOND[0]; i++) {
        sweep_expect(BOX_XYZ, BEYOND[i], BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                     "nvertices > 2^40", BEYOND[i]);
        sweep_expect(BOX_XYZ, 8, BOX_TRI, BEYOND[i], AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                     "ntriangles > 2^40", BEYOND[i]);
    }
    sweep_expect(BOX_XYZ, 8, BOX_TRI, 0, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_DEGENERATE), "ntriangles 0", 0);
    sweep_expect(NULL, 0, NULL, 0, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_DEGENERATE), "empty mesh", 0);
    /* fewer vertices than the triangles use */
    sweep_expect(BOX_XYZ, 7, BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "nvertices too small", 7);

    /* indices outside 0 .. nvertices - 1 */
    static const int64_t BAD_INDEX[] = {-1, 8, 9, INT64_MAX, INT64_MIN, (int64_t)1 << 40};
    for (size_t i = 0; i < sizeof BAD_INDEX / sizeof BAD_INDEX[0]; i++) {
        int64_t tri[36];
        memcpy(tri, BOX_TRI, sizeof tri);
        tri[(7 * i + 5) % 36] = BAD_INDEX[i];
        if (sweep_expect(BOX_XYZ, 8, tri, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "bad index",
                         BAD_INDEX[i]) == MFG_ERR_INVALID)
            detail_has("vertex index", "bad index");
    }

    /* non-finite / out-of-range coordinates of the mesh, the axis point and direction */
    for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
        double xyz[24];
        memcpy(xyz, BOX_XYZ, sizeof xyz);
        xyz[(5 * i + 2) % 24] = BAD_REALS[i];
        sweep_expect(xyz, 8, BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "bad vertex", (long long)i);
        for (int k = 0; k < 3; k++) {
            double ap[3] = {0, 0, 0}, ad[3] = {0, 0, 1};
            ap[k] = BAD_REALS[i];
            sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, ap, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "bad axis point",
                         (long long)(3 * i + k));
            ad[k] = BAD_REALS[i];
            sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, ad, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                         "bad axis direction", (long long)(3 * i + k));
        }
    }
    /* a bad value in a vertex no triangle uses is still a bad value */
    double xyz9[27];
    memcpy(xyz9, BOX_XYZ, sizeof BOX_XYZ);
    xyz9[24] = 1;
    xyz9[25] = NAN;
    xyz9[26] = 1;
    sweep_expect(xyz9, 9, BOX_TRI, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "NaN in an unused vertex", 0);
    /* the zero axis direction (also as -0) */
    static const double ZERO_DIRS[3][3] = {{0, 0, 0}, {-0.0, 0, -0.0}, {-0.0, -0.0, -0.0}};
    for (int k = 0; k < 3; k++)
        if (sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, ZERO_DIRS[k], 1.0, 0.01, 0, BIT(MFG_ERR_INVALID),
                         "zero axis direction", k) == MFG_ERR_INVALID)
            detail_has("zero", "zero axis direction");

    /* angles: (0, 2 pi], with 2 pi + 1e-12 still a full turn */
    static const double BAD_ANGLES[] = {0.0, -0.0, -1e-300, -1.0, -2 * M_PI, 2 * M_PI + 2e-12, 7.0, 1e300,
                                        INFINITY, -INFINITY, NAN, -NAN};
    for (size_t i = 0; i < sizeof BAD_ANGLES / sizeof BAD_ANGLES[0]; i++)
        if (sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, AXD, BAD_ANGLES[i], 0.01, 0, BIT(MFG_ERR_INVALID),
                         "bad angle", (long long)i) == MFG_ERR_INVALID)
            detail_has("angle", "bad angle");
    static const double GOOD_ANGLES[] = {2 * M_PI, 2 * M_PI + 0.5e-12, 2 * M_PI - 0.5e-12, M_PI, 1e-3};
    for (size_t i = 0; i < sizeof GOOD_ANGLES / sizeof GOOD_ANGLES[0]; i++)
        sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, AXD, GOOD_ANGLES[i], 0.05, 0, accepted, "good angle",
                     (long long)i);

    /* tolerances: > 0 and finite (and in the coordinate range) */
    static const double BAD_TOLS[] = {0.0, -0.0, -0.01, -INFINITY, INFINITY, NAN, -NAN, 1e300, 1e-300};
    for (size_t i = 0; i < sizeof BAD_TOLS / sizeof BAD_TOLS[0]; i++)
        if (sweep_expect(BOX_XYZ, 8, BOX_TRI, 12, AXP, AXD, 1.0, BAD_TOLS[i], 0, BIT(MFG_ERR_INVALID),
                         "bad tolerance", (long long)i) == MFG_ERR_INVALID)
            detail_has("tolerance", "bad tolerance");

    /* Meshes that bound no solid, refused as mfg_mesh_check_closed refuses them. */
    /* open: one triangle removed leaves its 3 sides as boundary edges */
    if (sweep_expect(BOX_XYZ, 8, BOX_TRI + 3, 11, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "open mesh", 0) ==
        MFG_ERR_INVALID) {
        detail_has("boundary edge", "open mesh");
        detail_has("3 boundary edges", "open mesh");
    }
    /* open: two triangles removed (a square hole): 4 boundary edges */
    if (sweep_expect(BOX_XYZ, 8, BOX_TRI + 6, 10, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "square hole", 0) ==
        MFG_ERR_INVALID)
        detail_has("4 boundary edges", "square hole");
    /* one triangle flipped: its 3 sides run the same way as their neighbours' */
    int64_t flip[36];
    memcpy(flip, BOX_TRI, sizeof flip);
    flip[4] = BOX_TRI[5];
    flip[5] = BOX_TRI[4];
    if (sweep_expect(BOX_XYZ, 8, flip, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "flipped triangle", 0) ==
        MFG_ERR_INVALID)
        detail_has("inconsistent orientation", "flipped triangle");
    /* every triangle flipped: consistent, but facing inward (negative volume) */
    int64_t inward[36];
    for (int t = 0; t < 12; t++) {
        inward[3 * t] = BOX_TRI[3 * t];
        inward[3 * t + 1] = BOX_TRI[3 * t + 2];
        inward[3 * t + 2] = BOX_TRI[3 * t + 1];
    }
    if (sweep_expect(BOX_XYZ, 8, inward, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "inward mesh", 0) ==
        MFG_ERR_INVALID)
        detail_has("negative volume", "inward mesh");
    /* non-manifold edge: two tetrahedra sharing the edge 0-1 (4 triangle sides on it) */
    static const double TT_XYZ[18] = {0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, 0.5, 1, 0.5, -1, 0, 0.5, -0.5, -1};
    static const int64_t TT_TRI[24] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2,   /* tetrahedron 0 1 2 3 */
                                       0, 1, 4, 0, 5, 1, 1, 5, 4, 0, 4, 5};  /* tetrahedron 0 1 4 5 */
    if (sweep_expect(TT_XYZ, 6, TT_TRI, 8, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "non-manifold edge", 0) ==
        MFG_ERR_INVALID)
        detail_has("non-manifold edge", "non-manifold edge");
    /* two tetrahedra touching at a vertex only */
    static const double TV_XYZ[21] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, -1, 0, 0, 0, -1, 0, 0, 0, -1};
    static const int64_t TV_TRI[24] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3,
                                       0, 5, 4, 0, 4, 6, 0, 6, 5, 4, 5, 6};
    if (sweep_expect(TV_XYZ, 7, TV_TRI, 8, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "non-manifold vertex", 0) ==
        MFG_ERR_INVALID)
        detail_has("non-manifold vertex", "non-manifold vertex");
    /* zero volume: a tetrahedron with its 4 vertices in one plane (non-zero areas) */
    static const double FLAT_XYZ[12] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 1, 1, 0};
    static const int64_t FLAT_TRI[12] = {0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2};
    if (sweep_expect(FLAT_XYZ, 4, FLAT_TRI, 4, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_DEGENERATE), "zero volume", 0) ==
        MFG_ERR_DEGENERATE)
        detail_has("zero volume", "zero volume");
    /* a triangle and its reverse: closed, consistent, no volume */
    static const int64_t TWO_SIDED[6] = {0, 1, 2, 0, 2, 1};
    sweep_expect(FLAT_XYZ, 4, TWO_SIDED, 2, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_DEGENERATE), "two-sided triangle", 0);
    /* a repeated index */
    int64_t rep[36];
    memcpy(rep, BOX_TRI, sizeof rep);
    rep[1] = rep[0];
    if (sweep_expect(BOX_XYZ, 8, rep, 12, AXP, AXD, 1.0, 0.01, 0, BIT(MFG_ERR_INVALID), "repeated index", 0) ==
        MFG_ERR_INVALID)
        detail_has("repeats a vertex index", "repeated index");
    /* the mesh check comes after the arguments: a bad angle with an open mesh is about
     * one of them, with a detail either way (no order is promised) */
    sweep_expect(BOX_XYZ, 8, BOX_TRI + 3, 11, AXP, AXD, NAN, 0.01, 0, BIT(MFG_ERR_INVALID), "open mesh, NaN angle", 0);
}

/* ------------------------------------------------------------------------ */
/* mfg_ray_blocked: the box mesh above, 2 sample points                      */
/* ------------------------------------------------------------------------ */

static const double RAY_PTS[6] = {0.5, 0.3, 0.5, 0.5, 0.3, 2}; /* inside, above (off the diagonals) */
static const int64_t RAY_OWN[2] = {-1, -1};
static const double RAY_D[3] = {0, 0, 1};

static void ray_expect(const double *xyz, int64_t nv, const int64_t *tri, int64_t nt, const double *pts,
                       const int64_t *own, int64_t np, const double *d, int null_out, unsigned allowed,
                       const char *what, long long which)
{
    uint8_t out[16];
    memset(out, OUT_SENTINEL, sizeof out);
    mfg_status st = mfg_ray_blocked(xyz, nv, tri, nt, pts, own, np, d, null_out ? NULL : out);
    expect(st, allowed, what, which);
    if (st != MFG_OK)
        CHECK(untouched(out, sizeof out));
}

static void test_rays(void)
{
    /* the good call: a point inside the box is blocked both ways, one above it along -z only */
    uint8_t out[2] = {0xFF, 0xFF};
    CHECK(mfg_ray_blocked(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, RAY_D, out) == MFG_OK);
    CHECK((out[0] & (MFG_RAY_BLOCKED_POS | MFG_RAY_BLOCKED_NEG)) ==
          (MFG_RAY_BLOCKED_POS | MFG_RAY_BLOCKED_NEG));
    CHECK((out[1] & (MFG_RAY_BLOCKED_POS | MFG_RAY_BLOCKED_NEG)) == MFG_RAY_BLOCKED_NEG);
    /* NULL pointers */
    ray_expect(NULL, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_NULL), "ray NULL xyz", 0);
    ray_expect(BOX_XYZ, 8, NULL, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_NULL), "ray NULL triangles", 0);
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, NULL, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_NULL), "ray NULL points", 0);
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, NULL, 0, BIT(MFG_ERR_NULL), "ray NULL direction", 0);
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 1, BIT(MFG_ERR_NULL), "ray NULL out", 0);
    /* own_triangle may be NULL (documented) */
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, NULL, 2, RAY_D, 0, BIT(MFG_OK), "ray NULL own_triangle", 0);
    /* negative and huge counts: each of the three counts in turn */
    for (size_t i = 0; i < sizeof NEGATIVE_COUNTS / sizeof NEGATIVE_COUNTS[0]; i++) {
        int64_t c = NEGATIVE_COUNTS[i];
        ray_expect(BOX_XYZ, c, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray nvertices<0", c);
        ray_expect(BOX_XYZ, 8, BOX_TRI, c, RAY_PTS, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray ntriangles<0", c);
        ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, c, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray npoints<0", c);
    }
    for (size_t i = 0; i < sizeof HUGE_COUNTS / sizeof HUGE_COUNTS[0]; i++) {
        int64_t c = HUGE_COUNTS[i];
        ray_expect(BOX_XYZ, c, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 0, ANY_ERR | BIT(MFG_ERR_NOMEM),
                   "ray huge nvertices", c);
        ray_expect(BOX_XYZ, 8, BOX_TRI, c, RAY_PTS, RAY_OWN, 2, RAY_D, 0, ANY_ERR | BIT(MFG_ERR_NOMEM),
                   "ray huge ntriangles", c);
        ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, c, RAY_D, 0, ANY_ERR | BIT(MFG_ERR_NOMEM),
                   "ray huge npoints", c);
    }
    /* out-of-range indices: a triangle's vertex, a point's own triangle */
    static const int64_t BAD_INDEX[] = {8, 9, -1, INT64_MAX, INT64_MIN};
    for (size_t i = 0; i < sizeof BAD_INDEX / sizeof BAD_INDEX[0]; i++) {
        int64_t tri[36];
        memcpy(tri, BOX_TRI, sizeof tri);
        tri[35] = BAD_INDEX[i];
        ray_expect(BOX_XYZ, 8, tri, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray vertex index",
                   (long long)BAD_INDEX[i]);
        if (BAD_INDEX[i] == -1)
            continue; /* -1 is "no own triangle" */
        int64_t own[2] = {0, BAD_INDEX[i] < 12 ? BAD_INDEX[i] + 4 : BAD_INDEX[i]}; /* 12, 13: past the 12 triangles */
        ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, own, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray own triangle",
                   (long long)own[1]);
    }
    int64_t own_neg[2] = {0, -2};
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, own_neg, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray own triangle", -2);
    /* NaN / Inf / zero direction, NaN / Inf coordinates and points */
    for (size_t i = 0; i < sizeof BAD_REALS / sizeof BAD_REALS[0]; i++) {
        double v = BAD_REALS[i];
        if (isfinite(v))
            continue;
        for (int k = 0; k < 3; k++) {
            double d[3] = {0, 0, 1}, pts[6], xyz[24];
            d[k] = v;
            ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, d, 0, BIT(MFG_ERR_INVALID), "ray direction", k);
            memcpy(pts, RAY_PTS, sizeof pts);
            pts[3 + k] = v;
            ray_expect(BOX_XYZ, 8, BOX_TRI, 12, pts, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray point", k);
            memcpy(xyz, BOX_XYZ, sizeof xyz);
            xyz[21 + k] = v;
            ray_expect(xyz, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, RAY_D, 0, BIT(MFG_ERR_INVALID), "ray vertex", k);
        }
    }
    static const double ZERO[3] = {0, 0, 0}, NEG_ZERO[3] = {-0.0, 0.0, -0.0};
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, ZERO, 0, BIT(MFG_ERR_INVALID), "ray zero direction", 0);
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 2, NEG_ZERO, 0, BIT(MFG_ERR_INVALID), "ray -0 direction", 0);
    /* zero points: nothing to test, nothing written (OK or a clean error, as documented) */
    ray_expect(BOX_XYZ, 8, BOX_TRI, 12, RAY_PTS, RAY_OWN, 0, RAY_D, 0, ANY_ERR | BIT(MFG_OK), "ray no points", 0);
}

int main(int argc, char **argv)
{
    /* "pointclass", "visibility", "sphere", "sweep" or "rays" runs one family (one ctest each, so one
     * family's failure does not hide another's); no argument runs all. */
    const char *only = argc > 1 ? argv[1] : "";
    if (!only[0] || !strcmp(only, "pointclass")) {
        test_pointclass_offsets();
        test_pointclass_counts();
        test_pointclass_null_and_values();
    }
    if (!only[0] || !strcmp(only, "visibility"))
        test_visibility();
    if (!only[0] || !strcmp(only, "sphere"))
        test_sphere();
    if (!only[0] || !strcmp(only, "sweep"))
        test_sweep();
    if (!only[0] || !strcmp(only, "rays"))
        test_rays();
    return mfg_test_report("test_hostile_api");
}
