/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* bigref.h - a test-only exact reference for the implicit points: fixed-width signed
 * big integers, and the constructions and predicates computed with them from the
 * integer grid coordinates (units of 2^-50), with formulas other than the library's
 * where there is a choice (orient3d as det[Wa - X, Wb - X, Wc - X], orient2d after
 * translating to p).  Independent of expansion arithmetic and of the library. */
#ifndef MFG_TEST_BIGREF_H
#define MFG_TEST_BIGREF_H

#include <stdint.h>
#include <string.h>

__extension__ typedef unsigned __int128 bigref_u128;

/* 28 limbs of 64 bits: the largest reference value is orient2d of three TPIs after the
 * translation, degree 26 in units of 2^-50 below 2^(56 * 26 + 12) < 2^1500. */
#define BIG_LIMBS 28

typedef struct big {
    int neg;                  /* 1 when negative (never for zero) */
    int n;                    /* limbs in use; 0 is zero */
    uint64_t d[BIG_LIMBS];    /* magnitude, little-endian */
} big;

/* Set when a result would not fit: the test reports it as a failure. */
static int big_overflowed = 0;

static inline void big_trim(big *r)
{
    while (r->n > 0 && r->d[r->n - 1] == 0)
        r->n--;
    if (r->n == 0)
        r->neg = 0;
}

static inline big big_i64(int64_t x)
{
    big r;
    memset(&r, 0, sizeof r);
    if (x != 0) {
        r.neg = x < 0;
        r.d[0] = x < 0 ? (uint64_t)0 - (uint64_t)x : (uint64_t)x;
        r.n = 1;
    }
    return r;
}

static inline int big_mag_cmp(const big *a, const big *b)
{
    if (a->n != b->n)
        return a->n < b->n ? -1 : 1;
    for (int i = a->n - 1; i >= 0; i--)
        if (a->d[i] != b->d[i])
            return a->d[i] < b->d[i] ? -1 : 1;
    return 0;
}

/* |a| + |b|, sign left to the caller. */
static inline big big_mag_add(const big *a, const big *b)
{
    big r;
    memset(&r, 0, sizeof r);
    int n = a->n > b->n ? a->n : b->n;
    uint64_t carry = 0;
    for (int i = 0; i < n; i++) {
        bigref_u128 s = (bigref_u128)(i < a->n ? a->d[i] : 0) + (i < b->n ? b->d[i] : 0) + carry;
        r.d[i] = (uint64_t)s;
        carry = (uint64_t)(s >> 64);
    }
    if (carry) {
        if (n == BIG_LIMBS) {
            big_overflowed = 1;
            return r;
        }
        r.d[n++] = carry;
    }
    r.n = n;
    return r;
}

/* |a| - |b| for |a| >= |b|. */
static inline big big_mag_sub(const big *a, const big *b)
{
    big r;
    memset(&r, 0, sizeof r);
    uint64_t borrow = 0;
    for (int i = 0; i < a->n; i++) {
        uint64_t bi = i < b->n ? b->d[i] : 0;
        uint64_t t = a->d[i] - bi - borrow;
        borrow = (a->d[i] < bi) || (a->d[i] - bi < borrow);
        r.d[i] = t;
    }
    r.n = a->n;
    big_trim(&r);
    return r;
}

static inline big big_add(big a, big b)
{
    big r;
    if (a.neg == b.neg) {
        r = big_mag_add(&a, &b);
        r.neg = a.neg;
    } else if (big_mag_cmp(&a, &b) >= 0) {
        r = big_mag_sub(&a, &b);
        r.neg = a.neg;
    } else {
        r = big_mag_sub(&b, &a);
        r.neg = b.neg;
    }
    big_trim(&r);
    return r;
}

static inline big big_neg(big a)
{
    if (a.n)
        a.neg ^= 1;
    return a;
}

static inline big big_sub(big a, big b)
{
    return big_add(a, big_neg(b));
}

static inline big big_mul(big a, big b)
{
    big r;
    memset(&r, 0, sizeof r);
    if (a.n == 0 || b.n == 0)
        return r;
    if (a.n + b.n > BIG_LIMBS) {
        big_overflowed = 1;
        return r;
    }
    for (int i = 0; i < a.n; i++) {
        uint64_t carry = 0;
        for (int j = 0; j < b.n; j++) {
            bigref_u128 t = (bigref_u128)a.d[i] * b.d[j] + r.d[i + j] + carry;
            r.d[i + j] = (uint64_t)t;
            carry = (uint64_t)(t >> 64);
        }
        r.d[i + b.n] = carry;
    }
    r.n = a.n + b.n;
    r.neg = a.neg ^ b.neg;
    big_trim(&r);
    return r;
}

