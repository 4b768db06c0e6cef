/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/medial_axis.c - entry point: input checks (rings, crossings), elements, BVH, the
 * traces from every leaf, mfg_medial_axis / mfg_medial_axis_p.  Overview and file map:
 * axis2d/axis2d.h. */
#include "axis2d/axis2d.h"

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
static int segs_touch(const double ab[4], const double cd[4])
{
    double ax = ab[0], ay = ab[1], bx = ab[2], by = ab[3];
    double cx = cd[0], cy = cd[1], dx = cd[2], dy = cd[3];
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
    return mfg_medial_axis_p(xy, ring_offsets, nrings, tol, out, NULL);
}

/* Work units between progress reports: an edge checked against its neighbours in the
 * index (~1 us), a branch traced (~0.1-1 ms). */
#define AXIS_EVERY_EDGES 16384
#define AXIS_EVERY_BRANCHES 32

/* The cleaned rings: vertices (vx, vy), each one's index in the caller's xy (vo), ring r
 * at [roff[r], roff[r + 1]), nv vertices in nrings rings. */
typedef struct {
    double *vx, *vy;
    int64_t *vo, *roff;
    int64_t nv, nrings;
} ma_rings;

/* The argument checks of mfg_medial_axis_p, in its order of messages. */
static mfg_status check_axis_args(const double *xy, const int64_t *ring_offsets, int64_t nrings,
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
    return MFG_OK;
}

/* The arrays of the rings and of the elements, for nin input vertices. */
static mfg_status alloc_input(ma_ctx *C, ma_rings *R, int64_t nin)
{
    ma_elems *E = &C->E;
    size_t n1 = (size_t)(nin > 0 ? nin : 1);
    R->vx = malloc(n1 * sizeof *R->vx), R->vy = malloc(n1 * sizeof *R->vy);
    R->vo = malloc(n1 * sizeof *R->vo);
    R->roff = malloc((size_t)(R->nrings + 1) * sizeof *R->roff);
    E->ax = malloc(n1 * sizeof(double)), E->ay = malloc(n1 * sizeof(double));
    E->ux = malloc(n1 * sizeof(double)), E->uy = malloc(n1 * sizeof(double));
    E->nx = malloc(n1 * sizeof(double)), E->ny = malloc(n1 * sizeof(double));
    E->len = malloc(n1 * sizeof(double));
    E->prev = malloc(n1 * sizeof(int64_t)), E->next = malloc(n1 * sizeof(int64_t));
    E->orig = malloc(n1 * sizeof(int64_t)), E->velem = malloc(n1 * sizeof(int64_t));
    E->vk = malloc(n1 * sizeof(int64_t));
    E->reflex = malloc(n1), E->convex = malloc(n1);
    C->reached = calloc(n1, 1);
    if (!R->vx || !R->vy || !R->vo || !R->roff || !E->ax || !E->ay || !E->ux || !E->uy ||
        !E->nx || !E->ny || !E->len || !E->prev || !E->next || !E->orig || !E->velem ||
        !E->vk || !E->reflex || !E->convex || !C->reached)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld ring vertices", (long long)nin);
    return MFG_OK;
}

/* Drops the vertices of ring [lo, *nv) where the boundary goes straight on (orient2d = 0,
 * dot > 0), in one pass: the ring rotated to start at a corner (which stays one: dropping
 * a straight vertex keeps both lines), then a stack.  A vertex where the ring turns back
 * (a spike) is a self-touching ring.  (Dropping each by a memmove of the rest was
 * O(n x dropped): a circle rounded to integers has thousands, and 10^5 vertices spent a
 * second moving memory.) */
