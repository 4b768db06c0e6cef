/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* visibility_hull.c - the pointed cone of the normals grown one normal at a time: its ray,
 * wedge or convex hull, with exact orientation tests and the inscribed cap that skips
 * inside points
 * (split from visibility.c; see sphere/visibility.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "sphere/sphere.h"
#include "sphere/visibility.h"

/* The inscribed cap of a cone (its quick inside test): the angular radius of its centre's
 * nearest side shrunk by CAP_IN_SHRINK (relative) and CAP_IN_MARGIN rad for the rounding
 * of asin and the unit vectors, kept only when above CAP_IN_MIN rad (else no use). */
#define CAP_IN_SHRINK 1e-6
#define CAP_IN_MARGIN 1e-9
#define CAP_IN_MIN 1e-5

mfg_status mfg_vm_hull_reserve(cone3 *k, int64_t n)
{
    if (n <= k->cap)
        return MFG_OK;
    int64_t cap = k->cap ? 2 * k->cap : 64;
    while (cap < n)
        cap *= 2;
    vref *h = realloc(k->h, (size_t)cap * sizeof(vref));
    if (h)
        k->h = h;
    int *o = realloc(k->o, (size_t)cap * sizeof(int));
    if (o)
        k->o = o;
    vref *t = realloc(k->tmp, (size_t)(cap + 1) * sizeof(vref));
    if (t)
        k->tmp = t;
    if (!h || !o || !t)
        return mfg_fail(MFG_ERR_NOMEM, "cannot grow the hull to %lld vertices", (long long)cap);
    k->cap = cap;
    return MFG_OK;
}

/* Inscribed cap: centre = normalised sum of the unit hull vertices (strictly inside a
 * pointed hull), radius = the smallest angular distance to an edge's great circle,
 * shrunk by a relative 1e-6 and 1e-9 rad so rounding can never admit an outside point.
 * Caps under 1e-5 rad are not kept: the test dot > cos(r) has an angular error of about
 * 1e-16 / sin(r), beyond the 1e-9 slack for tiny r (and cos(r) rounds to 1 below 1e-8,
 * where a point at the centre passed with dot = 1 + 2^-52: a nearly hemispherical hull,
 * whose vertex mean lies near its boundary, skipped one of its own vertices). */
void mfg_vm_update_cap(cone3 *k)
{
    double c[3] = {0, 0, 0};
    k->have_cap = 0;
    for (int64_t i = 0; i < k->nh; i++) {
        double u[3];
        mfg_unit3(k->h[i], u);
        c[0] += u[0];
        c[1] += u[1];
        c[2] += u[2];
    }
    if (!mfg_unit3(c, k->c))
        return;
    double min_sin = 1.0;
    for (int64_t i = 0; i < k->nh; i++) {
        double n[3], nu[3];
        mfg_cross3(k->h[i], k->h[(i + 1) % k->nh], n);
        if (!mfg_unit3(n, nu))
            return;
        min_sin = fmin(min_sin, mfg_dot3(nu, k->c));
    }
    double r = asin(fmin(fmax(min_sin, 0.0), 1.0)) * (1.0 - CAP_IN_SHRINK) - CAP_IN_MARGIN;
    if (r > CAP_IN_MIN) {
        k->cos2_in = cos(r) * cos(r);
        k->have_cap = 1;
    }
}

/* p strictly inside the inscribed cap (so inside the hull): (p.c)^2 > cos^2 r |p|^2 with
 * p.c > 0, no square root or division per normal. */
int mfg_vm_in_inscribed_cap(const cone3 *k, vref p)
{
    if (!k->have_cap)
        return 0;
    double d = mfg_dot3(p, k->c);
    return d > 0.0 && d * d > k->cos2_in * mfg_dot3(p, p);
}

/* p in the cone of one triangle h_0, h_i, h_i+1 of the fan from h_0, the triangle found
 * by binary search on the side of p from the rays h_0 -> h_i (then three exact tests
 * certify it): O(log h) orientation tests instead of h for a point inside, where the
 * inscribed cap does not help (a sliver hull of normals near one great circle). */
static int in_fan_triangle(const cone3 *k, vref p)
{
    int64_t n = k->nh, lo = 1, hi = n - 1;
    if (mfg_orient3(k->h[0], k->h[lo], p) < 0 || mfg_orient3(k->h[0], k->h[hi], p) > 0)
        return 0;
    while (hi - lo > 1) { /* p left of or on h_0 -> h_lo, right of or on h_0 -> h_hi */
        int64_t mid = lo + (hi - lo) / 2;
        if (mfg_orient3(k->h[0], k->h[mid], p) >= 0)
            lo = mid;
        else
            hi = mid;
    }
    return mfg_orient3(k->h[lo], k->h[hi], p) >= 0;
}

/* Adds p to a pointed polygonal hull, or moves to CONE_LINE when -p is in the cone. */
mfg_status mfg_vm_hull_add(cone3 *k, vref p)
{
    if (mfg_vm_in_inscribed_cap(k, p) || in_fan_triangle(k, p))
        return MFG_OK;
    int64_t n = k->nh, neg = 0, pos = 0;
    mfg_status st = mfg_vm_hull_reserve(k, n + 2);
    if (st != MFG_OK)
        return st;
    for (int64_t i = 0; i < n; i++) {
        int o = mfg_orient3(k->h[i], k->h[(i + 1) % n], p);
        k->o[i] = o;
        neg += o < 0;
        pos += o > 0;
    }
    if (neg == 0)
        return MFG_OK; /* inside or on the hull */
    if (pos == 0) {    /* right of or on every edge: -p is in the closed hull */
        k->state = CONE_LINE;
        k->q = p;
        return MFG_OK;
    }
    /* The edges p sees (strictly right of them) form one cyclic run. */
    int64_t start = -1, starts = 0;
    for (int64_t i = 0; i < n; i++)
        if (k->o[i] < 0 && k->o[(i + n - 1) % n] >= 0) {
            start = i;
            starts++;
        }
    if (starts != 1)
        return mfg_fail(MFG_ERR_INTERNAL, "visible hull edges are not contiguous");
    /* Keep h[start+neg] .. h[start] and put p after h[start]. */
    vref *t = k->tmp;
    int64_t m = 0;
    for (int64_t j = (start + neg) % n;; j = (j + 1) % n) {
        t[m++] = k->h[j];
        if (j == start)
            break;
    }
    t[m++] = p;
    /* p on the great circle of an edge next to the run (beyond its end) makes the
     * vertex between collinear: drop it so the hull stays strictly convex. */
    while (m > 3 && mfg_orient3(t[m - 3], t[m - 2], t[m - 1]) == 0) {
        t[m - 2] = t[m - 1];
        m--;
    }
    while (m > 3 && mfg_orient3(t[m - 1], t[0], t[1]) == 0) {
        memmove(t, t + 1, (size_t)(m - 1) * sizeof(vref));
        m--;
    }
    memcpy(k->h, t, (size_t)m * sizeof(vref));
    k->nh = m;
    mfg_vm_update_cap(k);
    return MFG_OK;
}

/* Adds p to a cone in state EMPTY, RAY or WEDGE. */
mfg_status mfg_vm_low_add(cone3 *k, vref p)
{
    switch (k->state) {
    case CONE_EMPTY:
        k->a = p;
        k->state = CONE_RAY;
        return MFG_OK;
    case CONE_RAY: {
        int par = mfg_parallel3(k->a, p);
        if (par < 0) {
            k->state = CONE_LINE;
            k->q = p;
        } else if (par == 0) {
            k->b = p;
            k->state = CONE_WEDGE;
        }
        return MFG_OK;
    }
    case CONE_WEDGE: {
        int o = mfg_orient3(k->a, k->b, p);
        if (o != 0) { /* leaves the plane: a triangle, ordered counter-clockwise */
            mfg_status st = mfg_vm_hull_reserve(k, 3);
            if (st != MFG_OK)
                return st;
            k->h[0] = o > 0 ? k->a : k->b;
            k->h[1] = o > 0 ? k->b : k->a;
            k->h[2] = p;
            k->nh = 3;
            k->state = CONE_HULL;
            mfg_vm_update_cap(k);
            return MFG_OK;
        }
        /* In the plane of the wedge: orientation about n = a x b, exactly, as
         * sign((a x b).(x x y)). */
        int s1 = mfg_cross_dot_sign(k->a, k->b, k->a, p);
        int s2 = mfg_cross_dot_sign(k->a, k->b, p, k->b);
        if (s1 >= 0 && s2 >= 0)
            return MFG_OK; /* inside the wedge */
        if (s1 <= 0 && s2 <= 0) {
            k->state = CONE_LINE; /* -p is in the wedge */
            k->q = p;
        } else if (s1 < 0) {
            k->a = p; /* p before a: wedge p .. b */
        } else {
            k->b = p; /* p after b: wedge a .. p */
        }
        return MFG_OK;
    }
    default:
        return mfg_fail(MFG_ERR_INTERNAL, "bad cone state");
    }
}
