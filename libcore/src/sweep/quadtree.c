/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/quadtree.c - The meridian decomposition: the quadtree: a cell's analysis (clean,
 * split, star, chords, fan or refine) and the tree of cells.  Overview and file map:
 * sweep/sweep.h. */
#include "sweep/sweep.h"

typedef struct sw_samples {
    hmap cache;            /* (ix, iz) -> index in pool */
    sw_struct *pool;
    int64_t n, cap;
} sw_samples;

/* Decides what to do with cell (ix, iz, level); fills the leaf fields and appends the
 * curves that pass through the cell to leaf_curves. */
/* What analyse_cell finds in a cell: its geometry and samples, the vertex images in it and
 * the curves through it (with their side crossings), from which classify_cell chooses the
 * cell's kind. */
typedef struct {
    int64_t s, vs;                 /* size in finest units; the cell's stamp */
    double ra, rb, za, zb;
    sw_struct centre;
    const sw_struct *all[5];       /* the samples: 4 corners, the centre */
    int any_arc;
    int64_t nimg;                  /* vertex images in the closed cell: 0, 1, 2 (many) */
    double img[2];
    int64_t imgv;
    int img_inside;
    int64_t npass, ncross_split, all_from_img, one_cross_each;
    int star_sag_ok;
    int img_on_axis, axis_touch;
    double touch_z;
    int all_spokes;
    double aeps, peps;
    double split_u[2], split_p[2][2];
    int64_t second_curve, ncross_second;
    double second_u[2], second_p[2][2];
    sw_jcurve jc[SW_MAXJUNCTION];
    int njc, jn_ok;
} sw_cellscan;

/* The samples of cell L (its corners and centre), the triangles that bound SV at them
 * (stamped S->vs), the triangles near the cell and those hidden in it. */
static int cell_samples(sw_ctx *c, sw_samples *sp, sw_leaf *L, sw_cellscan *S)
{
    S->s = (int64_t)1 << (c->lmax - L->level);
    S->ra = sw_grid_r(c, L->ix), S->rb = sw_grid_r(c, L->ix + S->s);
    S->za = sw_grid_z(c, L->iz), S->zb = sw_grid_z(c, L->iz + S->s);
    int64_t ci[4];
    int64_t cx[4] = {L->ix, L->ix + S->s, L->ix + S->s, L->ix}, cz[4] = {L->iz, L->iz, L->iz + S->s, L->iz + S->s};
    for (int k = 0; k < 4; k++)
        if (!sw_corner_sample(c, &sp->cache, cx[k], cz[k], &sp->pool, &sp->n, &sp->cap, &ci[k]))
            return 0;
    if (!sw_circle_arcs(c, 0.5 * (S->ra + S->rb), 0.5 * (S->za + S->zb), &S->centre))
        return 0;
    L->cfirst = c->nleaf_curves;
    L->cn = 0;
    L->split_curve = -1;
    L->cvtx = -1;
    L->empty = 0;
    /* the triangles that bound SV at the samples */
    c->stampv++;
    S->vs = c->stampv;
    for (int k = 0; k < 4; k++)
        S->all[k] = &sp->pool[ci[k]];
    S->all[4] = &S->centre;
    S->any_arc = 0;
    for (int k = 0; k < 5; k++) {
        if (S->all[k]->full || S->all[k]->n)
            S->any_arc = 1;

        for (int64_t a = 0; a < S->all[k]->n; a++) {
            const sw_arc *arc = &c->arcs[S->all[k]->first + a];
            c->vstamp[arc->start.tri] = S->vs;
            c->vstamp[arc->end.tri] = S->vs;
        }
    }
    if (!sw_gather(c, S->ra, S->rb, S->za, S->zb))
        return 0;
    /* the triangles hidden in the cell (the bounding ones never are) */
    if (!c->bounding_only && !sw_mark_hidden(c, &S->centre, S->ra, S->rb, S->za, S->zb, S->vs))
        return 0;
    return 1;
}

