/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* junctions.c - the paper's intersection points and curves (Lee & Lee, the medial surface
 * of a polyhedron, section 3.2; docs/design/medial.md section 4.3): inside one octree leaf,
 * the points equidistant from a set T of >= 4 elements.  The paper's search by
 * subdivision with bisector sign tests finds where they may be; Gauss-Newton with the
 * singular values of the Jacobian places them and tells an isolated point (rank 3: a
 * junction) from a curve of such points (rank 2: a degenerate seam, the axis of a square
 * prism).
 *
 * Equations.  The elements of a set fall into contact clusters, the components of their
 * incidence graph (a face with its edges and vertices touching at one foot counts once).
 * Between clusters: d_a^car = d_b^car for one representative of each.  Within a cluster,
 * the distance difference of an incident pair (F, E in the closure of F) is tangential
 * (it never changes sign and its gradient vanishes where it is 0), so the pair gives its
 * region boundary instead: the feet of x on both carriers coincide, foot_a(x) = foot_b(x),
 * an affine equation (one independent row for F-E and E-V, two for F-V). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

/* Elements within this fraction of L of D touch (design 4.3). */
#define TOUCH_REL 1e-9
/* Rank: sigma_i / sigma_1 above this counts (design 4.3). */
#define RANK_REL 1e-6
#define POLISH_ITERS 60
/* The Jacobi eigen-sweeps stop when the squared off-diagonal is below this times the
 * squared diagonal (off-diagonal entries ~1e-18 of the diagonal: below rounding). */
#define JACOBI_OFF 1e-36
/* Gauss-Newton stops at a step below this times the scale (a few ulps of it). */
#define GN_STEP_MIN 1e-15
/* Subsets of T tried per search (the full set first, then ever smaller ones). */
#define MAX_SUBSETS 512
/* Boxes kept per subdivision level: a leaf side <= tolerance needs 3 levels to reach
 * tolerance / 8, so at most 8^3 boxes even when a whole surface of T survives. */
#define MAX_BOXES 4096

/* The foot of x on e's carrier and the Jacobian of that affine map (row-major 3x3). */
static void carrier_foot(const md_elements *el, int64_t e, const double x[3], double foot[3],
                         double P[9])
{
    int kind = md_kind(el, e);
    if (kind == MD_FACE) {
        const double *pl = el->face_plane + 4 * e;
        double s = pl[3] - mfg_dot3(pl, x);
        for (int i = 0; i < 3; i++) {
            foot[i] = x[i] + s * pl[i];
            for (int j = 0; j < 3; j++)
                P[3 * i + j] = (i == j) - pl[i] * pl[j];
        }
    } else if (kind == MD_EDGE) {
        int64_t k = e - el->nfaces;
        const double *A = el->edge_seg + 6 * k, *u = el->edge_dir + 3 * k;
        double d[3] = {x[0] - A[0], x[1] - A[1], x[2] - A[2]};
        double t = mfg_dot3(d, u);
        for (int i = 0; i < 3; i++) {
            foot[i] = A[i] + t * u[i];
            for (int j = 0; j < 3; j++)
                P[3 * i + j] = u[i] * u[j];
        }
    } else {
        memcpy(foot, el->vert_xyz + 3 * (e - el->nfaces - el->nedges), 3 * sizeof(double));
        memset(P, 0, 9 * sizeof(double));
    }
}

/* Contact clusters of the set S (ascending): comp[i] = the smallest index of i's
 * component; returns their number. */
static int clusters(const md_elements *el, const int64_t *S, int n, int *comp)
{
    for (int i = 0; i < n; i++)
        comp[i] = i;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            if (md_incident(el, S[i], S[j])) {
                int a = comp[i], b = comp[j];
                while (comp[a] != a)
                    a = comp[a];
                while (comp[b] != b)
                    b = comp[b];
                if (a < b)
                    comp[b] = a;
                else if (b < a)
                    comp[a] = b;
            }
    int nc = 0;
    for (int i = 0; i < n; i++) {
        int a = i;
        while (comp[a] != a)
            a = comp[a];
        comp[i] = a;
        nc += a == i;
    }
    return nc;
}

/* The equations of a set S, prepared once (the incidence tests are not repeated at every
 * point): rep[c], the representative of contact cluster c, is the element of highest
 * dimension (smallest id among equals): any member has the same distance where the
 * cluster's feet coincide; pi/pj the incident pairs (S[pi] of higher dimension). */
typedef struct leafcache leafcache;
typedef struct eqsys {
    const int64_t *S;
    int nrep, npair;
    /* in the search: S[i] is element ti[i] of the leaf's set, whose values at the
     * subdivision's first centres lc keeps (NULL: no cache) */
    const int *ti;
    leafcache *lc;
    int rep[MD_JMAX];
    int pi[MD_JMAX * MD_JMAX / 2], pj[MD_JMAX * MD_JMAX / 2];
} eqsys;

