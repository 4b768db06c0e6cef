/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/turn.c - Turning points: the steps of the polylines, the points R(t_i) v of the
 * chords and the apexes M_i v of the tangents, each made once and snapped to the
 * arrangement's grid (so every predicate on the soup is exact; the snap moves a point by
 * at most 2^-51 of the unit extent). */
#include "sweep/envelope.h"

double sw_snap(double x)
{
    return ldexp(nearbyint(ldexp(x, ARR_GRID_LOG2)), -ARR_GRID_LOG2);
}

int64_t sw_add_vertex(sw_env *e, const double p[3])
{
    if (e->nv >= e->capv) {
        int64_t cap = mfg_grown_cap(e->capv, e->nv + 1, 1024);
        double *n = realloc(e->x, (size_t)cap * 3 * sizeof *n);
        if (!n)
            return -1;
        e->x = n;
        e->capv = cap;
    }
    for (int k = 0; k < 3; k++)
        e->x[3 * e->nv + k] = sw_snap(p[k]);
    return e->nv++;
}

/* p split into its part along the unit axis and the rest, and kh x p. */
static void split_axis(const sw_env *e, const double p[3], double par[3], double perp[3],
                       double side[3])
{
    double a = mfg_dot3(e->kh, p);
    for (int k = 0; k < 3; k++) {
        par[k] = e->kh[k] * a;
        perp[k] = p[k] - par[k];
    }
    mfg_cross3(e->kh, p, side);
}

double sw_radius(const sw_env *e, const double p[3])
{
    double par[3], perp[3], side[3];
    split_axis(e, p, par, perp, side);
    return mfg_norm3(perp);
}

/* cos and sin of t, exactly 0 / +-1 next to the quarter turns. */
static void trig(double t, double *c, double *s)
{
    *c = cos(t);
    *s = sin(t);
    if (fabs(*c) < SW_TRIG_SNAP) {
        *c = 0;
        *s = *s > 0 ? 1 : -1;
    } else if (fabs(*s) < SW_TRIG_SNAP) {
        *s = 0;
        *c = *c > 0 ? 1 : -1;
    }
}

/* p turned by angle t and scaled away from the axis by f (1 for a chord point). */
static void turn(const sw_env *e, const double p[3], double t, double f, double out[3])
{
    double par[3], perp[3], side[3], c, s;
    split_axis(e, p, par, perp, side);
    trig(t, &c, &s);
    for (int k = 0; k < 3; k++)
        out[k] = par[k] + f * (c * perp[k] + s * side[k]);
}

/* ---- The steps --------------------------------------------------------------------------- */

/* Vertices within this of each other in (distance from the axis, height along it) are
 * turns of one another (unit scale; CAD copies of a feature agree far better). */
#define SYM_RZ 0x1p-30
/* An angle between two such vertices is a multiple of 2 pi / m when it is within this
 * many turns of one. */
#define SYM_ANGLE 1e-7
/* The most-fold symmetry looked for (beyond it the steps would have to be too fine). */
#define SYM_MAX 360

typedef struct rzphi {
    double r, z, phi;
    int64_t zc, rc; /* the run of heights, then of distances within it, this one is in */
} rzphi;

static int cmp_z(const void *pa, const void *pb)
{
    const rzphi *a = pa, *b = pb;
    if (a->z != b->z)
        return a->z < b->z ? -1 : 1;
    return (a->phi > b->phi) - (a->phi < b->phi);
}

static int cmp_zc_r(const void *pa, const void *pb)
{
    const rzphi *a = pa, *b = pb;
    if (a->zc != b->zc)
        return a->zc < b->zc ? -1 : 1;
    if (a->r != b->r)
        return a->r < b->r ? -1 : 1;
    return (a->phi > b->phi) - (a->phi < b->phi);
}

/* The input's vertices off the axis as (distance from it, height along it, angle about
 * it), grouped by height and distance (runs of values at most apart): malloc'd *out (NULL
 * when out of memory), their count returned. */
