/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial.c - the medial surface's public entry point (issue 9, seed 004 Lee & Lee):
 * input checks, the pipeline elements -> BVH -> octree leaves -> sheets, junctions ->
 * assembly into mfg_medial, and mfg_medial_free.
 * STATUS: the pipeline after the elements is being built (work packages B, C); until it
 * lands the entry point checks its input and reports MFG_ERR_INTERNAL. */
#include <math.h>
#include <stdlib.h>

#include "medial.h"
#include "mfg_internal.h"

mfg_status mfg_medial_surface(const double *xyz, int64_t nvertices, const int64_t *triangles,
                              int64_t ntriangles, double tolerance, uint32_t flags,
                              int32_t nthreads, mfg_medial **out)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "mfg_medial_surface: out is NULL");
    if (flags & ~MFG_MEDIAL_FULL)
        return mfg_fail(MFG_ERR_INVALID, "mfg_medial_surface: unknown flags 0x%x",
                        (unsigned)(flags & ~MFG_MEDIAL_FULL));
    if (nthreads < 0)
        return mfg_fail(MFG_ERR_INVALID, "mfg_medial_surface: nthreads %d < 0", (int)nthreads);
    md_elements el;
    mfg_status st = md_elements_build(xyz, nvertices, triangles, ntriangles, tolerance, &el);
    if (st != MFG_OK)
        return st;
    md_elements_free(&el);
    return mfg_fail(MFG_ERR_INTERNAL, "mfg_medial_surface: the extraction is not built yet");
}

void mfg_medial_free(mfg_medial *m)
{
    if (!m)
        return;
    free(m->element_kinds);
    free(m->element_convex);
    free(m->face_of_triangle);
    free(m->face_planes);
    free(m->edge_segments);
    free(m->vertex_points);
    free(m->sheet_elements);
    free(m->sheet_forms);
    free(m->sheet_vertex_offsets);
    free(m->sheet_triangle_offsets);
    free(m->sheet_vertices);
    free(m->sheet_radii);
    free(m->sheet_triangles);
    free(m->seam_kinds);
    free(m->seam_point_offsets);
    free(m->seam_points);
    free(m->seam_radii);
    free(m->seam_element_offsets);
    free(m->seam_elements);
    free(m->seam_ends);
    free(m->junction_kinds);
    free(m->junction_points);
    free(m->junction_radii);
    free(m->junction_element_offsets);
    free(m->junction_elements);
    free(m);
}
