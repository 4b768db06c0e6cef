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

#include "sphere/visibility.h"

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
 * gnomonic projection about an exactly verified centre (see visibility_batch.c), so
 * the whole costs O(m log m).
 */


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

mfg_status mfg_vm_spoly_new(int kind, int64_t n, mfg_spoly **out)
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
void mfg_vm_any_orthogonal(const double a[3], double out[3])
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
    mfg_vm_any_orthogonal(au, e1);
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
        if ((st = mfg_vm_spoly_new(MFG_VM_POLYGON, 3, out)) != MFG_OK)
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
        if ((st = mfg_vm_spoly_new(MFG_VM_POLYGON, 4, out)) != MFG_OK)
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
    if ((st = mfg_vm_spoly_new(MFG_VM_POLYGON, k->nh, out)) != MFG_OK)
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
        if ((st = mfg_vm_spoly_new(MFG_VM_EDGE, 3, out)) != MFG_OK)
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
        if ((st = mfg_vm_spoly_new(MFG_VM_EDGE, 3, out)) != MFG_OK)
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
        if ((st = mfg_vm_spoly_new(MFG_VM_POINT, n, out)) != MFG_OK)
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
    return mfg_vm_spoly_new(MFG_VM_NULL, 0, out);
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
            st = mfg_vm_grow_in_batches(&k, normals, m, step, idx, stride);
            break;
        }
        vref p = normals + 3 * idx;
        idx += stride;
        if (idx >= m)
            idx -= m;
        st = k.state == CONE_HULL ? mfg_vm_hull_add(&k, p) : mfg_vm_low_add(&k, p);
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
            st = mfg_vm_apply_draft(&k, draft_angle, &map);
        } else { /* a degenerate map has no direction strictly inside every hemisphere */
            mfg_spoly_free(map);
            map = NULL;
            st = mfg_vm_spoly_new(MFG_VM_NULL, 0, &map);
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
