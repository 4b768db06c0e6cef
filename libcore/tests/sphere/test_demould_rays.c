/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_demould_rays.c - mfg_ray_blocked against voxel solids (whose answer is read off
 * the filled columns), a long-double brute force on random soups, an exact brute force
 * without the grid on lattice soups full of degeneracies, and hostile arguments. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mfg_test.h"
#include "mfgeom.h"
#include "common/predicates.h"

#define POS MFG_RAY_BLOCKED_POS
#define NEG MFG_RAY_BLOCKED_NEG
#define GPOS MFG_RAY_GRAZES_POS
#define GNEG MFG_RAY_GRAZES_NEG

/* ---- Voxel solids: the boundary quads between filled and empty unit cubes ----------- */

#define VN 6 /* voxel grid VN^3 */
typedef struct vox {
    unsigned char f[VN][VN][VN];
} vox;

typedef struct mesh {
    double *xyz;
    int64_t *tris;
    int64_t nv, nt;
    /* per triangle: the face's axis (0..2), its outward sign (+1/-1), and the voxel
     * column of the face (the cell indices on the two other axes) and its level */
    int *axis, *sign, *col0, *col1, *level;
} mesh;

static int filled(const vox *v, int x, int y, int z)
{
    if (x < 0 || y < 0 || z < 0 || x >= VN || y >= VN || z >= VN)
        return 0;
    return v->f[x][y][z];
}

static void mesh_free(mesh *m)
{
    free(m->xyz);
    free(m->tris);
    free(m->axis);
    free(m->sign);
    free(m->col0);
    free(m->col1);
    free(m->level);
}

