/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/cells.c - The meridian decomposition: cells: the quadtree grid, curves crossing a
 * cell's sides, and the cells cut along one curve (split), round a vertex image (star) or
 * along several chords.  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

double sw_grid_r(const sw_ctx *c, int64_t i)
{
    return c->r0 + (double)i * c->h;
}

double sw_grid_z(const sw_ctx *c, int64_t i)
{
    return c->z0 + (double)i * c->h;
}

/* A crossing of a curve with a side of a cell: its position along the side's line, the
 * curve parameter and which root. */
typedef struct sw_cross {
    double pos, u;
    int64_t curve;
} sw_cross;

/* The real roots of a x^2 + b x + c = 0 in ascending order, in the stable form (no
 * cancellation between -b and the square root); a negative discriminant counts as zero
 * (a double root) when clamp is set - a tangency lost to rounding - else gives none. */
int sw_solve_quadratic(double a, double b, double c, int clamp, double roots[2])
{
    if (a == 0) {
        if (b == 0)
            return 0;
        roots[0] = -c / b;
        return 1;
    }
    double disc = b * b - 4 * a * c;
    if (disc < 0) {
        if (!clamp)
            return 0;
        disc = 0;
    }
    double sq = sqrt(disc), q = -0.5 * (b + (b >= 0 ? sq : -sq));
    double r1 = q / a, r2 = q != 0 ? c / q : r1;
    if (r1 > r2) {
        double t = r1;
        r1 = r2;
        r2 = t;
    }
    roots[0] = r1;
    if (r2 == r1)
        return 1;
    roots[1] = r2;
    return 2;
}

/* Crossings of curve cv with the open segment of the line r = val (vertical_side) or
 * z = val between lo and hi.  Up to 2. */
int sw_curve_side(const sw_curve *cv, int rside, double val, double lo, double hi,
                  double pos[2], double us[2])
{
    int n = 0;
    if (!rside) {
        if (cv->dir[2] == 0)
            return 0; /* horizontal: lies in its own plane z = const, never crosses one */
        double u = (val - cv->p0[2]) / cv->dir[2];
        if (!(u >= 0 && u <= 1))
            return 0;
        double r2 = cv->qa * u * u + cv->qb * u + cv->qc;
        double r = sqrt(r2 > 0 ? r2 : 0);
        if (r > lo && r < hi) {
            pos[n] = r;
            us[n++] = u;
        }
        return n;
    }
    /* qa u^2 + qb u + qc - val^2 = 0 */
    double roots[2];
    int nr = sw_solve_quadratic(cv->qa, cv->qb, cv->qc - val * val, 0, roots);
    for (int k = 0; k < nr; k++) {
        double u = roots[k];
        if (!(u >= 0 && u <= 1))
            continue;
        double z = cv->p0[2] + u * cv->dir[2];
        if (z > lo && z < hi) {
            pos[n] = z;
            us[n++] = u;
        }
    }
    return n;
}

/* The 4 sides of cell (ix, iz, size s) in counter-clockwise order: side k runs from
 * corner k to corner k+1; corners (ix, iz), (ix+s, iz), (ix+s, iz+s), (ix, iz+s). */
void sw_side_geom(const sw_ctx *c, int64_t ix, int64_t iz, int64_t s, int k, int *rside,
                  double *val, double *lo, double *hi)
{
    double ra = sw_grid_r(c, ix), rb = sw_grid_r(c, ix + s), za = sw_grid_z(c, iz), zb = sw_grid_z(c, iz + s);
    switch (k) {
    case 0: *rside = 0; *val = za; *lo = ra; *hi = rb; break;
    case 1: *rside = 1; *val = rb; *lo = za; *hi = zb; break;
    case 2: *rside = 0; *val = zb; *lo = ra; *hi = rb; break;
    default: *rside = 1; *val = ra; *lo = za; *hi = zb; break;
    }
}

typedef struct sw_cellinfo {
    int kind;              /* 0 clean, 1 split, 2 star, 3 refine / fallback */
    int64_t split_curve;
    int64_t nvimg;         /* distinct vertex images in the closed cell */
    double vimg[2];        /* one of them */
    int64_t vimg_vtx;
    int vimg_inside;       /* strictly inside */
} sw_cellinfo;

