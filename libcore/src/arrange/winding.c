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

/* Faces of a patch tried as ray starts, largest first. */
#define RAY_TRIES 16


static int64_t uf_find(int64_t *uf, int64_t i)
{
    while (uf[i] != i) {
        uf[i] = uf[uf[i]];
        i = uf[i];
    }
    return i;
}

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

int arr_boundary_faces(arr_ctx *c, const arr_bvh *bvh, uint8_t *keep)
{
    int64_t nf = c->nface;
    edges E;
    memset(&E, 0, sizeof E);
    int64_t *uf = malloc((size_t)(nf + 1) * sizeof *uf);
    int64_t *pairs = malloc((size_t)(2 * nf + 2) * sizeof *pairs);
    double *area = malloc((size_t)(nf + 1) * sizeof *area);
    int8_t *state = malloc((size_t)(nf + 1));
    if (!uf || !pairs || !area || !state || !build_edges(c, &E)) {
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
        int64_t a = uf_find(uf, f0), b = uf_find(uf, f1);
        if (a < b)
            uf[b] = a;
        else if (b < a)
            uf[a] = b;
    }
    arr_points P = arr_view(&c->T);
    for (int64_t f = 0; f < nf; f++) {
        pairs[2 * f] = uf_find(uf, f);
        pairs[2 * f + 1] = f;
        area[f] = approx_area(&P, &c->face[f]);
        uf[f] = pairs[2 * f];
        state[f] = -1;
    }
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
        if (w != INT64_MIN)
            for (int64_t k = i; k < j; k++) {
                int64_t f = pairs[2 * k + 1];
                state[f] = (int8_t)(w <= 0 && w + c->face[f].mult > 0);
            }
        i = j;
    }
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
    edges_free(&E);
    return ok;
}
