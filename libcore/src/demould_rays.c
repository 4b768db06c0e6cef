/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* demould_rays.c - the ray test of demouldability (issue 17): does the ray from a sample
 * point along +d or -d leave the part without crossing one of its triangles? */
#include <math.h>
#include <stdlib.h>

#include "mesh.h"
#include "mfg_internal.h"
#include "predicates.h"

/*
 * All rays are parallel to d, so a ray can only meet a triangle whose projection along d
 * covers the projection of its origin.  The triangles not parallel to d are projected
 * along d onto the coordinate plane most nearly normal to d (dropping the axis k of the
 * largest |d_k|): x -> (x_i - x_k d_i / d_k, x_j - x_k d_j / d_k).  Their projected
 * bounding boxes, padded for rounding, are filed in a uniform grid (counting sort into
 * CSR lists); a point tests the triangles of the one cell its projection falls in.  The
 * grid only selects candidates: whether a ray meets a triangle is decided exactly.
 *
 * Exact test of the line L = {p + s d} against triangle abc (n = (b - a) x (c - a)):
 *   e_ab = sign det[a - p, b - p, d], e_bc, e_ca likewise: L passes every directed edge
 *   on the same side (all +, or all -) iff it pierces the triangle's interior; a zero
 *   among otherwise equal signs: it passes through an edge or a vertex; mixed: it misses.
 *   The crossing is at s* = ((a - p) . n) / (d . n); (a - p) . n = det[a-p, b-p, c-p]
 *   (orient3d(a, b, c, p)) and d . n = det[b - a, c - a, d], so the sign of s* is exact.
 * d . n = 0 (d parallel to the plane, or a zero-area triangle) means no crossing point:
 * such triangles are not filed at all.
 *
 * Rounding of the projection: the computed r = d_i / d_k (|r| <= 1), r * x_k and the
 * difference carry at most 4u (|x_i| + |x_j| + |x_k|) error each (u = 2^-53); a point
 * whose exact projection lies in a triangle's exact projection is within twice that of
 * the computed bounding box.  The pad is 64u times the largest such sum over all the
 * vertices and points: never too small, and far below any cell.
 */

#define U 1.1102230246251565e-16

/* Entries allowed per filed triangle before the grid is made coarser (long thin
 * triangles, e.g. the strips of a cylinder, would otherwise cover many cells each). */
#define ENTRIES_PER_TRIANGLE 16

typedef struct ray_grid {
    int axis_i, axis_j, axis_k;
    double ri, rj;          /* d_i / d_k, d_j / d_k */
    double x0, y0;          /* origin of the grid */
    double inv, inv_y;      /* cells per unit along u and v */
    int64_t gx, gy;         /* cells per row, rows */
    int64_t *offsets;       /* gx * gy + 1 */
    int64_t *entries;       /* triangle indices, by cell */
} ray_grid;

static inline void project(const ray_grid *g, const double *x, double *u, double *v)
{
    *u = x[g->axis_i] - g->ri * x[g->axis_k];
    *v = x[g->axis_j] - g->rj * x[g->axis_k];
}

/* The cell coordinate of projected value t along an axis of n cells: monotone in t, so
 * a value inside a padded box falls in a cell of the box's range. */
static inline int64_t cell_of(double t, double t0, double inv, int64_t n)
{
    double c = (t - t0) * inv;
    if (!(c >= 0.0))
        return -1;
    if (c >= (double)n)
        return n;
    int64_t ci = (int64_t)c;
    return ci < n ? ci : n - 1;
}

static inline int64_t clamp_cell(int64_t c, int64_t n)
{
    return c < 0 ? 0 : (c >= n ? n - 1 : c);
}

/* Sign of s* of the crossing of line p + s d with triangle abc, and where: 2 interior,
 * 1 edge or vertex, 0 no crossing.  dn is the sign of d . n (non-zero). */
static int cross_line(const double *p, const double *a, const double *b, const double *c,
                      const double *d, int dn, int *side)
{
    int e0 = mfg_orient3d_vec(p, a, b, d);
    int e1 = mfg_orient3d_vec(p, b, c, d);
    if (e0 * e1 < 0)
        return 0;
    int e2 = mfg_orient3d_vec(p, c, a, d);
    if (e0 * e2 < 0 || e1 * e2 < 0)
        return 0;
    int sp = mfg_orient3d(a, b, c, p);
    *side = sp * dn;
    if (*side == 0)
        return 0;
    return (e0 != 0 && e1 != 0 && e2 != 0) ? 2 : 1;
}

