/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_voxels.c - the medial surface's adaptive octree (medial/octree.c) on the
 * cuboid 100 x 60 x 20, the L-bracket, the cube 40, the 48-gon disc, a 160-segment cup
 * (wall strips about one leaf wide) and the L-bracket rotated, in major and full mode, at 0.5 % of L and at
 * coarse tolerances (leaf depth 1 .. 5), against brute-force references
 * (md_nearest_set_brute, md_dist_closed) and analytic inside tests:
 *   (a) completeness: at points x inside whose two nearest elements are within h / 4,
 *       moved onto their bisector (Newton; every third onto the seam or junction of its 3
 *       or 4 nearest), every allowed pair of the touching set T_{h/64}(x) is in P of the
 *       leaf that contains x;
 *   (b) the leaves are sorted and unique; every leaf's centre is inside the solid or
 *       within rho of it; C holds every closure within D + 2 rho of the centre, P only
 *       allowed pairs of C, nT = |T_2rho(centre)| (brute force); the cube's centre leaf
 *       holds exactly its 3 pairs of opposite faces, the cuboid's mid-sheet leaf {z0, z1};
 *   (c) the output is bit-identical for 1, 2 and 7 threads, for shuffled triangles
 *       (order, corner rotation, vertex numbering) and with or without the BVH;
 *   (d) leaves ~ area / h^2: 0.8 < leaves h^2 / A < 1.5 (cup: 1.7) at 1, 0.5 and 0.25 %
 *       of L.
 * Usage: test_medial_voxels [a|b|c|d] (no argument: all); "cost" times a curved cup of
 * about 5.5k triangles instead, "cost FILE" a raw mesh (int64 nv, nt; doubles; int64
 * triangles), printed, not asserted: speed targets live in bench/. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "medial/medial.h"
#include "medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"

/* A solid of revolution about z: the profile (r, z) runs from the axis round to the axis
 * (pr[0] and pr[np - 1] have r = 0: one vertex each), nseg segments.  Room: 2 + (np - 2)
 * nseg vertices, 2 (np - 1) nseg triangles; *nv, *nt get the counts. */
static void revolve(const double (*pr)[2], int np, int nseg, double *xyz, int64_t *nv,
                    int64_t *tr, int64_t *nt)
{
    int64_t n = 2 + (int64_t)(np - 2) * nseg, t = 0;
#define PV(i, j) ((i) == 0 ? 0 : (i) == np - 1 ? n - 1 : 1 + (int64_t)((i) - 1) * nseg + (j) % nseg)
    xyz[0] = xyz[1] = 0;
    xyz[2] = pr[0][1];
    xyz[3 * (n - 1)] = xyz[3 * (n - 1) + 1] = 0;
    xyz[3 * (n - 1) + 2] = pr[np - 1][1];
    for (int i = 1; i < np - 1; i++)
        for (int j = 0; j < nseg; j++) {
            double th = 2 * M_PI * j / nseg;
            double *v = xyz + 3 * PV(i, j);
            v[0] = pr[i][0] * cos(th), v[1] = pr[i][0] * sin(th), v[2] = pr[i][1];
        }
    for (int i = 0; i + 1 < np; i++)
        for (int j = 0; j < nseg; j++) {
            int64_t a = PV(i, j), b = PV(i + 1, j), c = PV(i + 1, j + 1), d = PV(i, j + 1);
            if (b != c) /* not the top axis point */
                tr[3 * t] = a, tr[3 * t + 1] = c, tr[3 * t + 2] = b, t++;
            if (a != d) /* not the bottom axis point */
                tr[3 * t] = a, tr[3 * t + 1] = d, tr[3 * t + 2] = (b != c ? c : b), t++;
        }
#undef PV
    *nv = n;
    *nt = t;
}

/* ---- the solids ---------------------------------------------------------------------- */

typedef struct solid {
    const char *name;
    tmesh m;
    double major_area; /* of the major sheets, for the leaf density */
    double max_density; /* bound on leaves h^2 / major_area (0: 1.5) */
    int (*inside)(const double *x);
} solid;

static int in_cuboid(const double *x)
{
    return x[0] > 0 && x[0] < 100 && x[1] > 0 && x[1] < 60 && x[2] > 0 && x[2] < 20;
}

static int in_cube(const double *x)
{
    return x[0] > 0 && x[0] < 40 && x[1] > 0 && x[1] < 40 && x[2] > 0 && x[2] < 40;
}

static int in_l(const double *x)
{
    return x[2] > 0 && x[2] < 40 && x[0] > 0 && x[1] > 0 && x[0] < 50 && x[1] < 50 &&
           (x[0] < 10 || x[1] < 10);
}

#define DISC_N 48
static double disc_p[DISC_N][2];

static int in_disc(const double *x)
{
    if (!(x[2] > 0 && x[2] < 4))
        return 0;
    for (int i = 0; i < DISC_N; i++) {
        const double *a = disc_p[i], *b = disc_p[(i + 1) % DISC_N];
        if ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) <= 0)
            return 0;
    }
    return 1;
}

