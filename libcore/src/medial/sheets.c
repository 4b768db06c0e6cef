/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheets.c - the sheets of the medial surface on the analytic bisectors, the sheet
 * extraction stage (issue 9; Lee & Lee, the medial surface of a polyhedron;
 * docs/design/medial.md section 4.1).  For every octree leaf and every pair (a, b) of
 * its P: marching tetrahedra on f_ab = d_a^car - d_b^car over the 6
 * Kuhn tets about the leaf's main diagonal, with every vertex a root of f_ab on its lattice
 * edge (md_root_on_segment, from the edge's smaller lattice point); then each polygon is
 * trimmed where tau < 0, tau = min(region margins of a and b, min over the other candidates
 * c of d_c - d_a^car, and with a BVH the signed distance to the boundary): where tau
 * changes sign along a polygon edge the boundary point is found on f_ab = 0 inside the tet
 * face; where the two ends of a cut are trimmed by different terms, the sheet's corner is
 * inserted (Newton on three equations); the cuts become seam segments.  Every float of a
 * shared vertex depends only on lattice points and the elements, so the leaves that share
 * a lattice edge or a tet face get the same bits, and welding is by key alone. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

/* Leaves per work unit: the units, not the threads, fix the order of the output. */
#define UNIT_LEAVES 16
/* ... unless all their sides are at most this times h: then they are collapsed. */
#define COLLAPSE_LEN 1e-2
/* Gauss-Newton on the seam and corner equations (seam_polish, corner_point): converged
 * at residuals below GN_TOL_REL L (a few hundred ulps of L), central differences with a
 * step of FD_STEP_REL h (about sqrt(u): the best-balanced truncation and rounding). */
#define GN_TOL_REL 1e-12
#define FD_STEP_REL 1e-7
/* A seam point is taken when both its equations are within this fraction of L (the steps
 * bounce about a kink of the trimming term at ~1e-9 L, see seam_polish). */
#define SEAM_ON_REL 1e-10
/* J J^T with det below this times g00 g11 (gradients within ~1e-6 rad of parallel) counts
 * as singular. */
#define GRAM_SINGULAR 1e-12
/* A pivot below this times the Jacobian's largest entry counts as singular (corner_point). */
#define PIVOT_REL 1e-6
/* The boundary point's search (boundary_point): its phase 0 bisects the sign of tau down
 * to a bracket of PHASE0_BRACKET of the tet side, phase 1 stops at a trimming term below
 * EDGE_TOL_REL L (a few ulps of L). */
#define EDGE_TOL_REL 1e-15
#define PHASE0_BRACKET 0x1p-10
/* Steps for a boundary point; they stop earlier at a 1-ulp bracket or a zero. */
#define BISECT_STEPS 80
/* Room per (leaf, pair): the 19 Kuhn edges of a cube, at most one boundary point per tet
 * face (18 distinct: 12 on the cube's faces, 6 inside), at most 2 corners per tet (12). */
#define MAX_PV 64
#define MAX_BP 48

/* A vertex key: the pair, and either one lattice edge (a vertex of the marching tets;
 * e[1] all -1, c = -2), or the two lattice edges of the polygon edge that holds a boundary
 * point (in a fixed order) and the element that trims it, or for a sheet corner (found in
 * one polygon only) the leaf's lattice point with direction 8 + tet, the cut's position
 * in the polygon, c = -3.  A lattice edge is its smaller lattice point (i, j, k) and its
 * Kuhn direction (1 .. 7: bit d set when it steps along axis d). */
typedef struct vkey {
    int64_t a, b;
    int32_t e[2][4];
    int64_t c;
} vkey;

typedef struct vrec {
    vkey k;
    double x[3];
    double r; /* D at the vertex */
} vrec;

/* One work unit's output, in leaf order; vertex indices are local to the unit. */
typedef struct unit_buf {
    vrec *v;
    int64_t nv, cv;
    int64_t *t, *tp; /* 3 vertices and the pair (a, b) per triangle */
    int64_t nt, ct;
    int64_t *s, *se, *sp; /* 2 vertices, 3 elements and the pair per seam segment */
    int32_t *sk;
    int64_t ns, cs;
    mfg_status st;
} unit_buf;

/* A vertex of a (leaf, pair): its record in the unit, its trim value and trimming
 * element, and its lattice edge (local corners lo < hi) or -1 for a boundary point. */
typedef struct pvert {
    int64_t rec;
    double tau;
    int64_t arg;
    int argk; /* the term of tau that arg belongs to: TRIM_A, TRIM_B, TRIM_NU, TRIM_OUT */
    int lo, hi;
} pvert;

enum { TRIM_A = 0, TRIM_B = 1, TRIM_NU = 2, TRIM_OUT = 3 };

/* Values at the leaf's centre of the element at one position of C, for Lipschitz bounds
 * over the leaf: g a face's in-plane margin (-inf: none), m the region margin, d the
 * carrier distance. */
typedef struct cbound {
    double g, m, d;
} cbound;

/* The state of one (leaf, pair). */
typedef struct ctx {
    const md_elements *el;
    const md_bvh *bvh; /* NULL: no inside test */
    int deep;          /* the leaf lies deeper than 2h inside the solid: no inside test */
    const int64_t *C;
    int nC;
    int64_t a, b;
    int ia, ib;        /* positions of a and b in C, or -1 */
    double ctr[3];     /* the leaf's centre */
    double sdc;        /* signed distance to the boundary there (with a BVH) */
    struct cbound *cb; /* per C position: bounds from ctr (NAN: not yet computed) */
    int capC;
    double cx[8][3];   /* corner c = dx | dy << 1 | dz << 2 */
    double h;
    int32_t cijk[8][3];
    double f[8];
    int slot[64];      /* lattice edge lo * 8 + hi -> pv index, or -1 */
    double ex[64][3];  /* lattice edge lo * 8 + hi -> its root, when bit lo * 8 + hi of */
    uint64_t have_ex;  /* have_ex is set */
    pvert pv[MAX_PV];
    int npv;
    int bpu[MAX_BP], bpv[MAX_BP], bpi[MAX_BP]; /* boundary points by polygon edge */
    int nbp;
    unit_buf *out;
} ctx;

static int cmp_key(const vkey *x, const vkey *y)
{
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 4; k++)
            if (x->e[i][k] != y->e[i][k])
                return x->e[i][k] < y->e[i][k] ? -1 : 1;
    return (x->c > y->c) - (x->c < y->c);
}