/* Every quad gets its own 4 vertices (a soup of quads; the ray test needs no welding). */
static mesh voxel_mesh(const vox *v)
{
    mesh m;
    int64_t cap = 6 * VN * VN * VN;
    m.xyz = malloc(sizeof(double) * 12 * cap);
    m.tris = malloc(sizeof(int64_t) * 6 * cap);
    m.axis = malloc(sizeof(int) * 2 * cap);
    m.sign = malloc(sizeof(int) * 2 * cap);
    m.col0 = malloc(sizeof(int) * 2 * cap);
    m.col1 = malloc(sizeof(int) * 2 * cap);
    m.level = malloc(sizeof(int) * 2 * cap);
    m.nv = m.nt = 0;
    for (int a = 0; a < 3; a++) {
        int b = (a + 1) % 3, c = (a + 2) % 3;
        for (int i = 0; i < VN; i++)
            for (int j = 0; j < VN; j++)
                for (int k = 0; k <= VN; k++) {
                    int lo[3], hi[3];
                    lo[a] = k - 1, lo[b] = i, lo[c] = j;
                    hi[a] = k, hi[b] = i, hi[c] = j;
                    int fl = filled(v, lo[0], lo[1], lo[2]), fh = filled(v, hi[0], hi[1], hi[2]);
                    if (fl == fh)
                        continue;
                    int s = fl ? 1 : -1; /* outward along +a when the lower cube is filled */
                    double q[4][3];
                    int corners[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
                    for (int n = 0; n < 4; n++) {
                        q[n][a] = k;
                        q[n][b] = i + corners[n][0];
                        q[n][c] = j + corners[n][1];
                    }
                    /* (b, c, a) is right-handed: corners 0,1,2,3 run counter-clockwise seen
                     * from +a. */
                    int64_t base = m.nv;
                    for (int n = 0; n < 4; n++) {
                        memcpy(m.xyz + 3 * m.nv, q[n], sizeof q[n]);
                        m.nv++;
                    }
                    int64_t t1[3] = {base, base + 1, base + 2}, t2[3] = {base, base + 2, base + 3};
                    if (s < 0) {
                        t1[1] = base + 2, t1[2] = base + 1;
                        t2[1] = base + 3, t2[2] = base + 2;
                    }
                    for (int w = 0; w < 2; w++) {
                        memcpy(m.tris + 3 * m.nt, w ? t2 : t1, sizeof t1);
                        m.axis[m.nt] = a, m.sign[m.nt] = s;
                        m.col0[m.nt] = i, m.col1[m.nt] = j, m.level[m.nt] = k;
                        m.nt++;
                    }
                }
    }
    return m;
}

/* Reference for a face's sample along +a / -a: a filled cube in its column at index >=
 * level (the ray enters or leaves the solid above) / below level. */
static uint8_t column_reference(const vox *v, const mesh *m, int64_t t, int ray_axis)
{
    int a = m->axis[t];
    if (a != ray_axis)
        return 0; /* walls parallel to the ray: checked separately */
    uint8_t bits = 0;
    for (int k = 0; k < VN; k++) {
        int idx[3];
        idx[a] = k, idx[(a + 1) % 3] = m->col0[t], idx[(a + 2) % 3] = m->col1[t];
        if (!filled(v, idx[0], idx[1], idx[2]))
            continue;
        if (k >= m->level[t])
            bits |= POS;
        else
            bits |= NEG;
    }
    return bits;
}

static void centroids(const mesh *m, double *pts, int64_t *own)
{
    for (int64_t t = 0; t < m->nt; t++) {
        for (int k = 0; k < 3; k++)
            pts[3 * t + k] = (m->xyz[3 * m->tris[3 * t] + k] + m->xyz[3 * m->tris[3 * t + 1] + k] +
                              m->xyz[3 * m->tris[3 * t + 2] + k]) / 3.0;
        own[t] = t;
    }
}

/* Checks every triangle centroid of the voxel solid along each axis against the columns;
 * for walls parallel to the ray only "not blocked" is asserted (the ray slides along
 * the wall plane and may graze the edges of the faces it reaches). */
static void check_voxels(const vox *v, const char *what)
{
    mesh m = voxel_mesh(v);
    double *pts = malloc(sizeof(double) * 3 * (size_t)(m.nt + 1));
    int64_t *own = malloc(sizeof(int64_t) * (size_t)(m.nt + 1));
    uint8_t *out = malloc((size_t)m.nt + 1);
    centroids(&m, pts, own);
    int bad = 0;
    for (int ax = 0; ax < 3; ax++)
        for (int sg = -1; sg <= 1; sg += 2) {
            double d[3] = {0, 0, 0};
            d[ax] = sg * (ax + 1.5);
            CHECK_EQ_INT(mfg_ray_blocked(m.xyz, m.nv, m.tris, m.nt, pts, own, m.nt, d, out), MFG_OK);
            for (int64_t t = 0; t < m.nt; t++) {
                uint8_t ref = column_reference(v, &m, t, ax);
                if (sg < 0) /* -d: the bits swap */
                    ref = (uint8_t)(((ref & POS) ? NEG : 0) | ((ref & NEG) ? POS : 0));
                uint8_t got = out[t];
                if (m.axis[t] == ax) {
                    if (got != ref && bad++ < 5)
                        fprintf(stderr, "%s: triangle %lld axis %d d %+d: got %d, expected %d\n",
                                what, (long long)t, ax, sg, got, ref);
                    CHECK(got == ref);
                } else {
                    CHECK((got & (POS | NEG)) == 0);
                }
            }
        }
    free(pts);
    free(own);
    free(out);
    mesh_free(&m);
}

static void fill_box(vox *v, int x0, int y0, int z0, int x1, int y1, int z1, int val)
{
    for (int x = x0; x < x1; x++)
        for (int y = y0; y < y1; y++)
            for (int z = z0; z < z1; z++)
                v->f[x][y][z] = (unsigned char)val;
}

static void test_voxel_solids(void)
{
    vox v;
    memset(&v, 0, sizeof v);
    fill_box(&v, 1, 1, 1, 4, 3, 3, 1); /* a box */
    check_voxels(&v, "box");
    fill_box(&v, 2, 1, 2, 3, 2, 3, 0); /* a blind pocket into the top */
    check_voxels(&v, "pocket");
    memset(&v, 0, sizeof v);
    fill_box(&v, 1, 1, 1, 2, 4, 5, 1); /* an L lying on its side: the overhang ... */
    fill_box(&v, 1, 1, 4, 5, 4, 5, 1); /* ... shadows the upward floor at z = 1 */
    fill_box(&v, 1, 1, 0, 5, 4, 1, 1); /* (a C: floor, post, roof) */
    check_voxels(&v, "C shape");
    memset(&v, 0, sizeof v);
    fill_box(&v, 2, 0, 0, 3, 5, 3, 1); /* T */
    fill_box(&v, 0, 0, 3, 5, 5, 4, 1);
    check_voxels(&v, "T");
    for (int r = 0; r < 40; r++) {
        for (int x = 0; x < VN; x++)
            for (int y = 0; y < VN; y++)
                for (int z = 0; z < VN; z++)
                    v.f[x][y][z] = (unsigned char)(rng_next() % 3 == 0);
        check_voxels(&v, "random voxels");
    }
}

/* The shadowed face of the C shape named explicitly: its normal says "free along +z",
 * the ray says blocked. */
static void test_shadowed_face(void)
{
    vox v;
    memset(&v, 0, sizeof v);
    fill_box(&v, 1, 1, 0, 5, 4, 1, 1);
    fill_box(&v, 1, 1, 1, 2, 4, 5, 1);
    fill_box(&v, 1, 1, 4, 5, 4, 5, 1);
    mesh m = voxel_mesh(&v);
    double pt[3] = {3.25, 2.5, 1.0}, d[3] = {0, 0, 1};
    int64_t own = -1;
    for (int64_t t = 0; t < m.nt; t++)
        if (m.axis[t] == 2 && m.sign[t] > 0 && m.level[t] == 1 && m.col0[t] == 3 && m.col1[t] == 2)
            own = t;
    CHECK(own >= 0);
    uint8_t out = 0xff;
    CHECK_EQ_INT(mfg_ray_blocked(m.xyz, m.nv, m.tris, m.nt, pt, &own, 1, d, &out), MFG_OK);
    CHECK_EQ_INT(out, POS | NEG); /* the roof above, the floor's own bottom below */
    double top[3] = {3.25, 2.5, 5.0};
    CHECK_EQ_INT(mfg_ray_blocked(m.xyz, m.nv, m.tris, m.nt, top, NULL, 1, d, &out), MFG_OK);
    CHECK_EQ_INT(out, NEG); /* on the roof's top: no own triangle, s = 0 does not count */
    mesh_free(&m);
}

/* ---- A rotated voxel solid: the same answers for the rotated direction -------------- */

static void random_rotation(double r[3][3])
{
    /* a random unit quaternion */
    double q[4], n = 0;
    for (int k = 0; k < 4; k++) {
        q[k] = rng_uniform(-1, 1);
        n += q[k] * q[k];
    }
    n = sqrt(n);
    double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
    double m[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    memcpy(r, m, sizeof m);
}

static void rotate(double r[3][3], const double *in, double *out)
{
    double t[3];
    for (int i = 0; i < 3; i++)
        t[i] = r[i][0] * in[0] + r[i][1] * in[1] + r[i][2] * in[2];
    memcpy(out, t, sizeof t);
}

static void test_rotated(void)
{
    vox v;
    for (int rep = 0; rep < 10; rep++) {
        memset(&v, 0, sizeof v);
        if (rep == 0)
            fill_box(&v, 1, 1, 1, 2, 2, 2, 1); /* the unit cube */
        else
            for (int x = 0; x < VN; x++)
                for (int y = 0; y < VN; y++)
                    for (int z = 0; z < VN; z++)
                        v.f[x][y][z] = (unsigned char)(rng_next() % 3 == 0);
        mesh m = voxel_mesh(&v);
        double *pts = malloc(sizeof(double) * 3 * (size_t)(m.nt + 1));
        int64_t *own = malloc(sizeof(int64_t) * (size_t)(m.nt + 1));
        uint8_t *out = malloc((size_t)m.nt + 1), *rout = malloc((size_t)m.nt + 1);
        centroids(&m, pts, own);
        double r[3][3];
        random_rotation(r);
        for (int ax = 0; ax < 3; ax++) {
            double d[3] = {0, 0, 0}, rd[3];
            d[ax] = 1;
            CHECK_EQ_INT(mfg_ray_blocked(m.xyz, m.nv, m.tris, m.nt, pts, own, m.nt, d, out), MFG_OK);
            mesh rm = m;
            double *rxyz = malloc(sizeof(double) * 3 * (size_t)m.nv);
            double *rpts = malloc(sizeof(double) * 3 * (size_t)(m.nt + 1));
            for (int64_t i = 0; i < m.nv; i++)
                rotate(r, m.xyz + 3 * i, rxyz + 3 * i);
            rm.xyz = rxyz;
            centroids(&rm, rpts, own);
            rotate(r, d, rd);
            CHECK_EQ_INT(mfg_ray_blocked(rxyz, m.nv, m.tris, m.nt, rpts, own, m.nt, rd, rout), MFG_OK);
            for (int64_t t = 0; t < m.nt; t++) {
                /* rotated walls parallel to d are no longer exactly parallel: compare the
                 * blocked bits of faces normal to d, and "not blocked" of the others
                 * only where the original is not grazing */
                if (m.axis[t] == ax)
                    CHECK_EQ_INT(rout[t] & (POS | NEG), out[t] & (POS | NEG));
            }
            if (rep == 0)
                for (int64_t t = 0; t < m.nt; t++)
                    if (m.axis[t] == ax) /* the cube: outward faces free, inward blocked */
                        CHECK_EQ_INT(rout[t] & (POS | NEG), m.sign[t] > 0 ? NEG : POS);
            free(rxyz);
            free(rpts);
        }
        free(pts);
        free(own);
        free(out);
        free(rout);
        mesh_free(&m);
    }
}

/* ---- Edges and vertices: the documented grazing rule --------------------------------- */

static void test_edges_vertices(void)
{
    /* The box [0,2]^2 x [0,1], two triangles per face, diagonals chosen below. */
    double xyz[8 * 3] = {0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 0, 0, 0, 1, 2, 0, 1, 2, 2, 1, 0, 2, 1};
    int64_t tris[12 * 3] = {
        0, 2, 1, 0, 3, 2, /* bottom (diagonal 0-2) */
        4, 5, 6, 4, 6, 7, /* top (diagonal 4-6, above 0-2) */
        0, 1, 5, 0, 5, 4, /* y = 0 */
        1, 2, 6, 1, 6, 5, /* x = 2 */
        2, 3, 7, 2, 7, 6, /* y = 2 */
        3, 0, 4, 3, 4, 7, /* x = 0 */
    };
    double d[3] = {0, 0, 1};
    uint8_t out[16];
    mfg_mesh_report rep;
    CHECK_EQ_INT(mfg_mesh_check_closed(xyz, 8, tris, 12, &rep), MFG_OK);
    /* 0: on the top diagonal (own = triangle 2): the other top triangle is met at s = 0;
     * down the ray passes the bottom diagonal: grazing, not blocked (the documented
     * rule).  1: inside top triangle 2: blocked down.  2: below the box under the
     * vertex 0: it grazes the bottom vertex 0, slides up the vertical edge (walls
     * parallel to d), grazes vertex 4.  3: below the middle of edge 0-1: grazes.
     * 4: below the bottom diagonal: grazes both diagonals.  5: below the bottom face's
     * interior: blocked up (twice).  6: a point on the bottom face, own = -1: s = 0 for
     * the bottom triangle, blocked up by the top.  7: beside the box: nothing. */
    double pts[8 * 3] = {1, 1, 1, 1.5, 0.5, 1, 0, 0, -1, 1, 0, -1,
                         0.5, 0.5, -3, 1.5, 0.5, -1, 1.5, 0.5, 0, 3, 1, 0.5};
    int64_t own[8] = {2, 2, -1, -1, -1, -1, -1, -1};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 8, tris, 12, pts, own, 8, d, out), MFG_OK);
    CHECK_EQ_INT(out[0], GNEG);
    CHECK_EQ_INT(out[1], NEG);
    CHECK_EQ_INT(out[2], GPOS);
    CHECK_EQ_INT(out[3], GPOS);
    CHECK_EQ_INT(out[4], GPOS);
    CHECK_EQ_INT(out[5], POS);
    CHECK_EQ_INT(out[6], POS);
    CHECK_EQ_INT(out[7], 0);
    /* The same with own_triangle NULL: point 0 lies on both top triangles (s = 0),
     * point 1 on triangle 2 (s = 0): no change. */
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 8, tris, 12, pts, NULL, 8, d, out), MFG_OK);
    CHECK_EQ_INT(out[0], GNEG);
    CHECK_EQ_INT(out[1], NEG);
    /* Along +x from the side face x = 0 (own 10): the ray runs through the solid and
     * leaves through x = 2: blocked; -x: free.  From a point on the bottom face along +x:
     * coplanar with the bottom, slides out, grazes only the edge of the x = 2 face. */
    double dx[3] = {1, 0, 0};
    double p2[2 * 3] = {0, 1.5, 0.25, 0.5, 1.2, 0};
    int64_t own2[2] = {10, 0};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 8, tris, 12, p2, own2, 2, dx, out), MFG_OK);
    CHECK_EQ_INT(out[0], POS);
    CHECK_EQ_INT(out[1], GPOS | GNEG);
    /* Zero-area triangles never block: the top face replaced by a collinear sliver. */
    int64_t sliver[3] = {4, 5, 5};
    double below[3] = {1, 0, -1};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 8, sliver, 1, below, NULL, 1, d, out), MFG_OK);
    CHECK_EQ_INT(out[0], 0);
}

