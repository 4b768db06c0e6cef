/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/lift.c - Output vertices, lifts: a polygon corner lifted onto the front triangle
 * at t = 0 or the back triangle turned by theta; output triangles.  Overview and file map:
 * sweep/sweep.h. */
#include "sweep/sweep.h"

/* The output vertex at local point p (merged with any vertex of the same doubles). */
int64_t sw_out_vertex(sw_ctx *c, sw_out *o, const double p[3], double phi)
{
    /* Points closer than the weld quantum (2^-40 of the part's size) are one vertex:
     * lifts of one corner onto the planes of two triangles of one face, or onto a face
     * and its neighbour at their common edge, agree only up to rounding. */
    int64_t q[3];
    double pz[3];
    /* a coordinate below the library's range (2^-200, mfg_coord_ok: a turn by a tiny
     * angle) is 0, far below the weld quantum */
    for (int i = 0; i < 3; i++)
        pz[i] = fabs(p[i]) < 0x1p-200 ? 0 : p[i];
    p = pz;
    for (int i = 0; i < 3; i++)
        q[i] = (int64_t)floor(p[i] / c->quantum + 0.5);
    hkey k = mkkey(q[0], q[1], q[2], 0);
    int64_t id = hmap_get(&c->outmap, &k);
    if (id >= 0)
        return id;
    /* a point just across a cell boundary of the quantisation */
    for (int dx = -1; dx <= 1; dx++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dz = -1; dz <= 1; dz++) {
                if (!dx && !dy && !dz)
                    continue;
                hkey kn = mkkey(q[0] + dx, q[1] + dy, q[2] + dz, 0);
                int64_t j = hmap_get(&c->outmap, &kn);
                if (j >= 0) {
                    const double *r = c->ox + 3 * j;
                    if (fabs(r[0] - p[0]) <= c->quantum && fabs(r[1] - p[1]) <= c->quantum &&
                        fabs(r[2] - p[2]) <= c->quantum)
                        return j;
                }
            }
    if (!mfg_grow((void **)&c->ox, &c->capout, c->nout + 1, 3 * sizeof *c->ox) ||
        !mfg_grow((void **)&o->phi, &o->capphi, c->nout + 1, sizeof *o->phi))
        return ctx_nomem(c) - 1;
    memcpy(c->ox + 3 * c->nout, p, 3 * sizeof *p);
    o->phi[c->nout] = phi;
    if (!hmap_put(&c->outmap, &k, c->nout))
        return ctx_nomem(c) - 1;
    return c->nout++;
}

int64_t sw_ring_vertex(sw_ctx *c, sw_out *o, const sw_vtx2 *w, double phi)
{
    double p[3] = {w->r * cos(phi), w->r * sin(phi), w->z};
    if (w->r == 0)
        p[0] = p[1] = 0;
    return sw_out_vertex(c, o, p, wrap_angle(phi));
}

/* The point over 2-D vertex w on the plane of triangle t at root sigma; turned by theta
 * for the end of an arc. */
