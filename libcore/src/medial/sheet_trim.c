/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheet_trim.c - the trim of the sheet extraction (sheets.c; docs/design/medial.md section
 * 4.1): tau, the trimming value of a point, the vertices on the lattice edges, the boundary
 * points where tau changes sign along a polygon edge, and the sheet corners. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/sheets.h"
#include "common/mfg_internal.h"

/* Gauss-Newton on the seam and corner equations (seam_polish, md_sheet_corner_point):
 * converged at residuals below GN_TOL_REL L (a few hundred ulps of L), central differences with a
 * step of FD_STEP_REL h (about sqrt(u): the best-balanced truncation and rounding). */
#define GN_TOL_REL 1e-12
#define FD_STEP_REL 1e-7
/* A seam point is taken when both its equations are within this fraction of L (the steps
 * bounce about a kink of the trimming term at ~1e-9 L, see seam_polish). */
#define SEAM_ON_REL 1e-10
/* J J^T with det below this times g00 g11 (gradients within ~1e-6 rad of parallel) counts
 * as singular. */
#define GRAM_SINGULAR 1e-12
/* A pivot below this times the Jacobian's largest entry counts as singular
 * (md_sheet_corner_point). */
#define PIVOT_REL 1e-6
/* The boundary point's search (md_sheet_boundary_point): its phase 0 bisects the sign of
 * tau down to a bracket of PHASE0_BRACKET of the tet side, phase 1 stops at a trimming term below
 * EDGE_TOL_REL L (a few ulps of L). */
#define EDGE_TOL_REL 1e-15
#define PHASE0_BRACKET 0x1p-10
/* Steps for a boundary point; they stop earlier at a 1-ulp bracket or a zero. */
#define BISECT_STEPS 80

/* The signed distance to the boundary (> 0 inside), from the BVH. */
double md_sheet_signed_dist(const ctx *c, const double *x)
{
    int inside;
    double d = md_bvh_nearest(c->bvh, c->el, x, NULL, &inside);
    return inside ? d : -d;
}

/* |x - ctr| plus the slack: a bound for the change of a 1-Lipschitz function from ctr. */
static double dist_ctr(const ctx *c, const double *x)
{
    double d[3] = {x[0] - c->ctr[0], x[1] - c->ctr[1], x[2] - c->ctr[2]};
    return sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + MD_ROUND_REL * c->el->diag;
}

/* md_region_margin(e, x) (only its sign when sign_only), for e at position i of the
 * leaf's C (-1: not there).  A face's margin is min(g, s): g the signed in-plane distance
 * of x's foot to the face's boundary (O(sides), the costly part), s the distance to its
 * plane.  g is 1-Lipschitz, so g(ctr) +- |x - ctr| bounds it over the leaf: where that
 * decides min(g, s) (or its sign), s alone gives the same result, bit for bit.  g(ctr) is
 * md_region_margin at ctr's foot moved 4 diagonals inside the plane, where s exceeds any
 * |g| (computed once per leaf and face, when first needed). */
static double leaf_margin(const ctx *c, int i, int64_t e, const double *x, int64_t *which,
                          int sign_only)
{
    const md_elements *el = c->el;
    if (i < 0 || md_kind(el, e) != MD_FACE)
        return md_region_margin(el, e, x, which);
    const double *pl = el->face_plane + 4 * e;
    double g = c->cb[i].g;
    if (isnan(g)) {
        double y[3], K = 4 * el->diag, t = K - (pl[3] - (pl[0] * c->ctr[0] + pl[1] * c->ctr[1] +
                                                           pl[2] * c->ctr[2]));
        for (int k = 0; k < 3; k++)
            y[k] = c->ctr[k] - t * pl[k];
        int64_t w;
        g = md_region_margin(el, e, y, &w);
        c->cb[i].g = g = w < 0 ? -INFINITY : g; /* s won (it cannot): no bound */
    }
    if (g == -INFINITY)
        return md_region_margin(el, e, x, which);
    double r = dist_ctr(c, x);
    double s = pl[3] - (pl[0] * x[0] + pl[1] * x[1] + pl[2] * x[2]);
    if (g - r > s || (sign_only && g - r > 0)) { /* min(g, s) = s, or its sign is s's */
        if (which)
            *which = -1;
        return s;
    }
    if (sign_only && g + r < 0)
        return -1.0; /* the foot is outside the face */
    return md_region_margin(el, e, x, which);
}

