/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/cdt.c - The constrained triangulation of one cluster: its points inserted into
 * an enclosing triangle, its segments made edges by flips (Sloan 1993: flip a crossing
 * edge whose quadrilateral is convex, until none crosses), then the multiplicity of each
 * triangle (how many member triangles cover it, counted with their orientation) by a walk
 * that adds each segment's delta when it crosses it.  Every predicate that decides the
 * triangulation's validity is arr_orient2d on the points' exact positions.  After each
 * point, Lawson's flips by a rounded in-circle test (legalise) keep the triangles roughly
 * Delaunay: only for speed - the multiplicities are the same on any triangulation. */
#include "arrange/arrange.h"

/* The rounded tests that only steer (never decide validity): a walk steps across an edge
 * when the point is outside it by more than CDT_WALK_CLEAR of the two vectors' sizes, and
 * a flip is tried when its quadrilateral's diagonal makes angles above CDT_FLIP_CLEAR
 * radians with the other two corners; at most CDT_FLIPS_PER_POINT flips per point (and
 * CDT_FLIPS_SPARE) per cluster, a bound on a rounded heuristic that could cycle. */
#define CDT_WALK_CLEAR 0x1p-40
#define CDT_FLIP_CLEAR 0x1p-30
#define CDT_FLIPS_PER_POINT 32
#define CDT_FLIPS_SPARE 1024

typedef struct cdt {
    const arr_points *P;
    int axis;
    int64_t *gid;      /* global point id of each local vertex */
    int64_t nv, capv;
    int64_t (*tv)[3];  /* vertices, counter-clockwise in the projection */
    int64_t (*tn)[3];  /* neighbour across the edge tv[e] -> tv[e+1] (-1: none) */
    int64_t nt, capt;
    int64_t *vt;       /* a triangle at each vertex */
    int64_t *queue;    /* crossing edges of the segment being inserted (pairs) */
    int64_t qcap;
    int32_t *mult;
    uint64_t rng;
    int64_t last;
    mfg_prog *prog;    /* polled in the long loops: a cancel is heard within a cluster */
    double at, of;     /* the cluster stage's progress to report meanwhile */
    int cancelled;
    double (*uv)[2];   /* rounded 2-D position of each local vertex (the flip heuristic) */
    int64_t capuv;
    int64_t *stack;    /* triangles to legalise after an insertion */
    int64_t capstack;
    int64_t flips;     /* legalising flips left for this cluster */
} cdt;

static int orient(const cdt *D, int64_t a, int64_t b, int64_t c)
{
    return arr_orient2d(D->P, D->gid[a], D->gid[b], D->gid[c], D->axis);
}

static int64_t new_tri(cdt *D)
{
    if (D->nt >= D->capt) {
        int64_t cap = mfg_grown_cap(D->capt, D->nt + 1, 16);
        int64_t(*v)[3] = realloc(D->tv, (size_t)cap * sizeof *v);
        if (!v)
            return -1;
        D->tv = v;
        int64_t(*n)[3] = realloc(D->tn, (size_t)cap * sizeof *n);
        if (!n)
            return -1;
        D->tn = n;
        D->capt = cap;
    }
    return D->nt++;
}

static void set_tri(cdt *D, int64_t t, int64_t a, int64_t b, int64_t c)
{
    D->tv[t][0] = a;
    D->tv[t][1] = b;
    D->tv[t][2] = c;
    D->vt[a] = D->vt[b] = D->vt[c] = t;
}

/* tn[t][e] = u, and u's edge that faces t (the reverse of t's edge e) points back. */
static void link(cdt *D, int64_t t, int e, int64_t u)
{
    D->tn[t][e] = u;
    if (u < 0)
        return;
    int64_t a = D->tv[t][e], b = D->tv[t][(e + 1) % 3];
    for (int f = 0; f < 3; f++)
        if (D->tv[u][f] == b && D->tv[u][(f + 1) % 3] == a) {
            D->tn[u][f] = t;
            return;
        }
}

