/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/polygons.c - Polygons of the decomposition: the leaves of the quadtree cut into
 * polygons, each with its arc structure.  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

static int64_t add_v2(sw_ctx *c, const hkey *k, double r, double z, int64_t curve, double u,
                      int64_t mvtx)
{
    int64_t id = hmap_get(&c->v2map, k);
    if (id >= 0)
        return id;
    if (!mfg_grow((void **)&c->v2, &c->capv2, c->nv2 + 1, sizeof *c->v2))
        return ctx_nomem(c) - 1;
    sw_vtx2 *w = &c->v2[c->nv2];
    w->r = r;
    w->z = z;
    w->curve = curve;
    w->u = u;
    w->mvtx = mvtx;
    w->ncurves = 0;
    if (curve >= 0) {
        w->curves[0] = curve;
        w->us[0] = u;
        w->ncurves = 1;
    }
    if (!hmap_put(&c->v2map, k, c->nv2))
        return ctx_nomem(c) - 1;
    return c->nv2++;
}

static int64_t corner_v2(sw_ctx *c, int64_t ix, int64_t iz)
{
    hkey k = mkkey(0, ix, iz, 0);
    return add_v2(c, &k, sw_grid_r(c, ix), sw_grid_z(c, iz), -1, 0, -1);
}

static const sw_leaf *leaf_at(const sw_ctx *c, int64_t x2, int64_t z2)
{
    if (x2 < 0 || z2 < 0)
        return NULL;
    for (int lv = c->lmax; lv >= 0; lv--) {
        int64_t S = (int64_t)1 << (c->lmax - lv);
        hkey k = mkkey(lv, (x2 / (2 * S)) * S, (z2 / (2 * S)) * S, 0);
        int64_t id = hmap_get(&c->leafmap, &k);
        if (id >= 0)
            return &c->leaves[id];
    }
    return NULL;
}

typedef struct sw_ipt {
    double key; /* position along the traversal direction */
    double pos, u;
    int64_t curve;
} sw_ipt;

static int cmp_ipt(const void *pa, const void *pb)
{
    const sw_ipt *a = pa, *b = pb;
    return sw_cmp_key(a->key, b->key, a->curve, b->curve);
}

/* Appends to *loop the vertices of the sub-side from integer point (ax, az) to (bx, bz)
 * (axis-parallel, excluding the end): the start, then the crossings of the curves of
 * this leaf and of the leaf across. */
