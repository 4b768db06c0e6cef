/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* battery_inputs.c - the battery's inputs: growable meshes, the families of solids (boxes,
 * prisms, L-brackets, frames with a through-hole, tori, octahedra and sheared boxes, two
 * tessellated real parts), their placements, axes, angles and tolerances, all drawn from
 * one seed; and OFF files (the real parts in, failing inputs out). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "battery.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define TWO_PI (2.0 * M_PI)

/* ------------------------------------------------------------------------ */
/* Meshes                                                                   */
/* ------------------------------------------------------------------------ */

int64_t bt_add_vertex(bt_mesh *m, double x, double y, double z)
{
    if (m->nv == m->cap_v) {
        m->cap_v = m->cap_v ? 2 * m->cap_v : 64;
        m->xyz = realloc(m->xyz, (size_t)m->cap_v * 3 * sizeof *m->xyz);
        if (!m->xyz)
            abort(); /* a test input of a few thousand vertices: out of memory is fatal */
    }
    double *p = m->xyz + 3 * m->nv;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return m->nv++;
}

void bt_add_tri(bt_mesh *m, int64_t a, int64_t b, int64_t c)
{
    if (m->nt == m->cap_t) {
        m->cap_t = m->cap_t ? 2 * m->cap_t : 64;
        m->tri = realloc(m->tri, (size_t)m->cap_t * 3 * sizeof *m->tri);
        if (!m->tri)
            abort();
    }
    int64_t *t = m->tri + 3 * m->nt++;
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

void bt_mesh_free(bt_mesh *m)
{
    free(m->xyz);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

bt_mesh bt_mesh_copy(const bt_mesh *m)
{
    bt_mesh c = {0};
    bt_mesh_append(&c, m);
    return c;
}

void bt_mesh_append(bt_mesh *dst, const bt_mesh *src)
{
    int64_t base = dst->nv;
    for (int64_t i = 0; i < src->nv; i++)
        bt_add_vertex(dst, src->xyz[3 * i], src->xyz[3 * i + 1], src->xyz[3 * i + 2]);
    for (int64_t t = 0; t < src->nt; t++)
        bt_add_tri(dst, base + src->tri[3 * t], base + src->tri[3 * t + 1], base + src->tri[3 * t + 2]);
}

mfg_mesh bt_as_mfg(const bt_mesh *m)
{
    mfg_mesh r = {m->nv, m->nt, m->xyz, m->tri};
    return r;
}

double bt_diag(const double *xyz, int64_t nv)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < nv; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], xyz[3 * i + c]);
            hi[c] = fmax(hi[c], xyz[3 * i + c]);
        }
    return nv ? sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]))
              : 0;
}

void bt_problem_free(bt_problem *p)
{
    bt_mesh_free(&p->in);
}

/* ------------------------------------------------------------------------ */
/* Building blocks                                                          */
/* ------------------------------------------------------------------------ */

/* A planar region (nxy vertices, counter-clockwise triangles) extruded from z0 to z1 with
 * nz layers of side wall: the bottom cap reversed, the top cap as is, and on every
 * boundary edge (a side of one triangle whose reverse no triangle has; the region on its
 * left) a column of quads whose outward normal is on the edge's right. */
static void extrude(bt_mesh *m, const double *xy, int nxy, const int *tri, int ntri, double z0, double z1, int nz)
{
    int64_t *id = malloc((size_t)(nz + 1) * (size_t)nxy * sizeof *id);
    for (int l = 0; l <= nz; l++)
        for (int i = 0; i < nxy; i++)
            id[l * nxy + i] = -1;
    /* cap vertices at both ends; wall vertices in between come with the walls */
    for (int i = 0; i < nxy; i++) {
        id[i] = bt_add_vertex(m, xy[2 * i], xy[2 * i + 1], z0);
        id[nz * nxy + i] = bt_add_vertex(m, xy[2 * i], xy[2 * i + 1], z1);
    }
    for (int t = 0; t < ntri; t++) {
        const int *v = tri + 3 * t;
        bt_add_tri(m, id[v[0]], id[v[2]], id[v[1]]);
        bt_add_tri(m, id[nz * nxy + v[0]], id[nz * nxy + v[1]], id[nz * nxy + v[2]]);
    }
    for (int t = 0; t < ntri; t++)
        for (int k = 0; k < 3; k++) {
            int a = tri[3 * t + k], b = tri[3 * t + (k + 1) % 3], inner = 0;
            for (int s = 0; s < ntri && !inner; s++)
                for (int j = 0; j < 3; j++)
                    if (tri[3 * s + j] == b && tri[3 * s + (j + 1) % 3] == a)
                        inner = 1;
            if (inner)
                continue;
            for (int l = 0; l < nz; l++) {
                int64_t *ra = id + (size_t)l * nxy, *rb = id + (size_t)(l + 1) * nxy;
                for (int w = 0; w < 2; w++) {
                    int64_t *row = w ? rb : ra;
                    double z = z0 + (z1 - z0) * (l + w) / nz;
                    if (row[a] < 0)
                        row[a] = bt_add_vertex(m, xy[2 * a], xy[2 * a + 1], z);
                    if (row[b] < 0)
                        row[b] = bt_add_vertex(m, xy[2 * b], xy[2 * b + 1], z);
                }
                bt_add_tri(m, ra[a], ra[b], rb[b]);
                bt_add_tri(m, ra[a], rb[b], rb[a]);
            }
        }
    free(id);
}