/* A cup of revolution, 160 segments (examples/parts/cup.py's sizes): outer radius 20,
 * wall 3, height 30, bottom 4.  Its wall strips (0.67 .. 0.79 wide) are about as wide as
 * the leaves at 1 % of L: the pairs of strips on one side, never medial, must be pruned
 * by their regions, and the real pairs across the wall kept. */
#define TUBE_N 160
static double tube_out[TUBE_N][2], tube_in[TUBE_N][2];

static int in_ngon(const double (*p)[2], int n, const double *x)
{
    for (int i = 0; i < n; i++) {
        const double *a = p[i], *b = p[(i + 1) % n];
        if ((b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]) <= 0)
            return 0;
    }
    return 1;
}

static int in_tube(const double *x)
{
    if (!(x[2] > 0 && x[2] < 30) || !in_ngon((const double(*)[2])tube_out, TUBE_N, x))
        return 0;
    /* The pocket (z >= 4 inside the inner polygon) is outside the solid. */
    return !(x[2] >= 4 && in_ngon((const double(*)[2])tube_in, TUBE_N, x));
}

/* The L-bracket turned by a rotation R (rows: an orthonormal frame): faces in general
 * directions, coordinates off every grid. */
static double rot[3][3];

static int in_l_rotated(const double *x)
{
    double y[3]; /* R^T x */
    for (int k = 0; k < 3; k++)
        y[k] = rot[0][k] * x[0] + rot[1][k] * x[1] + rot[2][k] * x[2];
    return in_l(y);
}

static void make_solids(solid *S)
{
    static const double R[4][2] = {{0, 0}, {100, 0}, {100, 60}, {0, 60}};
    S[0].name = "cuboid";
    ms_prism(&S[0].m, R, 4, 20);
    S[0].major_area = 3200;
    S[0].inside = in_cuboid;
    static const double Lp[6][2] = {{0, 0}, {50, 0}, {50, 10}, {10, 10}, {10, 50}, {0, 50}};
    S[1].name = "L-bracket";
    ms_prism(&S[1].m, Lp, 6, 40);
    S[1].major_area = 2 * 1050 + 2 * 180; /* {Fo,Fi}, {Go,Gi} and roughly the {Fo,E}s */
    S[1].inside = in_l;
    static const double Q[4][2] = {{0, 0}, {40, 0}, {40, 40}, {0, 40}};
    S[2].name = "cube";
    ms_prism(&S[2].m, Q, 4, 40);
    S[2].major_area = 0;
    S[2].inside = in_cube;
    for (int i = 0; i < DISC_N; i++) {
        disc_p[i][0] = 50 * cos(2 * M_PI * i / DISC_N);
        disc_p[i][1] = 50 * sin(2 * M_PI * i / DISC_N);
    }
    S[3].name = "disc48";
    ms_prism(&S[3].m, (const double(*)[2])disc_p, DISC_N, 4);
    S[3].major_area = 7216.3;
    S[3].inside = in_disc;
    static const double pr[6][2] = {{0, 0}, {20, 0}, {20, 30}, {17, 30}, {17, 4}, {0, 4}};
    S[4].name = "cup160";
    memset(&S[4].m, 0, sizeof S[4].m);
    revolve(pr, 6, TUBE_N, S[4].m.xyz, &S[4].m.nv, S[4].m.tri, &S[4].m.nt);
    for (int i = 0; i < TUBE_N; i++) {
        double th = 2 * M_PI * i / TUBE_N;
        tube_out[i][0] = 20 * cos(th), tube_out[i][1] = 20 * sin(th);
        tube_in[i][0] = 17 * cos(th), tube_in[i][1] = 17 * sin(th);
    }
    /* The mid-surface of the wall and of the bottom (to the wall's mid radius). */
    S[4].major_area = 2 * M_PI * 18.5 * 26 + M_PI * 18.5 * 18.5;
    S[4].inside = in_tube;
    /* 1.45 at 1 % of L; 2.10 when the strips one apart on one side are not pruned. */
    S[4].max_density = 1.7;
    /* R = Rz(0.7) Ry(0.4) Rx(0.3). */
    double cx = cos(0.3), sx = sin(0.3), cy = cos(0.4), sy = sin(0.4), cz = cos(0.7), sz = sin(0.7);
    double Rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
    double Ry[3][3] = {{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}};
    double Rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}}, T[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            T[i][j] = Ry[i][0] * Rx[0][j] + Ry[i][1] * Rx[1][j] + Ry[i][2] * Rx[2][j];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            rot[i][j] = Rz[i][0] * T[0][j] + Rz[i][1] * T[1][j] + Rz[i][2] * T[2][j];
    S[5] = S[1];
    S[5].name = "L-rotated";
    for (int64_t i = 0; i < S[5].m.nv; i++) {
        const double *p = S[1].m.xyz + 3 * i;
        for (int k = 0; k < 3; k++)
            S[5].m.xyz[3 * i + k] = rot[k][0] * p[0] + rot[k][1] * p[1] + rot[k][2] * p[2];
    }
    S[5].inside = in_l_rotated;
    /* An oblique plane crosses about |n|_1 A / h^2 leaves (up to sqrt 3). */
    S[5].max_density = 1.9;
}

