/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/winding.c - The winding number in front of every face of the arrangement, and
 * the faces that bound {w >= 1}.  Faces joined across an edge that has exactly two faces
 * (a closed chain makes those two consistently oriented, with equal jumps) see the same
 * winding in front: they form a patch, and one ray per patch decides it.  The ray starts
 * at a point strictly inside one face (a grid point of its projection lifted onto its
 * plane: ARR_LIFT) and runs along the face's projection axis towards its front; w in
 * front is the signed count of the input triangles it crosses (w = 0 at infinity), each
 * decided exactly: the projection of the start inside the projected triangle (orient2d
 * on doubles, with the start perturbed by (eps, eps^2) so that edges and corners are
 * never hit - every triangle of an edge sees the same perturbation), and the start on
 * the triangle's back or front (arr_orient3d). */
#include "arrange/arrange.h"
#include "common/expansion.h"

/* Faces of a patch tried as ray starts, largest first. */
#define RAY_TRIES 16


/* Sign of orient2d(p, q, r) on doubles with r perturbed by (eps, eps^2) along (x, y):
 * never 0 unless p and q coincide. */
static int orient_perturbed(const double *p, const double *q, const double *r)
{
    int s = mfg_orient2d(p[0], p[1], q[0], q[1], r[0], r[1]);
    if (s != 0)
        return s;
    /* d/d eps of (q - p) x (r + (eps, eps^2) - p) = -(q_y - p_y), then (q_x - p_x) */
    if (q[1] != p[1])
        return p[1] > q[1] ? 1 : -1;
    if (q[0] != p[0])
        return q[0] > p[0] ? 1 : -1;
    return 0;
}

typedef struct ray_ctx {
    const arr_ctx *c;
    const arr_points *P;
    int64_t start;      /* the lifted point */
    double uv[2];       /* its projection */
    int axis, dir;
    int64_t w;
} ray_ctx;

static int ray_hit(void *user, int64_t t)
{
    ray_ctx *R = user;
    const arr_ctx *c = R->c;
    if (c->tcluster[t] < 0)
        return 1;
    const int64_t *V = c->tri + 3 * t;
    int i1 = (R->axis + 1) % 3, i2 = (R->axis + 2) % 3;
    double p[3][2];
    for (int k = 0; k < 3; k++) {
        p[k][0] = c->T.xyz[3 * V[k] + i1];
        p[k][1] = c->T.xyz[3 * V[k] + i2];
    }
    int o2 = mfg_orient2d(p[0][0], p[0][1], p[1][0], p[1][1], p[2][0], p[2][1]);
    if (o2 == 0)
        return 1; /* parallel to the ray */
    for (int k = 0; k < 3; k++)
        if (orient_perturbed(p[k], p[(k + 1) % 3], R->uv) != o2)
            return 1;
    int s3 = arr_orient3d(R->P, V[0], V[1], V[2], R->start);
    if (s3 == 0)
        return 1; /* the start's own plane */
    if (s3 == o2 * R->dir)
        R->w += o2 * R->dir;
    return 1;
}

static double approx_area(const arr_points *P, const arr_face *f)
{
    double a[3], b[3], d[3], e1[3], e2[3], n[3];
    arr_coords(P, f->v[0], a);
    arr_coords(P, f->v[1], b);
    arr_coords(P, f->v[2], d);
    mfg_sub3(b, a, e1);
    mfg_sub3(d, a, e2);
    mfg_cross3(e1, e2, n);
    return mfg_norm3(n);
}

/* The lifted start points lie on the arrangement's grid (implicit.h): a face so thin
 * that no candidate grid point falls inside it (a sliver where two sheets cross at a
 * grazing angle) is decided by the faces round it (decide_by_balance). */
static double snap(double x)
{
    return ldexp(nearbyint(ldexp(x, ARR_GRID_LOG2)), -ARR_GRID_LOG2);
}

/* The winding number in front of face f, or INT64_MIN when no grid point lies strictly
 * inside it.  -2 (as *status) when out of memory. */
