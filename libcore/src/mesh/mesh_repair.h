/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mesh_repair.h - private: a surface that is closed and oriented in exact arithmetic (the
 * boundary an arrangement evaluates, arrange/) made a clean closed 2-manifold after its
 * points are rounded to doubles. */
#ifndef MFG_MESH_REPAIR_H
#define MFG_MESH_REPAIR_H

#include <stdint.h>

/* A triangle mesh the repair may grow (malloc'd arrays; g may be NULL). */
typedef struct mfg_rmesh {
    double *x;       /* 3 per vertex */
    int64_t nv, capv;
    int64_t *t;      /* 3 per triangle */
    int64_t nt, capt;
    int64_t *g;      /* per triangle: a label carried along (its planar group), or NULL */
} mfg_rmesh;

/*
 * Rounding the points of an exact boundary to doubles leaves, where its sheets meet at
 * grazing angles, features far below any tolerance that are wrong as a mesh: points a
 * few ulps apart, needles (a corner within rounding of the opposite side) that fold or
 * cross their neighbours, and where the solid touches itself along an edge or at a point
 * (two boxes sharing an edge), edges with four triangles and pinched vertices.  This:
 *  1. welds points closer than eps (each coordinate) and drops the triangles that lose
 *     their area; pairs of opposite triangles on the same three points cancel;
 *  2. removes needles: a triangle whose height over its longest side is below eps is
 *     dropped and its neighbour across that side (any live one, where sheets touch along
 *     it) is split at its far corner - or dropped too when it is the needle reversed (a
 *     flat pocket) - so the surface moves by less than eps and the mesh stays closed;
 *  3. separates the sheets that touch: at an edge of 2k triangles they are paired round
 *     the edge so that each pair bounds one wedge of the solid, and every vertex gets one
 *     copy per fan of triangles joined through its (paired) edges.
 * Copies made in 3 have the same coordinates as their original (a solid touching itself
 * stays touching; it is a 2-manifold combinatorially).  Returns 1, or 0 when out of
 * memory (the mesh is then valid but may be only partly repaired).
 */
int mfg_mesh_repair(mfg_rmesh *m, double eps);

/* Step 3 alone: the sheets that touch at edges and vertices separated (combinatorially;
 * no point moves).  1, or 0 when out of memory. */
int mfg_mesh_separate_sheets(mfg_rmesh *m);

/* Step 1 alone for a closed 2-chain (triangles counted with their orientation): points
 * closer than eps welded into the smallest-numbered one (whose coordinates stay), the
 * triangles that lose their area dropped, equal triangles of opposite orientations
 * cancelled (the rest kept as often as their net count): the chain stays closed.  1, or
 * 0 when out of memory. */
int mfg_chain_weld(mfg_rmesh *m, double eps);

/* 4. Shells that enclose no volume (mesh.h's mfg_shell_is_flat: faces folded onto each
 * other, zero volume within rounding) dropped: rounding an exact boundary can leave such
 * debris - a tetrahedron flattened onto the surface where a full turn's sheets touch - and
 * it has no inside to bound.  Vertices stay (unused).  1, or 0 when out of memory. */
int mfg_mesh_drop_flat_shells(mfg_rmesh *m);

#endif