static int64_t rz_records(const sw_env *e, double apart, rzphi **out)
{
    rzphi *v = malloc((size_t)(e->nin + 1) * sizeof *v);
    *out = v;
    if (!v)
        return 0;
    double ref[3] = {1, 0, 0};
    if (fabs(e->kh[0]) > 0.9)
        ref[0] = 0, ref[1] = 1;
    double u1[3], u2[3];
    mfg_cross3(e->kh, ref, u1);
    mfg_unit3(u1, u1);
    mfg_cross3(e->kh, u1, u2);
    int64_t n = 0;
    for (int64_t i = 0; i < e->nin; i++) {
        const double *p = e->x + 3 * i;
        double r = sw_radius(e, p);
        if (r < SW_ON_AXIS)
            continue;
        v[n].r = r;
        v[n].z = mfg_dot3(e->kh, p);
        v[n].phi = atan2(mfg_dot3(p, u2), mfg_dot3(p, u1));
        n++;
    }
    /* runs of heights no farther than apart, then of distances within each: sorted
     * by height and distance at once, two rings at one height (a torus about its own
     * axis) interleave when their heights carry noise, and no group is whole */
    if (n > 1)
        qsort(v, (size_t)n, sizeof *v, cmp_z);
    for (int64_t i = 0; i < n; i++)
        v[i].zc = i > 0 && v[i].z - v[i - 1].z <= apart ? v[i - 1].zc : i;
    if (n > 1)
        qsort(v, (size_t)n, sizeof *v, cmp_zc_r);
    for (int64_t i = 0; i < n; i++)
        v[i].rc = i > 0 && v[i].zc == v[i - 1].zc && v[i].r - v[i - 1].r <= apart ? v[i - 1].rc : i;
    return n;
}

/* Records i .. j - 1 of a sorted rz_records array: one (distance, height) group. */
static int64_t rz_group_end(const rzphi *v, int64_t n, int64_t i)
{
    int64_t j = i + 1;
    while (j < n && v[j].rc == v[i].rc)
        j++;
    return j;
}

/* The order m of the part's symmetry about the axis as its vertices show it: the smallest
 * m <= SYM_MAX such that any two vertices at the same distance from the axis and height
 * along it lie a multiple of 2 pi / m apart (1 when no vertices pair up, 0 when some do
 * but no such m exists).  Strips of symmetric contour edges then coincide exactly when the
 * steps are multiples of 2 pi / m (their points are welded, surface.c); otherwise they
 * are polyhedral copies of one surface in different phases, which cross everywhere. */
static int symmetry_order(const rzphi *v, int64_t n)
{
    if (!v)
        return 1; /* only an optimisation */
    /* the angle differences within groups, as fractions of a turn */
    double *diff = malloc((size_t)(n + 1) * sizeof *diff);
    int64_t nd = 0;
    if (!diff)
        return 1;
    for (int64_t i = 0; i < n;) {
        int64_t j = rz_group_end(v, n, i);
        for (int64_t k = i + 1; k < j; k++) {
            double f = (v[k].phi - v[i].phi) / MFG_TWO_PI;
            diff[nd++] = f - floor(f);
        }
        i = j;
    }
    int m = nd == 0 ? 1 : 0;
    for (int cand = 2; cand <= SYM_MAX && m == 0; cand++) {
        int ok = 1;
        for (int64_t i = 0; i < nd && ok; i++) {
            double x = diff[i] * cand;
            ok = fabs(x - nearbyint(x)) < SYM_ANGLE * cand;
        }
        if (ok)
            m = cand;
    }
    free(diff);
    return m;
}

/* A triangle's key: its vertices rotated to the smallest first (orientation kept). */
static hkey tri_key(int64_t a, int64_t b, int64_t c)
{
    if (b < a && b < c)
        return mkkey(b, c, a, 1);
    if (c < a && c < b)
        return mkkey(c, a, b, 1);
    return mkkey(a, b, c, 1);
}

/* 1 when the turns by 2 pi k / m map the part's surface onto itself: every input vertex
 * onto one within h, every triangle onto a triangle of the same orientation; 0 when not
 * (or out of memory: only a shortcut).  The vertex symmetry (symmetry_order) is not
 * enough: a symmetric point set can carry a surface that is not.  Every k, not only
 * k = 1: each vertex's orbit under the vertex map is followed round, its k-th member
 * within h of the vertex turned by 2 pi k / m (a surface within h of its turn by 2 pi / m
 * may drift by h at each turn, a twisted one), so the turned surfaces all lie within h
 * of the part. */
