/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/walls.c - Walls: the swept surfaces of revolution along the decomposition's edges
 * where exactly one side covers an angle.  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

static double line_at(const wline *l, double s)
{
    return l->pa + s * (l->pb - l->pa);
}

/* Does a side cover angle phi at s?  Arc a runs from its start line over a length that
 * varies linearly from lenu[a] (over u) to lenv[a] (over v): lengths are unwrapped from
 * the polygon's own sample, so an arc that closes to a full turn along the edge (its end
 * passing its start) covers everything instead of a sliver. */
static int covered(const wline *lines, const int64_t *starts, const double *lenu,
                   const double *lenv, int64_t narc, int full, double s, double phi)
{
    if (full)
        return 1;
    for (int64_t a = 0; a < narc; a++) {
        double len = lenu[a] + s * (lenv[a] - lenu[a]);
        if (len >= MFG_TWO_PI)
            return 1;
        if (len <= 0)
            continue;
        double st = line_at(&lines[starts[a]], s);
        if (wrap_angle(phi - st) <= len)
            return 1;
    }
    return 0;
}

static int ring_add(sw_ctx *c, sw_walls *W, int64_t v2, int64_t vid)
{
    if (!mfg_grow((void **)&W->rv2, &W->capring, W->nring + 1, sizeof *W->rv2) ||
        !mfg_grow((void **)&W->rvid, &W->capring2, W->nring + 1, sizeof *W->rvid))
        return ctx_nomem(c);
    W->rv2[W->nring] = v2;
    W->rvid[W->nring] = vid;
    W->nring++;
    return 1;
}

typedef struct sw_bd {
    double phi;
    int64_t line;
} sw_bd;

static int cmp_bd(const void *pa, const void *pb)
{
    const sw_bd *a = pa, *b = pb;
    return (a->phi > b->phi) - (a->phi < b->phi);
}

/* One edge u -> v of the decomposition between polygon P (its edge ip) on the left and Q
 * (edge iq, or -1) on the right, while sw_edge_walls builds its walls: the lines of the
 * arcs' ends over it, the events where lines cross, the event vertices. */
typedef struct {
    int64_t u, v, P, ip, Q, iq;
    const sw_poly *polys[2];
    const sw_vtx2 *wu, *wv;
    int64_t nl;                    /* lines: 2 per arc of each side */
    wline *lines;
    int64_t *starts, *ends;        /* per arc: its start and end line */
    double *lenu, *lenv;           /* per arc: its length over u and over v */
    int64_t narc[2], first_arc[2];
    double *ev;                    /* events: positions along u -> v in [0, 1] */
    int64_t nev, ninner;
    sw_bd *bd;
    int64_t *evv;                  /* per line and inner event: the event vertex */
    int64_t *evr_first;            /* per event: its vertices in W->evring */
} sw_edgewall;

static void edgewall_free(sw_edgewall *X)
{
    free(X->evv);
    free(X->evr_first);
    free(X->lenu);
    free(X->lenv);
    free(X->lines);
    free(X->starts);
    free(X->ends);
    free(X->ev);
    free(X->bd);
}

/* The lines over the edge: each arc end of each side lifted over u and over v. */
static int edge_lines(sw_ctx *c, sw_out *o, sw_walls *W, sw_edgewall *X)
{
    int ok = 1;
    int64_t k = 0;
    for (int sd = 0; sd < 2 && ok; sd++) {
        X->first_arc[sd] = k / 2;
        if (!X->polys[sd])
            continue;
        for (int64_t a = 0; a < X->polys[sd]->st.n && ok; a++) {
            const sw_arc *arc = &c->arcs[X->polys[sd]->st.first + a];
            for (int e = 0; e < 2; e++) {
                const sw_end *en = e ? &arc->end : &arc->start;
                wline *l = &X->lines[k];
                l->side = sd;
                l->isend = e;
                l->arc = a;
                l->cancelled = 0;
                l->va = sw_lift(c, o, X->u, en, e);
                l->vb = sw_lift(c, o, X->v, en, e);
                if (l->va < 0 || l->vb < 0) {
                    ok = 0;
                    break;
                }
                /* on the axis every angle is the same point: take the other end's */
                double fa = o->phi[l->va], fb = o->phi[l->vb];
                if (c->v2[X->u].r == 0)
                    fa = fb;
                if (c->v2[X->v].r == 0)
                    fb = fa;
                l->pa = fa;
                l->pb = l->pa + angle_diff(fb, l->pa);
                if (e)
                    X->ends[k / 2] = k;
                else
                    X->starts[k / 2] = k;
                ok = ok && ring_add(c, W, X->u, l->va) && ring_add(c, W, X->v, l->vb);
                k++;
            }
            if (ok) {
                /* the arc's length over u and v, unwrapped from its length at the sample */
                double L0 = arc->end.phi + c->theta - arc->start.phi;
                const wline *ls = &X->lines[k - 2], *le = &X->lines[k - 1];
                int64_t ai = k / 2 - 1;
                X->lenu[ai] = L0 + angle_diff(le->pa - ls->pa, L0);
                X->lenv[ai] = L0 + angle_diff(le->pb - ls->pb, L0);
            }
            X->narc[sd]++;
        }
    }
    return ok;
}

