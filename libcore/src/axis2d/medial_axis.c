/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial_axis.c - the medial axis of a planar face (issue 9 section 2) by ridge tracing.
 *
 * Method (design: the ma2d notes, section 2 and the lessons of section 7).  The elements
 * of the boundary are its edges as open segments (with the inward normal) and its reflex
 * vertices as points; convex vertices are the leaves of the axis (radius 0).  The axis is
 * a union of bisectors of element pairs: segment-segment (a line, or the midline of two
 * parallel edges), point-segment (a parabola), point-point (a line).  A trace starts at a
 * leaf and follows the bisector of its pair.  The bisector's point and radius are
 * polynomials of degree <= 2 in its parameter, so the first contact of every other element
 * with the moving disc (|p - v| = r for a reflex vertex, |n . (p - a)| = r with the foot
 * inside the open edge) is a root of a quadratic: exact in closed form.  The first event
 * is found by a best-first branch and bound over a BVH of the edges (node capsules give a
 * closed-form lower bound of their first contact).  At an event every element touching
 * the disc is gathered, sorted by the angle of its foot point, and each angularly
 * consecutive pair that is not (segment, its own endpoint) is a port -- a branch leaving
 * the junction.  Where the foot of a segment element leaves the open segment at a reflex
 * vertex (again a closed-form root), the element is switched to that vertex (a
 * transition along the branch, not a junction).  Junctions joined by a branch shorter
 * than tol are then contracted, and the result is put in canonical order (assemble).
 *
 * History: the first version advanced conservatively on a clearance margin that measured
 * an edge whose foot lies beyond its ends as +inf -- not a lower bound of the clearance --
 * so on needle spikes a step could jump over a contact (false leaves), and it scanned all
 * edges per step (1 000 segments: 2 s).  Now, on jittered needle stars with 16 holes
 * (bench/bench_medial_axis.py, 2 shared cores): 1 000 segments 12-17 ms, 10 000
 * 0.16-0.28 s, 100 000 1.2-2.0 s, i.e. 0.6-1.3 x Boost's Voronoi construct() on the same
 * segments, with the same topology.  The crossing check uses the same index. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/vec3.h"
#include "common/predicates.h"


/* ---- growable arrays ------------------------------------------------------------- */
typedef struct { double *v; int64_t n, cap; } dvec;
typedef struct { int64_t *v; int64_t n, cap; } ivec;

static int dvec_push(dvec *a, double x)
{
    if (a->n == a->cap) {
        int64_t c = a->cap ? 2 * a->cap : 64;
        double *p = realloc(a->v, (size_t)c * sizeof *p);
        if (!p)
            return 0;
        a->v = p;
        a->cap = c;
    }
    a->v[a->n++] = x;
    return 1;
}

static int ivec_push(ivec *a, int64_t x)
{
    if (a->n == a->cap) {
        int64_t c = a->cap ? 2 * a->cap : 64;
        int64_t *p = realloc(a->v, (size_t)c * sizeof *p);
        if (!p)
            return 0;
        a->v = p;
        a->cap = c;
    }
    a->v[a->n++] = x;
    return 1;
}

/* ---- the boundary elements ------------------------------------------------------- */
typedef struct {
    int64_t ns;                 /* segments: element ids 0 .. ns-1 */
    double *ax, *ay, *ux, *uy, *nx, *ny, *len;
    int64_t *prev, *next;       /* neighbouring segments in the ring */
    int64_t *orig;              /* caller's vertex index of the segment's start */
    int8_t *reflex, *convex;    /* of the vertex at the segment's start */
    int64_t *velem;             /* vertex k -> its element id (ns + j) or -1 */
    int64_t nv;                 /* reflex vertex elements: ids ns .. ns+nv-1 */
    int64_t *vk;                /* element ns+j -> vertex (segment start) index */
    double diag;
} ma_elems;

/* ---- the spatial index: a BVH over the segments ------------------------------------ */
/* Every clearance query (events, junction gathers, the crossing check) goes through this
 * one index.  A node holds a run of consecutive segments of one ring order (split in
 * halves: O(n), balanced, depth <= 1 + log2 n): consecutive edges of a boundary are near
 * each other, so a node is a compact piece of boundary -- and a bundle of thin needles (a
 * dense star) stays a thin fan, where a split of midpoints along an axis mixes needles of
 * different directions.  Each node has a box (for range queries) and a capsule (for the
 * event search, whose bounds it makes tight around thin fans).  A reflex vertex element
 * is reached through the segment that starts at it. */
typedef struct {
    int64_t nn;           /* nodes; node 0 is the root */
    double *box;          /* 4 per node: xmin, ymin, xmax, ymax */
    double *cap;          /* 5 per node: capsule axis (ax, ay)-(bx, by), radius */
    int64_t *kid;         /* 2 per node: children, or -1 and the leaf's first segment */
    int64_t *cnt;         /* segments of a leaf (0 for an inner node) */
    int64_t *end;         /* one past the last segment under the node */
    const double *x, *y;  /* the segments: s from (x[s], y[s]) to (x[nxt[s]], y[nxt[s]]) */
    const int64_t *nxt;
} ma_bvh;

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
    cap[4] = rho * (1 + 1e-12) + 1e-300;
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
    const double *cl = T->cap + 5 * l, *cr = T->cap + 5 * r;
    double P[8] = {cl[0], cl[1], cl[2], cl[3], cr[0], cr[1], cr[2], cr[3]};
    double R[4] = {cl[4], cl[4], cr[4], cr[4]};
    cap_fit(P, R, 4, T->cap + 5 * me);
    return me;
}

/* Segments 0 .. n-1 in ring order; the arrays are kept by reference.  0 on NOMEM. */
static int bvh_build(ma_bvh *T, const double *x, const double *y, const int64_t *nxt, int64_t n)
{
    memset(T, 0, sizeof *T);
    T->x = x, T->y = y, T->nxt = nxt;
    T->box = malloc((size_t)(2 * n + 1) * 4 * sizeof *T->box);
    T->cap = malloc((size_t)(2 * n + 1) * 5 * sizeof *T->cap);
    T->kid = malloc((size_t)(2 * n + 1) * 2 * sizeof *T->kid);
    T->cnt = malloc((size_t)(2 * n + 1) * sizeof *T->cnt);
    T->end = malloc((size_t)(2 * n + 1) * sizeof *T->end);
    if (!T->box || !T->cap || !T->kid || !T->cnt || !T->end)
        return 0;
    if (n > 0)
        bvh_node(T, 0, n);
    return 1;
}

