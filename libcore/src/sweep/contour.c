/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/contour.c - F and B, and the contour between them.
 *
 * On triangle T with normal n, f(p) = n . tau(p) = n . (k x p) is linear in p: T splits
 * along at most one line f = 0 into its F part (f <= 0: circles enter O there, the arcs
 * of O start) and its B part (f >= 0); a face perpendicular to the axis (f = 0 all over)
 * is F.  The signs of f at the corners are exact (mfg_cross_dot_sign on the grid
 * coordinates); the points where the line crosses a side are rounded to the grid.  Two
 * triangles of a side cut it at different points (their normals differ), so each side
 * carries every cut point of both, and each triangle's pieces run through all of them:
 * the pieces of neighbours share their vertices and the chain stays closed.  The contour
 * C = boundary of F is made of the cut lines inside triangles and of the pieces of sides
 * with F on one side and B on the other.  Each contour edge is cut into pieces short
 * enough that its strip quads' twist stays within its share of the tolerance (the
 * points are added to the pieces beside it too), then F is emitted at t = 0 and B turned
 * by theta, each piece triangulated on its plane. */
#include "sweep/envelope.h"
#include "mesh/polygon_triangulate.h"

typedef struct edge_pt {
    int64_t edge;
    double s;   /* position along the side from ea to eb */
    int64_t id;
} edge_pt;

typedef struct chord_pt {
    int64_t tri;
    int64_t order;
    int64_t id;
} chord_pt;

/* A contour edge before the twist split: u -> v, on a side (edge >= 0, between the
 * points at s0 and s1) or on the cut line of triangle tri. */
typedef struct cedge {
    int64_t u, v;
    int64_t edge, tri;
    double s0, s1;
} cedge;

typedef struct split {
    sw_env *e;
    int8_t *sgn;        /* 3 per triangle: the sign of f at each corner */
    double *fv;         /* 3 per triangle: f at each corner (rounded) */
    int64_t *eid;       /* 3 per triangle: the side's edge */
    int64_t *ea, *eb;   /* edge ends, ea < eb */
    int64_t *et;        /* 2 per edge: the triangle running ea -> eb, and eb -> ea */
    int64_t ne;
    int64_t *cut;       /* 2 per triangle: its cut points (-1: none) */
    int8_t *cutk;       /* 2 per triangle: the side of a made cut point, 3 + k for corner k */
    double *cuts;       /* 2 per triangle: the made point's position along its edge */
    int8_t *mixed;      /* F and B both */
    int8_t *type;       /* -1: all F, +1: all B (not mixed) */
    int64_t *group;     /* planar group of each triangle */
    int64_t ngroups;
    edge_pt *ep;
    int64_t nep, capep;
    int64_t *estart;    /* CSR of ep by edge (sorted by s) */
    chord_pt *cp;
    int64_t ncp, capcp;
    int64_t *cstart;    /* CSR of cp by triangle */
    cedge *ce;
    int64_t nce, capce;
    /* scratch for a ring */
    int64_t *ring;
    int8_t *rside;
    int64_t capring;
    double *xy;
    int64_t *tris;
    int64_t capxy;
    /* scratch of the twist split: the fractions where an edge is cut */
    double *fr;
    int64_t nfr, capfr;
} split;

static int nomem(sw_env *e)
{
    e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    return 0;
}

/* ---- Edges and planar groups ---------------------------------------------------------- */

