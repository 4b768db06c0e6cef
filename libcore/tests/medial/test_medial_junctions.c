/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_junctions.c - junctions and degenerate seams (medial/junctions.c;
 * docs/design/medial.md section 4.3) on solids whose equidistant points are known by hand:
 * the cube's centre, the cuboid's corners of its mid-sheet, the square prism's axis and its
 * ends, the L-bracket's junctions at the reflex edge (rho* = (2 - sqrt 2) 10) and at the
 * end of its smooth seam.  The search is run as the pipeline runs it: in a leaf-sized box,
 * with T the elements whose closure is within D + 2 rho of the box centre (a superset of
 * those that touch anywhere in the box, so the search must also drop the ones that do not). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "medial_find.h"
#include "mfg_test.h"
#include "mfgeom.h"
#include "medial_solids.h"

/* The search runs here without a BVH (bvh = NULL: every element is a candidate). */

static int64_t edge_on_line(const md_elements *el, double x, double y)
{
    for (int64_t i = 0; i < el->nedges; i++) {
        const double *A = el->edge_seg + 6 * i;
        if (A[0] == x && A[1] == y && A[3] == x && A[4] == y)
            return el->nfaces + i;
    }
    return -1;
}

static int cmp64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

/* The junctions found in the box of side `side` around p (lo = p minus an off-centre
 * offset, so that p is not on a box face). */
static int search_at(const md_elements *el, const double p[3], double side, double tol,
                     md_junction *out, int cap, int *nT_out)
{
    double lo[3], c[3], D;
    const double off[3] = {0.37, 0.41, 0.53};
    for (int k = 0; k < 3; k++) {
        lo[k] = p[k] - off[k] * side;
        c[k] = lo[k] + 0.5 * side;
    }
    double rho = 0.5 * sqrt(3.0) * side;
    int64_t *buf = malloc((size_t)el->nelements * sizeof *buf);
    md_nearest_set_brute(el, c, 0, buf, &D);
    int64_t T[MD_JMAX];
    int nT = 0;
    for (int64_t e = 0; e < el->nelements && nT < MD_JMAX; e++)
        if (md_dist_closed(el, e, c) <= D + 2 * rho)
            T[nT++] = e;
    free(buf);
    *nT_out = nT;
    return md_junction_search(&(md_jbox){el, NULL, lo, side, tol}, T, nT, out, cap);
}

static int same_set(const md_junction *j, int64_t *want, int n)
{
    qsort(want, (size_t)n, sizeof *want, cmp64);
    return j->n == n && !memcmp(j->elems, want, (size_t)n * sizeof *want);
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                (a[2] - b[2]) * (a[2] - b[2]));
}

static void test_cube(void)
{
    tmesh m;
    ms_box(&m, 40, 40, 40);
    md_elements el;
    double tol = 0.5;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    md_junction j[8];
    int nT, n = search_at(&el, (double[3]){20, 20, 20}, tol, tol, j, 8, &nT);
    CHECK_EQ_INT(nT, 6);
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK(dist3(j[0].x, (double[3]){20, 20, 20}) <= 1e-12);
        CHECK(fabs(j[0].r - 20) <= 1e-12);
        CHECK_EQ_INT(j[0].rank, 3);
        CHECK_EQ_INT(j[0].kind, MFG_MEDIAL_BRANCH);
        int64_t want[6] = {0, 1, 2, 3, 4, 5};
        CHECK(same_set(&j[0], want, 6));
    }
    md_elements_free(&el);
}

static void test_cuboid(void)
{
    tmesh m;
    ms_box(&m, 100, 60, 20);
    md_elements el;
    double tol = 0.5;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    md_junction j[8];
    int nT, n = search_at(&el, (double[3]){10, 10, 10}, tol, tol, j, 8, &nT);
    CHECK(nT >= 4);
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK(dist3(j[0].x, (double[3]){10, 10, 10}) <= 1e-12);
        CHECK(fabs(j[0].r - 10) <= 1e-12);
        CHECK_EQ_INT(j[0].rank, 3);
        CHECK_EQ_INT(j[0].kind, MFG_MEDIAL_BRANCH);
        int64_t want[4] = {face_with(&el, 0, 0, -1, 0), face_with(&el, 0, 0, 1, 20),
                           face_with(&el, -1, 0, 0, 0), face_with(&el, 0, -1, 0, 0)};
        CHECK(same_set(&j[0], want, 4));
    }
    /* On the seam {z0, z1, y0} away from the corner: the set with x0 has no point here. */
    int64_t T[4] = {face_with(&el, 0, 0, -1, 0), face_with(&el, 0, 0, 1, 20),
                    face_with(&el, -1, 0, 0, 0), face_with(&el, 0, -1, 0, 0)};
    qsort(T, 4, sizeof *T, cmp64);
    CHECK_EQ_INT(md_junction_search(&(md_jbox){&el, NULL, (double[3]){29.8, 9.8, 9.8}, tol, tol}, T, 4, j, 8), 0);
    /* The polish alone, from 0.3 away: the same point. */
    md_junction one;
    md_jbox box = {&el, NULL, (double[3]){9.75, 9.75, 9.75}, 0.5, tol};
    CHECK_EQ_INT(md_junction_polish(&box, (double[3]){10.2, 9.9, 10.1}, T, 4, &one), 1);
    CHECK(dist3(one.x, (double[3]){10, 10, 10}) <= 1e-12);
    md_elements_free(&el);
}

