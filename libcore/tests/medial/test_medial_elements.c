/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_elements.c - the medial surface's boundary elements (medial/elements.c), the
 * exact mfg_orient3d they rely on, and the bisector roots (medial/bisector.c), on solids
 * whose elements, distances and bisector points are known by hand.  "design N" cites
 * docs/design/medial.md section N. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "medial_find.h"
#include "medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"
#include "common/predicates.h"

static int64_t vertex_with(const md_elements *el, double x, double y, double z)
{
    for (int64_t j = 0; j < el->nverts; j++) {
        const double *p = el->vert_xyz + 3 * j;
        if (p[0] == x && p[1] == y && p[2] == z)
            return el->nfaces + el->nedges + j;
    }
    return -1;
}

/* ---- orient3d against exact integer determinants ---------------------------------------- */

static int exact_orient3d(const int64_t *a, const int64_t *b, const int64_t *c, const int64_t *d)
{
    __int128 m[3][3];
    for (int k = 0; k < 3; k++) {
        m[0][k] = (__int128)a[k] - d[k];
        m[1][k] = (__int128)b[k] - d[k];
        m[2][k] = (__int128)c[k] - d[k];
    }
    __int128 det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                   m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                   m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    return (det > 0) - (det < 0);
}

static void test_orient3d(void)
{
    /* Sign convention: d below the counter-clockwise triangle abc -> +1. */
    double a[3] = {0, 0, 0}, b[3] = {1, 0, 0}, c[3] = {0, 1, 0}, dn[3] = {0, 0, -1},
           dp[3] = {0, 0, 1}, d0[3] = {0.25, 0.5, 0};
    CHECK_EQ_INT(mfg_orient3d(a, b, c, dn), 1);
    CHECK_EQ_INT(mfg_orient3d(a, b, c, dp), -1);
    CHECK_EQ_INT(mfg_orient3d(a, b, c, d0), 0);
    /* Random near-coplanar integer configurations far from the origin (coordinates up
     * to 2^45: the differences are exact, the raw products are not). */
    int wrong = 0, zeros = 0;
    for (int it = 0; it < 20000; it++) {
        int64_t P[4][3];
        int64_t off = (int64_t)rng_int(0, 1L << 20) << 25;
        for (int i = 0; i < 3; i++)
            for (int k = 0; k < 3; k++)
                P[i][k] = off + rng_int(-(1L << 20), 1L << 20);
        long s = rng_int(-5, 5), t = rng_int(-5, 5);
        for (int k = 0; k < 3; k++)
            P[3][k] = P[0][k] + s * (P[1][k] - P[0][k]) + t * (P[2][k] - P[0][k]);
        P[3][rng_int(0, 2)] += rng_int(-1, 1);
        double D[4][3];
        for (int i = 0; i < 4; i++)
            for (int k = 0; k < 3; k++)
                D[i][k] = (double)P[i][k];
        int want = exact_orient3d(P[0], P[1], P[2], P[3]);
        zeros += want == 0;
        wrong += mfg_orient3d(D[0], D[1], D[2], D[3]) != want;
    }
    CHECK_EQ_INT(wrong, 0);
    CHECK(zeros > 1000); /* the exact path was exercised on true zeros */
    /* Non-integer: d = a + (b - a) / 3 rounded is off the line; exactness below 1 ulp. */
    double p[3] = {0.1, 0.2, 0.3}, q[3] = {1e10 + 0.1, 0.7, 0.3}, r[3] = {0.3, 1e10, 0.3};
    double z[3] = {12345.678, -0.3e9, 0.3};
    CHECK_EQ_INT(mfg_orient3d(p, q, r, z), 0);
    z[2] = nextafter(0.3, 1.0);
    CHECK_EQ_INT(mfg_orient3d(p, q, r, z), -1); /* above the counter-clockwise pqr */
}

/* ---- elements ----------------------------------------------------------------------- */

static void check_cube_elements(const md_elements *el, double s)
{
    CHECK_EQ_INT(el->nfaces, 6);
    CHECK_EQ_INT(el->nedges, 12);
    CHECK_EQ_INT(el->nverts, 8);
    CHECK_EQ_INT(el->nelements, 26);
    int convex = 0;
    for (int64_t i = 0; i < el->nedges; i++)
        convex += el->edge_convex[i] == 1;
    CHECK_EQ_INT(convex, 12);
    for (int ax = 0; ax < 3; ax++) {
        double n[3] = {0, 0, 0};
        n[ax] = 1;
        CHECK(face_with(el, n[0], n[1], n[2], s) >= 0);
        CHECK(face_with(el, -n[0], -n[1], -n[2], 0) >= 0);
    }
    for (int64_t j = 0; j < el->nverts; j++)
        CHECK_EQ_INT(el->vert_region_empty[j], 0);
    /* Ids are sorted by their keys: the first face holds the origin-most vertex list. */
    for (int64_t i = 0; i + 1 < el->nverts; i++) {
        const double *p = el->vert_xyz + 3 * i, *q = p + 3;
        CHECK(p[0] < q[0] || (p[0] == q[0] && (p[1] < q[1] || (p[1] == q[1] && p[2] < q[2]))));
    }
    /* Incidence and adjacency on the cube: x0 face, x0y0 edge, origin vertex. */
    int64_t fx0 = face_with(el, -1, 0, 0, 0), fx1 = face_with(el, 1, 0, 0, s);
    int64_t fy0 = face_with(el, 0, -1, 0, 0);
    double o[3] = {0, 0, 0}, oz[3] = {0, 0, s};
    int64_t e = edge_with(el, o, oz), v = vertex_with(el, 0, 0, 0);
    CHECK(e >= 0 && v >= 0);
    if (e >= 0 && v >= 0 && fx0 >= 0 && fx1 >= 0 && fy0 >= 0) {
        CHECK(md_incident(el, fx0, e));
        CHECK(md_incident(el, e, v));
        CHECK(md_incident(el, v, fx0));
        CHECK(!md_incident(el, fx0, fy0));
        CHECK(md_adjacent(el, fx0, fy0));
        CHECK(!md_adjacent(el, fx0, fx1));
        CHECK(md_kind(el, fx0) == MD_FACE && md_kind(el, e) == MD_EDGE && md_kind(el, v) == MD_VERTEX);
    }
}