/* ---- Random soups: long-double brute force, and exact brute force on lattices -------- */

/* Long-double reference: barycentric signs and the ray parameter; *clear = 0 when some
 * quantity is too close to 0 for the long double to be trusted. */
static uint8_t ld_reference(const double *xyz, const int64_t *tris, int64_t nt, const double *p,
                            int64_t own, const double *d, int *clear)
{
    uint8_t bits = 0;
    *clear = 1;
    for (int64_t t = 0; t < nt; t++) {
        if (t == own)
            continue;
        const double *v[3] = {xyz + 3 * tris[3 * t], xyz + 3 * tris[3 * t + 1], xyz + 3 * tris[3 * t + 2]};
        long double e[3];
        for (int k = 0; k < 3; k++) {
            const double *a = v[k], *b = v[(k + 1) % 3];
            long double ax = (long double)a[0] - p[0], ay = (long double)a[1] - p[1], az = (long double)a[2] - p[2];
            long double bx = (long double)b[0] - p[0], by = (long double)b[1] - p[1], bz = (long double)b[2] - p[2];
            e[k] = d[0] * (ay * bz - az * by) + d[1] * (az * bx - ax * bz) + d[2] * (ax * by - ay * bx);
        }
        long double ux = (long double)v[1][0] - v[0][0], uy = (long double)v[1][1] - v[0][1], uz = (long double)v[1][2] - v[0][2];
        long double wx = (long double)v[2][0] - v[0][0], wy = (long double)v[2][1] - v[0][1], wz = (long double)v[2][2] - v[0][2];
        long double nx = uy * wz - uz * wy, ny = uz * wx - ux * wz, nz = ux * wy - uy * wx;
        long double dn = nx * d[0] + ny * d[1] + nz * d[2];
        long double pn = nx * ((long double)v[0][0] - p[0]) + ny * ((long double)v[0][1] - p[1]) +
                         nz * ((long double)v[0][2] - p[2]);
        const long double eps = 1e-12L;
        int inside = (e[0] > eps && e[1] > eps && e[2] > eps) || (e[0] < -eps && e[1] < -eps && e[2] < -eps);
        int outside = 0;
        for (int k = 0; k < 3; k++)
            for (int l = 0; l < 3; l++)
                if (e[k] > eps && e[l] < -eps)
                    outside = 1;
        if (!inside && !outside) {
            *clear = 0;
            continue;
        }
        if (outside)
            continue;
        if (fabsl(dn) < eps || fabsl(pn) < eps) {
            *clear = 0;
            continue;
        }
        long double s = pn / dn;
        bits |= s > 0 ? POS : NEG;
    }
    return bits;
}

