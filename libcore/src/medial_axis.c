/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial_axis.c - the medial axis of a planar face (issue 9 section 2) by ridge tracing.
 *
 * Method (design: the ma2d notes, section 2 and the lessons of section 7).  The elements
 * of the boundary are its edges as open segments (with the inward normal) and its reflex
 * vertices as points; convex vertices are the leaves of the axis (radius 0).  The axis is
 * a union of bisectors of element pairs: segment-segment (a line, or the midline of two
 * parallel edges), point-segment (a parabola), point-point (a line).  A trace starts at a
 * leaf and follows the bisector of its pair; it advances conservatively on the clearance
 * margin m(t) = min over the other elements of d_e(p(t)) - r(t) (a step never exceeds
 * m / (|p'| + |r'|), so no third element can be passed) until a third element touches
 * the disc: an event.  At an event every element touching the disc is gathered, sorted
 * by the angle of its foot point, and each angularly consecutive pair that is not
 * (segment, its own endpoint) is a port -- a branch leaving the junction.  Where the
 * foot of a segment element leaves the open segment at a reflex vertex, the element is
 * switched to that vertex (a transition along the branch, not a junction).
 *
 * Status (first version, 2026-11-29):
 * - the nearest elements are found by scanning all of them (O(n) per advancement
 *   step) and events are approached by conservative advancement (hundreds of steps
 *   per branch): 1 000 segments take 2 s, 2 000 take 14 s (design target: 20 ms for
 *   1 000).  Next: the design's BVH and exact per-element event roots.
 * - needle spikes (3 000-segment jittered star, seed 7; test_needles, the disabled
 *   ctest medial_axis_needles): with the junction gather at 1e-7 diag a port paired the
 *   two segments adjacent at a reflex vertex (MFG_ERR_INTERNAL); fixed (gather 10 eps),
 *   but two branches still end at radius 0 inside the face, 0.34 from the boundary: a
 *   window switch at a convex vertex is taken for the leaf where a third element should
 *   have produced an event first.  Not yet diagnosed.
 * - junctions closer than tol are not merged; branch order follows the tracing; the
 *   crossing check is O(n^2). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_internal.h"
#include "predicates.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

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

typedef struct {
    int64_t j;      /* junction */
    int64_t e1, e2; /* element pair of the bisector leaving it */
    double angle;   /* direction of the port */
    int used;
} ma_port;

typedef struct {
    double x, y, r;
    int64_t first_elem, nelem, first_port, nport;
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
    double *dist;             /* scratch: distance to every element */
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
} ma_bis;

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