static int64_t front_winding(arr_ctx *c, const arr_bvh *bvh, const arr_face *f, int *nomem)
{
    const arr_cluster *K = &c->cl[f->cluster];
    int axis = K->axis, i1 = (axis + 1) % 3, i2 = (axis + 2) % 3;
    arr_points P = arr_view(&c->T);
    double x[3][3];
    for (int k = 0; k < 3; k++)
        arr_coords(&P, f->v[k], x[k]);
    int sf = arr_orient2d(&P, f->v[0], f->v[1], f->v[2], axis);
    if (sf == 0)
        return INT64_MIN;
    /* a few interior candidates: the centroid, then points pulled towards each corner */
    static const double wts[4][3] = {
        {1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.5, 0.25, 0.25}, {0.25, 0.5, 0.25}, {0.25, 0.25, 0.5}};
    int64_t mark = c->T.npts;
    for (int w = 0; w < 4; w++) {
        double u = snap(wts[w][0] * x[0][i1] + wts[w][1] * x[1][i1] + wts[w][2] * x[2][i1]);
        double v = snap(wts[w][0] * x[0][i2] + wts[w][1] * x[1][i2] + wts[w][2] * x[2][i2]);
        int64_t L = arr_lift(&c->T, c->tri + 3 * K->rep, axis, u, v);
        if (L == -1) {
            *nomem = 1;
            return INT64_MIN;
        }
        if (L < 0)
            continue;
        P = arr_view(&c->T);
        int inside = 1;
        for (int k = 0; k < 3 && inside; k++)
            inside = arr_orient2d(&P, f->v[k], f->v[(k + 1) % 3], L, axis) == sf;
        if (!inside) {
            arr_truncate(&c->T, mark);
            continue;
        }
        ray_ctx R;
        R.c = c;
        R.P = &P;
        R.start = L;
        R.uv[0] = u;
        R.uv[1] = v;
        R.axis = axis;
        R.dir = sf;
        R.w = 0;
        double o[3];
        arr_coords(&P, L, o);
        o[i1] = u;
        o[i2] = v;
        int r = arr_bvh_ray(bvh, o, axis, sf, ray_hit, &R);
        arr_truncate(&c->T, mark);
        if (r < 0) {
            *nomem = 1;
            return INT64_MIN;
        }
        return R.w;
    }
    return INT64_MIN;
}

typedef struct by_area {
    double area;
    int64_t f;
} by_area;

static int cmp_patch(const void *a, const void *b)
{
    const int64_t *x = a, *y = b; /* (root, face) pairs */
    if (x[0] != y[0])
        return x[0] < y[0] ? -1 : 1;
    return x[1] < y[1] ? -1 : x[1] > y[1];
}

/* The arrangement's edges: each face side's edge (fe), and per edge its faces (CSR). */
typedef struct edges {
    int64_t *fe;      /* 3 per face */
    int64_t ne;
    int64_t *start;   /* ne + 1 */
    int64_t *item;    /* 3 nf: face * 3 + side */
} edges;

static void edges_free(edges *E)
{
    free(E->fe);
    free(E->start);
    free(E->item);
}

static int build_edges(const arr_ctx *c, edges *E)
{
    int64_t nf = c->nface;
    hmap em;
    E->fe = malloc((size_t)(3 * nf + 1) * sizeof *E->fe);
    E->item = malloc((size_t)(3 * nf + 1) * sizeof *E->item);
    E->start = NULL;
    if (!E->fe || !E->item || !hmap_init(&em, 3 * nf + 1))
        return 0;
    E->ne = 0;
    for (int64_t f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++) {
            int64_t a = c->face[f].v[k], b = c->face[f].v[(k + 1) % 3];
            hkey key = mkkey(a < b ? a : b, a < b ? b : a, 0, 0);
            int64_t id = hmap_get(&em, &key);
            if (id < 0) {
                id = E->ne++;
                if (!hmap_put(&em, &key, id)) {
                    hmap_free(&em);
                    return 0;
                }
            }
            E->fe[3 * f + k] = id;
        }
    hmap_free(&em);
    E->start = calloc((size_t)(E->ne + 2), sizeof *E->start);
    if (!E->start)
        return 0;
    for (int64_t i = 0; i < 3 * nf; i++)
        E->start[E->fe[i] + 2]++;
    for (int64_t e = 0; e < E->ne; e++)
        E->start[e + 2] += E->start[e + 1];
    for (int64_t i = 0; i < 3 * nf; i++)
        E->item[E->start[E->fe[i] + 1]++] = i;
    return 1;
}

