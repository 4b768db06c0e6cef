/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/wallmesh.c - Walls: tessellation: wall strips tessellated on each circle (per-
 * radius grid plus arc ends) and the face pieces over each polygon.  Overview and file
 * map: sweep/sweep.h. */
#include "sweep/sweep.h"

typedef struct sw_pl {
    int64_t vid;
    double off;
    int grid;              /* a grid vertex of an outer wall's circumscribed polygon */
} sw_pl;

static int cmp_pl(const void *pa, const void *pb)
{
    const sw_pl *a = pa, *b = pb;
    return sw_cmp_key(a->off, b->off, a->vid, b->vid);
}

/* The vertices of one end of a strip, in increasing angle from lo to hi (a full turn for
 * full strips, closed by repeating the first), with offsets normalised to [0, 1]. */
static int end_polyline(sw_ctx *c, sw_out *o, const sw_walls *W, const wend *we, int full,
                        double span_mid, sw_pl **out, int64_t *nout, int64_t *capout)
{
    *nout = 0;
    sw_vtx2 w;
    memset(&w, 0, sizeof w);
    w.r = we->r;
    w.z = we->z;
    if (we->r == 0) {
        int64_t id = sw_ring_vertex(c, o, &w, 0);
        if (id < 0)
            return 0;
        if (!mfg_grow((void **)out, capout, 2, sizeof **out))
            return ctx_nomem(c);
        (*out)[0].vid = id;
        (*out)[0].off = 0;
        *nout = 1;
        return 1;
    }
    double plo, span;
    int64_t lo, hi;
    int lo_grid = 0; /* a full ring starting at the grid vertex at angle 0 */
    if (full) {
        sw_vtx2 w0 = w;
        if (we->v2 >= 0 && W->push[we->v2])
            w0.r = w.r / cos(MFG_PI / (double)sw_ring_steps(c, we->r));
        /* the ring starts at angle 0, or at the vertex already there: the other strips
         * on this circle drop the grid vertex at an angle where a line ends (below), and
         * on an outer wall's circle the two are not one point (a 4-edge hole next to the
         * apex of the tetrahedron about its edge) */
        lo = -1;
        int64_t nr = we->v2 >= 0 ? W->ring_start[we->v2 + 1] - W->ring_start[we->v2] : we->ring_n;
        for (int64_t i = 0; i < nr && lo < 0; i++) {
            int64_t vid = we->v2 >= 0 ? W->rvid[W->ring_start[we->v2] + i] : W->evring[we->ring_first + i];
            if (fabs(angle_diff(o->phi[vid], 0)) <= SW_EPS_ANGLE)
                lo = vid;
        }
        if (lo < 0) {
            lo = sw_ring_vertex(c, o, &w0, 0);
            lo_grid = 1;
        }
        hi = lo;
        if (lo < 0)
            return 0;
        plo = 0;
        span = MFG_TWO_PI;
    } else {
        lo = we->lo;
        hi = we->hi;
        plo = o->phi[lo];
        span = span_mid + angle_diff(o->phi[hi] - plo, span_mid);
        if (span < 0 || lo == hi)
            span = 0;
        /* one arc whose gap closes at this end (the paper's case 1.3 on a gap-closing
         * curve): its two lines share the vertex, and the arc is the whole circle */
        if (lo == hi && span_mid > MFG_PI)
            span = MFG_TWO_PI;
        if (span > MFG_TWO_PI)
            span = MFG_TWO_PI;
    }
    int64_t nsteps = sw_ring_steps(c, we->r);
    int64_t cand_n = we->v2 >= 0 ? W->ring_start[we->v2 + 1] - W->ring_start[we->v2] : we->ring_n;
    int64_t cap_need = cand_n + nsteps + 4;
    if (!mfg_grow((void **)out, capout, cap_need, sizeof **out))
        return ctx_nomem(c);
    sw_pl *pl = *out;
    int64_t n = 0;
    int pushed = we->v2 >= 0 && W->push[we->v2];
    memset(pl, 0, (size_t)cap_need * sizeof *pl);
    lo_grid = lo_grid && pushed;
    pl[n].vid = lo;
    pl[n].grid = lo_grid;
    pl[n++].off = 0;
    const double dtiny = SW_EPS_ANGLE;
    if (span > 0) {
        for (int64_t i = 0; i < cand_n; i++) {
            int64_t vid = we->v2 >= 0 ? W->rvid[W->ring_start[we->v2] + i] : W->evring[we->ring_first + i];
            if (vid == lo || vid == hi)
                continue;
            double off = wrap_angle(o->phi[vid] - plo);
            if (off > 0 && off < span && off < MFG_TWO_PI - SW_EPS_ANGLE_ROUND)
                pl[n].vid = vid, pl[n++].off = off;
        }
        /* grid vertices of an outer wall's circle lie on the circumscribed polygon */
        sw_vtx2 wg = w;
        if (we->v2 >= 0 && W->push[we->v2])
            wg.r = w.r / cos(MFG_PI / (double)nsteps);
        for (int64_t j = 0; j < nsteps; j++) {
            double ang = MFG_TWO_PI * (double)j / (double)nsteps;
            double off = wrap_angle(ang - plo);
            if (off > dtiny && off < span - dtiny) {
                /* a grid angle at an arc end on this circle is that end's vertex (which
                 * every strip here uses): no second vertex at one angle */
                int clash = 0;
                for (int64_t i = 0; i < cand_n && !clash; i++) {
                    int64_t vid = we->v2 >= 0 ? W->rvid[W->ring_start[we->v2] + i]
                                              : W->evring[we->ring_first + i];
                    clash = fabs(angle_diff(o->phi[vid], ang)) <= dtiny;
                }
                if (clash)
                    continue;
                int64_t id = sw_ring_vertex(c, o, &wg, ang);
                if (id < 0)
                    return 0;
                pl[n].vid = id;
                pl[n].grid = pushed;
                pl[n++].off = off;
            }
        }
        pl[n].vid = hi;
        pl[n].grid = lo_grid; /* a full ring ends where it starts */
        pl[n++].off = span;
    } else if (hi != lo) {
        /* two lines meeting (within rounding) at this end: a strip end of no width still
         * has both vertices, which the faces along the lines use */
        pl[n].vid = hi;
        pl[n++].off = 1;
        span = 1;
    }
    qsort(pl, (size_t)n, sizeof *pl, cmp_pl);
    /* drop repeats, normalise */
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++)
        if (m == 0 || pl[i].vid != pl[m - 1].vid)
            pl[m++] = pl[i];
    if (pushed && span > 0 && m > 1) {
        /* An outer wall's circle between two vertices that are not both grid vertices
         * of the circumscribed polygon: an arc end lies on the circle itself, so the
         * chord to its neighbour cuts into SV (an arc shorter than one grid step had
         * only its chord: the box about an edge turned by 1 deg held less than SV).
         * The point where the tangents there meet (at an arc end: the circle's tangent;
         * at a grid vertex: the polygon's side, tangent half a step away) goes in
         * between.  It depends only on the two vertices, which every strip using this
         * stretch of the circle has consecutive, so they all get it. */
        if (!mfg_grow((void **)out, capout, 2 * m + 2, sizeof **out))
            return ctx_nomem(c);
        pl = *out;
        int64_t mm = m;
        double half = MFG_PI / (double)nsteps;
        sw_pl *ins = malloc((size_t)(mm + 1) * sizeof *ins);
        if (!ins)
            return ctx_nomem(c);
        int64_t nins = 0;
        for (int64_t i = 0; i + 1 < mm; i++) {
            if (pl[i].grid && pl[i + 1].grid)
                continue;
            double t0 = pl[i].off + (pl[i].grid ? half : 0);
            double t1 = pl[i + 1].off - (pl[i + 1].grid ? half : 0);
            if (!(t1 - t0 > dtiny))
                continue;
            sw_vtx2 wx = w;
            wx.r = w.r / cos(0.5 * (t1 - t0));
            int64_t id = sw_ring_vertex(c, o, &wx, plo + 0.5 * (t0 + t1));
            if (id < 0) {
                free(ins);
                return 0;
            }
            ins[nins].vid = id;
            ins[nins].off = 0.5 * (t0 + t1);
            ins[nins++].grid = 0;
        }
        for (int64_t i = 0; i < nins; i++)
            pl[m++] = ins[i];
        free(ins);
        qsort(pl, (size_t)m, sizeof *pl, cmp_pl);
        /* a point welded to a neighbour (a circle of a radius near the weld quantum) */
        int64_t m2 = 0;
        for (int64_t i = 0; i < m; i++)
            if (m2 == 0 || pl[i].vid != pl[m2 - 1].vid)
                pl[m2++] = pl[i];
        m = m2;
    }
    for (int64_t i = 0; i < m; i++)
        pl[i].off = span > 0 ? pl[i].off / span : 0;
    if (m > 1)
        pl[m - 1].off = 1;
    *nout = m;
    return 1;
}

