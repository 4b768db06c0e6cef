/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/gaps.c - Gap-closing curves: the images of B n R(theta) A where a front face at t
 * = 0 meets a back face at t = theta (the paper's case 1.3).  Overview and file map:
 * sweep/sweep.h. */
#include "sweep/sweep.h"

/* Clips the line x(s) = p + s d, lying in the plane of the triangle (a, b, cc) with normal
 * n (counter-clockwise about n), to the triangle: the interval [*s0, *s1] shrinks. */
static void clip_to_triangle(const double *p, const double *d, const double *a, const double *b,
                             const double *cc, const double *n, double *s0, double *s1)
{
    const double *v[3] = {a, b, cc};
    for (int k = 0; k < 3 && *s0 <= *s1; k++) {
        const double *u = v[k], *w = v[(k + 1) % 3];
        double e[3] = {w[0] - u[0], w[1] - u[1], w[2] - u[2]};
        double q[3] = {p[0] - u[0], p[1] - u[1], p[2] - u[2]};
        /* f(s) = ((e x (p + s d - u)) . n) >= 0 inside */
        double f0 = (e[1] * q[2] - e[2] * q[1]) * n[0] + (e[2] * q[0] - e[0] * q[2]) * n[1] +
                    (e[0] * q[1] - e[1] * q[0]) * n[2];
        double f1 = (e[1] * d[2] - e[2] * d[1]) * n[0] + (e[2] * d[0] - e[0] * d[2]) * n[1] +
                    (e[0] * d[1] - e[1] * d[0]) * n[2];
        if (f1 == 0) {
            if (f0 < 0)
                *s1 = *s0 - 1;
        } else if (f1 > 0) {
            *s0 = fmax(*s0, -f0 / f1);
        } else {
            *s1 = fmin(*s1, -f0 / f1);
        }
    }
}

/* Clips the line x(s) = p + s d to where the circle direction (-y, x, 0) points out of
 * (sign > 0) or into (sign < 0) a plane of normal n: the interval [*s0, *s1] shrinks. */
static void clip_to_motion(const double *p, const double *d, const double *n, int sign,
                           double *s0, double *s1)
{
    double f0 = sign * (n[1] * p[0] - n[0] * p[1]), f1 = sign * (n[1] * d[0] - n[0] * d[1]);
    if (f1 == 0) {
        if (f0 < 0)
            *s1 = *s0 - 1;
    } else if (f1 > 0) {
        *s0 = fmax(*s0, -f0 / f1);
    } else {
        *s1 = fmin(*s1, -f0 / f1);
    }
}

/* Does segment x0 x1 lie (within eps) on the line of a side of triangle v? */
static int along_an_edge(const double *x0, const double *x1, const double *const *v, double eps)
{
    for (int k = 0; k < 3; k++) {
        const double *u = v[k], *w = v[(k + 1) % 3];
        double e[3] = {w[0] - u[0], w[1] - u[1], w[2] - u[2]};
        double le = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (!(le > 0))
            continue;
        int on = 1;
        for (int j = 0; j < 2 && on; j++) {
            const double *x = j ? x1 : x0;
            double q[3] = {x[0] - u[0], x[1] - u[1], x[2] - u[2]};
            double cx = q[1] * e[2] - q[2] * e[1], cy = q[2] * e[0] - q[0] * e[2],
                   cz = q[0] * e[1] - q[1] * e[0];
            on = sqrt(cx * cx + cy * cy + cz * cz) <= eps * le;
        }
        if (on)
            return 1;
    }
    return 0;
}

/* Does the circle direction (counter-clockwise about the axis) point into (sign < 0) or
 * out of (sign > 0) triangle T's plane somewhere on it? */
static int faces_motion(const sw_ctx *c, const sw_tri *T, int sign)
{
    for (int k = 0; k < 3; k++) {
        const double *p = c->lx + 3 * T->v[k];
        double nt = -T->n[0] * p[1] + T->n[1] * p[0];
        if (sign * nt > 0)
            return 1;
    }
    return 0;
}

/*
 * Gap-closing curves (the paper's case 1.3).  Where an exit face A, turned by theta, meets
 * an entry face B, the gap between two arcs of a circle closes: the arc structure changes
 * along the image of the 3-D segment B n R(theta) A although no edge is imaged there.
 * Without that curve the decomposition refined down to blocks all along it.  Each segment
 * is kept as a curve of B (its own lifts land on it), found for the pairs of triangles
 * whose (r, z) boxes overlap (the image of R(theta) A is A's).
 */
int sw_build_gap_curves(sw_ctx *c)
{
    if (c->full_turn)
        return 1;
    c->gstart = calloc((size_t)(c->nt + 2), sizeof *c->gstart);
    if (!c->gstart)
        return ctx_nomem(c);
    int64_t *items = NULL, nitems = 0, capitems = 0;
    double ct = cos(c->theta), st = sin(c->theta);
    for (int64_t b = 0; b < c->nt; b++) {
        c->gstart[b] = nitems;
        const sw_tri *B = &c->tris[b];
        if (!B->vertical_ok || !faces_motion(c, B, -1))
            continue;
        if (!sw_gather(c, B->rmin, B->rmax, B->zmin, B->zmax)) {
            free(items);
            return 0;
        }
        const double *pb[3] = {c->lx + 3 * B->v[0], c->lx + 3 * B->v[1], c->lx + 3 * B->v[2]};
        double nbn = sqrt(B->n[0] * B->n[0] + B->n[1] * B->n[1] + B->n[2] * B->n[2]);
        for (int64_t k = 0; k < c->ncand; k++) {
            int64_t a = c->cand[k];
            const sw_tri *A = &c->tris[a];
            if (!A->vertical_ok || !faces_motion(c, A, 1))
                continue;
            /* A turned by theta */
            double pa[3][3], na[3];
            for (int q = 0; q < 3; q++) {
                const double *x = c->lx + 3 * A->v[q];
                pa[q][0] = x[0] * ct - x[1] * st;
                pa[q][1] = x[0] * st + x[1] * ct;
                pa[q][2] = x[2];
            }
            na[0] = A->n[0] * ct - A->n[1] * st;
            na[1] = A->n[0] * st + A->n[1] * ct;
            na[2] = A->n[2];
            double d[3] = {B->n[1] * na[2] - B->n[2] * na[1], B->n[2] * na[0] - B->n[0] * na[2],
                           B->n[0] * na[1] - B->n[1] * na[0]};
            double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            double nan_ = sqrt(na[0] * na[0] + na[1] * na[1] + na[2] * na[2]);
            if (!(dd > SW_EPS_SIN2 * nbn * nbn * nan_ * nan_))
                continue; /* parallel planes: no crossing line */
            /* a point on both planes: p = (dB (na x d) + dA (d x nB)) / |d|^2 */
            double dA = A->d; /* turning keeps the plane's offset from the axis origin */
            double nxd[3] = {na[1] * d[2] - na[2] * d[1], na[2] * d[0] - na[0] * d[2], na[0] * d[1] - na[1] * d[0]};
            double dxn[3] = {d[1] * B->n[2] - d[2] * B->n[1], d[2] * B->n[0] - d[0] * B->n[2],
                             d[0] * B->n[1] - d[1] * B->n[0]};
            double p[3];
            for (int q = 0; q < 3; q++)
                p[q] = (B->d * nxd[q] + dA * dxn[q]) / dd;
            double s0 = -INFINITY, s1 = INFINITY;
            clip_to_triangle(p, d, pb[0], pb[1], pb[2], B->n, &s0, &s1);
            clip_to_triangle(p, d, pa[0], pa[1], pa[2], na, &s0, &s1);
            /* only where the circles enter B and leave A turned: elsewhere the two faces
             * do not bound one gap, and the arc structure does not change */
            clip_to_motion(p, d, B->n, -1, &s0, &s1);
            clip_to_motion(p, d, na, 1, &s0, &s1);
            if (!(s1 > s0) || !isfinite(s0) || !isfinite(s1))
                continue;
            double x0[3], x1[3], len = 0;
            for (int q = 0; q < 3; q++) {
                x0[q] = p[q] + s0 * d[q];
                x1[q] = p[q] + s1 * d[q];
                len += (x1[q] - x0[q]) * (x1[q] - x0[q]);
            }
            if (!(sqrt(len) > SW_TOL_FRAC * c->tol))
                continue;
            /* A segment stopped by the axis (where the motion changes sign, e.g. a plane and
             * its half turn) ends on it: exactly, and at u = 0, so that its image has r = 0
             * there (r(u) from the quadratic loses half the digits near the axis). */
            double scale = SW_EPS_REL * (B->rmax + fabs(B->zmin) + fabs(B->zmax));
            if (v_r(x1[0], x1[1]) <= scale) {
                double t[3];
                memcpy(t, x0, sizeof t);
                memcpy(x0, x1, sizeof t);
                memcpy(x1, t, sizeof t);
            }
            if (v_r(x0[0], x0[1]) <= scale)
                x0[0] = x0[1] = 0;
            /* On the axis (two planes through it), or along an edge of B or of A turned
             * (the gap closes just where a face ends): the image is the axis or that edge's,
             * whose curve already cuts the cell; a second curve on one image only made
             * coincident chords. */
            if (v_r(x1[0], x1[1]) <= scale || along_an_edge(x0, x1, pb, scale) ||
                along_an_edge(x0, x1, (const double *[3]){pa[0], pa[1], pa[2]}, scale))
                continue;
            if (!sw_add_curve(c, x0, x1, b, -1, -1, -1) ||
                !mfg_grow((void **)&items, &capitems, nitems + 1, sizeof *items)) {
                free(items);
                return ctx_nomem(c);
            }
            c->curves[c->ncurves - 1].gexit = a;
            items[nitems++] = c->ncurves - 1;
        }
    }
    c->gstart[c->nt] = nitems;
    c->gcurves = items;
    free(c->cstamp);
    c->cstamp = calloc((size_t)(c->ncurves + 1), sizeof *c->cstamp);
    if (!c->cstamp)
        return ctx_nomem(c);
    return 1;
}
