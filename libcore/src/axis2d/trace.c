/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/trace.c - tracing a bisector: its exact events (first contact of another element,
 * closed-form roots) by branch and bound over the BVH, and the samples.  Overview and file
 * map: axis2d/axis2d.h. */
#include "axis2d/axis2d.h"

/* ---- tracing ---------------------------------------------------------------------- */

static int push_sample(ma_ctx *C, double x, double y, double r)
{
    return dvec_push(&C->px, x) && dvec_push(&C->py, y) && dvec_push(&C->pr, r);
}

/* ---- exact events ----------------------------------------------------------------- */

/* The root of A t^2 + B t + C in (lo, hi] where the polynomial falls through zero (from
 * positive = outside the disc / inside the window, to negative), INFINITY if none.  A
 * quadratic has at most one such root; a root where it rises is an element leaving the
 * disc (the elements of the junction a trace starts from) and is not an event. */
static double quad_entry(double A, double B, double C, double lo, double hi)
{
    double best = INFINITY;
    if (A == 0) {
        if (B < 0) {
            double t = -C / B;
            if (t > lo && t <= hi)
                best = t;
        }
        return best;
    }
    double D = B * B - 4 * A * C;
    if (D < 0)
        return best;
    double sq = sqrt(D), q = -0.5 * (B + (B >= 0 ? sq : -sq));
    double rt[2] = {q / A, q != 0 ? C / q : q / A};
    for (int i = 0; i < 2; i++)
        if (rt[i] > lo && rt[i] <= hi && 2 * A * rt[i] + B < 0 && rt[i] < best)
            best = rt[i];
    return best;
}

/* The entry root of c . (p(t) - q) + c0 (a linear function of the point), lin = (c, q, c0). */
static double lin_entry(const ma_bis *b, const double lin[5], double lo, double hi)
{
    double cx = lin[0], cy = lin[1], qx = lin[2], qy = lin[3], c0 = lin[4];
    return quad_entry(cx * b->p2x + cy * b->p2y, cx * b->p1x + cy * b->p1y,
                      cx * (b->p0x - qx) + cy * (b->p0y - qy) + c0, lo, hi);
}

static void bis_pt(const ma_bis *b, double t, double *x, double *y)
{
    *x = b->p0x + t * (b->p1x + t * b->p2x);
    *y = b->p0y + t * (b->p1y + t * b->p2y);
}

/* The first t in (lo, hi] where element e (not of the pair) touches the disc of b from
 * outside: |p - v| = r for a reflex vertex, |n . (p - a)| = r with the foot inside the open
 * segment for an edge.  Closed forms, each at most a quadratic in t: for MA_PL and MA_PP
 * r = |p - f|, so |p - v|^2 - r^2 = 2 (f - v) . (p - (f + v) / 2) is linear in p. */
