/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/profile.c - A full turn: SV is the solid of revolution of its profile P, the set of
 * (r, z) whose circle meets O.  Building the envelope for 2 pi would sweep every contour
 * edge all the way round, and the strips of edges hidden inside SV would cross each other
 * on every step (two boxes about an axis through them: half a million crossing points);
 * the profile has only the outline to revolve.
 *
 * P in the half-plane H (angle phi0, coordinates (r, z)): on the circle of a point x the
 * full-turn chain counts w(x) = #arcs = [x in O] + w_2(image of C, x), C the contour (its
 * strip of revolution has, at x, the 2-D winding number of its image).  So P = {w >= 1} for
 * the 2-D chain  boundary(O n H) + image(C):
 *   - the section of O's boundary by the plane of H (a closed curve per crossing, from
 *     the triangles' crossing segments, oriented as the boundary of the section), clipped
 *     to r >= 0 and closed along the axis (each clipped end joined to a point Z0 of the
 *     axis below the part: those axis pieces cancel but where the section covers it);
 *   - each contour edge's image, a convex curve r(s) = |x_perp(s)| over z(s) linear: as
 *     chords (above the curve) where the edge rises along the axis - its strip's front
 *     faces away from the axis - and as tangents (below it) where it falls, so the
 *     polylines lie on the fronts, as the 3-D strips do, and P grows only.
 * The exact arrangement of the 2-D chain (arrange/: arr_chain2d_faces) gives every face of
 * the plane its winding; the faces with w >= 1 are P.  P is then grown by the chords' sag
 * along +r (grown_chain: a second arrangement) and the outline of the grown P', corners
 * between collinear sides dropped, becomes the contour of a full turn: strips.c revolves
 * it by chords alone (no F or B faces, no tangent polylines, no fins).  The result is the
 * image of P's solid of revolution under a radial scaling that depends on the angle only,
 * so it has no self-intersection by construction, and it holds SV (grown_chain says why);
 * the arrangement of the 3-D chain then only confirms that rounding made no crossing. */
#include "sweep/envelope.h"

/* A 2-D segment a -> b of the chain (points on the arrangement's grid). */
typedef struct seg2 {
    double a[2], b[2];
} seg2;

typedef struct prof {
    sw_env *e;
    double u1[3], u2[3]; /* H = {x . u2 = 0, x . u1 >= 0}; (r, z) = (x . u1, x . kh) */
    seg2 *s;
    int64_t ns, caps;
    double zlow;         /* Z0 = (0, zlow) */
} prof;

/* The image curve of a contour edge within this share of the tolerance of its polyline. */
#define PROF_SHARE 0.25
/* The most pieces one edge's image is cut into (curves near the axis bend hard). */
#define PROF_MAX_PIECES 4096

static int add_seg(prof *P, double ar, double az, double br, double bz)
{
    if (!mfg_grow((void **)&P->s, &P->caps, P->ns + 1, sizeof *P->s))
        return 0;
    seg2 *g = &P->s[P->ns];
    g->a[0] = sw_snap(ar);
    g->a[1] = sw_snap(az);
    g->b[0] = sw_snap(br);
    g->b[1] = sw_snap(bz);
    /* a segment of no length adds nothing to the chain (a clipped polygon's corner) */
    if (g->a[0] != g->b[0] || g->a[1] != g->b[1])
        P->ns++;
    return 1;
}

/* ---- The section --------------------------------------------------------------------- */

/* Appends the part with r >= 0 of section segment (ar, az) -> (br, bz), and its closure
 * along the axis where it crosses it. */
static int add_clipped(prof *P, double ar, double az, double br, double bz)
{
    if (ar >= 0 && br >= 0)
        return add_seg(P, ar, az, br, bz);
    if (ar < 0 && br < 0)
        return 1;
    double f = ar / (ar - br), zc = az + f * (bz - az);
    if (ar >= 0) /* leaves r >= 0 at (0, zc): then down the axis to Z0 */
        return add_seg(P, ar, az, 0, zc) && add_seg(P, 0, zc, 0, P->zlow);
    return add_seg(P, 0, P->zlow, 0, zc) && add_seg(P, 0, zc, br, bz);
}

