/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheet_coarse.c - the sheet of a coarse plane leaf (docs/design/medial.md sections 3.4 and
 * 4.1): a cell of side 2^m h whose only candidates are two faces a and b, each holding the
 * whole cell's projection, is crossed by their bisector plane alone, untrimmed (octree.c,
 * coarse_plane).  Its sheet is the plane's polygon in the cube; what it must share with
 * the neighbouring leaves is its boundary.  A neighbour of side h meets it in a square of
 * the fine lattice on the cube's face, split by the Kuhn diagonal from its smallest to its
 * largest lattice point; the neighbour's marching tets cut each such triangle whose corners
 * differ in the sign of f_ab along the segment between the roots on its two crossed
 * lattice edges.  So the coarse leaf walks the fine triangles of its six faces near the
 * plane, cuts every triangle whose corners' signs differ in the same way (the same f at
 * the same lattice points, the same roots from the same lattice edges, keyed by them), and
 * fans those segments from one point of the plane inside the cube.  Both sides then hold
 * the same boundary segments with the same bits and the welding by key joins them: the
 * sheet stays one conforming triangulation whatever the leaves' sizes.  Cost: O(2^m) per
 * face (the band of fine triangles near the plane's trace) instead of the 4^m leaves of
 * side h the plane crosses. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/sheets.h"
#include "common/mfg_internal.h"

/* The trace of the plane on a face is found from f's linearisation; lattice points whose
 * f lies within this bound (relative to the lattice's coordinates and L) of the trace may
 * have either computed sign, so the band of triangles visited covers them (far above
 * the rounding of f = s_a - s_b, about 8 ulps of those magnitudes). */
#define BAND_REL 1e-12

typedef struct coarse {
    const md_elements *el;
    const md_lattice *lat;
    int64_t a, b;
    unit_buf *out;
    /* The lattice edges already rooted: open addressing on (point, direction). */
    int64_t *hkey; /* 4 per slot: i, j, k, direction; direction 0: empty */
    int64_t *hrec; /* the record of the slot's root */
    int64_t hcap, hn;
    /* The boundary segments: 2 records each. */
    int64_t *seg;
    int64_t nseg, cseg;
} coarse;

static void lattice_point(const coarse *c, const int64_t *p, double *x)
{
    for (int d = 0; d < 3; d++)
        x[d] = c->lat->origin[d] + c->lat->h * (double)p[d];
}

/* f_ab at lattice point p, evaluated as the leaves of side h do (sheet_tet.c). */
static double lattice_f(const coarse *c, const int64_t *p)
{
    double x[3];
    lattice_point(c, p, x);
    return md_dist_car(c->el, c->a, x, NULL) - md_dist_car(c->el, c->b, x, NULL);
}

static uint64_t edge_hash(const int64_t *k)
{
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < 4; i++)
        h = (h ^ (uint64_t)k[i]) * 1099511628211ull;
    return h ^ (h >> 29);
}

static int grow_hash(coarse *c)
{
    int64_t ncap = c->hcap ? 2 * c->hcap : 1024;
    int64_t *nk = calloc((size_t)ncap, 4 * sizeof *nk), *nr = malloc((size_t)ncap * sizeof *nr);
    if (!nk || !nr) {
        free(nk);
        free(nr);
        return 0;
    }
    for (int64_t s = 0; s < c->hcap; s++) {
        if (c->hkey[4 * s + 3] == 0)
            continue;
        uint64_t q = edge_hash(c->hkey + 4 * s) & (uint64_t)(ncap - 1);
        while (nk[4 * q + 3] != 0)
            q = (q + 1) & (uint64_t)(ncap - 1);
        memcpy(nk + 4 * q, c->hkey + 4 * s, 4 * sizeof *nk);
        nr[q] = c->hrec[s];
    }
    free(c->hkey);
    free(c->hrec);
    c->hkey = nk;
    c->hrec = nr;
    c->hcap = ncap;
    return 1;
}

/* The record of the root on the lattice edge from p along the direction bits dir (p the
 * edge's smaller lattice point), made as md_sheet_edge_vertex makes it: the same key, the
 * same root (md_root_on_segment from p, or the end nearer to f = 0 when rounding hides the
 * sign change), radius min(d_a, d_b) (both regions hold it, nothing else is as near).
 * -1 on NOMEM. */
