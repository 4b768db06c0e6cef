/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_medial_bvh.c - the medial surface's distance field (medial/bvh.c) against brute
 * force over all elements (md_dist_closed, md_nearest_set_brute) and a solid-angle
 * winding number, at random points inside, outside and near the boundary of a cuboid, the
 * L-bracket, a grid-tessellated cube, a random affine image of a geodesic sphere and a
 * UV sphere; the same answers from two threads at once; and the query cost on UV
 * spheres of 1.5k .. 100k triangles (printed, not asserted). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "medial/medial.h"
#include "medial_solids.h"
#include "mfg_test.h"
#include "mfgeom.h"

typedef struct dmesh {
    double *xyz;
    int64_t *tri;
    int64_t nv, nt, cv, ct;
} dmesh;

static void mesh_free(dmesh *m)
{
    free(m->xyz);
    free(m->tri);
    memset(m, 0, sizeof *m);
}

static int64_t add_v(dmesh *m, double x, double y, double z)
{
    if (m->nv == m->cv) {
        m->cv = m->cv ? 2 * m->cv : 64;
        m->xyz = realloc(m->xyz, (size_t)(3 * m->cv) * sizeof *m->xyz);
    }
    m->xyz[3 * m->nv] = x;
    m->xyz[3 * m->nv + 1] = y;
    m->xyz[3 * m->nv + 2] = z;
    return m->nv++;
}

/* The vertex with these coordinates, added when new (small meshes only). */
static int64_t vtx(dmesh *m, double x, double y, double z)
{
    for (int64_t i = 0; i < m->nv; i++)
        if (m->xyz[3 * i] == x && m->xyz[3 * i + 1] == y && m->xyz[3 * i + 2] == z)
            return i;
    return add_v(m, x, y, z);
}

static void tri(dmesh *m, int64_t a, int64_t b, int64_t c)
{
    if (m->nt == m->ct) {
        m->ct = m->ct ? 2 * m->ct : 64;
        m->tri = realloc(m->tri, (size_t)(3 * m->ct) * sizeof *m->tri);
    }
    m->tri[3 * m->nt] = a;
    m->tri[3 * m->nt + 1] = b;
    m->tri[3 * m->nt + 2] = c;
    m->nt++;
}

/* A mesh of medial_solids.h (the cuboid, the L-bracket, the grid cube) as a dmesh. */
static void from_tmesh(dmesh *m, const tmesh *t)
{
    memset(m, 0, sizeof *m);
    for (int64_t i = 0; i < t->nv; i++)
        add_v(m, t->xyz[3 * i], t->xyz[3 * i + 1], t->xyz[3 * i + 2]);
    for (int64_t i = 0; i < t->nt; i++)
        tri(m, t->tri[3 * i], t->tri[3 * i + 1], t->tri[3 * i + 2]);
}

/* Box [0,a] x [0,b] x [0,c], each face a k x k grid (ms_grid_box). */
static void grid_box(dmesh *m, double a, double b, double c, int k)
{
    static tmesh t; /* 73 kB: not on the stack */
    ms_grid_box(&t, a, b, c, k);
    from_tmesh(m, &t);
}

/* L-bracket: arms [0,10] x [0,50] and [0,50] x [0,10], extruded over z in [0, 40]. */
static void l_bracket(dmesh *m)
{
    static tmesh t;
    ms_l_bracket(&t);
    from_tmesh(m, &t);
}

/* The icosahedron subdivided once (80 triangles) on the unit sphere, then a random
 * rotation, unequal scales, a shear and a shift: a convex polyhedron with no two faces
 * coplanar and no axis-aligned feature. */