/* tau(x) = min(l_a, l_b, nu, D), nu = min over c in C \ {a, b} of d_c(x) - d_a^car(x), with
 * restricted d_c, and D the signed distance to the boundary when there is a BVH (design
 * 4.1: outside the solid, e.g. in a non-convex notch, the restricted distances of the
 * faces facing away are +inf and nothing else would trim).  *arg gets the element of the
 * smallest term (l_a, l_b: the element of the boundary whose constraint is smallest, -1
 * for a face's own plane; nu: c; D: -1) and *argk which term it is; ties go to the smaller
 * id.  *D gets min over C of d_c(x). */
/* The bounds of C's element i, computed on first use in the leaf. */
static const cbound *leaf_bound(const ctx *c, int i)
{
    cbound *b = c->cb + i;
    if (isnan(b->m)) {
        b->m = md_region_margin(c->el, c->C[i], c->ctr, NULL);
        b->d = md_dist_car(c->el, c->C[i], c->ctr, NULL);
    }
    return b;
}

static double trim_tau(const ctx *c, const double *x, int64_t *arg, int *argk, double *D)
{
    const md_elements *el = c->el;
    double r = dist_ctr(c, x);
    int64_t wa, wb;
    double la = leaf_margin(c, c->ia, c->a, x, &wa, 0);
    double lb = leaf_margin(c, c->ib, c->b, x, &wb, 0);
    double da = md_dist_car(el, c->a, x, NULL), db = md_dist_car(el, c->b, x, NULL);
    double dmin = INFINITY, nu = INFINITY;
    if (la >= 0)
        dmin = da;
    if (lb >= 0 && db < dmin)
        dmin = db;
    int64_t wn = -1;
    for (int i = 0; i < c->nC; i++) {
        int64_t e = c->C[i];
        if (e == c->a || e == c->b)
            continue;
        /* The region margin and the carrier distance are 1-Lipschitz: their values at the
         * centre, +- r, skip the elements that the tests below would skip anyway. */
        const cbound *bd = leaf_bound(c, i);
        double dl = bd->d - r;
        if ((dl >= dmin && dl - da >= nu) || bd->m + r < 0)
            continue;
        /* d_e >= d_e^car: the region test (the costly part) only where it can matter. */
        double d = md_dist_car(el, e, x, NULL);
        if (!(d < dmin) && !(d - da < nu))
            continue;
        if (!(bd->m - r > 0) && leaf_margin(c, i, e, x, NULL, 1) < 0)
            continue; /* d_e = +inf */
        if (d < dmin)
            dmin = d;
        if (d - da < nu) { /* C ascending: the first of equals is the smaller id */
            nu = d - da;
            wn = e;
        }
    }
    double t = la;
    int64_t w = wa;
    int k = TRIM_A;
    if (lb < t || (lb == t && (unsigned long long)wb < (unsigned long long)w)) {
        t = lb;
        w = wb;
        k = TRIM_B;
    }
    if (nu < t || (nu == t && (unsigned long long)wn < (unsigned long long)w)) {
        t = nu;
        w = wn;
        k = TRIM_NU;
    }
    /* Only the sign matters where tau < 0 already; the signed distance is 1-Lipschitz, so
     * x lies inside where the centre's exceeds |x - ctr|. */
    if (c->bvh && !c->deep && t >= 0 && !(c->sdc > r)) {
        double sd = md_sheet_signed_dist(c, x);
        if (sd < 0) {
            t = sd;
            w = -1;
            k = TRIM_OUT;
        }
    }
    *arg = w;
    *argk = k;
    *D = dmin;
    return t;
}