static int build_edges(split *S)
{
    sw_env *e = S->e;
    int64_t nt = e->nt;
    S->eid = malloc((size_t)(3 * nt + 1) * sizeof *S->eid);
    S->ea = malloc((size_t)(3 * nt / 2 + 2) * sizeof *S->ea);
    S->eb = malloc((size_t)(3 * nt / 2 + 2) * sizeof *S->eb);
    S->et = malloc((size_t)(3 * nt + 4) * sizeof *S->et);
    S->group = malloc((size_t)(nt + 1) * sizeof *S->group);
    if (!S->eid || !S->ea || !S->eb || !S->et || !S->group)
        return 0;
    for (int64_t i = 0; i < 3 * nt; i++)
        S->eid[i] = -1;
    S->ne = 0;
    for (int64_t t = 0; t < nt; t++) {
        S->group[t] = t;
        for (int k = 0; k < 3; k++) {
            int64_t u = e->nb[3 * t + k];
            if (u < t)
                continue;
            int64_t a = e->tri[3 * t + k], b = e->tri[3 * t + (k + 1) % 3];
            int64_t id = S->ne++;
            S->ea[id] = a < b ? a : b;
            S->eb[id] = a < b ? b : a;
            S->et[2 * id] = a < b ? t : u;
            S->et[2 * id + 1] = a < b ? u : t;
            S->eid[3 * t + k] = id;
            for (int j = 0; j < 3; j++)
                if (e->tri[3 * u + j] == b && e->tri[3 * u + (j + 1) % 3] == a)
                    S->eid[3 * u + j] = id;
        }
    }
    /* planar groups: neighbours in one plane (exactly) */
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *V = e->tri + 3 * t;
        for (int k = 0; k < 3; k++) {
            int64_t u = e->nb[3 * t + k];
            if (u <= t)
                continue;
            int64_t d = -1;
            for (int j = 0; j < 3; j++) {
                int64_t w = e->tri[3 * u + j];
                if (w != V[k] && w != V[(k + 1) % 3])
                    d = w;
            }
            if (d >= 0 && mfg_orient3d(e->x + 3 * V[0], e->x + 3 * V[1], e->x + 3 * V[2],
                                       e->x + 3 * d) == 0) {
                int64_t a = mfg_uf_find(S->group, t), b = mfg_uf_find(S->group, u);
                if (a < b)
                    S->group[b] = a;
                else if (b < a)
                    S->group[a] = b;
            }
        }
    }
    int64_t *id = malloc((size_t)(nt + 1) * sizeof *id);
    if (!id)
        return 0;
    S->ngroups = 0;
    for (int64_t t = 0; t < nt; t++)
        id[t] = -1;
    for (int64_t t = 0; t < nt; t++) {
        int64_t r = mfg_uf_find(S->group, t);
        if (id[r] < 0)
            id[r] = S->ngroups++;
        S->group[t] = r;
    }
    for (int64_t t = 0; t < nt; t++)
        S->group[t] = id[S->group[t]];
    free(id);
    return 1;
}

/* ---- Signs and cut points -------------------------------------------------------------- */

static int add_edge_pt(split *S, int64_t edge, double s, int64_t id)
{
    if (!mfg_grow((void **)&S->ep, &S->capep, S->nep + 1, sizeof *S->ep))
        return 0;
    S->ep[S->nep].edge = edge;
    S->ep[S->nep].s = s;
    S->ep[S->nep].id = id;
    S->nep++;
    return 1;
}

/* A new point of edge at s (ea -> eb). */
static int64_t edge_point(split *S, int64_t edge, double s)
{
    const double *a = S->e->x + 3 * S->ea[edge], *b = S->e->x + 3 * S->eb[edge];
    double p[3];
    for (int k = 0; k < 3; k++)
        p[k] = a[k] + s * (b[k] - a[k]);
    int64_t id = sw_add_vertex(S->e, p);
    if (id < 0 || !add_edge_pt(S, edge, s, id))
        return -1;
    return id;
}

