/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* demould_rays.c - the ray test of demouldability (issue 17): does the ray from a sample
 * point along +d or -d leave the part without crossing one of its triangles? */
#include <math.h>
#include <stdlib.h>

#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"

/*
 * All rays are parallel to d, so a ray can only meet a triangle whose projection along d
 * covers the projection of its origin.  The triangles not parallel to d are projected
 * along d onto the coordinate plane most nearly normal to d (dropping the axis k of the
 * largest |d_k|): x -> (x_i - x_k d_i / d_k, x_j - x_k d_j / d_k).  Their projected
 * bounding boxes, padded for rounding, go into a 2-D bounding-volume hierarchy: sorted
 * along a Morton (Z-order) curve of their centres, cut into leaves of LEAF boxes, and a
 * complete binary tree of unions over the leaves (a linear BVH, Lauterbach et al. 2009).
 * A point descends into the nodes whose box holds its projection, O(log n + k): dense
 * patches (a finely meshed fillet on a big coarse part) and long strips (a cylinder seen
 * from the side) cost no more than a uniform mesh, which a uniform grid cannot offer.
 * The tree only selects candidates: whether a ray meets a triangle is decided exactly.
 *
 * Exact test of the line L = {p + s d} against triangle abc (n = (b - a) x (c - a)):
 *   e_ab = sign det[a - p, b - p, d], e_bc, e_ca likewise: L passes every directed edge
 *   on the same side (all +, or all -) iff it pierces the triangle's interior; a zero
 *   among otherwise equal signs: it passes through an edge or a vertex; mixed: it misses.
 *   The crossing is at s* = ((a - p) . n) / (d . n); (a - p) . n = det[a-p, b-p, c-p]
 *   (orient3d(a, b, c, p)) and d . n = det[b - a, c - a, d], so the sign of s* is exact.
 * d . n = 0 (d parallel to the plane, or a zero-area triangle) means no crossing point:
 * such triangles are not filed at all.
 *
 * Rounding of the projection: the computed r = d_i / d_k (|r| <= 1), r * x_k and the
 * difference carry at most 4u (|x_i| + |x_j| + |x_k|) error each (u = 2^-53); a point
 * whose exact projection lies in a triangle's exact projection is within twice that of
 * the computed bounding box.  The pad is 64u times the largest such sum over all the
 * vertices and points: never too small, and far below any feature.
 */

/* Unit roundoff of IEEE double (2^-53). */
#define U 1.1102230246251565e-16
/* The projected boxes' pad in units of u |x|: twice the 4u (|x_i| + |x_j| + |x_k|) a
 * projected coordinate may be off, with room to spare (the comment above). */
#define RAY_PAD_ULPS 64.0

#define LEAF 4 /* boxes per leaf of the tree */

typedef struct ray_proj {
    int axis_i, axis_j, axis_k;
    double ri, rj; /* d_i / d_k, d_j / d_k */
} ray_proj;

typedef struct morton_ref {
    uint32_t code;
    int64_t t;
} morton_ref;

