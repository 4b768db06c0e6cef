/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/bvh.c - the spatial index: a BVH over the boundary segments (boxes, capsules) and
 * its range query.  Overview and file map: axis2d/axis2d.h. */
#include "axis2d/axis2d.h"

enum { MA_LEAF = 4 };

/* The capsule around the discs (P[k], R[k]): the axis along the principal direction of
 * the centres, spanning their projections (so every centre projects inside it), the
 * radius max(perpendicular distance + R[k]). */
static void cap_fit(const double *P, const double *R, int k, double *cap)
{
    double cx = 0, cy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int i = 0; i < k; i++)
        cx += P[2 * i], cy += P[2 * i + 1];
    cx /= k, cy /= k;
    for (int i = 0; i < k; i++) {
        double dx = P[2 * i] - cx, dy = P[2 * i + 1] - cy;
        sxx += dx * dx, syy += dy * dy, sxy += dx * dy;
    }
    double a = 0.5 * atan2(2 * sxy, sxx - syy), ux = cos(a), uy = sin(a);
    double smin = INFINITY, smax = -INFINITY, rho = 0;
    for (int i = 0; i < k; i++) {
        double dx = P[2 * i] - cx, dy = P[2 * i + 1] - cy, sp = dx * ux + dy * uy;
        smin = fmin(smin, sp), smax = fmax(smax, sp);
        rho = fmax(rho, fabs(dx * uy - dy * ux) + R[i]);
    }
    cap[0] = cx + smin * ux, cap[1] = cy + smin * uy;
    cap[2] = cx + smax * ux, cap[3] = cy + smax * uy;
    cap[4] = rho * (1 + MA_EPS_ROUND) + MA_TINY;
}

static int64_t bvh_node(ma_bvh *T, int64_t lo, int64_t hi)
{
    int64_t me = T->nn++;
    double *bx = T->box + 4 * me;
    if (hi - lo <= MA_LEAF) {
        double P[4 * MA_LEAF], R[2 * MA_LEAF] = {0};
        bx[0] = bx[1] = INFINITY, bx[2] = bx[3] = -INFINITY;
        for (int64_t i = lo; i < hi; i++) {
            double *q = P + 4 * (i - lo);
            q[0] = T->x[i], q[1] = T->y[i], q[2] = T->x[T->nxt[i]], q[3] = T->y[T->nxt[i]];
            bx[0] = fmin(bx[0], fmin(q[0], q[2])), bx[2] = fmax(bx[2], fmax(q[0], q[2]));
            bx[1] = fmin(bx[1], fmin(q[1], q[3])), bx[3] = fmax(bx[3], fmax(q[1], q[3]));
        }
        T->kid[2 * me] = -1, T->kid[2 * me + 1] = lo, T->cnt[me] = hi - lo, T->end[me] = hi;
        T->beg[me] = lo;
        cap_fit(P, R, (int)(2 * (hi - lo)), T->cap + 5 * me);
        return me;
    }
    int64_t mid = lo + (hi - lo) / 2;
    int64_t l = bvh_node(T, lo, mid);
    int64_t r = bvh_node(T, mid, hi);
    const double *bl = T->box + 4 * l, *br = T->box + 4 * r;
    bx = T->box + 4 * me;
    bx[0] = fmin(bl[0], br[0]), bx[1] = fmin(bl[1], br[1]);
    bx[2] = fmax(bl[2], br[2]), bx[3] = fmax(bl[3], br[3]);
    T->kid[2 * me] = l, T->kid[2 * me + 1] = r, T->cnt[me] = 0, T->end[me] = hi;
    T->beg[me] = lo;
    const double *cl = T->cap + 5 * l, *cr = T->cap + 5 * r;
    double P[8] = {cl[0], cl[1], cl[2], cl[3], cr[0], cr[1], cr[2], cr[3]};
    double R[4] = {cl[4], cl[4], cr[4], cr[4]};
    cap_fit(P, R, 4, T->cap + 5 * me);
    return me;
}

/* Segments 0 .. n-1 in ring order; the arrays are kept by reference.  0 on NOMEM. */
int ma_bvh_build(ma_bvh *T, const double *x, const double *y, const int64_t *nxt, int64_t n)
{
    memset(T, 0, sizeof *T);
    T->x = x, T->y = y, T->nxt = nxt;
    T->box = malloc((size_t)(2 * n + 1) * 4 * sizeof *T->box);
    T->cap = malloc((size_t)(2 * n + 1) * 5 * sizeof *T->cap);
    T->kid = malloc((size_t)(2 * n + 1) * 2 * sizeof *T->kid);
    T->cnt = malloc((size_t)(2 * n + 1) * sizeof *T->cnt);
    T->end = malloc((size_t)(2 * n + 1) * sizeof *T->end);
    T->beg = malloc((size_t)(2 * n + 1) * sizeof *T->beg);
    if (!T->box || !T->cap || !T->kid || !T->cnt || !T->end || !T->beg)
        return 0;
    if (n > 0)
        bvh_node(T, 0, n);
    return 1;
}

void ma_bvh_free(ma_bvh *T)
{
    free(T->box), free(T->cap), free(T->kid), free(T->cnt), free(T->end), free(T->beg);
}