static void test_random_soups_long_double(void)
{
    int compared = 0;
    for (int rep = 0; rep < 30; rep++) {
        int64_t nt = rng_int(1, 300), np = 200;
        double *xyz = malloc(sizeof(double) * 9 * (size_t)nt);
        int64_t *tris = malloc(sizeof(int64_t) * 3 * (size_t)nt);
        double *pts = malloc(sizeof(double) * 3 * (size_t)np);
        int64_t *own = malloc(sizeof(int64_t) * (size_t)np);
        uint8_t *out = malloc((size_t)np);
        double size = rng_uniform(0.05, 0.6);
        for (int64_t t = 0; t < nt; t++) {
            double c[3] = {rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1)};
            for (int k = 0; k < 9; k++)
                xyz[9 * t + k] = c[k % 3] + rng_uniform(-size, size);
            for (int k = 0; k < 3; k++)
                tris[3 * t + k] = 3 * t + k;
        }
        for (int64_t i = 0; i < np; i++) {
            for (int k = 0; k < 3; k++)
                pts[3 * i + k] = rng_uniform(-1.2, 1.2);
            own[i] = (rng_next() % 4 == 0) ? (int64_t)rng_int(0, nt - 1) : -1;
        }
        double d[3] = {rng_uniform(-1, 1), rng_uniform(-1, 1), rng_uniform(-1, 1)};
        if (rep % 5 == 0)
            d[0] = d[1] = 0; /* axis directions too */
        CHECK_EQ_INT(mfg_ray_blocked(xyz, 3 * nt, tris, nt, pts, own, np, d, out), MFG_OK);
        for (int64_t i = 0; i < np; i++) {
            int clear;
            uint8_t ref = ld_reference(xyz, tris, nt, pts + 3 * i, own[i], d, &clear);
            if (!clear)
                continue;
            compared++;
            CHECK_EQ_INT(out[i], ref);
        }
        free(xyz);
        free(tris);
        free(pts);
        free(own);
        free(out);
    }
    CHECK(compared > 5000);
}