static double tol_of(const md_elements *el, double frac) { return frac * el->diag; }

/* ---- references ------------------------------------------------------------------------ */

static int allowed(const md_elements *el, int64_t a, int64_t b, int full)
{
    return !md_incident(el, a, b) && (full || !md_adjacent(el, a, b));
}

static const md_leaf *find_leaf(const md_leaves *lv, const int32_t ijk[3])
{
    int64_t lo = 0, hi = lv->nleaves;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        const int32_t *k = lv->leaf[mid].ijk;
        int c = k[0] != ijk[0] ? (k[0] < ijk[0] ? -1 : 1)
                : k[1] != ijk[1] ? (k[1] < ijk[1] ? -1 : 1)
                : k[2] != ijk[2] ? (k[2] < ijk[2] ? -1 : 1) : 0;
        if (c == 0)
            return &lv->leaf[mid];
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return NULL;
}

static int has_pair(const md_leaves *lv, const md_leaf *lf, int64_t a, int64_t b)
{
    for (int32_t p = 0; p < lf->nP; p++)
        if (lv->P[lf->P_off + 2 * p] == a && lv->P[lf->P_off + 2 * p + 1] == b)
            return 1;
    return 0;
}

static int in_list(const int64_t *l, int32_t n, int64_t v)
{
    for (int32_t i = 0; i < n; i++)
        if (l[i] == v)
            return 1;
    return 0;
}

static void leaf_centre(const md_leaves *lv, const md_leaf *lf, double c[3])
{
    for (int k = 0; k < 3; k++)
        c[k] = lv->lat.origin[k] + lv->lat.h * ((double)lf->ijk[k] + 0.5);
}

/* The two elements with the smallest restricted distances at x (a < b), 0 if < 2. */
static int two_nearest(const md_elements *el, const double *x, int64_t *a, int64_t *b)
{
    double d1 = INFINITY, d2 = INFINITY;
    int64_t e1 = -1, e2 = -1;
    for (int64_t e = 0; e < el->nelements; e++) {
        double d = md_dist(el, e, x);
        if (d < d1) {
            d2 = d1;
            e2 = e1;
            d1 = d;
            e1 = e;
        } else if (d < d2) {
            d2 = d;
            e2 = e;
        }
    }
    if (e2 < 0)
        return 0;
    *a = e1 < e2 ? e1 : e2;
    *b = e1 < e2 ? e2 : e1;
    return 1;
}

/* ---- (a) completeness -------------------------------------------------------------------- */

/* The octree's slack: it keeps the pairs whose distances come within h / 64 of each other
 * and of D somewhere in the leaf (medial/octree.c, delta). */
#define SLACK(h) ((h) / 64)

/* Gauss-Newton from x toward the points equidistant (carrier distances) from the n = 2, 3
 * or 4 elements e: the n - 1 equations d_e0 = d_ei, minimum-norm steps through the
 * normal equations.  1 when every |d_e0 - d_ei| <= 1e-12 L. */
static int onto_equidistant(const md_elements *el, const int64_t *e, int n, double *x)
{
    for (int it = 0; it < 16; it++) {
        double g0[3], F[3], J[3][3], gi[3];
        double d0 = md_dist_car(el, e[0], x, g0), worst = 0;
        for (int i = 1; i < n; i++) {
            F[i - 1] = d0 - md_dist_car(el, e[i], x, gi);
            for (int k = 0; k < 3; k++)
                J[i - 1][k] = g0[k] - gi[k];
            worst = fmax(worst, fabs(F[i - 1]));
        }
        if (worst <= 1e-12 * el->diag)
            return 1;
        /* Solve (J J^T) y = F, step x -= J^T y (m = n - 1 <= 3: Gaussian elimination). */
        int m = n - 1;
        double A[3][4];
        for (int i = 0; i < m; i++) {
            for (int j = 0; j < m; j++)
                A[i][j] = J[i][0] * J[j][0] + J[i][1] * J[j][1] + J[i][2] * J[j][2];
            A[i][m] = F[i];
        }
        for (int c = 0; c < m; c++) {
            int p = c;
            for (int r = c + 1; r < m; r++)
                if (fabs(A[r][c]) > fabs(A[p][c]))
                    p = r;
            if (!(fabs(A[p][c]) > 1e-14))
                return 0;
            for (int j = 0; j <= m; j++) {
                double t = A[c][j];
                A[c][j] = A[p][j];
                A[p][j] = t;
            }
            for (int r = 0; r < m; r++)
                if (r != c) {
                    double f = A[r][c] / A[c][c];
                    for (int j = c; j <= m; j++)
                        A[r][j] -= f * A[c][j];
                }
        }
        for (int i = 0; i < m; i++) {
            double y = A[i][m] / A[i][i];
            for (int k = 0; k < 3; k++)
                x[k] -= y * J[i][k];
        }
    }
    return 0;
}