static void bvh_free(ma_bvh *T)
{
    free(T->box), free(T->cap), free(T->kid), free(T->cnt), free(T->end);
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

static double pt_seg_d2(double px, double py, double ax, double ay, double bx, double by)
{
    double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy, wx = px - ax, wy = py - ay;
    double t = l2 > 0 ? (wx * dx + wy * dy) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    wx -= t * dx, wy -= t * dy;
    return wx * wx + wy * wy;
}

/* Squared distance of two segments (0 when they cross; floating point: only used with a
 * padding). */
static double seg_seg_d2(double ax, double ay, double bx, double by, double cx, double cy,
                         double dx, double dy)
{
    double o1 = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    double o2 = (bx - ax) * (dy - ay) - (by - ay) * (dx - ax);
    double o3 = (dx - cx) * (ay - cy) - (dy - cy) * (ax - cx);
    double o4 = (dx - cx) * (by - cy) - (dy - cy) * (bx - cx);
    if (((o1 < 0 && o2 > 0) || (o1 > 0 && o2 < 0)) && ((o3 < 0 && o4 > 0) || (o3 > 0 && o4 < 0)))
        return 0;
    double d = pt_seg_d2(ax, ay, cx, cy, dx, dy);
    d = MA_MIN(d, pt_seg_d2(bx, by, cx, cy, dx, dy));
    d = MA_MIN(d, pt_seg_d2(cx, cy, ax, ay, bx, by));
    return MA_MIN(d, pt_seg_d2(dx, dy, ax, ay, bx, by));
}

/* Appends to out every segment numbered from `from` on whose node lies within distance
 * rad of the segment (ax, ay)-(bx, by) (a capsule query; a point when a = b).  Returns 0
 * on NOMEM. */
static int bvh_collect(const ma_bvh *T, double ax, double ay, double bx, double by, double rad,
                       int64_t from, ivec *out)
{
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
        if (seg_seg_d2(ax, ay, bx, by, cp[0], cp[1], cp[2], cp[3]) > rc * rc)
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

typedef struct {
    int64_t j;      /* junction */
    int64_t e1, e2; /* element pair of the bisector leaving it */
    double angle;   /* direction of the port */
    int used;
} ma_port;

typedef struct {
    double x, y, r;
    int64_t first_elem, nelem, first_port, nport;
    int64_t hnext; /* next junction in its hash bucket */
} ma_junction;

typedef struct {
    ma_elems E;
    double tol, eps, gather, arrive;
    dvec px, py, pr;          /* samples */
    ivec boff, bend;          /* branch offsets (start of each branch), ends 2 per branch */
    ma_junction *J;
    int64_t nj, capj;
    ma_port *P;
    int64_t np, capp;
    ivec jelem;               /* element ids of the junctions */
    ivec stack;               /* ports to trace */
    int8_t *reached;          /* convex vertices reached by a branch */
    ma_bvh T;                 /* the spatial index over the segments */
    ivec cand;                /* scratch: segments returned by the index */
    double *heapk;            /* scratch: the branch and bound's heap (keys, nodes) */
    int64_t *heapn;
    int64_t *hhead, hmask;    /* junction hash: buckets of a grid of cell `arrive` */
    double hx0, hy0;
} ma_ctx;

static int is_seg(const ma_elems *E, int64_t e) { return e < E->ns; }

static void vpoint(const ma_elems *E, int64_t e, double *x, double *y)
{
    int64_t k = E->vk[e - E->ns];
    *x = E->ax[k];
    *y = E->ay[k];
}

/* Distance of p to element e (an open segment: +inf when the foot is outside it). */
static double elem_dist(const ma_elems *E, int64_t e, double x, double y)
{
    if (is_seg(E, e)) {
        double qx = x - E->ax[e], qy = y - E->ay[e];
        double t = qx * E->ux[e] + qy * E->uy[e];
        if (t > 0 && t < E->len[e])
            return fabs(qx * E->nx[e] + qy * E->ny[e]);
        return INFINITY;
    }
    double vx, vy;
    vpoint(E, e, &vx, &vy);
    return hypot(x - vx, y - vy);
}

/* (segment, its own endpoint vertex): their bisector is the normal at the vertex, not
 * part of the axis. */
static int own_pair(const ma_elems *E, int64_t a, int64_t b)
{
    if (is_seg(E, a) == is_seg(E, b))
        return 0;
    int64_t s = is_seg(E, a) ? a : b, v = is_seg(E, a) ? b : a;
    int64_t k = E->vk[v - E->ns];
    return k == s || k == E->next[s];
}

/* ---- bisectors ------------------------------------------------------------------- */
enum { MA_PAR, MA_LL, MA_PL, MA_PP };
typedef struct {
    int kind;
    int64_t e1, e2;
    double Px, Py, dx, dy, r0, qx, qy, sg;
    double ax, ay, ux, uy, nx, ny, fx, h, x0; /* point-segment: the segment's frame */
    double v1x, v1y;                          /* point-point: one of the points */
    /* p(t) = p0 + p1 t + p2 t^2 and (not MA_PP) r(t) = r0c + r1c t + r2c t^2: the event
     * and window equations below are at most quadratic in t.  (fpx, fpy): the pair's
     * reflex vertex (MA_PL, MA_PP), for which r = |p - f|. */
    double p0x, p0y, p1x, p1y, p2x, p2y, r0c, r1c, r2c, fpx, fpy;
} ma_bis;

/* The polynomial form of b (after bis_make). */
static void bis_poly(ma_bis *b)
{
    b->p2x = b->p2y = b->r1c = b->r2c = 0;
    switch (b->kind) {
    case MA_PAR:
        b->p0x = b->Px, b->p0y = b->Py, b->p1x = b->dx, b->p1y = b->dy, b->r0c = b->r0;
        return;
    case MA_LL:
        b->p0x = b->Px, b->p0y = b->Py, b->p1x = b->qx, b->p1y = b->qy;
        b->r0c = b->r0, b->r1c = b->sg;
        return;
    case MA_PL: {
        double g = b->x0 - b->fx, y0 = (g * g + b->h * b->h) / (2 * b->h), y1 = b->sg * g / b->h;
        b->p0x = b->ax + b->x0 * b->ux + y0 * b->nx, b->p0y = b->ay + b->x0 * b->uy + y0 * b->ny;
        b->p1x = b->sg * b->ux + y1 * b->nx, b->p1y = b->sg * b->uy + y1 * b->ny;
        b->p2x = b->nx / (2 * b->h), b->p2y = b->ny / (2 * b->h);
        b->r0c = y0, b->r1c = y1, b->r2c = 1 / (2 * b->h);
        return;
    }
    default:
        b->p0x = b->Px, b->p0y = b->Py, b->p1x = b->dx, b->p1y = b->dy;
        b->fpx = b->v1x, b->fpy = b->v1y;
        return;
    }
}

static void bis_make(const ma_elems *E, ma_bis *b, int64_t e1, int64_t e2, double Px, double Py,
                     double dx, double dy)
{
    memset(b, 0, sizeof *b);
    b->e1 = e1;
    b->e2 = e2;
    b->Px = Px;
    b->Py = Py;
    int s1 = is_seg(E, e1), s2 = is_seg(E, e2);
    if (s1 && s2) {
        double n1x = E->nx[e1], n1y = E->ny[e1], n2x = E->nx[e2], n2y = E->ny[e2];
        double det = n1x * n2y - n1y * n2x;
        /* Start on the bisector itself: a junction point is only equidistant to the
         * event accuracy, and r(t) extrapolates from r0 (the start would carry its
         * offset along the whole line). */
        double f = (Px - E->ax[e1]) * n1x + (Py - E->ay[e1]) * n1y -
                   (Px - E->ax[e2]) * n2x - (Py - E->ay[e2]) * n2y;
        double gx = n1x - n2x, gy = n1y - n2y, g2 = gx * gx + gy * gy;
        if (g2 > 1e-24)
            Px -= f * gx / g2, Py -= f * gy / g2;
        b->Px = Px, b->Py = Py;
        b->r0 = (Px - E->ax[e1]) * n1x + (Py - E->ay[e1]) * n1y;
        if (fabs(det) < 1e-12) { /* parallel edges: the midline, r constant */
            double ux = -n1y, uy = n1x;
            if (ux * dx + uy * dy < 0)
                ux = -ux, uy = -uy;
            b->kind = MA_PAR;
            b->dx = ux;
            b->dy = uy;
        } else { /* n1.q = n2.q = 1: r grows by 1 per unit of t along q */
            double qx = (n2y - n1y) / det, qy = (n1x - n2x) / det;
            b->sg = (qx * dx + qy * dy >= 0) ? 1.0 : -1.0;
            b->kind = MA_LL;
            b->qx = qx * b->sg;
            b->qy = qy * b->sg;
        }
    } else if (s1 || s2) { /* parabola: focus the vertex, directrix the segment's line */
        int64_t s = s1 ? e1 : e2, v = s1 ? e2 : e1;
        double fxp, fyp;
        vpoint(E, v, &fxp, &fyp);
        b->kind = MA_PL;
        b->fpx = fxp, b->fpy = fyp;
        b->ax = E->ax[s], b->ay = E->ay[s], b->ux = E->ux[s], b->uy = E->uy[s];
        b->nx = E->nx[s], b->ny = E->ny[s];
        b->fx = (fxp - b->ax) * b->ux + (fyp - b->ay) * b->uy;
        b->h = (fxp - b->ax) * b->nx + (fyp - b->ay) * b->ny;
        b->x0 = (Px - b->ax) * b->ux + (Py - b->ay) * b->uy;
        double g = (b->x0 - b->fx) / b->h;
        double tx = b->ux + g * b->nx, ty = b->uy + g * b->ny;
        b->sg = (tx * dx + ty * dy >= 0) ? 1.0 : -1.0;
    } else { /* two reflex vertices: their perpendicular bisector */
        double x1, y1, x2, y2;
        vpoint(E, e1, &x1, &y1);
        vpoint(E, e2, &x2, &y2);
        double wx = -(y2 - y1), wy = x2 - x1, wl = hypot(wx, wy);
        wx /= wl, wy /= wl;
        if (wx * dx + wy * dy < 0)
            wx = -wx, wy = -wy;
        b->kind = MA_PP;
        b->dx = wx, b->dy = wy, b->v1x = x1, b->v1y = y1;
        /* start on the bisector: project P along the line v1 v2 (see the line case) */
        double ex = x2 - x1, ey = y2 - y1, el2 = ex * ex + ey * ey;
        double f = (Px - 0.5 * (x1 + x2)) * ex + (Py - 0.5 * (y1 + y2)) * ey;
        b->Px = Px - f * ex / el2, b->Py = Py - f * ey / el2;
    }
    bis_poly(b);
}

static void bis_at(const ma_bis *b, double t, double *x, double *y, double *r)
{
    switch (b->kind) {
    case MA_PAR:
        *x = b->Px + t * b->dx, *y = b->Py + t * b->dy, *r = b->r0;
        return;
    case MA_LL:
        *x = b->Px + t * b->qx, *y = b->Py + t * b->qy, *r = b->r0 + b->sg * t;
        return;
    case MA_PL: {
        double xx = b->x0 + b->sg * t, yy = ((xx - b->fx) * (xx - b->fx) + b->h * b->h) / (2 * b->h);
        *x = b->ax + xx * b->ux + yy * b->nx;
        *y = b->ay + xx * b->uy + yy * b->ny;
        *r = yy;
        return;
    }
    default:
        *x = b->Px + t * b->dx, *y = b->Py + t * b->dy;
        *r = hypot(*x - b->v1x, *y - b->v1y);
    }
}

/* The longest step whose chord and linearly interpolated radius stay within tol
 * (lesson 6: the radius along a point-point line is not linear either). */
static double bis_max_step(const ma_bis *b, double t, double tol)
{
    if (b->kind == MA_PAR || b->kind == MA_LL)
        return INFINITY;
    if (b->kind == MA_PL)
        return sqrt(2 * tol * b->h);
    double x, y, r;
    bis_at(b, t, &x, &y, &r);
    double hh = fabs((x - b->v1x) * -b->dy + (y - b->v1y) * b->dx);
    if (hh < 1e-300)
        hh = 1e-300;
    return sqrt(2 * tol * hh);
}

static void bis_tangent(const ma_bis *b, double t, double *tx, double *ty)
{
    double x = b->p1x + 2 * b->p2x * t, y = b->p1y + 2 * b->p2y * t, l = hypot(x, y);
    *tx = x / l;
    *ty = y / l;
}

/* Window of the pair: 0 while both elements still govern p; else the element that
 * stopped and how (1 start / 2 end of a segment, 3 prev / 4 next side of a vertex). */
static int bis_window(const ma_elems *E, const ma_bis *b, double x, double y, int64_t *which)
{
    int64_t es[2] = {b->e1, b->e2};
    for (int i = 0; i < 2; i++) {
        int64_t e = es[i];
        *which = e;
        if (is_seg(E, e)) {
            double t = (x - E->ax[e]) * E->ux[e] + (y - E->ay[e]) * E->uy[e];
            if (t <= 0)
                return 1;
            if (t >= E->len[e])
                return 2;
        } else {
            int64_t k = E->vk[e - E->ns], pk = E->prev[k];
            double qx = x - E->ax[k], qy = y - E->ay[k];
            if (qx * E->ux[pk] + qy * E->uy[pk] < 0)
                return 3;
            if (qx * E->ux[k] + qy * E->uy[k] > 0)
                return 4;
        }
    }
    return 0;
}

/* The element that takes over from e at its window end, or -1 at a convex corner
 * (the leaf). */
static int64_t window_switch(const ma_elems *E, int64_t e, int how)
{
    if (is_seg(E, e)) {
        int64_t k = how == 1 ? e : E->next[e];
        return E->reflex[k] ? E->velem[k] : -1;
    }
    int64_t k = E->vk[e - E->ns];
    return how == 3 ? E->prev[k] : k;
}

/* ---- junctions ------------------------------------------------------------------- */
static double wrap_pi(double a)
{
    a = fmod(a + MFG_PI, 2 * MFG_PI);
    if (a < 0)
        a += 2 * MFG_PI;
    return a - MFG_PI;
}

typedef struct { int64_t e; double a; } ma_ea;

static int cmp_ea(const void *pa, const void *pb)
{
    const ma_ea *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->e > b->e) - (a->e < b->e);
}

/* Builds the junction at (x, y) of radius r from every element within the event
 * accuracy of the disc (lesson 3: not the user tol).  Returns its index or -1 (NOMEM). */
static int64_t junction_make(ma_ctx *C, double x, double y, double r)
{
    const ma_elems *E = &C->E;
    int64_t cnt = 0;
    C->cand.n = 0;
    if (!bvh_collect(&C->T, x, y, x, y, r + C->gather, 0, &C->cand))
        return -1;
    ma_ea *ea = malloc((size_t)(2 * C->cand.n + 1) * sizeof *ea);
    if (!ea)
        return -1;
    for (int64_t ci = 0; ci < 2 * C->cand.n; ci++) {
        int64_t s = C->cand.v[ci / 2], e = ci % 2 ? E->velem[s] : s;
        if (e < 0)
            continue;
        if (elem_dist(E, e, x, y) <= r + C->gather) {
            double fx, fy;
            if (is_seg(E, e)) {
                double d = (x - E->ax[e]) * E->nx[e] + (y - E->ay[e]) * E->ny[e];
                fx = x - d * E->nx[e];
                fy = y - d * E->ny[e];
            } else {
                vpoint(E, e, &fx, &fy);
            }
            ea[cnt].e = e;
            ea[cnt].a = atan2(fy - y, fx - x);
            cnt++;
        }
    }
    qsort(ea, (size_t)cnt, sizeof *ea, cmp_ea);
    if (C->nj == C->capj) {
        int64_t c = C->capj ? 2 * C->capj : 16;
        ma_junction *p = realloc(C->J, (size_t)c * sizeof *p);
        if (!p) {
            free(ea);
            return -1;
        }
        C->J = p;
        C->capj = c;
    }
    ma_junction *J = &C->J[C->nj];
    J->x = x, J->y = y, J->r = r;
    J->first_elem = C->jelem.n;
    J->nelem = cnt;
    J->first_port = C->np;
    J->nport = 0;
    for (int64_t i = 0; i < cnt; i++)
        if (!ivec_push(&C->jelem, ea[i].e)) {
            free(ea);
            return -1;
        }
    for (int64_t i = 0; cnt > 1 && i < cnt; i++) {
        int64_t a = ea[i].e, b = ea[(i + 1) % cnt].e;
        if (a == b || own_pair(E, a, b))
            continue;
        double da = fmod(ea[(i + 1) % cnt].a - ea[i].a + 4 * MFG_PI, 2 * MFG_PI);
        if (C->np == C->capp) {
            int64_t c = C->capp ? 2 * C->capp : 32;
            ma_port *p = realloc(C->P, (size_t)c * sizeof *p);
            if (!p) {
                free(ea);
                return -1;
            }
            C->P = p;
            C->capp = c;
        }
        ma_port *P = &C->P[C->np++];
        P->j = C->nj, P->e1 = a, P->e2 = b, P->angle = ea[i].a + da / 2, P->used = 0;
        J->nport++;
    }
    free(ea);
    return C->nj++;
}

/* The unused port of junction j best aligned with direction angle `a` (or the worst
 * aligned when `farthest`); -1 if none. */
static int64_t port_pick(const ma_ctx *C, int64_t j, double a, int farthest)
{
    int64_t best = -1;
    double bv = 0;
    for (int64_t p = C->J[j].first_port; p < C->J[j].first_port + C->J[j].nport; p++) {
        if (C->P[p].used)
            continue;
        double v = fabs(wrap_pi(C->P[p].angle - a));
        if (best < 0 || (farthest ? v > bv : v < bv))
            best = p, bv = v;
    }
    return best;
}

/* ---- tracing ---------------------------------------------------------------------- */
enum { TR_LEAF, TR_EVENT, TR_NOMEM, TR_STUCK, TR_BADPAIR, TR_MISSED };

static int push_sample(ma_ctx *C, double x, double y, double r)
{
    return dvec_push(&C->px, x) && dvec_push(&C->py, y) && dvec_push(&C->pr, r);
}

/* ---- exact events ----------------------------------------------------------------- */

/* The root of A t^2 + B t + C in (lo, hi] where the polynomial falls through zero (from
 * positive = outside the disc / inside the window, to negative), INFINITY if none.  A
 * quadratic has at most one such root; a root where it rises is an element leaving the
 * disc (the elements of the junction a trace starts from) and is not an event. */
static double quad_entry(double A, double B, double C, double lo, double hi)
{
    double best = INFINITY;
    if (A == 0) {
        if (B < 0) {
            double t = -C / B;
            if (t > lo && t <= hi)
                best = t;
        }
        return best;
    }
    double D = B * B - 4 * A * C;
    if (D < 0)
        return best;
    double sq = sqrt(D), q = -0.5 * (B + (B >= 0 ? sq : -sq));
    double rt[2] = {q / A, q != 0 ? C / q : q / A};
    for (int i = 0; i < 2; i++)
        if (rt[i] > lo && rt[i] <= hi && 2 * A * rt[i] + B < 0 && rt[i] < best)
            best = rt[i];
    return best;
}

/* The entry root of c . (p(t) - q) + c0 (a linear function of the point). */
static double lin_entry(const ma_bis *b, double cx, double cy, double qx, double qy, double c0,
                        double lo, double hi)
{
    return quad_entry(cx * b->p2x + cy * b->p2y, cx * b->p1x + cy * b->p1y,
                      cx * (b->p0x - qx) + cy * (b->p0y - qy) + c0, lo, hi);
}

static void bis_pt(const ma_bis *b, double t, double *x, double *y)
{
    *x = b->p0x + t * (b->p1x + t * b->p2x);
    *y = b->p0y + t * (b->p1y + t * b->p2y);
}

/* The first t in (lo, hi] where element e (not of the pair) touches the disc of b from
 * outside: |p - v| = r for a reflex vertex, |n . (p - a)| = r with the foot inside the open
 * segment for an edge.  Closed forms, each at most a quadratic in t: for MA_PL and MA_PP
 * r = |p - f|, so |p - v|^2 - r^2 = 2 (f - v) . (p - (f + v) / 2) is linear in p. */
static double elem_entry(const ma_elems *E, const ma_bis *b, int64_t e, double lo, double hi)
{
    int curved_r = b->kind == MA_PL || b->kind == MA_PP;
    if (!is_seg(E, e)) {
        double vx, vy;
        vpoint(E, e, &vx, &vy);
        if (curved_r)
            return lin_entry(b, 2 * (b->fpx - vx), 2 * (b->fpy - vy), 0.5 * (b->fpx + vx),
                             0.5 * (b->fpy + vy), 0.0, lo, hi);
        double wx = b->p0x - vx, wy = b->p0y - vy;
        return quad_entry(b->p1x * b->p1x + b->p1y * b->p1y - b->r1c * b->r1c,
                          2 * (b->p1x * wx + b->p1y * wy - b->r0c * b->r1c),
                          wx * wx + wy * wy - b->r0c * b->r0c, lo, hi);
    }
    double nx = E->nx[e], ny = E->ny[e];
    double d2 = nx * b->p2x + ny * b->p2y, d1 = nx * b->p1x + ny * b->p1y;
    double d0 = nx * (b->p0x - E->ax[e]) + ny * (b->p0y - E->ay[e]);
    double ts[2] = {INFINITY, INFINITY}, best = INFINITY;
    if (b->kind == MA_PP) { /* (n . (p - a))^2 - |p - f|^2, p linear in t */
        double wx = b->p0x - b->fpx, wy = b->p0y - b->fpy;
        ts[0] = quad_entry(d1 * d1 - (b->p1x * b->p1x + b->p1y * b->p1y),
                           2 * (d0 * d1 - (b->p1x * wx + b->p1y * wy)),
                           d0 * d0 - (wx * wx + wy * wy),
                           lo, hi);
    } else { /* +-n . (p - a) - r: the disc meets the line from either side */
        ts[0] = quad_entry(d2 - b->r2c, d1 - b->r1c, d0 - b->r0c, lo, hi);
        ts[1] = quad_entry(-d2 - b->r2c, -d1 - b->r1c, -d0 - b->r0c, lo, hi);
    }
    for (int i = 0; i < 2; i++) {
        if (!(ts[i] < best))
            continue;
        double x, y;
        bis_pt(b, ts[i], &x, &y);
        double f = (x - E->ax[e]) * E->ux[e] + (y - E->ay[e]) * E->uy[e];
        if (f > 0 && f < E->len[e])
            best = ts[i];
    }
    return best;
}

/* The first t in (lo, +inf) where a window of the pair closes (see bis_window for `how`). */
static double bis_window_exit(const ma_elems *E, const ma_bis *b, double lo, int64_t *which,
                              int *how)
{
    int64_t es[2] = {b->e1, b->e2};
    double best = INFINITY;
    for (int i = 0; i < 2; i++) {
        int64_t e = es[i];
        double t[2];
        if (is_seg(E, e)) {
            t[0] = lin_entry(b, E->ux[e], E->uy[e], E->ax[e], E->ay[e], 0.0, lo, INFINITY);
            t[1] = lin_entry(b, -E->ux[e], -E->uy[e], E->ax[e], E->ay[e], E->len[e], lo, INFINITY);
        } else {
            int64_t k = E->vk[e - E->ns], pk = E->prev[k];
            t[0] = lin_entry(b, E->ux[pk], E->uy[pk], E->ax[k], E->ay[k], 0.0, lo, INFINITY);
            t[1] = lin_entry(b, -E->ux[k], -E->uy[k], E->ax[k], E->ay[k], 0.0, lo, INFINITY);
        }
        for (int w = 0; w < 2; w++)
            if (t[w] < best)
                best = t[w], *which = e, *how = (is_seg(E, e) ? 1 : 3) + w;
    }
    return best;
}

/* The elements a bisector never meets except at its window ends (lesson 1): the pair, the
 * reflex endpoints of a pair segment and the other edge there (it lies beyond the line of
 * the pair segment, on the far side from the disc), the two edges of a pair vertex (they
 * lie beyond the disc's tangent at the vertex while the vertex's window is open). */
static int excluded_set(const ma_elems *E, const ma_bis *b, int64_t ex[10])
{
    int nex = 0;
    int64_t es[2] = {b->e1, b->e2};
    for (int i = 0; i < 2; i++) {
        int64_t e = es[i];
        ex[nex++] = e;
        if (is_seg(E, e)) {
            if (E->reflex[e])
                ex[nex++] = E->velem[e], ex[nex++] = E->prev[e];
            if (E->reflex[E->next[e]])
                ex[nex++] = E->velem[E->next[e]], ex[nex++] = E->next[e];
        } else {
            int64_t k = E->vk[e - E->ns];
            ex[nex++] = k;
            ex[nex++] = E->prev[k];
        }
    }
    return nex;
}

/* A lower bound of the first t >= 0 where the disc of b meets the disc (c, rho):
 * |p - c| <= r + rho.  Closed forms: for MA_PAR / MA_LL a quadratic; for MA_PL / MA_PP
 * (r = |p - f|) the condition is L = |p - c|^2 - |p - f|^2 - rho^2 <= 2 rho r with L
 * linear in p (MA_PL: r is a polynomial; MA_PP: L <= 0 or L^2 <= 4 rho^2 r^2, a
 * superset, hence still a bound). */
static double disc_bound(const ma_bis *b, double cx, double cy, double rho)
{
    if (b->kind == MA_PL || b->kind == MA_PP) {
        double kx = 2 * (b->fpx - cx), ky = 2 * (b->fpy - cy);
        double mx = 0.5 * (b->fpx + cx), my = 0.5 * (b->fpy + cy);
        double L2 = kx * b->p2x + ky * b->p2y, L1 = kx * b->p1x + ky * b->p1y;
        double L0 = kx * (b->p0x - mx) + ky * (b->p0y - my) - rho * rho;
        if (b->kind == MA_PL) {
            double A = L2 - 2 * rho * b->r2c, B = L1 - 2 * rho * b->r1c, C = L0 - 2 * rho * b->r0c;
            return C <= 0 ? 0.0 : quad_entry(A, B, C, 0.0, INFINITY);
        }
        double wx = b->p0x - b->fpx, wy = b->p0y - b->fpy, rr = 4 * rho * rho;
        double A = L1 * L1 - rr * (b->p1x * b->p1x + b->p1y * b->p1y);
        double B = 2 * L0 * L1 - rr * 2 * (b->p1x * wx + b->p1y * wy);
        double C = L0 * L0 - rr * (wx * wx + wy * wy);
        if (L0 <= 0 || C <= 0)
            return 0.0;
        return fmin(quad_entry(0.0, L1, L0, 0.0, INFINITY), quad_entry(A, B, C, 0.0, INFINITY));
    }
    double wx = b->p0x - cx, wy = b->p0y - cy, R0 = b->r0c + rho;
    double C = wx * wx + wy * wy - R0 * R0;
    if (C <= 0)
        return 0.0;
    return quad_entry(b->p1x * b->p1x + b->p1y * b->p1y - b->r1c * b->r1c,
                      2 * (b->p1x * wx + b->p1y * wy - R0 * b->r1c), C, 0.0, INFINITY);
}

/* A lower bound of the first t >= 0 where the disc of b meets the capsule cp (axis a-b,
 * radius rho): first contact is with an end cap (disc_bound) or with one of the two side
 * lines |n . (p - a)| = rho (their first contact, foot ignored: earlier, so a bound). */
static double node_bound(const ma_bis *b, const double *cp, double pad, double lim)
{
    double ax = cp[0], ay = cp[1], rho = cp[4] + pad;
    double dx = cp[2] - ax, dy = cp[3] - ay, l = sqrt(dx * dx + dy * dy);
    double r0 = b->kind == MA_PP ? hypot(b->p0x - b->fpx, b->p0y - b->fpy) : b->r0c;
    double d0 = pt_seg_d2(b->p0x, b->p0y, ax, ay, cp[2], cp[3]), R0 = r0 + rho;
    if (d0 <= R0 * R0)
        return 0.0;
    /* first the circumscribed disc (one quadratic): far nodes stop here */
    double tc = disc_bound(b, 0.5 * (ax + cp[2]), 0.5 * (ay + cp[3]), 0.5 * l + rho);
    if (!(tc < lim))
        return tc;
    double t = fmin(disc_bound(b, ax, ay, rho), disc_bound(b, cp[2], cp[3], rho));
    if (!(l > 0))
        return fmax(t, tc);
    double nx = -dy / l, ny = dx / l;
    double e2 = nx * b->p2x + ny * b->p2y, e1 = nx * b->p1x + ny * b->p1y;
    double e0 = nx * (b->p0x - ax) + ny * (b->p0y - ay);
    for (int sg = -1; sg <= 1; sg += 2) { /* g = sg n.(p - a) - rho: contact where g <= r */
        double g2 = sg * e2, g1 = sg * e1, g0 = sg * e0 - rho;
        if (b->kind == MA_PP) { /* g <= 0, or g^2 <= r^2 (a superset of g <= r) */
            double wx = b->p0x - b->fpx, wy = b->p0y - b->fpy;
            t = fmin(t, quad_entry(0.0, g1, g0, 0.0, INFINITY));
            t = fmin(t, quad_entry(g1 * g1 - (b->p1x * b->p1x + b->p1y * b->p1y),
                                   2 * (g0 * g1 - (b->p1x * wx + b->p1y * wy)),
                                   g0 * g0 - (wx * wx + wy * wy), 0.0, INFINITY));
        } else {
            t = fmin(t, quad_entry(g2 - b->r2c, g1 - b->r1c, g0 - b->r0c, 0.0, INFINITY));
        }
    }
    return fmax(t, tc); /* both are lower bounds */
}

/* The first event in (0, T]: the least entry root of a non-excluded element, by a
 * best-first branch and bound over the index on node_bound (a node is opened only if the
 * moving disc may reach it before the best event so far).  INFINITY if none; -1 on
 * NOMEM. */
static double event_search(ma_ctx *C, const ma_bis *b, const int64_t *ex, int nex, double T)
{
    const ma_elems *E = &C->E;
    const ma_bvh *BV = &C->T;
    double best = INFINITY, lim = T;
    int64_t nh = 0;
    if (BV->nn == 0)
        return best;
    double tb0 = node_bound(b, BV->cap, C->eps, lim);
    if (!(tb0 < lim))
        return best;
    C->heapk[0] = tb0, C->heapn[0] = 0, nh = 1;
    while (nh > 0) {
        double key = C->heapk[0];
        int64_t nd = C->heapn[0];
        /* pop: move the last to the root and sift down */
        nh--;
        {
            double k = C->heapk[nh];
            int64_t v = C->heapn[nh], i = 0;
            for (;;) {
                int64_t c = 2 * i + 1;
                if (c >= nh)
                    break;
                if (c + 1 < nh && C->heapk[c + 1] < C->heapk[c])
                    c++;
                if (!(C->heapk[c] < k))
                    break;
                C->heapk[i] = C->heapk[c], C->heapn[i] = C->heapn[c], i = c;
            }
            C->heapk[i] = k, C->heapn[i] = v;
        }
        if (!(key < lim))
            break;
        if (BV->kid[2 * nd] < 0) {
            for (int64_t it = 0; it < BV->cnt[nd]; it++) {
                int64_t sg = BV->kid[2 * nd + 1] + it;
                for (int w = 0; w < 2; w++) {
                    int64_t e = w ? E->velem[sg] : sg;
                    if (e < 0)
                        continue;
                    int skip = 0;
                    for (int i = 0; i < nex; i++)
                        skip |= ex[i] == e;
                    if (skip)
                        continue;
                    double t = elem_entry(E, b, e, 0.0, lim);
                    if (t < best)
                        best = t, lim = t;
                }
            }
            continue;
        }
        for (int w = 0; w < 2; w++) {
            int64_t kd = BV->kid[2 * nd + w];
            double tk = node_bound(b, BV->cap + 5 * kd, C->eps, lim);
            if (!(tk < lim))
                continue;
            int64_t i = nh++; /* push: sift up (the heap holds at most all nodes) */
            while (i > 0 && tk < C->heapk[(i - 1) / 2]) {
                C->heapk[i] = C->heapk[(i - 1) / 2], C->heapn[i] = C->heapn[(i - 1) / 2];
                i = (i - 1) / 2;
            }
            C->heapk[i] = tk, C->heapn[i] = kd;
        }
    }
    return best;
}

/* Appends the samples of b over (ta, tb] (the chord and interpolated radius within tol;
 * straight pieces with linear radius need only the end). */
static int sample_piece(ma_ctx *C, const ma_bis *b, double ta, double tb)
{
    double step = bis_max_step(b, ta, C->tol);
    int64_t k = 1;
    if (isfinite(step) && step > 0 && tb - ta > step)
        k = (int64_t)ceil((tb - ta) / step);
    if (k > 100000000)
        k = 100000000;
    for (int64_t i = 1; i <= k; i++) {
        double x, y, r;
        bis_at(b, i == k ? tb : ta + (tb - ta) * (double)i / (double)k, &x, &y, &r);
        if (!push_sample(C, x, y, r))
            return 0;
    }
    return 1;
}

/* The foot of segment `who` reached its convex end (`how` 1: start, 2: end) at the last
 * sample (px, py, pr): the leaf, where the radius is 0.  At a radius above the event
 * accuracy a third element must have touched first (a missed event): TR_MISSED rather
 * than a false leaf inside the face. */
static int corner_leaf(ma_ctx *C, int64_t who, int how, double px, double py, double pr,
                       double ev[5], int64_t *leafv)
{
    *leafv = how == 1 ? who : C->E.next[who];
    if (pr > 1e-6 * C->E.diag) {
        ev[0] = px, ev[1] = py, ev[2] = pr;
        return TR_MISSED;
    }
    C->pr.v[C->pr.n - 1] = 0.0;
    return TR_LEAF;
}

/* Traces from (x, y, r) along the bisector of (e1, e2) in direction (dx, dy), appending
 * samples (the start too when `first`).  Each piece runs to the first of: an event (the
 * least exact entry root of a third element, searched in doubling parameter intervals
 * through the index), the closing of a window of the pair (a transition: the element is
 * switched, or at a convex corner the leaf), the leaf (r = 0).  On TR_EVENT,
 * ev = (x, y, r, tx, ty); on TR_LEAF *leafv = the convex vertex (or -1 if unknown). */
static int trace(ma_ctx *C, double x, double y, double r, int64_t e1, int64_t e2, double dx,
                 double dy, int first, double ev[5], int64_t *leafv)
{
    const ma_elems *E = &C->E;
    ma_bis b;
    bis_make(E, &b, e1, e2, x, y, dx, dy);
    if (first && !push_sample(C, x, y, r))
        return TR_NOMEM;
    *leafv = -1;
    /* every piece ends at an event or a window switch to another element: a branch along
     * a finely discretised arc has as many pieces as chords */
    for (int64_t piece = 0; piece < 4 * (E->ns + E->nv) + 16; piece++) {
        if (!isfinite(b.p0x) || !isfinite(b.p0y) || (b.kind == MA_PL && !(b.h > 0))) {
            /* a pair without a bisector on the interior side (a parabola whose focus is
             * not inside of its directrix): fail rather than output a wrong branch */
            ev[0] = (double)b.e1, ev[1] = (double)b.e2;
            return TR_BADPAIR;
        }
        int64_t ex[10], who = -1;
        int nex = excluded_set(E, &b, ex), how = 0;
        double tw = bis_window_exit(E, &b, 0.0, &who, &how);
        double tl = (b.kind == MA_LL && b.sg < 0) ? b.r0 : INFINITY; /* r = r0 - t */
        double T = fmin(tw, tl), te = event_search(C, &b, ex, nex, T);
        if (te < 0)
            return TR_NOMEM;
        if (te < INFINITY && te <= T) { /* an event */
            if (!sample_piece(C, &b, 0.0, te))
                return TR_NOMEM;
            bis_at(&b, te, &ev[0], &ev[1], &ev[2]);
            bis_tangent(&b, te, &ev[3], &ev[4]);
            return TR_EVENT;
        }
        if (!(T < INFINITY))
            return TR_STUCK;
        if (tl <= tw) { /* the leaf: two edges meeting at a convex corner */
            if (!sample_piece(C, &b, 0.0, tl))
                return TR_NOMEM;
            C->pr.v[C->pr.n - 1] = 0.0;
            *leafv = E->next[b.e1] == b.e2 ? b.e2 : E->next[b.e2] == b.e1 ? b.e1 : -1;
            return TR_LEAF;
        }
        /* a window closes at tw */
        if (!sample_piece(C, &b, 0.0, tw))
            return TR_NOMEM;
        double tx, ty, phx, phy, phr;
        bis_tangent(&b, tw, &tx, &ty);
        bis_at(&b, tw, &phx, &phy, &phr);
        int64_t en = window_switch(E, who, how);
        if (en < 0)
            return corner_leaf(C, who, how, phx, phy, phr, ev, leafv);
        int64_t ea = b.e1 == who ? en : b.e1, eb = b.e1 == who ? b.e2 : en;
        bis_make(E, &b, ea, eb, phx, phy, tx, ty);
        for (int k = 0; k < 3; k++) { /* lesson 2: a double transition */
            double x1, y1, r1;
            bis_at(&b, 1e-9 * E->diag, &x1, &y1, &r1);
            how = bis_window(E, &b, x1, y1, &who);
            if (!how)
                break;
            en = window_switch(E, who, how);
            if (en < 0)
                return corner_leaf(C, who, how, phx, phy, phr, ev, leafv);
            ea = b.e1 == who ? en : b.e1, eb = b.e1 == who ? b.e2 : en;
            bis_make(E, &b, ea, eb, phx, phy, tx, ty);
        }
    }
    return TR_STUCK;
}

/* ---- the junction registry: a hash of a grid of cell `arrive` --------------------- */
static int64_t hcell(const ma_ctx *C, double v, double v0)
{
    return (int64_t)floor((v - v0) / C->arrive);
}

static int64_t hbucket(const ma_ctx *C, int64_t ix, int64_t iy)
{
    uint64_t h = (uint64_t)ix * 0x9E3779B97F4A7C15ULL ^ (uint64_t)iy * 0xC2B2AE3D27D4EB4FULL;
    return (int64_t)((h ^ (h >> 29)) & (uint64_t)C->hmask);
}

static void junction_link(ma_ctx *C, int64_t j)
{
    int64_t b = hbucket(C, hcell(C, C->J[j].x, C->hx0), hcell(C, C->J[j].y, C->hy0));
    C->J[j].hnext = C->hhead[b];
    C->hhead[b] = j;
}

/* Do junctions a and b touch the same elements? */
static int same_elements(const ma_ctx *C, int64_t a, int64_t b)
{
    const ma_junction *A = &C->J[a], *B = &C->J[b];
    if (A->nelem != B->nelem)
        return 0;
    for (int64_t i = 0; i < A->nelem; i++) {
        int found = 0;
        for (int64_t k = 0; k < B->nelem && !found; k++)
            found = C->jelem.v[A->first_elem + i] == C->jelem.v[B->first_elem + k];
        if (!found)
            return 0;
    }
    return 1;
}

/* The registered junction within `arrive` of the new (unregistered) junction jn that
 * touches the same elements (the lowest index if several), or -1.  Position alone is
 * not enough: at 100 000 segments distinct junctions at needle bases lie 1e-4 apart, and
 * an arriving trace taken for the wrong one left a true junction out (a zero-length
 * loop in its place). */
static int64_t junction_find(const ma_ctx *C, int64_t jn)
{
    double x = C->J[jn].x, y = C->J[jn].y;
    int64_t ix = hcell(C, x, C->hx0), iy = hcell(C, y, C->hy0), best = -1;
    for (int64_t a = ix - 1; a <= ix + 1; a++)
        for (int64_t c = iy - 1; c <= iy + 1; c++)
            for (int64_t j = C->hhead[hbucket(C, a, c)]; j >= 0; j = C->J[j].hnext)
                if (hypot(C->J[j].x - x, C->J[j].y - y) <= C->arrive && (best < 0 || j < best) &&
                    same_elements(C, j, jn))
                    best = j;
    return best;
}

/* Traces one branch from a leaf (j0 = -1) or a junction port, through pass-through
 * (degree-2) events, to a leaf or a junction; registers new junctions and their ports. */
static mfg_status run_branch(ma_ctx *C, double x, double y, double r, int64_t e1, int64_t e2,
                             double dx, double dy, int64_t j0)
{
    const ma_elems *E = &C->E;
    if (!ivec_push(&C->boff, C->px.n))
        return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (branches)");
    int first = 1;
    for (;;) {
        double ev[5];
        int64_t leafv;
        int rc = trace(C, x, y, r, e1, e2, dx, dy, first, ev, &leafv);
        if (rc == TR_NOMEM)
            return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (samples)");
        if (rc == TR_BADPAIR)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace from (%g, %g) reached elements %lld and "
                            "%lld, which have no bisector inside the face (a missed window "
                            "event; known on very thin spikes)",
                            x, y, (long long)ev[0], (long long)ev[1]);
        if (rc == TR_MISSED)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace of elements %lld and %lld reached a convex "
                            "corner at (%g, %g) with radius %g (a missed event)",
                            (long long)e1, (long long)e2, ev[0], ev[1], ev[2]);
        if (rc == TR_STUCK)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace of the bisector of elements %lld and %lld "
                            "from (%g, %g) did not reach an event",
                            (long long)e1, (long long)e2, x, y);
        if (rc == TR_LEAF) {
            int64_t n = C->px.n - 1, best = leafv;
            if (best < 0) { /* not identified by the trace: the nearest vertex */
                double bd = INFINITY;
                for (int64_t k = 0; k < E->ns; k++) {
                    double d = hypot(E->ax[k] - C->px.v[n], E->ay[k] - C->py.v[n]);
                    if (d < bd)
                        bd = d, best = k;
                }
            }
            C->reached[best] = 1;
            C->pr.v[n] = 0.0;
            return ivec_push(&C->bend, j0) && ivec_push(&C->bend, -1)
                       ? MFG_OK
                       : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        }
        double back = atan2(-ev[4], -ev[3]);
        int64_t j = junction_make(C, ev[0], ev[1], ev[2]);
        if (j < 0)
            return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (junctions)");
        /* A known junction (lesson 4: identified with the event accuracy, and by its
         * elements): forget the new one, arrive at the known one. */
        int64_t jk = junction_find(C, j);
        if (jk >= 0) {
            C->jelem.n = C->J[j].first_elem;
            C->np = C->J[j].first_port;
            C->nj--;
            j = jk;
            int64_t p = port_pick(C, j, back, 0);
            if (p >= 0)
                C->P[p].used = 1;
            int64_t n = C->px.n - 1;
            C->px.v[n] = C->J[j].x, C->py.v[n] = C->J[j].y, C->pr.v[n] = C->J[j].r;
            return ivec_push(&C->bend, j0) && ivec_push(&C->bend, j)
                       ? MFG_OK
                       : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        }
        if (C->J[j].nport == 2) { /* a pass-through: continue the same branch */
            int64_t p = port_pick(C, j, back, 1);
            x = ev[0], y = ev[1], r = ev[2];
            e1 = C->P[p].e1, e2 = C->P[p].e2;
            dx = cos(C->P[p].angle), dy = sin(C->P[p].angle);
            /* forget it: it is not a junction */
            C->jelem.n = C->J[j].first_elem;
            C->np = C->J[j].first_port;
            C->nj--;
            first = 0;
            continue;
        }
        junction_link(C, j);
        int64_t pin = port_pick(C, j, back, 0);
        if (pin >= 0)
            C->P[pin].used = 1;
        for (int64_t p = C->J[j].first_port; p < C->J[j].first_port + C->J[j].nport; p++)
            if (!C->P[p].used && !ivec_push(&C->stack, p))
                return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        return ivec_push(&C->bend, j0) && ivec_push(&C->bend, j)
                   ? MFG_OK
                   : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
    }
}