/* +1 when face side fs (face * 3 + side) runs from the smaller point id to the larger. */
static int side_dir(const arr_ctx *c, int64_t fs)
{
    const arr_face *F = &c->face[fs / 3];
    int k = (int)(fs % 3);
    return F->v[k] < F->v[(k + 1) % 3] ? 1 : -1;
}

/* Patches whose faces hold no start point (slivers thinner than a rounding step where
 * two sheets cross at a grazing angle) take the decision that closes the surface: at an
 * edge where every other face is decided, the kept faces must use the edge as often one
 * way as the other.  Returns the number left undecided (-1: out of memory). */
static int64_t decide_by_balance(const arr_ctx *c, const edges *E, const int64_t *root,
                                 int8_t *state /* per face: 1 keep, 0 drop, -1 undecided */)
{
    int64_t nf = c->nface, left = 0;
    for (int64_t f = 0; f < nf; f++)
        left += state[f] < 0;
    for (int changed = 1; changed && left > 0;) {
        changed = 0;
        for (int64_t e = 0; e < E->ne && left > 0; e++) {
            int64_t net = 0, patch = -1, contrib = 0;
            int mixed = 0;
            for (int64_t i = E->start[e]; i < E->start[e + 1]; i++) {
                int64_t fs = E->item[i], f = fs / 3;
                if (state[f] == 1)
                    net += side_dir(c, fs);
                else if (state[f] < 0) {
                    if (patch >= 0 && root[f] != patch)
                        mixed = 1;
                    patch = root[f];
                    contrib += side_dir(c, fs);
                }
            }
            if (patch < 0 || mixed || contrib == 0)
                continue;
            int keep;
            if (net == 0)
                keep = 0;
            else if (net + contrib == 0)
                keep = 1;
            else
                continue; /* cannot balance here: another edge may tell */
            for (int64_t f = 0; f < nf; f++)
                if (state[f] < 0 && root[f] == patch) {
                    state[f] = (int8_t)keep;
                    left--;
                }
            changed = 1;
        }
    }
    return left;
}

/* ---- The winding round an edge ------------------------------------------------------- */

/* A face too thin to hold a start point takes its winding from a neighbour across an edge
 * where three or more faces meet: round that edge (line L through p, q, direction l) the
 * faces are ordered by angle, and crossing face i in the direction of increasing angle
 * changes w by -mult * (its front lies ahead).  Every face lies in its cluster's plane
 * (normal n of the representative triangle), so with d_i the direction in that plane from
 * L towards the face's third corner r_i (d_i = s_i (n_i x l), s_i the side of r_i):
 *   sign (d_i x d_j) . l = s_i s_j sign det(n_i, n_j, l),   sign d_i . d_j = s_i s_j sign n_i . n_j
 * and det(n_i, n_j, l) = +-|n_i x n_j| |l| (both planes hold L): its sign is that of a
 * non-zero component k of n_i x n_j times the sign of q_k - p_k.  All exact. */

#define RX_MAX 64 /* components of the expansions below (products of the normals) */

/* The exact normal (b - a) x (c - a) of an explicit triangle, each component an
 * expansion (at most 8 components). */