/* The radius at a sheet point x with D = min over C of d_c(x): D itself, except where x
 * is a rounding error outside a's region (the boundary points, the corners), where D
 * misses a; never below 0 (a face's signed distance rounds to -0 on the boundary). */
static double radius(const ctx *c, const double *x, double D)
{
    double da = md_dist_car(c->el, c->a, x, NULL);
    double r = D < da ? D : da;
    return r > 0 ? r : 0.0;
}

/* The marching-tets vertex on the lattice edge from local corner lo to hi (hi's bits a
 * superset of lo's: lo is the smaller lattice point): pv index, or -1 on NOMEM. */
static const double *edge_root(ctx *c, int lo, int hi)
{
    int e = 8 * lo + hi;
    double *x = c->ex[e];
    if (c->have_ex >> e & 1)
        return x;
    if (!md_root_on_segment(c->el, c->a, c->b, c->cx[lo], c->cx[hi], x, NULL)) {
        /* p + 1 * (q - p) may round away from q and miss a sign seen at q: the corner
         * nearer to f = 0 is the root then. */
        memcpy(x, fabs(c->f[lo]) <= fabs(c->f[hi]) ? c->cx[lo] : c->cx[hi], 3 * sizeof *x);
    }
    c->have_ex |= (uint64_t)1 << e;
    return x;
}

/* Can the pair's sheet show in the leaf?  Only where some marching-tets vertex (a root on
 * a Kuhn edge, lo's bits a subset of hi's, with a sign change) lies in both a's and b's
 * regions: tau <= min(l_a, l_b), and where every vertex has tau < 0 the clip keeps
 * nothing (no boundary point, no corner).  Most of the pairs of a tessellated curved
 * wall are such, and the trim over C would cost them far more. */
int md_sheet_pair_shows(ctx *c)
{
    for (int lo = 0; lo < 8; lo++)
        for (int hi = lo + 1; hi < 8; hi++) {
            if ((lo & hi) != lo || (c->f[lo] >= 0) == (c->f[hi] >= 0))
                continue;
            const double *x = edge_root(c, lo, hi);
            if (leaf_margin(c, c->ia, c->a, x, NULL, 0) >= 0 &&
                leaf_margin(c, c->ib, c->b, x, NULL, 0) >= 0)
                return 1;
        }
    return 0;
}

int md_sheet_edge_vertex(ctx *c, int lo, int hi)
{
    int s = c->slot[8 * lo + hi];
    if (s >= 0)
        return s;
    double x[3];
    memcpy(x, edge_root(c, lo, hi), sizeof x);
    vkey k;
    memset(&k, 0xff, sizeof k);
    k.a = c->a;
    k.b = c->b;
    for (int d = 0; d < 3; d++)
        k.e[0][d] = c->cijk[lo][d];
    k.e[0][3] = lo ^ hi;
    k.c = -2;
    pvert *p = c->pv + c->npv;
    double D;
    p->tau = trim_tau(c, x, &p->arg, &p->argk, &D);
    p->rec = md_sheet_push_vertex(c->out, &k, x, radius(c, x, D));
    if (p->rec < 0)
        return -1;
    p->lo = lo;
    p->hi = hi;
    c->slot[8 * lo + hi] = c->npv;
    return c->npv++;
}

static int lattice_less(const ctx *c, int p, int q)
{
    for (int d = 0; d < 3; d++)
        if (c->cijk[p][d] != c->cijk[q][d])
            return c->cijk[p][d] < c->cijk[q][d];
    return 0;
}

static void edge_of(const ctx *c, const pvert *p, int32_t *e)
{
    for (int d = 0; d < 3; d++)
        e[d] = c->cijk[p->lo][d];
    e[3] = p->lo ^ p->hi;
}

/* The value at x of the trim term (kind k, element t): the region margin of a or b, or
 * d_t^car - d_a^car. */