/* ---- input -------------------------------------------------------------------------- */

/* Even-odd: is (x, y) inside ring r of the cleaned vertices?  (Only used for a vertex of
 * another ring, which the no-touching check guarantees is not on ring r.) */
static int ring_contains(const double *vx, const double *vy, int64_t lo, int64_t hi, double x,
                         double y)
{
    int in = 0;
    for (int64_t i = lo; i < hi; i++) {
        int64_t j = i + 1 < hi ? i + 1 : lo;
        if ((vy[i] > y) != (vy[j] > y)) {
            int o = mfg_orient2d(vx[i], vy[i], vx[j], vy[j], x, y);
            if ((vy[j] > vy[i]) ? o > 0 : o < 0)
                in = !in;
        }
    }
    return in;
}

/* Do closed segments ab and cd share a point?  Exact (orient2d, dot2d). */
static int segs_touch(double ax, double ay, double bx, double by, double cx, double cy,
                      double dx, double dy)
{
    int o1 = mfg_orient2d(ax, ay, bx, by, cx, cy), o2 = mfg_orient2d(ax, ay, bx, by, dx, dy);
    int o3 = mfg_orient2d(cx, cy, dx, dy, ax, ay), o4 = mfg_orient2d(cx, cy, dx, dy, bx, by);
    if (o1 * o2 < 0 && o3 * o4 < 0)
        return 1;
    /* a collinear endpoint on the other segment (closed: dot <= 0 from both ends) */
    if (o1 == 0 && mfg_dot2d(cx, cy, ax, ay, bx, by) <= 0)
        return 1;
    if (o2 == 0 && mfg_dot2d(dx, dy, ax, ay, bx, by) <= 0)
        return 1;
    if (o3 == 0 && mfg_dot2d(ax, ay, cx, cy, dx, dy) <= 0)
        return 1;
    if (o4 == 0 && mfg_dot2d(bx, by, cx, cy, dx, dy) <= 0)
        return 1;
    return 0;
}