static int64_t edge_record(coarse *c, const int64_t *p, int dir, double fp, double fq)
{
    if (2 * (c->hn + 1) > c->hcap && !grow_hash(c))
        return -1;
    int64_t key[4] = {p[0], p[1], p[2], dir};
    uint64_t q = edge_hash(key) & (uint64_t)(c->hcap - 1);
    while (c->hkey[4 * q + 3] != 0) {
        if (!memcmp(c->hkey + 4 * q, key, sizeof key))
            return c->hrec[q];
        q = (q + 1) & (uint64_t)(c->hcap - 1);
    }
    int64_t pq[3] = {p[0] + (dir & 1), p[1] + (dir >> 1 & 1), p[2] + (dir >> 2 & 1)};
    double xp[3], xq[3], x[3];
    lattice_point(c, p, xp);
    lattice_point(c, pq, xq);
    if (!md_root_on_segment(c->el, c->a, c->b, xp, xq, x, NULL))
        memcpy(x, fabs(fp) <= fabs(fq) ? xp : xq, sizeof x);
    double da = md_dist_car(c->el, c->a, x, NULL), db = md_dist_car(c->el, c->b, x, NULL);
    double r = db < da ? db : da;
    vkey k;
    memset(&k, 0xff, sizeof k);
    k.a = c->a;
    k.b = c->b;
    for (int d = 0; d < 3; d++)
        k.e[0][d] = (int32_t)p[d];
    k.e[0][3] = dir;
    k.c = -2;
    int64_t rec = md_sheet_push_vertex(c->out, &k, x, r > 0 ? r : 0.0);
    if (rec < 0)
        return -1;
    memcpy(c->hkey + 4 * q, key, sizeof key);
    c->hrec[q] = rec;
    c->hn++;
    return rec;
}

/* A boundary segment of the leaf's polygon (2 records).  0 on NOMEM. */
static int push_segment(coarse *c, int64_t p, int64_t q)
{
    if (c->nseg == c->cseg) {
        int64_t nc = c->cseg ? 2 * c->cseg : 256;
        if (!mfg_resize((void **)&c->seg, nc, 2 * sizeof *c->seg))
            return 0;
        c->cseg = nc;
    }
    c->seg[2 * c->nseg] = p;
    c->seg[2 * c->nseg + 1] = q;
    c->nseg++;
    return 1;
}

/* The segment of the fine triangle P[0..2] (lattice points of one face, f values fv)
 * where its corners' signs differ: between the roots on its two edges from the corner
 * whose sign is alone.  0 on NOMEM. */
static int cut_triangle(coarse *c, int64_t P[3][3], const double *fv)
{
    int pos = (fv[0] >= 0) + (fv[1] >= 0) + (fv[2] >= 0);
    if (pos == 0 || pos == 3)
        return 1;
    int lone = 0;
    for (int i = 0; i < 3; i++)
        if ((fv[i] >= 0) == (pos == 1))
            lone = i;
    int64_t rec[2];
    for (int s = 0, i = 0; i < 3; i++) {
        if (i == lone)
            continue;
        /* Kuhn edges run between lattice points one of which is componentwise <= the other. */
        int lo = lone, hi = i;
        if (P[lo][0] > P[hi][0] || P[lo][1] > P[hi][1] || P[lo][2] > P[hi][2]) {
            lo = i;
            hi = lone;
        }
        int dir = (int)((P[hi][0] - P[lo][0]) | (P[hi][1] - P[lo][1]) << 1 | (P[hi][2] - P[lo][2]) << 2);
        rec[s] = edge_record(c, P[lo], dir, fv[lo], fv[hi]);
        if (rec[s++] < 0)
            return 0;
    }
    return push_segment(c, rec[0], rec[1]);
}

/* ---- the leaves by position ---------------------------------------------------------- */

static uint64_t leaf_hash(const int32_t *ijk, int32_t level)
{
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < 3; i++)
        h = (h ^ (uint64_t)(uint32_t)ijk[i]) * 1099511628211ull;
    h = (h ^ (uint64_t)(uint32_t)level) * 1099511628211ull;
    return h ^ (h >> 29);
}