static int sub_side(sw_ctx *c, const sw_leaf *L, int64_t ax, int64_t az, int64_t bx, int64_t bz,
                    int64_t **loop, int64_t *nloop, int64_t *caploop)
{
    int64_t a = corner_v2(c, ax, az);
    if (a < 0)
        return 0;
    if (!mfg_grow((void **)loop, caploop, *nloop + 1, sizeof **loop))
        return ctx_nomem(c);
    (*loop)[(*nloop)++] = a;
    int64_t first_x = *nloop;
    int rside = ax == bx;
    double val = rside ? sw_grid_r(c, ax) : sw_grid_z(c, az);
    double pa = rside ? sw_grid_z(c, az) : sw_grid_r(c, ax), pb = rside ? sw_grid_z(c, bz) : sw_grid_r(c, bx);
    double lo = fmin(pa, pb), hi = fmax(pa, pb);
    int dirn = pb > pa ? 1 : -1;
    /* the leaf across: the point just outside the middle of the sub-side */
    int64_t mx2 = ax + bx, mz2 = az + bz;
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    if (rside)
        mx2 += ax == L->ix ? -1 : 1;
    else
        mz2 += az == L->iz ? -1 : 1;
    (void)s;
    const sw_leaf *N = leaf_at(c, mx2, mz2);
    sw_ipt pts[64];
    int np = 0;
    const sw_leaf *both[2] = {L, N};
    for (int w = 0; w < 2; w++) {
        if (!both[w])
            continue;
        for (int64_t k = 0; k < both[w]->cn; k++) {
            int64_t ic = c->leaf_curves[both[w]->cfirst + k];
            int dup = 0;
            for (int q = 0; q < np; q++)
                dup |= pts[q].curve == ic;
            if (dup)
                continue;
            double pos[2], us[2];
            int m = sw_curve_side(&c->curves[ic], rside, val, lo, hi, pos, us);
            for (int q = 0; q < m && np < 64; q++) {
                pts[np].pos = pos[q];
                pts[np].key = pos[q];
                pts[np].u = us[q];
                pts[np].curve = ic;
                np++;
            }
        }
    }
    /* Crossings within eps of one another are one vertex, made from the lowest of them:
     * sorted upwards whichever way this leaf runs along the side, so that the leaf across
     * (running the other way) makes the same vertex - a silhouette ending on an edge just
     * beside the side gave two vertices a rounding apart, one per leaf, and a crack. */
    qsort(pts, (size_t)np, sizeof *pts, cmp_ipt);
    /* the same merge distance as analyse_cell's chord test */
    double eps = SW_EPS_REL * (hi - lo) + SW_EPS_ROUND * (fabs(hi) + fabs(lo) + fabs(val));
    double last = dirn > 0 ? lo : -hi;
    (void)last;
    double prev = -INFINITY;
    int64_t prev_id = -1;
    for (int q = 0; q < np; q++) {
        if (fabs(pts[q].pos - pa) <= eps || fabs(pts[q].pos - pb) <= eps)
            continue;
        if (pts[q].key - prev <= eps) {
            /* another curve through the same point: the vertex keeps it for lifting */
            sw_vtx2 *w = &c->v2[prev_id];
            int known = 0;
            for (int j = 0; j < w->ncurves; j++)
                known |= w->curves[j] == pts[q].curve;
            if (!known && w->ncurves < SW_MAXCURVES) {
                w->curves[w->ncurves] = pts[q].curve;
                w->us[w->ncurves++] = pts[q].u;
            }
            continue;
        }
        prev = pts[q].key;
        const sw_curve *cv = &c->curves[pts[q].curve];
        int64_t mv = pts[q].u == 0 ? cv->vtx[0] : (pts[q].u == 1 ? cv->vtx[1] : -1);
        hkey k = mkkey(1 + rside, rside ? ax : az, dbits(pts[q].pos), 0);
        int64_t id = add_v2(c, &k, rside ? val : pts[q].pos, rside ? pts[q].pos : val,
                            pts[q].curve, pts[q].u, mv);
        if (id < 0)
            return 0;
        prev_id = id;
        if (!mfg_grow((void **)loop, caploop, *nloop + 1, sizeof **loop))
            return ctx_nomem(c);
        (*loop)[(*nloop)++] = id;
    }
    if (dirn < 0) /* back into this leaf's direction */
        for (int64_t i = first_x, j = *nloop - 1; i < j; i++, j--) {
            int64_t t = (*loop)[i];
            (*loop)[i] = (*loop)[j];
            (*loop)[j] = t;
        }
    return 1;
}

/* The side from (ax, az) to (bx, bz), cut at the corners of finer leaves across it. */
static int side_loop(sw_ctx *c, const sw_leaf *L, int64_t ax, int64_t az, int64_t bx, int64_t bz,
                     int64_t **loop, int64_t *nloop, int64_t *caploop)
{
    int64_t len = llabs(bx - ax) + llabs(bz - az);
    if (len >= 2) {
        int64_t mx = (ax + bx) / 2, mz = (az + bz) / 2;
        hkey k = mkkey(mx, mz, 0, 0);
        if (hmap_get(&c->corners, &k) >= 0)
            return side_loop(c, L, ax, az, mx, mz, loop, nloop, caploop) &&
                   side_loop(c, L, mx, mz, bx, bz, loop, nloop, caploop);
    }
    return sub_side(c, L, ax, az, bx, bz, loop, nloop, caploop);
}

/* Keeps polygon vs[0 .. n-1] with its arc structure (an empty one is dropped: nothing
 * covers it, and its edges bound nothing). */