/* Exact brute force (the predicates, every triangle, no grid) on lattice soups: many
 * rays through edges and vertices and along planes. */
static uint8_t exact_reference(const double *xyz, const int64_t *tris, int64_t nt, const double *p,
                               int64_t own, const double *d)
{
    uint8_t bits = 0;
    for (int64_t t = 0; t < nt; t++) {
        if (t == own)
            continue;
        const double *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1], *c = xyz + 3 * tris[3 * t + 2];
        int dn = mfg_orient3d_vec(a, b, c, d);
        int sp = mfg_orient3d(a, b, c, p);
        if (dn == 0 || sp == 0)
            continue;
        int e[3] = {mfg_orient3d_vec(p, a, b, d), mfg_orient3d_vec(p, b, c, d), mfg_orient3d_vec(p, c, a, d)};
        int pos = (e[0] > 0) + (e[1] > 0) + (e[2] > 0), neg = (e[0] < 0) + (e[1] < 0) + (e[2] < 0);
        if (pos && neg)
            continue;
        int up = sp * dn > 0;
        if (pos == 3 || neg == 3)
            bits |= up ? POS : NEG;
        else
            bits |= up ? GPOS : GNEG;
    }
    return bits;
}

static void test_lattice_soups_exact(void)
{
    long hits = 0, grazes = 0;
    for (int rep = 0; rep < 60; rep++) {
        int64_t nt = rng_int(1, 200), np = 300;
        double *xyz = malloc(sizeof(double) * 9 * (size_t)nt);
        int64_t *tris = malloc(sizeof(int64_t) * 3 * (size_t)nt);
        double *pts = malloc(sizeof(double) * 3 * (size_t)np);
        uint8_t *out = malloc((size_t)np);
        double scale = (rep % 3 == 0) ? 1e-7 : ((rep % 3 == 1) ? 1.0 : 3e5);
        for (int64_t t = 0; t < 9 * nt; t++)
            xyz[t] = scale * (double)rng_int(-4, 4);
        for (int64_t t = 0; t < 3 * nt; t++)
            tris[t] = t;
        for (int64_t i = 0; i < 3 * np; i++)
            pts[i] = scale * 0.5 * (double)rng_int(-10, 10);
        double d[3] = {(double)rng_int(-2, 2), (double)rng_int(-2, 2), (double)rng_int(-2, 2)};
        if (d[0] == 0 && d[1] == 0 && d[2] == 0)
            d[2] = 1;
        CHECK_EQ_INT(mfg_ray_blocked(xyz, 3 * nt, tris, nt, pts, NULL, np, d, out), MFG_OK);
        for (int64_t i = 0; i < np; i++) {
            uint8_t ref = exact_reference(xyz, tris, nt, pts + 3 * i, -1, d);
            CHECK_EQ_INT(out[i], ref);
            hits += (ref & (POS | NEG)) != 0;
            grazes += (ref & (GPOS | GNEG)) != 0;
        }
        free(xyz);
        free(tris);
        free(pts);
        free(out);
    }
    CHECK(hits > 1000);
    CHECK(grazes > 1000);
}

