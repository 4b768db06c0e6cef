/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* battery_checks.c - the battery's geometric checks of a sweep result: conservative (each
 * sampled point of the input surface, turned by every t in [0, angle], stays inside or on
 * the result: the arc is cut where it crosses the result's surface and each piece is
 * classified, pieces running along the surface by branch and bound with the Lipschitz
 * bound of a distance in t) and tight (every sampled result point within the tolerance of
 * SV: a branch and bound for min over t of the distance of the point turned back to the
 * input, which changes by at most r dt). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "battery.h"
#include "sweep_checks.h"

/* conservative: where in a piece between crossings its side is looked for (the middle
 * first; the others in case that one sits on the surface, at a tangency or an edge) */
static const double PIECE_AT[] = {0.5, 0.381966, 0.618034, 0.236068};
#define PIECE_TRIES ((int)(sizeof PIECE_AT / sizeof PIECE_AT[0]))
/* tight: the first spans of [0, angle] before any refinement */
#define TIGHT_FIRST_SPANS 8
/* a result triangle counts as a cap (a plane perpendicular to the axis, along which a
 * turned point may run on the surface for a long arc) when its normal leans from the axis
 * by at most this sine; beyond, the arc leaves its plane by more than eps anyway */
#define CAP_MAX_SINE 1e-6
/* crossings of the arc with a cap triangle's edges closer than this (radians) to the
 * sample itself are the edge it sits on, not an exit */
#define CAP_SAME_ANGLE 1e-13

/* ------------------------------------------------------------------------ */
/* A binary heap of spans [a, b] between two samples, largest key on top      */
/* ------------------------------------------------------------------------ */

typedef struct span {
    double key;
    int a, b; /* sample indices */
} span;

typedef struct heap {
    span *s;
    int n;
} heap;