/* Sample (cached at grid corners). */
int sw_corner_sample(sw_ctx *c, hmap *cache, int64_t ix, int64_t iz, sw_struct **pool,
                     int64_t *npool, int64_t *cappool, int64_t *out)
{
    hkey k = mkkey(ix, iz, 0, 0);
    int64_t v = hmap_get(cache, &k);
    if (v >= 0) {
        *out = v;
        return 1;
    }
    sw_struct s;
    if (!sw_circle_arcs(c, sw_grid_r(c, ix), sw_grid_z(c, iz), &s))
        return 0;
    if (!mfg_grow((void **)pool, cappool, *npool + 1, sizeof **pool))
        return ctx_nomem(c);
    (*pool)[*npool] = s;
    if (!hmap_put(cache, &k, *npool))
        return ctx_nomem(c);
    *out = (*npool)++;
    return 1;
}


/* Sag of curve cv between parameters ua and ub from its chord, in the (r, z) plane. */
double sw_curve_sag(const sw_curve *cv, double ua, double ub)
{
    double ra = sqrt(fmax(0, cv->qa * ua * ua + cv->qb * ua + cv->qc));
    double rb = sqrt(fmax(0, cv->qa * ub * ub + cv->qb * ub + cv->qc));
    double za = cv->p0[2] + ua * cv->dir[2], zb = cv->p0[2] + ub * cv->dir[2];
    double dr = rb - ra, dz = zb - za, len = sqrt(dr * dr + dz * dz);
    double worst = 0;
    for (int k = 1; k < 8; k++) {
        double u = ua + (ub - ua) * k / 8.0;
        double r = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
        double z = cv->p0[2] + u * cv->dir[2];
        double d = len > 0 ? fabs((r - ra) * dz - (z - za) * dr) / len : sqrt((r - ra) * (r - ra) + (z - za) * (z - za));
        if (d > worst)
            worst = d;
    }
    return worst;
}

/* Do the two crossings pts and q of chords with a cell's sides coincide (in either order)? */
int sw_same_pair(double pts[][2], double q[2][2], double eps)
{
    return (fabs(pts[0][0] - q[0][0]) <= eps && fabs(pts[0][1] - q[0][1]) <= eps &&
            fabs(pts[1][0] - q[1][0]) <= eps && fabs(pts[1][1] - q[1][1]) <= eps) ||
           (fabs(pts[0][0] - q[1][0]) <= eps && fabs(pts[0][1] - q[1][1]) <= eps &&
            fabs(pts[1][0] - q[0][0]) <= eps && fabs(pts[1][1] - q[0][1]) <= eps);
}

double sw_curve_r(const sw_curve *cv, double u)
{
    return sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
}

/* The parameter in [lo, hi] (widened by rounding) at which curve cv has radius r, or NAN. */
double sw_curve_u_at_r(const sw_curve *cv, double r, double lo, double hi)
{
    double roots[2], best = NAN, slack = SW_EPS_PARAM;
    int nr = sw_solve_quadratic(cv->qa, cv->qb, cv->qc - r * r, 1, roots);
    for (int k = 0; k < nr; k++)
        if (roots[k] >= lo - slack && roots[k] <= hi + slack)
            best = roots[k];
    return best;
}

/*
 * Where two chords cross inside a cell (two edge images, not at a vertex image), the
 * cell is cut into the four wedges round their crossing, like a star round a vertex image,
 * instead of being refined down to blocks at every crossing (the output grew with the
 * number of crossings times the depth of the tree).  Accepted when the two curves meet
 * once strictly inside the cell, each half of each curve stays within tol/4 of its chord
 * from the crossing, and the corners in the same wedge agree.  The crossing is computed
 * on the curves themselves, so that the lifts there land on both edges.
 */
