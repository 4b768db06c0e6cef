/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/surface.c - From the chain to the result: the boundary of {w >= 1} by the exact
 * arrangement (arrange/), its points rounded once, and the pieces of each plane merged
 * and triangulated again on their outlines (mesh/planar_merge.c).
 *
 * A plane's pieces: the arrangement's faces of one cluster lie in one plane exactly; the
 * pieces of one planar face of the input (F at t = 0, or B turned by theta) lie in one
 * plane up to the rounding of their cut points, and so do clusters that share a member
 * with such a face: all of them form one group (union-find over the input's planar
 * groups and the clusters). */
#include <stdio.h>

#include "sweep/envelope.h"
#include "mesh/mesh.h"
#include "mesh/mesh_repair.h"
#include "mesh/planar_merge.h"

static int64_t uf_find(int64_t *uf, int64_t i)
{
    while (uf[i] != i) {
        uf[i] = uf[uf[i]];
        i = uf[i];
    }
    return i;
}

static void uf_join(int64_t *uf, int64_t a, int64_t b)
{
    a = uf_find(uf, a);
    b = uf_find(uf, b);
    if (a < b)
        uf[b] = a;
    else if (b < a)
        uf[a] = b;
}

/* Points closer than this (unit scale; the tolerance is at least 2^-24) are welded and
 * needles thinner than it removed (mesh/mesh_repair.h): the surface moves by at most
 * this, far inside the tolerance's headroom. */
#define SW_REPAIR_EPS 0x1p-40
/* Points of the chain closer than this are welded before the arrangement: turns of
 * different vertices onto one position (a part symmetric about the axis, whose strips
 * coincide when the steps line up) come out of the rounding a few ulps apart, and as
 * separate points they would make the arrangement cut nearly coincident sheets into
 * slivers; welded, the sheets are one plane's (a cluster) and add up exactly. */
#define SW_SOUP_WELD 0x1p-36

/* How often the rounded boundary is arranged again: rounding the arrangement's implicit
 * points (and the welds of the repair) can make faces that met only along an edge cross
 * by an ulp, or fold a sliver; arranged again, the rounded surface's crossings become
 * points of their own and its boundary of {w >= 1} is taken once more.  Every pass moves
 * points by less than the last; a surface whose arrangement has no new point has no
 * crossing and is the result. */
#define SW_ROUND_PASSES 4

/* One arrangement of the closed chain (x, nv; tri, nt; grp: per triangle a planar group
 * below G or -1; NULL: none), its boundary rounded to the grid, repaired and closed-checked, each
 * plane's pieces merged.  *clean = 1 when the arrangement made no point of its own (the
 * chain was already free of crossings: the output is then the chain's own surface).
 * Returns MFG_OK with the new mesh in *out (grp: its planar groups). */
