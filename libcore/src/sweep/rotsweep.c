/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/rotsweep.c - Entry point: mfg_rotational_sweep / mfg_rotational_sweep_p.  Overview
 * and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

/* Frees what one placement of the decomposition built (leaves, 2-D vertices, polygons,
 * output) and leaves those fields empty, for ctx_free and for a rebuild. */
static void free_decomposition(sw_ctx *c)
{
    free(c->leaves);
    free(c->leaf_curves);
    hmap_free(&c->corners);
    hmap_free(&c->leafmap);
    free(c->v2);
    hmap_free(&c->v2map);
    free(c->poly_verts);
    free(c->polys);
    free(c->ox);
    hmap_free(&c->outmap);
    free(c->otri);
    free(c->oring);
    free(c->odir);
    free(c->oface);
    c->leaves = NULL; c->nleaves = c->capleaves = 0;
    c->leaf_curves = NULL; c->nleaf_curves = c->capleaf_curves = 0;
    c->v2 = NULL; c->nv2 = c->capv2 = 0;
    c->poly_verts = NULL; c->npv = c->cappv = 0;
    c->polys = NULL; c->npolys = c->cappolys = 0;
    c->ox = NULL; c->nout = c->capout = 0;
    c->otri = NULL; c->notri = c->capotri = 0;
    c->oring = NULL;
    c->odir = NULL;
    c->oface = NULL;
    c->caporing = c->capodir = c->capoface = 0;
}

static void ctx_free(sw_ctx *c)
{
    hmap_free(&c->refine);
    free(c->lx);
    free(c->vr);
    free(c->tris);
    free(c->tcurves);
    free(c->gstart);
    free(c->gcurves);
    free(c->cstamp);
    free(c->vstamp);
    free(c->hstamp);
    free(c->curves);
    free(c->bin_start);
    free(c->bin_items);
    free(c->stamp);
    free(c->cand);
    free(c->xphi);
    free(c->xtri);
    free(c->xentry);
    free(c->arcs);
    free(c->xpool);
    free_decomposition(c);
}

/* Drops everything built by one placement of the decomposition (the solid, its curves
 * and bins stay). */
static void reset_attempt(sw_ctx *c, sw_out *o)
{
    free_decomposition(c);
    free(o->phi);
    hmap_free(&o->lifts);
    o->phi = NULL;
    o->capphi = 0;
    c->narcs = 0;
    c->nxpool = 0;
}

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

/* The grid of placement `attempt` (0 .. 3) of the decomposition over the part's (r, z)
 * range: finest cell size, depth, origin and roots; leaves0: the first placement's leaves. */
static void place_grid(sw_ctx *c, int attempt, double rmax, double zmin, double zmax,
                       double tolerance, int64_t leaves0)
{
    static const double grid_scale[4] = {1.0123456789, 1.0371093751, 0.9812988281, 1.0557861328};
    static const double grid_shift[4] = {0.0371, 0.0629, 0.0147, 0.0853};
    double ext = fmax(rmax, zmax - zmin);
    c->ext = ext;
    c->quantum = ldexp(ext, -40);
    c->bounding_only = attempt >= 2;
    double S0 = 0.5 * ext * grid_scale[attempt];
    double hmin = 0.25 * tolerance;
    int lmax = 0;
    while (lmax < 40 && ldexp(S0, -lmax) > hmin)
        lmax++;
    c->lmax = lmax;
    c->h = ldexp(S0, -lmax);
    c->hmin = c->h;
    c->r0 = 0;
    c->z0 = zmin - grid_shift[attempt] * S0;
    c->nroot_r = (int64_t)floor(rmax / S0) + 1;
    c->nroot_z = (int64_t)floor((zmax - c->z0) / S0) + 1;
    /* A placement whose tree grows far past the first one's is given up at once: the
     * fallback placements on the 9-face arm grew to 1.4 M and 2.5 M triangles before
     * failing the check anyway (a refusal took 9 s and 1.5 GB). */
    c->capped = 0;
    c->leaf_cap = attempt > 0 ? 4 * leaves0 + 4096 : 0;
}

/* Appends to why (size bytes) the reason a placement was given up: fmt takes the
 * separator, the placement and a count. */
static void why_append(char *why, size_t size, const char *fmt, int attempt, long long n)
{
    size_t lw = strlen(why);
    snprintf(why + lw, size - lw, fmt, lw ? "; " : "", attempt, n);
}

/* The check of a placement's surface: a closed 2-manifold (*valid), whose shells do not
 * cross and which holds the input's volume, then its planar pieces merged.  1 (go on), 0
 * (a failure in the merge), -1 (out of memory: stop); why (nwhy bytes) says why not valid. */
