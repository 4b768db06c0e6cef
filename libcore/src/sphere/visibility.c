/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* visibility.c - visibility maps VM(P) = { d : d.p >= 0 } of a Gaussian map P on the unit
 * sphere (Ha 2001, seed 000 section 3), with every combinatorial decision exact. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "sphere/sphere.h"

/* The inscribed cap of a cone (its quick inside test): the angular radius of its centre's
 * nearest side shrunk by CAP_IN_SHRINK (relative) and CAP_IN_MARGIN rad for the rounding
 * of asin and the unit vectors, kept only when above CAP_IN_MIN rad (else no use). */
#define CAP_IN_SHRINK 1e-6
#define CAP_IN_MARGIN 1e-9
#define CAP_IN_MIN 1e-5
/* Rounding of a corner on its own two circles (dot products of unit vectors, ~1e-16). */
#define CORNER_SLACK 1e-13
/* A loop winds once around a centre when its turning angle is 2 pi within this. */
#define TURN_TOL 1e-6
/* A cone's draft cap is sampled a hair inside its radius; the sine the sample step
 * divides by is kept above MIN_SIN. */
#define CAP_INSIDE 1e-12
#define MIN_SIN 1e-12

/*
 * VM(P) is the dual of the cone C spanned by P.  The paper decides its kind with two
 * 2-variable LPs and a smallest enclosing sphere, then runs a Graham scan on the sphere;
 * those steps are floating-point and need tolerances for the degenerate kinds.  Here the
 * cone itself is grown incrementally (points in a fixed pseudo-random order) and every
 * test is an exact sign on the input doubles (orient3, cross_dot, parallel3), so:
 *  - C stays pointed (inside an open hemisphere) as long as no new normal p has -p in
 *    the current cone; its hull is a ray (VM = hemisphere), a wedge (VM = lune) or a
 *    convex polygon u_0..u_k-1 (VM vertices v_i = u_i x u_i+1, the paper's duality);
 *  - once p and -p are both in C, VM lies on the great circle GC(p), and the same
 *    incremental game is played in the plane orthogonal to p (the paper's 2-D LP on
 *    g^c): the projected cone is a ray (VM = half circle), a wedge (shorter arc), a
 *    line (two antipodal points), a half-plane (one point) or everything (NULL).
 * A point inside a cap inscribed in the current hull is skipped after one dot product;
 * the others cost O(h) exact orientation tests while the hull is small.  A large hull
 * (a finely tessellated cone has one vertex per normal) grows in batches merged in the
 * gnomonic projection about an exactly verified centre (see "Many hull vertices"), so
 * the whole costs O(m log m).
 */

typedef const double *vref; /* a normal: points into the caller's array */

enum cone_state { CONE_EMPTY, CONE_RAY, CONE_WEDGE, CONE_HULL, CONE_LINE };

typedef struct cone3 {
    enum cone_state state;
    vref a, b;   /* ray: a; wedge: from a counter-clockwise to b (about a x b) */
    vref *h;     /* hull vertices, counter-clockwise seen from outside */
    int *o;      /* scratch: orientation of p against each hull edge */
    vref *tmp;   /* scratch for rebuilding the hull */
    int64_t nh, cap;
    vref q;      /* CONE_LINE: q and -q both lie in the cone */
    double c[3], cos2_in; /* inscribed cap, cos^2 of its radius (floating point, only to
                           * skip inside points) */
    int have_cap;
} cone3;

static mfg_status hull_reserve(cone3 *k, int64_t n)
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
static void update_cap(cone3 *k)
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
static int in_inscribed_cap(const cone3 *k, vref p)
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
static mfg_status hull_add(cone3 *k, vref p)
{
    if (in_inscribed_cap(k, p) || in_fan_triangle(k, p))
        return MFG_OK;
    int64_t n = k->nh, neg = 0, pos = 0;
    mfg_status st = hull_reserve(k, n + 2);
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
    update_cap(k);
    return MFG_OK;
}

/* Adds p to a cone in state EMPTY, RAY or WEDGE. */
static mfg_status low_add(cone3 *k, vref p)
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
            mfg_status st = hull_reserve(k, 3);
            if (st != MFG_OK)
                return st;
            k->h[0] = o > 0 ? k->a : k->b;
            k->h[1] = o > 0 ? k->b : k->a;
            k->h[2] = p;
            k->nh = 3;
            k->state = CONE_HULL;
            update_cap(k);
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