static double trim_term(const ctx *c, int k, int64_t t, const double *x)
{
    if (k == TRIM_OUT)
        return md_sheet_signed_dist(c, x);
    if (k == TRIM_A)
        return leaf_margin(c, c->ia, c->a, x, NULL, 0);
    if (k == TRIM_B)
        return leaf_margin(c, c->ib, c->b, x, NULL, 0);
    return md_dist_car(c->el, t, x, NULL) - md_dist_car(c->el, c->a, x, NULL);
}

/* The stand-in for R(t) where f has no sign change from A to q (the bisector bends out
 * across B-C inside the tet face and back in: near a cone's apex, e.g. {z1, E} by the
 * L-bracket's convex corner (10, 10, 40) at r ~ 0.006): the root of f nearest to the chord
 * point x0 + t (x1 - x0) on the segments from it to the face's corners A, B, C.  Not the
 * chord point itself: it lies off the bisector (there 0.41), and the assembly drops every
 * triangle with a vertex off it, which left a notch a leaf wide.  One of the segments
 * brackets a root: f(A) != 0 has the other sign than f(B) and f(C) (the two vertices are
 * roots on A-B and A-C), so the chord point's sign differs from A's or from B's and C's.
 * The chord point lies in the face (x0 on A-B, x1 on A-C), so the root does too: in the
 * leaf, and like R(t) a function of the face's lattice points and its two vertices only
 * (the leaves sharing the face agree). */
static void face_root_near_chord(const ctx *c, const double *PA, const double *PB,
                                 const double *PC, const double *x0, const double *x1, double t,
                                 double *x)
{
    const double *P[3] = {PA, PB, PC};
    double xc[3], best = INFINITY;
    for (int d = 0; d < 3; d++)
        xc[d] = x0[d] + t * (x1[d] - x0[d]);
    memcpy(x, xc, sizeof xc); /* kept only if no segment brackets (f at a corner rounded) */
    for (int i = 0; i < 3; i++) {
        double y[3];
        if (!md_root_on_segment(c->el, c->a, c->b, xc, P[i], y, NULL))
            continue;
        double dd = mfg_dist3(xc, y);
        if (dd < best) {
            best = dd;
            memcpy(x, y, sizeof y);
        }
    }
}

/* The boundary point x (a root of f, after face_root_near_chord stood in for R(t): R(t)
 * jumps between the bisector's branches there, the bisection stops at the jump, and the
 * trimming term (kind k, element *t) need not vanish at x) moved onto the seam, f = 0 and
 * the term = 0: Gauss-Newton with the least-norm step (2 equations, 3 unknowns) and a
 * central-difference Jacobian, as in md_sheet_corner_point.  The seam lies outside the tet face
 * then (the bisector leaves it across B-C): the point is the seam's point near x, not
 * R(t).  Taken when the best iterate is within 1e-10 L of both (the steps bounce about a
 * kink of the term at ~1e-9 where the seam meets a corner of the region, the small tray's
 * rib top by its wall), within h of x (the lattice's h: the leaves sharing the face decide
 * alike), and nothing else trims it; otherwise x stays, on the bisector, off the seam.  A
 * region margin may reach 0 there on another side of the region than *t's (that corner):
 * *t becomes the element of that side, as near as a and b there. */