static double dot_r(const prof *P, const double *x)
{
    return mfg_dot3(x, P->u1);
}

static double dot_z(const prof *P, const double *x)
{
    return mfg_dot3(x, P->e->kh);
}

static int section(prof *P)
{
    sw_env *e = P->e;
    /* one side per vertex (on the plane counts as +), so neighbours agree */
    int8_t *side = malloc((size_t)(e->nin + 1));
    if (!side)
        return 0;
    for (int64_t v = 0; v < e->nin; v++)
        side[v] = mfg_dot3(e->x + 3 * v, P->u2) >= 0 ? 1 : -1;
    for (int64_t t = 0; t < e->nt; t++) {
        const int64_t *V = e->tri + 3 * t;
        int enter = -1, leave = -1;
        for (int k = 0; k < 3; k++) {
            int sa = side[V[k]], sb = side[V[(k + 1) % 3]];
            if (sa < 0 && sb > 0)
                enter = k;
            else if (sa > 0 && sb < 0)
                leave = k;
        }
        if (enter < 0 || leave < 0)
            continue;
        /* the boundary of the section runs from where the triangle enters the + side to
         * where it leaves it (the + part's ring, the edge on the plane) */
        double pt[2][3];
        int ks[2] = {enter, leave};
        for (int q = 0; q < 2; q++) {
            /* the crossing of an edge, computed from its ends in a fixed order (the same
             * point for both triangles of the edge) */
            int64_t a = V[ks[q]], b = V[(ks[q] + 1) % 3];
            if (a > b) {
                int64_t tmp = a;
                a = b;
                b = tmp;
            }
            const double *xa = e->x + 3 * a, *xb = e->x + 3 * b;
            double da = mfg_dot3(xa, P->u2), db = mfg_dot3(xb, P->u2);
            double f = da / (da - db);
            for (int k = 0; k < 3; k++)
                pt[q][k] = xa[k] + f * (xb[k] - xa[k]);
        }
        if (!add_clipped(P, dot_r(P, pt[0]), dot_z(P, pt[0]), dot_r(P, pt[1]), dot_z(P, pt[1]))) {
            free(side);
            return 0;
        }
    }
    free(side);
    return 1;
}

/* ---- The contour's image ----------------------------------------------------------- */

/* (r, z) of the point u + s (v - u). */
static void image_at(const prof *P, const double *u, const double *v, double s, double out[2])
{
    double x[3];
    for (int k = 0; k < 3; k++)
        x[k] = u[k] + s * (v[k] - u[k]);
    out[0] = sw_radius(P->e, x);
    out[1] = dot_z(P, x);
}

/* The tangent of the image curve at s: d(r, z)/ds. */
static void image_slope(const prof *P, const double *u, const double *v, double s, double out[2])
{
    double x[3], d[3], par[3], dpar[3];
    for (int k = 0; k < 3; k++) {
        x[k] = u[k] + s * (v[k] - u[k]);
        d[k] = v[k] - u[k];
    }
    const double *kh = P->e->kh;
    double a = mfg_dot3(kh, x), b = mfg_dot3(kh, d);
    for (int k = 0; k < 3; k++) {
        par[k] = x[k] - kh[k] * a; /* x_perp */
        dpar[k] = d[k] - kh[k] * b;
    }
    double r = mfg_norm3(par);
    out[0] = r > 0 ? mfg_dot3(par, dpar) / r : mfg_norm3(dpar);
    out[1] = b;
}

/* The image of contour edge u -> v as a polyline on its front: chords of the convex r(s)
 * (above it) for a rising edge, tangents (below it) for a falling one, enough pieces
 * for PROF_SHARE of the tolerance. */
