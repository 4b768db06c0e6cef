/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/hidden.c - The meridian decomposition: hidden triangles: the angles over which a
 * triangle lies inside a cell's circles, and the triangles a cell can ignore.  Overview
 * and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

int sw_cmp_iv(const void *pa, const void *pb)
{
    const sw_iv *x = pa, *y = pb;
    return (x->a > y->a) - (x->a < y->a);
}

/*
 * Hidden triangles.  Every triangle near a cell used to cut it with its curves, also where
 * it is crossed strictly inside an SV arc on every circle of the cell: on a tessellated
 * torus swept by a half or a full turn the images of all its edges crossed one another.
 * A cell now ignores the triangles it can show to be hidden, by this argument.  (At 90 deg
 * the bench torus has almost nothing hidden: 660 of 702 crossings of 233 random circles
 * start or end an SV arc.)
 *
 * Let Phi_t be an interval of angles holding every point of triangle t whose (r, z) lies in
 * the cell (tri_cell_angles: t clipped to the slab and the annulus of the cell, with a
 * margin).  The union of the Phi_t of all triangles near the cell is a set of closed
 * angular blocks; between them lie gaps.  The part of the cell's solid of revolution over a
 * gap meets no triangle and is connected, so it lies wholly inside O or wholly outside it,
 * on every circle of the cell alike: one ray test tells which.  SV on a circle is the set
 * of angles phi with [phi - theta, phi] meeting O, and O is the inside gaps plus its parts
 * in the blocks, so on every circle of the cell
 *     SV = C u  U_blocks B  cov(O n B),   C = U_inside gaps (a, b)  (a, b + theta),
 * with cov(O n B) inside [B.lo, B.hi + theta] whatever the triangles of B do.  A block
 * whose [B.lo, B.hi + theta] lies in one (open) component of C is hidden: what happens in
 * it (arcs born at silhouettes, crossings passing edges) changes no point of SV, and no
 * end of an SV arc lies in C.  So SV, its arcs and the triangles that start and end them
 * are functions of the crossings in the other blocks alone, whose triangles all keep their
 * curves: the structure changes only where one of their crossings changes triangle or root
 * (their edges and silhouettes), is born or dies (silhouettes, vertex images), or meets
 * the turned end of another (a gap-closing curve between two triangles of visible blocks;
 * a crossing meeting C's bounds meets the first crossing of the block there, the same
 * kind of event, or lies in C on both sides when that block is hidden).  Two triangles
 * sharing an edge have overlapping Phi, so a crossing never passes from a visible block
 * into a hidden one.  Hidden blocks are decided per cell, for every circle of the cell,
 * not from the samples alone: the argument holds when the samples differ too.  A full turn
 * with one inside gap hides everything (C is the whole circle).
 *
 * A block is the unit, not a triangle: a triangle whose crossings all lie in C, so that it
 * never starts or ends an arc, can still change SV - an arc of O born at its silhouette
 * covers [phi, phi + theta], which can reach past C and swallow the end of another arc
 * (the bench torus has such notches: they are kept).  A triangle of a hidden
 * block loses its edges, silhouette and gap-closing curves in the cell, and its vertices
 * are no vertex images there (the neighbours of the visible ones keep their common edges).
 */

/* Angles at which circles of the cell [ra, rb] x [za, zb] can meet triangle t: 0 when no
 * point of t lies over the cell, 1 with the closed interval [*lo, *hi] (lo in [0, 2 pi),
 * hi - lo < pi), 2 when t comes near the axis (no bound). */