/* Rotates triangle t so that its vertex at index k comes first. */
static void rotate(cdt *D, int64_t t, int k)
{
    int64_t v[3], n[3];
    for (int i = 0; i < 3; i++) {
        v[i] = D->tv[t][(i + k) % 3];
        n[i] = D->tn[t][(i + k) % 3];
    }
    for (int i = 0; i < 3; i++) {
        D->tv[t][i] = v[i];
        D->tn[t][i] = n[i];
    }
}

/* Flips the edge x -> y of tx (its edge ex) and y -> x of ty (its edge ey): tx = (x, y, p)
 * and ty = (y, x, q) become (x, q, p) and (q, y, p), kept in tx and ty.  The caller has
 * checked that x and y lie on either side of p -> q. */
static void flip(cdt *D, int64_t tx, int ex, int64_t ty, int ey)
{
    rotate(D, tx, ex);
    rotate(D, ty, ey);
    int64_t x = D->tv[tx][0], y = D->tv[tx][1], p = D->tv[tx][2], q = D->tv[ty][2];
    int64_t t_yp = D->tn[tx][1], t_px = D->tn[tx][2];
    int64_t u_xq = D->tn[ty][1], u_qy = D->tn[ty][2];
    set_tri(D, tx, x, q, p);
    set_tri(D, ty, q, y, p);
    link(D, tx, 0, u_xq);
    D->tn[tx][1] = ty;
    link(D, tx, 2, t_px);
    link(D, ty, 0, u_qy);
    link(D, ty, 1, t_yp);
    D->tn[ty][2] = tx;
    D->vt[x] = tx;
    D->vt[y] = ty;
    D->last = tx;
}

static uint64_t next_rand(cdt *D)
{
    D->rng = D->rng * 6364136223846793005ull + 1442695040888963407ull;
    return D->rng >> 33;
}

/* The triangle holding v (inside or on an edge): its id and *edge = the edge v lies on
 * (-1: strictly inside; -2: v is one of its corners). -1 when the walk fails. */
static int64_t locate(cdt *D, int64_t v, int *edge)
{
    int64_t t = D->last;
    /* first a walk by the rounded positions, which only picks the triangle the exact walk
     * starts from: a walk's steps past nearly collinear implicit points made the exact
     * orientation 17 % of a torus's arrangement.  It stops where the rounded tests see no
     * edge with v clearly outside (or after as many steps as the exact walk may take) */
    for (int64_t steps = 0; steps < 4 * D->nt + 64; steps++) {
        int start = (int)(next_rand(D) % 3);
        int64_t next = -1;
        for (int i = 0; i < 3 && next < 0; i++) {
            int e = (start + i) % 3;
            const double *a = D->uv[D->tv[t][e]], *b = D->uv[D->tv[t][(e + 1) % 3]];
            const double *p = D->uv[v];
            double o = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
            double scale = (fabs(b[0] - a[0]) + fabs(b[1] - a[1])) *
                           (fabs(p[0] - a[0]) + fabs(p[1] - a[1]));
            if (o < -CDT_WALK_CLEAR * scale)
                next = D->tn[t][e];
        }
        if (next < 0)
            break;
        t = next;
    }
    for (int64_t steps = 0; steps < 4 * D->nt + 64; steps++) {
        int start = (int)(next_rand(D) % 3), moved = 0, zero = -1, nzero = 0;
        for (int i = 0; i < 3; i++) {
            int e = (start + i) % 3;
            int o = orient(D, D->tv[t][e], D->tv[t][(e + 1) % 3], v);
            if (o < 0) {
                t = D->tn[t][e];
                moved = 1;
                break;
            }
            if (o == 0) {
                zero = e;
                nzero++;
            }
        }
        if (t < 0)
            return -1;
        if (!moved) {
            *edge = nzero == 0 ? -1 : nzero == 1 ? zero : -2;
            return t;
        }
    }
    return -1;
}