/* ---- The degenerate case: VM on the great circle GC(q) ---------------------------- */

enum flat_state { FLAT_EMPTY, FLAT_RAY, FLAT_WEDGE, FLAT_LINE, FLAT_HALF, FLAT_PLANE };

typedef struct flat_cone {
    enum flat_state state;
    vref a, b; /* ray a; wedge a .. b counter-clockwise about q; line / half-plane a */
    int side;  /* FLAT_HALF: the side (sign of det[q, a, p]) that the cone occupies */
} flat_cone;

/* Adds p (not parallel to q) to the cone of projections onto the plane orthogonal to q.
 * det[q, x, y] is the exact 2-D orientation of the projections of x and y, and
 * (q x x).(q x y) the sign of their dot product. */
static void flat_add(flat_cone *f, vref q, vref p)
{
    switch (f->state) {
    case FLAT_EMPTY:
        f->a = p;
        f->state = FLAT_RAY;
        break;
    case FLAT_RAY: {
        int o = mfg_orient3(q, f->a, p);
        if (o == 0) {
            if (mfg_cross_dot_sign(q, f->a, q, p) < 0)
                f->state = FLAT_LINE;
        } else {
            f->b = o > 0 ? p : f->a;
            f->a = o > 0 ? f->a : p;
            f->state = FLAT_WEDGE;
        }
        break;
    }
    case FLAT_WEDGE: {
        int s1 = mfg_orient3(q, f->a, p), s2 = mfg_orient3(q, p, f->b);
        if (s1 >= 0 && s2 >= 0)
            break;
        if (s1 <= 0 && s2 <= 0) { /* -p in the wedge: the cone holds the line of p */
            int sa = mfg_orient3(q, p, f->a), sb = mfg_orient3(q, p, f->b);
            if (sa >= 0 && sb >= 0) {
                f->side = 1;
            } else if (sa <= 0 && sb <= 0) {
                f->side = -1;
            } else {
                f->state = FLAT_PLANE;
                break;
            }
            f->a = p;
            f->state = FLAT_HALF;
        } else if (s1 < 0) {
            f->a = p;
        } else {
            f->b = p;
        }
        break;
    }
    case FLAT_LINE: {
        int o = mfg_orient3(q, f->a, p);
        if (o != 0) {
            f->side = o;
            f->state = FLAT_HALF;
        }
        break;
    }
    case FLAT_HALF: {
        int o = mfg_orient3(q, f->a, p);
        if (o != 0 && o != f->side)
            f->state = FLAT_PLANE;
        break;
    }
    case FLAT_PLANE:
        break;
    }
}

/* ---- Output ------------------------------------------------------------------------ */

static mfg_status spoly_new(int kind, int64_t n, mfg_spoly **out)
{
    mfg_spoly *s = calloc(1, sizeof *s);
    if (!s)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate a result");
    s->kind = kind;
    s->nvertices = n;
    if (n > 0) {
        s->vertices = malloc((size_t)n * 3 * sizeof(double));
        if (!s->vertices) {
            free(s);
            return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld vertices", (long long)n);
        }
    }
    *out = s;
    return MFG_OK;
}

void mfg_spoly_free(mfg_spoly *poly)
{
    if (!poly)
        return;
    free(poly->vertices);
    free(poly);
}

static void set_vertex(mfg_spoly *s, int64_t i, const double v[3])
{
    s->vertices[3 * i] = v[0];
    s->vertices[3 * i + 1] = v[1];
    s->vertices[3 * i + 2] = v[2];
}

/* A unit vector orthogonal to unit a (the larger of two candidate crosses). */
static void any_orthogonal(const double a[3], double out[3])
{
    double ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0}, t[3];
    mfg_cross3(a, fabs(a[0]) < fabs(a[1]) ? ex : ey, t);
    mfg_unit3(t, out);
}

/* Three points 120 degrees apart on GC(a), counter-clockwise about a. */
static void great_circle_triangle(const double a[3], double w[3][3])
{
    double au[3], e1[3], e2[3];
    mfg_unit3(a, au);
    any_orthogonal(au, e1);
    mfg_cross3(au, e1, e2);
    for (int k = 0; k < 3; k++) {
        double c = cos(2.0 * MFG_PI * k / 3.0), s = sin(2.0 * MFG_PI * k / 3.0);
        for (int i = 0; i < 3; i++)
            w[k][i] = c * e1[i] + s * e2[i];
    }
}

