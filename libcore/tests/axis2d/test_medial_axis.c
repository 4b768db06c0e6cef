/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_axis.c - the 2-D medial axis against the hand-derived axes of the
 * rectangle, the square, the square frame and the L (docs/design/axis2d.md, section 4), an
 * independent brute-force clearance (distance to the closed edges) and even-odd inside
 * test for every sample, and the bad-input errors. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_test.h"
#include "mfgeom.h"

/* ---- independent reference: distance to the closed boundary edges, even-odd inside
 * by a horizontal ray (the library decides sides by nesting and orientation). */
static double ref_dist(const double *xy, const int64_t *off, int64_t nrings, double x, double y)
{
    double best = INFINITY;
    for (int64_t r = 0; r < nrings; r++)
        for (int64_t k = off[r]; k < off[r + 1]; k++) {
            int64_t k2 = k + 1 < off[r + 1] ? k + 1 : off[r];
            double ax = xy[2 * k], ay = xy[2 * k + 1], bx = xy[2 * k2], by = xy[2 * k2 + 1];
            double ux = bx - ax, uy = by - ay, l2 = ux * ux + uy * uy;
            double t = l2 > 0 ? ((x - ax) * ux + (y - ay) * uy) / l2 : 0;
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            double d = hypot(x - ax - t * ux, y - ay - t * uy);
            if (d < best)
                best = d;
        }
    return best;
}

static int ref_inside(const double *xy, const int64_t *off, int64_t nrings, double x, double y)
{
    int in = 0;
    for (int64_t r = 0; r < nrings; r++)
        for (int64_t k = off[r]; k < off[r + 1]; k++) {
            int64_t k2 = k + 1 < off[r + 1] ? k + 1 : off[r];
            double ax = xy[2 * k], ay = xy[2 * k + 1], bx = xy[2 * k2], by = xy[2 * k2 + 1];
            if ((ay > y) != (by > y)) {
                double xc = ax + (y - ay) * (bx - ax) / (by - ay);
                if (xc > x)
                    in = !in;
            }
        }
    return in;
}

/* Checks valid for every shape: radii = clearance, samples inside, chord midpoints within
 * tol of the interpolated radius, branch ends on their junctions or at radius 0. */
static void check_axis(const struct mfg_medial_axis *A, const double *xy, const int64_t *off,
                       int64_t nrings, double diag, double tol)
{
    CHECK_EQ_INT(A->branch_offsets[0], 0);
    CHECK_EQ_INT(A->branch_offsets[A->nbranches], A->npoints);
    int bad_r = 0, bad_in = 0, bad_chord = 0, bad_end = 0;
    for (int64_t i = 0; i < A->npoints; i++) {
        double x = A->points[2 * i], y = A->points[2 * i + 1];
        double d = ref_dist(xy, off, nrings, x, y);
        if (fabs(d - A->radii[i]) > 1e-9 * diag)
            bad_r++;
        if (A->radii[i] > 1e-9 * diag && !ref_inside(xy, off, nrings, x, y))
            bad_in++;
    }
    for (int64_t b = 0; b < A->nbranches; b++) {
        int64_t lo = A->branch_offsets[b], hi = A->branch_offsets[b + 1];
        CHECK(hi - lo >= 2);
        for (int64_t i = lo; i + 1 < hi; i++) {
            double mx = 0.5 * (A->points[2 * i] + A->points[2 * i + 2]);
            double my = 0.5 * (A->points[2 * i + 1] + A->points[2 * i + 3]);
            double mr = 0.5 * (A->radii[i] + A->radii[i + 1]);
            if (fabs(ref_dist(xy, off, nrings, mx, my) - mr) > tol)
                bad_chord++;
        }
        for (int s = 0; s < 2; s++) {
            int64_t j = A->branch_ends[2 * b + s], i = s ? hi - 1 : lo;
            if (j < -1 || j >= A->njunctions) {
                bad_end++;
                continue;
            }
            if (j == -1 ? A->radii[i] != 0.0
                        : (hypot(A->points[2 * i] - A->junction_points[2 * j],
                                 A->points[2 * i + 1] - A->junction_points[2 * j + 1]) > 1e-12 * diag ||
                           A->radii[i] != A->junction_radii[j]))
                bad_end++;
        }
    }
    CHECK_EQ_INT(bad_r, 0);
    CHECK_EQ_INT(bad_in, 0);
    CHECK_EQ_INT(bad_chord, 0);
    CHECK_EQ_INT(bad_end, 0);
    for (int64_t j = 0; j < A->njunctions; j++) {
        double d = ref_dist(xy, off, nrings, A->junction_points[2 * j], A->junction_points[2 * j + 1]);
        CHECK(fabs(d - A->junction_radii[j]) <= 1e-9 * diag);
        CHECK(A->junction_offsets[j + 1] - A->junction_offsets[j] >= 3);
    }
}