static int tri_cell_angles(const sw_ctx *c, int64_t t, double ra, double rb, double za,
                           double zb, double *lo, double *hi)
{
    const sw_tri *T = &c->tris[t];
    double m = SW_EPS_REL * c->ext; /* the cell widened by far more than rounding */
    ra = fmax(0, ra - m);
    rb += m;
    za -= m;
    zb += m;
    if (T->rmax < ra || T->rmin > rb || T->zmax < za || T->zmin > zb)
        return 0;
    /* t clipped to the slab za <= z <= zb: a convex polygon of up to 5 corners */
    double P[8][3], Q[8][3];
    int n = 3;
    for (int k = 0; k < 3; k++)
        memcpy(P[k], c->lx + 3 * T->v[k], sizeof P[k]);
    for (int sd = 0; sd < 2 && n > 0; sd++) {
        int nq = 0;
        for (int i = 0; i < n; i++) {
            const double *a = P[i], *b = P[(i + 1) % n];
            double fa = sd ? zb - a[2] : a[2] - za, fb = sd ? zb - b[2] : b[2] - za;
            if (fa >= 0)
                memcpy(Q[nq++], a, sizeof Q[0]);
            if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0)) {
                double w = fa / (fa - fb);
                for (int q = 0; q < 3; q++)
                    Q[nq][q] = a[q] + w * (b[q] - a[q]);
                nq++;
            }
        }
        n = nq;
        memcpy(P, Q, (size_t)n * sizeof P[0]);
    }
    if (n == 0)
        return 0;
    /* its shadow on the plane z = 0: no bound when it covers the axis or comes within
     * 1e-7 of the part's size of it (angles lose their digits there) */
    double dist = INFINITY;
    int pos = 0, neg = 0;
    for (int i = 0; i < n; i++) {
        const double *u = P[i], *v = P[(i + 1) % n];
        double cr = u[0] * v[1] - u[1] * v[0];
        pos |= cr > 0;
        neg |= cr < 0;
        double dx = v[0] - u[0], dy = v[1] - u[1], l2 = dx * dx + dy * dy;
        double s = l2 > 0 ? fmin(1, fmax(0, -(u[0] * dx + u[1] * dy) / l2)) : 0;
        dist = fmin(dist, v_r(u[0] + s * dx, u[1] + s * dy));
    }
    if ((pos && !neg) || (neg && !pos) || !(dist > SW_EPS_AXIS_DIST * c->ext))
        return 2;
    /* a convex set away from the axis spans less than half a turn: its angles over the
     * annulus are those of its corners in the annulus and of its sides' crossings with the
     * annulus' two circles */
    int any = 0;
    double a0 = 0, dlo = 0, dhi = 0;
    for (int i = 0; i < n; i++) {
        const double *u = P[i], *v = P[(i + 1) % n];
        double pts[5][2];
        int np = 0;
        double ru = v_r(u[0], u[1]);
        if (ru >= ra && ru <= rb) {
            pts[np][0] = u[0];
            pts[np++][1] = u[1];
        }
        double dx = v[0] - u[0], dy = v[1] - u[1];
        double qa = dx * dx + dy * dy, qb = 2 * (u[0] * dx + u[1] * dy);
        for (int e = 0; e < 2 && qa > 0; e++) {
            double R = e ? rb : ra, roots[2];
            if (R <= 0)
                continue;
            int nr = sw_solve_quadratic(qa, qb, u[0] * u[0] + u[1] * u[1] - R * R, 0, roots);
            for (int k = 0; k < nr; k++)
                if (roots[k] >= 0 && roots[k] <= 1) {
                    pts[np][0] = u[0] + roots[k] * dx;
                    pts[np++][1] = u[1] + roots[k] * dy;
                }
        }
        for (int k = 0; k < np; k++) {
            double ang = atan2(pts[k][1], pts[k][0]);
            if (!any) {
                a0 = ang;
                any = 1;
                continue;
            }
            double d = angle_diff(ang, a0);
            dlo = fmin(dlo, d);
            dhi = fmax(dhi, d);
        }
    }
    if (!any)
        return 0;
    double marg = SW_EPS_ANGLE + SW_EPS_ANGLE_EXT * c->ext / dist;
    *lo = wrap_angle(a0 + dlo - marg);
    *hi = *lo + (dhi - dlo) + 2 * marg;
    return 1;
}

/* Merges the intervals iv[0 .. n-1] (a in [0, 2 pi)) on the circle into out: returns how
 * many disjoint ones are left (starting from one that no other reaches; their a and b
 * unwrapped from there), or -1 when they cover the whole circle.  Closed intervals that
 * touch merge; open ones do not. */
static int64_t merge_on_circle(sw_iv *iv, int64_t n, int open, sw_iv *out)
{
    if (n == 0)
        return 0;
    for (int64_t i = 0; i < n; i++)
        if (iv[i].b - iv[i].a >= MFG_TWO_PI)
            return -1;
    qsort(iv, (size_t)n, sizeof *iv, sw_cmp_iv);
    double best = -INFINITY;
    for (int64_t i = 0; i < n; i++)
        best = fmax(best, iv[i].b - MFG_TWO_PI);
    int64_t j0 = -1;
    for (int64_t i = 0; i < n; i++) {
        if (open ? iv[i].a >= best : iv[i].a > best) {
            j0 = i;
            break;
        }
        best = fmax(best, iv[i].b);
    }
    if (j0 < 0)
        return -1;
    int64_t m = 0;
    double ca = iv[j0].a, cb = iv[j0].b;
    for (int64_t k = 1; k <= n; k++) {
        int64_t i = (j0 + k) % n;
        double w = (j0 + k) >= n ? MFG_TWO_PI : 0, a = iv[i].a + w, b = iv[i].b + w;
        if (k < n && (open ? a < cb : a <= cb)) {
            cb = fmax(cb, b);
            continue;
        }
        out[m].a = ca;
        out[m].b = cb;
        m++;
        ca = a;
        cb = b;
    }
    return m;
}

/* The component of the merged intervals iv[0 .. n-1] holding the closed interval [x, y]
 * (x in [0, 2 pi), y >= x), open at both ends (strictly inside) or closed, or -1. */
static int64_t circle_component(const sw_iv *iv, int64_t n, double x, double y, int open)
{
    for (int64_t i = 0; i < n; i++) {
        double xs = iv[i].a + fmod(x - iv[i].a + 2 * MFG_TWO_PI, MFG_TWO_PI);
        double ys = xs + (y - x);
        if (open ? (xs > iv[i].a && ys < iv[i].b) : (xs >= iv[i].a && ys <= iv[i].b))
            return i;
    }
    return -1;
}