static int classify(split *S)
{
    sw_env *e = S->e;
    int64_t nt = e->nt;
    S->sgn = malloc((size_t)(3 * nt + 1));
    S->fv = malloc((size_t)(3 * nt + 1) * sizeof *S->fv);
    S->cut = malloc((size_t)(2 * nt + 1) * sizeof *S->cut);
    S->cutk = malloc((size_t)(2 * nt + 1));
    S->cuts = malloc((size_t)(2 * nt + 1) * sizeof *S->cuts);
    S->mixed = malloc((size_t)(nt + 1));
    S->type = malloc((size_t)(nt + 1));
    /* the first cut point made on each edge, so that the second triangle of the side can
     * reuse it when it cuts at the same place (a linear search would be quadratic) */
    int64_t *first = malloc((size_t)(S->ne + 1) * sizeof *first);
    if (!S->sgn || !S->fv || !S->cut || !S->cutk || !S->cuts || !S->mixed || !S->type || !first) {
        free(first);
        return nomem(e);
    }
    for (int64_t i = 0; i < S->ne; i++)
        first[i] = -1;
    for (int64_t t = 0; t < nt; t++) {
        if ((t & 1023) == 0 && !mfg_prog_poll(e->prog, (double)t, (double)nt)) {
            free(first);
            e->st_code = MFG_ERR_CANCELLED;
            return 0;
        }
        const int64_t *V = e->tri + 3 * t;
        const double *a = e->x + 3 * V[0], *b = e->x + 3 * V[1], *c = e->x + 3 * V[2];
        double u[3], w[3], n[3];
        mfg_sub3(b, a, u); /* exact: differences of grid points below 1 in size */
        mfg_sub3(c, a, w);
        mfg_cross3(u, w, n);
        int neg = 0, pos = 0;
        /* f = p . (n x k): its gradient n x k lies in the plane, so |f| / |n x k| is a
         * corner's distance from the line f = 0 */
        double grad = hypot(n[0] * e->k[1] - n[1] * e->k[0],
                            hypot(n[1] * e->k[2] - n[2] * e->k[1], n[2] * e->k[0] - n[0] * e->k[2]));
        for (int k = 0; k < 3; k++) {
            const double *p = e->x + 3 * V[k];
            int s = mfg_cross_dot_sign(e->k, p, u, w);
            double tau[3];
            mfg_cross3(e->k, p, tau);
            S->fv[3 * t + k] = mfg_dot3(tau, n);
            /* a line f = 0 within SW_CUT_SNAP of a corner goes through it: cut where
             * the line is, the side would get a point 1e-15 from the corner, and the
             * strips of the contour there become sheets 1e-15 above a face
             * perpendicular to the axis that cross its turned copies at grazing angles
             * (a plate with a hole about the hole's axis: the passes never ended).
             * What moves is a sliver of the face narrower than SW_CUT_SNAP, the error
             * of its classification as F or B no larger. */
            if (s != 0 && fabs(S->fv[3 * t + k]) <= SW_CUT_SNAP * grad)
                s = 0;
            S->sgn[3 * t + k] = (int8_t)s;
            neg += s < 0;
            pos += s > 0;
        }
        S->mixed[t] = neg > 0 && pos > 0;
        S->type[t] = pos > 0 ? 1 : -1;
        S->cut[2 * t] = S->cut[2 * t + 1] = -1;
        if (!S->mixed[t])
            continue;
        int nc = 0;
        for (int k = 0; k < 3 && nc < 2; k++) {
            int k1 = (k + 1) % 3;
            if (S->sgn[3 * t + k] == 0) {
                S->cut[2 * t + nc] = V[k];
                S->cutk[2 * t + nc] = (int8_t)(3 + k);
                nc++;
            }
            if (nc < 2 && S->sgn[3 * t + k] * S->sgn[3 * t + k1] < 0) {
                double fa = S->fv[3 * t + k], fb = S->fv[3 * t + k1];
                double s = fa / (fa - fb);
                if (!(s > 0))
                    s = 0x1p-30;
                if (!(s < 1))
                    s = 1 - 0x1p-30;
                int64_t edge = S->eid[3 * t + k];
                double sc = V[k] == S->ea[edge] ? s : 1 - s;
                int64_t id = -1;
                if (first[edge] >= 0 && S->ep[first[edge]].s == sc)
                    id = S->ep[first[edge]].id;
                else {
                    if (first[edge] < 0)
                        first[edge] = S->nep;
                    id = edge_point(S, edge, sc);
                }
                if (id < 0) {
                    free(first);
                    return nomem(e);
                }
                S->cut[2 * t + nc] = id;
                S->cutk[2 * t + nc] = (int8_t)k;
                S->cuts[2 * t + nc] = sc;
                nc++;
            }
        }
    }
    free(first);
    return 1;
}

/* ---- Points along the sides -------------------------------------------------------------- */

static int cmp_ep(const void *pa, const void *pb)
{
    const edge_pt *a = pa, *b = pb;
    if (a->edge != b->edge)
        return a->edge < b->edge ? -1 : 1;
    if (a->s != b->s)
        return a->s < b->s ? -1 : 1;
    return a->id < b->id ? -1 : a->id > b->id;
}

/* Sorts the side points and indexes them by edge. */
static int index_edge_points(split *S)
{
    if (S->nep > 1) /* qsort of no array is undefined (UBSan) */
        qsort(S->ep, (size_t)S->nep, sizeof *S->ep, cmp_ep);
    free(S->estart);
    S->estart = calloc((size_t)(S->ne + 2), sizeof *S->estart);
    if (!S->estart)
        return 0;
    for (int64_t i = 0; i < S->nep; i++)
        S->estart[S->ep[i].edge + 1]++;
    for (int64_t i = 0; i < S->ne; i++)
        S->estart[i + 1] += S->estart[i];
    return 1;
}