/* d inside the circle through a, b, c, by the rounded positions (a heuristic only). */
static int in_circle(const cdt *D, int64_t a, int64_t b, int64_t c, int64_t d)
{
    const double *pa = D->uv[a], *pb = D->uv[b], *pc = D->uv[c], *pd = D->uv[d];
    double adx = pa[0] - pd[0], ady = pa[1] - pd[1], bdx = pb[0] - pd[0], bdy = pb[1] - pd[1];
    double cdx = pc[0] - pd[0], cdy = pc[1] - pd[1];
    double ad = adx * adx + ady * ady, bd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
    double det = adx * (bdy * cd - bd * cdy) - ady * (bdx * cd - bd * cdx) + ad * (bdx * cdy - bdy * cdx);
    double o = (pb[0] - pa[0]) * (pc[1] - pa[1]) - (pb[1] - pa[1]) * (pc[0] - pa[0]);
    return det * o > 0;
}

/* x and y clearly on either side of the line v -> d by the rounded positions (angles
 * above CDT_FLIP_CLEAR): a quadrilateral nearly degenerate there is not flipped, so that the
 * exact test that confirms a flip is rarely needed beyond its filter (the exact
 * orientations of nearly collinear implicit points were 12 % of a torus's arrangement). */
static int clearly_convex(const cdt *D, int64_t v, int64_t d, int64_t x, int64_t y)
{
    const double *pv = D->uv[v], *pd = D->uv[d], *px = D->uv[x], *py = D->uv[y];
    double ex = pd[0] - pv[0], ey = pd[1] - pv[1];
    double ax = px[0] - pv[0], ay = px[1] - pv[1], bx = py[0] - pv[0], by = py[1] - pv[1];
    double ox = ex * ay - ey * ax, oy = ex * by - ey * bx;
    double le = hypot(ex, ey);
    return ox * oy < 0 && fabs(ox) > CDT_FLIP_CLEAR * le * hypot(ax, ay) &&
           fabs(oy) > CDT_FLIP_CLEAR * le * hypot(bx, by);
}

/* Lawson's flips round the new vertex v, from the triangles on the stack (n of them):
 * nothing needs a Delaunay triangulation (the multiplicities are the same on any), but
 * without it the points inserted in order of their first coordinate make fans of
 * needles that every later walk and segment crosses: a plate with a hole swept 5 rad
 * spent 85 % of its 18 s arrangement walking them, 3 s with the flips (perf,
 * 2026-12-06; the battery 185 -> 117 s).  The circle test is rounded, so a flip may be
 * "wrong" (any flip of a quadrilateral the exact orientations find convex keeps the
 * triangulation valid) and the flips are bounded per cluster. */
static void legalise(cdt *D, int64_t v, int64_t n)
{
    while (n > 0 && D->flips > 0) {
        int64_t t = D->stack[--n];
        int i = D->tv[t][0] == v ? 0 : D->tv[t][1] == v ? 1 : D->tv[t][2] == v ? 2 : -1;
        if (i < 0)
            continue;
        int e = (i + 1) % 3;
        int64_t x = D->tv[t][e], y = D->tv[t][(e + 1) % 3], u = D->tn[t][e];
        if (u < 0)
            continue;
        int f = 0;
        while (f < 3 && !(D->tv[u][f] == y && D->tv[u][(f + 1) % 3] == x))
            f++;
        if (f == 3)
            continue;
        int64_t d = D->tv[u][(f + 2) % 3];
        if (n + 2 > D->capstack || !in_circle(D, x, y, v, d) || !clearly_convex(D, v, d, x, y) ||
            orient(D, v, d, x) * orient(D, v, d, y) >= 0)
            continue;
        D->flips--;
        flip(D, t, e, u, f); /* t = (x, d, v), u = (d, y, v) */
        D->stack[n++] = t;
        D->stack[n++] = u;
    }
}

