/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_voxels_alloc.c - md_octree_build under allocation failure: every allocation
 * in turn fails (the failing allocator of tests/alloc_fail; one thread, as the allocator
 * counts without locks), and each time the build reports MFG_ERR_NOMEM, leaves its output
 * zeroed and leaks no block; a failure absorbed by libc (qsort) leaves the same leaves. */
#include <stdint.h>
#include <string.h>

#include "alloc_shim.h"
#include "medial/medial.h"
#include "mfg_test.h"
#include "mfgeom.h"

int main(void)
{
    /* The L-bracket, at a coarse tolerance (few leaves, every code path). */
    static const double P[6][2] = {{0, 0}, {50, 0}, {50, 10}, {10, 10}, {10, 50}, {0, 50}};
    static const int T[4][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}};
    double xyz[36];
    int64_t tri[60], nt = 0;
    for (int i = 0; i < 6; i++) {
        double *b = xyz + 3 * i, *t = xyz + 18 + 3 * i;
        b[0] = t[0] = P[i][0];
        b[1] = t[1] = P[i][1];
        b[2] = 0;
        t[2] = 40;
    }
#define TRI(a, b, c) (tri[3 * nt] = (a), tri[3 * nt + 1] = (b), tri[3 * nt + 2] = (c), nt++)
    for (int i = 0; i < 4; i++) {
        TRI(6 + T[i][0], 6 + T[i][1], 6 + T[i][2]);
        TRI(T[i][0], T[i][2], T[i][1]);
    }
    for (int i = 0; i < 6; i++) {
        int j = (i + 1) % 6;
        TRI(i, j, 6 + j);
        TRI(i, 6 + j, 6 + i);
    }
    const double tol = 2.0;
    md_elements el;
    CHECK_EQ_INT(md_elements_build(xyz, 12, tri, nt, tol, &el), MFG_OK);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    long total = 0;
    for (int use_bvh = 0; use_bvh < 2; use_bvh++) {
        md_leaves ref;
        CHECK_EQ_INT(md_octree_build(&el, use_bvh ? bvh : NULL, tol, 1, 1, &ref), MFG_OK);
        CHECK(ref.nleaves > 100);
        int64_t nC = ref.leaf[ref.nleaves - 1].C_off + ref.leaf[ref.nleaves - 1].nC;
        int64_t nP = ref.leaf[ref.nleaves - 1].P_off + 2 * ref.leaf[ref.nleaves - 1].nP;
        int done = 0;
        long n;
        for (n = 1; n < 5000 && !done; n++) {
            md_leaves lv;
            memset(&lv, 0x5a, sizeof lv);
            alloc_shim_arm(n);
            mfg_status st = md_octree_build(&el, use_bvh ? bvh : NULL, tol, 1, 1, &lv);
            int same = 0;
            if (st == MFG_OK) {
                same = lv.nleaves == ref.nleaves &&
                       !memcmp(lv.leaf, ref.leaf, (size_t)ref.nleaves * sizeof *lv.leaf) &&
                       !memcmp(lv.C, ref.C, (size_t)nC * sizeof *lv.C) &&
                       !memcmp(lv.P, ref.P, (size_t)nP * sizeof *lv.P);
                md_leaves_free(&lv);
            }
            alloc_shim_stats s = alloc_shim_disarm();
            CHECK_EQ_INT(s.net, 0);
            if (s.failed == 0) {
                done = 1;
                CHECK_EQ_INT(st, MFG_OK);
                continue;
            }
            if (st == MFG_OK) {
                CHECK(same);
                continue;
            }
            CHECK_EQ_INT(st, MFG_ERR_NOMEM);
            CHECK(lv.nleaves == 0 && lv.leaf == NULL && lv.C == NULL && lv.P == NULL &&
                  lv.cells_visited == 0);
        }
        CHECK(done);
        total += n - 2;
        md_leaves_free(&ref);
    }
    md_bvh_free(bvh);
    md_elements_free(&el);
    printf("allocations failed in turn: %ld\n", total);
    return mfg_test_report("medial_voxels_alloc");
}