/* The map of a pointed cone (ray, wedge or hull): always a POLYGON. */
static mfg_status polygon_from_cone(const cone3 *k, mfg_spoly **out)
{
    mfg_status st;
    if (k->state == CONE_RAY) { /* a hemisphere */
        double w[3][3];
        great_circle_triangle(k->a, w);
        if ((st = spoly_new(MFG_VM_POLYGON, 3, out)) != MFG_OK)
            return st;
        for (int i = 0; i < 3; i++)
            set_vertex(*out, i, w[i]);
        return MFG_OK;
    }
    if (k->state == CONE_WEDGE) { /* a lune: HS(a) and HS(b) */
        double au[3], bu[3], n[3], c1[3], c2[3], ma[3], mb[3];
        mfg_unit3(k->a, au);
        mfg_unit3(k->b, bu);
        mfg_cross3_accurate(k->a, k->b, n);
        if (!mfg_unit3(n, c1))
            return mfg_fail(MFG_ERR_INTERNAL, "wedge of parallel normals");
        c2[0] = -c1[0], c2[1] = -c1[1], c2[2] = -c1[2];
        /* midpoint of the half circle on GC(a) lies towards b, and vice versa:
         * c1 x a is on GC(a) and (c1 x a).b = det[c1, a, b] > 0 for c1 = a x b. */
        double t[3];
        mfg_cross3(c1, au, t);
        mfg_unit3(t, ma);
        mfg_cross3(bu, c1, t);
        mfg_unit3(t, mb);
        if ((st = spoly_new(MFG_VM_POLYGON, 4, out)) != MFG_OK)
            return st;
        /* Counter-clockwise: c1 -> mb -> c2 -> ma keeps a+b on the left (checked in
         * the tests against the definition). */
        set_vertex(*out, 0, c1);
        set_vertex(*out, 1, mb);
        set_vertex(*out, 2, c2);
        set_vertex(*out, 3, ma);
        return MFG_OK;
    }
    /* Hull u_0..u_k-1: VM vertex between GC(u_i) and GC(u_i+1) is u_i x u_i+1. */
    if ((st = spoly_new(MFG_VM_POLYGON, k->nh, out)) != MFG_OK)
        return st;
    for (int64_t i = 0; i < k->nh; i++) {
        double v[3], vu[3];
        mfg_cross3_accurate(k->h[i], k->h[(i + 1) % k->nh], v);
        if (!mfg_unit3(v, vu)) {
            mfg_spoly_free(*out);
            *out = NULL;
            return mfg_fail(MFG_ERR_INTERNAL, "coincident hull vertices");
        }
        set_vertex(*out, i, vu);
    }
    return MFG_OK;
}

