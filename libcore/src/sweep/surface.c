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

int sw_surface(sw_env *e, double **ox, int64_t *nox, int64_t **ot, int64_t *not_)
{
    mfg_rmesh soup = {e->x, e->nv, e->capv, e->st, e->nst, e->capst, e->sgroup};
    if (!mfg_chain_weld(&soup, SW_SOUP_WELD)) {
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
        return 0;
    }
    e->nst = soup.nt;
    static const arr_stages stages = {
        {"sweep: intersections", "sweep: faces", "sweep: boundary"}, {0.3, 0.55, 0.8, 0.9}};
    arr_table T;
    arr_face *F = NULL;
    int64_t nf = 0, *tcl = NULL, ncl = 0;
#ifdef ARR_DEBUG
    fprintf(stderr, "soup: %lld triangles, %lld vertices (input %lld)\n", (long long)e->nst,
            (long long)e->nv, (long long)e->nin);
    {
        hmap bal;
        memset(&bal, 0, sizeof bal);
        if (!hmap_init(&bal, 3 * e->nst + 1)) return 0;
        int64_t *cnt = calloc((size_t)(3 * e->nst + 1), sizeof *cnt), nk = 0;
        for (int64_t t = 0; t < e->nst; t++)
            for (int k = 0; k < 3; k++) {
                int64_t a = e->st[3 * t + k], b = e->st[3 * t + (k + 1) % 3];
                hkey key = mkkey(a < b ? a : b, a < b ? b : a, 0, 0);
                int64_t id = hmap_get(&bal, &key);
                if (id < 0) { id = nk++; hmap_put(&bal, &key, id); }
                cnt[id] += a < b ? 1 : -1;
            }
        int64_t open = 0;
        for (int64_t i = 0; i < nk; i++) open += cnt[i] != 0;
        fprintf(stderr, "soup: %lld unbalanced edges\n", (long long)open);
        if (getenv("MFG_SWEEP_DUMP")) {
            FILE *fp = fopen(getenv("MFG_SWEEP_DUMP"), "w");
            fprintf(fp, "%lld %lld\n", (long long)e->nv, (long long)e->nst);
            for (int64_t i = 0; i < e->nv; i++) fprintf(fp, "%.17g %.17g %.17g\n", e->x[3*i], e->x[3*i+1], e->x[3*i+2]);
            for (int64_t t = 0; t < e->nst; t++) fprintf(fp, "%lld %lld %lld\n", (long long)e->st[3*t], (long long)e->st[3*t+1], (long long)e->st[3*t+2]);
            fclose(fp);
        }
        free(cnt);
        hmap_free(&bal);
    }
#endif
    mfg_status st = arr_union_boundary(e->x, e->nv, e->st, e->nst, e->prog, &stages, &T, &F,
                                       &nf, &tcl, &ncl);
    if (st != MFG_OK) {
        e->st_code = st;
        return 0;
    }
    int64_t G = e->ngroups;
    int64_t *uf = malloc((size_t)(G + ncl + 1) * sizeof *uf);
    int64_t *map = malloc((size_t)(T.npts + 1) * sizeof *map);
    double *x = malloc((size_t)(3 * 3 * nf + 3) * sizeof *x);
    int64_t *tri = malloc((size_t)(3 * nf + 3) * sizeof *tri);
    int64_t *grp = malloc((size_t)(nf + 1) * sizeof *grp);
    int ok = uf && map && x && tri && grp;
    if (ok) {
        for (int64_t i = 0; i < G + ncl; i++)
            uf[i] = i;
        for (int64_t t = 0; t < e->nst; t++)
            if (e->sgroup[t] >= 0 && tcl[t] >= 0)
                uf_join(uf, e->sgroup[t], G + tcl[t]);
        for (int64_t i = 0; i < T.npts; i++)
            map[i] = -1;
        int64_t nv = 0;
        arr_points P = arr_view(&T);
        for (int64_t f = 0; f < nf; f++) {
            for (int k = 0; k < 3; k++) {
                int64_t p = F[f].v[k];
                if (map[p] < 0) {
                    map[p] = nv;
                    arr_coords(&P, p, x + 3 * nv);
                    nv++;
                }
                tri[3 * f + k] = map[p];
            }
            grp[f] = uf_find(uf, G + F[f].cluster);
        }
        mfg_rmesh rm = {x, nv, 3 * nf + 1, tri, nf, nf + 1, grp};
        int repaired = mfg_mesh_repair(&rm, SW_REPAIR_EPS);
        x = rm.x;
        nv = rm.nv;
        tri = rm.t;
        nf = rm.nt;
        grp = rm.g;
        mfg_mesh_report rep;
        st = repaired ? mfg_mesh_check_closed(x, nv, tri, nf, &rep) : MFG_ERR_NOMEM;
        if (st == MFG_OK) {
            int64_t ntri = nf;
            if (!mfg_merge_planar_groups(x, nv, tri, &ntri, grp, NULL))
                st = MFG_ERR_NOMEM;
            nf = ntri;
        } else if (st != MFG_ERR_NOMEM) {
            char why[256];
            snprintf(why, sizeof why, "%s", mfg_last_error());
            st = mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: the boundary is not a closed "
                          "2-manifold (%s); please report this input", why);
#ifdef ARR_DEBUG
            if (getenv("MFG_SWEEP_NOCHECK"))
                st = MFG_OK;
#endif
        }
        if (st == MFG_OK) {
            *ox = x;
            *nox = nv;
            *ot = tri;
            *not_ = nf;
            x = NULL;
            tri = NULL;
        } else {
            e->st_code = st == MFG_ERR_NOMEM
                             ? mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory")
                             : st;
            ok = 0;
        }
    } else {
        e->st_code = mfg_fail(MFG_ERR_NOMEM, "rotational sweep: out of memory");
    }
    free(uf);
    free(map);
    free(x);
    free(tri);
    free(grp);
    free(F);
    free(tcl);
    arr_table_free(&T);
    return ok;
}