/* mfg_orient3d_vec against orient3d with o + v exact (small integers). */
static void test_orient3d_vec(void)
{
    for (int rep = 0; rep < 20000; rep++) {
        double o[3], a[3], b[3], v[3], ov[3];
        for (int k = 0; k < 3; k++) {
            o[k] = (double)rng_int(-3, 3), a[k] = (double)rng_int(-3, 3);
            b[k] = (double)rng_int(-3, 3), v[k] = (double)rng_int(-3, 3);
            ov[k] = o[k] + v[k];
        }
        /* det[a - o, b - o, v] = det[a - o, b - o, ov - o] = orient3d(a, b, ov, o) */
        CHECK_EQ_INT(mfg_orient3d_vec(o, a, b, v), mfg_orient3d(a, b, ov, o));
    }
    /* A case the filter cannot decide: v nearly in the plane of a - o, b - o. */
    double o[3] = {0.1, 0.2, 0.3}, a[3] = {1.1, 0.2, 0.3}, b[3] = {0.1, 1.2, 0.3};
    double v[3] = {1, 1, 0x1p-1000};
    CHECK_EQ_INT(mfg_orient3d_vec(o, a, b, v), 1);
    v[2] = -0x1p-1000;
    CHECK_EQ_INT(mfg_orient3d_vec(o, a, b, v), -1);
}