/* ---- growing the unit's buffers -------------------------------------------------------- */

/* The next capacity of a unit's array of cap items that is full. */
static int64_t next_cap(int64_t cap)
{
    return cap ? 2 * cap : 64;
}

static int64_t push_vertex(unit_buf *u, const vkey *k, const double *x, double r)
{
    if (u->nv == u->cv) {
        int64_t c = next_cap(u->cv);
        if (!mfg_resize((void **)&u->v, c, sizeof *u->v))
            return -1;
        u->cv = c;
    }
    vrec *v = u->v + u->nv;
    v->k = *k;
    memcpy(v->x, x, sizeof v->x);
    v->r = r;
    return u->nv++;
}

static int push_tri(unit_buf *u, int64_t p, int64_t q, int64_t r, int64_t a, int64_t b)
{
    if (u->nt == u->ct) {
        /* An array already grown when the next fails is only larger: still consistent. */
        int64_t c = next_cap(u->ct);
        if (!mfg_resize((void **)&u->t, c, 3 * sizeof *u->t))
            return 0;
        if (!mfg_resize((void **)&u->tp, c, 2 * sizeof *u->tp))
            return 0;
        u->ct = c;
    }
    u->t[3 * u->nt] = p;
    u->t[3 * u->nt + 1] = q;
    u->t[3 * u->nt + 2] = r;
    u->tp[2 * u->nt] = a;
    u->tp[2 * u->nt + 1] = b;
    u->nt++;
    return 1;
}

static int push_seg(unit_buf *u, int64_t p, int64_t q, const int64_t *e3, int32_t kind, int64_t a,
                    int64_t b)
{
    if (u->ns == u->cs) {
        int64_t c = next_cap(u->cs);
        if (!mfg_resize((void **)&u->s, c, 2 * sizeof *u->s))
            return 0;
        if (!mfg_resize((void **)&u->se, c, 3 * sizeof *u->se))
            return 0;
        if (!mfg_resize((void **)&u->sk, c, sizeof *u->sk))
            return 0;
        if (!mfg_resize((void **)&u->sp, c, 2 * sizeof *u->sp))
            return 0;
        u->cs = c;
    }
    u->s[2 * u->ns] = p;
    u->s[2 * u->ns + 1] = q;
    memcpy(u->se + 3 * u->ns, e3, 3 * sizeof *e3);
    u->sk[u->ns] = kind;
    u->sp[2 * u->ns] = a;
    u->sp[2 * u->ns + 1] = b;
    u->ns++;
    return 1;
}

