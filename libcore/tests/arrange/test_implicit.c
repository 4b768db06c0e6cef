/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* test_implicit.c - the implicit points and their predicates (arrange/implicit.h) against
 * an exact big-integer reference (bigref.h), on random, exactly degenerate and nearly
 * degenerate configurations at every scale of the grid; counts how often the filter
 * decides and checks it never lies.  Modes (one ctest each):
 *   points      prepare, the exact homogeneous coordinates (value and degree) and the
 *               filter bounds h, herr against the reference; expansion primitives
 *   random      predicates on random constructions at many scales
 *   degenerate  equal points built differently, collinear and coplanar sets, flipped
 *               signs of W, shortcuts, invalid constructions
 *   near        the same configurations moved by one grid step (stress: many cases)
 *   extremes    coordinates at +-16 and steps of 2^-50
 *   coords      arr_coords within 2 ulps (1 when exact) of the exact quotient
 *   offgrid     inputs off the grid: refused or answered without a crash
 *   bench       ns per call of the filter path and of the exact stage
 *   dump N      writes N cases and the library's answers to stdout for
 *               tests/python/test_arrange_implicit.py (exact rationals) */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "mfg_test.h"
#include "bigref.h"
#include "arrange/implicit.h"
#include "common/expansion.h"
#include "common/predicates.h"

/* The sanitizer build runs the same tests on fewer cases. */
#if defined(__SANITIZE_ADDRESS__)
#define CASE_DIVISOR 4
#else
#define CASE_DIVISOR 1
#endif

#define UNITS_PER_ONE 0x1p50                 /* grid units in 1.0 */
#define UNITS_MAX ((int64_t)1 << 54)         /* 16.0 in grid units */
#define UNITS_EXACT ((int64_t)1 << 53)       /* above, only even units are doubles */

/* Degree of X for each kind (W is one less); implicit.h's table. */
static const int DEG_X[5] = {1, 4, 7, 3, 3};
static const int NVERTS[5] = {1, 5, 9, 4, 3};

/* Where the dump mode writes the cases (NULL: check against the reference instead). */
static FILE *dump_out = NULL;

/* ---- A pool of vertices (doubles and integer units) and points ---------------------- */

#define POOL_V 4096
#define POOL_P 2048

typedef struct pool {
    double xyz[3 * POOL_V];
    int64_t iu[3 * POOL_V]; /* the same coordinates in units of 2^-50 */
    int64_t nv;
    arr_point pts[POOL_P];
    int64_t lift_u[POOL_P][2];
    int ok[POOL_P];   /* arr_point_prepare's answer */
    bpt ref[POOL_P];  /* reference coordinates (check modes only) */
    int64_t np;
    int with_ref;
} pool;

static void pool_reset(pool *P)
{
    P->nv = 0;
    P->np = 0;
    if (dump_out)
        fprintf(dump_out, "CASE\n");
}

static arr_points view(const pool *P)
{
    arr_points v = {P->xyz, P->nv, (arr_point *)P->pts, P->np, NULL};
    return v;
}

/* 1 when u grid units are a double within the grid's range. */
static int units_ok(int64_t u)
{
    int64_t a = u < 0 ? -u : u;
    return a <= UNITS_MAX && (a <= UNITS_EXACT || a % 2 == 0);
}

static int64_t add_v(pool *P, const int64_t u[3])
{
    int64_t i = P->nv++;
    for (int k = 0; k < 3; k++) {
        P->iu[3 * i + k] = u[k];
        P->xyz[3 * i + k] = (double)u[k] / UNITS_PER_ONE;
    }
    if (dump_out)
        fprintf(dump_out, "V %ld %a %a %a\n", (long)i, P->xyz[3 * i], P->xyz[3 * i + 1],
                P->xyz[3 * i + 2]);
    return i;
}

/* ---- Statistics ------------------------------------------------------------------- */

typedef struct stats {
    long queries, filter_decided, filter_unsure, filter_wrong, exact_wrong, public_wrong;
    long zero_answers, shortcut_zero;
} stats;

static stats st;

static void stats_print(const char *what)
{
    printf("%s: %ld queries, filter decided %ld, unsure %ld (exact stage), zero answers %ld; "
           "wrong: filter %ld, exact %ld, public %ld\n",
           what, st.queries, st.filter_decided, st.filter_unsure, st.zero_answers,
           st.filter_wrong, st.exact_wrong, st.public_wrong);
}

/* One predicate answer against the reference: the filter may only be right or unsure,
 * the exact stage and the public predicate must be right. */
static void tally(int want, int filter, int exact, int pub)
{
    st.queries++;
    st.zero_answers += want == 0;
    if (filter == 0)
        st.filter_unsure++;
    else
        st.filter_decided++;
    if (filter != 0 && filter != want)
        st.filter_wrong++;
    if (exact != want)
        st.exact_wrong++;
    if (pub != want)
        st.public_wrong++;
}

/* ---- Points ------------------------------------------------------------------------ */

/* Adds a point; returns its index, or -1 when arr_point_prepare refused it (a degenerate
 * construction: the reference must agree that W = 0). */
static int64_t add_pt(pool *P, int kind, int axis, const int64_t *v, const int64_t *lift)
{
    int64_t i = P->np++;
    arr_point *p = &P->pts[i];
    memset(p, 0, sizeof *p);
    p->kind = (uint8_t)kind;
    p->axis = (uint8_t)axis;
    for (int m = 0; m < NVERTS[kind]; m++)
        p->v[m] = v[m];
    if (kind == ARR_LIFT) {
        P->lift_u[i][0] = lift[0];
        P->lift_u[i][1] = lift[1];
        p->lift[0] = (double)lift[0] / UNITS_PER_ONE;
        p->lift[1] = (double)lift[1] / UNITS_PER_ONE;
    }
    P->ok[i] = arr_point_prepare(P->xyz, p);
    if (P->with_ref) {
        const int64_t *u[9];
        for (int m = 0; m < NVERTS[kind]; m++)
            u[m] = &P->iu[3 * v[m]];
        P->ref[i] = bref_point(kind, axis, u, P->lift_u[i]);
        CHECK_EQ_INT(P->ok[i], big_sign(P->ref[i].W) != 0);
    }
    if (dump_out) {
        fprintf(dump_out, "P %ld %d %d", (long)i, kind, axis);
        for (int m = 0; m < 9; m++)
            fprintf(dump_out, " %ld", m < NVERTS[kind] ? (long)v[m] : -1L);
        fprintf(dump_out, " %a %a %d\n", p->lift[0], p->lift[1], P->ok[i]);
    }
    if (!P->ok[i]) {
        P->np--; /* not a point: forget it */
        return -1;
    }
    return i;
}

/* ---- Predicate queries: checked against the reference or dumped ------------------- */