/* ---- Hostile arguments ---------------------------------------------------------------- */

static void test_hostile(void)
{
    double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    int64_t tri[3] = {0, 1, 2}, own = -1;
    double p[3] = {0.2, 0.2, -1}, d[3] = {0, 0, 1};
    uint8_t out = 0x55;
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, 1, d, &out), MFG_OK);
    CHECK_EQ_INT(out, POS);
    out = 0x55;
    CHECK_EQ_INT(mfg_ray_blocked(NULL, 3, tri, 1, p, &own, 1, d, &out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, NULL, 1, p, &own, 1, d, &out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, NULL, &own, 1, d, &out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, 1, NULL, &out), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, 1, d, NULL), MFG_ERR_NULL);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, -1, tri, 1, p, &own, 1, d, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, -1, p, &own, 1, d, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, -1, d, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, (int64_t)1 << 50, d, &out), MFG_ERR_INVALID);
    int64_t badtri[3] = {0, 1, 3};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, badtri, 1, p, &own, 1, d, &out), MFG_ERR_INVALID);
    CHECK(strstr(mfg_last_error(), "triangle 0") != NULL);
    int64_t badown = 1;
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &badown, 1, d, &out), MFG_ERR_INVALID);
    badown = -2;
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &badown, 1, d, &out), MFG_ERR_INVALID);
    double zero[3] = {0, 0, 0}, nand[3] = {0, NAN, 1}, infd[3] = {INFINITY, 0, 0};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, 1, zero, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, 1, nand, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, p, &own, 1, infd, &out), MFG_ERR_INVALID);
    double nanp[3] = {0, 0, NAN}, hugep[3] = {1e300, 0, 0};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, nanp, &own, 1, d, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, hugep, &own, 1, d, &out), MFG_ERR_INVALID);
    double nanxyz[9] = {0, 0, 0, 1, NAN, 0, 0, 1, 0};
    CHECK_EQ_INT(mfg_ray_blocked(nanxyz, 3, tri, 1, p, &own, 1, d, &out), MFG_ERR_INVALID);
    CHECK_EQ_INT(out, 0x55); /* never written on failure */
    /* Empty inputs are fine. */
    CHECK_EQ_INT(mfg_ray_blocked(NULL, 0, NULL, 0, p, NULL, 1, d, &out), MFG_OK);
    CHECK_EQ_INT(out, 0);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 3, tri, 1, NULL, NULL, 0, d, NULL), MFG_OK);
    /* Extreme but accepted magnitudes. */
    double tiny[9] = {0, 0, 0, 1e-55, 0, 0, 0, 1e-55, 0}, ptiny[3] = {2e-56, 2e-56, -1e50};
    CHECK_EQ_INT(mfg_ray_blocked(tiny, 3, tri, 1, ptiny, NULL, 1, d, &out), MFG_OK);
    CHECK_EQ_INT(out, POS);
}

/* ---- Speed: a fine sphere, 10^5 triangles and 10^5 points (printed, not asserted) ---- */