static int cmp_cp(const void *pa, const void *pb)
{
    const chord_pt *a = pa, *b = pb;
    if (a->tri != b->tri)
        return a->tri < b->tri ? -1 : 1;
    return a->order < b->order ? -1 : a->order > b->order;
}

static int index_chord_points(split *S)
{
    if (S->ncp > 1)
        qsort(S->cp, (size_t)S->ncp, sizeof *S->cp, cmp_cp);
    free(S->cstart);
    S->cstart = calloc((size_t)(S->e->nt + 2), sizeof *S->cstart);
    if (!S->cstart)
        return 0;
    for (int64_t i = 0; i < S->ncp; i++)
        S->cstart[S->cp[i].tri + 1]++;
    for (int64_t i = 0; i < S->e->nt; i++)
        S->cstart[i + 1] += S->cstart[i];
    return 1;
}

/* The side of f a point at s on triangle t's side k lies on (-1 F, 0 on the line, +1 B);
 * id is the point (a cut point of t itself is on the line). */
static int side_of(const split *S, int64_t t, int k, int64_t id, double s)
{
    if (id == S->cut[2 * t] || id == S->cut[2 * t + 1])
        return 0;
    const int64_t *V = S->e->tri + 3 * t;
    int sa = S->sgn[3 * t + k], sb = S->sgn[3 * t + (k + 1) % 3];
    for (int c = 0; c < 2; c++)
        if (S->cutk[2 * t + c] == k && S->cut[2 * t + c] >= 0) {
            int64_t edge = S->eid[3 * t + k];
            int s_ea = V[k] == S->ea[edge] ? sa : sb, s_eb = V[k] == S->ea[edge] ? sb : sa;
            return s < S->cuts[2 * t + c] ? s_ea : s_eb;
        }
    return sa != 0 ? sa : sb;
}

/* Triangle t's ring: its corners and every point on its sides, in order, with sides. */
static int ring_of(split *S, int64_t t, int64_t *n)
{
    const sw_env *e = S->e;
    const int64_t *V = e->tri + 3 * t;
    int64_t m = 0;
    for (int k = 0; k < 3; k++) {
        int64_t edge = S->eid[3 * t + k];
        int64_t lo = S->estart[edge], hi = S->estart[edge + 1];
        if (!mfg_grow((void **)&S->ring, &S->capring, m + (hi - lo) + 4, sizeof *S->ring))
            return 0;
        int8_t *rs = realloc(S->rside, (size_t)S->capring); /* the old block stays on failure */
        if (!rs)
            return 0;
        S->rside = rs;
        S->ring[m] = V[k];
        S->rside[m++] = S->sgn[3 * t + k];
        int fwd = V[k] == S->ea[edge];
        for (int64_t i = 0; i < hi - lo; i++) {
            const edge_pt *p = &S->ep[fwd ? lo + i : hi - 1 - i];
            S->ring[m] = p->id;
            S->rside[m++] = (int8_t)side_of(S, t, k, p->id, p->s);
        }
    }
    *n = m;
    return 1;
}

/* ---- The contour --------------------------------------------------------------------- */

static int add_cedge(split *S, int64_t u, int64_t v, int64_t edge, int64_t tri, double s0, double s1)
{
    if (!mfg_grow((void **)&S->ce, &S->capce, S->nce + 1, sizeof *S->ce))
        return 0;
    cedge *c = &S->ce[S->nce++];
    c->u = u;
    c->v = v;
    c->edge = edge;
    c->tri = tri;
    c->s0 = s0;
    c->s1 = s1;
    return 1;
}

/* The F arc of a mixed triangle's ring: positions of its first and last point (the two
 * points on the line f = 0, the arc between them through the corners with f < 0). */
static int f_arc(const split *S, int64_t m, int64_t *from, int64_t *to)
{
    int64_t z[2], nz = 0;
    for (int64_t i = 0; i < m && nz < 2; i++)
        if (S->rside[i] == 0)
            z[nz++] = i;
    if (nz < 2)
        return 0;
    int neg = 0;
    for (int64_t i = z[0] + 1; i < z[1]; i++)
        neg |= S->rside[i] < 0;
    *from = neg ? z[0] : z[1];
    *to = neg ? z[1] : z[0];
    return 1;
}

/* Status of the side piece between two consecutive points for triangle t (side k):
 * -1 F, +1 B. */
static int piece_status(const split *S, int64_t t, int k, int64_t p, double sp, int64_t q, double sq)
{
    int a = side_of(S, t, k, p, sp), b = side_of(S, t, k, q, sq);
    if (a != 0)
        return a;
    if (b != 0)
        return b;
    return S->type[t];
}

