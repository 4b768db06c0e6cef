/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* implicit_exact.c - the exact stage of the implicit-point predicates: the homogeneous
 * coordinates of a construction and the predicates' polynomials as expansions
 * (common/expansion.h), in fixed stack buffers.
 *
 * Why fixed buffers suffice.  With every input on the grid (integer multiples of 2^-50,
 * magnitude <= 16), a value of degree d in the inputs is a multiple of 2^(-50 d), and so
 * is every component of an expansion computed for it (TwoSum and TwoProduct of multiples
 * of 2^-i and 2^-j give multiples of 2^-max(i,j) and 2^-(i+j)).  Its magnitude: a
 * coordinate is <= 2^4, a difference <= 2^5, a normal component <= 2^11, and by
 * induction over the formulas every quantity of degree d built here (partial sums and
 * partial products of expn_mul included) is below 2^(6 d + 9); the largest component of
 * an expansion is below twice the value.  The components of a non-overlapping expansion
 * occupy distinct bit positions, here from -50 d to 6 d + 10: at most 56 d + 11 of
 * them, within ARR_EXP_CAP(d) = 56 d + 24.  The degree never exceeds 20, so the smallest
 * bit is 2^-1000 (no underflow; a product's error is representable) and the largest
 * about 2^130 (no overflow).
 *
 * The largest frames: arr_orient2d_exact of three TPIs keeps their 12 coordinates
 * (40 KB) while each is built (tpi: about 70 KB with its products) and then the
 * determinant (about 65 KB): about 110 KB of stack at most. */
#include <stdlib.h>
#include <string.h>

#include "arrange/implicit.h"
#include "common/expansion.h"

#define CAP(d) ARR_EXP_CAP(d)
/* The largest degree of any value built here: arr_orient2d of three TPIs. */
#define DEG_MAX 20
#define CAP_MAX CAP(DEG_MAX)
/* Keeps a function's large frame off the stack of its caller's other calls. */
#if defined(__GNUC__)
#define NOINLINE __attribute__((noinline))
#else
#define NOINLINE
#endif

/* Products short enough for the small scratch of mul() (2 * 8 * 8 components). */
#define SMALL_PRODUCT 128

static inline const double *vtx(const double *xyz, int64_t i)
{
    return xyz + 3 * i;
}

/* h = e * f with scratch of the worst case; kept out of line so that its frame is only
 * on the stack while it runs. */
static NOINLINE int mul_large(int ne, const double *e, int nf, const double *f, double *h)
{
    double s1[CAP_MAX], s2[CAP_MAX];
    return expn_mul(ne, e, nf, f, h, s1, s2);
}

/* h = e * f; h needs min(2 ne nf, CAP(degree of the product)) slots. */
static int mul(int ne, const double *e, int nf, const double *f, double *h)
{
    if (2 * ne * nf <= SMALL_PRODUCT) {
        double s1[SMALL_PRODUCT], s2[SMALL_PRODUCT];
        return expn_mul(ne, e, nf, f, h, s1, s2);
    }
    return mul_large(ne, e, nf, f, h);
}

/* h = sum over t < m of sg[t] e[t] f[t], compressed; h needs CAP of the result degree. */
static NOINLINE int sum_of_products(int m, const double *const *e, const int *ne,
                                    const double *const *f, const int *nf, const int *sg,
                                    double *h)
{
    double prod[CAP_MAX], acc[CAP_MAX];
    int n = 0;
    for (int t = 0; t < m; t++) {
        int np = mul(ne[t], e[t], nf[t], f[t], prod);
        if (sg[t] < 0)
            expn_negate(np, prod);
        n = expn_sum(n, h, np, prod, acc);
        memcpy(h, acc, (size_t)n * sizeof(double));
    }
    return expn_compress(n, h);
}

/* h = e1 f1 - e2 f2 (a 2x2 minor), compressed. */
static int minor2(int ne1, const double *e1, int nf1, const double *f1, int ne2,
                  const double *e2, int nf2, const double *f2, double *h)
{
    const double *e[2] = {e1, e2}, *f[2] = {f1, f2};
    int ne[2] = {ne1, ne2}, nf[2] = {nf1, nf2}, sg[2] = {1, -1};
    return sum_of_products(2, e, ne, f, nf, sg, h);
}

/* Room for the short expansions: a normal component (a 2x2 minor of differences, at most
 * 2 * (2 * 2 * 2) = 16 components) or n . a (three normal components scaled by doubles,
 * summed: at most 3 * 32 = 96). */
#define SMALL_CAP 96

/* A short expansion with its length. */
typedef struct small {
    int n;
    double c[SMALL_CAP];
} small;

/* The normal (b - a) x (c - a) of a triangle, exact (16 components at most each). */
static void normal_exact(const double *a, const double *b, const double *c, small n[3])
{
    double e1[3][2], e2[3][2];
    int n1[3], n2[3];
    for (int k = 0; k < 3; k++) {
        n1[k] = expn_diff(b[k], a[k], e1[k]);
        n2[k] = expn_diff(c[k], a[k], e2[k]);
    }
    for (int k = 0; k < 3; k++) {
        int i = (k + 1) % 3, j = (k + 2) % 3;
        n[k].n = minor2(n1[i], e1[i], n2[j], e2[j], n1[j], e1[j], n2[i], e2[i], n[k].c);
    }
}

/* h = sum over k of e[k] * x[k] for three normal components e and doubles x; h needs
 * SMALL_CAP slots. */
static int dot_doubles(const small e[3], const double x[3], double *h)
{
    double t[3][2 * 16], s[4 * 16];
    int nt[3];
    for (int k = 0; k < 3; k++)
        nt[k] = expn_scale(e[k].n, e[k].c, x[k], t[k]);
    int n = expn_sum(nt[0], t[0], nt[1], t[1], s);
    n = expn_sum(n, s, nt[2], t[2], h);
    return expn_compress(n, h);
}

/* Sets out->c[k] to the double x (a one-component expansion). */
static void set_double(arr_exact *out, int k, double x)
{
    out->c[k][0] = x;
    out->n[k] = 1;
}

/* X = p W + num dq for the points on a line p + t dq, t = num / W (LPI, SSI). */
static void on_line(const double *p, int nw, const double *w, int nnum, const double *num,
                    const double *q, arr_exact *out)
{
    for (int k = 0; k < 3; k++) {
        double dq[2];
        int ndq = expn_diff(q[k], p[k], dq);
        double pw[2 * CAP(3)], t[2 * CAP(3)];
        int npw = expn_scale(nw, w, p[k], pw);
        int nt = mul(nnum, num, ndq, dq, t);
        int n = expn_sum(npw, pw, nt, t, out->c[k]);
        out->n[k] = expn_compress(n, out->c[k]);
    }
    memcpy(out->c[3], w, (size_t)nw * sizeof(double));
    out->n[3] = nw;
}

static void lpi_exact(const double *xyz, const arr_point *p, arr_exact *out)
{
    const double *a = vtx(xyz, p->v[0]), *b = vtx(xyz, p->v[1]), *r = vtx(xyz, p->v[2]);
    small n[3];
    normal_exact(r, vtx(xyz, p->v[3]), vtx(xyz, p->v[4]), n);
    /* W = n . (b - a) = n . b - n . a; num = n . (r - a) = n . r - n . a. */
    double na[SMALL_CAP], nb[SMALL_CAP], nr[SMALL_CAP], w[2 * SMALL_CAP], num[2 * SMALL_CAP];
    int nna = dot_doubles(n, a, na), nnb = dot_doubles(n, b, nb), nnr = dot_doubles(n, r, nr);
    int nw = expn_diff_expansions(nnb, nb, nna, na, w);
    int nnum = expn_diff_expansions(nnr, nr, nna, na, num);
    nw = expn_compress(nw, w);
    nnum = expn_compress(nnum, num);
    on_line(a, nw, w, nnum, num, b, out);
}

static void ssi_exact(const double *xyz, const arr_point *p, arr_exact *out)
{
    int i = (p->axis + 1) % 3, j = (p->axis + 2) % 3;
    const double *a = vtx(xyz, p->v[0]), *b = vtx(xyz, p->v[1]);
    const double *r = vtx(xyz, p->v[2]), *s = vtx(xyz, p->v[3]);
    double qi[2], qj[2], si[2], sj[2], ri[2], rj[2], w[CAP(2)], num[CAP(2)];
    int nqi = expn_diff(b[i], a[i], qi), nqj = expn_diff(b[j], a[j], qj);
    int nsi = expn_diff(s[i], r[i], si), nsj = expn_diff(s[j], r[j], sj);
    int nri = expn_diff(r[i], a[i], ri), nrj = expn_diff(r[j], a[j], rj);
    int nw = minor2(nqi, qi, nsj, sj, nqj, qj, nsi, si, w);
    int nnum = minor2(nri, ri, nsj, sj, nrj, rj, nsi, si, num);
    on_line(a, nw, w, nnum, num, b, out);
}

static void lift_exact(const double *xyz, const arr_point *p, arr_exact *out)
{
    int ax = p->axis, i = (ax + 1) % 3, j = (ax + 2) % 3;
    const double *a = vtx(xyz, p->v[0]);
    small n[3];
    normal_exact(a, vtx(xyz, p->v[1]), vtx(xyz, p->v[2]), n);
    /* X_axis = n_axis a_axis - n_i (l0 - a_i) - n_j (l1 - a_j). */
    double li[2], lj[2], t0[2 * CAP(2)], t1[2 * CAP(2)], t2[2 * CAP(2)], s[4 * CAP(2)];
    int nli = expn_diff(p->lift[0], a[i], li), nlj = expn_diff(p->lift[1], a[j], lj);
    int n0 = expn_scale(n[ax].n, n[ax].c, a[ax], t0);
    int n1 = mul(n[i].n, n[i].c, nli, li, t1);
    int n2 = mul(n[j].n, n[j].c, nlj, lj, t2);
    int ns = expn_diff_expansions(n0, t0, n1, t1, s);
    int nx = expn_diff_expansions(ns, s, n2, t2, out->c[ax]);
    out->n[ax] = expn_compress(nx, out->c[ax]);
    out->n[i] = expn_compress(expn_scale(n[ax].n, n[ax].c, p->lift[0], out->c[i]), out->c[i]);
    out->n[j] = expn_compress(expn_scale(n[ax].n, n[ax].c, p->lift[1], out->c[j]), out->c[j]);
    memcpy(out->c[3], n[ax].c, (size_t)n[ax].n * sizeof(double));
    out->n[3] = n[ax].n;
}

/* Cramer's rule for n_i . x = d_i (i = 0, 1, 2), d_i = n_i . a_i:
 * W = n0 . (n1 x n2), X = d0 (n1 x n2) + d1 (n2 x n0) + d2 (n0 x n1). */
static NOINLINE void tpi_exact(const double *xyz, const arr_point *p, arr_exact *out)
{
    small n[3][3], d[3];
    for (int i = 0; i < 3; i++) {
        const double *a = vtx(xyz, p->v[3 * i]);
        normal_exact(a, vtx(xyz, p->v[3 * i + 1]), vtx(xyz, p->v[3 * i + 2]), n[i]);
        d[i].n = dot_doubles(n[i], a, d[i].c);
    }
    double c[3][3][CAP(4)]; /* c[i] = n[i+1] x n[i+2] */
    int nc[3][3];
    for (int i = 0; i < 3; i++) {
        const small *u = n[(i + 1) % 3], *v = n[(i + 2) % 3];
        for (int k = 0; k < 3; k++) {
            int a = (k + 1) % 3, b = (k + 2) % 3;
            nc[i][k] = minor2(u[a].n, u[a].c, v[b].n, v[b].c, u[b].n, u[b].c, v[a].n, v[a].c,
                              c[i][k]);
        }
    }
    const int sg[3] = {1, 1, 1};
    for (int k = 0; k < 3; k++) {
        const double *e[3] = {d[0].c, d[1].c, d[2].c}, *f[3] = {c[0][k], c[1][k], c[2][k]};
        int ne[3] = {d[0].n, d[1].n, d[2].n}, nf[3] = {nc[0][k], nc[1][k], nc[2][k]};
        out->n[k] = sum_of_products(3, e, ne, f, nf, sg, out->c[k]);
    }
    const double *e[3] = {n[0][0].c, n[0][1].c, n[0][2].c}, *f[3] = {c[0][0], c[0][1], c[0][2]};
    int ne[3] = {n[0][0].n, n[0][1].n, n[0][2].n}, nf[3] = {nc[0][0], nc[0][1], nc[0][2]};
    out->n[3] = sum_of_products(3, e, ne, f, nf, sg, out->c[3]);
}

int arr_point_exact(const double *xyz, const arr_point *p, arr_exact *out)
{
    if (!arr_point_valid(xyz, p))
        return 0;
    switch (p->kind) {
    case ARR_EXPLICIT: {
        const double *a = vtx(xyz, p->v[0]);
        for (int k = 0; k < 3; k++)
            set_double(out, k, a[k]);
        set_double(out, 3, 1.0);
        break;
    }
    case ARR_LPI:
        lpi_exact(xyz, p, out);
        break;
    case ARR_TPI:
        tpi_exact(xyz, p, out);
        break;
    case ARR_SSI:
        ssi_exact(xyz, p, out);
        break;
    default:
        lift_exact(xyz, p, out);
        break;
    }
    return 1;
}

/* ---- The cache ---------------------------------------------------------------------- */

/* Direct-mapped by point id: slots are few and large (13 KB), and the exact stage meets
 * the points of one cluster in runs. */
#define XC_SLOTS 256

struct arr_exact_cache {
    int64_t id[XC_SLOTS]; /* -1: empty */
    arr_exact *x;         /* XC_SLOTS, allocated on first use (NULL: not yet, or no memory) */
    int tried;            /* the allocation was tried */
};

arr_exact_cache *arr_exact_cache_new(void)
{
    arr_exact_cache *xc = malloc(sizeof *xc);
    if (!xc)
        return NULL;
    for (int i = 0; i < XC_SLOTS; i++)
        xc->id[i] = -1;
    xc->x = NULL;
    xc->tried = 0;
    return xc;
}

void arr_exact_cache_free(arr_exact_cache *xc)
{
    if (!xc)
        return;
    free(xc->x);
    free(xc);
}

void arr_exact_cache_drop(arr_exact_cache *xc, int64_t id)
{
    if (!xc)
        return;
    for (int i = 0; i < XC_SLOTS; i++)
        if (xc->id[i] >= id)
            xc->id[i] = -1;
}

static void copy_exact(arr_exact *to, const arr_exact *from)
{
    for (int k = 0; k < 4; k++) {
        to->n[k] = from->n[k];
        memcpy(to->c[k], from->c[k], (size_t)from->n[k] * sizeof(double));
    }
}

/* arr_point_exact for point p of P, through P's cache when it has one. */
static int point_exact(const arr_points *P, int64_t p, arr_exact *out)
{
    arr_exact_cache *xc = P->xc;
    if (!xc || P->pts[p].kind == ARR_EXPLICIT)
        return arr_point_exact(P->xyz, &P->pts[p], out);
    int slot = (int)(((uint64_t)p * 0x9E3779B97F4A7C15u) >> 56) % XC_SLOTS;
    if (xc->x && xc->id[slot] == p) {
        copy_exact(out, &xc->x[slot]);
        return 1;
    }
    if (!arr_point_exact(P->xyz, &P->pts[p], out))
        return 0;
    if (!xc->x && !xc->tried) {
        xc->tried = 1;
        xc->x = malloc(XC_SLOTS * sizeof *xc->x);
    }
    if (xc->x) {
        copy_exact(&xc->x[slot], out);
        xc->id[slot] = p;
    }
    return 1;
}

/* ---- The predicates ---------------------------------------------------------------- */

static int wsign(const arr_exact *x)
{
    return expn_sign(x->n[3], x->c[3]);
}

int arr_orient3d_exact(const arr_points *P, int64_t a, int64_t b, int64_t c, int64_t q)
{
    const double *pa = vtx(P->xyz, a), *pb = vtx(P->xyz, b), *pc = vtx(P->xyz, c);
    for (int k = 0; k < 3; k++)
        if (!arr_on_grid(pa[k]) || !arr_on_grid(pb[k]) || !arr_on_grid(pc[k]))
            return ARR_NOT_EXACT;
    arr_exact x;
    if (!point_exact(P, q, &x))
        return ARR_NOT_EXACT;
    /* orient3d(a, b, c, q) = det[a - q, b - q, c - q] = -n . (q - a), n = (b-a) x (c-a);
     * with q = X / W: -sign(W) sign(n . (X - W a)). */
    small n[3];
    normal_exact(pa, pb, pc, n);
    double t[3][CAP(7)], wa[2 * CAP(6)];
    int nt[3];
    for (int k = 0; k < 3; k++) {
        int nwa = expn_scale(x.n[3], x.c[3], pa[k], wa);
        nt[k] = expn_diff_expansions(x.n[k], x.c[k], nwa, wa, t[k]);
    }
    double s[CAP(9)];
    const double *e[3] = {n[0].c, n[1].c, n[2].c}, *f[3] = {t[0], t[1], t[2]};
    const int ne[3] = {n[0].n, n[1].n, n[2].n}, sg[3] = {1, 1, 1};
    int ns = sum_of_products(3, e, ne, f, nt, sg, s);
    return -expn_sign(ns, s) * wsign(&x);
}

/* The determinant of the rows (X_i, X_j, W) of three points, expanded along W. */
static NOINLINE int det3_sign(const arr_exact *x[3], int i, int j)
{
    double m[3][CAP(14)];
    int nm[3];
    for (int r = 0; r < 3; r++) {
        const arr_exact *u = x[(r + 1) % 3], *v = x[(r + 2) % 3];
        nm[r] = minor2(u->n[i], u->c[i], v->n[j], v->c[j], u->n[j], u->c[j], v->n[i],
                       v->c[i], m[r]);
    }
    /* det = W0 m0 + W1 m1 + W2 m2 with m_r the minor of rows r+1, r+2 in cyclic order. */
    double d[CAP(DEG_MAX)];
    const double *e[3] = {x[0]->c[3], x[1]->c[3], x[2]->c[3]}, *f[3] = {m[0], m[1], m[2]};
    const int ne[3] = {x[0]->n[3], x[1]->n[3], x[2]->n[3]}, sg[3] = {1, 1, 1};
    int nd = sum_of_products(3, e, ne, f, nm, sg, d);
    return expn_sign(nd, d);
}

int arr_orient2d_exact(const arr_points *P, int64_t p, int64_t q, int64_t r, int axis)
{
    arr_exact x[3];
    if (!point_exact(P, p, &x[0]) ||
        !point_exact(P, q, &x[1]) ||
        !point_exact(P, r, &x[2]))
        return ARR_NOT_EXACT;
    /* det[(X_i, X_j, W) rows] = Wp Wq Wr orient2d(p, q, r). */
    const arr_exact *rows[3] = {&x[0], &x[1], &x[2]};
    int s = det3_sign(rows, (axis + 1) % 3, (axis + 2) % 3);
    return s * wsign(&x[0]) * wsign(&x[1]) * wsign(&x[2]);
}

/* Sign of p[k] - q[k] for exact points: sign(Xp_k Wq - Xq_k Wp) sign(Wp) sign(Wq). */
static int cmp_coords(const arr_exact *xp, const arr_exact *xq, int k)
{
    double h[CAP(13)];
    int n = minor2(xp->n[k], xp->c[k], xq->n[3], xq->c[3], xq->n[k], xq->c[k], xp->n[3],
                   xp->c[3], h);
    return expn_sign(n, h) * wsign(xp) * wsign(xq);
}

int arr_cmp_exact(const arr_points *P, int64_t p, int64_t q, int axis)
{
    arr_exact xp, xq;
    if (!point_exact(P, p, &xp) || !point_exact(P, q, &xq))
        return ARR_NOT_EXACT;
    return cmp_coords(&xp, &xq, axis);
}

int arr_same_exact(const arr_points *P, int64_t p, int64_t q)
{
    arr_exact xp, xq;
    if (!point_exact(P, p, &xp) || !point_exact(P, q, &xq))
        return ARR_NOT_EXACT;
    for (int k = 0; k < 3; k++)
        if (cmp_coords(&xp, &xq, k) != 0)
            return 0;
    return 1;
}

/* The double nearest X / W (within one ulp): the quotient of the leading components,
 * then one Newton correction with the exact residual X - q W. */
static double exact_quotient(int nx, const double *X, int nw, const double *W)
{
    if (expn_sign(nx, X) == 0)
        return 0.0;
    double w = W[nw - 1];
    double q = X[nx - 1] / w;
    /* q W is exact: |q| >= 2^-480 for a non-zero X / W, so q W's bits stay above 2^-850. */
    double qw[2 * CAP(7)], r[3 * CAP(7)];
    int nqw = expn_scale(nw, W, q, qw);
    int nr = expn_compress(expn_diff_expansions(nx, X, nqw, qw, r), r);
    return q + r[nr - 1] / w;
}

int arr_coords_exact(const arr_points *P, int64_t p, double out[3])
{
    arr_exact x;
    if (!point_exact(P, p, &x) || wsign(&x) == 0)
        return 0;
    for (int k = 0; k < 3; k++)
        out[k] = exact_quotient(x.n[k], x.c[k], x.n[3], x.c[3]);
    return 1;
}