/* Inserts local vertex v; 0 on failure (out of memory or a broken walk). */
static int insert_point(cdt *D, int64_t v, int *broken)
{
    int e;
    int64_t t = locate(D, v, &e);
    if (t < 0) {
        *broken = __LINE__;
        return 0;
    }
    if (e == -2) { /* the same position as a vertex: cannot happen after the dedupe */
        *broken = __LINE__;
        return 0;
    }
    if (e == -1) {
        int64_t a = D->tv[t][0], b = D->tv[t][1], c = D->tv[t][2];
        int64_t na = D->tn[t][0], nb = D->tn[t][1], nc = D->tn[t][2];
        int64_t t1 = new_tri(D), t2 = t1 < 0 ? -1 : new_tri(D);
        if (t2 < 0)
            return 0;
        set_tri(D, t, a, b, v);
        set_tri(D, t1, b, c, v);
        set_tri(D, t2, c, a, v);
        link(D, t, 0, na);
        link(D, t1, 0, nb);
        link(D, t2, 0, nc);
        D->tn[t][1] = t1;
        D->tn[t][2] = t2;
        D->tn[t1][1] = t2;
        D->tn[t1][2] = t;
        D->tn[t2][1] = t;
        D->tn[t2][2] = t1;
        D->last = t;
        D->stack[0] = t;
        D->stack[1] = t1;
        D->stack[2] = t2;
        legalise(D, v, 3);
        return 1;
    }
    rotate(D, t, e); /* v on t's edge 0: a -> b */
    int64_t u = D->tn[t][0];
    if (u < 0) { /* the enclosing triangle's edge: cannot happen, all points lie inside */
        *broken = __LINE__;
        return 0;
    }
    int64_t a = D->tv[t][0], b = D->tv[t][1], c = D->tv[t][2];
    for (int f = 0; f < 3; f++)
        if (D->tv[u][f] == b && D->tv[u][(f + 1) % 3] == a) {
            rotate(D, u, f);
            break;
        }
    int64_t d = D->tv[u][2];
    int64_t tb = D->tn[t][1], tc = D->tn[t][2], ua = D->tn[u][1], ub = D->tn[u][2];
    int64_t t1 = new_tri(D), u1 = t1 < 0 ? -1 : new_tri(D);
    if (u1 < 0)
        return 0;
    set_tri(D, t, a, v, c);
    set_tri(D, t1, v, b, c);
    set_tri(D, u, b, v, d);
    set_tri(D, u1, v, a, d);
    D->tn[t][0] = u1;
    D->tn[t][1] = t1;
    link(D, t, 2, tc);
    D->tn[t1][0] = u;
    link(D, t1, 1, tb);
    D->tn[t1][2] = t;
    D->tn[u][0] = t1;
    D->tn[u][1] = u1;
    link(D, u, 2, ub);
    D->tn[u1][0] = t;
    link(D, u1, 1, ua);
    D->tn[u1][2] = u;
    D->last = t;
    D->stack[0] = t;
    D->stack[1] = t1;
    D->stack[2] = u;
    D->stack[3] = u1;
    legalise(D, v, 4);
    return 1;
}

/* The triangle with the directed edge x -> y (and *e its index), or -1. */
static int64_t find_edge(const cdt *D, int64_t x, int64_t y, int *e)
{
    int64_t t0 = D->vt[x], t = t0;
    /* around x: from the triangle with x at index i, the next one across x's incoming
     * edge; a fan of an inner vertex is a cycle, one of the enclosing vertices is not */
    for (int dir = 0; dir < 2; dir++) {
        t = t0;
        for (int64_t steps = 0; t >= 0 && steps <= D->nt; steps++) {
            int i = D->tv[t][0] == x ? 0 : D->tv[t][1] == x ? 1 : 2;
            if (D->tv[t][(i + 1) % 3] == y) {
                *e = i;
                return t;
            }
            t = dir == 0 ? D->tn[t][(i + 2) % 3] : D->tn[t][i];
            if (t == t0)
                break;
        }
    }
    return -1;
}