static void random_convex(dmesh *m)
{
    memset(m, 0, sizeof *m);
    const double g = (1 + sqrt(5.0)) / 2;
    static const int F[20][3] = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                 {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                 {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                 {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
    double V[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                       {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    dmesh s;
    memset(&s, 0, sizeof s);
    for (int i = 0; i < 12; i++) {
        double l = sqrt(V[i][0] * V[i][0] + V[i][1] * V[i][1] + V[i][2] * V[i][2]);
        add_v(&s, V[i][0] / l, V[i][1] / l, V[i][2] / l);
    }
    for (int f = 0; f < 20; f++) {
        int64_t c[3], mid[3];
        for (int k = 0; k < 3; k++)
            c[k] = F[f][k];
        for (int k = 0; k < 3; k++) {
            const double *p = s.xyz + 3 * c[k], *q = s.xyz + 3 * c[(k + 1) % 3];
            double h[3] = {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
            double l = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
            mid[k] = vtx(&s, h[0] / l, h[1] / l, h[2] / l);
        }
        tri(&s, c[0], mid[0], mid[2]);
        tri(&s, mid[0], c[1], mid[1]);
        tri(&s, mid[2], mid[1], c[2]);
        tri(&s, mid[0], mid[1], mid[2]);
    }
    /* M = Rot(q) diag(30, 21, 13) (I + shear), q a random unit quaternion. */
    double q[4], ql = 0;
    for (int k = 0; k < 4; k++) {
        q[k] = rng_uniform(-1, 1);
        ql += q[k] * q[k];
    }
    ql = sqrt(ql);
    for (int k = 0; k < 4; k++)
        q[k] /= ql;
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double R[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    double S[3] = {30, 21, 13}, sh[3] = {0.3, -0.2, 0.25}, off[3] = {7.5, -3.25, 11.0};
    memset(m, 0, sizeof *m);
    for (int64_t i = 0; i < s.nv; i++) {
        const double *p = s.xyz + 3 * i;
        double u[3] = {p[0] + sh[0] * p[1] + sh[1] * p[2], p[1] + sh[2] * p[2], p[2]}, r[3];
        for (int a = 0; a < 3; a++) {
            r[a] = off[a];
            for (int b = 0; b < 3; b++)
                r[a] += R[a][b] * S[b] * u[b];
        }
        add_v(m, r[0], r[1], r[2]);
    }
    for (int64_t t = 0; t < s.nt; t++)
        tri(m, s.tri[3 * t], s.tri[3 * t + 1], s.tri[3 * t + 2]);
    mesh_free(&s);
}

/* UV sphere of radius r about (1, 2, 3): nlat bands, nlon meridians, 2 nlon (nlat - 1)
 * triangles (the quads between two rings are planar: faces of 2 triangles). */
static void uv_sphere(dmesh *m, double r, int nlon, int nlat)
{
    memset(m, 0, sizeof *m);
    const double c[3] = {1, 2, 3};
    int64_t np = add_v(m, c[0], c[1], c[2] + r);
    for (int i = 1; i < nlat; i++) {
        double th = M_PI * i / nlat;
        for (int j = 0; j < nlon; j++) {
            double ph = 2 * M_PI * j / nlon;
            add_v(m, c[0] + r * sin(th) * cos(ph), c[1] + r * sin(th) * sin(ph), c[2] + r * cos(th));
        }
    }
    int64_t sp = add_v(m, c[0], c[1], c[2] - r);
#define RING(i, j) (1 + (int64_t)((i)-1) * nlon + ((j) % nlon))
    for (int j = 0; j < nlon; j++) {
        tri(m, np, RING(1, j), RING(1, j + 1));
        tri(m, sp, RING(nlat - 1, j + 1), RING(nlat - 1, j));
    }
    for (int i = 1; i < nlat - 1; i++)
        for (int j = 0; j < nlon; j++) {
            tri(m, RING(i, j), RING(i + 1, j), RING(i + 1, j + 1));
            tri(m, RING(i, j), RING(i + 1, j + 1), RING(i, j + 1));
        }
#undef RING
}

/* ---- references ---------------------------------------------------------------------- */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Winding number of the mesh about x (solid angles, Van Oosterom & Strackee): 1 inside,
 * 0 outside; shares nothing with the pseudonormals. */
static int winding_inside(const dmesh *m, const double *x)
{
    double sum = 0;
    for (int64_t t = 0; t < m->nt; t++) {
        double v[3][3], l[3];
        for (int j = 0; j < 3; j++) {
            for (int k = 0; k < 3; k++)
                v[j][k] = m->xyz[3 * m->tri[3 * t + j] + k] - x[k];
            l[j] = sqrt(v[j][0] * v[j][0] + v[j][1] * v[j][1] + v[j][2] * v[j][2]);
        }
        double cx = v[1][1] * v[2][2] - v[1][2] * v[2][1], cy = v[1][2] * v[2][0] - v[1][0] * v[2][2],
               cz = v[1][0] * v[2][1] - v[1][1] * v[2][0];
        double det = v[0][0] * cx + v[0][1] * cy + v[0][2] * cz;
#define D3(a, b) (v[a][0] * v[b][0] + v[a][1] * v[b][1] + v[a][2] * v[b][2])
        double den = l[0] * l[1] * l[2] + D3(0, 1) * l[2] + D3(0, 2) * l[1] + D3(1, 2) * l[0];
#undef D3
        sum += 2 * atan2(det, den);
    }
    return sum > 2 * M_PI;
}

/* A random point: in the bounding box grown by 15 % (3 in 4), or near a random point of
 * a random triangle (often one of its sides or corners), off by up to 2 % of L. */
static void random_point(const dmesh *m, const md_elements *el, const double *lo,
                         const double *hi, double *x)
{
    if (rng_int(0, 3) > 0) {
        for (int k = 0; k < 3; k++) {
            double g = 0.15 * (hi[k] - lo[k]);
            x[k] = rng_uniform(lo[k] - g, hi[k] + g);
        }
        return;
    }
    const int64_t *tv = m->tri + 3 * rng_int(0, m->nt - 1);
    double b[3] = {rng_uniform(0, 1), rng_uniform(0, 1), 0};
    if (b[0] + b[1] > 1)
        b[0] = 1 - b[0], b[1] = 1 - b[1];
    b[2] = 1 - b[0] - b[1];
    int snap = (int)rng_int(0, 2);
    if (snap == 1) { /* a side */
        b[2] = 0, b[1] = 1 - b[0];
    } else if (snap == 2) { /* a corner */
        b[0] = 1, b[1] = b[2] = 0;
    }
    double d[3], dl = 0, s = rng_uniform(1e-6, 0.02) * el->diag;
    for (int k = 0; k < 3; k++) {
        d[k] = rng_uniform(-1, 1);
        dl += d[k] * d[k];
    }
    dl = sqrt(dl);
    for (int k = 0; k < 3; k++)
        x[k] = b[0] * m->xyz[3 * tv[0] + k] + b[1] * m->xyz[3 * tv[1] + k] +
               b[2] * m->xyz[3 * tv[2] + k] + s * d[k] / dl;
}

static void seg_closest(const double *x, const double *a, const double *b, double *q)
{
    double ab[3], ax[3];
    for (int k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], ax[k] = x[k] - a[k];
    double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    double t = l2 > 0 ? (ax[0] * ab[0] + ax[1] * ab[1] + ax[2] * ab[2]) / l2 : 0;
    t = t < 0 ? 0 : (t > 1 ? 1 : t);
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + t * ab[k];
}

static double d2(const double *a, const double *b)
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]);
}

/* Closest point of element e's closure to x: the vertex; the segment's projection; for a
 * face, the plane's foot when it falls inside one of its triangles (signs of the three
 * sides' cross products), else the nearest point on their sides (not Ericson's regions). */
static void elem_closest(const md_elements *el, int64_t e, const double *x, double *q)
{
    int kind = md_kind(el, e);
    if (kind == MD_VERTEX) {
        memcpy(q, el->vert_xyz + 3 * (e - el->nfaces - el->nedges), 3 * sizeof *q);
        return;
    }
    if (kind == MD_EDGE) {
        const double *A = el->edge_seg + 6 * (e - el->nfaces);
        seg_closest(x, A, A + 3, q);
        return;
    }
    double best = INFINITY;
    for (int64_t i = el->face_tri_offsets[e]; i < el->face_tri_offsets[e + 1]; i++) {
        const int64_t *tv = el->tris + 3 * el->face_tris[i];
        const double *P[3] = {el->xyz + 3 * tv[0], el->xyz + 3 * tv[1], el->xyz + 3 * tv[2]};
        double u[3], v[3], n[3], r[3];
        for (int k = 0; k < 3; k++)
            u[k] = P[1][k] - P[0][k], v[k] = P[2][k] - P[0][k];
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        double s = ((x[0] - P[0][0]) * n[0] + (x[1] - P[0][1]) * n[1] + (x[2] - P[0][2]) * n[2]) / nn;
        double f[3] = {x[0] - s * n[0], x[1] - s * n[1], x[2] - s * n[2]};
        int in = 1;
        for (int k = 0; k < 3; k++) {
            const double *a = P[k], *b = P[(k + 1) % 3];
            double c[3], ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
                         af[3] = {f[0] - a[0], f[1] - a[1], f[2] - a[2]};
            c[0] = ab[1] * af[2] - ab[2] * af[1];
            c[1] = ab[2] * af[0] - ab[0] * af[2];
            c[2] = ab[0] * af[1] - ab[1] * af[0];
            in = in && c[0] * n[0] + c[1] * n[1] + c[2] * n[2] >= 0;
        }
        if (in) {
            if (d2(x, f) < best)
                best = d2(x, f), memcpy(q, f, sizeof f);
            continue;
        }
        for (int k = 0; k < 3; k++) {
            seg_closest(x, P[k], P[(k + 1) % 3], r);
            if (d2(x, r) < best)
                best = d2(x, r), memcpy(q, r, sizeof r);
        }
    }
}

/* Brute force: the distance to the boundary (min over the elements' closures, dc[] gets
 * each) and the reference candidates for the nearest element: among the elements within
 * D + delta, those that are the lowest-dimensional at their own closest point (no element
 * of lower dimension has its closest point within delta of it).  The element whose
 * relative interior holds a nearest point is the lowest-dimensional one whose closure
 * holds it; comparing feet, not distances, keeps a foot 1e-4 from an edge (its distance
 * then 1e-8 larger, second order) on the face. */
static double brute_nearest(const md_elements *el, const double *x, double delta, int64_t *cand,
                            int64_t *ncand, double *dc)
{
    double D = INFINITY;
    for (int64_t e = 0; e < el->nelements; e++) {
        dc[e] = md_dist_closed(el, e, x);
        D = fmin(D, dc[e]);
    }
    int64_t near[256], nn = 0;
    double q[256][3];
    for (int64_t e = 0; e < el->nelements && nn < 256; e++)
        if (dc[e] <= D + delta) {
            elem_closest(el, e, x, q[nn]);
            near[nn++] = e;
        }
    *ncand = 0;
    for (int64_t i = 0; i < nn; i++) {
        int lowest = 1;
        for (int64_t j = 0; j < nn && lowest; j++)
            if (md_kind(el, near[j]) < md_kind(el, near[i]) && d2(q[i], q[j]) <= delta * delta)
                lowest = 0;
        if (lowest)
            cand[(*ncand)++] = near[i];
    }
    return D;
}

static int contains(const int64_t *l, int64_t n, int64_t v)
{
    for (int64_t i = 0; i < n; i++)
        if (l[i] == v)
            return 1;
    return 0;
}

/* Everything md_bvh_nearest and md_bvh_within answer at npoints random points, against
 * brute force over all elements. */
static void check_solid(const char *name, dmesh *m, int npoints)
{
    md_elements el;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = 0; i < m->nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], m->xyz[3 * i + k]);
            hi[k] = fmax(hi[k], m->xyz[3 * i + k]);
        }
    double L = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                    (hi[2] - lo[2]) * (hi[2] - lo[2]));
    mfg_status st = md_elements_build(m->xyz, m->nv, m->tri, m->nt, L / 50, &el);
    CHECK_EQ_INT(st, MFG_OK);
    if (st != MFG_OK) {
        fprintf(stderr, "  %s: %s\n", name, mfg_last_error());
        return;
    }
    md_bvh *bvh = NULL;
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    if (!bvh) {
        md_elements_free(&el);
        return;
    }
    size_t ne = (size_t)el.nelements;
    int64_t *cand = malloc(ne * sizeof *cand), *set = malloc(ne * sizeof *set),
            *got = malloc(ne * sizeof *got);
    double *dc = malloc(ne * sizeof *dc);
    const double tie = 1e-9 * L, tight = 1e-12 * L;
    int bad_d = 0, bad_e = 0, bad_in = 0, bad_inside_D = 0, bad_w = 0, bad_cap = 0;
    int ninside = 0, nnear = 0, nwithin = 0;
    double worst = 0;
    for (int i = 0; i < npoints; i++) {
        double x[3];
        random_point(m, &el, lo, hi, x);
        int64_t nc, e = -2;
        int inside = -1;
        double Dref = brute_nearest(&el, x, tie, cand, &nc, dc);
        double D = md_bvh_nearest(bvh, &el, x, &e, &inside);
        worst = fmax(worst, fabs(D - Dref));
        bad_d += !(fabs(D - Dref) <= tight);
        if (!contains(cand, nc, e)) {
            bad_e++;
            if (bad_e <= 3)
                fprintf(stderr, "  %s: x (%.17g, %.17g, %.17g): element %lld (kind %d, closed "
                        "distance %.17g), expected one of %lld starting %lld (kind %d), D %.17g\n",
                        name, x[0], x[1], x[2], (long long)e, e >= 0 ? md_kind(&el, e) : -1,
                        e >= 0 ? dc[e] : NAN, (long long)nc, (long long)cand[0],
                        md_kind(&el, cand[0]), Dref);
        }
        /* The pseudonormal sign against the winding number (not on the boundary). */
        if (Dref > tie) {
            int win = winding_inside(m, x);
            bad_in += inside != win;
            if (win) {
                /* Inside: D is min_e md_dist and the element is one of its minimisers. */
                double Db;
                int64_t n = md_nearest_set_brute(&el, x, tie, set, &Db);
                bad_inside_D += !(fabs(Db - D) <= tight) || !contains(set, n, e);
                ninside++;
            }
        }
        nnear += Dref < 0.02 * L;
        /* Balls: random radii, and exactly touching the boundary. */
        double R = (i % 3 == 0) ? Dref : rng_uniform(0, 0.4) * L;
        int64_t n = md_bvh_within(bvh, &el, x, R, got, (int64_t)ne);
        int ok = n >= 0 && n <= (int64_t)ne;
        for (int64_t j = 1; ok && j < n; j++)
            ok = got[j - 1] < got[j]; /* ascending, no duplicates */
        for (int64_t f = 0, j = 0; ok && f < (int64_t)ne; f++) {
            int in_got = j < n && got[j] == f;
            j += in_got;
            /* Only elements within rounding of the sphere may go either way. */
            if (in_got != (dc[f] <= R) && fabs(dc[f] - R) > tie)
                ok = 0;
        }
        bad_w += !ok;
        nwithin += (int)n;
        /* Too little room: the same count, the smallest ids first. */
        if (n > 2) {
            int64_t small[2];
            int64_t n2 = md_bvh_within(bvh, &el, x, R, small, 2);
            int64_t n0 = md_bvh_within(bvh, &el, x, R, NULL, 0);
            bad_cap += n2 != n || n0 != n || small[0] != got[0] || small[1] != got[1];
        }
    }
    CHECK_EQ_INT(bad_d, 0);
    CHECK_EQ_INT(bad_e, 0);
    CHECK_EQ_INT(bad_in, 0);
    CHECK_EQ_INT(bad_inside_D, 0);
    CHECK_EQ_INT(bad_w, 0);
    CHECK_EQ_INT(bad_cap, 0);
    CHECK(ninside > npoints / 10);
    printf("  %-16s %6lld triangles %6lld elements: %d points (%d inside, %d near the boundary), "
           "worst |D - brute| %.2g, mean |within| %.1f\n",
           name, (long long)m->nt, (long long)el.nelements, npoints, ninside, nnear, worst,
           (double)nwithin / npoints);
    free(cand);
    free(set);
    free(got);
    free(dc);
    md_bvh_free(bvh);
    md_elements_free(&el);
}