static void prepare(const md_elements *el, const int64_t *S, int n, const int *comp, eqsys *sy)
{
    sy->S = S;
    sy->nrep = sy->npair = 0;
    sy->ti = NULL;
    sy->lc = NULL;
    for (int i = 0; i < n; i++) {
        if (comp[i] != i)
            continue;
        int best = i;
        for (int j = i + 1; j < n; j++)
            if (comp[j] == i && md_kind(el, S[j]) > md_kind(el, S[best]))
                best = j;
        sy->rep[sy->nrep++] = best;
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            if (i != j && md_kind(el, S[i]) > md_kind(el, S[j]) && md_incident(el, S[i], S[j]) &&
                sy->npair < MD_JMAX * MD_JMAX / 2) {
                sy->pi[sy->npair] = i;
                sy->pj[sy->npair++] = j;
            }
}

/* The equations at x, accumulated as J^T J and J^T r (the rows themselves are not
 * needed), and the largest |residual| (for a foot row: the feet's distance).  Every
 * residual is 2-Lipschitz: a difference of two 1-Lipschitz distances, or of two
 * projections. */
typedef struct eqs {
    double JtJ[9], Jtr[3];
    double rmax;
} eqs;

static void add_row(eqs *q, const double row[3], double r)
{
    for (int a = 0; a < 3; a++) {
        q->Jtr[a] += row[a] * r;
        for (int b = 0; b < 3; b++)
            q->JtJ[3 * a + b] += row[a] * row[b];
    }
}

/* The box centres of the subdivision's levels 0 .. CACHE_LEVEL (1 + 8 + 64): every subset
 * of a leaf's set tests the same centres, and on a faceted wall hundreds of subsets are
 * tried, so each element's carrier distance and foot there are computed once per leaf
 * (the same calls on the same point: the same bits). */
#define CACHE_LEVEL 2
#define CACHE_SLOTS 73
struct leafcache {
    double d[CACHE_SLOTS][MD_JMAX], g[CACHE_SLOTS][MD_JMAX][3], f[CACHE_SLOTS][MD_JMAX][3];
    unsigned char have[CACHE_SLOTS][MD_JMAX]; /* bit 1: d and g, bit 2: f */
};

/* The slot of the box ijk of level lev, or -1 beyond CACHE_LEVEL. */
static int cache_slot(int lev, const int32_t ijk[3])
{
    if (lev > CACHE_LEVEL)
        return -1;
    int first = lev == 0 ? 0 : lev == 1 ? 1 : 9, w = 1 << lev;
    return first + (ijk[0] * w + ijk[1]) * w + ijk[2];
}

/* The carrier distance of S[i] at x and its gradient (x the centre of slot when slot >= 0;
 * g may be NULL). */
static double dist_grad_at(const md_elements *el, const eqsys *sy, int i, const double x[3],
                           int slot, double g[3])
{
    if (slot < 0 || !sy->lc)
        return md_dist_car(el, sy->S[i], x, g);
    int t = sy->ti[i];
    if (!(sy->lc->have[slot][t] & 1)) {
        sy->lc->d[slot][t] = md_dist_car(el, sy->S[i], x, sy->lc->g[slot][t]);
        sy->lc->have[slot][t] |= 1;
    }
    if (g)
        memcpy(g, sy->lc->g[slot][t], 3 * sizeof(double));
    return sy->lc->d[slot][t];
}

static double dist_at(const md_elements *el, const eqsys *sy, int i, const double x[3], int slot)
{
    return dist_grad_at(el, sy, i, x, slot, NULL);
}

/* The foot of x on S[i]'s carrier (x the centre of slot when slot >= 0). */
static void foot_at(const md_elements *el, const eqsys *sy, int i, const double x[3], int slot,
                    double foot[3])
{
    double P[9];
    if (slot < 0 || !sy->lc) {
        carrier_foot(el, sy->S[i], x, foot, P);
        return;
    }
    int t = sy->ti[i];
    if (!(sy->lc->have[slot][t] & 2)) {
        carrier_foot(el, sy->S[i], x, sy->lc->f[slot][t], P);
        sy->lc->have[slot][t] |= 2;
    }
    memcpy(foot, sy->lc->f[slot][t], 3 * sizeof(double));
}

/* ... with a finite stop only rmax, and only until it exceeds stop (J^T J, J^T r left
 * 0): the subdivision's test needs no more (wt-N2's fbd49f7, carried over to the
 * prepared equations).  Then x may be the centre of a cached slot (else slot -1). */
static void equations_upto(const md_elements *el, const eqsys *sy, const double x[3], eqs *q,
                           double stop, int slot)
{
    memset(q, 0, sizeof *q);
    if (stop != INFINITY) {
        double d0 = sy->nrep ? dist_at(el, sy, sy->rep[0], x, slot) : 0;
        for (int c = 1; c < sy->nrep; c++) {
            q->rmax = fmax(q->rmax, fabs(d0 - dist_at(el, sy, sy->rep[c], x, slot)));
            if (q->rmax > stop)
                return;
        }
        for (int p = 0; p < sy->npair; p++) {
            double fa[3], fb[3], nr = 0;
            foot_at(el, sy, sy->pi[p], x, slot, fa);
            foot_at(el, sy, sy->pj[p], x, slot, fb);
            for (int k = 0; k < 3; k++)
                nr += (fa[k] - fb[k]) * (fa[k] - fb[k]);
            q->rmax = fmax(q->rmax, sqrt(nr));
            if (q->rmax > stop)
                return;
        }
        return;
    }
    double g0[3], d0 = sy->nrep ? md_dist_car(el, sy->S[sy->rep[0]], x, g0) : 0;
    for (int c = 1; c < sy->nrep; c++) {
        double g[3], d = md_dist_car(el, sy->S[sy->rep[c]], x, g);
        double r = d0 - d, row[3] = {g0[0] - g[0], g0[1] - g[1], g0[2] - g[2]};
        if (stop == INFINITY)
            add_row(q, row, r);
        q->rmax = fmax(q->rmax, fabs(r));
        if (q->rmax > stop)
            return;
    }
    for (int p = 0; p < sy->npair; p++) {
        double fa[3], fb[3], Pa[9], Pb[9], r[3], nr = 0;
        carrier_foot(el, sy->S[sy->pi[p]], x, fa, Pa);
        carrier_foot(el, sy->S[sy->pj[p]], x, fb, Pb);
        for (int k = 0; k < 3; k++) {
            r[k] = fa[k] - fb[k];
            nr += r[k] * r[k];
        }
        for (int k = 0; k < 3 && stop == INFINITY; k++) { /* row k: d(fa_k - fb_k)/dx */
            double row[3] = {Pa[3 * k] - Pb[3 * k], Pa[3 * k + 1] - Pb[3 * k + 1], Pa[3 * k + 2] - Pb[3 * k + 2]};
            add_row(q, row, r[k]);
        }
        q->rmax = fmax(q->rmax, sqrt(nr));
        if (q->rmax > stop)
            return;
    }
}

static void equations(const md_elements *el, const eqsys *sy, const double x[3], eqs *q)
{
    equations_upto(el, sy, x, q, INFINITY, -1);
}

/* Eigen-decomposition of a symmetric 3x3 matrix by cyclic Jacobi rotations: lam
 * descending, V's columns the eigenvectors (V[3 * row + col]).  The singular values of
 * the Jacobian are the square roots of J^T J's eigenvalues. */
static void eig3(const double Ain[9], double lam[3], double V[9])
{
    double A[9];
    memcpy(A, Ain, sizeof A);
    for (int i = 0; i < 9; i++)
        V[i] = (i % 4) == 0;
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = A[1] * A[1] + A[2] * A[2] + A[5] * A[5];
        double tr = A[0] * A[0] + A[4] * A[4] + A[8] * A[8];
        if (off <= JACOBI_OFF * tr || off == 0)
            break;
        for (int p = 0; p < 2; p++)
            for (int r = p + 1; r < 3; r++) {
                double apr = A[3 * p + r];
                if (apr == 0)
                    continue;
                double theta = (A[3 * r + r] - A[3 * p + p]) / (2 * apr);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1));
                double c = 1 / sqrt(t * t + 1), s = t * c;
                for (int k = 0; k < 3; k++) { /* A <- A G (columns p, r) */
                    double akp = A[3 * k + p], akr = A[3 * k + r];
                    A[3 * k + p] = c * akp - s * akr;
                    A[3 * k + r] = s * akp + c * akr;
                }
                for (int k = 0; k < 3; k++) { /* A <- G^T A (rows p, r) */
                    double apk = A[3 * p + k], ark = A[3 * r + k];
                    A[3 * p + k] = c * apk - s * ark;
                    A[3 * r + k] = s * apk + c * ark;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = V[3 * k + p], vkr = V[3 * k + r];
                    V[3 * k + p] = c * vkp - s * vkr;
                    V[3 * k + r] = s * vkp + c * vkr;
                }
            }
    }
    int ord[3] = {0, 1, 2};
    double d[3] = {A[0], A[4], A[8]};
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++)
            if (d[ord[j]] > d[ord[i]]) {
                int t = ord[i];
                ord[i] = ord[j];
                ord[j] = t;
            }
    double W[9];
    for (int c = 0; c < 3; c++) {
        lam[c] = fmax(d[ord[c]], 0.0);
        for (int k = 0; k < 3; k++)
            W[3 * k + c] = V[3 * k + ord[c]];
    }
    memcpy(V, W, sizeof W);
}