static int push_edge(cdt *D, int64_t *qn, int64_t x, int64_t y)
{
    if (2 * (*qn + 1) > D->qcap) {
        int64_t cap = mfg_grown_cap(D->qcap, 2 * (*qn + 1), 16);
        int64_t *n = realloc(D->queue, (size_t)cap * sizeof *n);
        if (!n)
            return 0;
        D->queue = n;
        D->qcap = cap;
    }
    D->queue[2 * *qn] = x;
    D->queue[2 * *qn + 1] = y;
    (*qn)++;
    return 1;
}

/* Makes a -> b an edge.  No vertex lies inside the segment and no other constraint
 * crosses it (cluster.c split them), so the flips always finish. */
static int insert_segment(cdt *D, int64_t a, int64_t b, int *broken)
{
    int e;
    if (find_edge(D, a, b, &e) >= 0 || find_edge(D, b, a, &e) >= 0)
        return 1;
    /* the triangle at a whose opposite edge the segment crosses */
    int64_t t0 = D->vt[a], t = t0, l = -1, r = -1, cur = -1;
    for (int64_t steps = 0; steps <= D->nt; steps++) {
        int i = D->tv[t][0] == a ? 0 : D->tv[t][1] == a ? 1 : 2;
        int64_t x = D->tv[t][(i + 1) % 3], y = D->tv[t][(i + 2) % 3];
        if (orient(D, a, x, b) > 0 && orient(D, a, y, b) < 0) {
            r = x; /* right of a -> b */
            l = y;
            cur = t;
            break;
        }
        t = D->tn[t][(i + 2) % 3];
        if (t < 0 || t == t0)
            break;
    }
    if (cur < 0) {
        *broken = __LINE__;
        return 0;
    }
    int64_t qn = 0;
    if (!push_edge(D, &qn, l, r))
        return 0;
    /* walk to b, collecting the crossed edges */
    for (int64_t steps = 0; steps <= D->nt; steps++) {
        int f;
        int64_t u = find_edge(D, l, r, &f); /* the triangle beyond the crossed edge: l -> r */
        if (u < 0) {
            *broken = __LINE__;
            return 0;
        }
        int64_t w = D->tv[u][(f + 2) % 3];
        if (w == b)
            break;
        int o = orient(D, a, b, w);
        if (o == 0) {
#ifdef ARR_DEBUG
            double xa[3], xb[3], xw[3];
            arr_coords(D->P, D->gid[a], xa);
            arr_coords(D->P, D->gid[b], xb);
            arr_coords(D->P, D->gid[w], xw);
            fprintf(stderr, "collinear: a %lld (%g %g %g) b %lld (%g %g %g) w %lld (%g %g %g)\n",
                    (long long)D->gid[a], xa[0], xa[1], xa[2], (long long)D->gid[b], xb[0], xb[1],
                    xb[2], (long long)D->gid[w], xw[0], xw[1], xw[2]);
#endif
            *broken = __LINE__;
            return 0;
        }
        if (o > 0)
            l = w;
        else
            r = w;
        if (!push_edge(D, &qn, l, r))
            return 0;
    }
    /* flip until no edge crosses; the queue is a ring over D->queue */
    int64_t head = 0, count = qn, guard = 0, limit = 64 * (qn + 4) * (qn + 4);
    while (count > 0) {
        if ((guard & 4095) == 4095 && D->prog && !mfg_prog_poll(D->prog, D->at, D->of)) {
            D->cancelled = 1;
            return 0;
        }
        if (++guard > limit) {
            *broken = __LINE__;
            return 0;
        }
        int64_t x = D->queue[2 * head], y = D->queue[2 * head + 1];
        head = (head + 1) % qn;
        count--;
        int ex, ey;
        int64_t tx = find_edge(D, x, y, &ex), ty = find_edge(D, y, x, &ey);
        if (tx < 0 || ty < 0) {
            *broken = __LINE__;
            return 0;
        }
        int64_t p = D->tv[tx][(ex + 2) % 3], q = D->tv[ty][(ey + 2) % 3];
        int ox = orient(D, p, q, x), oy = orient(D, p, q, y);
        if (!(ox * oy < 0)) {
            /* not convex: try again later */
            int64_t slot = (head + count) % qn;
            D->queue[2 * slot] = x;
            D->queue[2 * slot + 1] = y;
            count++;
            continue;
        }
        flip(D, tx, ex, ty, ey); /* x-y to p-q */
        if (p == a || p == b || q == a || q == b)
            continue;
        int o1 = orient(D, a, b, p), o2 = orient(D, a, b, q);
        if (o1 * o2 < 0 && orient(D, p, q, a) * orient(D, p, q, b) < 0) {
            int64_t slot = (head + count) % qn;
            D->queue[2 * slot] = p;
            D->queue[2 * slot + 1] = q;
            count++;
        }
    }
    if (find_edge(D, a, b, &e) < 0 && find_edge(D, b, a, &e) < 0) {
        *broken = __LINE__;
        return 0;
    }
    return 1;
}

