/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/junctions.c - junctions (the elements touching a disc, sorted by angle, and their
 * ports), the junction registry, and one branch traced from a port.  Overview and file
 * map: axis2d/axis2d.h. */
#include "axis2d/axis2d.h"

/* ---- junctions ------------------------------------------------------------------- */
static double wrap_pi(double a)
{
    a = fmod(a + MFG_PI, 2 * MFG_PI);
    if (a < 0)
        a += 2 * MFG_PI;
    return a - MFG_PI;
}

typedef struct { int64_t e; double a; } ma_ea;

static int cmp_ea(const void *pa, const void *pb)
{
    const ma_ea *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    return (a->e > b->e) - (a->e < b->e);
}

/* Builds the junction at (x, y) of radius r from every element within the event
 * accuracy of the disc (lesson 3: not the user tol) and the nforce segments force[] (the
 * two at a corner the trace passed, whose feet may round to just beyond their ends).
 * Returns its index or -1 (NOMEM). */
static int64_t junction_make(ma_ctx *C, double x, double y, double r, const int64_t *force,
                             int nforce)
{
    const ma_elems *E = &C->E;
    int64_t cnt = 0;
    C->cand.n = 0;
    if (!ma_bvh_collect(&C->T, (const double[4]){x, y, x, y}, r + C->gather, 0, &C->cand))
        return -1;
    ma_ea *ea = malloc((size_t)(2 * C->cand.n + nforce + 1) * sizeof *ea);
    if (!ea)
        return -1;
    for (int64_t ci = 0; ci < 2 * C->cand.n + nforce; ci++) {
        int64_t s = ci < 2 * C->cand.n ? C->cand.v[ci / 2] : force[ci - 2 * C->cand.n];
        int64_t e = ci < 2 * C->cand.n && ci % 2 ? E->velem[s] : s;
        if (e < 0)
            continue;
        int forced = ci >= 2 * C->cand.n, dup = 0;
        for (int64_t i = 0; i < cnt && forced; i++)
            dup |= ea[i].e == e;
        if (dup)
            continue;
        if (forced || ma_elem_dist(E, e, x, y) <= r + C->gather) {
            double fx, fy;
            if (is_seg(E, e)) {
                double d = (x - E->ax[e]) * E->nx[e] + (y - E->ay[e]) * E->ny[e];
                fx = x - d * E->nx[e];
                fy = y - d * E->ny[e];
            } else {
                ma_vpoint(E, e, &fx, &fy);
            }
            ea[cnt].e = e;
            ea[cnt].a = atan2(fy - y, fx - x);
            cnt++;
        }
    }
    qsort(ea, (size_t)cnt, sizeof *ea, cmp_ea);
    if (C->nj == C->capj) {
        int64_t c = C->capj ? 2 * C->capj : 16;
        ma_junction *p = realloc(C->J, (size_t)c * sizeof *p);
        if (!p) {
            free(ea);
            return -1;
        }
        C->J = p;
        C->capj = c;
    }
    ma_junction *J = &C->J[C->nj];
    J->x = x, J->y = y, J->r = r;
    J->first_elem = C->jelem.n;
    J->nelem = cnt;
    J->first_port = C->np;
    J->nport = 0;
    J->first_pos = -1;
    for (int64_t i = 0; i < cnt; i++)
        if (!ivec_push(&C->jelem, ea[i].e)) {
            free(ea);
            return -1;
        }
    for (int64_t i = 0; cnt > 1 && i < cnt; i++) {
        int64_t a = ea[i].e, b = ea[(i + 1) % cnt].e;
        if (a == b || ma_own_pair(E, a, b))
            continue;
        double da = fmod(ea[(i + 1) % cnt].a - ea[i].a + 4 * MFG_PI, 2 * MFG_PI);
        if (C->np == C->capp) {
            int64_t c = C->capp ? 2 * C->capp : 32;
            ma_port *p = realloc(C->P, (size_t)c * sizeof *p);
            if (!p) {
                free(ea);
                return -1;
            }
            C->P = p;
            C->capp = c;
        }
        ma_port *P = &C->P[C->np++];
        P->j = C->nj, P->e1 = a, P->e2 = b, P->angle = ea[i].a + da / 2, P->used = 0;
        J->nport++;
    }
    free(ea);
    return C->nj++;
}

/* The unused port of junction j best aligned with direction angle `a` (or the worst
 * aligned when `farthest`); -1 if none. */
static int64_t port_pick(const ma_ctx *C, int64_t j, double a, int farthest)
{
    int64_t best = -1;
    double bv = 0;
    for (int64_t p = C->J[j].first_port; p < C->J[j].first_port + C->J[j].nport; p++) {
        if (C->P[p].used)
            continue;
        double v = fabs(wrap_pi(C->P[p].angle - a));
        if (best < 0 || (farthest ? v > bv : v < bv))
            best = p, bv = v;
    }
    return best;
}