/* Set while a scenario asks what is degenerate by construction: the reference must then
 * say so too (zero signs, the same point), so a generator slip cannot hide. */
static int expect_degenerate = 0;
static long expected_degenerate = 0;

static void check_expected(int want_is_degenerate)
{
    if (expect_degenerate) {
        expected_degenerate++;
        CHECK(want_is_degenerate);
    }
}

static void q_orient3d(pool *P, int64_t a, int64_t b, int64_t c, int64_t q)
{
    arr_points V = view(P);
    int pub = arr_orient3d(&V, a, b, c, q);
    if (dump_out) {
        fprintf(dump_out, "O3 %ld %ld %ld %ld %d\n", (long)a, (long)b, (long)c, (long)q, pub);
        return;
    }
    int want = bref_orient3d(&P->iu[3 * a], &P->iu[3 * b], &P->iu[3 * c], &P->ref[q]);
    check_expected(want == 0);
    tally(want, arr_orient3d_filter(&V, a, b, c, q), arr_orient3d_exact(&V, a, b, c, q), pub);
}

static void q_orient2d(pool *P, int64_t p, int64_t q, int64_t r, int axis)
{
    arr_points V = view(P);
    int pub = arr_orient2d(&V, p, q, r, axis);
    if (dump_out) {
        fprintf(dump_out, "O2 %ld %ld %ld %d %d\n", (long)p, (long)q, (long)r, axis, pub);
        return;
    }
    int want = bref_orient2d(&P->ref[p], &P->ref[q], &P->ref[r], axis);
    check_expected(want == 0);
    tally(want, arr_orient2d_filter(&V, p, q, r, axis), arr_orient2d_exact(&V, p, q, r, axis),
          pub);
}

static void q_cmp(pool *P, int64_t p, int64_t q, int axis)
{
    arr_points V = view(P);
    int pub = arr_cmp(&V, p, q, axis);
    if (dump_out) {
        fprintf(dump_out, "CMP %ld %ld %d %d\n", (long)p, (long)q, axis, pub);
        return;
    }
    int want = bref_cmp(&P->ref[p], &P->ref[q], axis);
    check_expected(want == 0);
    tally(want, arr_cmp_filter(&V, p, q, axis), arr_cmp_exact(&V, p, q, axis), pub);
}

static void q_same(pool *P, int64_t p, int64_t q)
{
    arr_points V = view(P);
    int pub = arr_same(&V, p, q);
    if (dump_out) {
        fprintf(dump_out, "SAME %ld %ld %d\n", (long)p, (long)q, pub);
        return;
    }
    int want = bref_same(&P->ref[p], &P->ref[q]);
    check_expected(want == 1);
    CHECK_EQ_INT(pub, want);
    CHECK_EQ_INT(arr_same_exact(&V, p, q), want);
}

/* arr_coords within 2 ulps of X / W: |out W 2^50 - X| <= 2 ulp(out) |W| 2^50 in units
 * (X in units of 2^-50 dX, W of 2^-50 dW, dX = dW + 1).  Returns 1 when out is exact. */
static long coords_checked, coords_exact_hits, coords_bad;
static void q_coords(pool *P, int64_t p)
{
    arr_points V = view(P);
    double out[3];
    arr_coords(&V, p, out);
    if (dump_out) {
        fprintf(dump_out, "XYZ %ld %a %a %a\n", (long)p, out[0], out[1], out[2]);
        return;
    }
    const bpt *r = &P->ref[p];
    for (int k = 0; k < 3; k++) {
        coords_checked++;
        /* out = M 2^E with an integer M; compare M W 2^(E + 50) with X, multiplying
         * both sides by 2^-(E + 50) when that is negative. */
        int ex;
        double m = frexp(out[k], &ex);
        int64_t M = (int64_t)ldexp(m, 53);
        int E = ex - 53;
        int sh = E + 50;
        big lhs = big_mul(big_i64(M), r->W), rhs = r->X[k];
        if (sh >= 0)
            lhs = big_shl(lhs, sh);
        else
            rhs = big_shl(rhs, -sh);
        big diff = big_sub(lhs, rhs);
        if (diff.n == 0) {
            coords_exact_hits++;
            continue;
        }
        if (out[k] == 0.0) { /* X != 0 but out == 0 */
            coords_bad++;
            continue;
        }
        /* 2 ulps, ulp(out) = 2^E (M has 53 bits): 2^(E+1) |W| 2^50 = |W| 2^(sh+1), or
         * 2 |W| after the scaling by 2^-sh. */
        big tol = big_shl(r->W, sh >= 0 ? sh + 1 : 1);
        diff.neg = 0;
        tol.neg = 0;
        if (big_mag_cmp(&diff, &tol) > 0)
            coords_bad++;
    }
}

/* ---- Random grid geometry ---------------------------------------------------------- */

/* A frame: where a configuration lives.  Vectors are unit * random integers of up to
 * mbits bits; the anchor region is kept so that anchor + 12 * vector stays in range. */
typedef struct frame {
    int64_t unit;   /* grid units per step of a vector (a power of two) */
    int mbits;      /* vector components in [-2^mbits, 2^mbits] steps */
    int64_t center[3];
    int64_t spread; /* anchors within center +- spread units */
} frame;

static int64_t rnd_range(int64_t lo, int64_t hi)
{
    uint64_t span = (uint64_t)(hi - lo) + 1;
    return lo + (int64_t)(span ? rng_next() % span : rng_next());
}

/* A frame at scale 2^s (s = log2 of the step in units of 1.0, -50 .. 1); extreme puts
 * the region against a corner of the +-16 box. */
static frame make_frame(int s, int mbits, int extreme)
{
    frame f;
    f.unit = (int64_t)1 << (s + 50);
    /* Beyond 2^53 units (|x| >= 8) only even units are doubles: a frame of odd steps
     * stays inside |x| < 8, an extreme one takes steps of 2 units (2^-49). */
    if (f.unit == 1 && extreme)
        f.unit = 2;
    int64_t lim = f.unit == 1 ? UNITS_EXACT : UNITS_MAX;
    f.mbits = mbits;
    int64_t reach = 12 * (f.unit << mbits); /* largest offset of a vertex from an anchor */
    if (reach > lim / 2)
        reach = lim / 2;
    int64_t room = lim - reach;
    for (int k = 0; k < 3; k++) {
        if (extreme) {
            int64_t sgn = (rng_next() & 1) ? 1 : -1;
            f.center[k] = sgn * (room - (int64_t)(rng_next() % 4) * f.unit);
        } else {
            f.center[k] = rnd_range(-room / 2, room / 2);
        }
    }
    f.spread = extreme ? (f.unit << mbits) : room / 2;
    if (f.spread > room / 2)
        f.spread = room / 2;
    return f;
}