/* a * 2^s, s >= 0. */
static inline big big_shl(big a, int s)
{
    big r;
    memset(&r, 0, sizeof r);
    if (a.n == 0)
        return r;
    int limbs = s / 64, bits = s % 64;
    if (a.n + limbs + 1 > BIG_LIMBS) {
        big_overflowed = 1;
        return r;
    }
    for (int i = 0; i < a.n; i++) {
        r.d[i + limbs] |= a.d[i] << bits;
        if (bits)
            r.d[i + limbs + 1] |= a.d[i] >> (64 - bits);
    }
    r.n = a.n + limbs + 1;
    r.neg = a.neg;
    big_trim(&r);
    return r;
}

static inline int big_sign(big a)
{
    return a.n == 0 ? 0 : (a.neg ? -1 : 1);
}

static inline int big_cmp(big a, big b)
{
    return big_sign(big_sub(a, b));
}

static inline int big_eq(big a, big b)
{
    return big_cmp(a, b) == 0;
}

/* The exact value of a double that is an integer multiple of 2^-e (e >= 0), times 2^e;
 * *ok = 0 when it is not such a multiple (or not finite). */
static inline big big_from_scaled_double(double x, int e, int *ok)
{
    big r = big_i64(0);
    if (x == 0.0)
        return r;
    if (!(x == x) || x - x != 0.0) {
        *ok = 0;
        return r;
    }
    int ex;
    double m = frexp(x, &ex); /* x = m 2^ex, 0.5 <= |m| < 1 */
    int64_t mi = (int64_t)ldexp(m, 53); /* x = mi 2^(ex - 53) exactly */
    int shift = ex - 53 + e;
    while (shift < 0 && (mi % 2) == 0) {
        mi /= 2;
        shift++;
    }
    if (shift < 0) {
        *ok = 0;
        return r;
    }
    return big_shl(big_i64(mi), shift);
}

/* ---- Vectors and points ---------------------------------------------------------- */

typedef struct bpt {
    big X[3];
    big W;
} bpt;

static inline void bvec(const int64_t *a, big o[3])
{
    for (int k = 0; k < 3; k++)
        o[k] = big_i64(a[k]);
}

static inline void bsub3(const big a[3], const big b[3], big o[3])
{
    for (int k = 0; k < 3; k++)
        o[k] = big_sub(a[k], b[k]);
}

static inline void bcross(const big a[3], const big b[3], big o[3])
{
    big x = big_sub(big_mul(a[1], b[2]), big_mul(a[2], b[1]));
    big y = big_sub(big_mul(a[2], b[0]), big_mul(a[0], b[2]));
    big z = big_sub(big_mul(a[0], b[1]), big_mul(a[1], b[0]));
    o[0] = x;
    o[1] = y;
    o[2] = z;
}

static inline big bdot(const big a[3], const big b[3])
{
    return big_add(big_add(big_mul(a[0], b[0]), big_mul(a[1], b[1])), big_mul(a[2], b[2]));
}

/* The normal (b - a) x (c - a) from integer coordinates. */
static inline void bnormal(const int64_t *a, const int64_t *b, const int64_t *c, big n[3])
{
    big A[3], B[3], C[3], e1[3], e2[3];
    bvec(a, A);
    bvec(b, B);
    bvec(c, C);
    bsub3(B, A, e1);
    bsub3(C, A, e2);
    bcross(e1, e2, n);
}

/* Homogeneous coordinates of a construction (kind/axis as in implicit.h) from the
 * integer coordinates of its vertices u[m] and lift l (units of 2^-50): X in units of
 * 2^(-50 dX), W in units of 2^(-50 dW). */