/* The map when q and -q are in the cone: a subset of GC(q). */
static mfg_status map_on_great_circle(const double *normals, int64_t m, vref q,
                                      mfg_spoly **out)
{
    flat_cone f = {FLAT_EMPTY, NULL, NULL, 0};
    for (int64_t i = 0; i < m && f.state != FLAT_PLANE; i++) {
        vref p = normals + 3 * i;
        if (mfg_parallel3(q, p) == 0)
            flat_add(&f, q, p);
    }
    double qu[3], t[3], s[3], e[3], mid[3];
    mfg_unit3(q, qu);
    mfg_status st;
    switch (f.state) {
    case FLAT_EMPTY: { /* every normal is +-q: the whole great circle */
        double w[3][3];
        great_circle_triangle(qu, w);
        if ((st = spoly_new(MFG_VM_EDGE, 3, out)) != MFG_OK)
            return st;
        (*out)->closed = 1;
        for (int i = 0; i < 3; i++)
            set_vertex(*out, i, w[i]);
        return MFG_OK;
    }
    case FLAT_RAY:   /* half circle centred on the projection of a */
    case FLAT_WEDGE: /* arc from b' turned -90 degrees to a' turned +90 degrees */
    {
        vref lo = f.state == FLAT_RAY ? f.a : f.b; /* start = -(q x lo) */
        vref hi = f.a;                             /* end = q x hi */
        double au[3], bu[3];
        mfg_cross3_accurate(q, lo, t);
        mfg_unit3(t, s);
        mfg_neg3(s, s);
        mfg_cross3_accurate(q, hi, t);
        mfg_unit3(t, e);
        /* The arc's midpoint is the bisector of the projections of a and b. */
        mfg_cross3(t, qu, au); /* (q x a) x q: projection of a, up to scale */
        mfg_unit3(au, au);
        mfg_cross3_accurate(q, lo, t);
        mfg_cross3(t, qu, bu);
        mfg_unit3(bu, bu);
        /* The bisector cancels when the wedge is nearly a half-plane (its projections a'
         * and b' all but antipodal; the fuzz case: normals of sizes 2^37 and 2^-23): the
         * arc is then short and its midpoint is that of its ends.  Of the two sums,
         * |a' + b'| = 2 sin(L/2) and |s + e| = 2 cos(L/2) for an arc of length L, one
         * is at least sqrt 2 (a half circle, L = pi, has s = -e). */
        double sum[3] = {au[0] + bu[0], au[1] + bu[1], au[2] + bu[2]};
        double ends[3] = {s[0] + e[0], s[1] + e[1], s[2] + e[2]};
        if (mfg_dot3(ends, ends) > mfg_dot3(sum, sum))
            memcpy(sum, ends, sizeof sum);
        if (!mfg_unit3(sum, mid))
            return mfg_fail(MFG_ERR_INTERNAL, "degenerate arc");
        if ((st = spoly_new(MFG_VM_EDGE, 3, out)) != MFG_OK)
            return st;
        set_vertex(*out, 0, s);
        set_vertex(*out, 1, mid);
        set_vertex(*out, 2, e);
        return MFG_OK;
    }
    case FLAT_LINE: /* all projections on one line: both poles of that plane */
    case FLAT_HALF: /* a half-plane: the pole on its side */
    {
        mfg_cross3_accurate(q, f.a, t);
        mfg_unit3(t, s);
        int sign = f.state == FLAT_HALF ? f.side : 1;
        s[0] *= sign, s[1] *= sign, s[2] *= sign;
        int64_t n = f.state == FLAT_LINE ? 2 : 1;
        if ((st = spoly_new(MFG_VM_POINT, n, out)) != MFG_OK)
            return st;
        set_vertex(*out, 0, s);
        if (n == 2) {
            double ns[3];
            mfg_neg3(s, ns);
            set_vertex(*out, 1, ns);
        }
        return MFG_OK;
    }
    case FLAT_PLANE:
        break;
    }
    return spoly_new(MFG_VM_NULL, 0, out);
}

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
        any_orthogonal(u, e1);
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
        any_orthogonal(uj, e1);
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

static mfg_status apply_draft(const cone3 *k, double draft, mfg_spoly **map)
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
        st = spoly_new(n >= 3 ? MFG_VM_POLYGON : MFG_VM_NULL, n >= 3 ? n : 0, &res);
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

/* Directions closer than this are one vertex of the output polygon. */
#define MERGE_ANGLE 1e-13

static int nearly_same(vref a, vref b)
{
    double c[3], au[3], bu[3];
    mfg_unit3(a, au);
    mfg_unit3(b, bu);
    mfg_cross3_accurate(au, bu, c);
    return sqrt(mfg_dot3(c, c)) < MERGE_ANGLE && mfg_dot3(au, bu) > 0;
}

/* Normals that differ by rounding only (p and 3.0*p, say) are distinct for the exact
 * hull, and the map vertex between them lies where two all-but-identical great circles
 * cross, anywhere along them.  For the output, such hull neighbours are merged (the map
 * moves by less than MERGE_ANGLE); the kind was decided exactly before. */
static void merge_near_duplicates(cone3 *k)
{
    if (k->state == CONE_HULL) {
        int64_t m = 0;
        for (int64_t i = 0; i < k->nh; i++)
            if (m == 0 || !nearly_same(k->h[m - 1], k->h[i]))
                k->h[m++] = k->h[i];
        while (m > 1 && nearly_same(k->h[m - 1], k->h[0]))
            m--;
        k->nh = m;
        if (m == 2) {
            k->a = k->h[0];
            k->b = k->h[1];
            k->state = CONE_WEDGE;
        } else if (m == 1) {
            k->a = k->h[0];
            k->state = CONE_RAY;
        }
    }
    if (k->state == CONE_WEDGE && nearly_same(k->a, k->b))
        k->state = CONE_RAY;
}

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
#define SMALL_HULL 48
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
    /* The frame is turned by an odd angle (1 rad) from the one any_orthogonal picks: a
     * cone about a coordinate axis, listed symmetrically, would otherwise give pairs of
     * normals with the same x up to rounding, each pair an exact comparison. */
    double a[3], b[3];
    any_orthogonal(f->c, a);
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
            if ((st = hull_reserve(k, nh + 2)) != MFG_OK)
                return st;
            memcpy(k->h, w->chain, (size_t)nh * sizeof(vref));
            k->nh = nh;
            update_cap(k);
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
        if ((st = hull_add(k, w->pend[i])) != MFG_OK)
            return st;
    return MFG_OK;
}