static int find_contour(split *S)
{
    sw_env *e = S->e;
    /* the cut lines: from the end of the F arc back to its start */
    for (int64_t t = 0; t < e->nt; t++) {
        if (!S->mixed[t])
            continue;
        int64_t m, from, to;
        if (!ring_of(S, t, &m))
            return nomem(e);
        if (!f_arc(S, m, &from, &to)) {
            e->st_code = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: triangle %lld has no "
                                  "two cut points", (long long)t);
            return 0;
        }
        if (!add_cedge(S, S->ring[to], S->ring[from], -1, t, 0, 0))
            return nomem(e);
    }
    /* the side pieces with F on one side and B on the other */
    for (int64_t edge = 0; edge < S->ne; edge++) {
        int64_t t1 = S->et[2 * edge], t2 = S->et[2 * edge + 1];
        int k1 = -1, k2 = -1;
        for (int k = 0; k < 3; k++) {
            if (S->eid[3 * t1 + k] == edge)
                k1 = k;
            if (S->eid[3 * t2 + k] == edge)
                k2 = k;
        }
        int64_t lo = S->estart[edge], hi = S->estart[edge + 1];
        int64_t prev = S->ea[edge];
        double sprev = 0;
        for (int64_t i = lo; i <= hi; i++) {
            int64_t cur = i < hi ? S->ep[i].id : S->eb[edge];
            double scur = i < hi ? S->ep[i].s : 1;
            int f1 = piece_status(S, t1, k1, prev, sprev, cur, scur);
            int f2 = piece_status(S, t2, k2, prev, sprev, cur, scur);
            int ok = 1;
            if (f1 < 0 && f2 > 0)
                ok = add_cedge(S, prev, cur, edge, -1, sprev, scur); /* t1 runs ea -> eb */
            else if (f1 > 0 && f2 < 0)
                ok = add_cedge(S, cur, prev, edge, -1, scur, sprev);
            if (!ok)
                return nomem(e);
            prev = cur;
            sprev = scur;
        }
    }
    return 1;
}

/* ---- The twist split --------------------------------------------------------------------- */

/* The normal distance between the two diagonals' midpoints of the quad swept by u -> v
 * over one interior step of its polyline kind: twice the most a triangulated quad
 * leaves its ruled surface by. */
static double twist_of(const sw_env *e, const double *u, const double *v, int kind)
{
    double pu[4][3];
    /* a step of the polyline: chords R(0) -> R(delta); tangents M_0 -> M_1 (or v -> M_0
     * when there is one step), with the apex factor */
    double t0 = kind == SW_CHORD || e->nsteps < 2 ? 0 : 0.5 * e->delta;
    double t1 = kind == SW_CHORD ? e->delta : (e->nsteps < 2 ? 0.5 * e->delta : 1.5 * e->delta);
    double f0 = kind == SW_CHORD || e->nsteps < 2 ? 1 : 1 / cos(0.5 * e->delta);
    double f1 = kind == SW_CHORD ? 1 : 1 / cos(0.5 * e->delta);
    const double *pts[2] = {u, v};
    for (int i = 0; i < 2; i++) {
        double par[3], perp[3], side[3];
        double a = mfg_dot3(e->kh, pts[i]);
        for (int k = 0; k < 3; k++) {
            par[k] = e->kh[k] * a;
            perp[k] = pts[i][k] - par[k];
        }
        mfg_cross3(e->kh, pts[i], side);
        for (int k = 0; k < 3; k++) {
            pu[i][k] = par[k] + f0 * (cos(t0) * perp[k] + sin(t0) * side[k]);
            pu[2 + i][k] = par[k] + f1 * (cos(t1) * perp[k] + sin(t1) * side[k]);
        }
    }
    /* corners u0 v0 v1 u1: diagonals u0-v1 and v0-u1 */
    double d1[3], d2[3], n[3], m[3];
    mfg_sub3(pu[3], pu[0], d1);
    mfg_sub3(pu[2], pu[1], d2);
    mfg_cross3(d1, d2, n);
    double ln = mfg_norm3(n);
    if (!(ln > 0))
        return 0;
    for (int k = 0; k < 3; k++)
        m[k] = 0.5 * (pu[0][k] + pu[3][k]) - 0.5 * (pu[1][k] + pu[2][k]);
    return fabs(mfg_dot3(m, n)) / ln;
}