static void exact_normal(const double *xyz, const int64_t *V, double n[3][8], int len[3])
{
    double u[3][2], w[3][2];
    int lu[3], lw[3];
    for (int k = 0; k < 3; k++) {
        lu[k] = expn_diff(xyz[3 * V[1] + k], xyz[3 * V[0] + k], u[k]);
        lw[k] = expn_diff(xyz[3 * V[2] + k], xyz[3 * V[0] + k], w[k]);
    }
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        double p1[8], p2[8], s1[8], s2[8];
        int l1 = expn_mul(lu[i], u[i], lw[j], w[j], p1, s1, s2);
        int l2 = expn_mul(lu[j], u[j], lw[i], w[i], p2, s1, s2);
        len[k] = expn_compress(expn_diff_expansions(l1, p1, l2, p2, n[k]), n[k]);
    }
}

/* Sign of a . b - c . d for expansions (a b and c d products of two of the normal's
 * components). */
static int sign_ab_minus_cd(const double *a, int la, const double *b, int lb, const double *c,
                            int lc, const double *d, int ld)
{
    double p1[2 * RX_MAX], p2[2 * RX_MAX], s1[2 * RX_MAX], s2[2 * RX_MAX], r[4 * RX_MAX];
    int l1 = expn_mul(la, a, lb, b, p1, s1, s2);
    int l2 = expn_mul(lc, c, ld, d, p2, s1, s2);
    return expn_sign(expn_diff_expansions(l1, p1, l2, p2, r), r);
}

/* sign of n_i . n_j */
static int normals_dot(double ni[3][8], const int *li, double nj[3][8], const int *lj)
{
    double acc[6 * RX_MAX], p[2 * RX_MAX], s1[2 * RX_MAX], s2[2 * RX_MAX], t[6 * RX_MAX];
    int la = 0;
    for (int k = 0; k < 3; k++) {
        int lp = expn_mul(li[k], ni[k], lj[k], nj[k], p, s1, s2);
        int lt = expn_sum(la, acc, lp, p, t);
        la = expn_compress(lt, t);
        memcpy(acc, t, (size_t)la * sizeof *acc);
    }
    return expn_sign(la, acc);
}

typedef struct rface {
    int64_t f;       /* the face */
    int s;           /* side of its third corner: sign of (n x l) . (r - p) */
    int o;           /* its front along +n (1) or -n (-1) */
    double n[3][8];  /* its plane's normal, exactly */
    int ln[3];
    int half;        /* 0: angle in [0, pi) from the first face, 1: [pi, 2 pi) */
} rface;

/* sign det(n_i, n_j, l), l = q - p */
static int det_nnl(const arr_points *P, const rface *a, const rface *b, int64_t p, int64_t q)
{
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        int sk = sign_ab_minus_cd(a->n[i], a->ln[i], b->n[j], b->ln[j], a->n[j], a->ln[j],
                                  b->n[i], b->ln[i]);
        if (sk != 0)
            return sk * arr_cmp(P, q, p, k);
    }
    return 0;
}

/* The winding in front of face f from the faces round its side from p to q whose
 * patches' windings are known (pw by patch root); INT64_MIN when none is. */