/* The vertex images in the closed cell (of the triangles not hidden in it). */
static void cell_images(const sw_ctx *c, sw_cellscan *S)
{
    /* vertex images in the closed cell */
    S->nimg = 0;
    S->img[0] = S->img[1] = 0;
    S->imgv = -1;
    S->img_inside = 0;
    for (int64_t k = 0; k < c->ncand; k++) {
        const sw_tri *T = &c->tris[c->cand[k]];
        if (c->hstamp[c->cand[k]] == S->vs)
            continue;
        for (int q = 0; q < 3; q++) {
            int64_t v = T->v[q];
            double r = c->vr[v], z = c->lx[3 * v + 2];
            if (r < S->ra || r > S->rb || z < S->za || z > S->zb)
                continue;
            if (S->nimg == 0) {
                S->img[0] = r;
                S->img[1] = z;
                S->imgv = v;
                S->img_inside = r > S->ra && r < S->rb && z > S->za && z < S->zb;
                S->nimg = 1;
            } else if (S->nimg == 1 && (r != S->img[0] || z != S->img[1])) {
                S->nimg = 2;
            }
        }
    }
}

/* One curve ic of a triangle near the cell: its crossings with the cell's sides, recorded
 * in L's curves and in S for the split, star, half-star, crossing and junction tests. */