static void heap_push(heap *h, span x)
{
    int i = h->n++;
    while (i > 0 && h->s[(i - 1) / 2].key < x.key) {
        h->s[i] = h->s[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->s[i] = x;
}

static span heap_pop(heap *h)
{
    span top = h->s[0], last = h->s[--h->n];
    int i = 0;
    for (;;) {
        int c = 2 * i + 1;
        if (c >= h->n)
            break;
        if (c + 1 < h->n && h->s[c + 1].key > h->s[c].key)
            c++;
        if (h->s[c].key <= last.key)
            break;
        h->s[i] = h->s[c];
        i = c;
    }
    if (h->n)
        h->s[i] = last;
    return top;
}

/* ------------------------------------------------------------------------ */
/* Points on a mesh                                                         */
/* ------------------------------------------------------------------------ */

/* A point of triangle t: kind 0 its corner k, 1 a point of its side k, 2 inside. */
static void surface_point(const double *V, const int64_t *T, int64_t t, int kind, bt_rng *r, double p[3])
{
    int k = (int)bt_int(r, 0, 2);
    const double *a = V + 3 * T[3 * t + k], *b = V + 3 * T[3 * t + (k + 1) % 3], *c = V + 3 * T[3 * t + (k + 2) % 3];
    double s = bt_unif(r, 0, 1), w = bt_unif(r, 0, 1);
    if (kind == 0) {
        memcpy(p, a, 3 * sizeof *p);
    } else if (kind == 1) {
        for (int i = 0; i < 3; i++)
            p[i] = a[i] + s * (b[i] - a[i]);
    } else { /* uniform on the triangle */
        double q = sqrt(s);
        for (int i = 0; i < 3; i++)
            p[i] = (1 - q) * a[i] + q * (1 - w) * b[i] + q * w * c[i];
    }
}

double bt_allowance(const bt_problem *p)
{
    double u[3], rmax = 0;
    unit3(p->ad, u);
    for (int64_t i = 0; i < p->in.nv; i++)
        rmax = fmax(rmax, dist_to_axis(p->ap, u, p->in.xyz + 3 * i));
    return BT_EPS_REL * (p->size + rmax);
}

/* ------------------------------------------------------------------------ */
/* Conservative                                                             */
/* ------------------------------------------------------------------------ */

typedef struct sample {
    double t, f;          /* f: signed distance to the result, > 0 outside */
    double cap_lo, cap_hi; /* the arc is on the cap triangle holding this sample over this range */
} sample;

typedef struct arc {
    const bt_index *res;
    const double *ap, *u;
    double p[3], foot[3], e1[3], e2[3], r, eps;
    long *unsure;
} arc;

static int in_tri2(const double x[2], const double X[3][2], double orient)
{
    for (int k = 0; k < 3; k++) {
        const double *a = X[k], *b = X[(k + 1) % 3];
        double o = (b[0] - a[0]) * (x[1] - a[1]) - (b[1] - a[1]) * (x[0] - a[0]);
        if (o * orient < 0)
            return 0;
    }
    return 1;
}

/* The range of t about the sample s over which the arc stays on result triangle tri, when
 * that triangle is a cap (its plane perpendicular to the axis to CAP_MAX_SINE, the arc in
 * it to eps): the arc in the triangle's plane is the circle of radius r about the axis,
 * its exits are where it crosses the triangle's sides.  Widens [s->cap_lo, s->cap_hi]. */
static void cap_range(const arc *A, int64_t tri, sample *s)
{
    const double *V = A->res->V;
    const int64_t *v = A->res->T + 3 * tri;
    double n[3], e1[3], e2[3], x[3];
    for (int c = 0; c < 3; c++) {
        e1[c] = V[3 * v[1] + c] - V[3 * v[0] + c];
        e2[c] = V[3 * v[2] + c] - V[3 * v[0] + c];
    }
    cross3(e1, e2, n);
    cross3(n, A->u, x);
    double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]), lean = sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    if (!(nn > 0) || lean > CAP_MAX_SINE * nn || fabs(s->f) + 2 * A->r * lean / nn > A->eps)
        return;
    double X[3][2];
    for (int k = 0; k < 3; k++) {
        double d[3];
        for (int c = 0; c < 3; c++)
            d[c] = V[3 * v[k] + c] - A->foot[c];
        X[k][0] = d[0] * A->e1[0] + d[1] * A->e1[1] + d[2] * A->e1[2];
        X[k][1] = d[0] * A->e2[0] + d[1] * A->e2[1] + d[2] * A->e2[2];
    }
    double orient = (X[1][0] - X[0][0]) * (X[2][1] - X[0][1]) - (X[1][1] - X[0][1]) * (X[2][0] - X[0][0]);
    /* the crossings of the circle with the sides, as angles after s->t in (0, 2 pi) */
    double fwd = INFINITY, back = INFINITY;
    int crossings = 0;
    for (int k = 0; k < 3; k++) {
        const double *a = X[k], *b = X[(k + 1) % 3];
        double D[2] = {b[0] - a[0], b[1] - a[1]};
        double qa = D[0] * D[0] + D[1] * D[1], qb = 2 * (a[0] * D[0] + a[1] * D[1]),
               qc = a[0] * a[0] + a[1] * a[1] - A->r * A->r, disc = qb * qb - 4 * qa * qc;
        if (!(qa > 0) || disc < 0)
            continue;
        for (int sg = -1; sg <= 1; sg += 2) {
            double w = (-qb + sg * sqrt(disc)) / (2 * qa);
            if (w < 0 || w > 1)
                continue;
            double phi = atan2(a[1] + w * D[1], a[0] + w * D[0]) - s->t;
            phi = fmod(phi, 2 * M_PI);
            if (phi < 0)
                phi += 2 * M_PI;
            crossings++;
            if (phi > CAP_SAME_ANGLE && phi < 2 * M_PI - CAP_SAME_ANGLE) {
                fwd = fmin(fwd, phi);
                back = fmin(back, 2 * M_PI - phi);
            }
        }
    }
    if (!crossings) { /* the whole circle in the triangle, or none of it */
        double at[2] = {A->r * cos(s->t), A->r * sin(s->t)};
        if (in_tri2(at, X, orient)) {
            s->cap_lo = -INFINITY;
            s->cap_hi = INFINITY;
        }
        return;
    }
    /* a range counts when its middle is in the triangle (the sample may sit on a side
     * the arc leaves through) */
    if (isfinite(fwd)) {
        double m = s->t + fwd / 2, at[2] = {A->r * cos(m), A->r * sin(m)};
        if (in_tri2(at, X, orient))
            s->cap_hi = fmax(s->cap_hi, s->t + fwd);
    }
    if (isfinite(back)) {
        double m = s->t - back / 2, at[2] = {A->r * cos(m), A->r * sin(m)};
        if (in_tri2(at, X, orient))
            s->cap_lo = fmin(s->cap_lo, s->t - back);
    }
}