static void rnd_vec(const frame *f, int64_t o[3])
{
    int64_t m = (int64_t)1 << f->mbits;
    for (int k = 0; k < 3; k++)
        o[k] = rnd_range(-m, m) * f->unit;
}

static void rnd_anchor(const frame *f, int64_t o[3])
{
    /* A multiple of the step, rounded towards zero: within the frame's room. */
    for (int k = 0; k < 3; k++) {
        int64_t c = f->center[k] + rnd_range(-f->spread, f->spread);
        if (c > UNITS_MAX - 12 * (f->unit << f->mbits))
            c = UNITS_MAX - 12 * (f->unit << f->mbits);
        if (c < -(UNITS_MAX - 12 * (f->unit << f->mbits)))
            c = -(UNITS_MAX - 12 * (f->unit << f->mbits));
        o[k] = c - c % f->unit;
    }
}

/* o = a + s * b (units), 0 when it leaves the grid. */
static int lin(const int64_t a[3], int64_t s, const int64_t b[3], int64_t o[3])
{
    for (int k = 0; k < 3; k++) {
        o[k] = a[k] + s * b[k];
        if (!units_ok(o[k]))
            return 0;
    }
    return 1;
}

static int64_t rnd_nonzero(int lo, int hi)
{
    int64_t x;
    do
        x = rnd_range(lo, hi);
    while (x == 0);
    return x;
}

/* A triangle whose plane contains the point c: c + u, c + v, c + a u + b v with
 * a + b != 1 (else the three are collinear) - c is not one of its vertices. */
static int tri_through(pool *P, const frame *f, const int64_t c[3], int64_t t[3])
{
    int64_t u[3], v[3], A[3], B[3], C[3], w[3];
    rnd_vec(f, u);
    rnd_vec(f, v);
    int64_t a, b;
    do {
        a = rnd_range(-3, 3);
        b = rnd_range(-3, 3);
    } while (a + b == 1);
    if (!lin(c, 1, u, A) || !lin(c, 1, v, B) || !lin(c, a, u, w) || !lin(w, b, v, C))
        return 0;
    t[0] = add_v(P, A);
    t[1] = add_v(P, B);
    t[2] = add_v(P, C);
    return 1;
}

/* A line through c: c + a w, c + b w with a != b. */
static int line_through(pool *P, const frame *f, const int64_t c[3], int64_t l[2])
{
    int64_t w[3], A[3], B[3];
    rnd_vec(f, w);
    int64_t a = rnd_range(-3, 3), b;
    do
        b = rnd_range(-3, 3);
    while (b == a);
    if (!lin(c, a, w, A) || !lin(c, b, w, B))
        return 0;
    l[0] = add_v(P, A);
    l[1] = add_v(P, B);
    return 1;
}

/* A point of the given kind located exactly at c (a grid point), built from fresh
 * vertices around it; -1 when the random construction is degenerate or leaves range. */
static int64_t rep_at(pool *P, const frame *f, const int64_t c[3], int kind, int axis)
{
    int64_t v[9], lift[2] = {0, 0};
    switch (kind) {
    case ARR_EXPLICIT:
        v[0] = add_v(P, c);
        break;
    case ARR_LPI:
        if (!line_through(P, f, c, v) || !tri_through(P, f, c, v + 2))
            return -1;
        break;
    case ARR_TPI:
        if (!tri_through(P, f, c, v) || !tri_through(P, f, c, v + 3) ||
            !tri_through(P, f, c, v + 6))
            return -1;
        break;
    case ARR_SSI:
        if (!line_through(P, f, c, v) || !line_through(P, f, c, v + 2))
            return -1;
        break;
    default:
        if (!tri_through(P, f, c, v))
            return -1;
        lift[0] = c[(axis + 1) % 3];
        lift[1] = c[(axis + 2) % 3];
        break;
    }
    return add_pt(P, kind, axis, v, lift);
}

/* A point of the given kind in general position near the frame's anchors. */
static int64_t rep_random(pool *P, const frame *f, int kind, int axis)
{
    int64_t v[9], lift[2] = {0, 0}, a[3];
    for (int m = 0; m < NVERTS[kind]; m++) {
        rnd_anchor(f, a);
        int64_t w[3], b[3];
        rnd_vec(f, w);
        if (!lin(a, 1, w, b))
            return -1;
        v[m] = add_v(P, b);
    }
    if (kind == ARR_LIFT) {
        rnd_anchor(f, a);
        lift[0] = a[(axis + 1) % 3];
        lift[1] = a[(axis + 2) % 3];
    }
    return add_pt(P, kind, axis, v, lift);
}

/* Like rep_at, then one vertex of the construction moved by one representable grid
 * step (half the time) or by 2^r steps, r up to 44 (the rest): the point moves off c by
 * a tiny rational amount, from far below the filter's resolution to just above it. */
static int64_t rep_near(pool *P, const frame *f, const int64_t c[3], int kind, int axis)
{
    int64_t i = rep_at(P, f, c, kind, axis);
    if (i < 0)
        return -1;
    /* Rebuild with one vertex nudged: copy the construction, nudge a fresh copy. */
    arr_point q = P->pts[i];
    int m = (int)rnd_range(0, NVERTS[kind] - 1);
    int64_t u[3];
    memcpy(u, &P->iu[3 * q.v[m]], sizeof u);
    int k = (int)rnd_range(0, 2);
    int64_t step = (u[k] > UNITS_EXACT - (1LL << 46) || u[k] < -UNITS_EXACT + (1LL << 46)) ? 2 : 1;
    if (rng_next() & 1)
        step <<= rnd_range(0, 44);
    u[k] += (rng_next() & 1) ? step : -step;
    if (!units_ok(u[k]))
        return -1;
    q.v[m] = add_v(P, u);
    int64_t lift[2] = {P->lift_u[i][0], P->lift_u[i][1]};
    return add_pt(P, kind, axis, q.v, lift);
}

/* The same construction with W's sign flipped (two vertices of a triangle or the two
 * ends of a line swapped): the same point. */
static int64_t rep_flipped(pool *P, int64_t i)
{
    arr_point q = P->pts[i];
    int64_t t;
    switch (q.kind) {
    case ARR_LPI:
    case ARR_SSI:
        t = q.v[0], q.v[0] = q.v[1], q.v[1] = t;
        break;
    case ARR_TPI: {
        int m = 3 * (int)rnd_range(0, 2);
        t = q.v[m], q.v[m] = q.v[m + 1], q.v[m + 1] = t;
        break;
    }
    case ARR_LIFT:
        t = q.v[1], q.v[1] = q.v[2], q.v[2] = t;
        break;
    default:
        return i;
    }
    int64_t lift[2] = {P->lift_u[i][0], P->lift_u[i][1]};
    return add_pt(P, q.kind, q.axis, q.v, lift);
}

static int rnd_kind(void)
{
    return (int)rnd_range(0, 4);
}