int sw_add_contour_piece(sw_env *e, int64_t u, int64_t v, int kind)
{
    if (!mfg_grow((void **)&e->ce, &e->capce, 2 * (e->nce + 1), sizeof *e->ce))
        return 0;
    int64_t cap = e->capce / 2;
    int8_t *k = realloc(e->ckind, (size_t)cap + 1);
    if (!k)
        return 0;
    e->ckind = k;
    e->ce[2 * e->nce] = u;
    e->ce[2 * e->nce + 1] = v;
    e->ckind[e->nce++] = (int8_t)kind;
    return 1;
}

/* Where the contour edge u -> v passes the axis (x = y = 0 in the axis frame) closer
 * than SW_ON_AXIS, between its ends: the parameter along it, else -1.  The line f = 0 of
 * a triangle the axis pierces runs through the piercing point exactly (f vanishes on the
 * axis), so the rounded contour passes it by ulps; its strip quads would then turn a
 * segment about a point of itself into bow ties crossing each other at the axis, and the
 * arrangement would make thousands of distinct points within 1e-13 of it (a torus
 * pierced by the axis: 56 million exact comparisons).  Split there, on the axis, the
 * strips are fans about one explicit point that a turn leaves in place. */
static double axis_crossing(const sw_env *e, const double *u, const double *v)
{
    if (sw_radius(e, u) < SW_ON_AXIS || sw_radius(e, v) < SW_ON_AXIS)
        return -1;
    double dx = v[0] - u[0], dy = v[1] - u[1], l2 = dx * dx + dy * dy;
    if (!(l2 > 0))
        return -1;
    double f = -(u[0] * dx + u[1] * dy) / l2;
    if (!(f > 0 && f < 1))
        return -1;
    return hypot(u[0] + f * dx, u[1] + f * dy) < SW_ON_AXIS ? f : -1;
}

/* A new point at f along contour edge c (u -> v), recorded on its side or its
 * triangle's cut line (order: its rank along the line) for the pieces beside it;
 * on_axis puts it exactly on the axis. */
static int64_t contour_point(split *S, const cedge *c, double f, int64_t order, int on_axis)
{
    sw_env *e = S->e;
    const double *u = e->x + 3 * c->u, *v = e->x + 3 * c->v;
    double p[3];
    for (int k = 0; k < 3; k++)
        p[k] = u[k] + f * (v[k] - u[k]);
    if (on_axis)
        p[0] = p[1] = 0;
    int64_t id = sw_add_vertex(e, p);
    if (id < 0)
        return -1;
    if (c->edge >= 0)
        return add_edge_pt(S, c->edge, c->s0 + f * (c->s1 - c->s0), id) ? id : -1;
    if (!mfg_grow((void **)&S->cp, &S->capcp, S->ncp + 1, sizeof *S->cp))
        return -1;
    S->cp[S->ncp].tri = c->tri;
    S->cp[S->ncp].order = order;
    S->cp[S->ncp].id = id;
    S->ncp++;
    return id;
}

/* The most pieces one contour edge is cut into for the twist, and the deepest the cut
 * goes (a piece 2^-40 of its edge long is not cut again: only a tolerance far below
 * what the input resolves asks for it, and check_tolerance refuses those). */
#define SW_TWIST_MAX_PIECES 1000000
#define SW_TWIST_MAX_DEPTH 40

/* The fractions in (lo, hi) where the part [lo, hi] of edge u -> v is cut so that every
 * piece's twist is within 2 SW_SHARE_TWIST tol, appended to S->fr in order.  The twist
 * is not proportional to a piece's length - it grows where the edge turns about the
 * axis fastest, near its foot (2026-12-06: a sheared box's edge cut in four equal
 * pieces by its mean twist kept one piece at 2.03 tol, and the result 1.02 tol from SV)
 * - so each part is cut by its own twist and its pieces checked again. */