/* The box [x0, x1] x [y0, y1] x [z0, z1] with its faces cut into n[0] x n[1] x n[2] grids
 * (a vertex where grid lines meet: no T-junction), outward. */
static void grid_box(bt_mesh *m, const double lo[3], const double hi[3], const int n[3], int inward)
{
    int64_t nx = n[0] + 1, ny = n[1] + 1, nz = n[2] + 1;
    int64_t *id = malloc((size_t)(nx * ny * nz) * sizeof *id);
    for (int64_t i = 0; i < nx * ny * nz; i++)
        id[i] = -1;
#define GID(i, j, k) id[((i) * ny + (j)) * nz + (k)]
    for (int c = 0; c < 3; c++) {
        int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        for (int side = 0; side < 2; side++)
            for (int i = 0; i < n[c1]; i++)
                for (int j = 0; j < n[c2]; j++) {
                    int64_t q[4];
                    static const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
                    for (int k = 0; k < 4; k++) {
                        int g[3];
                        g[c] = side ? n[c] : 0;
                        g[c1] = i + di[k];
                        g[c2] = j + dj[k];
                        int64_t *slot = &GID(g[0], g[1], g[2]);
                        if (*slot < 0) {
                            double x[3];
                            for (int d = 0; d < 3; d++)
                                x[d] = g[d] == n[d] ? hi[d] : lo[d] + (hi[d] - lo[d]) * g[d] / n[d];
                            *slot = bt_add_vertex(m, x[0], x[1], x[2]);
                        }
                        q[k] = *slot;
                    }
                    /* (c1, c2) counter-clockwise has normal +e_c: the max side as is */
                    if (side ^ inward) {
                        bt_add_tri(m, q[0], q[1], q[2]);
                        bt_add_tri(m, q[0], q[2], q[3]);
                    } else {
                        bt_add_tri(m, q[0], q[2], q[1]);
                        bt_add_tri(m, q[0], q[3], q[2]);
                    }
                }
    }
#undef GID
    free(id);
}

/* A torus about z: major radius R, tube radii rho (radial) and rho_z (along z), nu x nv
 * quads, centred at c; outward (d/du x d/dv points out of the tube). */
static void torus(bt_mesh *m, double R, double rho, double rho_z, int nu, int nv, const double c[3])
{
    int64_t base = m->nv;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            double u = TWO_PI * i / nu, v = TWO_PI * j / nv, w = R + rho * cos(v);
            bt_add_vertex(m, c[0] + w * cos(u), c[1] + w * sin(u), c[2] + rho_z * sin(v));
        }
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            int64_t a = base + i * nv + j, b = base + ((i + 1) % nu) * nv + j,
                    cc = base + ((i + 1) % nu) * nv + (j + 1) % nv, d = base + i * nv + (j + 1) % nv;
            bt_add_tri(m, a, b, cc);
            bt_add_tri(m, a, cc, d);
        }
}

/* Applies x -> A x (A with a positive determinant keeps the orientation). */
static void linear_map(bt_mesh *m, int64_t from, const double A[9])
{
    for (int64_t i = from; i < m->nv; i++) {
        double *p = m->xyz + 3 * i, x = p[0], y = p[1], z = p[2];
        for (int r = 0; r < 3; r++)
            p[r] = A[3 * r] * x + A[3 * r + 1] * y + A[3 * r + 2] * z;
    }
}

static double det3(const double A[9])
{
    return A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
           A[2] * (A[3] * A[7] - A[4] * A[6]);
}

static void random_unit(bt_rng *r, double u[3])
{
    double n;
    do {
        for (int c = 0; c < 3; c++)
            u[c] = bt_unif(r, -1, 1);
        n = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    } while (n > 1 || n < 0.1);
    for (int c = 0; c < 3; c++)
        u[c] /= n;
}