mfg_status mfg_ray_blocked(const double *xyz, int64_t nvertices, const int64_t *triangles,
                           int64_t ntriangles, const double *points,
                           const int64_t *own_triangle, int64_t npoints,
                           const double direction[3], uint8_t *blocked_out)
{
    mfg_status st = mfg_mesh_validate(xyz, nvertices, triangles, ntriangles);
    if (st != MFG_OK)
        return st;
    if (npoints < 0 || npoints > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "npoints must be between 0 and %lld (got %lld)",
                        (long long)MFG_MAX_COUNT, (long long)npoints);
    if (!direction)
        return mfg_fail(MFG_ERR_NULL, "direction is NULL");
    if (npoints > 0 && !points)
        return mfg_fail(MFG_ERR_NULL, "points is NULL");
    if (npoints > 0 && !blocked_out)
        return mfg_fail(MFG_ERR_NULL, "blocked_out is NULL");
    for (int k = 0; k < 3; k++)
        if (!mfg_coord_ok(direction[k]))
            return mfg_fail(MFG_ERR_INVALID,
                            "direction has a NaN, infinite or out-of-range component (%g)",
                            direction[k]);
    if (direction[0] == 0 && direction[1] == 0 && direction[2] == 0)
        return mfg_fail(MFG_ERR_INVALID, "direction is the zero vector");
    for (int64_t i = 0; i < 3 * npoints; i++)
        if (!mfg_coord_ok(points[i]))
            return mfg_fail(MFG_ERR_INVALID,
                            "point %lld has a NaN, infinite or out-of-range coordinate (%g)",
                            (long long)(i / 3), points[i]);
    if (own_triangle)
        for (int64_t i = 0; i < npoints; i++)
            if (own_triangle[i] < -1 || own_triangle[i] >= ntriangles)
                return mfg_fail(MFG_ERR_INVALID,
                                "own_triangle[%lld] = %lld is neither -1 nor a triangle index 0 .. %lld",
                                (long long)i, (long long)own_triangle[i],
                                (long long)(ntriangles - 1));

    const double *d = direction;
    ray_grid g;
    g.axis_k = 0;
    for (int k = 1; k < 3; k++)
        if (fabs(d[k]) > fabs(d[g.axis_k]))
            g.axis_k = k;
    g.axis_i = (g.axis_k + 1) % 3;
    g.axis_j = (g.axis_k + 2) % 3;
    g.ri = d[g.axis_i] / d[g.axis_k];
    g.rj = d[g.axis_j] / d[g.axis_k];

    /* Sizes: counts <= 2^40, so every allocation below is far below SIZE_MAX. */
    int8_t *dn = malloc((size_t)ntriangles + 1);
    double *box = malloc(((size_t)ntriangles + 1) * 4 * sizeof *box);
    int64_t *cells = malloc(((size_t)ntriangles + 1) * 4 * sizeof *cells);
    if (!dn || !box || !cells) {
        free(dn);
        free(box);
        free(cells);
        return mfg_fail(MFG_ERR_NOMEM, "out of memory for the ray grid of %lld triangles",
                        (long long)ntriangles);
    }

    /* The pad: 64u times the largest |x| + |y| + |z| of a vertex or a point. */
    double big = 0;
    for (int64_t v = 0; v < nvertices; v++) {
        const double *x = xyz + 3 * v;
        double s = fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
        big = s > big ? s : big;
    }
    for (int64_t i = 0; i < npoints; i++) {
        const double *x = points + 3 * i;
        double s = fabs(x[0]) + fabs(x[1]) + fabs(x[2]);
        big = s > big ? s : big;
    }
    double pad = 64.0 * U * big + MFG_MIN_COORD;

    /* The triangles that can be crossed, their sign of d . n and padded boxes. */
    int64_t nfiled = 0;
    double lo_u = INFINITY, lo_v = INFINITY, hi_u = -INFINITY, hi_v = -INFINITY;
    for (int64_t t = 0; t < ntriangles; t++) {
        const double *a = xyz + 3 * triangles[3 * t], *b = xyz + 3 * triangles[3 * t + 1];
        const double *c = xyz + 3 * triangles[3 * t + 2];
        dn[t] = (int8_t)mfg_orient3d_vec(a, b, c, d);
        if (dn[t] == 0)
            continue;
        double u[3], v[3];
        project(&g, a, &u[0], &v[0]);
        project(&g, b, &u[1], &v[1]);
        project(&g, c, &u[2], &v[2]);
        double *bx = box + 4 * t;
        bx[0] = fmin(u[0], fmin(u[1], u[2])) - pad;
        bx[1] = fmin(v[0], fmin(v[1], v[2])) - pad;
        bx[2] = fmax(u[0], fmax(u[1], u[2])) + pad;
        bx[3] = fmax(v[0], fmax(v[1], v[2])) + pad;
        lo_u = fmin(lo_u, bx[0]);
        lo_v = fmin(lo_v, bx[1]);
        hi_u = fmax(hi_u, bx[2]);
        hi_v = fmax(hi_v, bx[3]);
        nfiled++;
    }

    /* Grid: about one cell per filed triangle, cells shaped like the mean box (long thin
     * triangles, e.g. the strips of a cylinder seen from the side, then cover a cell or
     * two each instead of a whole row), made coarser while the boxes would cover more
     * than ENTRIES_PER_TRIANGLE cells each on average. */
    g.x0 = lo_u;
    g.y0 = lo_v;
    g.gx = g.gy = 1;
    g.inv = g.inv_y = 1.0;
    int64_t nentries = 0;
    if (nfiled > 0) {
        double w = hi_u - lo_u, h = hi_v - lo_v, mw = 0, mh = 0;
        for (int64_t t = 0; t < ntriangles; t++)
            if (dn[t]) {
                mw += box[4 * t + 2] - box[4 * t];
                mh += box[4 * t + 3] - box[4 * t + 1];
            }
        /* cw * ch = w * h / nfiled and cw / ch = mw / mh, each within the domain */
        double aspect = (mw > 0 && mh > 0) ? mw / mh : 1.0;
        double cell_area = w * h / (double)nfiled;
        double ch = sqrt(cell_area / aspect), cw = ch * aspect;
        if (!(cw <= w)) {
            cw = w;
            ch = cell_area / w;
        }
        if (!(ch <= h)) {
            ch = h;
            cw = fmin(w, cell_area / h);
        }
        if (!(cw > 0))
            cw = w > 0 ? w : 1.0;
        if (!(ch > 0))
            ch = h > 0 ? h : 1.0;
        for (;;) {
            double nx = ceil(w / cw), ny = ceil(h / ch);
            g.gx = nx < 1 ? 1 : (nx > 1e9 ? 1000000000 : (int64_t)nx);
            g.gy = ny < 1 ? 1 : (ny > 1e9 ? 1000000000 : (int64_t)ny);
            g.inv = (double)g.gx / w;
            g.inv_y = (double)g.gy / h;
            if (!(g.inv > 0) || !isfinite(g.inv))
                g.inv = 1.0, g.gx = 1;
            if (!(g.inv_y > 0) || !isfinite(g.inv_y))
                g.inv_y = 1.0, g.gy = 1;
            nentries = 0;
            for (int64_t t = 0; t < ntriangles; t++) {
                if (!dn[t])
                    continue;
                const double *bx = box + 4 * t;
                int64_t *cl = cells + 4 * t;
                cl[0] = clamp_cell(cell_of(bx[0], g.x0, g.inv, g.gx), g.gx);
                cl[1] = clamp_cell(cell_of(bx[1], g.y0, g.inv_y, g.gy), g.gy);
                cl[2] = clamp_cell(cell_of(bx[2], g.x0, g.inv, g.gx), g.gx);
                cl[3] = clamp_cell(cell_of(bx[3], g.y0, g.inv_y, g.gy), g.gy);
                nentries += (cl[2] - cl[0] + 1) * (cl[3] - cl[1] + 1);
            }
            if ((nentries <= ENTRIES_PER_TRIANGLE * nfiled &&
                 g.gx * g.gy <= 4 * nfiled + 16) || (g.gx == 1 && g.gy == 1))
                break;
            cw *= 2.0;
            ch *= 2.0;
        }
    }
    int64_t ncells = g.gx * g.gy;
    g.offsets = calloc((size_t)ncells + 1, sizeof *g.offsets);
    g.entries = malloc(((size_t)nentries + 1) * sizeof *g.entries);
    if (!g.offsets || !g.entries) {
        free(dn);
        free(box);
        free(cells);
        free(g.offsets);
        free(g.entries);
        return mfg_fail(MFG_ERR_NOMEM, "out of memory for a ray grid of %lld entries",
                        (long long)nentries);
    }
    for (int64_t t = 0; t < ntriangles && nfiled > 0; t++) {
        if (!dn[t])
            continue;
        const int64_t *cl = cells + 4 * t;
        for (int64_t cy = cl[1]; cy <= cl[3]; cy++)
            for (int64_t cx = cl[0]; cx <= cl[2]; cx++)
                g.offsets[cy * g.gx + cx + 1]++;
    }
    for (int64_t c = 0; c < ncells; c++)
        g.offsets[c + 1] += g.offsets[c];
    /* Fill with a moving cursor per cell (the cells array is reused as nothing else
     * needs the boxes' cell ranges after this pass). */
    int64_t *cursor = malloc(((size_t)ncells + 1) * sizeof *cursor);
    if (!cursor) {
        free(dn);
        free(box);
        free(cells);
        free(g.offsets);
        free(g.entries);
        return mfg_fail(MFG_ERR_NOMEM, "out of memory for a ray grid of %lld cells",
                        (long long)ncells);
    }
    memcpy(cursor, g.offsets, (size_t)ncells * sizeof *cursor);
    for (int64_t t = 0; t < ntriangles && nfiled > 0; t++) {
        if (!dn[t])
            continue;
        const int64_t *cl = cells + 4 * t;
        for (int64_t cy = cl[1]; cy <= cl[3]; cy++)
            for (int64_t cx = cl[0]; cx <= cl[2]; cx++)
                g.entries[cursor[cy * g.gx + cx]++] = t;
    }
    free(cursor);
    free(cells);

    /* The queries: nothing can fail from here on. */
    for (int64_t i = 0; i < npoints; i++) {
        const double *p = points + 3 * i;
        int64_t own = own_triangle ? own_triangle[i] : -1;
        uint8_t bits = 0;
        double pu, pv;
        project(&g, p, &pu, &pv);
        /* Outside the union of the padded boxes no triangle can be met; inside, the
         * clamped cell is in the cell range of every box holding the point. */
        if (nfiled > 0 && pu >= lo_u && pu <= hi_u && pv >= lo_v && pv <= hi_v) {
            int64_t cx = clamp_cell(cell_of(pu, g.x0, g.inv, g.gx), g.gx);
            int64_t cy = clamp_cell(cell_of(pv, g.y0, g.inv_y, g.gy), g.gy);
            int64_t c = cy * g.gx + cx;
            for (int64_t e = g.offsets[c]; e < g.offsets[c + 1]; e++) {
                int64_t t = g.entries[e];
                if (t == own)
                    continue;
                const double *bx = box + 4 * t;
                if (pu < bx[0] || pu > bx[2] || pv < bx[1] || pv > bx[3])
                    continue;
                const double *a = xyz + 3 * triangles[3 * t];
                const double *b = xyz + 3 * triangles[3 * t + 1];
                const double *cc = xyz + 3 * triangles[3 * t + 2];
                int side = 0;
                int where = cross_line(p, a, b, cc, d, dn[t], &side);
                if (where == 2)
                    bits |= side > 0 ? MFG_RAY_BLOCKED_POS : MFG_RAY_BLOCKED_NEG;
                else if (where == 1)
                    bits |= side > 0 ? MFG_RAY_GRAZES_POS : MFG_RAY_GRAZES_NEG;
                if ((bits & (MFG_RAY_BLOCKED_POS | MFG_RAY_BLOCKED_NEG)) ==
                        (MFG_RAY_BLOCKED_POS | MFG_RAY_BLOCKED_NEG) &&
                    (bits & (MFG_RAY_GRAZES_POS | MFG_RAY_GRAZES_NEG)) ==
                        (MFG_RAY_GRAZES_POS | MFG_RAY_GRAZES_NEG))
                    break;
            }
        }
        blocked_out[i] = bits;
    }
    free(dn);
    free(box);
    free(g.offsets);
    free(g.entries);
    mfg_clear_error();
    return MFG_OK;
}
