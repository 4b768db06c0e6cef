/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/rotsweep.c - Entry point: mfg_rotational_sweep / mfg_rotational_sweep_p.  The
 * design and the file map: sweep/envelope.h. */
#ifdef ARR_DEBUG
#include <stdio.h>
#include <time.h>
#endif
#include "sweep/envelope.h"
#include "mesh/mesh.h"

/* Arguments other than the mesh (which mfg_mesh_require_closed checks). */
static mfg_status check_sweep_args(const double *axis_point, const double *axis_dir,
                                   double angle, double tolerance, mfg_mesh **out_mesh)
{
    if (!axis_point || !axis_dir || !out_mesh)
        return mfg_fail(MFG_ERR_NULL, "rotational sweep: %s is NULL",
                        !axis_point ? "axis_point" : !axis_dir ? "axis_direction" : "out_mesh");
    for (int k = 0; k < 3; k++) {
        if (!mfg_coord_ok(axis_point[k]))
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: axis point coordinate %d is %g "
                            "(not finite or out of range)", k, axis_point[k]);
        if (!mfg_coord_ok(axis_dir[k]))
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: axis direction component %d is "
                            "%g (not finite or out of range)", k, axis_dir[k]);
    }
    if (axis_dir[0] == 0 && axis_dir[1] == 0 && axis_dir[2] == 0)
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: the axis direction is the zero vector");
    if (!(angle > 0) || !(angle <= MFG_TWO_PI + SW_FULL_TURN_EPS))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: angle %g rad is outside (0, 2*pi]",
                        angle);
    if (!(tolerance > 0) || !mfg_coord_ok(tolerance))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: tolerance %g must be positive and "
                        "finite", tolerance);
    return MFG_OK;
}

mfg_status mfg_rotational_sweep(const double *xyz, int64_t nvertices, const int64_t *triangles,
                                int64_t ntriangles, const double axis_point[3],
                                const double axis_direction[3], double angle, double tolerance,
                                mfg_mesh **out_mesh, mfg_sweep_stats *out_stats)
{
    return mfg_rotational_sweep_p(xyz, nvertices, triangles, ntriangles, axis_point,
                                  axis_direction, angle, tolerance, out_mesh, out_stats, NULL);
}

/* The exponent e of the power of two 2^e with ext / 2 < 2^e <= ext... (frexp's: ext =
 * f 2^e, f in [0.5, 1)), ext = the largest |coordinate - axis point|: itself scaled by
 * exactly 2^k when the input is (the differences round the same way), so the unit-scale
 * input does not depend on the unit. */
static int sweep_scale_exponent(const double *xyz, int64_t nv, const double axis_point[3])
{
    double ext = 0;
    for (int64_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++)
            ext = fmax(ext, fabs(xyz[3 * i + k] - axis_point[k]));
    int e = 0;
    if (ext > 0)
        (void)frexp(ext, &e);
    return e;
}

/* The axis frame: rows u1, u2, kh (right-handed, kh the unit axis).  The sweep works in
 * it, so the axis is exactly the z axis: a point is on it when its x and y are 0, k x p
 * is exact, and a turn changes x and y only.  About a coordinate axis the frame is a
 * signed permutation, so nothing is rounded and the input's planes stay where they are. */
static void axis_frame(const double d[3], double F[3][3])
{
    for (int i = 0; i < 3; i++)
        if (d[(i + 1) % 3] == 0 && d[(i + 2) % 3] == 0) {
            memset(F, 0, 9 * sizeof(double));
            int sg = d[i] > 0 ? 1 : -1;
            /* +e_i: u1 = e_(i+1), u2 = e_(i+2); -e_i: the two swapped */
            F[0][sg > 0 ? (i + 1) % 3 : (i + 2) % 3] = 1;
            F[1][sg > 0 ? (i + 2) % 3 : (i + 1) % 3] = 1;
            F[2][i] = sg;
            return;
        }
    double kh[3], ref[3] = {0, 0, 0}, u1[3], u2[3];
    mfg_unit3(d, kh);
    int small = 0; /* the coordinate axis farthest from kh */
    for (int i = 1; i < 3; i++)
        if (fabs(kh[i]) < fabs(kh[small]))
            small = i;
    ref[small] = 1;
    mfg_cross3(kh, ref, u1);
    mfg_unit3(u1, u1);
    mfg_cross3(kh, u1, u2);
    for (int k = 0; k < 3; k++) {
        F[0][k] = u1[k];
        F[1][k] = u2[k];
        F[2][k] = kh[k];
    }
}