static int contour_image(prof *P, const double *u, const double *v)
{
    double tol = PROF_SHARE * P->e->tol;
    double a[2], b[2];
    image_at(P, u, v, 0, a);
    image_at(P, u, v, 1, b);
    double dz = b[1] - a[1];
    /* pieces: the chord of r(s) over a piece of length h sags by at most r'' h^2 / 8;
     * measured by halving until every piece's midpoint is within tol */
    int n = 1;
    for (; n < PROF_MAX_PIECES; n *= 2) {
        double worst = 0;
        for (int i = 0; i < n; i++) {
            double p0[2], p1[2], pm[2];
            image_at(P, u, v, (double)i / n, p0);
            image_at(P, u, v, (double)(i + 1) / n, p1);
            image_at(P, u, v, (i + 0.5) / n, pm);
            worst = fmax(worst, 0.5 * (p0[0] + p1[0]) - pm[0]);
        }
        if (worst <= tol)
            break;
    }
    if (dz >= 0) { /* rising (or level: the image is a segment of one height) */
        double prev[2] = {a[0], a[1]};
        for (int i = 1; i <= n; i++) {
            double cur[2];
            image_at(P, u, v, (double)i / n, cur);
            if (!add_seg(P, prev[0], prev[1], cur[0], cur[1]))
                return 0;
            prev[0] = cur[0];
            prev[1] = cur[1];
        }
        return 1;
    }
    /* falling: the tangents at s = i / n, consecutive ones meeting at the polyline's
     * corners (a convex curve's tangents meet below it); the ends are u's and v's */
    double prev[2] = {a[0], a[1]};
    for (int i = 0; i < n; i++) {
        double p0[2], p1[2], t0[2], t1[2], x[2];
        image_at(P, u, v, (double)i / n, p0);
        image_at(P, u, v, (double)(i + 1) / n, p1);
        image_slope(P, u, v, (double)i / n, t0);
        image_slope(P, u, v, (double)(i + 1) / n, t1);
        /* p0 + a t0 = p1 + b t1 */
        double det = t0[0] * (-t1[1]) - t0[1] * (-t1[0]);
        double rx = p1[0] - p0[0], rz = p1[1] - p0[1];
        if (fabs(det) > 1e-300) {
            double al = (rx * (-t1[1]) - rz * (-t1[0])) / det;
            x[0] = p0[0] + al * t0[0];
            x[1] = p0[1] + al * t0[1];
            /* a corner outside the piece's box means nearly parallel tangents: the chord
             * pushed down by its sag instead */
            if (!(x[1] <= fmax(p0[1], p1[1]) && x[1] >= fmin(p0[1], p1[1]))) {
                x[0] = 0.5 * (p0[0] + p1[0]) - tol;
                x[1] = 0.5 * (p0[1] + p1[1]);
            }
        } else {
            x[0] = 0.5 * (p0[0] + p1[0]) - tol;
            x[1] = 0.5 * (p0[1] + p1[1]);
        }
        if (x[0] < 0)
            x[0] = 0;
        if (!add_seg(P, prev[0], prev[1], x[0], x[1]) || !add_seg(P, x[0], x[1], p1[0], p1[1]))
            return 0;
        prev[0] = p1[0];
        prev[1] = p1[1];
    }
    return 1;
}

/* ---- P and its outline ------------------------------------------------------------------ */

typedef struct bedge {
    int64_t a, b; /* profile points (ids of the arrangement's table) */
} bedge;

static int cmp_i64(const void *x, const void *y)
{
    int64_t a = *(const int64_t *)x, b = *(const int64_t *)y;
    return a < b ? -1 : a > b;
}

/* The outline of {w >= 1} of a 2-D chain's arrangement (faces F of T): the sides of its
 * counter-clockwise faces whose reverse is not a side of one, each with the region on
 * its left. */
