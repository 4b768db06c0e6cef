/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect.c - maximum (and level-k, minimum) intersection of spherical convex sets by
 * edge-based partition (Ha 2001, seed 000 section 4): the entry points. */
#include <math.h>
#include <stdlib.h>

#include "sphere/maxisect.h"

/* Work units between progress reports: cells taken from the search queue, candidates
 * turned into regions. */
#define MAXISECT_EVERY_CELLS 256
#define MAXISECT_EVERY_CANDIDATES 16

/*
 * Edge-based partition, as in the paper: every boundary edge of every set is split by
 * the other sets and each piece gets its ownership (the weight of the sets containing
 * it); the pieces of greatest ownership bound the maximum regions, and a region of
 * maximum weight D is exactly the intersection of the sets covering it (any point of that
 * intersection covered by one more set would beat D), hence convex.
 * How it is done here:
 *  - maxisect_sets.c checks the input and prepares each set: unit vertices, inward edge
 *    normals, a bounding cap, an inscribed circle and, for large polygons, the fan of
 *    triangles about its inscribed centre (membership and clipping in O(log v));
 *  - maxisect_search.c does branch and bound over cells of the sphere (the cube's faces
 *    quartered again and again): a cell knows the weight of the sets holding it whole
 *    and the sets (and their pieces) meeting it partly, so its bound prunes it;
 *  - in a cell with few partial sets, maxisect_sweep.c sweeps the pieces there: an edge
 *    a->b is parametrised by s in [0, 1] through x(s) = a + s (b - a) (a central
 *    projection of the arc, so every half-space constraint x.n >= -tol is linear in s),
 *    the part inside another convex set is one interval, and sweeping the intervals'
 *    ends (closed sets: a start sorts before an end at equal s) gives the ownership of
 *    every piece and point; those reaching the limit become candidates;
 *  - maxisect_regions.c turns each distinct cover set of a candidate into one region:
 *    the intersection of the set (the visibility map of its members' edge normals), its
 *    centre the centre of the smallest circle enclosing the poles of its edges (= the
 *    largest inscribed circle, the paper's dual construction), by Welzl's algorithm.
 * Coverage is decided with the angular tolerance MFG_SPHERE_TOL (a set contains the
 * directions within that distance), so the outcome does not depend on rounding in the
 * inputs' vertices; the order of the input sets does not enter any decision.  Weights
 * are scaled by a power of two and compared relative to their total, so only their
 * ratios matter.
 */

/* The three entry points differ only in the search mode and the region rule. */
mfg_status mfg_maxisect_run(int mode, const ms_input *in, double level, mfg_regions **out,
                            int64_t *ncells)
{
    return mfg_maxisect_run_p(mode, in, level, out, ncells, NULL, "mfg_maxisect_run");
}

mfg_status mfg_maxisect_run_p(int mode, const ms_input *in, double level, mfg_regions **out,
                              int64_t *ncells, const mfg_progress *progress, const char *call)
{
    if (ncells)
        *ncells = 0;
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out is NULL");
    mfg_prog prog;
    mfg_prog_init(&prog, progress, call);
    if (!mfg_prog_stage(&prog, "maxisect: sets", 0, 0.05, 1))
        return mfg_prog_fail(&prog);
    work W;
    mfg_status st = mfg_sets_prepare(in, &W);
    W.prog = &prog;
    double eps = W.eps, lev = mode == MODE_LEVEL ? ldexp(level, -W.scale_exp) : 0.0;
    if (st == MFG_OK && !mfg_prog_stage(&prog, "maxisect: search", 0.05, 0.8, MAXISECT_EVERY_CELLS))
        st = mfg_prog_fail(&prog);
    if (st == MFG_OK)
        st = mfg_cell_search(&W, mode, lev, eps);
    if (st == MFG_OK &&
        !mfg_prog_stage(&prog, "maxisect: regions", 0.8, 1.0, MAXISECT_EVERY_CANDIDATES))
        st = mfg_prog_fail(&prog);
    mfg_regions *res = NULL;
    if (st == MFG_OK)
        st = mfg_regions_of(&W, mode == MODE_LEVEL, mode == MODE_LEVEL ? lev : W.best, eps, &res);
    if (st == MFG_OK && !mfg_prog_stage(&prog, "maxisect: done", 1.0, 1.0, 1)) {
        mfg_regions_free(res);
        st = mfg_prog_fail(&prog);
    }
    /* A level is reported as asked for: scaled to a subnormal (or scaled back) it would
     * lose bits, and only the comparisons, which have the tolerance, use the scaled one. */
    if (st == MFG_OK && mode == MODE_LEVEL)
        res->weight = level;
    if (st == MFG_OK)
        *out = res;
    if (ncells)
        *ncells = W.ncells;
    mfg_sets_free(&W);
    if (st == MFG_OK)
        mfg_clear_error();
    return st;
}

mfg_status mfg_max_intersection(const double *vertices, const int64_t *offsets,
                                const int32_t *kinds, const int32_t *closed, int64_t npolys,
                                const double *weights, mfg_regions **out)
{
    return mfg_max_intersection_p(vertices, offsets, kinds, closed, npolys, weights, out, NULL);
}

mfg_status mfg_max_intersection_p(const double *vertices, const int64_t *offsets,
                                  const int32_t *kinds, const int32_t *closed, int64_t npolys,
                                  const double *weights, mfg_regions **out,
                                  const mfg_progress *progress)
{
    ms_input in = {vertices, offsets, kinds, closed, npolys, weights};
    return mfg_maxisect_run_p(MODE_MAX, &in, 0.0, out, NULL, progress, "mfg_max_intersection");
}

mfg_status mfg_level_regions(const double *vertices, const int64_t *offsets,
                             const int32_t *kinds, const int32_t *closed, int64_t npolys,
                             const double *weights, double level, mfg_regions **out)
{
    return mfg_level_regions_p(vertices, offsets, kinds, closed, npolys, weights, level, out,
                               NULL);
}

mfg_status mfg_level_regions_p(const double *vertices, const int64_t *offsets,
                               const int32_t *kinds, const int32_t *closed, int64_t npolys,
                               const double *weights, double level, mfg_regions **out,
                               const mfg_progress *progress)
{
    if (!(level > -1e300 && level < 1e300))
        return mfg_fail(MFG_ERR_INVALID, "level must be finite (got %g)", level);
    ms_input in = {vertices, offsets, kinds, closed, npolys, weights};
    return mfg_maxisect_run_p(MODE_LEVEL, &in, level, out, NULL, progress, "mfg_level_regions");
}

mfg_status mfg_min_intersection(const double *vertices, const int64_t *offsets,
                                const int32_t *kinds, const int32_t *closed, int64_t npolys,
                                const double *weights, mfg_regions **out)
{
    return mfg_min_intersection_p(vertices, offsets, kinds, closed, npolys, weights, out, NULL);
}

mfg_status mfg_min_intersection_p(const double *vertices, const int64_t *offsets,
                                  const int32_t *kinds, const int32_t *closed, int64_t npolys,
                                  const double *weights, mfg_regions **out,
                                  const mfg_progress *progress)
{
    ms_input in = {vertices, offsets, kinds, closed, npolys, weights};
    return mfg_maxisect_run_p(MODE_MIN, &in, 0.0, out, NULL, progress, "mfg_min_intersection");
}

void mfg_regions_free(mfg_regions *r)
{
    if (!r)
        return;
    free(r->kinds);
    free(r->closed);
    free(r->vertex_offsets);
    free(r->vertices);
    free(r->cover_offsets);
    free(r->cover);
    free(r->centres);
    free(r->margins);
    free(r);
}