static void test_solids(void)
{
    dmesh m;
    grid_box(&m, 100, 60, 20, 1);
    check_solid("cuboid", &m, 4000);
    mesh_free(&m);
    l_bracket(&m);
    check_solid("L-bracket", &m, 4000);
    mesh_free(&m);
    grid_box(&m, 40, 40, 40, 8);
    check_solid("grid cube 8x8", &m, 1500);
    mesh_free(&m);
    random_convex(&m);
    /* The fixture is convex: every vertex on the inner side of every triangle's plane. */
    int convex = 1;
    for (int64_t t = 0; t < m.nt; t++) {
        const double *a = m.xyz + 3 * m.tri[3 * t], *b = m.xyz + 3 * m.tri[3 * t + 1],
                     *c = m.xyz + 3 * m.tri[3 * t + 2];
        double u[3], v[3], n[3];
        for (int k = 0; k < 3; k++)
            u[k] = b[k] - a[k], v[k] = c[k] - a[k];
        n[0] = u[1] * v[2] - u[2] * v[1];
        n[1] = u[2] * v[0] - u[0] * v[2];
        n[2] = u[0] * v[1] - u[1] * v[0];
        for (int64_t i = 0; i < m.nv; i++) {
            const double *p = m.xyz + 3 * i;
            if ((p[0] - a[0]) * n[0] + (p[1] - a[1]) * n[1] + (p[2] - a[2]) * n[2] > 1e-9)
                convex = 0;
        }
    }
    CHECK(convex);
    check_solid("random convex", &m, 3000);
    mesh_free(&m);
    uv_sphere(&m, 50, 24, 12);
    check_solid("UV sphere", &m, 1000);
    mesh_free(&m);
}