/* Junction j of A at (x, y) with radius r (within 1e-9 * diag)?  Returns its index or -1. */
static int64_t find_junction(const struct mfg_medial_axis *A, double x, double y, double r,
                             double diag)
{
    for (int64_t j = 0; j < A->njunctions; j++)
        if (hypot(A->junction_points[2 * j] - x, A->junction_points[2 * j + 1] - y) <= 1e-9 * diag &&
            fabs(A->junction_radii[j] - r) <= 1e-9 * diag)
            return j;
    return -1;
}

static int64_t count_leaves(const struct mfg_medial_axis *A)
{
    int64_t n = 0;
    for (int64_t b = 0; b < 2 * A->nbranches; b++)
        n += A->branch_ends[b] == -1;
    return n;
}

/* Distance from (x, y) to the nearest sample. */
static double nearest_sample(const struct mfg_medial_axis *A, double x, double y)
{
    double best = INFINITY;
    for (int64_t i = 0; i < A->npoints; i++) {
        double d = hypot(A->points[2 * i] - x, A->points[2 * i + 1] - y);
        if (d < best)
            best = d;
    }
    return best;
}

static void test_rectangle(void)
{
    /* [0,10] x [0,4]: J (2,2) and (8,2), r 2, each touching 3 edges; 5 branches. */
    double xy[] = {0, 0, 10, 0, 10, 4, 0, 4};
    int64_t off[] = {0, 4};
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 1, 1e-2, &A), MFG_OK);
    if (!A)
        return;
    double diag = hypot(10, 4);
    CHECK_EQ_INT(A->nbranches, 5);
    CHECK_EQ_INT(A->njunctions, 2);
    CHECK_EQ_INT(count_leaves(A), 4);
    int64_t j1 = find_junction(A, 2, 2, 2, diag), j2 = find_junction(A, 8, 2, 2, diag);
    CHECK(j1 >= 0 && j2 >= 0);
    if (j1 >= 0 && j2 >= 0) {
        CHECK_EQ_INT(A->junction_degree[j1], 3);
        CHECK_EQ_INT(A->junction_degree[j2], 3);
        CHECK_EQ_INT(A->junction_offsets[j1 + 1] - A->junction_offsets[j1], 3);
    }
    /* straight bisectors with linear radii need no samples between their ends (the
     * advancement steps towards an event are not samples) */
    CHECK_EQ_INT(A->npoints, 2 * A->nbranches);
    check_axis(A, xy, off, 1, diag, 1e-2);
    mfg_medial_axis_free(A);
}

static void test_square(void)
{
    /* The degenerate junction: ONE junction at the centre touching 4 edges, degree 4.
     * Given clockwise, starting at another corner, with a repeated closing vertex. */
    double xy[] = {4, 0, 0, 0, 0, 4, 4, 4, 4, 0};
    int64_t off[] = {0, 5};
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 1, 1e-2, &A), MFG_OK);
    if (!A)
        return;
    double diag = hypot(4, 4);
    CHECK_EQ_INT(A->nbranches, 4);
    CHECK_EQ_INT(A->njunctions, 1);
    int64_t j = find_junction(A, 2, 2, 2, diag);
    CHECK(j == 0);
    if (j == 0) {
        CHECK_EQ_INT(A->junction_degree[0], 4);
        CHECK_EQ_INT(A->junction_offsets[1], 4);
    }
    check_axis(A, xy, off, 1, diag, 1e-2);
    mfg_medial_axis_free(A);
}