static mfg_status round_pass(sw_env *e, const double *x0, int64_t nv0, const int64_t *tri0,
                             int64_t nt0, const int64_t *grp0, int64_t G, mfg_rmesh *out,
                             int *clean)
{
    static const arr_stages stages = {
        {"sweep: intersections", "sweep: faces", "sweep: boundary"}, {0.3, 0.55, 0.8, 0.9}};
    arr_table T;
    arr_face *F = NULL;
    int64_t nf = 0, *tcl = NULL, ncl = 0;
    mfg_status st = arr_union_boundary(x0, nv0, tri0, nt0, e->prog, &stages, &T, &F, &nf,
                                       &tcl, &ncl);
    if (st != MFG_OK)
        return st;
    int64_t *uf = malloc((size_t)(G + ncl + 1) * sizeof *uf);
    int64_t *map = malloc((size_t)(T.npts + 1) * sizeof *map);
    double *x = malloc((size_t)(3 * 3 * nf + 3) * sizeof *x);
    int64_t *tri = malloc((size_t)(3 * nf + 3) * sizeof *tri);
    int64_t *grp = malloc((size_t)(nf + 1) * sizeof *grp);
    st = uf && map && x && tri && grp ? MFG_OK : MFG_ERR_NOMEM;
    if (st == MFG_OK) {
        for (int64_t i = 0; i < G + ncl; i++)
            uf[i] = i;
        for (int64_t t = 0; t < nt0; t++)
            if (grp0 && grp0[t] >= 0 && tcl[t] >= 0)
                uf_join(uf, grp0[t], G + tcl[t]);
        for (int64_t i = 0; i < T.npts; i++)
            map[i] = -1;
        int64_t nv = 0;
        *clean = nf == nt0;
        arr_points P = arr_view(&T);
        for (int64_t f = 0; f < nf; f++) {
            for (int k = 0; k < 3; k++) {
                int64_t p = F[f].v[k];
                if (map[p] < 0) {
                    map[p] = nv;
                    arr_coords(&P, p, x + 3 * nv);
                    for (int j = 0; j < 3; j++)
                        x[3 * nv + j] = sw_snap(x[3 * nv + j]);
                    nv++;
                }
                if (p >= nv0)
                    *clean = 0;
                tri[3 * f + k] = map[p];
            }
            grp[f] = uf_find(uf, G + F[f].cluster);
        }
        mfg_rmesh rm = {x, nv, 3 * nf + 1, tri, nf, nf + 1, grp};
        int repaired = mfg_mesh_repair(&rm, SW_REPAIR_EPS);
        x = rm.x;
        tri = rm.t;
        grp = rm.g;
        mfg_mesh_report rep;
        st = repaired ? mfg_mesh_check_closed(rm.x, rm.nv, rm.t, rm.nt, &rep) : MFG_ERR_NOMEM;
        if (st == MFG_OK) {
            int64_t ntri = rm.nt;
            if (!*clean && !mfg_merge_planar_groups(rm.x, rm.nv, rm.t, &ntri, rm.g, NULL))
                st = MFG_ERR_NOMEM;
            rm.nt = ntri;
        } else if (st != MFG_ERR_NOMEM) {
            char why[256];
            snprintf(why, sizeof why, "%s", mfg_last_error());
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the boundary is not a closed "
                          "2-manifold (%s); please report this input", why);
        }
        if (st == MFG_OK) {
            *out = rm;
            x = NULL;
            tri = NULL;
            grp = NULL;
        }
    }
    if (st == MFG_ERR_NOMEM)
        st = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    free(uf);
    free(map);
    free(x);
    free(tri);
    free(grp);
    free(F);
    free(tcl);
    arr_table_free(&T);
    return st;
}

int sw_surface(sw_env *e, double **ox, int64_t *nox, int64_t **ot, int64_t *not_)
{
    mfg_rmesh soup = {e->x, e->nv, e->capv, e->st, e->nst, e->capst, e->sgroup};
    if (!mfg_chain_weld(&soup, SW_SOUP_WELD)) {
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
        return 0;
    }
    e->nst = soup.nt;
#ifdef ARR_DEBUG
    if (getenv("MFG_SWEEP_DUMP")) {
        FILE *fp = fopen(getenv("MFG_SWEEP_DUMP"), "w");
        fprintf(fp, "%lld %lld\n", (long long)e->nv, (long long)e->nst);
        for (int64_t i = 0; i < e->nv; i++)
            fprintf(fp, "%.17g %.17g %.17g\n", e->x[3 * i], e->x[3 * i + 1], e->x[3 * i + 2]);
        for (int64_t t = 0; t < e->nst; t++)
            fprintf(fp, "%lld %lld %lld\n", (long long)e->st[3 * t], (long long)e->st[3 * t + 1],
                    (long long)e->st[3 * t + 2]);
        fclose(fp);
    }
#endif
    /* the first pass arranges the soup; later ones the previous pass's rounded surface,
     * whose pieces of one plane are merged only where they are still exactly one plane
     * (a cluster of that pass) */
    mfg_rmesh cur = {0}, next = {0};
    int clean = 0;
    mfg_status st = round_pass(e, e->x, e->nv, e->st, e->nst, e->sgroup, e->ngroups, &cur, &clean);
    for (int pass = 1; st == MFG_OK; pass++) {
        st = round_pass(e, cur.x, cur.nv, cur.t, cur.nt, NULL, 0, &next, &clean);
        if (st != MFG_OK)
            break;
        if (clean) { /* cur had no crossing: it is the result */
            free(next.x);
            free(next.t);
            free(next.g);
            break;
        }
        free(cur.x);
        free(cur.t);
        free(cur.g);
        cur = next;
        memset(&next, 0, sizeof next);
        if (pass + 1 >= SW_ROUND_PASSES) {
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the rounded boundary still "
                          "crosses itself after %d passes; please report this input", pass + 1);
            break;
        }
    }
    if (st == MFG_OK) {
        *ox = cur.x;
        *nox = cur.nv;
        *ot = cur.t;
        *not_ = cur.nt;
        free(cur.g);
        return 1;
    }
    free(cur.x);
    free(cur.t);
    free(cur.g);
    e->st_code = st;
    return 0;
}