static int store_poly(sw_ctx *c, const int64_t *vs, int64_t n, const sw_struct *st)
{
    if (!st->full && st->n == 0)
        return 1;
    if (!mfg_grow((void **)&c->polys, &c->cappolys, c->npolys + 1, sizeof *c->polys) ||
        !mfg_grow((void **)&c->poly_verts, &c->cappv, c->npv + n, sizeof *c->poly_verts))
        return ctx_nomem(c);
    sw_poly *P = &c->polys[c->npolys++];
    P->first = c->npv;
    P->n = n;
    P->st = *st;
    memcpy(c->poly_verts + c->npv, vs, (size_t)n * sizeof *vs);
    c->npv += n;
    return 1;
}

static int add_poly(sw_ctx *c, const int64_t *vs, int64_t n)
{
    if (n < 3)
        return 1;
    double r = 0, z = 0;
    for (int64_t i = 0; i < n; i++) {
        r += c->v2[vs[i]].r;
        z += c->v2[vs[i]].z;
    }
    r /= (double)n;
    z /= (double)n;
    sw_struct st;
    if (!sw_circle_arcs(c, r, z, &st))
        return 0;
    return store_poly(c, vs, n, &st);
}

/*
 * A cell still mixed at the finest size (several curves, vertex images, case-1.3 curves
 * crossing): a block.  Over the whole cell SV is taken as the union of its arcs at the
 * cell's corners, side points, centre and a 4 x 4 grid, each end moved out by the angle
 * the cell's size spans at its smallest radius (the cell is below a quarter of the
 * tolerance, so the block lies within it).  Its caps are flat pieces of meridian
 * half-planes; the walls to its neighbours come out of the common comparison.
 */
static int add_block(sw_ctx *c, const sw_leaf *L, const int64_t *loop, int64_t nloop)
{
    if (L->level < c->lmax) {
        hkey rk = mkkey(L->level, L->ix, L->iz, 0);
        if (!hmap_put(&c->refine, &rk, 1))
            return ctx_nomem(c);
        c->coarse_blocks++;
    }
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    double ra = sw_grid_r(c, L->ix), rb = sw_grid_r(c, L->ix + s);
    double za = sw_grid_z(c, L->iz), zb = sw_grid_z(c, L->iz + s);
    int64_t ns = nloop + 16;
    sw_iv *iv = NULL;
    int64_t niv = 0, capiv = 0;
    int full = 0, ok = 1;
    for (int64_t k = 0; k < ns && ok && !full; k++) {
        double r, z;
        if (k < nloop) {
            /* points on curves are where circles graze edges: the grid inside and the
             * corners sample the block */
            if (c->v2[loop[k]].ncurves > 0)
                continue;
            r = c->v2[loop[k]].r;
            z = c->v2[loop[k]].z;
        } else {
            int64_t q = k - nloop;
            r = ra + (rb - ra) * (0.125 + 0.25 * (double)(q % 4));
            z = za + (zb - za) * (0.125 + 0.25 * (double)(q / 4));
        }
        int64_t mark = c->narcs;
        sw_struct st;
        if (!sw_circle_arcs(c, r, z, &st)) {
            ok = 0;
            break;
        }
        if (st.full)
            full = 1;
        for (int64_t a = 0; a < st.n && ok; a++) {
            const sw_arc *arc = &c->arcs[st.first + a];
            if (!mfg_grow((void **)&iv, &capiv, niv + 1, sizeof *iv)) {
                ok = ctx_nomem(c);
                break;
            }
            double a0 = wrap_angle(arc->start.phi);
            iv[niv].a = a0;
            iv[niv].b = a0 + (arc->end.phi + c->theta - arc->start.phi);
            niv++;
        }
        c->narcs = mark; /* the samples' arcs are not kept */
    }
    if (!ok) {
        free(iv);
        return 0;
    }
    double rmin = fmax(ra, c->h);
    double margin = fmin(MFG_PI, 2 * (rb - ra) / rmin);
    sw_struct bst;
    bst.full = full;
    bst.n = 0;
    bst.first = c->narcs;
    if (!full && niv > 0) {
        for (int64_t i = 0; i < niv; i++) {
            iv[i].a -= margin;
            iv[i].b += margin;
            if (iv[i].b - iv[i].a >= MFG_TWO_PI)
                full = 1;
            double w = wrap_angle(iv[i].a);
            iv[i].b += w - iv[i].a;
            iv[i].a = w;
        }
        qsort(iv, (size_t)niv, sizeof *iv, sw_cmp_iv);
        /* merge on the circle: find an interval not reached by any earlier one (with the
         * wrap of the last ones), start there */
        double reach = -INFINITY;
        for (int64_t i = 0; i < niv; i++)
            reach = fmax(reach, iv[i].b - MFG_TWO_PI);
        int64_t j0 = -1;
        double best = reach;
        for (int64_t i = 0; i < niv && !full; i++) {
            if (iv[i].a > best) {
                j0 = i;
                break;
            }
            best = fmax(best, iv[i].b);
        }
        if (j0 < 0)
            full = 1;
        bst.full = full;
        if (!full) {
            double ca = iv[j0].a, cb = iv[j0].b;
            for (int64_t k = 1; k <= niv && ok; k++) {
                int64_t i = (j0 + k) % niv;
                double a = iv[i].a + ((j0 + k) >= niv ? MFG_TWO_PI : 0);
                double b = iv[i].b + ((j0 + k) >= niv ? MFG_TWO_PI : 0);
                if (k < niv && a <= cb) {
                    cb = fmax(cb, b);
                    continue;
                }
                sw_arc arc;
                memset(&arc, 0, sizeof arc);
                arc.start.tri = arc.end.tri = -1;
                arc.start.phi = ca;
                arc.end.phi = cb - c->theta;
                ok = sw_push_arc(c, &arc);
                bst.n++;
                ca = a;
                cb = b;
            }
        }
    }
    free(iv);
    if (!ok)
        return 0;
    return store_poly(c, loop, nloop, &bst);
}

