/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* fuzz_sweep.c - libFuzzer target for the properties of mfg_rotational_sweep's results
 * (issue 20): not only "no crash" (fuzz_api.c's sweep section covers the argument and
 * mesh checks), but what a result must be, on small generated solids:
 *
 *  (a) closed:      mfg_mesh_check_closed accepts the result (closed, outward, 2-manifold);
 *  (b) contains:    the input's vertices, edge midpoints and face centroids turned by
 *                   t = theta k / 24, k = 0 .. 24, lie inside the result (winding number)
 *                   or within CONTAIN_SLACK * tol of its surface;
 *  (c) covariant:   the same mesh, axis point and tolerance scaled by 2^k (k from the
 *                   input, |k| <= 120) gives the volume * 8^k to VOLUME_REL, and (when
 *                   SCALE_EXACT) the very same vertices times 2^k;
 *  (d) no refusal:  a closed solid is never refused with MFG_ERR_INTERNAL unless the
 *                   allowance below says so.
 *
 * The allowances below were the first design's known gaps (docs/known-gaps.md); the
 * second design passes at the strict values the issue asked for: no distance outside
 * beyond rounding, exact volume and vertices after scaling by 2^k, no MFG_ERR_INTERNAL.
 *
 * Build and run: tests/fuzz/run_fuzz.sh (with fuzz_pointclass and fuzz_api).
 */

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_reader.h"
#include "mfgeom.h"
#include "sweep_checks.h" /* libcore/tests/sweep: the checks test_rotsweep.c uses */

/* ---- allowances (the ratchet: may only get stricter) ---------------------- */
/* (b) distance outside the result, in tolerances, of a turned input point: rounding only
 * (the result's points are on a grid of 2^-50 of its coordinates; the tolerance here is
 * at least 1/8 of the part) */
#define CONTAIN_SLACK 1e-9
/* (c) relative volume difference after scaling by 2^k */
#define VOLUME_REL 0.0
/* (c) vertices bit-identical after scaling by 2^k */
#define SCALE_EXACT 1
/* (d) MFG_ERR_INTERNAL allowed: no (the first design refused some closed solids) */
#define ALLOW_INTERNAL 0

static void fail(const char *what, double value)
{
    fprintf(stderr, "fuzz_sweep: check failed: %s (%.17g; last error: \"%s\")\n", what, value,
            mfg_last_error());
    __builtin_trap();
}

#define CHECK(cond, what, value)   \
    do {                           \
        if (!(cond))               \
            fail(what, value);     \
    } while (0)

/* turned samples: each triangle's first vertex, first edge midpoint and centroid (so
 * every vertex and edge of a closed mesh is met) at t = theta k / NTURNS */
#define NTURNS 24
#define MAXV 16
#define MAXT 28