int md_leaf_index_build(const md_leaves *lv, md_leaf_index *li)
{
    memset(li, 0, sizeof *li);
    int64_t ncoarse = 0;
    for (int64_t i = 0; i < lv->nleaves; i++) {
        ncoarse += lv->leaf[i].level > 0;
        if (lv->leaf[i].level > li->maxlevel)
            li->maxlevel = lv->leaf[i].level;
    }
    if (ncoarse == 0)
        return 1;
    int64_t cap = 64;
    while (cap < 2 * lv->nleaves)
        cap *= 2;
    li->slot = malloc((size_t)cap * sizeof *li->slot);
    if (!li->slot)
        return 0;
    li->cap = cap;
    for (int64_t s = 0; s < cap; s++)
        li->slot[s] = -1;
    for (int64_t i = 0; i < lv->nleaves; i++) {
        uint64_t q = leaf_hash(lv->leaf[i].ijk, lv->leaf[i].level) & (uint64_t)(cap - 1);
        while (li->slot[q] >= 0)
            q = (q + 1) & (uint64_t)(cap - 1);
        li->slot[q] = i;
    }
    return 1;
}

void md_leaf_index_free(md_leaf_index *li)
{
    free(li->slot);
    memset(li, 0, sizeof *li);
}

/* The level of the leaf that holds the cube of side h at lattice point q, or -1. */
static int32_t level_at(const md_leaves *lv, const md_leaf_index *li, const int64_t *q)
{
    if (!li->slot || q[0] < 0 || q[1] < 0 || q[2] < 0)
        return -1;
    for (int32_t l = 0; l <= li->maxlevel; l++) {
        int32_t k[3];
        for (int d = 0; d < 3; d++)
            k[d] = (int32_t)(q[d] >> l << l);
        uint64_t s = leaf_hash(k, l) & (uint64_t)(li->cap - 1);
        for (; li->slot[s] >= 0; s = (s + 1) & (uint64_t)(li->cap - 1)) {
            const md_leaf *f = lv->leaf + li->slot[s];
            if (f->level == l && f->ijk[0] == k[0] && f->ijk[1] == k[1] && f->ijk[2] == k[2])
                return l;
        }
    }
    return -1;
}

/* ---- the faces ----------------------------------------------------------------------- */

/* The fine triangles of the square of side 2^0 at lattice point Q0 (axes u, v of the face)
 * whose corners differ in sign: cut as a leaf of side h cuts them.  0 on NOMEM. */
static int cut_fine_square(coarse *c, const int64_t *Q0, int u, int v)
{
    int64_t Q[4][3];
    double fq[4];
    for (int q = 0; q < 4; q++) {
        memcpy(Q[q], Q0, sizeof Q[q]);
        Q[q][u] += q & 1;
        Q[q][v] += q >> 1;
        fq[q] = lattice_f(c, Q[q]);
    }
    /* The Kuhn diagonal from (0, 0) to (1, 1) splits the square in two. */
    static const int TRI[2][3] = {{0, 1, 3}, {0, 2, 3}};
    for (int t = 0; t < 2; t++) {
        int64_t T[3][3];
        double ft[3];
        for (int i = 0; i < 3; i++) {
            memcpy(T[i], Q[TRI[t][i]], sizeof T[i]);
            ft[i] = fq[TRI[t][i]];
        }
        if (!cut_triangle(c, T, ft))
            return 0;
    }
    return 1;
}

/* Appends the records of the fine edges along the lattice segment from P0 over n steps in
 * direction w (bit w) whose ends differ in the sign of f, to rec (*nr, room 64; beyond
 * that the square is cut finely instead: returns 2).  Only the points within the band of
 * f's linear interpolation between the segment's ends are looked at: the segment alone
 * fixes them, so every leaf that has the segment on its boundary finds the same ones.
 * 1 done, 0 NOMEM. */
static int side_crossings(coarse *c, const int64_t *P0, int w, int64_t n, double E,
                          int64_t *rec, int *nr)
{
    int64_t P1[3] = {P0[0], P0[1], P0[2]};
    P1[w] += n;
    double f0 = lattice_f(c, P0), f1 = lattice_f(c, P1);
    if ((f0 >= 0) == (f1 >= 0) && fmin(fabs(f0), fabs(f1)) > E)
        return 1; /* f is affine: no point of the segment is within E of 0 */
    double slope = (f1 - f0) / (double)n;
    int64_t i0 = 0, i1 = n;
    if (slope != 0) {
        double W = E + fabs(slope), t0 = (-W - f0) / slope, t1 = (W - f0) / slope;
        if (t0 > t1) {
            double t = t0;
            t0 = t1;
            t1 = t;
        }
        i0 = t0 - 1.0 > 0 ? (int64_t)(t0 - 1.0) : 0;
        i1 = t1 + 2.0 < (double)n ? (int64_t)(t1 + 2.0) : n;
    }
    int64_t p[3] = {P0[0], P0[1], P0[2]};
    p[w] += i0;
    double fp = lattice_f(c, p);
    for (int64_t i = i0; i < i1; i++) {
        int64_t q[3] = {p[0], p[1], p[2]};
        q[w]++;
        double fq = lattice_f(c, q);
        if ((fp >= 0) != (fq >= 0)) {
            if (*nr == 64)
                return 2;
            rec[*nr] = edge_record(c, p, 1 << w, fp, fq);
            if (rec[(*nr)++] < 0)
                return 0;
        }
        memcpy(p, q, sizeof p);
        fp = fq;
    }
    return 1;
}