/* cap triangles looked at around a sample on the surface: a few meet at a vertex */
#define CAP_NEAR_MAX 64

static sample cons_eval(const arc *A, double t)
{
    sample s = {t, 0, t, t};
    double q[3];
    rotate(A->ap, A->u, t, A->p, q);
    int64_t near = -1;
    int unsure = 0;
    s.f = bt_signed(A->res, q, A->eps, &near, &unsure);
    *A->unsure += unsure;
    if (s.f <= A->eps && A->r > 0) {
        /* every triangle within eps, not only the nearest: on a cap's rim a wall is as
         * near as the cap */
        int64_t ids[CAP_NEAR_MAX];
        int n = bt_near(A->res, q, A->eps, ids, CAP_NEAR_MAX);
        for (int i = 0; i < n; i++)
            cap_range(A, ids[i], &s);
    }
    return s;
}

/* the largest value the signed distance can take between two samples (Lipschitz r) */
static double cons_key(const arc *A, const sample *a, const sample *b)
{
    return 0.5 * (a->f + b->f + A->r * (b->t - a->t));
}

enum { ARC_CHECKED, ARC_OUTSIDE, ARC_COARSE };

/* The scratch space of one arc's check. */
typedef struct arc_work {
    sample *S;     /* the branch and bound's samples */
    long nS;
    heap h;
    double *cross; /* the crossing angles */
    long ncross, cap_cross;
} arc_work;

/* Branch and bound over t in [S[0].t, S[n-1].t] from the n samples in S (in order of
 * t): the span whose bound on f is the largest is split first; a span is done when that
 * bound is at most eps (certified inside or on), when it lies on caps, or when its arc is
 * the fine step long (its ends were checked).  Spends at most `budget` queries; *used
 * gets how many, *step the longest arc left (ARC_COARSE), *bad the sample outside
 * (ARC_OUTSIDE). */
static int bnb(const arc *A, const bt_problem *pb, int n, long budget, arc_work *w, long *used, double *step,
               sample *bad)
{
    double fine = BT_FINE_ARC_TOLS * pb->tol, eps = A->eps;
    sample *S = w->S;
    long ns = n;
    int result = ARC_CHECKED;
    heap *h = &w->h;
    h->n = 0;
    for (int i = 0; i + 1 < n; i++)
        heap_push(h, (span){cons_key(A, S + i, S + i + 1), i, i + 1});
    double gap = A->r > 0 ? eps / A->r : 0; /* an angle whose arc is below eps */
    *used = 0;
    while (h->n && result == ARC_CHECKED) {
        span sp = heap_pop(h);
        if (sp.key <= eps)
            break; /* every span left is certified inside or on */
        sample *a = S + sp.a, *b = S + sp.b;
        if (a->cap_hi + gap >= b->t || b->cap_lo - gap <= a->t || a->cap_hi + gap >= b->cap_lo)
            continue; /* on caps all the way */
        if (A->r * (b->t - a->t) <= fine)
            continue; /* the fine grid's step reached */
        if (*used >= budget || ns >= w->nS) { /* budget spent: the longest span left is the step reached */
            result = ARC_COARSE;
            double longest = A->r * (b->t - a->t);
            for (int i = 0; i < h->n; i++)
                longest = fmax(longest, A->r * (S[h->s[i].b].t - S[h->s[i].a].t));
            *step = fmax(*step, longest);
            break;
        }
        /* next to a cap range's end when one ends inside the span (the next triangle:
         * about one query per cap triangle crossed), else the middle */
        double m = 0.5 * (a->t + b->t);
        if (a->cap_hi > a->t && a->cap_hi + gap < b->t)
            m = a->cap_hi + 0.5 * gap;
        else if (b->cap_lo < b->t && b->cap_lo - gap > a->t)
            m = b->cap_lo - 0.5 * gap;
        S[ns] = cons_eval(A, m);
        ++*used;
        if (S[ns].f > eps) {
            result = ARC_OUTSIDE;
            *bad = S[ns];
        }
        heap_push(h, (span){cons_key(A, a, S + ns), sp.a, (int)ns});
        heap_push(h, (span){cons_key(A, S + ns, b), (int)ns, sp.b});
        ns++;
    }
    return result;
}