static int rank_of(const double lam[3])
{
    if (!(lam[0] > 0))
        return 0;
    int r = 1;
    for (int i = 1; i < 3; i++)
        if (sqrt(lam[i] / lam[0]) > RANK_REL)
            r++;
    return r;
}

/* Does e touch the ball of radius D at x: its carrier distance within tol of D and x in
 * its Voronoi region up to tol (a foot on the region's boundary is decided by rounding;
 * the sub-element there touches as well). */
static int touches(const md_elements *el, int64_t e, const double x[3], double D, double tol)
{
    return fabs(md_dist_car(el, e, x, NULL) - D) <= tol &&
           md_region_margin(el, e, x, NULL) >= -tol;
}

int md_touching_set(const md_elements *el, const md_bvh *bvh, const double x[3], int64_t *out,
                    int cap, double *Dout)
{
    double tol = TOUCH_REL * el->diag;
    int64_t stack_buf[256], *buf = stack_buf, m;
    /* Candidates: every element when there is no BVH (unit tests), else the closures
     * within the BVH's distance (from triangles) plus 2 tol. */
    if (!bvh) {
        m = el->nelements;
        if (m > 256 && !(buf = malloc((size_t)m * sizeof *buf)))
            return -1;
        for (int64_t e = 0; e < m; e++)
            buf[e] = e;
    } else {
        double Db = md_bvh_nearest(bvh, el, x, NULL, NULL);
        m = md_bvh_within(bvh, el, x, Db + 2 * tol, buf, 256);
        if (m > 256) {
            if (!(buf = malloc((size_t)m * sizeof *buf)))
                return -1;
            md_bvh_within(bvh, el, x, Db + 2 * tol, buf, m);
        }
    }
    /* D from the elements, not from the triangles: carrier distances of the elements whose
     * region holds x up to tol (at a region's boundary the rounding may put x outside both
     * neighbours' regions by an ulp).  Triangle order then cannot change a bit. */
    double D = INFINITY;
    for (int64_t i = 0; i < m; i++)
        if (md_region_margin(el, buf[i], x, NULL) >= -tol)
            D = fmin(D, md_dist_car(el, buf[i], x, NULL));
    int n = 0;
    for (int64_t i = 0; i < m && isfinite(D); i++)
        if (touches(el, buf[i], x, D, tol)) {
            if (n < cap)
                out[n] = buf[i];
            n++;
        }
    if (buf != stack_buf)
        free(buf);
    if (Dout)
        *Dout = D;
    return n;
}

