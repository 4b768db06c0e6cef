/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial_solids.h - the analytic solids of the medial-surface tests (docs/design/medial.md
 * section 7): boxes, the L-bracket and regular n-gon discs as closed, outward-oriented
 * triangle meshes.  Header-only, for the C tests. */
#ifndef MEDIAL_SOLIDS_H
#define MEDIAL_SOLIDS_H
#include <math.h>
#include <stdint.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef struct tmesh {
    double xyz[3 * 1024];
    int64_t tri[3 * 2048];
    int64_t nv, nt;
} tmesh;

/* The vertex with these coordinates, added when new (meshes here are small). */
static inline int64_t ms_vtx(tmesh *m, double x, double y, double z)
{
    for (int64_t i = 0; i < m->nv; i++)
        if (m->xyz[3 * i] == x && m->xyz[3 * i + 1] == y && m->xyz[3 * i + 2] == z)
            return i;
    m->xyz[3 * m->nv] = x;
    m->xyz[3 * m->nv + 1] = y;
    m->xyz[3 * m->nv + 2] = z;
    return m->nv++;
}

static inline void ms_tri(tmesh *m, int64_t a, int64_t b, int64_t c)
{
    m->tri[3 * m->nt] = a;
    m->tri[3 * m->nt + 1] = b;
    m->tri[3 * m->nt + 2] = c;
    m->nt++;
}

/* A prism: the polygon P (n corners, counter-clockwise in xy) extruded over z in [0, H];
 * caps fanned from corner 0 (the polygons here are star-shaped from it). */
static inline void ms_prism(tmesh *m, const double (*P)[2], int n, double H)
{
    memset(m, 0, sizeof *m);
    int64_t b[128], t[128];
    for (int i = 0; i < n; i++) {
        b[i] = ms_vtx(m, P[i][0], P[i][1], 0);
        t[i] = ms_vtx(m, P[i][0], P[i][1], H);
    }
    for (int i = 1; i + 1 < n; i++) {
        ms_tri(m, t[0], t[i], t[i + 1]);
        ms_tri(m, b[0], b[i + 1], b[i]);
    }
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        ms_tri(m, b[i], b[j], t[j]);
        ms_tri(m, b[i], t[j], t[i]);
    }
}

/* The box [0, a] x [0, b] x [0, c]. */
static inline void ms_box(tmesh *m, double a, double b, double c)
{
    const double P[4][2] = {{0, 0}, {a, 0}, {a, b}, {0, b}};
    ms_prism(m, P, 4, c);
}

/* The box [0, a] x [0, b] x [0, c], each face a k x k grid of quads split into 2 triangles
 * (the diagonal alternating), counter-clockwise seen from outside (k <= 12 fits). */
static inline void ms_grid_box(tmesh *m, double a, double b, double c, int k)
{
    memset(m, 0, sizeof *m);
    double ext[3] = {a, b, c};
    for (int ax = 0; ax < 3; ax++)
        for (int side = 0; side < 2; side++)
            for (int u = 0; u < k; u++)
                for (int v = 0; v < k; v++) {
                    int64_t q[4];
                    int uv[4][2] = {{u, v}, {u + 1, v}, {u + 1, v + 1}, {u, v + 1}};
                    for (int j = 0; j < 4; j++) {
                        double p[3];
                        int i1 = (ax + 1) % 3, i2 = (ax + 2) % 3;
                        p[ax] = side * ext[ax];
                        p[i1] = uv[j][0] * ext[i1] / k;
                        p[i2] = uv[j][1] * ext[i2] / k;
                        q[j] = ms_vtx(m, p[0], p[1], p[2]);
                    }
                    if (!side) {
                        int64_t t = q[1];
                        q[1] = q[3];
                        q[3] = t;
                    }
                    if ((u + v) % 2) {
                        ms_tri(m, q[0], q[1], q[2]);
                        ms_tri(m, q[0], q[2], q[3]);
                    } else {
                        ms_tri(m, q[1], q[2], q[3]);
                        ms_tri(m, q[1], q[3], q[0]);
                    }
                }
}

/* L-bracket: arms [0,10] x [0,50] and [0,50] x [0,10], extruded over z in [0, 40]. */
static inline void ms_l_bracket(tmesh *m)
{
    const double P[6][2] = {{0, 0}, {50, 0}, {50, 10}, {10, 10}, {10, 50}, {0, 50}};
    ms_prism(m, P, 6, 40);
}

/* T-section: flange [0,60] x [0,10], web [25,35] x [10,50], extruded over z in [0, 40];
 * the caps are triangulated by hand (the T is not star-shaped from a corner). */
static inline void ms_tsection(tmesh *m)
{
    const double P[8][2] = {{0, 0}, {60, 0}, {60, 10}, {35, 10}, {35, 50}, {25, 50}, {25, 10}, {0, 10}};
    static const int C[6][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 6}, {0, 6, 7}, {6, 3, 4}, {6, 4, 5}};
    ms_prism(m, P, 8, 40);
    for (int i = 0; i < 6; i++) { /* ms_prism's first 12 triangles are the caps */
        int64_t *t = m->tri + 6 * i;
        for (int k = 0; k < 3; k++) {
            t[k] = ms_vtx(m, P[C[i][k]][0], P[C[i][k]][1], 40);
            t[3 + (3 - k) % 3] = ms_vtx(m, P[C[i][k]][0], P[C[i][k]][1], 0);
        }
    }
}