static inline bpt bref_point(int kind, int axis, const int64_t *const *u, const int64_t *l)
{
    bpt r;
    switch (kind) {
    case 0:
        bvec(u[0], r.X);
        r.W = big_i64(1);
        break;
    case 1: { /* LPI: t = n.(r - p) / n.(q - p) */
        big n[3], P[3], Q[3], R[3], dq[3], dr[3];
        bnormal(u[2], u[3], u[4], n);
        bvec(u[0], P);
        bvec(u[1], Q);
        bvec(u[2], R);
        bsub3(Q, P, dq);
        bsub3(R, P, dr);
        r.W = bdot(n, dq);
        big num = bdot(n, dr);
        for (int k = 0; k < 3; k++)
            r.X[k] = big_add(big_mul(P[k], r.W), big_mul(num, dq[k]));
        break;
    }
    case 2: { /* TPI: Cramer */
        big n[3][3], d[3], A[3], c[3][3];
        for (int i = 0; i < 3; i++) {
            bnormal(u[3 * i], u[3 * i + 1], u[3 * i + 2], n[i]);
            bvec(u[3 * i], A);
            d[i] = bdot(n[i], A);
        }
        for (int i = 0; i < 3; i++)
            bcross(n[(i + 1) % 3], n[(i + 2) % 3], c[i]);
        r.W = bdot(n[0], c[0]);
        for (int k = 0; k < 3; k++)
            r.X[k] = big_add(big_add(big_mul(d[0], c[0][k]), big_mul(d[1], c[1][k])),
                             big_mul(d[2], c[2][k]));
        break;
    }
    case 3: { /* SSI in the projection (i, j) */
        int i = (axis + 1) % 3, j = (axis + 2) % 3;
        big P[3], Q[3], R[3], S[3], dq[3], rs[3], rp[3];
        bvec(u[0], P);
        bvec(u[1], Q);
        bvec(u[2], R);
        bvec(u[3], S);
        bsub3(Q, P, dq);
        bsub3(S, R, rs);
        bsub3(R, P, rp);
        r.W = big_sub(big_mul(dq[i], rs[j]), big_mul(dq[j], rs[i]));
        big num = big_sub(big_mul(rp[i], rs[j]), big_mul(rp[j], rs[i]));
        for (int k = 0; k < 3; k++)
            r.X[k] = big_add(big_mul(P[k], r.W), big_mul(num, dq[k]));
        break;
    }
    default: { /* LIFT */
        int i = (axis + 1) % 3, j = (axis + 2) % 3;
        big n[3], A[3];
        bnormal(u[0], u[1], u[2], n);
        bvec(u[0], A);
        r.W = n[axis];
        big l0 = big_i64(l[0]), l1 = big_i64(l[1]);
        r.X[axis] = big_sub(big_sub(big_mul(n[axis], A[axis]), big_mul(n[i], big_sub(l0, A[i]))),
                            big_mul(n[j], big_sub(l1, A[j])));
        r.X[i] = big_mul(l0, r.W);
        r.X[j] = big_mul(l1, r.W);
        break;
    }
    }
    return r;
}

/* orient3d(a, b, c, q) = sign det[a - q, b - q, c - q]: with q = X / W the rows times W
 * give det[Wa - X, Wb - X, Wc - X] = W^3 det[...], whose sign is sign(W) times ours. */
static inline int bref_orient3d(const int64_t *a, const int64_t *b, const int64_t *c,
                                const bpt *q)
{
    const int64_t *v[3] = {a, b, c};
    big rows[3][3];
    for (int m = 0; m < 3; m++)
        for (int k = 0; k < 3; k++)
            rows[m][k] = big_sub(big_mul(q->W, big_i64(v[m][k])), q->X[k]);
    big cr[3];
    bcross(rows[1], rows[2], cr);
    return big_sign(bdot(rows[0], cr)) * big_sign(q->W);
}

/* orient2d after translating to p: A = Wp Wq (q - p), B = Wp Wr (r - p) in homogeneous
 * form, A x B = Wp^2 Wq Wr (q - p) x (r - p). */
static inline int bref_orient2d(const bpt *p, const bpt *q, const bpt *r, int axis)
{
    int i = (axis + 1) % 3, j = (axis + 2) % 3;
    big Ai = big_sub(big_mul(q->X[i], p->W), big_mul(p->X[i], q->W));
    big Aj = big_sub(big_mul(q->X[j], p->W), big_mul(p->X[j], q->W));
    big Bi = big_sub(big_mul(r->X[i], p->W), big_mul(p->X[i], r->W));
    big Bj = big_sub(big_mul(r->X[j], p->W), big_mul(p->X[j], r->W));
    big cr = big_sub(big_mul(Ai, Bj), big_mul(Aj, Bi));
    return big_sign(cr) * big_sign(q->W) * big_sign(r->W);
}

static inline int bref_cmp(const bpt *p, const bpt *q, int axis)
{
    big d = big_sub(big_mul(p->X[axis], q->W), big_mul(q->X[axis], p->W));
    return big_sign(d) * big_sign(p->W) * big_sign(q->W);
}

static inline int bref_same(const bpt *p, const bpt *q)
{
    return bref_cmp(p, q, 0) == 0 && bref_cmp(p, q, 1) == 0 && bref_cmp(p, q, 2) == 0;
}

#endif