/* Gauss-Newton on the equations of S from x0; the step is J^+ r over the singular
 * directions above RANK_REL, so on a curve of solutions (rank 2) it moves to the point
 * of the curve nearest x0 instead of along it. */
static int gauss_newton(const md_elements *el, const eqsys *sy, const double x0[3], double x[3],
                        double *rmax)
{
    memcpy(x, x0, 3 * sizeof(double));
    eqs q;
    double scale = el->diag;
    for (int it = 0; it < POLISH_ITERS; it++) {
        equations(el, sy, x, &q);
        double lam[3], V[9];
        eig3(q.JtJ, lam, V);
        int rk = rank_of(lam);
        double step[3] = {0, 0, 0}, ns = 0;
        for (int c = 0; c < rk; c++) {
            double a = (V[c] * q.Jtr[0] + V[3 + c] * q.Jtr[1] + V[6 + c] * q.Jtr[2]) / lam[c];
            for (int k = 0; k < 3; k++)
                step[k] -= a * V[3 * k + c];
        }
        for (int k = 0; k < 3; k++) {
            x[k] += step[k];
            ns += step[k] * step[k];
        }
        if (!(sqrt(ns) > GN_STEP_MIN * scale))
            break;
    }
    equations(el, sy, x, &q);
    *rmax = q.rmax;
    return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]);
}

/* Polish from x0 for the set S (ascending), then classify at the point reached by the
 * set that touches there. */