static int onto_bisector(const md_elements *el, int64_t a, int64_t b, double *x)
{
    int64_t e[2] = {a, b};
    return onto_equidistant(el, e, 2, x);
}

/* The k (<= 4) elements with the smallest restricted distances at x, nearest first;
 * returns how many are finite. */
static int k_nearest(const md_elements *el, const double *x, int k, int64_t *e, double *d)
{
    int n = 0;
    for (int64_t f = 0; f < el->nelements; f++) {
        double v = md_dist(el, f, x);
        if (!(v < INFINITY))
            continue;
        int i = n < k ? n++ : k;
        if (i == k && !(v < d[k - 1]))
            continue;
        if (i == k)
            i = k - 1;
        while (i > 0 && d[i - 1] > v) {
            d[i] = d[i - 1];
            e[i] = e[i - 1];
            i--;
        }
        d[i] = v;
        e[i] = f;
    }
    return n;
}

static const md_leaf *leaf_at(const md_leaves *lv, const double *x)
{
    int32_t ijk[3];
    for (int k = 0; k < 3; k++)
        ijk[k] = (int32_t)floor((x[k] - lv->lat.origin[k]) / lv->lat.h);
    return find_leaf(lv, ijk);
}

/* Sample points x inside whose two nearest elements (smallest restricted distances) a, b
 * are within h / 4 of each other and allowed; x is moved onto their bisector (Newton), and
 * where a and b still touch there (within D + h / 64) every allowed pair of the touching
 * set T_{h/64} must be in P of the leaf holding the point: the sheet through it would
 * otherwise be missing.  How often the leaf of the unmoved point (up to h / 4 off the
 * bisector) holds (a, b) is printed, not asserted: the sheet may pass in the next leaf. */
static void check_complete(const solid *S, const md_elements *el, const md_leaves *lv, int full,
                           int nseed)
{
    const double h = lv->lat.h;
    int64_t *T = malloc((size_t)el->nelements * sizeof *T);
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < S->m.nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], S->m.xyz[3 * i + k]);
            hi[k] = fmax(hi[k], S->m.xyz[3 * i + k]);
        }
    long near = 0, near_held = 0, tested = 0, pairs = 0, missing = 0, multi = 0;
    for (int s = 0; s < nseed; s++) {
        double x[3];
        for (int k = 0; k < 3; k++)
            x[k] = rng_uniform(lo[k], hi[k]);
        if (!S->inside(x))
            continue;
        int64_t a, b;
        if (!two_nearest(el, x, &a, &b))
            continue;
        /* Every other seed: pull x onto that bisector, then jitter it by up to h / 8. */
        if (s & 1) {
            onto_bisector(el, a, b, x);
            for (int k = 0; k < 3; k++)
                x[k] += rng_uniform(-h / 8, h / 8);
            if (!S->inside(x) || !two_nearest(el, x, &a, &b))
                continue;
        }
        if (fabs(md_dist(el, a, x) - md_dist(el, b, x)) > h / 4 || !allowed(el, a, b, full))
            continue;
        near++;
        const md_leaf *lf = leaf_at(lv, x);
        near_held += lf && has_pair(lv, lf, a, b);
        /* Every third point: onto the seam (or junction) of its 3 (4) nearest elements
         * when they are within 8 h of each other, where the pruning is most delicate
         * (regions end there). */
        int64_t e4[4];
        double d4[4];
        int nk = s % 3 == 2 ? k_nearest(el, x, 4, e4, d4) : 0;
        if (nk >= 3 && d4[2] - d4[0] <= 8 * h) {
            int m = nk >= 4 && d4[3] - d4[0] <= 8 * h ? 4 : 3;
            if (!onto_equidistant(el, e4, m, x) || !S->inside(x))
                continue;
        } else if (!onto_bisector(el, a, b, x) || !S->inside(x)) {
            continue;
        }
        double D;
        int64_t nT = md_nearest_set_brute(el, x, SLACK(h), T, &D);
        if (nT < 2)
            continue; /* off the sheet (past a seam) */
        lf = leaf_at(lv, x);
        tested++;
        multi += nT >= 3;
        for (int64_t i = 0; i < nT; i++)
            for (int64_t j = i + 1; j < nT; j++) {
                if (!allowed(el, T[i], T[j], full))
                    continue;
                pairs++;
                if (!(lf && has_pair(lv, lf, T[i], T[j]))) {
                    missing++;
                    if (missing < 10)
                        fprintf(stderr, "  %s %s: pair (%lld,%lld) missing at (%.17g,%.17g,%.17g)%s\n",
                                S->name, full ? "full" : "major", (long long)T[i],
                                (long long)T[j], x[0], x[1], x[2], lf ? "" : " (no leaf)");
                }
            }
    }
    CHECK_EQ_INT(missing, 0);
    /* The sampling reaches the sheets (and their seams) at all. */
    if (full || S->major_area > 0)
        CHECK(tested > nseed / 200);
    printf("  (a) %-9s %-5s: %ld medial points (%ld on a seam), %ld allowed pairs, %ld missing; "
           "%ld points within h/4, whose own leaf held the pair for %ld\n",
           S->name, full ? "full" : "major", tested, multi, pairs, missing, near, near_held);
    free(T);
}