static void test_cube(void)
{
    static tmesh m;
    for (int k = 1; k <= 3; k++) {
        ms_grid_box(&m, 40, 40, 40, k);
        md_elements el;
        mfg_status st = md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.5, &el);
        CHECK_EQ_INT(st, MFG_OK);
        if (st != MFG_OK) {
            fprintf(stderr, "  %s\n", mfg_last_error());
            continue;
        }
        check_cube_elements(&el, 40);
        /* Every triangle in a face; every side's element is the face or one of its edges. */
        for (int64_t t = 0; t < m.nt; t++) {
            CHECK(el.face_of_triangle[t] >= 0 && el.face_of_triangle[t] < 6);
            for (int c = 0; c < 3; c++) {
                int64_t se = el.side_elem[3 * t + c];
                CHECK(se == el.face_of_triangle[t] ||
                      (md_kind(&el, se) == MD_EDGE && md_incident(&el, se, el.face_of_triangle[t])));
            }
        }
        md_elements_free(&el);
    }
}

/* Shuffled triangles with rotated corners give the same elements bit for bit. */
static void check_shuffle_invariant(const tmesh *m, double tol)
{
    static tmesh r;
    r = *m;
    int64_t perm[1024];
    for (int64_t t = 0; t < m->nt; t++)
        perm[t] = t;
    for (int64_t t = m->nt - 1; t > 0; t--) {
        int64_t j = rng_int(0, t), x = perm[t];
        perm[t] = perm[j];
        perm[j] = x;
    }
    for (int64_t t = 0; t < m->nt; t++) {
        int rot = (int)rng_int(0, 2);
        for (int k = 0; k < 3; k++)
            r.tri[3 * perm[t] + k] = m->tri[3 * t + (k + rot) % 3];
    }
    md_elements a, b;
    CHECK_EQ_INT(md_elements_build(m->xyz, m->nv, m->tri, m->nt, tol, &a), MFG_OK);
    CHECK_EQ_INT(md_elements_build(r.xyz, r.nv, r.tri, r.nt, tol, &b), MFG_OK);
    CHECK_EQ_INT(a.nelements, b.nelements);
    if (a.nelements == b.nelements && a.nelements > 0 && a.nfaces == b.nfaces &&
        a.nedges == b.nedges) {
        size_t nf = (size_t)a.nfaces, ne = (size_t)a.nedges, nx = (size_t)a.nverts;
        CHECK(!memcmp(a.face_plane, b.face_plane, 4 * nf * sizeof(double)));
        CHECK(!memcmp(a.edge_seg, b.edge_seg, 6 * ne * sizeof(double)));
        CHECK(!memcmp(a.edge_faces, b.edge_faces, 2 * ne * sizeof(int64_t)));
        CHECK(!memcmp(a.edge_ends, b.edge_ends, 2 * ne * sizeof(int64_t)));
        CHECK(!memcmp(a.edge_w, b.edge_w, 6 * ne * sizeof(double)));
        CHECK(!memcmp(a.edge_convex, b.edge_convex, ne * sizeof(int32_t)));
        CHECK(!memcmp(a.vert_xyz, b.vert_xyz, 3 * nx * sizeof(double)));
        CHECK(!memcmp(a.vert_region_empty, b.vert_region_empty, nx * sizeof(int32_t)));
        CHECK(!memcmp(a.bound_offsets, b.bound_offsets, ((size_t)a.nelements + 1) * sizeof(int64_t)));
        CHECK(!memcmp(a.bound, b.bound, (size_t)a.bound_offsets[a.nelements] * sizeof(int64_t)));
        int same = 1;
        for (int64_t t = 0; t < m->nt; t++) {
            same &= a.face_of_triangle[t] == b.face_of_triangle[perm[t]];
            /* the same triangle's sides and corners, whatever its rotation */
            for (int k = 0; k < 3; k++) {
                int kk = -1;
                for (int j = 0; j < 3; j++)
                    if (b.tris[3 * perm[t] + j] == a.tris[3 * t + k])
                        kk = j;
                same &= kk >= 0 && a.corner_elem[3 * t + k] == b.corner_elem[3 * perm[t] + kk] &&
                        a.side_elem[3 * t + k] == b.side_elem[3 * perm[t] + kk];
            }
        }
        CHECK(same);
    }
    md_elements_free(&a);
    md_elements_free(&b);
}

static void test_canonical_ids(void)
{
    static tmesh m;
    ms_grid_box(&m, 40, 40, 40, 3);
    check_shuffle_invariant(&m, 0.5);
    ms_l_bracket(&m);
    check_shuffle_invariant(&m, 0.4);
}

