/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_bvh_alloc.c - md_bvh_build under allocation failure: every allocation in
 * turn fails (the failing allocator of tests/alloc_fail), and each time the build reports
 * MFG_ERR_NOMEM, leaves *out NULL and leaks no block; once nothing fails, the BVH answers
 * as one built without the shim. */
#include <stdint.h>
#include <string.h>

#include "alloc_shim.h"
#include "medial/medial.h"
#include "mfg_test.h"
#include "mfgeom.h"

int main(void)
{
    /* A box 100 x 60 x 20: 12 triangles, 26 elements. */
    double xyz[24];
    for (int k = 0; k < 8; k++) {
        xyz[3 * k] = (k & 1) ? 100 : 0;
        xyz[3 * k + 1] = (k & 2) ? 60 : 0;
        xyz[3 * k + 2] = (k & 4) ? 20 : 0;
    }
    static const int64_t tri[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                    2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
    md_elements el;
    if (md_elements_build(xyz, 8, tri, 12, 1.0, &el) != MFG_OK) {
        CHECK(0);
        return mfg_test_report("medial_bvh_alloc");
    }
    const double x[3] = {30, 20, 7};
    int done = 0;
    long n;
    for (n = 1; n < 100 && !done; n++) {
        md_bvh *bvh = (md_bvh *)&el; /* anything but NULL: a failure must clear it */
        alloc_shim_arm(n);
        mfg_status st = md_bvh_build(&el, &bvh);
        double D = -1;
        int64_t e = -1;
        if (st == MFG_OK) {
            D = md_bvh_nearest(bvh, &el, x, &e, NULL);
            md_bvh_free(bvh);
        }
        alloc_shim_stats s = alloc_shim_disarm();
        CHECK_EQ_INT(s.net, 0);
        if (s.failed == 0) {
            done = 1;
            CHECK_EQ_INT(st, MFG_OK);
            CHECK(D == 7 && md_kind(&el, e) == MD_FACE);
            continue;
        }
        if (st == MFG_OK) { /* absorbed by libc (qsort sorting in place) */
            CHECK(D == 7);
            continue;
        }
        CHECK_EQ_INT(st, MFG_ERR_NOMEM);
        CHECK(bvh == NULL);
    }
    CHECK(done);
    md_elements_free(&el);
    printf("allocations failed in turn: %ld\n", n - 2);
    return mfg_test_report("medial_bvh_alloc");
}