/* The region between an n-gon of vertex radius ro and one of vertex radius ri about the
 * z axis, extruded from z0 to z1 (the checks' reference results). */
void bt_ring(bt_mesh *m, int n, double ri, double ro, double z0, double z1)
{
    double *xy = malloc((size_t)(4 * n) * sizeof *xy);
    int *tri = malloc((size_t)(6 * n) * sizeof *tri);
    for (int k = 0; k < n; k++) {
        double a = TWO_PI * k / n;
        xy[2 * k] = ro * cos(a);
        xy[2 * k + 1] = ro * sin(a);
        xy[2 * (n + k)] = ri * cos(a);
        xy[2 * (n + k) + 1] = ri * sin(a);
    }
    for (int k = 0; k < n; k++) {
        int o0 = k, o1 = (k + 1) % n, i0 = n + k, i1 = n + (k + 1) % n;
        int t[6] = {o0, o1, i1, o0, i1, i0};
        memcpy(tri + 6 * k, t, sizeof t);
    }
    extrude(m, xy, 2 * n, tri, 2 * n, z0, z1, 1);
    free(xy);
    free(tri);
}

/* The box [lo, hi] (12 triangles), outward. */
void bt_box(bt_mesh *m, const double lo[3], const double hi[3])
{
    static const int ones[3] = {1, 1, 1};
    grid_box(m, lo, hi, ones, 0);
}

/* ------------------------------------------------------------------------ */
/* The families (local frame, about unit size)                              */
/* ------------------------------------------------------------------------ */

static const char *fam_box(bt_rng *r, bt_mesh *m)
{
    double lo[3] = {0, 0, 0}, hi[3];
    for (int c = 0; c < 3; c++)
        hi[c] = bt_unif(r, 0.2, 1);
    int ones[3] = {1, 1, 1};
    switch (bt_int(r, 0, 4)) {
    case 0:
        grid_box(m, lo, hi, ones, 0);
        return "box";
    case 1: { /* faces cut into grids: vertices inside faces and edges */
        int n[3] = {(int)bt_int(r, 1, 4), (int)bt_int(r, 1, 4), (int)bt_int(r, 1, 4)};
        grid_box(m, lo, hi, n, 0);
        return "grid box";
    }
    case 2: { /* two shells apart: the second beyond the first along one axis */
        grid_box(m, lo, hi, ones, 0);
        double lo2[3], hi2[3];
        int along = (int)bt_int(r, 0, 2), beyond = (int)bt_int(r, 0, 1);
        for (int c = 0; c < 3; c++) {
            double w = bt_unif(r, 0.1, 0.8);
            lo2[c] = bt_unif(r, -0.3, 0.8);
            if (c == along)
                lo2[c] = beyond ? hi[c] + bt_unif(r, 0.02, 0.5) : -bt_unif(r, 0.02, 0.5) - w;
            hi2[c] = lo2[c] + w;
        }
        grid_box(m, lo2, hi2, ones, 0);
        return "two boxes";
    }
    case 3: { /* a cavity: an inward inner shell */
        for (int c = 0; c < 3; c++)
            hi[c] = bt_unif(r, 0.5, 1);
        double ilo[3], ihi[3];
        for (int c = 0; c < 3; c++) {
            double wall = bt_unif(r, 0.05, 0.2) * hi[c];
            ilo[c] = wall;
            ihi[c] = hi[c] - bt_unif(r, 0.05, 0.2) * hi[c];
        }
        grid_box(m, lo, hi, ones, 0);
        grid_box(m, ilo, ihi, ones, 1);
        return "box with a cavity";
    }
    default: /* the unit cube: exact corners */
        for (int c = 0; c < 3; c++)
            hi[c] = 1;
        grid_box(m, lo, hi, ones, 0);
        return "cube";
    }
}

#define MAX_POLY 96

static const char *fam_prism(bt_rng *r, bt_mesh *m)
{
    double xy[2 * (MAX_POLY + 1)];
    int tri[3 * MAX_POLY], n = (int)bt_int(r, 3, 48), kind = (int)bt_int(r, 0, 2), nz = (int)bt_int(r, 1, 3);
    double h = bt_unif(r, 0.2, 1), phase = bt_unif(r, 0, TWO_PI);
    for (int k = 0; k < n; k++) {
        double a = phase + TWO_PI * k / n, rad = kind == 0 ? 0.5 : kind == 1 ? bt_unif(r, 0.15, 0.5) : bt_unif(r, 0.4, 0.5);
        xy[2 * k] = rad * cos(a);
        xy[2 * k + 1] = rad * sin(a);
    }
    if (kind == 0) { /* regular: a fan from vertex 0 (long thin triangles) */
        for (int k = 1; k + 1 < n; k++) {
            tri[3 * (k - 1)] = 0;
            tri[3 * (k - 1) + 1] = k;
            tri[3 * (k - 1) + 2] = k + 1;
        }
        extrude(m, xy, n, tri, n - 2, 0, h, nz);
        return "regular n-gon prism";
    }
    /* star-shaped about the centre: a fan from a centre vertex */
    xy[2 * n] = 0;
    xy[2 * n + 1] = 0;
    for (int k = 0; k < n; k++) {
        tri[3 * k] = n;
        tri[3 * k + 1] = k;
        tri[3 * k + 2] = (k + 1) % n;
    }
    extrude(m, xy, n + 1, tri, n, 0, h, nz);
    return kind == 1 ? "star n-gon prism" : "near-regular n-gon prism";
}

