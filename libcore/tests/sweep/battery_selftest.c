/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* battery_selftest.c - the battery's checks tested on their own (a verdict of a broken
 * check is worthless): the exact zero-area test against integer arithmetic, the index's
 * distances and exact sides against brute force and the winding number, the inputs'
 * validity, and reference results of known swept volumes - right ones must pass, a
 * shrunk one must fail "conservative", an inflated one "tight", one with a vertex pushed
 * through the other side "self-intersection", a moved one must be found near / not near. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "battery.h"
#include "sweep_checks.h"

static int failures;
static int verbose;

#define EXPECT(cond, ...)                                                          \
    do {                                                                           \
        if (!(cond)) {                                                             \
            failures++;                                                            \
            fprintf(stderr, "battery self-test: %s:%d: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                          \
            fprintf(stderr, "\n");                                                 \
        }                                                                          \
    } while (0)

/* ------------------------------------------------------------------------ */
/* Exact predicates                                                         */
/* ------------------------------------------------------------------------ */

/* orient2d_proj against __int128 on near-collinear integer points scaled by 2^-20 (so
 * that the doubles are not integers), and zero_area on a collinear and a nearly
 * collinear triangle. */
static void test_zero_area(void)
{
    bt_rng r = {1};
    long wrong = 0;
    for (int k = 0; k < 3000; k++) {
        int64_t P[3][3];
        for (int i = 0; i < 2; i++)
            for (int c = 0; c < 3; c++)
                P[i][c] = bt_int(&r, -(1L << 40), 1L << 40);
        int64_t s = bt_int(&r, -3, 3);
        for (int c = 0; c < 3; c++)
            P[2][c] = P[0][c] + s * (P[1][c] - P[0][c]);
        P[2][k % 3] += bt_int(&r, -1, 1);
        double D[3][3];
        for (int i = 0; i < 3; i++)
            for (int c = 0; c < 3; c++)
                D[i][c] = ldexp((double)P[i][c], -20);
        for (int i = 0; i < 3; i++) {
            int j = (i + 1) % 3;
            __int128 det = (__int128)(P[1][i] - P[0][i]) * (P[2][j] - P[0][j]) -
                           (__int128)(P[1][j] - P[0][j]) * (P[2][i] - P[0][i]);
            int want = det > 0 ? 1 : det < 0 ? -1 : 0;
            wrong += orient2d_proj(D[0], D[1], D[2], i, j) != want;
        }
    }
    EXPECT(wrong == 0, "%ld of 9000 near-collinear orientations wrong", wrong);
    double a[3] = {0.1, 0.2, 0.3}, b[3] = {0.5, 0.25, 1.0 / 3};
    double m[3] = {0.5, 0.5, 0.5}, n[3] = {0.75, 0.75, 0.75}, o[3] = {1, 1, 1};
    EXPECT(zero_area(m, n, o), "three points of the diagonal");
    o[2] = nextafter(1.0, 2.0);
    EXPECT(!zero_area(m, n, o), "one ulp off the diagonal");
    EXPECT(zero_area(a, a, b), "a repeated corner");
}

/* A closed box with one edge split by a vertex m and the zero-area triangle (b, m, a)
 * closing it: a valid closed solid for mfg_mesh_check_closed (zero-area triangles among
 * others are accepted), so only zero_area_triangles can see it. */
static void test_zero_area_mesh(void)
{
    bt_mesh box = {0};
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    bt_box(&box, lo, hi);
    /* the first triangle (x = 0 side, normal -x) and the one sharing its first side */
    int64_t *t0 = box.tri, a = t0[0], b = t0[1], c = t0[2], other = -1, d = -1;
    for (int64_t t = 1; t < box.nt && other < 0; t++)
        for (int k = 0; k < 3; k++)
            if (box.tri[3 * t + k] == b && box.tri[3 * t + (k + 1) % 3] == a) {
                other = t;
                d = box.tri[3 * t + (k + 2) % 3];
            }
    EXPECT(other >= 0, "the box's triangle across the first side");
    if (other < 0) {
        bt_mesh_free(&box);
        return;
    }
    double *A = box.xyz + 3 * a, *B = box.xyz + 3 * b;
    int64_t mv = bt_add_vertex(&box, 0.5 * (A[0] + B[0]), 0.5 * (A[1] + B[1]), 0.5 * (A[2] + B[2]));
    t0 = box.tri;
    t0[0] = a; /* (a, b, c) -> (a, m, c) + (m, b, c) */
    t0[1] = mv;
    t0[2] = c;
    bt_add_tri(&box, mv, b, c);
    bt_add_tri(&box, b, mv, a); /* the zero-area one: closes b -> a against (a, m), (m, b) */
    (void)d;
    mfg_mesh m = bt_as_mfg(&box);
    mfg_mesh_report rep;
    EXPECT(mfg_mesh_check_closed(m.vertices, m.nvertices, m.triangles, m.ntriangles, &rep) == MFG_OK,
           "the box with a zero-area triangle is closed: %s", mfg_last_error());
    int64_t first;
    EXPECT(zero_area_triangles(&m, &first) == 1 && first == box.nt - 1, "one zero-area triangle, the last");
    bt_mesh_free(&box);
}

/* ------------------------------------------------------------------------ */
/* The index                                                                */
/* ------------------------------------------------------------------------ */

static void test_index_on(const bt_problem *p)
{
    bt_index ix;
    bt_index_build(&ix, p->in.xyz, p->in.tri, p->in.nt);
    mfg_mesh m = bt_as_mfg(&p->in);
    bt_rng r = {p->seed};
    long dist_wrong = 0, side_wrong = 0, sides = 0;
    for (int k = 0; k < 300; k++) {
        double q[3];
        for (int c = 0; c < 3; c++) {
            double w = ix.box[3 + c] - ix.box[c];
            q[c] = bt_unif(&r, ix.box[c] - 0.2 * w, ix.box[3 + c] + 0.2 * w);
        }
        double d = bt_dist(&ix, q, NULL), brute = mesh_dist(&m, q);
        dist_wrong += d != brute;
        if (brute > 1e-6 * p->size) { /* the winding number is sure away from the surface */
            sides++;
            side_wrong += bt_inside(&ix, q) != (winding(&m, q) > 0.5);
        }
    }
    long on_wrong = 0;
    for (int64_t i = 0; i < p->in.nv; i++) /* vertices are on the surface exactly */
        on_wrong += bt_inside(&ix, p->in.xyz + 3 * i) != -1;
    EXPECT(dist_wrong == 0, "%s: %ld of 300 distances differ from brute force", p->what, dist_wrong);
    EXPECT(side_wrong == 0, "%s: %ld of %ld sides differ from the winding number", p->what, side_wrong, sides);
    EXPECT(on_wrong == 0, "%s: %ld of %lld vertices not found on the surface", p->what, on_wrong, (long long)p->in.nv);
    bt_index_free(&ix);
}

/* Every family's inputs are valid solids (closed, outward, no self-intersection, no
 * zero-area triangle), and the index agrees with brute force on some of them. */
static void test_inputs(void)
{
    self_intersections_quiet = 1;
    for (int k = 0; k < bt_nparts; k++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", MFG_SWEEP_DATA_DIR, bt_part_files[k]);
        bt_mesh part;
        if (!bt_read_off(path, &part)) {
            EXPECT(0, "cannot read %s", path);
            continue;
        }
        mfg_mesh m = bt_as_mfg(&part);
        mfg_mesh_report rep;
        int64_t first;
        EXPECT(mfg_mesh_check_closed(m.vertices, m.nvertices, m.triangles, m.ntriangles, &rep) == MFG_OK,
               "%s: %s", path, mfg_last_error());
        EXPECT(self_intersections(&m, path) == 0, "%s: self-intersecting", path);
        EXPECT(zero_area_triangles(&m, &first) == 0, "%s: zero-area triangle %lld", path, (long long)first);
        bt_mesh_free(&part);
    }
    for (int f = 0; f < bt_nfamilies; f++)
        for (uint64_t s = 1; s <= 12; s++) {
            bt_problem p;
            if (!bt_make(bt_families[f], s * 0x9E3779B97F4A7C15ULL, &p)) {
                EXPECT(0, "%s: no input", bt_families[f]);
                continue;
            }
            mfg_mesh m = bt_as_mfg(&p.in);
            mfg_mesh_report rep;
            int64_t first;
            EXPECT(mfg_mesh_check_closed(m.vertices, m.nvertices, m.triangles, m.ntriangles, &rep) == MFG_OK,
                   "%s: %s", p.what, mfg_last_error());
            EXPECT(self_intersections(&m, p.what) == 0, "%s: self-intersecting input", p.what);
            EXPECT(zero_area_triangles(&m, &first) == 0, "%s: zero-area triangle %lld", p.what, (long long)first);
            if (s <= 2)
                test_index_on(&p);
            bt_problem_free(&p);
        }
}

/* ------------------------------------------------------------------------ */
/* Reference results                                                        */
/* ------------------------------------------------------------------------ */

typedef struct outcome {
    long outside, coarse, beyond, undecided, selfint;
} outcome;

static outcome check_ref(const bt_problem *p, const bt_mesh *res, const char *name)
{
    outcome o;
    mfg_mesh m = bt_as_mfg(res);
    bt_index ri, ii;
    bt_index_build(&ri, m.vertices, m.triangles, m.ntriangles);
    bt_index_build(&ii, p->in.xyz, p->in.tri, p->in.nt);
    double eps = bt_allowance(p);
    bt_cons_report c;
    bt_tight_report t;
    bt_check_conservative(p, &ri, eps, BT_CONS_ARCS, BT_CONS_EVALS, BT_CONS_EVALS_PER_ARC, 7, &c);
    bt_check_tight(p, &ii, &m, eps, BT_TIGHT_VERTICES, BT_TIGHT_FACE_POINTS, BT_TIGHT_EVALS, BT_TIGHT_EVALS_PER_POINT, 8, &t);
    self_intersections_quiet = 1;
    o.selfint = self_intersections(&m, name);
    o.outside = c.outside;
    o.coarse = c.coarse;
    o.beyond = t.beyond;
    o.undecided = t.undecided;
    if (verbose)
        printf("  self-test %-34s: %ld/%ld arcs outside (worst %.3g tol), %ld coarse, %ld queries; %ld/%ld points "
               "beyond (%.3g tol), %ld undecided, %ld queries; %ld self-intersections\n",
               name, c.outside, c.arcs, c.worst / p->tol, c.coarse, c.evals, t.beyond, t.points, t.worst_lb / p->tol,
               t.undecided, t.evals, o.selfint);
    bt_index_free(&ri);
    bt_index_free(&ii);
    return o;
}

/* The box [1, 2] x [0.5, 1.5] x [0, 1] turned a full turn about z: SV is the annulus
 * ri = |(1, 0.5)| <= r <= ro = |(2, 1.5)| = 2.5, 0 <= z <= 1.  The reference result is
 * the region between a 96-gon round the outer circle (vertex radius ro / cos(pi / 96): it
 * holds the circle, 1.3e-3 outside at the vertices) and one inscribed in the inner circle
 * (inside it): conservative and tight for tol 0.02, caps exactly on SV's. */
#define RING_N 96
#define RING_TOL 0.02

static void ring_problem(bt_problem *p)
{
    memset(p, 0, sizeof *p);
    p->family = "selftest";
    double lo[3] = {1, 0.5, 0}, hi[3] = {2, 1.5, 1};
    bt_box(&p->in, lo, hi);
    p->ad[2] = 1;
    p->angle = 2 * M_PI;
    p->tol = RING_TOL;
    p->size = bt_diag(p->in.xyz, p->in.nv);
    snprintf(p->what, sizeof p->what, "ring reference");
}

static void test_ring(void)
{
    bt_problem p;
    ring_problem(&p);
    double ri = hypot(1, 0.5), ro = 2.5, circ = 1 / cos(M_PI / RING_N);
    bt_mesh good = {0}, shrunk = {0}, inflated = {0}, pushed = {0};
    bt_ring(&good, RING_N, ri, ro * circ, 0, 1);
    /* shrunk by 0.4 %: the outer polygon inside the outer circle */
    bt_ring(&shrunk, RING_N, ri, ro * circ * 0.996, 0, 1);
    /* inflated by 3 tol: its outer vertices 3 tol beyond SV */
    bt_ring(&inflated, RING_N, ri, ro * circ + 3 * RING_TOL, 0, 1);
    /* a top outer vertex pushed down through the bottom cap */
    bt_ring(&pushed, RING_N, ri, ro * circ, 0, 1);
    for (int64_t i = 0; i < pushed.nv; i++)
        if (pushed.xyz[3 * i + 2] == 1 && hypot(pushed.xyz[3 * i], pushed.xyz[3 * i + 1]) > 2) {
            pushed.xyz[3 * i + 2] = -0.5;
            break;
        }
    outcome o = check_ref(&p, &good, "ring: right");
    EXPECT(o.outside == 0 && o.beyond == 0 && o.selfint == 0, "the right ring fails: %ld outside, %ld beyond, %ld "
           "self-intersections", o.outside, o.beyond, o.selfint);
    EXPECT(o.coarse == 0 && o.undecided == 0, "the right ring: %ld arcs coarse, %ld points undecided", o.coarse,
           o.undecided);
    o = check_ref(&p, &shrunk, "ring: shrunk 0.4 %");
    EXPECT(o.outside > 0, "the shrunk ring passes \"conservative\"");
    o = check_ref(&p, &inflated, "ring: inflated 3 tol");
    EXPECT(o.beyond > 0, "the inflated ring passes \"tight\"");
    EXPECT(o.outside == 0, "the inflated ring fails \"conservative\"");
    /* one outer vertex (top and bottom) pulled in by tol / 100: its edges now cut the
     * outer circle, a dent 1e-4 deep and a few degrees wide that only the arcs at the
     * outer radius pass (the box's outer corner and edge) */
    bt_mesh dent = {0};
    bt_ring(&dent, RING_N, ri, ro * circ, 0, 1);
    for (int64_t i = 0; i < dent.nv; i++)
        if (dent.xyz[3 * i + 1] == 0 && dent.xyz[3 * i] > 2)
            dent.xyz[3 * i] -= RING_TOL / 100;
    o = check_ref(&p, &dent, "ring: a vertex pulled in tol/100");
    EXPECT(o.outside > 0, "the dented ring passes \"conservative\"");
    bt_mesh_free(&dent);
    o = check_ref(&p, &pushed, "ring: vertex pushed through");
    EXPECT(o.selfint > 0, "the ring with a vertex pushed through has no self-intersection");

    /* the rigid-motion check: a result and the same result moved with its problem are
     * within tol of each other; the inflated one is not within tol of the right one */
    mfg_mesh mg = bt_as_mfg(&good), mi = bt_as_mfg(&inflated);
    bt_index ig, ii;
    bt_index_build(&ig, mg.vertices, mg.triangles, mg.ntriangles);
    bt_index_build(&ii, mi.vertices, mi.triangles, mi.ntriangles);
    double worst;
    long b1 = bt_within_solid(&mg, &ig, RING_TOL, BT_NEAR_POINTS, 3, &worst);
    EXPECT(b1 == 0, "the ring is not within tol of itself (%ld points, %.3g)", b1, worst);
    long b2 = bt_within_solid(&mi, &ig, RING_TOL, BT_NEAR_POINTS, 3, &worst);
    EXPECT(b2 > 0, "the inflated ring is within tol of the right one");
    long b3 = bt_within_solid(&mg, &ii, RING_TOL, BT_NEAR_POINTS, 3, &worst);
    EXPECT(b3 == 0, "the right ring is not inside the inflated one (%ld points, %.3g)", b3, worst);
    bt_index_free(&ig);
    bt_index_free(&ii);

    /* the same at a partial angle: a quarter turn of the box about z is inside the full
     * ring (conservative) but the ring is far from it (not tight) */
    p.angle = M_PI / 2;
    o = check_ref(&p, &good, "ring for a quarter turn");
    EXPECT(o.outside == 0 && o.beyond > 0, "the full ring for a quarter turn: %ld outside, %ld beyond", o.outside,
           o.beyond);
    bt_mesh_free(&good);
    bt_mesh_free(&shrunk);
    bt_mesh_free(&inflated);
    bt_mesh_free(&pushed);
    bt_problem_free(&p);
}

/* The unit cube turned by 1e-6 about the z axis through (-0.5, -0.5, 0): SV lies within
 * r theta < 2.2e-6 of the cube.  The cube grown by 1e-5 holds it and is within tol = 1e-3;
 * shrunk by 1e-4 it leaves the input's surface outside; grown by 3 tol it is not tight. */
static void test_tiny_angle(void)
{
    bt_problem p;
    memset(&p, 0, sizeof p);
    p.family = "selftest";
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    bt_box(&p.in, lo, hi);
    p.ap[0] = p.ap[1] = -0.5;
    p.ad[2] = 1;
    p.angle = 1e-6;
    p.tol = 1e-3;
    p.size = bt_diag(p.in.xyz, p.in.nv);
    snprintf(p.what, sizeof p.what, "tiny angle reference");
    static const double grow[3] = {1e-5, -1e-4, 3e-3};
    for (int k = 0; k < 3; k++) {
        bt_mesh r = {0};
        double l[3], h[3];
        for (int c = 0; c < 3; c++) {
            l[c] = -grow[k];
            h[c] = 1 + grow[k];
        }
        bt_box(&r, l, h);
        char name[64];
        snprintf(name, sizeof name, "cube by 1e-6: grown %g", grow[k]);
        outcome o = check_ref(&p, &r, name);
        if (k == 0)
            EXPECT(o.outside == 0 && o.beyond == 0 && o.undecided == 0, "the grown cube: %ld outside, %ld beyond, %ld "
                   "undecided", o.outside, o.beyond, o.undecided);
        else if (k == 1)
            EXPECT(o.outside > 0, "the shrunk cube passes \"conservative\"");
        else
            EXPECT(o.outside == 0 && o.beyond > 0, "the cube grown by 3 tol: %ld outside, %ld beyond", o.outside,
                   o.beyond);
        bt_mesh_free(&r);
    }
    bt_problem_free(&p);
}

int bt_selftest(int verbose_)
{
    verbose = verbose_;
    failures = 0;
    test_zero_area();
    test_zero_area_mesh();
    test_inputs();
    test_ring();
    test_tiny_angle();
    return failures;
}
