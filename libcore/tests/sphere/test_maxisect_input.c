/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_maxisect_input.c - the maximum / level / minimum intersection entry points refuse
 * malformed input with MFG_ERR_INVALID (or NULL / DEGENERATE) and a message naming the
 * map and what is wrong, never read out of bounds, never overflow (issue 6, items 5, 8). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "mfg_test.h"
#include "mfgeom.h"

static const double OCT[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

/* Runs all three entry points on the input: each must give status st and leave out
 * untouched; the message must contain want (when given). */
static void expect(const double *v, const int64_t *off, const int32_t *kinds, const int32_t *closed,
                   int64_t n, const double *w, mfg_status st, const char *want, int line)
{
    for (int mode = 0; mode < 3; mode++) {
        mfg_regions *r = (mfg_regions *)&r;
        mfg_status got = mode == 0   ? mfg_max_intersection(v, off, kinds, closed, n, w, &r)
                         : mode == 1 ? mfg_level_regions(v, off, kinds, closed, n, w, 1.0, &r)
                                     : mfg_min_intersection(v, off, kinds, closed, n, w, &r);
        CHECK_EQ_INT(got, st);
        if (st != MFG_OK)
            CHECK(r == (mfg_regions *)&r);
        if (got == MFG_OK && r != (mfg_regions *)&r)
            mfg_regions_free(r);
        if (want && !strstr(mfg_last_error(), want)) {
            fprintf(stderr, "line %d: message \"%s\" lacks \"%s\"\n", line, mfg_last_error(), want);
            CHECK(0);
        }
        if (got != st)
            fprintf(stderr, "line %d mode %d: status %d (%s)\n", line, mode, got, mfg_last_error());
    }
}
#define EXPECT(v, off, kinds, closed, n, w, st, want) expect(v, off, kinds, closed, n, w, st, want, __LINE__)

/* Item 5: counts, offsets, kinds, closed flags and weights. */
static void test_layout(void)
{
    int32_t k1[] = {MFG_VM_POLYGON}, k2[] = {MFG_VM_POLYGON, MFG_VM_POLYGON};
    /* offsets = {0, INT64_MAX}: an impossible count, not an allocation failure */
    int64_t huge[] = {0, INT64_MAX};
    EXPECT(OCT, huge, k1, NULL, 1, NULL, MFG_ERR_INVALID, "offsets[1]");
    int64_t neg[] = {0, -3};
    EXPECT(OCT, neg, k1, NULL, 1, NULL, MFG_ERR_INVALID, "non-decreasing");
    int64_t wrap[] = {0, 3, INT64_MIN + 2};
    EXPECT(OCT, wrap, k2, NULL, 2, NULL, MFG_ERR_INVALID, "non-decreasing");
    int64_t down[] = {0, 3, 2};
    EXPECT(OCT, down, k2, NULL, 2, NULL, MFG_ERR_INVALID, "offsets[2]");
    int64_t start[] = {1, 3};
    EXPECT(OCT, start, k1, NULL, 1, NULL, MFG_ERR_INVALID, "offsets[0]");
    int64_t off[] = {0, 3};
    /* npolys huge: refused before offsets[npolys] is read */
    EXPECT(OCT, off, k1, NULL, INT64_MAX, NULL, MFG_ERR_INVALID, "npolys");
    EXPECT(OCT, off, k1, NULL, -1, NULL, MFG_ERR_INVALID, "npolys = -1");
    EXPECT(OCT, off, k1, NULL, 0, NULL, MFG_ERR_DEGENERATE, NULL);
    int32_t bad4[] = {4}, badm[] = {-1};
    EXPECT(OCT, off, bad4, NULL, 1, NULL, MFG_ERR_INVALID, "map 0 has unknown kind 4");
    EXPECT(OCT, off, badm, NULL, 1, NULL, MFG_ERR_INVALID, "unknown kind -1");
    int32_t cl2[] = {2}, cl1[] = {1};
    EXPECT(OCT, off, k1, cl2, 1, NULL, MFG_ERR_INVALID, "closed must be 0 or 1");
    EXPECT(OCT, off, k1, cl1, 1, NULL, MFG_ERR_INVALID, "only for an EDGE");
    double wnan[] = {NAN}, wneg[] = {-1}, winf[] = {INFINITY}, wmax[] = {DBL_MAX, DBL_MAX};
    EXPECT(OCT, off, k1, NULL, 1, wnan, MFG_ERR_INVALID, "weight 0");
    EXPECT(OCT, off, k1, NULL, 1, wneg, MFG_ERR_INVALID, "weight 0");
    EXPECT(OCT, off, k1, NULL, 1, winf, MFG_ERR_INVALID, "weight 0");
    double v2[18];
    memcpy(v2, OCT, sizeof OCT), memcpy(v2 + 9, OCT, sizeof OCT);
    int64_t off2[] = {0, 3, 6};
    EXPECT(v2, off2, k2, NULL, 2, wmax, MFG_ERR_INVALID, "overflows");
    EXPECT(NULL, off, k1, NULL, 1, NULL, MFG_ERR_NULL, "vertices");
}

/* Item 8: maps whose vertices do not make the shape their kind says. */
static void test_shapes(void)
{
    int64_t off2[] = {0, 3, 5}, off3[] = {0, 3, 6};
    double v[18];
    memcpy(v, OCT, sizeof OCT);
    /* a POINT with two vertices that are not antipodal (it was silently truncated) */
    int32_t kp[] = {MFG_VM_POLYGON, MFG_VM_POINT};
    double p2[6] = {1, 0, 0, 0, 1, 0};
    memcpy(v + 9, p2, sizeof p2);
    EXPECT(v, off2, kp, NULL, 2, NULL, MFG_ERR_INVALID, "map 1: a POINT with two vertices must have them antipodal");
    double p2ok[6] = {0, 0, 1, 0, 0, -1};
    memcpy(v + 9, p2ok, sizeof p2ok);
    EXPECT(v, off2, kp, NULL, 2, NULL, MFG_OK, NULL);
    /* an EDGE given as two antipodal vertices (was "no normals (m = 0)") */
    int32_t ke[] = {MFG_VM_POLYGON, MFG_VM_EDGE};
    double e2[6] = {1, 0, 0, -1, 0, 0};
    memcpy(v + 9, e2, sizeof e2);
    EXPECT(v, off2, ke, NULL, 2, NULL, MFG_ERR_INVALID, "map 1: EDGE vertices 0 and 1 are antipodal");
    /* an EDGE with a kink: its third vertex is off the great circle (was reshaped) */
    double e3[9] = {1, 0, 0, 0.6, 0.8, 0, 0, 0.6, 0.8};
    memcpy(v + 9, e3, sizeof e3);
    EXPECT(v, off3, ke, NULL, 2, NULL, MFG_ERR_INVALID, "off the great circle");
    /* an EDGE going back on itself */
    double eb[9] = {1, 0, 0, 0.6, 0.8, 0, 0.8, 0.6, 0};
    memcpy(v + 9, eb, sizeof eb);
    EXPECT(v, off3, ke, NULL, 2, NULL, MFG_ERR_INVALID, "map 1:");
    /* a closed EDGE that does not go round once (three vertices within a quarter) */
    int32_t kc[] = {MFG_VM_POLYGON, MFG_VM_EDGE}, cc[] = {0, 1};
    double ec[9] = {1, 0, 0, 0.8, 0.6, 0, 0.6, 0.8, 0};
    memcpy(v + 9, ec, sizeof ec);
    EXPECT(v, off3, kc, cc, 2, NULL, MFG_ERR_INVALID, "map 1:");
    double eok[9] = {1, 0, 0, -0.5, sqrt(0.75), 0, -0.5, -sqrt(0.75), 0};
    memcpy(v + 9, eok, sizeof eok);
    EXPECT(v, off3, kc, cc, 2, NULL, MFG_OK, NULL);
    /* polygons: clockwise, reflex, wound twice, not unit */
    int32_t kk[] = {MFG_VM_POLYGON, MFG_VM_POLYGON};
    double cw[9] = {1, 0, 0, 0, 0, 1, 0, 1, 0};
    memcpy(v + 9, cw, sizeof cw);
    EXPECT(v, off3, kk, NULL, 2, NULL, MFG_ERR_INVALID, "map 1: POLYGON is not convex and counter-clockwise");
    /* a reflex quadrilateral (a dart) around the north pole */
    double dart[12];
    const double ang[4] = {0, 2.2, 3.14159, 4.1}, rad[4] = {0.5, 0.5, 0.1, 0.5};
    for (int k = 0; k < 4; k++) {
        dart[3 * k] = sin(rad[k]) * cos(ang[k]);
        dart[3 * k + 1] = sin(rad[k]) * sin(ang[k]);
        dart[3 * k + 2] = cos(rad[k]);
    }
    double vd[21];
    memcpy(vd, OCT, sizeof OCT), memcpy(vd + 9, dart, sizeof dart);
    int64_t off4[] = {0, 3, 7};
    EXPECT(vd, off4, kk, NULL, 2, NULL, MFG_ERR_INVALID, "map 1: POLYGON is not convex");
    /* a pentagram: every turn to the left, but round the centre twice */
    double star[15];
    for (int k = 0; k < 5; k++) {
        double a = 2 * M_PI * (2 * k % 5) / 5;
        star[3 * k] = sin(0.3) * cos(a), star[3 * k + 1] = sin(0.3) * sin(a), star[3 * k + 2] = cos(0.3);
    }
    double vs[24];
    memcpy(vs, OCT, sizeof OCT), memcpy(vs + 9, star, sizeof star);
    int64_t off5[] = {0, 3, 8};
    EXPECT(vs, off5, kk, NULL, 2, NULL, MFG_ERR_INVALID, "map 1: POLYGON is not convex");
    /* the same five vertices in order: a convex pentagon, accepted */
    for (int k = 0; k < 5; k++) {
        double a = 2 * M_PI * k / 5;
        vs[9 + 3 * k] = sin(0.3) * cos(a), vs[9 + 3 * k + 1] = sin(0.3) * sin(a), vs[9 + 3 * k + 2] = cos(0.3);
    }
    EXPECT(vs, off5, kk, NULL, 2, NULL, MFG_OK, NULL);
    /* a vertex of length 1.01: a direction must be a unit vector (within 1e-6) */
    double vl[18];
    memcpy(vl, OCT, sizeof OCT), memcpy(vl + 9, OCT, sizeof OCT);
    vl[13] = 1.01;
    EXPECT(vl, off3, kk, NULL, 2, NULL, MFG_ERR_INVALID, "map 1, vertex 1 is not a unit vector");
    vl[13] = 1.0 + 1e-9; /* rounding-sized: accepted */
    EXPECT(vl, off3, kk, NULL, 2, NULL, MFG_OK, NULL);
    /* a hemisphere (3 vertices on its circle) and a lune (4) stay accepted */
    double hemi[9] = {1, 0, 0, -0.5, sqrt(0.75), 0, -0.5, -sqrt(0.75), 0};
    double lune[12] = {0, 0, 1, 1, 0, 0, 0, 0, -1, 0, 1, 0};
    double vh[21];
    memcpy(vh, hemi, sizeof hemi), memcpy(vh + 9, lune, sizeof lune);
    int64_t offh[] = {0, 3, 7};
    EXPECT(vh, offh, kk, NULL, 2, NULL, MFG_OK, NULL);
}

int main(void)
{
    test_layout();
    test_shapes();
    return mfg_test_report("test_maxisect_input");
}
