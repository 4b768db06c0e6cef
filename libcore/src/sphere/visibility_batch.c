/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* visibility_batch.c - a large hull grown in batches merged in the gnomonic projection about
 * an exactly verified centre
 * (split from visibility.c; see sphere/visibility.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "sphere/sphere.h"
#include "sphere/visibility.h"

/* ---- Many hull vertices: batches merged in the gnomonic projection ------------------ */

/*
 * One insertion costs O(h) orientation tests, so normals that are nearly all hull
 * vertices (a finely tessellated cone) would take O(m^2).  Once the hull has more than
 * SMALL_HULL vertices, the remaining normals come in batches three times as large as
 * everything seen so far (so each normal is sorted about 4/3 times, and a batch has few
 * normals outside the centre's hemisphere, the prefix being a scrambled sample; repeats
 * are dropped first).  Let c be a direction with c.u > 0 (exactly) for every hull vertex u: the centre
 * of the smallest cap around the hull, which is the centre of the largest circle inside
 * the map.  The gnomonic projection about c maps the hull and every normal p with c.p > 0
 * to the plane, where the orientation of three projected points is exactly the sign of
 * det[a, b, p] = mfg_orient3: the new hull is a planar monotone-chain hull of the old
 * vertices and the batch, O(n log n) with the exactly decided sort below.  Normals with
 * c.p <= 0 are retried against the centre of the grown hull, and the last few are
 * inserted one at a time (which also finds -p in the cone: the cone is not pointed).
 */
#define FEW_LEFT 16 /* normals outside every centre's hemisphere inserted one at a time */

typedef struct proj_frame {
    double c[3], e1[3], e2[3]; /* centre, and a frame with det[e1, e2, c] > 0 */
} proj_frame;

/* A normal's projection x = p.e1 / p.c, y = p.e2 / p.c in floating point, with a bound
 * err on the error of both: most comparisons need no exact predicate. */
typedef struct proj_pt {
    double x, y, err;
    vref p;
} proj_pt;

static proj_pt project(const proj_frame *f, vref p)
{
    const double u4 = 2.0 * DBL_EPSILON; /* 4u: a 3-term dot product's relative error */
    double d = mfg_dot3(p, f->c), n1 = mfg_dot3(p, f->e1), n2 = mfg_dot3(p, f->e2);
    double ed = 0, en = 0;
    for (int i = 0; i < 3; i++) {
        ed += fabs(p[i] * f->c[i]);
        en += fabs(p[i] * f->e1[i]) + fabs(p[i] * f->e2[i]); /* bounds both */
    }
    ed *= u4;
    en *= u4;
    proj_pt q = {0.0, 0.0, INFINITY, p};
    if (d > 4.0 * ed) { /* else the quotient is unreliable: compare exactly */
        q.x = n1 / d;
        q.y = n2 / d;
        double ax = fmax(fabs(q.x), fabs(q.y));
        /* |x~ - x| <= (|x~| ed + en) / d~ * 4/3 (d >= 3/4 d~) + u |x~|: doubled */
        q.err = 2.0 * (ax * ed + en) / d + DBL_EPSILON * ax;
    }
    return q;
}

/* Lexicographic order of the projections: sign(x_a - x_b) = sign((a.e1)(b.c) -
 * (a.c)(b.e1)) as both dots with c are positive, decided exactly when the floating-point
 * values are too close. */
static int proj_cmp(const proj_frame *f, const proj_pt *a, const proj_pt *b)
{
    double tol = a->err + b->err;
    if (a->x - b->x > tol)
        return 1;
    if (b->x - a->x > tol)
        return -1;
    if (mfg_parallel3(a->p, b->p) > 0)
        return 0; /* repeated normals (p, 2p, 3p...): cheaper than two exact expansions */
    int s = mfg_cross_dot_sign(a->p, b->p, f->e1, f->c);
    if (s != 0)
        return s;
    if (a->y - b->y > tol)
        return 1;
    if (b->y - a->y > tol)
        return -1;
    return mfg_cross_dot_sign(a->p, b->p, f->e2, f->c);
}

/* Merge sort with the exact comparison (tmp: room for n / 2 + 1). */
static void proj_sort(const proj_frame *f, proj_pt *a, proj_pt *tmp, int64_t n)
{
    if (n <= 12) {
        for (int64_t i = 1; i < n; i++) {
            proj_pt t = a[i];
            int64_t j = i;
            for (; j > 0 && proj_cmp(f, &a[j - 1], &t) > 0; j--)
                a[j] = a[j - 1];
            a[j] = t;
        }
        return;
    }
    int64_t h = n / 2;
    proj_sort(f, a, tmp, h);
    proj_sort(f, a + h, tmp, n - h);
    if (proj_cmp(f, &a[h - 1], &a[h]) <= 0)
        return; /* already in order (runs of a boundary given in order) */
    memcpy(tmp, a, (size_t)h * sizeof *a);
    int64_t i = 0, j = h, o = 0;
    while (i < h && j < n)
        a[o++] = proj_cmp(f, &tmp[i], &a[j]) <= 0 ? tmp[i++] : a[j++];
    while (i < h)
        a[o++] = tmp[i++];
}

/* Exact b - a, or 0 when a component's difference rounds (Knuth's two-difference error). */
static int exact_diff(vref a, vref b, double d[3])
{
    for (int i = 0; i < 3; i++) {
        double s = b[i] - a[i], bv = s + a[i], av = bv - s;
        if ((b[i] - bv) + (av - a[i]) != 0.0)
            return 0;
        d[i] = s;
    }
    return 1;
}

/* sign(det[a, b, p]) for neighbouring hull vertices.  A tessellated circle's neighbours
 * are so close that det (about the cube of their distance) sits below the floating-point
 * filter of mfg_orient3 and every test took the exact path; det[a, b - a, p - a] is the
 * same determinant with small terms, so its filter decides, when both differences are
 * exact (they usually are: Sterbenz's lemma for components of equal sign and size). */
static int orient3_close(vref a, vref b, vref p)
{
    double d1[3], d2[3];
    if (exact_diff(a, b, d1) && exact_diff(a, p, d2))
        return mfg_orient3(a, d1, d2);
    return mfg_orient3(a, b, p);
}

/* Strictly convex hull of the sorted points (Andrew's monotone chain), counter-clockwise:
 * orient3 > 0 at every vertex; repeats and points on an edge are popped (orient3 = 0).
 * out has room for 2n; returns its size. */
static int64_t monotone_chain(const proj_pt *s, int64_t n, vref *out)
{
    int64_t k = 0;
    for (int64_t i = 0; i < n; i++) {
        while (k >= 2 && orient3_close(out[k - 2], out[k - 1], s[i].p) <= 0)
            k--;
        out[k++] = s[i].p;
    }
    for (int64_t i = n - 2, lower = k + 1; i >= 0; i--) {
        while (k >= lower && orient3_close(out[k - 2], out[k - 1], s[i].p) <= 0)
            k--;
        out[k++] = s[i].p;
    }
    return n > 1 ? k - 1 : k;
}

typedef struct batch_work {
    proj_pt *pts, *tmp;
    vref *chain, *pend, *bad, *seen;
    double *units;
    int64_t n_pts, n_tmp, n_chain, n_pend, n_bad, n_seen, n_units; /* capacities */
} batch_work;

#define RESERVE(buf, cap, need)                                                          \
    do {                                                                                 \
        if (!mfg_grow((void **)&(buf), &(cap), (need), sizeof *(buf)))                   \
            return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld projected normals",     \
                            (long long)(need));                                          \
    } while (0)

static void batch_work_free(batch_work *w)
{
    free(w->pts);
    free(w->tmp);
    free(w->chain);
    free(w->pend);
    free(w->bad);
    free(w->seen);
    free(w->units);
}

/* The centre c (smallest cap around the unit hull vertices), accepted only when c.u > 0
 * exactly for every hull vertex u; then a frame e1, e2 with det[e1, e2, c] near 1 > 0. */
static mfg_status map_centre(const cone3 *k, batch_work *w, proj_frame *f, int *ok)
{
    *ok = 0;
    RESERVE(w->units, w->n_units, 3 * k->nh);
    for (int64_t i = 0; i < k->nh; i++)
        mfg_unit3(k->h[i], w->units + 3 * i);
    double cosr;
    mfg_enclosing_cap(w->units, k->nh, f->c, &cosr);
    for (int64_t i = 0; i < k->nh; i++)
        if (mfg_dot3_sign(f->c, k->h[i]) <= 0)
            return MFG_OK;
    /* The frame is turned by an odd angle (1 rad) from the one mfg_vm_any_orthogonal picks: a
     * cone about a coordinate axis, listed symmetrically, would otherwise give pairs of
     * normals with the same x up to rounding, each pair an exact comparison. */
    double a[3], b[3];
    mfg_vm_any_orthogonal(f->c, a);
    mfg_cross3(f->c, a, b);
    for (int i = 0; i < 3; i++)
        f->e1[i] = 0.5403023058681398 * a[i] + 0.8414709848078965 * b[i];
    mfg_cross3(f->c, f->e1, f->e2);
    *ok = 1;
    return MFG_OK;
}

/* p scaled by a power of two (exact) so that its largest component lies in [0.5, 1):
 * p, 2p and p / 4 have the same key. */
static void repeat_key(vref p, double key[3])
{
    int e;
    frexp(fmax(fabs(p[0]), fmax(fabs(p[1]), fabs(p[2]))), &e);
    for (int i = 0; i < 3; i++)
        key[i] = ldexp(p[i], -e) + 0.0; /* + 0.0: -0 and 0 alike */
}

/* Drops repeats (the same direction up to a power-of-two length) from the np normals
 * w->pend; returns how many are left, or -1 when memory runs out.  A flat face's normal
 * repeated for each of its triangles is common, and repeats would meet in the sort and
 * the chain, each tie an exact evaluation (two variants of 10^3 directions, each
 * repeated 500 times: 25x slower). */
static int64_t drop_repeats(batch_work *w, int64_t np)
{
    int64_t size = 64;
    while (size < 2 * np)
        size *= 2;
    if (!mfg_grow((void **)&w->seen, &w->n_seen, size, sizeof *w->seen))
        return -1;
    vref *seen = w->seen;
    memset(seen, 0, (size_t)size * sizeof *seen);
    int64_t kept = 0;
    for (int64_t i = 0; i < np; i++) {
        vref p = w->pend[i];
        double key[3], other[3];
        uint64_t b[3];
        repeat_key(p, key);
        memcpy(b, key, sizeof b);
        uint64_t x = b[0] * 0x9E3779B97F4A7C15ULL ^ b[1] * 0xC2B2AE3D27D4EB4FULL ^
                     b[2] * 0x165667B19E3779F9ULL;
        x ^= x >> 29;
        int64_t slot = (int64_t)(x & (uint64_t)(size - 1));
        for (; seen[slot]; slot = (slot + 1) & (size - 1)) {
            repeat_key(seen[slot], other);
            if (memcmp(key, other, sizeof key) == 0)
                break;
        }
        if (!seen[slot]) {
            seen[slot] = p;
            w->pend[kept++] = p;
        }
    }
    return kept;
}

/* Adds the np normals w->pend to the hull of a pointed cone; stops at CONE_LINE. */
static mfg_status add_batch(cone3 *k, batch_work *w, int64_t np)
{
    mfg_status st;
    while (np > 0) {
        proj_frame f;
        int ok;
        if ((st = map_centre(k, w, &f, &ok)) != MFG_OK)
            return st;
        if (!ok)
            break; /* no exact centre (a map thinner than rounding): one at a time */
        int64_t h = k->nh, need = h + np, n = 0, nbad = 0;
        RESERVE(w->pts, w->n_pts, need);
        RESERVE(w->tmp, w->n_tmp, need / 2 + 1);
        RESERVE(w->chain, w->n_chain, 2 * need + 2);
        RESERVE(w->bad, w->n_bad, np);
        for (int64_t i = 0; i < h; i++)
            w->pts[n++] = project(&f, k->h[i]);
        for (int64_t i = 0; i < np; i++) {
            /* a finite err means p.c passed a filter stricter than mfg_dot3_sign's */
            proj_pt q = project(&f, w->pend[i]);
            if (q.err < INFINITY || mfg_dot3_sign(f.c, w->pend[i]) > 0)
                w->pts[n++] = q;
            else
                w->bad[nbad++] = w->pend[i];
        }
        if (n > h) {
            proj_sort(&f, w->pts, w->tmp, n);
            int64_t nh = monotone_chain(w->pts, n, w->chain);
            if (nh < 3) /* it holds the old hull, which spans the space */
                return mfg_fail(MFG_ERR_INTERNAL, "projected hull of %lld points collapsed",
                                (long long)n);
            if ((st = mfg_vm_hull_reserve(k, nh + 2)) != MFG_OK)
                return st;
            memcpy(k->h, w->chain, (size_t)nh * sizeof(vref));
            k->nh = nh;
            mfg_vm_update_cap(k);
        }
        vref *t = w->pend; /* the rest goes back to w->pend */
        w->pend = w->bad;
        w->bad = t;
        int64_t tc = w->n_pend;
        w->n_pend = w->n_bad;
        w->n_bad = tc;
        int progress = nbad < np;
        np = nbad;
        if (np <= FEW_LEFT || !progress)
            break; /* else retry against the grown hull's centre */
    }
    for (int64_t i = 0; i < np && k->state == CONE_HULL; i++)
        if ((st = mfg_vm_hull_add(k, w->pend[i])) != MFG_OK)
            return st;
    return MFG_OK;
}

/* Continues the incremental game in batches once the hull is large: the normals from
 * step on in the scrambled order (index idx, stride), each batch three times the number
 * of normals already seen; normals inside the hull's inscribed cap are skipped first. */
mfg_status mfg_vm_grow_in_batches(cone3 *k, const double *normals, int64_t m, int64_t step,
                                  int64_t idx, int64_t stride)
{
    batch_work w;
    memset(&w, 0, sizeof w);
    mfg_status st = MFG_OK;
    while (step < m && st == MFG_OK && k->state == CONE_HULL) {
        int64_t b = 3 * step < m - step ? 3 * step : m - step, np = 0;
        if (!mfg_grow((void **)&w.pend, &w.n_pend, b, sizeof *w.pend)) {
            st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate a batch of %lld normals", (long long)b);
            break;
        }
        for (int64_t i = 0; i < b; i++) {
            vref p = normals + 3 * idx;
            idx += stride;
            if (idx >= m)
                idx -= m;
            if (!mfg_vm_in_inscribed_cap(k, p))
                w.pend[np++] = p;
        }
        step += b;
        if ((np = drop_repeats(&w, np)) < 0) {
            st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate a table of %lld normals", (long long)b);
            break;
        }
        st = add_batch(k, &w, np);
    }
    batch_work_free(&w);
    return st;
}