static const char *fam_lbracket(bt_rng *r, bt_mesh *m)
{
    /* the L of [0, A] x [0, t1] and [0, t2] x [0, B]: star-shaped from (0, 0), a fan */
    double A = bt_unif(r, 0.4, 1), B = bt_unif(r, 0.4, 1), t1 = bt_unif(r, 0.05, 0.3) * A,
           t2 = bt_unif(r, 0.05, 0.3) * B, h = bt_unif(r, 0.1, 1);
    double xy[12] = {0, 0, A, 0, A, t1, t2, t1, t2, B, 0, B};
    static const int tri[12] = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5};
    extrude(m, xy, 6, tri, 4, 0, h, (int)bt_int(r, 1, 3));
    return "L-bracket";
}

static const char *fam_frame(bt_rng *r, bt_mesh *m)
{
    double xy[4 * MAX_POLY];
    int tri[6 * MAX_POLY], n;
    const char *what;
    if (bt_int(r, 0, 1)) { /* a rectangular frame, the hole off centre */
        n = 4;
        double W = bt_unif(r, 0.3, 0.6), H = bt_unif(r, 0.3, 0.6);
        double w = bt_unif(r, 0.3, 0.8) * W, hh = bt_unif(r, 0.3, 0.8) * H;
        double ox = bt_unif(r, -0.5, 0.5) * (W - w), oy = bt_unif(r, -0.5, 0.5) * (H - hh);
        static const double sx[4] = {-1, 1, 1, -1}, sy[4] = {-1, -1, 1, 1};
        for (int k = 0; k < 4; k++) {
            xy[2 * k] = W * sx[k];
            xy[2 * k + 1] = H * sy[k];
            xy[2 * (4 + k)] = ox + w * sx[k];
            xy[2 * (4 + k) + 1] = oy + hh * sy[k];
        }
        what = "rectangular frame";
    } else { /* a square plate with a round hole: both sampled on the same rays */
        n = 8 * (int)bt_int(r, 1, 6);
        double R = 0.5, rad = bt_unif(r, 0.15, 0.6) * R, ox = bt_unif(r, -0.1, 0.1) * R, oy = bt_unif(r, -0.1, 0.1) * R;
        for (int k = 0; k < n; k++) {
            double a = TWO_PI * k / n, s = R / fmax(fabs(cos(a)), fabs(sin(a)));
            xy[2 * k] = s * cos(a);
            xy[2 * k + 1] = s * sin(a);
            xy[2 * (n + k)] = ox + rad * cos(a);
            xy[2 * (n + k) + 1] = oy + rad * sin(a);
        }
        what = "plate with a round hole";
    }
    for (int k = 0; k < n; k++) {
        int o0 = k, o1 = (k + 1) % n, i0 = n + k, i1 = n + (k + 1) % n;
        int t[6] = {o0, o1, i1, o0, i1, i0};
        memcpy(tri + 6 * k, t, sizeof t);
    }
    extrude(m, xy, 2 * n, tri, 2 * n, 0, bt_unif(r, 0.1, 0.6), (int)bt_int(r, 1, 2));
    return what;
}

static const char *fam_torus(bt_rng *r, bt_mesh *m)
{
    int nu = (int)bt_int(r, 12, 40), nv = (int)bt_int(r, 8, 28);
    double R = 0.5, rho = bt_unif(r, 0.1, 0.45) * R, rz = rho * bt_unif(r, 0.6, 1.4), c[3] = {0, 0, 0};
    torus(m, R, rho, rz, nu, nv, c);
    if (bt_int(r, 0, 3))
        return "torus";
    /* two linked tori (two shells): the second in the xz plane through the first's hole;
     * their core circles stay R apart, the tubes are thinner than R/2 */
    int64_t from = m->nv;
    double c2[3] = {0, 0, 0};
    torus(m, R, rho, rho, nu / 2 + 4, nv / 2 + 4, c2);
    static const double to_xz[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0}; /* a quarter turn about x */
    linear_map(m, from, to_xz);
    for (int64_t i = from; i < m->nv; i++)
        m->xyz[3 * i] += R;
    return "two linked tori";
}