/* ---- Scenarios ------------------------------------------------------------------------ */

/* Scales: the step of a vector as a power of two, from the grid step up. */
static const int SCALES[] = {-50, -49, -46, -40, -30, -20, -12, -6, -3, 0};
#define NSCALES ((int)(sizeof SCALES / sizeof SCALES[0]))

static frame rnd_frame(int extreme)
{
    int s = SCALES[rnd_range(0, NSCALES - 1)];
    int maxbits = 48 - (s + 50);          /* keep 12 * 2^(s+50+mbits) well inside 2^54 */
    if (maxbits > 20)
        maxbits = 20;
    if (maxbits < 1)
        maxbits = 1;
    int mbits = (int)rnd_range(1, maxbits);
    return make_frame(s, mbits, extreme);
}

/* Random points of every kind; every predicate among them. */
static void sc_random(pool *P, int extreme)
{
    frame f = rnd_frame(extreme);
    int64_t ids[10];
    int n = 0;
    for (int t = 0; t < 10; t++) {
        int64_t i = rep_random(P, &f, t % 5, (int)rnd_range(0, 2));
        if (i >= 0)
            ids[n++] = i;
    }
    if (n < 3)
        return;
    int64_t a[3], tri[3];
    for (int m = 0; m < 3; m++) {
        rnd_anchor(&f, a);
        tri[m] = add_v(P, a);
    }
    for (int m = 0; m < n; m++) {
        q_orient3d(P, tri[0], tri[1], tri[2], ids[m]);
        q_cmp(P, ids[m], ids[(m + 1) % n], (int)rnd_range(0, 2));
        q_same(P, ids[m], ids[(m + 1) % n]);
        q_orient2d(P, ids[m], ids[(m + 1) % n], ids[(m + 2) % n], (int)rnd_range(0, 2));
        q_coords(P, ids[m]);
    }
}

/* One anchor, built in every way (and with W flipped): all the same point. */
static void sc_same(pool *P, int extreme)
{
    frame f = rnd_frame(extreme);
    int64_t c[3], ids[16]; /* 5 kinds x 2, and 4 flipped */
    int n = 0;
    rnd_anchor(&f, c);
    for (int kind = 0; kind < 5; kind++)
        for (int rep = 0; rep < 2; rep++) {
            int64_t i = rep_at(P, &f, c, kind, (int)rnd_range(0, 2));
            if (i < 0)
                continue;
            ids[n++] = i;
            if (rep == 1 && kind != ARR_EXPLICIT) {
                int64_t j = rep_flipped(P, i);
                if (j >= 0)
                    ids[n++] = j;
            }
        }
    for (int a = 0; a < n; a++)
        q_coords(P, ids[a]);
    expect_degenerate = 1;
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n; b++) {
            q_same(P, ids[a], ids[b]);
            q_cmp(P, ids[a], ids[b], (int)rnd_range(0, 2));
        }
    /* A plane through c (not through any construction vertex): every rep is on it. */
    int64_t t[3];
    if (tri_through(P, &f, c, t))
        for (int a = 0; a < n; a++)
            q_orient3d(P, t[0], t[1], t[2], ids[a]);
    /* Three reps of c: coincident, so collinear in every view. */
    for (int a = 0; a + 2 < n; a += 3)
        q_orient2d(P, ids[a], ids[a + 1], ids[a + 2], (int)rnd_range(0, 2));
    expect_degenerate = 0;
}

/* Three anchors on a line (or on a line of one projection only, offset along axis),
 * optionally nudged: orient2d of their reps. */
static void sc_collinear(pool *P, int extreme, int nudge)
{
    frame f = rnd_frame(extreme);
    int64_t c1[3], d[3], c2[3], c3[3];
    rnd_anchor(&f, c1);
    rnd_vec(&f, d);
    int64_t k2 = rnd_nonzero(-2, 2), k3;
    do
        k3 = rnd_nonzero(-3, 3);
    while (k3 == k2);
    if (!lin(c1, k2, d, c2) || !lin(c1, k3, d, c3))
        return;
    int axis = (int)rnd_range(0, 2);
    int projected_only = (rng_next() % 3) == 0;
    if (projected_only) { /* move c3 along the dropped axis: collinear in this view */
        int64_t e[3] = {0, 0, 0};
        e[axis] = rnd_nonzero(-8, 8) * f.unit;
        if (!lin(c3, 1, e, c3))
            return;
    }
    int64_t ids[3];
    const int64_t *cs[3] = {c1, c2, c3};
    for (int m = 0; m < 3; m++) {
        int kind = rnd_kind();
        ids[m] = nudge && m == 2 ? rep_near(P, &f, cs[m], kind, (int)rnd_range(0, 2))
                                 : rep_at(P, &f, cs[m], kind, (int)rnd_range(0, 2));
        if (ids[m] < 0)
            return;
    }
    expect_degenerate = !nudge;
    q_orient2d(P, ids[0], ids[1], ids[2], axis);
    q_orient2d(P, ids[1], ids[2], ids[0], axis);
    q_orient2d(P, ids[1], ids[0], ids[2], axis);
    if (!projected_only)
        q_orient2d(P, ids[0], ids[1], ids[2], (axis + 1) % 3);
    expect_degenerate = 0;
}

/* Three TPIs on a line (the degree-20 case), optionally one nudged. */
static void sc_collinear_tpi(pool *P, int extreme, int nudge)
{
    frame f = rnd_frame(extreme);
    int64_t c1[3], d[3], c2[3], c3[3];
    rnd_anchor(&f, c1);
    rnd_vec(&f, d);
    if (!lin(c1, 1, d, c2) || !lin(c1, -2, d, c3))
        return;
    int64_t a = rep_at(P, &f, c1, ARR_TPI, 0), b = rep_at(P, &f, c2, ARR_TPI, 0);
    int64_t c = nudge ? rep_near(P, &f, c3, ARR_TPI, 0) : rep_at(P, &f, c3, ARR_TPI, 0);
    if (a < 0 || b < 0 || c < 0)
        return;
    int axis = (int)rnd_range(0, 2);
    expect_degenerate = !nudge;
    q_orient2d(P, a, b, c, axis);
    q_orient2d(P, c, a, b, axis);
    expect_degenerate = 0;
}

/* A plane of three explicit vertices and an anchor in it, optionally nudged: orient3d
 * of its reps (in several vertex orders of the plane). */