/* The face with outward normal (nx, ny, nz) (axis-aligned solids: exact), or -1. */
static int64_t face_with(const md_elements *el, double nx, double ny, double nz)
{
    for (int64_t f = 0; f < el->nfaces; f++) {
        const double *p = el->face_plane + 4 * f;
        if (p[0] == nx && p[1] == ny && p[2] == nz)
            return f;
    }
    return -1;
}

/* The leaf at x holds the pairs of opposite faces whose axes are set in axes (bit k: the
 * faces with normals -e_k and +e_k), and no other pair, and nT >= 2 x their number. */
static void check_opposite_pairs(const md_elements *el, const md_leaves *lv, const double *x,
                                 int axes)
{
    const md_leaf *lf = leaf_at(lv, x);
    CHECK(lf != NULL);
    if (!lf)
        return;
    int n = 0;
    for (int k = 0; k < 3; k++) {
        if (!(axes >> k & 1))
            continue;
        double nv[3] = {0, 0, 0};
        nv[k] = -1;
        int64_t a = face_with(el, nv[0], nv[1], nv[2]);
        nv[k] = 1;
        int64_t b = face_with(el, nv[0], nv[1], nv[2]);
        CHECK(a >= 0 && b >= 0 && has_pair(lv, lf, a < b ? a : b, a < b ? b : a));
        n++;
    }
    CHECK_EQ_INT(lf->nP, n);
    CHECK(lf->nT >= 2 * n);
}

/* ---- (b) the leaves' contents --------------------------------------------------------------- */

static void check_leaves(const solid *S, const md_elements *el, const md_leaves *lv, int full)
{
    const double h = lv->lat.h, rho = h * (0.5 * sqrt(3.0));
    int64_t *T = malloc((size_t)el->nelements * sizeof *T);
    long bad_place = 0, bad_C = 0, bad_P = 0, bad_T = 0, junction = 0, checked = 0;
    /* Sorted by (i, j, k), without repeats. */
    for (int64_t i = 1; i < lv->nleaves; i++) {
        const int32_t *a = lv->leaf[i - 1].ijk, *b = lv->leaf[i].ijk;
        CHECK(a[0] < b[0] || (a[0] == b[0] && (a[1] < b[1] || (a[1] == b[1] && a[2] < b[2]))));
    }
    /* The brute-force checks on a sample of about 4e6 / |elements| leaves (and every
     * junction leaf). */
    int64_t stride = lv->nleaves / (4000000 / (el->nelements + 1) + 1) + 1;
    for (int64_t i = 0; i < lv->nleaves; i++) {
        const md_leaf *lf = &lv->leaf[i];
        junction += lf->nT >= 4;
        if (i % stride && lf->nT < 4)
            continue;
        checked++;
        double c[3], u = INFINITY;
        leaf_centre(lv, lf, c);
        for (int64_t f = 0; f < el->nfaces; f++)
            u = fmin(u, md_dist_closed(el, f, c));
        int in = S->inside(c);
        bad_place += !(in || u <= rho * (1 + 1e-12));
        /* C: ascending, and holds every closure within u + 2 rho. */
        const int64_t *C = lv->C + lf->C_off;
        for (int32_t q = 1; q < lf->nC; q++)
            bad_C += C[q - 1] >= C[q];
        for (int64_t e = 0; e < el->nelements; e++)
            if (md_dist_closed(el, e, c) <= u + 2 * rho && !in_list(C, lf->nC, e))
                bad_C++;
        /* P: non-empty, ascending allowed pairs of C. */
        bad_P += lf->nP < 1;
        for (int32_t p = 0; p < lf->nP; p++) {
            int64_t a = lv->P[lf->P_off + 2 * p], b = lv->P[lf->P_off + 2 * p + 1];
            bad_P += !(a < b) || !allowed(el, a, b, full) || !in_list(C, lf->nC, a) ||
                     !in_list(C, lf->nC, b);
        }
        /* nT against the brute force (inside, where D is the restricted minimum). */
        if (in) {
            double D;
            int64_t nT = md_nearest_set_brute(el, c, 2 * rho, T, &D);
            bad_T += nT != lf->nT;
        }
    }
    CHECK_EQ_INT(bad_place, 0);
    CHECK_EQ_INT(bad_C, 0);
    CHECK_EQ_INT(bad_P, 0);
    CHECK_EQ_INT(bad_T, 0);
    CHECK(lv->nleaves > 0);
    printf("  (b) %-9s %-5s: %ld of %lld leaves checked, %ld with nT >= 4\n", S->name,
           full ? "full" : "major", checked, (long long)lv->nleaves, junction);
    free(T);
}