static void test_l_bracket(void)
{
    static tmesh m;
    ms_l_bracket(&m);
    md_elements el;
    mfg_status st = md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.4, &el);
    CHECK_EQ_INT(st, MFG_OK);
    if (st != MFG_OK) {
        fprintf(stderr, "  %s\n", mfg_last_error());
        return;
    }
    CHECK_EQ_INT(el.nfaces, 8);
    CHECK_EQ_INT(el.nedges, 18);
    CHECK_EQ_INT(el.nverts, 12);
    double r0[3] = {10, 10, 0}, r1[3] = {10, 10, 40};
    int64_t E = edge_with(&el, r0, r1);
    CHECK(E >= 0);
    int reflex = 0;
    for (int64_t i = 0; i < el.nedges; i++)
        reflex += el.edge_convex[i] == 0;
    CHECK_EQ_INT(reflex, 1);
    if (E >= 0)
        CHECK_EQ_INT(el.edge_convex[E - el.nfaces], 0);
    /* The reflex corners of the L's caps empty their vertices' regions (design 1.7). */
    int empty = 0;
    for (int64_t j = 0; j < el.nverts; j++)
        empty += el.vert_region_empty[j];
    CHECK_EQ_INT(empty, 2);
    int64_t v0 = vertex_with(&el, 10, 10, 0);
    CHECK(v0 >= 0 && el.vert_region_empty[v0 - el.nfaces - el.nedges] == 1);

    int64_t Fo = face_with(&el, -1, 0, 0, 0), Go = face_with(&el, 0, -1, 0, 0);
    int64_t Gi = face_with(&el, 0, 1, 0, 10), Fi = face_with(&el, 1, 0, 0, 10);
    CHECK(Fo >= 0 && Go >= 0 && Gi >= 0 && Fi >= 0);
    if (E < 0 || Fo < 0 || Go < 0 || Gi < 0 || Fi < 0) {
        md_elements_free(&el);
        return;
    }
    /* Distances by hand.  Near the reflex edge: d_E = |(7,6) - (10,10)| = 5, inside its
     * normal wedge; D = 5 and the touching set is {E}. */
    double x1[3] = {7, 6, 20};
    CHECK(fabs(md_dist(&el, E, x1) - 5.0) <= 1e-14);
    CHECK(fabs(md_dist(&el, Fo, x1) - 7.0) <= 1e-14);
    CHECK(fabs(md_dist(&el, Go, x1) - 6.0) <= 1e-14);
    CHECK(md_dist(&el, Fi, x1) == INFINITY); /* behind the face (s < 0) */
    int64_t set[64];
    double D;
    int64_t n = md_nearest_set_brute(&el, x1, 1e-9, set, &D);
    CHECK_EQ_INT(n, 1);
    CHECK(n == 1 && set[0] == E);
    CHECK(fabs(D - 5.0) <= 1e-14);
    /* In the x arm's middle: Go and Gi at 5 each, the major pair. */
    double x2[3] = {30, 5, 20};
    n = md_nearest_set_brute(&el, x2, 1e-9, set, &D);
    CHECK_EQ_INT(n, 2);
    CHECK(fabs(D - 5.0) <= 1e-14);
    if (n == 2)
        CHECK((set[0] == Go && set[1] == Gi) || (set[0] == Gi && set[1] == Go));
    CHECK(!md_adjacent(&el, Go, Gi));
    CHECK(md_adjacent(&el, Fo, Go));
    /* Gi's plane is 5 away from (5,5,20) but the foot (5,10,20) is outside Gi: +inf. */
    double x3[3] = {5, 5, 20};
    CHECK(fabs(md_dist_car(&el, Gi, x3, NULL) - 5.0) <= 1e-14);
    CHECK(md_dist(&el, Gi, x3) == INFINITY);
    int64_t which = -2;
    double mg = md_region_margin(&el, Gi, x3, &which);
    CHECK(fabs(mg + 5.0) <= 1e-12); /* 5 outside its nearest side, on the reflex edge */
    CHECK(which == E);
    /* The reflex edge's wedge: (13, 6, 20) is behind Gi's side of the wedge (x > 10). */
    double x4[3] = {13, 6, 20};
    CHECK(md_dist(&el, E, x4) == INFINITY);
    md_elements_free(&el);
}

static void test_cube_distances(void)
{
    static tmesh m;
    ms_grid_box(&m, 40, 40, 40, 1);
    md_elements el;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.5, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    int64_t set[64];
    double D;
    /* The centre touches the 6 faces; the convex edges' and vertices' regions are outside. */
    double c[3] = {20, 20, 20};
    int64_t n = md_nearest_set_brute(&el, c, 1e-9, set, &D);
    CHECK_EQ_INT(n, 6);
    CHECK(D == 20.0);
    double x[3] = {10, 20, 25};
    n = md_nearest_set_brute(&el, x, 1e-9, set, &D);
    CHECK_EQ_INT(n, 1);
    CHECK(n == 1 && set[0] == face_with(&el, -1, 0, 0, 0));
    CHECK(D == 10.0);
    /* Outside, by the edge x = z = 40: 5 away, in its wedge; by the corner: sqrt(50). */
    double a[3] = {40, 0, 40}, b[3] = {40, 40, 40};
    int64_t e = edge_with(&el, a, b), v = vertex_with(&el, 40, 40, 40);
    double p[3] = {43, 20, 44}, q[3] = {43, 44, 45}, r[3] = {43, 20, 39};
    CHECK(fabs(md_dist(&el, e, p) - 5.0) <= 1e-14);
    CHECK(md_dist(&el, e, r) == INFINITY);
    CHECK(fabs(md_dist(&el, v, q) - sqrt(50.0)) <= 1e-14);
    CHECK(md_dist(&el, v, p) == INFINITY);
    CHECK(md_dist(&el, face_with(&el, 1, 0, 0, 40), p) == INFINITY); /* outside: s < 0 */
    md_elements_free(&el);
}

/* ---- bisector roots ------------------------------------------------------------------- */