static const char *fam_octa(bt_rng *r, bt_mesh *m)
{
    double A[9];
    do { /* a shear / stretch of positive determinant, not too flat */
        for (int i = 0; i < 9; i++)
            A[i] = (i % 4 == 0 ? 1 : 0) + bt_unif(r, -0.6, 0.6);
    } while (det3(A) < 0.2);
    int kind = (int)bt_int(r, 0, 2);
    if (kind == 0) { /* octahedron: +x, -x, +y, -y, +z, -z */
        static const int64_t O[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
        for (int k = 0; k < 6; k++) {
            double p[3] = {0, 0, 0};
            p[k / 2] = (k % 2 ? -1 : 1) * bt_unif(r, 0.2, 0.5);
            bt_add_vertex(m, p[0], p[1], p[2]);
        }
        for (int t = 0; t < 8; t++)
            bt_add_tri(m, O[3 * t], O[3 * t + 1], O[3 * t + 2]);
        linear_map(m, 0, A);
        return "sheared octahedron";
    }
    if (kind == 1) { /* tetrahedron: outward by its signed volume */
        double p[4][3];
        for (int k = 0; k < 4; k++)
            for (int c = 0; c < 3; c++)
                p[k][c] = bt_unif(r, -0.5, 0.5);
        for (int k = 0; k < 4; k++)
            bt_add_vertex(m, p[k][0], p[k][1], p[k][2]);
        double e[3][3];
        for (int k = 0; k < 3; k++)
            for (int c = 0; c < 3; c++)
                e[k][c] = p[k + 1][c] - p[0][c];
        double vol = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                     e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
        if (fabs(vol) < 0.01) { /* too flat: a regular one instead */
            static const double reg[4][3] = {{0.5, 0.5, 0.5}, {0.5, -0.5, -0.5}, {-0.5, 0.5, -0.5}, {-0.5, -0.5, 0.5}};
            for (int k = 0; k < 4; k++)
                memcpy(m->xyz + 3 * k, reg[k], sizeof reg[k]);
            vol = -1; /* (1-0, 2-0, 3-0) of reg is left-handed */
        }
        if (vol > 0) {
            bt_add_tri(m, 0, 2, 1);
            bt_add_tri(m, 0, 1, 3);
            bt_add_tri(m, 0, 3, 2);
            bt_add_tri(m, 1, 2, 3);
        } else {
            bt_add_tri(m, 0, 1, 2);
            bt_add_tri(m, 0, 3, 1);
            bt_add_tri(m, 0, 2, 3);
            bt_add_tri(m, 1, 3, 2);
        }
        linear_map(m, 0, A);
        return "sheared tetrahedron";
    }
    double lo[3] = {0, 0, 0}, hi[3] = {bt_unif(r, 0.2, 0.8), bt_unif(r, 0.2, 0.8), bt_unif(r, 0.2, 0.8)};
    int ones[3] = {1, 1, 1};
    grid_box(m, lo, hi, ones, 0);
    linear_map(m, 0, A);
    return "sheared box";
}

/* The real parts, read once from MFG_SWEEP_DATA_DIR (data/README.md: origin, licence). */
const char *const bt_part_files[] = {"tcmt1107_insert.off", "pump_nut.off"};
#define N_PARTS ((int)(sizeof bt_part_files / sizeof bt_part_files[0]))
const int bt_nparts = N_PARTS;
static bt_mesh parts[N_PARTS];
static int parts_read[N_PARTS];

static const char *fam_part(bt_rng *r, bt_mesh *m)
{
    int k = (int)bt_int(r, 0, N_PARTS - 1);
    if (!parts_read[k]) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", MFG_SWEEP_DATA_DIR, bt_part_files[k]);
        parts_read[k] = bt_read_off(path, &parts[k]) ? 1 : -1;
        if (parts_read[k] < 0)
            fprintf(stderr, "battery: cannot read %s\n", path);
    }
    if (parts_read[k] < 0)
        return NULL;
    bt_mesh_append(m, &parts[k]);
    return bt_part_files[k];
}

typedef const char *(*family_fn)(bt_rng *r, bt_mesh *m);
const char *const bt_families[] = {"box", "prism", "lbracket", "frame", "torus", "octa", "part"};
static const family_fn FAMILY_FN[] = {fam_box, fam_prism, fam_lbracket, fam_frame, fam_torus, fam_octa, fam_part};
const int bt_nfamilies = (int)(sizeof bt_families / sizeof bt_families[0]);