int md_junction_polish(const md_jbox *B, const double x0[3], const int64_t *T, int nT,
                       md_junction *out)
{
    const md_elements *el = B->el;
    const md_bvh *bvh = B->bvh;
    const double *lo = B->lo;
    double side = B->side, tolerance = B->tolerance;
    if (nT < 2 || nT > MD_JMAX)
        return 0;
    int comp[MD_JMAX];
    clusters(el, T, nT, comp);
    eqsys sy;
    prepare(el, T, nT, comp, &sy);
    double x[3], rmax, tol = TOUCH_REL * el->diag;
    if (!gauss_newton(el, &sy, x0, x, &rmax) || !(rmax <= tol))
        return 0;
    for (int k = 0; k < 3; k++)
        if (!(x[k] >= lo[k] - tolerance && x[k] <= lo[k] + side + tolerance))
            return 0;
    md_junction j;
    memset(&j, 0, sizeof j);
    double D;
    int n = md_touching_set(el, bvh, x, j.elems, MD_JMAX, &D);
    if (n < 0)
        return -1;
    /* A ball of radius ~0 is a boundary point (a corner), not a junction. */
    if (n > MD_JMAX || n < 4 || !(D > 1e3 * tol))
        return 0;
    /* Every element of T touches, or the point is not a medial point of T (another
     * element is nearer). */
    for (int i = 0; i < nT; i++)
        if (!touches(el, T[i], x, D, tol))
            return 0;
    j.n = n;
    int jc[MD_JMAX];
    int nc = clusters(el, j.elems, n, jc);
    /* Rank from the whole touching set: the prism's axis meets its end face at a point. */
    eqs q;
    prepare(el, j.elems, n, jc, &sy);
    equations(el, &sy, x, &q);
    double lam[3], V[9];
    eig3(q.JtJ, lam, V);
    int rk = rank_of(lam);
    if (rk == 3) {
        j.kind = nc >= 4 ? MFG_MEDIAL_BRANCH : MFG_MEDIAL_SMOOTH;
    } else if (rk == 2 && nc >= 4) {
        /* A curve where >= 4 clusters stay equidistant: a degenerate seam; its tangent is
         * the Jacobian's null direction, signed so that its largest component is > 0. */
        j.kind = MFG_MEDIAL_DEGENERATE;
        int big = 0;
        for (int k = 1; k < 3; k++)
            if (fabs(V[3 * k + 2]) > fabs(V[3 * big + 2]))
                big = k;
        double sg = V[3 * big + 2] < 0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; k++)
            j.dir[k] = sg * V[3 * k + 2];
    } else {
        return 0;
    }
    j.rank = rk;
    memcpy(j.x, x, sizeof x);
    j.r = D;
    *out = j;
    return 1;
}

/* A point of the seam of S (a curve where the elements of S stay equidistant, >= 3 of
 * them in >= 2 contact clusters): Gauss-Newton from x0 moves to the point of the curve
 * nearest x0 (gauss_newton steps only across the curve at rank 2), and the tangent there
 * is the Jacobian's null direction.  Seam tracing in the assembly steps along it. */
int md_seam_point(const md_elements *el, const int64_t *S, int nS, const double x0[3],
                  double x[3], double dir[3])
{
    if (nS < 3 || nS > MD_JMAX)
        return 0;
    int comp[MD_JMAX];
    if (clusters(el, S, nS, comp) < 2)
        return 0;
    eqsys sy;
    prepare(el, S, nS, comp, &sy);
    double rmax;
    if (!gauss_newton(el, &sy, x0, x, &rmax) || !(rmax <= TOUCH_REL * el->diag))
        return 0;
    eqs q;
    equations(el, &sy, x, &q);
    double lam[3], V[9];
    eig3(q.JtJ, lam, V);
    if (rank_of(lam) != 2)
        return 0;
    for (int k = 0; k < 3; k++)
        dir[k] = V[3 * k + 2];
    return 1;
}

/* ---- the search ------------------------------------------------------------------------ */

typedef struct box {
    int32_t ijk[3]; /* at the current level: lo + side_level * ijk */
} box;

/* How far a carrier distance may depart from its linearisation at the centre of a cube of
 * half-diagonal rho: a face's is affine (0); a line's or point's is convex with Hessian
 * norm 1/d' at distance d', >= d - rho inside the cube, so the Taylor remainder is at
 * most rho^2 / (2 (d - rho)) (infinite when the carrier may pass through the cube). */
static double lin_slack(const md_elements *el, int64_t e, double d, double rho)
{
    if (md_kind(el, e) == MD_FACE)
        return 0.0;
    return d > 2 * rho ? rho * rho / (2 * (d - rho)) : INFINITY;
}

/* Can d_p - d_q be 0 somewhere in the cube of centre c, side s (half-diagonal rho), given
 * both carrier distances and gradients at c?  The row is its linearisation at c within the
 * two remainders (lin_slack), so |r(x) - r(c)| <= (s/2) |g_p - g_q|_1 + Q_p + Q_q, and
 * never more than 2 rho (a difference of two 1-Lipschitz distances).  On a faceted wall
 * the gradients of near-parallel facets differ by the facet angle, so this rules out boxes
 * ~1/angle times larger than the Lipschitz bound alone.  slack (4e-9 L) covers rounding;
 * Gauss-Newton accepts residuals of 1e-9 L. */