/* ---- (c) identical outputs ------------------------------------------------------------------- */

static int same_leaves(const md_leaves *a, const md_leaves *b)
{
    if (memcmp(&a->lat, &b->lat, sizeof a->lat) || a->nleaves != b->nleaves ||
        a->cells_visited != b->cells_visited)
        return 0;
    if (memcmp(a->leaf, b->leaf, (size_t)a->nleaves * sizeof *a->leaf))
        return 0;
    int64_t nC = 0, nP = 0;
    if (a->nleaves) {
        const md_leaf *l = &a->leaf[a->nleaves - 1];
        nC = l->C_off + l->nC;
        nP = l->P_off + 2 * l->nP;
    }
    return !memcmp(a->C, b->C, (size_t)nC * sizeof *a->C) &&
           !memcmp(a->P, b->P, (size_t)nP * sizeof *a->P);
}

/* The same solid with triangles in random order, corners rotated, vertices renumbered. */
static void shuffled(const tmesh *in, tmesh *out)
{
    int64_t perm[1024], tp[2048];
    for (int64_t i = 0; i < in->nv; i++)
        perm[i] = i;
    for (int64_t i = in->nv - 1; i > 0; i--) {
        int64_t j = rng_int(0, i), t = perm[i];
        perm[i] = perm[j];
        perm[j] = t;
    }
    for (int64_t i = 0; i < in->nt; i++)
        tp[i] = i;
    for (int64_t i = in->nt - 1; i > 0; i--) {
        int64_t j = rng_int(0, i), t = tp[i];
        tp[i] = tp[j];
        tp[j] = t;
    }
    memset(out, 0, sizeof *out);
    out->nv = in->nv;
    out->nt = in->nt;
    for (int64_t i = 0; i < in->nv; i++)
        memcpy(out->xyz + 3 * perm[i], in->xyz + 3 * i, 3 * sizeof(double));
    for (int64_t i = 0; i < in->nt; i++) {
        int r = (int)rng_int(0, 2);
        for (int k = 0; k < 3; k++)
            out->tri[3 * i + k] = perm[in->tri[3 * tp[i] + (k + r) % 3]];
    }
}

static void check_identical(const solid *S, const md_elements *el, const md_bvh *bvh,
                            const md_leaves *ref, double tol, int full)
{
    static const int threads[2] = {2, 7};
    for (int t = 0; t < 2; t++) {
        md_leaves lv;
        CHECK_EQ_INT(md_octree_build(el, bvh, tol, full, threads[t], &lv), MFG_OK);
        CHECK(same_leaves(ref, &lv));
        md_leaves_free(&lv);
    }
    /* Without the BVH: the sign from a winding number, the top candidates from all. */
    if (bvh) {
        md_leaves lv;
        CHECK_EQ_INT(md_octree_build(el, NULL, tol, full, 2, &lv), MFG_OK);
        CHECK(same_leaves(ref, &lv));
        md_leaves_free(&lv);
    }
    tmesh sh;
    shuffled(&S->m, &sh);
    md_elements el2;
    CHECK_EQ_INT(md_elements_build(sh.xyz, sh.nv, sh.tri, sh.nt, tol, &el2), MFG_OK);
    md_bvh *bvh2 = NULL;
    if (bvh)
        CHECK_EQ_INT(md_bvh_build(&el2, &bvh2), MFG_OK);
    md_leaves lv;
    CHECK_EQ_INT(md_octree_build(&el2, bvh2, tol, full, 3, &lv), MFG_OK);
    CHECK(same_leaves(ref, &lv));
    md_leaves_free(&lv);
    md_bvh_free(bvh2);
    md_elements_free(&el2);
    printf("  (c) %-9s %-5s: identical for 1/2/7 threads, %sshuffled triangles\n", S->name,
           full ? "full" : "major", bvh ? "no BVH, " : "");
}

/* ---- driver -------------------------------------------------------------------------------- */

/* CPU time of the process (all threads): the machine may be shared, wall time is not a
 * measure of the work. */
static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static double wall(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---- cost: a thin-walled cup of revolution (curved wall, 64 segments) ------------------- */

static int cost_mesh(const char *name, const double *xyz, int64_t nv, const int64_t *tr,
                     int64_t nt);

/* A mesh from a raw file: int64 nv, nt, then nv x 3 doubles and nt x 3 int64 (native). */
static int cost_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    int64_t n[2] = {0, 0};
    if (!f || fread(n, sizeof n[0], 2, f) != 2 || n[0] <= 0 || n[1] <= 0) {
        fprintf(stderr, "%s: cannot read\n", path);
        if (f)
            fclose(f);
        return 1;
    }
    double *xyz = malloc((size_t)n[0] * 3 * sizeof *xyz);
    int64_t *tr = malloc((size_t)n[1] * 3 * sizeof *tr);
    int ok = xyz && tr && fread(xyz, sizeof *xyz, (size_t)(3 * n[0]), f) == (size_t)(3 * n[0]) &&
             fread(tr, sizeof *tr, (size_t)(3 * n[1]), f) == (size_t)(3 * n[1]);
    fclose(f);
    int rc = ok ? cost_mesh(path, xyz, n[0], tr, n[1]) : 1;
    free(xyz);
    free(tr);
    return rc;
}