/* ------------------------------------------------------------------------ */
/* Placement, axis, angle, tolerance                                        */
/* ------------------------------------------------------------------------ */

/* the part's size (box diagonal) is drawn log-uniformly from 10^SIZE_LOG10_LO .. _HI */
#define SIZE_LOG10_LO (-0.5)
#define SIZE_LOG10_HI 1.5
/* translations of the placement: up to this many sizes from the origin */
#define SHIFT_SIZES 2.0
/* tolerances: 10^TOL_LOG10_LO .. 10^TOL_LOG10_HI of the size (the brief's 1e-4 .. 1e-1) */
#define TOL_LOG10_LO (-4.0)
#define TOL_LOG10_HI (-1.0)
/* the smallest angle the contract names, and the one just short of a full turn */
#define TINY_ANGLE 1e-6
#define SHORT_OF_FULL 1e-9
/* tries at a random point inside the solid before the centroid of a triangle is used */
#define INSIDE_TRIES 64

static void pick_angle(bt_rng *r, bt_problem *p, char *what, size_t n)
{
    int k = (int)bt_int(r, 0, 99);
    /* weights in percent: the named angles often, the rest spread over (0, 2 pi] */
    if (k < 10) {
        p->angle = TINY_ANGLE;
        snprintf(what, n, "1e-6");
    } else if (k < 25) {
        p->angle = TWO_PI;
        snprintf(what, n, "2pi");
    } else if (k < 33) {
        p->angle = TWO_PI - SHORT_OF_FULL;
        snprintf(what, n, "2pi-1e-9");
    } else if (k < 43) {
        p->angle = M_PI / 2;
        snprintf(what, n, "pi/2");
    } else if (k < 53) {
        p->angle = M_PI;
        snprintf(what, n, "pi");
    } else if (k < 70) {
        p->angle = TINY_ANGLE * pow(TWO_PI / TINY_ANGLE, bt_unif(r, 0, 1));
        snprintf(what, n, "%.6g", p->angle);
    } else {
        p->angle = bt_unif(r, TINY_ANGLE, TWO_PI);
        snprintf(what, n, "%.6g", p->angle);
    }
}

/* the rotation of a unit quaternion drawn uniformly (battery.h) */
void bt_random_rotation(bt_rng *r, double R[9])
{
    double q[4], n;
    do {
        n = 0;
        for (int i = 0; i < 4; i++) {
            q[i] = bt_unif(r, -1, 1);
            n += q[i] * q[i];
        }
    } while (n > 1 || n < 0.01);
    n = sqrt(n);
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    double M[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
                   2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                   2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)};
    memcpy(R, M, sizeof M);
}

