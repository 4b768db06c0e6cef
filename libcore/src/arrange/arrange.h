/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/arrange.h - The exact arrangement of a closed triangle chain and the boundary
 * of the region where its winding number is at least one (the second sweep design's
 * boundary evaluation, docs/design/sweep.md; usable for any union of closed meshes).
 *
 * Input: a "soup" of oriented triangles over explicit vertices whose sum is a closed
 * 2-chain (every edge, counted with its directions, cancels; coplanar overlaps, touching
 * and T-junctions allowed), so the winding number w(x) is an integer off the triangles.
 * Output: the faces of the arrangement that separate w <= 0 (in front) from w >= 1
 * (behind), oriented outward, over the arrangement's points (explicit or implicit,
 * arrange/implicit.h): a closed surface bounding {w >= 1}.
 *
 * The stages (one file each):
 *   points.c    the point table: explicit vertices, implicit points by their
 *               construction key, exact position dedupe
 *   bvh.c       a bounding-box hierarchy over the triangles: candidate pairs, rays
 *   pairs.c     coplanar clusters; the segment where two triangles of different planes
 *               meet (exact: orient3d signs, LPI end points, order along the line)
 *   cluster.c   per cluster (triangles of one plane that touch): its segments crossed
 *               (TPI / LPI / SSI points), split at the points on them
 *   cdt.c       the constrained triangulation of a cluster's points and segments and
 *               the multiplicity of each of its faces
 *   winding.c   patches (faces joined across edges with two faces) and one exact ray
 *               per patch for its winding number; the boundary faces
 *   arrange.c   the pipeline
 *
 * Exact: every decision is a predicate of arrange/implicit.h on the explicit
 * coordinates; no point is rounded before the output (arr_coords).  The explicit
 * coordinates must lie on the grid of implicit.h (multiples of 2^-ARR_GRID_LOG2, at most
 * ARR_COORD_MAX in magnitude): the caller snaps.
 */
#ifndef MFG_ARRANGE_ARRANGE_H
#define MFG_ARRANGE_ARRANGE_H

#ifdef ARR_DEBUG /* the debugging prints of arrange/ and sweep/ */
#include <stdio.h>
#include <stdlib.h>
#endif
#include <stdint.h>

#include "arrange/implicit.h"
#include "common/hashmap.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "common/vec3.h"

/* ---- The point table (points.c) ------------------------------------------------------ */

/* Explicit vertex i of the input is point i.  Implicit points are appended, each once per
 * construction key; positions shared by different constructions are merged afterwards
 * by arr_dedupe (canon[]). */
typedef struct arr_table {
    double *xyz;        /* explicit coordinates: the input's, then auxiliary ones */
    int64_t nxyz, capxyz;
    arr_point *pts;
    int64_t npts, cappts;
    hmap keys;          /* construction key -> point id */
    int64_t *canon;     /* after arr_dedupe: the representative of each point's position */
    int64_t ncanon;     /* points covered by canon (the rest are their own) */
    arr_exact_cache *xc; /* exact coordinates last computed (NULL: none) */
} arr_table;

/* Key kinds of implicit points (first word of the key). */
enum { ARR_KEY_LPI = 1, ARR_KEY_TPI = 2, ARR_KEY_SSI = 3, ARR_KEY_AUX = 4 };

int arr_table_init(arr_table *T, const double *xyz, int64_t nv);
void arr_table_free(arr_table *T);
/* The arr_points view predicates take (valid until the table grows). */
static inline arr_points arr_view(const arr_table *T)
{
    arr_points P = {T->xyz, T->nxyz, T->pts, T->npts, T->xc};
    return P;
}
/* The point of segment a-b (explicit) crossing the plane of triangle (p0, p1, p2); the
 * caller knows it crosses.  plane_id names the plane in the key (its cluster).  Returns
 * the point id, or -1 when out of memory. */
int64_t arr_lpi(arr_table *T, int64_t a, int64_t b, int64_t plane_id, const int64_t plane[3]);
/* The point of three planes (each: its id and three explicit vertices). */
int64_t arr_tpi(arr_table *T, const int64_t id[3], const int64_t plane[3][3]);
/* The crossing of coplanar segments a-b and c-d, seen along axis. */
int64_t arr_ssi(arr_table *T, int64_t a, int64_t b, int64_t c, int64_t d, int axis);
/* An explicit auxiliary vertex (a cluster's enclosing triangle, a ray origin's lift):
 * appended to xyz without a key.  Returns its explicit index (not a point id), or -1. */