static int cell_curve(sw_ctx *c, sw_leaf *L, sw_cellscan *S, int64_t ic)
{
    const sw_curve *cv = &c->curves[ic];
    if (cv->gexit >= 0 && c->hstamp[cv->gexit] == S->vs)
        return 1; /* the exit turned onto this triangle is hidden */
    if (cv->rmax < S->ra || cv->rmin > S->rb || cv->zmax < S->za || cv->zmin > S->zb)
        return 1;
    int ncr = 0, nd = 0;
    double us[8], pts[8][2];
    for (int sd = 0; sd < 4; sd++) {
        int rside;
        double val, lo, hi, pos[2], uu[2];
        sw_side_geom(c, L->ix, L->iz, S->s, sd, &rside, &val, &lo, &hi);
        int m = sw_curve_side(cv, rside, val, lo, hi, pos, uu);
        for (int j = 0; j < m && ncr < 8; j++) {
            double pr = rside ? val : pos[j], pz = rside ? pos[j] : val;
            int dup = 0;
            for (int q2 = 0; q2 < nd; q2++)
                dup |= fabs(pts[q2][0] - pr) <= S->peps && fabs(pts[q2][1] - pz) <= S->peps;
            if (!dup) {
                pts[nd][0] = pr;
                pts[nd][1] = pz;
                us[nd++] = uu[j];
            }
            ncr++;
        }
    }
    ncr = nd; /* a curve folded on its image (a horizontal edge) meets a side
                 twice at one point */
    int end_in = 0;
    for (int e = 0; e < 2; e++) {
        double u = (double)e;
        double r = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
        double z = cv->p0[2] + u * cv->dir[2];
        if (r > S->ra && r < S->rb && z > S->za && z < S->zb)
            end_in = 1;
    }
    /* a horizontal curve inside the open cell has no crossing with a z side but
     * may cross neither r side either when it ends inside: end_in covers it */
    if (ncr == 0 && !end_in)
        return 1;
    if (!mfg_grow((void **)&c->leaf_curves, &c->capleaf_curves, c->nleaf_curves + 1,
              sizeof *c->leaf_curves))
        return ctx_nomem(c);
    c->leaf_curves[c->nleaf_curves++] = ic;
    L->cn++;
    /* curves with one image (the edges of a face perpendicular to the axis, a
     * silhouette along an edge) cut the cell along one chord: one group */
    int same_chord = S->npass > 0 && S->ncross_split == 2 && !end_in && ncr == 2 &&
                     ((fabs(pts[0][0] - S->split_p[0][0]) <= S->peps && fabs(pts[0][1] - S->split_p[0][1]) <= S->peps &&
                       fabs(pts[1][0] - S->split_p[1][0]) <= S->peps && fabs(pts[1][1] - S->split_p[1][1]) <= S->peps) ||
                      (fabs(pts[0][0] - S->split_p[1][0]) <= S->peps && fabs(pts[0][1] - S->split_p[1][1]) <= S->peps &&
                       fabs(pts[1][0] - S->split_p[0][0]) <= S->peps && fabs(pts[1][1] - S->split_p[0][1]) <= S->peps));
    /* a second chord (for a crossing of two chords, below), with its own group
     * of coincident curves */
    int same_second = !same_chord && S->npass == 2 && S->ncross_second == 2 && !end_in &&
                      ncr == 2 && sw_same_pair(pts, S->second_p, S->peps);
    if (!same_chord && !same_second)
        S->npass++;
    if (S->npass == 2 && !same_chord && !same_second) {
        S->second_curve = ic;
        S->ncross_second = end_in ? -1 : ncr;
        if (ncr == 2) {
            S->second_u[0] = us[0];
            S->second_u[1] = us[1];
            memcpy(S->second_p, pts, sizeof S->second_p);
        }
    }
    if (S->npass == 1 && !same_chord) {
        L->split_curve = ic;
        S->ncross_split = end_in ? -1 : ncr;
        if (ncr == 2) {
            S->split_u[0] = us[0];
            S->split_u[1] = us[1];
            memcpy(S->split_p, pts, sizeof S->split_p);
        }
    }
    /* star: the curve must end at the vertex image and leave the cell once */
    int from_img = 0;
    for (int e = 0; e < 2; e++) {
        double u = (double)e;
        double r = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
        double z = cv->p0[2] + u * cv->dir[2];
        /* an end at a mesh vertex: the vertex's own image (r(1) from the
         * quadratic differs from it by rounding, and the star was refused) */
        if (cv->vtx[e] >= 0) {
            r = c->vr[cv->vtx[e]];
            z = c->lx[3 * cv->vtx[e] + 2];
        }
        if (S->nimg == 1 && r == S->img[0] && z == S->img[1]) {
            from_img = 1;
            /* the spoke is the chord from the image to the crossing: within
             * tol/4 of the curve, as a split's chord (an edge whose image leaves
             * the image of its end nearest the axis tangentially bends away from
             * its chord by more than the tolerance over a coarse cell: the
             * result missed SV there by 3 tol, box about a face diagonal) */
            if (ncr == 1 && sw_curve_sag(cv, fmin(u, us[0]), fmax(u, us[0])) > 0.25 * c->tol)
                S->star_sag_ok = 0;
        }
    }
    /* a horizontal curve at the image's height passing through it (an edge or
     * the image of a face perpendicular to the axis, running through the image
     * of a vertex of that face: the 9-face arm's top corners) is two spokes of
     * the star, one to each r side: its image is exactly the line z = const */
    int through_img = S->nimg == 1 && cv->dir[2] == 0 && cv->p0[2] == S->img[1];
    /* ... also when it ends at the image or folds back over it (a diagonal of a
     * face perpendicular to the axis, whose image runs in to its nearest point
     * and back out to the vertex): every point of it in the cell is on that
     * line, so every crossing is a spoke, if no end other than the image lies
     * inside the cell */
    for (int e = 0; e < 2 && through_img; e++) {
        double r = cv->vtx[e] >= 0 ? c->vr[cv->vtx[e]] : sw_curve_r(cv, (double)e);
        if (r > S->ra && r < S->rb && !(cv->vtx[e] >= 0 ? r == S->img[0] : fabs(r - S->img[0]) <= S->aeps))
            through_img = 0;
    }
    if (!from_img && !through_img)
        S->all_from_img = 0;
    if (ncr != 1 && !through_img)
        S->one_cross_each = 0;
    if (S->img_on_axis) {
        /* a spoke of the half star: from the image (or, a horizontal curve
         * folded on itself, through it) out of the cell once; its crossing
         * with the axis side, if any is found, is the image itself.  The image
         * of a segment from a point of the axis is straight ((r, z) linear in
         * the parameter), so the spoke is exactly its chord. */
        int nat = 0, nother = 0;
        for (int j = 0; j < ncr; j++) {
            if (pts[j][0] == S->ra && fabs(pts[j][1] - S->img[1]) <= S->aeps)
                nat++;
            else
                nother++;
        }
        /* through the image: a crossing of the axis side there (a gap-closing
         * curve's computed end, a horizontal curve folded on itself) */
        if (end_in || nother != 1 || nat > 1 || !(from_img || nat == 1))
            S->all_spokes = 0;
    }
    if (S->axis_touch) {
        /* through the touching point, its one crossing with the axis side: each
         * half of the curve a spoke from it (straight, as above), out of the cell
         * once */
        int nat = 0, nother = 0;
        for (int j = 0; j < ncr; j++) {
            if (pts[j][0] != S->ra) {
                nother++;
                continue;
            }
            if (!(S->touch_z == S->touch_z))
                S->touch_z = pts[j][1];
            if (fabs(pts[j][1] - S->touch_z) <= S->aeps)
                nat++;
            else
                S->all_spokes = 0;
        }
        if (end_in || nat != 1 || nother < 1 || nother > 2)
            S->all_spokes = 0;
    }
    if (S->njc < SW_MAXJUNCTION && ncr <= 2) {
        S->jc[S->njc].curve = ic;
        S->jc[S->njc].ncr = ncr;
        memcpy(S->jc[S->njc].pts, pts, sizeof S->jc[S->njc].pts);
        S->njc++;
    } else {
        S->jn_ok = 0;
    }
    return 1;
}