/* ---- The cluster ----------------------------------------------------------------------- */

/* The enclosing triangle's corners in the 2-D coordinates of an axis: it holds every
 * point of the unit-scale part (coordinates at most ~1.1 after the sweep's apexes, see
 * sweep/) with room, and its coordinates are small integers (on every grid). */
static const double ENCLOSE[3][2] = {{-8, -6}, {8, -6}, {0, 10}};
/* The points a cluster may hold: inside [-ENCLOSE_HOLDS, ENCLOSE_HOLDS]^2. */
#define ENCLOSE_HOLDS 3.0

static int64_t super_point(arr_ctx *c, int axis, int k)
{
    if (c->super[axis][k] >= 0)
        return c->super[axis][k];
    double x[3] = {0, 0, 0};
    x[(axis + 1) % 3] = ENCLOSE[k][0];
    x[(axis + 2) % 3] = ENCLOSE[k][1];
    int64_t xi = arr_aux_vertex(&c->T, x);
    int64_t p = xi < 0 ? -1 : arr_aux_point(&c->T, xi);
    c->super[axis][k] = p;
    return p;
}

static int64_t local_index(const int64_t *pts, int64_t n, int64_t p)
{
    int64_t lo = 0, hi = n - 1;
    while (lo <= hi) {
        int64_t m = (lo + hi) / 2;
        if (pts[m] == p)
            return m;
        if (pts[m] < p)
            lo = m + 1;
        else
            hi = m - 1;
    }
    return -1;
}

void arr_cdt_free(arr_ctx *c)
{
    cdt *D = c->cdt_scratch;
    if (!D)
        return;
    free(D->gid);
    free(D->tv);
    free(D->tn);
    free(D->vt);
    free(D->queue);
    free(D->mult);
    free(D->uv);
    free(D->stack);
    free(D);
    c->cdt_scratch = NULL;
}

typedef struct order_item {
    double key;
    int64_t v;
} order_item;

static int cmp_order(const void *a, const void *b)
{
    const order_item *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return x->v < y->v ? -1 : x->v > y->v;
}