static void test_frame(void)
{
    /* Outer [0,10]^2, hole [2,8]^2: 4 junctions (t,t)... r t = (2 - sqrt 2) * 2, each
     * touching 2 outer edges and a hole corner; 4 leaves, 4 side branches (parabola, line,
     * parabola) with the transitions at (1, 2), (1, 8), ... (radius 1); one cycle. */
    double xy[] = {0, 0, 10, 0, 10, 10, 0, 10, 2, 2, 2, 8, 8, 8, 8, 2};
    int64_t off[] = {0, 4, 8};
    double tol = 1e-2;
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 2, tol, &A), MFG_OK);
    if (!A)
        return;
    double diag = hypot(10, 10), t = (2 - sqrt(2.0)) * 2;
    CHECK_EQ_INT(A->nbranches, 8);
    CHECK_EQ_INT(A->njunctions, 4);
    CHECK_EQ_INT(count_leaves(A), 4);
    double J[4][2] = {{t, t}, {10 - t, t}, {t, 10 - t}, {10 - t, 10 - t}};
    for (int i = 0; i < 4; i++) {
        int64_t j = find_junction(A, J[i][0], J[i][1], t, diag);
        CHECK(j >= 0);
        if (j < 0)
            continue;
        CHECK_EQ_INT(A->junction_degree[j], 3);
        int nreflex = 0;
        for (int64_t k = A->junction_offsets[j]; k < A->junction_offsets[j + 1]; k++)
            nreflex += A->junction_elements[k] < 0;
        CHECK_EQ_INT(nreflex, 1);
    }
    double T[8][2] = {{1, 2}, {1, 8}, {9, 2}, {9, 8}, {2, 1}, {8, 1}, {2, 9}, {8, 9}};
    for (int i = 0; i < 8; i++)
        CHECK(nearest_sample(A, T[i][0], T[i][1]) <= 1e-7 * diag);
    /* the hole's corners are reflex vertices of the face: -1 - k, k = 4 .. 7 */
    check_axis(A, xy, off, 2, diag, tol);
    mfg_medial_axis_free(A);
}

static void test_L(void)
{
    /* (0,0),(10,0),(10,2),(2,2),(2,8),(0,8): J0 (t,t) r t touching y = 0, x = 0 and the
     * reflex vertex (2,2); J1 (1,7) r 1; J2 (9,1) r 1; 7 branches. */
    double xy[] = {0, 0, 10, 0, 10, 2, 2, 2, 2, 8, 0, 8};
    int64_t off[] = {0, 6};
    double tol = 1e-2;
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 1, tol, &A), MFG_OK);
    if (!A)
        return;
    double diag = hypot(10, 8), t = (2 - sqrt(2.0)) * 2;
    CHECK_EQ_INT(A->nbranches, 7);
    CHECK_EQ_INT(A->njunctions, 3);
    CHECK_EQ_INT(count_leaves(A), 5);
    int64_t j0 = find_junction(A, t, t, t, diag);
    CHECK(j0 >= 0);
    CHECK(find_junction(A, 1, 7, 1, diag) >= 0);
    CHECK(find_junction(A, 9, 1, 1, diag) >= 0);
    if (j0 >= 0) {
        /* elements: edge 0 (y = 0), edge 5 (x = 0), reflex vertex 3 -> -4 */
        int64_t k = A->junction_offsets[j0], n = A->junction_offsets[j0 + 1] - k;
        CHECK_EQ_INT(n, 3);
        int has0 = 0, has5 = 0, hasv = 0;
        for (int64_t i = k; i < k + n; i++) {
            has0 |= A->junction_elements[i] == 0;
            has5 |= A->junction_elements[i] == 5;
            hasv |= A->junction_elements[i] == -4;
        }
        CHECK(has0 && has5 && hasv);
    }
    CHECK(nearest_sample(A, 1, 2) <= 1e-7 * diag);
    CHECK(nearest_sample(A, 2, 1) <= 1e-7 * diag);
    check_axis(A, xy, off, 1, diag, tol);
    mfg_medial_axis_free(A);
}