/* Lines on both sides that are one cancel; events where two lines cross (X->ev, X->nev). */
static int edge_events(sw_edgewall *X, int ok)
{
    /* the same line on both sides bounds nothing */
    for (int64_t i = 0; i < X->nl && ok; i++)
        for (int64_t j = 0; j < X->nl; j++)
            if (X->lines[i].side == 0 && X->lines[j].side == 1 && !X->lines[i].cancelled &&
                !X->lines[j].cancelled && X->lines[i].va == X->lines[j].va && X->lines[i].vb == X->lines[j].vb &&
                X->lines[i].isend == X->lines[j].isend) {
                X->lines[i].cancelled = X->lines[j].cancelled = 1;
                break;
            }
    /* events: where two lines cross */
    X->nev = 0;
    X->ev[X->nev++] = 0;
    for (int64_t i = 0; i < X->nl && ok; i++)
        for (int64_t j = 0; j < X->nl; j++) {
            /* any two lines: a polygon's own start and end lines cross where its arc
             * closes to a full turn (a fan piece astride a case-1.3 curve) */
            if (j <= i)
                continue; /* cancelled lines too: their arcs' closing still cuts faces */
            double f0 = X->lines[i].pa - X->lines[j].pa, f1 = X->lines[i].pb - X->lines[j].pb;
            double lo = fmin(f0, f1), hi = fmax(f0, f1);
            for (double m = ceil(lo / MFG_TWO_PI); m * MFG_TWO_PI <= hi; m += 1) {
                if (f1 == f0)
                    break;
                double s = (m * MFG_TWO_PI - f0) / (f1 - f0);
                if (s > SW_EPS_PARAM && s < 1 - SW_EPS_PARAM)
                    X->ev[X->nev++] = s;
            }
        }
    X->ev[X->nev++] = 1;
    qsort(X->ev, (size_t)X->nev, sizeof *X->ev, sw_cmp_double_asc);
    int64_t m = 0;
    for (int64_t i = 0; i < X->nev; i++)
        if (m == 0 || X->ev[i] - X->ev[m - 1] > SW_EPS_PARAM)
            X->ev[m++] = X->ev[i];
    if (X->ev[m - 1] != 1)
        X->ev[m - 1] = 1;
    X->nev = m;
    return ok;
}

/* The event vertices and their circles (W->evring). */
static int event_vertices(sw_ctx *c, sw_out *o, sw_walls *W, sw_edgewall *X, int ok)
{
    /* event vertices: on every line's chord at every inner event (lines that meet there
     * share one) */
    X->ninner = X->nev - 2;
    X->evv = malloc((size_t)(X->nl * (X->ninner > 0 ? X->ninner : 1) + 1) * sizeof *X->evv);
    X->evr_first = malloc((size_t)(X->nev + 1) * sizeof *X->evr_first);
    if (!X->evv || !X->evr_first) {
        free(X->evv);
        free(X->evr_first);
        X->evv = NULL; /* freed again at the end */
        X->evr_first = NULL;
        ok = ctx_nomem(c);
    }
    for (int64_t e = 1; e + 1 < X->nev && ok; e++) {
        double s = X->ev[e];
        X->evr_first[e] = W->nevring;
        for (int64_t i = 0; i < X->nl && ok; i++) {
            int64_t id = -1;
            double val = line_at(&X->lines[i], s);
            for (int64_t j = 0; j < i; j++)
                if (fabs(angle_diff(line_at(&X->lines[j], s), val)) < SW_EPS_ANGLE_ROUND) {
                    id = X->evv[j * X->ninner + e - 1];
                    break;
                }
            if (id < 0) {
                const double *a = c->ox + 3 * X->lines[i].va, *b = c->ox + 3 * X->lines[i].vb;
                double p[3] = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                               a[2] + s * (b[2] - a[2])};
                id = sw_out_vertex(c, o, p, wrap_angle(atan2(p[1], p[0])));
                if (id < 0) {
                    ok = 0;
                    break;
                }
            }
            X->evv[i * X->ninner + e - 1] = id;
            if (!mfg_grow((void **)&W->evring, &W->capevring, W->nevring + 1, sizeof *W->evring)) {
                ok = ctx_nomem(c);
                break;
            }
            W->evring[W->nevring++] = id;
        }
    }
    if (ok)
        X->evr_first[X->nev - 1] = W->nevring;
    return ok;
}

