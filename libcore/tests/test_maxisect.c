/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_maxisect.c - maximum / level / minimum intersection: API errors, hand-made cases
 * with known answers, and agreement with brute-force coverage counting on samples. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_test.h"
#include "mfgeom.h"

/* Octant-like triangles: x>=0,y>=0,z>=0 is the spherical triangle (1,0,0),(0,1,0),(0,0,1). */
static const double OCT[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

static void test_errors(void)
{
    int64_t off[] = {0, 3};
    int32_t kinds[] = {MFG_VM_POLYGON};
    mfg_regions *r = (mfg_regions *)&r;
    CHECK_EQ_INT(mfg_max_intersection(OCT, off, kinds, NULL, 1, NULL, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_max_intersection(OCT, off, kinds, NULL, 0, NULL, &r), MFG_ERR_DEGENERATE);
    CHECK_EQ_INT(mfg_max_intersection(OCT, NULL, kinds, NULL, 1, NULL, &r), MFG_ERR_NULL);
    int32_t bad_kind[] = {7};
    CHECK_EQ_INT(mfg_max_intersection(OCT, off, bad_kind, NULL, 1, NULL, &r), MFG_ERR_INVALID);
    double cw[9] = {1, 0, 0, 0, 0, 1, 0, 1, 0}; /* clockwise */
    CHECK_EQ_INT(mfg_max_intersection(cw, off, kinds, NULL, 1, NULL, &r), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "counter-clockwise") != NULL);
    double nanv[9] = {1, 0, 0, 0, NAN, 0, 0, 0, 1};
    CHECK_EQ_INT(mfg_max_intersection(nanv, off, kinds, NULL, 1, NULL, &r), MFG_ERR_INVALID);
    double negw[] = {-1};
    CHECK_EQ_INT(mfg_max_intersection(OCT, off, kinds, NULL, 1, negw, &r), MFG_ERR_INVALID);
    int64_t off2[] = {0, 2};
    CHECK_EQ_INT(mfg_max_intersection(OCT, off2, kinds, NULL, 1, NULL, &r), MFG_ERR_DEGENERATE);
    double zerow[] = {0};
    CHECK_EQ_INT(mfg_max_intersection(OCT, off, kinds, NULL, 1, zerow, &r), MFG_ERR_DEGENERATE);
    CHECK(r == (mfg_regions *)&r); /* untouched on failure */
    CHECK_EQ_INT(mfg_level_regions(OCT, off, kinds, NULL, 1, NULL, NAN, &r), MFG_ERR_INVALID);
    mfg_regions_free(NULL);
}

/* Three octant triangles sharing the corner (0,0,1)... and a nested one: the maximum is
 * the small triangle, covered by all four; its centre is its incentre. */
static void test_nested(void)
{
    const double s = 0.2;
    double v[36];
    memcpy(v, OCT, sizeof OCT);
    /* a small triangle around the octant's centre (1,1,1)/sqrt(3) */
    double c[3] = {1 / sqrt(3.0), 1 / sqrt(3.0), 1 / sqrt(3.0)};
    double e1[3] = {1 / sqrt(2.0), -1 / sqrt(2.0), 0}, e2[3];
    e2[0] = c[1] * e1[2] - c[2] * e1[1];
    e2[1] = c[2] * e1[0] - c[0] * e1[2];
    e2[2] = c[0] * e1[1] - c[1] * e1[0];
    for (int k = 0; k < 3; k++) {
        double a = 2 * M_PI * k / 3;
        for (int i = 0; i < 3; i++)
            v[9 + 3 * k + i] = c[i] + s * (cos(a) * e1[i] + sin(a) * e2[i]);
    }
    /* the octant again, and the octant rotated a little about z */
    memcpy(v + 18, OCT, sizeof OCT);
    double t = 0.1;
    double rot[9] = {cos(t), sin(t), 0, -sin(t), cos(t), 0, 0, 0, 1};
    memcpy(v + 27, rot, sizeof rot);
    int64_t off[] = {0, 3, 6, 9, 12};
    int32_t kinds[] = {3, 3, 3, 3};
    mfg_regions *r = NULL;
    CHECK_EQ_INT(mfg_max_intersection(v, off, kinds, NULL, 4, NULL, &r), MFG_OK);
    if (!r)
        return;
    CHECK(r->weight == 4.0);
    CHECK_EQ_INT(r->nregions, 1);
    CHECK_EQ_INT(r->kinds[0], MFG_VM_POLYGON);
    CHECK_EQ_INT(r->cover_offsets[1], 4);
    /* the small triangle is centred on c: so is the region's inscribed circle */
    double d = r->centres[0] * c[0] + r->centres[1] * c[1] + r->centres[2] * c[2];
    CHECK(d > 1 - 1e-12);
    CHECK(r->margins[0] > 0.05 && r->margins[0] < s);
    mfg_regions_free(r);
    /* weights: make the rotated octant count 10: then it alone (with the others it
     * meets) decides; the level-5 regions all contain it */
    double w[] = {1, 1, 1, 10};
    CHECK_EQ_INT(mfg_max_intersection(v, off, kinds, NULL, 4, w, &r), MFG_OK);
    CHECK(r && r->weight == 13.0);
    mfg_regions_free(r);
    CHECK_EQ_INT(mfg_level_regions(v, off, kinds, NULL, 4, w, 11.5, &r), MFG_OK);
    CHECK(r && r->nregions >= 1);
    for (int64_t i = 0; r && i < r->nregions; i++) {
        int has3 = 0;
        for (int64_t k = r->cover_offsets[i]; k < r->cover_offsets[i + 1]; k++)
            has3 |= r->cover[k] == 3;
        CHECK(has3);
    }
    mfg_regions_free(r);
    /* minimum: most of the sphere is covered by nothing */
    CHECK_EQ_INT(mfg_min_intersection(v, off, kinds, NULL, 4, NULL, &r), MFG_OK);
    CHECK(r && r->weight == 0.0 && r->nregions >= 1 && r->cover_offsets[1] == 0);
    mfg_regions_free(r);
}

/* Two maps touching along a shared great circle: the maximum is the shared arc. */
static void test_touching(void)
{
    /* the octant above z = 0 and its mirror image below, both counter-clockwise:
     * they share the quarter circle from (1,0,0) to (0,1,0) */
    double v[] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 1, 0, 0, 0, 0, -1};
    int64_t off[] = {0, 3, 6};
    int32_t kinds[] = {3, 3};
    mfg_regions *r = NULL;
    mfg_status st = mfg_max_intersection(v, off, kinds, NULL, 2, NULL, &r);
    CHECK_EQ_INT(st, MFG_OK);
    if (!r)
        return;
    CHECK(r->weight == 2.0);
    CHECK_EQ_INT(r->nregions, 1);
    CHECK_EQ_INT(r->kinds[0], MFG_VM_EDGE);
    CHECK(fabs(r->centres[2]) < 1e-9); /* on z = 0 */
    mfg_regions_free(r);
}