static int outline_of(arr_table *T, const arr_face *F, int64_t nf, bedge **out, int64_t *nout)
{
    arr_points AP = arr_view(T);
    hmap sides;
    bedge *be = NULL;
    int64_t nbe = 0, capbe = 0;
    int ok = hmap_init(&sides, 3 * nf + 1);
    for (int pass = 0; pass < 2 && ok; pass++)
        for (int64_t f = 0; ok && f < nf; f++) {
            int o = arr_orient2d(&AP, F[f].v[0], F[f].v[1], F[f].v[2], 2);
            if (F[f].mult * o < 1)
                continue;
            for (int k = 0; k < 3 && ok; k++) {
                int64_t a = F[f].v[k], b = F[f].v[(k + 1) % 3];
                if (pass == 0) {
                    hkey key = mkkey(a, b, 0, 0);
                    ok = hmap_put(&sides, &key, f);
                    continue;
                }
                hkey rev = mkkey(b, a, 0, 0);
                if (hmap_get(&sides, &rev) >= 0)
                    continue;
                ok = mfg_grow((void **)&be, &capbe, nbe + 1, sizeof *be);
                if (ok) {
                    be[nbe].a = a;
                    be[nbe].b = b;
                    nbe++;
                }
            }
        }
    hmap_free(&sides);
    if (!ok) {
        free(be);
        return 0;
    }
    *out = be;
    *nout = nbe;
    return 1;
}

/* The outline with the corners between two collinear sides dropped (exact orient2d; a
 * point with other than one side in and one out stays): the images of a face's
 * contour edges all lie on the profile's outline where the face is perpendicular to the
 * axis, and every one of their ends would otherwise ring the result (a box about its
 * edge: 141 outline pieces for a rectangle). */
static int merge_collinear(arr_table *T, bedge *be, int64_t *nbe_io)
{
    int64_t nbe = *nbe_io;
    arr_points AP = arr_view(T);
    hmap at;
    int64_t *io = NULL, nio = 0, capio = 0; /* 3 per point: out side, #in, #out */
    int ok = hmap_init(&at, 2 * nbe + 1);
    for (int64_t i = 0; ok && i < nbe; i++)
        for (int q = 0; q < 2 && ok; q++) {
            int64_t p = q ? be[i].b : be[i].a;
            hkey key = mkkey(p, 0, 0, 0);
            int64_t j = hmap_get(&at, &key);
            if (j < 0) {
                ok = mfg_grow((void **)&io, &capio, 3 * (nio + 1), sizeof *io) &&
                     hmap_put(&at, &key, nio);
                if (!ok)
                    break;
                j = nio++;
                io[3 * j] = -1;
                io[3 * j + 1] = io[3 * j + 2] = 0;
            }
            if (q == 0)
                io[3 * j] = i;
            io[3 * j + 1 + (q ? 0 : 1)]++;
        }
    if (!ok) {
        hmap_free(&at);
        free(io);
        return 0;
    }
    /* drop[i]: side i starts at a corner that goes */
    int8_t *drop = calloc((size_t)nbe + 1, 1);
    if (!drop) {
        hmap_free(&at);
        free(io);
        return 0;
    }
    for (int64_t i = 0; i < nbe; i++) {
        hkey key = mkkey(be[i].b, 0, 0, 0);
        int64_t j = hmap_get(&at, &key);
        if (io[3 * j + 1] != 1 || io[3 * j + 2] != 1)
            continue;
        int64_t o = io[3 * j];
        if (o != i && be[o].b != be[i].a && arr_orient2d(&AP, be[i].a, be[i].b, be[o].b, 2) == 0) {
            /* collinear and going on (not back): the corner goes */
            double a[3], b[3], c[3];
            arr_coords(&AP, be[i].a, a);
            arr_coords(&AP, be[i].b, b);
            arr_coords(&AP, be[o].b, c);
            if ((b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]) > 0)
                drop[o] = 1;
        }
    }
    /* the merged sides: their ends first (the walk reads be), then compacted */
    int64_t *ends = malloc((size_t)(nbe + 1) * sizeof *ends);
    if (!ends) {
        free(drop);
        hmap_free(&at);
        free(io);
        return 0;
    }
    for (int64_t i = 0; i < nbe; i++) {
        ends[i] = be[i].b;
        if (drop[i])
            continue;
        bedge m = be[i];
        for (int64_t guard = 0; guard < nbe; guard++) {
            hkey key = mkkey(m.b, 0, 0, 0);
            int64_t o = io[3 * hmap_get(&at, &key)];
            if (o < 0 || !drop[o])
                break;
            m.b = be[o].b;
        }
        ends[i] = m.b;
    }
    int64_t n = 0;
    for (int64_t i = 0; i < nbe; i++)
        if (!drop[i]) {
            be[n].a = be[i].a;
            be[n++].b = ends[i];
        }
    *nbe_io = n;
    free(ends);
    free(drop);
    hmap_free(&at);
    free(io);
    return 1;
}