static int cmp_morton(const void *pa, const void *pb)
{
    const morton_ref *a = pa, *b = pb;
    if (a->code != b->code)
        return a->code < b->code ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

/* The 16 bits of x spread to the even bits of the result. */
static uint32_t spread16(uint32_t x)
{
    x &= 0xffff;
    x = (x | (x << 8)) & 0x00ff00ffu;
    x = (x | (x << 4)) & 0x0f0f0f0fu;
    x = (x | (x << 2)) & 0x33333333u;
    x = (x | (x << 1)) & 0x55555555u;
    return x;
}

static uint32_t quantize16(double t, double lo, double scale)
{
    double q = (t - lo) * scale;
    if (!(q > 0))
        return 0;
    return q >= 65535.0 ? 65535u : (uint32_t)q;
}

static inline void project(const ray_proj *g, const double *x, double *u, double *v)
{
    *u = x[g->axis_i] - g->ri * x[g->axis_k];
    *v = x[g->axis_j] - g->rj * x[g->axis_k];
}

/* Sign of s* of the crossing of line p + s d with triangle abc, and where: 2 interior,
 * 1 edge or vertex, 0 no crossing.  dn is the sign of d . n (non-zero). */
static int cross_line(const double *p, const double *a, const double *b, const double *c,
                      const double *d, int dn, int *side)
{
    int e0 = mfg_orient3d_vec(p, a, b, d);
    int e1 = mfg_orient3d_vec(p, b, c, d);
    if (e0 * e1 < 0)
        return 0;
    int e2 = mfg_orient3d_vec(p, c, a, d);
    if (e0 * e2 < 0 || e1 * e2 < 0)
        return 0;
    int sp = mfg_orient3d(a, b, c, p);
    *side = sp * dn;
    if (*side == 0)
        return 0;
    return (e0 != 0 && e1 != 0 && e2 != 0) ? 2 : 1;
}

mfg_status mfg_ray_blocked(const double *xyz, int64_t nvertices, const int64_t *triangles,
                           int64_t ntriangles, const double *points,
                           const int64_t *own_triangle, int64_t npoints,
                           const double direction[3], uint8_t *blocked_out)
{
    return mfg_ray_blocked_p(xyz, nvertices, triangles, ntriangles, points, own_triangle,
                             npoints, direction, blocked_out, NULL);
}

/* Work units between progress reports: a triangle filed (~0.1 us), a point queried
 * (~0.5-2 us on tessellations). */
#define RAY_EVERY_TRIANGLES 65536
#define RAY_EVERY_POINTS 8192

/* The triangles filed for the ray test and their tree (see the comment at the top). */
typedef struct ray_tree {
    ray_proj g;
    int8_t *dn;         /* per triangle: the sign of d . n, 0 not filed */
    double *box;        /* per triangle: its padded projected box (u0, v0, u1, v1) */
    morton_ref *order;  /* the filed triangles in Z-order */
    int64_t nfiled;
    double lo_u, lo_v, hi_u, hi_v; /* the union of the boxes */
    double *node;       /* 4 per node of the complete tree over the leaves */
    int64_t pow2;       /* leaves of the tree (a power of 2) */
} ray_tree;

/* Files the triangles that can be crossed: their sign of d . n and padded boxes.  0 when
 * the progress callback cancels. */
static int file_triangles(ray_tree *T, const double *xyz, const int64_t *triangles,
                          int64_t ntriangles, const double *d, double pad, mfg_prog *prog)
{
    T->nfiled = 0;
    T->lo_u = T->lo_v = INFINITY;
    T->hi_u = T->hi_v = -INFINITY;
    for (int64_t t = 0; t < ntriangles; t++) {
        if (!mfg_prog_poll(prog, (double)t, (double)ntriangles))
            return 0;
        const double *a = xyz + 3 * triangles[3 * t], *b = xyz + 3 * triangles[3 * t + 1];
        const double *c = xyz + 3 * triangles[3 * t + 2];
        T->dn[t] = (int8_t)mfg_orient3d_vec(a, b, c, d);
        if (T->dn[t] == 0)
            continue;
        double u[3], v[3];
        project(&T->g, a, &u[0], &v[0]);
        project(&T->g, b, &u[1], &v[1]);
        project(&T->g, c, &u[2], &v[2]);
        double *bx = T->box + 4 * t;
        bx[0] = fmin(u[0], fmin(u[1], u[2])) - pad;
        bx[1] = fmin(v[0], fmin(v[1], v[2])) - pad;
        bx[2] = fmax(u[0], fmax(u[1], u[2])) + pad;
        bx[3] = fmax(v[0], fmax(v[1], v[2])) + pad;
        T->lo_u = fmin(T->lo_u, bx[0]);
        T->lo_v = fmin(T->lo_v, bx[1]);
        T->hi_u = fmax(T->hi_u, bx[2]);
        T->hi_v = fmax(T->hi_v, bx[3]);
        T->order[T->nfiled].t = t;
        T->nfiled++;
    }
    return 1;
}

/* Z-order of the filed boxes' centres; sets pow2. */
static void order_boxes(ray_tree *T)
{
    double su = T->hi_u > T->lo_u ? 65535.0 / (T->hi_u - T->lo_u) : 0.0;
    double sv = T->hi_v > T->lo_v ? 65535.0 / (T->hi_v - T->lo_v) : 0.0;
    for (int64_t r = 0; r < T->nfiled; r++) {
        const double *bx = T->box + 4 * T->order[r].t;
        uint32_t qu = quantize16(0.5 * bx[0] + 0.5 * bx[2], T->lo_u, su);
        uint32_t qv = quantize16(0.5 * bx[1] + 0.5 * bx[3], T->lo_v, sv);
        T->order[r].code = spread16(qu) | (spread16(qv) << 1);
    }
    qsort(T->order, (size_t)T->nfiled, sizeof *T->order, cmp_morton);
    int64_t nleaves = (T->nfiled + LEAF - 1) / LEAF, pow2 = 1;
    while (pow2 < nleaves)
        pow2 *= 2;
    T->pow2 = pow2;
}

/* The complete tree over the leaves (node has room for 2 pow2 - 1): node k has children
 * 2k+1 and 2k+2; the leaves are nodes pow2 - 1 .. 2 pow2 - 2, leaf l holding
 * order[l * LEAF ..] (fewer in the last, none in the padding). */
static void fill_nodes(ray_tree *T)
{
    int64_t pow2 = T->pow2;
    for (int64_t l = 0; l < pow2; l++) {
        double *nb = T->node + 4 * (pow2 - 1 + l);
        nb[0] = nb[1] = INFINITY;
        nb[2] = nb[3] = -INFINITY;
        for (int64_t r = l * LEAF; r < (l + 1) * LEAF && r < T->nfiled; r++) {
            const double *bx = T->box + 4 * T->order[r].t;
            nb[0] = fmin(nb[0], bx[0]);
            nb[1] = fmin(nb[1], bx[1]);
            nb[2] = fmax(nb[2], bx[2]);
            nb[3] = fmax(nb[3], bx[3]);
        }
    }
    for (int64_t k = pow2 - 2; k >= 0; k--) {
        double *nb = T->node + 4 * k;
        const double *l = T->node + 4 * (2 * k + 1), *r = T->node + 4 * (2 * k + 2);
        nb[0] = fmin(l[0], r[0]);
        nb[1] = fmin(l[1], r[1]);
        nb[2] = fmax(l[2], r[2]);
        nb[3] = fmax(l[3], r[3]);
    }
}

/* The MFG_RAY_* bits of the rays from p along +d and -d (own: the triangle p lies on, or
 * -1).  The tree's depth is log2(pow2) <= 40, so a stack of 64 suffices (each pop pushes
 * at most two). */
static uint8_t ray_query(const ray_tree *T, const double *xyz, const int64_t *triangles,
                         const double *d, const double *p, int64_t own, int64_t *stack)
{
    int64_t pow2 = T->pow2;
    uint8_t bits = 0;
    double pu, pv;
    project(&T->g, p, &pu, &pv);
    int64_t top = 0;
    if (T->nfiled > 0)
        stack[top++] = 0;
    while (top > 0) {
        int64_t k = stack[--top];
        const double *nb = T->node + 4 * k;
        if (pu < nb[0] || pu > nb[2] || pv < nb[1] || pv > nb[3])
            continue;
        if (k < pow2 - 1) {
            stack[top++] = 2 * k + 2;
            stack[top++] = 2 * k + 1;
            continue;
        }
        int64_t l = k - (pow2 - 1);
        for (int64_t r = l * LEAF; r < (l + 1) * LEAF && r < T->nfiled; r++) {
            int64_t t = T->order[r].t;
            if (t == own)
                continue;
            const double *bx = T->box + 4 * t;
            if (pu < bx[0] || pu > bx[2] || pv < bx[1] || pv > bx[3])
                continue;
            const double *a = xyz + 3 * triangles[3 * t];
            const double *b = xyz + 3 * triangles[3 * t + 1];
            const double *cc = xyz + 3 * triangles[3 * t + 2];
            int side = 0;
            int where = cross_line(p, a, b, cc, d, T->dn[t], &side);
            if (where == 2)
                bits |= side > 0 ? MFG_RAY_BLOCKED_POS : MFG_RAY_BLOCKED_NEG;
            else if (where == 1)
                bits |= side > 0 ? MFG_RAY_GRAZES_POS : MFG_RAY_GRAZES_NEG;
        }
        if (bits == (MFG_RAY_BLOCKED_POS | MFG_RAY_BLOCKED_NEG | MFG_RAY_GRAZES_POS |
                     MFG_RAY_GRAZES_NEG))
            break;
    }
    return bits;
}

mfg_status mfg_ray_blocked_p(const double *xyz, int64_t nvertices, const int64_t *triangles,
                             int64_t ntriangles, const double *points,
                             const int64_t *own_triangle, int64_t npoints,
                             const double direction[3], uint8_t *blocked_out,
                             const mfg_progress *progress)
{
    mfg_status st = mfg_mesh_validate(xyz, nvertices, triangles, ntriangles);
    if (st != MFG_OK)
        return st;
    if (npoints < 0 || npoints > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "npoints must be between 0 and %lld (got %lld)",
                        (long long)MFG_MAX_COUNT, (long long)npoints);
    if (!direction)
        return mfg_fail(MFG_ERR_NULL, "direction is NULL");
    if (npoints > 0 && !points)
        return mfg_fail(MFG_ERR_NULL, "points is NULL");
    if (npoints > 0 && !blocked_out)
        return mfg_fail(MFG_ERR_NULL, "blocked_out is NULL");
    for (int k = 0; k < 3; k++)
        if (!mfg_coord_ok(direction[k]))
            return mfg_fail(MFG_ERR_INVALID,
                            "direction has a NaN, infinite or out-of-range component (%g)",
                            direction[k]);
    if (direction[0] == 0 && direction[1] == 0 && direction[2] == 0)
        return mfg_fail(MFG_ERR_INVALID, "direction is the zero vector");
    for (int64_t i = 0; i < 3 * npoints; i++)
        if (!mfg_coord_ok(points[i]))
            return mfg_fail(MFG_ERR_INVALID,
                            "point %lld has a NaN, infinite or out-of-range coordinate (%g)",
                            (long long)(i / 3), points[i]);
    if (own_triangle)
        for (int64_t i = 0; i < npoints; i++)
            if (own_triangle[i] < -1 || own_triangle[i] >= ntriangles)
                return mfg_fail(MFG_ERR_INVALID,
                                "own_triangle[%lld] = %lld is neither -1 nor a triangle index "
                                "0 .. %lld",
                                (long long)i, (long long)own_triangle[i],
                                (long long)(ntriangles - 1));

    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_ray_blocked");
    if (!mfg_prog_stage(&prog, "rays: index", 0, 0.3, RAY_EVERY_TRIANGLES))
        return mfg_prog_fail(&prog);
    const double *d = direction;
    ray_tree T;
    ray_proj *g = &T.g;
    g->axis_k = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(d[k]) > fabs(d[g->axis_k]))
            g->axis_k = k;
    g->axis_i = (g->axis_k + 1) % 3;
    g->axis_j = (g->axis_k + 2) % 3;
    g->ri = d[g->axis_i] / d[g->axis_k];
    g->rj = d[g->axis_j] / d[g->axis_k];

    /* Sizes: counts <= 2^40, so every allocation below is far below SIZE_MAX. */
    T.dn = malloc((size_t)ntriangles + 1);
    T.box = malloc(((size_t)ntriangles + 1) * 4 * sizeof *T.box);
    T.order = malloc(((size_t)ntriangles + 1) * sizeof *T.order);
    T.node = NULL;
    if (!T.dn || !T.box || !T.order) {
        free(T.dn);
        free(T.box);
        free(T.order);
        return mfg_fail(MFG_ERR_NOMEM, "out of memory for the ray test of %lld triangles",
                        (long long)ntriangles);
    }

    /* The pad: 64u times the largest |x| + |y| + |z| of a vertex or a point. */
    double big = 0;
    for (int64_t v = 0; v < nvertices; v++) {
        const double *x = xyz + 3 * v;
        double s = fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
        big = s > big ? s : big;
    }
    for (int64_t i = 0; i < npoints; i++) {
        const double *x = points + 3 * i;
        double s = fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
        big = s > big ? s : big;
    }
    double pad = RAY_PAD_ULPS * U * big + MFG_MIN_COORD;

    if (!file_triangles(&T, xyz, triangles, ntriangles, d, pad, &prog)) {
        free(T.dn);
        free(T.box);
        free(T.order);
        return mfg_prog_fail(&prog);
    }
    order_boxes(&T);
    int64_t nnodes = 2 * T.pow2 - 1;
    T.node = malloc((size_t)nnodes * 4 * sizeof *T.node);
    int64_t *stack = malloc(((size_t)64 + 1) * sizeof *stack);
    /* With progress the flags go to a buffer first: a cancel leaves blocked_out as it was. */
    uint8_t *flags = prog.fn ? malloc((size_t)npoints + 1) : blocked_out;
    if (!T.node || !stack || (prog.fn && !flags)) {
        free(T.dn);
        free(T.box);
        free(T.order);
        free(T.node);
        free(stack);
        if (prog.fn)
            free(flags);
        return mfg_fail(MFG_ERR_NOMEM, "out of memory for the ray tree of %lld triangles",
                        (long long)T.nfiled);
    }
    fill_nodes(&T);

    /* The queries: nothing but a cancel can fail from here on. */
    int go = mfg_prog_stage(&prog, "rays: queries", 0.3, 1.0, RAY_EVERY_POINTS);
    for (int64_t i = 0; i < npoints && go; i++) {
        if (!mfg_prog_poll(&prog, (double)i, (double)npoints)) {
            go = 0;
            break;
        }
        flags[i] = ray_query(&T, xyz, triangles, d, points + 3 * i,
                             own_triangle ? own_triangle[i] : -1, stack);
    }
    if (go)
        go = mfg_prog_stage(&prog, "rays: done", 1.0, 1.0, 1);
    if (go && prog.fn && npoints > 0)
        memcpy(blocked_out, flags, (size_t)npoints);
    if (prog.fn)
        free(flags);
    free(T.dn);
    free(T.box);
    free(T.order);
    free(T.node);
    free(stack);
    if (!go)
        return mfg_prog_fail(&prog);
    mfg_clear_error();
    return MFG_OK;
}
