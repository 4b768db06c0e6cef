/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* planar_merge.h - private: pieces of one plane in a closed triangle mesh merged back into
 * one triangulated region each (the rotational sweep's face pieces). */
#ifndef MFG_PLANAR_MERGE_H
#define MFG_PLANAR_MERGE_H

#include <stdint.h>

/*
 * tris (*ntris triangles over the nvertices points xyz) is a closed, consistently oriented
 * triangle mesh; group[t] >= 0 names the plane triangle t lies in (triangles of one group
 * lie in one plane and face one way), -1 for a triangle of no group.  Every region of a
 * group joined through shared edges is triangulated again on its boundary vertices only:
 * its boundary loops (every vertex kept, collinear ones too), not its inner vertices, and
 * nothing else of the mesh changes, so the mesh stays closed, oriented and manifold.  A
 * region is left as it is when it is not a clean planar region (corners more than 1e-12
 * of their coordinates off one plane, loops that do not close or that cross, an inner
 * vertex used elsewhere, a new edge that exists elsewhere, an area that differs by more
 * than 1e-9 relative) or when nothing would be gained.  Pieces folded over each other
 * inside a region (slivers turned over in the plane) are allowed: only the boundary
 * counts, and the new triangles cover what its winding number says.  Merged triangles are written after the kept ones (group is not
 * reordered: it describes the input).
 *
 * Returns 1 and updates tris and *ntris (never more triangles than before); *nregions
 * (when not NULL) gets the number of regions triangulated again.  Returns 0 when out of
 * memory, with tris unchanged.
 */
int mfg_merge_planar_groups(const double *xyz, int64_t nvertices, int64_t *tris, int64_t *ntris,
                            const int64_t *group, int64_t *nregions);

/*
 * The same, and the boundary loops thinned before they are triangulated (the medial
 * sheets, whose boundary has a vertex per octree leaf along every seam): a run of loop
 * vertices is replaced by the chord between its ends when every vertex of the run lies
 * within thin_tol of the chord (3-D distance) and the run holds one chain: label[x] >= 0
 * names the chain of vertex x, -1 goes with any chain, < -1 (a corner) and a vertex where
 * the region's boundary touches itself or that a triangle outside the region uses are
 * kept.  A loop left with fewer than 3 vertices, or thinned loops that cross, leave the
 * region as it was.  label NULL: no thinning (mfg_merge_planar_groups).  The checks are
 * those above with the thinned loops in place of the old boundary and the loops' area in
 * place of the old one.  thinned (nvertices, may be NULL) gets 1 at the loop vertices of
 * every region triangulated again (the ones kept), 0 elsewhere: a later simplification
 * must keep them, or the dropped ones could end farther than thin_tol from the boundary.
 */
int mfg_merge_planar_groups_thin(const double *xyz, int64_t nvertices, int64_t *tris,
                                 int64_t *ntris, const int64_t *group, int64_t *nregions,
                                 const int64_t *label, double thin_tol, char *thinned);

#endif
