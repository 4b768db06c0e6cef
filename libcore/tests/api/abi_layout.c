/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* abi_layout.c - the memory layout of every public struct of mfgeom.h, for the ctypes
 * binding's twins (tests/python/test_abi_layout.py compares them).  One line per struct
 * and per field, in declaration order:
 *     version <mfg_version()>
 *     struct <tag> <sizeof> <alignof>
 *     field <tag> <name> <offsetof> <sizeof>
 * A struct or field added to mfgeom.h must be added here too: the Python test parses the
 * header and fails on a struct or field this program does not print. */
#include <stddef.h>
#include <stdio.h>

#include "mfgeom.h"

#define STRUCT(tag) \
    printf("struct %s %zu %zu\n", #tag, sizeof(struct tag), _Alignof(struct tag))
#define FIELD(tag, name)                                                                  \
    printf("field %s %s %zu %zu\n", #tag, #name, offsetof(struct tag, name),              \
           sizeof(((struct tag *)0)->name))

int main(void)
{
    printf("version %s\n", mfg_version());

    STRUCT(mfg_progress);
    FIELD(mfg_progress, callback);
    FIELD(mfg_progress, user);

    STRUCT(mfg_region_info);
    FIELD(mfg_region_info, columns);
    FIELD(mfg_region_info, rows);
    FIELD(mfg_region_info, edge_cells);
    FIELD(mfg_region_info, grid_entries);
    FIELD(mfg_region_info, edge_entries);
    FIELD(mfg_region_info, list_entries);
    FIELD(mfg_region_info, ordered_entries);
    FIELD(mfg_region_info, nodes);
    FIELD(mfg_region_info, list_leaves);
    FIELD(mfg_region_info, ordered_leaves);
    FIELD(mfg_region_info, max_depth);
    FIELD(mfg_region_info, max_list);
    FIELD(mfg_region_info, bytes);

    STRUCT(mfg_spoly);
    FIELD(mfg_spoly, kind);
    FIELD(mfg_spoly, closed);
    FIELD(mfg_spoly, nvertices);
    FIELD(mfg_spoly, vertices);

    STRUCT(mfg_regions);
    FIELD(mfg_regions, weight);
    FIELD(mfg_regions, nregions);
    FIELD(mfg_regions, kinds);
    FIELD(mfg_regions, closed);
    FIELD(mfg_regions, vertex_offsets);
    FIELD(mfg_regions, vertices);
    FIELD(mfg_regions, cover_offsets);
    FIELD(mfg_regions, cover);
    FIELD(mfg_regions, centres);
    FIELD(mfg_regions, margins);

    STRUCT(mfg_mesh_report);
    FIELD(mfg_mesh_report, nvertices);
    FIELD(mfg_mesh_report, ntriangles);
    FIELD(mfg_mesh_report, boundary_edges);
    FIELD(mfg_mesh_report, nonmanifold_edges);
    FIELD(mfg_mesh_report, inconsistent_edges);
    FIELD(mfg_mesh_report, nonmanifold_vertices);
    FIELD(mfg_mesh_report, degenerate_triangles);
    FIELD(mfg_mesh_report, unused_vertices);
    FIELD(mfg_mesh_report, components);
    FIELD(mfg_mesh_report, volume);
    FIELD(mfg_mesh_report, area);
    FIELD(mfg_mesh_report, bbox);

    STRUCT(mfg_mesh);
    FIELD(mfg_mesh, nvertices);
    FIELD(mfg_mesh, ntriangles);
    FIELD(mfg_mesh, vertices);
    FIELD(mfg_mesh, triangles);

    STRUCT(mfg_sweep_stats);
    FIELD(mfg_sweep_stats, volume);
    FIELD(mfg_sweep_stats, area);
    FIELD(mfg_sweep_stats, bbox);

    STRUCT(mfg_medial_axis);
    FIELD(mfg_medial_axis, nbranches);
    FIELD(mfg_medial_axis, branch_offsets);
    FIELD(mfg_medial_axis, npoints);
    FIELD(mfg_medial_axis, points);
    FIELD(mfg_medial_axis, radii);
    FIELD(mfg_medial_axis, branch_ends);
    FIELD(mfg_medial_axis, njunctions);
    FIELD(mfg_medial_axis, junction_points);
    FIELD(mfg_medial_axis, junction_radii);
    FIELD(mfg_medial_axis, junction_degree);
    FIELD(mfg_medial_axis, junction_offsets);
    FIELD(mfg_medial_axis, junction_elements);

    STRUCT(mfg_medial);
    FIELD(mfg_medial, nelements);
    FIELD(mfg_medial, nfaces);
    FIELD(mfg_medial, nedges);
    FIELD(mfg_medial, nvertices);
    FIELD(mfg_medial, ntriangles);
    FIELD(mfg_medial, element_kinds);
    FIELD(mfg_medial, element_convex);
    FIELD(mfg_medial, face_of_triangle);
    FIELD(mfg_medial, face_planes);
    FIELD(mfg_medial, edge_segments);
    FIELD(mfg_medial, vertex_points);
    FIELD(mfg_medial, nsheets);
    FIELD(mfg_medial, sheet_elements);
    FIELD(mfg_medial, sheet_forms);
    FIELD(mfg_medial, sheet_vertex_offsets);
    FIELD(mfg_medial, sheet_triangle_offsets);
    FIELD(mfg_medial, sheet_vertices);
    FIELD(mfg_medial, sheet_radii);
    FIELD(mfg_medial, sheet_triangles);
    FIELD(mfg_medial, nseams);
    FIELD(mfg_medial, seam_kinds);
    FIELD(mfg_medial, seam_point_offsets);
    FIELD(mfg_medial, seam_points);
    FIELD(mfg_medial, seam_radii);
    FIELD(mfg_medial, seam_element_offsets);
    FIELD(mfg_medial, seam_elements);
    FIELD(mfg_medial, seam_ends);
    FIELD(mfg_medial, njunctions);
    FIELD(mfg_medial, junction_kinds);
    FIELD(mfg_medial, junction_points);
    FIELD(mfg_medial, junction_radii);
    FIELD(mfg_medial, junction_element_offsets);
    FIELD(mfg_medial, junction_elements);
    FIELD(mfg_medial, cells_visited);
    FIELD(mfg_medial, leaves);
    FIELD(mfg_medial, leaf_size);
    return fflush(stdout) == 0 ? 0 : 1;
}