static mfg_status drop_straight(double *vx, double *vy, int64_t *vo, int64_t lo, int64_t *nv,
                                int64_t ring)
{
    int64_t n = *nv - lo, c0 = -1;
    for (int64_t i = 0; i < n && c0 < 0; i++) {
        int64_t a = lo + (i + n - 1) % n, b = lo + i, c = lo + (i + 1) % n;
        if (mfg_orient2d(vx[a], vy[a], vx[b], vy[b], vx[c], vy[c]) != 0)
            c0 = i;
    }
    for (int64_t i = 0; i < n && c0 < 0; i++) { /* all on one line: it turns back */
        int64_t a = lo + (i + n - 1) % n, b = lo + i, c = lo + (i + 1) % n;
        if (mfg_dot2d(vx[b], vy[b], vx[a], vy[a], vx[c], vy[c]) > 0)
            return mfg_fail(MFG_ERR_INVALID,
                            "ring %lld turns back on itself at vertex %lld (a spike: the "
                            "ring touches itself)",
                            (long long)ring, (long long)vo[b]);
    }
    if (c0 < 0)
        return MFG_OK;
    /* rotate left by c0 (three reversals) */
    for (int pass = 0; pass < 3; pass++) {
        int64_t a = pass == 1 ? lo + c0 : lo, b = pass == 0 ? lo + c0 - 1 : *nv - 1;
        for (; a < b; a++, b--) {
            double tx = vx[a], ty = vy[a];
            int64_t to = vo[a];
            vx[a] = vx[b], vy[a] = vy[b], vo[a] = vo[b];
            vx[b] = tx, vy[b] = ty, vo[b] = to;
        }
    }
    int64_t top = lo + 1; /* the stack vx[lo .. top); the corner at lo stays */
    for (int64_t i = lo + 1; i <= *nv; i++) {
        if (i < *nv) {
            vx[top] = vx[i], vy[top] = vy[i], vo[top] = vo[i];
            top++;
        }
        /* the last three straight at the middle one: drop it; at the end (i == *nv) the
         * last two with the corner closing the ring */
        while (top - lo >= 3) {
            int64_t a = i < *nv ? top - 3 : top - 2, b = a + 1, c = i < *nv ? top - 1 : lo;
            if (mfg_orient2d(vx[a], vy[a], vx[b], vy[b], vx[c], vy[c]) != 0)
                break;
            if (mfg_dot2d(vx[b], vy[b], vx[a], vy[a], vx[c], vy[c]) > 0)
                return mfg_fail(MFG_ERR_INVALID,
                                "ring %lld turns back on itself at vertex %lld (a spike: the "
                                "ring touches itself)",
                                (long long)ring, (long long)vo[b]);
            if (i < *nv)
                vx[b] = vx[c], vy[b] = vy[c], vo[b] = vo[c];
            top--;
        }
    }
    *nv = top;
    return MFG_OK;
}

static mfg_status clean_rings(ma_rings *R, const double *xy, const int64_t *ring_offsets)
{
    mfg_status st = MFG_OK;
    double *vx = R->vx, *vy = R->vy;
    int64_t *vo = R->vo, *roff = R->roff, nrings = R->nrings;
    /* (1) Clean each ring: a run of consecutive vertices within MA_EPS_GATHER of the
     * input's extent of its first is one vertex, the run's last (so that its edge, which
     * the results name, is the long one after the run; a closing run is the ring's first
     * vertex); then vertices where the boundary goes straight on (orient2d = 0, dot > 0)
     * go; a vertex where it turns back (a spike) is a self-touching ring.  Not only equal
     * vertices: two 1e-14 apart (a closed edge's polyline ends at cos(2 pi) of its start)
     * are one to the junctions, which gather elements within MA_EPS_GATHER - the pair's
     * perpendicular bisector then made a branch into the boundary (issue 22). */
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    for (int64_t k = 0; k < ring_offsets[nrings]; k++) {
        xlo = fmin(xlo, xy[2 * k]), xhi = fmax(xhi, xy[2 * k]);
        ylo = fmin(ylo, xy[2 * k + 1]), yhi = fmax(yhi, xy[2 * k + 1]);
    }
    double same = MA_EPS_GATHER * fmax(xhi - xlo, yhi - ylo);
    int64_t nv = 0;
    roff[0] = 0;
    for (int64_t r = 0; r < nrings; r++) {
        int64_t lo = nv;
        double runx = 0, runy = 0; /* the first vertex of the current run */
        for (int64_t k = ring_offsets[r]; k < ring_offsets[r + 1]; k++) {
            double x = xy[2 * k], y = xy[2 * k + 1];
            if (nv > lo && fabs(x - runx) <= same && fabs(y - runy) <= same) {
                vx[nv - 1] = x, vy[nv - 1] = y, vo[nv - 1] = k; /* the run's last */
                continue;
            }
            runx = x, runy = y;
            vx[nv] = x, vy[nv] = y, vo[nv] = k, nv++;
        }
        while (nv - lo > 1 && fabs(vx[nv - 1] - vx[lo]) <= same && fabs(vy[nv - 1] - vy[lo]) <= same)
            nv--;
        if (nv - lo >= 3) {
            st = drop_straight(vx, vy, vo, lo, &nv, r);
            if (st != MFG_OK)
                return st;
        }
        if (nv - lo < 3) {
            st = mfg_fail(MFG_ERR_DEGENERATE,
                          "ring %lld has fewer than 3 distinct, non-collinear vertices (%lld "
                          "given)",
                          (long long)r, (long long)(ring_offsets[r + 1] - ring_offsets[r]));
            return st;
        }
        roff[r + 1] = nv;
    }
    R->nv = nv;
    return st;
}