static int distances_may_meet(const md_elements *el, int64_t p, double dp, const double gp[3],
                              int64_t q, double dq, const double gq[3], double s, double rho)
{
    double var = 0.5 * s * (fabs(gp[0] - gq[0]) + fabs(gp[1] - gq[1]) + fabs(gp[2] - gq[2])) +
                 lin_slack(el, p, dp, rho) + lin_slack(el, q, dq, rho);
    return fabs(dp - dq) <= fmin(var * (1 + MD_ROUND_REL), 2 * rho) + 4 * TOUCH_REL * el->diag;
}

/* Can the feet of an incident pair coincide in the cube?  Their difference is affine with
 * matrix P_a - P_b, whose norm is 1 for F-E, E-V and F-V: it varies by <= rho. */
static int feet_may_meet(const md_elements *el, const double fa[3], const double fb[3], double rho)
{
    double nr = (fa[0] - fb[0]) * (fa[0] - fb[0]) + (fa[1] - fb[1]) * (fa[1] - fb[1]) +
                (fa[2] - fb[2]) * (fa[2] - fb[2]);
    return sqrt(nr) <= rho * (1 + MD_ROUND_REL) + 4 * TOUCH_REL * el->diag;
}

/* Can every equation of S be 0 somewhere in the cube of centre c, side s?  The paper's
 * sign test, without corner samples: each row's variation over the cube bounded as above
 * (the 5 000-triangle cup: 3.5x fewer boxes than by the 2-Lipschitz bound). */
static int may_hold(const md_elements *el, const eqsys *sy, const double c[3], double s,
                    double rho, int slot)
{
    if (sy->nrep) {
        int64_t e0 = sy->S[sy->rep[0]];
        double g0[3], d0 = dist_grad_at(el, sy, sy->rep[0], c, slot, g0);
        for (int k = 1; k < sy->nrep; k++) {
            double g[3], d = dist_grad_at(el, sy, sy->rep[k], c, slot, g);
            if (!distances_may_meet(el, e0, d0, g0, sy->S[sy->rep[k]], d, g, s, rho))
                return 0;
        }
    }
    for (int p = 0; p < sy->npair; p++) {
        double fa[3], fb[3];
        foot_at(el, sy, sy->pi[p], c, slot, fa);
        foot_at(el, sy, sy->pj[p], c, slot, fb);
        if (!feet_may_meet(el, fa, fb, rho))
            return 0;
    }
    return 1;
}

static int box_cmp(const void *pa, const void *pb)
{
    const box *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->ijk[k] != b->ijk[k])
            return a->ijk[k] < b->ijk[k] ? -1 : 1;
    return 0;
}

/* Subdivision for one subset S; polished points appended to out (deduplicated).  Returns
 * the new count, or -1 on NOMEM. */
/* The leaf's elements at its centre: carrier distance, gradient and foot, and which pairs
 * are incident (the subset walk's pair test). */
typedef struct leafsets {
    double d[MD_JMAX], g[MD_JMAX][3], ft[MD_JMAX][3];
    unsigned char inc[MD_JMAX][MD_JMAX];
} leafsets;

/* The subdivision's box lists, allocated once per search. */
typedef struct boxbuf {
    box *cur, *nxt;
    int *grp;
    eqsys sy;
    leafcache *lc;
    leafsets ls;
} boxbuf;

/* One junction search's box, tolerance, scratch and output (md_junction_search). */
typedef struct search_box {
    md_jbox box;
    md_junction *out; /* room for cap results */
    int cap;
    boxbuf *bb;
} search_box;