/* Whether a node's box may meet the arc's circle: it reaches both sides of the circle's
 * plane, and its nearest and farthest points from the centre bracket the radius (slack:
 * the rounding of these sums, far below eps). */
static int box_meets_circle(const bt_node *n, const arc *A)
{
    double lo = 0, hi = 0, near2 = 0, far2 = 0;
    for (int c = 0; c < 3; c++) {
        double a = n->lo[c] - A->foot[c], b = n->hi[c] - A->foot[c];
        lo += A->u[c] * (A->u[c] > 0 ? a : b);
        hi += A->u[c] * (A->u[c] > 0 ? b : a);
        double near = a > 0 ? a : b < 0 ? -b : 0, far = fmax(fabs(a), fabs(b));
        near2 += near * near;
        far2 += far * far;
    }
    double slack = A->eps;
    return lo <= slack && hi >= -slack && sqrt(near2) <= A->r + slack && sqrt(far2) >= A->r - slack;
}

static void add_cross(arc_work *w, double t)
{
    if (w->ncross == w->cap_cross) {
        w->cap_cross = w->cap_cross ? 2 * w->cap_cross : 256;
        w->cross = realloc(w->cross, (size_t)w->cap_cross * sizeof *w->cross);
        if (!w->cross)
            abort(); /* the test cannot go on without memory */
    }
    w->cross[w->ncross++] = t;
}

/* The angles in (0, angle) where the arc's circle crosses triangle tri (its intersection
 * with the circle's plane, a segment, met by the circle).  A triangle in the plane (a cap)
 * gives none: the arc on it is on the surface, and its sides are where walls meet it. */