static int surface_symmetric(const sw_env *e, const hmap *tris, int m, double h)
{
    int64_t n = e->nin;
    int64_t *next = malloc((size_t)(n + 1) * sizeof *next), *img = malloc((size_t)(n + 1) * sizeof *img);
    hmap grid = {0};
    int ok = next && img && hmap_init(&grid, n + 1);
    for (int64_t v = 0; ok && v < n; v++) {
        hkey key = hmap_cell_key(e->x + 3 * v, h, 13);
        next[v] = hmap_get(&grid, &key);
        ok = hmap_put(&grid, &key, v);
    }
    for (int64_t v = 0; ok && v < n; v++) {
        double q[3];
        turn(e, e->x + 3 * v, MFG_TWO_PI / m, 1.0, q);
        img[v] = -1;
        for (int d = 0; d < 27 && img[v] < 0; d++) {
            hkey key = hmap_cell_key(q, h, d);
            for (int64_t w = hmap_get(&grid, &key); w >= 0 && img[v] < 0; w = next[w]) {
                const double *x = e->x + 3 * w;
                if (fabs(x[0] - q[0]) <= h && fabs(x[1] - q[1]) <= h && fabs(x[2] - q[2]) <= h)
                    img[v] = w;
            }
        }
        ok = img[v] >= 0;
    }
    /* the orbits: next[] is free now, it marks the vertices already on one */
    for (int64_t v = 0; ok && v < n; v++)
        next[v] = 0;
    for (int64_t v = 0; ok && v < n; v++) {
        if (next[v])
            continue;
        int64_t w = v;
        for (int k = 1; ok && k <= m; k++) {
            w = img[w];
            next[w] = 1;
            double q[3];
            turn(e, e->x + 3 * v, MFG_TWO_PI * k / m, 1.0, q);
            const double *x = e->x + 3 * w;
            ok = fabs(x[0] - q[0]) <= h && fabs(x[1] - q[1]) <= h && fabs(x[2] - q[2]) <= h;
        }
        ok = ok && w == v;
    }
    for (int64_t t = 0; ok && t < e->nt; t++) {
        const int64_t *V = e->tri + 3 * t;
        hkey key = tri_key(img[V[0]], img[V[1]], img[V[2]]);
        ok = hmap_get(tris, &key) >= 0;
    }
    hmap_free(&grid);
    free(next);
    free(img);
    return ok;
}

/* The largest d such that the turn by 2 pi / d <= theta maps the part onto itself (0:
 * none).  Then SV(theta) = SV(2 pi / d) = the solid of revolution: any t in [0, theta] is
 * 2 pi k / d + s with s in [0, 2 pi / d), and R(t) O = R(s) O.  The sweep by theta itself
 * would meet the turned copies of each face and strip as nearly coincident sheets in other
 * phases, crossing everywhere (a regular octahedron about its threefold axis by 4.29 or 6
 * rad was refused: the rounding passes multiplied; the fuzzer).  The turns that can map
 * the part onto itself take a vertex to one at the same distance and height: the
 * candidates are the angles from a vertex of the smallest such group to the others (a
 * rectangle's corners are two orbits of its half turn, so not every angle within a group
 * is a symmetry), each 2 pi / d for a whole d.  The surface is checked to within
 * SW_SHARE_PUSH tol (the shares' headroom: the sweep of a surface that far from symmetric
 * is that far from SV). */
static int symmetric_period(const sw_env *e, const rzphi *v, int64_t n, double h)
{
    if (!v || n < 2)
        return 0;
    int64_t best = -1, bestn = 0;
    for (int64_t i = 0; i < n;) {
        int64_t j = rz_group_end(v, n, i);
        if (j - i >= 2 && (best < 0 || j - i < bestn)) {
            best = i;
            bestn = j - i;
        }
        i = j;
    }
    if (best < 0)
        return 0;
    /* the triangles by their vertices, for the candidates' checks (out of memory: no
     * symmetry, only a shortcut) */
    hmap tris;
    if (!hmap_init(&tris, e->nt + 1))
        return 0;
    for (int64_t t = 0; t < e->nt; t++) {
        const int64_t *V = e->tri + 3 * t;
        hkey key = tri_key(V[0], V[1], V[2]);
        if (!hmap_put(&tris, &key, t)) {
            hmap_free(&tris);
            return 0;
        }
    }
    int found = 0;
    /* the angle may be off by the vertices' own deviation: h at distance r */
    double slack = fmax(SYM_ANGLE, h / (MFG_TWO_PI * fmax(v[best].r, SW_ON_AXIS)));
    for (int64_t k = best + 1; k < best + bestn; k++) {
        double f = (v[k].phi - v[best].phi) / MFG_TWO_PI;
        f -= floor(f);
        double d = f > 0 ? nearbyint(1 / f) : 0;
        if (d > found && d <= SYM_MAX && fabs(f * d - 1) < slack * d &&
            e->theta >= MFG_TWO_PI / d && surface_symmetric(e, &tris, (int)d, h))
            found = (int)d;
    }
    hmap_free(&tris);
    return found;
}