void mfg_medial_axis_free(struct mfg_medial_axis *a)
{
    if (!a)
        return;
    free(a->branch_offsets);
    free(a->points);
    free(a->radii);
    free(a->branch_ends);
    free(a->junction_points);
    free(a->junction_radii);
    free(a->junction_degree);
    free(a->junction_offsets);
    free(a->junction_elements);
    free(a);
}

static void elems_free(ma_elems *E)
{
    free(E->ax), free(E->ay), free(E->ux), free(E->uy), free(E->nx), free(E->ny);
    free(E->len), free(E->prev), free(E->next), free(E->orig), free(E->reflex);
    free(E->convex), free(E->velem), free(E->vk);
}

/* ---- the result: short junction-junction branches contracted, canonical order -------- */

typedef struct { double x, y, r; int64_t id; } ma_jkey;

static int cmp_jkey(const void *pa, const void *pb)
{
    const ma_jkey *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    if (a->r != b->r)
        return a->r < b->r ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

typedef struct { int64_t a, c; double ex, ey, mx, my; int64_t b; int flip; } ma_bkey;

static int cmp_bkey(const void *pa, const void *pb)
{
    const ma_bkey *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    if (a->c != b->c)
        return a->c < b->c ? -1 : 1;
    double ka[4] = {a->ex, a->ey, a->mx, a->my}, kb[4] = {b->ex, b->ey, b->mx, b->my};
    for (int i = 0; i < 4; i++)
        if (ka[i] != kb[i])
            return ka[i] < kb[i] ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

typedef struct { double len; int64_t b; } ma_lkey;

static int cmp_lkey(const void *pa, const void *pb)
{
    const ma_lkey *a = pa, *b = pb;
    if (a->len != b->len)
        return a->len < b->len ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

/* The flat result.  Junctions joined by a branch shorter than tol are one junction
 * (contracted in order of length, so a branch closing a cycle is kept: the cycle around a
 * tiny hole stays): the representative is the member touching the most elements (then the
 * lowest (x, y)), the elements the union, the degree the branch ends at it; the ends of the other
 * branches are moved onto it (by < tol, radius its own).  Canonical order: junctions by
 * (x, y, r); a branch runs from its lower junction (a leaf end last), self-loops from the
 * side with the lower second sample, and branches are sorted by (start junction, end
 * junction -- leaves after all junctions --, far end point, middle sample). */
static mfg_status assemble(const ma_ctx *C, struct mfg_medial_axis **out)
{
    const ma_elems *E = &C->E;
    int64_t nb = C->boff.n, ns = C->px.n, nj = C->nj;
    mfg_status st = MFG_OK;
    size_t zb = (size_t)(nb + 1), zj = (size_t)(nj + 1);
    int64_t *par = malloc(zj * sizeof *par), *rep = malloc(zj * sizeof *rep);
    int64_t *newid = malloc(zj * sizeof *newid), *deg = calloc(zj, sizeof *deg);
    int64_t *mhead = malloc(zj * sizeof *mhead), *mnext = malloc(zj * sizeof *mnext);
    int8_t *gone = calloc(zb, 1);
    ma_lkey *lk = malloc(zb * sizeof *lk);
    ma_jkey *jk = malloc(zj * sizeof *jk);
    ma_bkey *bk = malloc(zb * sizeof *bk);
    int64_t *eids = malloc((size_t)(C->jelem.n + 1) * sizeof *eids);
    struct mfg_medial_axis *A = calloc(1, sizeof *A);
    if (!par || !rep || !newid || !deg || !mhead || !mnext || !gone || !lk || !jk || !bk ||
        !eids || !A) {
        st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (result)");
        goto fail;
    }
    /* contract the short junction-junction branches */
    int64_t nl = 0;
    for (int64_t j = 0; j < nj; j++)
        par[j] = j;
    for (int64_t b = 0; b < nb; b++) {
        int64_t lo = C->boff.v[b], hi = b + 1 < nb ? C->boff.v[b + 1] : ns;
        int64_t j0 = C->bend.v[2 * b], j1 = C->bend.v[2 * b + 1];
        if (j0 < 0 || j1 < 0 || j0 == j1)
            continue;
        double len = 0;
        for (int64_t i = lo; i + 1 < hi && len < C->tol; i++)
            len += hypot(C->px.v[i + 1] - C->px.v[i], C->py.v[i + 1] - C->py.v[i]);
        if (len < C->tol)
            lk[nl].len = len, lk[nl].b = b, nl++;
    }
    qsort(lk, (size_t)nl, sizeof *lk, cmp_lkey);
    for (int64_t i = 0; i < nl; i++) {
        int64_t b = lk[i].b;
        int64_t r0 = mfg_uf_find(par, C->bend.v[2 * b]), r1 = mfg_uf_find(par, C->bend.v[2 * b + 1]);
        if (r0 == r1)
            continue;
        par[r0 > r1 ? r0 : r1] = r0 > r1 ? r1 : r0;
        gone[b] = 1;
    }
    /* representatives and canonical junction order */
    for (int64_t j = 0; j < nj; j++)
        rep[j] = mhead[j] = -1;
    for (int64_t j = nj - 1; j >= 0; j--) { /* most elements, then lowest (x, y): not the
                                               tracing order, which follows the input's */
        int64_t r = mfg_uf_find(par, j), k = rep[r];
        const ma_junction *A = &C->J[j], *B = k >= 0 ? &C->J[k] : NULL;
        if (!B || A->nelem > B->nelem ||
            (A->nelem == B->nelem && (A->x < B->x || (A->x == B->x && A->y < B->y))))
            rep[r] = j;
        mnext[j] = mhead[r], mhead[r] = j;
    }
    int64_t nk = 0;
    for (int64_t j = 0; j < nj; j++)
        if (par[j] == j) {
            const ma_junction *J = &C->J[rep[j]];
            jk[nk].x = J->x, jk[nk].y = J->y, jk[nk].r = J->r, jk[nk].id = j, nk++;
        }
    qsort(jk, (size_t)nk, sizeof *jk, cmp_jkey);
    for (int64_t k = 0; k < nk; k++)
        newid[jk[k].id] = k;
    /* branches: ends mapped, orientation, order */
    int64_t nbo = 0, nso = 0;
    for (int64_t b = 0; b < nb; b++) {
        if (gone[b])
            continue;
        int64_t lo = C->boff.v[b], hi = b + 1 < nb ? C->boff.v[b + 1] : ns;
        int64_t j0 = C->bend.v[2 * b], j1 = C->bend.v[2 * b + 1];
        int64_t a = j0 >= 0 ? newid[mfg_uf_find(par, j0)] : INT64_MAX;
        int64_t c = j1 >= 0 ? newid[mfg_uf_find(par, j1)] : INT64_MAX;
        int flip = c < a;
        if (a == c && hi - lo >= 3) { /* a self-loop, or both ends leaves */
            int64_t p = a == INT64_MAX ? lo : lo + 1, q = a == INT64_MAX ? hi - 1 : hi - 2;
            flip = C->px.v[q] < C->px.v[p] || (C->px.v[q] == C->px.v[p] && C->py.v[q] < C->py.v[p]);
        }
        ma_bkey *K = &bk[nbo++];
        K->a = flip ? c : a, K->c = flip ? a : c, K->b = b, K->flip = flip;
        int64_t far = flip ? lo : hi - 1, mid = lo + (hi - lo) / 2;
        K->ex = C->px.v[far], K->ey = C->py.v[far], K->mx = C->px.v[mid], K->my = C->py.v[mid];
        if (K->a != INT64_MAX)
            deg[K->a]++;
        if (K->c != INT64_MAX)
            deg[K->c]++;
        nso += hi - lo;
    }
    qsort(bk, (size_t)nbo, sizeof *bk, cmp_bkey);
    /* the flat arrays */
    A->nbranches = nbo, A->npoints = nso, A->njunctions = nk;
    A->branch_offsets = malloc((size_t)(nbo + 1) * sizeof(int64_t));
    A->points = malloc((size_t)(2 * nso + 1) * sizeof(double));
    A->radii = malloc((size_t)(nso + 1) * sizeof(double));
    A->branch_ends = malloc((size_t)(2 * nbo + 1) * sizeof(int64_t));
    A->junction_points = malloc((size_t)(2 * nk + 1) * sizeof(double));
    A->junction_radii = malloc((size_t)(nk + 1) * sizeof(double));
    A->junction_degree = malloc((size_t)(nk + 1) * sizeof(int64_t));
    A->junction_offsets = malloc((size_t)(nk + 1) * sizeof(int64_t));
    A->junction_elements = malloc((size_t)(C->jelem.n + 1) * sizeof(int64_t));
    if (!A->branch_offsets || !A->points || !A->radii || !A->branch_ends ||
        !A->junction_points || !A->junction_radii || !A->junction_degree ||
        !A->junction_offsets || !A->junction_elements) {
        st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (result)");
        goto fail;
    }
    int64_t o = 0;
    for (int64_t k = 0; k < nbo; k++) {
        const ma_bkey *K = &bk[k];
        int64_t lo = C->boff.v[K->b], hi = K->b + 1 < nb ? C->boff.v[K->b + 1] : ns;
        A->branch_offsets[k] = o;
        A->branch_ends[2 * k] = K->a == INT64_MAX ? -1 : K->a;
        A->branch_ends[2 * k + 1] = K->c == INT64_MAX ? -1 : K->c;
        for (int64_t i = 0; i < hi - lo; i++, o++) {
            int64_t s = K->flip ? hi - 1 - i : lo + i;
            A->points[2 * o] = C->px.v[s], A->points[2 * o + 1] = C->py.v[s];
            A->radii[o] = C->pr.v[s];
        }
        for (int e = 0; e < 2; e++) { /* ends onto their (representative) junction */
            int64_t j = A->branch_ends[2 * k + e], s = e ? o - 1 : A->branch_offsets[k];
            if (j < 0)
                continue;
            const ma_junction *J = &C->J[rep[jk[j].id]];
            A->points[2 * s] = J->x, A->points[2 * s + 1] = J->y, A->radii[s] = J->r;
        }
    }
    A->branch_offsets[nbo] = o;
    int64_t oe = 0;
    for (int64_t k = 0; k < nk; k++) {
        const ma_junction *J = &C->J[rep[jk[k].id]];
        A->junction_points[2 * k] = J->x, A->junction_points[2 * k + 1] = J->y;
        A->junction_radii[k] = J->r;
        A->junction_degree[k] = deg[k];
        A->junction_offsets[k] = oe;
        int64_t ne = 0;
        for (int64_t j = mhead[jk[k].id]; j >= 0; j = mnext[j]) { /* the members */
            for (int64_t i = 0; i < C->J[j].nelem; i++) {
                int64_t e = C->jelem.v[C->J[j].first_elem + i];
                eids[ne++] = is_seg(E, e) ? E->orig[e] : -1 - E->orig[E->vk[e - E->ns]];
            }
        }
        qsort(eids, (size_t)ne, sizeof *eids, mfg_cmp_i64);
        for (int64_t i = 0; i < ne; i++)
            if (i == 0 || eids[i] != eids[i - 1])
                A->junction_elements[oe++] = eids[i];
    }
    A->junction_offsets[nk] = oe;
    *out = A;
    A = NULL;
fail:
    mfg_medial_axis_free(A);
    free(par), free(rep), free(newid), free(deg), free(mhead), free(mnext), free(gone);
    free(lk), free(jk), free(bk);
    free(eids);
    return st;
}

mfg_status mfg_medial_axis(const double *xy, const int64_t *ring_offsets, int64_t nrings,
                           double tol, struct mfg_medial_axis **out)
{
    return mfg_medial_axis_p(xy, ring_offsets, nrings, tol, out, NULL);
}

/* Work units between progress reports: an edge checked against its neighbours in the
 * index (~1 us), a branch traced (~0.1-1 ms). */
#define AXIS_EVERY_EDGES 16384
#define AXIS_EVERY_BRANCHES 32

mfg_status mfg_medial_axis_p(const double *xy, const int64_t *ring_offsets, int64_t nrings,
                             double tol, struct mfg_medial_axis **out,
                             const mfg_progress *progress)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out is NULL");
    if (!ring_offsets)
        return mfg_fail(MFG_ERR_NULL, "ring_offsets is NULL");
    if (nrings < 0 || nrings > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "nrings must be between 0 and 2^40 (got %lld)",
                        (long long)nrings);
    if (nrings == 0)
        return mfg_fail(MFG_ERR_DEGENERATE, "no rings: a face needs at least one ring");
    if (!(tol > 0) || !mfg_coord_ok(tol))
        return mfg_fail(MFG_ERR_INVALID,
                        "tolerance must be > 0 and between 2^-200 and 2^200 (got %g)", tol);
    if (ring_offsets[0] != 0)
        return mfg_fail(MFG_ERR_INVALID, "ring_offsets[0] must be 0 (got %lld)",
                        (long long)ring_offsets[0]);
    for (int64_t r = 0; r < nrings; r++) {
        if (ring_offsets[r + 1] < ring_offsets[r] || ring_offsets[r + 1] > MFG_MAX_COUNT)
            return mfg_fail(MFG_ERR_INVALID,
                            "ring_offsets must be non-decreasing and <= 2^40 (ring %lld: %lld "
                            "after %lld)",
                            (long long)r, (long long)ring_offsets[r + 1],
                            (long long)ring_offsets[r]);
    }
    int64_t nin = ring_offsets[nrings];
    if (nin > 0 && !xy)
        return mfg_fail(MFG_ERR_NULL, "xy (ring vertices) is NULL");
    for (int64_t k = 0; k < nin; k++)
        if (!mfg_coord_ok(xy[2 * k]) || !mfg_coord_ok(xy[2 * k + 1]))
            return mfg_fail(MFG_ERR_INVALID,
                            "vertex %lld is NaN, infinite or out of range: (%g, %g)",
                            (long long)k, xy[2 * k], xy[2 * k + 1]);

    mfg_status st = MFG_OK;
    ma_ctx C;
    memset(&C, 0, sizeof C);
    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_medial_axis");
    struct mfg_medial_axis *res = NULL;
    ma_elems *E = &C.E;
    size_t n1 = (size_t)(nin > 0 ? nin : 1);
    double *vx = malloc(n1 * sizeof *vx), *vy = malloc(n1 * sizeof *vy);
    int64_t *vo = malloc(n1 * sizeof *vo), *roff = malloc((size_t)(nrings + 1) * sizeof *roff);
    E->ax = malloc(n1 * sizeof(double)), E->ay = malloc(n1 * sizeof(double));
    E->ux = malloc(n1 * sizeof(double)), E->uy = malloc(n1 * sizeof(double));
    E->nx = malloc(n1 * sizeof(double)), E->ny = malloc(n1 * sizeof(double));
    E->len = malloc(n1 * sizeof(double));
    E->prev = malloc(n1 * sizeof(int64_t)), E->next = malloc(n1 * sizeof(int64_t));
    E->orig = malloc(n1 * sizeof(int64_t)), E->velem = malloc(n1 * sizeof(int64_t));
    E->vk = malloc(n1 * sizeof(int64_t));
    E->reflex = malloc(n1), E->convex = malloc(n1);
    C.reached = calloc(n1, 1);
    if (!vx || !vy || !vo || !roff || !E->ax || !E->ay || !E->ux || !E->uy || !E->nx ||
        !E->ny || !E->len || !E->prev || !E->next || !E->orig || !E->velem || !E->vk ||
        !E->reflex || !E->convex || !C.reached) {
        st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld ring vertices", (long long)nin);
        goto done;
    }

    if (!mfg_prog_stage(&prog, "axis: setup", 0, 0.1, AXIS_EVERY_EDGES)) {
        st = mfg_prog_fail(&prog);
        goto done;
    }
    /* (1) Clean each ring: drop consecutive equal vertices (and a repeated closing one),
     * then vertices where the boundary goes straight on (orient2d = 0, dot > 0); a
     * vertex where it turns back (a spike) is a self-touching ring. */
    int64_t nv = 0;
    roff[0] = 0;
    for (int64_t r = 0; r < nrings; r++) {
        int64_t lo = nv;
        for (int64_t k = ring_offsets[r]; k < ring_offsets[r + 1]; k++) {
            double x = xy[2 * k], y = xy[2 * k + 1];
            if (nv > lo && vx[nv - 1] == x && vy[nv - 1] == y)
                continue;
            vx[nv] = x, vy[nv] = y, vo[nv] = k, nv++;
        }
        while (nv - lo > 1 && vx[nv - 1] == vx[lo] && vy[nv - 1] == vy[lo])
            nv--;
        for (int changed = 1; changed && nv - lo >= 3;) {
            changed = 0;
            int64_t m = nv - lo;
            for (int64_t i = 0; i < m && m >= 3; i++) {
                int64_t a = lo + (i + m - 1) % m, b = lo + i, c = lo + (i + 1) % m;
                if (mfg_orient2d(vx[a], vy[a], vx[b], vy[b], vx[c], vy[c]) != 0)
                    continue;
                if (mfg_dot2d(vx[b], vy[b], vx[a], vy[a], vx[c], vy[c]) > 0) {
                    st = mfg_fail(MFG_ERR_INVALID,
                                  "ring %lld turns back on itself at vertex %lld (a spike: the "
                                  "ring touches itself)",
                                  (long long)r, (long long)vo[b]);
                    goto done;
                }
                memmove(vx + b, vx + b + 1, (size_t)(nv - b - 1) * sizeof *vx);
                memmove(vy + b, vy + b + 1, (size_t)(nv - b - 1) * sizeof *vy);
                memmove(vo + b, vo + b + 1, (size_t)(nv - b - 1) * sizeof *vo);
                nv--, m--, changed = 1;
                i--;
            }
        }
        if (nv - lo < 3) {
            st = mfg_fail(MFG_ERR_DEGENERATE,
                          "ring %lld has fewer than 3 distinct, non-collinear vertices (%lld "
                          "given)",
                          (long long)r, (long long)(ring_offsets[r + 1] - ring_offsets[r]));
            goto done;
        }
        roff[r + 1] = nv;
    }

    /* (2) The index over the cleaned segments; no two edges may share a point other than
     * the common vertex of neighbours (exact tests on the pairs whose boxes touch; the
     * lowest pair (i, j) is reported). */
    for (int64_t r = 0; r < nrings; r++)
        for (int64_t k = roff[r]; k < roff[r + 1]; k++) {
            int64_t k2 = k + 1 < roff[r + 1] ? k + 1 : roff[r];
            E->next[k] = k2, E->prev[k2] = k, E->orig[k] = r; /* orig: the ring, for now */
        }
    if (!bvh_build(&C.T, vx, vy, E->next, nv)) {
        st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate the index of %lld edges", (long long)nv);
        goto done;
    }
    double diag0 = 0; /* the boxes' padding: a touch may round to a tiny distance */
    for (int64_t k = 0; k < nv; k++)
        diag0 = fmax(diag0, fmax(fabs(vx[k] - vx[0]), fabs(vy[k] - vy[0])));
    for (int64_t i = 0; i < nv; i++) {
        if (!mfg_prog_poll(&prog, (double)i, (double)nv)) {
            st = mfg_prog_fail(&prog);
            goto done;
        }
        int64_t i2 = E->next[i], jbest = -1;
        C.cand.n = 0;
        if (!bvh_collect(&C.T, vx[i], vy[i], vx[i2], vy[i2], 1e-9 * diag0, i + 1, &C.cand)) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (index query)");
            goto done;
        }
        for (int64_t c = 0; c < C.cand.n; c++) {
            int64_t jj = C.cand.v[c], j2 = E->next[jj];
            if (jj <= i || (jbest >= 0 && jj >= jbest) || jj == i2 || j2 == i)
                continue; /* neighbours share their common vertex only, unless they
                             overlap (excluded by the spike check) */
            if (segs_touch(vx[i], vy[i], vx[i2], vy[i2], vx[jj], vy[jj], vx[j2], vy[j2]))
                jbest = jj;
        }
        if (jbest >= 0) {
            st = mfg_fail(MFG_ERR_INVALID,
                          "the boundary touches or crosses itself: edge %lld (ring %lld) and "
                          "edge %lld (ring %lld); the medial axis needs disjoint simple rings",
                          (long long)vo[i], (long long)E->orig[i], (long long)vo[jbest],
                          (long long)E->orig[jbest]);
            goto done;
        }
    }

    /* (3) Segments with inward normals: the interior is on the left of a ring iff its
     * orientation (signed area) and its nesting parity agree. */
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (int64_t k = 0; k < nv; k++) {
        xmin = fmin(xmin, vx[k]), xmax = fmax(xmax, vx[k]);
        ymin = fmin(ymin, vy[k]), ymax = fmax(ymax, vy[k]);
    }
    E->diag = hypot(xmax - xmin, ymax - ymin);
    E->ns = nv;
    for (int64_t r = 0; r < nrings; r++) {
        int64_t lo = roff[r], hi = roff[r + 1];
        /* orientation from the exact turn at the lowest (then leftmost) vertex */
        int64_t b = lo;
        for (int64_t k = lo; k < hi; k++)
            if (vy[k] < vy[b] || (vy[k] == vy[b] && vx[k] < vx[b]))
                b = k;
        int64_t a = b > lo ? b - 1 : hi - 1, c = b + 1 < hi ? b + 1 : lo;
        int ccw = mfg_orient2d(vx[a], vy[a], vx[b], vy[b], vx[c], vy[c]) > 0;
        int depth = 0;
        for (int64_t s = 0; s < nrings; s++)
            if (s != r)
                depth += ring_contains(vx, vy, roff[s], roff[s + 1], vx[lo], vy[lo]);
        double side = (ccw == (depth % 2 == 0)) ? 1.0 : -1.0; /* +1: interior on the left */
        for (int64_t k = lo; k < hi; k++) {
            int64_t k2 = k + 1 < hi ? k + 1 : lo;
            double dx = vx[k2] - vx[k], dy = vy[k2] - vy[k], l = hypot(dx, dy);
            E->ax[k] = vx[k], E->ay[k] = vy[k], E->ux[k] = dx / l, E->uy[k] = dy / l;
            E->nx[k] = -side * dy / l, E->ny[k] = side * dx / l, E->len[k] = l;
            E->next[k] = k2, E->prev[k2] = k, E->orig[k] = vo[k];
        }
        for (int64_t k = lo; k < hi; k++) {
            int64_t p = E->prev[k];
            int o = mfg_orient2d(vx[p], vy[p], vx[k], vy[k], vx[E->next[k]], vy[E->next[k]]);
            E->reflex[k] = (o * side < 0);
            E->convex[k] = (o * side > 0);
        }
    }
    E->nv = 0;
    for (int64_t k = 0; k < nv; k++) {
        E->velem[k] = E->reflex[k] ? nv + E->nv : -1;
        if (E->reflex[k])
            E->vk[E->nv++] = k;
    }
    C.tol = tol;
    C.eps = 1e-10 * E->diag; /* padding of the index's bounds */
    /* Events are exact roots, so a junction's elements touch its disc to rounding
     * (~1e-15 diag): gather them with 1e-11 diag.  Wider picks up elements of a thin
     * spike that do not touch (7.6e-8 diag away on a 100k-segment star with 1e-9), whose
     * foot angles then misorder the ports (a port between two segments adjacent at a
     * reflex vertex: no bisector inside).  An arriving trace locates its junction less
     * precisely (a grazing third element: a near-double root): 1e-6 diag. */
    C.gather = 1e-11 * E->diag;
    C.arrive = 1e-6 * E->diag;
    {
        int64_t nb = 64;
        while (nb < 4 * (E->ns + E->nv))
            nb *= 2;
        C.hhead = malloc((size_t)nb * sizeof *C.hhead);
        if (!C.hhead) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (junction registry)");
            goto done;
        }
        for (int64_t b = 0; b < nb; b++)
            C.hhead[b] = -1;
        C.hmask = nb - 1, C.hx0 = xmin, C.hy0 = ymin;
        C.heapk = malloc((size_t)(C.T.nn + 1) * sizeof *C.heapk);
        C.heapn = malloc((size_t)(C.T.nn + 1) * sizeof *C.heapn);
        if (!C.heapk || !C.heapn) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (search heap)");
            goto done;
        }
    }

    /* (4) Trace from every convex corner not yet reached, then every open port.  A
     * branch is a unit of progress; there are about as many as vertices. */
    if (!mfg_prog_stage(&prog, "axis: branches", 0.1, 0.95, AXIS_EVERY_BRANCHES)) {
        st = mfg_prog_fail(&prog);
        goto done;
    }
    int64_t nrun = 0;
    for (int64_t k = 0; k < nv; k++) {
        if (!E->convex[k] || C.reached[k])
            continue;
        if (!mfg_prog_poll(&prog, (double)nrun++, (double)(2 * nv))) {
            st = mfg_prog_fail(&prog);
            goto done;
        }
        C.reached[k] = 1;
        int64_t p = E->prev[k];
        double dx = E->nx[p] + E->nx[k], dy = E->ny[p] + E->ny[k], l = hypot(dx, dy);
        st = run_branch(&C, vx[k], vy[k], 0.0, p, k, dx / l, dy / l, -1);
        if (st != MFG_OK)
            goto done;
        while (C.stack.n > 0) {
            int64_t q = C.stack.v[--C.stack.n];
            if (C.P[q].used)
                continue;
            C.P[q].used = 1;
            if (!mfg_prog_poll(&prog, (double)nrun++, (double)(2 * nv))) {
                st = mfg_prog_fail(&prog);
                goto done;
            }
            ma_junction *J = &C.J[C.P[q].j];
            st = run_branch(&C, J->x, J->y, J->r, C.P[q].e1, C.P[q].e2, cos(C.P[q].angle),
                            sin(C.P[q].angle), C.P[q].j);
            if (st != MFG_OK)
                goto done;
        }
    }

    /* (5) The flat result. */
    if (!mfg_prog_stage(&prog, "axis: output", 0.95, 1.0, 1)) {
        st = mfg_prog_fail(&prog);
        goto done;
    }
    st = assemble(&C, &res);
    if (st == MFG_OK && !mfg_prog_stage(&prog, "axis: done", 1.0, 1.0, 1)) {
        mfg_medial_axis_free(res);
        st = mfg_prog_fail(&prog);
    }
    if (st == MFG_OK) {
        *out = res;
        mfg_clear_error();
    }
done:
    free(vx), free(vy), free(vo), free(roff);
    elems_free(E);
    free(C.reached), free(C.hhead), free(C.cand.v), free(C.heapk), free(C.heapn);
    bvh_free(&C.T);
    free(C.px.v), free(C.py.v), free(C.pr.v), free(C.boff.v), free(C.bend.v);
    free(C.J), free(C.P), free(C.jelem.v), free(C.stack.v);
    return st;
}