/* ---- the junction registry: a hash of a grid of cell `arrive` --------------------- */
static int64_t hcell(const ma_ctx *C, double v, double v0)
{
    return (int64_t)floor((v - v0) / C->arrive);
}

static int64_t hbucket(const ma_ctx *C, int64_t ix, int64_t iy)
{
    uint64_t h = (uint64_t)ix * 0x9E3779B97F4A7C15ULL ^ (uint64_t)iy * 0xC2B2AE3D27D4EB4FULL;
    return (int64_t)((h ^ (h >> 29)) & (uint64_t)C->hmask);
}

static void junction_link(ma_ctx *C, int64_t j)
{
    int64_t b = hbucket(C, hcell(C, C->J[j].x, C->hx0), hcell(C, C->J[j].y, C->hy0));
    C->J[j].hnext = C->hhead[b];
    C->hhead[b] = j;
}

/* Do junctions a and b touch the same elements? */
static int same_elements(const ma_ctx *C, int64_t a, int64_t b)
{
    const ma_junction *A = &C->J[a], *B = &C->J[b];
    if (A->nelem != B->nelem)
        return 0;
    for (int64_t i = 0; i < A->nelem; i++) {
        int found = 0;
        for (int64_t k = 0; k < B->nelem && !found; k++)
            found = C->jelem.v[A->first_elem + i] == C->jelem.v[B->first_elem + k];
        if (!found)
            return 0;
    }
    return 1;
}

/* The registered junction within `arrive` of the new (unregistered) junction jn that
 * touches the same elements (the lowest index if several), or -1.  Position alone is
 * not enough: at 100 000 segments distinct junctions at needle bases lie 1e-4 apart, and
 * an arriving trace taken for the wrong one left a true junction out (a zero-length
 * loop in its place). */
static int64_t junction_find(const ma_ctx *C, int64_t jn)
{
    double x = C->J[jn].x, y = C->J[jn].y;
    int64_t ix = hcell(C, x, C->hx0), iy = hcell(C, y, C->hy0), best = -1;
    for (int64_t a = ix - 1; a <= ix + 1; a++)
        for (int64_t c = iy - 1; c <= iy + 1; c++)
            for (int64_t j = C->hhead[hbucket(C, a, c)]; j >= 0; j = C->J[j].hnext)
                if (hypot(C->J[j].x - x, C->J[j].y - y) <= C->arrive && (best < 0 || j < best) &&
                    same_elements(C, j, jn))
                    best = j;
    return best;
}

/* ---- the pocket of a port (ma_window) -------------------------------------------- */
static int64_t elem_pos(const ma_elems *E, int64_t e)
{
    return is_seg(E, e) ? e : E->vk[e - E->ns];
}

/* The ring holding position p: its segments [*lo, *hi). */
static void ring_of(const ma_ctx *C, int64_t p, int64_t *lo, int64_t *hi)
{
    int64_t a = 0, b = C->nrings; /* roff[a] <= p < roff[b] */
    while (b - a > 1) {
        int64_t m = a + (b - a) / 2;
        if (C->roff[m] <= p)
            a = m;
        else
            b = m;
    }
    *lo = C->roff[a], *hi = C->roff[a + 1];
}

/* The position after p among the junction's positions of ring [lo, hi) (cyclic), or -1
 * when p is not there exactly once. */
static int64_t next_pos(const int64_t *P, int64_t n, int64_t p, int64_t lo, int64_t hi)
{
    int64_t i = mfg_lower_bound_i64(P, n, p);
    if (i >= n || P[i] != p || (i + 1 < n && P[i + 1] == p))
        return -1;
    if (i + 1 < n && P[i + 1] < hi)
        return P[i + 1];
    return P[mfg_lower_bound_i64(P, n, lo)]; /* wrap to the ring's first */
}

/* Sets C->win to the pocket of the port (a, b) of junction j (see ma_window), or leaves
 * it inactive where that is not clear: a and b on different rings, a position held by two
 * of the junction's elements, or no other element of the junction on their ring.
 * 0 on NOMEM. */
static int port_window(ma_ctx *C, int64_t j, int64_t a, int64_t b)
{
    const ma_elems *E = &C->E;
    C->win.active = 0;
    if (j < 0 || C->J[j].nelem < 3)
        return 1;
    if (C->J[j].first_pos < 0) {
        int64_t first = C->jpos.n;
        for (int64_t i = 0; i < C->J[j].nelem; i++)
            if (!ivec_push(&C->jpos, elem_pos(E, C->jelem.v[C->J[j].first_elem + i])))
                return 0;
        qsort(C->jpos.v + first, (size_t)C->J[j].nelem, sizeof *C->jpos.v, mfg_cmp_i64);
        C->J[j].first_pos = first;
    }
    const int64_t *P = C->jpos.v + C->J[j].first_pos;
    int64_t n = C->J[j].nelem, pa = elem_pos(E, a), pb = elem_pos(E, b), lo, hi;
    ring_of(C, pa, &lo, &hi);
    if (pb < lo || pb >= hi)
        return 1;
    int fwd = next_pos(P, n, pa, lo, hi) == pb, bwd = next_pos(P, n, pb, lo, hi) == pa;
    if (fwd == bwd)
        return 1;
    int64_t from = fwd ? pa : pb, to = fwd ? pb : pa, m = hi - lo;
    C->win = (ma_window){1, lo, hi, from, ((to - from) % m + m) % m};
    return 1;
}