typedef struct along {
    double t;
    int64_t rec;
} along;

static int cmp_along(const void *pa, const void *pb)
{
    const along *x = pa, *y = pb;
    if (x->t != y->t)
        return x->t < y->t ? -1 : 1;
    return (x->rec > y->rec) - (x->rec < y->rec);
}

/* The square of side 2^j at lattice point S0 on the face normal to axis d (axes u < v in
 * it), across which the leaves lie at offset `across` along d.  Where one leaf across
 * holds the whole square (its level >= j) and j > 0, the square is a patch that both
 * sides cut alike: the crossings of f's sign on its four sides, joined in pairs in their
 * order along the plane's trace (usually one segment).  Smaller leaves across, or none
 * at the square's first lattice point: the four quarters, down to side h, where the fine
 * triangles are cut as the leaves of side h cut them.  Squares that f keeps away from 0
 * are skipped.  0 on NOMEM. */
static int cut_square(coarse *c, const md_leaves *lv, const md_leaf_index *li, const int64_t *S0,
                      int j, int d, int u, int v, int64_t across, const double *g3, double E)
{
    int64_t n = (int64_t)1 << j;
    double fc[4];
    int pos = 0;
    for (int q = 0; q < 4; q++) {
        int64_t Q[3] = {S0[0], S0[1], S0[2]};
        Q[u] += (q & 1) * n;
        Q[v] += (q >> 1) * n;
        fc[q] = lattice_f(c, Q);
        pos += fc[q] >= 0;
    }
    if ((pos == 0 || pos == 4) &&
        fmin(fmin(fabs(fc[0]), fabs(fc[1])), fmin(fabs(fc[2]), fabs(fc[3]))) > E)
        return 1; /* f is affine: the square holds no point within E of 0 */
    if (j == 0)
        return cut_fine_square(c, S0, u, v);
    int64_t A[3] = {S0[0], S0[1], S0[2]};
    A[d] += across;
    int32_t lvl = level_at(lv, li, A);
    if (lvl >= j) {
        int64_t rec[64];
        int nr = 0, r = 1;
        for (int side = 0; side < 4 && r == 1; side++) {
            int64_t P0[3] = {S0[0], S0[1], S0[2]};
            int w = side < 2 ? u : v;
            if (side == 1)
                P0[v] += n; /* the side v = n, along u */
            if (side == 3)
                P0[u] += n; /* the side u = n, along v */
            r = side_crossings(c, P0, w, n, E, rec, &nr);
        }
        if (r == 0)
            return 0;
        if (r == 1 && nr % 2 == 0) {
            /* the trace's direction in the face: g3 x e_d, one for both sides of it */
            double t3[3] = {0, 0, 0};
            t3[(d + 1) % 3] = g3[(d + 2) % 3];
            t3[(d + 2) % 3] = -g3[(d + 1) % 3];
            along al[64];
            for (int i = 0; i < nr; i++) {
                const double *x = c->out->v[rec[i]].x;
                al[i].t = t3[0] * x[0] + t3[1] * x[1] + t3[2] * x[2];
                al[i].rec = rec[i];
            }
            qsort(al, (size_t)nr, sizeof *al, cmp_along);
            for (int i = 0; i + 1 < nr; i += 2)
                if (!push_segment(c, al[i].rec, al[i + 1].rec))
                    return 0;
            return 1;
        }
        /* more than 64 crossings, or an odd count (a crossing outside the band): the
         * leaf across finds the same on the same square and does the same - the fine
         * triangles */
        for (int64_t a = 0; a < n; a++)
            for (int64_t b = 0; b < n; b++) {
                int64_t Q[3] = {S0[0], S0[1], S0[2]};
                Q[u] += a;
                Q[v] += b;
                if (!cut_square(c, lv, li, Q, 0, d, u, v, across, g3, E))
                    return 0;
            }
        return 1;
    }
    for (int q = 0; q < 4; q++) {
        int64_t Q[3] = {S0[0], S0[1], S0[2]};
        Q[u] += (q & 1) * (n / 2);
        Q[v] += (q >> 1) * (n / 2);
        if (!cut_square(c, lv, li, Q, j - 1, d, u, v, across, g3, E))
            return 0;
    }
    return 1;
}