static int twist_fractions(split *S, const double *u, const double *v, int kind, double lo,
                           double hi, int depth)
{
    sw_env *e = S->e;
    double a[3], b[3];
    for (int k = 0; k < 3; k++) {
        a[k] = u[k] + lo * (v[k] - u[k]);
        b[k] = u[k] + hi * (v[k] - u[k]);
    }
    double m = ceil(twist_of(e, a, b, kind) / (2 * SW_SHARE_TWIST * e->tol));
    if (!(m > 1) || depth >= SW_TWIST_MAX_DEPTH || S->nfr >= SW_TWIST_MAX_PIECES)
        return 1;
    int64_t parts = m > 64 ? 64 : (int64_t)m; /* the rest by the parts' own twists */
    for (int64_t j = 0; j < parts; j++) {
        double f0 = lo + (hi - lo) * (double)j / (double)parts;
        double f1 = j + 1 == parts ? hi : lo + (hi - lo) * (double)(j + 1) / (double)parts;
        if (j > 0) {
            if (!mfg_grow((void **)&S->fr, &S->capfr, S->nfr + 1, sizeof *S->fr))
                return 0;
            S->fr[S->nfr++] = f0;
        }
        if (!twist_fractions(S, u, v, kind, f0, f1, depth + 1))
            return 0;
    }
    return 1;
}

/* Each contour edge split where it passes the axis, then in pieces whose strip quads
 * twist within the tolerance's share; the new points go onto its side (or its
 * triangle's cut line) for the pieces beside it. */
static int split_contour(split *S)
{
    sw_env *e = S->e;
    for (int64_t i = 0; i < S->nce; i++) {
        const cedge *c = &S->ce[i];
        double d[3];
        mfg_sub3(e->x + 3 * c->v, e->x + 3 * c->u, d);
        int up = mfg_dot3_sign(d, e->k);
        int kind = up > 0 ? SW_TANGENT : up < 0 ? SW_CHORD : -1;
        /* the parts [0, fa], [fa, 1] (one part when the edge does not pass the axis) */
        double fa = axis_crossing(e, e->x + 3 * c->u, e->x + 3 * c->v);
        double lo[2] = {0, fa}, hi[2] = {fa, 1};
        int parts = fa > 0 ? 2 : 1;
        if (parts == 1)
            hi[0] = 1;
        /* ranks along a cut line: part 0's points 1 .. 10^6, the axis point 2^21, part
         * 1's 2^22 + j */
        int64_t prev = c->u, end = -1;
        for (int part = 0; part < parts; part++) {
            if (part + 1 < parts) {
                end = contour_point(S, c, hi[part], (int64_t)1 << 21, 1);
                if (end < 0)
                    return nomem(e);
            } else {
                end = c->v;
            }
            /* the cuts of this part, from its ends as they are (u, v: explicit) */
            S->nfr = 0;
            if (kind >= 0 && !twist_fractions(S, e->x + 3 * c->u, e->x + 3 * c->v, kind,
                                              lo[part], hi[part], 0))
                return nomem(e);
            for (int64_t j = 0; j <= S->nfr; j++) {
                int64_t cur = end;
                if (j < S->nfr) {
                    cur = contour_point(S, c, S->fr[j], part == 0 ? j + 1 : ((int64_t)1 << 22) + j + 1, 0);
                    if (cur < 0)
                        return nomem(e);
                }
                if (!sw_add_contour_piece(e, prev, cur, kind))
                    return nomem(e);
                prev = cur;
            }
        }
    }
    return index_edge_points(S) && index_chord_points(S) ? 1 : nomem(e);
}

/* ---- The pieces of F and B ----------------------------------------------------------------- */

/* Triangulates polygon poly (n points) of triangle t's plane and emits it: at t = 0 (F)
 * or turned by theta (B). */
static int emit_polygon(split *S, int64_t t, const int64_t *poly, int64_t n, int turned)
{
    sw_env *e = S->e;
    if (n < 3)
        return 1;
    const int64_t *V = e->tri + 3 * t;
    double u[3], w[3], nn[3];
    mfg_sub3(e->x + 3 * V[1], e->x + 3 * V[0], u);
    mfg_sub3(e->x + 3 * V[2], e->x + 3 * V[0], w);
    mfg_cross3(u, w, nn);
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(nn[k]) > fabs(nn[ax]))
            ax = k;
    int flip = nn[ax] < 0;
    if (!mfg_grow((void **)&S->xy, &S->capxy, 2 * n + 2, sizeof *S->xy))
        return nomem(e);
    int64_t *tris = realloc(S->tris, (size_t)(3 * n + 3) * sizeof *S->tris);
    if (!tris) /* S->tris stays valid for split_free */
        return nomem(e);
    S->tris = tris;
    for (int64_t i = 0; i < n; i++) {
        int64_t p = poly[flip ? n - 1 - i : i];
        S->xy[2 * i] = e->x[3 * p + (ax + 1) % 3];
        S->xy[2 * i + 1] = e->x[3 * p + (ax + 2) % 3];
    }
    int64_t ls[2] = {0, n}, ntri = 0;
    int r = mfg_polygon_triangulate(S->xy, ls, 1, S->tris, &ntri);
    if (r < 0)
        return nomem(e);
    if (r == 0) { /* rounding made the piece not quite simple: a fan still closes the chain */
        ntri = n - 2;
        for (int64_t i = 0; i < ntri; i++) {
            S->tris[3 * i] = 0;
            S->tris[3 * i + 1] = i + 1;
            S->tris[3 * i + 2] = i + 2;
        }
    }
    int64_t g = S->group[t] + (turned && !e->full_turn ? S->ngroups : 0);
    for (int64_t i = 0; i < ntri; i++) {
        int64_t q[3];
        for (int k = 0; k < 3; k++) {
            int64_t li = S->tris[3 * i + k];
            q[k] = poly[flip ? n - 1 - li : li];
            if (turned && (q[k] = sw_chord_point(e, q[k], e->nsteps)) < 0)
                return nomem(e);
        }
        int ok = flip ? sw_emit(e, q[0], q[2], q[1], g) : sw_emit(e, q[0], q[1], q[2], g);
        if (!ok)
            return nomem(e);
    }
    return 1;
}