static mfg_status run_branch(ma_ctx *C, const ma_start *s, int64_t j0);

/* Traces one branch from a leaf (j0 = -1) or a junction port, through pass-through
 * (degree-2) events, to a leaf or a junction; registers new junctions and their ports.
 * A branch from a port searches its pocket only (ma_window). */
mfg_status ma_run_branch(ma_ctx *C, const ma_start *s, int64_t j0)
{
    if (!port_window(C, j0, s->e1, s->e2))
        return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (junctions)");
    mfg_status st = run_branch(C, s, j0);
    C->win.active = 0;
    return st;
}

static mfg_status run_branch(ma_ctx *C, const ma_start *s, int64_t j0)
{
    double x = s->x, y = s->y, r = s->r, dx = s->dx, dy = s->dy;
    int64_t e1 = s->e1, e2 = s->e2;
    const ma_elems *E = &C->E;
    if (!ivec_push(&C->boff, C->px.n))
        return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (branches)");
    int first = 1;
    for (;;) {
        double ev[5];
        int64_t leafv;
        int rc = ma_trace(C, &(ma_start){x, y, r, e1, e2, dx, dy}, first, ev, &leafv);
        if (rc == TR_NOMEM)
            return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (samples)");
        if (rc == TR_BADPAIR)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace from (%g, %g) reached elements %lld and "
                            "%lld, which have no bisector inside the face (a missed window "
                            "event; known on very thin spikes)",
                            x, y, (long long)ev[0], (long long)ev[1]);
        if (rc == TR_MISSED)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace of elements %lld and %lld reached a convex "
                            "corner at (%g, %g) with radius %g (a missed event)",
                            (long long)e1, (long long)e2, ev[0], ev[1], ev[2]);
        if (rc == TR_STUCK)
            return mfg_fail(MFG_ERR_INTERNAL,
                            "medial axis: the trace of the bisector of elements %lld and %lld "
                            "from (%g, %g) did not reach an event",
                            (long long)e1, (long long)e2, x, y);
        if (rc == TR_LEAF) {
            int64_t n = C->px.n - 1, best = leafv;
            if (best < 0) { /* not identified by the trace: the nearest vertex */
                double bd = INFINITY;
                for (int64_t k = 0; k < E->ns; k++) {
                    double d = hypot(E->ax[k] - C->px.v[n], E->ay[k] - C->py.v[n]);
                    if (d < bd)
                        bd = d, best = k;
                }
            }
            C->reached[best] = 1;
            C->pr.v[n] = 0.0;
            return ivec_push(&C->bend, j0) && ivec_push(&C->bend, -1)
                       ? MFG_OK
                       : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        }
        double back = atan2(-ev[4], -ev[3]);
        int64_t j = junction_make(C, ev[0], ev[1], ev[2], C->corner, rc == TR_CORNER ? 2 : 0);
        if (j < 0)
            return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (junctions)");
        /* A known junction (lesson 4: identified with the event accuracy, and by its
         * elements): forget the new one, arrive at the known one. */
        int64_t jk = junction_find(C, j);
        if (jk >= 0) {
            C->jelem.n = C->J[j].first_elem;
            C->np = C->J[j].first_port;
            C->nj--;
            j = jk;
            int64_t p = port_pick(C, j, back, 0);
            if (p >= 0)
                C->P[p].used = 1;
            int64_t n = C->px.n - 1;
            C->px.v[n] = C->J[j].x, C->py.v[n] = C->J[j].y, C->pr.v[n] = C->J[j].r;
            return ivec_push(&C->bend, j0) && ivec_push(&C->bend, j)
                       ? MFG_OK
                       : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        }
        if (C->J[j].nport == 2) { /* a pass-through: continue the same branch */
            int64_t p = port_pick(C, j, back, 1);
            x = ev[0], y = ev[1], r = ev[2];
            e1 = C->P[p].e1, e2 = C->P[p].e2;
            dx = cos(C->P[p].angle), dy = sin(C->P[p].angle);
            /* forget it: it is not a junction */
            C->jelem.n = C->J[j].first_elem;
            C->np = C->J[j].first_port;
            C->nj--;
            first = 0;
            continue;
        }
        junction_link(C, j);
        int64_t pin = port_pick(C, j, back, 0);
        if (pin >= 0)
            C->P[pin].used = 1;
        for (int64_t p = C->J[j].first_port; p < C->J[j].first_port + C->J[j].nport; p++)
            if (!C->P[p].used && !ivec_push(&C->stack, p))
                return mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
        return ivec_push(&C->bend, j0) && ivec_push(&C->bend, j)
                   ? MFG_OK
                   : mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory");
    }
}
