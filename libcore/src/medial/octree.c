/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* octree.c - the adaptive octree of the 3-D medial surface (issue 9; Lee & Lee, the medial
 * surface of a polyhedron; docs/design/medial.md sections 3 and 5).
 *
 * The root cube (side S = 1.02 x the largest extent) is subdivided down to leaves of side
 * h, the largest S / 2^k <= tolerance.  A cell survives only when some pair of boundary
 * elements may have a (near-)medial bisector point inside it; every surviving cell reaches
 * size h, so the sheet leaves form one sparse lattice (md_lattice) -- except, when the
 * caller asks for them, the coarse plane leaves (coarse_plane below, design 3.4): cells
 * crossed by the bisector plane of two faces alone stop at any size.
 *
 * The cell test, at the centre c with half-diagonal rho:
 *  1. u = min over the candidates of the closed distance: the unsigned distance from c to
 *     the boundary.  Its sign (inside / outside) is inherited from the parent when the
 *     boundary is farther from the parent's centre than the child's centre is, and tested
 *     afresh (the BVH's pseudonormal, or a winding number without BVH) only when needed.
 *     Outside and u > rho: the whole cell is outside; pruned.
 *  2. C = {e : dist(c, closure of e) <= u + 2 rho + delta}, delta = h / 64 (slack, below).
 *  3. P = the pairs of "admissible" elements of C that are not incident (major mode:
 *     whose closures are disjoint, md_adjacent) and pass the pair tests.  P empty: pruned.
 *  4. At side h: a leaf {ijk, C, P, nT}.
 *
 * Soundness (a missed pair is a missing sheet).  Let x be a point of the cell (|x - c| <=
 * rho) inside the solid where a and b are near-medial: x lies in both Voronoi regions,
 * d_a(x) = D(x) and d_b(x) <= D(x) + delta (delta = 0: exactly medial).  Closed distances
 * dc_e, the carrier distances d_e^car, the region margins and the boundary distance u are
 * 1-Lipschitz, the restricted distance equals the closed and the carrier distance inside
 * the region, and D(x) = u(x) inside the solid.  Therefore, at the centre:
 *   - dc_b(c) <= dc_b(x) + rho = d_b(x) + rho <= u(x) + delta + rho <= u(c) + 2 rho + delta:
 *     a and b are in C (every element nearest somewhere in the cell is, for the same reason);
 *   - margin_e(c) >= margin_e(x) - rho >= -rho (e in {a, b});
 *   - d_e^car(c) lies within var_e of d_e^car(x) in [u(x), u(x) + delta], u(x) within rho of
 *     u(c); var_e is the variation of d_e^car over the cell: (s/2) |n|_1 for a face (its
 *     carrier distance is linear), rho for an edge's line or a vertex;
 *   - |d_a^car(c) - d_b^car(c)| <= var_a + var_b + delta and |dc_a(c) - dc_b(c)| <= 2 rho +
 *     delta: the bisector (or, with delta, the band of near-medial points) may cross;
 *   - every half-space h(x) = g.x - k >= 0 that contains a's region (region_halfspaces) has
 *     h(x) >= 0, so its maximum over the cube, h(c) + (s/2) |g|_1, is >= 0; and for one
 *     half-space of a and one of b, the sum h_a + h_b is >= 0 at x, so its maximum over
 *     the cube is >= 0 (the regions may meet in the cell).
 * Every test below is one of these inequalities (plus tau for rounding), so a pair that is
 * (near-)medial somewhere in a cell survives in that cell and all its ancestors.  They
 * replace design 3's step 4 ("both distances <= D + 2 rho at the centre or a corner"): at
 * the centre that holds for every pair of C, and restricted distances at the corners can
 * miss a region that passes between them.  The slack delta = h / 64 keeps the pairs whose
 * distances come within h / 64 of each other (and of D) in the leaf: it covers rounding by
 * far, and costs a second layer of leaves only where a sheet runs within h / 128 of a
 * lattice plane.  [choice] The brief's test band h / 4 would make delta = h / 4, which
 * doubles the leaves of a sheet within h / 8 of a lattice plane (the disc: 46k -> 92k);
 * exact soundness is what the sheets need, so the tests check medial points (on the
 * bisector) with the band h / 64.
 *
 * Inheritance (design 3, step 2): at depth >= 3 the candidates are the parent's C.  The
 * child's ball lies in the parent's: |c - c_p| = rho (the child's), u(c) <= u(c_p) + rho
 * and 2 rho_child = rho_parent, so |c - c_p| + u(c) + 2 rho + delta <= u(c_p) + 2 rho_p +
 * delta.  The nearest boundary point of c is then in the parent's C too, so u(c) is exact.
 * A face's closed distance needs the signed in-plane distance of the centre's projection
 * to the face's boundary (O(sides)); a lower bound of it is inherited (the projection is
 * 1-Lipschitz), and while it stays positive the closed distance is |s_F|, O(1).
 *
 * Cost: a cell costs O(|parent's C|) distance evaluations, plus O(|A|^2) pair tests at the
 * leaves (A: the admissible elements); above the leaves the pair search stops at the
 * first pair.
 *
 * Parallelism (design 5): the cells at depth wd (the smallest with 8^wd >= 16 threads)
 * are the work units, in Morton order, taken from an atomic counter; each thread has its
 * own scratch and output buffers.  A cell's outcome depends only on its ancestors, and the
 * leaves are sorted by (i, j, k) at the end, so the output is bit-identical for any number
 * of threads.  No global state. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

#define INHERIT_DEPTH 3 /* from this depth on, candidates come from the parent (design 3) */
#define MAX_DEPTH 21    /* the lattice key holds 21 bits per axis */
#define MAX_THREADS 64

/* The context a cell leaves to its children. */
typedef struct level {
    int64_t n;   /* |C| */
    int64_t *C;  /* candidates, ascending */
    double *dc;  /* closed distances from the centre */
    double *inb; /* faces: lower bound of the in-plane margin of the centre's projection */
    double u;    /* unsigned distance from the centre to the boundary */
    int sign;    /* +1 inside, -1 outside, 0 not known */
} level;

typedef struct job job;

typedef struct worker {
    job *J;
    level *lev;          /* lev[d], d = 0 .. depth: the cells on the current path */
    int64_t *lev_cap;    /* room in lev[d]'s arrays (grown on demand: C shrinks with depth) */
    /* per-cell scratch, nelements each */
    int64_t *cand;
    double *dc, *inb, *car, *mg, *var;
    int64_t *hk; /* 2 per C index: the two region half-spaces most violated at the centre */
    double *hv;  /* 2 per C index: their values there */
    int64_t *A; /* indices into C of the admissible elements */
    int64_t *pairs;
    int64_t cap_pairs;
    /* output */
    md_leaf *leaf;
    int64_t nleaf, cap_leaf;
    int64_t *C;
    int64_t nC, cap_C;
    int64_t *P;
    int64_t nP, cap_P;
    int64_t visited;
    int nomem;
} worker;

struct job {
    const md_elements *el;
    const md_bvh *bvh;
    md_lattice lat;
    int full;
    int coarse;       /* 1: coarse plane leaves (design 3.4) */
    double delta;     /* h / 64: the slack of the pair tests */
    double tau;       /* rounding: 1e-9 L + 4 eta */
    double shift;     /* 4 L: moves a point off a face to read its in-plane margin */
    int8_t *may_pair; /* per element: may enter P */
    double *half_l1;  /* per face: |n|_1 / 2 */
    /* Half-spaces g.x - k >= 0 (g a unit vector) that hold on each element's Voronoi
     * region: hs[4 j ..] = (g, k) for j in hs_off[e] .. hs_off[e + 1]. */
    int64_t *hs_off;
    double *hs;
    /* work units: children of the saved cells at depth wd - 1 */
    int wd;
    level *par;
    int32_t (*par_ijk)[3];
    int64_t npar, cap_par;
    atomic_llong next;
    atomic_int stop;
    mfg_prog *prog; /* progress (NULL: none); only the caller's thread reports */
    pthread_t caller;
};

/* ---- the cell test ------------------------------------------------------------------- */

/* Signed in-plane distance from the projection of x on face f's plane to the face's
 * boundary (> 0 inside the polygon).  md_region_margin gives min(s_F, that); at a point
 * moved 4 L behind the face along -n (same projection, up to rounding covered by tau)
 * s_F exceeds any in-plane distance, which is <= L inside the polygon. */
static double face_inplane(const job *J, int64_t f, const double x[3])
{
    const double *n = J->el->face_plane + 4 * f;
    double y[3];
    for (int k = 0; k < 3; k++)
        y[k] = x[k] - J->shift * n[k];
    return md_region_margin(J->el, f, y, NULL);
}

/* Solid-angle winding number (Van Oosterom & Strackee) of the mesh around x: the inside
 * test without BVH.  Only called at |x - boundary| > rho > 0, where it is far from 1/2. */
static int inside_winding(const md_elements *el, const double x[3])
{
    double w = 0;
    for (int64_t t = 0; t < el->nt; t++) {
        double a[3], b[3], c[3];
        for (int k = 0; k < 3; k++) {
            a[k] = el->xyz[3 * el->tris[3 * t] + k] - x[k];
            b[k] = el->xyz[3 * el->tris[3 * t + 1] + k] - x[k];
            c[k] = el->xyz[3 * el->tris[3 * t + 2] + k] - x[k];
        }
        double la = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        double lb = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        double lc = sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
        double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
        double ab = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        double ac = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
        double bc = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
        w += atan2(det, la * lb * lc + ab * lc + ac * lb + bc * la);
    }
    /* The solid angles sum to 4 pi (sum of half-angles 2 pi) inside, 0 outside. */
    return fabs(w) > MFG_PI;
}

static int point_inside(const job *J, const double x[3])
{
    if (J->bvh) {
        int in = 0;
        md_bvh_nearest(J->bvh, J->el, x, NULL, &in);
        return in;
    }
    return inside_winding(J->el, x);
}

/* The region's half-spaces at the centre c of a cell of side s: 0 when one of them misses
 * the whole cell (its maximum over the cube, value + (s/2) |g|_1, is negative);
 * otherwise the two most violated ones go to hk / hv (-1: none) for regions_apart. */
static int region_meets_cell(const job *J, int64_t e, const double c[3], double s,
                             int64_t hk[2], double hv[2])
{
    hk[0] = hk[1] = -1;
    hv[0] = hv[1] = INFINITY;
    for (int64_t j = J->hs_off[e]; j < J->hs_off[e + 1]; j++) {
        const double *g = J->hs + 4 * j;
        double v = g[0] * c[0] + g[1] * c[1] + g[2] * c[2] - g[3];
        if (v + 0.5 * s * (fabs(g[0]) + fabs(g[1]) + fabs(g[2])) < -J->tau)
            return 0;
        if (v < hv[0]) {
            hk[1] = hk[0];
            hv[1] = hv[0];
            hk[0] = j;
            hv[0] = v;
        } else if (v < hv[1]) {
            hk[1] = j;
            hv[1] = v;
        }
    }
    return 1;
}

/* 1 when the regions of a and b cannot meet in the cell: a half-space of each whose sum
 * (g_a + g_b).x - k_a - k_b, nonnegative on the intersection, is negative on the whole
 * cube (a Farkas certificate with unit weights, tried on the two most violated
 * half-spaces of each).  E.g. two faces of a finely tessellated wall one strip apart:
 * their prisms are separated by the strip between them however large the cell. */
static int regions_apart(const job *J, double s, const int64_t ka[2], const double va[2],
                         const int64_t kb[2], const double vb[2])
{
    for (int i = 0; i < 2 && ka[i] >= 0; i++)
        for (int j = 0; j < 2 && kb[j] >= 0; j++) {
            const double *ga = J->hs + 4 * ka[i], *gb = J->hs + 4 * kb[j];
            double l1 = fabs(ga[0] + gb[0]) + fabs(ga[1] + gb[1]) + fabs(ga[2] + gb[2]);
            if (va[i] + vb[j] + 0.5 * s * l1 < -J->tau)
                return 1;
        }
    return 0;
}

enum { CELL_PRUNED, CELL_SPLIT, CELL_LEAF, CELL_NOMEM };

/* Is cell ijk at depth d < lat.depth (centre c, half-diagonal rho, candidates me->C with
 * |C| = 2) a coarse plane leaf (design 3.4)?  1 yes, 0 no (split it), -1 when the pair's
 * bisector misses the cell (nothing in it is medial: pruned).
 *
 * Why this is exact at any size: C holds every element that is nearest anywhere in the
 * cell (design 3, step 2), so with C = {a, b} only a and b are; both are faces, so their
 * carrier distances are affine and the bisector is a plane; each face's in-plane margin
 * at the centre's projection exceeds rho (a lower bound of it, inherited or exact), so
 * the foot of every point of the cell lies inside both polygons; and s_a = s_b > tau on
 * the plane's polygon in the cube (affine on a convex polygon whose vertices are the
 * plane's crossings of the cube's edges, checked there with 2 tau for their rounding,
 * far above it): every point of
 * that polygon lies in both regions, inside the solid (its nearest boundary point is
 * interior to a face and on that face's inner side), at equal distance from a and b, and
 * no third element comes near.  The polygon is the whole medial surface in the cell:
 * untrimmed, no seam, no junction (nT = 2). */
static int coarse_plane(const job *J, const level *me, const int32_t ijk[3], int d, double rho)
{
    const md_elements *el = J->el;
    int64_t a = me->C[0], b = me->C[1];
    if (b >= el->nfaces || !(me->inb[0] - rho > J->tau) || !(me->inb[1] - rho > J->tau))
        return 0;
    int64_t M = (int64_t)1 << (J->lat.depth - d);
    double sa[8], sb[8];
    int npos = 0;
    for (int q = 0; q < 8; q++) {
        double x[3];
        for (int k = 0; k < 3; k++)
            x[k] = J->lat.origin[k] + J->lat.h * (double)((int64_t)ijk[k] * M + ((q >> k) & 1) * M);
        sa[q] = md_dist_car(el, a, x, NULL);
        sb[q] = md_dist_car(el, b, x, NULL);
        npos += sa[q] - sb[q] >= 0;
    }
    if (npos == 0 || npos == 8)
        return -1;
    /* s_a at the plane's crossing of each cube edge it crosses (s_a is affine along the
     * edge; the corners themselves may lie outside the solid: a wall thinner than the
     * cell) */
    for (int q = 0; q < 8; q++)
        for (int k = 0; k < 3; k++) {
            int r = q | 1 << k;
            double fq = sa[q] - sb[q], fr = sa[r] - sb[r];
            if (r == q || (fq >= 0) == (fr >= 0))
                continue;
            double t = fq / (fq - fr); /* in [0, 1] */
            double s = sa[q] + t * (sa[r] - sa[q]);
            if (!(s > 2 * J->tau))
                return 0;
        }
    return 1;
}

/* Appends the leaf ijk (level lvl, nT, C = me->C[0 .. n), P = w->pairs[0 .. 2 np)). */
static int emit_leaf(worker *w, const int32_t ijk[3], int32_t lvl, const level *me, int64_t n,
                     int64_t np, int32_t nT)
{
    if (!mfg_grow((void **)&w->leaf, &w->cap_leaf, w->nleaf + 1, sizeof *w->leaf) ||
        !mfg_grow((void **)&w->C, &w->cap_C, w->nC + n, sizeof *w->C) ||
        !mfg_grow((void **)&w->P, &w->cap_P, w->nP + 2 * np, sizeof *w->P))
        return CELL_NOMEM;
    md_leaf *lf = &w->leaf[w->nleaf++];
    memset(lf, 0, sizeof *lf); /* the padding too: leaves are compared as bytes (tests) */
    memcpy(lf->ijk, ijk, sizeof lf->ijk);
    lf->nC = (int32_t)n;
    lf->nP = (int32_t)np;
    lf->nT = nT;
    lf->level = lvl;
    lf->C_off = w->nC;
    lf->P_off = w->nP;
    memcpy(w->C + w->nC, me->C, (size_t)n * sizeof *w->C);
    memcpy(w->P + w->nP, w->pairs, (size_t)(2 * np) * sizeof *w->P);
    w->nC += n;
    w->nP += 2 * np;
    return CELL_LEAF;
}

/* Evaluates cell ijk at depth d (par: its parent's context, NULL at the root) and fills
 * me for its children.  Emits the leaf at depth == lat.depth. */
static int cell(worker *w, int d, const int32_t ijk[3], const level *par, level *me)
{
    const job *J = w->J;
    const md_elements *el = J->el;
    const int L = J->lat.depth;
    w->visited++;

    double scale = ldexp(1.0, L - d), s = J->lat.h * scale;
    double rho = s * (0.5 * sqrt(3.0));
    const double tau = J->tau, delta = J->delta;
    double c[3];
    for (int k = 0; k < 3; k++)
        c[k] = J->lat.origin[k] + J->lat.h * (((double)ijk[k] + 0.5) * scale);

    /* Candidates: every element near the top of the tree, then the parent's C. */
    int inherit = par && d >= INHERIT_DEPTH;
    int64_t nc;
    const int64_t *cand;
    if (inherit) {
        nc = par->n;
        cand = par->C;
    } else if (J->bvh) {
        /* A superset of the ball below (the BVH's distances are not ours to the bit):
         * u_bvh + 2 rho + delta with margin; the exact filter follows. */
        double ub = md_bvh_nearest(J->bvh, el, c, NULL, NULL);
        double R = ub + 2 * rho + delta + 4 * tau + MD_ROUND_REL * ub;
        nc = md_bvh_within(J->bvh, el, c, R, w->cand, el->nelements);
        cand = w->cand;
    } else {
        nc = el->nelements;
        for (int64_t e = 0; e < nc; e++)
            w->cand[e] = e;
        cand = w->cand;
    }

    if (nc > w->lev_cap[d]) {
        int64_t cap = w->lev_cap[d];
        if (!mfg_grow((void **)&me->C, &cap, nc, sizeof *me->C))
            return CELL_NOMEM;
        cap = w->lev_cap[d];
        if (!mfg_grow((void **)&me->dc, &cap, nc, sizeof *me->dc))
            return CELL_NOMEM;
        cap = w->lev_cap[d];
        if (!mfg_grow((void **)&me->inb, &cap, nc, sizeof *me->inb))
            return CELL_NOMEM;
        w->lev_cap[d] = cap;
    }

    /* 1. Closed distances and u.  A face's exact closed distance costs O(its sides)
     * unless the inherited in-plane bound shows the projection inside (then |s_F|).  Below
     * the top, lower bounds come first (|s_F|, and dc(c_p) - rho: 1-Lipschitz), and only
     * the faces that may pass the filter of step 2 (u <= u(c_p) + rho) get the exact one. */
    double u = INFINITY, R_up = INFINITY;
    if (inherit)
        R_up = par->u + rho + 2 * rho + delta + 2 * tau;
    for (int64_t q = 0; q < nc; q++) {
        int64_t e = cand[q];
        double dc, ib = 0;
        if (e < el->nfaces) {
            double sf = md_dist_car(el, e, c, NULL);
            w->car[q] = sf;
            if (inherit && par->inb[q] - rho > tau) {
                ib = par->inb[q] - rho; /* the projection stays inside the polygon */
                dc = fabs(sf);
            } else if (inherit && fmax(fabs(sf), par->dc[q] - rho - tau) > R_up) {
                ib = -INFINITY; /* not in C (below): never used */
                dc = INFINITY;
            } else {
                ib = face_inplane(J, e, c);
                dc = ib >= 0 ? fabs(sf) : hypot(sf, ib);
            }
        } else {
            dc = md_dist_closed(el, e, c);
            w->car[q] = 0; /* computed below for the kept ones */
        }
        w->dc[q] = dc;
        w->inb[q] = ib;
        if (dc < u)
            u = dc;
    }

    /* 2. C: the closures that meet the ball B(c, u + 2 rho + delta). */
    double R = u + 2 * rho + delta + tau;
    int64_t n = 0;
    for (int64_t q = 0; q < nc; q++)
        if (w->dc[q] <= R) {
            me->C[n] = cand[q];
            me->dc[n] = w->dc[q];
            me->inb[n] = w->inb[q];
            w->dc[n] = w->dc[q];
            w->car[n] = w->car[q]; /* faces only; the rest is filled below */
            n++;
        }
    me->n = n;
    me->u = u;

    /* 3. Admissible elements: those that may be one of a near-medial pair in the cell. */
    int64_t na = 0;
    for (int64_t q = 0; q < n; q++) {
        int64_t e = me->C[q];
        double car, mg, var;
        if (e < el->nfaces) {
            car = w->car[q];
            mg = fmin(car, me->inb[q]); /* exact, or a lower bound > tau where only s_F decides */
            var = s * J->half_l1[e];
        } else {
            car = md_dist_car(el, e, c, NULL);
            mg = md_region_margin(el, e, c, NULL);
            var = rho;
        }
        w->car[q] = car;
        w->mg[q] = mg;
        w->var[q] = var;
        if (J->may_pair[e] && mg >= -rho - tau && car >= u - rho - var - tau &&
            car <= u + rho + delta + var + tau && region_meets_cell(J, e, c, s, w->hk + 2 * q,
                                                                    w->hv + 2 * q))
            w->A[na++] = q;
    }

    /* 4. The pairs whose bisector (or near-medial band) may cross the cell.  Above the
     * leaves only whether there is one matters (the children test their own): the search
     * stops at the first, which keeps large cells at O(|C|) instead of O(|C|^2). */
    int64_t np = 0;
    for (int64_t i = 0; i < na && !(d < L && np); i++) {
        int64_t qa = w->A[i], a = me->C[qa];
        for (int64_t j = i + 1; j < na && !(d < L && np); j++) {
            int64_t qb = w->A[j], b = me->C[qb];
            if (fabs(w->car[qa] - w->car[qb]) > w->var[qa] + w->var[qb] + delta + tau)
                continue;
            if (fabs(w->dc[qa] - w->dc[qb]) > 2 * rho + delta + tau)
                continue;
            if (regions_apart(J, s, w->hk + 2 * qa, w->hv + 2 * qa, w->hk + 2 * qb,
                              w->hv + 2 * qb))
                continue;
            if (md_incident(el, a, b) || (!J->full && md_adjacent(el, a, b)))
                continue;
            if (!mfg_grow((void **)&w->pairs, &w->cap_pairs, 2 * np + 2, sizeof *w->pairs))
                return CELL_NOMEM;
            w->pairs[2 * np] = a;
            w->pairs[2 * np + 1] = b;
            np++;
        }
    }
    /* P empty: C lies in one flag F > E > V (or its pairs cannot be medial here). */
    if (np == 0)
        return CELL_PRUNED;

    /* 5. Inside or outside.  The child's centre is rho from the parent's: when the
     * boundary is farther than that from the parent's centre, they are on the same side. */
    if (par && par->sign != 0 && par->u > rho + tau)
        me->sign = par->sign;
    else if (u > rho + tau)
        me->sign = point_inside(J, c) ? 1 : -1;
    else
        me->sign = 0;
    if (me->sign < 0 && u > rho + tau)
        return CELL_PRUNED; /* the whole cell is outside */

    if (d < L) {
        if (J->coarse && n == 2) { /* np = 1: the pair is (C[0], C[1]) */
            int cp = coarse_plane(J, me, ijk, d, rho);
            if (cp < 0)
                return CELL_PRUNED;
            if (cp > 0) {
                int32_t fine[3];
                for (int k = 0; k < 3; k++)
                    fine[k] = (int32_t)((int64_t)ijk[k] << (L - d));
                return emit_leaf(w, fine, L - d, me, n, np, 2);
            }
        }
        return CELL_SPLIT;
    }

    /* 6. The leaf.  nT = |T_2rho(c)| with restricted distances (md_dist): the margin is
     * exact for edges and vertices, and for faces exact or a positive lower bound of the
     * in-plane part, so mg >= 0 decides the region either way. */
    double Dr = INFINITY;
    for (int64_t q = 0; q < n; q++) {
        w->dc[q] = w->mg[q] >= 0 ? w->car[q] : INFINITY;
        if (w->dc[q] < Dr)
            Dr = w->dc[q];
    }
    int32_t nT = 0;
    if (Dr < INFINITY)
        for (int64_t q = 0; q < n; q++)
            nT += w->dc[q] <= Dr + 2 * rho;

    return emit_leaf(w, ijk, 0, me, n, np, nT);
}

/* Saves a cell's context at depth wd - 1: its children are the work units. */
static int save_parent(job *J, const int32_t ijk[3], const level *me)
{
    if (J->npar == J->cap_par) {
        int64_t nc = J->cap_par ? 2 * J->cap_par : 64;
        level *p = realloc(J->par, (size_t)nc * sizeof *p);
        if (!p)
            return 0;
        J->par = p;
        int32_t(*q)[3] = realloc(J->par_ijk, (size_t)nc * sizeof *q);
        if (!q)
            return 0;
        J->par_ijk = q;
        J->cap_par = nc;
    }
    level *p = &J->par[J->npar];
    *p = *me;
    p->C = malloc((size_t)(me->n + 1) * sizeof *p->C);
    p->dc = malloc((size_t)(me->n + 1) * sizeof *p->dc);
    p->inb = malloc((size_t)(me->n + 1) * sizeof *p->inb);
    if (!p->C || !p->dc || !p->inb) {
        free(p->C);
        free(p->dc);
        free(p->inb);
        return 0;
    }
    memcpy(p->C, me->C, (size_t)me->n * sizeof *p->C);
    memcpy(p->dc, me->dc, (size_t)me->n * sizeof *p->dc);
    memcpy(p->inb, me->inb, (size_t)me->n * sizeof *p->inb);
    memcpy(J->par_ijk[J->npar], ijk, sizeof J->par_ijk[0]);
    J->npar++;
    return 1;
}

/* Depth-first from cell ijk at depth d; at depth stop (>= 0) the surviving cells are saved
 * as parents of work units instead.  0, or -1 on NOMEM. */
static int descend(worker *w, int d, const int32_t ijk[3], const level *par, int stop)
{
    level *me = &w->lev[d];
    int r = cell(w, d, ijk, par, me);
    if (r == CELL_NOMEM)
        return -1;
    if (r != CELL_SPLIT)
        return 0;
    if (d == stop)
        return save_parent(w->J, ijk, me) ? 0 : -1;
    for (int q = 0; q < 8; q++) {
        int32_t ch[3] = {2 * ijk[0] + (q & 1), 2 * ijk[1] + ((q >> 1) & 1), 2 * ijk[2] + (q >> 2)};
        if (descend(w, d + 1, ch, me, stop) < 0)
            return -1;
    }
    return 0;
}

static void *work(void *arg)
{
    worker *w = arg;
    job *J = w->J;
    int is_caller = pthread_equal(pthread_self(), J->caller) != 0;
    for (;;) {
        if (atomic_load(&J->stop))
            break;
        if (!mfg_prog_poll_mt(J->prog, is_caller, (double)atomic_load(&J->next),
                              (double)(8 * J->npar)))
            break;
        long long unit = atomic_fetch_add(&J->next, 1);
        if (unit >= 8 * J->npar)
            break;
        const int32_t *pi = J->par_ijk[unit / 8];
        int q = (int)(unit % 8);
        int32_t ch[3] = {2 * pi[0] + (q & 1), 2 * pi[1] + ((q >> 1) & 1), 2 * pi[2] + (q >> 2)};
        if (descend(w, J->wd, ch, &J->par[unit / 8], -1) < 0) {
            w->nomem = 1;
            atomic_store(&J->stop, 1);
            break;
        }
    }
    return NULL;
}

/* ---- setup, merge ------------------------------------------------------------------- */

static void worker_free(worker *w)
{
    if (w->lev)
        for (int d = 0; d <= w->J->lat.depth; d++) {
            free(w->lev[d].C);
            free(w->lev[d].dc);
            free(w->lev[d].inb);
        }
    free(w->lev);
    free(w->lev_cap);
    free(w->cand);
    free(w->dc);
    free(w->inb);
    free(w->car);
    free(w->mg);
    free(w->var);
    free(w->hk);
    free(w->hv);
    free(w->A);
    free(w->pairs);
    free(w->leaf);
    free(w->C);
    free(w->P);
}

static int worker_init(worker *w, job *J)
{
    memset(w, 0, sizeof *w);
    w->J = J;
    size_t n = (size_t)J->el->nelements + 1, nl = (size_t)J->lat.depth + 1;
    w->lev = calloc(nl, sizeof *w->lev);
    w->lev_cap = calloc(nl, sizeof *w->lev_cap);
    w->cand = malloc(n * sizeof *w->cand);
    w->dc = malloc(n * sizeof *w->dc);
    w->inb = malloc(n * sizeof *w->inb);
    w->car = malloc(n * sizeof *w->car);
    w->mg = malloc(n * sizeof *w->mg);
    w->var = malloc(n * sizeof *w->var);
    w->hk = malloc(2 * n * sizeof *w->hk);
    w->hv = malloc(2 * n * sizeof *w->hv);
    w->A = malloc(n * sizeof *w->A);
    if (!w->lev || !w->lev_cap || !w->cand || !w->dc || !w->inb || !w->car ||
        !w->mg || !w->var || !w->hk || !w->hv || !w->A) {
        worker_free(w);
        return 0;
    }
    return 1;
}

static int cmp_leaf(const void *pa, const void *pb)
{
    const md_leaf *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->ijk[k] != b->ijk[k])
            return a->ijk[k] < b->ijk[k] ? -1 : 1;
    return 0;
}

/* Merges the workers' leaves into out: sorted by (i, j, k), their C and P repacked in that
 * order, so that nothing depends on which thread made which leaf.  0 on NOMEM (out
 * zeroed). */
static int merge(const job *J, const worker *W, int nw, md_leaves *out)
{
    int64_t nl = 0, tC = 0, tP = 0;
    for (int t = 0; t < nw; t++) {
        nl += W[t].nleaf;
        tC += W[t].nC;
        tP += W[t].nP;
    }
    /* ref: the leaves with their pool offsets made global (worker t's pools follow those
     * of the workers before it, in pool). */
    md_leaf *ref = malloc((size_t)(nl + 1) * sizeof *ref);
    int64_t *poolC = malloc((size_t)(tC + 1) * sizeof *poolC);
    int64_t *poolP = malloc((size_t)(tP + 1) * sizeof *poolP);
    out->leaf = malloc((size_t)(nl + 1) * sizeof *out->leaf);
    out->C = malloc((size_t)(tC + 1) * sizeof *out->C);
    out->P = malloc((size_t)(tP + 1) * sizeof *out->P);
    if (!ref || !poolC || !poolP || !out->leaf || !out->C || !out->P) {
        free(ref);
        free(poolC);
        free(poolP);
        md_leaves_free(out);
        return 0;
    }
    int64_t k = 0, bC = 0, bP = 0;
    for (int t = 0; t < nw; t++) {
        for (int64_t i = 0; i < W[t].nleaf; i++) {
            ref[k] = W[t].leaf[i];
            ref[k].C_off += bC;
            ref[k].P_off += bP;
            k++;
        }
        if (W[t].nC)
            memcpy(poolC + bC, W[t].C, (size_t)W[t].nC * sizeof *poolC);
        if (W[t].nP)
            memcpy(poolP + bP, W[t].P, (size_t)W[t].nP * sizeof *poolP);
        bC += W[t].nC;
        bP += W[t].nP;
    }
    qsort(ref, (size_t)nl, sizeof *ref, cmp_leaf); /* (i, j, k) are unique */
    int64_t oc = 0, op = 0;
    for (int64_t i = 0; i < nl; i++) {
        out->leaf[i] = ref[i];
        memcpy(out->C + oc, poolC + ref[i].C_off, (size_t)ref[i].nC * sizeof *out->C);
        memcpy(out->P + op, poolP + ref[i].P_off, (size_t)(2 * ref[i].nP) * sizeof *out->P);
        out->leaf[i].C_off = oc;
        out->leaf[i].P_off = op;
        oc += ref[i].nC;
        op += 2 * ref[i].nP;
    }
    free(ref);
    free(poolC);
    free(poolP);
    out->lat = J->lat;
    out->nleaves = nl;
    for (int t = 0; t < nw; t++)
        out->cells_visited += W[t].visited;
    return 1;
}

/* Appends (or counts, hs NULL) the half-spaces of element e's Voronoi region (design 1.7):
 * a face's s_F >= 0 and the side lines of its polygon that have the whole polygon on their
 * inner side (all of them for a convex face; faces of > 256 sides keep s_F only); an
 * edge's slab 0 <= t <= len and normal wedge; a vertex's cone.  Each relaxed by the largest
 * violation within tau (near-coplanar faces). */
static int64_t region_halfspaces(const job *J, int64_t e, double *hs)
{
    const md_elements *el = J->el;
    int64_t n = 0;
#define PUT(gx, gy, gz, kk)                                                                   \
    do {                                                                                    \
        if (hs) {                                                                           \
            hs[4 * n] = (gx), hs[4 * n + 1] = (gy), hs[4 * n + 2] = (gz), hs[4 * n + 3] = (kk); \
        }                                                                                   \
        n++;                                                                                \
    } while (0)
    int kind = md_kind(el, e);
    if (kind == MD_FACE) {
        const double *pl = el->face_plane + 4 * e;
        PUT(-pl[0], -pl[1], -pl[2], -pl[3]);
        int64_t q0 = el->face_side_offsets[e], q1 = el->face_side_offsets[e + 1];
        if (q1 - q0 > 256)
            return n;
        for (int64_t q = q0; q < q1; q++) {
            int64_t sd = el->face_sides[q], t = sd / 3, k = sd % 3;
            const double *a = el->xyz + 3 * el->tris[3 * t + k];
            const double *b = el->xyz + 3 * el->tris[3 * t + (k + 1) % 3];
            /* The inward in-plane normal: n x (b - a), the polygon on the left. */
            double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, wv[3];
            wv[0] = pl[1] * ab[2] - pl[2] * ab[1];
            wv[1] = pl[2] * ab[0] - pl[0] * ab[2];
            wv[2] = pl[0] * ab[1] - pl[1] * ab[0];
            double len = sqrt(wv[0] * wv[0] + wv[1] * wv[1] + wv[2] * wv[2]);
            if (!(len > 0))
                continue;
            for (int i = 0; i < 3; i++)
                wv[i] /= len;
            double kk = wv[0] * a[0] + wv[1] * a[1] + wv[2] * a[2], worst = 0;
            for (int64_t r = q0; r < q1; r++) {
                int64_t sr = el->face_sides[r];
                const double *v = el->xyz + 3 * el->tris[3 * (sr / 3) + sr % 3];
                worst = fmin(worst, wv[0] * v[0] + wv[1] * v[1] + wv[2] * v[2] - kk);
            }
            if (worst >= -J->tau)
                PUT(wv[0], wv[1], wv[2], kk + worst - J->tau);
        }
    } else if (kind == MD_EDGE) {
        int64_t i = e - el->nfaces;
        const double *A = el->edge_seg + 6 * i, *u = el->edge_dir + 3 * i;
        const double *wi = el->edge_w + 6 * i, *wj = wi + 3;
        double uA = u[0] * A[0] + u[1] * A[1] + u[2] * A[2];
        PUT(u[0], u[1], u[2], uA);
        PUT(-u[0], -u[1], -u[2], -uA - el->edge_len[i]);
        PUT(-wi[0], -wi[1], -wi[2], -(wi[0] * A[0] + wi[1] * A[1] + wi[2] * A[2]));
        PUT(-wj[0], -wj[1], -wj[2], -(wj[0] * A[0] + wj[1] * A[1] + wj[2] * A[2]));
    } else {
        int64_t j = e - el->nfaces - el->nedges;
        const double *V = el->vert_xyz + 3 * j;
        for (int64_t q = el->vert_edge_offsets[j]; q < el->vert_edge_offsets[j + 1]; q++) {
            int64_t ed = el->vert_edges[q], i = ed - el->nfaces;
            double sg = el->edge_ends[2 * i] == e ? -1.0 : 1.0; /* -(direction away from V) */
            const double *u = el->edge_dir + 3 * i;
            PUT(sg * u[0], sg * u[1], sg * u[2], sg * (u[0] * V[0] + u[1] * V[1] + u[2] * V[2]));
        }
    }
#undef PUT
    return n;
}

static int build_halfspaces(job *J)
{
    const md_elements *el = J->el;
    J->hs_off = malloc(((size_t)el->nelements + 1) * sizeof *J->hs_off);
    if (!J->hs_off)
        return 0;
    J->hs_off[0] = 0;
    for (int64_t e = 0; e < el->nelements; e++)
        J->hs_off[e + 1] = J->hs_off[e] + region_halfspaces(J, e, NULL);
    J->hs = malloc(((size_t)J->hs_off[el->nelements] + 1) * 4 * sizeof *J->hs);
    if (!J->hs)
        return 0;
    for (int64_t e = 0; e < el->nelements; e++)
        region_halfspaces(J, e, J->hs + 4 * J->hs_off[e]);
    return 1;
}

/* The lattice of design 3: root side S = 1.02 x the largest extent, h = S / 2^depth the
 * largest <= tolerance with depth >= 1, origin off the round coordinates. */
static int make_lattice(const md_elements *el, double tolerance, md_lattice *lat)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t t = 0; t < 3 * el->nt; t++) {
        const double *p = el->xyz + 3 * el->tris[t];
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], p[k]);
            hi[k] = fmax(hi[k], p[k]);
        }
    }
    double ext = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    if (!(ext > 0) || !(tolerance > 0))
        return 0;
    double S = 1.02 * ext, h = S;
    int depth = 0;
    /* depth >= 1: with h = S the origin's offset would exceed the 2 % margin. */
    while (h > tolerance || depth < 1) {
        h *= 0.5;
        depth++;
        if (depth > MAX_DEPTH)
            return 0;
    }
    /* [choice, design 3] the offsets keep axis-aligned mid-planes and centres off the
     * lattice; with depth >= 1 they are < 0.0156 S, inside the 0.02 x extent margin. */
    static const double off[3] = {0.0137, 0.0213, 0.0311};
    for (int k = 0; k < 3; k++)
        lat->origin[k] = lo[k] - off[k] * h;
    lat->h = h;
    lat->depth = depth;
    return 1;
}