static void seam_polish(const ctx *c, int k, int64_t *t, double *x)
{
    double tol = GN_TOL_REL * c->el->diag, step = FD_STEP_REL * c->h, y[3], yb[3], Fb = INFINITY;
    memcpy(y, x, sizeof y);
    for (int it = 0; it < 40; it++) {
        double F[2], J[2][3];
        F[0] = md_dist_car(c->el, c->a, y, NULL) - md_dist_car(c->el, c->b, y, NULL);
        F[1] = trim_term(c, k, *t, y);
        double Fm = fmax(fabs(F[0]), fabs(F[1]));
        if (it == 0 && Fm <= SEAM_ON_REL * c->el->diag)
            return; /* on the seam already (the bisection ended on R(t), not a stand-in) */
        if (Fm < Fb) {
            Fb = Fm;
            memcpy(yb, y, sizeof y);
        }
        if (Fm <= tol)
            break;
        for (int d = 0; d < 3; d++) {
            double yp[3] = {y[0], y[1], y[2]}, ym[3] = {y[0], y[1], y[2]};
            yp[d] += step;
            ym[d] -= step;
            J[0][d] = (md_dist_car(c->el, c->a, yp, NULL) - md_dist_car(c->el, c->b, yp, NULL) -
                       md_dist_car(c->el, c->a, ym, NULL) + md_dist_car(c->el, c->b, ym, NULL)) /
                      (2 * step);
            J[1][d] = (trim_term(c, k, *t, yp) - trim_term(c, k, *t, ym)) / (2 * step);
        }
        /* dy = -J^T (J J^T)^-1 F; a near-singular J J^T (parallel gradients) gives up. */
        double g00 = mfg_dot3(J[0], J[0]), g01 = mfg_dot3(J[0], J[1]), g11 = mfg_dot3(J[1], J[1]);
        double det = g00 * g11 - g01 * g01;
        if (!(det > GRAM_SINGULAR * g00 * g11))
            break;
        double l0 = (g11 * F[0] - g01 * F[1]) / det, l1 = (g00 * F[1] - g01 * F[0]) / det;
        double dy = 0;
        for (int d = 0; d < 3; d++) {
            double s = l0 * J[0][d] + l1 * J[1][d];
            y[d] -= s;
            dy += fabs(s);
        }
        if (!(dy <= 4 * c->h))
            break;
    }
    int64_t arg;
    int argk;
    double D;
    if (!(Fb <= SEAM_ON_REL * c->el->diag) || !(mfg_dist3(x, yb) <= c->h) ||
        trim_tau(c, yb, &arg, &argk, &D) < -MD_ROUND_REL * c->el->diag)
        return;
    if (k == TRIM_A || k == TRIM_B)
        md_region_margin(c->el, k == TRIM_A ? c->a : c->b, yb, t);
    memcpy(x, yb, sizeof yb);
}

/* The boundary point on the polygon edge between marching-tets vertices iu and iv, whose
 * trims differ in sign.  The polygon edge lies in the tet face of its two lattice edges;
 * they share the corner A of the lone sign of f, the others are B < C (lattice order).
 * R(t) is the root of f on the segment from A to B + t (C - B): R(0), R(1) are the two
 * vertices (as computed on their lattice edges).  tau(R(t)) is bisected to a 1-ulp bracket
 * in t; the point is R at the bracket's kept end (tau >= 0), trimmed by the element that
 * is smallest at its other end.  Everything depends only on the face's lattice points and
 * the two vertices, never on the tet or the leaf, so the leaves sharing the face agree.
 * Returns the pv index, or -1 on NOMEM. */