static int cost(void)
{
    enum { NSEG = 64, NW = 20 };
    /* Profile (r, z), from the axis at the bottom round to the axis inside: outer wall
     * r = 40 + 5 sin(pi z / 100), wall 3, bottom 3. */
    double pr[2 * NW + 8][2];
    int np = 0;
    pr[np][0] = 0, pr[np++][1] = 0;
    for (int i = 0; i <= NW; i++) {
        double z = 100.0 * i / NW;
        pr[np][0] = 40 + 5 * sin(M_PI * z / 100), pr[np++][1] = z;
    }
    for (int i = NW; i >= 0; i--) {
        double z = 3 + 97.0 * i / NW;
        pr[np][0] = 37 + 5 * sin(M_PI * z / 100), pr[np++][1] = z;
    }
    pr[np][0] = 0, pr[np++][1] = 3;
    int64_t nv = 2 + (int64_t)(np - 2) * NSEG, nt = 2 * (int64_t)(np - 1) * NSEG;
    double *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int64_t *tr = malloc((size_t)nt * 3 * sizeof *tr);
    revolve(pr, np, NSEG, xyz, &nv, tr, &nt);
    int rc = cost_mesh("cup", xyz, nv, tr, nt);
    free(xyz);
    free(tr);
    return rc;
}