static void check_root(const md_elements *el, int64_t a, int64_t b, const double *p,
                       const double *q, const double *want)
{
    double x[3], s;
    int ok = md_root_on_segment(el, a, b, p, q, x, &s);
    CHECK(ok);
    if (!ok)
        return;
    double da = md_dist_car(el, a, x, NULL), db = md_dist_car(el, b, x, NULL);
    double r = fmax(fabs(da), fabs(db));
    CHECK(fabs(da - db) <= 1e-12 * r);
    double err = fabs(x[0] - want[0]) + fabs(x[1] - want[1]) + fabs(x[2] - want[2]);
    CHECK(err <= 1e-12 * 40);
    if (fabs(da - db) > 1e-12 * r || err > 1e-12 * 40)
        fprintf(stderr, "  root (%.17g %.17g %.17g) want (%g %g %g): d %.17g %.17g\n", x[0], x[1],
                x[2], want[0], want[1], want[2], da, db);
    /* The segment the other way round finds the same root (to rounding). */
    double y[3];
    CHECK(md_root_on_segment(el, a, b, q, p, y, NULL));
    CHECK(fabs(y[0] - x[0]) + fabs(y[1] - x[1]) + fabs(y[2] - x[2]) <= 1e-12 * 40);
}

static void test_bisector(void)
{
    static tmesh m;
    ms_grid_box(&m, 40, 40, 40, 1);
    md_elements el;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.5, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    int64_t x0 = face_with(&el, -1, 0, 0, 0), x1 = face_with(&el, 1, 0, 0, 40);
    int64_t z0 = face_with(&el, 0, 0, -1, 0);
    /* plane/plane, crossing: x = z. */
    double p1[3] = {5, 20, 15}, q1[3] = {15, 20, 5}, w1[3] = {10, 20, 10};
    check_root(&el, x0, z0, p1, q1, w1);
    /* plane/plane, parallel: x = 20. */
    double p2[3] = {5, 7, 9}, q2[3] = {35, 7, 9}, w2[3] = {20, 7, 9};
    check_root(&el, x0, x1, p2, q2, w2);
    /* plane/vertex (40,40,40) along y = 30, z = 35: x^2 = (40-x)^2 + 125, x = 21.5625. */
    int64_t v = vertex_with(&el, 40, 40, 40);
    double p3[3] = {10, 30, 35}, q3[3] = {30, 30, 35}, w3[3] = {21.5625, 30, 35};
    check_root(&el, x0, v, p3, q3, w3);
    /* edge/edge: the z-edge x = y = 0 and the y-edge x = z = 40, along y = 5, z = 20:
     * x^2 + 25 = (40-x)^2 + 400, x = 24.6875. */
    double o[3] = {0, 0, 0}, oz[3] = {0, 0, 40}, a[3] = {40, 0, 40}, b[3] = {40, 40, 40};
    int64_t ez = edge_with(&el, o, oz), ey = edge_with(&el, a, b);
    double p4[3] = {5, 5, 20}, q4[3] = {35, 5, 20}, w4[3] = {24.6875, 5, 20};
    check_root(&el, ez, ey, p4, q4, w4);
    /* No sign change: 0, out untouched. */
    double out[3] = {-1, -1, -1}, p5[3] = {5, 7, 9}, q5[3] = {15, 7, 9};
    CHECK_EQ_INT(md_root_on_segment(&el, x0, x1, p5, q5, out, NULL), 0);
    CHECK(out[0] == -1 && out[1] == -1 && out[2] == -1);
    md_elements_free(&el);

    /* plane/edge on the L-bracket: Fo (x = 0) and the reflex edge (10,10,z), along
     * y = 3: x^2 = (10-x)^2 + 49, x = 7.45. */
    ms_l_bracket(&m);
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.4, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    double r0[3] = {10, 10, 0}, r1[3] = {10, 10, 40};
    int64_t E = edge_with(&el, r0, r1), Fo = face_with(&el, -1, 0, 0, 0);
    double p6[3] = {1, 3, 20}, q6[3] = {9, 3, 20}, w6[3] = {7.45, 3, 20};
    check_root(&el, Fo, E, p6, q6, w6);
    /* A skew segment, plane/edge: the root satisfies the bisector to 1e-12. */
    double p7[3] = {1, 2, 3}, q7[3] = {9, 4.5, 31}, x[3];
    CHECK(md_root_on_segment(&el, Fo, E, p7, q7, x, NULL));
    double da = md_dist_car(&el, Fo, x, NULL), db = md_dist_car(&el, E, x, NULL);
    CHECK(fabs(da - db) <= 1e-12 * fmax(da, db));
    md_elements_free(&el);
}

/* ---- D(x) against an independent reference --------------------------------------------- */

/* Distance from x to triangle abc by Ericson's closest-point regions (Real-Time Collision
 * Detection, 5.1.5), sharing no code with medial/elements.c. */
static double tri_dist(const double *p, const double *a, const double *b, const double *c)
{
    double ab[3], ac[3], ap[3], r[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = p[k] - a[k];
    }
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    double d1 = DOT(ab, ap), d2 = DOT(ac, ap), v, w;
    if (d1 <= 0 && d2 <= 0) {
        v = 0, w = 0;
    } else {
        double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
        double d3 = DOT(ab, bp), d4 = DOT(ac, bp);
        double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
        double d5 = DOT(ab, cp), d6 = DOT(ac, cp);
        double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (d3 >= 0 && d4 <= d3) {
            v = 1, w = 0;
        } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
            v = d1 / (d1 - d3), w = 0;
        } else if (d6 >= 0 && d5 <= d6) {
            v = 0, w = 1;
        } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
            v = 0, w = d2 / (d2 - d6);
        } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
            w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
            v = 1 - w;
        } else {
            double den = 1 / (va + vb + vc);
            v = vb * den, w = vc * den;
        }
    }