void md_leaves_free(md_leaves *leaves)
{
    if (!leaves)
        return;
    free(leaves->leaf);
    free(leaves->C);
    free(leaves->P);
    memset(leaves, 0, sizeof *leaves);
}

mfg_status md_octree_build(const md_elements *el, const md_bvh *bvh, double tolerance,
                           int full, int nthreads, md_leaves *out)
{
    return md_octree_build_p(el, bvh, tolerance, full, 0, nthreads, out, NULL);
}

mfg_status md_octree_build_p(const md_elements *el, const md_bvh *bvh, double tolerance,
                             int full, int coarse, int nthreads, md_leaves *out,
                             mfg_prog *prog)
{
    memset(out, 0, sizeof *out);
    job J;
    memset(&J, 0, sizeof J);
    J.prog = prog;
    J.caller = pthread_self();
    int cancelled = 0;
    J.el = el;
    J.bvh = bvh;
    J.full = full != 0;
    J.coarse = coarse != 0;
    if (!make_lattice(el, tolerance, &J.lat))
        return mfg_fail(MFG_ERR_INVALID, "medial octree: tolerance %g gives no lattice of <= %d "
                        "levels", tolerance, MAX_DEPTH);
    J.delta = J.lat.h / 64; /* see the header comment: soundness needs > 0 only for rounding */
    J.tau = MD_ROUND_REL * el->diag + 4 * el->eta;
    J.shift = 4 * el->diag;
    atomic_init(&J.next, 0);
    atomic_init(&J.stop, 0);
    if (nthreads < 1)
        nthreads = 1;
    if (nthreads > MAX_THREADS)
        nthreads = MAX_THREADS;
    /* Work units: the cells at the smallest depth wd with 8^wd >= 16 threads. */
    J.wd = 1;
    while ((1LL << (3 * J.wd)) < 16LL * nthreads)
        J.wd++;
    if (J.wd > J.lat.depth)
        J.wd = J.lat.depth;

    mfg_status st = MFG_ERR_NOMEM;
    worker *W = calloc((size_t)nthreads, sizeof *W);
    pthread_t *tid = calloc((size_t)nthreads, sizeof *tid);
    J.may_pair = malloc((size_t)el->nelements + 1);
    J.half_l1 = malloc(((size_t)el->nfaces + 1) * sizeof *J.half_l1);
    int nw = 0, nthr = nthreads, started = 1;
    if (!W || !tid || !J.may_pair || !J.half_l1)
        goto done;

    for (int64_t f = 0; f < el->nfaces; f++) {
        const double *n = el->face_plane + 4 * f;
        J.half_l1[f] = 0.5 * (fabs(n[0]) + fabs(n[1]) + fabs(n[2]));
    }
    /* Convex edges, and vertices all of whose edges are convex, have their Voronoi regions
     * outside the solid: they never enter a pair (design 3, step 3). */
    for (int64_t e = 0; e < el->nelements; e++) {
        int k = md_kind(el, e), ok = 1;
        if (k == MD_EDGE) {
            ok = !el->edge_convex[e - el->nfaces];
        } else if (k == MD_VERTEX) {
            int64_t j = e - el->nfaces - el->nedges;
            ok = 0;
            if (!el->vert_region_empty[j])
                for (int64_t q = el->vert_edge_offsets[j]; q < el->vert_edge_offsets[j + 1]; q++)
                    ok |= !el->edge_convex[el->vert_edges[q] - el->nfaces];
        }
        J.may_pair[e] = (int8_t)ok;
    }

    if (!build_halfspaces(&J))
        goto done;
    for (nw = 0; nw < nthreads; nw++)
        if (!worker_init(&W[nw], &J))
            goto done;

    /* The top of the tree, sequentially. */
    static const int32_t root[3] = {0, 0, 0};
    if (descend(&W[0], 0, root, NULL, J.wd - 1) < 0)
        goto done;

    /* The units, in parallel (the caller's thread is worker 0). */
    if (nthr > 8 * J.npar)
        nthr = J.npar > 0 ? (int)(8 * J.npar) : 1;
    for (; started < nthr; started++)
        if (pthread_create(&tid[started], NULL, work, &W[started]) != 0)
            break; /* fewer threads: the same result */
    work(&W[0]);
    for (int t = 1; t < started; t++)
        pthread_join(tid[t], NULL);
    for (int t = 0; t < nw; t++)
        if (W[t].nomem)
            goto done;
    if (prog && mfg_prog_stopped(prog)) {
        cancelled = 1;
        goto done;
    }

    if (!merge(&J, W, nw, out))
        goto done;
    st = MFG_OK;

done:
    for (int t = 0; t < nw; t++)
        worker_free(&W[t]);
    for (int64_t i = 0; i < J.npar; i++) {
        free(J.par[i].C);
        free(J.par[i].dc);
        free(J.par[i].inb);
    }
    free(J.par);
    free(J.par_ijk);
    free(W);
    free(tid);
    free(J.may_pair);
    free(J.half_l1);
    free(J.hs_off);
    free(J.hs);
    if (cancelled)
        return mfg_prog_fail(prog);
    if (st != MFG_OK)
        return mfg_fail(MFG_ERR_NOMEM, "medial octree: out of memory");
    return MFG_OK;
}