/* The curves of the triangles near the cell (not hidden in it) through the cell. */
static int cell_curves(sw_ctx *c, sw_leaf *L, sw_cellscan *S)
{
    /* curves of the bounding triangles through the cell */
    S->npass = 0, S->ncross_split = 0, S->all_from_img = 1, S->one_cross_each = 1;
    S->star_sag_ok = 1;
    /* a vertex image on the axis lies on the cell's side r = 0, never strictly inside:
     * a half star round it (below) when every curve is a spoke from it */
    S->img_on_axis = S->nimg == 1 && S->img[0] == 0 && S->ra == 0 && S->img[1] > S->za && S->img[1] < S->zb;
    /* ... and, with no vertex image, round the point where curves touch the axis (an
     * edge or a face diagonal crossing it): their images fold there */
    S->axis_touch = S->nimg == 0 && S->ra == 0;
    S->touch_z = NAN;
    S->all_spokes = 1;
    S->aeps = sw_point_eps(c, S->rb, S->zb);
    memset(S->split_u, 0, sizeof S->split_u), memset(S->split_p, 0, sizeof S->split_p);
    S->second_curve = -1, S->ncross_second = 0;
    memset(S->second_u, 0, sizeof S->second_u), memset(S->second_p, 0, sizeof S->second_p);
    S->peps = SW_EPS_REL * (S->rb - S->ra) + SW_EPS_ROUND * (fabs(S->rb) + fabs(S->zb));
    /* the curves through the cell with their side crossings, for a junction of
     * gap-closing curves or several chords (below) */
    S->njc = 0, S->jn_ok = 1;
    for (int64_t k = 0; k < c->ncand; k++) {
        int64_t t = c->cand[k];
        /* Every triangle near the cell counts, not only those bounding SV at the
         * samples: a face can enter the cell between samples (the inner wall of a
         * ring-shaped sweep entered a large cell whose five samples all missed it).
         * Only the triangles shown hidden on every circle of the cell are left out
         * (mark_hidden).
         * The last two placements fall back to the bounding triangles only, which
         * closes surfaces the full rule leaves open at vertices on the axis (a cube
         * spun about its diagonal), at the price of that blind spot. */
        if ((c->bounding_only && c->vstamp[t] != S->vs) || c->hstamp[t] == S->vs)
            continue;
        int64_t nq = 4 + (c->gstart ? c->gstart[t + 1] - c->gstart[t] : 0);
        for (int64_t q = 0; q < nq; q++) {
            int64_t ic = q < 4 ? c->tcurves[4 * t + q] : c->gcurves[c->gstart[t] + q - 4];
            if (ic < 0 || c->cstamp[ic] == S->vs)
                continue;
            c->cstamp[ic] = S->vs;
            if (!cell_curve(c, L, S, ic))
                return 0;
        }
    }
    return 1;
}