/* Per polygon edge and line, the event vertices in the polygon's direction (W->evlists). */
static int event_lists(sw_ctx *c, sw_walls *W, sw_edgewall *X, int ok)
{
    /* per polygon edge and line, the event vertices in the polygon's direction */
    for (int64_t i = 0; i < X->nl && ok && X->ninner > 0; i++) {
        int sd = X->lines[i].side;
        int64_t pid = sd ? X->Q : X->P, eid = sd ? X->iq : X->ip;
        hkey key = mkkey(pid, eid, 2 * X->lines[i].arc + X->lines[i].isend, 0);
        if (!mfg_grow((void **)&W->evl, &W->capevl, W->nevl + 2 * X->ninner + 1, sizeof *W->evl)) {
            ok = ctx_nomem(c);
            break;
        }
        if (!hmap_put(&W->evlists, &key, W->nevl)) {
            ok = ctx_nomem(c);
            break;
        }
        /* count, then (vertex, position along the polygon's edge as double bits) */
        W->evl[W->nevl++] = X->ninner;
        for (int64_t e = 0; e < X->ninner; e++) {
            int64_t ei = sd ? X->ninner - 1 - e : e;
            double sp = sd ? 1 - X->ev[ei + 1] : X->ev[ei + 1];
            W->evl[W->nevl++] = X->evv[i * X->ninner + ei];
            memcpy(&W->evl[W->nevl++], &sp, sizeof sp);
        }
    }
    return ok;
}