int64_t sw_lift(sw_ctx *c, sw_out *o, int64_t iw, const sw_end *en, int isexit)
{
    int64_t t = en->tri;
    int sigma = en->sigma;
    const sw_vtx2 *w = &c->v2[iw];
    if (t < 0) {
        /* a block's cap: the meridian half-plane at a fixed angle (the end's angle is
         * stored before the turn, like an exit's) */
        double ang = en->phi + (isexit ? c->theta : 0);
        return sw_ring_vertex(c, o, w, ang);
    }
    hkey k = mkkey(iw, t, sigma + 1, isexit);
    int64_t id = hmap_get(&o->lifts, &k);
    if (id >= 0)
        return id;
    const sw_tri *T = &c->tris[t];
    double p[3];
    int done = 0;
    if (w->r == 0) {
        p[0] = p[1] = 0;
        p[2] = w->z;
        done = 1;
    }
    double phi_root = 0;
    {
        double A = T->n[0] * w->r, B = T->n[1] * w->r, C = T->d - T->n[2] * w->z;
        double R = sqrt(A * A + B * B);
        double cv = R > 0 ? C / R : 1;
        if (cv > 1)
            cv = 1;
        if (cv < -1)
            cv = -1;
        phi_root = T->phi0 + sigma * acos(cv);
    }
    /* a vertex of the triangle imaged here, at this root: the vertex itself (a triangle
     * may hold two vertices with one image, mirror images across its meridian) */
    for (int q = 0; q < 3 && !done; q++) {
        int64_t v = T->v[q];
        if (c->vr[v] == w->r && c->lx[3 * v + 2] == w->z) {
            double dphi = fabs(angle_diff(atan2(c->lx[3 * v + 1], c->lx[3 * v]), phi_root));
            if (dphi * w->r <= SW_TOL_FRAC * (w->r + c->tol) + SW_TOL_SNAP * c->tol) {
                memcpy(p, c->lx + 3 * v, sizeof p);
                done = 1;
            }
        }
    }
    /* on a curve (an edge or silhouette): the curve's own point when this root lands on
     * it, so that every piece meeting there shares the vertex; curves of the triangle
     * first */
    if (!done && w->ncurves > 0) {
        double snap = sw_point_eps(c, w->r, w->z);
        double pr[3] = {w->r * cos(phi_root), w->r * sin(phi_root), w->z};
        for (int pass = 0; pass < 2 && !done; pass++)
            for (int j = 0; j < w->ncurves && !done; j++) {
                const sw_curve *cv = &c->curves[w->curves[j]];
                /* a gap-closing curve lies on its entry triangle and, turned back by
                 * theta, on its exit triangle: the end there lifts to the same point */
                int back = isexit && cv->gexit == t;
                int own = cv->tri[0] == t || cv->tri[1] == t || back;
                if ((pass == 0) != own || cv->dir[2] == 0)
                    continue;
                double q[3];
                for (int i = 0; i < 3; i++)
                    q[i] = cv->p0[i] + w->us[j] * cv->dir[i];
                if (back) {
                    double dx0 = q[0] - pr[0], dy0 = q[1] - pr[1];
                    double ct = cos(c->theta), st = sin(c->theta);
                    double qb[3] = {q[0] * ct + q[1] * st, -q[0] * st + q[1] * ct, q[2]};
                    double dxb = qb[0] - pr[0], dyb = qb[1] - pr[1];
                    /* the exit triangle may be the entry one: the nearer of the two */
                    if (cv->tri[0] != t || dxb * dxb + dyb * dyb < dx0 * dx0 + dy0 * dy0)
                        memcpy(q, qb, sizeof q);
                }
                double dx = q[0] - pr[0], dy = q[1] - pr[1];
                double lim = own ? SW_TOL_FRAC * (w->r + c->tol) + SW_TOL_SNAP * c->tol : snap;
                if (sqrt(dx * dx + dy * dy) <= lim) {
                    memcpy(p, q, sizeof p);
                    done = 1;
                }
            }
    }
    if (!done) {
        p[0] = w->r * cos(phi_root);
        p[1] = w->r * sin(phi_root);
        p[2] = w->z;
    }
    if (isexit && w->r != 0) {
        double ct = cos(c->theta), st = sin(c->theta);
        double x = p[0] * ct - p[1] * st, y = p[0] * st + p[1] * ct;
        p[0] = x;
        p[1] = y;
    }
    id = sw_out_vertex(c, o, p, wrap_angle(atan2(p[1], p[0])));
    if (id < 0)
        return -1;
    if (!hmap_put(&o->lifts, &k, id))
        return ctx_nomem(c) - 1;
    return id;
}

/* Appends triangle (a, b, d).  A wall triangle names its edge along a circle (ring_a,
 * ring_b) and the direction (angle in the meridian plane) in which the wall leaves that
 * circle: what resolve_pinches orders pieces by, where coordinates would mislead (a chord's
 * sag, circumscribed vertices). */
int sw_emit_tri_ring(sw_ctx *c, int64_t a, int64_t b, int64_t d, int64_t ring_a, int64_t ring_b,
                     double dir)
{
    if (a == b || b == d || d == a)
        return 1;
    if (!mfg_grow((void **)&c->otri, &c->capotri, c->notri + 1, 3 * sizeof *c->otri) ||
        !mfg_grow((void **)&c->oring, &c->caporing, c->notri + 1, 2 * sizeof *c->oring) ||
        !mfg_grow((void **)&c->odir, &c->capodir, c->notri + 1, sizeof *c->odir) ||
        !mfg_grow((void **)&c->oface, &c->capoface, c->notri + 1, sizeof *c->oface))
        return ctx_nomem(c);
    c->otri[3 * c->notri] = a;
    c->otri[3 * c->notri + 1] = b;
    c->otri[3 * c->notri + 2] = d;
    c->oring[2 * c->notri] = ring_a;
    c->oring[2 * c->notri + 1] = ring_b;
    c->odir[c->notri] = dir;
    c->oface[c->notri] = -1;
    c->notri++;
    return 1;
}

/* A face triangle: a piece of input triangle tri's plane (turned by theta for an exit),
 * which merge_faces joins with the other pieces of that plane; tri < 0 for none. */
int sw_emit_tri(sw_ctx *c, int64_t a, int64_t b, int64_t d, int64_t tri, int isexit)
{
    int64_t n = c->notri;
    if (!sw_emit_tri_ring(c, a, b, d, -1, -1, 0))
        return 0;
    if (c->notri > n && tri >= 0)
        c->oface[n] = 2 * tri + isexit;
    return 1;
}

/* Number of grid steps on a circle of radius r: chord sag r (1 - cos(pi / N)) below half
 * the tolerance. */
int64_t sw_ring_steps(const sw_ctx *c, double r)
{
    double sag = 0.5 * c->tol;
    if (r <= sag)
        return 8;
    double step = 2 * acos(1 - sag / r);
    double n = ceil(MFG_TWO_PI / step);
    if (n < 8)
        n = 8;
    if (n > 1 << 20)
        n = 1 << 20;
    return (int64_t)n;
}