int sw_crossing_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                     double rb, double za, double zb, const double *ua, int64_t cb,
                     const double *ub)
{
    const sw_curve *A = &c->curves[L->split_curve], *B = &c->curves[cb];
    double alo = fmin(ua[0], ua[1]), ahi = fmax(ua[0], ua[1]);
    double blo = fmin(ub[0], ub[1]), bhi = fmax(ub[0], ub[1]);
    if (A->dir[2] == 0 && B->dir[2] == 0)
        return 0;
    if (A->dir[2] == 0) {
        const sw_curve *t = A;
        A = B;
        B = t;
        double t0 = alo, t1 = ahi;
        alo = blo;
        ahi = bhi;
        blo = t0;
        bhi = t1;
    }
    /* A is not horizontal: z = A.p0z + u A.dz, u in [alo, ahi] */
    double u = NAN, v = NAN;
    if (B->dir[2] == 0) {
        double z = B->p0[2];
        u = (z - A->p0[2]) / A->dir[2];
        if (!(u > alo && u < ahi))
            return 0;
        v = sw_curve_u_at_r(B, sw_curve_r(A, u), blo, bhi);
    } else {
        /* r_A(z)^2 = r_B(z)^2, with u = (z - a0) / ad, v = (z - b0) / bd: a quadratic in z */
        double a0 = A->p0[2], ad = A->dir[2], b0 = B->p0[2], bd = B->dir[2];
        double ka = A->qa / (ad * ad), kb = B->qa / (bd * bd);
        double qa = ka - kb;
        double qb = A->qb / ad - 2 * ka * a0 - (B->qb / bd - 2 * kb * b0);
        double qc = ka * a0 * a0 - A->qb * a0 / ad + A->qc - (kb * b0 * b0 - B->qb * b0 / bd + B->qc);
        double zs[2];
        int nz = sw_solve_quadratic(qa, qb, qc, 0, zs);
        int found = 0;
        for (int k = 0; k < nz; k++) {
            double uu = (zs[k] - a0) / ad, vv = (zs[k] - b0) / bd;
            if (uu > alo && uu < ahi && vv > blo && vv < bhi) {
                found++;
                u = uu;
                v = vv;
            }
        }
        if (found != 1)
            return 0;
    }
    if (!(v > blo && v < bhi) || !(u > alo && u < ahi))
        return 0;
    double cr = sw_curve_r(A, u), cz = A->p0[2] + u * A->dir[2];
    /* not within rounding of a side: a crossing on the axis (a plane and its half turn
     * meet there) computed at r = 1e-9 left a ring of that radius open */
    double eps = sw_point_eps(c, rb, zb);
    if (!(cr - ra > eps && rb - cr > eps && cz - za > eps && zb - cz > eps))
        return 0;
    double lim = 0.25 * c->tol;
    if (sw_curve_sag(A, alo, u) > lim || sw_curve_sag(A, u, ahi) > lim || sw_curve_sag(B, blo, v) > lim ||
        sw_curve_sag(B, v, bhi) > lim)
        return 0;
    /* corners in one wedge (same side of both chords) agree */
    double pa[2][2], pb[2][2];
    for (int e = 0; e < 2; e++) {
        double ue = e ? ahi : alo, ve = e ? bhi : blo;
        pa[e][0] = sw_curve_r(A, ue);
        pa[e][1] = A->p0[2] + ue * A->dir[2];
        pb[e][0] = sw_curve_r(B, ve);
        pb[e][1] = B->p0[2] + ve * B->dir[2];
    }
    double crs[4][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb}};
    int side[4][2];
    for (int k = 0; k < 4; k++) {
        double oa = (pa[1][0] - pa[0][0]) * (crs[k][1] - pa[0][1]) - (pa[1][1] - pa[0][1]) * (crs[k][0] - pa[0][0]);
        double ob = (pb[1][0] - pb[0][0]) * (crs[k][1] - pb[0][1]) - (pb[1][1] - pb[0][1]) * (crs[k][0] - pb[0][0]);
        if (oa == 0 || ob == 0)
            return 0;
        side[k][0] = oa > 0;
        side[k][1] = ob > 0;
    }
    for (int k = 0; k < 4; k++)
        for (int j = k + 1; j < 4; j++)
            if (side[k][0] == side[j][0] && side[k][1] == side[j][1] &&
                !sw_same_struct(c, all[k], all[j]))
                return 0;
    L->kind = LEAF_STAR;
    L->cr = cr;
    L->cz = cz;
    L->cvtx = -1;
    return 1;
}