static void sc_coplanar(pool *P, int extreme, int nudge)
{
    frame f = rnd_frame(extreme);
    int64_t A[3], u[3], v[3], B[3], C[3], c[3], w[3];
    rnd_anchor(&f, A);
    rnd_vec(&f, u);
    rnd_vec(&f, v);
    int64_t a = rnd_nonzero(-3, 3), b = rnd_nonzero(-3, 3);
    if (!lin(A, 1, u, B) || !lin(A, 1, v, C) || !lin(A, a, u, w) || !lin(w, b, v, c))
        return;
    int64_t ta = add_v(P, A), tb = add_v(P, B), tc = add_v(P, C);
    for (int t = 0; t < 3; t++) {
        int kind = rnd_kind(), axis = (int)rnd_range(0, 2);
        int64_t q = nudge ? rep_near(P, &f, c, kind, axis) : rep_at(P, &f, c, kind, axis);
        if (q < 0)
            continue;
        expect_degenerate = !nudge;
        q_orient3d(P, ta, tb, tc, q);
        q_orient3d(P, tb, ta, tc, q);
        q_orient3d(P, tc, ta, tb, q);
        expect_degenerate = 0;
    }
}

/* Points on a plane or line by construction (the shortcuts) and the same relations
 * through other vertices (no shortcut): all zero. */
static void sc_shortcuts(pool *P, int extreme)
{
    frame f = rnd_frame(extreme);
    int64_t i = rep_random(P, &f, ARR_LPI, 0), j = rep_random(P, &f, ARR_TPI, 0);
    int64_t k = rep_random(P, &f, ARR_SSI, (int)rnd_range(0, 2));
    int64_t l = rep_random(P, &f, ARR_LIFT, (int)rnd_range(0, 2));
    expect_degenerate = 1;
    if (i >= 0) {
        const int64_t *v = P->pts[i].v;
        q_orient3d(P, v[2], v[3], v[4], i);
        q_orient3d(P, v[4], v[3], v[2], i);
        q_orient3d(P, v[1], v[3], v[0], i); /* a plane through its line */
        int64_t e0 = add_pt(P, ARR_EXPLICIT, 0, &v[0], NULL);
        int64_t e1 = add_pt(P, ARR_EXPLICIT, 0, &v[1], NULL);
        int64_t e0b = add_pt(P, ARR_EXPLICIT, 0, &v[0], NULL); /* same vertex again */
        for (int ax = 0; ax < 3; ax++) {
            q_orient2d(P, e0, e1, i, ax);
            q_orient2d(P, e0, e0b, i, ax);
        }
        q_same(P, e0, e0b);
        q_orient2d(P, i, i, e1, 0);
    }
    if (j >= 0)
        for (int m = 0; m < 3; m++) {
            const int64_t *v = P->pts[j].v + 3 * m;
            q_orient3d(P, v[1], v[2], v[0], j);
        }
    if (k >= 0) {
        const int64_t *v = P->pts[k].v;
        int64_t e[4];
        for (int m = 0; m < 4; m++)
            e[m] = add_pt(P, ARR_EXPLICIT, 0, &v[m], NULL);
        q_orient2d(P, e[0], e[1], k, (int)rnd_range(0, 2));
        q_orient3d(P, v[0], v[2], v[1], k); /* a plane through its first line */
        q_orient2d(P, e[2], e[3], k, P->pts[k].axis); /* second segment, own view */
        expect_degenerate = 0;
        q_orient2d(P, e[2], e[3], k, (P->pts[k].axis + 1) % 3); /* not a shortcut */
        expect_degenerate = 1;
    }
    if (l >= 0) {
        const int64_t *v = P->pts[l].v;
        q_orient3d(P, v[0], v[1], v[2], l);
    }
    expect_degenerate = 0;
}

/* Degenerate constructions: prepare must refuse exactly those with W = 0 (add_pt
 * checks against the reference). */
static void sc_invalid(pool *P, int extreme)
{
    frame f = rnd_frame(extreme);
    int64_t c[3], w[3], z[3], A[3], Z[3], v[9];
    rnd_anchor(&f, c);
    rnd_vec(&f, w);
    if (!lin(c, 1, w, A))
        return;
    int64_t ic = add_v(P, c), iw = add_v(P, A);
    /* TPI: three planes through the line c + t w. */
    for (int m = 0; m < 3; m++) {
        rnd_vec(&f, z);
        if (!lin(c, 1, z, Z))
            return;
        v[3 * m] = ic;
        v[3 * m + 1] = iw;
        v[3 * m + 2] = add_v(P, Z);
    }
    add_pt(P, ARR_TPI, 0, v, NULL);
    /* LPI: the line O, O + w parallel to the plane c, c + w, Z. */
    int64_t O[3], Ow[3];
    rnd_vec(&f, z);
    if (lin(c, 2, z, O) && lin(O, 1, w, Ow)) {
        int64_t l[5] = {add_v(P, O), add_v(P, Ow), ic, iw, v[2]};
        add_pt(P, ARR_LPI, 0, l, NULL);
    }
    /* SSI: the segments c, c + w and Z, Z + 2 w are parallel in every view. */
    int axis = (int)rnd_range(0, 2);
    int64_t Z2[3];
    if (lin(Z, 2, w, Z2)) {
        int64_t sv[4] = {ic, iw, v[8], add_v(P, Z2)};
        add_pt(P, ARR_SSI, axis, sv, NULL);
    }
    /* LIFT: a plane that contains the axis direction (n_axis = 0). */
    int64_t e[3] = {0, 0, 0}, ce[3];
    e[axis] = rnd_nonzero(-4, 4) * f.unit;
    if (lin(c, 1, e, ce)) {
        int64_t t[3] = {ic, iw, add_v(P, ce)};
        int64_t lift[2] = {c[(axis + 1) % 3], c[(axis + 2) % 3]};
        add_pt(P, ARR_LIFT, axis, t, lift);
    }
}

/* ---- Modes --------------------------------------------------------------------------- */

static pool the_pool;

/* Expansion primitives on values with a known exact sum. */
static void test_expansion_primitives(void)
{
    int bad = 0;
    for (int t = 0; t < 20000; t++) {
        double a = ldexp((double)rnd_range(-(1LL << 52), 1LL << 52), (int)rnd_range(-60, 10));
        double b = ldexp((double)rnd_range(-(1LL << 52), 1LL << 52), (int)rnd_range(-60, 10));
        double e[2], f[2], h[8], g[8], s1[8], s2[8];
        int ne = expn_diff(a, b, e), nf = expn_product(a, b, f);
        /* (a - b) + ab - ab = a - b: sum then difference. */
        int nh = expn_sum(ne, e, nf, f, h);
        int ng = expn_diff_expansions(nh, h, nf, f, g);
        ng = expn_compress(ng, g);
        double z[8];
        bad += expn_sign(expn_diff_expansions(ng, g, ne, e, z), z) != 0;
        bad += ng > 2 || g[ng - 1] != e[ne - 1]; /* compressed: the top is a - b rounded */
        /* (a - b)(a - b) against a^2 - 2ab + b^2 built from products. */
        double sq[8], a2[2], b2[2], ab2[2], t1[8], t2[8];
        int nsq = expn_mul(ne, e, ne, e, sq, s1, s2);
        int na2 = expn_product(a, a, a2), nb2 = expn_product(b, b, b2);
        int nab = expn_product(2.0 * a, b, ab2);
        int n1 = expn_sum(na2, a2, nb2, b2, t1);
        int n2 = expn_diff_expansions(n1, t1, nab, ab2, t2);
        int nd = expn_diff_expansions(nsq, sq, n2, t2, h);
        bad += expn_sign(nd, h) != 0;
        bad += expn_sign(expn_compress(nsq, sq), sq) != (a != b);
        /* grow by one double = sum with a one-component expansion. */
        double gw[4], gs[4], gd[8];
        int ngw = expn_grow(ne, e, b, gw), ngs = expn_sum(ne, e, 1, &b, gs);
        bad += expn_sign(expn_diff_expansions(ngw, gw, ngs, gs, gd), gd) != 0;
        bad += expn_sign(expn_diff(a, 0.0, gd), gd) != (a > 0) - (a < 0);
    }
    CHECK_EQ_INT(bad, 0);
}

