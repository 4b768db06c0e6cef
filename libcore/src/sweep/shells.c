/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/shells.c - Shells: volumes, nested shells, slivers, twin triangles, merged faces;
 * the walls stage.  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

/* Six times the signed volume of the tetrahedron (origin, a, b, d): a triangle's share of
 * the volume its closed surface encloses (divergence theorem about the origin). */
static double tet_volume6(const double *a, const double *b, const double *d)
{
    return a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0]) +
           a[2] * (b[0] * d[1] - b[1] * d[0]);
}

/* The volume enclosed by triangles tris (n of them) over the points xyz (about the
 * origin; local coordinates keep the numbers small). */
double sw_mesh_volume(const double *xyz, const int64_t *tris, int64_t n)
{
    double vol = 0;
    for (int64_t t = 0; t < n; t++)
        vol += tet_volume6(xyz + 3 * tris[3 * t], xyz + 3 * tris[3 * t + 1], xyz + 3 * tris[3 * t + 2]);
    return vol / 6;
}

/* Parity of the ray from p along dir through the triangles of component comp (tcomp per
 * triangle): 1 inside, 0 outside, -1 when the ray grazes an edge or vertex (undecided). */
static int ray_parity(const sw_ctx *c, const int64_t *tcomp, int64_t comp, const double *p,
                      const double *dir)
{
    int inside = 0;
    for (int64_t t = 0; t < c->notri; t++) {
        if (tcomp[t] != comp)
            continue;
        const double *a = c->ox + 3 * c->otri[3 * t], *b = c->ox + 3 * c->otri[3 * t + 1],
                     *d = c->ox + 3 * c->otri[3 * t + 2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        double q[3] = {dir[1] * e2[2] - dir[2] * e2[1], dir[2] * e2[0] - dir[0] * e2[2],
                       dir[0] * e2[1] - dir[1] * e2[0]};
        double det = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
        if (det == 0)
            continue;
        double w[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        double u = (w[0] * q[0] + w[1] * q[1] + w[2] * q[2]) / det;
        double rr[3] = {w[1] * e1[2] - w[2] * e1[1], w[2] * e1[0] - w[0] * e1[2], w[0] * e1[1] - w[1] * e1[0]};
        double v = (dir[0] * rr[0] + dir[1] * rr[1] + dir[2] * rr[2]) / det;
        double tt = (e2[0] * rr[0] + e2[1] * rr[1] + e2[2] * rr[2]) / det;
        const double g = SW_EPS_PARAM;
        if (u < -g || v < -g || u + v > 1 + g || tt < -g)
            continue;
        if (u < g || v < g || u + v > 1 - g || tt < g)
            return -1;
        inside ^= 1;
    }
    return inside;
}

/*
 * A shell of the result lying wholly inside another (two walls of a sliver left inside the
 * solid where pieces of the decomposition did not cancel) bounds nothing the union does
 * not already hold, but it is no part of the boundary: such shells are dropped.  A shell
 * is dropped only when every one of its sampled vertices is inside the other shell by two
 * rays that do not graze it.  A shell with some vertex inside another and some not
 * crosses it: *overlap is set, and the caller treats the result as it treats an open one.
 */
int sw_drop_nested_shells(sw_ctx *c, int *overlap)
{
    *overlap = 0;
    int64_t nt = c->notri, nv = c->nout;
    int64_t *parent = malloc((size_t)(nv + 1) * sizeof *parent);
    int64_t *tcomp = malloc((size_t)(nt + 1) * sizeof *tcomp);
    if (!parent || !tcomp) {
        free(parent);
        free(tcomp);
        return ctx_nomem(c);
    }
    for (int64_t i = 0; i < nv; i++)
        parent[i] = i;
    for (int64_t t = 0; t < nt; t++) {
        mfg_uf_union(parent, c->otri[3 * t], c->otri[3 * t + 1]);
        mfg_uf_union(parent, c->otri[3 * t], c->otri[3 * t + 2]);
    }
    /* components: roots, their volumes */
    int64_t ncomp = 0, *roots = NULL, capr = 0;
    double *vol = NULL, *box = NULL;
    int64_t capv = 0, capb = 0, *count = NULL, capn = 0;
    int ok = 1;
    for (int64_t t = 0; t < nt && ok; t++) {
        int64_t r = mfg_uf_find(parent, c->otri[3 * t]);
        int64_t k = 0;
        while (k < ncomp && roots[k] != r)
            k++;
        if (k == ncomp) {
            if (ncomp >= 64) { /* many shells: leave them (the search below is quadratic) */
                ncomp = 0;
                break;
            }
            if (!mfg_grow((void **)&roots, &capr, ncomp + 1, sizeof *roots) ||
                !mfg_grow((void **)&vol, &capv, ncomp + 1, sizeof *vol) ||
                !mfg_grow((void **)&count, &capn, ncomp + 1, sizeof *count) ||
                !mfg_grow((void **)&box, &capb, 6 * (ncomp + 1), sizeof *box)) {
                ok = ctx_nomem(c);
                break;
            }
            roots[ncomp] = r;
            vol[ncomp] = 0;
            count[ncomp] = 0;
            for (int e = 0; e < 3; e++) {
                box[6 * ncomp + e] = INFINITY;
                box[6 * ncomp + 3 + e] = -INFINITY;
            }
            ncomp++;
        }
        tcomp[t] = k;
        count[k]++;
        const double *a = c->ox + 3 * c->otri[3 * t], *b = c->ox + 3 * c->otri[3 * t + 1],
                     *d = c->ox + 3 * c->otri[3 * t + 2];
        vol[k] += tet_volume6(a, b, d);
        for (int q = 0; q < 3; q++)
            for (int e = 0; e < 3; e++) {
                double x = c->ox[3 * c->otri[3 * t + q] + e];
                box[6 * k + e] = fmin(box[6 * k + e], x);
                box[6 * k + 3 + e] = fmax(box[6 * k + 3 + e], x);
            }
    }
    char *drop = ok && ncomp > 1 ? calloc((size_t)ncomp, 1) : NULL;
    if (ok && ncomp > 1 && !drop)
        ok = ctx_nomem(c);
    static const double rays[2][3] = {{0.5377, 0.3141, 0.7826}, {-0.2718, 0.8660, -0.4192}};
    for (int64_t k = 0; ok && drop && k < ncomp; k++) {
        if (!(vol[k] > 0))
            continue;
        for (int64_t j = 0; j < ncomp && !drop[k]; j++) {
            if (j == k || drop[j] || !(vol[j] > vol[k]))
                continue;
            /* up to 16 vertices of shell k, spread over its triangles: all inside j? */
            int all_in = 1, tested = 0, some_in = 0;
            const double *bj = box + 6 * j;
            int64_t stride = count[k] / 16 + 1, seen = 0;
            for (int64_t t = 0; t < nt && all_in; t++) {
                if (tcomp[t] != k || seen++ % stride)
                    continue;
                const double *p = c->ox + 3 * c->otri[3 * t];
                if (ray_parity(c, tcomp, j, p, rays[0]) != 1 || ray_parity(c, tcomp, j, p, rays[1]) != 1)
                    all_in = 0;
                tested++;
            }
            if (all_in && tested > 0) {
                drop[k] = 1;
                continue;
            }
            /* else: does shell k reach into j?  Its vertices in j's box, up to 256 */
            int64_t nin = 0;
            for (int64_t t = 0; t < nt; t++) {
                if (tcomp[t] != k)
                    continue;
                const double *p = c->ox + 3 * c->otri[3 * t];
                nin += p[0] > bj[0] && p[1] > bj[1] && p[2] > bj[2] && p[0] < bj[3] &&
                       p[1] < bj[4] && p[2] < bj[5];
            }
            stride = nin / 256 + 1;
            seen = 0;
            for (int64_t t = 0; t < nt && !some_in; t++) {
                if (tcomp[t] != k)
                    continue;
                const double *p = c->ox + 3 * c->otri[3 * t];
                if (!(p[0] > bj[0] && p[1] > bj[1] && p[2] > bj[2] && p[0] < bj[3] &&
                      p[1] < bj[4] && p[2] < bj[5]) || seen++ % stride)
                    continue;
                some_in = ray_parity(c, tcomp, j, p, rays[0]) == 1 &&
                          ray_parity(c, tcomp, j, p, rays[1]) == 1;
            }
            if (some_in)
                *overlap = 1; /* two shells crossing: the union's boundary is neither */
        }
    }
    if (ok && drop) {
        int64_t m = 0;
        for (int64_t t = 0; t < nt; t++) {
            if (drop[tcomp[t]])
                continue;
            for (int q = 0; q < 3; q++)
                c->otri[3 * m + q] = c->otri[3 * t + q];
            c->oring[2 * m] = c->oring[2 * t];
            c->oring[2 * m + 1] = c->oring[2 * t + 1];
            c->odir[m] = c->odir[t];
            c->oface[m] = c->oface[t];
            m++;
        }
        c->notri = m;
    }
    free(drop);
    free(roots);
    free(vol);
    free(count);
    free(box);
    free(parent);
    free(tcomp);
    return ok;
}

/* Two copies of one triangle with opposite orientations (a strip of no width laid on a
 * face, a face met by its own copy) bound nothing: both go. */
/* Height of corner m over the line through p and q, and whether m projects strictly
 * between them. */
static double corner_height(const double *p, const double *q, const double *m, int *between)
{
    double d[3], e[3];
    for (int k = 0; k < 3; k++) {
        d[k] = q[k] - p[k];
        e[k] = m[k] - p[k];
    }
    double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    double de = d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
    double x[3] = {d[1] * e[2] - d[2] * e[1], d[2] * e[0] - d[0] * e[2], d[0] * e[1] - d[1] * e[0]};
    *between = dd > 0 && de > 0 && de < dd;
    return dd > 0 ? sqrt((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) / dd) : INFINITY;
}

/* The height of triangle (a, b, d) over its longest side; *side (optional) gets that
 * side's index k (from corner k to k + 1), *between whether the opposite corner projects
 * strictly between its ends. */
static double tri_flatness(const double *a, const double *b, const double *d, int *side,
                           int *between)
{
    const double *v[3] = {a, b, d};
    double best = -1;
    int kl = 0;
    for (int k = 0; k < 3; k++) {
        const double *p = v[k], *q = v[(k + 1) % 3];
        double l = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                   (q[2] - p[2]) * (q[2] - p[2]);
        if (l > best)
            best = l, kl = k;
    }
    int btw;
    double h = corner_height(v[kl], v[(kl + 1) % 3], v[(kl + 2) % 3], &btw);
    if (side)
        *side = kl;
    if (between)
        *between = btw;
    return h;
}

/* Slivers flipped away.  Where a wall's strip or a face's fan has three corners on one
 * line (a ruling of a cylinder cut at a vertex of the neighbouring strip, a face's
 * collinear corners), the triangle has no area; OCCT's sewing and solid check (the
 * Solid representation) take its corners for a self-intersecting wire, and the bench
 * arm came out with 64 such triangles.  A triangle (p, q, m) whose corner m lies within
 * 2^-30 of the part's size of its longest side p q, between p and q, is replaced with
 * its neighbour (q, p, d) across that side by (q, m, d) and (m, p, d): the neighbour
 * split at m, the same surface up to that height.  Skipped when the edge m d exists
 * already (the mesh would stop being a 2-manifold) or a new triangle would be a sliver
 * too; the mesh stays closed and oriented either way. */
int sw_flip_out_slivers(sw_ctx *c)
{
    double eps = ldexp(c->ext, -30);
    hmap he;
    if (!hmap_init(&he, 3 * c->notri))
        return ctx_nomem(c);
    int ok = 1;
    /* directed edge (a, b) -> triangle + 1 (0: gone) */
    for (int64_t t = 0; t < c->notri && ok; t++)
        for (int k = 0; k < 3 && ok; k++) {
            hkey key = mkkey(c->otri[3 * t + k], c->otri[3 * t + (k + 1) % 3], 0, 0);
            ok = hmap_put(&he, &key, t + 1);
        }
    /* a run of collinear corners (a ruling cut at several vertices) is a chain of
     * slivers, each the neighbour of the next across its longest side: the outermost
     * flips first, the next one on the following pass */
    int64_t flipped = 1;
    for (int pass = 0; pass < 16 && flipped && ok; pass++) {
        flipped = 0;
        for (int64_t t = 0; t < c->notri && ok; t++) {
            int64_t *T = c->otri + 3 * t;
            /* the longest side p -> q, m opposite */
            int kl, between;
            double h = tri_flatness(c->ox + 3 * T[0], c->ox + 3 * T[1], c->ox + 3 * T[2], &kl,
                                    &between);
            if (!(h <= eps) || !between)
                continue;
            int64_t p = T[kl], q = T[(kl + 1) % 3], mm = T[(kl + 2) % 3];
            hkey kqp = mkkey(q, p, 0, 0);
            int64_t t2 = hmap_get(&he, &kqp) - 1;
            if (t2 < 0 || t2 == t)
                continue;
            int64_t *U = c->otri + 3 * t2;
            int64_t d = -1;
            for (int k = 0; k < 3; k++)
                if (U[k] != p && U[k] != q)
                    d = U[k];
            hkey kmd = mkkey(mm, d, 0, 0), kdm = mkkey(d, mm, 0, 0);
            if (d < 0 || d == mm || hmap_get(&he, &kmd) > 0 || hmap_get(&he, &kdm) > 0)
                continue;
            const double *X = c->ox;
            if (!(tri_flatness(X + 3 * q, X + 3 * mm, X + 3 * d, NULL, NULL) > eps) ||
                !(tri_flatness(X + 3 * mm, X + 3 * p, X + 3 * d, NULL, NULL) > eps))
                continue;
            T[0] = q, T[1] = mm, T[2] = d;
            U[0] = mm, U[1] = p, U[2] = d;
            hkey gone[2] = {mkkey(p, q, 0, 0), kqp};
            hkey toT[3] = {mkkey(q, mm, 0, 0), kmd, mkkey(d, q, 0, 0)};
            hkey toU[3] = {mkkey(mm, p, 0, 0), mkkey(p, d, 0, 0), kdm};
            for (int k = 0; k < 2 && ok; k++)
                ok = hmap_put(&he, &gone[k], 0);
            for (int k = 0; k < 3 && ok; k++)
                ok = hmap_put(&he, &toT[k], t + 1) && hmap_put(&he, &toU[k], t2 + 1);
            flipped++;
        }
    }
    hmap_free(&he);
    return ok ? 1 : ctx_nomem(c);
}

int sw_cancel_twins(sw_ctx *c)
{
    hmap m;
    if (!hmap_init(&m, c->notri + 16))
        return ctx_nomem(c);
    char *dead = calloc((size_t)(c->notri + 1), 1);
    if (!dead) {
        hmap_free(&m);
        return ctx_nomem(c);
    }
    int ok = 1;
    for (int64_t t = 0; t < c->notri && ok; t++) {
        int64_t *v = c->otri + 3 * t;
        /* rotate so the smallest index is first: (a, b, c) keeps its orientation */
        int r = v[0] < v[1] ? (v[0] < v[2] ? 0 : 2) : (v[1] < v[2] ? 1 : 2);
        int64_t a = v[r], b = v[(r + 1) % 3], d = v[(r + 2) % 3];
        hkey twin = mkkey(a, d, b, 0);
        int64_t o = hmap_get(&m, &twin);
        if (o >= 0 && o < c->notri && !dead[o]) {
            dead[o] = dead[t] = 1;
            hkey gone = twin;
            ok = hmap_put(&m, &gone, c->notri); /* past every triangle: the slot is used up */
            continue;
        }
        hkey mine = mkkey(a, b, d, 0);
        if (hmap_get(&m, &mine) < 0)
            ok = hmap_put(&m, &mine, t);
    }
    if (ok) {
        int64_t n = 0;
        for (int64_t t = 0; t < c->notri; t++)
            if (!dead[t]) {
                memmove(c->otri + 3 * n, c->otri + 3 * t, 3 * sizeof *c->otri);
                c->oring[2 * n] = c->oring[2 * t];
                c->oring[2 * n + 1] = c->oring[2 * t + 1];
                c->odir[n] = c->odir[t];
                c->oface[n] = c->oface[t];
                n++;
            }
        c->notri = n;
    } else {
        ctx_nomem(c);
    }
    free(dead);
    hmap_free(&m);
    return ok;
}

/* The face pieces of one input plane (an input face: edge-adjacent triangles in one plane,
 * at the start or turned by theta), and the walls in one plane z = const (the annuli
 * swept by faces perpendicular to the axis: every corner at that height), merged
 * back into one triangulated region each: the decomposition cuts every face into one
 * piece per cell, which only adds inner vertices (planar_merge.c).  Where the merged
 * surface would not pass the closed-manifold check, the pieces are kept.  oring, odir and
 * oface no longer describe the triangles after it. */
int sw_merge_faces(sw_ctx *c)
{
    int64_t *root = malloc((size_t)(c->nt + 1) * sizeof *root);
    int64_t *group = malloc((size_t)(c->notri + 1) * sizeof *group);
    int64_t *keep = malloc((size_t)(3 * c->notri + 1) * sizeof *keep);
    hmap zs;
    memset(&zs, 0, sizeof zs);
    if (!root || !group || !keep || !hmap_init(&zs, 64)) {
        free(root);
        free(group);
        free(keep);
        hmap_free(&zs);
        return ctx_nomem(c);
    }
    for (int64_t t = 0; t < c->nt; t++)
        root[t] = t;
    /* neighbours across an edge (a curve with two triangles) in one plane: the fourth
     * vertex on the first one's plane up to rounding, the normals the same way */
    for (int64_t i = 0; i < c->ncurves; i++) {
        const sw_curve *cv = &c->curves[i];
        if (cv->tri[1] < 0)
            continue;
        const sw_tri *A = &c->tris[cv->tri[0]], *B = &c->tris[cv->tri[1]];
        double na = sqrt(A->n[0] * A->n[0] + A->n[1] * A->n[1] + A->n[2] * A->n[2]);
        if (!(na > 0) || A->n[0] * B->n[0] + A->n[1] * B->n[1] + A->n[2] * B->n[2] <= 0)
            continue;
        int flat = 1;
        for (int k = 0; k < 3; k++) {
            const double *p = c->lx + 3 * B->v[k];
            if (fabs(A->n[0] * p[0] + A->n[1] * p[1] + A->n[2] * p[2] - A->d) > SW_EPS_ROUND * c->ext * na)
                flat = 0;
        }
        if (!flat)
            continue;
        int64_t a = cv->tri[0], b = cv->tri[1];
        while (root[a] != a)
            a = root[a] = root[root[a]];
        while (root[b] != b)
            b = root[b] = root[root[b]];
        if (a != b)
            root[a < b ? b : a] = a < b ? a : b;
    }
    int ok = 1;
    for (int64_t t = 0; t < c->notri && ok; t++) {
        const int64_t *tv = c->otri + 3 * t;
        double z = c->ox[3 * tv[0] + 2];
        if (c->oface[t] < 0 && c->ox[3 * tv[1] + 2] == z && c->ox[3 * tv[2] + 2] == z) {
            hkey k = mkkey(dbits(z), 0, 0, 0);
            int64_t id = hmap_get(&zs, &k);
            if (id < 0) {
                id = 2 * c->nt + zs.n;
                ok = hmap_put(&zs, &k, id);
            }
            group[t] = id;
            continue;
        }
        int64_t f = c->oface[t];
        if (f < 0) {
            group[t] = -1;
            continue;
        }
        int64_t r = f / 2;
        while (root[r] != r)
            r = root[r];
        group[t] = 2 * r + (f & 1);
    }
    memcpy(keep, c->otri, (size_t)(3 * c->notri) * sizeof *keep);
    int64_t nkeep = c->notri;
    if (ok)
        ok = mfg_merge_planar_groups(c->ox, c->nout, c->otri, &c->notri, group, NULL);
    if (!ok) {
        ctx_nomem(c);
    } else if (c->notri != nkeep) {
        mfg_mesh_report rep;
        mfg_status cs = mfg_mesh_check_closed(c->ox, c->nout, c->otri, c->notri, &rep);
        if (cs == MFG_ERR_NOMEM)
            ok = ctx_nomem(c);
        if (cs != MFG_OK) {
            memcpy(c->otri, keep, (size_t)(3 * nkeep) * sizeof *keep);
            c->notri = nkeep;
        }
    }
    free(root);
    free(group);
    free(keep);
    hmap_free(&zs);
    return ok;
}

int sw_build_walls(sw_ctx *c, sw_out *o)
{
    sw_walls W;
    memset(&W, 0, sizeof W);
    hmap edges;
    if (!hmap_init(&W.evlists, 1024) || !hmap_init(&edges, c->npv + 64)) {
        hmap_free(&W.evlists);
        return ctx_nomem(c);
    }
    int ok = 1;
    W.push = calloc((size_t)(c->nv2 + 1), 1);
    W.cappush = c->nv2 + 1;
    if (!W.push)
        ok = ctx_nomem(c);
    for (int64_t pi = 0; pi < c->npolys && ok; pi++) {
        const sw_poly *P = &c->polys[pi];
        for (int64_t i = 0; i < P->n && ok; i++) {
            int64_t a = c->poly_verts[P->first + i], b = c->poly_verts[P->first + (i + 1) % P->n];
            hkey k = mkkey(a, b, 0, 0);
            if (!hmap_put(&edges, &k, pi * ((int64_t)1 << 24) + i))
                ok = ctx_nomem(c);
        }
    }
    for (int64_t pi = 0; pi < c->npolys && ok; pi++) {
        if (!sw_poll(c, (double)pi, (double)c->npolys)) {
            ok = 0;
            break;
        }
        const sw_poly *P = &c->polys[pi];
        for (int64_t i = 0; i < P->n && ok; i++) {
            int64_t a = c->poly_verts[P->first + i], b = c->poly_verts[P->first + (i + 1) % P->n];
            if (a == b)
                continue;
            hkey k = mkkey(b, a, 0, 0);
            int64_t tw = hmap_get(&edges, &k);
            int64_t Q = tw >= 0 ? tw / ((int64_t)1 << 24) : -1, iq = tw >= 0 ? tw % ((int64_t)1 << 24) : -1;
            if (Q >= 0 && Q < pi)
                continue; /* done from Q's side */
            ok = sw_edge_walls(c, o, &W, a, b, pi, i, Q, iq);
        }
    }
    hmap_free(&edges);
    if (ok)
        ok = sw_report(c, 0.4) && sw_emit_strips(c, o, &W) && sw_report(c, 0.55) &&
             sw_emit_faces(c, o, &W);
    free(W.strips);
    free(W.rv2);
    free(W.rvid);
    free(W.ring_start);
    free(W.evring);
    free(W.evl);
    free(W.push);
    hmap_free(&W.evlists);
    return ok;
}