static double elem_entry(const ma_elems *E, const ma_bis *b, int64_t e, double lo, double hi)
{
    int curved_r = b->kind == MA_PL || b->kind == MA_PP;
    if (!is_seg(E, e)) {
        double vx, vy;
        ma_vpoint(E, e, &vx, &vy);
        if (curved_r)
            return lin_entry(b,
                             (const double[5]){2 * (b->fpx - vx), 2 * (b->fpy - vy),
                                               0.5 * (b->fpx + vx), 0.5 * (b->fpy + vy), 0.0},
                             lo, hi);
        double wx = b->p0x - vx, wy = b->p0y - vy;
        return quad_entry(b->p1x * b->p1x + b->p1y * b->p1y - b->r1c * b->r1c,
                          2 * (b->p1x * wx + b->p1y * wy - b->r0c * b->r1c),
                          wx * wx + wy * wy - b->r0c * b->r0c, lo, hi);
    }
    double nx = E->nx[e], ny = E->ny[e];
    double d2 = nx * b->p2x + ny * b->p2y, d1 = nx * b->p1x + ny * b->p1y;
    double d0 = nx * (b->p0x - E->ax[e]) + ny * (b->p0y - E->ay[e]);
    double ts[2] = {INFINITY, INFINITY}, best = INFINITY;
    if (b->kind == MA_PP) { /* (n . (p - a))^2 - |p - f|^2, p linear in t */
        double wx = b->p0x - b->fpx, wy = b->p0y - b->fpy;
        ts[0] = quad_entry(d1 * d1 - (b->p1x * b->p1x + b->p1y * b->p1y),
                           2 * (d0 * d1 - (b->p1x * wx + b->p1y * wy)),
                           d0 * d0 - (wx * wx + wy * wy),
                           lo, hi);
    } else { /* +-n . (p - a) - r: the disc meets the line from either side */
        ts[0] = quad_entry(d2 - b->r2c, d1 - b->r1c, d0 - b->r0c, lo, hi);
        ts[1] = quad_entry(-d2 - b->r2c, -d1 - b->r1c, -d0 - b->r0c, lo, hi);
    }
    for (int i = 0; i < 2; i++) {
        if (!(ts[i] < best))
            continue;
        double x, y;
        bis_pt(b, ts[i], &x, &y);
        double f = (x - E->ax[e]) * E->ux[e] + (y - E->ay[e]) * E->uy[e];
        if (f > 0 && f < E->len[e])
            best = ts[i];
    }
    return best;
}

/* The first t in (lo, +inf) where a window of the pair closes (see bis_window for `how`). */
static double bis_window_exit(const ma_elems *E, const ma_bis *b, double lo, int64_t *which,
                              int *how)
{
    int64_t es[2] = {b->e1, b->e2};
    double best = INFINITY;
    for (int i = 0; i < 2; i++) {
        int64_t e = es[i];
        double t[2];
        if (is_seg(E, e)) {
            t[0] = lin_entry(b, (const double[5]){E->ux[e], E->uy[e], E->ax[e], E->ay[e], 0.0}, lo, INFINITY);
            t[1] = lin_entry(b, (const double[5]){-E->ux[e], -E->uy[e], E->ax[e], E->ay[e], E->len[e]}, lo,
                             INFINITY);
        } else {
            int64_t k = E->vk[e - E->ns], pk = E->prev[k];
            t[0] = lin_entry(b, (const double[5]){E->ux[pk], E->uy[pk], E->ax[k], E->ay[k], 0.0}, lo, INFINITY);
            t[1] = lin_entry(b, (const double[5]){-E->ux[k], -E->uy[k], E->ax[k], E->ay[k], 0.0}, lo, INFINITY);
        }
        for (int w = 0; w < 2; w++)
            if (t[w] < best)
                best = t[w], *which = e, *how = (is_seg(E, e) ? 1 : 3) + w;
    }
    return best;
}

/* The elements a bisector never meets except at its window ends (lesson 1): the pair, the
 * reflex endpoints of a pair segment and the other edge there (it lies beyond the line of
 * the pair segment, on the far side from the disc), the two edges of a pair vertex (they
 * lie beyond the disc's tangent at the vertex while the vertex's window is open). */
static int excluded_set(const ma_elems *E, const ma_bis *b, int64_t ex[10])
{
    int nex = 0;
    int64_t es[2] = {b->e1, b->e2};
    for (int i = 0; i < 2; i++) {
        int64_t e = es[i];
        ex[nex++] = e;
        if (is_seg(E, e)) {
            if (E->reflex[e])
                ex[nex++] = E->velem[e], ex[nex++] = E->prev[e];
            if (E->reflex[E->next[e]])
                ex[nex++] = E->velem[E->next[e]], ex[nex++] = E->next[e];
        } else {
            int64_t k = E->vk[e - E->ns];
            ex[nex++] = k;
            ex[nex++] = E->prev[k];
        }
    }
    return nex;
}