/* The point of curve cv at (r, z) within eps, or NAN: its parameter there. */
static double curve_u_at(const sw_curve *cv, double r, double z, double eps)
{
    double u;
    if (cv->dir[2] != 0) {
        u = (z - cv->p0[2]) / cv->dir[2];
    } else {
        if (fabs(cv->p0[2] - z) > eps)
            return NAN;
        u = sw_curve_u_at_r(cv, r, 0, 1);
    }
    if (!(u >= -SW_EPS_PARAM && u <= 1 + SW_EPS_PARAM) || fabs(sw_curve_r(cv, u) - r) > eps)
        return NAN;
    return u;
}

/*
 * Where gap-closing curves meet (the exit or entry face changes across an edge, or the
 * gap stops at a silhouette), the arc structure changes round a point that is not the
 * image of a mesh vertex: the end of a gap-closing curve on another curve.  The cell is
 * cut into a star round it, as round a vertex image, when every curve through the cell
 * ends there or passes through it, each piece from the junction to a side stays within
 * tol/4 of its chord, and the corners and the centre in one wedge agree.
 */
int sw_junction_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                     double rb, double za, double zb, const sw_jcurve *jc, int njc)
{
    double eps = sw_point_eps(c, rb, zb);
    double J[2] = {NAN, NAN};
    /* the junction: an end of a gap-closing curve strictly inside the cell */
    for (int i = 0; i < njc && !(J[0] == J[0]); i++) {
        const sw_curve *cv = &c->curves[jc[i].curve];
        if (cv->gexit < 0)
            continue;
        for (int e = 0; e < 2; e++) {
            double r = sw_curve_r(cv, e), z = cv->p0[2] + e * cv->dir[2];
            if (r > ra && r < rb && z > za && z < zb) {
                J[0] = r;
                J[1] = z;
                break;
            }
        }
    }
    /* ... or an end of a silhouette or of a face's image that is no vertex's image: where
     * the image of an edge folds back at its point nearest the axis (a horizontal edge
     * of a part about a parallel axis: the silhouette of the side face through it ends
     * there, and the image of the cap starts there) */
    for (int i = 0; i < njc && !(J[0] == J[0]); i++) {
        const sw_curve *cv = &c->curves[jc[i].curve];
        if (cv->tri[1] >= 0 || cv->gexit >= 0)
            continue;
        for (int e = 0; e < 2; e++) {
            double r = sw_curve_r(cv, e), z = cv->p0[2] + e * cv->dir[2];
            if (cv->vtx[e] < 0 && r > ra && r < rb && z > za && z < zb) {
                J[0] = r;
                J[1] = z;
                break;
            }
        }
    }
    if (!(J[0] == J[0]))
        return 0;
    if (!(J[0] - ra > eps && rb - J[0] > eps && J[1] - za > eps && zb - J[1] > eps))
        return 0;
    double ang[2 * SW_MAXJUNCTION];
    int nray = 0;
    for (int i = 0; i < njc; i++) {
        const sw_curve *cv = &c->curves[jc[i].curve];
        double u = curve_u_at(cv, J[0], J[1], eps);
        if (!(u == u))
            return 0;
        int at_end = u <= SW_EPS_PARAM || u >= 1 - SW_EPS_PARAM;
        /* ends at J: one crossing; passes through J: two; a horizontal curve at J's
         * height lies on the line through it, folded or not: one or two */
        int along = cv->dir[2] == 0 && fabs(cv->p0[2] - J[1]) <= eps;
        if (along ? jc[i].ncr < 1 : jc[i].ncr != (at_end ? 1 : 2))
            return 0;
        for (int k = 0; k < jc[i].ncr; k++) {
            double pr = jc[i].pts[k][0], pz = jc[i].pts[k][1];
            double uk = curve_u_at(cv, pr, pz, eps);
            if (!(uk == uk) || sw_curve_sag(cv, fmin(u, uk), fmax(u, uk)) > 0.25 * c->tol)
                return 0;
            ang[nray++] = atan2(pz - J[1], pr - J[0]);
        }
    }
    if (nray < 2)
        return 0;
    qsort(ang, (size_t)nray, sizeof *ang, sw_cmp_double_asc);
    /* the wedge of each sample: the number of rays below its direction */
    double crs[5][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb}, {0.5 * (ra + rb), 0.5 * (za + zb)}};
    int wedge[5];
    for (int k = 0; k < 5; k++) {
        double dr = crs[k][0] - J[0], dz = crs[k][1] - J[1];
        if (fabs(dr) <= eps && fabs(dz) <= eps) {
            wedge[k] = -1;
            continue;
        }
        double a = atan2(dz, dr);
        int w = 0;
        for (int q = 0; q < nray; q++) {
            if (a == ang[q])
                return 0;
            w += ang[q] < a;
        }
        wedge[k] = w % nray;
    }
    for (int k = 0; k < 5; k++)
        for (int j = k + 1; j < 5; j++)
            if (wedge[k] >= 0 && wedge[k] == wedge[j] && !sw_same_struct(c, all[k], all[j]))
                return 0;
    L->kind = LEAF_STAR;
    L->cr = J[0];
    L->cz = J[1];
    L->cvtx = -1;
    return 1;
}