/* Continues the incremental game in batches once the hull is large: the normals from
 * step on in the scrambled order (index idx, stride), each batch three times the number
 * of normals already seen; normals inside the hull's inscribed cap are skipped first. */
static mfg_status grow_in_batches(cone3 *k, const double *normals, int64_t m, int64_t step,
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
            if (!in_inscribed_cap(k, p))
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

/* ---- Entry point ---------------------------------------------------------------------- */

mfg_status mfg_visibility_map(const double *normals, int64_t m, double draft_angle,
                              mfg_spoly **out_map)
{
    if (!out_map)
        return mfg_fail(MFG_ERR_NULL, "out_map is NULL");
    if (m < 0 || m > MFG_MAX_COUNT) /* a count no caller's array can have */
        return mfg_fail(MFG_ERR_INVALID, "m must be between 0 and %lld (got %lld)",
                        (long long)MFG_MAX_COUNT, (long long)m);
    if (m == 0)
        return mfg_fail(MFG_ERR_DEGENERATE, "no normals (m = %lld)", (long long)m);
    if (!normals)
        return mfg_fail(MFG_ERR_NULL, "normals is NULL");
    if (!(draft_angle >= 0.0 && draft_angle < MFG_PI / 2))
        return mfg_fail(MFG_ERR_INVALID, "draft angle must be in [0, pi/2) radians (got %g)",
                        draft_angle);
    for (int64_t i = 0; i < m; i++) {
        const double *p = normals + 3 * i;
        for (int c = 0; c < 3; c++)
            if (!mfg_coord_ok(p[c]))
                return mfg_fail(MFG_ERR_INVALID,
                                "normal %lld has a NaN, infinite or out-of-range component (%g; allowed: 0 or 2^-200 <= |x| <= 2^200)",
                                (long long)i, p[c]);
        if (p[0] == 0.0 && p[1] == 0.0 && p[2] == 0.0)
            return mfg_fail(MFG_ERR_INVALID, "normal %lld is the zero vector", (long long)i);
    }

    cone3 k;
    memset(&k, 0, sizeof k);
    mfg_status st = MFG_OK;
    int64_t stride = mfg_scramble_stride(m), idx = 0;
    for (int64_t step = 0; step < m && st == MFG_OK && k.state != CONE_LINE; step++) {
        if (k.state == CONE_HULL && k.nh > SMALL_HULL) {
            st = grow_in_batches(&k, normals, m, step, idx, stride);
            break;
        }
        vref p = normals + 3 * idx;
        idx += stride;
        if (idx >= m)
            idx -= m;
        st = k.state == CONE_HULL ? hull_add(&k, p) : low_add(&k, p);
    }
    mfg_spoly *map = NULL;
    if (st == MFG_OK && k.state != CONE_LINE)
        merge_near_duplicates(&k);
    if (st == MFG_OK) {
        if (k.state == CONE_LINE)
            st = map_on_great_circle(normals, m, k.q, &map);
        else
            st = polygon_from_cone(&k, &map);
    }
    if (st == MFG_OK && draft_angle > 0.0) {
        if (map->kind == MFG_VM_POLYGON) {
            st = apply_draft(&k, draft_angle, &map);
        } else { /* a degenerate map has no direction strictly inside every hemisphere */
            mfg_spoly_free(map);
            map = NULL;
            st = spoly_new(MFG_VM_NULL, 0, &map);
        }
    }
    free(k.h);
    free(k.o);
    free(k.tmp);
    if (st != MFG_OK) {
        mfg_spoly_free(map);
        return st;
    }
    *out_map = map;
    mfg_clear_error();
    return MFG_OK;
}
