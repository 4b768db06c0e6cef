/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* battery_index.c - a bounding volume hierarchy over a triangle mesh for the battery's
 * checks: the distance of a point to the surface and an exact point-in-solid test (the
 * parity of a segment's crossings, each decided with sweep_checks.h's exact orient3d), so
 * that checking thousands of turned points against a result costs a few microseconds each
 * instead of a pass over every triangle. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "battery.h"
#include "sweep_checks.h"

/* triangles per leaf: a few, so a leaf costs about as much as a box test on the way */
#define LEAF_SIZE 4
/* the deepest stack a query needs: median splits give depth about log2(n / LEAF_SIZE),
 * 2^60 triangles would not fit in memory */
#define STACK_DEPTH 128
/* node boxes are widened by this fraction of the mesh's magnitude so that the rounded
 * slab test of a segment never misses a triangle the exact test would count (a missed
 * candidate changes the parity; an extra one costs only an exact test) */
#define BOX_SLACK 0x1p-40

typedef struct build_ctx {
    bt_index *ix;
    double *cen;  /* triangle centroids, 3 per triangle */
    double *tbox; /* triangle boxes, 6 per triangle */
} build_ctx;

/* Reorders ids[lo .. hi) so that the k-th smallest by centroid coordinate c is at k, the
 * smaller ones before it, the larger after (quickselect, Hoare partition). */
