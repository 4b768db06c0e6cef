/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_surface_alloc.c - mfg_medial_surface under allocation failure: every
 * allocation of the whole pipeline (elements, BVH, octree, sheets, junctions, assembly) in
 * turn fails (the failing allocator of tests/alloc_fail), and each time the call reports
 * MFG_ERR_NOMEM, leaves *out untouched and leaks no block (or, where libc absorbs the
 * failure, returns the same result).  One thread: the failing allocator is single-threaded. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "alloc_shim.h"
#include "medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"

static int same_counts(const mfg_medial *a, const mfg_medial *b)
{
    return a->nelements == b->nelements && a->nsheets == b->nsheets && a->nseams == b->nseams &&
           a->njunctions == b->njunctions &&
           a->sheet_vertex_offsets[a->nsheets] == b->sheet_vertex_offsets[b->nsheets] &&
           a->seam_point_offsets[a->nseams] == b->seam_point_offsets[b->nseams] &&
           !memcmp(a->junction_points, b->junction_points, 3 * (size_t)a->njunctions * sizeof(double));
}

/* Fails allocation n for every n (stride 1), or for a bigger case every stride-th one
 * plus all of the last tail (the assembly's, where the junction recovery allocates). */
static void run_case(const char *name, const tmesh *t, double tol, uint32_t flags, long stride,
                     long tail)
{
    mfg_medial *ref = NULL;
    CHECK_EQ_INT(mfg_medial_surface(t->xyz, t->nv, t->tri, t->nt, tol, flags, 1, &ref), MFG_OK);
    if (!ref)
        return;
    alloc_shim_arm(0);
    mfg_medial *cnt = NULL;
    mfg_medial_surface(t->xyz, t->nv, t->tri, t->nt, tol, flags, 1, &cnt);
    mfg_medial_free(cnt);
    long total = alloc_shim_disarm().attempts, tried = 0;
    int done = 0;
    long n, absorbed = 0;
    for (n = 1; n < 200000 && !done; n++) {
        if (stride > 1 && n % stride != 0 && n <= total - tail)
            continue;
        tried++;
        mfg_medial *sentinel = (mfg_medial *)&done, *out = sentinel;
        alloc_shim_arm(n);
        mfg_status st = mfg_medial_surface(t->xyz, t->nv, t->tri, t->nt, tol, flags, 1, &out);
        int same = 0;
        if (st == MFG_OK) {
            same = out != sentinel && same_counts(out, ref);
            mfg_medial_free(out);
        }
        alloc_shim_stats s = alloc_shim_disarm();
        CHECK_EQ_INT(s.net, 0);
        if (s.failed == 0) {
            done = 1;
            CHECK_EQ_INT(st, MFG_OK);
            continue;
        }
        if (st == MFG_OK) {
            absorbed++;
            CHECK(same);
            continue;
        }
        CHECK_EQ_INT(st, MFG_ERR_NOMEM);
        CHECK(out == sentinel);
    }
    CHECK(done);
    mfg_medial_free(ref);
    printf("%s: %ld of %ld allocations failed in turn (%ld absorbed by libc)\n", name, tried - 1,
           total, absorbed);
}

int main(void)
{
    tmesh t;
    ms_l_bracket(&t);
    run_case("L-bracket major", &t, 4.0, 0, 1, 0);
    ms_box(&t, 20, 20, 100);
    run_case("square prism", &t, 5.0, 0, 1, 0);
    /* 8 segments at 2 % of L: 13 seam ends go through the junction recovery and tracing */
    memset(&t, 0, sizeof t);
    ms_cup(&t, 8);
    run_case("cup, 8 segments", &t, 1.281, 0, 37, 0);
    return mfg_test_report("medial_surface_alloc");
}