static int cmp_ring(const void *pa, const void *pb)
{
    const int64_t *a = pa, *b = pb;
    if (a[0] != b[0])
        return (a[0] > b[0]) - (a[0] < b[0]);
    return (a[1] > b[1]) - (a[1] < b[1]);
}

int sw_emit_strips(sw_ctx *c, sw_out *o, sw_walls *W)
{
    /* ring entries sorted by 2-D vertex, without repeats */
    int64_t n = W->nring;
    int64_t *pairs = malloc((size_t)(2 * n + 2) * sizeof *pairs);
    W->ring_start = calloc((size_t)(c->nv2 + 2), sizeof *W->ring_start);
    if (!pairs || !W->ring_start) {
        free(pairs);
        return ctx_nomem(c);
    }
    for (int64_t i = 0; i < n; i++) {
        pairs[2 * i] = W->rv2[i];
        pairs[2 * i + 1] = W->rvid[i];
    }
    qsort(pairs, (size_t)n, 2 * sizeof *pairs, cmp_ring);
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++)
        if (m == 0 || pairs[2 * i] != W->rv2[m - 1] || pairs[2 * i + 1] != W->rvid[m - 1]) {
            W->rv2[m] = pairs[2 * i];
            W->rvid[m] = pairs[2 * i + 1];
            m++;
        }
    free(pairs);
    W->nring = m;
    for (int64_t i = 0; i < m; i++)
        W->ring_start[W->rv2[i] + 1]++;
    for (int64_t v = 0; v < c->nv2; v++)
        W->ring_start[v + 1] += W->ring_start[v];
    sw_pl *A = NULL, *B = NULL;
    int64_t na = 0, nb = 0, capa = 0, capb = 0;
    int ok = 1;
    for (int64_t si = 0; si < W->nstrips && ok; si++) {
        const wstrip *S = &W->strips[si];
        ok = end_polyline(c, o, W, &S->e[0], S->full, S->span_mid, &A, &na, &capa) &&
             end_polyline(c, o, W, &S->e[1], S->full, S->span_mid, &B, &nb, &capb);
        if (!ok)
            break;
        if (S->full) {
            /* close the rings: the first vertex again at offset 1 */
            if (na > 1) {
                if (!mfg_grow((void **)&A, &capa, na + 1, sizeof *A)) { ok = ctx_nomem(c); break; }
                A[na] = A[0];
                A[na++].off = 1;
            }
            if (nb > 1) {
                if (!mfg_grow((void **)&B, &capb, nb + 1, sizeof *B)) { ok = ctx_nomem(c); break; }
                B[nb] = B[0];
                B[nb++].off = 1;
            }
        }
        int64_t i = 0, j = 0;
        while (ok && (i + 1 < na || j + 1 < nb)) {
            int adv_a;
            if (i + 1 >= na)
                adv_a = 0;
            else if (j + 1 >= nb)
                adv_a = 1;
            else if (A[i + 1].off != B[j + 1].off)
                adv_a = A[i + 1].off < B[j + 1].off;
            else {
                /* both ends step at one angle: the quad's diagonal through its smallest
                 * vertex, whichever end is A, so that a copy of this strip with the
                 * opposite orientation (a wall met by its own copy) gets the same two
                 * triangles and cancel_twins removes the pair */
                int64_t mn = A[i].vid;
                if (A[i + 1].vid < mn)
                    mn = A[i + 1].vid;
                if (B[j].vid < mn)
                    mn = B[j].vid;
                if (B[j + 1].vid < mn)
                    mn = B[j + 1].vid;
                adv_a = mn == A[i + 1].vid || mn == B[j].vid;
            }
            int64_t t0 = A[i].vid, t1 = B[j].vid, t2 = adv_a ? A[i + 1].vid : B[j + 1].vid;
            /* the circle edge of this triangle and the wall's direction off it */
            int64_t ra = adv_a ? A[i].vid : B[j].vid, rb = t2;
            double dir = adv_a ? atan2(S->e[1].z - S->e[0].z, S->e[1].r - S->e[0].r)
                               : atan2(S->e[0].z - S->e[1].z, S->e[0].r - S->e[1].r);
            /* (A_i, B_j, next) has its normal to the left of u -> v: outward when the right
             * side covers the strip */
            if (S->left_covers)
                ok = sw_emit_tri_ring(c, t0, t2, t1, ra, rb, dir);
            else
                ok = sw_emit_tri_ring(c, t0, t1, t2, ra, rb, dir);
            if (adv_a)
                i++;
            else
                j++;
        }
    }
    free(A);
    free(B);
    return ok;
}

