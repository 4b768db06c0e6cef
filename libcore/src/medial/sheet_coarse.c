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
    if (c->nseg == c->cseg) {
        int64_t nc = c->cseg ? 2 * c->cseg : 256;
        if (!mfg_resize((void **)&c->seg, nc, 2 * sizeof *c->seg))
            return 0;
        c->cseg = nc;
    }
    c->seg[2 * c->nseg] = rec[0];
    c->seg[2 * c->nseg + 1] = rec[1];
    c->nseg++;
    return 1;
}

/* The fine triangles of the cube face normal to axis d at lattice coordinate I whose
 * corners may differ in sign: per row of squares, the range where the linearised f at the
 * square's centre is within W of 0 (W: the band plus half the change across a square),
 * widened by one square.  0 on NOMEM. */
static int cut_face(coarse *c, const int64_t *P0, int64_t M, int d, int64_t I, const double *g3,
                    double E)
{
    int u = d == 0 ? 1 : 0, v = d == 2 ? 1 : 2;
    int64_t base[3] = {P0[0], P0[1], P0[2]};
    base[d] = I;
    double F0 = lattice_f(c, base), h = c->lat->h;
    double gu = h * g3[u], gv = h * g3[v];
    double W = E + 0.5 * (fabs(gu) + fabs(gv));
    for (int64_t k = 0; k < M; k++) {
        double B = F0 + gv * ((double)k + 0.5);
        int64_t j0 = 0, j1 = M - 1;
        if (gu != 0) {
            double t0 = (-W - B) / gu - 0.5, t1 = (W - B) / gu - 0.5;
            if (t0 > t1) {
                double t = t0;
                t0 = t1;
                t1 = t;
            }
            if (!(t1 >= -1.0) || !(t0 <= (double)M))
                continue;
            j0 = t0 - 1.0 > 0 ? (int64_t)(t0 - 1.0) : 0;
            j1 = t1 + 1.0 < (double)(M - 1) ? (int64_t)(t1 + 1.0) : M - 1;
        } else if (!(fabs(B) <= W)) {
            continue;
        }
        for (int64_t j = j0; j <= j1; j++) {
            /* Corners: (j, k), (j+1, k), (j, k+1), (j+1, k+1) of the face. */
            int64_t Q[4][3];
            double fq[4];
            for (int q = 0; q < 4; q++) {
                memcpy(Q[q], base, sizeof Q[q]);
                Q[q][u] += j + (q & 1);
                Q[q][v] += k + (q >> 1);
                fq[q] = lattice_f(c, Q[q]);
            }
            /* The Kuhn diagonal (j, k) - (j+1, k+1) splits the square in two. */
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
        }
    }
    return 1;
}

mfg_status md_sheet_coarse_leaf(const md_elements *el, const md_leaves *lv, const md_leaf *L,
                                unit_buf *ub)
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
        for (int side = 0; side < 2; side++)
            if (!cut_face(&c, P0, M, d, P0[d] + side * M, g3, E))
                goto done;
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