static void unit_free(unit_buf *u)
{
    free(u->v);
    free(u->t);
    free(u->tp);
    free(u->s);
    free(u->se);
    free(u->sk);
    free(u->sp);
}

/* ---- the trim ----------------------------------------------------------------------- */

/* The signed distance to the boundary (> 0 inside), from the BVH. */
static double signed_dist(const ctx *c, const double *x)
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
        double sd = signed_dist(c, x);
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
static int pair_shows(ctx *c)
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

static int edge_vertex(ctx *c, int lo, int hi)
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
    p->rec = push_vertex(c->out, &k, x, radius(c, x, D));
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
        return signed_dist(c, x);
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
 * central-difference Jacobian, as in corner_point.  The seam lies outside the tet face
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
static int boundary_point(ctx *c, int iu, int iv)
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
    p->rec = push_vertex(c->out, &k, best, radius(c, best, bestD));
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
static int corner_point(const ctx *c, const pvert *p, const pvert *q, double *x, double *Dout)
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

/* ---- one tet ---------------------------------------------------------------------------- */

static double tri_area2(const double *p, const double *q, const double *r)
{
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Can element e be nearest inside the solid?  Not a convex edge, nor a vertex whose edges
 * are all convex (design 3.3: their regions lie outside).  A sheet trimmed by one of those
 * meets the solid's boundary there (r -> 0): no seam. */
static int inside_element(const md_elements *el, int64_t e)
{
    int k = md_kind(el, e);
    if (k == MD_EDGE)
        return !el->edge_convex[e - el->nfaces];
    if (k == MD_VERTEX) {
        int64_t j = e - el->nfaces - el->nedges;
        for (int64_t q = el->vert_edge_offsets[j]; q < el->vert_edge_offsets[j + 1]; q++)
            if (!el->edge_convex[el->vert_edges[q] - el->nfaces])
                return !el->vert_region_empty[j];
        return 0;
    }
    return 1;
}

/* The seam kind of a boundary trimmed by element t: a sub-element of a or b whose region
 * ended is SMOOTH, any element not incident to either is BRANCH. */
static int32_t seam_kind(const md_elements *el, int64_t a, int64_t b, int64_t t)
{
    return md_incident(el, t, a) || md_incident(el, t, b) ? MFG_MEDIAL_SMOOTH : MFG_MEDIAL_BRANCH;
}

/* Marching tets on tet (v[0..3], local corners, each a bit-superset of the previous):
 * the polygon of f = 0, oriented with its normal towards f > 0, clipped to tau >= 0,
 * fanned from its smallest key, and its clip edges as seam segments.  0 on NOMEM. */
static int do_tet(ctx *c, const int *v, int tet)
{
    int pos[4], neg[4], np = 0, nn = 0;
    for (int i = 0; i < 4; i++) {
        if (c->f[v[i]] >= 0)
            pos[np++] = v[i];
        else
            neg[nn++] = v[i];
    }
    if (np == 0 || nn == 0)
        return 1;
    int e[4][2], ne = 0; /* polygon vertices as lattice edges (corner, corner) */
    if (np == 1 || nn == 1) {
        int lone = np == 1 ? pos[0] : neg[0];
        const int *oth = np == 1 ? neg : pos;
        for (int i = 0; i < 3; i++) {
            e[ne][0] = lone;
            e[ne][1] = oth[i];
            ne++;
        }
    } else {
        int cyc[4][2] = {{pos[0], neg[0]}, {pos[0], neg[1]}, {pos[1], neg[1]}, {pos[1], neg[0]}};
        memcpy(e, cyc, sizeof cyc);
        ne = 4;
    }
    /* Orientation, exactly on local corner coordinates (doubled): the Newell normal of the
     * polygon of edge midpoints against the direction from the negative corners to the
     * positive ones.  The midpoint polygon is never degenerate. */
    long m[4][3], nrm[3] = {0, 0, 0}, dir[3] = {0, 0, 0};
    for (int i = 0; i < ne; i++)
        for (int d = 0; d < 3; d++)
            m[i][d] = ((e[i][0] >> d) & 1) + ((e[i][1] >> d) & 1);
    for (int i = 0; i < ne; i++) {
        const long *p = m[i], *q = m[(i + 1) % ne];
        nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
        nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
        nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    for (int d = 0; d < 3; d++) {
        for (int i = 0; i < np; i++)
            dir[d] += nn * ((pos[i] >> d) & 1);
        for (int i = 0; i < nn; i++)
            dir[d] -= np * ((neg[i] >> d) & 1);
    }
    if (nrm[0] * dir[0] + nrm[1] * dir[1] + nrm[2] * dir[2] < 0)
        for (int i = 0; i < ne / 2; i++) {
            int t0 = e[i][0], t1 = e[i][1];
            e[i][0] = e[ne - 1 - i][0];
            e[i][1] = e[ne - 1 - i][1];
            e[ne - 1 - i][0] = t0;
            e[ne - 1 - i][1] = t1;
        }
    int pvi[4];
    for (int i = 0; i < ne; i++) {
        int lo = e[i][0], hi = e[i][1];
        if ((lo & hi) != lo) { /* order the edge from its smaller lattice point */
            int t = lo;
            lo = hi;
            hi = t;
        }
        pvi[i] = edge_vertex(c, lo, hi);
        if (pvi[i] < 0)
            return 0;
    }
    /* Clip to tau >= 0 (Sutherland-Hodgman on the cycle). */
    int out[8], exit_after[8], no = 0;
    for (int i = 0; i < ne; i++) {
        int u = pvi[i], w = pvi[(i + 1) % ne];
        int in_u = c->pv[u].tau >= 0, in_w = c->pv[w].tau >= 0;
        if (in_u) {
            exit_after[no] = 0;
            out[no++] = u;
        }
        if (in_u != in_w) {
            int bp = boundary_point(c, u, w);
            if (bp < 0)
                return 0;
            exit_after[no] = in_u;
            out[no++] = bp;
        }
    }
    if (no < 3)
        return 1;
    /* Clip edges: a corner of the sheet where the trimming changes (inserted when it is
     * found), and the seam segments along them. */
    unit_buf *ub = c->out;
    int poly[16], n2 = 0;
    int64_t segt[16]; /* the element trimming the edge from poly[i] to the next, or < 0 */
    for (int i = 0; i < no; i++) {
        poly[n2] = out[i];
        segt[n2] = -1;
        if (exit_after[i]) {
            const pvert *p = c->pv + out[i], *q = c->pv + out[(i + 1) % no];
            double x[3], D;
            if ((p->arg != q->arg || p->argk != q->argk) && corner_point(c, p, q, x, &D)) {
                segt[n2++] = p->arg;
                vkey k;
                memset(&k, 0xff, sizeof k);
                k.a = c->a;
                k.b = c->b;
                memcpy(k.e[0], c->cijk[0], sizeof c->cijk[0]);
                k.e[0][3] = 8 + tet;
                k.e[1][0] = i;
                k.c = -3;
                pvert *j = c->pv + c->npv;
                j->rec = push_vertex(ub, &k, x, D);
                if (j->rec < 0)
                    return 0;
                j->tau = 0.0;
                j->arg = -1;
                j->argk = TRIM_NU;
                j->lo = j->hi = -1;
                poly[n2] = c->npv++;
                segt[n2] = q->arg;
            } else if (p->arg == q->arg) {
                segt[n2] = p->arg;
            }
            /* Otherwise no corner in this leaf: the kept region's boundary left the polygon
             * between samples (near the boundary of the solid, or a junction beside this
             * polygon), and the chord is on no seam. */
        }
        n2++;
    }
    for (int i = 0; i < n2; i++) {
        int64_t t = segt[i];
        if (t < 0 || !inside_element(c->el, t))
            continue; /* not a clip edge, or the sheet meets the solid's boundary */
        int64_t e3[3] = {c->a, c->b, t};
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2 - x; y++)
                if (e3[y] > e3[y + 1]) {
                    int64_t sw = e3[y];
                    e3[y] = e3[y + 1];
                    e3[y + 1] = sw;
                }
        if (!push_seg(ub, c->pv[poly[i]].rec, c->pv[poly[(i + 1) % n2]].rec, e3,
                      seam_kind(c->el, c->a, c->b, t), c->a, c->b))
            return 0;
    }
    int *out_ = poly;
    no = n2;
    int s0 = 0;
    for (int i = 1; i < no; i++)
        if (cmp_key(&ub->v[c->pv[out_[i]].rec].k, &ub->v[c->pv[out_[s0]].rec].k) < 0)
            s0 = i;
    for (int i = 1; i + 1 < no; i++) {
        int64_t p = c->pv[out_[s0]].rec, q = c->pv[out_[(s0 + i) % no]].rec;
        int64_t r = c->pv[out_[(s0 + i + 1) % no]].rec;
        if (!push_tri(ub, p, q, r, c->a, c->b))
            return 0;
    }
    return 1;
}

/* The 6 Kuhn tets of the unit cube about its main diagonal 0 -> 7: one per order of the
 * axes, each a monotone path of corners. */
static const int KUHN[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                               {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

/* The position of element e in the leaf's C (ascending), or -1. */
static int c_index(const ctx *c, int64_t e)
{
    int lo = 0, hi = c->nC;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (c->C[mid] < e)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < c->nC && c->C[lo] == e ? lo : -1;
}

static mfg_status do_leaf(const md_elements *el, const md_bvh *bvh, const md_leaves *lv,
                          const md_leaf *L, unit_buf *ub, ctx *c)
{
    c->el = el;
    c->bvh = bvh;
    c->C = lv->C + L->C_off;
    c->nC = L->nC;
    c->out = ub;
    c->h = lv->lat.h;
    for (int k = 0; k < 8; k++)
        for (int d = 0; d < 3; d++) {
            c->cijk[k][d] = L->ijk[d] + ((k >> d) & 1);
            c->cx[k][d] = lv->lat.origin[d] + lv->lat.h * (double)c->cijk[k][d];
        }
    /* Every point evaluated for this leaf (corners grown by h / 2 included) lies within
     * 2h of its centre. */
    c->deep = 0;
    for (int d = 0; d < 3; d++)
        c->ctr[d] = lv->lat.origin[d] + lv->lat.h * ((double)L->ijk[d] + 0.5);
    if (bvh && L->nP > 0) {
        c->sdc = signed_dist(c, c->ctr);
        c->deep = c->sdc > 2 * lv->lat.h;
    }
    if (L->nC > c->capC) {
        cbound *g = realloc(c->cb, (size_t)L->nC * sizeof *g);
        if (!g)
            return MFG_ERR_NOMEM;
        c->cb = g;
        c->capC = L->nC;
    }
    for (int i = 0; i < L->nC; i++)
        c->cb[i].g = c->cb[i].m = c->cb[i].d = NAN;
    for (int p = 0; p < L->nP; p++) {
        c->a = lv->P[L->P_off + 2 * p];
        c->b = lv->P[L->P_off + 2 * p + 1];
        c->ia = c_index(c, c->a);
        c->ib = c_index(c, c->b);
        int npos = 0;
        for (int k = 0; k < 8; k++) {
            c->f[k] = md_dist_car(el, c->a, c->cx[k], NULL) - md_dist_car(el, c->b, c->cx[k], NULL);
            npos += c->f[k] >= 0;
        }
        if (npos == 0 || npos == 8)
            continue;
        c->have_ex = 0;
        if (!pair_shows(c))
            continue;
        for (int i = 0; i < 64; i++)
            c->slot[i] = -1;
        c->npv = 0;
        c->nbp = 0;
        for (int t = 0; t < 6; t++)
            if (!do_tet(c, KUHN[t], t))
                return MFG_ERR_NOMEM;
    }
    return MFG_OK;
}

/* ---- threads ------------------------------------------------------------------------------ */

typedef struct job {
    const md_elements *el;
    const md_bvh *bvh;
    const md_leaves *lv;
    int64_t nunits;
    unit_buf *units;
    atomic_llong next;
    atomic_int failed;
    mfg_prog *prog;   /* progress (NULL: none); only the caller's thread reports */
    pthread_t caller;
} job;

static void *worker(void *arg)
{
    job *j = arg;
    ctx *c = malloc(sizeof *c);
    if (c) {
        c->cb = NULL;
        c->capC = 0;
    }
    int is_caller = pthread_equal(pthread_self(), j->caller) != 0;
    for (;;) {
        if (!mfg_prog_poll_mt(j->prog, is_caller, (double)atomic_load(&j->next),
                              (double)j->nunits))
            break;
        long long u = atomic_fetch_add(&j->next, 1);
        if (u >= j->nunits || atomic_load(&j->failed))
            break;
        unit_buf *ub = j->units + u;
        if (!c) {
            ub->st = MFG_ERR_NOMEM;
            atomic_store(&j->failed, 1);
            break;
        }
        int64_t end = (u + 1) * UNIT_LEAVES;
        if (end > j->lv->nleaves)
            end = j->lv->nleaves;
        for (int64_t i = u * UNIT_LEAVES; i < end && ub->st == MFG_OK; i++)
            ub->st = do_leaf(j->el, j->bvh, j->lv, j->lv->leaf + i, ub, c);
        if (ub->st != MFG_OK)
            atomic_store(&j->failed, 1);
    }
    if (c)
        free(c->cb);
    free(c);
    return NULL;
}

/* ---- merge ------------------------------------------------------------------------------- */

typedef struct sref {
    const vrec *r;
    int64_t g; /* global record index: unit order, then the unit's own order */
} sref;

static int cmp_sref(const sref *x, const sref *y)
{
    int c = cmp_key(&x->r->k, &y->r->k);
    return c ? c : (x->g > y->g) - (x->g < y->g);
}

/* Sorts s[0..n) by cmp_sref (a total order: g is unique), with tmp of n / 2 + 1 items: a merge
 * sort with the comparison inlined, about twice as fast as qsort's indirect calls on the
 * millions of records of a large part. */
static void sort_srefs(sref *s, sref *tmp, int64_t n)
{
    if (n <= 16) {
        for (int64_t i = 1; i < n; i++) {
            sref v = s[i];
            int64_t j = i;
            for (; j > 0 && cmp_sref(&v, s + j - 1) < 0; j--)
                s[j] = s[j - 1];
            s[j] = v;
        }
        return;
    }
    int64_t m = n / 2;
    sort_srefs(s, tmp, m);
    sort_srefs(s + m, tmp, n - m);
    if (cmp_sref(s + m - 1, s + m) <= 0)
        return; /* already in order (records of one leaf often are) */
    memcpy(tmp, s, (size_t)m * sizeof *s);
    int64_t i = 0, j = m, k = 0;
    while (i < m && j < n)
        s[k++] = cmp_sref(s + j, tmp + i) < 0 ? s[j++] : tmp[i++];
    while (i < m)
        s[k++] = tmp[i++];
}

void md_soup_free(md_soup *s)
{
    if (!s)
        return;
    free(s->xyz);
    free(s->radius);
    free(s->tris);
    free(s->tri_pair);
    free(s->seg_verts);
    free(s->seg_elems);
    free(s->seg_kind);
    free(s->seg_pair);
    memset(s, 0, sizeof *s);
}

/* Welds the units' records by key (ids in key order), collapses the tiny triangles, drops
 * degenerate triangles and unreferenced vertices, and writes the soup in unit order. */
static mfg_status merge(const unit_buf *units, int64_t nunits, double h, md_soup *out)
{
    int64_t N = 0, NT = 0, NS = 0;
    for (int64_t u = 0; u < nunits; u++) {
        N += units[u].nv;
        NT += units[u].nt;
        NS += units[u].ns;
    }
    mfg_status st = MFG_ERR_NOMEM;
    sref *sr = malloc((size_t)(N ? N : 1) * sizeof *sr);
    int64_t *gid = malloc((size_t)(N ? N : 1) * sizeof *gid);
    int64_t *rep = malloc((size_t)(N ? N : 1) * sizeof *rep);   /* id -> representative */
    int64_t *newid = malloc((size_t)(N ? N : 1) * sizeof *newid);
    int64_t *uoff = malloc((size_t)(nunits + 1) * sizeof *uoff);
    const vrec **recs = malloc((size_t)(N ? N : 1) * sizeof *recs);
    sref *tmp = malloc((size_t)(N / 2 + 1) * sizeof *tmp);
    md_soup s;
    memset(&s, 0, sizeof s);
    s.tris = malloc((size_t)(NT ? 3 * NT : 1) * sizeof *s.tris);
    s.tri_pair = malloc((size_t)(NT ? 2 * NT : 1) * sizeof *s.tri_pair);
    s.seg_verts = malloc((size_t)(NS ? 2 * NS : 1) * sizeof *s.seg_verts);
    s.seg_elems = malloc((size_t)(NS ? 3 * NS : 1) * sizeof *s.seg_elems);
    s.seg_kind = malloc((size_t)(NS ? NS : 1) * sizeof *s.seg_kind);
    s.seg_pair = malloc((size_t)(NS ? 2 * NS : 1) * sizeof *s.seg_pair);
    if (!sr || !gid || !rep || !newid || !uoff || !recs || !tmp || !s.tris || !s.tri_pair || !s.seg_verts ||
        !s.seg_elems || !s.seg_kind || !s.seg_pair)
        goto done;
    uoff[0] = 0;
    for (int64_t u = 0; u < nunits; u++) {
        uoff[u + 1] = uoff[u] + units[u].nv;
        for (int64_t i = 0; i < units[u].nv; i++) {
            sr[uoff[u] + i].r = units[u].v + i;
            sr[uoff[u] + i].g = uoff[u] + i;
            recs[uoff[u] + i] = units[u].v + i;
        }
    }
    sort_srefs(sr, tmp, N);
    int64_t nid = 0;
    for (int64_t i = 0; i < N; i++) {
        if (i == 0 || cmp_key(&sr[i].r->k, &sr[i - 1].r->k) != 0)
            rep[nid++] = sr[i].g;
        gid[sr[i].g] = nid - 1;
    }
    double amin = MD_AREA_DROP * h * h, lmax = COLLAPSE_LEN * h;
    /* Where the sheet passes within rounding of a lattice point, the roots on the Kuhn
     * edges there crowd about it and the tets give triangles below amin with all sides
     * short: dropping one leaves a pinhole (the T-section's {z1, E} by (33.94, 54.02,
     * 35.84) at tol 1 % L).  Such a triangle of three roots is collapsed instead: its
     * vertices become one (the smallest id, a vertex on the bisector), so that its
     * neighbours' sides weld and they close the hole; the order of the unions does not
     * matter.  Boundary points and corners (the seams' vertices) never move: a tiny
     * triangle at a seam is dropped as before (moving a vertex of the T-section's seam of
     * four elements gave a spurious seam of three). */
    for (int64_t i = 0; i < nid; i++)
        newid[i] = i; /* union-find parents here; reset below */
    for (int64_t u = 0; u < nunits; u++) {
        const unit_buf *ub = units + u;
        for (int64_t t = 0; t < ub->nt; t++) {
            int64_t g[3];
            for (int k = 0; k < 3; k++)
                g[k] = gid[uoff[u] + ub->t[3 * t + k]];
            const double *x0 = recs[rep[g[0]]]->x, *x1 = recs[rep[g[1]]]->x;
            const double *x2 = recs[rep[g[2]]]->x;
            int roots = recs[rep[g[0]]]->k.c == -2 && recs[rep[g[1]]]->k.c == -2 &&
                        recs[rep[g[2]]]->k.c == -2;
            if (roots && 0.5 * tri_area2(x0, x1, x2) < amin && mfg_dist3(x0, x1) <= lmax &&
                mfg_dist3(x1, x2) <= lmax && mfg_dist3(x2, x0) <= lmax) {
                mfg_uf_union(newid, g[0], g[1]);
                mfg_uf_union(newid, g[0], g[2]);
            }
        }
    }
    for (int64_t i = 0; i < nid; i++)
        rep[i] = rep[mfg_uf_find(newid, i)];
    for (int64_t i = 0; i < N; i++)
        gid[i] = mfg_uf_find(newid, gid[i]);
    for (int64_t i = 0; i < nid; i++)
        newid[i] = -1;
    for (int64_t u = 0; u < nunits; u++) {
        const unit_buf *ub = units + u;
        for (int64_t t = 0; t < ub->nt; t++) {
            int64_t g[3];
            for (int k = 0; k < 3; k++)
                g[k] = gid[uoff[u] + ub->t[3 * t + k]];
            if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2])
                continue;
            if (0.5 * tri_area2(recs[rep[g[0]]]->x, recs[rep[g[1]]]->x, recs[rep[g[2]]]->x) < amin)
                continue;
            memcpy(s.tris + 3 * s.ntris, g, sizeof g);
            s.tri_pair[2 * s.ntris] = ub->tp[2 * t];
            s.tri_pair[2 * s.ntris + 1] = ub->tp[2 * t + 1];
            s.ntris++;
            for (int k = 0; k < 3; k++)
                newid[g[k]] = 0;
        }
        for (int64_t t = 0; t < ub->ns; t++) {
            int64_t g0 = gid[uoff[u] + ub->s[2 * t]], g1 = gid[uoff[u] + ub->s[2 * t + 1]];
            if (g0 == g1)
                continue;
            s.seg_verts[2 * s.nsegs] = g0;
            s.seg_verts[2 * s.nsegs + 1] = g1;
            memcpy(s.seg_elems + 3 * s.nsegs, ub->se + 3 * t, 3 * sizeof(int64_t));
            s.seg_kind[s.nsegs] = ub->sk[t];
            s.seg_pair[2 * s.nsegs] = ub->sp[2 * t];
            s.seg_pair[2 * s.nsegs + 1] = ub->sp[2 * t + 1];
            s.nsegs++;
            newid[g0] = newid[g1] = 0;
        }
    }
    for (int64_t i = 0; i < nid; i++)
        if (newid[i] == 0)
            newid[i] = s.nverts++;
    s.xyz = malloc((size_t)(s.nverts ? 3 * s.nverts : 1) * sizeof *s.xyz);
    s.radius = malloc((size_t)(s.nverts ? s.nverts : 1) * sizeof *s.radius);
    if (!s.xyz || !s.radius)
        goto done;
    for (int64_t i = 0; i < nid; i++)
        if (newid[i] >= 0) {
            const vrec *r = recs[rep[i]];
            memcpy(s.xyz + 3 * newid[i], r->x, sizeof r->x);
            s.radius[newid[i]] = r->r;
        }
    for (int64_t t = 0; t < 3 * s.ntris; t++)
        s.tris[t] = newid[s.tris[t]];
    for (int64_t t = 0; t < 2 * s.nsegs; t++)
        s.seg_verts[t] = newid[s.seg_verts[t]];
    *out = s;
    memset(&s, 0, sizeof s);
    st = MFG_OK;
done:
    md_soup_free(&s);
    free(sr);
    free(gid);
    free(rep);
    free(newid);
    free(uoff);
    free(recs);
    free(tmp);
    return st;
}

mfg_status md_sheets_extract(const md_elements *el, const md_bvh *bvh, const md_leaves *leaves,
                             double tolerance, int nthreads, md_soup *out)
{
    return md_sheets_extract_p(el, bvh, leaves, tolerance, nthreads, out, NULL);
}

mfg_status md_sheets_extract_p(const md_elements *el, const md_bvh *bvh, const md_leaves *leaves,
                               double tolerance, int nthreads, md_soup *out, mfg_prog *prog)
{
    (void)tolerance; /* the leaf side h sets every threshold here */
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "md_sheets_extract: out is NULL");
    memset(out, 0, sizeof *out);
    if (!el || !leaves)
        return mfg_fail(MFG_ERR_NULL, "md_sheets_extract: elements or leaves NULL");
    int64_t nunits = (leaves->nleaves + UNIT_LEAVES - 1) / UNIT_LEAVES;
    job j;
    j.el = el;
    j.bvh = bvh;
    j.lv = leaves;
    j.nunits = nunits;
    j.prog = prog;
    j.caller = pthread_self();
    j.units = calloc((size_t)(nunits ? nunits : 1), sizeof *j.units);
    if (!j.units)
        return mfg_fail(MFG_ERR_NOMEM, "md_sheets_extract: out of memory");
    atomic_init(&j.next, 0);
    atomic_init(&j.failed, 0);
    int nt = nthreads < 1 ? 1 : nthreads;
    if (nt > 64)
        nt = 64;
    if (nt > nunits)
        nt = nunits > 0 ? (int)nunits : 1;
    pthread_t tid[64];
    int started = 0;
    for (int i = 1; i < nt; i++) {
        if (pthread_create(tid + started, NULL, worker, &j) != 0)
            break; /* fewer threads: the same output, later */
        started++;
    }
    worker(&j);
    for (int i = 0; i < started; i++)
        pthread_join(tid[i], NULL);
    mfg_status st = MFG_OK;
    for (int64_t u = 0; u < nunits && st == MFG_OK; u++)
        st = j.units[u].st;
    if (st == MFG_OK && atomic_load(&j.failed))
        st = MFG_ERR_NOMEM; /* a worker without its context stopped before any unit */
    int cancelled = st == MFG_OK && prog && mfg_prog_stopped(prog);
    if (cancelled)
        st = MFG_ERR_CANCELLED;
    if (st == MFG_OK)
        st = merge(j.units, nunits, leaves->lat.h, out);
    for (int64_t u = 0; u < nunits; u++)
        unit_free(j.units + u);
    free(j.units);
    if (st != MFG_OK) {
        memset(out, 0, sizeof *out);
        if (cancelled)
            return mfg_prog_fail(prog);
        return mfg_fail(st, "md_sheets_extract: out of memory");
    }
    return MFG_OK;
}