int64_t arr_aux_vertex(arr_table *T, const double x[3]);
/* An explicit point for auxiliary vertex xi (its point id), or -1. */
int64_t arr_aux_point(arr_table *T, int64_t xi);
/* A lifted point (kind ARR_LIFT) on the plane of explicit triangle tri, without a key;
 * -1 when out of memory, -2 when there is none (the plane parallel to axis). */
int64_t arr_lift(arr_table *T, const int64_t tri[3], int axis, double u, double v);
/* Drops the points appended after npts (temporary lifts). */
void arr_truncate(arr_table *T, int64_t npts);

/* Merges points at exactly the same position: canon[p] = the smallest id at p's
 * position, for every point so far.  1, 0 when out of memory, -1 when prog (may be NULL)
 * asked to stop. */
int arr_dedupe(arr_table *T, mfg_prog *prog);
static inline int64_t arr_canon(const arr_table *T, int64_t p)
{
    return p < T->ncanon ? T->canon[p] : p;
}

/* ---- Boxes (bvh.c) -------------------------------------------------------------------- */

typedef struct arr_bvh arr_bvh;
/* A hierarchy over n boxes (6 doubles each: lo[3], hi[3]). NULL when out of memory. */
arr_bvh *arr_bvh_build(const double *boxes, int64_t n);
void arr_bvh_free(arr_bvh *h);
/* Calls fn(user, i, j) once for every pair i < j of boxes that overlap (closed boxes).
 * Stops and returns 0 when fn returns 0; else 1. */
int arr_bvh_pairs(const arr_bvh *h, int (*fn)(void *user, int64_t i, int64_t j), void *user);
/* Calls fn(user, i) for every box that the ray from o along +axis (dir = +1) or -axis
 * (dir = -1) may meet (the boxes are padded, so a box is never missed by rounding). */
int arr_bvh_ray(const arr_bvh *h, const double o[3], int axis, int dir,
                int (*fn)(void *user, int64_t i), void *user);

/* ---- The arrangement ------------------------------------------------------------------ */

/* A segment of a cluster: its end points and what it lies on, for the crossings: either
 * the plane of another cluster (support >= 0: that cluster) or an edge of a member
 * triangle (support = -1; ea, eb its explicit vertices). delta is the change of the
 * cluster's multiplicity across it from right to left (seen along the cluster's axis):
 * the sum over member edges along it of +1 (same direction) / -1 (opposite). */
typedef struct arr_seg {
    int64_t p, q;
    int64_t support;
    int64_t ea, eb;
    int32_t delta;
} arr_seg;

/* A face of the arrangement: three point ids (canonical), counter-clockwise seen from
 * its front; mult = the jump of the winding number across it (front w, back w + mult). */
typedef struct arr_face {
    int64_t v[3];
    int64_t cluster;
    int32_t mult;
} arr_face;

typedef struct arr_cluster {
    int64_t rep;        /* its representative triangle (the smallest id) */
    int axis;           /* the coordinate dropped for its 2-D work */
    int sign;           /* sign of the representative's normal along axis */
} arr_cluster;

/* The progress stages of an arrangement (static strings, the caller's names) and the
 * fractions where they start and where the last one ends. */
typedef struct arr_stages {
    const char *name[3]; /* the pairs, the clusters' faces, the winding numbers */
    double at[4];
    /* the most points the table may hold (0: no bound): beyond, the run stops with
     * MFG_ERR_INTERNAL ("more points than the caller's bound"), for a caller that knows
     * its input should make few and would rather try another way than wait */
    int64_t max_points;
} arr_stages;

typedef struct arr_ctx {
    mfg_prog *prog;
    const int64_t *tri; /* input triangles (explicit vertex ids) */
    int64_t ntri;
    arr_table T;
    int64_t *tcluster;  /* cluster of each triangle (-1: zero-area triangle, dropped) */
    arr_cluster *cl;
    int64_t ncl;
    /* per cluster segments and loose points (from the pair stage), CSR by cluster */
    arr_seg *seg;
    int64_t nseg, capseg;
    int64_t *segcl;     /* cluster of each segment record (before the CSR sort) */
    int64_t *pt, *ptcl; /* loose points and their clusters */
    int64_t npt, cappt;
    arr_face *face;
    int64_t nface, capface;
    int64_t super[3][3]; /* point ids of the enclosing triangle's corners, per axis */
    void *cdt_scratch;   /* cdt.c's buffers, kept between clusters */
    int64_t max_points;  /* arr_stages.max_points */
    mfg_status st;
} arr_ctx;