#undef DOT
    for (int k = 0; k < 3; k++)
        r[k] = ap[k] - v * ab[k] - w * ac[k];
    return sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

/* Inside the L-bracket (open set), by its definition. */
static int in_l(const double *x)
{
    return x[2] > 0 && x[2] < 40 && x[0] > 0 && x[1] > 0 &&
           ((x[0] < 10 && x[1] < 50) || (x[1] < 10 && x[0] < 50));
}

/* D(x) = min over elements of the restricted distances equals the distance to the
 * boundary (the minimum over the triangles) at random interior points: the Voronoi
 * regions (with the reflex corners' empty vertex regions) cover the interior and never
 * admit a carrier distance below the true one. */
static void test_distance_field(void)
{
    static tmesh m;
    ms_l_bracket(&m);
    md_elements el;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.4, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    int64_t set[64];
    int bad = 0, tested = 0;
    double worst = 0;
    while (tested < 20000) {
        double x[3] = {rng_uniform(0, 50), rng_uniform(0, 50), rng_uniform(0, 40)};
        if (tested % 4 == 0) /* a quarter near the reflex edge, where the regions meet */
            x[0] = rng_uniform(4, 16), x[1] = rng_uniform(4, 16), x[2] = rng_uniform(0, 40);
        if (!in_l(x))
            continue;
        tested++;
        double ref = INFINITY, D;
        for (int64_t t = 0; t < m.nt; t++)
            ref = fmin(ref, tri_dist(x, m.xyz + 3 * m.tri[3 * t], m.xyz + 3 * m.tri[3 * t + 1],
                                     m.xyz + 3 * m.tri[3 * t + 2]));
        int64_t n = md_nearest_set_brute(&el, x, 1e-9, set, &D);
        double err = fabs(D - ref);
        worst = fmax(worst, err);
        bad += n < 1 || err > 1e-12 * 50;
    }
    CHECK_EQ_INT(bad, 0);
    if (bad)
        fprintf(stderr, "  %d of %d points: D differs from the triangle distance (worst %g)\n",
                bad, tested, worst);
    md_elements_free(&el);
}

/* A tilted box rounded to float32 (as an STL gives it): its faces are never exactly
 * coplanar, the near-coplanar threshold eta merges them (design 1.3 [choice]). */
static void test_float32_tilted(void)
{
    /* One triangle pair per face far from the origin, 3 x 3 grids near it, and 3 x 3 grids
     * shifted by 100 (L = 69): float32 rounding there is up to 7.6e-6 and tilts a small
     * seed triangle's plane by more than 1e-7 L = 6.9e-6 over the face, so eta also scales
     * with max|coordinate| (this case split into 9 faces when eta was min(1e-7 L, 1e-3 tol)). */
    static const struct { int k; double off; } cases[3] = {{1, 100.25}, {3, 0.0}, {3, 100.0}};
    for (int c = 0; c < 3; c++) {
        static tmesh m;
        ms_grid_box(&m, 40, 40, 40, cases[c].k);
        double ca = cos(0.3), sa = sin(0.3), cb = cos(0.7), sb = sin(0.7);
        for (int64_t i = 0; i < m.nv; i++) {
            double *p = m.xyz + 3 * i;
            double x = ca * p[0] - sa * p[1], y = sa * p[0] + ca * p[1], z = p[2];
            double y2 = cb * y - sb * z, z2 = sb * y + cb * z;
            p[0] = (float)(x + cases[c].off);
            p[1] = (float)(y2 - 0.2 * cases[c].off);
            p[2] = (float)(z2 + 0.03 * cases[c].off);
        }
        md_elements el;
        mfg_status st = md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.5, &el);
        CHECK_EQ_INT(st, MFG_OK);
        if (st != MFG_OK) {
            fprintf(stderr, "  %s\n", mfg_last_error());
            continue;
        }
        CHECK_EQ_INT(el.nfaces, 6);
        CHECK_EQ_INT(el.nedges, 12);
        CHECK_EQ_INT(el.nverts, 8);
        int convex = 0;
        for (int64_t i = 0; i < el.nedges; i++)
            convex += el.edge_convex[i] == 1;
        CHECK_EQ_INT(convex, 12);
        /* Not exactly coplanar: the merge came from eta (without it, more faces). */
        md_elements_free(&el);
    }
}

/* A zero-area triangle inside a face (A, C and the diagonal's midpoint M) bridges the
 * face's triangles: no face of its own, the counts stay 6 / 12 / 8, and M (inside the
 * face) is no element. */