static int check_surface(sw_ctx *c, double in_volume, char *why, size_t nwhy, int *valid)
{
    mfg_mesh_report rep;
    mfg_status cs = mfg_mesh_check_closed(c->ox, c->nout, c->otri, c->notri, &rep);
    if (cs != MFG_OK) {
        if (cs == MFG_ERR_NOMEM) {
            ctx_nomem(c);
            return -1;
        }
        snprintf(why, nwhy, "%s", mfg_last_error());
        return 1;
    }
    *valid = 1;
    int overlap = 0;
    if (!sw_drop_nested_shells(c, &overlap))
        return -1;
    if (overlap) {
        /* treated like an open surface: another placement, or a refusal */
        *valid = 0;
        snprintf(why, nwhy, "two of its shells cross each other");
    } else if (!(sw_mesh_volume(c->ox, c->otri, c->notri) >= in_volume * (1 - SW_EPS_VOLUME))) {
        /* SV holds O (t = 0): a closed surface holding less is wrong somewhere, like an
         * open one (found by fuzz_api) */
        *valid = 0;
        snprintf(why, nwhy, "it holds less volume than the input");
    }
    /* the merge of planar pieces last, on the shells that are kept (it reads oface, which
     * drop_nested_shells keeps aligned with the triangles) */
    if (*valid)
        return sw_merge_faces(c);
    return 1;
}

/* The result mesh in the caller's frame: only the vertices the triangles use (lifts and
 * ring points left over by cancelled twins are dropped), numbered in order of first use. */
static int output_mesh(sw_ctx *c, int scale_exp, mfg_mesh **out)
{
    mfg_mesh *m = calloc(1, sizeof *m);
    if (m) {
        m->vertices = malloc((size_t)(3 * c->nout + 1) * sizeof *m->vertices);
        m->triangles = malloc((size_t)(3 * c->notri + 1) * sizeof *m->triangles);
    }
    if (!m || !m->vertices || !m->triangles) {
        if (m) {
            free(m->vertices);
            free(m->triangles);
            free(m);
        }
        return ctx_nomem(c);
    }
    int ok = 1;
    /* only the vertices the triangles use (lifts and ring points left over by
     * cancelled twins are dropped), numbered in order of first use */
    int64_t *map = malloc((size_t)(c->nout + 1) * sizeof *map);
    if (!map) {
        free(m->vertices);
        free(m->triangles);
        free(m);
        m = NULL;
        ok = ctx_nomem(c);
    } else {
        for (int64_t i = 0; i < c->nout; i++)
            map[i] = -1;
        int64_t nused = 0;
        for (int64_t i = 0; i < 3 * c->notri; i++) {
            int64_t w = c->otri[i];
            if (map[w] < 0) {
                map[w] = nused;
                const double *p = c->ox + 3 * w;
                for (int k = 0; k < 3; k++) {
                    double x = c->origin[k] + p[0] * c->frame[0][k] + p[1] * c->frame[1][k] +
                               p[2] * c->frame[2][k];
                    m->vertices[3 * nused + k] = fabs(x) < 0x1p-200 ? 0 : ldexp(x, scale_exp);
                }
                nused++;
            }
            m->triangles[i] = map[w];
        }
        free(map);
        m->nvertices = nused;
        m->ntriangles = c->notri;
    }
    *out = ok ? m : NULL;
    return ok;
}

