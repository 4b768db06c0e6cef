/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/bisector.c - the boundary elements' distances and the bisectors of element pairs
 * (line, midline, parabola) in polynomial form, their windows.  Overview and file map:
 * axis2d/axis2d.h. */
#include "axis2d/axis2d.h"

void ma_vpoint(const ma_elems *E, int64_t e, double *x, double *y)
{
    int64_t k = E->vk[e - E->ns];
    *x = E->ax[k];
    *y = E->ay[k];
}

/* Distance of p to element e (an open segment: +inf when the foot is outside it). */
double ma_elem_dist(const ma_elems *E, int64_t e, double x, double y)
{
    if (is_seg(E, e)) {
        double qx = x - E->ax[e], qy = y - E->ay[e];
        double t = qx * E->ux[e] + qy * E->uy[e];
        if (t > 0 && t < E->len[e])
            return fabs(qx * E->nx[e] + qy * E->ny[e]);
        return INFINITY;
    }
    double vx, vy;
    ma_vpoint(E, e, &vx, &vy);
    return hypot(x - vx, y - vy);
}

/* (segment, its own endpoint vertex): their bisector is the normal at the vertex, not
 * part of the axis. */
int ma_own_pair(const ma_elems *E, int64_t a, int64_t b)
{
    if (is_seg(E, a) == is_seg(E, b))
        return 0;
    int64_t s = is_seg(E, a) ? a : b, v = is_seg(E, a) ? b : a;
    int64_t k = E->vk[v - E->ns];
    return k == s || k == E->next[s];
}



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

void ma_bis_make(const ma_elems *E, ma_bis *b, const ma_start *s)
{
    int64_t e1 = s->e1, e2 = s->e2;
    double Px = s->x, Py = s->y, dx = s->dx, dy = s->dy;
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
        if (g2 > MA_EPS_NORMAL2)
            Px -= f * gx / g2, Py -= f * gy / g2;
        b->Px = Px, b->Py = Py;
        b->r0 = (Px - E->ax[e1]) * n1x + (Py - E->ay[e1]) * n1y;
        double c = n1x * n2x + n1y * n2y;
        if (c >= 0) {
            /* Normals within 90 degrees (edges meeting at a corner, or turning less): q with
             * n1.q = n2.q = 1 is (n1 + n2) / (1 + n1.n2), well conditioned however small
             * the turn.  The cross-product form below divides two O(turn) quantities: at
             * turns of 1e-14 (a circle's polygon rounded to a grid) its rounding turned q
             * by 0.3 %, and below MA_EPS_PARALLEL it took the pair for parallel edges and
             * ran the leaf's branch along the boundary. */
            double qx = (n1x + n2x) / (1 + c), qy = (n1y + n2y) / (1 + c);
            int64_t corner = E->next[e1] == e2 ? e2 : E->next[e2] == e1 ? e1 : -1;
            if (corner >= 0) {
                /* adjacent: the bisector is the line through their corner V along q; start
                 * on it.  (A start on the perpendicular at the corner - where a window
                 * closed - is r tan(turn / 2) off it, and the other window closed again at
                 * once: a second junction beside the first, and the corner reached twice.) */
                double vx = E->ax[corner], vy = E->ay[corner], q2 = qx * qx + qy * qy;
                double sq = ((Px - vx) * qx + (Py - vy) * qy) / q2;
                Px = vx + sq * qx, Py = vy + sq * qy;
                b->Px = Px, b->Py = Py;
                b->r0 = (Px - E->ax[e1]) * n1x + (Py - E->ay[e1]) * n1y;
            }
            b->sg = (qx * dx + qy * dy >= 0) ? 1.0 : -1.0;
            b->kind = MA_LL;
            b->qx = qx * b->sg;
            b->qy = qy * b->sg;
        } else if (fabs(det) < MA_EPS_PARALLEL) { /* parallel edges: the midline, r constant */
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
        ma_vpoint(E, v, &fxp, &fyp);
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
        ma_vpoint(E, e1, &x1, &y1);
        ma_vpoint(E, e2, &x2, &y2);
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

void ma_bis_at(const ma_bis *b, double t, double *x, double *y, double *r)
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

/* Where the radius along a point-point line is least (its apex: the midpoint of the two
 * vertices), as a parameter t; apex_a: half the vertices' distance, that least radius. */
static double pp_apex(const ma_bis *b, double *apex_a)
{
    *apex_a = fabs((b->Px - b->v1x) * -b->dy + (b->Py - b->v1y) * b->dx);
    return -((b->Px - b->v1x) * b->dx + (b->Py - b->v1y) * b->dy);
}

int ma_bis_split_at(const ma_bis *b, double ta, double tb, double tol, double *t_split)
{
    if (b->kind != MA_PP)
        return 0;
    double a, t0 = pp_apex(b, &a);
    *t_split = t0;
    return a <= tol && t0 > ta && t0 < tb;
}

/* The longest uniform step over [ta, tb] whose chords and linearly interpolated radii stay
 * within tol (lesson 6: the radius along a point-point line is not linear either).
 *
 * Point-point line: r(s) = sqrt(s^2 + a^2), s from the apex, a half the vertices'
 * distance; the path is straight and only the radius errs.  By at most a, on a piece not
 * crossing the apex (r lies between |s| and |s| + a, and |s| is linear there; sample_piece
 * splits at the apex, ma_bis_split_at); and by at most step^2 max r'' / 2 with
 * r'' = a^2 / r^3 largest at the piece's least radius.  The bound was once 1/a over the
 * whole line: two ring vertices 1e-14 apart (a closed edge's polyline ending at
 * cos(2 pi) of its start) gave a 2.5-long branch 65 M samples and 7 GB (issue 22). */
double ma_bis_max_step(const ma_bis *b, double ta, double tb, double tol)
{
    if (b->kind == MA_PAR || b->kind == MA_LL)
        return INFINITY;
    if (b->kind == MA_PL)
        return sqrt(2 * tol * b->h);
    double a, t0 = pp_apex(b, &a);
    int crosses = t0 > ta && t0 < tb;
    if (a <= tol && !crosses)
        return INFINITY;
    double smin = crosses ? 0.0 : fmin(fabs(ta - t0), fabs(tb - t0));
    double rmin = hypot(smin, a);
    if (a < MA_TINY)
        a = MA_TINY;
    return sqrt(2 * tol * rmin) * (rmin / a);
}

void ma_bis_tangent(const ma_bis *b, double t, double *tx, double *ty)
{
    double x = b->p1x + 2 * b->p2x * t, y = b->p1y + 2 * b->p2y * t, l = hypot(x, y);
    *tx = x / l;
    *ty = y / l;
}

/* Window of the pair: 0 while both elements still govern p; else the element that
 * stopped and how (1 start / 2 end of a segment, 3 prev / 4 next side of a vertex). */
int ma_bis_window(const ma_elems *E, const ma_bis *b, double x, double y, int64_t *which)
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
int64_t ma_window_switch(const ma_elems *E, int64_t e, int how)
{
    if (is_seg(E, e)) {
        int64_t k = how == 1 ? e : E->next[e];
        return E->reflex[k] ? E->velem[k] : -1;
    }
    int64_t k = E->vk[e - E->ns];
    return how == 3 ? E->prev[k] : k;
}