/* Jittered stars (n tips, radii 100 / 40 +- 15 %) with small square holes: no exact
 * axis, but the topology is fixed by Euler (a connected axis with one cycle per hole:
 * branches = junctions + leaves - 1 + holes; degrees + leaves = 2 branches; every tip is
 * a leaf) and every sample must have radius = clearance.  Regression: junction points are
 * equidistant only to the event accuracy, and a line bisector started from one carried
 * that offset along (radius errors 4.9e-7 on 200 segments, 1.7e-9 of the diagonal). */
static void test_stars(void)
{
    for (int c = 0; c < 4; c++) {
        int n = c < 2 ? 25 : 100, holes = c % 2 ? 4 + c : 0;
        int64_t nv = 2 * n + 4 * holes;
        double *xy = malloc((size_t)nv * 2 * sizeof *xy);
        int64_t off[16];
        for (int i = 0; i < 2 * n; i++) {
            double rad = (i % 2 ? 40.0 : 100.0) * (1 + 0.15 * rng_uniform(-1, 1));
            xy[2 * i] = rad * cos(i * M_PI / n);
            xy[2 * i + 1] = rad * sin(i * M_PI / n);
        }
        off[0] = 0, off[1] = 2 * n;
        for (int h = 0; h < holes; h++) {
            double cx = 20 * cos(h * 2 * M_PI / holes), cy = 20 * sin(h * 2 * M_PI / holes);
            double sq[4][2] = {{-2, -2}, {-2, 2}, {2, 2}, {2, -2}};
            for (int k = 0; k < 4; k++) {
                xy[2 * (off[h + 1] + k)] = cx + sq[k][0];
                xy[2 * (off[h + 1] + k) + 1] = cy + sq[k][1];
            }
            off[h + 2] = off[h + 1] + 4;
        }
        struct mfg_medial_axis *A = NULL;
        CHECK_EQ_INT(mfg_medial_axis(xy, off, 1 + holes, 1e-2, &A), MFG_OK);
        if (A) {
            int64_t leaves = count_leaves(A), deg = 0;
            for (int64_t j = 0; j < A->njunctions; j++)
                deg += A->junction_degree[j];
            CHECK_EQ_INT(leaves, n);
            CHECK_EQ_INT(A->nbranches, A->njunctions + leaves - 1 + holes);
            CHECK_EQ_INT(deg + leaves, 2 * A->nbranches);
            check_axis(A, xy, off, 1 + holes, 2 * 115.0, 1e-2);
            mfg_medial_axis_free(A);
        }
        free(xy);
    }
}

/* Regression: needle spikes (50 vertices of a 3 000-segment jittered star, closed by
 * three far vertices).  A junction gathered with 1e-7 of the diagonal took in a segment
 * and a reflex vertex of the neighbouring spike that do not touch its disc (2e-5 away);
 * their foot angles misordered the ports, one port paired the two segments adjacent at a
 * reflex vertex, and the trace failed with MFG_ERR_INTERNAL.  Then two branches ended at
 * radius 0 inside the face, 0.34 from the boundary: the conservative advancement's
 * margin measured an edge as +inf while the foot of the centre lay beyond the edge's
 * ends, so it was not a lower bound of the clearance and a step jumped over the contact
 * with a neighbouring needle's edge; the window switch at the needle's convex tip was
 * then taken for the leaf.  Fixed by exact event roots (every element's first contact
 * with the moving disc in closed form).  Run as the ctest medial_axis_needles. */
