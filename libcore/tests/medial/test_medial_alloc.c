/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_alloc.c - md_elements_build under allocation failure: every allocation in
 * turn fails (the failing allocator of tests/alloc_fail), and each time the build reports
 * MFG_ERR_NOMEM, leaves its output zeroed and leaks no block. */
#include <stdint.h>
#include <string.h>

#include "alloc_shim.h"
#include "medial/medial.h"
#include "mfg_test.h"
#include "mfgeom.h"

int main(void)
{
    /* The L-bracket: 8 faces, 18 edges (one reflex), 12 vertices. */
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
    md_elements ref;
    CHECK_EQ_INT(md_elements_build(xyz, 12, tri, nt, 0.4, &ref), MFG_OK);
    int done = 0;
    long n, ok_despite = 0;
    for (n = 1; n < 1000 && !done; n++) {
        md_elements el;
        memset(&el, 0x5a, sizeof el);
        alloc_shim_arm(n);
        mfg_status st = md_elements_build(xyz, 12, tri, nt, 0.4, &el);
        int same = 0;
        if (st == MFG_OK) {
            /* A failure the callee absorbs (glibc's qsort falls back to sorting in place)
             * must leave the same result. */
            same = el.nfaces == ref.nfaces && el.nedges == ref.nedges && el.nverts == ref.nverts &&
                   !memcmp(el.face_plane, ref.face_plane, 4 * (size_t)ref.nfaces * sizeof(double)) &&
                   !memcmp(el.edge_seg, ref.edge_seg, 6 * (size_t)ref.nedges * sizeof(double)) &&
                   !memcmp(el.edge_convex, ref.edge_convex, (size_t)ref.nedges * sizeof(int32_t)) &&
                   !memcmp(el.vert_xyz, ref.vert_xyz, 3 * (size_t)ref.nverts * sizeof(double));
            md_elements_free(&el);
        }
        alloc_shim_stats s = alloc_shim_disarm();
        CHECK_EQ_INT(s.net, 0);
        if (s.failed == 0) {
            done = 1;
            CHECK_EQ_INT(st, MFG_OK);
            continue;
        }
        if (st == MFG_OK) {
            ok_despite++;
            CHECK(same);
            continue;
        }
        CHECK_EQ_INT(st, MFG_ERR_NOMEM);
        CHECK(el.nelements == 0 && el.xyz == NULL && el.face_plane == NULL);
    }
    CHECK(done);
    md_elements_free(&ref);
    printf("allocations failed in turn: %ld (%ld absorbed by libc)\n", n - 2, ok_despite);
    return mfg_test_report("medial_alloc");
}