/* prepare, exact coordinates (value, degree) and the filter's bounds, per kind. */
static void mode_points(int ncases)
{
    pool *P = &the_pool;
    long checked = 0, bound_bad = 0, value_bad = 0, degree_bad = 0, refused = 0;
    for (int t = 0; t < ncases; t++) {
        pool_reset(P);
        P->with_ref = 1;
        frame f = rnd_frame(t % 4 == 0);
        int64_t c[3];
        rnd_anchor(&f, c);
        int kind = t % 5, axis = (int)rnd_range(0, 2);
        int64_t i = (t / 5) % 3 == 0 ? rep_at(P, &f, c, kind, axis)
                                     : (t / 5) % 3 == 1 ? rep_random(P, &f, kind, axis)
                                                        : rep_near(P, &f, c, kind, axis);
        if (i < 0) {
            refused++;
            continue;
        }
        checked++;
        arr_exact ex;
        CHECK(arr_point_exact(P->xyz, &P->pts[i], &ex) == 1);
        const bpt *r = &P->ref[i];
        for (int k = 0; k < 4; k++) {
            int deg = k < 3 ? DEG_X[kind] : DEG_X[kind] - 1;
            /* The expansion's components are multiples of 2^(-50 deg) (the degree), and
             * their sum is the reference value. */
            big sum = big_i64(0);
            int ok = 1;
            for (int m = 0; m < ex.n[k]; m++)
                sum = big_add(sum, big_from_scaled_double(ex.c[k][m], 50 * deg, &ok));
            degree_bad += !ok;
            const big *want = k < 3 ? &r->X[k] : &r->W;
            value_bad += !big_eq(sum, *want);
            /* |h - exact| <= herr: h is a multiple of the grid too; herr rounded up. */
            int okh = 1;
            big hb = big_from_scaled_double(P->pts[i].h[k], 50 * deg, &okh);
            degree_bad += !okh;
            big diff = big_sub(hb, *want);
            diff.neg = 0;
            double eb = ceil(ldexp(P->pts[i].herr[k], 50 * deg));
            int oke = 1;
            big ebig = big_from_scaled_double(eb, 0, &oke);
            bound_bad += !oke || big_mag_cmp(&diff, &ebig) > 0;
        }
        /* The sign of h[3] is W's. */
        CHECK_EQ_INT((P->pts[i].h[3] > 0) - (P->pts[i].h[3] < 0), big_sign(r->W));
    }
    printf("points: %ld checked (%ld refused as degenerate), exact value wrong %ld, "
           "off the degree's grid %ld, h outside herr %ld\n",
           checked, refused, value_bad, degree_bad, bound_bad);
    CHECK_EQ_INT(value_bad, 0);
    CHECK_EQ_INT(degree_bad, 0);
    CHECK_EQ_INT(bound_bad, 0);
    CHECK(checked > ncases / 2);
    /* The predicates' degrees (implicit.h): the largest is orient2d of three TPIs, 20,
     * within the 21 the grid allows (2^-1050 > 2^-1074). */
    int maxdeg = 0;
    for (int a = 0; a < 5; a++)
        for (int b = 0; b < 5; b++)
            for (int c = 0; c < 5; c++) {
                int d2 = DEG_X[a] + DEG_X[b] + DEG_X[c] - 1;
                maxdeg = d2 > maxdeg ? d2 : maxdeg;
            }
    CHECK_EQ_INT(maxdeg, 20);
    CHECK_EQ_INT(2 + DEG_X[ARR_TPI], 9);
    CHECK_EQ_INT(DEG_X[ARR_TPI] + DEG_X[ARR_TPI] - 1, 13);
    CHECK(50 * maxdeg <= 1074 - 53);
    test_expansion_primitives();
}

static void run_scenarios(int ncases, int near_only)
{
    pool *P = &the_pool;
    for (int t = 0; t < ncases; t++) {
        pool_reset(P);
        P->with_ref = dump_out == NULL;
        int extreme = t % 5 == 0;
        if (near_only) {
            switch (t % 3) {
            case 0:
                sc_collinear(P, extreme, 1);
                break;
            case 1:
                sc_coplanar(P, extreme, 1);
                break;
            default:
                sc_collinear_tpi(P, extreme, 1);
                break;
            }
            continue;
        }
        switch (t % 9) {
        case 0:
            sc_random(P, extreme);
            break;
        case 1:
            sc_same(P, extreme);
            break;
        case 2:
            sc_collinear(P, extreme, 0);
            break;
        case 3:
            sc_coplanar(P, extreme, 0);
            break;
        case 4:
            sc_shortcuts(P, extreme);
            break;
        case 5:
            sc_invalid(P, extreme);
            break;
        case 6:
            sc_collinear(P, extreme, 1);
            break;
        case 7:
            sc_coplanar(P, extreme, 1);
            break;
        default:
            sc_collinear_tpi(P, extreme, t % 2);
            break;
        }
    }
}

static void check_stats(const char *what, int want_exact)
{
    stats_print(what);
    printf("%s: %ld answers degenerate by construction, confirmed by the reference\n", what,
           expected_degenerate);
    CHECK_EQ_INT(st.filter_wrong, 0);
    CHECK_EQ_INT(st.exact_wrong, 0);
    CHECK_EQ_INT(st.public_wrong, 0);
    CHECK_EQ_INT(big_overflowed, 0);
    CHECK(st.queries > 0);
    if (want_exact)
        CHECK(st.filter_unsure > 0 && st.zero_answers > 0);
}