/* A lower bound of the first t >= 0 where the disc of b meets the disc (c, rho):
 * |p - c| <= r + rho.  Closed forms: for MA_PAR / MA_LL a quadratic; for MA_PL / MA_PP
 * (r = |p - f|) the condition is L = |p - c|^2 - |p - f|^2 - rho^2 <= 2 rho r with L
 * linear in p (MA_PL: r is a polynomial; MA_PP: L <= 0 or L^2 <= 4 rho^2 r^2, a
 * superset, hence still a bound). */
static double disc_bound(const ma_bis *b, double cx, double cy, double rho)
{
    if (b->kind == MA_PL || b->kind == MA_PP) {
        double kx = 2 * (b->fpx - cx), ky = 2 * (b->fpy - cy);
        double mx = 0.5 * (b->fpx + cx), my = 0.5 * (b->fpy + cy);
        double L2 = kx * b->p2x + ky * b->p2y, L1 = kx * b->p1x + ky * b->p1y;
        double L0 = kx * (b->p0x - mx) + ky * (b->p0y - my) - rho * rho;
        if (b->kind == MA_PL) {
            double A = L2 - 2 * rho * b->r2c, B = L1 - 2 * rho * b->r1c, C = L0 - 2 * rho * b->r0c;
            return C <= 0 ? 0.0 : quad_entry(A, B, C, 0.0, INFINITY);
        }
        double wx = b->p0x - b->fpx, wy = b->p0y - b->fpy, rr = 4 * rho * rho;
        double A = L1 * L1 - rr * (b->p1x * b->p1x + b->p1y * b->p1y);
        double B = 2 * L0 * L1 - rr * 2 * (b->p1x * wx + b->p1y * wy);
        double C = L0 * L0 - rr * (wx * wx + wy * wy);
        if (L0 <= 0 || C <= 0)
            return 0.0;
        return fmin(quad_entry(0.0, L1, L0, 0.0, INFINITY), quad_entry(A, B, C, 0.0, INFINITY));
    }
    double wx = b->p0x - cx, wy = b->p0y - cy, R0 = b->r0c + rho;
    double C = wx * wx + wy * wy - R0 * R0;
    if (C <= 0)
        return 0.0;
    return quad_entry(b->p1x * b->p1x + b->p1y * b->p1y - b->r1c * b->r1c,
                      2 * (b->p1x * wx + b->p1y * wy - R0 * b->r1c), C, 0.0, INFINITY);
}

/* A lower bound of the first t >= 0 where the disc of b meets the capsule cp (axis a-b,
 * radius rho): first contact is with an end cap (disc_bound) or with one of the two side
 * lines |n . (p - a)| = rho (their first contact, foot ignored: earlier, so a bound). */