static int64_t winding_round_edge(const arr_ctx *c, const int64_t *root, const int64_t *pw,
                                  const int64_t *faces, int64_t nfaces, int64_t p, int64_t q,
                                  int64_t f, rface *R)
{
    arr_points P = arr_view(&c->T);
    int known = -1, me = -1;
    if (nfaces > 16)
        return INT64_MIN;
    for (int64_t i = 0; i < nfaces; i++) {
        const arr_face *F = &c->face[faces[i]];
        const arr_cluster *K = &c->cl[F->cluster];
        rface *r = &R[i];
        r->f = faces[i];
        int64_t third = -1;
        for (int k = 0; k < 3; k++)
            if (F->v[k] != p && F->v[k] != q)
                third = F->v[k];
        if (third < 0)
            return INT64_MIN;
        r->s = arr_orient2d(&P, p, q, third, K->axis) * K->sign;
        r->o = arr_orient2d(&P, F->v[0], F->v[1], F->v[2], K->axis) * K->sign;
        if (r->s == 0 || r->o == 0)
            return INT64_MIN;
        exact_normal(c->T.xyz, c->tri + 3 * K->rep, r->n, r->ln);
        if (faces[i] == f)
            me = (int)i;
        else if (known < 0 && pw[root[faces[i]]] != INT64_MIN)
            known = (int)i;
    }
    if (me < 0 || known < 0)
        return INT64_MIN;
    /* halves relative to face 0, then insertion sort by angle */
    for (int64_t i = 0; i < nfaces; i++) {
        if (i == 0) {
            R[i].half = 0;
            continue;
        }
        int sn = R[0].s * R[i].s * det_nnl(&P, &R[0], &R[i], p, q);
        int cs = R[0].s * R[i].s * normals_dot(R[0].n, R[0].ln, R[i].n, R[i].ln);
        R[i].half = sn > 0 || (sn == 0 && cs > 0) ? 0 : 1;
    }
    int order[16];
    for (int i = 0; i < nfaces; i++)
        order[i] = i;
    for (int i = 1; i < nfaces; i++) {
        int x = order[i], j = i - 1;
        while (j >= 0) {
            const rface *a = &R[order[j]], *b = &R[x];
            int before; /* b comes before a */
            if (a->half != b->half)
                before = b->half < a->half;
            else
                before = a->s * b->s * det_nnl(&P, b, a, p, q) > 0;
            if (!before)
                break;
            order[j + 1] = order[j];
            j--;
        }
        order[j + 1] = x;
    }
    /* the wedge after each face (in sorted order), from the known face */
    int64_t wedge[16];
    int pk = -1, pm = -1;
    for (int i = 0; i < nfaces; i++) {
        if (order[i] == known)
            pk = i;
        if (order[i] == me)
            pm = i;
    }
    const rface *K0 = &R[order[pk]];
    int64_t wk = pw[root[K0->f]];
    int64_t mk = c->face[K0->f].mult;
    /* ahead of the known face: its front when its front lies ahead, else its back */
    wedge[pk] = K0->s * K0->o > 0 ? wk : wk + mk;
    for (int step = 1; step < nfaces; step++) {
        int i = (pk + step) % (int)nfaces, prev = (i + (int)nfaces - 1) % (int)nfaces;
        const rface *r = &R[order[i]];
        wedge[i] = wedge[prev] - c->face[r->f].mult * (r->s * r->o);
    }
    const rface *M = &R[order[pm]];
    int64_t behind = wedge[(pm + (int)nfaces - 1) % (int)nfaces];
    return M->s * M->o > 0 ? wedge[pm] : behind;
}