/* The curves of leaf L through its centre (a crossing of chords), with their parameters
 * there, kept on the centre's 2-D vertex: its lifts onto the triangles of those edges
 * land on the edges, so that the pieces meeting there share the vertex. */
static void centre_curves(const sw_ctx *c, const sw_leaf *L, sw_vtx2 *w)
{
    double eps = sw_point_eps(c, w->r, w->z);
    for (int64_t k = 0; k < L->cn && w->ncurves < SW_MAXCURVES; k++) {
        int64_t ic = c->leaf_curves[L->cfirst + k];
        const sw_curve *cv = &c->curves[ic];
        double u;
        if (cv->dir[2] != 0) {
            u = (w->z - cv->p0[2]) / cv->dir[2];
        } else {
            if (fabs(cv->p0[2] - w->z) > eps)
                continue;
            u = sw_curve_u_at_r(cv, w->r, 0, 1);
        }
        /* an end of a gap-closing curve at a junction: u = 0 or 1 up to rounding */
        if (u < 0 && u >= -SW_EPS_PARAM)
            u = 0;
        if (u > 1 && u <= 1 + SW_EPS_PARAM)
            u = 1;
        if (!(u >= 0 && u <= 1) || fabs(sw_curve_r(cv, u) - w->r) > eps)
            continue;
        int known = 0;
        for (int j = 0; j < w->ncurves; j++)
            known |= w->curves[j] == ic;
        if (!known) {
            w->curves[w->ncurves] = ic;
            w->us[w->ncurves++] = u;
        }
    }
}

static int on_curve(const sw_vtx2 *w, int64_t ic)
{
    for (int j = 0; j < w->ncurves; j++)
        if (w->curves[j] == ic)
            return 1;
    return 0;
}

/* Cuts the boundary loop of a LEAF_CHORDS cell along each of its curves' chords and adds
 * the pieces; 0 on error, -1 when a chord's two ends are not found in one piece (then the
 * caller makes the cell a block). */