static int search_subset(const search_box *q, const int64_t *S, const int *ti, int n, int nout)
{
    const md_elements *el = q->box.el;
    const double *lo = q->box.lo;
    double side = q->box.side, tolerance = q->box.tolerance;
    md_junction *out = q->out;
    int cap = q->cap;
    boxbuf *bb = q->bb;
    int comp[MD_JMAX];
    int nc = clusters(el, S, n, comp);
    eqsys *sy = &bb->sy;
    prepare(el, S, n, comp, sy);
    sy->ti = ti;
    sy->lc = bb->lc;
    /* One cluster is one foot; two clusters without an incident pair meet on a sheet.
     * Two clusters with incident pairs can still fix a point: the tray's inner corner
     * (1.5, 3, 3), where the outer wall faces the inner wall, its two reflex edges and
     * their reflex vertex (four smooth seams end there). */
    if (nc < 2 || (nc == 2 && sy->npair == 0))
        return nout;
    box *cur = bb->cur, *nxt = bb->nxt;
    int *grp = bb->grp;
    int ncur = 0, lev = 0;
    double s = side;
    {
        double c[3] = {lo[0] + 0.5 * s, lo[1] + 0.5 * s, lo[2] + 0.5 * s};
        if (may_hold(el, sy, c, s, 0.5 * sqrt(3.0) * s, 0))
            cur[ncur++] = (box){{0, 0, 0}};
    }
    while (ncur > 0 && s > tolerance / 8) {
        double cs = 0.5 * s, rho = 0.5 * sqrt(3.0) * cs;
        int nn = 0, overflow = 0;
        for (int b = 0; b < ncur && !overflow; b++)
            for (int o = 0; o < 8; o++) {
                box ch = {{2 * cur[b].ijk[0] + (o & 1), 2 * cur[b].ijk[1] + ((o >> 1) & 1),
                           2 * cur[b].ijk[2] + ((o >> 2) & 1)}};
                double c[3];
                for (int k = 0; k < 3; k++)
                    c[k] = lo[k] + cs * ((double)ch.ijk[k] + 0.5);
                if (!may_hold(el, sy, c, cs, rho, cache_slot(lev + 1, ch.ijk)))
                    continue;
                if (nn == MAX_BOXES) {
                    overflow = 1;
                    break;
                }
                nxt[nn++] = ch;
            }
        if (overflow)
            break; /* a surface of solutions: polish from the boxes we have */
        box *t = cur;
        cur = nxt;
        nxt = t;
        ncur = nn;
        s = cs;
        lev++;
    }
    /* Disjoint groups of surviving boxes (sharing no point) are separate searches. */
    qsort(cur, (size_t)ncur, sizeof *cur, box_cmp);
    for (int b = 0; b < ncur; b++)
        grp[b] = b;
    for (int a = 0; a < ncur; a++)
        for (int b = a + 1; b < ncur; b++) {
            if (abs(cur[a].ijk[0] - cur[b].ijk[0]) > 1)
                break; /* sorted by i: no later box touches a */
            if (abs(cur[a].ijk[1] - cur[b].ijk[1]) <= 1 && abs(cur[a].ijk[2] - cur[b].ijk[2]) <= 1) {
                int ra = a, rb = b;
                while (grp[ra] != ra)
                    ra = grp[ra];
                while (grp[rb] != rb)
                    rb = grp[rb];
                if (ra < rb)
                    grp[rb] = ra;
                else if (rb < ra)
                    grp[ra] = rb;
            }
        }
    for (int b = 0; b < ncur; b++) {
        int r = b;
        while (grp[r] != r)
            r = grp[r];
        grp[b] = r;
    }
    for (int g = 0; g < ncur; g++) {
        if (grp[g] != g)
            continue;
        /* Start from the group's box whose centre has the smallest residual. */
        double best = INFINITY, x0[3] = {0, 0, 0};
        for (int b = g; b < ncur; b++) {
            if (grp[b] != g)
                continue;
            double c[3];
            eqs q;
            for (int k = 0; k < 3; k++)
                c[k] = lo[k] + s * ((double)cur[b].ijk[k] + 0.5);
            /* stops once it cannot win */
            equations_upto(el, sy, c, &q, best, cache_slot(lev, cur[b].ijk));
            if (q.rmax < best) {
                best = q.rmax;
                memcpy(x0, c, sizeof c);
            }
        }
        md_junction j;
        int ok = md_junction_polish(&q->box, x0, S, n, &j);
        if (ok < 0) {
            nout = -1;
            break;
        }
        if (!ok)
            continue;
        int dup = 0;
        for (int i = 0; i < nout && !dup; i++) {
            double d2 = 0;
            for (int k = 0; k < 3; k++)
                d2 += (out[i].x[k] - j.x[k]) * (out[i].x[k] - j.x[k]);
            dup = out[i].n == j.n && !memcmp(out[i].elems, j.elems, (size_t)j.n * sizeof j.elems[0]) &&
                  sqrt(d2) <= tolerance / 8;
        }
        if (!dup && nout < cap)
            out[nout++] = j;
    }
    return nout;
}