/* The result's bounding box, volume and area. */
static void sweep_stats(const sw_ctx *c, int scale_exp, const mfg_mesh *m, mfg_sweep_stats *out)
{
    mfg_sweep_stats S;
    memset(&S, 0, sizeof S);
    for (int k = 0; k < 3; k++) {
        S.bbox[k] = INFINITY;
        S.bbox[3 + k] = -INFINITY;
    }
    for (int64_t i = 0; i < m->nvertices; i++)
        for (int k = 0; k < 3; k++) {
            S.bbox[k] = fmin(S.bbox[k], m->vertices[3 * i + k]);
            S.bbox[3 + k] = fmax(S.bbox[3 + k], m->vertices[3 * i + k]);
        }
    double area = 0;
    for (int64_t t = 0; t < c->notri; t++) {
        const double *a = c->ox + 3 * c->otri[3 * t], *b = c->ox + 3 * c->otri[3 * t + 1],
                     *d = c->ox + 3 * c->otri[3 * t + 2];
        double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double e2[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
               cz = e1[0] * e2[1] - e1[1] * e2[0];
        area += 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
    }
    /* c->ox is at unit scale (the caller's numbers times 2^-scale_exp); m is not */
    S.volume = ldexp(sw_mesh_volume(c->ox, c->otri, c->notri), 3 * scale_exp); /* about the axis point */
    S.area = ldexp(area, 2 * scale_exp);
    *out = S;
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
    int64_t *nb = NULL;
    st = mfg_mesh_require_closed(xyz, nvertices, triangles, ntriangles, NULL, &nb);
    if (st != MFG_OK)
        return st; /* its message numbers the caller's triangles */
    free(nb);
    nb = NULL;
    /* from here on the canonical copy (sweep/canonical.c): the result does not depend on
     * the caller's order; it is as closed as the caller's mesh, so the check passes */
    double *canon_xyz = NULL;
    int64_t *canon_tris = NULL;
    if (!sw_canonical_input(xyz, nvertices, triangles, ntriangles, &canon_xyz, &canon_tris))
        return mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    xyz = canon_xyz;
    triangles = canon_tris;
    st = mfg_mesh_require_closed(xyz, nvertices, triangles, ntriangles, NULL, &nb);
    if (st != MFG_OK) {
        free(canon_xyz);
        free(canon_tris);
        return st;
    }
    /* Unit scale (issue 20: results changed with the unit, by up to 42 % in volume after
     * scaling by 2^-120, and expressions of degree 8 overflowed from ~2e51 up).  The copy,
     * the axis point and the tolerance are divided by S = 2^scale_exp, the power of two of
     * the part's extent about the axis point; scaling by a power of two is exact in binary
     * floating point (barring subnormals), so every later operation rounds exactly as it
     * would on the caller's numbers times 2^-scale_exp, every constant of the stages is
     * relative to the part's size, and the input scaled by 2^k gives the same result
     * scaled by 2^k, bit for bit.  The output is scaled back in output_mesh / sweep_stats. */
    int scale_exp = sweep_scale_exponent(xyz, nvertices, axis_point);
    double unit_point[3];
    for (int64_t i = 0; i < 3 * nvertices; i++)
        canon_xyz[i] = ldexp(canon_xyz[i], -scale_exp);
    for (int k = 0; k < 3; k++)
        unit_point[k] = ldexp(axis_point[k], -scale_exp);
    axis_point = unit_point;
    tolerance = ldexp(tolerance, -scale_exp);
    /* A tolerance the coordinates cannot resolve is refused (issue 20: a unit cube at
     * 1e15, ulp 0.125, tol 0.02 was accepted and its turned corners lay 0.088 outside):
     * at least 2^12 ulps of the largest coordinate, so the rounding of every constructed
     * point stays far below it; and at least 2^-24 of the part's extent about the axis
     * point (unit scale: the extent is in [1/2, 1)), which bounds the decomposition's
     * depth and work (1e-9 of the part ran 5 minutes and 2 GB without an answer). */
    {
        double maxabs = 0;
        for (int64_t i = 0; i < 3 * nvertices; i++)
            maxabs = fmax(maxabs, fabs(canon_xyz[i]));
        for (int k = 0; k < 3; k++)
            maxabs = fmax(maxabs, fabs(unit_point[k]));
        int me = 0;
        (void)frexp(maxabs, &me);
        double min_tol = fmax(ldexp(1.0, me - 53 + SW_TOL_MIN_ULPS_LOG2), ldexp(1.0, SW_TOL_MIN_REL_LOG2));
        if (tolerance < min_tol) {
            free(nb);
            free(canon_xyz);
            free(canon_tris);
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: tolerance %g is below what this "
                            "input resolves (coordinates up to %g, part extent about the axis "
                            "point up to %g): the smallest accepted is %g",
                            ldexp(tolerance, scale_exp), ldexp(maxabs, scale_exp),
                            ldexp(1.0, scale_exp), ldexp(min_tol, scale_exp));
        }
    }
    /* A tolerance comparable to the part (fuzzing: 2.2 on a part of ~4 left a turned
     * vertex 3.9 outside) is met by computing to 1/16 of the unit extent instead: a
     * tighter result keeps the contract (within tol of SV, containing it). */
    tolerance = fmin(tolerance, SW_TOL_MAX_UNIT);
    sw_ctx c;
    memset(&c, 0, sizeof c);
    c.st = MFG_OK;
    c.prog = &prog;
    c.nv = nvertices;
    c.nt = ntriangles;
    c.full_turn = angle >= MFG_TWO_PI - SW_FULL_TURN_EPS;
    c.theta = c.full_turn ? MFG_TWO_PI : angle;
    c.tol = tolerance;
    sw_make_frame(&c, axis_point, axis_direction);
    sw_out o;
    memset(&o, 0, sizeof o);
    int ok = sw_setup(&c, xyz, triangles, nb);
    free(nb);
    double rmax = 0, zmin = INFINITY, zmax = -INFINITY;
    if (ok) {
        for (int64_t i = 0; i < c.nv; i++) {
            rmax = fmax(rmax, c.vr[i]);
            zmin = fmin(zmin, c.lx[3 * i + 2]);
            zmax = fmax(zmax, c.lx[3 * i + 2]);
        }
        ok = sw_build_bins(&c, rmax, zmin, zmax);
        if (ok)
            ok = sw_build_gap_curves(&c);
    }
    /* The decomposition's grid is placed by odd factors, so that its lines rarely pass
     * through vertices or along edges of round-numbered parts.  When they do and the
     * result is not a closed 2-manifold (checked as the input is), the decomposition is
     * built again on a grid placed differently; after the last placement the call fails
     * with MFG_ERR_INTERNAL rather than return an open surface. */
    double in_volume = ok ? sw_mesh_volume(c.lx, triangles, ntriangles) : 0;
    int attempt = 0, valid = 0;
    int64_t leaves0 = 0;
    char why[256] = "";
    for (attempt = 0; ok && attempt < 4 && !valid; attempt++) {
        if (attempt > 0)
            reset_attempt(&c, &o);
        place_grid(&c, attempt, rmax, zmin, zmax, tolerance, leaves0);
        ok = sw_stage(&c, "sweep: cells", 0.05, 0.35, SWEEP_EVERY_CELLS) && sw_build_quadtree(&c);
        if (attempt == 0)
            leaves0 = c.nleaves;
        if (ok && c.capped) {
            why_append(why, sizeof why, "%splacement %d given up past %lld cells", attempt,
                       (long long)c.leaf_cap);
            continue;
        }
        /* A cut that fails in build_polygons (a chord or star whose vertices do not come
         * out on the loop) leaves a block the size of its cell, beyond the tolerance where
         * the cell is coarse: the cube spun about its diagonal had vertices 1.03 tol
         * outside SV, from blocks a quarter of the part wide.  Such cells are refined when
         * the tree is built again, until no cut fails above the finest size; a placement
         * that still has such blocks after 8 rounds is given up (another placement, or a
         * refusal). */
        hmap_free(&c.refine);
        if (ok && !hmap_init(&c.refine, 64))
            ok = ctx_nomem(&c);
        int rounds = 0;
        for (;;) {
            c.coarse_blocks = 0;
            ok = ok && sw_stage(&c, "sweep: polygons", 0.35, 0.6, SWEEP_EVERY_LEAVES) &&
                 sw_build_polygons(&c);
            if (!ok || !c.coarse_blocks || ++rounds > 8)
                break;
            reset_attempt(&c, &o);
            ok = sw_stage(&c, "sweep: cells", 0.05, 0.35, SWEEP_EVERY_CELLS) &&
                 sw_build_quadtree(&c);
            if (ok && c.capped)
                break;
        }
        if (ok && c.capped) {
            why_append(why, sizeof why, "%splacement %d given up past %lld cells", attempt,
                       (long long)c.leaf_cap);
            continue;
        }
        if (ok && c.coarse_blocks) {
            why_append(why, sizeof why, "%splacement %d: %lld cuts failed in coarse cells",
                       attempt, (long long)c.coarse_blocks);
            continue;
        }
        if (ok)
            ok = hmap_init(&c.outmap, 1024) && hmap_init(&o.lifts, 1024) ? 1 : ctx_nomem(&c);
        /* the walls: one unit per polygon, then the strips and faces (build_walls), the
         * twins and the pinches, each reported when done */
        if (ok)
            ok = sw_stage(&c, "sweep: walls", 0.6, 0.85, SWEEP_EVERY_POLYS) &&
                 sw_build_walls(&c, &o) && sw_report(&c, 0.7) && sw_cancel_twins(&c) &&
                 sw_report(&c, 0.8) && sw_resolve_pinches(&c, &o);
        ok = ok && sw_stage(&c, "sweep: check", 0.85, 0.95, 1);
        if (ok) {
            int r = check_surface(&c, in_volume, why, sizeof why, &valid);
            if (r < 0) {
                ok = 0;
                break;
            }
            ok = r;
        }
    }
    if (ok && !valid) {
        ok = 0;
        c.st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the swept surface could not be made "
                        "a closed 2-manifold (%s) on 4 placements of the decomposition; please "
                        "report this input", why);
    }
    if (ok)
        ok = sw_stage(&c, "sweep: output", 0.95, 1.0, 1) && sw_flip_out_slivers(&c);
    mfg_mesh *m = NULL;
    if (ok)
        ok = output_mesh(&c, scale_exp, &m);
    if (ok && !sw_stage(&c, "sweep: done", 1.0, 1.0, 1)) {
        mfg_mesh_free(m);
        m = NULL;
        ok = 0;
    }
    if (ok) {
        if (out_stats)
            sweep_stats(&c, scale_exp, m, out_stats);
        *out_mesh = m;
    }
    st = ok ? MFG_OK : c.st;
    free(o.phi);
    hmap_free(&o.lifts);
    ctx_free(&c);
    free(canon_xyz);
    free(canon_tris);
    if (st == MFG_OK)
        mfg_clear_error();
    return st;
}