static void test_needles(void)
{
    static const double xy[] = {
        72.727948803394881, -68.296089846282328, 26.784289635784919, -25.046763931211419,
        62.25854615773801, -57.975825529300941, 26.844922366916759, -24.893505051084603,
        69.533650922143636, -64.208760357318681, 28.907731846216841, -26.582022082572845,
        72.582463410587494, -66.462979005712086, 29.985713004317791, -27.342354351447206,
        73.459386718108917, -66.702413187672306, 25.511737822987964, -23.067805022073408,
        69.11916928533303, -62.235179563020885, 33.909710012322833, -30.404083441903737,
        64.018494679871537, -57.158768427803011, 31.992414611888869, -28.444160323062256,
        74.341725231271766, -65.818279168703654, 31.867023257388077, -28.094560186983465,
        71.373219429620079, -62.658776359315539, 28.94174522821082, -25.300914399698453,
        75.804825797113864, -65.989098736742633, 33.939571944385605, -29.420122372875166,
        71.802230328493138, -61.978022655228699, 26.565695394492149, -22.833973918122631,
        65.448599641146757, -56.017023633894979, 33.928297855606083, -28.916111920145497,
        71.983776146670266, -61.089893099210975, 27.064584582687385, -22.871347230199994,
        78.727940418187842, -66.248127410053655, 33.832038880743838, -28.348225672638986,
        79.076727675730936, -65.977828380808759, 27.5523189359028, -22.890627172425557,
        74.872294652349481, -61.939748896473702, 28.711049647831445, -23.650735407795349,
        66.104396445964582, -54.221520385114964, 35.308218842773321, -28.837750111027532,
        76.633401897934988, -62.322706067400553, 27.679345496885237, -22.414292032665802,
        86.835265789743715, -70.017194258328757, 35.730516380419765, -28.687025747304045,
        85.513291186276177, -68.362162063465576, 28.982690309725733, -23.070395416922565,
        71.093759849099527, -56.348219714110691, 31.636262315235431, -24.966888580190751,
        80.598425542713073, -63.333644482331898, 35.079490245011499, -27.446562084257128,
        89.944773822903926, -70.0705336594432, 35.497432523766605, -27.534631103551959,
        75.39416653125447, -58.229206720713044, 32.522887155157704, -25.009843431918878,
        70.439407804819936, -53.932957160618159, 31.990617527041714, -24.3879718295968, 0, 0,
        -150, 0, -150, -150};
    int64_t off[] = {0, 53};
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 1, 1e-2, &A), MFG_OK);
    if (!A)
        return;
    int64_t leaves = count_leaves(A), deg = 0;
    for (int64_t j = 0; j < A->njunctions; j++)
        deg += A->junction_degree[j];
    CHECK_EQ_INT(A->nbranches, A->njunctions + leaves - 1);
    CHECK_EQ_INT(deg + leaves, 2 * A->nbranches);
    check_axis(A, xy, off, 1, 250.0, 1e-2);
    mfg_medial_axis_free(A);
}

/* Junctions closer than tol are one junction: the 4.004 x 4 rectangle has two junctions
 * (2, 2) and (2.004, 2) joined by a branch of length 0.004; with tol 1e-2 they are one of
 * degree 4 touching the 4 edges (the square's answer), with tol 1e-3 they stay apart. */