mfg_status md_sheet_coarse_leaf(const md_elements *el, const md_leaves *lv,
                                const md_leaf_index *li, const md_leaf *L, unit_buf *ub)
{
    coarse c;
    memset(&c, 0, sizeof c);
    c.el = el;
    c.lat = &lv->lat;
    c.a = lv->P[L->P_off];
    c.b = lv->P[L->P_off + 1];
    c.out = ub;
    mfg_status st = MFG_ERR_NOMEM;
    int64_t M = (int64_t)1 << L->level, P0[3] = {L->ijk[0], L->ijk[1], L->ijk[2]};
    const double *na = el->face_plane + 4 * c.a, *nb = el->face_plane + 4 * c.b;
    double g3[3] = {nb[0] - na[0], nb[1] - na[1], nb[2] - na[2]}; /* grad f = n_b - n_a */
    double X = 0;
    for (int d = 0; d < 3; d++)
        X = fmax(X, fmax(fabs(lv->lat.origin[d]), fabs(lv->lat.origin[d] + lv->lat.h *
                                                            (double)(P0[d] + M))));
    double E = BAND_REL * (fabs(na[3]) + fabs(nb[3]) + 2 * X + el->diag);
    for (int d = 0; d < 3; d++)
        for (int side = 0; side < 2; side++) {
            int u = d == 0 ? 1 : 0, v = d == 2 ? 1 : 2;
            int64_t S0[3] = {P0[0], P0[1], P0[2]};
            S0[d] += side * M;
            if (!cut_square(&c, lv, li, S0, L->level, d, u, v, side ? 0 : -1, g3, E))
                goto done;
        }
    if (c.nseg > 0) {
        /* The fan's centre: the mean of the boundary points, moved onto the plane (f is
         * affine: one Newton step), keyed by the leaf (no other leaf has it). */
        double z[3] = {0, 0, 0};
        for (int64_t s = 0; s < 2 * c.nseg; s++)
            for (int d = 0; d < 3; d++)
                z[d] += ub->v[c.seg[s]].x[d];
        for (int d = 0; d < 3; d++)
            z[d] /= (double)(2 * c.nseg);
        double fz = md_dist_car(el, c.a, z, NULL) - md_dist_car(el, c.b, z, NULL);
        double gg = g3[0] * g3[0] + g3[1] * g3[1] + g3[2] * g3[2];
        for (int d = 0; d < 3; d++)
            z[d] -= fz * g3[d] / gg;
        double da = md_dist_car(el, c.a, z, NULL), db = md_dist_car(el, c.b, z, NULL);
        double r = db < da ? db : da;
        vkey k;
        memset(&k, 0xff, sizeof k);
        k.a = c.a;
        k.b = c.b;
        for (int d = 0; d < 3; d++)
            k.e[0][d] = L->ijk[d];
        k.e[0][3] = 16 + L->level;
        k.c = -4;
        int64_t zr = md_sheet_push_vertex(ub, &k, z, r > 0 ? r : 0.0);
        if (zr < 0)
            goto done;
        /* Each triangle faces f > 0, as the marching tets orient theirs (its normal from
         * the points themselves: a triangle large enough to be kept has a reliable one). */
        for (int64_t s = 0; s < c.nseg; s++) {
            int64_t p = c.seg[2 * s], q = c.seg[2 * s + 1];
            const double *xp = ub->v[p].x, *xq = ub->v[q].x;
            double e1[3] = {xp[0] - z[0], xp[1] - z[1], xp[2] - z[2]};
            double e2[3] = {xq[0] - z[0], xq[1] - z[1], xq[2] - z[2]};
            double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                           e1[0] * e2[1] - e1[1] * e2[0]};
            if (n[0] * g3[0] + n[1] * g3[1] + n[2] * g3[2] < 0) {
                int64_t t = p;
                p = q;
                q = t;
            }
            if (!md_sheet_push_tri(ub, zr, p, q, c.a, c.b))
                goto done;
        }
    }
    st = MFG_OK;
done:
    free(c.hkey);
    free(c.hrec);
    free(c.seg);
    return st;
}