/* The result in the caller's frame (unit scale about the axis point -> caller's units):
 * only the vertices the triangles use, numbered in order of first use. */
static mfg_status output_mesh(const double *ox, int64_t nox, const int64_t *ot, int64_t not_,
                              int scale_exp, mfg_mesh **out, mfg_sweep_stats *stats)
{
    mfg_mesh *m = calloc(1, sizeof *m);
    int64_t *map = malloc((size_t)(nox + 1) * sizeof *map);
    if (m) {
        m->vertices = malloc((size_t)(3 * nox + 1) * sizeof *m->vertices);
        m->triangles = malloc((size_t)(3 * not_ + 1) * sizeof *m->triangles);
    }
    if (!m || !map || !m->vertices || !m->triangles) {
        free(map);
        mfg_mesh_free(m);
        return mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    }
    for (int64_t i = 0; i < nox; i++)
        map[i] = -1;
    int64_t nused = 0;
    double vol = 0, area = 0;
    for (int64_t i = 0; i < 3 * not_; i++) {
        int64_t w = ot[i];
        if (map[w] < 0) {
            map[w] = nused;
            /* the caller's axes already (surface.c): exact; + 0.0 makes a -0 (a turned
             * coordinate that came out as zero) +0, as the stats' bounding box has it */
            for (int k = 0; k < 3; k++)
                m->vertices[3 * nused + k] = ldexp(ox[3 * w + k], scale_exp) + 0.0;
            nused++;
        }
        m->triangles[i] = map[w];
    }
    for (int64_t t = 0; t < not_; t++) {
        /* about the first vertex (the part may lie far from the origin), scaled back
         * exactly */
        double a[3], b[3], c[3], e1[3], e2[3], n[3], bc[3];
        mfg_sub3(ox + 3 * ot[3 * t], ox, a);
        mfg_sub3(ox + 3 * ot[3 * t + 1], ox, b);
        mfg_sub3(ox + 3 * ot[3 * t + 2], ox, c);
        mfg_sub3(b, a, e1);
        mfg_sub3(c, a, e2);
        mfg_cross3(e1, e2, n);
        area += 0.5 * mfg_norm3(n);
        mfg_cross3(b, c, bc);
        vol += mfg_dot3(a, bc);
    }
    free(map);
    m->nvertices = nused;
    m->ntriangles = not_;
    {
        memset(stats, 0, sizeof *stats);
        for (int k = 0; k < 3; k++) {
            stats->bbox[k] = INFINITY;
            stats->bbox[3 + k] = -INFINITY;
        }
        for (int64_t i = 0; i < nused; i++)
            for (int k = 0; k < 3; k++) {
                stats->bbox[k] = fmin(stats->bbox[k], m->vertices[3 * i + k]);
                stats->bbox[3 + k] = fmax(stats->bbox[3 + k], m->vertices[3 * i + k]);
            }
        stats->volume = ldexp(vol / 6, 3 * scale_exp);
        stats->area = ldexp(area, 2 * scale_exp);
    }
    *out = m;
    return MFG_OK;
}

/* Refuses a tolerance the coordinates cannot resolve (issue 20: a unit cube at 1e15, ulp
 * 0.125, tol 0.02 was accepted and its turned corners lay 0.088 outside): at least 2^12
 * ulps of the largest coordinate; and at least 2^-24 of the part's extent about the axis
 * point, which bounds the work (1e-9 of the part ran 5 minutes and 2 GB in the first
 * design). */
/* The largest |coordinate| of the mesh and the axis point. */
static double max_abs_coordinate(const double *cx, int64_t nv, const double unit_point[3])
{
    double maxabs = 0;
    for (int64_t i = 0; i < 3 * nv; i++)
        maxabs = fmax(maxabs, fabs(cx[i]));
    for (int k = 0; k < 3; k++)
        maxabs = fmax(maxabs, fabs(unit_point[k]));
    return maxabs;
}

static mfg_status check_tolerance(const double *cx, int64_t nv, const double unit_point[3],
                                  double tol, int scale_exp)
{
    double maxabs = max_abs_coordinate(cx, nv, unit_point);
    int me = 0;
    (void)frexp(maxabs, &me);
    double min_tol = fmax(ldexp(1.0, me - 53 + SW_TOL_MIN_ULPS_LOG2), ldexp(1.0, SW_TOL_MIN_REL_LOG2));
    if (tol < min_tol)
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: tolerance %g is below what this "
                        "input resolves (coordinates up to %g, part extent about the axis "
                        "point up to %g): the smallest accepted is %g",
                        ldexp(tol, scale_exp), ldexp(maxabs, scale_exp), ldexp(1.0, scale_exp),
                        ldexp(min_tol, scale_exp));
    return MFG_OK;
}