void sw_setup_steps(sw_env *e)
{
    double len = mfg_norm3(e->k);
    for (int k = 0; k < 3; k++)
        e->kh[k] = e->k[k] / len;
    /* a coordinate axis stays exact (the rounded division may already be, but make
     * sure: the turned faces of a box about its own axis stay in their planes) */
    for (int k = 0; k < 3; k++)
        if (e->k[(k + 1) % 3] == 0 && e->k[(k + 2) % 3] == 0) {
            e->kh[k] = e->k[k] > 0 ? 1 : -1;
            e->kh[(k + 1) % 3] = e->kh[(k + 2) % 3] = 0;
        }
    e->theta = e->theta_asked; /* a build before this one may have made it a full turn */
    e->tol = e->tol_asked;
    e->full_turn = e->theta >= MFG_TWO_PI;
    e->rmax = 0;
    for (int64_t v = 0; v < e->nin; v++)
        e->rmax = fmax(e->rmax, sw_radius(e, e->x + 3 * v));
    /* An angle short of a full turn by less than the push's share of the tolerance at
     * rmax is a full turn: the full sweep holds SV(theta) and no point of it is farther
     * from SV(theta) than the missing arc (rmax (2 pi - theta)), while a sweep to
     * 2 pi - 1e-9 would meet its own start face at t = 0 as a nearly coplanar sheet all
     * round (the battery's octahedron and frame at 2 pi - 1e-9: no result in 60 s). */
    if (!e->full_turn && (MFG_TWO_PI - e->theta) * e->rmax <= SW_SHARE_PUSH * e->tol) {
        e->full_turn = 1;
        e->theta = MFG_TWO_PI;
    }
    /* a part with a d-fold symmetry swept by 2 pi / d or more: its builds sweep it by
     * 2 pi / d, the last one in the axis frame revolves it (both are SV; a torus about
     * its own axis was refused as a revolution, and with 1e-9 of noise on its vertices
     * the revolution ran for minutes; a regular octahedron about its threefold axis by
     * 4.29 rad was refused as a sweep by that angle) */
    rzphi *rz;
    int64_t nrz = rz_records(e, SYM_RZ, &rz);
    int d = symmetric_period(e, rz, nrz, fmin(SW_SHARE_PUSH * e->tol, SYM_RZ));
    if (d >= 2) {
        e->full_turn = e->attempt == SW_ATTEMPTS - 1 && !e->caller_first;
        e->theta = e->full_turn ? MFG_TWO_PI : MFG_TWO_PI / d;
    } else if (!e->full_turn) {
        /* Nearly symmetric: every turn by 2 pi k / d maps the surface within
         * h = SW_SHARE_PUSH tol of itself (a surface of revolution tessellated with noise,
         * from a float STL: a shaft about its own axis), theta >= 2 pi / d.  Then any
         * R(t) p, t = 2 pi k / d + s with s < 2 pi / d, is R(s) of a point within h of
         * the part, so the solid of revolution holds SV(theta) and lies within h of it:
         * the part is revolved at tol - h.  Swept by theta, every face of such a surface
         * is nearly neutral to the motion, and the strips of its contour lie on the
         * surface itself (a 36 x 18 torus with 1e-6 of noise about its own axis by 90
         * degrees ran over 200 s; revolved: 4 s).  The exactly symmetric part keeps the
         * period above (its revolution has folds on flat rings). */
        rzphi *near;
        double h = SW_SHARE_PUSH * e->tol;
        int64_t nnear = rz_records(e, h, &near);
        if (symmetric_period(e, near, nnear, h) >= 2) {
            e->full_turn = 1;
            e->theta = MFG_TWO_PI;
            e->tol = e->tol_asked - h;
        }
        free(near);
    }
    int m = symmetry_order(rz, nrz);
    free(rz);
    e->symmetry = m;
    /* the apex height r (sec(delta/2) - 1) within its share of the tolerance at rmax */
    double step = MFG_PI / 2;
    if (e->rmax > 0) {
        /* a full turn revolves the profile grown by SW_SHARE_APEX tol (profile.c), whose
         * radii reach rmax + 1.082 of that: the chords' sag there within the growth */
        double r = e->full_turn ? e->rmax + e->tol : e->rmax;
        double sec = 1 + SW_SHARE_APEX * e->tol / r;
        step = fmin(step, 2 * acos(1 / sec));
    }
    /* steps of 2 pi / (m q) for a part with an m-fold symmetry about the axis: the last
     * step ends at theta and may be shorter */
    if (m >= 2) {
        double q = ceil(MFG_TWO_PI / (m * step)) + e->attempt;
        e->delta = MFG_TWO_PI / (m * q);
        double n = ceil(e->theta / e->delta * (1 - 1e-12));
        e->nsteps = n < 1 ? 1 : (int)n;
        if (e->full_turn)
            e->delta = MFG_TWO_PI / e->nsteps;
    } else {
        double n = ceil(e->theta / step) + e->attempt;
        e->nsteps = n < 1 ? 1 : (int)n;
        e->delta = e->theta / e->nsteps;
    }
}