/* The kind of the cell from what cell_samples, cell_images and cell_curves found. */
static void classify_cell(sw_ctx *c, sw_leaf *L, sw_cellscan *S)
{
    int same5 = sw_same_struct(c, S->all[0], S->all[1]) && sw_same_struct(c, S->all[0], S->all[2]) &&
                sw_same_struct(c, S->all[0], S->all[3]) && sw_same_struct(c, S->all[0], S->all[4]);
    if (S->npass == 0 && S->nimg == 0 && same5) {
        L->kind = LEAF_CLEAN;
        return;
    }
    if (S->npass == 1 && S->nimg == 0 && S->ncross_split == 2) {
        const sw_curve *cv = &c->curves[L->split_curve];
        if (sw_curve_sag(cv, S->split_u[0], S->split_u[1]) <= 0.25 * c->tol) {
            /* corners on each side of the chord must agree, and the centre with its side */
            double p[2][2];
            for (int e = 0; e < 2; e++) {
                double u = S->split_u[e];
                p[e][0] = sqrt(fmax(0, cv->qa * u * u + cv->qb * u + cv->qc));
                p[e][1] = cv->p0[2] + u * cv->dir[2];
            }
            double crs[5][2] = {{S->ra, S->za}, {S->rb, S->za}, {S->rb, S->zb}, {S->ra, S->zb},
                                {0.5 * (S->ra + S->rb), 0.5 * (S->za + S->zb)}};
            int side_of[5];
            for (int k = 0; k < 5; k++) {
                double o = (p[1][0] - p[0][0]) * (crs[k][1] - p[0][1]) -
                           (p[1][1] - p[0][1]) * (crs[k][0] - p[0][0]);
                side_of[k] = o > 0 ? 1 : (o < 0 ? -1 : 0);
            }
            int ok = 1;
            for (int k = 0; k < 5 && ok; k++)
                for (int j = k + 1; j < 5 && ok; j++)
                    if (side_of[k] == 0 || side_of[j] == 0 ||
                        (side_of[k] == side_of[j] && !sw_same_struct(c, S->all[k], S->all[j])))
                        ok = 0;
            if (ok) {
                L->kind = LEAF_SPLIT;
                return;
            }
        }
    }
    if (S->nimg == 1 && S->img_inside && S->npass >= 1 && S->all_from_img && S->one_cross_each && S->star_sag_ok) {
        L->kind = LEAF_STAR;
        L->cr = S->img[0];
        L->cz = S->img[1];
        L->cvtx = S->imgv;
        return;
    }
    if ((S->img_on_axis || (S->axis_touch && S->touch_z == S->touch_z)) && S->npass >= 1 && S->all_spokes) {
        /* the half star: built round the image on the axis side (build_polygons) */
        L->kind = LEAF_STAR;
        L->cr = 0;
        L->cz = S->img_on_axis ? S->img[1] : S->touch_z;
        L->cvtx = S->img_on_axis ? S->imgv : -1;
        return;
    }
    if (S->npass == 2 && S->nimg == 0 && S->ncross_split == 2 && S->ncross_second == 2 &&
        sw_crossing_cell(c, L, S->all, S->ra, S->rb, S->za, S->zb, S->split_u, S->second_curve, S->second_u))
        return;
    if (S->nimg == 0 && S->jn_ok && S->njc >= 2 && sw_junction_cell(c, L, S->all, S->ra, S->rb, S->za, S->zb, S->jc, S->njc))
        return;
    if (S->nimg == 0 && S->jn_ok && S->njc >= 2 && sw_chords_cell(c, L, S->all, S->ra, S->rb, S->za, S->zb, S->jc, S->njc, S->peps))
        return;
    if (L->level < c->lmax) {
        L->kind = LEAF_REFINE;
        c->nleaf_curves = L->cfirst; /* the children find their own */
        L->cn = 0;
        return;
    }
    L->kind = LEAF_FAN;
    if (S->nimg == 1 && S->img_inside) {
        L->cr = S->img[0];
        L->cz = S->img[1];
        L->cvtx = S->imgv;
    } else {
        L->cr = 0.5 * (S->ra + S->rb);
        L->cz = 0.5 * (S->za + S->zb);
    }
    return;
}

