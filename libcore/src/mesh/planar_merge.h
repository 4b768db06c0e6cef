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

#endif