static mfg_status check_crossings(ma_ctx *C, const ma_rings *R, mfg_prog *prog)
{
    mfg_status st = MFG_OK;
    ma_elems *E = &C->E;
    const double *vx = R->vx, *vy = R->vy;
    const int64_t *vo = R->vo, *roff = R->roff;
    int64_t nv = R->nv, nrings = R->nrings;
    /* (2) The index over the cleaned segments; no two edges may share a point other than
     * the common vertex of neighbours (exact tests on the pairs whose boxes touch; the
     * lowest pair (i, j) is reported). */
    for (int64_t r = 0; r < nrings; r++)
        for (int64_t k = roff[r]; k < roff[r + 1]; k++) {
            int64_t k2 = k + 1 < roff[r + 1] ? k + 1 : roff[r];
            E->next[k] = k2, E->prev[k2] = k, E->orig[k] = r; /* orig: the ring, for now */
        }
    if (!ma_bvh_build(&C->T, vx, vy, E->next, nv)) {
        st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate the index of %lld edges", (long long)nv);
        return st;
    }
    double diag0 = 0; /* the boxes' padding: a touch may round to a tiny distance */
    for (int64_t k = 0; k < nv; k++)
        diag0 = fmax(diag0, fmax(fabs(vx[k] - vx[0]), fabs(vy[k] - vy[0])));
    for (int64_t i = 0; i < nv; i++) {
        if (!mfg_prog_poll(prog, (double)i, (double)nv)) {
            st = mfg_prog_fail(prog);
            return st;
        }
        int64_t i2 = E->next[i], jbest = -1;
        C->cand.n = 0;
        const double seg_i[4] = {vx[i], vy[i], vx[i2], vy[i2]};
        if (!ma_bvh_collect(&C->T, seg_i, MA_EPS_TOUCH * diag0, i + 1, &C->cand)) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (index query)");
            return st;
        }
        for (int64_t c = 0; c < C->cand.n; c++) {
            int64_t jj = C->cand.v[c], j2 = E->next[jj];
            if (jj <= i || (jbest >= 0 && jj >= jbest) || jj == i2 || j2 == i)
                continue; /* neighbours share their common vertex only, unless they
                             overlap (excluded by the spike check) */
            if (segs_touch(seg_i, (const double[4]){vx[jj], vy[jj], vx[j2], vy[j2]}))
                jbest = jj;
        }
        if (jbest >= 0) {
            st = mfg_fail(MFG_ERR_INVALID,
                          "the boundary touches or crosses itself: edge %lld (ring %lld) and "
                          "edge %lld (ring %lld); the medial axis needs disjoint simple rings",
                          (long long)vo[i], (long long)E->orig[i], (long long)vo[jbest],
                          (long long)E->orig[jbest]);
            return st;
        }
    }
    return st;
}

static mfg_status build_elements(ma_ctx *C, const ma_rings *R, double tol)
{
    mfg_status st = MFG_OK;
    ma_elems *E = &C->E;
    const double *vx = R->vx, *vy = R->vy;
    const int64_t *vo = R->vo, *roff = R->roff;
    int64_t nv = R->nv, nrings = R->nrings;
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
    C->tol = tol;
    C->eps = MA_EPS_PAD * E->diag; /* padding of the index's bounds */
    /* Events are exact roots, so a junction's elements touch its disc to rounding
     * (~1e-15 diag): gather them with 1e-11 diag.  Wider picks up elements of a thin
     * spike that do not touch (7.6e-8 diag away on a 100k-segment star with 1e-9), whose
     * foot angles then misorder the ports (a port between two segments adjacent at a
     * reflex vertex: no bisector inside).  An arriving trace locates its junction less
     * precisely (a grazing third element: a near-double root): 1e-6 diag. */
    C->gather = MA_EPS_GATHER * E->diag;
    C->arrive = MA_EPS_ARRIVE * E->diag;
    {
        int64_t nb = 64;
        while (nb < 4 * (E->ns + E->nv))
            nb *= 2;
        C->hhead = malloc((size_t)nb * sizeof *C->hhead);
        if (!C->hhead) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (junction registry)");
            return st;
        }
        for (int64_t b = 0; b < nb; b++)
            C->hhead[b] = -1;
        C->hmask = nb - 1, C->hx0 = xmin, C->hy0 = ymin;
        C->heapk = malloc((size_t)(C->T.nn + 1) * sizeof *C->heapk);
        C->heapn = malloc((size_t)(C->T.nn + 1) * sizeof *C->heapn);
        if (!C->heapk || !C->heapn) {
            st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (search heap)");
            return st;
        }
    }
    return st;
}