static void mode_random(int n)
{
    pool *P = &the_pool;
    for (int t = 0; t < n; t++) {
        pool_reset(P);
        P->with_ref = 1;
        sc_random(P, t % 5 == 0);
    }
    /* Explicit points alone: the exact stage agrees with predicates.c. */
    long mismatch = 0;
    for (int t = 0; t < n; t++) {
        pool_reset(P);
        P->with_ref = 0;
        frame f = rnd_frame(t % 5 == 0);
        int64_t e[4];
        for (int m = 0; m < 4; m++) {
            int64_t a[3];
            rnd_anchor(&f, a);
            int64_t v = add_v(P, a);
            e[m] = add_pt(P, ARR_EXPLICIT, 0, &v, NULL);
        }
        arr_points V = view(P);
        const double *x = P->xyz;
        int axis = t % 3, i = (axis + 1) % 3, j = (axis + 2) % 3;
        mismatch += arr_orient3d_exact(&V, 0, 1, 2, e[3]) != mfg_orient3d(x, x + 3, x + 6, x + 9);
        mismatch += arr_orient2d_exact(&V, e[0], e[1], e[2], axis) !=
                    mfg_orient2d(x[i], x[j], x[3 + i], x[3 + j], x[6 + i], x[6 + j]);
    }
    CHECK_EQ_INT(mismatch, 0);
    check_stats("random", 0);
    /* General position: the filter decides nearly everything. */
    CHECK(st.filter_decided > 2 * st.filter_unsure);
}

static void mode_degenerate(int n)
{
    pool *P = &the_pool;
    for (int t = 0; t < n; t++) {
        pool_reset(P);
        P->with_ref = 1;
        switch (t % 5) {
        case 0:
            sc_same(P, t % 10 == 0);
            break;
        case 1:
            sc_collinear(P, t % 10 == 1, 0);
            break;
        case 2:
            sc_coplanar(P, t % 10 == 2, 0);
            break;
        case 3:
            sc_shortcuts(P, t % 10 == 3);
            break;
        default:
            sc_invalid(P, t % 10 == 4);
            sc_collinear_tpi(P, t % 10 == 4, 0);
            break;
        }
    }
    check_stats("degenerate", 1);
}

static void mode_near(int n)
{
    run_scenarios(n, 1);
    check_stats("near", 1);
}

static void mode_extremes(int n)
{
    pool *P = &the_pool;
    /* Every scenario against the box corners, and the finest steps in the middle. */
    for (int t = 0; t < n; t++) {
        pool_reset(P);
        P->with_ref = 1;
        switch (t % 6) {
        case 0:
            sc_same(P, 1);
            break;
        case 1:
            sc_collinear(P, 1, t % 4 == 1);
            break;
        case 2:
            sc_coplanar(P, 1, t % 4 == 2);
            break;
        case 3:
            sc_collinear_tpi(P, 1, t % 4 == 3);
            break;
        case 4:
            sc_random(P, 1);
            break;
        default:
            sc_invalid(P, 1);
            break;
        }
    }
    /* Hand-made corners: the box's extreme vertices, steps of 2^-49 there (the grid's
     * representable step beyond 8) and a TPI at a corner made of tiny triangles. */
    pool_reset(P);
    P->with_ref = 1;
    int64_t M = UNITS_MAX, s = 2;
    int64_t c[3] = {M - 8 * s, -M + 8 * s, M - 8 * s};
    frame f = make_frame(-49, 2, 1);
    for (int kind = 0; kind < 5; kind++) {
        int64_t a = rep_at(P, &f, c, kind, kind % 3), b = rep_near(P, &f, c, kind, kind % 3);
        if (a >= 0 && b >= 0) {
            q_same(P, a, b);
            for (int ax = 0; ax < 3; ax++)
                q_cmp(P, a, b, ax);
            q_coords(P, a);
            q_coords(P, b);
        }
    }
    int64_t big_tri[3][3] = {{M, M, M}, {-M, M, -M}, {M, -M, -M}};
    int64_t t0 = add_v(P, big_tri[0]), t1 = add_v(P, big_tri[1]), t2 = add_v(P, big_tri[2]);
    for (int64_t q = 0; q < P->np; q++)
        q_orient3d(P, t0, t1, t2, q);
    check_stats("extremes", 1);
}

static void mode_coords(int n)
{
    pool *P = &the_pool;
    for (int t = 0; t < n; t++) {
        pool_reset(P);
        P->with_ref = 1;
        frame f = rnd_frame(t % 5 == 0);
        int64_t c[3];
        rnd_anchor(&f, c);
        int kind = 1 + t % 4;
        int64_t i = (t / 4) % 2 ? rep_random(P, &f, kind, (int)rnd_range(0, 2))
                                : rep_near(P, &f, c, kind, (int)rnd_range(0, 2));
        if (i >= 0)
            q_coords(P, i);
        int64_t j = rep_at(P, &f, c, kind, (int)rnd_range(0, 2));
        if (j >= 0) {
            arr_points V = view(P);
            double out[3];
            arr_coords(&V, j, out);
            /* A point on the grid comes back exactly. */
            CHECK(out[0] == (double)c[0] / UNITS_PER_ONE &&
                  out[1] == (double)c[1] / UNITS_PER_ONE && out[2] == (double)c[2] / UNITS_PER_ONE);
        }
    }
    printf("coords: %ld coordinates, %ld exact, %ld beyond 2 ulps\n", coords_checked,
           coords_exact_hits, coords_bad);
    CHECK_EQ_INT(coords_bad, 0);
    CHECK(coords_checked > 0);
}

/* Inputs off the grid: prepare refuses, a predicate answers without a crash. */
static void mode_offgrid(void)
{
    pool *P = &the_pool;
    pool_reset(P);
    P->with_ref = 0;
    frame f = make_frame(-20, 10, 0);
    for (int m = 0; m < 12; m++) {
        int64_t u[3];
        rnd_anchor(&f, u);
        add_v(P, u);
    }
    int64_t v[9] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
    int64_t good = add_pt(P, ARR_TPI, 0, v, NULL);
    CHECK(good >= 0);
    double bad[5] = {0x1p-51, 16.5, NAN, INFINITY, 1.0 + 0x1p-52};
    for (int b = 0; b < 5; b++) {
        P->xyz[3 * 9] = bad[b];
        int64_t w[9] = {9, 1, 2, 3, 4, 5, 6, 7, 8};
        arr_point p;
        memset(&p, 0, sizeof p);
        p.kind = ARR_TPI;
        memcpy(p.v, w, sizeof w);
        CHECK_EQ_INT(arr_point_prepare(P->xyz, &p), 0);
        arr_exact ex;
        CHECK_EQ_INT(arr_point_exact(P->xyz, &p, &ex), 0);
        /* A triangle with the bad vertex against the good point: no crash, and the
         * exact stage says it cannot run. */
        arr_points V = view(P);
        int s = arr_orient3d(&V, 9, 1, 2, good);
        CHECK(s >= -1 && s <= 1);
        CHECK_EQ_INT(arr_orient3d_exact(&V, 9, 1, 2, good), ARR_NOT_EXACT);
    }
    arr_point p;
    memset(&p, 0, sizeof p);
    p.kind = 7;
    CHECK_EQ_INT(arr_point_prepare(P->xyz, &p), 0);
    p.kind = ARR_SSI;
    p.axis = 3;
    CHECK_EQ_INT(arr_point_prepare(P->xyz, &p), 0);
    printf("offgrid: refused and answered without a crash\n");
}