int arr_cdt_cluster(arr_ctx *c, int64_t cl, const int64_t *pts, int64_t npts,
                    const arr_seg *segs, int64_t nsegs)
{
    const arr_cluster *K = &c->cl[cl];
    int64_t sp[3];
    for (int k = 0; k < 3; k++)
        if ((sp[k] = super_point(c, K->axis, k)) < 0)
            return 0;
    if (!c->cdt_scratch && !(c->cdt_scratch = calloc(1, sizeof(cdt))))
        return 0;
    cdt *D = c->cdt_scratch;
    arr_points P = arr_view(&c->T);
    D->P = &P;
    D->axis = K->axis;
    D->nt = 0;
    D->nv = npts + 3;
    D->rng = 0x9E3779B97F4A7C15ull ^ (uint64_t)cl;
    if (D->capv < D->nv) {
        int64_t cap = mfg_grown_cap(D->capv, D->nv, 16);
        int64_t *g = realloc(D->gid, (size_t)cap * sizeof *g);
        if (!g)
            return 0;
        D->gid = g;
        int64_t *v = realloc(D->vt, (size_t)cap * sizeof *v);
        if (!v)
            return 0;
        D->vt = v;
        D->capv = cap;
    }
    /* the legalising stack holds at most the new vertex's triangles */
    if (D->capuv < D->nv) {
        int64_t cap = mfg_grown_cap(D->capuv, D->nv, 16);
        double(*w)[2] = realloc(D->uv, (size_t)cap * sizeof *w);
        if (!w)
            return 0;
        D->uv = w;
        int64_t *st = realloc(D->stack, (size_t)(cap + 8) * sizeof *st);
        if (!st)
            return 0;
        D->stack = st;
        D->capuv = cap;
        D->capstack = cap + 8;
    }
    D->flips = CDT_FLIPS_PER_POINT * npts + CDT_FLIPS_SPARE;
    for (int64_t i = 0; i < npts; i++)
        D->gid[i] = pts[i];
    for (int k = 0; k < 3; k++) {
        double x[3];
        D->gid[npts + k] = sp[k];
        arr_coords(&P, sp[k], x);
        D->uv[npts + k][0] = x[(K->axis + 1) % 3];
        D->uv[npts + k][1] = x[(K->axis + 2) % 3];
    }
    int64_t t0 = new_tri(D);
    if (t0 < 0)
        return 0;
    set_tri(D, t0, npts, npts + 1, npts + 2);
    D->tn[t0][0] = D->tn[t0][1] = D->tn[t0][2] = -1;
    D->last = t0;
    /* points in the order of their first coordinate, so each walk starts near */
    order_item *ord = malloc((size_t)(npts + 1) * sizeof *ord);
    if (!ord)
        return 0;
    for (int64_t i = 0; i < npts; i++) {
        double x[3];
        arr_coords(&P, pts[i], x);
        ord[i].key = x[(K->axis + 1) % 3] + 0x1p-20 * x[(K->axis + 2) % 3];
        D->uv[i][0] = x[(K->axis + 1) % 3];
        D->uv[i][1] = x[(K->axis + 2) % 3];
        ord[i].v = i;
        if (fabs(x[(K->axis + 1) % 3]) > ENCLOSE_HOLDS || fabs(x[(K->axis + 2) % 3]) > ENCLOSE_HOLDS) {
            free(ord);
            c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: a point lies outside the "
                             "enclosing triangle (coordinates beyond %g)", ENCLOSE_HOLDS);
            return 0;
        }
    }
    if (npts > 1)
        qsort(ord, (size_t)npts, sizeof *ord, cmp_order);
    int broken = 0;
    /* one cluster can hold most of a run (walks through fans of needles: a plate with a
     * hole swept 5 rad spent 25 s in a few clusters): a cancel is heard here too */
    D->prog = c->prog;
    D->at = 0.3 * (double)c->ncl + 0.7 * (double)cl;
    D->of = c->ncl > 0 ? (double)c->ncl : 1;
    D->cancelled = 0;
    for (int64_t i = 0; i < npts; i++) {
        if ((i & 63) == 63 && c->prog && !mfg_prog_poll(c->prog, D->at, D->of)) {
            free(ord);
            c->st = MFG_ERR_CANCELLED;
            return 0;
        }
        if (!insert_point(D, ord[i].v, &broken)) {
            free(ord);
            if (broken)
                c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: point location failed in "
                                 "cluster %lld (cdt.c:%d)", (long long)cl, broken);
            return 0;
        }
    }
    free(ord);
    for (int64_t s = 0; s < nsegs; s++) {
        if ((s & 63) == 63 && c->prog && !mfg_prog_poll(c->prog, D->at, D->of)) {
            c->st = MFG_ERR_CANCELLED;
            return 0;
        }
        int64_t a = local_index(pts, npts, segs[s].p), b = local_index(pts, npts, segs[s].q);
        if (a < 0 || b < 0 || !insert_segment(D, a, b, &broken)) {
            if (D->cancelled) {
                c->st = MFG_ERR_CANCELLED;
                return 0;
            }
            if (a < 0 || b < 0 || broken)
                c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: a segment could not be "
                                 "inserted in cluster %lld (cdt.c:%d)", (long long)cl,
                                 a < 0 || b < 0 ? -1 : broken);
            return 0;
        }
    }