/* a signed permutation matrix of determinant +1 (a rotation by quarter turns) */
static void quarter_rotation(bt_rng *r, double R[9])
{
    static const int perms[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
    int k = (int)bt_int(r, 0, 5);
    double s[3] = {bt_int(r, 0, 1) ? 1.0 : -1.0, bt_int(r, 0, 1) ? 1.0 : -1.0, 1};
    memset(R, 0, 9 * sizeof *R);
    for (int i = 0; i < 3; i++)
        R[3 * i + perms[k][i]] = s[i];
    if (det3(R) < 0)
        for (int c = 0; c < 3; c++)
            R[6 + c] = -R[6 + c];
}

int bt_make(const char *family, uint64_t seed, bt_problem *p)
{
    memset(p, 0, sizeof *p);
    int f = -1;
    for (int i = 0; i < bt_nfamilies; i++)
        if (!strcmp(family, bt_families[i]))
            f = i;
    if (f < 0)
        return 0;
    p->family = bt_families[f];
    p->seed = seed;
    bt_rng rr = {seed}, *r = &rr;
    const char *variant = FAMILY_FN[f](r, &p->in);
    if (!variant)
        return 0;

    /* placement: a random rotation, or exact ones (identity or quarter turns, a scale and
     * shift of powers of two) that keep faces parallel to the coordinate planes and the
     * coordinates exact, so axes along them are exactly along them */
    double d0 = bt_diag(p->in.xyz, p->in.nv), size = pow(10, bt_unif(r, SIZE_LOG10_LO, SIZE_LOG10_HI));
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, T[3], s = size / d0;
    int pk = (int)bt_int(r, 0, 3);
    const char *pose = pk <= 1 ? "random" : pk == 2 ? "exact" : "quarter";
    if (pk <= 1) {
        bt_random_rotation(r, R);
        for (int c = 0; c < 3; c++)
            T[c] = bt_unif(r, -SHIFT_SIZES, SHIFT_SIZES) * size;
    } else {
        s = exp2(round(log2(s)));
        if (pk == 3)
            quarter_rotation(r, R);
        for (int c = 0; c < 3; c++)
            T[c] = (double)bt_int(r, -2, 2) * exp2(round(log2(size)));
    }
    for (int64_t i = 0; i < p->in.nv; i++) {
        double *x = p->in.xyz + 3 * i, y[3];
        for (int c = 0; c < 3; c++)
            y[c] = s * (R[3 * c] * x[0] + R[3 * c + 1] * x[1] + R[3 * c + 2] * x[2]) + T[c];
        memcpy(x, y, sizeof y);
    }
    p->size = bt_diag(p->in.xyz, p->in.nv);

    /* the axis */
    const double *V = p->in.xyz;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, cen[3];
    for (int64_t i = 0; i < p->in.nv; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], V[3 * i + c]);
            hi[c] = fmax(hi[c], V[3 * i + c]);
        }
    for (int c = 0; c < 3; c++)
        cen[c] = 0.5 * (lo[c] + hi[c]);
    int ak = (int)bt_int(r, 0, 7);
    static const char *const axis_kind[8] = {"random",  "vertex",  "edge",    "face",
                                             "through", "outside", "aligned", "symmetry"};
    int64_t t = bt_int(r, 0, p->in.nt - 1), k = bt_int(r, 0, 2);
    const double *a = V + 3 * p->in.tri[3 * t + k], *b = V + 3 * p->in.tri[3 * t + (k + 1) % 3],
                 *c3 = V + 3 * p->in.tri[3 * t + (k + 2) % 3];
    switch (ak) {
    case 0: /* a random point near the part, a random direction */
        for (int c = 0; c < 3; c++)
            p->ap[c] = bt_unif(r, lo[c] - 0.25 * (hi[c] - lo[c]), hi[c] + 0.25 * (hi[c] - lo[c]));
        random_unit(r, p->ad);
        break;
    case 1: /* through a vertex */
        memcpy(p->ap, a, sizeof p->ap);
        random_unit(r, p->ad);
        break;
    case 2: /* along an edge */
        memcpy(p->ap, a, sizeof p->ap);
        for (int c = 0; c < 3; c++)
            p->ad[c] = b[c] - a[c];
        break;
    case 3: { /* in the plane of a face: through its corner or its centroid */
        double e1[3], e2[3], n1 = 0, dot = 0, n2 = 0, w = bt_unif(r, 0, TWO_PI);
        for (int c = 0; c < 3; c++) {
            e1[c] = b[c] - a[c];
            n1 += e1[c] * e1[c];
        }
        for (int c = 0; c < 3; c++)
            dot += (c3[c] - a[c]) * e1[c] / n1;
        for (int c = 0; c < 3; c++) {
            e2[c] = c3[c] - a[c] - dot * e1[c];
            n2 += e2[c] * e2[c];
        }
        n1 = sqrt(n1);
        n2 = sqrt(n2);
        for (int c = 0; c < 3; c++) {
            p->ad[c] = cos(w) * e1[c] / n1 + sin(w) * e2[c] / n2;
            p->ap[c] = bt_int(r, 0, 1) ? a[c] : (a[c] + b[c] + c3[c]) / 3;
        }
        break;
    }
    case 4: { /* through a point inside the solid */
        bt_index ix;
        bt_index_build(&ix, V, p->in.tri, p->in.nt);
        int found = 0;
        for (int tries = 0; tries < INSIDE_TRIES && !found; tries++) {
            for (int c = 0; c < 3; c++)
                p->ap[c] = bt_unif(r, lo[c], hi[c]);
            found = bt_inside(&ix, p->ap) == 1;
        }
        bt_index_free(&ix);
        if (!found)
            for (int c = 0; c < 3; c++)
                p->ap[c] = (a[c] + b[c] + c3[c]) / 3;
        random_unit(r, p->ad);
        break;
    }
    case 5: { /* outside: perpendicular to an offset longer than the bounding sphere */
        double w[3], v[3], dot = 0, n = 0, off = (0.5 + bt_unif(r, 0.1, 2)) * p->size;
        random_unit(r, w);
        random_unit(r, v);
        for (int c = 0; c < 3; c++)
            dot += v[c] * w[c];
        for (int c = 0; c < 3; c++) {
            v[c] -= dot * w[c];
            n += v[c] * v[c];
        }
        for (int c = 0; c < 3; c++) {
            p->ap[c] = cen[c] + off * w[c];
            p->ad[c] = v[c] / sqrt(n);
        }
        break;
    }
    case 7: /* the local z axis through the local origin: the axis of symmetry of the tori,
             * n-gon prisms and plates with a hole (SV is the solid itself for a torus) */
        for (int c = 0; c < 3; c++) {
            p->ap[c] = T[c];
            p->ad[c] = R[3 * c + 2];
        }
        break;
    default: { /* parallel to a local coordinate axis (faces of the boxes, prisms, frames
                * perpendicular or parallel to it), through a vertex */
        int e = (int)bt_int(r, 0, 2);
        for (int c = 0; c < 3; c++)
            p->ad[c] = R[3 * c + e];
        memcpy(p->ap, a, sizeof p->ap);
        break;
    }
    }
    if (bt_int(r, 0, 1)) /* either sense */
        for (int c = 0; c < 3; c++)
            p->ad[c] = -p->ad[c];

    char angle_what[32];
    pick_angle(r, p, angle_what, sizeof angle_what);
    double rel = pow(10, bt_unif(r, TOL_LOG10_LO, TOL_LOG10_HI));
    p->tol = rel * p->size;
    snprintf(p->what, sizeof p->what, "%s, pose %s, axis %s, angle %s, tol %.2e*size, %lld triangles, size %.3g",
             variant, pose, axis_kind[ak], angle_what, rel, (long long)p->in.nt, p->size);
    return 1;
}