/* 1 when the table holds more points than the caller's bound, with ctx->st set. */
int arr_over_budget(arr_ctx *c);

/* Records point p as a vertex of cluster cl's arrangement (pairs.c).  0: out of memory. */
int arr_add_point_record(arr_ctx *c, int64_t cl, int64_t p);
/* pairs.c: clusters (tcluster, cl) and the intersection segments / points of triangles
 * of different clusters (seg/segcl, pt/ptcl).  1, or 0 with ctx->st set. */
int arr_pairs(arr_ctx *c, arr_bvh *bvh);
/* cluster.c + cdt.c: the faces of every cluster.  1, or 0 with ctx->st set. */
int arr_clusters(arr_ctx *c);
/* cluster.c: the arrangement of the 2-D chain seg (nseg segments, pairs of explicit point
 * ids) in the plane of cluster 0 (set up by the caller), each segment counting +1 from
 * its right to its left: faces with their windings into c->face.  1, or 0 with c->st. */
int arr_planar_chain(arr_ctx *c, const int64_t *seg, int64_t nseg);
/* cdt.c: the faces of one cluster from its points and segments (split already: no two
 * cross, no point lies inside a segment).  Appends to c->face. */
int arr_cdt_cluster(arr_ctx *c, int64_t cl, const int64_t *pts, int64_t npts,
                    const arr_seg *segs, int64_t nsegs);
/* Appends a face (cluster.c); 0 when out of memory. */
int arr_push_face(arr_ctx *c, const arr_face *f);
/* Frees cdt.c's buffers. */
void arr_cdt_free(arr_ctx *c);
/* winding.c: keeps the faces on the boundary of {w >= 1}, oriented outward.  keep[f] =
 * 1 for them. */
int arr_boundary_faces(arr_ctx *c, const arr_bvh *bvh, uint8_t *keep);

/* The whole pipeline: the boundary of {w >= 1} of the closed chain (xyz on the grid, nv
 * vertices; tri, ntri oriented triangles).  On success (MFG_OK) *out_faces / *nfaces are
 * the boundary faces (malloc'd; point ids of *table, which the caller frees with
 * arr_table_free; each face's cluster set), and, when out_tcluster is not NULL, the
 * cluster of every input triangle (malloc'd; -1 for a triangle of zero area; a cluster
 * is one plane).  Errors: MFG_ERR_NOMEM, MFG_ERR_CANCELLED, MFG_ERR_INTERNAL (with the
 * detail set). */
mfg_status arr_union_boundary(const double *xyz, int64_t nv, const int64_t *tri, int64_t ntri,
                              mfg_prog *prog, const arr_stages *stages, arr_table *table,
                              arr_face **out_faces, int64_t *nfaces, int64_t **out_tcluster,
                              int64_t *nclusters);

/* The faces of the plane z = 0 cut by the closed 2-D chain of nseg segments (seg: pairs of
 * vertex ids into xyz, whose z is 0), each with its winding number (mult, the face
 * counter-clockwise about the normal direction of its winding's sign; windings 0 are
 * left out): a 2-D union or winding computation, exact.  Errors as arr_union_boundary. */
mfg_status arr_chain2d_faces(const double *xyz, int64_t nv, const int64_t *seg, int64_t nseg,
                             mfg_prog *prog, arr_table *table, arr_face **out_faces,
                             int64_t *nfaces);

/* The faces of every cluster with their multiplicities (the 2-D arrangements alone, no
 * winding numbers): for a chain whose triangles all lie in one plane, the faces of the
 * plane's arrangement, each counted as often as the chain covers it (mult, with the face
 * counter-clockwise about the normal direction of its multiplicity's sign).  The same
 * outputs and errors as arr_union_boundary; stages->name[2] is not used. */
mfg_status arr_cluster_faces(const double *xyz, int64_t nv, const int64_t *tri, int64_t ntri,
                             mfg_prog *prog, const arr_stages *stages, arr_table *table,
                             arr_face **out_faces, int64_t *nfaces);

#endif