/* Points of the medial surface of axis-aligned solids, where several faces are exactly
 * equally near (the distances come out bit-equal: the normal coordinate of every foot is
 * exact): the smallest face id wins, whatever the traversal order. */
static void test_ties(void)
{
    static const struct { double a, b, c; int k; double x[3]; int nfaces; } cases[] = {
        {100, 60, 20, 1, {50, 30, 10}, 2},  /* {z0, z1} */
        {100, 60, 20, 1, {10, 30, 10}, 3},  /* {x0, z0, z1} */
        {100, 60, 20, 1, {30, 10, 10}, 3},  /* {y0, z0, z1} */
        {100, 60, 20, 1, {10, 10, 10}, 4},  /* a junction: {x0, y0, z0, z1} */
        {100, 60, 20, 1, {90, 50, 10}, 4},
        {40, 40, 40, 8, {20, 20, 20}, 6},   /* the cube's centre: all six */
        {40, 40, 40, 8, {20, 20, 7.5}, 1},  /* z0 alone */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        dmesh m;
        grid_box(&m, cases[c].a, cases[c].b, cases[c].c, cases[c].k);
        md_elements el;
        md_bvh *bvh = NULL;
        if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 1.0, &el) != MFG_OK) {
            CHECK(0);
            mesh_free(&m);
            continue;
        }
        CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
        const double *x = cases[c].x;
        int64_t e = -1, first = -1;
        int inside = 0, n = 0;
        double D = md_bvh_nearest(bvh, &el, x, &e, &inside);
        for (int64_t f = 0; f < el.nelements; f++)
            if (fabs(md_dist_closed(&el, f, x) - D) <= 1e-12 && md_kind(&el, f) == MD_FACE) {
                n++;
                if (first < 0)
                    first = f;
            }
        CHECK_EQ_INT(n, cases[c].nfaces);
        CHECK_EQ_INT(e, first);
        CHECK_EQ_INT(inside, 1);
        md_bvh_free(bvh);
        md_elements_free(&el);
        mesh_free(&m);
    }
}