static double node_bound(const ma_bis *b, const double *cp, double pad, double lim)
{
    double ax = cp[0], ay = cp[1], rho = cp[4] + pad;
    double dx = cp[2] - ax, dy = cp[3] - ay, l = sqrt(dx * dx + dy * dy);
    double r0 = b->kind == MA_PP ? hypot(b->p0x - b->fpx, b->p0y - b->fpy) : b->r0c;
    double d0 = ma_pt_seg_d2(b->p0x, b->p0y, ax, ay, cp[2], cp[3]), R0 = r0 + rho;
    if (d0 <= R0 * R0)
        return 0.0;
    /* first the circumscribed disc (one quadratic): far nodes stop here */
    double tc = disc_bound(b, 0.5 * (ax + cp[2]), 0.5 * (ay + cp[3]), 0.5 * l + rho);
    if (!(tc < lim))
        return tc;
    double t = fmin(disc_bound(b, ax, ay, rho), disc_bound(b, cp[2], cp[3], rho));
    if (!(l > 0))
        return fmax(t, tc);
    double nx = -dy / l, ny = dx / l;
    double e2 = nx * b->p2x + ny * b->p2y, e1 = nx * b->p1x + ny * b->p1y;
    double e0 = nx * (b->p0x - ax) + ny * (b->p0y - ay);
    for (int sg = -1; sg <= 1; sg += 2) { /* g = sg n.(p - a) - rho: contact where g <= r */
        double g2 = sg * e2, g1 = sg * e1, g0 = sg * e0 - rho;
        if (b->kind == MA_PP) { /* g <= 0, or g^2 <= r^2 (a superset of g <= r) */
            double wx = b->p0x - b->fpx, wy = b->p0y - b->fpy;
            t = fmin(t, quad_entry(0.0, g1, g0, 0.0, INFINITY));
            t = fmin(t, quad_entry(g1 * g1 - (b->p1x * b->p1x + b->p1y * b->p1y),
                                   2 * (g0 * g1 - (b->p1x * wx + b->p1y * wy)),
                                   g0 * g0 - (wx * wx + wy * wy), 0.0, INFINITY));
        } else {
            t = fmin(t, quad_entry(g2 - b->r2c, g1 - b->r1c, g0 - b->r0c, 0.0, INFINITY));
        }
    }
    return fmax(t, tc); /* both are lower bounds */
}

/* Does the branch's pocket (ma_window) hold ring position s? */
static int win_holds(const ma_window *w, int64_t s)
{
    if (!w->active || s < w->lo || s >= w->hi)
        return 1;
    int64_t m = w->hi - w->lo;
    return ((s - w->from) % m + m) % m <= w->len;
}

/* Does it hold any of the positions [a, b) (a node's run)? */
static int win_meets(const ma_window *w, int64_t a, int64_t b)
{
    if (!w->active || a < w->lo || b > w->hi)
        return 1;
    if (w->from + w->len < w->hi) /* one run: from .. from + len */
        return a <= w->from + w->len && b > w->from;
    /* two runs: from .. hi - 1 and lo .. from + len - m */
    return b > w->from || a <= w->from + w->len - (w->hi - w->lo);
}

/* The first event in (0, T]: the least entry root of a non-excluded element, by a
 * best-first branch and bound over the index on node_bound (a node is opened only if the
 * moving disc may reach it before the best event so far).  INFINITY if none; -1 on
 * NOMEM. */
static double event_search(ma_ctx *C, const ma_bis *b, const int64_t *ex, int nex, double T)
{
    const ma_elems *E = &C->E;
    const ma_bvh *BV = &C->T;
    double best = INFINITY, lim = T;
    int64_t nh = 0;
    if (BV->nn == 0)
        return best;
    double tb0 = node_bound(b, BV->cap, C->eps, lim);
    if (!(tb0 < lim))
        return best;
    C->heapk[0] = tb0, C->heapn[0] = 0, nh = 1;
    while (nh > 0) {
        double key = C->heapk[0];
        int64_t nd = C->heapn[0];
        /* pop: move the last to the root and sift down */
        nh--;
        {
            double k = C->heapk[nh];
            int64_t v = C->heapn[nh], i = 0;
            for (;;) {
                int64_t c = 2 * i + 1;
                if (c >= nh)
                    break;
                if (c + 1 < nh && C->heapk[c + 1] < C->heapk[c])
                    c++;
                if (!(C->heapk[c] < k))
                    break;
                C->heapk[i] = C->heapk[c], C->heapn[i] = C->heapn[c], i = c;
            }
            C->heapk[i] = k, C->heapn[i] = v;
        }
        if (!(key < lim))
            break;
        if (BV->kid[2 * nd] < 0) {
            for (int64_t it = 0; it < BV->cnt[nd]; it++) {
                int64_t sg = BV->kid[2 * nd + 1] + it;
                if (!win_holds(&C->win, sg))
                    continue;
                for (int w = 0; w < 2; w++) {
                    int64_t e = w ? E->velem[sg] : sg;
                    if (e < 0)
                        continue;
                    int skip = 0;
                    for (int i = 0; i < nex; i++)
                        skip |= ex[i] == e;
                    if (skip)
                        continue;
                    double t = elem_entry(E, b, e, 0.0, lim);
                    if (t < best)
                        best = t, lim = t;
                }
            }
            continue;
        }
        for (int w = 0; w < 2; w++) {
            int64_t kd = BV->kid[2 * nd + w];
            if (!win_meets(&C->win, BV->beg[kd], BV->end[kd]))
                continue;
            double tk = node_bound(b, BV->cap + 5 * kd, C->eps, lim);
            if (!(tk < lim))
                continue;
            int64_t i = nh++; /* push: sift up (the heap holds at most all nodes) */
            while (i > 0 && tk < C->heapk[(i - 1) / 2]) {
                C->heapk[i] = C->heapk[(i - 1) / 2], C->heapn[i] = C->heapn[(i - 1) / 2];
                i = (i - 1) / 2;
            }
            C->heapk[i] = tk, C->heapn[i] = kd;
        }
    }
    return best;
}