static void test_zero_area_bridge(void)
{
    static tmesh m, r;
    ms_grid_box(&m, 40, 40, 40, 1);
    memset(&r, 0, sizeof r);
    r.nv = m.nv;
    memcpy(r.xyz, m.xyz, sizeof m.xyz);
    for (int64_t t = 0; t < m.nt; t++) {
        const int64_t *tv = m.tri + 3 * t;
        if (m.xyz[3 * tv[0] + 2] == 40 && m.xyz[3 * tv[1] + 2] == 40 && m.xyz[3 * tv[2] + 2] == 40)
            continue;
        ms_tri(&r, tv[0], tv[1], tv[2]);
    }
    int64_t A = ms_vtx(&r, 0, 0, 40), B = ms_vtx(&r, 40, 0, 40), C = ms_vtx(&r, 40, 40, 40),
            D = ms_vtx(&r, 0, 40, 40), M = ms_vtx(&r, 20, 20, 40);
    ms_tri(&r, A, B, C);
    int64_t zt = r.nt;
    ms_tri(&r, A, C, M); /* zero area */
    ms_tri(&r, M, C, D);
    ms_tri(&r, A, M, D);
    md_elements el;
    mfg_status st = md_elements_build(r.xyz, r.nv, r.tri, r.nt, 0.5, &el);
    CHECK_EQ_INT(st, MFG_OK);
    if (st != MFG_OK) {
        fprintf(stderr, "  %s\n", mfg_last_error());
        return;
    }
    CHECK_EQ_INT(el.nfaces, 6);
    CHECK_EQ_INT(el.nedges, 12);
    CHECK_EQ_INT(el.nverts, 8);
    int64_t top = face_with(&el, 0, 0, 1, 40);
    CHECK_EQ_INT(el.face_of_triangle[zt], -1);
    CHECK_EQ_INT(el.face_of_triangle[zt + 1], top);
    CHECK_EQ_INT(el.face_of_triangle[zt + 2], top);
    for (int k = 0; k < 3; k++) {
        CHECK_EQ_INT(el.side_elem[3 * zt + k], top);
        if (el.tris[3 * zt + k] == M)
            CHECK_EQ_INT(el.corner_elem[3 * zt + k], top);
    }
    md_elements_free(&el);
}

/* Square pyramid: base [0,40]^2 at z = 0, apex (20, 20, 30): oblique lateral edges. */
static void pyramid(tmesh *m)
{
    memset(m, 0, sizeof *m);
    int64_t a = ms_vtx(m, 0, 0, 0), b = ms_vtx(m, 40, 0, 0), c = ms_vtx(m, 40, 40, 0), d = ms_vtx(m, 0, 40, 0);
    int64_t t = ms_vtx(m, 20, 20, 30);
    ms_tri(m, a, c, b);
    ms_tri(m, a, d, c);
    ms_tri(m, a, b, t);
    ms_tri(m, b, c, t);
    ms_tri(m, c, d, t);
    ms_tri(m, d, a, t);
}

static void test_forms(void)
{
    static tmesh m;
    ms_grid_box(&m, 40, 40, 40, 1);
    md_elements el;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.5, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    int64_t x0 = face_with(&el, -1, 0, 0, 0), x1 = face_with(&el, 1, 0, 0, 40);
    int64_t z0 = face_with(&el, 0, 0, -1, 0);
    double o[3] = {0, 0, 0}, oz[3] = {0, 0, 40}, ox[3] = {40, 0, 0}, c1[3] = {40, 40, 0},
           c2[3] = {40, 40, 40}, a[3] = {40, 0, 40};
    int64_t ez0 = edge_with(&el, o, oz), ez1 = edge_with(&el, c1, c2), ex = edge_with(&el, o, ox);
    int64_t ey = edge_with(&el, a, c2), v0 = vertex_with(&el, 0, 0, 0),
            v1 = vertex_with(&el, 40, 40, 40);
    CHECK_EQ_INT(md_form(&el, x0, x1), MD_FORM_PLANE_PLANE_PARALLEL);
    CHECK_EQ_INT(md_form(&el, z0, x0), MD_FORM_PLANE_PLANE);
    CHECK_EQ_INT(md_form(&el, x0, ez1), MD_FORM_PLANE_LINE_PARALLEL);
    CHECK_EQ_INT(md_form(&el, ez1, x0), MD_FORM_PLANE_LINE_PARALLEL);
    CHECK_EQ_INT(md_form(&el, z0, ez1), MD_FORM_PLANE_LINE_PERPENDICULAR);
    CHECK_EQ_INT(md_form(&el, v1, x0), MD_FORM_PLANE_POINT);
    CHECK_EQ_INT(md_form(&el, ez0, ez1), MD_FORM_LINE_LINE_PARALLEL);
    CHECK_EQ_INT(md_form(&el, ez0, ex), MD_FORM_LINE_LINE_CROSSING);
    CHECK_EQ_INT(md_form(&el, ez0, ey), MD_FORM_LINE_LINE_SKEW);
    CHECK_EQ_INT(md_form(&el, v0, ey), MD_FORM_LINE_POINT);
    CHECK_EQ_INT(md_form(&el, v0, v1), MD_FORM_POINT_POINT);
    md_elements_free(&el);
    pyramid(&m);
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.5, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    CHECK_EQ_INT(el.nfaces, 5);
    CHECK_EQ_INT(el.nedges, 8);
    CHECK_EQ_INT(el.nverts, 5);
    double apex[3] = {20, 20, 30};
    int64_t base = face_with(&el, 0, 0, -1, 0), lat = edge_with(&el, o, apex);
    CHECK_EQ_INT(md_form(&el, base, lat), MD_FORM_PLANE_LINE_OBLIQUE);
    md_elements_free(&el);
}

