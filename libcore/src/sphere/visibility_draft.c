/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* visibility_draft.c - the draft angle: the visibility map shrunk to the directions at least
 * the draft angle inside every hemisphere (intersection of equal caps)
 * (split from visibility.c; see sphere/visibility.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "sphere/sphere.h"
#include "sphere/visibility.h"

/* Rounding of a corner on its own two circles (dot products of unit vectors, ~1e-16). */
#define CORNER_SLACK 1e-13
/* A loop winds once around a centre when its turning angle is 2 pi within this. */
#define TURN_TOL 1e-6
/* A cone's draft cap is sampled a hair inside its radius; the sine the sample step
 * divides by is kept above MIN_SIN. */
#define CAP_INSIDE 1e-12
#define MIN_SIN 1e-12

/* ---- Draft angle -------------------------------------------------------------------- */

/*
 * The drafted map D = { d : d.u^ >= sin(draft) } over the hull normals u is the
 * intersection of equal caps of radius rho = pi/2 - draft about the u^ (rho a hair
 * smaller, so rounding stays inside).  D is empty when no direction lies within rho of
 * every u^: when the smallest cap around them is wider than rho.  Otherwise equal caps
 * about points in convex position meet D's boundary in the hull's cyclic order, each at
 * most once, so the boundary is found like a half-plane intersection sorted by angle, in
 * O(h): a deque of caps, the last (first) dropped while the corner it makes with its
 * neighbour lies outside the next cap.  That analogy with half-planes is not exact for
 * caps wide against the hull (long thin hulls gave corners far outside other caps), so
 * the deque's boundary is certified against the caps (draft_boundary_ok, O(h)) and, when
 * it fails, D is computed the slow plain way (draft_by_clipping), whose caps, certified
 * in turn, give D's exact corners.  Each boundary arc is then sampled with chords of
 * sagitta below MFG_DRAFT_TOL; a chord between two points of D stays in every (convex)
 * cap, so the polygon is conservative.
 */

/* The corner where D's boundary leaves cap a's circle for cap b's (unit centres, d.u^ =
 * s on both): the common point on the side of a x b (at draft 0, the map's vertex). */
static int cap_corner(const double *ua, const double *ub, double s, double out[3])
{
    double g = mfg_dot3(ua, ub), w[3], wu[3];
    if (!(g > -1.0))
        return 0;
    double f = s / (1.0 + g), t2 = 1.0 - 2.0 * s * f; /* |f (ua + ub)|^2 = 2 s f */
    mfg_cross3_accurate(ua, ub, w);
    if (!(t2 >= 0.0) || !mfg_unit3(w, wu))
        return 0;
    double t = sqrt(t2);
    for (int i = 0; i < 3; i++)
        out[i] = f * (ua[i] + ub[i]) + t * wu[i];
    return 1;
}

static int corner_inside(const double *u, int64_t a, int64_t b, int64_t c, double s)
{
    double x[3];
    return cap_corner(u + 3 * a, u + 3 * b, s, x) && mfg_dot3(x, u + 3 * c) >= s;
}

/* Appends the circle of cap u (cos rho = s, sin rho = sr) from p counter-clockwise about
 * u through the angle phi (or the whole circle when p is NULL), in chords of at most
 * `step`, at least min_steps; p itself first, the end point not. */
static int64_t arc_points(const double *u, double s, double sr, const double *p, double phi,
                          double step, int64_t min_steps, double *out)
{
    double e1[3], e2[3];
    if (p) {
        double t[3] = {p[0] - s * u[0], p[1] - s * u[1], p[2] - s * u[2]};
        mfg_unit3(t, e1);
    } else {
        mfg_vm_any_orthogonal(u, e1);
    }
    mfg_cross3(u, e1, e2);
    int64_t n = (int64_t)ceil(phi / step);
    if (n < min_steps)
        n = min_steps;
    for (int64_t j = 0; j < n; j++) {
        double a = phi * (double)j / (double)n, ca = cos(a), sa = sin(a);
        for (int i = 0; i < 3; i++)
            out[3 * j + i] = s * u[i] + sr * (ca * e1[i] + sa * e2[i]);
    }
    if (p)
        memcpy(out, p, 3 * sizeof(double));
    return n;
}

/* Checks the deque's boundary (caps q[0..r-1], a subsequence of the hull order) against
 * what D's boundary must be.  The deque mimics a half-plane intersection, but the analogy
 * breaks for equal caps that are wide against the hull's spread (a long thin hull, a few
 * normals far apart): a cap may be dropped although it bounds D, or kept although its arc
 * is empty, and the corners then lie outside other caps (a fuzz case: d.p^ = -0.73 where
 * the draft asks 0.2955).  D's arcs do follow the hull order, so a cap i cutting the
 * candidate region removes a piece of its boundary holding the corner x_j of the caps
 * q_j, q_j+1 between which i lies in that order; hence it suffices that every corner lies
 * in the caps from q_j-1 to q_j+2 (O(h) in all), and that the corners go once round
 * counter-clockwise about c, the centre of the smallest cap around the u (inside D, as
 * its radius is below rho).  Returns 0 when the boundary is not certified. */
static int draft_boundary_ok(const double *u, int64_t nu, const int64_t *q, int64_t r, double s,
                             const double c[3])
{
    if (r < 2)
        return nu == 1;
    const double slack = CORNER_SLACK;
    for (int64_t j = 0; j < r; j++) {
        double x[3];
        if (!cap_corner(u + 3 * q[j], u + 3 * q[(j + 1) % r], s, x))
            return 0;
        int64_t from = q[(j + r - 1) % r], to = q[(j + 2) % r];
        int64_t len = (to - from + nu) % nu + 1;
        if (r <= 3)
            len = nu, from = 0; /* the ranges wrap: every cap */
        for (int64_t t = 0; t < len; t++)
            if (mfg_dot3(x, u + 3 * ((from + t) % nu)) < s - slack)
                return 0;
    }
    if (r == 2)
        return 1; /* a lens: its two corners, on the sides of a x b and b x a */
    /* the corners' azimuths about c, a point inside D, turn once round */
    double turn = 0.0;
    for (int64_t j = 0; j < r; j++) {
        double xa[3], xb[3], pa[3], pb[3], w[3];
        if (!cap_corner(u + 3 * q[j], u + 3 * q[(j + 1) % r], s, xa) ||
            !cap_corner(u + 3 * q[(j + 1) % r], u + 3 * q[(j + 2) % r], s, xb))
            return 0;
        double da = mfg_dot3(xa, c), db = mfg_dot3(xb, c);
        for (int i = 0; i < 3; i++)
            pa[i] = xa[i] - da * c[i], pb[i] = xb[i] - db * c[i];
        mfg_cross3(pa, pb, w);
        double ang = atan2(mfg_dot3(w, c), mfg_dot3(pa, pb));
        if (ang < 0.0) /* one arc may span more than pi; corners out of order add 2 pi */
            ang += 2.0 * MFG_PI;
        turn += ang;
    }
    return fabs(turn - 2.0 * MFG_PI) < TURN_TOL;
}

/* Clips convex spherical polygon (n unit vertices in poly, room for n+1 in out) by the
 * hemisphere { d : d.nrm >= 0 }; returns the new vertex count.  lab[i] names the cap whose
 * chord the edge poly[i] -> poly[i+1] lies on; the new labels go to olab, the new chord's
 * being `cap`. */
static int64_t clip_hemisphere(const double *poly, const int64_t *lab, int64_t n,
                               const double nrm[3], int64_t cap, double *out, int64_t *olab)
{
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++) {
        const double *a = poly + 3 * i, *b = poly + 3 * ((i + 1) % n);
        double sa = mfg_dot3(a, nrm), sb = mfg_dot3(b, nrm);
        if (sa >= 0) {
            memcpy(out + 3 * m, a, 3 * sizeof(double));
            olab[m++] = lab[i];
        }
        if ((sa >= 0) != (sb >= 0)) {
            double x[3] = {sa * b[0] - sb * a[0], sa * b[1] - sb * a[1], sa * b[2] - sb * a[2]};
            if (sa < 0)
                x[0] = -x[0], x[1] = -x[1], x[2] = -x[2];
            if (mfg_unit3(x, out + 3 * m))
                olab[m++] = sa >= 0 ? cap : lab[i]; /* leaving: along the chord */
        }
    }
    return m;
}