/* Refuses a part the grids cannot resolve: its own extent (the largest side of its
 * bounding box) below 2^SW_PART_MIN_REL_LOG2 of its extent about the axis point (the
 * axis frame's grid), or below 2^SW_PART_MIN_CELLS_LOG2 cells of the caller's grid: the
 * passes after the turn round to 2^-ARR_GRID_LOG2 of the largest coordinate (to_caller_axes
 * in surface.c), and a unit cube at 1e15 was one such cell and came out with no
 * triangles. */
static mfg_status check_part_size(const double *cx, int64_t nv, const double unit_point[3],
                                  int scale_exp)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double maxabs = max_abs_coordinate(cx, nv, unit_point);
    for (int64_t i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], cx[3 * i + k]);
            hi[k] = fmax(hi[k], cx[3 * i + k]);
        }
    double size = 0;
    for (int k = 0; k < 3; k++)
        size = fmax(size, hi[k] - lo[k]);
    if (nv > 0 && size < ldexp(1.0, SW_PART_MIN_REL_LOG2))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: the part (%g across) is too small "
                        "against its distance from the axis point (up to %g): below 2^%d of it "
                        "the sweep cannot resolve the part; give an axis point nearer the part "
                        "(any point of the axis will do) or move the part nearer the axis",
                        ldexp(size, scale_exp), ldexp(1.0, scale_exp), SW_PART_MIN_REL_LOG2);
    /* the result reaches at most twice the largest coordinate: its grid is at most
     * 2^(me + 1 - ARR_GRID_LOG2) */
    int me = 0;
    (void)frexp(maxabs, &me);
    double min_size = ldexp(1.0, me + 1 - ARR_GRID_LOG2 + SW_PART_MIN_CELLS_LOG2);
    if (nv > 0 && size < min_size)
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: the part (%g across) is too small "
                        "for its coordinates (up to %g): the result's points are resolved to "
                        "2^-%d of them, and the part must be at least %g across; move the part "
                        "and the axis point nearer the origin",
                        ldexp(size, scale_exp), ldexp(maxabs, scale_exp),
                        ARR_GRID_LOG2 - 1, ldexp(min_size, scale_exp));
    return MFG_OK;
}

/* Orders (height, vertex) records. */
static int cmp_height(const void *pa, const void *pb)
{
    const double *a = pa, *b = pb;
    return a[0] < b[0] ? -1 : a[0] > b[0] ? 1 : (a[1] > b[1]) - (a[1] < b[1]);
}

/* Heights along the axis that differ by rounding only are made one (p: n points in the
 * axis frame, 3 each).  A face perpendicular to the axis is one plane in the caller's
 * axes, but its corners turned into the axis frame get heights a few ulps apart; the
 * turns keep each height exactly, so its turned copies and the strips of its rim become
 * faces at grazing angles of 1e-15 instead of one plane, and the rounded boundary's
 * passes never end there (a star prism about an axis along its own: 77 crossing pairs,
 * all in that plane, after every pass; 6 of the battery's 8 refusals).  Heights within
 * SW_LEVEL of their neighbour in sorted order form a run; a run no wider than
 * SW_LEVEL_SPAN takes its middle height (a wider run is a surface, not a rounded plane,
 * and is left as it is).  The same for the coordinates across the axis (edges parallel
 * to it) changed none of the refusals left and is not done. */
static int level_heights(double *p, int64_t n)
{
    double *h = malloc((size_t)(2 * n + 2) * sizeof *h);
    if (!h)
        return 0;
    for (int64_t i = 0; i < n; i++) {
        h[2 * i] = p[3 * i + 2];
        h[2 * i + 1] = (double)i;
    }
    qsort(h, (size_t)n, 2 * sizeof *h, cmp_height);
    for (int64_t i = 0, j; i < n; i = j) {
        for (j = i + 1; j < n && h[2 * j] - h[2 * (j - 1)] <= SW_LEVEL; j++)
            ;
        if (j - i < 2 || h[2 * (j - 1)] - h[2 * i] > SW_LEVEL_SPAN)
            continue;
        double mid = h[2 * ((i + j - 1) / 2)];
        for (int64_t q = i; q < j; q++)
            p[3 * (int64_t)h[2 * q + 1] + 2] = mid;
    }
    free(h);
    return 1;
}

