/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/arrange.c - The pipeline: triangles to clusters and meeting segments (pairs.c),
 * each cluster's faces (cluster.c, cdt.c), the faces that bound {w >= 1} (winding.c). */
#include "arrange/arrange.h"

static void ctx_free(arr_ctx *c)
{
    free(c->tcluster);
    free(c->cl);
    free(c->seg);
    free(c->segcl);
    free(c->pt);
    free(c->ptcl);
    free(c->face);
    arr_cdt_free(c);
}

/* 1 when the triangle has zero area, exactly: all three projections are degenerate. */
static int zero_area(const arr_points *P, const int64_t *V)
{
    if (V[0] == V[1] || V[1] == V[2] || V[2] == V[0])
        return 1;
    for (int k = 0; k < 3; k++)
        if (arr_orient2d(P, V[0], V[1], V[2], k) != 0)
            return 0;
    return 1;
}

int arr_over_budget(arr_ctx *c)
{
    if (c->max_points <= 0 || c->T.npts <= c->max_points)
        return 0;
    c->st = mfg_fail(MFG_ERR_INTERNAL, "arrangement: more than %lld points, the caller's bound",
                     (long long)c->max_points);
    return 1;
}

/* The pipeline; every_face: stop after the clusters' faces (all of them, no winding). */
static mfg_status run(const double *xyz, int64_t nv, const int64_t *tri, int64_t ntri,
                      mfg_prog *prog, const arr_stages *stages, arr_table *table,
                      arr_face **out_faces, int64_t *nfaces, int64_t **out_tcluster,
                      int64_t *nclusters, int every_face)
{
    arr_ctx c;
    memset(&c, 0, sizeof c);
    c.prog = prog;
    c.tri = tri;
    c.ntri = ntri;
    c.max_points = stages->max_points;
    c.st = MFG_OK;
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++)
            c.super[a][k] = -1;
    *out_faces = NULL;
    *nfaces = 0;
    if (!arr_table_init(&c.T, xyz, nv))
        return mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
    c.tcluster = malloc((size_t)(ntri + 1) * sizeof *c.tcluster);
    double *boxes = malloc((size_t)(6 * ntri + 6) * sizeof *boxes);
    arr_bvh *bvh = NULL;
    uint8_t *keep = NULL;
    if (!c.tcluster || !boxes) {
        c.st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        goto done;
    }
    if (!mfg_prog_stage(prog, stages->name[0], stages->at[0], stages->at[1], 4096)) {
        c.st = MFG_ERR_CANCELLED;
        goto done;
    }
    arr_points P = arr_view(&c.T);
    for (int64_t t = 0; t < ntri; t++) {
        const int64_t *V = tri + 3 * t;
        c.tcluster[t] = zero_area(&P, V) ? -1 : 0;
        for (int k = 0; k < 3; k++) {
            boxes[6 * t + k] = fmin(xyz[3 * V[0] + k], fmin(xyz[3 * V[1] + k], xyz[3 * V[2] + k]));
            boxes[6 * t + 3 + k] = fmax(xyz[3 * V[0] + k], fmax(xyz[3 * V[1] + k], xyz[3 * V[2] + k]));
        }
    }
    bvh = arr_bvh_build(boxes, ntri);
    if (!bvh) {
        c.st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        goto done;
    }
    if (!arr_pairs(&c, bvh))
        goto done;
    if (!mfg_prog_stage(prog, stages->name[1], stages->at[1], stages->at[2], 256)) {
        c.st = MFG_ERR_CANCELLED;
        goto done;
    }
    if (!arr_clusters(&c))
        goto done;
    if (every_face) {
        *out_faces = c.face;
        *nfaces = c.nface;
        c.face = NULL;
        goto done;
    }
    if (!mfg_prog_stage(prog, stages->name[2], stages->at[2], stages->at[3], 64)) {
        c.st = MFG_ERR_CANCELLED;
        goto done;
    }
    keep = calloc((size_t)(c.nface + 1), 1);
    if (!keep) {
        c.st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        goto done;
    }
    if (!arr_boundary_faces(&c, bvh, keep))
        goto done;
    int64_t n = 0;
    for (int64_t f = 0; f < c.nface; f++)
        if (keep[f])
            c.face[n++] = c.face[f];
    *out_faces = c.face;
    *nfaces = n;
    c.face = NULL;
    if (out_tcluster) {
        *out_tcluster = c.tcluster;
        c.tcluster = NULL;
    }
    if (nclusters)
        *nclusters = c.ncl;
done:
    free(boxes);
    free(keep);
    arr_bvh_free(bvh);
    mfg_status st = c.st;
    ctx_free(&c);
    if (st == MFG_OK)
        *table = c.T;
    else
        arr_table_free(&c.T);
    return st;
}

mfg_status arr_union_boundary(const double *xyz, int64_t nv, const int64_t *tri, int64_t ntri,
                              mfg_prog *prog, const arr_stages *stages, arr_table *table,
                              arr_face **out_faces, int64_t *nfaces, int64_t **out_tcluster,
                              int64_t *nclusters)
{
    return run(xyz, nv, tri, ntri, prog, stages, table, out_faces, nfaces, out_tcluster,
               nclusters, 0);
}

mfg_status arr_cluster_faces(const double *xyz, int64_t nv, const int64_t *tri, int64_t ntri,
                             mfg_prog *prog, const arr_stages *stages, arr_table *table,
                             arr_face **out_faces, int64_t *nfaces)
{
    return run(xyz, nv, tri, ntri, prog, stages, table, out_faces, nfaces, NULL, NULL, 1);
}

mfg_status arr_chain2d_faces(const double *xyz, int64_t nv, const int64_t *seg, int64_t nseg,
                             mfg_prog *prog, arr_table *table, arr_face **out_faces,
                             int64_t *nfaces)
{
    arr_ctx c;
    memset(&c, 0, sizeof c);
    c.prog = prog;
    c.st = MFG_OK;
    for (int a = 0; a < 3; a++)
        for (int k = 0; k < 3; k++)
            c.super[a][k] = -1;
    *out_faces = NULL;
    *nfaces = 0;
    if (!arr_table_init(&c.T, xyz, nv))
        return mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
    /* one cluster, the plane z = 0, through a triangle of auxiliary points */
    static const double plane[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    int64_t ptri[3];
    c.tri = ptri;
    c.ntri = 1;
    c.tcluster = malloc(sizeof *c.tcluster);
    c.cl = malloc(sizeof *c.cl);
    int ok = c.tcluster && c.cl;
    for (int k = 0; ok && k < 3; k++)
        ok = (ptri[k] = arr_aux_vertex(&c.T, plane[k])) >= 0;
    if (!ok) {
        c.st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
    } else {
        c.tcluster[0] = 0;
        c.cl[0].rep = 0;
        c.cl[0].axis = 2;
        c.cl[0].sign = 1;
        c.ncl = 1;
        if (arr_planar_chain(&c, seg, nseg)) {
            *out_faces = c.face;
            *nfaces = c.nface;
            c.face = NULL;
        }
    }
    c.tri = NULL;
    mfg_status st = c.st;
    ctx_free(&c);
    if (st == MFG_OK)
        *table = c.T;
    else
        arr_table_free(&c.T);
    return st;
}