/* The slow, plainly correct way (used when the deque's boundary is not certified): the
 * first cap's inscribed polygon clipped by the chords of every other cap's inscribed
 * polygon (each chord lies inside its cap, so the result is conservative; the chords'
 * sagitta is below MFG_DRAFT_TOL); a cap holding every vertex is skipped.  O(h x n)
 * time, and O(steps x n) more per cap that cuts the polygon.  *out: n unit vertices, or
 * NULL with *n_out = 0 when empty; q[0..*nq-1]: the caps along its boundary in order
 * (consecutive repeats merged), for the caller to certify and redo with exact corners
 * (near a sharp corner of D the chords cut off more than their sagitta). */
static mfg_status draft_by_clipping(const double *u, int64_t nu, double s, double sr,
                                    double step, double **out, int64_t *n_out, int64_t *q,
                                    int64_t *nq)
{
    int64_t steps = (int64_t)ceil(2.0 * MFG_PI / step);
    if (steps < 8)
        steps = 8;
    int64_t cap = 2 * steps + 8; /* grown below: a clip adds at most one vertex */
    double *a = malloc((size_t)cap * 3 * sizeof(double));
    double *b = malloc((size_t)cap * 3 * sizeof(double));
    int64_t *la = malloc((size_t)cap * sizeof(int64_t));
    int64_t *lb = malloc((size_t)cap * sizeof(int64_t));
    mfg_status st = MFG_OK;
    *out = NULL;
    *n_out = 0;
    *nq = 0;
    int64_t n = 0;
    if (!a || !b || !la || !lb)
        st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate the draft polygon");
    for (int64_t j = 0; st == MFG_OK && j < nu && (j == 0 || n >= 3); j++) {
        const double *uj = u + 3 * j;
        int out_of_cap = j == 0;
        for (int64_t i = 0; i < n && !out_of_cap; i++)
            out_of_cap = mfg_dot3(a + 3 * i, uj) < s;
        if (!out_of_cap)
            continue; /* every vertex in the cap, so the polygon (convex cap): no chord */
        double e1[3], e2[3];
        mfg_vm_any_orthogonal(uj, e1);
        mfg_cross3(uj, e1, e2);
        double prev[3] = {0, 0, 0}, first[3] = {0, 0, 0};
        for (int64_t t = 0; t <= steps && (j == 0 || n >= 3); t++) {
            double th = 2.0 * MFG_PI * (double)(t % steps) / (double)steps, w[3];
            for (int i = 0; i < 3; i++)
                w[i] = s * uj[i] + sr * (cos(th) * e1[i] + sin(th) * e2[i]);
            if (j == 0) {
                if (t < steps) {
                    la[n] = 0;
                    memcpy(a + 3 * n++, w, sizeof w);
                }
                continue;
            }
            if (t == 0) {
                memcpy(first, w, sizeof w);
            } else {
                double nrm[3];
                if (n + 1 > cap) {
                    double *na = realloc(a, (size_t)(2 * cap) * 3 * sizeof(double));
                    a = na ? na : a;
                    double *nb = realloc(b, (size_t)(2 * cap) * 3 * sizeof(double));
                    b = nb ? nb : b;
                    int64_t *nla = realloc(la, (size_t)(2 * cap) * sizeof(int64_t));
                    la = nla ? nla : la;
                    int64_t *nlb = realloc(lb, (size_t)(2 * cap) * sizeof(int64_t));
                    lb = nlb ? nlb : lb;
                    if (!na || !nb || !nla || !nlb) {
                        st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate the draft polygon");
                        break;
                    }
                    cap *= 2;
                }
                mfg_cross3(prev, t == steps ? first : w, nrm); /* interior on the left */
                n = clip_hemisphere(a, la, n, nrm, j, b, lb);
                double *sw = a;
                a = b;
                b = sw;
                int64_t *sl = la;
                la = lb;
                lb = sl;
            }
            memcpy(prev, w, sizeof w);
        }
    }
    if (st == MFG_OK && n >= 3) {
        for (int64_t i = 0; i < n; i++) /* the runs of labels; at most nu of them */
            if (la[i] != la[(i + n - 1) % n] && *nq < nu)
                q[(*nq)++] = la[i];
        if (*nq == 0)
            q[(*nq)++] = la[0];
        *out = a;
        *n_out = n;
        a = NULL;
    }
    free(a);
    free(b);
    free(la);
    free(lb);
    return st;
}