static void test_speed(int print)
{
    int nu = 250, nv = 200; /* 2 * nu * (nv - 1) ~ 10^5 triangles */
    int64_t nvert = (int64_t)nu * (nv + 1), nt = 0;
    double *xyz = malloc(sizeof(double) * 3 * (size_t)nvert);
    int64_t *tris = malloc(sizeof(int64_t) * 6 * (size_t)nu * (size_t)nv);
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i < nu; i++) {
            double th = M_PI * j / nv, ph = 2 * M_PI * i / nu;
            double *x = xyz + 3 * ((int64_t)j * nu + i);
            x[0] = sin(th) * cos(ph), x[1] = sin(th) * sin(ph), x[2] = cos(th);
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            int64_t a = (int64_t)j * nu + i, b = (int64_t)j * nu + (i + 1) % nu;
            int64_t c = a + nu, e = b + nu;
            if (j > 0) {
                tris[3 * nt] = a, tris[3 * nt + 1] = c, tris[3 * nt + 2] = b;
                nt++;
            }
            if (j < nv - 1) {
                tris[3 * nt] = b, tris[3 * nt + 1] = c, tris[3 * nt + 2] = e;
                nt++;
            }
        }
    int64_t np = 100000;
    double *pts = malloc(sizeof(double) * 3 * (size_t)np);
    int64_t *own = malloc(sizeof(int64_t) * (size_t)np);
    uint8_t *out = malloc((size_t)np);
    for (int64_t i = 0; i < np; i++) {
        int64_t t = i % nt;
        for (int k = 0; k < 3; k++)
            pts[3 * i + k] = (xyz[3 * tris[3 * t] + k] + xyz[3 * tris[3 * t + 1] + k] +
                              xyz[3 * tris[3 * t + 2] + k]) / 3.0;
        own[i] = t;
    }
    double d[3] = {0.3, -0.2, 0.9};
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECK_EQ_INT(mfg_ray_blocked(xyz, nvert, tris, nt, pts, own, np, d, out), MFG_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    /* On the convex sphere, a centroid is free on exactly the side its triangle faces. */
    int64_t wrong = 0;
    for (int64_t i = 0; i < np; i++) {
        int64_t t = own[i];
        const double *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1], *c = xyz + 3 * tris[3 * t + 2];
        int dn = mfg_orient3d_vec(a, b, c, d);
        uint8_t expect = dn > 0 ? NEG : (dn < 0 ? POS : 0);
        if ((out[i] & (POS | NEG)) != expect)
            wrong++;
    }
    CHECK_EQ_INT(wrong, 0);
    if (print)
        printf("sphere: %lld triangles, %lld points: %.3f s\n", (long long)nt, (long long)np,
               (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
    free(xyz);
    free(tris);
    free(pts);
    free(own);
    free(out);
}

/* An open tube of long strips seen from the side (the grid's cells follow the strips'
 * shape): with d normal to the axis a centroid is free exactly on the side its strip
 * faces. */
static void test_tube_strips(void)
{
    int n = 3000;
    double *xyz = malloc(sizeof(double) * 6 * (size_t)n);
    int64_t *tris = malloc(sizeof(int64_t) * 6 * (size_t)n);
    for (int k = 0; k < n; k++) {
        double th = 2 * M_PI * k / n;
        double *lo = xyz + 3 * k, *hi = xyz + 3 * (n + k);
        lo[0] = hi[0] = cos(th), lo[1] = hi[1] = sin(th), lo[2] = 0, hi[2] = 100;
        int64_t k1 = (k + 1) % n;
        int64_t *t = tris + 6 * k;
        t[0] = k, t[1] = k1, t[2] = k1 + n, t[3] = k, t[4] = k1 + n, t[5] = k + n;
    }
    int64_t nt = 2 * (int64_t)n;
    double *pts = malloc(sizeof(double) * 3 * (size_t)nt);
    int64_t *own = malloc(sizeof(int64_t) * (size_t)nt);
    uint8_t *out = malloc((size_t)nt);
    for (int64_t t = 0; t < nt; t++) {
        for (int k = 0; k < 3; k++)
            pts[3 * t + k] = (xyz[3 * tris[3 * t] + k] + xyz[3 * tris[3 * t + 1] + k] +
                              xyz[3 * tris[3 * t + 2] + k]) / 3.0;
        own[t] = t;
    }
    double d[3] = {0.8, -0.6, 0};
    CHECK_EQ_INT(mfg_ray_blocked(xyz, 2 * (int64_t)n, tris, nt, pts, own, nt, d, out), MFG_OK);
    int64_t wrong = 0;
    for (int64_t t = 0; t < nt; t++) {
        const double *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1], *c = xyz + 3 * tris[3 * t + 2];
        int dn = mfg_orient3d_vec(a, b, c, d);
        uint8_t expect = dn > 0 ? NEG : (dn < 0 ? POS : 0);
        wrong += (out[t] & (POS | NEG)) != expect;
    }
    CHECK_EQ_INT(wrong, 0);
    free(xyz);
    free(tris);
    free(pts);
    free(own);
    free(out);
}

int main(int argc, char **argv)
{
    test_tube_strips();
    test_orient3d_vec();
    test_hostile();
    test_edges_vertices();
    test_shadowed_face();
    test_voxel_solids();
    test_rotated();
    test_random_soups_long_double();
    test_lattice_soups_exact();
    test_speed(argc > 1 && strcmp(argv[1], "speed") == 0);
    return mfg_test_report("demould_rays");
}