/* P swept by eps along +r (the Minkowski sum with the segment [0, eps] e_r), as a sum of
 * closed counter-clockwise chains whose region {w >= 1} is the union: P's outline and,
 * for each outline side that rises (dz > 0: P on its left is at smaller r, the side faces
 * away from the axis), the parallelogram it sweeps - a point of the sum outside P left P
 * moving in +r through such a side.  Sides perpendicular to the axis sweep nothing: the
 * faces of the part perpendicular to the axis stay on their planes.
 * Why: revolved with chords at the steps t_i (strips.c), the outline of P' bounds the
 * image of P's exact solid of revolution under x -> x h(phi), a scaling of the radius by
 * a factor h in [cos(delta/2), 1] that depends on the angle only - a homeomorphism, so
 * the result has no self-intersection by construction (no tangent polylines, no fins,
 * nothing for the arrangement to cut) - and it holds the solid of revolution of P when
 * a point (r, z) of P has (r / h, z) in P', i.e. when eps >= rmax (sec(delta/2) - 1). */
static int grown_chain(prof *P, const arr_points *AP, const bedge *be, int64_t nbe, double eps)
{
    int ok = 1;
    for (int64_t i = 0; ok && i < nbe; i++) {
        double a[3], b[3];
        arr_coords(AP, be[i].a, a);
        arr_coords(AP, be[i].b, b);
        ok = add_seg(P, a[0], a[1], b[0], b[1]);
        if (ok && arr_cmp(AP, be[i].b, be[i].a, 1) > 0)
            ok = add_seg(P, a[0], a[1], a[0] + eps, a[1]) && /* counter-clockwise */
                 add_seg(P, a[0] + eps, a[1], b[0] + eps, b[1]) &&
                 add_seg(P, b[0] + eps, b[1], b[0], b[1]) && add_seg(P, b[0], b[1], a[0], a[1]);
    }
    return ok;
}

/* One arrangement of the 2-D chain P->s and the outline of its {w >= 1}; P->s freed. */
static mfg_status chain_outline(prof *P, arr_table *T, arr_face **F, bedge **be, int64_t *nbe)
{
    int64_t np = 2 * P->ns;
    double *xy = malloc((size_t)(3 * np + 3) * sizeof *xy);
    int64_t *seg = malloc((size_t)(2 * P->ns + 2) * sizeof *seg);
    if (!xy || !seg) {
        free(xy);
        free(seg);
        return MFG_ERR_NOMEM;
    }
    for (int64_t i = 0; i < P->ns; i++) {
        for (int q = 0; q < 2; q++) {
            const double *c = q ? P->s[i].b : P->s[i].a;
            xy[3 * (2 * i + q)] = c[0];
            xy[3 * (2 * i + q) + 1] = c[1];
            xy[3 * (2 * i + q) + 2] = 0;
            seg[2 * i + q] = 2 * i + q;
        }
    }
    int64_t nseg = P->ns;
    free(P->s);
    P->s = NULL;
    P->ns = P->caps = 0;
    /* equal 2-D points of different segments are one point of the arrangement (its
     * exact merge), so the chain's pieces join */
    int64_t nf = 0;
    mfg_status st = arr_chain2d_faces(xy, np, seg, nseg, P->e->prog, T, F, &nf);
    free(xy);
    free(seg);
    if (st != MFG_OK)
        return st;
    if (!outline_of(T, *F, nf, be, nbe) || !merge_collinear(T, *be, nbe)) {
        free(*be);
        *be = NULL;
        free(*F);
        *F = NULL;
        arr_table_free(T);
        return MFG_ERR_NOMEM;
    }
    return MFG_OK;
}