static void test_merge(void)
{
    double xy[] = {0, 0, 4.004, 0, 4.004, 4, 0, 4};
    double xy2[] = {4.004, 4, 0, 4, 0, 0, 4.004, 0}; /* traced from the other corner first */
    int64_t off[] = {0, 4};
    for (int v = 0; v < 2; v++) {
        struct mfg_medial_axis *A = NULL;
        CHECK_EQ_INT(mfg_medial_axis(v ? xy2 : xy, off, 1, 1e-2, &A), MFG_OK);
        if (A) {
            CHECK_EQ_INT(A->njunctions, 1);
            CHECK_EQ_INT(A->nbranches, 4);
            CHECK_EQ_INT(count_leaves(A), 4);
            if (A->njunctions == 1) {
                CHECK_EQ_INT(A->junction_degree[0], 4);
                CHECK_EQ_INT(A->junction_offsets[1], 4);
                for (int64_t k = 0; k < 4 && k < A->junction_offsets[1]; k++)
                    CHECK_EQ_INT(A->junction_elements[k], k); /* sorted edge ids 0..3 */
                /* the representative: of the two true junctions (3 elements each) the lower
                 * (x, y) -- whatever the tracing order */
                double jx = A->junction_points[0], jy = A->junction_points[1];
                CHECK(fabs(jy - 2) < 1e-12 && fabs(jx - 2) < 1e-12);
                CHECK(fabs(A->junction_radii[0] - 2) < 1e-12);
            }
            /* every branch starts at the junction (a leaf end last), radius = clearance */
            for (int64_t b = 0; b < A->nbranches; b++) {
                CHECK_EQ_INT(A->branch_ends[2 * b], 0);
                CHECK_EQ_INT(A->branch_ends[2 * b + 1], -1);
            }
            check_axis(A, v ? xy2 : xy, off, 1, hypot(4.004, 4), 1e-2);
            mfg_medial_axis_free(A);
        }
    }
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 1, 1e-3, &A), MFG_OK);
    if (A) {
        CHECK_EQ_INT(A->njunctions, 2);
        CHECK_EQ_INT(A->nbranches, 5);
        mfg_medial_axis_free(A);
    }
}

/* Canonical order: junctions sorted by (x, y); a branch starts at its lower junction;
 * branches sorted by (start, end).  The same arrays (to rounding) whatever the ring's
 * start vertex and orientation (a jittered star with two holes, holes given in the other
 * order too). */
static void test_canonical_order(void)
{
    enum { N = 40 };
    double base[2 * N + 8][2];
    for (int i = 0; i < N; i++) {
        double rad = (i % 2 ? 40.0 : 100.0) * (1 + 0.15 * rng_uniform(-1, 1));
        base[i][0] = rad * cos(i * 2 * M_PI / N), base[i][1] = rad * sin(i * 2 * M_PI / N);
    }
    double sq[4][2] = {{-2, -2}, {2, -2}, {2, 2}, {-2, 2}};
    for (int k = 0; k < 4; k++) {
        base[N + k][0] = 15 + sq[k][0], base[N + k][1] = 3 + sq[k][1];
        base[N + 4 + k][0] = -12 + sq[k][0], base[N + 4 + k][1] = -5 + sq[k][1];
    }
    struct mfg_medial_axis *R[3] = {NULL, NULL, NULL};
    for (int v = 0; v < 3; v++) {
        double xy[2 * (N + 8)];
        int64_t off[4] = {0, N, N + 4, N + 8};
        for (int i = 0; i < N; i++) { /* v 1: start at vertex 7; v 2: reversed too */
            int src = v == 0 ? i : v == 1 ? (i + 7) % N : (7 + N - i) % N;
            xy[2 * i] = base[src][0], xy[2 * i + 1] = base[src][1];
        }
        for (int k = 0; k < 8; k++) { /* v >= 1: the holes swapped, rotated */
            int src = v == 0 ? N + k : N + (k < 4 ? 4 + (k + 1) % 4 : (k + 1) % 4);
            xy[2 * (N + k)] = base[src][0], xy[2 * (N + k) + 1] = base[src][1];
        }
        CHECK_EQ_INT(mfg_medial_axis(xy, off, 3, 1e-2, &R[v]), MFG_OK);
    }
    for (int v = 1; v < 3 && R[0] && R[v]; v++) {
        const struct mfg_medial_axis *A = R[0], *B = R[v];
        CHECK_EQ_INT(B->njunctions, A->njunctions);
        CHECK_EQ_INT(B->nbranches, A->nbranches);
        if (B->njunctions != A->njunctions || B->nbranches != A->nbranches)
            continue;
        double dj = 0, de = 0;
        int bad_ends = 0;
        for (int64_t j = 0; j < A->njunctions; j++) {
            dj = fmax(dj, hypot(A->junction_points[2 * j] - B->junction_points[2 * j],
                                A->junction_points[2 * j + 1] - B->junction_points[2 * j + 1]));
            CHECK_EQ_INT(A->junction_degree[j], B->junction_degree[j]);
        }
        for (int64_t b = 0; b < A->nbranches; b++) {
            bad_ends += A->branch_ends[2 * b] != B->branch_ends[2 * b];
            bad_ends += A->branch_ends[2 * b + 1] != B->branch_ends[2 * b + 1];
            int64_t a1 = A->branch_offsets[b + 1] - 1, b1 = B->branch_offsets[b + 1] - 1;
            de = fmax(de, hypot(A->points[2 * a1] - B->points[2 * b1],
                                A->points[2 * a1 + 1] - B->points[2 * b1 + 1]));
        }
        CHECK(dj < 1e-9);
        CHECK(de < 1e-9);
        CHECK_EQ_INT(bad_ends, 0);
    }
    if (R[0]) { /* the documented order itself */
        const struct mfg_medial_axis *A = R[0];
        int bad = 0;
        for (int64_t j = 0; j + 1 < A->njunctions; j++)
            bad += A->junction_points[2 * j] > A->junction_points[2 * j + 2];
        int64_t pa = -1, pc = -1;
        for (int64_t b = 0; b < A->nbranches; b++) {
            int64_t a = A->branch_ends[2 * b], c = A->branch_ends[2 * b + 1];
            int64_t ka = a < 0 ? INT64_MAX : a, kc = c < 0 ? INT64_MAX : c;
            bad += ka > kc;                                 /* from the lower end */
            bad += ka < pa || (ka == pa && kc < pc);        /* sorted by (start, end) */
            pa = ka, pc = kc;
        }
        CHECK_EQ_INT(bad, 0);
    }
    for (int v = 0; v < 3; v++)
        mfg_medial_axis_free(R[v]);
}