/* ---- threads -------------------------------------------------------------------------- */

typedef struct job {
    const md_bvh *bvh;
    const md_elements *el;
    const double *pts;
    int n;
    double *D;
    int64_t *e, *cnt;
    int *in;
} job;

static void *run_job(void *arg)
{
    job *j = arg;
    int64_t buf[64];
    for (int i = 0; i < j->n; i++) {
        j->D[i] = md_bvh_nearest(j->bvh, j->el, j->pts + 3 * i, &j->e[i], &j->in[i]);
        j->cnt[i] = md_bvh_within(j->bvh, j->el, j->pts + 3 * i, 0.1 * j->el->diag, buf, 64);
    }
    return NULL;
}

/* Two threads querying one BVH at once get the single-threaded answers bit for bit. */
static void test_threads(void)
{
    dmesh m;
    uv_sphere(&m, 50, 64, 32);
    md_elements el;
    md_bvh *bvh = NULL;
    if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 1.0, &el) != MFG_OK) {
        CHECK(0);
        mesh_free(&m);
        return;
    }
    CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
    enum { N = 4000 };
    static double pts[3 * N], D[3][N];
    static int64_t e[3][N], cnt[3][N];
    static int in[3][N];
    for (int i = 0; i < 3 * N; i++)
        pts[i] = rng_uniform(-60, 60);
    job jobs[3];
    for (int k = 0; k < 3; k++)
        jobs[k] = (job){bvh, &el, pts, N, D[k], e[k], cnt[k], in[k]};
    run_job(&jobs[0]);
    pthread_t th[2];
    for (int k = 0; k < 2; k++)
        CHECK_EQ_INT(pthread_create(&th[k], NULL, run_job, &jobs[k + 1]), 0);
    for (int k = 0; k < 2; k++)
        pthread_join(th[k], NULL);
    int diff = 0;
    for (int k = 1; k < 3; k++)
        for (int i = 0; i < N; i++)
            diff += D[k][i] != D[0][i] || e[k][i] != e[0][i] || cnt[k][i] != cnt[0][i] ||
                    in[k][i] != in[0][i];
    CHECK_EQ_INT(diff, 0);
    md_bvh_free(bvh);
    md_elements_free(&el);
    mesh_free(&m);
}