#ifdef ARR_DEBUG
    for (int64_t t = 0; t < D->nt; t++)
        if (orient(D, D->tv[t][0], D->tv[t][1], D->tv[t][2]) <= 0)
            fprintf(stderr, "cdt: cluster %lld triangle %lld (%lld %lld %lld) has orientation %d\n", (long long)cl, (long long)t,
                    (long long)D->gid[D->tv[t][0]], (long long)D->gid[D->tv[t][1]], (long long)D->gid[D->tv[t][2]],
                    orient(D, D->tv[t][0], D->tv[t][1], D->tv[t][2]));
#endif
    /* the multiplicity of each triangle: 0 at the enclosing corners, then across each
     * edge minus the delta of the segment it lies on (left to right) */
    hmap deltas;
    if (!hmap_init(&deltas, nsegs + 1))
        return 0;
    for (int64_t s = 0; s < nsegs; s++) {
        int64_t a = local_index(pts, npts, segs[s].p), b = local_index(pts, npts, segs[s].q);
        hkey k = mkkey(a < b ? a : b, a < b ? b : a, 0, 0);
        /* values must be >= 0: store the delta offset by 2^31 */
        if (!hmap_put(&deltas, &k, (int64_t)(a < b ? segs[s].delta : -segs[s].delta) + 0x80000000ll)) {
            hmap_free(&deltas);
            return 0;
        }
    }
    int32_t *m = realloc(D->mult, (size_t)(D->nt + 1) * sizeof *m);
    int64_t *stack = malloc((size_t)(D->nt + 1) * sizeof *stack);
    if (!m || !stack) {
        if (m)
            D->mult = m;
        free(stack);
        hmap_free(&deltas);
        return 0;
    }
    D->mult = m;
    const int32_t UNSET = INT32_MIN;
    for (int64_t t = 0; t < D->nt; t++)
        m[t] = UNSET;
    int64_t top = 0;
    m[D->vt[npts]] = 0;
    stack[top++] = D->vt[npts];
    int bad = 0;
    while (top > 0 && !bad) {
        int64_t t = stack[--top];
        for (int e = 0; e < 3; e++) {
            int64_t u = D->tn[t][e];
            if (u < 0)
                continue;
            int64_t x = D->tv[t][e], y = D->tv[t][(e + 1) % 3];
            hkey k = mkkey(x < y ? x : y, x < y ? y : x, 0, 0);
            int64_t dv = hmap_get(&deltas, &k);
            int32_t d = dv < 0 ? 0 : (int32_t)(dv - 0x80000000ll);
            if (x > y)
                d = -d;
            int32_t want = m[t] - d;
            if (m[u] == UNSET) {
                m[u] = want;
                stack[top++] = u;
            } else if (m[u] != want) {
                bad = 1;
                break;
            }
        }
    }
    hmap_free(&deltas);
    free(stack);
    if (bad) {
        c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: inconsistent multiplicities in "
                         "cluster %lld", (long long)cl);
        return 0;
    }
    for (int64_t t = 0; t < D->nt; t++) {
        if (m[t] == 0)
            continue;
        if (D->tv[t][0] >= npts || D->tv[t][1] >= npts || D->tv[t][2] >= npts || m[t] == UNSET) {
            c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: cluster %lld covers its "
                             "enclosing triangle", (long long)cl);
            return 0;
        }
        arr_face f;
        f.cluster = cl;
        f.mult = m[t] > 0 ? m[t] : -m[t];
        f.v[0] = pts[D->tv[t][0]];
        f.v[1] = pts[D->tv[t][m[t] > 0 ? 1 : 2]];
        f.v[2] = pts[D->tv[t][m[t] > 0 ? 2 : 1]];
        if (!arr_push_face(c, &f))
            return 0;
    }
    return 1;
}