/* The wall strips between consecutive events, where exactly one side covers an angle. */
static int edge_strips(sw_ctx *c, sw_walls *W, sw_edgewall *X, int ok)
{
    /* strips between consecutive events */
    for (int64_t e = 0; e + 1 < X->nev && ok; e++) {
        double s0 = X->ev[e], s1 = X->ev[e + 1], sm = 0.5 * (s0 + s1);
        int64_t nb = 0;
        for (int64_t i = 0; i < X->nl; i++)
            if (!X->lines[i].cancelled) {
                X->bd[nb].phi = wrap_angle(line_at(&X->lines[i], sm));
                X->bd[nb].line = i;
                nb++;
            }
        qsort(X->bd, (size_t)nb, sizeof *X->bd, cmp_bd);
        int fullL = X->polys[0]->st.full, fullR = X->polys[1] ? X->polys[1]->st.full : 0;
        int64_t nseg = nb > 0 ? nb : 1;
        for (int64_t q = 0; q < nseg && ok; q++) {
            double a0, a1;
            if (nb > 0) {
                a0 = X->bd[q].phi;
                a1 = q + 1 < nb ? X->bd[q + 1].phi : X->bd[0].phi + MFG_TWO_PI;
                if (a1 - a0 <= 0)
                    continue;
            } else {
                a0 = 0;
                a1 = MFG_TWO_PI;
            }
            double ph = 0.5 * (a0 + a1);
            int cl = covered(X->lines, X->starts + X->first_arc[0], X->lenu + X->first_arc[0], X->lenv + X->first_arc[0],
                             X->narc[0], fullL, sm, ph);
            int cr = X->polys[1] ? covered(X->lines, X->starts + X->first_arc[1], X->lenu + X->first_arc[1],
                                        X->lenv + X->first_arc[1], X->narc[1], fullR, sm, ph)
                              : 0;
            if (cl == cr)
                continue;
            if (!mfg_grow((void **)&W->strips, &W->capstrips, W->nstrips + 1, sizeof *W->strips)) {
                ok = ctx_nomem(c);
                break;
            }
            wstrip *S = &W->strips[W->nstrips++];
            S->full = nb == 0;
            S->left_covers = cl;
            {
                /* an outer wall (its outward normal points away from the axis): the
                 * chords of its circles would cut into SV; mark them to circumscribe */
                double dz = X->wv->z - X->wu->z;
                double nr = cl ? dz : -dz;
                if (nr > 0) {
                    if (!mfg_grow((void **)&W->push, &W->cappush, c->nv2, sizeof *W->push)) {
                        ok = ctx_nomem(c);
                        break;
                    }
                    W->push[X->u] = W->push[X->v] = 1;
                }
            }
            S->span_mid = a1 - a0;
            for (int end = 0; end < 2; end++) {
                double s = end ? s1 : s0;
                int64_t ei = end ? e + 1 : e;
                wend *we = &S->e[end];
                if (ei == 0 || ei == X->nev - 1) {
                    const sw_vtx2 *w = ei == 0 ? X->wu : X->wv;
                    we->v2 = ei == 0 ? X->u : X->v;
                    we->r = w->r;
                    we->z = w->z;
                    we->ring_first = we->ring_n = 0;
                    if (!S->full) {
                        const wline *llo = &X->lines[X->bd[q].line], *lhi = &X->lines[X->bd[(q + 1) % nb].line];
                        we->lo = ei == 0 ? llo->va : llo->vb;
                        we->hi = ei == 0 ? lhi->va : lhi->vb;
                    }
                } else {
                    we->v2 = -1;
                    we->r = X->wu->r + s * (X->wv->r - X->wu->r);
                    we->z = X->wu->z + s * (X->wv->z - X->wu->z);
                    we->ring_first = X->evr_first[ei];
                    we->ring_n = X->evr_first[ei + 1] - X->evr_first[ei];
                    if (!S->full) {
                        we->lo = X->evv[X->bd[q].line * X->ninner + ei - 1];
                        we->hi = X->evv[X->bd[(q + 1) % nb].line * X->ninner + ei - 1];
                    }
                }
            }
        }
    }
    return ok;
}

/* The walls along the edge u -> v: P is the polygon on its left (edge index ip), Q the one
 * on its right (edge index iq of v -> u) or -1. */
int sw_edge_walls(sw_ctx *c, sw_out *o, sw_walls *W, int64_t u, int64_t v, int64_t P,
                  int64_t ip, int64_t Q, int64_t iq)
{
    sw_edgewall X;
    memset(&X, 0, sizeof X);
    X.u = u, X.v = v, X.P = P, X.ip = ip, X.Q = Q, X.iq = iq;
    X.polys[0] = &c->polys[P];
    X.polys[1] = Q >= 0 ? &c->polys[Q] : NULL;
    X.wu = &c->v2[u], X.wv = &c->v2[v];
    const sw_poly *const *polys = X.polys;
    for (int sd = 0; sd < 2; sd++)
        if (polys[sd])
            X.nl += 2 * polys[sd]->st.n;
    X.lines = malloc((size_t)(X.nl + 1) * sizeof *X.lines);
    X.starts = malloc((size_t)(X.nl + 1) * sizeof *X.starts);
    X.ends = malloc((size_t)(X.nl + 1) * sizeof *X.ends);
    X.lenu = malloc((size_t)(X.nl + 1) * sizeof *X.lenu);
    X.lenv = malloc((size_t)(X.nl + 1) * sizeof *X.lenv);
    X.ev = malloc((size_t)(X.nl * X.nl + 2) * sizeof *X.ev);
    X.bd = malloc((size_t)(X.nl + 1) * sizeof *X.bd);
    if (!X.lines || !X.starts || !X.ends || !X.ev || !X.bd || !X.lenu || !X.lenv) {
        edgewall_free(&X);
        return ctx_nomem(c);
    }
    int ok = edge_lines(c, o, W, &X);
    ok = edge_events(&X, ok);
    ok = event_vertices(c, o, W, &X, ok);
    ok = event_lists(c, W, &X, ok);
    ok = edge_strips(c, W, &X, ok);
    edgewall_free(&X);
    return ok;
}