/* md_dist_closed against the independent point-triangle distance, and <= md_dist. */
static void test_dist_closed(void)
{
    static tmesh m;
    ms_l_bracket(&m);
    md_elements el;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.4, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    int bad = 0, above = 0;
    for (int it = 0; it < 2000; it++) {
        double x[3] = {rng_uniform(-10, 60), rng_uniform(-10, 60), rng_uniform(-10, 50)};
        for (int64_t f = 0; f < el.nfaces; f++) {
            double ref = INFINITY;
            for (int64_t t = 0; t < m.nt; t++)
                if (el.face_of_triangle[t] == f)
                    ref = fmin(ref, tri_dist(x, m.xyz + 3 * m.tri[3 * t], m.xyz + 3 * m.tri[3 * t + 1],
                                             m.xyz + 3 * m.tri[3 * t + 2]));
            bad += fabs(md_dist_closed(&el, f, x) - ref) > 1e-12 * 60;
        }
        for (int64_t e = 0; e < el.nelements; e++) {
            double d = md_dist(&el, e, x);
            above += d < INFINITY && md_dist_closed(&el, e, x) > fabs(d) + 1e-12 * 60;
        }
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(above, 0);
    md_elements_free(&el);
}

/* Roots on random segments for every pair of elements of the pyramid and the L-bracket
 * (all 11 forms between them).  Design 4.0 asks |d_a - d_b| <= 8u r; the carrier
 * distances are evaluated at world coordinates (s_F = delta - n.x cancels), so their own
 * rounding is a few u (r + |x|), and that is what is asserted: 8u (r + |x|).  The worst
 * in units of u r is printed (measured: 40.8 u r at r = 0.78, |x| = 31). */
static void test_random_roots(void)
{
    static tmesh m;
    int seen[12] = {0};
    double worst = 0, worst_abs = 0;
    int roots = 0, bad = 0;
    for (int solid = 0; solid < 2; solid++) {
        if (solid)
            ms_l_bracket(&m);
        else
            pyramid(&m);
        md_elements el;
        if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.4, &el) != MFG_OK) {
            CHECK(0);
            return;
        }
        for (int64_t a = 0; a < el.nelements; a++)
            for (int64_t b = a + 1; b < el.nelements; b++)
                for (int it = 0; it < 20; it++) {
                    double p[3], q[3], x[3];
                    for (int k = 0; k < 3; k++) {
                        p[k] = rng_uniform(-5, 55);
                        q[k] = rng_uniform(-5, 55);
                    }
                    if (!md_root_on_segment(&el, a, b, p, q, x, NULL))
                        continue;
                    double da = md_dist_car(&el, a, x, NULL), db = md_dist_car(&el, b, x, NULL);
                    double r = fmax(fabs(da), fabs(db)), err = fabs(da - db) / (0x1p-53 * r);
                    roots++;
                    seen[md_form(&el, a, b)] = 1;
                    if (r > 0)
                        worst = fmax(worst, err);
                    double xn = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
                    worst_abs = fmax(worst_abs, fabs(da - db) / (0x1p-53 * (r + xn)));
                    bad += fabs(da - db) > 8.0 * 0x1p-53 * (r + xn);
                }
        md_elements_free(&el);
    }
    int forms = 0;
    for (int k = 1; k <= 11; k++)
        forms += seen[k];
    CHECK_EQ_INT(forms, 11);
    CHECK_EQ_INT(bad, 0);
    printf("random roots: %d, forms seen %d, worst |d_a - d_b| = %.2f u r = %.2f u (r + |x|)\n",
           roots, forms, worst, worst_abs);
}

/* A zero-area sliver (A, M, B) along the cube's edge A = (0,0,40), B = (40,0,40), with M
 * splitting the front face's side: still 6 / 12 / 8, the sliver has no face, and the edge
 * A-B is one element whichever face claimed the sliver. */
static void test_zero_area_on_edge(void)
{
    static tmesh m, r;
    ms_grid_box(&m, 40, 40, 40, 1);
    memset(&r, 0, sizeof r);
    r.nv = m.nv;
    memcpy(r.xyz, m.xyz, sizeof m.xyz);
    for (int64_t t = 0; t < m.nt; t++) {
        const int64_t *tv = m.tri + 3 * t;
        if (m.xyz[3 * tv[0] + 1] == 0 && m.xyz[3 * tv[1] + 1] == 0 && m.xyz[3 * tv[2] + 1] == 0)
            continue; /* the front face y = 0, rebuilt below */
        ms_tri(&r, tv[0], tv[1], tv[2]);
    }
    int64_t P0 = ms_vtx(&r, 0, 0, 0), P1 = ms_vtx(&r, 40, 0, 0), A = ms_vtx(&r, 0, 0, 40),
            B = ms_vtx(&r, 40, 0, 40), M = ms_vtx(&r, 20, 0, 40);
    ms_tri(&r, P0, P1, B);
    ms_tri(&r, P0, B, M);
    ms_tri(&r, P0, M, A);
    int64_t zt = r.nt;
    ms_tri(&r, A, M, B); /* zero area */
    md_elements el;
    mfg_status st = md_elements_build(r.xyz, r.nv, r.tri, r.nt, 0.5, &el);
    CHECK_EQ_INT(st, MFG_OK);
    if (st != MFG_OK) {
        fprintf(stderr, "  %s\n", mfg_last_error());
        return;
    }
    CHECK_EQ_INT(el.nfaces, 6);
    CHECK_EQ_INT(el.nedges, 12);
    CHECK_EQ_INT(el.nverts, 8);
    CHECK_EQ_INT(el.face_of_triangle[zt], -1);
    double a[3] = {0, 0, 40}, b[3] = {40, 0, 40};
    int64_t E = edge_with(&el, a, b);
    CHECK(E >= 0);
    if (E >= 0)
        CHECK_EQ_INT(el.edge_convex[E - el.nfaces], 1);
    /* M lies on the edge: every corner at M, and every side of the sliver, is the edge's. */
    int corners = 0;
    for (int64_t t = 0; t < r.nt; t++)
        for (int k = 0; k < 3; k++)
            if (el.tris[3 * t + k] == M) {
                corners++;
                CHECK_EQ_INT(el.corner_elem[3 * t + k], E);
            }
    CHECK_EQ_INT(corners, 3);
    for (int k = 0; k < 3; k++)
        CHECK_EQ_INT(el.side_elem[3 * zt + k], E);
    md_elements_free(&el);
}

/* ---- refusals ------------------------------------------------------------------------- */