/* An event found through an element that only grazes the disc (a near-double root) is off
 * by up to the square root of rounding: 1.4e-9 early at the centre of an 8 000-gon, where
 * 1 658 of its 8 000 edges were then within the gather distance and made a junction of
 * their own beside the true one (and each leaf near them was reached twice).  The root of
 * the element the disc meets most head-on (its foot most along the trace's direction)
 * among those touching the disc there is well conditioned: it is taken when it lies within
 * the arrival accuracy.  -1 on NOMEM. */
static double event_refine(ma_ctx *C, const ma_bis *b, const int64_t *ex, int nex, double te,
                           double T)
{
    const ma_elems *E = &C->E;
    double x, y, r, tx, ty;
    ma_bis_at(b, te, &x, &y, &r);
    ma_bis_tangent(b, te, &tx, &ty);
    C->cand.n = 0;
    if (!ma_bvh_collect(&C->T, (const double[4]){x, y, x, y}, r + C->gather, 0, &C->cand))
        return -1;
    int64_t best = -1;
    double bestv = -INFINITY;
    for (int64_t ci = 0; ci < 2 * C->cand.n; ci++) {
        int64_t sg = C->cand.v[ci / 2], e = ci % 2 ? E->velem[sg] : sg;
        int skip = e < 0;
        for (int i = 0; i < nex && !skip; i++)
            skip = ex[i] == e;
        if (skip || !(ma_elem_dist(E, e, x, y) <= r + C->gather))
            continue;
        double fx, fy;
        if (is_seg(E, e)) {
            double d = (x - E->ax[e]) * E->nx[e] + (y - E->ay[e]) * E->ny[e];
            fx = -d * E->nx[e], fy = -d * E->ny[e];
        } else {
            ma_vpoint(E, e, &fx, &fy);
            fx -= x, fy -= y;
        }
        double v = (tx * fx + ty * fy) / fmax(hypot(fx, fy), MA_TINY);
        if (v > bestv || (v == bestv && e < best))
            best = e, bestv = v;
    }
    if (best < 0)
        return te;
    double sx = b->p1x + 2 * b->p2x * te, sy = b->p1y + 2 * b->p2y * te;
    double w = C->arrive / fmax(hypot(sx, sy), MA_TINY);
    double t2 = elem_entry(E, b, best, fmax(0.0, te - w), fmin(T, te + w));
    return t2 < INFINITY ? t2 : te;
}

/* Appends the samples of b over (ta, tb] (the chord and interpolated radius within tol;
 * straight pieces with linear radius need only the end). */