/* ---- cost ------------------------------------------------------------------------------ */

/* UV spheres from 1.5k to 100k triangles: build time, per-query times of nearest and
 * within (R = 2 % of L) at points uniform in the bounding box and at points within 1 % of
 * L of the sphere, against brute force over all elements (the BVH's answers are checked
 * on a few points of each).  Printed only: speed targets live in bench/.  (Uniform points
 * near the centre are the BVH's worst case: every triangle there is nearly as near as
 * the nearest.) */
static void test_cost(void)
{
    static const int sizes[4][2] = {{32, 25}, {64, 50}, {128, 100}, {256, 200}};
    printf("  %9s %9s %9s | %-23s | %-23s | %s\n", "triangles", "elements", "build ms",
           "uniform: nearest within", "near: nearest within", "brute us/query");
    for (int s = 0; s < 4; s++) {
        dmesh m;
        uv_sphere(&m, 50, sizes[s][0], sizes[s][1]);
        md_elements el;
        double t0 = now();
        if (md_elements_build(m.xyz, m.nv, m.tri, m.nt, 1e-3, &el) != MFG_OK) {
            CHECK(0);
            fprintf(stderr, "  %s\n", mfg_last_error());
            mesh_free(&m);
            continue;
        }
        double t1 = now();
        md_bvh *bvh = NULL;
        CHECK_EQ_INT(md_bvh_build(&el, &bvh), MFG_OK);
        double t2 = now();
        enum { NQ = 20000, NB = 10 };
        double *pts = malloc(2 * 3 * NQ * sizeof *pts), sink = 0, us[2][2];
        for (int i = 0; i < NQ; i++) {
            double *u = pts + 3 * i, *v = pts + 3 * (NQ + i), d[3], dl = 0;
            for (int k = 0; k < 3; k++) {
                u[k] = (k + 1) + rng_uniform(-55, 55);
                d[k] = rng_uniform(-1, 1);
                dl += d[k] * d[k];
            }
            double r = 50 + rng_uniform(-0.01, 0.01) * el.diag;
            for (int k = 0; k < 3; k++)
                v[k] = (k + 1) + r * d[k] / sqrt(dl);
        }
        int64_t *buf = malloc((size_t)el.nelements * sizeof *buf), e;
        double *dc = malloc((size_t)el.nelements * sizeof *dc);
        int inside;
        for (int set = 0; set < 2; set++) {
            const double *P = pts + 3 * NQ * set;
            double ta = now();
            for (int i = 0; i < NQ; i++)
                sink += md_bvh_nearest(bvh, &el, P + 3 * i, &e, &inside);
            double tb = now();
            for (int i = 0; i < NQ; i++)
                sink += (double)md_bvh_within(bvh, &el, P + 3 * i, 0.02 * el.diag, buf, el.nelements);
            double tc = now();
            us[set][0] = 1e6 * (tb - ta) / NQ;
            us[set][1] = 1e6 * (tc - tb) / NQ;
        }
        int bad = 0;
        double t5 = now();
        for (int i = 0; i < 2 * NB; i++) {
            const double *x = pts + 3 * (i < NB ? i : NQ + i);
            int64_t nc;
            double Dref = brute_nearest(&el, x, 1e-9 * el.diag, buf, &nc, dc);
            double D = md_bvh_nearest(bvh, &el, x, &e, &inside);
            bad += !(fabs(D - Dref) <= 1e-12 * el.diag) || !contains(buf, nc, e);
        }
        double t6 = now();
        CHECK_EQ_INT(bad, 0);
        printf("  %9lld %9lld %9.1f | %8.2f us %8.2f us | %8.2f us %8.2f us | %8.0f us   (elements %.0f ms)\n",
               (long long)m.nt, (long long)el.nelements, 1e3 * (t2 - t1), us[0][0], us[0][1],
               us[1][0], us[1][1], 1e6 * (t6 - t5) / (2 * NB), 1e3 * (t1 - t0));
        CHECK(sink > 0);
        free(pts);
        free(buf);
        free(dc);
        md_bvh_free(bvh);
        md_elements_free(&el);
        mesh_free(&m);
    }
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : "";
    if (!*only || !strcmp(only, "solids"))
        test_solids();
    if (!*only || !strcmp(only, "solids"))
        test_ties();
    if (!*only || !strcmp(only, "threads"))
        test_threads();
    if (!*only || !strcmp(only, "cost"))
        test_cost();
    return mfg_test_report("medial_bvh");
}