/*
 * Several curves cross the cell, each from side to side, without crossing one another in
 * it: two curves diverging from a junction or a vertex image just outside, a gap-closing
 * curve beside the edge it ends on.  The cell is cut along all their chords (instead of
 * being refined down to blocks all along the narrow angle between them) when each curve
 * stays within tol/4 of its chord, no two chords meet, and the samples with the same
 * sides of every chord agree.  Coincident chords (one image) count once.
 */
int sw_chords_cell(sw_ctx *c, sw_leaf *L, const sw_struct *const *all, double ra,
                   double rb, double za, double zb, const sw_jcurve *jc, int njc,
                   double peps)
{
    double ch[SW_MAXJUNCTION][2][2];
    int nch = 0;
    for (int i = 0; i < njc; i++) {
        if (jc[i].ncr != 2)
            return 0;
        double q[2][2];
        memcpy(q, jc[i].pts, sizeof q);
        int dup = 0;
        for (int j = 0; j < nch && !dup; j++)
            dup = sw_same_pair(ch[j], q, peps);
        if (dup)
            continue;
        const sw_curve *cv = &c->curves[jc[i].curve];
        double eps = sw_point_eps(c, rb, zb);
        double u0 = curve_u_at(cv, q[0][0], q[0][1], eps), u1 = curve_u_at(cv, q[1][0], q[1][1], eps);
        if (!(u0 == u0) || !(u1 == u1) || sw_curve_sag(cv, fmin(u0, u1), fmax(u0, u1)) > 0.25 * c->tol)
            return 0;
        memcpy(ch[nch], q, sizeof q);
        nch++;
    }
    if (nch < 2)
        return 0;
    /* chords of a convex cell with ends on its sides cross iff the ends of one lie on both
     * sides of the other; ends in common are refused too */
    for (int i = 0; i < nch; i++)
        for (int j = 0; j < nch; j++) {
            if (i == j)
                continue;
            double o[2];
            for (int e = 0; e < 2; e++)
                o[e] = (ch[i][1][0] - ch[i][0][0]) * (ch[j][e][1] - ch[i][0][1]) -
                       (ch[i][1][1] - ch[i][0][1]) * (ch[j][e][0] - ch[i][0][0]);
            if (o[0] == 0 || o[1] == 0 || (o[0] > 0) != (o[1] > 0))
                return 0;
            for (int e = 0; e < 2; e++)
                for (int f = 0; f < 2; f++)
                    if (fabs(ch[i][e][0] - ch[j][f][0]) <= peps && fabs(ch[i][e][1] - ch[j][f][1]) <= peps)
                        return 0;
        }
    double crs[5][2] = {{ra, za}, {rb, za}, {rb, zb}, {ra, zb}, {0.5 * (ra + rb), 0.5 * (za + zb)}};
    unsigned sig[5];
    for (int k = 0; k < 5; k++) {
        sig[k] = 0;
        for (int i = 0; i < nch; i++) {
            double o = (ch[i][1][0] - ch[i][0][0]) * (crs[k][1] - ch[i][0][1]) -
                       (ch[i][1][1] - ch[i][0][1]) * (crs[k][0] - ch[i][0][0]);
            if (o == 0)
                return 0;
            sig[k] |= (unsigned)(o > 0) << i;
        }
    }
    for (int k = 0; k < 5; k++)
        for (int j = k + 1; j < 5; j++)
            if (sig[k] == sig[j] && !sw_same_struct(c, all[k], all[j]))
                return 0;
    L->kind = LEAF_CHORDS;
    L->nchords = nch;
    return 1;
}
