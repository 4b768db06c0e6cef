/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_arrange_union.c - the arrangement's boundary of {w >= 1} (arrange/arrange.h) on
 * unions of boxes, against references that share no code with it:
 *  - axis-aligned boxes on a coarse dyadic grid (touching, overlapping, coplanar, nested,
 *    the same box twice, a box and its reverse): the union's volume by coordinate
 *    compression, exact in doubles;
 *  - turned boxes in general position: membership of sampled points (in any box, by the
 *    box's own inequalities) against the result's winding number, away from the surface;
 * and every result, rounded and repaired as the sweep does it (mesh/mesh_repair.h), closed,
 * outward and free of self-intersections (the exact check of
 * libcore/tests/sweep/sweep_checks.h). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "arrange/arrange.h"
#include "mesh/mesh_repair.h"
#include "mfg_test.h"
#include "sweep/sweep_checks.h"

#define MAXBOX 8

typedef struct boxset {
    int n;
    double lo[MAXBOX][3], hi[MAXBOX][3];
    double rot[MAXBOX][9]; /* world = rot * local (local box = [lo, hi]) */
    int reversed[MAXBOX];  /* the box's triangles inward (its winding -1 inside) */
} boxset;

static const int BOX_TRI[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};

static double snap50(double x)
{
    return ldexp(nearbyint(ldexp(x, ARR_GRID_LOG2)), -ARR_GRID_LOG2);
}

/* The soup of the boxes: 8 vertices and 12 triangles each. */
static void soup_of(const boxset *B, double *xyz, int64_t *tri)
{
    for (int b = 0; b < B->n; b++) {
        for (int i = 0; i < 8; i++) {
            double l[3] = {(i & 1) ? B->hi[b][0] : B->lo[b][0], (i & 2) ? B->hi[b][1] : B->lo[b][1],
                           (i & 4) ? B->hi[b][2] : B->lo[b][2]};
            for (int k = 0; k < 3; k++) {
                const double *R = B->rot[b] + 3 * k;
                xyz[3 * (8 * b + i) + k] = snap50(R[0] * l[0] + R[1] * l[1] + R[2] * l[2]);
            }
        }
        for (int f = 0; f < 12; f++)
            for (int k = 0; k < 3; k++)
                tri[3 * (12 * b + f) + k] =
                    8 * b + BOX_TRI[f][B->reversed[b] ? 2 - k : k];
    }
}

/* Runs the arrangement; the result as a mesh (rounded points, only those used). */
static mfg_status run(const boxset *B, mfg_mesh *out)
{
    double xyz[3 * 8 * MAXBOX];
    int64_t tri[3 * 12 * MAXBOX];
    soup_of(B, xyz, tri);
    mfg_prog prog;
    mfg_prog_init(&prog, NULL, "test");
    static const arr_stages S = {{"a", "b", "c"}, {0, 0.3, 0.6, 1}, 0};
    arr_table T;
    arr_face *F = NULL;
    int64_t nf = 0;
    mfg_status st = arr_union_boundary(xyz, 8 * B->n, tri, 12 * B->n, &prog, &S, &T, &F, &nf,
                                       NULL, NULL);
    memset(out, 0, sizeof *out);
    if (st != MFG_OK)
        return st;
    int64_t *map = malloc((size_t)(T.npts + 1) * sizeof *map);
    out->vertices = malloc((size_t)(9 * nf + 3) * sizeof *out->vertices);
    out->triangles = malloc((size_t)(3 * nf + 3) * sizeof *out->triangles);
    for (int64_t i = 0; i < T.npts; i++)
        map[i] = -1;
    arr_points P = arr_view(&T);
    for (int64_t f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++) {
            int64_t p = F[f].v[k];
            if (map[p] < 0) {
                map[p] = out->nvertices;
                arr_coords(&P, p, out->vertices + 3 * out->nvertices++);
            }
            out->triangles[3 * f + k] = map[p];
        }
    out->ntriangles = nf;
    /* rounded: repaired as the sweep does (welds and needles below 2^-40) */
    mfg_rmesh rm = {out->vertices, out->nvertices, 3 * nf + 1, out->triangles, nf, nf + 1, NULL};
    if (!mfg_mesh_repair(&rm, 0x1p-40))
        st = MFG_ERR_NOMEM;
    out->vertices = rm.x;
    out->nvertices = rm.nv;
    out->triangles = rm.t;
    out->ntriangles = rm.nt;
    free(map);
    free(F);
    arr_table_free(&T);
    return st;
}

static void free_mesh(mfg_mesh *m)
{
    free(m->vertices);
    free(m->triangles);
}

/* Union volume of axis-aligned boxes by coordinate compression (dyadic: exact). */
static double union_volume(const boxset *B)
{
    double cs[3][2 * MAXBOX];
    int nc[3];
    for (int k = 0; k < 3; k++) {
        nc[k] = 0;
        for (int b = 0; b < B->n; b++) {
            cs[k][nc[k]++] = B->lo[b][k];
            cs[k][nc[k]++] = B->hi[b][k];
        }
        for (int i = 1; i < nc[k]; i++) /* insertion sort */
            for (int j = i; j > 0 && cs[k][j - 1] > cs[k][j]; j--) {
                double t = cs[k][j];
                cs[k][j] = cs[k][j - 1];
                cs[k][j - 1] = t;
            }
    }
    double vol = 0;
    for (int i = 0; i + 1 < nc[0]; i++)
        for (int j = 0; j + 1 < nc[1]; j++)
            for (int l = 0; l + 1 < nc[2]; l++) {
                double c[3] = {0.5 * (cs[0][i] + cs[0][i + 1]), 0.5 * (cs[1][j] + cs[1][j + 1]),
                               0.5 * (cs[2][l] + cs[2][l + 1])};
                int w = 0;
                for (int b = 0; b < B->n; b++) {
                    int in = 1;
                    for (int k = 0; k < 3; k++)
                        in &= c[k] > B->lo[b][k] && c[k] < B->hi[b][k];
                    w += in ? (B->reversed[b] ? -1 : 1) : 0;
                }
                if (w >= 1)
                    vol += (cs[0][i + 1] - cs[0][i]) * (cs[1][j + 1] - cs[1][j]) * (cs[2][l + 1] - cs[2][l]);
            }
    return vol;
}

static void identity(double *R)
{
    static const double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    memcpy(R, I, sizeof I);
}

/* The checks every result passes: closed and outward (or empty), no self-intersection. */
static void check_mesh(const char *name, const mfg_mesh *m)
{
    if (m->ntriangles == 0)
        return;
    mfg_mesh_report rep;
    mfg_status cs = mfg_mesh_check_closed(m->vertices, m->nvertices, m->triangles, m->ntriangles, &rep);
    if (cs != MFG_OK)
        fprintf(stderr, "%s: not closed: %s\n", name, mfg_last_error());
    CHECK_EQ_INT(cs, MFG_OK);
    CHECK_EQ_INT(self_intersections(m, name), 0);
}

static void test_grid_boxes(void)
{
    int fails = 0;
    for (int trial = 0; trial < 300; trial++) {
        boxset B;
        memset(&B, 0, sizeof B);
        B.n = (int)rng_int(1, 5);
        for (int b = 0; b < B.n; b++) {
            identity(B.rot[b]);
            for (int k = 0; k < 3; k++) {
                long a = rng_int(0, 8), c = rng_int(0, 8);
                if (a == c)
                    c = a + 1;
                B.lo[b][k] = (a < c ? a : c) / 8.0;
                B.hi[b][k] = (a < c ? c : a) / 8.0;
            }
            /* sometimes the same box twice, or a box with its reverse inside a bigger one */
            if (b > 0 && rng_int(0, 9) == 0) {
                memcpy(B.lo[b], B.lo[b - 1], sizeof B.lo[b]);
                memcpy(B.hi[b], B.hi[b - 1], sizeof B.hi[b]);
            }
        }
        if (B.n >= 2 && rng_int(0, 7) == 0) {
            /* the last box reversed, strictly inside the first: a cavity */
            int l = B.n - 1;
            for (int k = 0; k < 3; k++) {
                B.lo[0][k] = 0;
                B.hi[0][k] = 1;
                B.lo[l][k] = 0.25;
                B.hi[l][k] = 0.5 + 0.125 * (double)rng_int(0, 2);
            }
            B.reversed[l] = 1;
            for (int b = 1; b < l; b++) /* the others outside the cavity's reach */
                for (int k = 0; k < 3; k++) {
                    B.lo[b][k] += 1.125;
                    B.hi[b][k] += 1.125;
                }
        }
        mfg_mesh m;
        mfg_status st = run(&B, &m);
        CHECK_EQ_INT(st, MFG_OK);
        if (st != MFG_OK) {
            fprintf(stderr, "grid trial %d: %s\n", trial, mfg_last_error());
            continue;
        }
        double vol, area, bb[6];
        mesh_measure(m.vertices, m.nvertices, m.triangles, m.ntriangles, &vol, &area, bb);
        double want = union_volume(&B);
        if (fabs(vol - want) > 1e-10 && fails++ < 5)
            fprintf(stderr, "grid trial %d: volume %.17g, union %.17g\n", trial, vol, want);
        CHECK(fabs(vol - want) <= 1e-10);
        char name[64];
        snprintf(name, sizeof name, "grid trial %d", trial);
        check_mesh(name, &m);
        free_mesh(&m);
    }
}

/* A random rotation matrix (from a random unit quaternion). */
static void random_rotation(double *R)
{
    double q[4], n = 0;
    for (int i = 0; i < 4; i++) {
        q[i] = rng_uniform(-1, 1);
        n += q[i] * q[i];
    }
    n = sqrt(n);
    for (int i = 0; i < 4; i++)
        q[i] /= n;
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                   2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)};
    memcpy(R, M, sizeof M);
}

