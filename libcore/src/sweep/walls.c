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

static int cmp_double(const void *pa, const void *pb)
{
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* The walls along the edge u -> v: P is the polygon on its left (edge index ip), Q the one
 * on its right (edge index iq of v -> u) or -1. */
int sw_edge_walls(sw_ctx *c, sw_out *o, sw_walls *W, int64_t u, int64_t v, int64_t P,
                  int64_t ip, int64_t Q, int64_t iq)
{
    const sw_poly *polys[2] = {&c->polys[P], Q >= 0 ? &c->polys[Q] : NULL};
    int64_t nl = 0;
    for (int sd = 0; sd < 2; sd++)
        if (polys[sd])
            nl += 2 * polys[sd]->st.n;
    wline *lines = malloc((size_t)(nl + 1) * sizeof *lines);
    int64_t *starts = malloc((size_t)(nl + 1) * sizeof *starts);
    int64_t *ends = malloc((size_t)(nl + 1) * sizeof *ends);
    double *lenu = malloc((size_t)(nl + 1) * sizeof *lenu);
    double *lenv = malloc((size_t)(nl + 1) * sizeof *lenv);
    double *ev = malloc((size_t)(nl * nl + 2) * sizeof *ev);
    sw_bd *bd = malloc((size_t)(nl + 1) * sizeof *bd);
    if (!lines || !starts || !ends || !ev || !bd || !lenu || !lenv) {
        free(lenu);
        free(lenv);
        free(lines);
        free(starts);
        free(ends);
        free(ev);
        free(bd);
        return ctx_nomem(c);
    }
    int ok = 1;
    int64_t k = 0, narc[2] = {0, 0}, first_arc[2] = {0, 0};
    for (int sd = 0; sd < 2 && ok; sd++) {
        first_arc[sd] = k / 2;
        if (!polys[sd])
            continue;
        for (int64_t a = 0; a < polys[sd]->st.n && ok; a++) {
            const sw_arc *arc = &c->arcs[polys[sd]->st.first + a];
            for (int e = 0; e < 2; e++) {
                const sw_end *en = e ? &arc->end : &arc->start;
                wline *l = &lines[k];
                l->side = sd;
                l->isend = e;
                l->arc = a;
                l->cancelled = 0;
                l->va = sw_lift(c, o, u, en, e);
                l->vb = sw_lift(c, o, v, en, e);
                if (l->va < 0 || l->vb < 0) {
                    ok = 0;
                    break;
                }
                /* on the axis every angle is the same point: take the other end's */
                double fa = o->phi[l->va], fb = o->phi[l->vb];
                if (c->v2[u].r == 0)
                    fa = fb;
                if (c->v2[v].r == 0)
                    fb = fa;
                l->pa = fa;
                l->pb = l->pa + angle_diff(fb, l->pa);
                if (e)
                    ends[k / 2] = k;
                else
                    starts[k / 2] = k;
                ok = ok && ring_add(c, W, u, l->va) && ring_add(c, W, v, l->vb);
                k++;
            }
            if (ok) {
                /* the arc's length over u and v, unwrapped from its length at the sample */
                double L0 = arc->end.phi + c->theta - arc->start.phi;
                const wline *ls = &lines[k - 2], *le = &lines[k - 1];
                int64_t ai = k / 2 - 1;
                lenu[ai] = L0 + angle_diff(le->pa - ls->pa, L0);
                lenv[ai] = L0 + angle_diff(le->pb - ls->pb, L0);
            }
            narc[sd]++;
        }
    }
    /* the same line on both sides bounds nothing */
    for (int64_t i = 0; i < nl && ok; i++)
        for (int64_t j = 0; j < nl; j++)
            if (lines[i].side == 0 && lines[j].side == 1 && !lines[i].cancelled &&
                !lines[j].cancelled && lines[i].va == lines[j].va && lines[i].vb == lines[j].vb &&
                lines[i].isend == lines[j].isend) {
                lines[i].cancelled = lines[j].cancelled = 1;
                break;
            }
    /* events: where two lines cross */
    int64_t nev = 0;
    ev[nev++] = 0;
    for (int64_t i = 0; i < nl && ok; i++)
        for (int64_t j = 0; j < nl; j++) {
            /* any two lines: a polygon's own start and end lines cross where its arc
             * closes to a full turn (a fan piece astride a case-1.3 curve) */
            if (j <= i)
                continue; /* cancelled lines too: their arcs' closing still cuts faces */
            double f0 = lines[i].pa - lines[j].pa, f1 = lines[i].pb - lines[j].pb;
            double lo = fmin(f0, f1), hi = fmax(f0, f1);
            for (double m = ceil(lo / MFG_TWO_PI); m * MFG_TWO_PI <= hi; m += 1) {
                if (f1 == f0)
                    break;
                double s = (m * MFG_TWO_PI - f0) / (f1 - f0);
                if (s > 1e-9 && s < 1 - 1e-9)
                    ev[nev++] = s;
            }
        }
    ev[nev++] = 1;
    qsort(ev, (size_t)nev, sizeof *ev, cmp_double);
    int64_t m = 0;
    for (int64_t i = 0; i < nev; i++)
        if (m == 0 || ev[i] - ev[m - 1] > 1e-9)
            ev[m++] = ev[i];
    if (ev[m - 1] != 1)
        ev[m - 1] = 1;
    nev = m;
    /* event vertices: on every line's chord at every inner event (lines that meet there
     * share one) */
    int64_t ninner = nev - 2;
    int64_t *evv = malloc((size_t)(nl * (ninner > 0 ? ninner : 1) + 1) * sizeof *evv);
    int64_t *evr_first = malloc((size_t)(nev + 1) * sizeof *evr_first);
    if (!evv || !evr_first) {
        free(evv);
        free(evr_first);
        evv = NULL; /* freed again at the end */
        evr_first = NULL;
        ok = ctx_nomem(c);
    }
    const sw_vtx2 *wu = &c->v2[u], *wv = &c->v2[v];
    for (int64_t e = 1; e + 1 < nev && ok; e++) {
        double s = ev[e];
        evr_first[e] = W->nevring;
        for (int64_t i = 0; i < nl && ok; i++) {
            int64_t id = -1;
            double val = line_at(&lines[i], s);
            for (int64_t j = 0; j < i; j++)
                if (fabs(angle_diff(line_at(&lines[j], s), val)) < 1e-12) {
                    id = evv[j * ninner + e - 1];
                    break;
                }
            if (id < 0) {
                const double *a = c->ox + 3 * lines[i].va, *b = c->ox + 3 * lines[i].vb;
                double p[3] = {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                               a[2] + s * (b[2] - a[2])};
                id = sw_out_vertex(c, o, p, wrap_angle(atan2(p[1], p[0])));
                if (id < 0) {
                    ok = 0;
                    break;
                }
            }
            evv[i * ninner + e - 1] = id;
            if (!mfg_grow((void **)&W->evring, &W->capevring, W->nevring + 1, sizeof *W->evring)) {
                ok = ctx_nomem(c);
                break;
            }
            W->evring[W->nevring++] = id;
        }
    }
    if (ok)
        evr_first[nev - 1] = W->nevring;
    /* per polygon edge and line, the event vertices in the polygon's direction */
    for (int64_t i = 0; i < nl && ok && ninner > 0; i++) {
        int sd = lines[i].side;
        int64_t pid = sd ? Q : P, eid = sd ? iq : ip;
        hkey key = mkkey(pid, eid, 2 * lines[i].arc + lines[i].isend, 0);
        if (!mfg_grow((void **)&W->evl, &W->capevl, W->nevl + 2 * ninner + 1, sizeof *W->evl)) {
            ok = ctx_nomem(c);
            break;
        }
        if (!hmap_put(&W->evlists, &key, W->nevl)) {
            ok = ctx_nomem(c);
            break;
        }
        /* count, then (vertex, position along the polygon's edge as double bits) */
        W->evl[W->nevl++] = ninner;
        for (int64_t e = 0; e < ninner; e++) {
            int64_t ei = sd ? ninner - 1 - e : e;
            double sp = sd ? 1 - ev[ei + 1] : ev[ei + 1];
            W->evl[W->nevl++] = evv[i * ninner + ei];
            memcpy(&W->evl[W->nevl++], &sp, sizeof sp);
        }
    }
    /* strips between consecutive events */
    for (int64_t e = 0; e + 1 < nev && ok; e++) {
        double s0 = ev[e], s1 = ev[e + 1], sm = 0.5 * (s0 + s1);
        int64_t nb = 0;
        for (int64_t i = 0; i < nl; i++)
            if (!lines[i].cancelled) {
                bd[nb].phi = wrap_angle(line_at(&lines[i], sm));
                bd[nb].line = i;
                nb++;
            }
        qsort(bd, (size_t)nb, sizeof *bd, cmp_bd);
        int fullL = polys[0]->st.full, fullR = polys[1] ? polys[1]->st.full : 0;
        int64_t nseg = nb > 0 ? nb : 1;
        for (int64_t q = 0; q < nseg && ok; q++) {
            double a0, a1;
            if (nb > 0) {
                a0 = bd[q].phi;
                a1 = q + 1 < nb ? bd[q + 1].phi : bd[0].phi + MFG_TWO_PI;
                if (a1 - a0 <= 0)
                    continue;
            } else {
                a0 = 0;
                a1 = MFG_TWO_PI;
            }
            double ph = 0.5 * (a0 + a1);
            int cl = covered(lines, starts + first_arc[0], lenu + first_arc[0], lenv + first_arc[0],
                             narc[0], fullL, sm, ph);
            int cr = polys[1] ? covered(lines, starts + first_arc[1], lenu + first_arc[1],
                                        lenv + first_arc[1], narc[1], fullR, sm, ph)
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
                double dz = wv->z - wu->z;
                double nr = cl ? dz : -dz;
                if (nr > 0) {
                    if (!mfg_grow((void **)&W->push, &W->cappush, c->nv2, sizeof *W->push)) {
                        ok = ctx_nomem(c);
                        break;
                    }
                    W->push[u] = W->push[v] = 1;
                }
            }
            S->span_mid = a1 - a0;
            for (int end = 0; end < 2; end++) {
                double s = end ? s1 : s0;
                int64_t ei = end ? e + 1 : e;
                wend *we = &S->e[end];
                if (ei == 0 || ei == nev - 1) {
                    const sw_vtx2 *w = ei == 0 ? wu : wv;
                    we->v2 = ei == 0 ? u : v;
                    we->r = w->r;
                    we->z = w->z;
                    we->ring_first = we->ring_n = 0;
                    if (!S->full) {
                        const wline *llo = &lines[bd[q].line], *lhi = &lines[bd[(q + 1) % nb].line];
                        we->lo = ei == 0 ? llo->va : llo->vb;
                        we->hi = ei == 0 ? lhi->va : lhi->vb;
                    }
                } else {
                    we->v2 = -1;
                    we->r = wu->r + s * (wv->r - wu->r);
                    we->z = wu->z + s * (wv->z - wu->z);
                    we->ring_first = evr_first[ei];
                    we->ring_n = evr_first[ei + 1] - evr_first[ei];
                    if (!S->full) {
                        we->lo = evv[bd[q].line * ninner + ei - 1];
                        we->hi = evv[bd[(q + 1) % nb].line * ninner + ei - 1];
                    }
                }
            }
        }
    }
    free(evv);
    free(evr_first);
    free(lenu);
    free(lenv);
    free(lines);
    free(starts);
    free(ends);
    free(ev);
    free(bd);
    return ok;
}