#define MA_MIN(a, b) ((a) < (b) ? (a) : (b))
#define MA_MAX(a, b) ((a) > (b) ? (a) : (b))

/* Squared distance of the segment (a, b) to the box bx (xmin, ymin, xmax, ymax): 0 if
 * they meet (Liang-Barsky clip), else attained at an end of the segment or a corner of
 * the box. */
static double seg_box_d2(double ax, double ay, double bx_, double by, const double *bx)
{
    double dx = bx_ - ax, dy = by - ay, t0 = 0, t1 = 1;
    double pp[4] = {-dx, dx, -dy, dy}, qq[4] = {ax - bx[0], bx[2] - ax, ay - bx[1], bx[3] - ay};
    int meet = 1;
    for (int k = 0; k < 4 && meet; k++) {
        if (pp[k] == 0) {
            if (qq[k] < 0)
                meet = 0;
        } else {
            double t = qq[k] / pp[k];
            if (pp[k] < 0)
                t0 = MA_MAX(t0, t);
            else
                t1 = MA_MIN(t1, t);
            if (t0 > t1)
                meet = 0;
        }
    }
    if (meet)
        return 0;
    double best = INFINITY, l2 = dx * dx + dy * dy;
    double ex[2] = {ax, bx_}, ey[2] = {ay, by};
    for (int k = 0; k < 2; k++) {
        double ux = MA_MAX(0.0, MA_MAX(bx[0] - ex[k], ex[k] - bx[2]));
        double uy = MA_MAX(0.0, MA_MAX(bx[1] - ey[k], ey[k] - bx[3]));
        best = MA_MIN(best, ux * ux + uy * uy);
    }
    for (int k = 0; k < 4; k++) {
        double cx = bx[k & 1 ? 2 : 0] - ax, cy = bx[k & 2 ? 3 : 1] - ay;
        double t = l2 > 0 ? (cx * dx + cy * dy) / l2 : 0;
        t = t < 0 ? 0 : t > 1 ? 1 : t;
        double wx = cx - t * dx, wy = cy - t * dy;
        best = MA_MIN(best, wx * wx + wy * wy);
    }
    return best;
}

double ma_pt_seg_d2(double px, double py, double ax, double ay, double bx, double by)
{
    double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy, wx = px - ax, wy = py - ay;
    double t = l2 > 0 ? (wx * dx + wy * dy) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    wx -= t * dx, wy -= t * dy;
    return wx * wx + wy * wy;
}

/* Squared distance of two segments (0 when they cross; floating point: only used with a
 * padding). */
static double seg_seg_d2(const double ab[4], const double cd[4])
{
    double ax = ab[0], ay = ab[1], bx = ab[2], by = ab[3];
    double cx = cd[0], cy = cd[1], dx = cd[2], dy = cd[3];
    double o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    double o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax);
    double o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx);
    double o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx);
    if (((o1 < 0 && o2 > 0) || (o1 > 0 && o2 < 0)) && ((o3 < 0 && o4 > 0) || (o3 > 0 && o4 < 0)))
        return 0;
    double d = ma_pt_seg_d2(ax, ay, cx, cy, dx, dy);
    d = MA_MIN(d, ma_pt_seg_d2(bx, by, cx, cy, dx, dy));
    d = MA_MIN(d, ma_pt_seg_d2(cx, cy, ax, ay, bx, by));
    return MA_MIN(d, ma_pt_seg_d2(dx, dy, ax, ay, bx, by));
}

/* Appends to out every segment numbered from `from` on whose node lies within distance
 * rad of the segment seg = (ax, ay, bx, by) (a capsule query; a point when a = b).
 * Returns 0 on NOMEM. */
int ma_bvh_collect(const ma_bvh *T, const double seg[4], double rad, int64_t from, ivec *out)
{
    double ax = seg[0], ay = seg[1], bx = seg[2], by = seg[3];
    if (T->nn == 0)
        return 1;
    int64_t stack[192];
    int sp = 0;
    double r2 = rad * rad;
    double q0 = MA_MIN(ax, bx), q1 = MA_MIN(ay, by), q2 = MA_MAX(ax, bx), q3 = MA_MAX(ay, by);
    int point = ax == bx && ay == by;
    stack[sp++] = 0;
    while (sp > 0) {
        int64_t nd = stack[--sp];
        const double *b = T->box + 4 * nd;
        if (T->end[nd] <= from)
            continue;
        double dx = MA_MAX(0.0, MA_MAX(b[0] - q2, q0 - b[2]));
        double dy = MA_MAX(0.0, MA_MAX(b[1] - q3, q1 - b[3]));
        if (dx * dx + dy * dy > r2)
            continue;
        const double *cp = T->cap + 5 * nd;
        double rc = rad + cp[4];
        if (seg_seg_d2(seg, cp) > rc * rc)
            continue;
        if (!point && seg_box_d2(ax, ay, bx, by, b) > r2)
            continue;
        if (T->kid[2 * nd] < 0) {
            for (int64_t i = 0; i < T->cnt[nd]; i++)
                if (!ivec_push(out, T->kid[2 * nd + 1] + i))
                    return 0;
        } else {
            stack[sp++] = T->kid[2 * nd];
            stack[sp++] = T->kid[2 * nd + 1];
        }
    }
    return 1;
}