/* In box b of the set (by its own inequalities, in its local frame), with margin. */
static int in_box(const boxset *B, int b, const double *p, double margin)
{
    const double *R = B->rot[b];
    for (int k = 0; k < 3; k++) {
        double l = R[k] * p[0] + R[3 + k] * p[1] + R[6 + k] * p[2]; /* R^T p */
        if (l < B->lo[b][k] + margin || l > B->hi[b][k] - margin)
            return 0;
    }
    return 1;
}

static void test_turned_boxes(void)
{
    int bad = 0;
    for (int trial = 0; trial < 100; trial++) {
        boxset B;
        memset(&B, 0, sizeof B);
        B.n = (int)rng_int(2, 5);
        for (int b = 0; b < B.n; b++) {
            random_rotation(B.rot[b]);
            for (int k = 0; k < 3; k++) {
                double c = rng_uniform(-0.4, 0.4), h = rng_uniform(0.1, 0.5);
                B.lo[b][k] = c - h;
                B.hi[b][k] = c + h;
            }
        }
        mfg_mesh m;
        mfg_status st = run(&B, &m);
        CHECK_EQ_INT(st, MFG_OK);
        if (st != MFG_OK) {
            fprintf(stderr, "turned trial %d: %s\n", trial, mfg_last_error());
            continue;
        }
        char name[64];
        snprintf(name, sizeof name, "turned trial %d", trial);
        check_mesh(name, &m);
        /* membership: a point well inside a box is inside the result, a point well
         * outside every box is outside (winding of the result's triangles) */
        for (int s = 0; s < 200; s++) {
            double p[3] = {rng_uniform(-1.3, 1.3), rng_uniform(-1.3, 1.3), rng_uniform(-1.3, 1.3)};
            int in = 0, out = 1;
            for (int b = 0; b < B.n; b++) {
                in |= in_box(&B, b, p, 1e-6);
                out &= !in_box(&B, b, p, -1e-6);
            }
            if (!in && !out)
                continue;
            double w = winding(&m, p);
            int ok = in ? w > 0.5 : w < 0.5;
            if (!ok && bad++ < 5)
                fprintf(stderr, "turned trial %d: point (%g %g %g) %s the boxes, winding %g\n",
                        trial, p[0], p[1], p[2], in ? "inside" : "outside", w);
            CHECK(ok);
        }
        free_mesh(&m);
    }
}

int main(void)
{
    test_grid_boxes();
    test_turned_boxes();
    return mfg_test_report("test_arrange_union");
}