/* A bound of |p'| + |r'| over [t0, t1]: the step that keeps the margin non-negative. */
static double bis_speed(const ma_bis *b, double t0, double t1)
{
    switch (b->kind) {
    case MA_PAR:
        return 1.0;
    case MA_LL:
        return hypot(b->qx, b->qy) + 1.0;
    case MA_PP:
        return 2.0;
    default: {
        double g0 = fabs(b->x0 + b->sg * t0 - b->fx), g1 = fabs(b->x0 + b->sg * t1 - b->fx);
        double g = (g0 > g1 ? g0 : g1) / b->h;
        return sqrt(1 + g * g) + g;
    }
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

static void bis_tangent(const ma_bis *b, double t, double diag, double *tx, double *ty)
{
    double x0, y0, x1, y1, r;
    bis_at(b, t, &x0, &y0, &r);
    bis_at(b, t + 1e-7 * diag, &x1, &y1, &r);
    double l = hypot(x1 - x0, y1 - y0);
    *tx = (x1 - x0) / l;
    *ty = (y1 - y0) / l;
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
    a = fmod(a + M_PI, 2 * M_PI);
    if (a < 0)
        a += 2 * M_PI;
    return a - M_PI;
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
    int64_t ne = E->ns + E->nv, cnt = 0;
    ma_ea *ea = malloc((size_t)(ne > 0 ? ne : 1) * sizeof *ea);
    if (!ea)
        return -1;
    for (int64_t e = 0; e < ne; e++) {
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
        double da = fmod(ea[(i + 1) % cnt].a - ea[i].a + 4 * M_PI, 2 * M_PI);
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
enum { TR_LEAF, TR_EVENT, TR_NOMEM, TR_STUCK, TR_BADPAIR };

static int push_sample(ma_ctx *C, double x, double y, double r)
{
    return dvec_push(&C->px, x) && dvec_push(&C->py, y) && dvec_push(&C->pr, r);
}

/* Margin of the disc at (x, y, r) against every element except the pair and the
 * elements its windows govern (lesson 1: those touch the disc exactly at a window end). */
static double margin(ma_ctx *C, const ma_bis *b, double x, double y, double r)
{
    const ma_elems *E = &C->E;
    int64_t ex[6], nex = 0;
    int64_t es[2] = {b->e1, b->e2};
    for (int i = 0; i < 2; i++) {
        int64_t e = es[i];
        ex[nex++] = e;
        if (is_seg(E, e)) {
            if (E->reflex[e])
                ex[nex++] = E->velem[e];
            if (E->reflex[E->next[e]])
                ex[nex++] = E->velem[E->next[e]];
        } else {
            int64_t k = E->vk[e - E->ns];
            ex[nex++] = k;
            ex[nex++] = E->prev[k];
        }
    }
    double m = INFINITY;
    for (int64_t e = 0; e < E->ns + E->nv; e++) {
        int skip = 0;
        for (int i = 0; i < nex; i++)
            skip |= ex[i] == e;
        if (skip)
            continue;
        double d = elem_dist(E, e, x, y);
        if (d < m)
            m = d;
    }
    return m - r;
}

/* Traces from (x, y, r) along the bisector of (e1, e2) in direction (dx, dy), appending
 * samples (the start too when `first`).  On TR_EVENT, ev = (x, y, r, tx, ty). */
static int trace(ma_ctx *C, double x, double y, double r, int64_t e1, int64_t e2, double dx,
                 double dy, int leaving, int first, double ev[5])
{
    const ma_elems *E = &C->E;
    ma_bis b;
    bis_make(E, &b, e1, e2, x, y, dx, dy);
    if (first && !push_sample(C, x, y, r))
        return TR_NOMEM;
    double t = leaving ? 1e-7 * E->diag : 0.0; /* lesson 5: leave the junction's disc */
    /* Samples are spaced by the sampling step from the last one; the (many, short)
     * advancement steps near an event add no samples. */
    double t_last = t;
    for (int iter = 0; iter < 1000000; iter++) {
        double px, py, pr;
        bis_at(&b, t, &px, &py, &pr);
        if (b.kind == MA_LL && b.sg < 0 && pr <= C->eps) /* r reached 0: a convex corner */
            return push_sample(C, px, py, 0.0) ? TR_LEAF : TR_NOMEM;
        double m = margin(C, &b, px, py, pr);
        if (!isfinite(px) || !isfinite(py) || isnan(m) ||
            (b.kind == MA_PL && !(b.h > 0))) {
            /* a pair without a bisector on the interior side (a parabola whose focus is
             * not inside of its directrix): fail now rather than spin */
            ev[0] = (double)b.e1, ev[1] = (double)b.e2;
            return TR_BADPAIR;
        }
        if (m <= C->eps) {
            ev[0] = px, ev[1] = py, ev[2] = pr;
            bis_tangent(&b, t, E->diag, &ev[3], &ev[4]);
            return push_sample(C, px, py, pr) ? TR_EVENT : TR_NOMEM;
        }
        if (m > 0.1 * E->diag)
            m = 0.1 * E->diag;
        double dt = m / bis_speed(&b, t, t + m);
        double room = t_last + bis_max_step(&b, t_last, C->tol) - t;
        int sample = room <= dt;
        if (sample)
            dt = room > 0 ? room : 0;
        if (b.kind == MA_LL && b.sg < 0 && pr < dt)
            dt = pr; /* land on the leaf exactly */
        double x1, y1, r1;
        bis_at(&b, t + dt, &x1, &y1, &r1);
        int64_t who;
        int how = bis_window(E, &b, x1, y1, &who);
        if (how) { /* a window ends inside the step: find it by bisection */
            double lo = t, hi = t + dt;
            for (int i = 0; i < 60; i++) {
                double mid = 0.5 * (lo + hi), mx, my, mr;
                int64_t w2;
                bis_at(&b, mid, &mx, &my, &mr);
                if (bis_window(E, &b, mx, my, &w2) == 0)
                    lo = mid;
                else
                    hi = mid;
            }
            double tx, ty, phx, phy, phr;
            bis_at(&b, lo, &px, &py, &pr);
            bis_tangent(&b, lo, E->diag, &tx, &ty);
            if (!push_sample(C, px, py, pr))
                return TR_NOMEM;
            bis_at(&b, hi, &phx, &phy, &phr);
            int64_t en = window_switch(E, who, how);
            if (en < 0)
                return TR_LEAF;
            int64_t ea = b.e1 == who ? en : b.e1, eb = b.e1 == who ? b.e2 : en;
            bis_make(E, &b, ea, eb, phx, phy, tx, ty);
            t = 1e-9 * E->diag;
            t_last = t;
            for (int k = 0; k < 3; k++) { /* lesson 2: a double transition */
                bis_at(&b, t, &x1, &y1, &r1);
                how = bis_window(E, &b, x1, y1, &who);
                if (!how)
                    break;
                en = window_switch(E, who, how);
                if (en < 0)
                    return TR_LEAF;
                ea = b.e1 == who ? en : b.e1, eb = b.e1 == who ? b.e2 : en;
                bis_make(E, &b, ea, eb, phx, phy, tx, ty);
            }
            continue;
        }
        t += dt;
        if (sample) {
            if (!push_sample(C, x1, y1, r1))
                return TR_NOMEM;
            t_last = t;
        }
    }
    return TR_STUCK;
}

/* Traces one branch from a leaf (j0 = -1) or a junction port, through pass-through
 * (degree-2) events, to a leaf or a junction; registers new junctions and their ports. */
static mfg_status run_branch(ma_ctx *C, double x, double y, double r, int64_t e1, int64_t e2,
                             double dx, double dy, int64_t j0)
{
    const ma_elems *E = &C->E;
    if (!ivec_push(&C->boff, C->px.n))
        return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (branches)");
    int first = 1, leaving = j0 >= 0;
    for (;;) {
        double ev[5];
        int rc = trace(C, x, y, r, e1, e2, dx, dy, leaving, first, ev);
        if (rc == TR_NOMEM)
            return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (samples)");
        if (rc == TR_BADPAIR)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace from (%g, %g) reached elements %lld and "
                            "%lld, which have no bisector inside the face (a missed window "
                            "event; known on very thin spikes)",
                            x, y, (long long)ev[0], (long long)ev[1]);
        if (rc == TR_STUCK)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace of the bisector of elements %lld and %lld "
                            "from (%g, %g) did not reach an event",
                            (long long)e1, (long long)e2, x, y);
        if (rc == TR_LEAF) {
            int64_t n = C->px.n - 1, best = 0;
            double bd = INFINITY;
            for (int64_t k = 0; k < E->ns; k++) {
                double d = hypot(E->ax[k] - C->px.v[n], E->ay[k] - C->py.v[n]);
                if (d < bd)
                    bd = d, best = k;
            }
            C->reached[best] = 1;
            C->pr.v[n] = 0.0;
            return ivec_push(&C->bend, j0) && ivec_push(&C->bend, -1)
                       ? MFG_OK
                       : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        }
        double back = atan2(-ev[4], -ev[3]);
        /* A known junction (lesson 4: identified with the event accuracy). */
        for (int64_t j = 0; j < C->nj; j++) {
            if (hypot(C->J[j].x - ev[0], C->J[j].y - ev[1]) <= C->arrive) {
                int64_t p = port_pick(C, j, back, 0);
                if (p >= 0)
                    C->P[p].used = 1;
                int64_t n = C->px.n - 1;
                C->px.v[n] = C->J[j].x, C->py.v[n] = C->J[j].y, C->pr.v[n] = C->J[j].r;
                return ivec_push(&C->bend, j0) && ivec_push(&C->bend, j)
                           ? MFG_OK
                           : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
            }
        }
        int64_t j = junction_make(C, ev[0], ev[1], ev[2]);
        if (j < 0)
            return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (junctions)");
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
            leaving = 1;
            continue;
        }
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

mfg_status mfg_medial_axis(const double *xy, const int64_t *ring_offsets, int64_t nrings,
                           double tol, struct mfg_medial_axis **out)
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

    /* (2) No two edges may share a point other than the common vertex of neighbours.
     * O(n^2) pair test (exact); the design's BVH pair query replaces it later. */
    for (int64_t r = 0; r < nrings; r++)
        for (int64_t i = roff[r]; i < roff[r + 1]; i++) {
            int64_t i2 = i + 1 < roff[r + 1] ? i + 1 : roff[r];
            for (int64_t s = r; s < nrings; s++)
                for (int64_t j = (s == r ? i + 1 : roff[s]); j < roff[s + 1]; j++) {
                    int64_t j2 = j + 1 < roff[s + 1] ? j + 1 : roff[s];
                    if (s == r && (j == i2 || j2 == i))
                        continue; /* neighbours: they share their common vertex only,
                                     unless they overlap (excluded by the spike check) */
                    if (segs_touch(vx[i], vy[i], vx[i2], vy[i2], vx[j], vy[j], vx[j2], vy[j2])) {
                        st = mfg_fail(MFG_ERR_INVALID,
                                      "the boundary touches or crosses itself: edge %lld (ring "
                                      "%lld) and edge %lld (ring %lld); the medial axis needs "
                                      "disjoint simple rings",
                                      (long long)vo[i], (long long)r, (long long)vo[j],
                                      (long long)s);
                        goto done;
                    }
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
    C.eps = 1e-10 * E->diag;
    /* An event stops at margin <= eps, so a junction's elements touch its disc to ~eps:
     * gather them with 10 eps.  Wider (1e-7 diag, the prototype's) picks up elements of
     * a thin spike that do not touch, whose foot angles then misorder the ports (a port
     * between two segments adjacent at a reflex vertex).  An arriving trace locates its
     * junction less precisely (a grazing third element): 1e-6 diag. */
    C.gather = 1e-9 * E->diag;
    C.arrive = 1e-6 * E->diag;

    /* (4) Trace from every convex corner not yet reached, then every open port. */
    for (int64_t k = 0; k < nv; k++) {
        if (!E->convex[k] || C.reached[k])
            continue;
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
            ma_junction *J = &C.J[C.P[q].j];
            st = run_branch(&C, J->x, J->y, J->r, C.P[q].e1, C.P[q].e2, cos(C.P[q].angle),
                            sin(C.P[q].angle), C.P[q].j);
            if (st != MFG_OK)
                goto done;
        }
    }

    /* (5) The flat result. */
    {
        struct mfg_medial_axis *A = calloc(1, sizeof *A);
        int64_t nb = C.boff.n, ns = C.px.n, nj = C.nj;
        if (!A) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (result)");
            goto done;
        }
        A->nbranches = nb, A->npoints = ns, A->njunctions = nj;
        A->branch_offsets = malloc((size_t)(nb + 1) * sizeof(int64_t));
        A->points = malloc((size_t)(2 * ns + 1) * sizeof(double));
        A->radii = malloc((size_t)(ns + 1) * sizeof(double));
        A->branch_ends = malloc((size_t)(2 * nb + 1) * sizeof(int64_t));
        A->junction_points = malloc((size_t)(2 * nj + 1) * sizeof(double));
        A->junction_radii = malloc((size_t)(nj + 1) * sizeof(double));
        A->junction_degree = malloc((size_t)(nj + 1) * sizeof(int64_t));
        A->junction_offsets = malloc((size_t)(nj + 1) * sizeof(int64_t));
        A->junction_elements = malloc((size_t)(C.jelem.n + 1) * sizeof(int64_t));
        if (!A->branch_offsets || !A->points || !A->radii || !A->branch_ends ||
            !A->junction_points || !A->junction_radii || !A->junction_degree ||
            !A->junction_offsets || !A->junction_elements) {
            mfg_medial_axis_free(A);
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (result)");
            goto done;
        }
        for (int64_t b = 0; b < nb; b++)
            A->branch_offsets[b] = C.boff.v[b];
        A->branch_offsets[nb] = ns;
        memcpy(A->branch_ends, C.bend.v, (size_t)(2 * nb) * sizeof(int64_t));
        for (int64_t i = 0; i < ns; i++) {
            A->points[2 * i] = C.px.v[i], A->points[2 * i + 1] = C.py.v[i];
            A->radii[i] = C.pr.v[i];
        }
        int64_t o = 0;
        for (int64_t j = 0; j < nj; j++) {
            A->junction_points[2 * j] = C.J[j].x, A->junction_points[2 * j + 1] = C.J[j].y;
            A->junction_radii[j] = C.J[j].r;
            A->junction_degree[j] = C.J[j].nport;
            A->junction_offsets[j] = o;
            for (int64_t i = 0; i < C.J[j].nelem; i++) {
                int64_t e = C.jelem.v[C.J[j].first_elem + i];
                A->junction_elements[o++] = is_seg(E, e) ? E->orig[e] : -1 - E->orig[E->vk[e - nv]];
            }
        }
        A->junction_offsets[nj] = o;
        *out = A;
        mfg_clear_error();
    }
done:
    free(vx), free(vy), free(vo), free(roff);
    elems_free(E);
    free(C.reached), free(C.dist);
    free(C.px.v), free(C.py.v), free(C.pr.v), free(C.boff.v), free(C.bend.v);
    free(C.J), free(C.P), free(C.jelem.v), free(C.stack.v);
    return st;
}