int md_sheet_boundary_point(ctx *c, int iu, int iv)
{
    int lo = iu < iv ? iu : iv, hi = iu < iv ? iv : iu;
    for (int i = 0; i < c->nbp; i++)
        if (c->bpu[i] == lo && c->bpv[i] == hi)
            return c->bpi[i];
    const pvert *pu = c->pv + iu, *pw = c->pv + iv;
    int A = (pu->lo == pw->lo || pu->lo == pw->hi) ? pu->lo : pu->hi;
    int Bu = pu->lo == A ? pu->hi : pu->lo, Cv = pw->lo == A ? pw->hi : pw->lo;
    /* t = 0 at the vertex on edge A-B, B the smaller lattice point of the two. */
    const pvert *p0 = pu, *p1 = pw;
    int B = Bu, C = Cv;
    if (lattice_less(c, Cv, Bu)) {
        p0 = pw;
        p1 = pu;
        B = Cv;
        C = Bu;
    }
    const double *x0 = c->out->v[p0->rec].x, *x1 = c->out->v[p1->rec].x;
    double tn, tp, best[3], bestD;
    int64_t argn;
    int argkn;
    if (p0->tau < 0) {
        tn = 0.0;
        tp = 1.0;
        argn = p0->arg;
        argkn = p0->argk;
        memcpy(best, x1, sizeof best);
        bestD = c->out->v[p1->rec].r;
    } else {
        tn = 1.0;
        tp = 0.0;
        argn = p1->arg;
        argkn = p1->argk;
        memcpy(best, x0, sizeof best);
        bestD = c->out->v[p0->rec].r;
    }
    const double *PA = c->cx[A], *PB = c->cx[B], *PC = c->cx[C];
    double xn[3], gn = 0, gp = 0, tol = EDGE_TOL_REL * c->el->diag;
    memcpy(xn, p0->tau < 0 ? x0 : x1, sizeof xn);
    int phase = 0, last = 0, fell_back = 0;
    for (int it = 0; it < BISECT_STEPS; it++) {
        /* Phase 0 bisects the sign of tau (which may jump where a region ends) down to a
         * bracket of 2^-10; phase 1 then solves the trimming term of the negative end,
         * which is continuous, by Illinois regula falsi (every 4th step a bisection). */
        double tm = 0.5 * (tn + tp);
        if (phase == 1 && it % 4 != 3) {
            double r = tn + (tp - tn) * (gn / (gn - gp));
            if ((r - tn) * (r - tp) < 0)
                tm = r;
        }
        if (tm == tn || tm == tp)
            break;
        double q[3], x[3];
        for (int d = 0; d < 3; d++)
            q[d] = PB[d] + tm * (PC[d] - PB[d]);
        if (!md_root_on_segment(c->el, c->a, c->b, PA, q, x, NULL)) {
            face_root_near_chord(c, PA, PB, PC, x0, x1, tm, x);
            fell_back = 1;
        }
        if (phase == 0) {
            int64_t arg;
            int argk;
            double D, tau = trim_tau(c, x, &arg, &argk, &D);
            if (tau < 0) {
                tn = tm;
                argn = arg;
                argkn = argk;
                memcpy(xn, x, sizeof xn);
            } else {
                tp = tm;
                memcpy(best, x, sizeof best);
            }
            if (fabs(tp - tn) <= PHASE0_BRACKET) {
                gn = trim_term(c, argkn, argn, xn);
                gp = trim_term(c, argkn, argn, best);
                phase = gn < 0 && gp >= 0; /* otherwise the bisection goes on */
            }
            continue;
        }
        double g = trim_term(c, argkn, argn, x);
        if (fabs(g) <= tol) {
            memcpy(best, x, sizeof best);
            break;
        }
        if (g < 0) {
            tn = tm;
            gn = g;
            if (last < 0)
                gp *= 0.5;
            last = -1;
        } else {
            tp = tm;
            gp = g;
            memcpy(best, x, sizeof best);
            if (last > 0)
                gn *= 0.5;
            last = 1;
        }
    }
    if (fell_back)
        seam_polish(c, argkn, &argn, best);
    {
        int64_t arg;
        int argk;
        trim_tau(c, best, &arg, &argk, &bestD);
    }
    vkey k;
    k.a = c->a;
    k.b = c->b;
    int32_t eu[4], ev[4];
    edge_of(c, pu, eu);
    edge_of(c, pw, ev);
    int swap = memcmp(eu, ev, sizeof eu) > 0; /* any fixed order of the two edges will do */
    memcpy(k.e[0], swap ? ev : eu, sizeof eu);
    memcpy(k.e[1], swap ? eu : ev, sizeof eu);
    k.c = argn;
    pvert *p = c->pv + c->npv;
    p->rec = md_sheet_push_vertex(c->out, &k, best, radius(c, best, bestD));
    if (p->rec < 0)
        return -1;
    p->tau = 0.0;
    p->arg = argn;
    p->argk = argkn;
    p->lo = p->hi = -1;
    c->bpu[c->nbp] = lo;
    c->bpv[c->nbp] = hi;
    c->bpi[c->nbp] = c->npv;
    c->nbp++;
    return c->npv++;
}

