/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mesh.h - private: the closed-solid check every mesh algorithm (sweep/, medial/)
 * runs on its input, and the edge adjacency it finds on the way. */
#ifndef MFG_MESH_H
#define MFG_MESH_H

#include <stdint.h>

#include "mfgeom.h"

/*
 * The check of mfg_mesh_check_closed (mfgeom.h), for the library's own entry points:
 * validates the arguments (NULL, counts, coordinates, indices), then refuses anything but
 * a closed, consistently and outward oriented 2-manifold with MFG_ERR_INVALID or
 * MFG_ERR_DEGENERATE and a detail naming the first problem and the counts.
 * On success (MFG_OK):
 *  - *report (when report is not NULL) is filled as by mfg_mesh_check;
 *  - *out_neighbours (when not NULL) gets a malloc'd array of 3 * ntriangles indices:
 *    neighbours[3t + k] is the triangle on the other side of the side from
 *    triangles[3t + k] to triangles[3t + (k+1)%3] (every side has exactly one, since
 *    the mesh is closed and manifold).  The caller releases it with free().
 * On failure neither is written.
 */
mfg_status mfg_mesh_require_closed(const double *xyz, int64_t nvertices,
                                   const int64_t *triangles, int64_t ntriangles,
                                   mfg_mesh_report *report, int64_t **out_neighbours);

/* The argument checks every mesh entry point makes (mfg_mesh_check, the closed check, the
 * ray test): counts within 0 .. MFG_MAX_COUNT, xyz and triangles not NULL when needed,
 * every coordinate accepted by mfg_coord_ok, every index within 0 .. nvertices-1.
 * MFG_ERR_NULL / MFG_ERR_INVALID with a detail naming the first bad value. */
mfg_status mfg_mesh_validate(const double *xyz, int64_t nvertices, const int64_t *triangles,
                             int64_t ntriangles);

/* The closed check's last test (shell_crossing.c, issue 22), for a mesh that passed every
 * other: two triangles sharing no vertex cross (exactly: overlapping or self-intersecting
 * shells), a shell encloses no volume (flat), or a shell lies inside another facing the
 * same way (nested shells).  MFG_ERR_INVALID naming the first pair / shell, MFG_ERR_NOMEM,
 * or MFG_OK. */
mfg_status mfg_mesh_shells_problem(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt);

/* One shell (triangles joined through shared vertices) of a mesh. */
typedef struct mfg_shell_info {
    int64_t ntriangles, first;      /* how many; the first in the mesh's order */
    int64_t largest;                /* the one of largest area (-1: all of zero area) */
    double largest_area2;           /* twice its area */
    double volume6, volume6_bound;  /* 6 x signed volume (about the mesh's box centre) and
                                     * its rounding bound */
    double lo[3], hi[3];            /* bounding box */
} mfg_shell_info;

/* The shells of a mesh: shell_of[t] (nt entries, the caller's) numbers them 0.. in order of
 * their first triangle; *out (malloc'd, free()) describes each.  Returns how many, or -1
 * when out of memory (*out NULL). */
int64_t mfg_mesh_shells(const double *xyz, int64_t nv, const int64_t *tris, int64_t nt,
                        int64_t *shell_of, mfg_shell_info **out);

/* 1 when the shell's volume is zero within its rounding bound: it encloses no solid. */
int mfg_shell_is_flat(const mfg_shell_info *s);

/* 1 when triangle abc has zero area, exactly (its three projected orientations vanish). */
int mfg_triangle_zero_area(const double *a, const double *b, const double *c);

#endif