static void select_kth(int64_t *ids, int64_t lo, int64_t hi, int64_t k, const double *cen, int c)
{
    while (hi - lo > 1) {
        double pivot = cen[3 * ids[lo + (hi - lo) / 2] + c];
        int64_t i = lo, j = hi - 1;
        while (i <= j) {
            while (cen[3 * ids[i] + c] < pivot)
                i++;
            while (cen[3 * ids[j] + c] > pivot)
                j--;
            if (i <= j) {
                int64_t t = ids[i];
                ids[i] = ids[j];
                ids[j] = t;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j + 1;
        else if (k >= i)
            lo = i;
        else
            return;
    }
}

static int64_t build(build_ctx *b, int64_t first, int64_t count)
{
    bt_index *ix = b->ix;
    int64_t n = ix->nnodes++;
    bt_node *node = ix->nodes + n;
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int c = 0; c < 3; c++) {
        node->lo[c] = INFINITY;
        node->hi[c] = -INFINITY;
    }
    for (int64_t i = first; i < first + count; i++) {
        int64_t t = ix->ids[i];
        for (int c = 0; c < 3; c++) {
            node->lo[c] = fmin(node->lo[c], b->tbox[6 * t + c]);
            node->hi[c] = fmax(node->hi[c], b->tbox[6 * t + 3 + c]);
            clo[c] = fmin(clo[c], b->cen[3 * t + c]);
            chi[c] = fmax(chi[c], b->cen[3 * t + c]);
        }
    }
    if (count <= LEAF_SIZE) {
        node->first = first;
        node->count = count;
        node->right = -1;
        return n;
    }
    int axis = 0;
    for (int c = 1; c < 3; c++)
        if (chi[c] - clo[c] > chi[axis] - clo[axis])
            axis = c;
    int64_t half = count / 2;
    select_kth(ix->ids, first, first + count, first + half, b->cen, axis);
    node->first = first;
    node->count = 0;
    build(b, first, half);
    int64_t right = build(b, first + half, count - half);
    ix->nodes[n].right = right; /* the array did not move: it was sized up front */
    return n;
}

int bt_index_build(bt_index *ix, const double *V, const int64_t *T, int64_t nt)
{
    memset(ix, 0, sizeof *ix);
    ix->V = V;
    ix->T = T;
    ix->nt = nt;
    ix->ids = malloc((size_t)(nt + 1) * sizeof *ix->ids);
    ix->nodes = malloc((size_t)(2 * nt + 1) * sizeof *ix->nodes);
    ix->flat = calloc((size_t)nt + 1, 1);
    build_ctx b = {ix, malloc((size_t)(3 * nt + 1) * sizeof(double)), malloc((size_t)(6 * nt + 1) * sizeof(double))};
    if (!ix->ids || !ix->nodes || !ix->flat || !b.cen || !b.tbox) {
        free(b.cen);
        free(b.tbox);
        bt_index_free(ix);
        return 0;
    }
    for (int c = 0; c < 3; c++) {
        ix->box[c] = INFINITY;
        ix->box[3 + c] = -INFINITY;
    }
    double mag = 0;
    for (int64_t t = 0; t < nt; t++) {
        ix->ids[t] = t;
        const double *p[3] = {V + 3 * T[3 * t], V + 3 * T[3 * t + 1], V + 3 * T[3 * t + 2]};
        ix->flat[t] = (unsigned char)zero_area(p[0], p[1], p[2]);
        for (int c = 0; c < 3; c++) {
            double lo = fmin(p[0][c], fmin(p[1][c], p[2][c])), hi = fmax(p[0][c], fmax(p[1][c], p[2][c]));
            b.tbox[6 * t + c] = lo;
            b.tbox[6 * t + 3 + c] = hi;
            b.cen[3 * t + c] = (p[0][c] + p[1][c] + p[2][c]) / 3;
            ix->box[c] = fmin(ix->box[c], lo);
            ix->box[3 + c] = fmax(ix->box[3 + c], hi);
            mag = fmax(mag, fmax(fabs(lo), fabs(hi)));
        }
    }
    if (nt > 0)
        build(&b, 0, nt);
    double slack = BOX_SLACK * mag;
    for (int64_t n = 0; n < ix->nnodes; n++)
        for (int c = 0; c < 3; c++) {
            ix->nodes[n].lo[c] -= slack;
            ix->nodes[n].hi[c] += slack;
        }
    ix->diag = nt > 0 ? sqrt((ix->box[3] - ix->box[0]) * (ix->box[3] - ix->box[0]) +
                             (ix->box[4] - ix->box[1]) * (ix->box[4] - ix->box[1]) +
                             (ix->box[5] - ix->box[2]) * (ix->box[5] - ix->box[2]))
                      : 0;
    free(b.cen);
    free(b.tbox);
    return 1;
}

void bt_index_free(bt_index *ix)
{
    free(ix->ids);
    free(ix->nodes);
    free(ix->flat);
    memset(ix, 0, sizeof *ix);
}

static double box_dist2(const bt_node *n, const double p[3])
{
    double s = 0;
    for (int c = 0; c < 3; c++) {
        double d = p[c] < n->lo[c] ? n->lo[c] - p[c] : p[c] > n->hi[c] ? p[c] - n->hi[c] : 0;
        s += d * d;
    }
    return s;
}

double bt_dist(const bt_index *ix, const double p[3], int64_t *nearest)
{
    double best = INFINITY;
    int64_t best_t = -1;
    if (ix->nnodes == 0)
        return best;
    int64_t stack[STACK_DEPTH];
    int sp = 0;
    stack[sp++] = 0;
    while (sp) {
        const bt_node *n = ix->nodes + stack[--sp];
        if (box_dist2(n, p) >= best * best)
            continue;
        if (n->count) {
            for (int64_t i = n->first; i < n->first + n->count; i++) {
                int64_t t = ix->ids[i];
                const int64_t *v = ix->T + 3 * t;
                double d = tri_dist(p, ix->V + 3 * v[0], ix->V + 3 * v[1], ix->V + 3 * v[2]);
                if (d < best) {
                    best = d;
                    best_t = t;
                }
            }
            continue;
        }
        int64_t l = n - ix->nodes + 1, r = n->right;
        double dl = box_dist2(ix->nodes + l, p), dr = box_dist2(ix->nodes + r, p);
        /* the nearer child is searched first: it lowers `best` for the other */
        if (dl <= dr) {
            stack[sp++] = r;
            stack[sp++] = l;
        } else {
            stack[sp++] = l;
            stack[sp++] = r;
        }
    }
    if (nearest)
        *nearest = best_t;
    return best;
}

int bt_near(const bt_index *ix, const double p[3], double radius, int64_t *ids, int max)
{
    int n = 0;
    if (ix->nnodes == 0)
        return 0;
    int64_t stack[STACK_DEPTH];
    int sp = 0;
    stack[sp++] = 0;
    while (sp && n < max) {
        const bt_node *nd = ix->nodes + stack[--sp];
        if (box_dist2(nd, p) > radius * radius)
            continue;
        if (!nd->count) {
            stack[sp++] = nd->right;
            stack[sp++] = nd - ix->nodes + 1;
            continue;
        }
        for (int64_t i = nd->first; i < nd->first + nd->count && n < max; i++) {
            const int64_t *v = ix->T + 3 * ix->ids[i];
            if (tri_dist(p, ix->V + 3 * v[0], ix->V + 3 * v[1], ix->V + 3 * v[2]) <= radius)
                ids[n++] = ix->ids[i];
        }
    }
    return n;
}

/* Whether the segment p + s d, s in [0, 1], meets the (widened) box: a rounded slab test;
 * the widening covers its rounding. */
static int seg_box(const bt_node *n, const double p[3], const double d[3])
{
    double s0 = 0, s1 = 1;
    for (int c = 0; c < 3; c++) {
        if (d[c] == 0) {
            if (p[c] < n->lo[c] || p[c] > n->hi[c])
                return 0;
            continue;
        }
        double a = (n->lo[c] - p[c]) / d[c], b = (n->hi[c] - p[c]) / d[c];
        if (a > b) {
            double t = a;
            a = b;
            b = t;
        }
        s0 = fmax(s0, a);
        s1 = fmin(s1, b);
        if (s0 > s1)
            return 0;
    }
    return 1;
}

enum { CROSS_NONE, CROSS_ONE, CROSS_DEGENERATE, CROSS_ON };

/* The closed segment pq against triangle abc (not of zero area), exactly: CROSS_ON when p
 * lies on the triangle, CROSS_ONE for a crossing through the triangle's interior,
 * CROSS_DEGENERATE when the segment meets an edge or a vertex, or lies in the plane (the
 * parity would be ambiguous: another segment is tried), else CROSS_NONE. */
static int seg_cross(const double *p, const double *q, const double *a, const double *b, const double *c)
{
    int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
    if (sp == 0) {
        if (sq == 0)
            return CROSS_DEGENERATE;
        double e[3];
        if (off_plane(a, b, c, e) < 0)
            return CROSS_DEGENERATE;
        return point_in_tri_coplanar(p, a, b, c, e) ? CROSS_ON : CROSS_NONE;
    }
    if (sq == 0)
        return CROSS_DEGENERATE;
    if (sp == sq)
        return CROSS_NONE;
    int o1 = orient3d(p, q, a, b), o2 = orient3d(p, q, b, c), o3 = orient3d(p, q, c, a);
    if ((o1 > 0 || o2 > 0 || o3 > 0) && (o1 < 0 || o2 < 0 || o3 < 0))
        return CROSS_NONE;
    if (o1 == 0 || o2 == 0 || o3 == 0)
        return CROSS_DEGENERATE;
    return CROSS_ONE;
}

/* Directions of the segments tried in turn: no two components in a simple ratio, so a
 * segment meets an edge or vertex of a mesh only by a coincidence of measure zero. */
static const double RAY_DIRS[][3] = {
    {0.5377397, 0.8342209, -0.1219548}, {-0.6715863, 0.2814709, 0.6853147},
    {0.1726339, -0.7409021, 0.6490537}, {-0.3148829, -0.4532697, -0.8339647},
    {0.8931214, -0.2249311, -0.3896219}, {-0.0832917, 0.9521473, 0.2942461},
    {0.4428193, 0.3166281, 0.8389734}, {-0.8622497, -0.4713319, 0.1853373},
};
#define N_RAY_DIRS ((int)(sizeof RAY_DIRS / sizeof RAY_DIRS[0]))

int bt_inside(const bt_index *ix, const double p[3])
{
    /* strictly outside the box of the vertices: outside the solid */
    for (int c = 0; c < 3; c++)
        if (p[c] < ix->box[c] || p[c] > ix->box[3 + c])
            return 0;
    /* a segment that ends beyond the box (twice the diagonal from inside it) */
    double len = 2 * ix->diag + 1e-300;
    int64_t stack[STACK_DEPTH];
    for (int k = 0; k < N_RAY_DIRS; k++) {
        double q[3], d[3];
        for (int c = 0; c < 3; c++) {
            q[c] = p[c] + len * RAY_DIRS[k][c];
            d[c] = q[c] - p[c];
        }
        long crossings = 0;
        int degenerate = 0, sp = 0;
        stack[sp++] = 0;
        while (sp && !degenerate) {
            const bt_node *n = ix->nodes + stack[--sp];
            if (!seg_box(n, p, d))
                continue;
            if (!n->count) {
                stack[sp++] = n->right;
                stack[sp++] = n - ix->nodes + 1;
                continue;
            }
            for (int64_t i = n->first; i < n->first + n->count && !degenerate; i++) {
                int64_t t = ix->ids[i];
                if (ix->flat[t])
                    continue;
                const int64_t *v = ix->T + 3 * t;
                int r = seg_cross(p, q, ix->V + 3 * v[0], ix->V + 3 * v[1], ix->V + 3 * v[2]);
                if (r == CROSS_ON)
                    return -1;
                if (r == CROSS_DEGENERATE)
                    degenerate = 1;
                crossings += r == CROSS_ONE;
            }
        }
        if (!degenerate)
            return (int)(crossings & 1);
    }
    return -1;
}

double bt_signed(const bt_index *ix, const double p[3], double band, int64_t *nearest, int *unsure)
{
    double d = bt_dist(ix, p, nearest);
    if (d <= band)
        return d;
    int in = bt_inside(ix, p);
    if (in < 0) {
        /* only on the surface, which the distance says p is not: count it, call it on */
        if (unsure)
            (*unsure)++;
        return 0;
    }
    return in ? -d : d;
}