static int cut_chords(sw_ctx *c, const sw_leaf *L, const int64_t *loop, int64_t nloop)
{
    int64_t cap = 3 * (nloop + 2 * SW_MAXJUNCTION) + 8;
    int64_t *buf = malloc((size_t)cap * sizeof *buf);
    int64_t first[SW_MAXJUNCTION + 2], len[SW_MAXJUNCTION + 2];
    if (!buf)
        return ctx_nomem(c);
    memcpy(buf, loop, (size_t)nloop * sizeof *buf);
    int np = 1, res = 1;
    int64_t used = nloop;
    first[0] = 0;
    len[0] = nloop;
    for (int64_t k = 0; k < L->cn && res == 1; k++) {
        int64_t ic = c->leaf_curves[L->cfirst + k];
        int done = 0, seen = 0;
        for (int p = 0; p < np && !done; p++) {
            int64_t at[2], m = 0, n = len[p];
            const int64_t *v = buf + first[p];
            for (int64_t i = 0; i < n; i++)
                if (on_curve(&c->v2[v[i]], ic)) {
                    if (m < 2)
                        at[m] = i;
                    m++;
                }
            seen += (int)m;
            if (m != 2)
                continue;
            if (at[1] == at[0] + 1 || (at[0] == 0 && at[1] == n - 1)) {
                done = 1; /* a coincident chord, already cut */
                continue;
            }
            if (np >= SW_MAXJUNCTION + 2 || used + n + 2 > cap)
                break;
            /* the piece from at[0] to at[1], and the rest from at[1] round to at[0] */
            int64_t f2 = used, n1 = at[1] - at[0] + 1, n2 = n - n1 + 2;
            for (int64_t i = 0; i < n2; i++)
                buf[f2 + i] = v[(at[1] + i) % n];
            int64_t *w = buf + first[p];
            memmove(w, w + at[0], (size_t)n1 * sizeof *w);
            len[p] = n1;
            first[np] = f2;
            len[np] = n2;
            np++;
            used += n2;
            done = 1;
        }
        /* a curve named at fewer than two vertices: one of several with one chord,
         * whose vertices keep SW_MAXCURVES of them (the count below checks the cut) */
        if (!done && seen >= 2)
            res = -1;
    }
    if (np != L->nchords + 1)
        res = -1;
    for (int p = 0; p < np && res == 1; p++)
        res = add_poly(c, buf + first[p], len[p]);
    free(buf);
    return res;
}

/*
 * The half star round a vertex image on the axis (analyse_cell): the image lies on the
 * cell's side r = 0, where the loop already has a vertex if a curve's crossing with that
 * side was found there (within rounding).  That vertex becomes the centre (one 2-D vertex
 * at the image, at the image's exact coordinates); the other vertices of the side
 * strictly between its corners are crossings at the image too (analyse_cell allows no
 * other) and are dropped.  Then one triangle from the centre to every loop edge that
 * does not touch it, each with the structure at its own centroid.  No cell lies across
 * the side r = 0, so its vertices belong to this cell alone.
 */
static int half_star(sw_ctx *c, const sw_leaf *L, const int64_t *loop, int64_t nloop)
{
    int64_t s = (int64_t)1 << (c->lmax - L->level);
    double za = sw_grid_z(c, L->iz), zb = sw_grid_z(c, L->iz + s);
    int64_t *w = malloc((size_t)(nloop + 1) * sizeof *w);
    if (!w)
        return ctx_nomem(c);
    int64_t n = 0, centre = -1, at = -1;
    for (int64_t i = 0; i < nloop; i++) {
        const sw_vtx2 *v = &c->v2[loop[i]];
        if (v->r == 0 && v->z > za && v->z < zb) {
            if (centre < 0)
                centre = loop[i];
            continue;
        }
        w[n++] = loop[i];
        if (v->r == 0 && v->z == zb)
            at = n; /* the side r = 0 runs down from here */
    }
    if (centre < 0) {
        hkey k = mkkey(3, dbits(0), dbits(L->cz), 0);
        centre = add_v2(c, &k, 0, L->cz, -1, 0, L->cvtx);
        if (centre < 0) {
            free(w);
            return 0;
        }
    }
    if (at < 0) { /* no corner (0, zb): cannot happen; a block is always safe */
        free(w);
        return add_block(c, L, loop, nloop);
    }
    sw_vtx2 *cv = &c->v2[centre];
    cv->z = L->cz;
    cv->mvtx = L->cvtx;
    memmove(w + at + 1, w + at, (size_t)(n - at) * sizeof *w);
    w[at] = centre;
    n++;
    int ok = 1;
    for (int64_t i = 0; i < n && ok; i++) {
        int64_t a = w[i], b = w[(i + 1) % n];
        if (a == centre || b == centre)
            continue;
        int64_t tri[3] = {centre, a, b};
        ok = add_poly(c, tri, 3);
    }
    free(w);
    return ok;
}