static int sample_piece(ma_ctx *C, const ma_bis *b, double ta, double tb)
{
    double tm;
    if (ma_bis_split_at(b, ta, tb, C->tol, &tm)) /* each side of a point-point apex */
        return sample_piece(C, b, ta, tm) && sample_piece(C, b, tm, tb);
    double step = ma_bis_max_step(b, ta, tb, C->tol);
    int64_t k = 1;
    if (isfinite(step) && step > 0 && tb - ta > step)
        k = (int64_t)ceil((tb - ta) / step);
    if (k > 100000000)
        k = 100000000;
    for (int64_t i = 1; i <= k; i++) {
        double x, y, r;
        ma_bis_at(b, i == k ? tb : ta + (tb - ta) * (double)i / (double)k, &x, &y, &r);
        if (!push_sample(C, x, y, r))
            return 0;
    }
    return 1;
}

/* The foot of segment `who` reached its convex end (`how` 1: start, 2: end) at the last
 * sample p = (x, y, r).  At r = 0 (up to the arrival accuracy) that is the leaf.
 *
 * Above it, the segment beyond the corner (nxt) turns toward the disc and has entered it,
 * by r (1 - cos turn): a near-double root that the event search cannot see when the turn
 * is tiny (a circle's polygon rounded to a grid: 1e-14 rad; the inflections of the 10 000-
 * gon flower of issue 22: 2e-7 rad).  So p is a junction of the pair and nxt -- TR_CORNER,
 * ma_ctx.corner = (who, nxt) -- whose third branch, between who and nxt, runs straight
 * back to the corner.  (Taking p for the leaf -- appending the corner, r jumping from 187
 * to 0 -- left the branch from nxt's side without its junction: the same corner was
 * reached twice.)  A segment inside the disc by more than the arrival accuracy is a third
 * element the event search missed: TR_MISSED rather than a wrong junction. */
static int corner_leaf(ma_ctx *C, int64_t who, int how, const double p[3], double tx,
                       double ty, double ev[5], int64_t *leafv)
{
    const ma_elems *E = &C->E;
    double px = p[0], py = p[1], pr = p[2], acc = MA_EPS_ARRIVE * E->diag;
    int64_t k = how == 1 ? who : E->next[who]; /* the corner: the start of segment k */
    *leafv = k;
    if (pr <= acc) { /* at the corner up to the arrival accuracy: the corner itself */
        C->px.v[C->px.n - 1] = E->ax[k];
        C->py.v[C->py.n - 1] = E->ay[k];
        C->pr.v[C->pr.n - 1] = 0.0;
        return TR_LEAF;
    }
    C->cand.n = 0;
    if (!ma_bvh_collect(&C->T, (const double[4]){px, py, px, py}, pr - acc, 0, &C->cand))
        return TR_NOMEM;
    for (int64_t i = 0; i < C->cand.n; i++) {
        int64_t sg = C->cand.v[i], nx = E->next[sg];
        if (sg == k || sg == E->prev[k])
            continue;
        if (ma_pt_seg_d2(px, py, E->ax[sg], E->ay[sg], E->ax[nx], E->ay[nx]) < (pr - acc) * (pr - acc)) {
            ev[0] = px, ev[1] = py, ev[2] = pr;
            return TR_MISSED;
        }
    }
    ev[0] = px, ev[1] = py, ev[2] = pr, ev[3] = tx, ev[4] = ty;
    C->corner[0] = who;
    C->corner[1] = how == 1 ? E->prev[who] : E->next[who];
    *leafv = -1;
    return TR_CORNER;
}

/* Traces from s = (x, y, r) along the bisector of (e1, e2) in direction (dx, dy), appending
 * samples (the start too when `first`).  Each piece runs to the first of: an event (the
 * least exact entry root of a third element, searched in doubling parameter intervals
 * through the index), the closing of a window of the pair (a transition: the element is
 * switched, or at a convex corner the leaf or TR_CORNER), the leaf (r = 0).  On TR_EVENT and
 * TR_CORNER, ev = (x, y, r, tx, ty); on TR_LEAF *leafv = the convex vertex (or -1 if unknown). */