static int cost_mesh(const char *name, const double *xyz, int64_t nv, const int64_t *tr,
                     int64_t nt)
{
    md_elements el;
    /* 0.5 % of the bounding-box diagonal. */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], xyz[3 * i + k]);
            hi[k] = fmax(hi[k], xyz[3 * i + k]);
        }
    double tol = 0.005 * sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                              (hi[2] - lo[2]) * (hi[2] - lo[2]));
    mfg_status st = md_elements_build(xyz, nv, tr, nt, tol, &el);
    if (st != MFG_OK) {
        fprintf(stderr, "%s: %s\n", name, mfg_last_error());
        CHECK_EQ_INT(st, MFG_OK);
        return mfg_test_report("medial_voxels cost");
    }
    printf("%s: %lld triangles, %lld faces, %lld edges, %lld vertices, L %.4g, tol %.4g\n",
           name, (long long)nt, (long long)el.nfaces, (long long)el.nedges, (long long)el.nverts,
           el.diag, tol);
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    /* MFG_COST_QUICK: only major, 1 thread, with the BVH (for profiling). */
    int quick = getenv("MFG_COST_QUICK") != NULL;
    for (int full = 0; full < 2 - quick; full++)
        for (int th = 1; th <= 2 - quick; th++)
            for (int b = quick; b < 2; b++) {
                md_leaves lv;
                double t0 = now(), w0 = wall();
                CHECK_EQ_INT(md_octree_build(&el, b ? bvh : NULL, tol, full, th, &lv), MFG_OK);
                double t1 = now(), w1 = wall();
                int64_t nC = 0, nP = 0;
                for (int64_t i = 0; i < lv.nleaves; i++)
                    nC += lv.leaf[i].nC, nP += lv.leaf[i].nP;
                printf("  %s, %d thread(s), %s: h %.4g, %lld cells visited, %lld leaves, "
                       "mean |C| %.2f, |P| %.2f, cpu %.3f s, wall %.3f s\n",
                       full ? "full" : "major", th, b ? "BVH" : "no BVH", lv.lat.h,
                       (long long)lv.cells_visited, (long long)lv.nleaves,
                       (double)nC / (lv.nleaves ? lv.nleaves : 1),
                       (double)nP / (lv.nleaves ? lv.nleaves : 1), t1 - t0, w1 - w0);
                md_leaves_free(&lv);
            }
    md_bvh_free(bvh);
    md_elements_free(&el);
    return mfg_test_report("medial_voxels cost");
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : "";
    if (!strcmp(only, "cost"))
        return argc > 2 ? cost_file(argv[2]) : cost();
    int all = !*only;
    static solid S[6];
    make_solids(S);
    for (int s = 0; s < 6; s++) {
        md_elements el;
        double tol0 = 0;
        {
            /* The tolerance is 0.5 % of L: build once to learn L. */
            CHECK_EQ_INT(md_elements_build(S[s].m.xyz, S[s].m.nv, S[s].m.tri, S[s].m.nt, 1.0, &el),
                         MFG_OK);
            tol0 = tol_of(&el, 0.005);
            md_elements_free(&el);
        }
        CHECK_EQ_INT(md_elements_build(S[s].m.xyz, S[s].m.nv, S[s].m.tri, S[s].m.nt, tol0, &el),
                     MFG_OK);
        md_bvh *bvh = NULL;
        CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
        for (int full = 0; full < 2; full++) {
            md_leaves lv;
            double t0 = now();
            CHECK_EQ_INT(md_octree_build(&el, bvh, tol0, full, 1, &lv), MFG_OK);
            double t1 = now();
            int64_t npairs = 0, nC = 0;
            for (int64_t i = 0; i < lv.nleaves; i++) {
                npairs += lv.leaf[i].nP;
                nC += lv.leaf[i].nC;
            }
            printf("%s %s, tol %.4g (0.5%% L), h %.4g: %lld cells visited, %lld leaves, "
                   "mean |C| %.2f, mean |P| %.2f, %.3f s (1 thread, cpu)\n",
                   S[s].name, full ? "full" : "major", tol0, lv.lat.h,
                   (long long)lv.cells_visited, (long long)lv.nleaves,
                   lv.nleaves ? (double)nC / lv.nleaves : 0.0,
                   lv.nleaves ? (double)npairs / lv.nleaves : 0.0, t1 - t0);
            if (all || !strcmp(only, "a"))
                check_complete(&S[s], &el, &lv, full, 6000);
            if (all || !strcmp(only, "b"))
                check_leaves(&S[s], &el, &lv, full);
            if ((all || !strcmp(only, "b")) && !full) {
                /* Analytic: the cube's centre leaf holds its 3 pairs of opposite faces (the
                 * junction), a mid-sheet leaf of the cuboid only {z0, z1}. */
                static const double cube_c[3] = {20, 20, 20}, cuboid_m[3] = {50, 30, 10};
                if (s == 2)
                    check_opposite_pairs(&el, &lv, cube_c, 7);
                if (s == 0)
                    check_opposite_pairs(&el, &lv, cuboid_m, 4);
            }
            if (all || !strcmp(only, "c"))
                check_identical(&S[s], &el, bvh, &lv, tol0, full);
            md_leaves_free(&lv);
        }
        /* Coarse tolerances: leaves at depth 1 .. 4, above the inheritance depth 3 and the
         * work-unit depth (clamped to the leaf depth). */
        if (all || !strcmp(only, "a") || !strcmp(only, "b") || !strcmp(only, "c"))
            for (int i = 0; i < 3; i++) {
                static const double fr[3] = {0.6, 0.3, 0.05};
                md_elements e2;
                double tol = tol_of(&el, fr[i]);
                CHECK_EQ_INT(md_elements_build(S[s].m.xyz, S[s].m.nv, S[s].m.tri, S[s].m.nt,
                                               tol, &e2), MFG_OK);
                md_bvh *b2 = NULL;
                CHECK_EQ_INT(md_bvh_build(&e2, &b2), MFG_OK);
                for (int full = 0; full < 2; full++) {
                    md_leaves lv;
                    CHECK_EQ_INT(md_octree_build(&e2, b2, tol, full, 1, &lv), MFG_OK);
                    printf("%s %s, tol %.3g L: depth %d, %lld leaves\n", S[s].name,
                           full ? "full" : "major", fr[i], lv.lat.depth, (long long)lv.nleaves);
                    check_complete(&S[s], &e2, &lv, full, 1000);
                    check_leaves(&S[s], &e2, &lv, full);
                    check_identical(&S[s], &e2, b2, &lv, tol, full);
                    md_leaves_free(&lv);
                }
                md_bvh_free(b2);
                md_elements_free(&e2);
            }
        if ((all || !strcmp(only, "d")) && S[s].major_area > 0) {
            /* (d) leaves ~ A / h^2: each halving of the tolerance halves h exactly. */
            for (int i = 0; i < 3; i++) {
                double frac = 0.01 / (1 << i), tol = tol_of(&el, frac);
                md_elements e2;
                CHECK_EQ_INT(md_elements_build(S[s].m.xyz, S[s].m.nv, S[s].m.tri, S[s].m.nt,
                                               tol, &e2), MFG_OK);
                md_leaves lv;
                double t0 = now();
                CHECK_EQ_INT(md_octree_build(&e2, NULL, tol, 0, 1, &lv), MFG_OK);
                double t1 = now();
                double dens = lv.nleaves * lv.lat.h * lv.lat.h / S[s].major_area;
                printf("  (d) %-9s major tol %.3g%% L: h %.4g, %lld leaves, %lld cells, "
                       "leaves h^2 / A = %.2f, cpu %.3f s\n",
                       S[s].name, 100 * frac, lv.lat.h, (long long)lv.nleaves,
                       (long long)lv.cells_visited, dens, t1 - t0);
                /* About one layer of leaves along a sheet (two only where it runs
                 * within h / 128 of a lattice plane: the slack of the pair test). */
                CHECK(dens > 0.8 && dens < (S[s].max_density > 0 ? S[s].max_density : 1.5));
                md_leaves_free(&lv);
                md_elements_free(&e2);
            }
        }
        md_bvh_free(bvh);
        md_elements_free(&el);
    }
    return mfg_test_report("medial_voxels");
}