static int emit_pieces(split *S)
{
    sw_env *e = S->e;
    int64_t *poly = NULL, cappoly = 0;
    for (int64_t t = 0; t < e->nt; t++) {
        if ((t & 1023) == 0 && !mfg_prog_poll(e->prog, (double)t, (double)e->nt)) {
            free(poly);
            e->st_code = MFG_ERR_CANCELLED;
            return 0;
        }
        int64_t m;
        if (!ring_of(S, t, &m)) {
            free(poly);
            return nomem(e);
        }
        if (!S->mixed[t]) {
            if (!emit_polygon(S, t, S->ring, m, S->type[t] > 0)) {
                free(poly);
                return 0;
            }
            continue;
        }
        int64_t from, to;
        if (!f_arc(S, m, &from, &to)) {
            free(poly);
            e->st_code = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: triangle %lld has no "
                                  "two cut points", (long long)t);
            return 0;
        }
        int64_t nc = S->cstart[t + 1] - S->cstart[t];
        const chord_pt *cp = nc > 0 ? S->cp + S->cstart[t] : NULL; /* S->cp may be NULL */
        if (!mfg_grow((void **)&poly, &cappoly, m + nc + 2, sizeof *poly)) {
            free(poly);
            return nomem(e);
        }
        /* F: the arc from -> to, then the cut line back (its points run to -> from) */
        int64_t n = 0;
        for (int64_t i = from;; i = (i + 1) % m) {
            poly[n++] = S->ring[i];
            if (i == to)
                break;
        }
        for (int64_t j = 0; j < nc; j++)
            poly[n++] = cp[j].id;
        if (!emit_polygon(S, t, poly, n, 0)) {
            free(poly);
            return 0;
        }
        /* B: the arc to -> from, then the cut line from -> to */
        n = 0;
        for (int64_t i = to;; i = (i + 1) % m) {
            poly[n++] = S->ring[i];
            if (i == from)
                break;
        }
        for (int64_t j = nc - 1; j >= 0; j--)
            poly[n++] = cp[j].id;
        if (!emit_polygon(S, t, poly, n, 1)) {
            free(poly);
            return 0;
        }
    }
    free(poly);
    return 1;
}

static void split_free(split *S)
{
    free(S->sgn);
    free(S->fv);
    free(S->eid);
    free(S->ea);
    free(S->eb);
    free(S->et);
    free(S->cut);
    free(S->cutk);
    free(S->cuts);
    free(S->fr);
    free(S->mixed);
    free(S->type);
    free(S->group);
    free(S->ep);
    free(S->estart);
    free(S->cp);
    free(S->cstart);
    free(S->ce);
    free(S->ring);
    free(S->rside);
    free(S->xy);
    free(S->tris);
}

int sw_build_faces(sw_env *e)
{
    split S;
    memset(&S, 0, sizeof S);
    S.e = e;
    int ok = build_edges(&S) ? 1 : nomem(e);
    ok = ok && classify(&S);
    ok = ok && (index_edge_points(&S) && index_chord_points(&S) ? 1 : nomem(e));
    ok = ok && find_contour(&S) && split_contour(&S) && emit_pieces(&S);
    e->ngroups = 2 * S.ngroups;
    split_free(&S);
    return ok;
}