static void tri_crossings(const arc *A, int64_t tri, double angle, arc_work *w)
{
    const double *V = A->res->V;
    const int64_t *v = A->res->T + 3 * tri;
    double h[3], P[2][3];
    int sg[3], np = 0;
    for (int k = 0; k < 3; k++) {
        const double *x = V + 3 * v[k];
        h[k] = (x[0] - A->foot[0]) * A->u[0] + (x[1] - A->foot[1]) * A->u[1] + (x[2] - A->foot[2]) * A->u[2];
        sg[k] = h[k] > 0 ? 1 : h[k] < 0 ? -1 : 0;
    }
    if ((sg[0] == sg[1] && sg[1] == sg[2]))
        return; /* on one side, or in the plane */
    for (int k = 0; k < 3 && np < 2; k++) {
        int j = (k + 1) % 3;
        const double *a = V + 3 * v[k], *b = V + 3 * v[j];
        if (sg[k] == 0) {
            memcpy(P[np++], a, sizeof P[0]);
        } else if (sg[k] * sg[j] < 0) {
            double s = h[k] / (h[k] - h[j]);
            for (int c = 0; c < 3; c++)
                P[np][c] = a[c] + s * (b[c] - a[c]);
            np++;
        }
    }
    if (np < 2)
        return; /* touches the plane at one point */
    double X[2][2];
    for (int k = 0; k < 2; k++) {
        double d[3] = {P[k][0] - A->foot[0], P[k][1] - A->foot[1], P[k][2] - A->foot[2]};
        X[k][0] = d[0] * A->e1[0] + d[1] * A->e1[1] + d[2] * A->e1[2];
        X[k][1] = d[0] * A->e2[0] + d[1] * A->e2[1] + d[2] * A->e2[2];
    }
    double D[2] = {X[1][0] - X[0][0], X[1][1] - X[0][1]};
    double qa = D[0] * D[0] + D[1] * D[1], qb = 2 * (X[0][0] * D[0] + X[0][1] * D[1]),
           qc = X[0][0] * X[0][0] + X[0][1] * X[0][1] - A->r * A->r, disc = qb * qb - 4 * qa * qc;
    if (!(qa > 0) || disc < 0)
        return; /* a point, or a miss (a tangency missed by rounding only hides an excursion
                 * of depth about the square of the rounding) */
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        double s = (-qb + sgn * sqrt(disc)) / (2 * qa);
        if (s < 0 || s > 1)
            continue;
        double t = atan2(X[0][1] + s * D[1], X[0][0] + s * D[0]);
        if (t < 0)
            t += 2 * M_PI;
        if (t > 0 && t < angle)
            add_cross(w, t);
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Every crossing of the arc with the result's surface, sorted, between 0 and angle. */
static void arc_crossings(const arc *A, double angle, arc_work *w)
{
    const bt_index *ix = A->res;
    w->ncross = 0;
    add_cross(w, 0);
    int64_t stack[128]; /* the index's depth is about log2(n): far below */
    int sp = 0;
    if (ix->nnodes)
        stack[sp++] = 0;
    while (sp) {
        const bt_node *n = ix->nodes + stack[--sp];
        if (!box_meets_circle(n, A))
            continue;
        if (!n->count) {
            stack[sp++] = n->right;
            stack[sp++] = n - ix->nodes + 1;
            continue;
        }
        for (int64_t i = n->first; i < n->first + n->count; i++)
            if (!ix->flat[ix->ids[i]])
                tri_crossings(A, ix->ids[i], angle, w);
    }
    add_cross(w, angle);
    qsort(w->cross + 1, (size_t)(w->ncross - 2), sizeof *w->cross, cmp_double);
}

/* One arc: between consecutive crossings with the result's surface the arc stays on one
 * side of it (in the closed solid or in its closed complement), so one sample in the
 * middle of each piece says which: inside certifies the piece, outside by more than eps
 * is a failure, and a piece whose middle is outside by less than eps or exactly on the
 * surface gets the branch and bound.  Spends at most `budget` queries.  (A crossing
 * missed by rounding - a tangency - hides an excursion only about as deep as the square
 * of the rounding: far below eps.) */
static int run_arc(const arc *A, const bt_problem *pb, long budget, arc_work *w, long *used, double *step,
                   sample *bad)
{
    double fine = BT_FINE_ARC_TOLS * pb->tol, eps = A->eps;
    *used = 0;
    *step = 0;
    if (A->r * pb->angle <= eps) { /* the arc is a point to within eps */
        sample s = cons_eval(A, 0);
        *used = 1;
        if (s.f > eps) {
            *bad = s;
            return ARC_OUTSIDE;
        }
        return ARC_CHECKED;
    }
    arc_crossings(A, pb->angle, w);
    for (long i = 0; i + 1 < w->ncross; i++) {
        double a = w->cross[i], b = w->cross[i + 1];
        if (!(b > a))
            continue;
        if (*used >= budget) { /* the pieces left are unchecked */
            for (long j = i; j + 1 < w->ncross; j++)
                *step = fmax(*step, A->r * (w->cross[j + 1] - w->cross[j]));
            return ARC_COARSE;
        }
        /* the piece is on one side: the first sample that is clearly on one side says
         * which (a sample on the surface - a tangency, a touched edge - says nothing) */
        int side = 0; /* 1: in the closed solid */
        for (int k = 0; k < PIECE_TRIES && !side; k++) {
            sample m = cons_eval(A, a + PIECE_AT[k] * (b - a));
            ++*used;
            if (m.f > eps) {
                *bad = m;
                return ARC_OUTSIDE;
            }
            double q[3];
            rotate(A->ap, A->u, m.t, A->p, q);
            /* inside by more than eps, on a cap (whose sides are where walls meet its
             * plane: crossings), or inside exactly */
            if (m.f < -eps || m.cap_lo < m.t || m.cap_hi > m.t || bt_inside(A->res, q) == 1)
                side = 1;
            if (A->r * (b - a) <= fine)
                side = 1; /* the fine step: this sample is the grid's */
        }
        if (side)
            continue;
        /* on the surface, or outside by less than eps, wherever tried: branch and bound
         * from the piece's ends and middle */
        w->S[0] = cons_eval(A, a);
        w->S[1] = cons_eval(A, 0.5 * (a + b));
        w->S[2] = cons_eval(A, b);
        *used += 3;
        for (int k = 0; k < 3; k++)
            if (w->S[k].f > eps) {
                *bad = w->S[k];
                return ARC_OUTSIDE;
            }
        long more = 0;
        int r = bnb(A, pb, 3, budget - *used, w, &more, step, bad);
        *used += more;
        if (r == ARC_OUTSIDE)
            return r;
        if (r == ARC_COARSE) {
            for (long j = i + 1; j + 1 < w->ncross; j++)
                *step = fmax(*step, A->r * (w->cross[j + 1] - w->cross[j]));
            return r;
        }
    }
    return ARC_CHECKED;
}

static void arc_setup(arc *A, const double u[3])
{
    A->r = dist_to_axis(A->ap, u, A->p);
    double along = 0;
    for (int c = 0; c < 3; c++)
        along += (A->p[c] - A->ap[c]) * u[c];
    for (int c = 0; c < 3; c++) {
        A->foot[c] = A->ap[c] + along * u[c];
        A->e1[c] = A->r > 0 ? (A->p[c] - A->foot[c]) / A->r : 0;
    }
    cross3(u, A->e1, A->e2);
}

void bt_check_conservative(const bt_problem *pb, const bt_index *res, double eps, int npoints, long evals,
                           long evals_per_arc, uint64_t seed, bt_cons_report *out)
{
    memset(out, 0, sizeof *out);
    bt_rng rng = {seed};
    double u[3];
    unit3(pb->ad, u);
    const double *V = pb->in.xyz;
    const int64_t *T = pb->in.tri;
    arc_work w = {0};
    w.nS = evals_per_arc + 4;
    w.S = malloc((size_t)w.nS * sizeof *w.S);
    w.h.s = malloc((size_t)(2 * w.nS) * sizeof(span));
    double *points = malloc((size_t)(3 * npoints + 1) * sizeof *points);
    int ncoarse = 0;
    /* round 1: half the budget, evenly; round 2: what is left, shared by the arcs that
     * ran out (arcs running along the result's surface over long stretches) */
    long first = evals / 2 / (npoints > 0 ? npoints : 1);
    for (int round = 1; round <= 2; round++) {
        int n = round == 1 ? npoints : ncoarse;
        for (int k = 0; k < n; k++) {
            arc A = {res, pb->ap, u, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, {0, 0, 0}, 0, eps, &out->unsure_side};
            long budget;
            if (round == 1) {
                /* a third each: corners, side points, face points; every corner when
                 * they are few (then side points in the corners' place when done) */
                int kind = k % 3, all_corners = pb->in.nv <= npoints / 3;
                if (kind == 0 && all_corners && k / 3 < pb->in.nv)
                    memcpy(A.p, V + 3 * (k / 3), sizeof A.p);
                else
                    surface_point(V, T, bt_int(&rng, 0, pb->in.nt - 1), kind == 0 && all_corners ? 1 : kind, &rng,
                                  A.p);
                out->arcs++;
                budget = first;
            } else {
                memcpy(A.p, points + 3 * k, sizeof A.p);
                budget = (evals - out->evals) / (ncoarse - k);
                budget = budget < first ? first : budget;
            }
            budget = budget < evals_per_arc ? budget : evals_per_arc;
            arc_setup(&A, u);
            long used = 0;
            double step = 0;
            sample bad = {0, 0, 0, 0};
            int r = run_arc(&A, pb, budget, &w, &used, &step, &bad);
            out->evals += used;
            if (r == ARC_COARSE && round == 1)
                memcpy(points + 3 * ncoarse++, A.p, sizeof A.p);
            if (r == ARC_COARSE && round == 2) {
                out->coarse++;
                out->coarse_step = fmax(out->coarse_step, step / pb->tol);
            }
            if (r == ARC_OUTSIDE) {
                out->outside++;
                if (bad.f > out->worst) {
                    out->worst = bad.f;
                    out->worst_t = bad.t;
                    rotate(pb->ap, u, bad.t, A.p, out->worst_q);
                }
            }
        }
    }
    free(points);
    free(w.S);
    free(w.h.s);
    free(w.cross);
}

/* ------------------------------------------------------------------------ */
/* Tight                                                                    */
/* ------------------------------------------------------------------------ */

/* The distance from p turned back by t to the input solid (0 inside it); above `enough`
 * only then is the side asked. */
static double sv_dist(const bt_problem *pb, const bt_index *in, const double u[3], const double p[3], double t,
                      double enough)
{
    double x[3];
    rotate(pb->ap, u, -t, p, x);
    double d = bt_dist(in, x, NULL);
    if (d <= enough)
        return d;
    return bt_inside(in, x) == 1 ? 0 : d;
}

enum { POINT_WITHIN, POINT_BEYOND, POINT_UNDECIDED };

/* One result point p: branch and bound for min over t of the distance of p turned back to
 * the input (the span with the lowest bound first; the heap keeps the largest key on top:
 * keys are negated bounds), until a sample is within `bound` (within), every span's bound
 * is above it (beyond, certified), or `budget` queries are spent (undecided).  *lb gets the
 * lowest bound left, *best the smallest distance sampled, *used the queries. */
static int tight_point(const bt_problem *pb, const bt_index *input, const double u[3], const double p[3],
                       double bound, double eps, long budget, double *t, double *g, heap *h, double *lb, double *best,
                       long *used)
{
    double r = dist_to_axis(pb->ap, u, p);
    int spans = r * pb->angle > eps ? TIGHT_FIRST_SPANS : 0, result = POINT_UNDECIDED;
    long ns = 0;
    *best = INFINITY;
    for (int i = 0; i <= spans && result != POINT_WITHIN; i++) {
        t[ns] = spans ? (i == spans ? pb->angle : pb->angle * i / spans) : 0;
        g[ns] = sv_dist(pb, input, u, p, t[ns], bound);
        *best = fmin(*best, g[ns]);
        if (g[ns++] <= bound)
            result = POINT_WITHIN;
    }
    h->n = 0;
    for (int i = 0; i < spans && result != POINT_WITHIN; i++)
        heap_push(h, (span){-0.5 * (g[i] + g[i + 1] - r * (t[i + 1] - t[i])), i, i + 1});
    *lb = spans ? -INFINITY : g[0];
    if (!spans && result != POINT_WITHIN)
        result = POINT_BEYOND; /* on the axis: the one distance is the distance */
    while (result == POINT_UNDECIDED && h->n) {
        span sp = heap_pop(h);
        *lb = -sp.key;
        if (*lb > bound) {
            result = POINT_BEYOND; /* every span's bound is above */
            break;
        }
        if (ns >= budget + TIGHT_FIRST_SPANS + 1)
            break; /* undecided: *lb is the lowest bound left */
        double m = 0.5 * (t[sp.a] + t[sp.b]);
        t[ns] = m;
        g[ns] = sv_dist(pb, input, u, p, m, bound);
        *best = fmin(*best, g[ns]);
        if (g[ns] <= bound) {
            result = POINT_WITHIN;
            ns++;
            break;
        }
        heap_push(h, (span){-0.5 * (g[sp.a] + g[ns] - r * (m - t[sp.a])), sp.a, (int)ns});
        heap_push(h, (span){-0.5 * (g[ns] + g[sp.b] - r * (t[sp.b] - m)), (int)ns, sp.b});
        ns++;
    }
    *used = ns;
    return result;
}

void bt_check_tight(const bt_problem *pb, const bt_index *input, const mfg_mesh *res, double eps, int nvertices,
                    int nfacepoints, long evals, long evals_per_point, uint64_t seed, bt_tight_report *out)
{
    memset(out, 0, sizeof *out);
    bt_rng rng = {seed};
    double u[3];
    unit3(pb->ad, u);
    double bound = pb->tol + eps;
    long cap = evals_per_point + TIGHT_FIRST_SPANS + 2;
    double *t = malloc((size_t)cap * sizeof *t), *g = malloc((size_t)cap * sizeof *g);
    heap h = {malloc((size_t)(2 * cap) * sizeof(span)), 0};
    /* face points by area: the cumulative areas */
    double *cum = malloc((size_t)(res->ntriangles + 1) * sizeof *cum), total = 0;
    for (int64_t k = 0; k < res->ntriangles; k++) {
        const double *a = res->vertices + 3 * res->triangles[3 * k], *b = res->vertices + 3 * res->triangles[3 * k + 1],
                     *c = res->vertices + 3 * res->triangles[3 * k + 2];
        double e1[3], e2[3], n[3];
        for (int i = 0; i < 3; i++) {
            e1[i] = b[i] - a[i];
            e2[i] = c[i] - a[i];
        }
        cross3(e1, e2, n);
        total += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        cum[k] = total;
    }
    int all_vertices = res->nvertices <= nvertices, nv_used = all_vertices ? (int)res->nvertices : nvertices;
    int npts = nv_used + nfacepoints, nleft = 0;
    double *left = malloc((size_t)(3 * npts + 1) * sizeof *left);
    /* round 1: every point with the first budget; round 2: the undecided ones share what
     * is left of the total (points whose distance stays near the tolerance along a long
     * stretch of the arc need many queries) */
    long first = evals / 2 / (npts > 0 ? npts : 1);
    first = first < evals_per_point ? first : evals_per_point;
    for (int round = 1; round <= 2; round++) {
        int n = round == 1 ? npts : nleft;
        for (int k = 0; k < n; k++) {
            double p[3];
            long budget = first;
            if (round == 2) {
                memcpy(p, left + 3 * k, sizeof p);
                budget = (evals - out->evals) / (nleft - k);
                budget = budget < first ? first : budget < evals_per_point ? budget : evals_per_point;
            } else if (k < nv_used) {
                int64_t v = all_vertices ? k : bt_int(&rng, 0, res->nvertices - 1);
                memcpy(p, res->vertices + 3 * v, sizeof p);
            } else {
                int64_t tri;
                if (k % 2 && total > 0) { /* by area: big triangles bridge concavities */
                    double x = bt_unif(&rng, 0, total);
                    int64_t lo = 0, hi = res->ntriangles - 1;
                    while (lo < hi) {
                        int64_t mid = (lo + hi) / 2;
                        if (cum[mid] < x)
                            lo = mid + 1;
                        else
                            hi = mid;
                    }
                    tri = lo;
                } else {
                    tri = bt_int(&rng, 0, res->ntriangles - 1);
                }
                surface_point(res->vertices, res->triangles, tri, 2, &rng, p);
            }
            double lb, best;
            long used;
            int r = tight_point(pb, input, u, p, bound, eps, budget, t, g, &h, &lb, &best, &used);
            out->evals += used;
            if (round == 1)
                out->points++;
            if (r == POINT_UNDECIDED && round == 1) {
                memcpy(left + 3 * nleft++, p, sizeof p);
                continue;
            }
            if (r == POINT_WITHIN) {
                out->within++;
            } else if (r == POINT_BEYOND) {
                out->beyond++;
                if (lb > out->worst_lb) {
                    out->worst_lb = lb;
                    memcpy(out->worst_p, p, sizeof p);
                }
            } else {
                if (!out->undecided++) {
                    memcpy(out->undecided_p, p, sizeof p);
                    out->undecided_min = best;
                }
                out->undecided_lb = fmax(out->undecided_lb, lb);
            }
        }
    }
    free(left);
    free(t);
    free(g);
    free(h.s);
    free(cum);
}

/* ------------------------------------------------------------------------ */
/* Near another solid                                                       */
/* ------------------------------------------------------------------------ */

long bt_within_solid(const mfg_mesh *a, const bt_index *b, double bound, int npoints, uint64_t seed,
                     double *worst)
{
    bt_rng rng = {seed};
    long bad = 0;
    *worst = -INFINITY;
    for (int k = 0; k < npoints; k++) {
        double p[3];
        if (k % 2 == 0) {
            int64_t v = a->nvertices <= npoints / 2 ? (k / 2) % a->nvertices : bt_int(&rng, 0, a->nvertices - 1);
            memcpy(p, a->vertices + 3 * v, sizeof p);
        } else {
            surface_point(a->vertices, a->triangles, bt_int(&rng, 0, a->ntriangles - 1), 2, &rng, p);
        }
        double f = bt_signed(b, p, 0, NULL, NULL);
        *worst = fmax(*worst, f);
        bad += f > bound;
    }
    return bad;
}