int sw_build_polygons(sw_ctx *c)
{
    if (!hmap_init(&c->v2map, 4 * c->nleaves + 64))
        return ctx_nomem(c);
    int64_t *loop = NULL, nloop = 0, caploop = 0;
    int ok = 1;
    for (int64_t li = 0; li < c->nleaves && ok; li++) {
        if (!sw_poll(c, (double)li, (double)c->nleaves)) {
            ok = 0;
            break;
        }
        const sw_leaf *L = &c->leaves[li];
        if (L->empty)
            continue;
        int64_t s = (int64_t)1 << (c->lmax - L->level);
        int64_t cx[5] = {L->ix, L->ix + s, L->ix + s, L->ix, L->ix};
        int64_t cz[5] = {L->iz, L->iz, L->iz + s, L->iz + s, L->iz};
        nloop = 0;
        for (int k = 0; k < 4 && ok; k++)
            ok = side_loop(c, L, cx[k], cz[k], cx[k + 1], cz[k + 1], &loop, &nloop, &caploop);
        if (!ok)
            break;
        int kind = L->kind;
        if (kind == LEAF_SPLIT) {
            int64_t at[2], m = 0;
            for (int64_t i = 0; i < nloop && m <= 2; i++) {
                const sw_vtx2 *w = &c->v2[loop[i]];
                int on = 0;
                for (int j = 0; j < w->ncurves; j++)
                    on |= w->curves[j] == L->split_curve;
                if (on) {
                    if (m < 2)
                        at[m] = i;
                    m++;
                }
            }
            if (m != 2) {
                kind = LEAF_FAN;
            } else {
                int64_t *tmp = malloc((size_t)(nloop + 2) * sizeof *tmp);
                if (!tmp) {
                    ok = ctx_nomem(c);
                    break;
                }
                int64_t n1 = 0;
                for (int64_t i = at[0]; i <= at[1]; i++)
                    tmp[n1++] = loop[i];
                ok = add_poly(c, tmp, n1);
                int64_t n2 = 0;
                for (int64_t i = at[1]; i != at[0]; i = (i + 1) % nloop)
                    tmp[n2++] = loop[i];
                tmp[n2++] = loop[at[0]];
                if (ok)
                    ok = add_poly(c, tmp, n2);
                free(tmp);
                continue;
            }
        }
        if (kind == LEAF_CHORDS) {
            int r = cut_chords(c, L, loop, nloop);
            if (r == 0) {
                ok = 0;
                break;
            }
            if (r == 1)
                continue;
            kind = LEAF_FAN; /* nothing was added: the pieces are added after the cuts */
        }
        if (kind == LEAF_CLEAN) {
            ok = add_poly(c, loop, nloop);
            continue;
        }
        if (kind == LEAF_FAN) {
            ok = add_block(c, L, loop, nloop);
            continue;
        }
        if (kind == LEAF_STAR && L->cr == 0) {
            ok = half_star(c, L, loop, nloop);
            continue;
        }
        /* star round the vertex image */
        hkey k = mkkey(3, dbits(L->cr), dbits(L->cz), 0);
        int64_t cv = add_v2(c, &k, L->cr, L->cz, -1, 0, kind == LEAF_STAR || L->cvtx >= 0 ? L->cvtx : -1);
        if (cv < 0) {
            ok = 0;
            break;
        }
        if (L->cvtx < 0)
            centre_curves(c, L, &c->v2[cv]);
        for (int64_t i = 0; i < nloop && ok; i++) {
            int64_t tri[3] = {cv, loop[i], loop[(i + 1) % nloop]};
            ok = add_poly(c, tri, 3);
        }
    }
    free(loop);
    return ok;
}