/* The start (entry at t = 0) and end (exit turned by theta) faces over every polygon. */
#define SW_MAXARCS_FACE 64

int sw_emit_faces(sw_ctx *c, sw_out *o, sw_walls *W)
{
    int64_t *loop = NULL, nloop = 0, caploop = 0;
    int64_t *face = NULL, capface = 0;
    int ok = 1;
    for (int64_t pi = 0; pi < c->npolys && ok; pi++) {
        const sw_poly *P = &c->polys[pi];
        /* The boundary of the polygon with its event points: at each point the start and
         * end vertex of every arc.  A face stops where the gap before it closes (the end
         * of the previous arc turned by theta reaches this arc's start; for a single arc,
         * its own end): the two lines share a vertex there, and the start face and the end
         * face meet in the crease of the paper's case 1.3. */
        int64_t na = P->st.n;
        if (na == 0)
            continue;
        int64_t w = 2 * na;
        nloop = 0;
        for (int64_t i = 0; i < P->n && ok; i++) {
            int64_t w0 = c->poly_verts[P->first + i];
            int64_t ne = -1;
            int64_t at[2 * SW_MAXARCS_FACE];
            if (na > SW_MAXARCS_FACE) {
                ok = 0;
                c->st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: more than %d arcs on one circle",
                                 SW_MAXARCS_FACE);
                break;
            }
            for (int64_t l = 0; l < w; l++) {
                hkey key = mkkey(pi, i, l, 0);
                at[l] = hmap_get(&W->evlists, &key);
                int64_t cnt = at[l] >= 0 ? W->evl[at[l]] : 0;
                if (ne < 0 || cnt < ne)
                    ne = cnt;
            }
            if (!mfg_grow((void **)&loop, &caploop, w * (nloop + ne + 1), sizeof *loop)) {
                ok = ctx_nomem(c);
                break;
            }
            for (int64_t l = 0; l < w && ok; l++) {
                const sw_arc *arc = &c->arcs[P->st.first + l / 2];
                const sw_end *en = (l & 1) ? &arc->end : &arc->start;
                int64_t id = sw_lift(c, o, w0, en, (int)(l & 1));
                if (id < 0)
                    ok = 0;
                loop[w * nloop + l] = id;
            }
            nloop++;
            for (int64_t q = 0; q < ne && ok; q++) {
                for (int64_t l = 0; l < w; l++)
                    loop[w * nloop + l] = W->evl[at[l] + 1 + 2 * q];
                nloop++;
            }
        }
        if (!ok)
            break;
        for (int64_t a = 0; a < na && ok; a++) {
            const sw_arc *arc = &c->arcs[P->st.first + a];
            const sw_arc *prev = &c->arcs[P->st.first + (a + na - 1) % na];
            const sw_arc *next = &c->arcs[P->st.first + (a + 1) % na];
            int64_t ap = (a + na - 1) % na, an = (a + 1) % na;
            /* gaps at the sample: before this arc, and after it */
            double g_before = wrap_angle(arc->start.phi - (prev->end.phi + c->theta));
            double g_after = wrap_angle(next->start.phi - (arc->end.phi + c->theta));
            if (na == 1) {
                g_before = g_after = MFG_TWO_PI - (arc->end.phi + c->theta - arc->start.phi);
            }
            for (int e = 0; e < 2 && ok; e++) {
                int64_t m = 0;
                if (!mfg_grow((void **)&face, &capface, nloop + 1, sizeof *face)) {
                    ok = ctx_nomem(c);
                    break;
                }
                for (int64_t i = 0; i < nloop; i++) {
                    const int64_t *L = loop + w * i;
                    int64_t mine = L[2 * a + e];
                    /* the other line of the gap next to this face */
                    int64_t other = e == 0 ? L[2 * ap + 1] : L[2 * an];
                    double g0 = e == 0 ? g_before : g_after;
                    double raw = e == 0 ? o->phi[mine] - o->phi[other] : o->phi[other] - o->phi[mine];
                    double gap = g0 + angle_diff(raw, g0);
                    if (!(gap > 0 || mine == other))
                        continue;
                    if (m == 0 || face[m - 1] != mine)
                        face[m++] = mine;
                }
                while (m > 1 && face[m - 1] == face[0])
                    m--;
                int64_t ft = e == 0 ? arc->start.tri : arc->end.tri;
                for (int64_t i = 1; i + 1 < m && ok; i++) {
                    if (e == 0)
                        ok = sw_emit_tri(c, face[0], face[i], face[i + 1], ft, e);
                    else
                        ok = sw_emit_tri(c, face[0], face[i + 1], face[i], ft, e);
                }
            }
        }
    }
    free(face);
    free(loop);
    return ok;
}