static int analyse_cell(sw_ctx *c, sw_samples *sp, sw_leaf *L)
{
    if (L->level < c->lmax && c->refine.keys) {
        /* a cell whose cut failed when the polygons were built last time */
        hkey rk = mkkey(L->level, L->ix, L->iz, 0);
        if (hmap_get(&c->refine, &rk) >= 0) {
            L->cfirst = c->nleaf_curves;
            L->cn = 0;
            L->split_curve = -1;
            L->cvtx = -1;
            L->empty = 0;
            L->kind = LEAF_REFINE;
            return 1;
        }
    }
    sw_cellscan S;
    if (!cell_samples(c, sp, L, &S))
        return 0;
    cell_images(c, &S);
    if (c->ncand == 0 && !S.any_arc) {
        L->empty = 1;
        L->kind = LEAF_CLEAN;
        return 1;
    }
    if (!cell_curves(c, L, &S))
        return 0;
    classify_cell(c, L, &S);
    return 1;
}

int sw_build_quadtree(sw_ctx *c)
{
    sw_samples sp;
    memset(&sp, 0, sizeof sp);
    if (!hmap_init(&sp.cache, 1024) || !hmap_init(&c->corners, 1024) ||
        !hmap_init(&c->leafmap, 1024)) {
        hmap_free(&sp.cache);
        return ctx_nomem(c);
    }
    int ok = 1;
    sw_leaf *stack = NULL;
    int64_t nstack = 0, capstack = 0;
    int64_t root = (int64_t)1 << c->lmax;
    for (int64_t j = c->nroot_z - 1; j >= 0 && ok; j--)
        for (int64_t i = c->nroot_r - 1; i >= 0; i--) {
            if (!mfg_grow((void **)&stack, &capstack, nstack + 1, sizeof *stack)) {
                ok = ctx_nomem(c);
                break;
            }
            memset(&stack[nstack], 0, sizeof *stack);
            stack[nstack].ix = i * root;
            stack[nstack].iz = j * root;
            stack[nstack].level = 0;
            nstack++;
        }
    while (ok && nstack > 0) {
        if (c->leaf_cap > 0 && c->nleaves > c->leaf_cap) {
            c->capped = 1;
            break;
        }
        if (!sw_poll(c, (double)c->nleaves, (double)(c->nleaves + 4 * nstack))) {
            ok = 0;
            break;
        }
        sw_leaf L = stack[--nstack];
        /* arcs of the centre sample are scratch: keep the pool from growing without end */
        int64_t mark = c->narcs;
        if (!analyse_cell(c, &sp, &L)) {
            ok = 0;
            break;
        }
        (void)mark;
        if (L.kind == LEAF_REFINE) {
            int64_t h2 = (int64_t)1 << (c->lmax - L.level - 1);
            if (!mfg_grow((void **)&stack, &capstack, nstack + 4, sizeof *stack)) {
                ok = ctx_nomem(c);
                break;
            }
            for (int q = 3; q >= 0; q--) {
                sw_leaf ch;
                memset(&ch, 0, sizeof ch);
                ch.ix = L.ix + (q & 1) * h2;
                ch.iz = L.iz + (q >> 1) * h2;
                ch.level = L.level + 1;
                stack[nstack++] = ch;
            }
            continue;
        }
        if (!mfg_grow((void **)&c->leaves, &c->capleaves, c->nleaves + 1, sizeof *c->leaves)) {
            ok = ctx_nomem(c);
            break;
        }
        c->leaves[c->nleaves] = L;
        int64_t s = (int64_t)1 << (c->lmax - L.level);
        hkey lk = mkkey(L.level, L.ix, L.iz, 0);
        if (!hmap_put(&c->leafmap, &lk, c->nleaves)) {
            ok = ctx_nomem(c);
            break;
        }
        int64_t cxs[4] = {L.ix, L.ix + s, L.ix + s, L.ix}, czs[4] = {L.iz, L.iz, L.iz + s, L.iz + s};
        for (int k = 0; k < 4 && ok; k++) {
            hkey ck = mkkey(cxs[k], czs[k], 0, 0);
            if (!hmap_put(&c->corners, &ck, 1))
                ok = ctx_nomem(c);
        }
        c->nleaves++;
    }
    free(stack);
    hmap_free(&sp.cache);
    free(sp.pool);
    return ok;
}