int ma_trace(ma_ctx *C, const ma_start *s, int first, double ev[5], int64_t *leafv)
{
    const ma_elems *E = &C->E;
    double x = s->x, y = s->y, r = s->r;
    ma_bis b;
    ma_bis_make(E, &b, s);
    if (first && !push_sample(C, x, y, r))
        return TR_NOMEM;
    *leafv = -1;
    /* every piece ends at an event or a window switch to another element: a branch along
     * a finely discretised arc has as many pieces as chords */
    for (int64_t piece = 0; piece < 4 * (E->ns + E->nv) + 16; piece++) {
        if (!isfinite(b.p0x) || !isfinite(b.p0y) || (b.kind == MA_PL && !(b.h > 0))) {
            /* a pair without a bisector on the interior side (a parabola whose focus is
             * not inside of its directrix): fail rather than output a wrong branch */
            ev[0] = (double)b.e1, ev[1] = (double)b.e2;
            return TR_BADPAIR;
        }
        int64_t ex[10], who = -1;
        int nex = excluded_set(E, &b, ex), how = 0;
        double tw = bis_window_exit(E, &b, 0.0, &who, &how);
        double tl = (b.kind == MA_LL && b.sg < 0) ? b.r0 : INFINITY; /* r = r0 - t */
        double T = fmin(tw, tl), te = event_search(C, &b, ex, nex, T);
        if (te < 0)
            return TR_NOMEM;
        if (te < INFINITY && te <= T) { /* an event */
            te = event_refine(C, &b, ex, nex, te, T);
            if (te < 0)
                return TR_NOMEM;
            if (!sample_piece(C, &b, 0.0, te))
                return TR_NOMEM;
            ma_bis_at(&b, te, &ev[0], &ev[1], &ev[2]);
            ma_bis_tangent(&b, te, &ev[3], &ev[4]);
            return TR_EVENT;
        }
        if (!(T < INFINITY))
            return TR_STUCK;
        if (tl <= tw) { /* the leaf: two edges meeting at a convex corner */
            if (!sample_piece(C, &b, 0.0, tl))
                return TR_NOMEM;
            C->pr.v[C->pr.n - 1] = 0.0;
            *leafv = E->next[b.e1] == b.e2 ? b.e2 : E->next[b.e2] == b.e1 ? b.e1 : -1;
            return TR_LEAF;
        }
        /* a window closes at tw */
        if (!sample_piece(C, &b, 0.0, tw))
            return TR_NOMEM;
        double tx, ty, phx, phy, phr;
        ma_bis_tangent(&b, tw, &tx, &ty);
        ma_bis_at(&b, tw, &phx, &phy, &phr);
        int64_t en = ma_window_switch(E, who, how);
        if (en < 0)
            return corner_leaf(C, who, how, (const double[3]){phx, phy, phr}, tx, ty, ev, leafv);
        int64_t ea = b.e1 == who ? en : b.e1, eb = b.e1 == who ? b.e2 : en;
        ma_bis_make(E, &b, &(ma_start){phx, phy, phr, ea, eb, tx, ty});
        for (int k = 0; k < 3; k++) { /* lesson 2: a double transition */
            double x1, y1, r1;
            ma_bis_at(&b, MA_EPS_STEP * E->diag, &x1, &y1, &r1);
            how = ma_bis_window(E, &b, x1, y1, &who);
            if (!how)
                break;
            en = ma_window_switch(E, who, how);
            if (en < 0)
                return corner_leaf(C, who, how, (const double[3]){phx, phy, phr}, tx, ty, ev,
                                   leafv);
            ea = b.e1 == who ? en : b.e1, eb = b.e1 == who ? b.e2 : en;
            ma_bis_make(E, &b, &(ma_start){phx, phy, phr, ea, eb, tx, ty});
        }
    }
    return TR_STUCK;
}