static void expect_refused(const tmesh *m, double tol, mfg_status st, const char *text)
{
    md_elements el;
    memset(&el, 0x5a, sizeof el);
    mfg_status got = md_elements_build(m->xyz, m->nv, m->tri, m->nt, tol, &el);
    CHECK_EQ_INT(got, st);
    CHECK(strstr(mfg_last_error(), text) != NULL);
    if (!strstr(mfg_last_error(), text))
        fprintf(stderr, "  detail was: \"%s\", expected \"%s\"\n", mfg_last_error(), text);
    CHECK(el.nelements == 0 && el.face_plane == NULL); /* zeroed: nothing to free */
}

static void test_refusals(void)
{
    static tmesh m;
    ms_grid_box(&m, 40, 40, 40, 1);
    expect_refused(&m, 0.0, MFG_ERR_INVALID, "tolerance must be finite and > 0");
    expect_refused(&m, -1.0, MFG_ERR_INVALID, "tolerance must be finite and > 0");
    expect_refused(&m, NAN, MFG_ERR_INVALID, "tolerance must be finite and > 0");
    expect_refused(&m, 100.0, MFG_ERR_INVALID, "smaller than the bounding-box diagonal");
    expect_refused(&m, 1e-6, MFG_ERR_INVALID, "2^20");
    m.nt--; /* open */
    expect_refused(&m, 0.5, MFG_ERR_INVALID, "not closed");
    ms_grid_box(&m, 40, 40, 40, 1);
    int64_t t = m.tri[0]; /* flip one triangle */
    m.tri[0] = m.tri[1];
    m.tri[1] = t;
    expect_refused(&m, 0.5, MFG_ERR_INVALID, "inconsistent orientation");
}

/* The region margin of a face with many sides (a side tree, element_distances.c) against
 * a plain computation here: a non-convex 121-gon (the origin and 120 points on an arc of
 * alternating radii 10 and 7), extruded 4; its bottom face (z = 0, s_F = z).  Reference:
 * the foot's 2-D distance to the polygon's sides, inside by crossing parity, margin =
 * min(s_F, +-distance).  Random points, the corners and side midpoints (margin 0 there). */
static double seg2_dist(const double *p, const double *a, const double *b)
{
    double ux = b[0] - a[0], uy = b[1] - a[1], wx = p[0] - a[0], wy = p[1] - a[1];
    double t = (ux * wx + uy * wy) / (ux * ux + uy * uy);
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    return hypot(wx - t * ux, wy - t * uy);
}

static void test_side_tree_margin(void)
{
    static tmesh m;
    static double P[121][2];
    int n = 121;
    P[0][0] = P[0][1] = 0;
    for (int i = 1; i < n; i++) {
        double a = 0.5 * M_PI * (i - 1) / (n - 2), r = i % 2 ? 10.0 : 7.0;
        P[i][0] = r * cos(a);
        P[i][1] = r * sin(a);
    }
    ms_prism(&m, (const double(*)[2])P, n, 4.0);
    md_elements el;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 0.05, &el) != MFG_OK) {
        CHECK(0);
        return;
    }
    int64_t bottom = -1;
    for (int64_t f = 0; f < el.nfaces; f++)
        if (el.face_plane[4 * f + 2] < -0.999)
            bottom = f;
    CHECK(bottom >= 0);
    CHECK(el.face_side_offsets[bottom + 1] - el.face_side_offsets[bottom] == n);
    CHECK(el.side_tree_offsets[bottom + 1] > el.side_tree_offsets[bottom]); /* has a tree */
    int bad = 0, bad_which = 0, npts = 0;
    for (int it = 0; it < 20000 + 2 * n; it++) {
        double x[3];
        if (it < 20000) {
            x[0] = rng_uniform(-3, 12);
            x[1] = rng_uniform(-3, 12);
            x[2] = rng_uniform(-1, 5);
        } else { /* corners and side midpoints, on the plane and above it */
            int i = (it - 20000) / 2, j = (i + 1) % n;
            double w = (it % 2) ? 0.5 : 0.0;
            x[0] = P[i][0] + w * (P[j][0] - P[i][0]);
            x[1] = P[i][1] + w * (P[j][1] - P[i][1]);
            x[2] = 1.0;
        }
        double d = INFINITY;
        int cross = 0;
        for (int i = 0; i < n; i++) {
            const double *a = P[i], *b = P[(i + 1) % n];
            d = fmin(d, seg2_dist(x, a, b));
            if ((a[1] > x[1]) != (b[1] > x[1]) &&
                x[0] < a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
                cross ^= 1;
        }
        double ref = fmin(x[2], d == 0 || cross ? d : -d);
        int64_t which = -2;
        double mg = md_region_margin(&el, bottom, x, &which);
        bad += !(fabs(mg - ref) <= 1e-12 * 12);
        if (mg < x[2]) { /* a side won: which is an edge at that distance */
            npts++;
            bad_which += !(md_kind(&el, which) == MD_EDGE &&
                           fabs(md_dist_closed(&el, which, (double[3]){x[0], x[1], 0}) - fabs(mg)) <=
                               1e-12 * 12);
        }
    }
    CHECK_EQ_INT(bad, 0);
    CHECK_EQ_INT(bad_which, 0);
    CHECK(npts > 1000);
    md_elements_free(&el);
}

int main(void)
{
    test_orient3d();
    test_cube();
    test_canonical_ids();
    test_l_bracket();
    test_cube_distances();
    test_bisector();
    test_distance_field();
    test_float32_tilted();
    test_zero_area_bridge();
    test_zero_area_on_edge();
    test_forms();
    test_dist_closed();
    test_random_roots();
    test_refusals();
    test_side_tree_margin();
    return mfg_test_report("medial_elements");
}