/* Marks (c->hstamp[t] = vs) the triangles of the candidate list c->cand that are hidden in
 * the cell [ra, rb] x [za, zb] (see above); centre is SV at the cell's centre, a shortcut for
 * the gaps outside O.  c->cand is left as it was. */
int sw_mark_hidden(sw_ctx *c, const sw_struct *centre, double ra, double rb, double za,
                   double zb, int64_t vs)
{
    int64_t n = c->ncand;
    if (n == 0)
        return 1;
    int64_t *cand = malloc((size_t)n * sizeof *cand);
    sw_iv *phi = malloc((size_t)n * sizeof *phi), *blk = malloc((size_t)n * sizeof *blk);
    sw_iv *cv = malloc((size_t)(n + 1) * sizeof *cv), *cm = malloc((size_t)(n + 1) * sizeof *cm);
    signed char *kind = malloc((size_t)n);
    int ok = 1;
    if (!cand || !phi || !blk || !cv || !cm || !kind) {
        ok = ctx_nomem(c);
        goto done;
    }
    memcpy(cand, c->cand, (size_t)n * sizeof *cand);
    int64_t nphi = 0;
    for (int64_t k = 0; k < n; k++) {
        phi[k].a = phi[k].b = 0;
        kind[k] = (signed char)tri_cell_angles(c, cand[k], ra, rb, za, zb, &phi[k].a, &phi[k].b);
        if (kind[k] == 2)
            goto done; /* no gap: nothing is hidden */
        if (kind[k] == 1) {
            /* widened by 5e-10 for the blocks: gaps narrower than 1e-9 close, and each
             * Phi_t lies well inside its own block, in no other */
            double w = wrap_angle(phi[k].a - SW_EPS_ANGLE_HALF);
            cv[nphi].a = w;
            cv[nphi++].b = w + (phi[k].b - phi[k].a) + SW_EPS_ANGLE;
        }
    }
    int64_t nb = merge_on_circle(cv, nphi, 0, blk);
    if (nb < 0)
        goto done;
    /* C from the gaps inside O */
    int64_t nc = 0;
    int cfull = 0;
    double rc = 0.5 * (ra + rb), zc = 0.5 * (za + zb);
    /* the centre sample may have been moved (circle_arcs) by up to 2^-24 of the part */
    int shortcut = !centre->full && 0.5 * (rb - ra) > 0x1p-22 * c->ext;
    for (int64_t a = 0; a < centre->n; a++)
        if (c->arcs[centre->first + a].start.tri < 0)
            shortcut = 0; /* a conservative arc, not SV's */
    for (int64_t i = 0; i < nb && !cfull; i++) {
        double ga = blk[i].b, gb = i + 1 < nb ? blk[i + 1].a : blk[0].a + MFG_TWO_PI;
        if (!(gb > ga))
            continue;
        double psi = wrap_angle(0.5 * (ga + gb));
        if (shortcut) {
            /* O lies in SV: an angle SV misses at the centre is outside O */
            int in_sv = 0;
            for (int64_t a = 0; a < centre->n && !in_sv; a++) {
                const sw_arc *arc = &c->arcs[centre->first + a];
                double s0 = arc->start.phi, len = arc->end.phi + c->theta - s0;
                in_sv = fmod(psi - s0 + 2 * MFG_TWO_PI, MFG_TWO_PI) <= len;
            }
            if (!in_sv)
                continue;
        }
        int in = sw_point_inside(c, rc, zc, psi);
        if (in < 0) {
            ok = 0;
            goto done;
        }
        if (!in)
            continue;
        if (gb + c->theta - ga >= MFG_TWO_PI || c->full_turn) {
            cfull = 1;
            break;
        }
        cv[nc].a = wrap_angle(ga);
        cv[nc].b = cv[nc].a + (gb + c->theta - ga);
        nc++;
    }
    int64_t ncm = 0;
    if (!cfull) {
        ncm = merge_on_circle(cv, nc, 1, cm);
        cfull = ncm < 0;
    }
    if (!cfull && ncm == 0)
        goto done;
    /* the hidden blocks, then their triangles */
    for (int64_t i = 0; i < nb; i++) {
        double x = wrap_angle(blk[i].a), len = blk[i].b - blk[i].a + c->theta;
        blk[i].a = x;
        blk[i].b = cfull || circle_component(cm, ncm, x, x + len, 1) >= 0 ? x + (len - c->theta) : -1;
    }
    for (int64_t k = 0; k < n; k++) {
        int64_t t = cand[k];
        if (kind[k] == 0) {
            c->hstamp[t] = vs; /* nothing of it over the cell */
            continue;
        }
        for (int64_t i = 0; i < nb && kind[k] == 1; i++)
            if (blk[i].b >= 0 && circle_component(blk + i, 1, phi[k].a, phi[k].b, 0) == 0) {
                c->hstamp[t] = vs;
                break;
            }
    }
done:
    if (cand) {
        memcpy(c->cand, cand, (size_t)n * sizeof *cand);
        c->ncand = n;
    }
    free(cand);
    free(phi);
    free(blk);
    free(cv);
    free(cm);
    free(kind);
    return ok;
}