/* ------------------------------------------------------------------------ */
/* OFF files                                                                */
/* ------------------------------------------------------------------------ */

/* the next line that is not empty nor a comment */
static int next_line(FILE *f, char *buf, size_t n)
{
    while (fgets(buf, (int)n, f)) {
        char *s = buf;
        while (*s == ' ' || *s == '\t')
            s++;
        if (*s && *s != '#' && *s != '\n' && *s != '\r')
            return 1;
    }
    return 0;
}

int bt_read_off(const char *path, bt_mesh *out)
{
    memset(out, 0, sizeof *out);
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    char line[512];
    long nv, nf;
    int ok = next_line(f, line, sizeof line) && !strncmp(line, "OFF", 3) && next_line(f, line, sizeof line) &&
             sscanf(line, "%ld %ld", &nv, &nf) == 2 && nv > 0 && nf > 0;
    for (long i = 0; ok && i < nv; i++) {
        double x, y, z;
        ok = next_line(f, line, sizeof line) && sscanf(line, "%lf %lf %lf", &x, &y, &z) == 3;
        if (ok)
            bt_add_vertex(out, x, y, z);
    }
    for (long i = 0; ok && i < nf; i++) {
        long k, a, b, c;
        ok = next_line(f, line, sizeof line) && sscanf(line, "%ld %ld %ld %ld", &k, &a, &b, &c) == 4 && k == 3 &&
             a >= 0 && b >= 0 && c >= 0 && a < nv && b < nv && c < nv;
        if (ok)
            bt_add_tri(out, a, b, c);
    }
    fclose(f);
    if (!ok)
        bt_mesh_free(out);
    return ok;
}

int bt_write_problem(const char *dir, const char *tag, const bt_problem *p)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s.off", dir, tag);
    FILE *f = fopen(path, "w");
    if (!f)
        return 0;
    fprintf(f, "OFF\n# %s seed 0x%016llx: %s\n%lld %lld 0\n", p->family, (unsigned long long)p->seed, p->what,
            (long long)p->in.nv, (long long)p->in.nt);
    for (int64_t i = 0; i < p->in.nv; i++)
        fprintf(f, "%.17g %.17g %.17g\n", p->in.xyz[3 * i], p->in.xyz[3 * i + 1], p->in.xyz[3 * i + 2]);
    for (int64_t t = 0; t < p->in.nt; t++)
        fprintf(f, "3 %lld %lld %lld\n", (long long)p->in.tri[3 * t], (long long)p->in.tri[3 * t + 1],
                (long long)p->in.tri[3 * t + 2]);
    fclose(f);
    snprintf(path, sizeof path, "%s/%s.txt", dir, tag);
    f = fopen(path, "w");
    if (!f)
        return 0;
    fprintf(f, "# mfg_rotational_sweep(%s.off, axis_point, axis_direction, angle, tolerance)\n", tag);
    fprintf(f, "# %s seed 0x%016llx: %s\n", p->family, (unsigned long long)p->seed, p->what);
    fprintf(f, "axis_point %.17g %.17g %.17g\n", p->ap[0], p->ap[1], p->ap[2]);
    fprintf(f, "axis_direction %.17g %.17g %.17g\n", p->ad[0], p->ad[1], p->ad[2]);
    fprintf(f, "angle %.17g\ntolerance %.17g\n", p->angle, p->tol);
    fclose(f);
    return 1;
}