static void test_square_prism(void)
{
    tmesh m;
    ms_box(&m, 20, 20, 100);
    md_elements el;
    double tol = 0.5;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    int64_t sides[4] = {face_with(&el, -1, 0, 0, 0), face_with(&el, 1, 0, 0, 20),
                        face_with(&el, 0, -1, 0, 0), face_with(&el, 0, 1, 0, 20)};
    md_junction j[8];
    /* The axis: rank 2, a degenerate seam along z. */
    int nT, n = search_at(&el, (double[3]){10, 10, 50}, tol, tol, j, 8, &nT);
    CHECK_EQ_INT(nT, 4);
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK(fabs(j[0].x[0] - 10) <= 1e-12 && fabs(j[0].x[1] - 10) <= 1e-12);
        CHECK(fabs(j[0].x[2] - 50) <= tol);
        CHECK(fabs(j[0].r - 10) <= 1e-12);
        CHECK_EQ_INT(j[0].rank, 2);
        CHECK_EQ_INT(j[0].kind, MFG_MEDIAL_DEGENERATE);
        CHECK(fabs(j[0].dir[2] - 1) <= 1e-12);
        int64_t want[4];
        memcpy(want, sides, sizeof want);
        CHECK(same_set(&j[0], want, 4));
    }
    /* Its end: rank 3 with the 5 faces. */
    n = search_at(&el, (double[3]){10, 10, 10}, tol, tol, j, 8, &nT);
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK(dist3(j[0].x, (double[3]){10, 10, 10}) <= 1e-12);
        CHECK(fabs(j[0].r - 10) <= 1e-12);
        CHECK_EQ_INT(j[0].rank, 3);
        CHECK_EQ_INT(j[0].kind, MFG_MEDIAL_BRANCH);
        int64_t want[5] = {sides[0], sides[1], sides[2], sides[3], face_with(&el, 0, 0, -1, 0)};
        CHECK(same_set(&j[0], want, 5));
    }
    md_elements_free(&el);
}

static void test_l_bracket(void)
{
    tmesh m;
    ms_l_bracket(&m);
    md_elements el;
    double tol = 0.4;
    CHECK_EQ_INT(md_elements_build(m.xyz, m.nv, m.tri, m.nt, tol, &el), MFG_OK);
    int64_t Fo = face_with(&el, -1, 0, 0, 0), Go = face_with(&el, 0, -1, 0, 0);
    int64_t Fi = face_with(&el, 1, 0, 0, 10), z0 = face_with(&el, 0, 0, -1, 0);
    int64_t E = edge_on_line(&el, 10, 10);
    CHECK(Fo >= 0 && Go >= 0 && Fi >= 0 && z0 >= 0 && E >= 0);
    double rs = (2 - sqrt(2.0)) * 10;
    md_junction j[8];
    int nT, n = search_at(&el, (double[3]){rs, rs, rs}, tol, tol, j, 8, &nT);
    CHECK(nT > 4); /* Fi and Gi's closures reach as near as E: the search drops them */
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK(dist3(j[0].x, (double[3]){rs, rs, rs}) <= 1e-12);
        CHECK(fabs(j[0].r - rs) <= 1e-12);
        CHECK_EQ_INT(j[0].rank, 3);
        CHECK_EQ_INT(j[0].kind, MFG_MEDIAL_BRANCH);
        int64_t want[4] = {Fo, Go, E, z0};
        CHECK(same_set(&j[0], want, 4));
    }
    /* The end of the smooth seam {Fo, Fi, E}: (5, 10, 5), three contact clusters. */
    n = search_at(&el, (double[3]){5, 10, 5}, tol, tol, j, 8, &nT);
    CHECK_EQ_INT(n, 1);
    if (n == 1) {
        CHECK(dist3(j[0].x, (double[3]){5, 10, 5}) <= 1e-12);
        CHECK(fabs(j[0].r - 5) <= 1e-12);
        CHECK_EQ_INT(j[0].rank, 3);
        CHECK_EQ_INT(j[0].kind, MFG_MEDIAL_SMOOTH);
        int64_t want[4] = {Fo, Fi, E, z0};
        CHECK(same_set(&j[0], want, 4));
    }
    md_elements_free(&el);
}

int main(void)
{
    test_cube();
    test_cuboid();
    test_square_prism();
    test_l_bracket();
    return mfg_test_report("test_medial_junctions");
}