/* Random maps: no sampled direction is covered by more than the answer, and the
 * answer's centres are covered by exactly it. */
static int covered(const double *v, int64_t n, const double *d)
{
    for (int64_t k = 0; k < n; k++) {
        const double *a = v + 3 * k, *b = v + 3 * ((k + 1) % n);
        double c[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        double nn = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        if ((c[0] * d[0] + c[1] * d[1] + c[2] * d[2]) / nn < -1e-12)
            return 0;
    }
    return 1;
}

static void test_random_against_sampling(void)
{
    enum { NMAP = 40, NS = 40000 };
    int bad = 0;
    for (int trial = 0; trial < 5; trial++) {
        double normals[3 * 12];
        double *verts = malloc(sizeof(double) * 3 * 64 * NMAP);
        int64_t off[NMAP + 1];
        int32_t kinds[NMAP];
        int64_t nm = 0, nv = 0;
        off[0] = 0;
        while (nm < NMAP) {
            double c[3] = {rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1)};
            int m = (int)rng_int(3, 12);
            double r = rng_uniform(0.2, 0.8);
            for (int k = 0; k < m; k++)
                for (int i = 0; i < 3; i++)
                    normals[3 * k + i] = c[i] + rng_uniform(-r, r);
            mfg_spoly *vm = NULL;
            if (mfg_visibility_map(normals, m, 0.0, &vm) != MFG_OK)
                continue;
            if (vm->kind == MFG_VM_POLYGON && vm->nvertices <= 64) {
                memcpy(verts + 3 * nv, vm->vertices, sizeof(double) * 3 * vm->nvertices);
                nv += vm->nvertices;
                kinds[nm] = MFG_VM_POLYGON;
                off[++nm] = nv;
            }
            mfg_spoly_free(vm);
        }
        mfg_regions *res = NULL;
        CHECK_EQ_INT(mfg_max_intersection(verts, off, kinds, NULL, NMAP, NULL, &res), MFG_OK);
        if (!res) {
            free(verts);
            continue;
        }
        int most = 0;
        for (int s = 0; s < NS; s++) { /* Fibonacci sphere */
            double z = 1 - (2.0 * s + 1) / NS, rr = sqrt(1 - z * z), th = s * M_PI * (3 - sqrt(5.0));
            double d[3] = {rr * cos(th), rr * sin(th), z};
            int cnt = 0;
            for (int64_t i = 0; i < NMAP; i++)
                cnt += covered(verts + 3 * off[i], off[i + 1] - off[i], d);
            if (cnt > most)
                most = cnt;
        }
        bad += most > res->weight;
        for (int64_t g = 0; g < res->nregions; g++) {
            int cnt = 0;
            for (int64_t i = 0; i < NMAP; i++)
                cnt += covered(verts + 3 * off[i], off[i + 1] - off[i], res->centres + 3 * g);
            if (res->margins[g] > 1e-9)
                bad += cnt != (int)res->weight;
        }
        mfg_regions_free(res);
        free(verts);
    }
    CHECK_EQ_INT(bad, 0);
}

int main(void)
{
    test_errors();
    test_nested();
    test_touching();
    test_random_against_sampling();
    return mfg_test_report("test_maxisect");
}