/* Rotates q[0..r-1] to start at its smallest cap; 1 when it then increases strictly (a
 * subsequence of the hull order, as draft_boundary_ok needs). */
static int hull_ordered(int64_t *q, int64_t r)
{
    int64_t lo = 0;
    for (int64_t j = 1; j < r; j++)
        if (q[j] < q[lo])
            lo = j;
    /* rotate left by lo: reverse both parts, then the whole */
    for (int64_t pass = 0; pass < 3; pass++) {
        int64_t i = pass == 1 ? lo : 0, j = (pass == 0 ? lo : r) - 1;
        for (; i < j; i++, j--) {
            int64_t t = q[i];
            q[i] = q[j];
            q[j] = t;
        }
    }
    for (int64_t j = 1; j < r; j++)
        if (q[j] <= q[j - 1])
            return 0;
    return 1;
}

mfg_status mfg_vm_apply_draft(const cone3 *k, double draft, mfg_spoly **map)
{
    vref single[2];
    const vref *us;
    int64_t nu;
    if (k->state == CONE_RAY) {
        single[0] = k->a;
        us = single;
        nu = 1;
    } else if (k->state == CONE_WEDGE) {
        single[0] = k->a;
        single[1] = k->b;
        us = single;
        nu = 2;
    } else {
        us = k->h;
        nu = k->nh;
    }
    double rho = MFG_PI / 2 - draft - CAP_INSIDE; /* cap radius, a hair inside */
    double sr = sin(rho), s = cos(rho);
    double step = sqrt(8.0 * MFG_DRAFT_TOL / fmax(sr, MIN_SIN)); /* sagitta sr step^2 / 8 */
    step = fmin(step, 2.0 * MFG_PI / 8.0);
    double *u = calloc((size_t)nu * 3, sizeof(double)); /* calloc: quiets a false gcc warning */
    int64_t *q = malloc((size_t)nu * sizeof(int64_t));
    double *pts = NULL;
    mfg_spoly *res = NULL;
    mfg_status st = MFG_OK;
    if (!u || !q) {
        st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate the draft polygon");
        goto done;
    }
    for (int64_t i = 0; i < nu; i++)
        mfg_unit3(us[i], u + 3 * i);
    double c[3], cosr, wide = 0.0;
    mfg_enclosing_cap(u, nu, c, &cosr);
    for (int64_t i = 0; i < nu; i++) /* the cap's true radius, past Welzl's slack */
        wide = fmax(wide, mfg_angle3(c, u + 3 * i));
    int64_t head = 0, tail = 0, n = 0;
    if (wide < rho) {
        for (int64_t i = 0; i < nu; i++) {
            while (tail - head >= 2 && !corner_inside(u, q[tail - 2], q[tail - 1], i, s))
                tail--;
            while (tail - head >= 2 && !corner_inside(u, q[head], q[head + 1], i, s))
                head++;
            q[tail++] = i;
        }
        while (tail - head >= 3 && !corner_inside(u, q[tail - 2], q[tail - 1], q[head], s))
            tail--;
        while (tail - head >= 3 && !corner_inside(u, q[head], q[head + 1], q[tail - 1], s))
            head++;
        int exact = draft_boundary_ok(u, nu, q + head, tail - head, s, c);
        if (!exact) {
            int64_t nq;
            st = draft_by_clipping(u, nu, s, sr, step, &pts, &n, q, &nq);
            head = 0;
            tail = nq;
            /* the clipped polygon's caps, when certified, give D with exact corners */
            if (st == MFG_OK && nq > 0 && hull_ordered(q, nq) &&
                draft_boundary_ok(u, nu, q, nq, s, c)) {
                free(pts);
                pts = NULL;
                n = 0;
                exact = 1;
            }
        }
        if (exact) {
        /* a corner per arc, and its chords: the arcs turn by at most 2 pi about their
         * centres in all (D's perimeter is at most a cap's, 2 pi sin rho) */
        int64_t r = tail - head, total = 3 * r + (int64_t)ceil(3.0 * MFG_PI / step) + 8;
        pts = malloc((size_t)total * 3 * sizeof(double));
        if (!pts) {
            st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate the draft polygon");
            goto done;
        }
        if (r == 1) {
            n = arc_points(u + 3 * q[head], s, sr, NULL, 2.0 * MFG_PI, step, 8, pts);
        } else {
            double first[3], p0[3], p1[3];
            for (int64_t j = 0; j < r && st == MFG_OK; j++) {
                int64_t a = q[head + j], b = q[head + (j + 1) % r], cc = q[head + (j + 2) % r];
                if (j == 0 && !cap_corner(u + 3 * a, u + 3 * b, s, first))
                    st = mfg_fail(MFG_ERR_INTERNAL, "draft caps do not meet");
                memcpy(p0, j == 0 ? first : p1, sizeof p0);
                if (st == MFG_OK && !cap_corner(u + 3 * b, u + 3 * cc, s, p1))
                    st = mfg_fail(MFG_ERR_INTERNAL, "draft caps do not meet");
                if (st != MFG_OK)
                    break;
                /* the arc of cap b from p0 to p1, counter-clockwise about b */
                double t0[3], t1[3], e1[3], e2[3];
                for (int i = 0; i < 3; i++)
                    t0[i] = p0[i] - s * u[3 * b + i], t1[i] = p1[i] - s * u[3 * b + i];
                mfg_unit3(t0, e1);
                mfg_cross3(u + 3 * b, e1, e2);
                double phi = atan2(mfg_dot3(t1, e2), mfg_dot3(t1, e1));
                if (phi < 0.0)
                    phi += 2.0 * MFG_PI;
                int64_t want = (int64_t)ceil(phi / step) + (r == 2 ? 2 : 1);
                if (n + want > total) { /* cannot happen for a consistent boundary */
                    st = mfg_fail(MFG_ERR_INTERNAL, "draft boundary turns too far");
                    break;
                }
                n += arc_points(u + 3 * b, s, sr, p0, phi, step, r == 2 ? 2 : 1, pts + 3 * n);
            }
        }
        }
    }
    if (st == MFG_OK)
        st = mfg_vm_spoly_new(n >= 3 ? MFG_VM_POLYGON : MFG_VM_NULL, n >= 3 ? n : 0, &res);
    if (st == MFG_OK && n >= 3)
        memcpy(res->vertices, pts, (size_t)n * 3 * sizeof(double));
done:
    free(u);
    free(q);
    free(pts);
    if (st != MFG_OK)
        return st;
    mfg_spoly_free(*map);
    *map = res;
    return MFG_OK;
}