/* Regression: a branch with more than 10 000 pieces (window switches) was reported as
 * "did not reach an event".  A 40 x 40 square with a hole: a circle of radius 10 as a
 * 40 000-gon (all its vertices reflex for the face).  Between two corner junctions a
 * branch follows a quarter of the circle: a transition at each of its 10 000 vertices
 * from edge to vertex and back.  4 leaves, 4 junctions, 8 branches (one cycle); every
 * 997th sample checked against the brute-force clearance. */
static void test_many_transitions(void)
{
    enum { NC = 40000 };
    double *xy = malloc((size_t)(4 + NC) * 2 * sizeof *xy);
    if (!xy)
        return;
    double sq[4][2] = {{-20, -20}, {20, -20}, {20, 20}, {-20, 20}};
    for (int k = 0; k < 4; k++)
        xy[2 * k] = sq[k][0], xy[2 * k + 1] = sq[k][1];
    for (int i = 0; i < NC; i++) {
        double a = 2 * M_PI * (i + 0.5) / NC;
        xy[8 + 2 * i] = 10 * cos(a), xy[8 + 2 * i + 1] = 10 * sin(a);
    }
    int64_t off[] = {0, 4, 4 + NC};
    struct mfg_medial_axis *A = NULL;
    CHECK_EQ_INT(mfg_medial_axis(xy, off, 2, 1e-3, &A), MFG_OK);
    if (A) {
        CHECK_EQ_INT(A->njunctions, 4);
        CHECK_EQ_INT(A->nbranches, 8);
        CHECK_EQ_INT(count_leaves(A), 4);
        int bad = 0;
        for (int64_t i = 0; i < A->npoints; i += 997)
            bad += fabs(ref_dist(xy, off, 2, A->points[2 * i], A->points[2 * i + 1]) -
                        A->radii[i]) > 1e-9 * 60;
        CHECK_EQ_INT(bad, 0);
        mfg_medial_axis_free(A);
    }
    free(xy);
}