int md_junction_search(const md_jbox *B, const int64_t *T, int nT, md_junction *out, int cap)
{
    const md_elements *el = B->el;
    const double *lo = B->lo;
    double side = B->side;
    if (nT < 4 || cap <= 0)
        return 0;
    /* Elements whose Voronoi region stays away from the box touch nowhere in it: the
     * region margin is 1-Lipschitz (a minimum of unit-gradient constraints, or a signed
     * distance to the face's polygon), so margin(c) < -rho rules them out.  Convex edges
     * and vertices (regions outside the solid) go here; near a 48-gon disc's rim they
     * would otherwise multiply the subsets tried below beyond MAX_SUBSETS. */
    int64_t Tk[MD_JMAX];
    int nk = 0;
    {
        double c[3] = {lo[0] + 0.5 * side, lo[1] + 0.5 * side, lo[2] + 0.5 * side};
        double rho = 0.5 * sqrt(3.0) * side + 2 * TOUCH_REL * el->diag;
        for (int i = 0; i < nT && nk < MD_JMAX; i++)
            if (md_region_margin(el, T[i], c, NULL) >= -rho)
                Tk[nk++] = T[i];
    }
    T = Tk;
    nT = nk;
    if (nT < 4)
        return 0;
    /* T may hold elements that touch nowhere in the box (it is the set near the leaf's
     * centre): when the whole set has no equidistant point here, try the sets with one
     * element fewer, and so on down to 4 (the paper drops the farthest element; at a
     * reflex edge several are equally far, so every subset of the size is tried).  Only
     * sets whose every pair may meet in the box: two elements touching one ball have
     * equal distances (not incident) or one foot (incident), and a pair that cannot
     * (distances_may_meet, feet_may_meet over the leaf) never does. */
    boxbuf bb;
    bb.cur = malloc(MAX_BOXES * sizeof(box));
    bb.nxt = malloc(MAX_BOXES * sizeof(box));
    bb.grp = malloc(MAX_BOXES * sizeof(int));
    bb.lc = malloc(sizeof *bb.lc);
    if (!bb.cur || !bb.nxt || !bb.grp || !bb.lc) {
        free(bb.cur);
        free(bb.nxt);
        free(bb.grp);
        free(bb.lc);
        return mfg_fail(MFG_ERR_NOMEM, "md_junction_search: out of memory"), -1;
    }
    memset(bb.lc->have, 0, sizeof bb.lc->have);
    search_box sbox = {*B, out, cap, &bb};
    unsigned char compat[MD_JMAX][MD_JMAX];
    leafsets *ls = &bb.ls;
    {
        double c[3] = {lo[0] + 0.5 * side, lo[1] + 0.5 * side, lo[2] + 0.5 * side};
        double rho = 0.5 * sqrt(3.0) * side;
        for (int i = 0; i < nT; i++) { /* c is the centre of slot 0 */
            ls->d[i] = bb.lc->d[0][i] = md_dist_car(el, T[i], c, bb.lc->g[0][i]);
            memcpy(ls->g[i], bb.lc->g[0][i], sizeof ls->g[i]);
            double P[9];
            carrier_foot(el, T[i], c, ls->ft[i], P);
            memcpy(bb.lc->f[0][i], ls->ft[i], sizeof ls->ft[i]);
            bb.lc->have[0][i] = 3;
        }
        /* The subdivision's first test, for every pair at once: a subset with a pair that
         * cannot meet in the leaf has no box left after level 0, so it is not enumerated
         * (whole branches of the subset walk die here). */
        for (int i = 0; i < nT; i++)
            for (int j = 0; j < nT; j++) {
                ls->inc[i][j] = i != j && md_incident(el, T[i], T[j]);
                compat[i][j] = ls->inc[i][j]
                                   ? feet_may_meet(el, ls->ft[i], ls->ft[j], rho)
                                   : distances_may_meet(el, T[i], ls->d[i], ls->g[i], T[j],
                                                        ls->d[j], ls->g[j], side, rho);
            }
    }
    int nout = 0, tried = 0;
    for (int k = nT; k >= 4 && nout == 0 && tried < MAX_SUBSETS; k--) {
        /* the k-subsets of mutually compatible elements, in lexicographic order: a
         * depth-first walk over idx[0 .. depth) */
        int idx[MD_JMAX], depth = 0;
        idx[0] = 0;
        while (depth >= 0 && nout >= 0 && tried < MAX_SUBSETS) {
            int i = idx[depth];
            if (i > nT - (k - depth)) { /* no room left: back up */
                if (--depth >= 0)
                    idx[depth]++;
                continue;
            }
            int ok = 1;
            for (int q = 0; q < depth && ok; q++)
                ok = compat[idx[q]][i];
            if (!ok) {
                idx[depth]++;
                continue;
            }
            if (depth + 1 < k) {
                idx[depth + 1] = i + 1;
                depth++;
                continue;
            }
            int64_t S[MD_JMAX];
            for (int q = 0; q < k; q++)
                S[q] = T[idx[q]];
            nout = search_subset(&sbox, S, idx, k, nout);
            tried++;
            idx[depth]++;
        }
        if (nout < 0)
            break;
    }
    free(bb.cur);
    free(bb.nxt);
    free(bb.grp);
    free(bb.lc);
    if (nout < 0)
        return mfg_fail(MFG_ERR_NOMEM, "md_junction_search: out of memory"), -1;
    return nout;
}