double sw_step_angle(const sw_env *e, int i)
{
    return i >= e->nsteps ? e->theta : i * e->delta;
}

/* Codes of the turned-point map: chord point i is i, apex i is nsteps + 1 + i. */
static int64_t cached(sw_env *e, int64_t v, int64_t code, int apex, int i)
{
    hkey key = mkkey(v, code, 0, 0);
    int64_t id = hmap_get(&e->turned, &key);
    if (id >= 0)
        return id;
    const double *p = e->x + 3 * v;
    double q[3];
    if (sw_radius(e, p) < SW_ON_AXIS) {
        id = v; /* on the axis: a turn leaves it */
    } else {
        if (apex) {
            /* pushed out by a little more than the apex height: a tangent polyline may
             * only move outwards (its strips' fronts face away from the axis), and this
             * tilts the first quad of a strip that leaves its face tangentially (a cut
             * line: the first tangent lies in the face's plane) clear of that plane, so
             * the arrangement never meets the two as nearly coplanar sheets */
            double t0 = sw_step_angle(e, i), t1 = sw_step_angle(e, i + 1);
            double r = sw_radius(e, p);
            turn(e, p, 0.5 * (t0 + t1), 1 / cos(0.5 * (t1 - t0)) + SW_SHARE_PUSH * e->tol / r, q);
        } else {
            turn(e, p, sw_step_angle(e, i), 1, q);
        }
        id = sw_add_vertex(e, q);
        if (id < 0)
            return -1;
    }
    if (!hmap_put(&e->turned, &key, id))
        return -1;
    return id;
}

int64_t sw_chord_point(sw_env *e, int64_t v, int i)
{
    if (i == 0 || (i == e->nsteps && e->full_turn))
        return v;
    return cached(e, v, i, 0, i);
}

int64_t sw_apex_point(sw_env *e, int64_t v, int i)
{
    return cached(e, v, (int64_t)e->nsteps + 1 + i, 1, i);
}

int64_t sw_track_point(sw_env *e, int64_t v, int kind, int j)
{
    if (kind == SW_CHORD)
        return sw_chord_point(e, v, j);
    if (j == 0)
        return v;
    if (j == e->nsteps + 1)
        return sw_chord_point(e, v, e->nsteps);
    return sw_apex_point(e, v, j - 1);
}

int sw_emit(sw_env *e, int64_t a, int64_t b, int64_t c, int64_t g)
{
    if (a == b || b == c || c == a)
        return 1; /* no area: nothing to add to the chain */
    if (e->nst >= e->capst) {
        int64_t cap = mfg_grown_cap(e->capst, e->nst + 1, 1024);
        int64_t *n = realloc(e->st, (size_t)cap * 3 * sizeof *n);
        if (!n)
            return 0;
        e->st = n;
        int64_t *gn = realloc(e->sgroup, (size_t)cap * sizeof *gn);
        if (!gn)
            return 0;
        e->sgroup = gn;
        e->capst = cap;
    }
    e->st[3 * e->nst] = a;
    e->st[3 * e->nst + 1] = b;
    e->st[3 * e->nst + 2] = c;
    e->sgroup[e->nst] = g;
    e->nst++;
    return 1;
}