int arr_boundary_faces(arr_ctx *c, const arr_bvh *bvh, uint8_t *keep)
{
    int64_t nf = c->nface;
    edges E;
    memset(&E, 0, sizeof E);
    int64_t *uf = malloc((size_t)(nf + 1) * sizeof *uf);
    int64_t *pairs = malloc((size_t)(2 * nf + 2) * sizeof *pairs);
    double *area = malloc((size_t)(nf + 1) * sizeof *area);
    int8_t *state = malloc((size_t)(nf + 1));
    int64_t *pw = malloc((size_t)(nf + 1) * sizeof *pw); /* w in front, per patch root */
    if (!uf || !pairs || !area || !state || !pw || !build_edges(c, &E)) {
        free(pw);
        free(uf);
        free(pairs);
        free(area);
        free(state);
        edges_free(&E);
        c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        return 0;
    }
    /* patches: faces joined across edges with exactly two faces, consistently oriented
     * with equal jumps (what a closed chain gives; anything else stays apart) */
    for (int64_t f = 0; f < nf; f++)
        uf[f] = f;
    for (int64_t e = 0; e < E.ne; e++) {
        if (E.start[e + 1] - E.start[e] != 2)
            continue;
        int64_t s0 = E.item[E.start[e]], s1 = E.item[E.start[e] + 1];
        int64_t f0 = s0 / 3, f1 = s1 / 3;
        if (side_dir(c, s0) == side_dir(c, s1) || c->face[f0].mult != c->face[f1].mult)
            continue;
        int64_t a = mfg_uf_find(uf, f0), b = mfg_uf_find(uf, f1);
        if (a < b)
            uf[b] = a;
        else if (b < a)
            uf[a] = b;
    }
    arr_points P = arr_view(&c->T);
    for (int64_t f = 0; f < nf; f++) {
        pairs[2 * f] = mfg_uf_find(uf, f);
        pairs[2 * f + 1] = f;
        area[f] = approx_area(&P, &c->face[f]);
        uf[f] = pairs[2 * f];
        state[f] = -1;
        pw[f] = INT64_MIN;
    }
    if (nf > 1)
        qsort(pairs, (size_t)nf, 2 * sizeof *pairs, cmp_patch);
    int ok = 1;
    by_area cand[RAY_TRIES];
    for (int64_t i = 0; i < nf && ok;) {
        int64_t j = i;
        while (j < nf && pairs[2 * j] == pairs[2 * i])
            j++;
        if (!mfg_prog_poll(c->prog, (double)i, (double)nf)) {
            c->st = MFG_ERR_CANCELLED;
            ok = 0;
            break;
        }
        /* the largest faces of the patch (a small selection, not a sort) */
        int nc = 0;
        for (int64_t k = i; k < j; k++) {
            int64_t f = pairs[2 * k + 1];
            by_area b = {area[f], f};
            int pos = nc < RAY_TRIES ? nc++ : RAY_TRIES;
            if (pos == RAY_TRIES) {
                if (b.area <= cand[RAY_TRIES - 1].area)
                    continue;
                pos = RAY_TRIES - 1;
            }
            while (pos > 0 && cand[pos - 1].area < b.area) {
                cand[pos] = cand[pos - 1];
                pos--;
            }
            cand[pos] = b;
        }
        int64_t w = INT64_MIN;
        int nomem = 0;
        for (int t = 0; t < nc && w == INT64_MIN && !nomem; t++)
            w = front_winding(c, bvh, &c->face[cand[t].f], &nomem);
        if (nomem) {
            c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
            ok = 0;
            break;
        }
        pw[pairs[2 * i]] = w;
        i = j;
    }
    /* patches no start point decided: from their neighbours round an edge, as long as
     * that decides more */
    rface R[16];
    for (int progress = 1; ok && progress;) {
        progress = 0;
        for (int64_t f = 0; f < nf; f++) {
            if (pw[uf[f]] != INT64_MIN)
                continue;
            for (int k = 0; k < 3 && pw[uf[f]] == INT64_MIN; k++) {
                int64_t e = E.fe[3 * f + k], n = E.start[e + 1] - E.start[e];
                if (n < 3 || n > 16)
                    continue;
                int64_t faces[16];
                for (int64_t q = 0; q < n; q++)
                    faces[q] = E.item[E.start[e] + q] / 3;
                int64_t w = winding_round_edge(c, uf, pw, faces, n, c->face[f].v[k],
                                               c->face[f].v[(k + 1) % 3], f, R);
                if (w != INT64_MIN) {
                    pw[uf[f]] = w;
                    progress = 1;
                }
            }
        }
    }
    for (int64_t f = 0; f < nf; f++)
        if (pw[uf[f]] != INT64_MIN)
            state[f] = (int8_t)(pw[uf[f]] <= 0 && pw[uf[f]] + c->face[f].mult > 0);
    if (ok) {
        int64_t left = decide_by_balance(c, &E, uf, state);
        if (left > 0) {
            c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: %lld faces of slivers could not "
                             "be decided", (long long)left);
            ok = 0;
        }
        for (int64_t f = 0; f < nf; f++)
            keep[f] = state[f] == 1;
    }
    free(uf);
    free(pairs);
    free(area);
    free(state);
    free(pw);
    edges_free(&E);
    return ok;
}