static mfg_status trace_all(ma_ctx *C, const ma_rings *R, mfg_prog *prog)
{
    mfg_status st = MFG_OK;
    ma_elems *E = &C->E;
    const double *vx = R->vx, *vy = R->vy;
    int64_t nv = R->nv;
    /* (4) Trace from every convex corner not yet reached, then every open port.  A
     * branch is a unit of progress; there are about as many as vertices. */
    if (!mfg_prog_stage(prog, "axis: branches", 0.1, 0.95, AXIS_EVERY_BRANCHES)) {
        st = mfg_prog_fail(prog);
        return st;
    }
    int64_t nrun = 0;
    for (int64_t k = 0; k < nv; k++) {
        if (!E->convex[k] || C->reached[k])
            continue;
        if (!mfg_prog_poll(prog, (double)nrun++, (double)(2 * nv))) {
            st = mfg_prog_fail(prog);
            return st;
        }
        C->reached[k] = 1;
        int64_t p = E->prev[k];
        double dx = E->nx[p] + E->nx[k], dy = E->ny[p] + E->ny[k], l = hypot(dx, dy);
        st = ma_run_branch(C, &(ma_start){vx[k], vy[k], 0.0, p, k, dx / l, dy / l}, -1);
        if (st != MFG_OK)
            return st;
        while (C->stack.n > 0) {
            int64_t q = C->stack.v[--C->stack.n];
            if (C->P[q].used)
                continue;
            C->P[q].used = 1;
            if (!mfg_prog_poll(prog, (double)nrun++, (double)(2 * nv))) {
                st = mfg_prog_fail(prog);
                return st;
            }
            ma_junction *J = &C->J[C->P[q].j];
            const ma_port *Pq = &C->P[q];
            st = ma_run_branch(C,
                               &(ma_start){J->x, J->y, J->r, Pq->e1, Pq->e2, cos(Pq->angle),
                                           sin(Pq->angle)},
                               C->P[q].j);
            if (st != MFG_OK)
                return st;
        }
    }
    return st;
}

mfg_status mfg_medial_axis_p(const double *xy, const int64_t *ring_offsets, int64_t nrings,
                             double tol, struct mfg_medial_axis **out,
                             const mfg_progress *progress)
{
    mfg_status st = check_axis_args(xy, ring_offsets, nrings, tol, out);
    if (st != MFG_OK)
        return st;
    int64_t nin = ring_offsets[nrings];
    ma_ctx C;
    memset(&C, 0, sizeof C);
    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_medial_axis");
    struct mfg_medial_axis *res = NULL;
    ma_elems *E = &C.E;
    ma_rings R = {NULL, NULL, NULL, NULL, 0, nrings};
    st = alloc_input(&C, &R, nin);
    if (st == MFG_OK && !mfg_prog_stage(&prog, "axis: setup", 0, 0.1, AXIS_EVERY_EDGES))
        st = mfg_prog_fail(&prog);
    /* (1) clean rings, (2) no crossings, (3) the elements, (4) the traces */
    if (st == MFG_OK)
        st = clean_rings(&R, xy, ring_offsets);
    if (st == MFG_OK)
        st = check_crossings(&C, &R, &prog);
    if (st == MFG_OK)
        st = build_elements(&C, &R, tol);
    if (st == MFG_OK) {
        C.roff = R.roff, C.nrings = R.nrings;
        st = trace_all(&C, &R, &prog);
    }
    if (st != MFG_OK)
        goto done;

    /* (5) The flat result. */
    if (!mfg_prog_stage(&prog, "axis: output", 0.95, 1.0, 1)) {
        st = mfg_prog_fail(&prog);
        goto done;
    }
    st = ma_assemble(&C, &res);
    if (st == MFG_OK && !mfg_prog_stage(&prog, "axis: done", 1.0, 1.0, 1)) {
        mfg_medial_axis_free(res);
        st = mfg_prog_fail(&prog);
    }
    if (st == MFG_OK) {
        *out = res;
        mfg_clear_error();
    }
done:
    free(R.vx), free(R.vy), free(R.vo), free(R.roff);
    elems_free(E);
    free(C.reached), free(C.hhead), free(C.cand.v), free(C.heapk), free(C.heapn);
    ma_bvh_free(&C.T);
    free(C.px.v), free(C.py.v), free(C.pr.v), free(C.boff.v), free(C.bend.v);
    free(C.J), free(C.P), free(C.jelem.v), free(C.jpos.v), free(C.stack.v);
    return st;
}