/* Box corners k = (x: bit 0, y: bit 1, z: bit 2); 12 triangles, outward. */
static const int64_t BOX[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
/* Octahedron: vertices +x, -x, +y, -y, +z, -z; 8 triangles, outward. */
static const int64_t OCTA[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};

/* multiples of 1/32 in [-4, 4): exact, and exactly scalable */
static double small(reader *r) { return (double)(int8_t)rd_u8(r) * (1.0 / 32); }

typedef struct solid {
    double xyz[3 * MAXV];
    int64_t tri[3 * MAXT];
    int64_t nv, nt;
} solid;

/* A small closed outward solid: a box, a box with its top corners moved, an octahedron
 * with a radius per vertex, or an n-gon prism (n = 3 .. 6). */
static void make_solid(reader *r, solid *s)
{
    memset(s, 0, sizeof *s);
    int kind = rd_u8(r) % 4;
    if (kind <= 1) {
        double lo[3], hi[3];
        for (int c = 0; c < 3; c++) {
            lo[c] = small(r);
            hi[c] = lo[c] + (double)(1 + rd_u8(r) % 64) * (1.0 / 32);
        }
        for (int k = 0; k < 8; k++)
            for (int c = 0; c < 3; c++)
                s->xyz[3 * k + c] = (k >> c) & 1 ? hi[c] : lo[c];
        if (kind == 1) { /* sheared: the top face moved as a whole in x and y (stays planar) */
            double dx = (hi[0] - lo[0]) * (double)((int)(rd_u8(r) % 9) - 4) * (1.0 / 16);
            double dy = (hi[1] - lo[1]) * (double)((int)(rd_u8(r) % 9) - 4) * (1.0 / 16);
            for (int k = 4; k < 8; k++) {
                s->xyz[3 * k] += dx;
                s->xyz[3 * k + 1] += dy;
            }
        }
        memcpy(s->tri, BOX, sizeof BOX);
        s->nv = 8;
        s->nt = 12;
    } else if (kind == 2) {
        double ctr[3] = {small(r), small(r), small(r)};
        for (int k = 0; k < 6; k++) {
            double rad = (double)(1 + rd_u8(r) % 64) * (1.0 / 32);
            for (int c = 0; c < 3; c++)
                s->xyz[3 * k + c] = ctr[c] + (c == k / 2 ? (k % 2 ? -rad : rad) : 0.0);
        }
        memcpy(s->tri, OCTA, sizeof OCTA);
        s->nv = 6;
        s->nt = 8;
    } else {
        int n = 3 + rd_u8(r) % 4;
        double cx = small(r), cy = small(r), z0 = small(r);
        double rad = (double)(4 + rd_u8(r) % 60) * (1.0 / 32), h = (double)(1 + rd_u8(r) % 64) * (1.0 / 32);
        for (int i = 0; i < n; i++) {
            double a = 2 * M_PI * i / n;
            double x = cx + rad * cos(a), y = cy + rad * sin(a);
            s->xyz[3 * i] = s->xyz[3 * (n + i)] = x;
            s->xyz[3 * i + 1] = s->xyz[3 * (n + i) + 1] = y;
            s->xyz[3 * i + 2] = z0;
            s->xyz[3 * (n + i) + 2] = z0 + h;
        }
        int64_t t = 0;
        for (int i = 0; i < n; i++) {
            int j = (i + 1) % n;
            int64_t q[6] = {i, j, n + j, i, n + j, n + i};
            memcpy(s->tri + 3 * t, q, sizeof q);
            t += 2;
        }
        for (int i = 1; i + 1 < n; i++) { /* bottom (outward: down), top (up) */
            int64_t q[6] = {0, i + 1, i, n, n + i, n + i + 1};
            memcpy(s->tri + 3 * t, q, sizeof q);
            t += 2;
        }
        s->nv = 2 * n;
        s->nt = t;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader rd = {data, size};
    solid s;
    make_solid(&rd, &s);
    mfg_mesh_report in_rep;
    if (mfg_mesh_check_closed(s.xyz, s.nv, s.tri, s.nt, &in_rep) != MFG_OK)
        return 0; /* a degenerate draw (zero size); fuzz_api covers refusals */

    /* the axis: through a random point, a vertex, or along an edge */
    double ap[3], ad[3];
    uint8_t mode = rd_u8(&rd);
    for (int c = 0; c < 3; c++) {
        ap[c] = small(&rd);
        ad[c] = (double)(int8_t)rd_u8(&rd);
    }
    if (mode & 1) {
        int64_t a = s.tri[0], b = s.tri[1];
        for (int c = 0; c < 3; c++) {
            ap[c] = s.xyz[3 * a + c];
            if (mode & 2)
                ad[c] = s.xyz[3 * b + c] - s.xyz[3 * a + c];
        }
    }
    if (ad[0] == 0 && ad[1] == 0 && ad[2] == 0)
        ad[2] = 1;
    uint8_t ab = rd_u8(&rd);
    double angle = ab >= 0xF8 ? (double[]){1e-6, 1e-3, 2 * M_PI, 2 * M_PI - 1e-9, M_PI, M_PI / 2, 1e-9, 0.5}[ab - 0xF8]
                              : (double)(ab + 1) * (2 * M_PI / 0xF8);
    double ext = 0;
    for (int64_t k = 0; k < s.nv; k++)
        for (int c = 0; c < 3; c++)
            ext = fmax(ext, fabs(s.xyz[3 * k + c] - ap[c]));
    /* 1/8 .. 1 of the extent about the axis point: milliseconds per call */
    double tol = ext * (double)(4 + rd_u8(&rd) % 29) * (1.0 / 32);
    int k2 = (int)(rd_u8(&rd) % 7) - 3; /* scale 2^(40 k2): -120 .. 120 */
    if (k2 == 0)
        k2 = 1;
    int shift = 40 * k2 + (k2 > 0 ? -39 : 39) * (rd_u8(&rd) & 1); /* also +-1 */

    mfg_mesh *m = NULL;
    mfg_sweep_stats st;
    mfg_status status = mfg_rotational_sweep(s.xyz, s.nv, s.tri, s.nt, ap, ad, angle, tol, &m, &st);
    if (status == MFG_ERR_INTERNAL) {
        CHECK(ALLOW_INTERNAL, "a closed solid refused with MFG_ERR_INTERNAL", 0);
        return 0;
    }
    CHECK(status == MFG_OK, "a closed solid refused", (double)status);

    /* (a) closed */
    mfg_mesh_report rep;
    CHECK(mfg_mesh_check_closed(m->vertices, m->nvertices, m->triangles, m->ntriangles, &rep) == MFG_OK,
          "the result is not a closed outward 2-manifold", 0);

    /* (b) contains the turned input */
    double u[3];
    unit3(ad, u);
    double worst = 0;
    for (int64_t t = 0; t < s.nt; t++) {
        const double *P[3] = {s.xyz + 3 * s.tri[3 * t], s.xyz + 3 * s.tri[3 * t + 1], s.xyz + 3 * s.tri[3 * t + 2]};
        double pts[3][3];
        for (int c = 0; c < 3; c++) {
            pts[0][c] = P[0][c];
            pts[1][c] = 0.5 * (P[0][c] + P[1][c]);
            pts[2][c] = (P[0][c] + P[1][c] + P[2][c]) / 3;
        }
        for (int i = 0; i < 3; i++)
            for (int k = 0; k <= NTURNS; k++) {
                double q[3];
                rotate(ap, u, angle * k / NTURNS, pts[i], q);
                if (winding(m, q) > 0.5)
                    continue;
                worst = fmax(worst, mesh_dist(m, q) / tol);
            }
    }
    CHECK(worst <= CONTAIN_SLACK + 1e-9, "a turned input point lies outside the result (in tolerances)", worst);

    /* (c) power-of-two scale covariance */
    solid t2 = s;
    double ap2[3];
    for (int64_t k = 0; k < 3 * s.nv; k++)
        t2.xyz[k] = ldexp(s.xyz[k], shift);
    for (int c = 0; c < 3; c++)
        ap2[c] = ldexp(ap[c], shift);
    mfg_mesh *m2 = NULL;
    mfg_sweep_stats st2;
    mfg_status status2 = mfg_rotational_sweep(t2.xyz, t2.nv, t2.tri, t2.nt, ap2, ad, angle, ldexp(tol, shift),
                                              &m2, &st2);
    if (status2 == MFG_ERR_INTERNAL) {
        CHECK(ALLOW_INTERNAL, "the scaled solid refused with MFG_ERR_INTERNAL", (double)shift);
    } else {
        CHECK(status2 == MFG_OK, "the scaled solid refused", (double)shift);
        double v2 = ldexp(st2.volume, -3 * shift);
        double rel = fabs(v2 - st.volume) / fabs(st.volume);
        CHECK(rel <= VOLUME_REL, "volume / 8^k differs after scaling by 2^k", rel);
        if (SCALE_EXACT) {
            CHECK(m2->nvertices == m->nvertices && m2->ntriangles == m->ntriangles,
                  "another mesh after scaling by 2^k", (double)shift);
            for (int64_t k = 0; k < 3 * m->nvertices; k++)
                CHECK(ldexp(m2->vertices[k], -shift) == m->vertices[k], "a vertex moved after scaling by 2^k",
                      (double)k);
            CHECK(memcmp(m2->triangles, m->triangles, (size_t)(3 * m->ntriangles) * sizeof *m->triangles) == 0,
                  "other triangles after scaling by 2^k", (double)shift);
        }
        mfg_mesh_free(m2);
    }
    mfg_mesh_free(m);
    return 0;
}