static void env_free(sw_env *e)
{
    free(e->x);
    hmap_free(&e->turned);
    free(e->st);
    free(e->sgroup);
    free(e->ce);
    free(e->ckind);
}

mfg_status mfg_rotational_sweep_p(const double *xyz, int64_t nvertices,
                                  const int64_t *triangles, int64_t ntriangles,
                                  const double axis_point[3], const double axis_direction[3],
                                  double angle, double tolerance, mfg_mesh **out_mesh,
                                  mfg_sweep_stats *out_stats, const mfg_progress *progress)
{
    mfg_status st = check_sweep_args(axis_point, axis_direction, angle, tolerance, out_mesh);
    if (st != MFG_OK)
        return st;
    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_rotational_sweep");
    if (!mfg_prog_stage(&prog, "sweep: setup", 0, 0.05, 1))
        return mfg_prog_fail(&prog);
    st = mfg_mesh_require_closed(xyz, nvertices, triangles, ntriangles, NULL, NULL);
    if (st != MFG_OK)
        return st; /* its message numbers the caller's triangles */
    /* From here on the canonical copy (canonical.c): the result does not depend on the
     * caller's order; it is as closed as the caller's mesh. */
    double *cx = NULL;
    int64_t *ct = NULL, *nb = NULL;
    if (!sw_canonical_input(xyz, nvertices, triangles, ntriangles, &cx, &ct))
        return mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    st = mfg_mesh_require_closed(cx, nvertices, ct, ntriangles, NULL, &nb);
    if (st != MFG_OK) {
        free(cx);
        free(ct);
        return st;
    }
    /* Unit scale (issue 20: results changed with the unit): the copy, the axis point and
     * the tolerance divided by 2^scale_exp, the power of two of the part's extent about
     * the axis point - exact, so the input scaled by 2^k gives the result scaled by 2^k
     * bit for bit, and every constant below is relative to the part's size. */
    int scale_exp = sweep_scale_exponent(cx, nvertices, axis_point);
    double unit_point[3];
    for (int64_t i = 0; i < 3 * nvertices; i++)
        cx[i] = ldexp(cx[i], -scale_exp);
    for (int k = 0; k < 3; k++)
        unit_point[k] = ldexp(axis_point[k], -scale_exp);
    tolerance = ldexp(tolerance, -scale_exp);
    st = check_tolerance(cx, nvertices, unit_point, tolerance, scale_exp);
    if (st == MFG_OK)
        st = check_part_size(cx, nvertices, unit_point, scale_exp);
    if (st != MFG_OK) {
        free(cx);
        free(ct);
        free(nb);
        return st;
    }
    sw_env e;
    memset(&e, 0, sizeof e);
    e.prog = &prog;
    e.st_code = MFG_OK;
    e.tri = ct;
    e.nt = ntriangles;
    e.nb = nb;
    e.full_turn = angle >= MFG_TWO_PI - SW_FULL_TURN_EPS;
    e.theta = e.full_turn ? MFG_TWO_PI : angle;
    e.theta_asked = e.theta;
    /* a tolerance comparable to the part is met by computing to 1/16 of the unit extent
     * (a tighter result keeps the contract) */
    e.tol = fmin(tolerance, SW_TOL_MAX_UNIT);
    e.tol_asked = e.tol;
    double F[3][3];
    axis_frame(axis_direction, F);
    memcpy(e.frame, F, sizeof F);
    memcpy(e.origin, unit_point, sizeof unit_point);
    e.k[0] = e.k[1] = 0;
    e.k[2] = 1;
    int ok = hmap_init(&e.turned, 4 * nvertices + 64);
    /* the input about the axis point in the axis frame, on the arrangement's grid; a
     * vertex closer to the axis than SW_ON_AXIS is put on it (a vertex on the axis of a
     * moved part is off it by rounding, and its turns would be circles of ulps).  xin
     * keeps them for the builds after one that turned them to the caller's axes in place
     * (surface.c). */
    double *xin = ok ? malloc((size_t)(3 * nvertices + 3) * sizeof *xin) : NULL;
    ok = xin != NULL;
    for (int64_t i = 0; ok && i < nvertices; i++) {
        double d[3], *p = xin + 3 * i;
        for (int k = 0; k < 3; k++)
            d[k] = cx[3 * i + k] - unit_point[k];
        for (int r = 0; r < 3; r++)
            p[r] = mfg_dot3(F[r], d);
        if (hypot(p[0], p[1]) < SW_ON_AXIS)
            p[0] = p[1] = 0;
    }
    ok = ok && level_heights(xin, nvertices);
    for (int64_t i = 0; ok && i < nvertices; i++) {
        for (int k = 0; k < 3; k++)
            xin[3 * i + k] = sw_snap(xin[3 * i + k]); /* as sw_add_vertex stores them */
        ok = sw_add_vertex(&e, xin + 3 * i) >= 0;
    }
    if (!ok)
        e.st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    e.nin = nvertices;
    double *ox = NULL;
    int64_t nox = 0, *ot = NULL, not_ = 0;
    /* A broken invariant of the arrangement or of the repair of its rounded boundary
     * (a bug, or a configuration rounding defeats) is not the caller's problem while
     * another build can avoid it: the soup is built again with one step more (other
     * turned points, other crossings), up to SW_ATTEMPTS times in the axis frame and then
     * SW_CALLER_ATTEMPTS times in the caller's axes (envelope.h), before the call reports
     * MFG_ERR_INTERNAL. */
    e.cx = cx;
    for (int attempt = 0; ok && attempt < SW_ATTEMPTS + SW_CALLER_ATTEMPTS; attempt++) {
        if (attempt > 0) {
            memcpy(e.x, xin, (size_t)(3 * nvertices) * sizeof *xin);
            e.nv = e.nin;
            e.nst = 0;
            e.nce = 0;
            hmap_free(&e.turned);
            if (!hmap_init(&e.turned, 4 * nvertices + 64)) {
                e.st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
                ok = 0;
                break;
            }
            e.st_code = MFG_OK;
        }
        e.caller_first = attempt >= SW_ATTEMPTS;
        e.attempt = e.caller_first ? attempt - SW_ATTEMPTS : attempt;
        sw_setup_steps(&e);
        int built = (mfg_prog_stage(&prog, "sweep: contour", 0.05, 0.15, 1024) ||
                     (e.st_code = MFG_ERR_CANCELLED, 0)) &&
                    sw_build_faces(&e);
#ifdef ARR_DEBUG
        int64_t nfaces_soup = e.nst;
#endif
        if (built && e.full_turn) {
            /* a full turn revolves the profile's outline, not the contour */
            e.nst = 0;
            built = sw_build_profile(&e);
        }
        built = built && (mfg_prog_stage(&prog, "sweep: strips", 0.15, 0.3, 256) ||
                          (e.st_code = MFG_ERR_CANCELLED, 0)) &&
                sw_build_strips(&e);
#ifdef ARR_DEBUG
        fprintf(stderr, "faces F/B (%.2f s of CPU): soup 0..%lld, strips and fins after; steps %d, contour pieces %lld\n", (double)clock() / CLOCKS_PER_SEC,
                (long long)nfaces_soup, e.nsteps, (long long)e.nce);
#endif
        built = built && sw_surface(&e, &ox, &nox, &ot, &not_);
        if (built || e.st_code != MFG_ERR_INTERNAL)
            ok = built;
        if (built || e.st_code != MFG_ERR_INTERNAL)
            break;
        if (attempt + 1 == SW_ATTEMPTS + SW_CALLER_ATTEMPTS)
            ok = 0;
    }
    ok = ok && (mfg_prog_stage(&prog, "sweep: output", 0.9, 1.0, 1) || (e.st_code = MFG_ERR_CANCELLED, 0));
    mfg_mesh *m = NULL;
    mfg_sweep_stats stats; /* the caller's copy is written only on success */
    if (ok) {
        st = output_mesh(ox, nox, ot, not_, scale_exp + e.out_exp, &m, &stats);
        if (st != MFG_OK) {
            e.st_code = st;
            ok = 0;
        }
    }
    if (ok && !mfg_prog_stage(&prog, "sweep: done", 1.0, 1.0, 1)) {
        mfg_mesh_free(m);
        m = NULL;
        e.st_code = MFG_ERR_CANCELLED;
        ok = 0;
    }
    st = ok ? MFG_OK : e.st_code;
    if (st == MFG_ERR_CANCELLED)
        st = mfg_prog_fail(&prog);
    if (ok) {
        *out_mesh = m;
        if (out_stats)
            *out_stats = stats;
    }
    free(ox);
    free(ot);
    free(xin);
    env_free(&e);
    free(cx);
    free(ct);
    free(nb);
    if (st == MFG_OK)
        mfg_clear_error();
    return st;
}