int sw_build_profile(sw_env *e)
{
    prof P;
    memset(&P, 0, sizeof P);
    P.e = e;
    /* the half-plane's direction: any direction across the axis; one that no vertex is
     * likely to lie on (a rounded irrational angle from a helper) */
    double h[3] = {0.8017837257372732, 0.5345224838248488, 0.2672612419124244};
    mfg_cross3(e->kh, h, P.u2);
    if (!mfg_unit3(P.u2, P.u2)) {
        double h2[3] = {0.2672612419124244, 0.8017837257372732, 0.5345224838248488};
        mfg_cross3(e->kh, h2, P.u2);
        mfg_unit3(P.u2, P.u2);
    }
    mfg_cross3(P.u2, e->kh, P.u1); /* (u1, u2, kh) right-handed */
    double zmin = INFINITY;
    for (int64_t v = 0; v < e->nin; v++)
        zmin = fmin(zmin, dot_z(&P, e->x + 3 * v));
    P.zlow = floor(zmin) - 1;
    int ok = section(&P);
    for (int64_t i = 0; ok && i < e->nce; i++)
        ok = contour_image(&P, e->x + 3 * e->ce[2 * i], e->x + 3 * e->ce[2 * i + 1]);
    if (!ok) {
        free(P.s);
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
        return 0;
    }
    /* P, then P grown by eps (grown_chain) */
    arr_table T;
    arr_face *F = NULL;
    bedge *be = NULL;
    int64_t nbe = 0;
    mfg_status st = chain_outline(&P, &T, &F, &be, &nbe);
    if (st == MFG_OK) {
        arr_points AP0 = arr_view(&T);
        ok = grown_chain(&P, &AP0, be, nbe, SW_SHARE_APEX * e->tol);
        free(be);
        free(F);
        arr_table_free(&T);
        be = NULL;
        F = NULL;
        st = ok ? chain_outline(&P, &T, &F, &be, &nbe) : MFG_ERR_NOMEM;
    }
    if (st != MFG_OK) {
        free(P.s);
        e->st_code = st == MFG_ERR_NOMEM ? mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory") : st;
        return 0;
    }
    arr_points AP = arr_view(&T);
    /* the outline's points as soup vertices: (r, z) -> r u1 + z kh */
    int64_t *pts = malloc((size_t)(2 * nbe + 1) * sizeof *pts);
    int64_t npts = 0;
    hmap vid;
    memset(&vid, 0, sizeof vid);
    ok = ok && pts && hmap_init(&vid, 2 * nbe + 1);
    for (int64_t i = 0; ok && i < nbe; i++) {
        pts[npts++] = be[i].a;
        pts[npts++] = be[i].b;
    }
    if (ok) {
        qsort(pts, (size_t)npts, sizeof *pts, cmp_i64);
        e->nce = 0;
        for (int64_t i = 0; ok && i < npts; i++) {
            if (i > 0 && pts[i] == pts[i - 1])
                continue;
            double c[3], x[3];
            arr_coords(&AP, pts[i], c);
            double r = c[0] < SW_ON_AXIS ? 0 : c[0];
            for (int k = 0; k < 3; k++)
                x[k] = r * P.u1[k] + c[1] * e->kh[k];
            int64_t id = sw_add_vertex(e, x);
            hkey key = mkkey(pts[i], 0, 0, 0);
            ok = id >= 0 && hmap_put(&vid, &key, id);
        }
        /* each outline side a contour piece revolved by chords (grown_chain says why) */
        for (int64_t i = 0; ok && i < nbe; i++) {
            hkey ka = mkkey(be[i].a, 0, 0, 0), kb = mkkey(be[i].b, 0, 0, 0);
            int64_t u = hmap_get(&vid, &ka), v = hmap_get(&vid, &kb);
            if (u == v)
                continue;
            ok = sw_add_contour_piece(e, u, v, SW_CHORD);
        }
    }
    hmap_free(&vid);
    free(pts);
    free(be);
    free(F);
    arr_table_free(&T);
    if (!ok)
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    return ok;
}