/* The union of the occupied cells [xs[i], xs[i+1]] x [ys[j], ys[j+1]] x [zs[k], zs[k+1]]
 * of a 2 x 2 x 2 grid (occ[i][j][k]), each boundary cell side as two triangles on the
 * grid nodes (conforming: every vertex is a node). */
static inline void ms_grid2(tmesh *m, const double *xs, const double *ys, const double *zs,
                            const int occ[2][2][2])
{
    memset(m, 0, sizeof *m);
    const double *g[3] = {xs, ys, zs};
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++)
            for (int k = 0; k < 2; k++) {
                if (!occ[i][j][k])
                    continue;
                int c[3] = {i, j, k};
                for (int ax = 0; ax < 3; ax++)
                    for (int side = 0; side < 2; side++) {
                        int nb[3] = {i, j, k};
                        nb[ax] += side ? 1 : -1;
                        if (nb[ax] >= 0 && nb[ax] < 2 && occ[nb[0]][nb[1]][nb[2]])
                            continue;
                        int a1 = (ax + 1) % 3, a2 = (ax + 2) % 3;
                        int64_t q[4];
                        const int uv[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                        for (int n = 0; n < 4; n++) {
                            double p[3];
                            p[ax] = g[ax][c[ax] + side];
                            p[a1] = g[a1][c[a1] + uv[n][0]];
                            p[a2] = g[a2][c[a2] + uv[n][1]];
                            q[n] = ms_vtx(m, p[0], p[1], p[2]);
                        }
                        /* (a1, a2, ax) is right-handed: counter-clockwise seen from +ax */
                        if (side) {
                            ms_tri(m, q[0], q[1], q[2]);
                            ms_tri(m, q[0], q[2], q[3]);
                        } else {
                            ms_tri(m, q[0], q[2], q[1]);
                            ms_tri(m, q[0], q[3], q[2]);
                        }
                    }
            }
}

/* Regular n-gon disc: circumradius R, thickness H, corner 0 at (R, 0). */
static inline void ms_disc(tmesh *m, int n, double R, double H)
{
    double P[128][2];
    for (int i = 0; i < n; i++) {
        P[i][0] = R * cos(2 * M_PI * i / n);
        P[i][1] = R * sin(2 * M_PI * i / n);
    }
    ms_prism(m, (const double(*)[2])P, n, H);
}

/* The solid of revolution about z of a closed simple profile (r >= 0, z), k points,
 * with n segments; points with r == 0 lie on the axis (one vertex each).  Outward
 * orientation (flipped when the signed volume comes out negative). */
static inline void ms_revolve(tmesh *m, const double (*prof)[2], int k, int n)
{
    int64_t ids[16][128];
    for (int i = 0; i < k; i++)
        for (int s = 0; s < n; s++) {
            double a = 2 * M_PI * s / n, r = prof[i][0];
            ids[i][s] = r == 0 ? ms_vtx(m, 0, 0, prof[i][1])
                               : ms_vtx(m, r * cos(a), r * sin(a), prof[i][1]);
        }
    int64_t t0 = m->nt;
    for (int i = 0; i < k; i++) {
        int j = (i + 1) % k;
        for (int s = 0; s < n; s++) {
            int t = (s + 1) % n;
            int64_t a = ids[i][s], b = ids[i][t], c = ids[j][s], d = ids[j][t];
            if (a != b && b != d && a != d)
                ms_tri(m, a, b, d);
            if (a != d && d != c && a != c)
                ms_tri(m, a, d, c);
        }
    }
    double vol = 0;
    for (int64_t t = t0; t < m->nt; t++) {
        const double *p = m->xyz + 3 * m->tri[3 * t], *q = m->xyz + 3 * m->tri[3 * t + 1],
                     *r = m->xyz + 3 * m->tri[3 * t + 2];
        vol += p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
               p[2] * (q[0] * r[1] - q[1] * r[0]);
    }
    if (vol < 0)
        for (int64_t t = t0; t < m->nt; t++) {
            int64_t x = m->tri[3 * t + 1];
            m->tri[3 * t + 1] = m->tri[3 * t + 2];
            m->tri[3 * t + 2] = x;
        }
}

/* examples/parts/cup.py (a cylinder R 20, height 30, with a blind pocket: wall 3, bottom
 * 4) with n <= 128 segments: 8 n triangles. */
static inline void ms_cup(tmesh *m, int n)
{
    const double P[6][2] = {{0, 0}, {20, 0}, {20, 30}, {17, 30}, {17, 4}, {0, 4}};
    ms_revolve(m, P, 6, n);
}

/* A permutation of the triangles (and a rotation of each one's corners) from seed. */
static inline void ms_shuffle(tmesh *m, unsigned long long seed)
{
    for (int64_t i = m->nt - 1; i > 0; i--) {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        int64_t j = (int64_t)((seed >> 33) % (unsigned long long)(i + 1));
        int64_t t[3];
        memcpy(t, m->tri + 3 * i, sizeof t);
        memcpy(m->tri + 3 * i, m->tri + 3 * j, sizeof t);
        memcpy(m->tri + 3 * j, t, sizeof t);
    }
    for (int64_t i = 0; i < m->nt; i++) {
        int r = (int)((seed >> (i % 60)) % 3);
        int64_t *t = m->tri + 3 * i;
        for (int k = 0; k < r; k++) {
            int64_t a = t[0];
            t[0] = t[1];
            t[1] = t[2];
            t[2] = a;
        }
    }
}
#endif