static void expect_error(const double *xy, const int64_t *off, int64_t nrings, double tol,
                         mfg_status want, const char *needle)
{
    struct mfg_medial_axis *A = (struct mfg_medial_axis *)&A; /* must stay untouched */
    struct mfg_medial_axis *sentinel = A;
    mfg_status st = mfg_medial_axis(xy, off, nrings, tol, &A);
    CHECK_EQ_INT(st, want);
    CHECK(A == sentinel);
    if (needle && !strstr(mfg_last_error(), needle)) {
        fprintf(stderr, "error detail \"%s\" lacks \"%s\"\n", mfg_last_error(), needle);
        CHECK(0);
    }
}

static void test_bad_input(void)
{
    double sq[] = {0, 0, 1, 0, 1, 1, 0, 1};
    int64_t off1[] = {0, 4};
    expect_error(sq, off1, 1, 0.0, MFG_ERR_INVALID, "tolerance");
    expect_error(sq, off1, 1, -1.0, MFG_ERR_INVALID, "tolerance");
    expect_error(sq, off1, 1, NAN, MFG_ERR_INVALID, "tolerance");
    double nan_xy[] = {0, 0, 1, 0, NAN, 1, 0, 1};
    expect_error(nan_xy, off1, 1, 1e-3, MFG_ERR_INVALID, "vertex 2");
    int64_t off2[] = {0, 2};
    expect_error(sq, off2, 1, 1e-3, MFG_ERR_DEGENERATE, "fewer than 3");
    double dup[] = {0, 0, 0, 0, 1, 0, 1, 0};
    expect_error(dup, off1, 1, 1e-3, MFG_ERR_DEGENERATE, "fewer than 3");
    double line[] = {0, 0, 1, 0, 2, 0, 3, 0};
    expect_error(line, off1, 1, 1e-3, MFG_ERR_INVALID, "turns back");
    int64_t bad0[] = {1, 4};
    expect_error(sq, bad0, 1, 1e-3, MFG_ERR_INVALID, "ring_offsets[0]");
    int64_t dec[] = {0, 4, 2};
    expect_error(sq, dec, 2, 1e-3, MFG_ERR_INVALID, "non-decreasing");
    expect_error(sq, off1, 0, 1e-3, MFG_ERR_DEGENERATE, "no rings");
    expect_error(NULL, off1, 1, 1e-3, MFG_ERR_NULL, "xy");
    expect_error(sq, NULL, 1, 1e-3, MFG_ERR_NULL, "ring_offsets");
    CHECK_EQ_INT(mfg_medial_axis(sq, off1, 1, 1e-3, NULL), MFG_ERR_NULL);
    /* a bow tie: edges 0 and 2 cross */
    double bow[] = {0, 0, 1, 1, 1, 0, 0, 1};
    expect_error(bow, off1, 1, 1e-3, MFG_ERR_INVALID, "edge 0 (ring 0) and edge 2");
    /* a hole touching the outer ring at a vertex */
    double touch[] = {0, 0, 4, 0, 4, 4, 0, 4, 0, 2, 1, 1, 1, 3};
    int64_t off3[] = {0, 4, 7};
    expect_error(touch, off3, 2, 1e-3, MFG_ERR_INVALID, "touches or crosses");
    /* a ring touching itself: a vertex on a non-adjacent edge */
    double self[] = {0, 0, 4, 0, 4, 4, 2, 0, 0, 4};
    int64_t off5[] = {0, 5};
    expect_error(self, off5, 1, 1e-3, MFG_ERR_INVALID, "touches or crosses");
    mfg_medial_axis_free(NULL);
}

int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "needles") == 0) {
        test_needles();
        return mfg_test_report("medial_axis needles");
    }
    test_rectangle();
    test_square();
    test_frame();
    test_L();
    test_stars();
    test_merge();
    test_canonical_order();
    test_many_transitions();
    test_bad_input();
    return mfg_test_report("medial_axis");
}