static void corner_eqs(const ctx *c, const pvert *p, const pvert *q, const double *x, double *F)
{
    F[0] = md_dist_car(c->el, c->a, x, NULL) - md_dist_car(c->el, c->b, x, NULL);
    F[1] = trim_term(c, p->argk, p->arg, x);
    F[2] = trim_term(c, q->argk, q->arg, x);
}

/* The corner of the sheet inside a clip edge whose ends p and q are trimmed by different
 * terms (design 4.1 "Corners"; a junction or the sheet's meeting with the boundary): Newton
 * on (f_ab, term_p, term_q) = 0 from the chord's midpoint, with a central-difference
 * Jacobian (the terms are distances, or piecewise linear).  The corner lies in this
 * polygon alone, so no neighbour has to agree on its bits.  1 with x and D(x) when it
 * converges inside the leaf (grown by h / 2) and nothing else trims it; 0 keeps the
 * chord. */
int md_sheet_corner_point(const ctx *c, const pvert *p, const pvert *q, double *x, double *Dout)
{
    const double *xp = c->out->v[p->rec].x, *xq = c->out->v[q->rec].x;
    double tol = GN_TOL_REL * c->el->diag, step = FD_STEP_REL * c->h, F[3];
    for (int d = 0; d < 3; d++)
        x[d] = 0.5 * (xp[d] + xq[d]);
    int ok = 0;
    for (int it = 0; it < 40; it++) {
        corner_eqs(c, p, q, x, F);
        if (fabs(F[0]) <= tol && fabs(F[1]) <= tol && fabs(F[2]) <= tol) {
            ok = 1;
            break;
        }
        double J[3][4];
        for (int d = 0; d < 3; d++) {
            double xa[3] = {x[0], x[1], x[2]}, xb[3] = {x[0], x[1], x[2]}, Fa[3], Fb[3];
            xa[d] += step;
            xb[d] -= step;
            corner_eqs(c, p, q, xa, Fa);
            corner_eqs(c, p, q, xb, Fb);
            for (int i = 0; i < 3; i++)
                J[i][d] = (Fa[i] - Fb[i]) / (2 * step);
        }
        for (int i = 0; i < 3; i++)
            J[i][3] = -F[i];
        /* Gaussian elimination with partial pivoting; a near-singular system (the terms
         * dependent, e.g. two planes through one edge) gives up. */
        double scale = 0;
        for (int i = 0; i < 3; i++)
            for (int d = 0; d < 3; d++)
                scale = fmax(scale, fabs(J[i][d]));
        for (int col = 0; col < 3; col++) {
            int piv = col;
            for (int i = col + 1; i < 3; i++)
                if (fabs(J[i][col]) > fabs(J[piv][col]))
                    piv = i;
            if (!(fabs(J[piv][col]) > PIVOT_REL * scale))
                return 0;
            for (int d = 0; d < 4; d++) {
                double t = J[col][d];
                J[col][d] = J[piv][d];
                J[piv][d] = t;
            }
            for (int i = col + 1; i < 3; i++) {
                double m = J[i][col] / J[col][col];
                for (int d = col; d < 4; d++)
                    J[i][d] -= m * J[col][d];
            }
        }
        double dx[3];
        for (int i = 2; i >= 0; i--) {
            double v = J[i][3];
            for (int d = i + 1; d < 3; d++)
                v -= J[i][d] * dx[d];
            dx[i] = v / J[i][i];
        }
        for (int d = 0; d < 3; d++)
            x[d] += dx[d];
        if (!(fabs(dx[0]) + fabs(dx[1]) + fabs(dx[2]) <= 4 * c->h))
            return 0;
    }
    if (!ok)
        return 0;
    for (int d = 0; d < 3; d++)
        if (!(x[d] >= c->cx[0][d] - 0.5 * c->h && x[d] <= c->cx[7][d] + 0.5 * c->h))
            return 0;
    int64_t arg;
    int argk;
    double D;
    if (trim_tau(c, x, &arg, &argk, &D) < -MD_ROUND_REL * c->el->diag)
        return 0;
    *Dout = radius(c, x, D);
    return 1;
}