/* ---- Bench ------------------------------------------------------------------------- */

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static volatile int bench_sink;

/* The points of the bench: 64 of each kind in general position, and a triangle. */
typedef struct bench_set {
    int64_t ids[5][64];
    int64_t tri[3];
} bench_set;

/* One timed loop of reps calls of predicate `what` on points of `kind`; ns per call. */
static double bench_once(pool *P, const bench_set *B, int kind, int what, int reps)
{
    arr_points V = view(P);
    const int64_t *id = B->ids[kind];
    int acc = 0;
    double out[3];
    double t0 = now_ns();
    for (int r = 0; r < reps; r++) {
        int64_t a = id[r & 63], b = id[(r + 1) & 63], c = id[(r + 2) & 63];
        switch (what) {
        case 0: {
            arr_point p = P->pts[a];
            acc += arr_point_prepare(P->xyz, &p);
            break;
        }
        case 1:
            acc += arr_orient3d(&V, B->tri[0], B->tri[1], B->tri[2], a);
            break;
        case 2:
            acc += arr_orient2d(&V, a, b, c, r % 3);
            break;
        case 3:
            acc += arr_cmp(&V, a, id[(r + 7) & 63], r % 3);
            break;
        case 4:
            acc += arr_same(&V, a, id[(r + 7) & 63]);
            break;
        case 5:
            acc += arr_orient3d_exact(&V, B->tri[0], B->tri[1], B->tri[2], a);
            break;
        case 6:
            acc += arr_orient2d_exact(&V, a, b, c, r % 3);
            break;
        case 7:
            acc += arr_same_exact(&V, a, id[(r + 7) & 63]);
            break;
        default:
            arr_coords(&V, a, out);
            acc += out[0] > 0;
            break;
        }
    }
    bench_sink += acc;
    return (now_ns() - t0) / reps;
}

/* The best of five runs: the machine may be busy with other work. */
static double bench_best(pool *P, const bench_set *B, int kind, int what, int reps)
{
    double best = 1e300;
    for (int k = 0; k < 5; k++) {
        double t = bench_once(P, B, kind, what, reps);
        best = t < best ? t : best;
    }
    return best;
}

static void mode_bench(int reps)
{
    pool *P = &the_pool;
    static bench_set B;
    pool_reset(P);
    P->with_ref = 0;
    frame f = make_frame(-20, 18, 0);
    for (int kind = 0; kind < 5; kind++)
        for (int n = 0; n < 64;) {
            int64_t i = rep_random(P, &f, kind, (int)rnd_range(0, 2));
            if (i >= 0)
                B.ids[kind][n++] = i;
        }
    for (int m = 0; m < 3; m++) {
        int64_t a[3];
        rnd_anchor(&f, a);
        B.tri[m] = add_v(P, a);
    }
    arr_points V = view(P);
    const char *names[5] = {"explicit", "LPI", "TPI", "SSI", "LIFT"};
    /* How often the filter decides on these points (general position: nearly all). */
    long decided = 0, total = 0;
    for (int kind = 0; kind < 5; kind++)
        for (int r = 0; r < 64; r++) {
            const int64_t *id = B.ids[kind];
            decided += arr_orient3d_filter(&V, B.tri[0], B.tri[1], B.tri[2], id[r]) != 0;
            decided += arr_orient2d_filter(&V, id[r], id[(r + 1) & 63], id[(r + 2) & 63],
                                           r % 3) != 0;
            decided += arr_cmp_filter(&V, id[r], id[(r + 7) & 63], r % 3) != 0;
            total += 3;
        }
    printf("bench: the filter decides %ld of %ld calls on these points\n", decided, total);
    printf("bench (ns per call, best of 5 runs of %d; explicit triples go to predicates.c):\n",
           reps);
    for (int kind = 0; kind < 5; kind++)
        printf("  %-8s prepare %6.1f  orient3d %6.1f  orient2d %6.1f  cmp %6.1f  same %6.1f\n",
               names[kind], bench_best(P, &B, kind, 0, reps), bench_best(P, &B, kind, 1, reps),
               bench_best(P, &B, kind, 2, reps), bench_best(P, &B, kind, 3, reps),
               bench_best(P, &B, kind, 4, reps));
    int xr = reps / 50 > 10 ? reps / 50 : 10;
    printf("bench (us per call, the exact stage alone, best of 5 runs of %d):\n", xr);
    for (int kind = 0; kind < 5; kind++)
        printf("  %-8s orient3d %7.2f  orient2d %7.2f  same %7.2f  arr_coords %7.2f\n",
               names[kind], bench_best(P, &B, kind, 5, xr) / 1e3,
               bench_best(P, &B, kind, 6, xr) / 1e3, bench_best(P, &B, kind, 7, xr) / 1e3,
               bench_best(P, &B, kind, 8, xr) / 1e3);
    CHECK(decided > total * 9 / 10);
}

/* ---- Main -------------------------------------------------------------------------- */

int main(int argc, char **argv)
{
    const char *mode = argc > 1 ? argv[1] : "points";
    long n = argc > 2 ? atol(argv[2]) : 0;
    if (!strcmp(mode, "dump")) {
        dump_out = stdout;
        the_pool.with_ref = 0;
        run_scenarios(n > 0 ? (int)n : 900, 0);
        return 0;
    }
    if (!strcmp(mode, "points"))
        mode_points(n > 0 ? (int)n : 30000 / CASE_DIVISOR);
    else if (!strcmp(mode, "random"))
        mode_random(n > 0 ? (int)n : 20000 / CASE_DIVISOR);
    else if (!strcmp(mode, "degenerate"))
        mode_degenerate(n > 0 ? (int)n : 20000 / CASE_DIVISOR);
    else if (!strcmp(mode, "near"))
        mode_near(n > 0 ? (int)n : 60000 / CASE_DIVISOR);
    else if (!strcmp(mode, "extremes"))
        mode_extremes(n > 0 ? (int)n : 6000 / CASE_DIVISOR);
    else if (!strcmp(mode, "coords"))
        mode_coords(n > 0 ? (int)n : 20000 / CASE_DIVISOR);
    else if (!strcmp(mode, "offgrid"))
        mode_offgrid();
    else if (!strcmp(mode, "bench"))
        mode_bench(n > 0 ? (int)n : 200000 / CASE_DIVISOR);
    else {
        fprintf(stderr, "unknown mode %s\n", mode);
        return 2;
    }
    return mfg_test_report(mode);
}
